"""Interval type-2 fuzzy sets: an upper and a lower membership function, lower <= upper.

An :class:`IT2Set` pairs two type-1 membership functions. Its constructors follow the common
conventions of the field:

- :meth:`IT2Set.triangle` / :meth:`IT2Set.trapezoid`: the IT2FLS toolbox (Taskin & Kumbasar)
  convention, upper and lower parameter vectors ``[a b c h]`` / ``[a b c d h]``;
- :meth:`IT2Set.from_fou`: a type-1 centre line widened by a Footprint of Uncertainty of width
  ``w`` -- upper feet move outwards by ``w/2``, lower feet inwards by ``w/2`` (DESIGN.md sec. 3;
  reproduces the paper's Tables 1 and 4);
- :meth:`IT2Set.gaussian_uncertain_mean` / :meth:`IT2Set.gaussian_uncertain_std`;
- :meth:`IT2Set.from_scale_lag`: MATLAB's ``LowerScale`` / ``LowerLag`` construction.

``lower <= upper`` is checked on the input's universe when the set is attached to an input (see
:class:`it2track.fuzzy.rules.Input`), or here when ``universe`` is given.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from decimal import Decimal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .membership import (
    Gaussian,
    MembershipFunction,
    PiecewiseLinear,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
)
from .parametric import Parametric

__all__ = ["IT2Set", "ScaledLagged"]

FloatArray = NDArray[np.float64]

#: Number of grid points used (besides all breakpoints) to check lower <= upper on a universe.
CHECK_POINTS = 4001


@dataclass(frozen=True)
class ScaledLagged:
    """``scale h clip((upper(x)/h - lag) / (1 - lag), 0, 1)``: MATLAB's lower MF of a type-2 MF.

    ``h`` is the upper MF's height (its ``h`` attribute, 1 if it has none).

    Our reading of MATLAB's ``fismftype2`` documentation: the lower MF is zero until the upper MF
    reaches ``LowerLag`` and peaks at ``LowerScale`` where the upper MF peaks. For piecewise-
    linear upper MFs :meth:`IT2Set.from_scale_lag` returns the equivalent trapezoid instead.
    """

    upper: MembershipFunction
    scale: float = 1.0
    lag: float = 0.0

    def __post_init__(self) -> None:
        if not 0.0 < self.scale <= 1.0:
            raise ValueError(f"LowerScale={self.scale!r} must satisfy 0 < scale <= 1")
        if not 0.0 <= self.lag < 1.0:
            raise ValueError(f"LowerLag={self.lag!r} must satisfy 0 <= lag < 1")

    def __call__(self, x: ArrayLike) -> FloatArray:
        # The lag is relative to the upper MF's height, as for triangles and trapezoids.
        peak = float(getattr(self.upper, "h", 1.0))
        u = self.upper(x)
        return (self.scale * peak) * np.clip((u / peak - self.lag) / (1.0 - self.lag), 0.0, 1.0)


@dataclass(frozen=True)
class IT2Set:
    """An interval type-2 fuzzy set.

    Parameters
    ----------
    upper, lower : MembershipFunction
        Upper and lower membership functions; ``0 <= lower <= upper <= 1``. A type-1 set is an
        ``IT2Set`` whose ``lower`` is its ``upper`` (see :meth:`type1`).
    name : str
        Linguistic label, e.g. ``"N"``; rules refer to sets by it.
    universe : (float, float), optional
        If given, ``lower <= upper`` is checked on it now.

    Raises
    ------
    ValueError
        If the lower MF exceeds the upper MF somewhere on ``universe``, naming the set and the
        place.
    """

    upper: MembershipFunction
    lower: MembershipFunction
    name: str = ""
    universe: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        for which in ("upper", "lower"):
            if not callable(getattr(self, which)):
                raise ValueError(f"set {self.name!r}: {which} MF must be callable")
        if self.universe is not None:
            self.check_on(self.universe, owner="")

    # -- constructors -------------------------------------------------------------------------
    @classmethod
    def type1(cls, mf: MembershipFunction, name: str = "") -> IT2Set:
        """A type-1 set (no footprint): lower and upper are the same MF."""
        return cls(mf, mf, name)

    @classmethod
    def triangle(
        cls, upper: Sequence[float], lower: Sequence[float], name: str = ""
    ) -> IT2Set:
        """Triangles in the IT2FLS-toolbox convention ``[a b c h]`` (``h`` optional, default 1).

        Examples
        --------
        >>> s = IT2Set.triangle([-0.9, 0, 0.9, 1], [-0.7, 0, 0.7, 1], "Z")
        >>> [round(float(v), 6) for v in (s.upper(0.35), s.lower(0.35))]
        [0.611111, 0.5]
        """
        return cls(
            _from_params(Triangle, upper, name, "upper", 3),
            _from_params(Triangle, lower, name, "lower", 3),
            name,
        )

    @classmethod
    def trapezoid(
        cls, upper: Sequence[float], lower: Sequence[float], name: str = ""
    ) -> IT2Set:
        """Trapezoids ``[a b c d h]`` (``h`` optional, default 1)."""
        return cls(
            _from_params(Trapezoid, upper, name, "upper", 4),
            _from_params(Trapezoid, lower, name, "lower", 4),
            name,
        )

    @classmethod
    def from_fou(cls, centre: Triangle | Trapezoid, width: float, name: str = "") -> IT2Set:
        """Widen a type-1 triangle or trapezoid into an IT2 set with FoU width ``width``.

        Each sloped side's foot moves outwards by ``width/2`` in the upper MF and inwards by
        ``width/2`` in the lower MF; peaks and shoulders stay. ``width == 0`` gives the type-1 set.
        The shifts are done in decimal on the shortest representation of the parameters, so that
        printed tables come out exactly (``-0.2 + 0.3/2`` gives ``-0.05``, not
        ``-0.05000000000000002``).

        Raises
        ------
        ValueError
            If ``width`` is negative or so large that a lower MF foot would reach its peak.

        Examples
        --------
        >>> s = IT2Set.from_fou(Triangle(-1, -1, -0.2), 0.2, "N")  # the paper's Table 1
        >>> s.upper, s.lower
        (Triangle(a=-1.0, b=-1.0, c=-0.1, h=1.0), Triangle(a=-1.0, b=-1.0, c=-0.3, h=1.0))
        """
        if not math.isfinite(width) or width < 0:
            raise ValueError(f"set {name!r}: FoU width={width!r} must be finite and >= 0")
        a, b, c, d, h = centre.as_trapezoid()
        half = 0.5 * width
        shift_left = 0.0 if a == b else half
        shift_right = 0.0 if c == d else half
        up = (_add(a, -shift_left), b, c, _add(d, shift_right), h)
        lo = (_add(a, shift_left), b, c, _add(d, -shift_right), h)
        # A sloped side's lower foot must stay short of its peak: reaching it would turn the
        # side into a shoulder (value h beyond the peak), far above the upper MF.
        if (shift_left and lo[0] >= lo[1]) or (shift_right and lo[2] >= lo[3]):
            raise ValueError(
                f"set {name!r}: FoU width={width!r} too large for {centre}: the lower MF's feet "
                f"would reach its peak (it must be less than "
                f"{2 * min(b - a or math.inf, d - c or math.inf)})"
            )
        if isinstance(centre, Triangle):
            upper: PiecewiseLinear = Triangle(up[0], up[1], up[3], h)
            lower: PiecewiseLinear = Triangle(lo[0], lo[1], lo[3], h)
        else:
            upper, lower = Trapezoid(*up), Trapezoid(*lo)
        if width == 0:
            lower = upper
        return cls(upper, lower, name)

    @classmethod
    def gaussian_uncertain_mean(
        cls, m1: float, m2: float, sigma: float, name: str = "", h: float = 1.0
    ) -> IT2Set:
        """Gaussian with uncertain mean in ``[m1, m2]`` and fixed ``sigma``."""
        return cls(
            UncertainMeanGaussianUpper(m1, m2, sigma, h),
            UncertainMeanGaussianLower(m1, m2, sigma, h),
            name,
        )

    @classmethod
    def gaussian_uncertain_std(
        cls, mean: float, sigma1: float, sigma2: float, name: str = "", h: float = 1.0
    ) -> IT2Set:
        """Gaussian with fixed ``mean`` and uncertain std in ``[sigma1, sigma2]``."""
        if not sigma1 <= sigma2:
            raise ValueError(f"set {name!r}: sigma1={sigma1!r} must be <= sigma2={sigma2!r}")
        return cls(Gaussian(mean, sigma2, h), Gaussian(mean, sigma1, h), name)

    @classmethod
    def from_scale_lag(
        cls,
        upper: MembershipFunction,
        *,
        scale: float = 1.0,
        lag: float | Sequence[float] = 0.0,
        name: str = "",
    ) -> IT2Set:
        """MATLAB-style IT2 set: an upper MF plus ``LowerScale`` and ``LowerLag``.

        For a triangle or trapezoid upper MF the lower MF is the trapezoid whose feet lie where
        the upper MF equals the lag (a two-element ``lag`` gives left and right lags) and whose
        height is ``scale * h``. For any other upper MF it is :class:`ScaledLagged`.

        Examples
        --------
        >>> s = IT2Set.from_scale_lag(Triangle(5, 7, 9), scale=0.8, lag=0.3)
        >>> s.lower
        Trapezoid(a=5.6, b=7.0, c=7.0, d=8.4, h=0.8)
        """
        lags = (lag, lag) if isinstance(lag, int | float) else tuple(lag)
        if len(lags) != 2:
            raise ValueError(f"set {name!r}: LowerLag={lag!r} must be a number or two numbers")
        for value in lags:
            if not 0.0 <= value < 1.0:
                raise ValueError(f"set {name!r}: LowerLag={lag!r} must satisfy 0 <= lag < 1")
        if not 0.0 < scale <= 1.0:
            raise ValueError(f"set {name!r}: LowerScale={scale!r} must satisfy 0 < scale <= 1")
        if isinstance(upper, PiecewiseLinear):
            a, b, c, d, h = upper.as_trapezoid()
            # The upper side reaches `lag * h` at a + lag (b - a); shoulders stay shoulders.
            # (min/max keep the feet on their side of the peak whatever the rounding.)
            la = a if a == b else min(a + lags[0] * (b - a), b)
            ld = d if c == d else max(d - lags[1] * (d - c), c)
            lower: MembershipFunction = Trapezoid(la, b, c, ld, scale * h)
        else:
            if lags[0] != lags[1]:
                raise ValueError(f"set {name!r}: a two-sided LowerLag needs a triangle/trapezoid")
            lower = ScaledLagged(upper, scale, lags[0])
        return cls(upper, lower, name)

    # -- queries ------------------------------------------------------------------------------
    @property
    def is_type1(self) -> bool:
        """True if the lower MF is the upper MF (no footprint of uncertainty)."""
        return self.lower is self.upper or self.lower == self.upper

    def __call__(self, x: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """``(lower, upper)`` membership degrees at ``x``."""
        return self.lower(x), self.upper(x)

    def check_on(self, universe: tuple[float, float], *, owner: str) -> None:
        """Check ``0 <= lower <= upper <= 1`` on ``universe`` (grid plus all breakpoints).

        Raises
        ------
        ValueError
            Naming ``owner`` (e.g. ``"input 'e'"``), the set and the first offending point.
        """
        if isinstance(self.upper, Parametric) or isinstance(self.lower, Parametric):
            return  # its parameters are inputs: it checks them per sample (.parametric)
        lo, hi = universe
        points = [np.linspace(lo, hi, CHECK_POINTS)]
        for mf in (self.upper, self.lower):
            if isinstance(mf, PiecewiseLinear):
                bp = np.asarray(mf.breakpoints(), dtype=np.float64)
                points.append(bp[(bp >= lo) & (bp <= hi)])
        x = np.unique(np.concatenate(points))
        up = np.asarray(self.upper(x), dtype=np.float64)
        low = np.asarray(self.lower(x), dtype=np.float64)
        where = f"{owner} set {self.name!r}" if owner else f"set {self.name!r}"
        for label, values in (("upper", up), ("lower", low)):
            bad = ~((values >= 0.0) & (values <= 1.0))
            if bad.any():
                i = int(np.argmax(bad))
                raise ValueError(
                    f"{where}: {label} MF {getattr(self, label)!r} gives {values[i]!r} at "
                    f"x={x[i]!r}, outside [0, 1]"
                )
        bad = low > up + 1e-12
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(
                f"{where}: lower MF {self.lower!r} exceeds upper MF {self.upper!r} at x={x[i]:.6g} "
                f"(lower {low[i]:.6g} > upper {up[i]:.6g}); check the lower MF parameters"
            )


def _add(x: float, delta: float) -> float:
    """``x + delta`` rounded once from the exact sum of their shortest decimal representations."""
    if delta == 0.0:
        return x
    return float(Decimal(repr(float(x))) + Decimal(repr(float(delta))))


def _from_params(
    kind: type[Triangle] | type[Trapezoid],
    params: Sequence[float],
    name: str,
    which: str,
    n: int,
) -> Triangle | Trapezoid:
    values = [float(v) for v in params]
    if len(values) not in (n, n + 1):
        raise ValueError(
            f"set {name!r}: {which} parameters {list(params)!r} must have {n} values"
            f" (or {n + 1} with the height h)"
        )
    try:
        return kind(*values)
    except ValueError as exc:
        raise ValueError(f"set {name!r}, {which} MF: {exc}") from None

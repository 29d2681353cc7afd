"""Edge and geometric membership shapes: ramps (MATLAB's ``linsmf``/``linzmf``, fuzzylite's
``Ramp``), ``Rectangle``, ``Point`` (jFuzzyLogic's input singleton), ``Binary``, ``Discrete``,
``Concave``, ``Arc`` and ``SemiEllipse``.

As in :mod:`.curves`: frozen classes of their parameters (height ``h`` last, in ``(0, 1]``),
checked on construction, evaluated by ``term(x)`` with the documented formula, lowered to a
compiled row by ``kernel_row`` and named in MATLAB's and fuzzylite's vocabulary. The monotonic
ones (ramps, ``Concave``, ``Arc``) have an ``inverse`` (the Tsukamoto consequent value).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .kinds import MFKind, Row
from .membership import Term, _check_finite, _check_height

__all__ = [
    "Arc",
    "Binary",
    "Concave",
    "Discrete",
    "LinearSShape",
    "LinearZShape",
    "Point",
    "Ramp",
    "Rectangle",
    "SemiEllipse",
    "linsmf",
    "linzmf",
]

FloatArray = NDArray[np.float64]


def _f64(x: ArrayLike) -> FloatArray:
    return np.asarray(x, dtype=np.float64)


def _scalar(y: FloatArray) -> FloatArray:
    return y[()] if y.ndim == 0 else y


def trapezoid_row(x: ArrayLike, a: float, wl: float, d: float, wr: float, h: float
                  ) -> FloatArray:
    """A ``TRAPEZOID`` row ``h clip(min((x - a) / wl, (d - x) / wr), 0, 1)`` exactly as
    :meth:`SystemTables.memberships <it2track.fuzzy.tables.SystemTables.memberships>`
    evaluates it (an infinite ``a`` or ``d`` is a side that never binds)."""
    x = _f64(x)
    v = np.minimum((x - a) / wl, (d - x) / wr)
    return _scalar(np.maximum(np.minimum(v, 1.0), 0.0) * h)


def step_row(x: ArrayLike, edge: float, rising: float, closed: float, h: float) -> FloatArray:
    """A ``STEP`` row: ``h`` where ``x >= edge`` (``rising``; ``x > edge`` unless ``closed``)
    or ``x <= edge`` (falling; ``x < edge`` unless ``closed``), else 0."""
    x = _f64(x)
    if rising:
        on = (x >= edge) if closed else (x > edge)
    else:
        on = (x <= edge) if closed else (x < edge)
    return _scalar(np.where(on, h, 0.0))


def linsmf(x: ArrayLike, a: float, b: float) -> FloatArray:
    """MATLAB's linear S-shaped saturation ``linsmf(x, [a b])``, ``a <= b``.

    MATLAB documents, for ``a < b``: 0 for ``x < a``, ``(x - a) / (b - a)`` for
    ``a <= x <= b``, 1 for ``x > b``; for ``a == b``: 0 for ``x < a``, 1 for ``x >= a``.

    Parameters
    ----------
    x : array_like
        Points, any shape.
    a, b : float
        Foot and shoulder.

    Returns
    -------
    ndarray
        Membership degrees in ``[0, 1]``, shape of ``x``.

    Examples
    --------
    MATLAB's documented example ``linsmf(x, [4 6])``, and the crisp ``a == b``:

    >>> linsmf([3.0, 4.0, 5.0, 6.0, 7.0], 4, 6).tolist()
    [0.0, 0.0, 0.5, 1.0, 1.0]
    >>> linsmf([4.999, 5.0], 5, 5).tolist()
    [0.0, 1.0]
    """
    return LinearSShape(a, b)(x)


def linzmf(x: ArrayLike, a: float, b: float) -> FloatArray:
    """MATLAB's linear Z-shaped saturation ``linzmf(x, [a b])``, ``a <= b``.

    MATLAB documents, for ``a < b``: 1 for ``x < a``, ``(b - x) / (b - a)`` for
    ``a <= x <= b``, 0 for ``x > b``; for ``a == b``: 1 for ``x < a``, 0 for ``x >= a``.

    Parameters
    ----------
    x : array_like
        Points, any shape.
    a, b : float
        Shoulder and foot.

    Returns
    -------
    ndarray
        Membership degrees in ``[0, 1]``, shape of ``x``.

    Examples
    --------
    MATLAB's documented example ``linzmf(x, [4 6])``, and the crisp ``a == b``:

    >>> linzmf([3.0, 4.0, 5.0, 6.0, 7.0], 4, 6).tolist()
    [1.0, 1.0, 0.5, 0.0, 0.0]
    >>> linzmf([4.999, 5.0], 5, 5).tolist()
    [1.0, 0.0]
    """
    return LinearZShape(a, b)(x)


@dataclass(frozen=True)
class _Linear(Term):
    a: float
    b: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = self._check()
        if not self.a <= self.b:
            raise ValueError(f"{name}: a={self.a!r} must be <= b={self.b!r}")

    def __call__(self, x: ArrayLike) -> FloatArray:
        kind, p = self.kernel_row()
        if kind is MFKind.STEP:
            return step_row(x, *p[:4])
        return trapezoid_row(x, *p)

    def matlab_params(self) -> tuple[float, ...]:
        return (float(self.a), float(self.b))


@dataclass(frozen=True)
class LinearSShape(_Linear):
    """MATLAB's ``linsmf [a b]``: 0 left of ``a``, rising linearly to ``h`` at ``b``; a step
    up at ``a`` (``h`` for ``x >= a``) when ``a == b``. Requires ``a <= b``.

    The same function as fuzzylite's ``Ramp a b`` for ``a < b``. Monotonic (:meth:`inverse`).
    """

    MATLAB = "linsmf"
    FUZZYLITE = "Ramp"

    def kernel_row(self) -> Row:
        """``TRAPEZOID`` ``(a, b - a, inf, 1, h)``; ``STEP`` ``(a, 1, 1, h, 0)`` if ``a == b``."""
        a, b, h = float(self.a), float(self.b), float(self.h)
        if a == b:
            return MFKind.STEP, (a, 1.0, 1.0, h, 0.0)
        return MFKind.TRAPEZOID, (a, b - a, math.inf, 1.0, h)

    def fuzzylite_params(self) -> tuple[float, ...]:
        if self.a == self.b:
            raise NotImplementedError("a crisp linsmf (a == b) has no fuzzylite Ramp")
        return (float(self.a), float(self.b))

    def inverse(self, w: ArrayLike) -> FloatArray:
        """``a + (b - a) w / h``: the ``x`` where the membership is ``w``."""
        return _scalar(self.a + (self.b - self.a) * _f64(w) / self.h)


@dataclass(frozen=True)
class LinearZShape(_Linear):
    """MATLAB's ``linzmf [a b]``: ``h`` left of ``a``, falling linearly to 0 at ``b``; a step
    down at ``a`` (0 for ``x >= a``) when ``a == b``. Requires ``a <= b``.

    The same function as fuzzylite's ``Ramp b a`` for ``a < b``. Monotonic (:meth:`inverse`).
    """

    MATLAB = "linzmf"
    FUZZYLITE = "Ramp"

    def kernel_row(self) -> Row:
        """``TRAPEZOID`` ``(-inf, 1, b, b - a, h)``; ``STEP`` ``(a, 0, 0, h, 0)`` if ``a == b``."""
        a, b, h = float(self.a), float(self.b), float(self.h)
        if a == b:
            return MFKind.STEP, (a, 0.0, 0.0, h, 0.0)
        return MFKind.TRAPEZOID, (-math.inf, 1.0, b, b - a, h)

    def fuzzylite_params(self) -> tuple[float, ...]:
        if self.a == self.b:
            raise NotImplementedError("a crisp linzmf (a == b) has no fuzzylite Ramp")
        return (float(self.b), float(self.a))

    def inverse(self, w: ArrayLike) -> FloatArray:
        """``b - (b - a) w / h``: the ``x`` where the membership is ``w``."""
        return _scalar(self.b - (self.b - self.a) * _f64(w) / self.h)


@dataclass(frozen=True)
class Ramp(Term):
    """fuzzylite's ``Ramp start end [height]``: 0 at ``start``, ``h`` at ``end`` and beyond,
    linear between (rising if ``start < end``, falling if ``start > end``); ``start != end``.

    Monotonic (:meth:`inverse`: Tsukamoto).
    """

    FUZZYLITE = "Ramp"
    start: float
    end: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = self._check()
        if self.start == self.end:
            raise ValueError(f"{name}: start={self.start!r} must differ from end (fuzzylite's "
                             "Ramp is undefined there)")

    def __call__(self, x: ArrayLike) -> FloatArray:
        return trapezoid_row(x, *self.kernel_row()[1])

    def kernel_row(self) -> Row:
        """``TRAPEZOID``: ``(start, end - start, inf, 1, h)`` rising, ``(-inf, 1, start,
        start - end, h)`` falling."""
        s, e, h = float(self.start), float(self.end), float(self.h)
        if s < e:
            return MFKind.TRAPEZOID, (s, e - s, math.inf, 1.0, h)
        return MFKind.TRAPEZOID, (-math.inf, 1.0, s, s - e, h)

    def inverse(self, w: ArrayLike) -> FloatArray:
        """``start + (end - start) w / h`` (fuzzylite's Tsukamoto value)."""
        return _scalar(self.start + (self.end - self.start) * _f64(w) / self.h)


@dataclass(frozen=True)
class Rectangle(Term):
    """fuzzylite's ``Rectangle start end [height]``: ``h`` on ``[start, end]``, 0 elsewhere;
    ``start < end``."""

    FUZZYLITE = "Rectangle"
    start: float
    end: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = self._check()
        if not self.start < self.end:
            raise ValueError(f"{name}: start={self.start!r} must be < end={self.end!r}")

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = _f64(x)
        return _scalar(np.where((x >= self.start) & (x <= self.end), self.h, 0.0))

    def kernel_row(self) -> Row:
        """``RECTANGLE``: ``p = (start, end, h, 0, 0)``."""
        return MFKind.RECTANGLE, (float(self.start), float(self.end), float(self.h), 0.0, 0.0)


@dataclass(frozen=True)
class Point(Term):
    """A point (jFuzzyLogic's input singleton, ``TERM t := 5;``:
    ``MembershipFunctionSingleton``): ``h`` where ``x == value`` exactly, 0 elsewhere (the
    next float either side included) and at NaN, as jFuzzyLogic's ``in == value``.

    The compiled row is a :class:`Rectangle`'s with ``start == end == value``, the same
    comparisons (``x >= value and x <= value``). Neither MATLAB nor fuzzylite has the term, so
    their writers (and FML's, and the C generators) refuse it; TOML writes it (``point``) and
    FCL reads it.
    """

    value: float
    h: float = 1.0

    def __post_init__(self) -> None:
        self._check()

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = _f64(x)
        return _scalar(np.where((x >= self.value) & (x <= self.value), self.h, 0.0))

    def kernel_row(self) -> Row:
        """``RECTANGLE``: ``p = (value, value, h, 0, 0)``."""
        v = float(self.value)
        return MFKind.RECTANGLE, (v, v, float(self.h), 0.0, 0.0)


@dataclass(frozen=True)
class Binary(Term):
    """fuzzylite's ``Binary start direction [height]``: ``h`` for ``x >= start`` if
    ``direction > start`` (e.g. ``inf``), for ``x <= start`` if ``direction < start``; 0
    elsewhere. ``direction`` may be infinite, not equal to ``start``."""

    FUZZYLITE = "Binary"
    start: float
    direction: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = self._check(infinite_ok=("direction",))
        if self.direction == self.start:
            raise ValueError(f"{name}: direction={self.direction!r} must differ from start")

    def __call__(self, x: ArrayLike) -> FloatArray:
        return step_row(x, *self.kernel_row()[1][:4])

    def kernel_row(self) -> Row:
        """``STEP``: ``p = (start, direction > start, 1, h, 0)``."""
        return MFKind.STEP, (float(self.start), float(self.direction > self.start), 1.0,
                             float(self.h), 0.0)


@dataclass(frozen=True)
class Concave(Term):
    """fuzzylite's ``Concave inflection end [height]``; ``inflection != end``.

    Increasing (``inflection < end``): ``h (end - inflection) / (2 end - inflection - x)`` for
    ``x < end``, ``h`` beyond; decreasing (``inflection > end``):
    ``h (inflection - end) / (inflection - 2 end + x)`` for ``x > end``, ``h`` below. Half
    height at the inflection. Monotonic (:meth:`inverse`: Tsukamoto).
    """

    FUZZYLITE = "Concave"
    inflection: float
    end: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = self._check()
        if self.inflection == self.end:
            raise ValueError(f"{name}: inflection={self.inflection!r} must differ from end")

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = _f64(x)
        i, e = self.inflection, self.end
        with np.errstate(divide="ignore", invalid="ignore"):
            if i < e:
                y = np.where(x < e, (e - i) / ((2.0 * e - i) - x), 1.0)
            else:
                y = np.where(x > e, (i - e) / ((i - 2.0 * e) + x), 1.0)
        return _scalar(self.h * y)

    def kernel_row(self) -> Row:
        """``CONCAVE``: ``p = (inflection, end, h, 0, 0)``."""
        return MFKind.CONCAVE, (float(self.inflection), float(self.end), float(self.h), 0.0,
                                0.0)

    def inverse(self, w: ArrayLike) -> FloatArray:
        """``h (inflection - end) / w + 2 end - inflection`` (fuzzylite's Tsukamoto value)."""
        w = _f64(w)
        i, e = self.inflection, self.end
        with np.errstate(divide="ignore"):
            return _scalar(self.h * (i - e) / w + 2.0 * e - i)


@dataclass(frozen=True)
class Arc(Term):
    """fuzzylite's ``Arc start end [height]``: a quarter circle from 0 at ``start`` to ``h`` at
    ``end`` (and ``h`` beyond), ``h sqrt(r^2 - (x - end)^2) / |r|`` with ``r = end - start``;
    ``start != end``. Monotonic (:meth:`inverse`: Tsukamoto).
    """

    FUZZYLITE = "Arc"
    start: float
    end: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = self._check()
        if self.start == self.end:
            raise ValueError(f"{name}: start={self.start!r} must differ from end")

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = _f64(x)
        s, e = self.start, self.end
        r = e - s
        d = x - e
        arc = np.sqrt(np.maximum(r * r - d * d, 0.0)) / abs(r)
        if s < e:
            y = np.where(x > e, 1.0, np.where(x >= s, arc, 0.0))
        else:
            y = np.where(x < e, 1.0, np.where(x <= s, arc, 0.0))
        return _scalar(self.h * y)

    def kernel_row(self) -> Row:
        """``ARC``: ``p = (start, end, h, 0, 0)``."""
        return MFKind.ARC, (float(self.start), float(self.end), float(self.h), 0.0, 0.0)

    def inverse(self, w: ArrayLike) -> FloatArray:
        """``end -+ sqrt(r^2 - (w r / h)^2)`` (fuzzylite's Tsukamoto value)."""
        w = _f64(w)
        r = self.end - self.start
        sign = -1.0 if self.start < self.end else 1.0
        q = w * r / self.h
        return _scalar(self.end + sign * np.sqrt(np.maximum(r * r - q * q, 0.0)))


@dataclass(frozen=True)
class SemiEllipse(Term):
    """fuzzylite's ``SemiEllipse start end [height]``: ``h sqrt(r^2 - (x - c)^2) / r`` on
    ``[start, end]`` with ``r = (end - start) / 2``, ``c = start + r``; ``start < end``.

    (Where rounding puts ``|x - c|`` a hair above ``r`` at the ends, the root is of 0, not of
    a negative number: fuzzylite gives NaN there.)
    """

    FUZZYLITE = "SemiEllipse"
    start: float
    end: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = self._check()
        if not self.start < self.end:
            raise ValueError(f"{name}: start={self.start!r} must be < end={self.end!r}")

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = _f64(x)
        r = (self.end - self.start) / 2.0
        d = x - (self.start + r)
        y = np.sqrt(np.maximum(r * r - d * d, 0.0)) / r
        return _scalar(self.h * np.where((x >= self.start) & (x <= self.end), y, 0.0))

    def kernel_row(self) -> Row:
        """``SEMI_ELLIPSE``: ``p = (start, end, h, 0, 0)``."""
        return MFKind.SEMI_ELLIPSE, (float(self.start), float(self.end), float(self.h), 0.0,
                                     0.0)


@dataclass(frozen=True, init=False)
class Discrete(Term):
    """fuzzylite's ``Discrete`` term (its pairs ``x_k y_k`` and an optional height): linear
    interpolation of the points, their first / last ``y`` outside them, times ``h``.

    Parameters
    ----------
    points : sequence of (float, float)
        ``(x, y)`` pairs, ``x`` non-decreasing, ``y`` in ``[0, 1]``, at least one.
    h : float
        Height in ``(0, 1]``.

    Examples
    --------
    >>> d = Discrete([(0, 0), (1, 1), (3, 0)])
    >>> d([-1.0, 0.5, 2.0, 9.0]).tolist()
    [0.0, 0.5, 0.5, 0.0]
    """

    FUZZYLITE = "Discrete"
    points: tuple[tuple[float, float], ...]
    h: float = 1.0

    def __init__(self, points: Sequence[Sequence[float]], h: float = 1.0) -> None:
        try:
            pts = tuple((float(p[0]), float(p[1])) for p in points if len(p) == 2)
            ok = len(pts) == len(points) and len(pts) > 0
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ValueError(f"Discrete: points={points!r} must be one or more (x, y) pairs")
        name = f"Discrete(points={pts!r}, h={h!r})"
        for k, (px, py) in enumerate(pts):
            _check_finite(name, **{f"x{k + 1}": px, f"y{k + 1}": py})
            if not 0.0 <= py <= 1.0:
                raise ValueError(f"{name}: y{k + 1}={py!r} must be in [0, 1]")
            if k and px < pts[k - 1][0]:
                raise ValueError(f"{name}: x{k + 1}={px!r} is below x{k}={pts[k - 1][0]!r}; "
                                 "the points must be sorted by x")
        _check_height(name, h)
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "h", h)

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = _f64(x)
        xs = np.array([p[0] for p in self.points])
        ys = np.array([p[1] for p in self.points])
        if xs.size == 1:
            return _scalar(np.full_like(x, self.h * ys[0]))
        j = np.clip(np.searchsorted(xs, x, side="right") - 1, 0, xs.size - 2)
        x0, x1, y0, y1 = xs[j], xs[j + 1], ys[j], ys[j + 1]
        with np.errstate(divide="ignore", invalid="ignore"):
            inner = y0 + (y1 - y0) * ((x - x0) / (x1 - x0))
        y = np.where(x <= xs[0], ys[0], np.where(x >= xs[-1], ys[-1], inner))
        return _scalar(self.h * y)

    def fuzzylite_params(self) -> tuple[float, ...]:
        return tuple(v for p in self.points for v in p)

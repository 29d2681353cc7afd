"""Type-1 membership functions: pure vectorised functions and their frozen dataclass forms.

Every function takes an array ``x`` of any shape and returns membership degrees of the same
shape (numpy broadcasting applies to the parameters too). The dataclasses wrap one parameter set
each, validate it on construction and are callable: ``Triangle(-1, 0, 1)(x)``.

Shoulders follow the IT2FLS-toolbox (and MATLAB) convention: a triangle ``[a b c]`` with
``a == b`` is a *left shoulder* whose value is the height ``h`` for every ``x <= b``; with
``b == c`` it is a *right shoulder*, ``h`` for every ``x >= b``. Trapezoids likewise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import ClassVar, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .kinds import MFKind, Row
from .libm import exp

__all__ = [
    "FootedTrapezoid",
    "Gaussian",
    "MembershipFunction",
    "PiecewiseLinear",
    "Term",
    "Trapezoid",
    "Triangle",
    "UncertainMeanGaussianLower",
    "UncertainMeanGaussianUpper",
    "gaussmf",
    "trapmf",
    "trimf",
]

FloatArray = NDArray[np.float64]


def trapmf(x: ArrayLike, a: float, b: float, c: float, d: float, h: float = 1.0) -> FloatArray:
    """Trapezoidal membership function.

    Parameters
    ----------
    x : array_like
        Points to evaluate, any shape.
    a, b, c, d : float
        Left foot, left shoulder, right shoulder, right foot. Requires ``a <= b <= c <= d``.
        ``a == b`` makes the left side a shoulder (value ``h`` for ``x <= c``); ``c == d`` the
        right side.
    h : float, optional
        Height, ``0 < h <= 1``.

    Returns
    -------
    ndarray
        Membership degrees in ``[0, h]``, shape of ``x``.

    Examples
    --------
    >>> trapmf([-1.0, 0.0, 0.5, 2.0], -1, 0, 1, 2).tolist()
    [0.0, 1.0, 1.0, 0.0]
    """
    x = np.asarray(x, dtype=np.float64)
    left = np.ones_like(x) if a == b else (x - a) / (b - a)
    right = np.ones_like(x) if c == d else (d - x) / (d - c)
    return h * np.clip(np.minimum(left, right), 0.0, 1.0)


def trimf(x: ArrayLike, a: float, b: float, c: float, h: float = 1.0) -> FloatArray:
    """Triangular membership function ``[a b c]`` with height ``h``.

    Requires ``a <= b <= c`` and ``a < c``. ``a == b`` is a left shoulder, ``b == c`` a right
    shoulder (see the module docstring).

    Examples
    --------
    >>> trimf([-1.0, -0.5, 0.0, 0.5, 1.0], -1, 0, 1).tolist()
    [0.0, 0.5, 1.0, 0.5, 0.0]
    >>> trimf([-2.0, -1.0, -0.5], -1, -1, 0).tolist()
    [1.0, 1.0, 0.5]
    """
    return trapmf(x, a, b, b, c, h)


def gaussmf(x: ArrayLike, mean: float, sigma: float, h: float = 1.0) -> FloatArray:
    """Gaussian membership function ``h * exp(-(x - mean)**2 / (2 sigma**2))``, ``sigma > 0``.

    ``exp`` is :func:`it2track.fuzzy.libm.exp` (within 1 ulp of the C library's, and the same
    bits in the numpy and the compiled evaluation).

    Examples
    --------
    >>> float(gaussmf(1.0, 0.0, 1.0))  # doctest: +ELLIPSIS
    0.6065306597...
    """
    x = np.asarray(x, dtype=np.float64)
    z = (x - mean) / sigma
    return h * exp(-0.5 * z * z)  # not np.exp: see .libm (same bits as compiled code)


@runtime_checkable
class MembershipFunction(Protocol):
    """Anything callable on an array returning degrees in ``[0, 1]`` of the same shape."""

    def __call__(self, x: ArrayLike) -> FloatArray: ...


def _check_finite(owner: str, **values: float) -> None:
    for name, value in values.items():
        if not isinstance(value, int | float | np.floating | np.integer) or not math.isfinite(
            value
        ):
            raise ValueError(f"{owner}: parameter {name}={value!r} must be a finite number")


def _check_height(owner: str, h: float) -> None:
    if not 0.0 < h <= 1.0:
        raise ValueError(f"{owner}: height h={h!r} must satisfy 0 < h <= 1")


class Term:
    """Base of the membership classes of :mod:`.curves` and :mod:`.shapes` (fuzzylite's one
    class per term): each is a frozen dataclass of its parameters (height ``h`` last), checks
    them on construction, evaluates itself (``term(x)``), lowers itself to a row of the
    compiled kernels (:meth:`kernel_row`) and names itself in MATLAB's and fuzzylite's
    vocabulary (:attr:`MATLAB`, :meth:`matlab_params`, :attr:`FUZZYLITE`,
    :meth:`fuzzylite_params`; see :mod:`.terms` for the factories every reader and writer
    goes through).
    """

    #: MATLAB's name of the function (``"gbellmf"``), ``None`` if MATLAB has none.
    MATLAB: ClassVar[str | None] = None
    #: fuzzylite's name of the term (``"Bell"``), ``None`` if fuzzylite has none.
    FUZZYLITE: ClassVar[str | None] = None

    def __call__(self, x: ArrayLike) -> FloatArray:
        raise NotImplementedError

    def kernel_row(self) -> Row:
        """``(kind, 5 parameters)`` of the compiled kernels (:class:`~.kinds.MFKind`)."""
        return MFKind.OTHER, (0.0, 0.0, 0.0, 0.0, 0.0)

    def matlab_params(self) -> tuple[float, ...]:
        """The parameter vector of :attr:`MATLAB` (its documented order), height excluded."""
        raise NotImplementedError(f"{type(self).__name__} has no MATLAB membership function")

    def fuzzylite_params(self) -> tuple[float, ...]:
        """The parameters of :attr:`FUZZYLITE` in fuzzylite's order, height excluded."""
        return tuple(float(getattr(self, f.name)) for f in fields(self)  # type: ignore[arg-type]
                     if f.name != "h")

    def _name(self) -> str:
        values = ", ".join(f"{f.name}={getattr(self, f.name)!r}"
                           for f in fields(self))  # type: ignore[arg-type]
        return f"{type(self).__name__}({values})"

    def _check(self, *, nonzero: tuple[str, ...] = (), positive: tuple[str, ...] = (),
               infinite_ok: tuple[str, ...] = ()) -> str:
        """Check finiteness (but ``infinite_ok``), ``!= 0``, ``> 0`` and the height; returns
        the term's name for further messages."""
        name = self._name()
        finite = {f.name: getattr(self, f.name) for f in fields(self)  # type: ignore[arg-type]
                  if f.name not in infinite_ok}
        _check_finite(name, **finite)
        for key in infinite_ok:
            value = getattr(self, key)
            if not isinstance(value, int | float | np.floating | np.integer) or math.isnan(value):
                raise ValueError(f"{name}: parameter {key}={value!r} must be a number")
        for key in nonzero:
            if getattr(self, key) == 0:
                raise ValueError(f"{name}: {key}={getattr(self, key)!r} must be != 0")
        for key in positive:
            if not getattr(self, key) > 0:
                raise ValueError(f"{name}: {key}={getattr(self, key)!r} must be > 0")
        _check_height(name, getattr(self, "h", 1.0))
        return name


class PiecewiseLinear:
    """Marker base class for trapezoids and triangles.

    Subclasses expose ``as_trapezoid() -> (a, b, c, d, h)``, which lets a fuzzy system evaluate
    all its piecewise-linear sets in one vectorised pass.
    """

    def as_trapezoid(self) -> tuple[float, float, float, float, float]:
        raise NotImplementedError

    def __call__(self, x: ArrayLike) -> FloatArray:
        return trapmf(x, *self.as_trapezoid())

    def breakpoints(self) -> tuple[float, ...]:
        """The corner abscissae, where a piecewise-linear function can change slope."""
        a, b, c, d, _ = self.as_trapezoid()
        return (a, b, c, d)


@dataclass(frozen=True)
class Trapezoid(PiecewiseLinear):
    """Trapezoid ``[a b c d]`` with height ``h``; requires ``a <= b <= c <= d``, ``a < d``."""

    a: float
    b: float
    c: float
    d: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = f"Trapezoid({self.a}, {self.b}, {self.c}, {self.d}, h={self.h})"
        _check_finite(name, a=self.a, b=self.b, c=self.c, d=self.d, h=self.h)
        if not (self.a <= self.b <= self.c <= self.d) or self.a == self.d:
            raise ValueError(f"{name}: feet and shoulders must satisfy a <= b <= c <= d, a < d")
        _check_height(name, self.h)

    def as_trapezoid(self) -> tuple[float, float, float, float, float]:
        return (float(self.a), float(self.b), float(self.c), float(self.d), float(self.h))


@dataclass(frozen=True)
class FootedTrapezoid(Term):
    """A trapezoid ``[a b c d]`` (height ``h``) that is 0 outside its feet ``[a, d]`` even
    where a side is vertical (``a == b``: it rises to ``h`` at ``a``; ``c == d``: it drops to
    0 after ``d``): MATLAB's ``trapmf``/``trimf``, fuzzylite's and jFuzzyLogic's trapezoids
    and triangles, where :class:`Trapezoid` keeps a shoulder's height beyond it. Between the
    feet (both included) it equals ``Trapezoid(a, b, c, d, h)``. Evaluated by numpy.

    Examples
    --------
    >>> FootedTrapezoid(1, 1, 2, 3)(np.array([0.5, 1.0, 2.5, 3.5])).tolist()
    [0.0, 1.0, 0.5, 0.0]
    """

    FUZZYLITE = "Trapezoid"
    a: float
    b: float
    c: float
    d: float
    h: float = 1.0

    def __post_init__(self) -> None:
        Trapezoid(self.a, self.b, self.c, self.d, self.h)  # the same checks

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = np.asarray(x, dtype=np.float64)
        y = trapmf(x, self.a, self.b, self.c, self.d, self.h)
        return np.where((x < self.a) | (x > self.d), 0.0, y)


@dataclass(frozen=True)
class Triangle(PiecewiseLinear):
    """Triangle ``[a b c]`` with height ``h`` (IT2FLS toolbox ``[a b c h]``).

    Requires ``a <= b <= c`` and ``a < c``. ``a == b``: left shoulder; ``b == c``: right shoulder.
    """

    a: float
    b: float
    c: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = f"Triangle({self.a}, {self.b}, {self.c}, h={self.h})"
        _check_finite(name, a=self.a, b=self.b, c=self.c, h=self.h)
        if not (self.a <= self.b <= self.c) or self.a == self.c:
            raise ValueError(f"{name}: feet and peak must satisfy a <= b <= c, a < c")
        _check_height(name, self.h)

    def as_trapezoid(self) -> tuple[float, float, float, float, float]:
        return (float(self.a), float(self.b), float(self.b), float(self.c), float(self.h))


@dataclass(frozen=True)
class Gaussian:
    """Gaussian ``h * exp(-(x - mean)^2 / (2 sigma^2))``; requires ``sigma > 0``."""

    mean: float
    sigma: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = f"Gaussian(mean={self.mean}, sigma={self.sigma}, h={self.h})"
        _check_finite(name, mean=self.mean, sigma=self.sigma, h=self.h)
        if self.sigma <= 0:
            raise ValueError(f"{name}: sigma={self.sigma!r} must be > 0")
        _check_height(name, self.h)

    def __call__(self, x: ArrayLike) -> FloatArray:
        return gaussmf(x, self.mean, self.sigma, self.h)


@dataclass(frozen=True)
class _UncertainMeanGaussian:
    """Parameters shared by the two bounds of a Gaussian with uncertain mean in ``[m1, m2]``:
    ``sigma > 0`` is the common standard deviation, ``h`` the height."""

    m1: float
    m2: float
    sigma: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = f"{type(self).__name__}(m1={self.m1}, m2={self.m2}, sigma={self.sigma})"
        _check_finite(name, m1=self.m1, m2=self.m2, sigma=self.sigma, h=self.h)
        if self.m1 > self.m2:
            raise ValueError(f"{name}: means must satisfy m1 <= m2")
        if self.sigma <= 0:
            raise ValueError(f"{name}: sigma={self.sigma!r} must be > 0")
        _check_height(name, self.h)


@dataclass(frozen=True)
class UncertainMeanGaussianUpper(_UncertainMeanGaussian):
    """Upper MF of a Gaussian with uncertain mean in ``[m1, m2]``: flat top ``h`` between means.

    ``sigma > 0`` is the common standard deviation, ``h`` the height.
    """

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = np.asarray(x, dtype=np.float64)
        nearest = np.clip(x, self.m1, self.m2)
        return gaussmf(x - nearest, 0.0, self.sigma, self.h)


@dataclass(frozen=True)
class UncertainMeanGaussianLower(_UncertainMeanGaussian):
    """Lower MF of a Gaussian with uncertain mean in ``[m1, m2]``: the smaller of the two.

    ``sigma > 0`` is the common standard deviation, ``h`` the height.
    """

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = np.asarray(x, dtype=np.float64)
        farthest = np.where(x <= 0.5 * (self.m1 + self.m2), self.m2, self.m1)
        return gaussmf(x - farthest, 0.0, self.sigma, self.h)

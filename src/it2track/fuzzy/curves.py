"""Smooth membership curves: bell, sigmoids, spline S/Z/Pi shapes, two-sided Gaussian,
cosine and spike -- MATLAB's ``gbellmf``, ``sigmf``, ``dsigmf``, ``psigmf``, ``smf``,
``zmf``, ``pimf``, ``gauss2mf`` and fuzzylite's ``Bell``, ``Sigmoid``, ``SigmoidDifference``,
``SigmoidProduct``, ``SShape``, ``ZShape``, ``PiShape``, ``GaussianProduct``, ``Cosine``,
``Spike``.

Each shape is a pure function in MATLAB's parameter order (``gbellmf(x, a, b, c)``) and a
frozen class in fuzzylite's (``Bell(center, width, slope, h)``); both compute the same bits.
The formulas are the documented ones (MATLAB's Fuzzy Logic Toolbox reference pages, fuzzylite's
term documentation), quoted in each docstring; ``exp``, ``log`` and ``cos`` come from
:mod:`it2track.fuzzy.libm`, so that the compiled kernels give the same bits. The classes add a
height ``h`` in ``(0, 1]`` (fuzzylite's ``height``; MATLAB's functions have none: ``h = 1``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .kinds import MFKind, Row
from .libm import cospi, exp, log
from .membership import Term

__all__ = [
    "Bell",
    "Cosine",
    "GaussianProduct",
    "PiShape",
    "SShape",
    "Sigmoid",
    "SigmoidDifference",
    "SigmoidProduct",
    "Spike",
    "ZShape",
    "dsigmf",
    "gauss2mf",
    "gbellmf",
    "pimf",
    "psigmf",
    "sigmf",
    "smf",
    "zmf",
]

FloatArray = NDArray[np.float64]


def _f64(x: ArrayLike) -> FloatArray:
    return np.asarray(x, dtype=np.float64)


def _scalar(y: FloatArray) -> FloatArray:
    return y[()] if y.ndim == 0 else y


#: Exponents ``2 slope`` of a bell up to this, if whole numbers, are powers by squaring.
MAX_SQUARING = 1 << 20


def integer_power(t: FloatArray, n: int) -> FloatArray:
    """``t ** n`` for a whole ``n >= 1`` by binary squaring (exact where the result is
    representable, as ``2 ** 8``); the compiled kernels do the same multiplications."""
    result = np.ones_like(t)
    base = t
    while n:
        if n & 1:
            result = result * base
        n >>= 1
        if n:
            base = base * base
    return result


def _bell(x: FloatArray, center: float, width: float, slope: float) -> FloatArray:
    n = 2.0 * slope
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        t = np.abs((x - center) / width)
        if n == int(n) and n <= MAX_SQUARING:
            p = integer_power(t, int(n))
        else:
            p = exp(n * log(t))  # |t|^(2 slope); t = 0 gives exp(-inf) = 0
        return 1.0 / (1.0 + p)


def _sigmoid(x: FloatArray, inflection: float, slope: float) -> FloatArray:
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + exp(-slope * (x - inflection)))


def _s_shape(x: FloatArray, a: float, b: float) -> FloatArray:
    w = b - a
    mid = (a + b) / 2.0
    q1 = (x - a) / w
    q2 = (x - b) / w
    return np.where(x <= a, 0.0, np.where(x <= mid, 2.0 * (q1 * q1),
                    np.where(x < b, 1.0 - 2.0 * (q2 * q2), 1.0)))  # fmt: skip


def _z_shape(x: FloatArray, a: float, b: float) -> FloatArray:
    w = b - a
    mid = (a + b) / 2.0
    q1 = (x - a) / w
    q2 = (x - b) / w
    return np.where(x <= a, 1.0, np.where(x <= mid, 1.0 - 2.0 * (q1 * q1),
                    np.where(x < b, 2.0 * (q2 * q2), 0.0)))  # fmt: skip


def _gaussian_product(x: FloatArray, ma: float, sa: float, mb: float, sb: float) -> FloatArray:
    za = np.minimum(x - ma, 0.0) / sa
    zb = np.maximum(x - mb, 0.0) / sb
    return exp(-0.5 * za * za) * exp(-0.5 * zb * zb)


# -- MATLAB's functions -----------------------------------------------------------------------
def gbellmf(x: ArrayLike, a: float, b: float, c: float) -> FloatArray:
    """MATLAB's generalized bell ``gbellmf(x, [a b c])``.

    MATLAB documents ``f(x; a, b, c) = 1 / (1 + |(x - c) / a|^(2b))``: ``a`` the half width
    (``f(c +- a) = 1/2``), ``b`` the slope, ``c`` the centre. Here ``a != 0`` and ``b > 0``
    (see :class:`Bell`); the power is by squaring when ``2 b`` is a whole number (up to
    :data:`MAX_SQUARING`), else ``exp(2 b log|t|)`` (:mod:`it2track.fuzzy.libm`).

    Parameters
    ----------
    x : array_like
        Points, any shape.
    a, b, c : float
        Width, slope, centre (MATLAB's ``params = [a b c]``).

    Returns
    -------
    ndarray
        Membership degrees in ``[0, 1]``, shape of ``x``.

    Examples
    --------
    MATLAB's documentation plots ``gbellmf(x, [2 4 6])``: 1 at the centre, 1/2 at ``c +- a``:

    >>> gbellmf([6.0, 4.0, 8.0, 2.0], 2, 4, 6).tolist()  # 1/(1 + 2^8) at x = 2
    [1.0, 0.5, 0.5, 0.0038910505836575876]
    """
    return Bell(c, a, b)(x)


def sigmf(x: ArrayLike, a: float, c: float) -> FloatArray:
    """MATLAB's sigmoid ``sigmf(x, [a c]) = 1 / (1 + exp(-a (x - c)))``.

    ``a`` is the slope (its sign opens the curve to the right or the left), ``c`` the
    crossover point (``sigmf(c) = 1/2``); ``a != 0``.

    Parameters
    ----------
    x : array_like
        Points, any shape.
    a, c : float
        Slope and crossover (MATLAB's ``params = [a c]``).

    Returns
    -------
    ndarray
        Membership degrees in ``[0, 1]``, shape of ``x``.

    Examples
    --------
    MATLAB's documented example ``sigmf(x, [2 4])``:

    >>> sigmf([4.0, 0.0, 10.0], 2, 4).round(6).tolist()
    [0.5, 0.000335, 0.999994]
    """
    return Sigmoid(c, a)(x)


def dsigmf(x: ArrayLike, a1: float, c1: float, a2: float, c2: float) -> FloatArray:
    """MATLAB's difference of two sigmoids ``dsigmf(x, [a1 c1 a2 c2])``.

    ``|f1(x) - f2(x)|`` with ``fk(x) = 1 / (1 + exp(-ak (x - ck)))`` (MATLAB's and fuzzylite's
    ``SigmoidDifference``, both taking the absolute value).

    Parameters
    ----------
    x : array_like
        Points, any shape.
    a1, c1, a2, c2 : float
        Slope and crossover of the first and of the second sigmoid.

    Returns
    -------
    ndarray
        Membership degrees in ``[0, 1]``, shape of ``x``.

    Examples
    --------
    MATLAB's documented example ``dsigmf(x, [5 2 5 7])``, a plateau between 2 and 7:

    >>> dsigmf([4.5, 0.0, 10.0], 5, 2, 5, 7).round(6).tolist()
    [0.999993, 4.5e-05, 0.0]
    """
    return SigmoidDifference(c1, a1, a2, c2)(x)


def psigmf(x: ArrayLike, a1: float, c1: float, a2: float, c2: float) -> FloatArray:
    """MATLAB's product of two sigmoids ``psigmf(x, [a1 c1 a2 c2]) = f1(x) f2(x)``.

    ``fk(x) = 1 / (1 + exp(-ak (x - ck)))``.

    Parameters
    ----------
    x : array_like
        Points, any shape.
    a1, c1, a2, c2 : float
        Slope and crossover of the first and of the second sigmoid.

    Returns
    -------
    ndarray
        Membership degrees in ``[0, 1]``, shape of ``x``.

    Examples
    --------
    MATLAB's documented example ``psigmf(x, [2 3 -5 8])``:

    >>> psigmf([3.0, 8.0], 2, 3, -5, 8).round(6).tolist()
    [0.5, 0.499977]
    """
    return SigmoidProduct(c1, a1, a2, c2)(x)


def smf(x: ArrayLike, a: float, b: float) -> FloatArray:
    """MATLAB's spline S-shaped ``smf(x, [a b])``, ``a < b``.

    MATLAB documents ``0`` for ``x <= a``; ``2 ((x - a) / (b - a))^2`` for
    ``a <= x <= (a + b) / 2``; ``1 - 2 ((x - b) / (b - a))^2`` for ``(a + b) / 2 <= x <= b``;
    ``1`` for ``x >= b``.

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
    MATLAB's documented example ``smf(x, [1 8])``:

    >>> smf([1.0, 2.75, 4.5, 8.0], 1, 8).tolist()
    [0.0, 0.125, 0.5, 1.0]
    """
    return SShape(a, b)(x)


def zmf(x: ArrayLike, a: float, b: float) -> FloatArray:
    """MATLAB's spline Z-shaped ``zmf(x, [a b])``, ``a < b``: the mirror of :func:`smf`.

    MATLAB documents ``1`` for ``x <= a``; ``1 - 2 ((x - a) / (b - a))^2`` for
    ``a <= x <= (a + b) / 2``; ``2 ((x - b) / (b - a))^2`` for ``(a + b) / 2 <= x <= b``;
    ``0`` for ``x >= b``.

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
    MATLAB's documented example ``zmf(x, [3 7])``:

    >>> zmf([3.0, 4.0, 5.0, 7.0], 3, 7).tolist()
    [1.0, 0.875, 0.5, 0.0]
    """
    return ZShape(a, b)(x)


def pimf(x: ArrayLike, a: float, b: float, c: float, d: float) -> FloatArray:
    """MATLAB's spline Pi-shaped ``pimf(x, [a b c d]) = smf(x, [a b]) zmf(x, [c d])``.

    Feet ``a``, ``d``, shoulders ``b``, ``c``; ``a < b <= c < d``.

    Parameters
    ----------
    x : array_like
        Points, any shape.
    a, b, c, d : float
        Left foot, left shoulder, right shoulder, right foot.

    Returns
    -------
    ndarray
        Membership degrees in ``[0, 1]``, shape of ``x``.

    Examples
    --------
    MATLAB's documented example ``pimf(x, [1 4 5 10])``:

    >>> pimf([1.0, 2.5, 4.5, 7.5, 10.0], 1, 4, 5, 10).tolist()
    [0.0, 0.5, 1.0, 0.5, 0.0]
    """
    return PiShape(a, b, c, d)(x)


def gauss2mf(x: ArrayLike, sig1: float, c1: float, sig2: float, c2: float) -> FloatArray:
    """MATLAB's two-sided Gaussian ``gauss2mf(x, [sig1 c1 sig2 c2])``.

    The Gaussian ``exp(-(x - c1)^2 / (2 sig1^2))`` left of ``c1`` times the Gaussian of
    ``(sig2, c2)`` right of ``c2`` (each 1 on its other side): flat 1 between ``c1`` and ``c2``
    when ``c1 <= c2``.

    Parameters
    ----------
    x : array_like
        Points, any shape.
    sig1, c1, sig2, c2 : float
        Standard deviation and mean of the left and of the right Gaussian; ``sig1, sig2 > 0``.

    Returns
    -------
    ndarray
        Membership degrees in ``[0, 1]``, shape of ``x``.

    Examples
    --------
    MATLAB's documented example ``gauss2mf(x, [2 4 1 8])``:

    >>> gauss2mf([4.0, 6.0, 8.0, 9.0], 2, 4, 1, 8).round(6).tolist()
    [1.0, 1.0, 1.0, 0.606531]
    """
    return GaussianProduct(c1, sig1, c2, sig2)(x)


# -- the classes ------------------------------------------------------------------------------
@dataclass(frozen=True)
class Bell(Term):
    """Generalised bell ``h / (1 + |(x - center) / width|^(2 slope))``.

    MATLAB ``gbellmf [a b c]`` = ``Bell(center=c, width=a, slope=b)``; fuzzylite
    ``Bell center width slope [height]``. Requires ``width != 0`` and ``slope > 0``;
    ``Bell(c, a, b)(c +- a) == h / 2`` exactly.
    """

    MATLAB = "gbellmf"
    FUZZYLITE = "Bell"
    center: float
    width: float
    slope: float
    h: float = 1.0

    def __post_init__(self) -> None:
        self._check(nonzero=("width",), positive=("slope",))

    def __call__(self, x: ArrayLike) -> FloatArray:
        return _scalar(self.h * _bell(_f64(x), self.center, self.width, self.slope))

    def kernel_row(self) -> Row:
        """``BELL``: ``p = (center, width, 2 slope, h, 0)``."""
        return MFKind.BELL, (float(self.center), float(self.width), 2.0 * self.slope,
                             float(self.h), 0.0)

    def matlab_params(self) -> tuple[float, ...]:
        return (float(self.width), float(self.slope), float(self.center))


@dataclass(frozen=True)
class Sigmoid(Term):
    """Sigmoid ``h / (1 + exp(-slope (x - inflection)))``; ``slope != 0``.

    MATLAB ``sigmf [a c]`` = ``Sigmoid(inflection=c, slope=a)``; fuzzylite
    ``Sigmoid inflection slope [height]``. Monotonic (:meth:`inverse`: Tsukamoto).
    """

    MATLAB = "sigmf"
    FUZZYLITE = "Sigmoid"
    inflection: float
    slope: float
    h: float = 1.0

    def __post_init__(self) -> None:
        self._check(nonzero=("slope",))

    def __call__(self, x: ArrayLike) -> FloatArray:
        return _scalar(self.h * _sigmoid(_f64(x), self.inflection, self.slope))

    def kernel_row(self) -> Row:
        """``SIGMOID``: ``p = (inflection, slope, h, 0, 0)``."""
        return MFKind.SIGMOID, (float(self.inflection), float(self.slope), float(self.h),
                                0.0, 0.0)

    def matlab_params(self) -> tuple[float, ...]:
        return (float(self.slope), float(self.inflection))

    def inverse(self, w: ArrayLike) -> FloatArray:
        """The ``x`` where the membership is ``w`` in ``(0, h)``:
        ``inflection - log(h / w - 1) / slope`` (fuzzylite's Tsukamoto value)."""
        w = _f64(w)
        with np.errstate(divide="ignore", invalid="ignore"):
            return _scalar(self.inflection + log(self.h / w - 1.0) / -self.slope)


@dataclass(frozen=True)
class _TwoSigmoids(Term):
    left: float
    rising: float
    falling: float
    right: float
    h: float = 1.0

    def __post_init__(self) -> None:
        self._check(nonzero=("rising", "falling"))

    def _pair(self, x: ArrayLike) -> tuple[FloatArray, FloatArray]:
        x = _f64(x)
        return _sigmoid(x, self.left, self.rising), _sigmoid(x, self.right, self.falling)

    def matlab_params(self) -> tuple[float, ...]:
        return (float(self.rising), float(self.left), float(self.falling), float(self.right))

    def _params(self) -> tuple[float, float, float, float, float]:
        return (float(self.left), float(self.rising), float(self.right), float(self.falling),
                float(self.h))


@dataclass(frozen=True)
class SigmoidDifference(_TwoSigmoids):
    """``h |s1(x) - s2(x)|`` of the sigmoids ``s1 = Sigmoid(left, rising)`` and
    ``s2 = Sigmoid(right, falling)``; ``rising, falling != 0``.

    MATLAB ``dsigmf [a1 c1 a2 c2]`` = ``SigmoidDifference(left=c1, rising=a1, falling=a2,
    right=c2)``; fuzzylite ``SigmoidDifference left rising falling right [height]``.
    """

    MATLAB = "dsigmf"
    FUZZYLITE = "SigmoidDifference"

    def __call__(self, x: ArrayLike) -> FloatArray:
        a, b = self._pair(x)
        return _scalar(self.h * np.abs(a - b))

    def kernel_row(self) -> Row:
        """``SIGMOID_DIFFERENCE``: ``p = (left, rising, right, falling, h)``."""
        return MFKind.SIGMOID_DIFFERENCE, self._params()


@dataclass(frozen=True)
class SigmoidProduct(_TwoSigmoids):
    """``h s1(x) s2(x)`` of the sigmoids ``s1 = Sigmoid(left, rising)`` and
    ``s2 = Sigmoid(right, falling)``; ``rising, falling != 0``.

    MATLAB ``psigmf [a1 c1 a2 c2]`` = ``SigmoidProduct(left=c1, rising=a1, falling=a2,
    right=c2)``; fuzzylite ``SigmoidProduct left rising falling right [height]``.
    """

    MATLAB = "psigmf"
    FUZZYLITE = "SigmoidProduct"

    def __call__(self, x: ArrayLike) -> FloatArray:
        a, b = self._pair(x)
        return _scalar(self.h * (a * b))

    def kernel_row(self) -> Row:
        """``SIGMOID_PRODUCT``: ``p = (left, rising, right, falling, h)``."""
        return MFKind.SIGMOID_PRODUCT, self._params()


@dataclass(frozen=True)
class _Spline(Term):
    start: float
    end: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = self._check()
        if not self.start < self.end:
            raise ValueError(f"{name}: start={self.start!r} must be < end={self.end!r}")

    def matlab_params(self) -> tuple[float, ...]:
        return (float(self.start), float(self.end))

    def _row(self, kind: MFKind) -> Row:
        return kind, (float(self.start), float(self.end), float(self.h), 0.0, 0.0)

    def _sqrt(self, v: FloatArray) -> FloatArray:
        return np.sqrt(v / (2.0 * self.h))


@dataclass(frozen=True)
class SShape(_Spline):
    """Spline S-shape from 0 at ``start`` to ``h`` at ``end`` (``start < end``), 1/2 of ``h``
    at the midpoint.

    MATLAB ``smf [a b]`` = ``SShape(start=a, end=b)`` (formula in :func:`smf`); fuzzylite
    ``SShape start end [height]``. Monotonic (:meth:`inverse`: Tsukamoto).
    """

    MATLAB = "smf"
    FUZZYLITE = "SShape"

    def __call__(self, x: ArrayLike) -> FloatArray:
        return _scalar(self.h * _s_shape(_f64(x), self.start, self.end))

    def kernel_row(self) -> Row:
        """``S_SHAPE``: ``p = (start, end, h, 0, 0)``."""
        return self._row(MFKind.S_SHAPE)

    def inverse(self, w: ArrayLike) -> FloatArray:
        """The ``x`` where the membership is ``w`` in ``[0, h]`` (fuzzylite's Tsukamoto)."""
        w = _f64(w)
        s, e = self.start, self.end
        with np.errstate(invalid="ignore"):
            return _scalar(np.where(w <= self.h / 2.0, s + (e - s) * self._sqrt(w),
                                    e - (e - s) * self._sqrt(self.h - w)))


@dataclass(frozen=True)
class ZShape(_Spline):
    """Spline Z-shape from ``h`` at ``start`` to 0 at ``end`` (``start < end``).

    MATLAB ``zmf [a b]`` = ``ZShape(start=a, end=b)`` (formula in :func:`zmf`); fuzzylite
    ``ZShape start end [height]``. Monotonic (:meth:`inverse`: Tsukamoto).
    """

    MATLAB = "zmf"
    FUZZYLITE = "ZShape"

    def __call__(self, x: ArrayLike) -> FloatArray:
        return _scalar(self.h * _z_shape(_f64(x), self.start, self.end))

    def kernel_row(self) -> Row:
        """``Z_SHAPE``: ``p = (start, end, h, 0, 0)``."""
        return self._row(MFKind.Z_SHAPE)

    def inverse(self, w: ArrayLike) -> FloatArray:
        """The ``x`` where the membership is ``w`` in ``[0, h]`` (fuzzylite's Tsukamoto)."""
        w = _f64(w)
        s, e = self.start, self.end
        with np.errstate(invalid="ignore"):
            return _scalar(np.where(w <= self.h / 2.0, e - (e - s) * self._sqrt(w),
                                    s + (e - s) * self._sqrt(self.h - w)))


@dataclass(frozen=True)
class PiShape(Term):
    """``h SShape(bottom_left, top_left)(x) ZShape(top_right, bottom_right)(x)``; requires
    ``bottom_left < top_left <= top_right < bottom_right``.

    MATLAB ``pimf [a b c d]`` = ``PiShape(a, b, c, d)``; fuzzylite
    ``PiShape bottomLeft topLeft topRight bottomRight [height]``.
    """

    MATLAB = "pimf"
    FUZZYLITE = "PiShape"
    bottom_left: float
    top_left: float
    top_right: float
    bottom_right: float
    h: float = 1.0

    def __post_init__(self) -> None:
        name = self._check()
        if not self.bottom_left < self.top_left <= self.top_right < self.bottom_right:
            raise ValueError(f"{name}: parameters must satisfy bottom_left < top_left <= "
                             "top_right < bottom_right")

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = _f64(x)
        s = _s_shape(x, self.bottom_left, self.top_left)
        z = _z_shape(x, self.top_right, self.bottom_right)
        return _scalar(self.h * (s * z))

    def kernel_row(self) -> Row:
        """``PI_SHAPE``: ``p = (bottom_left, top_left, top_right, bottom_right, h)``."""
        return MFKind.PI_SHAPE, (float(self.bottom_left), float(self.top_left),
                                 float(self.top_right), float(self.bottom_right), float(self.h))

    def matlab_params(self) -> tuple[float, ...]:
        return self.fuzzylite_params()


@dataclass(frozen=True)
class GaussianProduct(Term):
    """Two-sided Gaussian: the Gaussian ``(mean_a, sigma_a)`` left of ``mean_a`` times the
    Gaussian ``(mean_b, sigma_b)`` right of ``mean_b`` (each 1 on its other side), times ``h``.

    MATLAB ``gauss2mf [sig1 c1 sig2 c2]`` = ``GaussianProduct(c1, sig1, c2, sig2)``; fuzzylite
    ``GaussianProduct meanA standardDeviationA meanB standardDeviationB [height]``.
    ``sigma_a, sigma_b > 0``; any means (``mean_a > mean_b`` peaks below ``h``).
    """

    MATLAB = "gauss2mf"
    FUZZYLITE = "GaussianProduct"
    mean_a: float
    sigma_a: float
    mean_b: float
    sigma_b: float
    h: float = 1.0

    def __post_init__(self) -> None:
        self._check(positive=("sigma_a", "sigma_b"))

    def __call__(self, x: ArrayLike) -> FloatArray:
        return _scalar(self.h * _gaussian_product(_f64(x), self.mean_a, self.sigma_a,
                                                  self.mean_b, self.sigma_b))

    def kernel_row(self) -> Row:
        """``GAUSSIAN_PRODUCT``: ``p = (mean_a, sigma_a, mean_b, sigma_b, h)``."""
        return MFKind.GAUSSIAN_PRODUCT, (float(self.mean_a), float(self.sigma_a),
                                         float(self.mean_b), float(self.sigma_b), float(self.h))

    def matlab_params(self) -> tuple[float, ...]:
        return (float(self.sigma_a), float(self.mean_a), float(self.sigma_b),
                float(self.mean_b))


@dataclass(frozen=True)
class Cosine(Term):
    """Raised cosine ``h (1 + cos(2 pi (x - center) / width)) / 2`` on
    ``|x - center| <= width / 2``, 0 outside; ``width > 0``.

    fuzzylite ``Cosine center width [height]`` (MATLAB has none). ``cos`` is
    :func:`~.libm.cospi`: exactly ``h`` at the centre, ``h / 2`` at ``center +- width / 4`` and
    0 at the ends.
    """

    FUZZYLITE = "Cosine"
    center: float
    width: float
    h: float = 1.0

    def __post_init__(self) -> None:
        self._check(positive=("width",))

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = _f64(x)
        half = 0.5 * self.width
        inside = (x >= self.center - half) & (x <= self.center + half)
        u = np.where(inside, (x - self.center) / half, 1.0)
        return _scalar(self.h * np.where(inside, 0.5 * (1.0 + cospi(u)), 0.0))

    def kernel_row(self) -> Row:
        """``COSINE``: ``p = (center, width, h, 0, 0)``."""
        return MFKind.COSINE, (float(self.center), float(self.width), float(self.h), 0.0, 0.0)


@dataclass(frozen=True)
class Spike(Term):
    """Spike ``h exp(-|10 (x - center) / width|)``; ``width != 0``.

    fuzzylite ``Spike center width [height]`` (MATLAB has none).
    """

    FUZZYLITE = "Spike"
    center: float
    width: float
    h: float = 1.0

    def __post_init__(self) -> None:
        self._check(nonzero=("width",))

    def __call__(self, x: ArrayLike) -> FloatArray:
        x = _f64(x)
        return _scalar(self.h * exp(-np.abs(10.0 / self.width * (x - self.center))))

    def kernel_row(self) -> Row:
        """``SPIKE``: ``p = (center, width, h, 0, 0)``."""
        return MFKind.SPIKE, (float(self.center), float(self.width), float(self.h), 0.0, 0.0)

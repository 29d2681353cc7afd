"""Smooth membership curves: bell, two-sided Gaussian, cosine and spike -- MATLAB's
``gbellmf``, ``gauss2mf`` and fuzzylite's ``Bell``, ``GaussianProduct``, ``Cosine``, ``Spike``;
the sigmoids are in :mod:`.sigmoids`, the S/Z/Pi splines in :mod:`.splines`.

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
    "Spike",
    "gauss2mf",
    "gbellmf",
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


def _gaussian_product(x: FloatArray, ma: float, sa: float, mb: float, sb: float) -> FloatArray:
    za = np.minimum(x - ma, 0.0) / sa
    zb = np.maximum(x - mb, 0.0) / sb
    return exp(-0.5 * za * za) * exp(-0.5 * zb * zb)


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

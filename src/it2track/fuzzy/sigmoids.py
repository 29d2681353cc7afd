"""Sigmoid membership functions: MATLAB's ``sigmf``, ``dsigmf``, ``psigmf`` and fuzzylite's
``Sigmoid``, ``SigmoidDifference``, ``SigmoidProduct`` (conventions as in :mod:`.curves`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .kinds import MFKind, Row
from .libm import exp, log
from .membership import Term

__all__ = [
    "Sigmoid",
    "SigmoidDifference",
    "SigmoidProduct",
    "dsigmf",
    "psigmf",
    "sigmf",
]

FloatArray = NDArray[np.float64]


def _f64(x: ArrayLike) -> FloatArray:
    return np.asarray(x, dtype=np.float64)


def _scalar(y: FloatArray) -> FloatArray:
    return y[()] if y.ndim == 0 else y


#: Exponents ``2 slope`` of a bell up to this, if whole numbers, are powers by squaring.


def _sigmoid(x: FloatArray, inflection: float, slope: float) -> FloatArray:
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + exp(-slope * (x - inflection)))


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

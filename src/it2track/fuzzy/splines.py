"""Spline membership functions: MATLAB's ``smf``, ``zmf``, ``pimf`` and fuzzylite's
``SShape``, ``ZShape``, ``PiShape`` (conventions as in :mod:`.curves`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .kinds import MFKind, Row
from .membership import Term

__all__ = [
    "PiShape",
    "SShape",
    "ZShape",
    "pimf",
    "smf",
    "zmf",
]

FloatArray = NDArray[np.float64]


def _f64(x: ArrayLike) -> FloatArray:
    return np.asarray(x, dtype=np.float64)


def _scalar(y: FloatArray) -> FloatArray:
    return y[()] if y.ndim == 0 else y


#: Exponents ``2 slope`` of a bell up to this, if whole numbers, are powers by squaring.


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

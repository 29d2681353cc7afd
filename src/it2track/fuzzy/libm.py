"""``exp`` computed the same way, bit for bit, by numpy and by compiled code.

numpy's ``np.exp`` uses SIMD implementations on some CPUs (AVX-512 here) whose results differ
from the C library's ``exp`` (which compiled code calls) in the last bit for a few percent of
arguments, and from machine to machine. The membership functions use :func:`exp` instead: one
fixed algorithm (fdlibm's ``e_exp.c``: reduction by ``ln 2`` with a two-part constant and its
degree-5 minimax kernel, within 1 ulp of the correctly rounded result), written once as
elementwise numpy operations and once as scalar code (:func:`exp_scalar`, compiled by
:mod:`it2track.fuzzy.kernels`), with the same IEEE operations in the same order. Neither
contracts multiply-adds, so both give the same bits on any machine.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["exp", "exp_scalar"]

_LN2_HI = 6.93147180369123816490e-01  # ln 2 to 32 bits: k * _LN2_HI exact for |k| < 2^11
_LN2_LO = 1.90821492927058770002e-10  # ln 2 - _LN2_HI
_INV_LN2 = 1.44269504088896338700e00
_HALF_LN2 = 3.46573590279972654709e-01  # below this |x| no reduction (k = 0)
_P1 = 1.66666666666666019037e-01  # fdlibm's minimax kernel of exp on [-ln2/2, ln2/2]
_P2 = -2.77777777770155933842e-03
_P3 = 6.61375632143793436117e-05
_P4 = -1.65339022054652515390e-06
_P5 = 4.13813679705723846039e-08
_LOW = -746.0  # exp(x) rounds to 0 below this ...
_HIGH = 710.0  # ... and overflows above this


def exp(x: ArrayLike) -> NDArray[np.float64]:
    """Elementwise ``e**x`` (within 1 ulp), bit-identical to :func:`exp_scalar`.

    Parameters
    ----------
    x : array_like
        Any shape; NaN gives NaN, ``-inf`` gives 0, ``+inf`` gives ``inf``.

    Returns
    -------
    ndarray
        Same shape as ``x``, float64.

    Examples
    --------
    >>> float(exp(0.0)), float(exp(-0.5))
    (1.0, 0.6065306597126334)
    """
    arr = np.asarray(x, dtype=np.float64)
    xc = np.clip(arr.reshape(-1), _LOW, _HIGH)  # NaN stays NaN
    with np.errstate(over="ignore", invalid="ignore"):
        k = xc * _INV_LN2
        k += np.copysign(0.5, xc)
        np.trunc(k, out=k)
        k[~(np.abs(xc) > _HALF_LN2)] = 0.0  # (NaN too: k = 0, the result stays NaN)
        hi = xc - k * _LN2_HI
        lo = k * _LN2_LO
        r = hi - lo
        t = r * r
        c = _P4 + t * _P5
        c = _P3 + t * c
        c = _P2 + t * c
        c = _P1 + t * c
        c = r - t * c
        y = 1.0 - ((lo - (r * c) / (2.0 - c)) - hi)
        out: NDArray[np.float64] = np.ldexp(y, k.astype(np.int64)).reshape(arr.shape)
    return out[()] if out.ndim == 0 else out  # a numpy scalar for a scalar, like np.exp


def exp_scalar(x: float) -> float:
    """:func:`exp` for one float: the same operations in the same order (compiled by
    :mod:`it2track.fuzzy.kernels`; in plain Python it raises ``OverflowError`` above 709.78)."""
    xc = _LOW if x < _LOW else _HIGH if x > _HIGH else x
    k = 0.0
    if abs(xc) > _HALF_LN2:
        k = float(int(xc * _INV_LN2 + math.copysign(0.5, xc)))
    hi = xc - k * _LN2_HI
    lo = k * _LN2_LO
    r = hi - lo
    t = r * r
    c = _P4 + t * _P5
    c = _P3 + t * c
    c = _P2 + t * c
    c = _P1 + t * c
    c = r - t * c
    y = 1.0 - ((lo - (r * c) / (2.0 - c)) - hi)
    return math.ldexp(y, int(k))

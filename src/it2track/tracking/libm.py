"""``atan2`` computed the same way, bit for bit, by numpy and by compiled code.

numpy's ``np.arctan2`` uses SIMD implementations on some CPUs (AVX-512 here) whose results
differ from the C library's ``atan2`` (which compiled code calls) in the last bit for a few
percent of arguments, and from machine to machine. The closed loop's desired heading uses
:func:`atan2` instead: fdlibm's algorithm (``e_atan2.c``/``s_atan.c``: reduction of
``|y / x|`` to ``|t| <= 7/16`` by one of five argument transforms, an odd minimax polynomial,
and two-part constants for the added angles), written once as elementwise numpy operations and
once as scalar code (:func:`atan2_scalar`, compiled by :mod:`it2track.tracking._jit`), with the
same IEEE operations in the same order. Results are within 1 ulp of the C library's.

The five transforms are written as one ``(A t + B) / (C t + D)`` with per-interval constants;
for each interval this is, operation for operation, fdlibm's expression (``2t - 1 / (t + 2)``,
``(t - 1) / (t + 1)``, ``(t - 1.5) / (1.5 t + 1)``, ``-1 / t``; ``t / 1`` below 7/16).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["atan2", "atan2_scalar"]

_PI = 3.1415926535897931160e00
_PI_LO = 1.2246467991473531772e-16  # pi - _PI
_PIO2 = 1.5707963267948966192e00  # fdlibm's atanhi[3] + atanlo[3], rounded
_BIG = 2.0**60  # |y / x| beyond this: +-pi/2 (the rest is below 2^-60 rad)
_BOUNDS = (0.4375, 0.6875, 1.1875, 2.4375)
# Per interval of t = |y / x|: reduced argument (A t + B) / (C t + D), then
# atan t = HI - ((r (s1 + s2) - LO) - r).
_A = np.array([1.0, 2.0, 1.0, 1.0, 0.0])
_B = np.array([0.0, -1.0, -1.0, -1.5, -1.0])
_C = np.array([0.0, 1.0, 1.0, 1.5, 1.0])
_D = np.array([1.0, 2.0, 1.0, 1.0, 0.0])
_HI = np.array([0.0, 4.63647609000806093515e-01, 7.85398163397448278999e-01,
                9.82793723247329054082e-01, 1.57079632679489655800e00])  # fmt: skip
_LO = np.array([0.0, 2.26987774529616870924e-17, 3.06161699786838301793e-17,
                1.39033110312309984516e-17, 6.12323399573676603587e-17])  # fmt: skip
_AT = (  # fdlibm aT[0..10]
    3.33333333333329318027e-01, -1.99999999998764832476e-01, 1.42857142725034663711e-01,
    -1.11111104054623557880e-01, 9.09088713343650656196e-02, -7.69187620504482999495e-02,
    6.66107313738753120669e-02, -5.83357013379057348645e-02, 4.97687799461593236017e-02,
    -3.65315727442169155270e-02, 1.62858201153657823623e-02,
)  # fmt: skip


def atan2(y: ArrayLike, x: ArrayLike) -> NDArray[np.float64]:
    """Elementwise ``atan2(y, x)`` in ``[-pi, pi]`` (within 1 ulp of the C library's),
    bit-identical to :func:`atan2_scalar`; signed zeros, infinities and NaN as in C.

    Parameters
    ----------
    y, x : array_like
        Broadcast together.

    Returns
    -------
    ndarray
        The broadcast shape, float64.

    Examples
    --------
    >>> atan2([1.0, 1.0, -0.0, 0.0], [1.0, -1.0, -1.0, 0.0]).tolist()
    [0.7853981633974483, 2.356194490192345, -3.141592653589793, 0.0]
    """
    yb, xb = np.broadcast_arrays(np.asarray(y, dtype=np.float64), np.asarray(x, dtype=np.float64))
    shape = yb.shape
    yv, xv = yb.reshape(-1), xb.reshape(-1)
    ay, ax = np.abs(yv), np.abs(xv)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        t = ay / ax
    t[ay == 0.0] = 0.0
    big = t >= _BIG  # (also x = 0, y != 0, and infinite y)
    t[big] = 0.0
    k = np.zeros(t.shape, dtype=np.intp)
    for bound in _BOUNDS:
        k += t >= bound
    r = _A[k] * t
    r += _B[k]
    den = _C[k] * t
    den += _D[k]
    r /= den
    z = r * r
    w = z * z
    s1 = _AT[8] + w * _AT[10]
    s1 = _AT[6] + w * s1
    s1 = _AT[4] + w * s1
    s1 = _AT[2] + w * s1
    s1 = z * (_AT[0] + w * s1)
    s2 = _AT[7] + w * _AT[9]
    s2 = _AT[5] + w * s2
    s2 = _AT[3] + w * s2
    s2 = w * (_AT[1] + w * s2)
    a = _HI[k] - ((r * (s1 + s2) - _LO[k]) - r)
    a[big] = _PIO2
    neg = (xv < 0.0) | ((ay == 0.0) & np.signbit(xv))
    neg &= ~big
    a[neg] = _PI - (a[neg] - _PI_LO)
    np.negative(a, out=a, where=np.signbit(yv))
    odd = ~(np.isfinite(xv) & np.isfinite(yv))
    if odd.any():
        a[odd] = np.arctan2(yv[odd], xv[odd])  # inf/NaN: exact constants or NaN
    return a.reshape(shape)


def atan2_scalar(y: float, x: float) -> float:
    """:func:`atan2` for one pair of floats: the same operations in the same order."""
    if not (math.isfinite(x) and math.isfinite(y)):
        return math.atan2(y, x)
    ay, ax = abs(y), abs(x)
    if ay == 0.0:
        t = 0.0
    elif ax == 0.0:
        t = math.inf
    else:
        t = ay / ax
    neg = x < 0.0 or (ay == 0.0 and math.copysign(1.0, x) < 0.0)
    if t >= _BIG:
        a = _PIO2
        neg = False
    else:
        if t < 0.4375:
            r, hi, lo = (1.0 * t + 0.0) / (0.0 * t + 1.0), 0.0, 0.0
        elif t < 0.6875:
            r = (2.0 * t + -1.0) / (1.0 * t + 2.0)
            hi, lo = 4.63647609000806093515e-01, 2.26987774529616870924e-17
        elif t < 1.1875:
            r = (1.0 * t + -1.0) / (1.0 * t + 1.0)
            hi, lo = 7.85398163397448278999e-01, 3.06161699786838301793e-17
        elif t < 2.4375:
            r = (1.0 * t + -1.5) / (1.5 * t + 1.0)
            hi, lo = 9.82793723247329054082e-01, 1.39033110312309984516e-17
        else:
            r = (0.0 * t + -1.0) / (1.0 * t + 0.0)
            hi, lo = 1.57079632679489655800e00, 6.12323399573676603587e-17
        z = r * r
        w = z * z
        s1 = _AT[8] + w * _AT[10]
        s1 = _AT[6] + w * s1
        s1 = _AT[4] + w * s1
        s1 = _AT[2] + w * s1
        s1 = z * (_AT[0] + w * s1)
        s2 = _AT[7] + w * _AT[9]
        s2 = _AT[5] + w * s2
        s2 = _AT[3] + w * s2
        s2 = w * (_AT[1] + w * s2)
        a = hi - ((r * (s1 + s2) - lo) - r)
    if neg:
        a = _PI - (a - _PI_LO)
    return -a if math.copysign(1.0, y) < 0.0 else a

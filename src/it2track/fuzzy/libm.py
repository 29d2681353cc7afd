"""``exp``, ``log`` and ``cos(pi u)`` computed the same way, bit for bit, by numpy and by
compiled code.

numpy's ``np.exp`` uses SIMD implementations on some CPUs (AVX-512 here) whose results differ
from the C library's ``exp`` (which compiled code calls) in the last bit for a few percent of
arguments, and from machine to machine. The membership functions use :func:`exp` instead: one
fixed algorithm (fdlibm's ``e_exp.c``: reduction by ``ln 2`` with a two-part constant and its
degree-5 minimax kernel, within 1 ulp of the correctly rounded result), written once as
elementwise numpy operations and once as scalar code (:func:`exp_scalar`, compiled by
:mod:`it2track.fuzzy.kernels`), with the same IEEE operations in the same order. Neither
contracts multiply-adds, so both give the same bits on any machine.

:func:`log` (fdlibm's ``e_log.c``: ``x = 2^k m`` with ``m`` in ``[sqrt(1/2), sqrt(2))`` and its
degree-14 minimax kernel in ``s = (m - 1) / (m + 1)``) and :func:`cospi` (``cos(pi u)`` for
``|u| <= 1``: an exact reduction of ``u`` to ``[-1/4, 1/4]`` and fdlibm's ``k_cos.c`` /
``k_sin.c`` kernels) follow the same rule. The membership functions use them where numpy's
SIMD ``log``/``power``/``cos`` would differ from the C library's in the last bits.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["cospi", "cospi_scalar", "exp", "exp_scalar", "log", "log_scalar"]

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


_LG1 = 6.666666666666735130e-01  # fdlibm's minimax kernel of log on [sqrt(1/2), sqrt(2)]
_LG2 = 3.999999999940941908e-01
_LG3 = 2.857142874366239149e-01
_LG4 = 2.222219843214978396e-01
_LG5 = 1.818357216161805012e-01
_LG6 = 1.531383769920937332e-01
_LG7 = 1.479819860511658591e-01
_SQRT_HALF = 0.70710678118654752440


def log(x: ArrayLike) -> NDArray[np.float64]:
    """Elementwise natural logarithm (within 1 ulp), bit-identical to :func:`log_scalar`.

    Parameters
    ----------
    x : array_like
        Any shape; ``0`` gives ``-inf``, negative numbers and NaN give NaN, ``inf`` gives ``inf``.

    Returns
    -------
    ndarray
        Same shape as ``x``, float64.

    Examples
    --------
    >>> float(log(1.0)), float(log(0.0)), float(log(8.0)) == 3 * float(log(2.0))
    (0.0, -inf, True)
    """
    arr = np.asarray(x, dtype=np.float64)
    flat = arr.reshape(-1)
    m, e = np.frexp(flat)  # m in [0.5, 1) for finite non-zero x
    small = m < _SQRT_HALF
    m = np.where(small, m * 2.0, m)
    k = e.astype(np.float64) - small
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        f = m - 1.0
        s = f / (2.0 + f)
        z = s * s
        w = z * z
        t1 = w * (_LG2 + w * (_LG4 + w * _LG6))
        t2 = z * (_LG1 + w * (_LG3 + w * (_LG5 + w * _LG7)))
        r = t2 + t1
        hfsq = 0.5 * f * f
        y = k * _LN2_HI - ((hfsq - (s * (hfsq + r) + k * _LN2_LO)) - f)
    y = np.where(flat > 0.0, y, np.where(flat == 0.0, -np.inf, np.nan))
    y = np.where(flat == np.inf, np.inf, y)
    out: NDArray[np.float64] = y.reshape(arr.shape)
    return out[()] if out.ndim == 0 else out


def log_scalar(x: float) -> float:
    """:func:`log` for one float: the same operations in the same order (compiled by
    :mod:`it2track.fuzzy.kernels`)."""
    if not x > 0.0:
        return -math.inf if x == 0.0 else math.nan
    if x == math.inf:
        return math.inf
    m, e = math.frexp(x)
    k = float(e)
    if m < _SQRT_HALF:
        m = m * 2.0
        k = k - 1.0
    f = m - 1.0
    s = f / (2.0 + f)
    z = s * s
    w = z * z
    t1 = w * (_LG2 + w * (_LG4 + w * _LG6))
    t2 = z * (_LG1 + w * (_LG3 + w * (_LG5 + w * _LG7)))
    r = t2 + t1
    hfsq = 0.5 * f * f
    return k * _LN2_HI - ((hfsq - (s * (hfsq + r) + k * _LN2_LO)) - f)


_C1 = 4.16666666666666019037e-02  # fdlibm's kernel of cos on [-pi/4, pi/4]
_C2 = -1.38888888888741095749e-03
_C3 = 2.48015872894767294178e-05
_C4 = -2.75573143513906633035e-07
_C5 = 2.08757232129817482790e-09
_C6 = -1.13596475577881948265e-11
_S1 = -1.66666666666666324348e-01  # fdlibm's kernel of sin on [-pi/4, pi/4]
_S2 = 8.33333333332248946124e-03
_S3 = -1.98412698298579493134e-04
_S4 = 2.75573137070700676789e-06
_S5 = -2.50507602534068634195e-08
_S6 = 1.58969099521155010221e-10
_PI = 3.14159265358979311600e00


def _kcos(t: NDArray[np.float64]) -> NDArray[np.float64]:
    z = t * t
    w = z * z
    r = z * (_C1 + z * (_C2 + z * _C3)) + w * w * (_C4 + z * (_C5 + z * _C6))
    hz = 0.5 * z
    v = 1.0 - hz
    out: NDArray[np.float64] = v + (((1.0 - v) - hz) + z * r)
    return out


def _ksin(t: NDArray[np.float64]) -> NDArray[np.float64]:
    z = t * t
    w = z * z
    r = _S2 + z * (_S3 + z * _S4) + z * w * (_S5 + z * _S6)
    out: NDArray[np.float64] = t + (z * t) * (_S1 + z * r)
    return out


def cospi(u: ArrayLike) -> NDArray[np.float64]:
    """Elementwise ``cos(pi u)`` for ``|u| <= 1``, bit-identical to :func:`cospi_scalar`.

    ``u`` is reduced exactly: ``|u| <= 1/4`` gives ``cos(pi |u|)``, ``|u| <= 3/4`` gives
    ``sin(pi (1/2 - |u|))`` and the rest ``-cos(pi (1 - |u|))`` (each difference exact), so
    ``cospi(0) == 1``, ``cospi(1/2) == 0`` and ``cospi(1) == -1`` exactly. Outside
    ``[-1, 1]`` the result is unspecified (the callers never go there).

    Parameters
    ----------
    u : array_like
        Any shape, ``|u| <= 1``.

    Returns
    -------
    ndarray
        Same shape as ``u``, float64.

    Examples
    --------
    >>> cospi([0.0, 0.5, -1.0, 1 / 3]).round(15).tolist()
    [1.0, 0.0, -1.0, 0.5]
    """
    arr = np.asarray(u, dtype=np.float64)
    r = np.abs(arr)
    near = _kcos(_PI * r)
    mid = _ksin(_PI * (0.5 - r))
    far = -_kcos(_PI * (1.0 - r))
    out: NDArray[np.float64] = np.where(r <= 0.25, near, np.where(r <= 0.75, mid, far))
    return out[()] if out.ndim == 0 else out


def cospi_scalar(u: float) -> float:
    """:func:`cospi` for one float: the same operations in the same order."""
    r = abs(u)
    if r <= 0.25:
        t = _PI * r
    elif r <= 0.75:
        t = _PI * (0.5 - r)
    else:
        t = _PI * (1.0 - r)
    z = t * t
    if r <= 0.25 or r > 0.75:
        w = z * z
        c = z * (_C1 + z * (_C2 + z * _C3)) + w * w * (_C4 + z * (_C5 + z * _C6))
        hz = 0.5 * z
        v = 1.0 - hz
        y = v + (((1.0 - v) - hz) + z * c)
        return y if r <= 0.25 else -y
    w = z * z
    c = _S2 + z * (_S3 + z * _S4) + z * w * (_S5 + z * _S6)
    return t + (z * t) * (_S1 + z * c)

"""Elementwise sine and cosine for the differential drive's step (numpy, bit-identical for
any batch); the compiled loop (:mod:`it2track.tracking._jit`) uses the same constants."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

# --- elementwise sine and cosine --------------------------------------------------------
# numpy's float64 sin/cos call the scalar C library (~8-15 ns per element), which made them
# most of a step. These vectorised versions (Cody-Waite reduction by pi/2, fdlibm's minimax
# kernels on [-pi/4, pi/4], quadrant selection by exact arithmetic) give sin and cos together
# in about the time the C library takes for one, within 1 ulp of it, and are purely
# elementwise, so bit-identical for any batch. They write into caller-provided buffers: the
# step allocates no large temporaries (repeatedly freeing and re-faulting ~100 kB arrays
# cost more than the arithmetic).
_TWO_OVER_PI = 6.36619772367581382433e-01
_PIO2_HI = 1.57079632673412561417e00  # first 33 bits of pi/2: k * _PIO2_HI exact, |k| < 2^20
_PIO2_LO = 6.07710050650619224932e-11  # pi/2 - _PIO2_HI
_SIN_KERNEL = (  # fdlibm __kernel_sin S1..S6, for |r| <= pi/4
    -1.66666666666666324348e-01,
    8.33333333332248946124e-03,
    -1.98412698298579493134e-04,
    2.75573137070700676789e-06,
    -2.50507602534068634195e-08,
    1.58969099521155010221e-10,
)
_COS_KERNEL = (  # fdlibm __kernel_cos C1..C6, for |r| <= pi/4
    4.16666666666666019037e-02,
    -1.38888888888741095749e-03,
    2.48015872894767294178e-05,
    -2.75573143513906633035e-07,
    2.08757232129817482790e-09,
    -1.13596475577881948265e-11,
)
_KERNEL_LIMIT = math.pi / 4.0  # the kernels alone serve |r| <= pi/4
_SINCOS_LIMIT = 1.0e6  # beyond this |x| the reduction is not exact: C library instead
_N_WORK = 7  # work buffers _sincos needs


def _sincos_kernels(
    r: NDArray[np.float64],
    s: NDArray[np.float64],
    c: NDArray[np.float64],
    z: NDArray[np.float64],
    t: NDArray[np.float64],
) -> None:
    """``s = sin r``, ``c = cos r`` for ``|r| <= pi/4`` (fdlibm kernels); z, t: work."""
    np.multiply(r, r, out=z)
    np.multiply(z, _SIN_KERNEL[5], out=s)
    for coef in _SIN_KERNEL[4::-1]:
        s += coef
        s *= z
    s *= r
    s += r  # r + r^3 (S1 + z (S2 + ...))
    np.multiply(z, _COS_KERNEL[5], out=c)
    for coef in _COS_KERNEL[4::-1]:
        c += coef
        c *= z
    c *= z
    np.multiply(z, 0.5, out=t)
    t -= c
    np.subtract(1.0, t, out=c)  # 1 - (z/2 - z^2 (C1 + z (C2 + ...)))


def _sincos(
    x: NDArray[np.float64],
    s: NDArray[np.float64],
    c: NDArray[np.float64],
    work: Sequence[NDArray[np.float64]],
) -> None:
    """``s = sin x``, ``c = cos x`` elementwise, within 1 ulp of ``np.sin``/``np.cos``.

    ``work`` holds ``_N_WORK`` buffers of the shape of ``x``. Every output element
    depends on its input element only (the ``|x| > 1e6`` fallback to the C library is
    applied element by element).
    """
    k, r, z, t, ps, pc, h = work[:_N_WORK]
    np.multiply(x, _TWO_OVER_PI, out=k)
    np.rint(k, out=k)  # x = k pi/2 + r, |r| <= pi/4 (up to rounding)
    np.multiply(k, _PIO2_HI, out=r)
    np.subtract(x, r, out=r)  # exact (Sterbenz)
    np.multiply(k, _PIO2_LO, out=t)
    r -= t
    _sincos_kernels(r, ps, pc, z, t)
    # Quadrant k mod 4 = b0 + 2 b1 in exact floating-point arithmetic (np.where with an
    # unpredictable mask is slow): sin x = A sin r + B cos r, cos x = A cos r - B sin r,
    # with A = (1 - b0) sgn, B = b0 sgn, sgn = 1 - 2 b1.
    b0, sgn = r, z  # reuse
    np.multiply(k, 0.5, out=h)
    np.floor(h, out=h)
    np.multiply(h, -2.0, out=b0)
    b0 += k  # b0 = k - 2 floor(k/2)
    np.multiply(h, 0.5, out=k)
    np.floor(k, out=k)
    k *= -2.0
    k += h  # b1 = h - 2 floor(h/2)
    np.multiply(k, -2.0, out=sgn)
    sgn += 1.0
    b0 *= sgn  # B
    sgn -= b0  # A
    np.multiply(ps, sgn, out=s)
    np.multiply(pc, b0, out=t)
    s += t
    np.multiply(pc, sgn, out=c)
    np.multiply(ps, b0, out=t)
    c -= t
    np.abs(x, out=t)
    big = t > _SINCOS_LIMIT
    if big.any():
        s[big] = np.sin(x[big])
        c[big] = np.cos(x[big])


def _sincos_small(
    x: NDArray[np.float64],
    s: NDArray[np.float64],
    c: NDArray[np.float64],
    work: Sequence[NDArray[np.float64]],
) -> None:
    """Like :func:`_sincos`, fastest for ``|x| <= pi/4`` (kernels only, no reduction).

    Larger elements (rare: a heading change above pi/4 within one node offset) go through
    :func:`_sincos`, element by element.
    """
    z, t = work[0], work[1]
    _sincos_kernels(x, s, c, z, t)
    np.abs(x, out=t)
    big = t > _KERNEL_LIMIT
    if big.any():
        xb = x[big]
        sb, cb = np.empty_like(xb), np.empty_like(xb)
        _sincos(xb, sb, cb, [np.empty_like(xb) for _ in range(_N_WORK)])
        s[big] = sb
        c[big] = cb

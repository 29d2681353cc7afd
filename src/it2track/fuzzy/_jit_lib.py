"""The scalar building blocks of the compiled kernels (imported lazily, with :mod:`._jit`):
numba's options, branch-free ``min``/``max``, ``exp``/``log``/``cos(pi u)`` of :mod:`.libm`,
the membership curves of :mod:`.curves` and :mod:`.shapes`, and the t-norms of
:class:`~.norms.TNorm` -- each the numpy reference's operations in the same order.

numba checks a cached function against its own source file only: after editing this file in a
development checkout, touch ``_jit.py`` and ``tracking/_jit.py`` too (or clear
``__pycache__``).
"""

from __future__ import annotations

import math
from typing import Any

from numba import njit

from .curves import MAX_SQUARING
from .libm import cospi_scalar, exp_scalar, log_scalar

# t-norm codes (TNORM of a packed system): product, minimum, then the others of
# kernels._TNORMS.
PRODUCT, MINIMUM, BOUNDED_DIFFERENCE, DRASTIC, EINSTEIN, HAMACHER, NILPOTENT = range(7)


def _compiled(*, inline: bool = False) -> Any:
    """numba's ``njit`` with this package's options: cached on disk, IEEE division semantics
    (``error_model="numpy"``: x / 0 is inf or NaN, as in numpy), no fast-math, GIL released.

    ``inline``: inline in numba IR. Small helpers called in per-lane loops are inlined: a call
    of a compiled function with array arguments costs reference-count updates (atomic) that
    LLVM cannot remove. Larger functions are called once per block: inlining them would
    multiply the compile time.
    """
    return njit(cache=True, error_model="numpy", nogil=True,
                inline="always" if inline else "never")


exp = _compiled()(exp_scalar)
# (inlined into their one caller, _curve: a compiled function of their own would cost its own
# share of the cold compile time)
log = _compiled(inline=True)(log_scalar)
cospi = _compiled(inline=True)(cospi_scalar)


@_compiled(inline=True)
def fmax(a, b):
    """Python's (and numba's) ``max(a, b)`` for floats, ``b if b > a else a``, as a plain
    select: numba's builtin calls a comparison the loop vectoriser does not see through."""
    return b if b > a else a


@_compiled(inline=True)
def fmin(a, b):
    """Python's ``min(a, b)`` for floats, ``b if b < a else a`` (see :func:`fmax`)."""
    return b if b < a else a  # scalar arguments: a call costs no reference counting


@_compiled()
def _curve(kind, a, b, c, d, h, v):
    """The membership at ``v`` of a row of the kinds of :mod:`.curves` and :mod:`.shapes`
    (their numpy ``__call__`` operation for operation; parameters as each class's
    ``kernel_row`` documents)."""
    if kind == 4:  # bell (center, width, 2 slope, h)
        t = abs((v - a) / b)
        if c == int(c) and c <= MAX_SQUARING:
            r = 1.0
            base = t
            m = int(c)
            while m:
                if m & 1:
                    r = r * base
                m >>= 1
                if m:
                    base = base * base
            return d * (1.0 / (1.0 + r))
        return d * (1.0 / (1.0 + exp(c * log(t))))
    if kind == 5:  # sigmoid (inflection, slope, h)
        return c * (1.0 / (1.0 + exp(-b * (v - a))))
    if kind == 6 or kind == 7:  # sigmoid difference / product (left, rising, right, falling, h)
        s1 = 1.0 / (1.0 + exp(-b * (v - a)))
        s2 = 1.0 / (1.0 + exp(-d * (v - c)))
        return h * (abs(s1 - s2) if kind == 6 else s1 * s2)
    if kind == 8 or kind == 9:  # S / Z shape (start, end, h)
        return c * _spline(v, a, b, kind == 8)
    if kind == 10:  # Pi shape (a, b, c, d, h)
        return h * (_spline(v, a, b, True) * _spline(v, c, d, False))
    if kind == 11:  # Gaussian product (mean_a, sigma_a, mean_b, sigma_b, h)
        za = fmin(v - a, 0.0) / b
        zb = fmax(v - c, 0.0) / d
        return h * (exp(-0.5 * za * za) * exp(-0.5 * zb * zb))
    if kind == 12:  # cosine (center, width, h)
        half = 0.5 * b
        if (v >= a - half) & (v <= a + half):
            return c * (0.5 * (1.0 + cospi((v - a) / half)))
        return c * 0.0
    if kind == 13:  # spike (center, width, h)
        return c * exp(-abs(10.0 / b * (v - a)))
    if kind == 14:  # concave (inflection, end, h)
        if a < b:
            return c * ((b - a) / ((2.0 * b - a) - v) if v < b else 1.0)
        return c * ((a - b) / ((a - 2.0 * b) + v) if v > b else 1.0)
    if kind == 15:  # rectangle (start, end, h)
        return c if (v >= a) & (v <= b) else 0.0
    if kind == 16:  # step (edge, rising, closed, h)
        if b != 0.0:
            on = (v >= a) if c != 0.0 else (v > a)
        else:
            on = (v <= a) if c != 0.0 else (v < a)
        return d if on else 0.0
    if kind == 17:  # arc (start, end, h)
        r = b - a
        e = v - b
        arc = math.sqrt(fmax(r * r - e * e, 0.0)) / abs(r)
        if a < b:
            return c * (1.0 if v > b else (arc if v >= a else 0.0))
        return c * (1.0 if v < b else (arc if v <= a else 0.0))
    # semi-ellipse (start, end, h)
    r = (b - a) / 2.0
    e = v - (a + r)
    y = math.sqrt(fmax(r * r - e * e, 0.0)) / r
    return c * (y if (v >= a) & (v <= b) else 0.0)


@_compiled(inline=True)
def _spline(v, a, b, rising):
    """MATLAB's ``smf`` (``rising``) or ``zmf`` on ``[a, b]``, as curves._s_shape/_z_shape."""
    w = b - a
    mid = (a + b) / 2.0
    q1 = (v - a) / w
    q2 = (v - b) / w
    if rising:
        return 0.0 if v <= a else (2.0 * (q1 * q1) if v <= mid else
                                   (1.0 - 2.0 * (q2 * q2) if v < b else 1.0))
    return 1.0 if v <= a else (1.0 - 2.0 * (q1 * q1) if v <= mid else
                               (2.0 * (q2 * q2) if v < b else 0.0))


@_compiled(inline=True)
def _tnorm(code, a, b):
    """The t-norms of norms.TNorm other than product and minimum, as their numpy forms."""
    if code == BOUNDED_DIFFERENCE:
        return fmax(0.0, a + b - 1.0)
    if code == DRASTIC:
        return fmin(a, b) if fmax(a, b) == 1.0 else 0.0
    if code == EINSTEIN:
        ab = a * b
        return ab / (2.0 - (a + b - ab))
    if code == HAMACHER:
        ab = a * b
        return ab / (a + b - ab) if a + b != 0.0 else 0.0
    return fmin(a, b) if a + b > 1.0 else 0.0  # nilpotent minimum

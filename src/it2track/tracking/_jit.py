"""numba-compiled closed loop (imported lazily by :mod:`.compiled`).

One task advances a *block* of up to :data:`LANES` runs that share a controller through the
whole run, lane by lane: desired heading, noise, errors, controller,
saturation, metrics and the exact-ZOH plant step, with the operations of :meth:`._Engine.run`,
:meth:`~it2track.plant.DifferentialDrive.step` and :class:`.metrics.MetricAccumulator` in the
same order, so every number is the numpy engine's, bit for bit. The kernel is serial and
releases the GIL; :mod:`.compiled` runs disjoint sets of blocks on several threads. A run never
reads another run's numbers, so results do not depend on the block, the batch or the number of
threads. Fuzzy controllers are evaluated by :func:`it2track.fuzzy._jit.eval_block` on the
block's lanes.

What makes the lane loops vectorise (AVX-512 here; checked with ``inspect_asm`` and LLVM's
``-pass-remarks-missed=loop-vectorize``), each worth 2-10x on the loop it touches:

* a constant trip count (:data:`LANES`; spare lanes of a short block compute copies of its
  first run) over rows of one array at constant offsets, so no run-time overlap checks;
* runs sorted by path within a controller: a block on one path (the usual case) reads its
  point and feed-forward as scalars, others gather them in a loop of their own;
* no call and no rarely-taken branch in a lane loop: the rare lanes (non-finite atan2
  arguments, angles outside (-pi, pi], sine/cosine beyond the kernels' range) are counted by a
  branch-free pass and fixed only if there are any; ``min``/``max`` written as selects
  (:func:`~it2track.fuzzy._jit.fmin`), numba's builtins call a comparison LLVM does not see
  through.

Cost per run-step (4096 runs x 1001 steps, sinusoidal path, sigma = 0, one thread, CPU time on
the shared 2-core AVX-512 machine, measured with 128 lanes a block; 64 lanes, chosen for the
study's many short blocks, cost ~13 % more on such long ones; numpy engine 137 ns): PD
controller 8 ns (plant step with five sine/cosine pairs ~4, atan2 ~1, metrics, wrap and
bookkeeping the rest), paper IT2FLC with the exhaustive reducer ~22 ns (the fuzzy block ~14: 24
divisions for the trapezoid memberships, 20 for the reducer, ~300 other flops), Nie-Tan ~16.
Noise: drawing a seed's row (numpy PCG64, ~17 ns per sample) is done once per distinct seed and
call, and not at all for sigma = 0.

numba checks a cached function against its own source file only: after editing
``fuzzy/_jit.py``, ``fuzzy/_jit_lib.py``, ``fuzzy/libm.py``, ``fuzzy/curves.py``'s ``MAX_SQUARING``,
``tracking/libm.py`` or ``plant/drive.py``'s sine/cosine constants in a development checkout,
touch this file too (or clear ``__pycache__``).
"""

from __future__ import annotations

import math

import numpy as np

from ..fuzzy._jit import N_ROWS, N_RULES, OK, WORK_ROWS, _compiled, eval_block, fmax, fmin
from ..plant._sincos import (
    _COS_KERNEL,
    _KERNEL_LIMIT,
    _PIO2_HI,
    _PIO2_LO,
    _SIN_KERNEL,
    _SINCOS_LIMIT,
    _TWO_OVER_PI,
)

LANES = 64  # runs per block (a constant: see the module docstring)
#: Controller kinds in a packed controller (first value).
FUZZY, PD = 0.0, 1.0
#: Config vector: ts, voltage limit, r/2, r/(2l), N, metric start index, previous-pose flag.
TS, V_LIM, HALF_R, W_SCALE, N_STEPS, K_START, PREVIOUS = range(7)
N_METRICS = 14
N_FIELDS = 17

_PI = math.pi
_TWO_PI = 2.0 * math.pi
_S1, _S2, _S3, _S4, _S5, _S6 = _SIN_KERNEL
_C1, _C2, _C3, _C4, _C5, _C6 = _COS_KERNEL


@_compiled(inline=True)
def _wrap(a):
    """heading._wrap_inplace for one angle outside (-pi, pi] (the caller picks those)."""
    w = _PI - ((_PI - a) % _TWO_PI)  # Python/numba float % is numpy's np.mod
    return _PI if w <= -_PI else w


@_compiled(inline=True)
def _kernels(r):
    """plant._sincos._sincos_kernels for one value: (sin r, cos r), |r| <= pi/4."""
    z = r * r
    s = z * _S6
    s = (s + _S5) * z
    s = (s + _S4) * z
    s = (s + _S3) * z
    s = (s + _S2) * z
    s = (s + _S1) * z
    s = s * r
    s = s + r
    c = z * _C6
    c = (c + _C5) * z
    c = (c + _C4) * z
    c = (c + _C3) * z
    c = (c + _C2) * z
    c = (c + _C1) * z
    c = c * z
    t = z * 0.5
    t = t - c
    return s, 1.0 - t


@_compiled(inline=True)
def _sincos(x):
    """plant._sincos._sincos for one value."""
    if abs(x) > _SINCOS_LIMIT:
        return math.sin(x), math.cos(x)
    k = np.rint(x * _TWO_OVER_PI)
    r = x - k * _PIO2_HI
    r = r - k * _PIO2_LO
    ps, pc = _kernels(r)
    h = math.floor(k * 0.5)
    b0 = h * -2.0 + k
    b1 = math.floor(h * 0.5) * -2.0 + h
    sgn = b1 * -2.0 + 1.0
    bb = b0 * sgn
    aa = sgn - bb
    return ps * aa + pc * bb, pc * aa - ps * bb


_BIG = 2.0**60
_PIO2 = 1.5707963267948966192e00
_PI_LO = 1.2246467991473531772e-16
_AT0, _AT1, _AT2, _AT3, _AT4, _AT5, _AT6, _AT7, _AT8, _AT9, _AT10 = (
    3.33333333333329318027e-01, -1.99999999998764832476e-01, 1.42857142725034663711e-01,
    -1.11111104054623557880e-01, 9.09088713343650656196e-02, -7.69187620504482999495e-02,
    6.66107313738753120669e-02, -5.83357013379057348645e-02, 4.97687799461593236017e-02,
    -3.65315727442169155270e-02, 1.62858201153657823623e-02,
)  # fmt: skip
_H1, _H2, _H3, _H4 = (4.63647609000806093515e-01, 7.85398163397448278999e-01,
                      9.82793723247329054082e-01, 1.57079632679489655800e00)  # fmt: skip
_L1, _L2, _L3, _L4 = (2.26987774529616870924e-17, 3.06161699786838301793e-17,
                      1.39033110312309984516e-17, 6.12323399573676603587e-17)  # fmt: skip


@_compiled(inline=True)
def _atan2_lanes(W, ry, rx, rout, L):
    """W[rout] = atan2(W[ry], W[rx]) for the lanes: tracking.libm.atan2's elementwise form
    (branch-free, so it vectorises), then the C library for non-finite lanes."""
    for j in range(L):
        y = W[ry, j]
        x = W[rx, j]
        ay = abs(y)
        ax = abs(x)
        t = ay / ax
        t = 0.0 if ay == 0.0 else t
        big = t >= _BIG
        t = 0.0 if big else t
        c1 = t >= 0.4375
        c2 = t >= 0.6875
        c3 = t >= 1.1875
        c4 = t >= 2.4375
        a_ = 0.0 if c4 else (1.0 if c2 else (2.0 if c1 else 1.0))
        b_ = -1.0 if c4 else (-1.5 if c3 else (-1.0 if c1 else 0.0))
        c_ = 1.0 if c4 else (1.5 if c3 else (1.0 if c1 else 0.0))
        d_ = 0.0 if c4 else (1.0 if c2 else (2.0 if c1 else 1.0))
        hi = _H4 if c4 else (_H3 if c3 else (_H2 if c2 else (_H1 if c1 else 0.0)))
        lo = _L4 if c4 else (_L3 if c3 else (_L2 if c2 else (_L1 if c1 else 0.0)))
        r = a_ * t
        r = r + b_
        den = c_ * t
        den = den + d_
        r = r / den
        z = r * r
        w = z * z
        s1 = _AT8 + w * _AT10
        s1 = _AT6 + w * s1
        s1 = _AT4 + w * s1
        s1 = _AT2 + w * s1
        s1 = z * (_AT0 + w * s1)
        s2 = _AT7 + w * _AT9
        s2 = _AT5 + w * s2
        s2 = _AT3 + w * s2
        s2 = w * (_AT1 + w * s2)
        a = hi - ((r * (s1 + s2) - lo) - r)
        a = _PIO2 if big else a
        neg = (x < 0.0 or (ay == 0.0 and math.copysign(1.0, x) < 0.0)) and not big
        a = _PI - (a - _PI_LO) if neg else a
        rv = -a if math.copysign(1.0, y) < 0.0 else a
        W[rout, j] = rv
    odd = 0  # counted by a branch-free pass: a loop with a rare call costs ~10 ns per lane
    for j in range(L):
        odd += 0 if (abs(W[rx, j]) < math.inf and abs(W[ry, j]) < math.inf) else 1
    if odd:
        for j in range(L):
            if not (math.isfinite(W[rx, j]) and math.isfinite(W[ry, j])):
                W[rout, j] = math.atan2(W[ry, j], W[rx, j])


@_compiled(inline=True)
def _wrap_lanes(W, row, L):
    """_wrap on W[row] (nothing to do for the usual angle in (-pi, pi]: one branch-free
    counting pass, then the rare angles outside)."""
    out = 0
    for j in range(L):
        a = W[row, j]
        out += 1 if (a <= -_PI or a > _PI) else 0
    if out:
        for j in range(L):
            a = W[row, j]
            if a <= -_PI or a > _PI:
                W[row, j] = _wrap(a)


@_compiled(inline=True)
def _sincos_lanes(W, rx, rs, rc, L, small):
    """W[rs], W[rc] = sin, cos of W[rx]: plant._sincos._sincos (``small``: _sincos_small) for
    the lanes, branch-free where it vectorises, then the rare lanes through the scalar path."""
    for j in range(L):
        x = W[rx, j]
        if small:
            r = x
        else:
            k = np.rint(x * _TWO_OVER_PI)
            r = x - k * _PIO2_HI
            r = r - k * _PIO2_LO
        z = r * r
        s = z * _S6
        s = (s + _S5) * z
        s = (s + _S4) * z
        s = (s + _S3) * z
        s = (s + _S2) * z
        s = (s + _S1) * z
        s = s * r
        ps = s + r
        c = z * _C6
        c = (c + _C5) * z
        c = (c + _C4) * z
        c = (c + _C3) * z
        c = (c + _C2) * z
        c = (c + _C1) * z
        c = c * z
        t = z * 0.5
        t = t - c
        pc = 1.0 - t
        if small:
            W[rs, j] = ps
            W[rc, j] = pc
        else:
            h = math.floor(k * 0.5)
            b0 = h * -2.0 + k
            b1 = math.floor(h * 0.5) * -2.0 + h
            sgn = b1 * -2.0 + 1.0
            bb = b0 * sgn
            aa = sgn - bb
            W[rs, j] = ps * aa + pc * bb
            W[rc, j] = pc * aa - ps * bb
    limit = _KERNEL_LIMIT if small else _SINCOS_LIMIT
    big = 0
    for j in range(L):
        big += 1 if abs(W[rx, j]) > limit else 0
    if big:
        for j in range(L):
            x = W[rx, j]
            if abs(x) > limit:
                sv, cv = _sincos(x)
                W[rs, j] = sv
                W[rc, j] = cv


@_compiled(inline=True)
def _plant_lanes(W, plant, n_nodes, VR, VL):
    """DifferentialDrive.step for the lanes (rows as in _loop; VR, VL: row indices)."""
    L = LANES
    for j in range(L):
        i_r, w_r, i_l, w_l = W[3, j], W[4, j], W[5, j], W[6, j]
        W[24, j] = i_r + i_l  # s_i
        W[25, j] = w_r + w_l  # s_w
        W[26, j] = W[VR, j] + W[VL, j]  # s_v
        W[27, j] = i_r - i_l  # d_i
        W[28, j] = w_r - w_l  # d_w
        W[29, j] = W[VR, j] - W[VL, j]  # d_v
    _sincos_lanes(W, 2, 30, 31, L, False)  # sin0, cos0
    for n in range(n_nodes):
        q = 9 + 6 * n
        w0, w1, w2 = plant[q], plant[q + 1], plant[q + 2]
        a0, a1, a2 = plant[q + 3], plant[q + 4], plant[q + 5]
        for j in range(L):
            weight = W[24, j] * w0
            weight = weight + W[25, j] * w1
            W[32, j] = weight + W[26, j] * w2
            delta = W[27, j] * a0
            delta = delta + W[28, j] * a1
            W[33, j] = delta + W[29, j] * a2
        _sincos_lanes(W, 33, 34, 35, L, True)
        if n == 0:
            for j in range(L):
                W[36, j] = W[35, j] * W[32, j]
                W[37, j] = W[34, j] * W[32, j]
        else:
            for j in range(L):
                W[36, j] = W[36, j] + W[35, j] * W[32, j]
                W[37, j] = W[37, j] + W[34, j] * W[32, j]
    h0, h1, h2 = plant[6], plant[7], plant[8]
    a00, a01, b0, a10, a11, b1 = plant[0], plant[1], plant[2], plant[3], plant[4], plant[5]
    for j in range(L):
        sin0, cos0, acc_c, acc_s = W[30, j], W[31, j], W[36, j], W[37, j]
        W[0, j] = W[0, j] + (cos0 * acc_c - sin0 * acc_s)
        W[1, j] = W[1, j] + (sin0 * acc_c + cos0 * acc_s)
        delta = W[27, j] * h0
        delta = delta + W[28, j] * h1
        delta = delta + W[29, j] * h2
        W[2, j] = W[2, j] + delta
        i_r, w_r, i_l, w_l = W[3, j], W[4, j], W[5, j], W[6, j]
        vr, vl = W[VR, j], W[VL, j]
        W[3, j] = (i_r * a00 + w_r * a01) + vr * b0
        W[4, j] = (i_r * a10 + w_r * a11) + vr * b1
        W[5, j] = (i_l * a00 + w_l * a01) + vl * b0
        W[6, j] = (i_l * a10 + w_l * a11) + vl * b1


@_compiled(inline=True)
def _integrals(A, base, W, row, t, end):
    """_IntegralErrors.update for the lanes (error row ``row`` of W): rows base..base+3
    sums, base+4..base+7 the end values."""
    for j in range(LANES):
        e = W[row, j]
        a = abs(e)
        s = e * e
        A[base, j] += a
        A[base + 2, j] += s
        A[base + 1, j] += a * t
        A[base + 3, j] += s * t
    if end:
        for j in range(LANES):
            e = W[row, j]
            a = abs(e)
            s = e * e
            A[base + 4, j] += a
            A[base + 6, j] += s
            A[base + 5, j] += a * t
            A[base + 7, j] += s * t


# Rows of the lane state W: pose and wheels (0-6), previous x, y (7, 8), e_prev (9), de (10),
# PD derivative (11), per-step values (12-23), plant work rows (24-37), saturation flag (38),
# the reference point and feed-forward per lane (39-41).
_W_ROWS = 42
# Rows of the accumulators A: true integrals (0-7), measured (8-15), dist_sq, dist_max,
# dist_final, effort_sum, effort_ends, u_prev, u_tv, sat_steps (16-23).
_A_ROWS = 24


def _loop(C, c_off, blocks, tidx, std, zinv, Z, hold, xref, yref, v0ref, start, plant, cfg,
          metrics, rec, record, status):  # fmt: skip
    """Advance every block of runs through the whole run (see the module docstring).

    ``blocks`` (n_blocks, 4): first run, end, controller, trajectory of the first run; runs
    are rows of ``tidx`` (trajectory), ``std`` (noise std), ``zinv`` (row of ``Z``, the
    standard noise). Writes ``metrics`` (B, 14), ``rec`` (17, B, N+1) if ``record``, and
    ``status`` (B,): not OK where the fuzzy reference would raise (the block stops there).

    Every lane loop runs over all :data:`LANES` lanes (a constant trip count over rows at
    constant offsets lets LLVM vectorise without run-time overlap checks); a block of fewer
    runs fills its spare lanes with copies of its first run, whose numbers are not written.
    """
    n_steps = int(cfg[N_STEPS])
    k_start = int(cfg[K_START])
    previous = cfg[PREVIOUS] != 0.0
    ts, v_lim, half_r, w_scale = cfg[TS], cfg[V_LIM], cfg[HALF_R], cfg[W_SCALE]
    n_nodes = (plant.size - 9) // 6
    W = np.zeros((_W_ROWS, LANES))
    A = np.zeros((_A_ROWS, LANES))
    X = np.empty((2, LANES))
    # The lane count as a run-time value, not the literal LANES: eval_block is then compiled
    # once for the loop, the batch and the scalar call (a literal would be a specialisation
    # of its own, with every reducer in it: twice the compile time of a first run).
    lanes = X.shape[1]
    yl = np.empty(LANES)
    yr = np.empty(LANES)
    st = np.zeros(LANES, dtype=np.int8)
    zi = np.zeros(LANES, dtype=np.int64)
    tl = np.zeros(LANES, dtype=np.int64)
    sd = np.zeros(LANES)
    for b in range(blocks.shape[0]):
        first, stop, ci, tj = blocks[b, 0], blocks[b, 1], blocks[b, 2], blocks[b, 3]
        L = stop - first
        off = c_off[ci]
        kind = C[off]
        if kind == FUZZY:
            ke, kde = C[off + 1], C[off + 2]
            P = C[off + 3 : c_off[ci + 1]]
            S = np.empty((int(P[N_ROWS]) + 1 + 2 * int(P[N_RULES]) + WORK_ROWS, LANES))
            lo0, lo1 = P[int(P[12])], P[int(P[12]) + 1]
            hi0, hi1 = P[int(P[13])], P[int(P[13]) + 1]
        else:
            ke, kde = 0.0, 0.0
            P = C[off : off + 1]
            S = np.empty((1, LANES))
            lo0 = lo1 = hi0 = hi1 = 0.0
        kp, kd, tf, u_max = 0.0, 0.0, 0.0, 0.0
        if kind == PD:
            kp, kd, tf, u_max = C[off + 1], C[off + 2], C[off + 3], C[off + 4]
        quiet = True
        one_path = True
        for j in range(LANES):
            g = first + j if j < L else first
            zi[j] = zinv[g]
            sd[j] = std[g]
            tl[j] = tidx[g]
            quiet = quiet and std[g] == 0.0
            one_path = one_path and tidx[g] == tj
        for r in range(_W_ROWS):
            for j in range(LANES):
                W[r, j] = 0.0
        for r in range(_A_ROWS):
            for j in range(LANES):
                A[r, j] = 0.0
        for j in range(LANES):
            W[0, j] = start[tl[j], 0]
            W[1, j] = start[tl[j], 1]
            W[2, j] = start[tl[j], 2]
            W[7, j] = W[0, j]
            W[8, j] = W[1, j]
        failed = False
        for k in range(n_steps + 1):
            h = hold[k]
            t = k * ts
            end = k == k_start or k == n_steps
            if one_path:  # (runs are sorted by path: the usual block has one)
                xr, yr_, v0 = xref[k, tj], yref[k, tj], v0ref[k, tj]
                for j in range(LANES):
                    W[39, j] = xr
                    W[40, j] = yr_
                    W[41, j] = v0
            else:  # a gather: a loop of its own
                for j in range(LANES):
                    W[39, j] = xref[k, tl[j]]
                    W[40, j] = yref[k, tl[j]]
                    W[41, j] = v0ref[k, tl[j]]
            for j in range(LANES):  # desired heading, errors
                W[12, j] = W[39, j] - W[0, j]  # dx
                W[13, j] = W[40, j] - W[1, j]  # dy
            if previous:
                for j in range(LANES):
                    W[20, j] = W[39, j] - W[7, j]
                    W[21, j] = W[40, j] - W[8, j]
                _atan2_lanes(W, 21, 20, 14, LANES)  # theta_d
            else:
                _atan2_lanes(W, 13, 12, 14, LANES)
            if quiet:  # sigma = 0: theta + 0 * 0.0, as the numpy engine's zero row
                for j in range(LANES):
                    W[15, j] = W[2, j] + 0.0
            else:  # theta_meas (a gather: a loop of its own)
                for j in range(LANES):
                    W[15, j] = W[2, j] + Z[zi[j], h] * sd[j]
            for j in range(LANES):
                W[16, j] = W[14, j] - W[2, j]
                W[17, j] = W[14, j] - W[15, j]
            _wrap_lanes(W, 16, LANES)  # e_true
            _wrap_lanes(W, 17, LANES)  # e_meas
            if k:
                for j in range(LANES):
                    W[10, j] = W[17, j] - W[9, j]
                _wrap_lanes(W, 10, LANES)  # de
            if kind == FUZZY:
                for j in range(LANES):
                    X[0, j] = fmin(fmax(W[17, j] * ke, lo0), hi0)
                    X[1, j] = fmin(fmax(W[10, j] * kde, lo1), hi1)
                eval_block(P, X, lanes, S, yl, yr, st)
                for j in range(LANES):
                    W[18, j] = (yl[j] + yr[j]) * 0.5
                bad = 0
                for j in range(LANES):
                    bad += 0 if st[j] == OK else 1
                if bad:
                    for j in range(L):
                        if st[j] != OK:
                            status[first + j] = st[j]
                    failed = True
                    break
            else:
                for j in range(LANES):
                    d = W[11, j] * tf
                    d = d + W[10, j]
                    d = d / (tf + ts)
                    W[11, j] = d
                    u = kp * W[17, j] + kd * d
                    W[18, j] = fmin(fmax(u, -u_max), u_max)
            for j in range(LANES):  # voltages
                u = W[18, j]
                v0 = W[41, j]
                vr_req = v0 + u
                vl_req = v0 - u
                W[22, j] = fmin(fmax(vr_req, -v_lim), v_lim)
                W[23, j] = fmin(fmax(vl_req, -v_lim), v_lim)
                W[38, j] = 1.0 if (abs(vr_req) > v_lim or abs(vl_req) > v_lim) else 0.0
            if k >= k_start:  # metrics
                _integrals(A, 0, W, 16, t, end)
                _integrals(A, 8, W, 17, t, end)
            for j in range(LANES):
                dx, dy = W[12, j], W[13, j]
                dist = math.sqrt(dx * dx + dy * dy)
                A[16, j] += dist * dist
                A[17, j] = fmax(A[17, j], dist)
                A[18, j] = dist
            for j in range(LANES):
                u = W[18, j]
                uu = u * u
                A[19, j] += uu
            if k == 0 or k == n_steps:
                for j in range(LANES):
                    u = W[18, j]
                    A[20, j] += u * u
            if k > 0:
                for j in range(LANES):
                    A[22, j] += abs(W[18, j] - A[21, j])
            for j in range(LANES):
                A[21, j] = W[18, j]
            if k < n_steps:
                for j in range(LANES):
                    A[23, j] += W[38, j]
            if record:
                for j in range(L):
                    g = first + j
                    wr, wl = W[4, j], W[6, j]
                    rec[0, g, k] = W[0, j]
                    rec[1, g, k] = W[1, j]
                    rec[2, g, k] = W[2, j]
                    rec[3, g, k] = W[39, j]
                    rec[4, g, k] = W[40, j]
                    rec[5, g, k] = W[14, j]
                    rec[6, g, k] = W[15, j]
                    rec[7, g, k] = W[16, j]
                    rec[8, g, k] = W[17, j]
                    rec[9, g, k] = W[10, j]
                    rec[10, g, k] = W[18, j]
                    rec[11, g, k] = W[22, j]
                    rec[12, g, k] = W[23, j]
                    rec[13, g, k] = wr
                    rec[14, g, k] = wl
                    rec[15, g, k] = half_r * (wr + wl)
                    rec[16, g, k] = w_scale * (wr - wl)
            for j in range(LANES):
                W[9, j] = W[17, j]  # e_prev
            if k < n_steps:
                if previous:
                    for j in range(LANES):
                        W[7, j] = W[0, j]
                        W[8, j] = W[1, j]
                _plant_lanes(W, plant, n_nodes, 22, 23)
        if failed:
            continue
        for j in range(L):
            g = first + j
            for q in range(2):
                base = 8 * q
                for i in range(4):
                    metrics[g, 4 * q + i] = ts * (A[base + i, j] - 0.5 * A[base + 4 + i, j])
            metrics[g, 8] = math.sqrt(A[16, j] / (n_steps + 1))
            metrics[g, 9] = A[17, j]
            metrics[g, 10] = A[18, j]
            metrics[g, 11] = ts * (A[19, j] - 0.5 * A[20, j])
            metrics[g, 12] = A[22, j]
            metrics[g, 13] = A[23, j] * ts


loop = _compiled()(_loop)

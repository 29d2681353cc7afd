"""numba-compiled closed loop (imported lazily by :mod:`.compiled`).

One task advances a *block* of up to :data:`LANES` runs that share a controller through the
whole run, lane by lane: desired heading, noise, errors, controller, saturation, metrics and
the exact-ZOH plant step, with the operations of :meth:`._Engine.run`,
:meth:`~it2track.plant.DifferentialDrive.step` and :class:`.metrics.MetricAccumulator` in the
same order, so every number is the numpy engine's, bit for bit. The kernel is serial and
releases the GIL; :mod:`.compiled` runs disjoint sets of blocks on several threads. A run never
reads another run's numbers, so results do not depend on the block, the batch or the number of
threads. Fuzzy controllers are evaluated by
:func:`it2track.fuzzy._jit.eval_block` on the block's lanes.

numba checks a cached function against its own source file only: after editing
``fuzzy/_jit.py``, ``fuzzy/libm.py``, ``tracking/libm.py`` or ``plant/drive.py``'s sine/cosine
constants in a development checkout, touch this file too (or clear ``__pycache__``).
"""

from __future__ import annotations

import math

import numpy as np

from ..fuzzy._jit import N_ROWS, N_RULES, OK, _compiled, eval_block
from ..plant.drive import (
    _COS_KERNEL,
    _KERNEL_LIMIT,
    _PIO2_HI,
    _PIO2_LO,
    _SIN_KERNEL,
    _SINCOS_LIMIT,
    _TWO_OVER_PI,
)
from .libm import atan2_scalar

LANES = 64  # runs per block
#: Controller kinds in a packed controller (first value).
FUZZY, PD = 0.0, 1.0
#: Config vector: ts, voltage limit, r/2, r/(2l), N, metric start index, previous-pose flag.
TS, V_LIM, HALF_R, W_SCALE, N_STEPS, K_START, PREVIOUS = range(7)
N_METRICS = 14
N_FIELDS = 17

atan2 = _compiled(inline=True)(atan2_scalar)  # scalar arguments: calls cost no reference counting
_PI = math.pi
_TWO_PI = 2.0 * math.pi
_S1, _S2, _S3, _S4, _S5, _S6 = _SIN_KERNEL
_C1, _C2, _C3, _C4, _C5, _C6 = _COS_KERNEL


@_compiled(inline=True)
def _wrap(a):
    """simulate._wrap_inplace for one angle."""
    if a <= -_PI or a > _PI:
        w = _PI - ((_PI - a) % _TWO_PI)  # Python/numba float % is numpy's np.mod
        return _PI if w <= -_PI else w
    return a


@_compiled(inline=True)
def _kernels(r):
    """drive._sincos_kernels for one value: (sin r, cos r), |r| <= pi/4."""
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
    """drive._sincos for one value."""
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


@_compiled(inline=True)
def _sincos_small(x):
    """drive._sincos_small for one value."""
    if abs(x) > _KERNEL_LIMIT:
        return _sincos(x)
    return _kernels(x)


@_compiled()
def _plant_step(W, j, plant, n_nodes, VR, VL):
    """DifferentialDrive.step for lane ``j`` of the state rows W[0:7] = x, y, theta, i_R,
    omega_R, i_L, omega_L. ``plant`` = wheel map (6), heading map (3), then per node the
    speed (3) and heading (3) maps."""
    x, y, th = W[0, j], W[1, j], W[2, j]
    i_r, w_r, i_l, w_l = W[3, j], W[4, j], W[5, j], W[6, j]
    s_i = i_r + i_l
    s_w = w_r + w_l
    s_v = VR + VL
    d_i = i_r - i_l
    d_w = w_r - w_l
    d_v = VR - VL
    sin0, cos0 = _sincos(th)
    acc_c = 0.0
    acc_s = 0.0
    for n in range(n_nodes):
        q = 9 + 6 * n
        weight = s_i * plant[q]
        weight = weight + s_w * plant[q + 1]
        weight = weight + s_v * plant[q + 2]
        delta = d_i * plant[q + 3]
        delta = delta + d_w * plant[q + 4]
        delta = delta + d_v * plant[q + 5]
        sn, cs = _sincos_small(delta)
        if n == 0:
            acc_c = cs * weight
            acc_s = sn * weight
        else:
            acc_c = acc_c + cs * weight
            acc_s = acc_s + sn * weight
    W[0, j] = x + (cos0 * acc_c - sin0 * acc_s)
    W[1, j] = y + (sin0 * acc_c + cos0 * acc_s)
    delta = d_i * plant[6]
    delta = delta + d_w * plant[7]
    delta = delta + d_v * plant[8]
    W[2, j] = th + delta
    a00, a01, b0, a10, a11, b1 = plant[0], plant[1], plant[2], plant[3], plant[4], plant[5]
    W[3, j] = (i_r * a00 + w_r * a01) + VR * b0
    W[4, j] = (i_r * a10 + w_r * a11) + VR * b1
    W[5, j] = (i_l * a00 + w_l * a01) + VL * b0
    W[6, j] = (i_l * a10 + w_l * a11) + VL * b1


@_compiled(inline=True)
def _integrals(A, base, j, e, t, end):
    """_IntegralErrors.update for lane j: rows base..base+3 sums, base+4..base+7 ends."""
    a = abs(e)
    s = e * e
    A[base, j] += a
    A[base + 2, j] += s
    if end:
        A[base + 4, j] += a
        A[base + 6, j] += s
    a = a * t
    s = s * t
    A[base + 1, j] += a
    A[base + 3, j] += s
    if end:
        A[base + 5, j] += a
        A[base + 7, j] += s


# Rows of the lane state W: pose and wheels (0-6), previous x, y (7, 8), e_prev (9), de (10),
# PD derivative (11), then per-step values.
_W_ROWS = 24
# Rows of the accumulators A: true integrals (0-7), measured (8-15), dist_sq, dist_max,
# dist_final, effort_sum, effort_ends, u_prev, u_tv, sat_steps (16-23).
_A_ROWS = 24


def _loop(C, c_off, blocks, tidx, std, zinv, Z, hold, xref, yref, v0ref, start, plant, cfg,
          metrics, rec, record, status):  # fmt: skip
    """Advance every block of runs through the whole run (see the module docstring).

    ``blocks`` (n_blocks, 3): first run, end, controller; runs are rows of ``tidx`` (trajectory),
    ``std`` (noise std), ``zinv`` (row of ``Z``, the standard noise). Writes ``metrics``
    (B, 14), ``rec`` (17, B, N+1) if ``record``, and ``status`` (B,): not OK where the fuzzy
    reference would raise (the block stops there).
    """
    n_steps = int(cfg[N_STEPS])
    k_start = int(cfg[K_START])
    previous = cfg[PREVIOUS] != 0.0
    ts, v_lim, half_r, w_scale = cfg[TS], cfg[V_LIM], cfg[HALF_R], cfg[W_SCALE]
    n_nodes = (plant.size - 9) // 6
    for b in range(blocks.shape[0]):
        first, stop, ci = blocks[b, 0], blocks[b, 1], blocks[b, 2]
        L = stop - first
        off = c_off[ci]
        kind = C[off]
        W = np.zeros((_W_ROWS, LANES))
        A = np.zeros((_A_ROWS, LANES))
        if kind == FUZZY:
            ke, kde = C[off + 1], C[off + 2]
            P = C[off + 3 : c_off[ci + 1]]
            S = np.empty((int(P[N_ROWS]) + 4 + 2 * int(P[N_RULES]), LANES))
        else:
            ke, kde = 0.0, 0.0
            P = C[off : off + 1]
            S = np.empty((1, LANES))
        X = np.empty((2, LANES))
        yl = np.empty(LANES)
        yr = np.empty(LANES)
        st = np.zeros(LANES, dtype=np.int8)
        for j in range(L):
            tj = tidx[first + j]
            W[0, j] = start[tj, 0]
            W[1, j] = start[tj, 1]
            W[2, j] = start[tj, 2]
            W[7, j] = W[0, j]
            W[8, j] = W[1, j]
        failed = False
        for k in range(n_steps + 1):
            h = hold[k]
            t = k * ts
            end = k == k_start or k == n_steps
            for j in range(L):  # desired heading, measurement, errors
                g = first + j
                tj = tidx[g]
                xr = xref[k, tj]
                yr_ = yref[k, tj]
                dx = xr - W[0, j]
                dy = yr_ - W[1, j]
                if previous:
                    theta_d = atan2(yr_ - W[8, j], xr - W[7, j])
                else:
                    theta_d = atan2(dy, dx)
                th = W[2, j]
                theta_meas = th + Z[zinv[g], h] * std[g]
                e_true = _wrap(theta_d - th)
                e_meas = _wrap(theta_d - theta_meas)
                if k:
                    W[10, j] = _wrap(e_meas - W[9, j])
                W[12, j] = dx
                W[13, j] = dy
                W[14, j] = theta_d
                W[15, j] = theta_meas
                W[16, j] = e_true
                W[17, j] = e_meas
            if kind == FUZZY:
                for j in range(L):
                    X[0, j] = min(max(W[17, j] * ke, P[int(P[12])]), P[int(P[13])])
                    X[1, j] = min(max(W[10, j] * kde, P[int(P[12]) + 1]), P[int(P[13]) + 1])
                eval_block(P, X, L, S, yl, yr, st)
                for j in range(L):
                    if st[j] != OK:
                        status[first + j] = st[j]
                        failed = True
                    W[18, j] = (yl[j] + yr[j]) * 0.5
                if failed:
                    break
            else:
                kp, kd, tf, u_max = C[off + 1], C[off + 2], C[off + 3], C[off + 4]
                for j in range(L):
                    d = W[11, j] * tf
                    d = d + W[10, j]
                    d = d / (tf + ts)
                    W[11, j] = d
                    u = kp * W[17, j] + kd * d
                    W[18, j] = min(max(u, -u_max), u_max)
            for j in range(L):  # voltages, metrics, record, plant
                g = first + j
                tj = tidx[g]
                u = W[18, j]
                v0 = v0ref[k, tj]
                vr_req = v0 + u
                vl_req = v0 - u
                VR = min(max(vr_req, -v_lim), v_lim)
                VL = min(max(vl_req, -v_lim), v_lim)
                dx, dy = W[12, j], W[13, j]
                dist = math.sqrt(dx * dx + dy * dy)
                if k >= k_start:
                    _integrals(A, 0, j, W[16, j], t, end)
                    _integrals(A, 8, j, W[17, j], t, end)
                A[16, j] += dist * dist
                A[17, j] = max(A[17, j], dist)
                if k == n_steps:
                    A[18, j] = dist
                uu = u * u
                A[19, j] += uu
                if k == 0 or k == n_steps:
                    A[20, j] += uu
                if k > 0:
                    A[22, j] += abs(u - A[21, j])
                A[21, j] = u
                if k < n_steps and (abs(vr_req) > v_lim or abs(vl_req) > v_lim):
                    A[23, j] += 1.0
                if record:
                    wr, wl = W[4, j], W[6, j]
                    rec[0, g, k] = W[0, j]
                    rec[1, g, k] = W[1, j]
                    rec[2, g, k] = W[2, j]
                    rec[3, g, k] = xref[k, tj]
                    rec[4, g, k] = yref[k, tj]
                    rec[5, g, k] = W[14, j]
                    rec[6, g, k] = W[15, j]
                    rec[7, g, k] = W[16, j]
                    rec[8, g, k] = W[17, j]
                    rec[9, g, k] = W[10, j]
                    rec[10, g, k] = u
                    rec[11, g, k] = VR
                    rec[12, g, k] = VL
                    rec[13, g, k] = wr
                    rec[14, g, k] = wl
                    rec[15, g, k] = half_r * (wr + wl)
                    rec[16, g, k] = w_scale * (wr - wl)
                if k < n_steps:
                    if previous:
                        W[7, j] = W[0, j]
                        W[8, j] = W[1, j]
                    _plant_step(W, j, plant, n_nodes, VR, VL)
                W[9, j] = W[17, j]  # e_prev
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

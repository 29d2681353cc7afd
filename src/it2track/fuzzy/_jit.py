"""numba-compiled evaluation of a packed Sugeno system (imported lazily by :mod:`.kernels`).

Every function here mirrors the numpy reference (:mod:`.tables`, :mod:`.sugeno`,
:mod:`.reducers`) operation for operation, so the results are the same bits: the same IEEE
operations in the same order, sums over rules in rule order, no fast-math, no contraction of
multiply-adds. A system is one flat float64 array ``P`` (layout in :mod:`.kernels`), so one
compilation serves every system and a call passes a single array.

The scalar building blocks (numba options, min/max selects, ``exp``/``log``/``cos``, the
membership curves and t-norms) are in :mod:`._jit_lib`; this module holds the block kernels.

Compiled functions are cached on disk (``cache=True``): the first call of a process loads them
(tens of ms) instead of compiling them (seconds). numba checks a cached function against its
own source file only; :mod:`it2track.tracking._jit` calls :func:`eval_block` from here, so
after editing this file or ``_jit_lib.py`` in a development checkout touch this one and that
one too (or clear ``__pycache__``).
"""

from __future__ import annotations

import math

import numpy as np

from ._jit_lib import MINIMUM, _compiled, _curve, _tnorm, exp, fmax, fmin

# Header of a packed system (see kernels.pack); offsets point into the same array.
N_IN, N_ROWS, N_RULES, REDUCER, TNORM, MAX_ITER, HAS_ZERO, ZERO = 0, 1, 2, 3, 4, 5, 6, 7
TOL_L, TOL_R, K0_L, K0_R = 8, 9, 10, 11
O_LO, O_HI, O_KIND, O_PAR, O_INP, O_UR, O_LR, O_YLO, O_YHS, O_OHI = range(12, 22)
O_WM, O_YM, O_YHI = 22, 23, 24
HEADER = 25

# Reducer codes (REDUCER); T1 / T1_SUM are the T1Sugeno weighted average / weighted sum.
EXHAUSTIVE, KM, EKM, EIASC, NIE_TAN, WU_MENDEL, T1, T1_SUM = 0, 1, 2, 3, 4, 5, 6, 7
# Status codes: the reference raises where the status is not OK.
OK, ZERO_FIRING, WM_ZERO_LOWER, NOT_CONVERGED = 0, 1, 2, 3

WORK_ROWS = 13  # work rows of the reducers in a block's scratch


@_compiled()
def _memberships(P, X, L, S, ext):
    """Rows ``S[0:M]`` = memberships of the points ``X[:, :L]``; ``S[M]`` = 1. The kinds of
    :mod:`.curves`, :mod:`.shapes` and MATLAB's lagged lower MFs only where ``ext`` is not
    None (see :func:`eval_block`)."""
    n_rows = int(P[N_ROWS])
    o_kind, o_par, o_inp = int(P[O_KIND]), int(P[O_PAR]), int(P[O_INP])
    for k in range(n_rows):
        kind = int(P[o_kind + k])
        p = o_par + 5 * k
        i = int(P[o_inp + k])
        a, b, c, d, h = P[p], P[p + 1], P[p + 2], P[p + 3], P[p + 4]
        if kind == 0:  # trapezoid (a, wl, d, wr, h); min/max: branch-free, never NaN here
            for j in range(L):
                v = X[i, j]
                S[k, j] = fmax(fmin(fmin((v - a) / b, (c - v) / d), 1.0), 0.0) * h
        elif kind == 1:  # Gaussian (mean, sigma, h)
            for j in range(L):
                z = (X[i, j] - a) / b
                S[k, j] = c * exp((-0.5 * z) * z)
        elif kind == 2:  # uncertain-mean Gaussian, upper (m1, m2, sigma, h)
            for j in range(L):
                v = X[i, j]
                z = ((v - fmin(fmax(v, a), b)) - 0.0) / c
                S[k, j] = d * exp((-0.5 * z) * z)
        elif kind == 3:  # uncertain-mean Gaussian, lower
            mid = 0.5 * (a + b)
            for j in range(L):
                v = X[i, j]
                z = ((v - (b if v <= mid else a)) - 0.0) / c
                S[k, j] = d * exp((-0.5 * z) * z)
        elif ext is not None:  # (pruned at compile time when ext is None)
            if kind == 19:  # scaled and lagged row a (MATLAB's type-2 lower MF)
                up = int(a)  # (row, scale peak, lag, peak)
                for j in range(L):
                    S[k, j] = b * fmin(fmax((S[up, j] / d - c) / (1.0 - c), 0.0), 1.0)
            else:  # one scalar function for the other shapes
                for j in range(L):
                    S[k, j] = _curve(kind, a, b, c, d, h, X[i, j])
    for j in range(L):
        S[n_rows, j] = 1.0


@_compiled()
def _firing(P, L, S, flb, fub, ext):
    """Rule firing ``S[flb + r]``, ``S[fub + r]``; the t-norms other than product and minimum
    only where ``ext`` is not None (see :func:`eval_block`)."""
    n_in, n_rules = int(P[N_IN]), int(P[N_RULES])
    o_ur, o_lr = int(P[O_UR]), int(P[O_LR])
    if ext is not None:  # (pruned at compile time when ext is None)
        code = int(P[TNORM])
        if code > MINIMUM:
            _firing_mentioned(P, L, S, flb, fub, code)
            return
    prod = P[TNORM] == 0.0
    for r in range(n_rules):
        b = r * n_in
        u = int(P[o_ur + b])
        lw = int(P[o_lr + b])
        for j in range(L):
            S[fub + r, j] = S[u, j]
            S[flb + r, j] = S[lw, j]
        for i in range(1, n_in):
            u = int(P[o_ur + b + i])
            lw = int(P[o_lr + b + i])
            if prod:
                for j in range(L):
                    S[fub + r, j] = S[fub + r, j] * S[u, j]
                    S[flb + r, j] = S[flb + r, j] * S[lw, j]
            else:
                for j in range(L):
                    S[fub + r, j] = fmin(S[fub + r, j], S[u, j])
                    S[flb + r, j] = fmin(S[flb + r, j], S[lw, j])


@_compiled()
def _firing_mentioned(P, L, S, flb, fub, code):
    """AND over the inputs each rule mentions only (tables' fold for the t-norms whose identity
    is not exact): the first one copied, the others folded left to right."""
    n_in, n_rows, n_rules = int(P[N_IN]), int(P[N_ROWS]), int(P[N_RULES])
    o_ur, o_lr = int(P[O_UR]), int(P[O_LR])
    for r in range(n_rules):
        b = r * n_in
        first = True
        for i in range(n_in):
            u = int(P[o_ur + b + i])
            lw = int(P[o_lr + b + i])
            if u == n_rows:
                continue
            if first:
                for j in range(L):
                    S[fub + r, j] = S[u, j]
                    S[flb + r, j] = S[lw, j]
                first = False
            else:
                for j in range(L):
                    S[fub + r, j] = _tnorm(code, S[fub + r, j], S[u, j])
                    S[flb + r, j] = _tnorm(code, S[flb + r, j], S[lw, j])


@_compiled(inline=True)
def _row(P, o_idx, n):
    """Position of the n-th rule of an ordering (``o_idx < 0``: identity)."""
    return n if o_idx < 0 else int(P[o_idx + n])


@_compiled()
def _exhaustive(P, L, S, flb, fub, tb, oy, o_idx, left, out):
    """reducers._exhaustive_both for the lanes: ``yl`` (left) or ``yr`` into ``out``."""
    n_rules = int(P[N_RULES])
    num, den, best = tb, tb + 1, tb + 2
    g = _row(P, o_idx, 0)
    y = P[oy]
    for j in range(L):
        S[num, j] = S[flb + g, j] * y
        S[den, j] = S[flb + g, j]
    for n in range(1, n_rules):
        g = _row(P, o_idx, n)
        y = P[oy + n]
        for j in range(L):
            S[num, j] += S[flb + g, j] * y
            S[den, j] += S[flb + g, j]
    for j in range(L):
        S[best, j] = S[num, j] / S[den, j]
    for m in range(n_rules):
        n = m if left else n_rules - 1 - m
        g = _row(P, o_idx, n)
        y = P[oy + n]
        for j in range(L):
            dd = S[fub + g, j] - S[flb + g, j]
            S[num, j] += dd * y
            S[den, j] += dd
            c = S[num, j] / S[den, j]
            bj = S[best, j]
            if left:  # np.fmin / np.fmax: a NaN loses
                S[best, j] = c if (c < bj or bj != bj) else bj
            else:
                S[best, j] = c if (c > bj or bj != bj) else bj
    for j in range(L):
        out[j] = S[best, j]


@_compiled()
def _centroid_lanes(P, L, S, flb, fub, oy, o_idx, left, krow, onum, oden):
    """``S[onum]`` = centroid of the lanes with ``S[krow]`` rules (from the bottom) at upper
    firing for ``yl`` (at lower firing for ``yr``): reducers' ``_centroid(theta(k, ...))``,
    the sums in rule order."""
    n_rules = int(P[N_RULES])
    g = _row(P, o_idx, 0)
    y = P[oy]
    for j in range(L):  # both loads before the select: a conditional load does not vectorise
        u, lo = S[fub + g, j], S[flb + g, j]
        t = u if (S[krow, j] > 0.0) == left else lo
        S[onum, j] = t * y
        S[oden, j] = t
    for n in range(1, n_rules):
        g = _row(P, o_idx, n)
        y = P[oy + n]
        for j in range(L):
            u, lo = S[fub + g, j], S[flb + g, j]
            t = u if (S[krow, j] > n) == left else lo
            S[onum, j] += t * y
            S[oden, j] += t
    for j in range(L):
        S[onum, j] = S[onum, j] / S[oden, j]


@_compiled()
def _switch_lanes(P, L, S, flb, fub, tb, oy, o_idx, left, k0, tol, out, st):
    """reducers._switch_iterations (KM: ``k0 < 0``; EKM: start at ``k0``) for the lanes,
    vectorised: every lane makes the reference's iterations, with its tie resolution (a
    consequent within ``tol`` of the centroid: both placements evaluated), as branch-free
    selects, until its switch point stops moving. ``out[j]``: the centroid; ``st[j]`` becomes
    NOT_CONVERGED where it is OK and the lane does not converge. Work rows ``tb .. tb + 12``.

    ``searchsorted(y, v, "right")`` on the sorted consequents is the count of ``y_n <= v``
    (``"left"``: ``y_n < v``; NaN: all), and the reference's tie test
    ``min(c - below, above - c) <= tol`` holds exactly when some ``|c - y_n| <= tol``.
    """
    n_rules, max_iter = int(P[N_RULES]), int(P[MAX_ITER])
    all_upper = float(n_rules if left else 0)
    num, den, kk, act, tie, tk, ty = tb, tb + 1, tb + 2, tb + 3, tb + 4, tb + 5, tb + 6
    ka, kb, an, ad, bn, bd = tb + 7, tb + 8, tb + 9, tb + 10, tb + 11, tb + 12
    if k0 < 0:  # KM: start from the centroid of the interval midpoints
        g = _row(P, o_idx, 0)
        y = P[oy]
        for j in range(L):
            t = 0.5 * (S[flb + g, j] + S[fub + g, j])
            S[num, j] = t * y
            S[den, j] = t
        for n in range(1, n_rules):
            g = _row(P, o_idx, n)
            y = P[oy + n]
            for j in range(L):
                t = 0.5 * (S[flb + g, j] + S[fub + g, j])
                S[num, j] += t * y
                S[den, j] += t
        for j in range(L):
            S[num, j] = S[num, j] / S[den, j]
            S[kk, j] = 0.0
        for n in range(n_rules):
            y = P[oy + n]
            for j in range(L):
                S[kk, j] += 1.0 if y <= S[num, j] else 0.0
        for j in range(L):
            c = S[num, j]
            S[kk, j] = all_upper if c != c else S[kk, j]
    else:
        for j in range(L):
            S[kk, j] = float(k0)
    for j in range(L):
        S[act, j] = 1.0
        S[tk, j] = -1.0
        S[ty, j] = math.nan
        out[j] = math.nan
    for _ in range(max_iter):
        _centroid_lanes(P, L, S, flb, fub, oy, o_idx, left, kk, num, den)  # c_new
        for j in range(L):
            S[den, j] = 0.0  # k_new
            S[tie, j] = 0.0
        for n in range(n_rules):
            y = P[oy + n]
            for j in range(L):
                c = S[num, j]
                S[den, j] += 1.0 if y <= c else 0.0
                S[tie, j] = 1.0 if abs(c - y) <= tol else S[tie, j]
        # (every load before the selects, bitwise & on the flags, integer counts: what the
        # loop vectoriser needs)
        ties = 0
        for j in range(L):
            c, k, kn, tj, aj = S[num, j], S[kk, j], S[den, j], S[tie, j], S[act, j]
            tkj, tyj = S[tk, j], S[ty, j]
            k_new = all_upper if c != c else kn
            near = (tj != 0.0) & (aj != 0.0)
            settled = near & (k == tkj) & (abs(c - tyj) <= tol)
            S[den, j] = k if settled else k_new
            t = near & ~settled
            S[tie, j] = 1.0 if t else 0.0
            ties += 1 if t else 0
        if ties:  # resolve the ties: both placements, keep the better
            for j in range(L):
                S[ka, j] = 0.0
                S[kb, j] = 0.0
            for n in range(n_rules):
                y = P[oy + n]
                for j in range(L):
                    c = S[num, j]
                    S[ka, j] += 1.0 if y < c - tol else 0.0
                    S[kb, j] += 1.0 if y <= c + tol else 0.0
            _centroid_lanes(P, L, S, flb, fub, oy, o_idx, left, ka, an, ad)
            _centroid_lanes(P, L, S, flb, fub, oy, o_idx, left, kb, bn, bd)
            for j in range(L):
                ca, cb, kaj, kbj, kj = S[an, j], S[bn, j], S[ka, j], S[kb, j], S[kk, j]
                t, dj, tkj = S[tie, j] != 0.0, S[den, j], S[tk, j]
                better = (ca < cb) if left else (ca > cb)
                take_a = better | (cb != cb) | ((ca == cb) & (kj == kaj))
                pick = kaj if take_a else kbj
                S[den, j] = pick if t else dj
                S[tk, j] = pick if t else tkj
                S[kb, j] = kbj - 1.0 if kbj > 0.0 else float(n_rules - 1)  # y[kb - 1]
            for n in range(n_rules):
                y = P[oy + n]
                for j in range(L):
                    tj, kbj, tyj = S[tie, j], S[kb, j], S[ty, j]
                    S[ty, j] = y if ((tj != 0.0) & (kbj == n)) else tyj
        active = 0
        for j in range(L):
            c, k, k_new, aj, oj = S[num, j], S[kk, j], S[den, j], S[act, j], out[j]
            done = (k_new == k) | ((c != c) & (k == all_upper))
            a = aj != 0.0
            out[j] = c if (a & done) else oj
            still = a & ~done
            S[act, j] = 1.0 if still else 0.0
            S[kk, j] = k_new
            active += 1 if still else 0
        if active == 0:
            return
    for j in range(L):  # not converged in max_iter
        if S[act, j] != 0.0:
            out[j] = math.nan
            st[j] = st[j] if st[j] != OK else NOT_CONVERGED


@_compiled()
def _eiasc_lanes(P, L, S, flb, fub, tb, oy, o_idx, left, out, st):
    """reducers' EIASC for the lanes, vectorised: the same sums in the same order; a lane keeps
    the first centroid that stops it. Work rows ``tb .. tb + 2``."""
    n_rules, max_iter = int(P[N_RULES]), int(P[MAX_ITER])
    sa, sb, act = tb, tb + 1, tb + 2
    g = _row(P, o_idx, 0)
    y = P[oy]
    for j in range(L):
        S[sa, j] = S[flb + g, j] * y
        S[sb, j] = S[flb + g, j]
        S[act, j] = 1.0
    for n in range(1, n_rules):
        g = _row(P, o_idx, n)
        y = P[oy + n]
        for j in range(L):
            S[sa, j] += S[flb + g, j] * y
            S[sb, j] += S[flb + g, j]
    for it in range(n_rules):
        if it >= max_iter:
            for j in range(L):
                if S[act, j] != 0.0:
                    out[j] = math.nan
                    st[j] = st[j] if st[j] != OK else NOT_CONVERGED
            return
        n = it if left else n_rules - 1 - it
        g = _row(P, o_idx, n)
        y = P[oy + n]
        last = n + 1 >= n_rules if left else n == 0
        nxt = 0.0 if last else P[oy + n + 1] if left else P[oy + n - 1]
        active = 0
        for j in range(L):  # loads first, bitwise flags, an integer count: vectorises
            u, lo, aj, oj = S[fub + g, j], S[flb + g, j], S[act, j], out[j]
            step = u - lo
            a_ = S[sa, j] + y * step
            b_ = S[sb, j] + step
            S[sa, j] = a_
            S[sb, j] = b_
            c = a_ / b_
            stop = last | ((c <= nxt) if left else (c >= nxt))
            a = aj != 0.0
            out[j] = c if (a & stop) else oj
            still = a & ~stop
            S[act, j] = 1.0 if still else 0.0
            active += 1 if still else 0
        if active == 0:
            return


@_compiled()
def _wu_mendel(P, L, S, flb, fub, tb, yl, yr):
    """reducers._wu_mendel for the lanes (rows in rule order, as _dot_rows/_sum_rows)."""
    n_rules = int(P[N_RULES])
    ylo, yhi, wm = int(P[O_YLO]), int(P[O_YHI]), int(P[O_WM])
    for j in range(L):
        sl = S[flb, j]
        su = S[fub, j]
        a0 = S[flb, j] * P[ylo]  # sum fl y_lo
        a1 = S[fub, j] * P[ylo]  # sum fu y_lo
        a2 = S[flb, j] * P[yhi]  # sum fl y_hi
        a3 = S[fub, j] * P[yhi]  # sum fu y_hi
        pl = S[flb, j] * P[wm]
        ql = S[fub, j] * P[wm + n_rules]
        pr = S[fub, j] * P[wm + 2 * n_rules]
        qr = S[flb, j] * P[wm + 3 * n_rules]
        for n in range(1, n_rules):
            fl = S[flb + n, j]
            fu = S[fub + n, j]
            sl += fl
            su += fu
            a0 += fl * P[ylo + n]
            a1 += fu * P[ylo + n]
            a2 += fl * P[yhi + n]
            a3 += fu * P[yhi + n]
            pl += fl * P[wm + n]
            ql += fu * P[wm + n_rules + n]
            pr += fu * P[wm + 2 * n_rules + n]
            qr += fl * P[wm + 3 * n_rules + n]
        yl0 = a0 / sl
        ylm = a1 / su
        yr0 = a2 / sl
        yrm = a3 / su
        # np.minimum / np.maximum: NaN wins, and of equal values (zeros of either sign) the
        # second
        yl_outer_hi = math.nan if yl0 != yl0 or ylm != ylm else (yl0 if yl0 < ylm else ylm)
        yr_outer_lo = math.nan if yr0 != yr0 or yrm != yrm else (yr0 if yr0 > yrm else yrm)
        spread = (su - sl) / (su * sl)
        yl_lo = yl_outer_hi - spread * (pl * ql / (pl + ql) if pl + ql > 0 else 0.0)
        yr_hi = yr_outer_lo + spread * (pr * qr / (pr + qr) if pr + qr > 0 else 0.0)
        yl[j] = 0.5 * (yl_lo + yl_outer_hi)
        yr[j] = 0.5 * (yr_outer_lo + yr_hi)


@_compiled()
def eval_block(P, X, L, S, yl, yr, st, ext=None):
    """``yl[:L]``, ``yr[:L]`` and ``st[:L]`` (status) of the clipped points ``X[:, :L]``;
    ``S`` is scratch of at least ``L`` columns and ``M + 1 + 2 R + WORK_ROWS`` rows:
    memberships (``M = P[N_ROWS]`` rows and the row of ones), lower and upper firing
    (``R = P[N_RULES]`` each) and :data:`WORK_ROWS` work rows.

    ``ext`` (None or True) chooses the specialisation: left out, numba prunes the branches of
    the kinds of :mod:`.curves`/:mod:`.shapes`, MATLAB's lagged lower MFs, the t-norms other
    than product/minimum and ``wtsum`` before compiling, so that systems without them (the
    paper's) compile and run exactly the code they did before those existed;
    :func:`it2track.fuzzy.kernels.extended` says which systems need ``ext=True``."""
    n_rows, n_rules = int(P[N_ROWS]), int(P[N_RULES])
    flb = n_rows + 1
    fub = flb + n_rules
    tb = fub + n_rules
    _memberships(P, X, L, S, ext)
    _firing(P, L, S, flb, fub, ext)
    red = int(P[REDUCER])
    for j in range(L):
        st[j] = OK
    ylo, yhs, ohi = int(P[O_YLO]), int(P[O_YHS]), int(P[O_OHI])
    if red == T1 or red == T1_SUM:  # T1Sugeno: weighted average / sum of the firing
        num, den = tb, tb + 1
        y = P[ylo]
        for j in range(L):
            S[num, j] = S[fub, j] * y
            S[den, j] = S[fub, j]
        for n in range(1, n_rules):
            y = P[ylo + n]
            for j in range(L):
                S[num, j] += S[fub + n, j] * y
                S[den, j] += S[fub + n, j]
        if red == T1:
            for j in range(L):
                u = S[num, j] / S[den, j]
                yl[j] = u
                yr[j] = u
        elif ext is not None:  # wtsum, as numpy's where(den != 0, num, nan)
            for j in range(L):
                nj, dj = S[num, j], S[den, j]
                u = nj if dj != 0.0 else math.nan
                yl[j] = u
                yr[j] = u
    elif red == EXHAUSTIVE:  # (one call site, the side a run-time value: one compile)
        for side in range(2):
            left = side == 0
            _exhaustive(P, L, S, flb, fub, tb, ylo if left else yhs, -1 if left else ohi,
                        left, yl if left else yr)
    elif red == NIE_TAN:
        num, den = tb, tb + 1
        ym = int(P[O_YM])
        y = P[ym]
        for j in range(L):
            w = S[flb, j] + S[fub, j]
            S[num, j] = w * y
            S[den, j] = w
        for n in range(1, n_rules):
            y = P[ym + n]
            for j in range(L):
                w = S[flb + n, j] + S[fub + n, j]
                S[num, j] += w * y
                S[den, j] += w
        for j in range(L):
            yl[j] = S[num, j] / S[den, j]
            yr[j] = yl[j]
    elif red == WU_MENDEL:
        _wu_mendel(P, L, S, flb, fub, tb, yl, yr)
    elif red == EIASC:  # status: the left side's failure first, as s1 if s1 != OK else s2
        for side in range(2):
            left = side == 0
            _eiasc_lanes(P, L, S, flb, fub, tb, ylo if left else yhs, -1 if left else ohi,
                         left, yl if left else yr, st)
    else:  # KM, EKM: left then right through one call site with the side a run-time value
        # (a literal side compiles _switch_lanes, the costliest reducer to compile, twice)
        k0l = -1 if red == KM else int(P[K0_L])
        k0r = -1 if red == KM else int(P[K0_R])
        for side in range(2):
            left = side == 0
            _switch_lanes(P, L, S, flb, fub, tb, ylo if left else yhs, -1 if left else ohi,
                          left, k0l if left else k0r, P[TOL_L] if left else P[TOL_R],
                          yl if left else yr, st)
    # Zero firing (as IT2Sugeno/T1Sugeno._interval_blocks): the reference raises where the
    # status is not OK. Lanes to look at are counted first by a branch-free pass (a loop with
    # a rare branch costs ~10 ns per lane even when the branch is never taken).
    odd = 0
    for j in range(L):
        odd += 0 if (st[j] == OK and yl[j] == yl[j] and yr[j] == yr[j]) else 1
    if odd == 0:
        return
    for j in range(L):
        if st[j] != OK or (yl[j] == yl[j] and yr[j] == yr[j]):
            continue
        if red != T1 and red != T1_SUM:
            for n in range(n_rules):
                if S[fub + n, j] > 0.0:
                    st[j] = WM_ZERO_LOWER
        if st[j] == OK:
            if P[HAS_ZERO] == 0.0:
                st[j] = ZERO_FIRING
            else:
                yl[j] = P[ZERO]
                yr[j] = P[ZERO]


@_compiled(inline=True)
def clip_input(P, i, v):
    """Input ``i`` clipped to its universe, as ``np.minimum(np.maximum(v, lo), hi)``."""
    return fmin(fmax(v, P[int(P[O_LO]) + i]), P[int(P[O_HI]) + i])


@_compiled()
def scalar2(P, a, b, ext=None):
    """Crisp output of a two-input system at ``(a, b)``; NaN where the reference raises
    (a non-finite input, zero firing without a value, ...): the caller then asks it. ``ext``
    as in :func:`eval_block`."""
    if not (math.isfinite(a) and math.isfinite(b)):
        return math.nan
    rows = int(P[N_ROWS]) + 1 + 2 * int(P[N_RULES]) + WORK_ROWS
    buf = np.empty(rows + 4)  # one allocation: scratch, the point, yl and yr
    S = buf[:rows].reshape((rows, 1))
    X = buf[rows : rows + 2].reshape((2, 1))
    X[0, 0] = clip_input(P, 0, a)
    X[1, 0] = clip_input(P, 1, b)
    st = np.empty(1, dtype=np.int8)
    yl, yr = buf[rows + 2 : rows + 3], buf[rows + 3 : rows + 4]
    # X.shape[1], not the literal 1: the same specialisation of eval_block as batch and loop
    if ext is None:  # (one basic specialisation of eval_block: ext left out, as everywhere)
        eval_block(P, X, X.shape[1], S, yl, yr, st)
    else:
        eval_block(P, X, X.shape[1], S, yl, yr, st, ext)
    if st[0] != OK:
        return math.nan
    return (buf[rows + 2] + buf[rows + 3]) * 0.5


BLOCK = 256  # points per block (the block's scratch stays in the L1/L2 cache)


@_compiled()
def batch(P, X, out_a, out_b, status, crisp, first, last, ext=None):
    """Evaluate the clipped points ``X[:, first:last]`` (X: n_inputs x N): ``crisp`` writes
    ``(yl + yr) / 2`` to ``out_a``, otherwise ``yl`` and ``yr`` to ``out_a``/``out_b``;
    ``status`` per point; ``ext`` as in :func:`eval_block`. Releases the GIL: threads may run
    disjoint ranges at once."""
    n_in = X.shape[0]
    rows = int(P[N_ROWS]) + 1 + 2 * int(P[N_RULES]) + WORK_ROWS
    S = np.empty((rows, BLOCK))
    xb = np.empty((n_in, BLOCK))
    yl = np.empty(BLOCK)
    yr = np.empty(BLOCK)
    st = np.empty(BLOCK, dtype=np.int8)
    for a in range(first, last, BLOCK):
        L = min(last, a + BLOCK) - a
        for i in range(n_in):
            for j in range(L):
                xb[i, j] = X[i, a + j]
        if ext is None:  # (ext left out: the one basic specialisation, see scalar2)
            eval_block(P, xb, L, S, yl, yr, st)
        else:
            eval_block(P, xb, L, S, yl, yr, st, ext)
        for j in range(L):
            status[a + j] = st[j]
            if crisp:
                out_a[a + j] = (yl[j] + yr[j]) * 0.5
            else:
                out_a[a + j] = yl[j]
                out_b[a + j] = yr[j]

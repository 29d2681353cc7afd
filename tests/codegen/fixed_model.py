"""An independent model of the q15 build's integer arithmetic, in numpy and Python integers.

It follows the specification in :mod:`it2track.codegen.fixedpoint` -- integer thresholds, the
slope formula, the rounded Q24 product, the exact minimum / maximum of the centroid over the
box of integer firings, the floor division with 4 extra bits -- without the C's algorithms: the
type reduction here compares every switch point's centroid with every other by exact rational
arithmetic (no theorem about where the minimum lies), so the C's exhaustive scan, KM, EKM and
EIASC are each checked against it. The tests check the compiled C equals it bit for bit, and
then use its intermediate values (memberships, firings, the exact quotient) to test each term
of the error bound.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

ONE = 1 << 24


def memberships(plan, q):
    """Rows (n_rows, N) as int64 in Q24 for integer inputs q (N, n_in) (clipped here)."""
    fmt = plan.fmt
    x = np.clip(np.asarray(q, dtype=np.int64), np.array(fmt.in_lo), np.array(fmt.in_hi))
    out = np.zeros((len(plan.rows), x.shape[0]), dtype=np.int64)
    for row in plan.rows:
        v = x[:, row.inp]
        val = np.zeros(v.shape, dtype=np.int64)
        left = (v > row.qa) & (v < row.qb)
        flat = (v >= row.qb) & (v <= row.qc)
        right = (v > row.qc) & (v < row.qd)
        for mask, sl, du in ((left, row.left, v - row.left.origin),
                             (right, row.right, row.right.origin - v)):
            if mask.any():
                assert np.all(du[mask] >= 0) and np.all(du[mask] <= 0xFFFF)
                half = 1 << (sl.sh - 1)
                val[mask] = np.minimum(
                    sl.cint + ((du[mask] * sl.k + sl.cfrac + half) >> sl.sh), row.height)
        val[flat] = row.height
        out[row.row] = val
    return out


def mul(a, b):
    """round(a b / 2^24), with a factor of exactly 1 passed through."""
    prod = (a * b + (1 << 23)) >> 24
    return np.where(a == ONE, b, np.where(b == ONE, a, prod))


def firings(system, m):
    """(fl, fu) int64 (R, N), rules in the tables' sorted order."""
    t = system.tables
    from it2track.fuzzy import TNorm
    out = []
    for rows in (t.lower_rows_s, t.upper_rows_s):
        f = np.full((t.n_rules, m.shape[1]), ONE, dtype=np.int64)
        for r in range(t.n_rules):
            used = [int(k) for k in rows[r] if k != t.n_rows]
            if not used:
                continue
            acc = m[used[0]]
            for k in used[1:]:
                acc = mul(acc, m[k]) if system.tnorm is TNorm.PRODUCT else np.minimum(acc, m[k])
            f[r] = acc
        out.append(f)
    return out[0], out[1]


def _extreme(w_lo, w_hi, y, left):
    """Exact (num, den) of the min (left) or max of sum(w y) / sum(w) over w in the box
    [w_lo, w_hi] (Python ints), by comparing every switch point's centroid with the best."""
    order = sorted(range(len(y)), key=lambda i: y[i])
    best = None
    for k in range(len(order) + 1):
        num = den = 0
        for pos, i in enumerate(order):
            upper = (pos < k) == left
            w = w_hi[i] if upper else w_lo[i]
            num += w * y[i]
            den += w
        if den == 0:
            continue
        c = Fraction(num, den)
        if best is None or (c < best[0] if left else c > best[0]):
            best = (c, num, den)
    assert best is not None
    return best


def evaluate(system, plan, q):
    """Model outputs for integer inputs q: (u, yl, yr, status, exact_l, exact_r), the last two
    the exact centroids of the integer firings in output units (Fractions; None where no rule
    fires)."""
    fmt = plan.fmt
    x = np.asarray(q)
    m = memberships(plan, x)
    fl, fu = firings(system, m)
    name = plan.reducer
    ylo = [v - plan.y_min for v in plan.y_lo_q]
    yhi = [v - plan.y_min for v in plan.y_hi_q]
    xb = fmt.extra_bits
    n = x.shape[0]
    u = np.zeros(n, dtype=np.int64)
    yl = np.zeros(n, dtype=np.int64)
    yr = np.zeros(n, dtype=np.int64)
    status = np.zeros(n, dtype=np.int64)
    exact_l: list[Fraction | None] = [None] * n
    exact_r: list[Fraction | None] = [None] * n
    for j in range(n):
        fire = [r for r in range(system.n_rules) if fu[r, j] > 0]
        if not fire:
            if plan.zero_q is None:
                status[j] = 2
            else:
                u[j] = yl[j] = yr[j] = plan.zero_q
            continue
        hi = [int(fu[r, j]) for r in fire]
        lo = [min(int(fl[r, j]), b) for r, b in zip(fire, hi, strict=True)]
        yl_f = [ylo[r] for r in fire]
        yr_f = [yhi[r] for r in fire]
        if name == "nie-tan":
            w = [a + b for a, b in zip(lo, hi, strict=True)]
            num = sum(wi * (a + b) for wi, a, b in zip(w, yl_f, yr_f, strict=True))
            den = 2 * sum(w)
            pairs = [(num, den), (num, den)]
        elif name == "type-1" or bool(system.tables.type1):
            w = [int(fu[r, j]) for r in fire]
            pairs = [(sum(a * b for a, b in zip(w, yl_f, strict=True)), sum(w)),
                     (sum(a * b for a, b in zip(w, yr_f, strict=True)), sum(w))]
        else:
            _, nl, dl = _extreme(lo, hi, yl_f, True)
            _, nr, dr = _extreme(lo, hi, yr_f, False)
            pairs = [(nl, dl), (nr, dr)]
        (nl, dl), (nr, dr) = pairs
        ql = (nl << xb) // dl
        qr = (nr << xb) // dr
        exact_l[j] = Fraction(nl, dl) + plan.y_min
        exact_r[j] = Fraction(nr, dr) + plan.y_min
        yl[j] = plan.y_min + ((ql + (1 << (xb - 1))) >> xb)
        yr[j] = plan.y_min + ((qr + (1 << (xb - 1))) >> xb)
        one_div = name == "nie-tan" or (bool(system.tables.type1) and bool(system.tables.crisp))
        u[j] = yl[j] if one_div else plan.y_min + ((ql + qr + (1 << xb)) >> (xb + 1))
    return u, yl, yr, status, exact_l, exact_r

"""The float error bound's terms, shared by the Sugeno bound (:mod:`.errorbound`, whose
docstring derives them) and the Mamdani one (:mod:`.errorbound_mamdani`)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..fuzzy import MFKind, TNorm

#: Unit roundoff of IEEE binary32.
EPS32 = 2.0**-24

FloatArray = NDArray[np.float64]


def _gamma(k: int) -> float:
    return k * EPS32 / (1.0 - k * EPS32)


def row_errors(system: Any, tables: Any = None) -> FloatArray:
    """Bound ``e`` on the float error of every membership row, shape ``(M + 1,)``.

    The last entry (the constant 1 of unmentioned inputs) is 0. See the module docstring.
    ``tables`` are the system's rule tables (a Mamdani system's antecedents; by default
    ``system.tables``).
    """
    return _row_errors(system.tables if tables is None else tables)


def _row_errors(t: Any) -> FloatArray:
    """:func:`row_errors` of the rule tables ``t``."""
    out = np.zeros(t.n_rows + 1)
    for k in range(t.n_rows):
        i = int(t.mf_input[k])
        big_u = max(abs(float(t.lo[i])), abs(float(t.hi[i])))
        p = [float(v) for v in t.mf_params[k]]
        kind = MFKind(int(t.mf_kind[k]))
        if kind is MFKind.TRAPEZOID:
            a, wl, d, wr, h = p
            widths = [w for w, end in ((wl, a), (wr, d)) if math.isfinite(end)]
            points = [abs(v) for v in (a, a + wl, d - wr, d) if math.isfinite(v)]
            if not widths:
                out[k] = 2.0 * EPS32 * h
                continue
            out[k] = EPS32 * (2.0 * h * (big_u + max(points)) / min(widths) + 8.0)
        elif kind is MFKind.GAUSSIAN:
            mean, sigma, h = p[:3]
            out[k] = EPS32 * h * (2.0 * (big_u + abs(mean)) / sigma + 8.0)
        elif kind in (MFKind.UM_GAUSSIAN_UPPER, MFKind.UM_GAUSSIAN_LOWER):
            m1, m2, sigma, h = p[:4]
            out[k] = EPS32 * h * (2.0 * (big_u + max(abs(m1), abs(m2))) / sigma + 8.0)
        else:
            raise ValueError(f"row {k} of kind {kind.name} has no float error bound")
    return out


def _firing_error(m: FloatArray, e: FloatArray, rows: NDArray[np.intp], tnorm: TNorm
                  ) -> FloatArray:
    """Per-rule firing error bound, shape (R, N), from memberships m (M+1, N)."""
    mu = m[rows]  # (R, n_in, N)
    err = e[rows][:, :, None] * np.ones_like(mu)
    if tnorm is TNorm.MINIMUM:
        out: FloatArray = err.max(axis=1)
        return out
    n_in = rows.shape[1]
    padded = mu + err
    total = np.zeros(mu[:, 0].shape)
    for i in range(n_in):
        others = np.ones_like(total)
        for j in range(n_in):
            if j != i:
                others = others * padded[:, j]
        total += err[:, i] * others
    total += (n_in - 1) * EPS32 * np.prod(padded, axis=1)
    return total


def _centroid_bound(lower_sum: FloatArray, sum_e: FloatArray, spread_y: float,
                    arith: float) -> FloatArray:
    """``spread_y sum E / (lower_sum - sum E) + A``, inf where the denominator is not positive
    (called under :func:`_wu_mendel_side`'s ``errstate``)."""
    s = lower_sum - sum_e
    b: FloatArray = np.where(s > 0, spread_y * sum_e / s + arith, np.inf)
    return b


def _weighted_bound(lower_sum: FloatArray, big_e: FloatArray, y: FloatArray,
                    c: FloatArray, arith: Any) -> FloatArray:
    """``sum_r E_r |y_r - c| / (sum fl - 3 sum E) + A`` (see the module docstring, step 3);
    ``y`` is ``(R,)`` or, for consequents that depend on the input, ``(R, N)``."""
    sum_e = big_e.sum(axis=0)
    s = lower_sum - 3.0 * sum_e
    y2 = y if y.ndim == 2 else y[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        num = np.einsum("rn,rn->n", big_e, np.abs(y2 - c[None, :]))
        b = np.where((s > 0) & np.isfinite(c), num / s + arith, np.inf)
    return b


def _linear_error(t: Any, xc: FloatArray) -> FloatArray:
    """Bound on the float error of every first-order consequent at the clipped inputs ``xc``
    (n_in, N), the largest over the rules, shape (N,).

    The C computes ``c0 + sum_i min(clo_i x_i, chi_i x_i)`` (or the max) with every constant
    rounded once (``eps |c|``), the input clipped to the float-rounded universe (``eps U_i``
    from the double's clipped input), one rounding per product (``eps |c_i x_i|``) and ``n``
    additions (``gamma_n`` of the sum of the magnitudes)::

        delta_r = gamma_{n + 2} (|c0| + sum_i |c_i| |x_i|) + eps sum_i |c_i| U_i.
    """
    n_in = t.n_inputs
    c0 = np.maximum(np.abs(t.y_lo_s), np.abs(t.y_hi_s))[:, None]
    ci = np.maximum(np.abs(t.coef_lo_s), np.abs(t.coef_hi_s))  # (R, n_in)
    big_u = np.maximum(np.abs(t.lo), np.abs(t.hi))
    mag = c0 + ci @ np.abs(xc)
    delta = _gamma(n_in + 2) * mag + EPS32 * (ci @ big_u)[:, None]
    out: FloatArray = delta.max(axis=0)
    return out


def firing_and_errors(system: Any, t: Any, xc: FloatArray
                      ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Exact firing intervals ``(fl, fu)`` (R, N) at the clipped inputs and the bounds on the
    float error of each (``eu``, ``el``; steps 1 and 2 of the module docstring)."""
    m = t.memberships(xc).copy()
    e = _row_errors(t)
    general = bool(t.features & {"not", "or", "weights"})
    if general:
        # NOT, OR, weights: rows [m, 1, 0, 1 - m] with errors [e, 0, 0, e + eps]; every t-norm
        # and s-norm here is 1-Lipschitz in each argument on [0, 1] (the probabilistic OR too:
        # d(a + b - ab)/da = 1 - b), so a rule's error is at most the sum of its antecedents'
        # plus one rounding per operation, times its weight.
        fl_b, fu_b = t.firing_block(xc, system.tnorm)
        fl, fu = fl_b.copy(), fu_b.copy()
        n_rows = t.n_rows
        e_ext = np.concatenate([e[:n_rows], [0.0, 0.0], e[:n_rows] + EPS32])
        w = t.weight_s[:, None]
        n_in = t.n_inputs
        eu = (e_ext[t.up_ext_s].sum(axis=1)[:, None] + 3.0 * n_in * EPS32) * w + EPS32 * fu
        el = (e_ext[t.lo_ext_s].sum(axis=1)[:, None] + 3.0 * n_in * EPS32) * w + EPS32 * fl
    else:
        fu = np.prod(m[t.upper_rows_s], axis=1) if system.tnorm is TNorm.PRODUCT else \
            np.min(m[t.upper_rows_s], axis=1)
        fl = np.prod(m[t.lower_rows_s], axis=1) if system.tnorm is TNorm.PRODUCT else \
            np.min(m[t.lower_rows_s], axis=1)
        eu = _firing_error(m, e, t.upper_rows_s, system.tnorm)
        el = _firing_error(m, e, t.lower_rows_s, system.tnorm)
    return fl, fu, eu, el


def _wu_mendel_side(fl: FloatArray, fu: FloatArray, y: FloatArray, sl: FloatArray,
                    su: FloatArray, sum_e: FloatArray, spread_y: Any, arith: Any, r: int,
                    *, left: bool) -> FloatArray:
    with np.errstate(divide="ignore", invalid="ignore"):
        d0 = _centroid_bound(sl, sum_e, spread_y, arith)
        dm = _centroid_bound(su, sum_e, spread_y, arith)
        outer = np.maximum(d0, dm)
        spread = np.where(sl > 0, 1.0 / sl - 1.0 / su, np.inf)
        d_spread = np.where(sl > sum_e, sum_e / (sl * (sl - sum_e)), np.inf) + np.where(
            su > sum_e, sum_e / (su * (su - sum_e)), np.inf)
        y2 = y if y.ndim == 2 else y[:, None]
        lo_y, hi_y = y2.min(axis=0), y2.max(axis=0)
        if left:
            p = (fl * (y2 - lo_y)).sum(axis=0)
            q = (fu * (hi_y - y2)).sum(axis=0)
        else:
            p = (fu * (y2 - lo_y)).sum(axis=0)
            q = (fl * (hi_y - y2)).sum(axis=0)
        tt = np.where(p + q > 0, p * q / (p + q), 0.0)
        d_t = 2.0 * sum_e * spread_y
        d_prod = d_spread * (tt + d_t) + spread * d_t
        arith_prod = (_gamma(r) * (su + sl) / (su * sl) + 6.0 * EPS32 * spread) * tt \
            + 4.0 * EPS32 * np.abs(y2).max(axis=0)
        out: FloatArray = outer + 0.5 * (d_prod + arith_prod)
    return np.where(np.isfinite(out), out, np.inf)

r"""How far a float (binary32) build of the generated C may be from the Python (binary64) system.

:func:`float_error_bound` returns, for each input point, a bound on ``|C_float - Python|`` for
``yl``, ``yr`` and ``u``, evaluated from the double-precision evaluation at that point. The
inputs are taken as float-representable (the C function receives floats, so the comparison is
made at the point it actually sees). The bound is first order in the float unit roundoff
``eps = 2**-24`` (terms in ``eps**2`` are dropped; they are below ``1e-13`` of the bound for
any system here).

Derivation
----------
**1. Membership rows.** Every table constant ``c`` is rounded once to float, ``|c~ - c| <=
eps |c|``; the input clipped to the float-rounded universe moves by at most ``eps U``,
``U = max(|lo|, |hi|)``. On a slope of width ``w`` a trapezoid row is
``h (x - a) / w`` computed as ``h~ * fl(fl(x - a~) * fl(1 / w))``: the difference ``x - a``
carries an absolute error ``<= eps (2 U + 2 P)`` (clipping, the rounded ``a``, the subtraction;
``P`` the largest finite breakpoint magnitude), which the slope multiplies by ``h / w``; the
remaining roundings (reciprocal, product, height) are relative, ``<= 4 eps`` of a value ``<= 1``.
A branch decided on the wrong side of a rounded breakpoint costs no more, because the row is
continuous with slope ``<= h / w``. Hence, per row::

    e_trap = eps [ 2 h (U + P) / w_min + 8 ].

A Gaussian row ``h exp(-z^2 / 2)``, ``z = (x - m) / sigma``: ``z`` carries an absolute error
``<= eps (2 U + 2 |m|) / sigma + 2 eps |z|``; ``d/dz exp(-z^2/2) = -z exp(-z^2/2)`` is at most
``e^(-1/2)`` in magnitude and ``z^2 exp(-z^2/2) <= 2/e``; the argument's two roundings and
``expf``'s error (taken as ``<= 2`` ulp) add ``<= 4 eps``. With the same bound for the
uncertain-mean rows (``|m| = max(|m1|, |m2|)``; their pieces join continuously)::

    e_gauss = eps h [ 2 (U + |m|) / sigma + 8 ].

**2. Firing.** (With NOT, OR rules or weights every operation is 1-Lipschitz in each argument
on ``[0, 1]``, so a rule's error is at most the sum of its antecedents' errors plus one rounding
per operation, times its weight; a negated row ``1 - mu`` adds one rounding.) For the product
t-norm ``theta = prod_i mu_i``,
``|theta~ - theta| <= sum_i e_i prod_{j != i} (mu_j + e_j) + (n - 1) eps prod_j (mu_j + e_j)``;
the minimum is 1-Lipschitz in the max norm: ``|theta~ - theta| <= max_i e_i``. The type
reducers form ``d = fl(fu - fl)``, a relative error ``eps`` of ``fu - fl <= fu``, which we book
as a firing perturbation of ``eps fu``. ``E_r`` is the larger of the rule's upper and lower
firing errors (so the float firing box lies within ``E_r`` of the exact one).

**3. The centroid.** For weights ``a, b > 0`` of the same rules, the identity::

    c(a) - c(b) = sum_r (a_r - b_r) (y_r - c(a)) / sum_r b_r

holds, where ``c(t) = sum t y / sum t``. ``yl`` is the minimum of ``c`` over the firing box
``[fl, fu]``, so (i) taking the exact minimiser ``t*`` and its nearest point in the float box
bounds ``yl~ - yl`` by ``sum_r E_r |y_r - c(a)| / sum t*``, and (ii) taking the float
minimiser ``t~*`` and its nearest point ``a`` in the exact box bounds ``yl - yl~`` by
``sum_r E_r |y_r - c(a)| / sum t~*``. Both denominators are at least ``sum fl - sum E``, and
``|y_r - c(a)| <= |y_r - yl| + 2 B`` for the bound ``B`` sought (``c(a)`` lies between ``yl``
and ``yl~ + B``). Solving for ``B``::

    |yl~ - yl| <= sum_r E_r |y_r - yl| / (sum fl - 3 sum E) + A,   (likewise yr with y_hi)

where ``A`` is the arithmetic of the reduction itself: running sums of at most ``2R + 2``
non-negative terms (``gamma_k = k eps / (1 - k eps)``), the cross-multiplied comparison and
the final division: ``A = (2 gamma_{2R+2} + 4 eps) max|y|``. The iterative reducers stop at a
switch point whose optimality was tested on rounded centroids; a wrong call moves the result
to a neighbouring switch point by at most the same arithmetic error, so ``A`` doubles for KM,
EKM and EIASC. ``yl`` in the bound is the exact value (evaluated in double); a type-1 system
is the degenerate box ``fl = fu``.

Nie-Tan is one centroid with weights ``fl + fu`` (perturbed by ``2 E_r``) and the midpoints of
the consequents. The Wu-Mendel bounds combine the centroids ``yl0 = c(fl)``, ``ylm = c(fu)``
(each bounded as above with denominators ``sum fl``, ``sum fu``) with
``spread = 1 / sum fl - 1 / sum fu`` and ``T = p q / (p + q)`` (``p``, ``q`` linear in the
firing, ``|dT/dp|, |dT/dq| <= 1``):
``|Delta(spread T)| <= |Delta spread| (T + |Delta T|) + spread |Delta T|``, plus the
arithmetic of the difference ``sum fu - sum fl`` (``gamma_R (sum fu + sum fl) / (sum fu
sum fl)`` relative to ``T``).

Where ``sum fl <= 3 sum E`` (the total lower firing is within rounding of zero) no bound
follows from this argument: the function returns ``inf`` there, and the tests check only that
the float result lies in the consequents' hull.

``u = (yl + yr) / 2`` adds one rounding: ``|u~ - u| <= (b_yl + b_yr) / 2 + eps max|y|``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..fuzzy import EXHAUSTIVE, MFKind, TNorm

__all__ = ["EPS32", "FIXED_TERMS", "FixedBound", "fixed_error_bound", "float_error_bound",
           "row_errors"]

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
    t = system.tables if tables is None else tables
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
    s = lower_sum - sum_e
    with np.errstate(divide="ignore", invalid="ignore"):
        b = np.where(s > 0, spread_y * sum_e / s + arith, np.inf)
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


def float_error_bound(system: Any, x: ArrayLike
                      ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Bound on ``|C_float - Python|`` at each point (see the module docstring; a Mamdani
    system's is :func:`~it2track.codegen.errorbound_mamdani.mamdani_float_error_bound`).

    Parameters
    ----------
    system : IT2Sugeno, T1Sugeno, IT2Mamdani or T1Mamdani
        The system the C was generated from (with its reducer).
    x : array_like, shape (N, n_inputs)
        Input points (float-representable values; they are clipped as the system does).

    Returns
    -------
    b_yl, b_yr, b_u : ndarray, shape (N,)
        Bounds for ``yl``, ``yr`` and ``u``; ``inf`` where the total lower firing is within
        rounding of zero (no bound follows there).
    """
    from .lowering import antecedent_tables
    from .mamdani_c import is_centroid_mamdani

    if is_centroid_mamdani(system):
        from .errorbound_mamdani import mamdani_float_error_bound

        return mamdani_float_error_bound(system, x)
    t = antecedent_tables(system)
    arr = np.asarray(x, dtype=np.float64)
    xc = np.clip(arr, t.lo, t.hi).T.copy()  # (n_in, N)
    fl, fu, eu, el = firing_and_errors(system, t, xc)
    big_e = np.maximum(eu, el) + EPS32 * fu  # + the rounding of d = fu - fl in the reducers
    r = t.n_rules
    linear = "linear" in frozenset(getattr(t, "features", frozenset()))
    if linear:
        # first-order consequents at the clipped inputs, and each one's float error (below)
        y_lo, y_hi = (np.array(v) for v in t.consequents_block(xc))
        cons = _linear_error(t, xc)
    else:
        y_lo, y_hi = t.y_lo_s, t.y_hi_s
        cons = np.zeros(arr.shape[0])
    ymax = np.maximum(np.abs(y_lo).max(axis=0), np.abs(y_hi).max(axis=0))
    range_l = y_lo.max(axis=0) - y_lo.min(axis=0)
    range_r = y_hi.max(axis=0) - y_hi.min(axis=0)
    sum_e = big_e.sum(axis=0)
    arith = (2.0 * _gamma(2 * r + 2) + 4.0 * EPS32) * ymax
    reducer = getattr(system, "reducer", None)
    name = "type-1" if reducer is None else reducer.name
    if name in ("km", "ekm", "eiasc"):
        arith *= 2.0
    sl = fl.sum(axis=0)
    su = fu.sum(axis=0)
    if name == "nie-tan":
        ym = 0.5 * (y_lo + y_hi)
        w = fl + fu
        ym2 = ym if ym.ndim == 2 else ym[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            ref = (w * ym2).sum(axis=0) / w.sum(axis=0)
        # weights fl + fu are perturbed by 2 E and sum to at least sum(fl + fu)
        b = _weighted_bound(sl + su, 2.0 * big_e, ym, ref, arith)
        b_yl = b_yr = b
    elif name == "wu-mendel":
        b_yl = _wu_mendel_side(fl, fu, y_lo, sl, su, sum_e, range_l, arith, r, left=True)
        b_yr = _wu_mendel_side(fl, fu, y_hi, sl, su, sum_e, range_r, arith, r, left=False)
    else:
        if linear:
            ref_l, ref_r = EXHAUSTIVE.reduce_per_sample(fl, fu, y_lo, y_hi)
        else:
            ref_l, ref_r = EXHAUSTIVE.reduce_rules_first(fl, fu, y_lo, y_hi, t.order_ident,
                                                         t.order_hi_s)
        b_yl = _weighted_bound(sl, big_e, y_lo, ref_l, arith)
        b_yr = _weighted_bound(sl, big_e, y_hi, ref_r, arith)
    # perturbing every consequent by at most cons moves each weighted average, and so the
    # extremes over the firing box, by at most cons
    b_yl = b_yl + cons
    b_yr = b_yr + cons
    b_u = 0.5 * (b_yl + b_yr) + EPS32 * ymax
    return b_yl, b_yr, b_u


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
    e = row_errors(system, t)
    general = bool(frozenset(getattr(t, "features", frozenset())) & {"not", "or", "weights"})
    if general:
        # NOT, OR, weights: rows [m, 1, 0, 1 - m] with errors [e, 0, 0, e + eps]; every t-norm
        # and s-norm here is 1-Lipschitz in each argument on [0, 1] (the probabilistic OR too:
        # d(a + b - ab)/da = 1 - b), so a rule's error is at most the sum of its antecedents'
        # plus one rounding per operation, times its weight.
        fl_b, fu_b = t.firing_block(xc, system.tnorm)
        fl, fu = fl_b.copy(), fu_b.copy()
        n_rows = t.n_rows
        e_ext = np.concatenate([e[:n_rows], [0.0, 0.0], e[:n_rows] + EPS32])
        w = np.asarray(getattr(t, "weight_s", np.ones(t.n_rules)))[:, None]
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


# The fixed-point bound lives beside its own derivation (re-exported here).
from .errorbound_fixed import FIXED_TERMS, FixedBound, fixed_error_bound  # noqa: E402

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
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..fuzzy import EXHAUSTIVE, IT2Sugeno, MFKind, T1Sugeno, TNorm

__all__ = ["EPS32", "FIXED_TERMS", "FixedBound", "fixed_error_bound", "float_error_bound",
           "row_errors"]

#: Unit roundoff of IEEE binary32.
EPS32 = 2.0**-24

FloatArray = NDArray[np.float64]


def _gamma(k: int) -> float:
    return k * EPS32 / (1.0 - k * EPS32)


def row_errors(system: IT2Sugeno | T1Sugeno) -> FloatArray:
    """Bound ``e`` on the float error of every membership row, shape ``(M + 1,)``.

    The last entry (the constant 1 of unmentioned inputs) is 0. See the module docstring.
    """
    t = system.tables
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
                    c: FloatArray, arith: float) -> FloatArray:
    """``sum_r E_r |y_r - c| / (sum fl - 3 sum E) + A`` (see the module docstring, step 3)."""
    sum_e = big_e.sum(axis=0)
    s = lower_sum - 3.0 * sum_e
    with np.errstate(divide="ignore", invalid="ignore"):
        num = np.einsum("rn,rn->n", big_e, np.abs(y[:, None] - c[None, :]))
        b = np.where((s > 0) & np.isfinite(c), num / s + arith, np.inf)
    return b


def float_error_bound(system: IT2Sugeno | T1Sugeno, x: ArrayLike
                      ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Bound on ``|C_float - Python|`` at each point (see the module docstring).

    Parameters
    ----------
    system : IT2Sugeno or T1Sugeno
        The system the C was generated from (with its reducer).
    x : array_like, shape (N, n_inputs)
        Input points (float-representable values; they are clipped as the system does).

    Returns
    -------
    b_yl, b_yr, b_u : ndarray, shape (N,)
        Bounds for ``yl``, ``yr`` and ``u``; ``inf`` where the total lower firing is within
        rounding of zero (no bound follows there).
    """
    t = system.tables
    arr = np.asarray(x, dtype=np.float64)
    xc = np.clip(arr, t.lo, t.hi).T.copy()  # (n_in, N)
    m = t.memberships(xc).copy()
    e = row_errors(system)
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
    big_e = np.maximum(eu, el) + EPS32 * fu
    sum_e = big_e.sum(axis=0)
    r = t.n_rules
    y_lo, y_hi = t.y_lo_s, t.y_hi_s
    ymax = float(max(np.abs(y_lo).max(), np.abs(y_hi).max()))
    range_l = float(y_lo.max() - y_lo.min())
    range_r = float(y_hi.max() - y_hi.min())
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
        with np.errstate(divide="ignore", invalid="ignore"):
            ref = np.einsum("rn,r->n", w, ym) / w.sum(axis=0)
        # weights fl + fu are perturbed by 2 E and sum to at least sum(fl + fu)
        b = _weighted_bound(sl + su, 2.0 * big_e, ym, ref, arith)
        b_yl = b_yr = b
    elif name == "wu-mendel":
        b_yl = _wu_mendel_side(fl, fu, y_lo, sl, su, sum_e, range_l, arith, r, left=True)
        b_yr = _wu_mendel_side(fl, fu, y_hi, sl, su, sum_e, range_r, arith, r, left=False)
    else:
        ref_l, ref_r = EXHAUSTIVE.reduce_rules_first(fl, fu, y_lo, y_hi, t.order_ident,
                                                     t.order_hi_s)
        b_yl = _weighted_bound(sl, big_e, y_lo, ref_l, arith)
        b_yr = _weighted_bound(sl, big_e, y_hi, ref_r, arith)
    b_u = 0.5 * (b_yl + b_yr) + EPS32 * ymax
    return b_yl, b_yr, b_u


def _wu_mendel_side(fl: FloatArray, fu: FloatArray, y: FloatArray, sl: FloatArray,
                    su: FloatArray, sum_e: FloatArray, spread_y: float, arith: float, r: int,
                    *, left: bool) -> FloatArray:
    with np.errstate(divide="ignore", invalid="ignore"):
        d0 = _centroid_bound(sl, sum_e, spread_y, arith)
        dm = _centroid_bound(su, sum_e, spread_y, arith)
        outer = np.maximum(d0, dm)
        spread = np.where(sl > 0, 1.0 / sl - 1.0 / su, np.inf)
        d_spread = np.where(sl > sum_e, sum_e / (sl * (sl - sum_e)), np.inf) + np.where(
            su > sum_e, sum_e / (su * (su - sum_e)), np.inf)
        if left:
            p = np.einsum("rn,r->n", fl, y - y.min())
            q = np.einsum("rn,r->n", fu, y.max() - y)
        else:
            p = np.einsum("rn,r->n", fu, y - y.min())
            q = np.einsum("rn,r->n", fl, y.max() - y)
        tt = np.where(p + q > 0, p * q / (p + q), 0.0)
        d_t = 2.0 * sum_e * spread_y
        d_prod = d_spread * (tt + d_t) + spread * d_t
        arith_prod = (_gamma(r) * (su + sl) / (su * sl) + 6.0 * EPS32 * spread) * tt \
            + 4.0 * EPS32 * float(np.abs(y).max())
        out: FloatArray = outer + 0.5 * (d_prod + arith_prod)
    return np.where(np.isfinite(out), out, np.inf)


# -- fixed point ---------------------------------------------------------------------------------

#: The terms of :class:`FixedBound`, in the order the error propagates.
FIXED_TERMS = ("input", "rows", "products", "consequents", "output")


@dataclass(frozen=True, kw_only=True)
class FixedBound:
    r"""Bound on ``|C_fixed - Python|`` at each point, and its terms (see
    :func:`fixed_error_bound`).

    Attributes
    ----------
    yl, yr, u : ndarray, shape (N,)
        The bounds (``inf`` where the total lower firing is within rounding of zero).
    terms : dict of str -> (ndarray, ndarray, ndarray)
        Each term's share of the ``yl``, ``yr`` and ``u`` bounds (they add up to them):
        ``input`` the inputs' rounding to their Q format and the universe's to its integer
        grid, ``rows`` the membership rows' arithmetic (rounded constants, the final rounding),
        ``products`` the rounding of each firing product, ``consequents`` the consequents'
        rounding to the output's Q format, ``output`` the final rounding of ``yl``, ``yr``,
        ``u``. The first three are membership or firing errors carried through the type
        reducer's sensitivity.
    """

    yl: FloatArray
    yr: FloatArray
    u: FloatArray
    terms: dict[str, tuple[FloatArray, FloatArray, FloatArray]]


def fixed_error_bound(system: IT2Sugeno | T1Sugeno, fmt: Any, x: ArrayLike, *,
                      plan: Any = None) -> FixedBound:
    r"""Bound on ``|C_fixed - Python|`` for a fixed-point build, at real inputs ``x``.

    The C receives ``fmt.to_int(x)`` and the bound compares its result with the double system
    at ``x`` (clipped to the universe), so it covers the inputs' rounding as well; at inputs
    on the integer grid that term is 0.

    Derivation (first order in the fixed-point steps; every step is exact integer arithmetic
    except the roundings named here):

    1. *Rows.* The C evaluates row ``k`` at the grid point ``x'`` nearest ``x`` (clipped to
       the integer universe, which lies within one step of the real one):
       ``|mu~_k(x') - mu_k(clip x)| <= e_k + L_k |x' - clip x|`` with ``L_k = h / w`` the
       row's steepest slope and ``e_k`` (:meth:`FixedRow.error
       <it2track.codegen.fixedpoint.FixedRow.error>`) the rounded slope and value constants
       over the slope's whole length plus 1/2 for the final rounding (or the height's
       rounding), in units of ``2**-24``. Branches are decided exactly (integer thresholds).
    2. *Firing.* Product t-norm: ``|f~ - f| <= sum_i e_i prod_{j != i} (mu_j + e_j) + p / 2``
       (units ``2**-24``) with ``p`` the number of products (mentioned inputs minus one), each
       rounded to nearest; minimum: ``max_i e_i``, no rounding. ``E_r`` is the larger of the
       rule's upper and lower bounds. A rule whose upper firing rounds to 0 is dropped, which
       stays within ``E_r``; so does a lower firing rounded above the upper one (the C clamps
       it to the upper).
    3. *Type reduction.* The exact reducers find, in exact integer arithmetic, the true minimum
       (maximum) of the centroid of the integer firings over their box, so
       :func:`float_error_bound`'s sensitivity step applies with no arithmetic term:
       ``sum_r E_r |y_r - yl| / (sum fl - 3 sum E)``; Nie-Tan has weights ``fl + fu``
       perturbed by ``2 E_r``. The consequents' rounding to the output's Q format moves the
       minimum by at most their largest rounding (a weighted average of them moves no more).
    4. *Output.* ``yl``, ``yr`` are the exact quotient rounded to the nearest output step
       (half a step); ``u`` is formed from the quotients with 4 more fraction bits, within
       ``1/2 + 2**-4`` step of ``(yl + yr) / 2`` of the exact quotients.

    Parameters
    ----------
    system : IT2Sugeno or T1Sugeno
        The system the C was generated from.
    fmt : FixedFormat
        The build's scaling (``CCode.fixed``).
    x : array_like, shape (N, n_inputs)
        Real inputs (the C sees ``fmt.to_int(x)``).
    plan : FixedPlan, optional
        The build's integer tables (recomputed from ``system`` when not given).

    Returns
    -------
    FixedBound
    """
    from .fixedpoint import fixed_plan
    from .lowering import reducer_of

    t = system.tables
    reducer = reducer_of(system)
    name = "type-1" if reducer is None else reducer.name
    if plan is None:
        plan = fixed_plan(system, name, fmt.width)
    step_m = 2.0 ** -fmt.m_frac
    arr = np.asarray(x, dtype=np.float64)
    xc = np.clip(arr, t.lo, t.hi)
    seen = fmt.inputs_seen(fmt.to_int(arr))
    delta = np.abs(seen - xc).T  # (n_in, N)
    m = t.memberships(seen.T.copy()).copy()  # the exact rows at the point the C sees
    n_rows = t.n_rows
    e_in = np.zeros((n_rows + 1, arr.shape[0]))
    e_ar = np.zeros((n_rows + 1, 1))
    for row in plan.rows:
        e_in[row.row] = row.lipschitz * delta[row.inp]
        e_ar[row.row] = row.error() * step_m
    e_ar = e_ar * np.ones_like(e_in)
    # the double rows at clip(x) differ from those at x' by at most e_in
    m_c = t.memberships(xc.T.copy()).copy()
    e_tot = e_in + e_ar
    fl_c = _fold_rows(m_c, t.lower_rows_s, system.tnorm)
    fu_c = _fold_rows(m_c, t.upper_rows_s, system.tnorm)
    del m
    shares = {}
    for key, part in (("input", e_in), ("rows", e_ar)):
        eu = _fixed_firing_share(m_c, e_tot, part, t.upper_rows_s, system.tnorm, n_rows)
        el = _fixed_firing_share(m_c, e_tot, part, t.lower_rows_s, system.tnorm, n_rows)
        shares[key] = np.maximum(eu, el)
    if system.tnorm is TNorm.PRODUCT:
        n_prod = np.maximum((t.upper_rows_s != n_rows).sum(axis=1) - 1, 0)
        n_prod = np.maximum(n_prod, np.maximum((t.lower_rows_s != n_rows).sum(axis=1) - 1, 0))
    else:
        n_prod = np.zeros(t.n_rules, dtype=int)
    shares["products"] = (0.5 * step_m * n_prod)[:, None] * np.ones_like(fl_c)
    big_e = shares["input"] + shares["rows"] + shares["products"]
    sum_e = big_e.sum(axis=0)
    scale = 2.0 ** -fmt.out_frac
    y_lo, y_hi = t.y_lo_s, t.y_hi_s
    dy_lo = np.abs(np.array(plan.y_lo_q) * scale - y_lo)
    dy_hi = np.abs(np.array(plan.y_hi_q) * scale - y_hi)
    sl = fl_c.sum(axis=0)
    su = fu_c.sum(axis=0)
    one_div = name == "nie-tan" or (bool(t.type1) and bool(t.crisp) and (
        reducer is None or reducer.exact))
    with np.errstate(divide="ignore", invalid="ignore"):
        if name == "nie-tan":
            # one centroid of the midpoints with weights fl + fu, each perturbed by 2 E
            ym = 0.5 * (y_lo + y_hi)
            w = fl_c + fu_c
            ref = np.einsum("rn,r->n", w, ym) / w.sum(axis=0)
            weights = (2.0 * np.abs(ym[:, None] - ref[None, :]),) * 2
            denom = sl + su - 6.0 * sum_e
            cons_l = cons_r = 0.5 * float(np.max(dy_lo + dy_hi))
        else:
            ref_l, ref_r = EXHAUSTIVE.reduce_rules_first(fl_c, fu_c, y_lo, y_hi, t.order_ident,
                                                         t.order_hi_s)
            weights = (np.abs(y_lo[:, None] - ref_l[None, :]),
                       np.abs(y_hi[:, None] - ref_r[None, :]))
            denom = sl - 3.0 * sum_e
            cons_l, cons_r = float(dy_lo.max()), float(dy_hi.max())
        terms: dict[str, tuple[FloatArray, FloatArray, FloatArray]] = {}
        for key in ("input", "rows", "products"):
            bl, br = (np.where(denom > 0, np.einsum("rn,rn->n", shares[key], wt) / denom, np.inf)
                      for wt in weights)
            terms[key] = (bl, br, 0.5 * (bl + br))
    ones = np.ones(arr.shape[0])
    terms["consequents"] = (cons_l * ones, cons_r * ones, 0.5 * (cons_l + cons_r) * ones)
    half = 0.5 * scale
    u_out = half if one_div else (0.5 + 2.0 ** -fmt.extra_bits) * scale
    terms["output"] = (half * ones, half * ones, u_out * ones)
    total = [np.sum([terms[k][j] for k in FIXED_TERMS], axis=0) for j in range(3)]
    return FixedBound(yl=total[0], yr=total[1], u=total[2], terms=terms)


def _fold_rows(m: FloatArray, rows: NDArray[np.intp], tnorm: TNorm) -> FloatArray:
    mu = m[rows]
    out: FloatArray = np.prod(mu, axis=1) if tnorm is TNorm.PRODUCT else np.min(mu, axis=1)
    return out


def _fixed_firing_share(m: FloatArray, e_tot: FloatArray, part: FloatArray,
                        rows: NDArray[np.intp], tnorm: TNorm, n_rows: int) -> FloatArray:
    """The share of the membership errors ``part`` in a rule's firing error bound, shape
    (R, N): ``sum_i part_i prod_{j != i} (mu_j + e_j)`` (product) or ``max_i part_i``
    (minimum), over the inputs the rule mentions."""
    mu = m[rows]  # (R, n_in, N)
    pad = mu + e_tot[rows]
    share = part[rows]
    mentioned = (rows != n_rows)[:, :, None]
    share = np.where(mentioned, share, 0.0)
    if tnorm is TNorm.MINIMUM:
        out: FloatArray = share.max(axis=1)
        return out
    n_in = rows.shape[1]
    total = np.zeros(mu[:, 0].shape)
    for i in range(n_in):
        others = np.ones_like(total)
        for j in range(n_in):
            if j != i:
                others = others * pad[:, j]
        total += share[:, i] * others
    return total

"""The q15 build's error bound against the double system (:func:`fixed_error_bound`): its
derivation is in the function's docstring, its integer plan in :mod:`.fixedpoint`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..fuzzy import EXHAUSTIVE, IT2Sugeno, T1Sugeno, TNorm

__all__ = ["FIXED_TERMS", "FixedBound", "fixed_error_bound"]

FloatArray = NDArray[np.float64]


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

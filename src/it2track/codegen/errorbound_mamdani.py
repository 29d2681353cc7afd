r"""How far a float build of a Mamdani system's C may be from the Python (double) system.

:func:`mamdani_float_error_bound` extends :func:`~it2track.codegen.errorbound.float_error_bound`
(whose steps 1 and 2 give the firing errors ``el_r``, ``eu_r`` of every rule) through the
output grid, first order in ``eps = 2**-24``:

3. *Implication* at grid point ``y_j`` of a rule of firing ``f`` (error ``e``) with its set's MF
   ``mu`` (a table constant rounded once: ``eps mu``): ``min(f, mu)`` is 1-Lipschitz, error
   ``max(e, eps mu)``; ``mu f`` has ``mu e + f eps mu + eps mu f``.
4. *Aggregation*: ``max`` is 1-Lipschitz in the max norm (the C takes the strongest firing of
   each set first, exactly as Python); the sum adds the terms' errors plus ``gamma_R`` of the
   sum; the probabilistic OR ``a + t - a t`` has partial derivatives ``1 - t`` and ``1 - a``
   in ``[0, 1]``, so the terms' errors add, plus three roundings per step (``3 eps``; every
   value is at most 1). This bounds ``El_j``, ``Eu_j`` at each grid point.
5. *Centroid.* The aggregated set is a centre-of-sets problem over the grid ("rules" ``y_j``,
   firing ``[agg_l, agg_u]``), so the sensitivity step of the Sugeno bound applies with
   ``E_j = max(El_j, Eu_j) + eps agg_u`` (the reducers' ``d = gu - gl``), the grid's own
   rounding (``eps max|y|``: a weighted average of values each moved by at most that) and the
   arithmetic of sums of ``2J + 2`` terms. A type-1 system is the degenerate box (its
   centroid is one weighted average).

``inf`` where the total lower aggregate is within rounding of zero (no bound follows there).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..fuzzy import EXHAUSTIVE, Aggregation, Implication, IT2Mamdani
from ._errorcore import EPS32, _gamma, _weighted_bound, _wu_mendel_side, firing_and_errors

__all__ = ["mamdani_float_error_bound"]

FloatArray = NDArray[np.float64]


def _aggregate_error(system: Any, f: FloatArray, e: FloatArray, mf: FloatArray,
                     sets: NDArray[np.intp]) -> tuple[FloatArray, FloatArray]:
    """The aggregated set (J, N) in double (as Python) and its float error bound (J, N)."""
    j_pts, n = mf.shape[1], f.shape[1]
    agg = np.zeros((j_pts, n))
    err = np.zeros((j_pts, n))
    clip = system.implication is Implication.MINIMUM
    terms = []
    for r in range(f.shape[0]):
        mu = mf[sets[r]][:, None]
        fr, er = f[r][None, :], e[r][None, :]
        if clip:
            term = np.minimum(fr, mu)
            t_err = np.maximum(er, EPS32 * mu)
        else:
            term = mu * fr
            t_err = mu * er + 2.0 * EPS32 * mu * fr
        terms.append((term, t_err))
    if system.aggregation is Aggregation.MAXIMUM:
        for term, t_err in terms:
            np.maximum(agg, term, out=agg)
            np.maximum(err, t_err, out=err)
        return agg, err
    for term, t_err in terms:
        if system.aggregation is Aggregation.SUM:
            agg = agg + term
            err = err + t_err
        else:
            agg = agg + term - agg * term
            err = err + t_err + 3.0 * EPS32
    if system.aggregation is Aggregation.SUM:
        err = err + _gamma(len(terms)) * agg
    return agg, err


def mamdani_float_error_bound(system: Any, x: ArrayLike
                              ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Bound on ``|C_float - Python|`` of a Mamdani system (one output, centroid on the grid)
    at each point (see the module docstring).

    Parameters
    ----------
    system : IT2Mamdani or T1Mamdani
        The system the C was generated from.
    x : array_like, shape (N, n_inputs)
        Input points (float-representable values; clipped as the system does).

    Returns
    -------
    b_yl, b_yr, b_u : ndarray, shape (N,)
        Bounds for ``yl``, ``yr`` and ``u``; ``inf`` where the total lower aggregate is within
        rounding of zero.
    """
    m = system.tables
    t = m.antecedents
    arr = np.asarray(x, dtype=np.float64)
    xc = np.clip(arr, t.lo, t.hi).T.copy()
    fl, fu, eu, el = firing_and_errors(system, t, xc)
    sets = m.rule_set_s[0]
    y = np.asarray(m.grids[0], dtype=np.float64)
    agg_u, err_u = _aggregate_error(system, fu, eu, m.upper_mf[0], sets)
    it2 = isinstance(system, IT2Mamdani)
    if it2:
        agg_l, err_l = _aggregate_error(system, fl, el, m.lower_mf[0], sets)
    else:
        agg_l, err_l = agg_u, err_u
    big_e = np.maximum(err_u, err_l) + (EPS32 * agg_u if it2 else 0.0)
    ymax = float(np.abs(y).max())
    j_pts = y.size
    arith = (2.0 * _gamma(2 * j_pts + 2) + 4.0 * EPS32) * ymax
    name = system.reducer.name if it2 else "type-1"
    if name in ("km", "ekm", "eiasc"):
        arith *= 2.0
    sl, su = agg_l.sum(axis=0), agg_u.sum(axis=0)
    if name == "nie-tan":
        w = agg_l + agg_u
        with np.errstate(divide="ignore", invalid="ignore"):
            ref = (w * y[:, None]).sum(axis=0) / w.sum(axis=0)
        b_yl = b_yr = _weighted_bound(sl + su, 2.0 * big_e, y, ref, arith)
    elif name == "wu-mendel":
        sum_e = big_e.sum(axis=0)
        spread = float(y.max() - y.min())
        b_yl = _wu_mendel_side(agg_l, agg_u, y, sl, su, sum_e, spread, arith, j_pts, left=True)
        b_yr = _wu_mendel_side(agg_l, agg_u, y, sl, su, sum_e, spread, arith, j_pts,
                               left=False)
    else:
        ident = np.arange(j_pts)
        ref_l, ref_r = EXHAUSTIVE.reduce_rules_first(agg_l, agg_u, y, y, ident, ident)
        b_yl = _weighted_bound(sl, big_e, y, ref_l, arith)
        b_yr = _weighted_bound(sl, big_e, y, ref_r, arith)
    grid = EPS32 * ymax  # the grid's own rounding to float
    b_yl, b_yr = b_yl + grid, b_yr + grid
    b_u = 0.5 * (b_yl + b_yr) + EPS32 * ymax
    return b_yl, b_yr, b_u

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

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..fuzzy import EXHAUSTIVE

__all__ = ["EPS32", "FIXED_TERMS", "FixedBound", "fixed_error_bound", "float_error_bound",
           "row_errors"]

from ._errorcore import (
    EPS32,
    FloatArray,
    _gamma,
    _linear_error,
    _weighted_bound,
    _wu_mendel_side,
    firing_and_errors,
    row_errors,
)


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
    linear = "linear" in t.features
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


# The fixed-point bound lives beside its own derivation (re-exported here).
from .errorbound_fixed import FIXED_TERMS, FixedBound, fixed_error_bound  # noqa: E402

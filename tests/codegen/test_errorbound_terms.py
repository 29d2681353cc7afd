"""The float error bound's remaining terms pinned by hand (``codegen/errorbound.py`` and
``_errorcore.py``): the Wu-Mendel bound (``yl0``/``ylm`` centroids, ``spread``, ``T = p q /
(p + q)`` and their perturbations and arithmetic), first-order consequents (evaluated at the
clipped inputs, the consequent error ``gamma_{n+2} (|c0| + sum |c_i| |x_i|) + eps sum |c_i|
U_i``, the exact centroid by enumerating the firing box's corners), Nie-Tan with per-point
midpoints, batches (every sum is per point), and the edges where no bound follows (``inf``,
never NaN, and no floating-point warning).

Every expected value is computed here from the closed forms of the module docstring, in plain
Python floats, from memberships evaluated by hand; ``REL`` is tight enough that dropping or
changing any single term (the smallest is a few ``eps`` of a bound of tens of ``eps``) fails.
"""

from __future__ import annotations

import itertools
import math
from fractions import Fraction

import numpy as np
import pytest

from it2track.codegen._errorcore import firing_and_errors, row_errors
from it2track.codegen.errorbound import float_error_bound
from it2track.codegen.errorbound_mamdani import mamdani_float_error_bound
from it2track.codegen.lowering import antecedent_tables
from it2track.fuzzy import (
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    Bell,
    Input,
    IT2Mamdani,
    IT2Set,
    IT2Sugeno,
    Linear,
    Output,
    Rule,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
)

EPS = 2.0**-24
REL = 1e-12


def gamma(k: int) -> float:
    return k * EPS / (1.0 - k * EPS)


def arith(n_rules: int, ymax: float) -> float:
    """``A = (2 gamma_{2R+2} + 4 eps) max|y|``."""
    return (2.0 * gamma(2 * n_rules + 2) + 4.0 * EPS) * ymax


def e_trap(h: float, big_u: float, big_p: float, w_min: float) -> float:
    """``e_trap = eps [2 h (U + P) / w_min + 8]``."""
    return EPS * (2.0 * h * (big_u + big_p) / w_min + 8.0)


def tri(x: float, a: float, b: float, c: float, h: float = 1.0) -> float:
    if x <= a or x >= c:
        return 0.0
    return h * ((x - a) / (b - a) if x <= b else (c - x) / (c - b))


def weighted(f, big_e, y, c):
    """``sum_r E_r |y_r - c| / (sum f - 3 sum E)``."""
    return sum(e * abs(yi - c) for e, yi in zip(big_e, y, strict=True)) / (
        sum(f) - 3.0 * sum(big_e))


def corners(fl, fu, y, pick):
    """The exact ``yl`` (pick=min) or ``yr`` (max): the centroid's extreme over the firing box
    is at one of its corners -- enumerated, no switch point assumed."""
    vals = []
    for t in itertools.product(*zip(fl, fu, strict=True)):
        if sum(t) > 0:
            vals.append(sum(ti * yi for ti, yi in zip(t, y, strict=True)) / sum(t))
    return pick(vals)


# --- an interval type-2 input: upper and lower triangles of different supports ----------------
# universe (0, 4), U = 4
A_UP, A_LO = (0.0, 1.0, 3.0, 1.0), (0.5, 1.0, 2.0, 0.5)
B_UP, B_LO = (1.0, 3.0, 4.0, 1.0), (2.0, 3.0, 3.5, 0.5)
E_A_UP = e_trap(1.0, 4.0, 3.0, 1.0)  # 22 eps
E_A_LO = e_trap(0.5, 4.0, 2.0, 0.5)  # 20 eps
E_B_UP = e_trap(1.0, 4.0, 4.0, 1.0)  # 24 eps
E_B_LO = e_trap(0.5, 4.0, 3.5, 0.5)  # 23 eps


def it2_input(name: str = "x") -> Input:
    return Input(name, (0, 4), [IT2Set(Triangle(*A_UP[:3]), Triangle(*A_LO[:3], h=A_LO[3]), "a"),
                                IT2Set(Triangle(*B_UP[:3]), Triangle(*B_LO[:3], h=B_LO[3]), "b")])


def one_input_firing(x: float):
    """(fl, fu, E) of rules a, b on the interval input at x (one input: each firing error is
    its row's error; E_r = max(eu, el) + eps fu)."""
    fu = [tri(x, *A_UP), tri(x, *B_UP)]
    fl = [tri(x, *A_LO), tri(x, *B_LO)]
    big_e = [max(E_A_UP, E_A_LO) + EPS * fu[0], max(E_B_UP, E_B_LO) + EPS * fu[1]]
    return fl, fu, big_e


def test_the_rows_of_the_interval_input_are_the_closed_forms():
    s = IT2Sugeno(inputs=[it2_input()], rules=[Rule(["a"], 1.0), Rule(["b"], 2.0)])
    e = row_errors(s)
    assert sorted(e[:-1].tolist()) == pytest.approx(
        sorted([E_A_UP, E_A_LO, E_B_UP, E_B_LO]), rel=1e-14)
    assert (E_A_UP, E_A_LO, E_B_UP, E_B_LO) == pytest.approx(
        (22 * EPS, 20 * EPS, 24 * EPS, 23 * EPS), rel=1e-14)


# --- Wu-Mendel ---------------------------------------------------------------------------------

def wu_mendel_side(fl, fu, y, big_e, n_rules, a, *, left):
    """The docstring's Wu-Mendel bound for one side, in scalars: the outer centroids
    ``yl0 = c(fl)``, ``ylm = c(fu)`` (denominators ``sum fl``, ``sum fu``), ``spread = 1 / sum fl -
    1 / sum fu`` and ``T = p q / (p + q)`` with their perturbations, and the arithmetic."""
    sl, su, se = sum(fl), sum(fu), sum(big_e)
    spread_y = max(y) - min(y)
    outer = max(spread_y * se / (sl - se) + a, spread_y * se / (su - se) + a)
    spread = 1.0 / sl - 1.0 / su
    d_spread = se / (sl * (sl - se)) + se / (su * (su - se))
    lo, hi = min(y), max(y)
    wp, wq = (fl, fu) if left else (fu, fl)
    p = sum(w * (yi - lo) for w, yi in zip(wp, y, strict=True))
    q = sum(w * (hi - yi) for w, yi in zip(wq, y, strict=True))
    t = p * q / (p + q) if p + q > 0 else 0.0
    d_t = 2.0 * se * spread_y
    d_prod = d_spread * (t + d_t) + spread * d_t
    arith_prod = (gamma(n_rules) * (su + sl) / (su * sl) + 6.0 * EPS * spread) * t \
        + 4.0 * EPS * max(abs(v) for v in y)
    return outer + 0.5 * (d_prod + arith_prod), t, p + q


Y_LO, Y_HI = [-1.0, -0.75], [0.5, 4.0]  # y_lo spans 1/4, y_hi spans 7/2; max|y| = 4


def test_wu_mendel_bound_by_hand_on_a_batch():
    s = IT2Sugeno(inputs=[it2_input()], reducer=WU_MENDEL,
                  rules=[Rule(["a"], (Y_LO[0], Y_HI[0])), Rule(["b"], (Y_LO[1], Y_HI[1]))])
    xs = [1.5, 2.5, 3.25]  # sum fu is 1 between the peaks, 3/4 at 3.25
    b_yl, b_yr, b_u = float_error_bound(s, [[x] for x in xs])
    assert b_yl.shape == b_yr.shape == b_u.shape == (3,)
    seen_t, seen_pq = set(), []
    for j, x in enumerate(xs):
        fl, fu, big_e = one_input_firing(x)
        a = arith(2, 4.0)  # not doubled: Wu-Mendel does not iterate
        want_l, t_l, pq_l = wu_mendel_side(fl, fu, Y_LO, big_e, 2, a, left=True)
        want_r, t_r, pq_r = wu_mendel_side(fl, fu, Y_HI, big_e, 2, a, left=False)
        seen_t |= {t_l > 0, t_r > 0}
        seen_pq += [pq_l, pq_r]
        assert (b_yl[j], b_yr[j]) == pytest.approx((want_l, want_r), rel=REL), x
        assert b_u[j] == pytest.approx(0.5 * (want_l + want_r) + EPS * 4.0, rel=REL), x
    # the case covers T = 0 and T > 0, p + q below 1 and above, sum fl below 1
    assert seen_t == {True, False}
    assert min(seen_pq) < 1.0 < max(seen_pq)
    assert all(sum(one_input_firing(x)[0]) < 1.0 for x in xs)


def test_wu_mendel_with_one_consequent_value_has_no_spread_terms():
    # y_lo all 1 and y_hi all 2: spread_y = 0, p = q = 0 (T = 0, not 0 / 0): the bound is the
    # reduction's arithmetic A plus half the final 4 eps max|y|
    s = IT2Sugeno(inputs=[it2_input()], reducer=WU_MENDEL,
                  rules=[Rule(["a"], (1.0, 2.0)), Rule(["b"], (1.0, 2.0))])
    b_yl, b_yr, b_u = float_error_bound(s, [[1.5], [2.5]])
    want_l = arith(2, 2.0) + 0.5 * 4.0 * EPS * 1.0
    want_r = arith(2, 2.0) + 0.5 * 4.0 * EPS * 2.0
    assert b_yl.tolist() == pytest.approx([want_l] * 2, rel=REL)
    assert b_yr.tolist() == pytest.approx([want_r] * 2, rel=REL)
    assert b_u.tolist() == pytest.approx([0.5 * (want_l + want_r) + 2.0 * EPS] * 2, rel=REL)


@pytest.mark.parametrize("spread", [0.0, 1.0])
def test_wu_mendel_gives_inf_where_the_lower_firing_is_within_rounding(spread):
    # x = 0.5 + 2**-22: the lower a fires 2**-22 (below sum E, ~46 eps); x = 0.25: the upper a
    # fires, no lower set does; x = 2: both lower sets are 0. With one consequent value the
    # unguarded terms would be inf * 0 = NaN: inf, never NaN, and no warning
    s = IT2Sugeno(inputs=[it2_input()], reducer=WU_MENDEL,
                  rules=[Rule(["a"], (1.0, 2.0)), Rule(["b"], (1.0 + spread, 2.0 + spread))])
    xs = [0.5 + 2.0**-22, 0.25, 2.0, 1.5]
    assert tri(xs[0], *A_LO) == pytest.approx(2.0**-22, rel=1e-12)
    assert 0 < tri(xs[0], *A_LO) < E_A_UP
    b_yl, b_yr, b_u = float_error_bound(s, [[x] for x in xs])
    for b in (b_yl, b_yr, b_u):
        assert b[:3].tolist() == [math.inf] * 3
        assert math.isfinite(b[3])


# --- first-order consequents ----------------------------------------------------------------

# x2 on (-2, 1) (U = 2) has one set, 1/2 over its whole universe: row error 2 eps h = eps
HALF = 0.5
E_ALL = 2.0 * EPS * HALF
CONS_A = ([2.0, -1.0], 0.5)        # y_a = 0.5 + 2 x1 - x2
CONS_B = ([-0.5, 3.0], -1.0)       # y_b = -1 - 0.5 x1 + 3 x2
X_BATCH = [(1.5, -1.5), (2.5, 0.5), (1.5, 3.0)]  # the last one's x2 is clipped to 1
X_CLIPPED = [(1.5, -1.5), (2.5, 0.5), (1.5, 1.0)]
U_IN = [4.0, 2.0]


def second_input() -> Input:
    return Input("x2", (-2, 1), [IT2Set.type1(Trapezoid(-2, -2, 1, 1, h=HALF), "all")])


def linear_error(rules, x):
    """``max_r gamma_{n+2} (|c0| + sum_i |c_i| |x_i|) + eps sum_i |c_i| U_i`` (n = 2)."""
    out = []
    for coefs, c0 in rules:
        ci = [max(abs(v) for v in (c if isinstance(c, tuple) else (c, c))) for c in coefs]
        c0m = max(abs(v) for v in (c0 if isinstance(c0, tuple) else (c0, c0)))
        mag = c0m + sum(c * abs(xi) for c, xi in zip(ci, x, strict=True))
        out.append(gamma(4) * mag + EPS * sum(c * u for c, u in zip(ci, U_IN, strict=True)))
    return max(out)


def interval_value(coefs, c0, x, pick):
    """``c0 + sum_i min/max(c_lo x_i, c_hi x_i)`` (Linear's interval arithmetic)."""
    lo0, hi0 = c0 if isinstance(c0, tuple) else (c0, c0)
    total = lo0 if pick is min else hi0
    for c, xi in zip(coefs, x, strict=True):
        lo, hi = c if isinstance(c, tuple) else (c, c)
        total += pick(lo * xi, hi * xi)
    return total


def fire2(mu1, e1, mu2, e2):
    """Product of two rows: ``e1 (mu2 + e2) + e2 (mu1 + e1) + eps (mu1 + e1)(mu2 + e2)``."""
    return e1 * (mu2 + e2) + e2 * (mu1 + e1) + EPS * (mu1 + e1) * (mu2 + e2)


def test_type1_first_order_consequents_by_hand():
    x1 = Input("x1", (0, 4), [("a", Triangle(*A_UP[:3])), ("b", Triangle(*B_UP[:3]))])
    s = T1Sugeno(inputs=[x1, second_input()],
                 rules=[Rule(["a", "all"], Linear(*CONS_A)), Rule(["b", None], Linear(*CONS_B))])
    b_yl, b_yr, b_u = float_error_bound(s, X_BATCH)
    assert b_yl.shape == (3,)
    for j, x in enumerate(X_CLIPPED):
        f = [tri(x[0], *A_UP) * HALF, tri(x[0], *B_UP)]
        # rule b's second row is the constant 1 of an unmentioned input: error 0
        fire = [fire2(tri(x[0], *A_UP), E_A_UP, HALF, E_ALL), fire2(tri(x[0], *B_UP), E_B_UP,
                                                                     1.0, 0.0)]
        big_e = [fe + EPS * fi for fe, fi in zip(fire, f, strict=True)]
        y = [CONS_A[1] + 2.0 * x[0] - x[1], CONS_B[1] - 0.5 * x[0] + 3.0 * x[1]]
        c = sum(fi * yi for fi, yi in zip(f, y, strict=True)) / sum(f)
        want = weighted(f, big_e, y, c) + arith(2, max(abs(v) for v in y)) \
            + linear_error([CONS_A, CONS_B], x)
        assert (b_yl[j], b_yr[j]) == pytest.approx((want, want), rel=REL), x
        assert b_u[j] == pytest.approx(want + EPS * max(abs(v) for v in y), rel=REL), x


INT_A = ([(1.0, 2.0), -1.0], (0.25, 0.5))
INT_B = ([-0.5, (2.0, 3.0)], (-1.0, -0.5))


def interval_tsk(reducer):
    return IT2Sugeno(inputs=[it2_input("x1"), second_input()], reducer=reducer,
                     rules=[Rule(["a", "all"], Linear(*INT_A)), Rule(["b", None], Linear(*INT_B))])


def interval_tsk_firing(x):
    """(fl, fu, E, y_lo, y_hi) at the clipped point x of :func:`interval_tsk`."""
    fu = [tri(x[0], *A_UP) * HALF, tri(x[0], *B_UP)]
    fl = [tri(x[0], *A_LO) * HALF, tri(x[0], *B_LO)]
    eu = [fire2(tri(x[0], *A_UP), E_A_UP, HALF, E_ALL), fire2(tri(x[0], *B_UP), E_B_UP, 1.0, 0.0)]
    el = [fire2(tri(x[0], *A_LO), E_A_LO, HALF, E_ALL), fire2(tri(x[0], *B_LO), E_B_LO, 1.0, 0.0)]
    big_e = [max(u, v) + EPS * f for u, v, f in zip(eu, el, fu, strict=True)]
    y_lo = [interval_value(*INT_A, x, min), interval_value(*INT_B, x, min)]
    y_hi = [interval_value(*INT_A, x, max), interval_value(*INT_B, x, max)]
    return fl, fu, big_e, y_lo, y_hi


@pytest.mark.parametrize(("reducer", "factor"), [(EXHAUSTIVE, 1.0), (KM, 2.0)])
def test_interval_first_order_consequents_by_hand(reducer, factor):
    xs, clipped = [*X_BATCH[:2], (2.5, 3.0)], [*X_CLIPPED[:2], (2.5, 1.0)]
    b_yl, b_yr, b_u = float_error_bound(interval_tsk(reducer), xs)
    for j, x in enumerate(clipped):
        fl, fu, big_e, y_lo, y_hi = interval_tsk_firing(x)
        assert y_lo != y_hi and fl != fu
        ymax = max(abs(v) for v in y_lo + y_hi)
        a = factor * arith(2, ymax)
        cons = linear_error([INT_A, INT_B], x)
        want_l = weighted(fl, big_e, y_lo, corners(fl, fu, y_lo, min)) + a + cons
        want_r = weighted(fl, big_e, y_hi, corners(fl, fu, y_hi, max)) + a + cons
        assert (b_yl[j], b_yr[j]) == pytest.approx((want_l, want_r), rel=REL), x
        assert b_u[j] == pytest.approx(0.5 * (want_l + want_r) + EPS * ymax, rel=REL), x


def test_nie_tan_with_first_order_consequents_by_hand():
    xs, clipped = [(1.5, -1.5), (2.5, 3.0)], [(1.5, -1.5), (2.5, 1.0)]
    b_yl, b_yr, b_u = float_error_bound(interval_tsk(NIE_TAN), xs)
    for j, x in enumerate(clipped):
        fl, fu, big_e, y_lo, y_hi = interval_tsk_firing(x)
        w = [a + b for a, b in zip(fl, fu, strict=True)]
        ym = [0.5 * (a + b) for a, b in zip(y_lo, y_hi, strict=True)]
        ref = sum(wi * yi for wi, yi in zip(w, ym, strict=True)) / sum(w)
        ymax = max(abs(v) for v in y_lo + y_hi)
        want = weighted(w, [2.0 * e for e in big_e], ym, ref) + arith(2, ymax) \
            + linear_error([INT_A, INT_B], x)
        assert (b_yl[j], b_yr[j]) == pytest.approx((want, want), rel=REL), x
        assert b_u[j] == pytest.approx(want + EPS * ymax, rel=REL), x


def test_wu_mendel_with_first_order_consequents_by_hand():
    # the consequents' spreads (max - min over the rules) are per point, as everything else
    xs, clipped = [(1.5, -1.5), (2.5, 3.0)], [(1.5, -1.5), (2.5, 1.0)]
    b_yl, b_yr, b_u = float_error_bound(interval_tsk(WU_MENDEL), xs)
    spreads = []
    for j, x in enumerate(clipped):
        fl, fu, big_e, y_lo, y_hi = interval_tsk_firing(x)
        ymax = max(abs(v) for v in y_lo + y_hi)
        a, cons = arith(2, ymax), linear_error([INT_A, INT_B], x)
        want_l = wu_mendel_side(fl, fu, y_lo, big_e, 2, a, left=True)[0] + cons
        want_r = wu_mendel_side(fl, fu, y_hi, big_e, 2, a, left=False)[0] + cons
        spreads.append((max(y_lo) - min(y_lo), max(y_hi) - min(y_hi)))
        assert (b_yl[j], b_yr[j]) == pytest.approx((want_l, want_r), rel=REL), x
        assert b_u[j] == pytest.approx(0.5 * (want_l + want_r) + EPS * ymax, rel=REL), x
    assert spreads[0] != spreads[1]


def test_nie_tan_batch_with_a_point_where_nothing_fires():
    # zero-order, per-point sums; at x = 0 nothing fires (ref = 0 / 0): inf, no warning
    s = IT2Sugeno(inputs=[it2_input()], reducer=NIE_TAN,
                  rules=[Rule(["a"], (Y_LO[0], Y_HI[0])), Rule(["b"], (Y_LO[1], Y_HI[1]))])
    b_yl, b_yr, b_u = float_error_bound(s, [[1.5], [0.0], [2.5]])
    assert [b_yl[1], b_yr[1], b_u[1]] == [math.inf] * 3
    ym = [0.5 * (a + b) for a, b in zip(Y_LO, Y_HI, strict=True)]
    for j, x in ((0, 1.5), (2, 2.5)):
        fl, fu, big_e = one_input_firing(x)
        w = [a + b for a, b in zip(fl, fu, strict=True)]
        ref = sum(wi * yi for wi, yi in zip(w, ym, strict=True)) / sum(w)
        want = weighted(w, [2.0 * e for e in big_e], ym, ref) + arith(2, 4.0)
        assert (b_yl[j], b_yr[j]) == pytest.approx((want, want), rel=REL), x
        assert b_u[j] == pytest.approx(want + EPS * 4.0, rel=REL), x


# --- batches, firing shapes and the no-bound edge --------------------------------------------

@pytest.mark.parametrize("tnorm", [TNorm.MINIMUM, TNorm.PRODUCT])
def test_two_inputs_three_points_each_point_alone(tnorm):
    # N = 3 points of n_in = 2 inputs (the shapes cannot be mixed up), interval sets: the
    # minimum's error is the larger of the rule's row errors, the product's fire2
    s = IT2Sugeno(inputs=[it2_input("x1"), it2_input("x2")], tnorm=tnorm, reducer=EXHAUSTIVE,
                  rules=[Rule(["a", "b"], (Y_LO[0], Y_HI[0])),
                         Rule(["b", "a"], (Y_LO[1], Y_HI[1]))])
    pts = [(1.5, 2.5), (2.5, 1.5), (1.25, 2.75)]
    b_yl, b_yr, _ = float_error_bound(s, pts)
    assert b_yl.shape == (3,)
    for j, (x1, x2) in enumerate(pts):
        mu = {("a", "u"): tri(x1, *A_UP), ("a", "l"): tri(x1, *A_LO),
              ("b", "u"): tri(x1, *B_UP), ("b", "l"): tri(x1, *B_LO)}
        mu2 = {("a", "u"): tri(x2, *A_UP), ("a", "l"): tri(x2, *A_LO),
               ("b", "u"): tri(x2, *B_UP), ("b", "l"): tri(x2, *B_LO)}
        err = {("a", "u"): E_A_UP, ("a", "l"): E_A_LO, ("b", "u"): E_B_UP, ("b", "l"): E_B_LO}
        fl, fu, big_e = [], [], []
        for s1, s2 in (("a", "b"), ("b", "a")):
            side = {}
            for k in ("u", "l"):
                m1, m2, e1, e2 = mu[s1, k], mu2[s2, k], err[s1, k], err[s2, k]
                if tnorm is TNorm.MINIMUM:
                    side[k] = (min(m1, m2), max(e1, e2))
                else:
                    side[k] = (m1 * m2, fire2(m1, e1, m2, e2))
            fu.append(side["u"][0])
            fl.append(side["l"][0])
            big_e.append(max(side["u"][1], side["l"][1]) + EPS * side["u"][0])
        a = arith(2, 4.0)
        want_l = weighted(fl, big_e, Y_LO, corners(fl, fu, Y_LO, min)) + a
        want_r = weighted(fl, big_e, Y_HI, corners(fl, fu, Y_HI, max)) + a
        assert (b_yl[j], b_yr[j]) == pytest.approx((want_l, want_r), rel=REL), (x1, x2)


@pytest.mark.parametrize("n_rules", [1, 2])
def test_the_bound_is_inf_exactly_at_sum_fl_equal_to_3_sum_e(n_rules):
    # x on the rising edge of a triangle (0, 1, 3) of the universe (0, 4): f = x, E = e + eps f;
    # a second rule (triangle 1, 3, 4) does not fire there but adds its row error e_b to sum E.
    # At the x where f == 3 sum E exactly the denominator is 0, and the numerator sum E |y - c|
    # is 0 (one rule: 0 / 0) or not (two: e_b |y_b - y_a| / 0): no bound, inf, no warning
    e, e_b = e_trap(1.0, 4.0, 3.0, 1.0), e_trap(1.0, 4.0, 4.0, 1.0) if n_rules == 2 else 0.0
    x = 3.0 * (e + e_b) / (1.0 - 3.0 * EPS)
    for _ in range(5):
        x = 3.0 * ((e + EPS * x) + e_b)
    assert x == 3.0 * ((e + EPS * x) + e_b)
    sets = [("a", Triangle(0, 1, 3)), ("b", Triangle(1, 3, 4))][:n_rules]
    s = T1Sugeno(inputs=[Input("x", (0, 4), sets)],
                 rules=[Rule(["a"], -1.0), Rule(["b"], 2.0)][:n_rules])
    t = antecedent_tables(s)
    fl, _, eu, _ = firing_and_errors(s, t, np.array([[x]]))
    assert fl[:, 0].tolist() == [x, 0.0][:n_rules]
    assert eu[:, 0].tolist() == [e, e_b][:n_rules]
    b_yl, b_yr, b_u = float_error_bound(s, [[x], [np.nextafter(x, 1.0) * 2.0]])
    assert [b_yl[0], b_yr[0], b_u[0]] == [math.inf] * 3
    assert math.isfinite(b_yl[1])


def test_a_point_of_tiny_lower_firing_has_no_bound_though_its_centroid_is_finite():
    # x = 2**-22 on the rising edge: f = 2**-22 < 3 E (E ~ 22 eps), c = y_r finite
    s = T1Sugeno(inputs=[Input("x", (0, 4), [("a", Triangle(0, 1, 3)), ("b", Triangle(1, 3, 4))])],
                 rules=[Rule(["a"], -1.0), Rule(["b"], 2.0)])
    b_yl, b_yr, b_u = float_error_bound(s, [[2.0**-22], [1.5]])
    assert [b_yl[0], b_yr[0], b_u[0]] == [math.inf] * 3
    assert np.isfinite([b_yl[1], b_yr[1], b_u[1]]).all()


# --- the general firing bound with interval rows and two inputs --------------------------------

def test_general_firing_upper_and_lower_errors_with_or_rules():
    # three inputs (3 n_in eps = 9 eps per side). Rule 1: x1 a OR x2 b WITH 0.5, x3 unmentioned;
    # rule 2: x1 b OR x3 a, x2 unmentioned. An input an OR rule does not mention is its
    # identity, the constant 0, of error 0. Each side: (sum of its rows' errors + 9 eps) w +
    # eps f; the upper side the larger in both rules
    s = IT2Sugeno(inputs=[it2_input("x1"), it2_input("x2"), it2_input("x3")], reducer=EXHAUSTIVE,
                  rules=[Rule(["a", "b", None], (Y_LO[0], Y_HI[0]), connective="or", weight=0.5),
                         Rule(["b", None, "a"], (Y_LO[1], Y_HI[1]), connective="or")])
    assert s.tables.is_or_s.tolist() == [True, True]
    x1, x2, x3 = 1.5, 2.5, 2.75
    fu = [0.5 * max(tri(x1, *A_UP), tri(x2, *B_UP)), max(tri(x1, *B_UP), tri(x3, *A_UP))]
    fl = [0.5 * max(tri(x1, *A_LO), tri(x2, *B_LO)), max(tri(x1, *B_LO), tri(x3, *A_LO))]
    eu = [(E_A_UP + E_B_UP + 9 * EPS) * 0.5 + EPS * fu[0], E_B_UP + E_A_UP + 9 * EPS + EPS * fu[1]]
    el = [(E_A_LO + E_B_LO + 9 * EPS) * 0.5 + EPS * fl[0], E_B_LO + E_A_LO + 9 * EPS + EPS * fl[1]]
    assert eu[0] > el[0] and eu[1] > el[1]
    big_e = [max(u, v) + EPS * f for u, v, f in zip(eu, el, fu, strict=True)]
    b_yl, b_yr, _ = float_error_bound(s, [[x1, x2, x3]])
    want_l = weighted(fl, big_e, Y_LO, corners(fl, fu, Y_LO, min)) + arith(2, 4.0)
    want_r = weighted(fl, big_e, Y_HI, corners(fl, fu, Y_HI, max)) + arith(2, 4.0)
    assert (b_yl[0], b_yr[0]) == pytest.approx((want_l, want_r), rel=REL)


def test_general_firing_lower_errors_the_larger_under_not():
    # NOT swaps the rows: a negated upper firing 1 - lower(a) carries the lower row's error
    # (+ eps for the 1 - mu); with two inputs 3 n_in eps = 6 eps per side
    s = IT2Sugeno(inputs=[it2_input("x1"), it2_input("x2")], reducer=EXHAUSTIVE,
                  rules=[Rule(["a", "b"], (Y_LO[0], Y_HI[0]), negated=[True, False]),
                         Rule(["b", "a"], (Y_LO[1], Y_HI[1]))])
    x1, x2 = 1.5, 2.5
    m1u, m1l, m2u, m2l = tri(x1, *A_UP), tri(x1, *A_LO), tri(x2, *B_UP), tri(x2, *B_LO)
    n1u, n1l, n2u, n2l = tri(x1, *B_UP), tri(x1, *B_LO), tri(x2, *A_UP), tri(x2, *A_LO)
    fu = [(1.0 - m1l) * m2u, n1u * n2u]
    fl = [(1.0 - m1u) * m2l, n1l * n2l]
    eu = [(E_A_LO + EPS) + E_B_UP + 6 * EPS + EPS * fu[0], E_B_UP + E_A_UP + 6 * EPS + EPS * fu[1]]
    el = [(E_A_UP + EPS) + E_B_LO + 6 * EPS + EPS * fl[0], E_B_LO + E_A_LO + 6 * EPS + EPS * fl[1]]
    assert el[0] > eu[0] and eu[1] > el[1]
    big_e = [max(u, v) + EPS * f for u, v, f in zip(eu, el, fu, strict=True)]
    b_yl, b_yr, _ = float_error_bound(s, [[x1, x2]])
    want_l = weighted(fl, big_e, Y_LO, corners(fl, fu, Y_LO, min)) + arith(2, 4.0)
    want_r = weighted(fl, big_e, Y_HI, corners(fl, fu, Y_HI, max)) + arith(2, 4.0)
    assert (b_yl[0], b_yr[0]) == pytest.approx((want_l, want_r), rel=REL)


# --- rows, Mamdani antecedents and the dispatch ----------------------------------------------

def test_a_flat_row_over_the_whole_universe_scales_with_its_height():
    s = T1Sugeno(inputs=[second_input()], rules=[Rule(["all"], 1.0)])
    assert row_errors(s).tolist() == [2.0 * EPS * HALF, 0.0]


def test_a_row_without_a_float_bound_is_named():
    s = T1Sugeno(inputs=[Input("x", (0, 4), [("t", Triangle(0, 1, 3)), ("g", Bell(2, 1, 2))])],
                 rules=[Rule(["t"], 1.0), Rule(["g"], 2.0)])
    with pytest.raises(ValueError) as info:
        row_errors(s)
    assert str(info.value) == "row 1 of kind BELL has no float error bound"


def mamdani_system():
    y = Output("y", (0, 4), [IT2Set(Triangle(0, 0, 4), Triangle(0, 0, 2), "small"),
                             IT2Set(Triangle(0, 4, 4), Triangle(2, 4, 4), "big")])
    return IT2Mamdani(inputs=[it2_input()], outputs=[y], resolution=9,
                      rules=[Rule(["a"], "small"), Rule(["b"], "big")])


def test_a_mamdani_systems_rows_and_firing_are_its_antecedents():
    m = mamdani_system()
    t = antecedent_tables(m)
    assert t is m.tables.antecedents
    assert sorted(row_errors(m, t)[:-1].tolist()) == pytest.approx(
        sorted([E_A_UP, E_A_LO, E_B_UP, E_B_LO]), rel=1e-14)
    fl, fu, eu, el = firing_and_errors(m, t, np.array([[1.5, 2.5]]))
    # minimum t-norm, one input: each firing's error is its row's
    assert fu.tolist() == [[0.75, 0.25], [0.25, 0.75]]
    assert fl.tolist() == [[0.25, 0.0], [0.0, 0.25]]
    assert eu.tolist() == [[E_A_UP] * 2, [E_B_UP] * 2]
    assert el.tolist() == [[E_A_LO] * 2, [E_B_LO] * 2]


def test_a_centroid_mamdani_system_takes_the_mamdani_bound():
    m = mamdani_system()
    x = [[1.5], [2.5]]
    got, want = float_error_bound(m, x), mamdani_float_error_bound(m, x)
    assert len(got) == 3
    for g, w in zip(got, want, strict=True):
        assert g.shape == (2,) and np.isfinite(g).all()
        assert g.tolist() == w.tolist()


def test_the_bound_is_double_whatever_the_points_type():
    # first-order consequents are evaluated at the points themselves: in double
    s = interval_tsk(EXHAUSTIVE)
    want = float_error_bound(s, [[1.5, -1.5]])
    for x in (np.array([[1.5, -1.5]], np.float32), np.array([[1.5, -1.5]], np.longdouble),
              [[1.5, -1.5]], [[Fraction(3, 2), Fraction(-3, 2)]]):
        got = float_error_bound(s, x)
        assert [b.dtype for b in got] == [np.float64] * 3
        assert [b.tolist() for b in got] == [b.tolist() for b in want]

"""The float error bound of the generated C, term by term, against its derivation's closed forms.

The other codegen tests check that the observed float error stays below the bound, which a
bound missing a term still passes. Here every term of ``codegen/errorbound.py``'s module
docstring is evaluated by hand for small systems and compared with the function: the rows'
``e_trap`` / ``e_gauss``, the product and minimum firing errors, the ``eps fu`` of the width,
the weighted centroid bound, the reduction arithmetic ``A`` (doubled for the iterative
reducers), the ``u`` rounding and the ``inf`` where no bound follows. No compiler needed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from it2track.codegen.errorbound import EPS32, float_error_bound, row_errors
from it2track.fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    Gaussian,
    Input,
    IT2Set,
    IT2Sugeno,
    Rule,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
)

EPS = 2.0**-24


def gamma(k: int) -> float:
    return k * EPS / (1.0 - k * EPS)


def arith(n_rules: int, ymax: float) -> float:
    """``A = (2 gamma_{2R+2} + 4 eps) max|y|``."""
    return (2.0 * gamma(2 * n_rules + 2) + 4.0 * EPS) * ymax


def test_eps32_is_binary32s_unit_roundoff():
    assert EPS32 == EPS == np.finfo(np.float32).eps / 2


def test_row_errors_are_the_derived_closed_forms():
    # universe (-2, 4): U = 4
    sets = [
        # left shoulder (a = -inf): widths [wr = 1], finite points {0, 1}: eps (2 (4 + 1) + 8)
        IT2Set.type1(Trapezoid(-2, -2, 0, 1), "L"),
        # triangle 0, 1, 3 of height 1/2: w_min 1, P 3: eps (2 0.5 (4 + 3) / 1 + 8)
        IT2Set.type1(Triangle(0, 1, 3, h=0.5), "T"),
        # right shoulder: widths [wl = 2], finite points {2, 4}: eps (2 (4 + 4) / 2 + 8)
        IT2Set.type1(Trapezoid(2, 4, 4, 4), "R"),
        # 1 over the whole universe (both ends infinite): 2 eps h
        IT2Set.type1(Trapezoid(-2, -2, 4, 4), "A"),
        # Gaussian mean 1, sigma 1/2, h 0.8: eps h (2 (4 + 1) / 0.5 + 8)
        IT2Set.type1(Gaussian(1, 0.5, 0.8), "G"),
        # uncertain mean in [-1, 0.5], sigma 2, h 0.9, both rows: eps h (2 (4 + 1) / 2 + 8)
        IT2Set.gaussian_uncertain_mean(-1, 0.5, 2, "U", h=0.9),
    ]
    system = IT2Sugeno(inputs=[Input("x", (-2, 4), sets)],
                       rules=[Rule([s.name], float(i)) for i, s in enumerate(sets)])
    want = [18.0, 15.0, 16.0, 2.0, 0.8 * 28.0, 0.9 * 13.0, 0.9 * 13.0]
    e = row_errors(system)
    assert e.shape == (len(want) + 1,) and e[-1] == 0.0
    assert sorted(e[:-1] / EPS) == pytest.approx(sorted(want), rel=1e-14)


def test_row_errors_use_the_larger_universe_end():
    # universe (-6, 1): U = 6 (|lo|), triangle -1, 0, 1: eps (2 (6 + 1) / 1 + 8) = 22 eps
    s = T1Sugeno(inputs=[Input("x", (-6, 1), [("t", Triangle(-1, 0, 1))])],
                 rules=[Rule(["t"], 1.0)])
    assert row_errors(s)[0] == pytest.approx(22.0 * EPS, rel=1e-14)


@pytest.mark.parametrize("y", [3.0, -5.0])
def test_one_rule_leaves_only_the_arithmetic(y):
    # one rule: c(a) = y_r, so sum E |y_r - c| = 0 and the bound is A (R = 1) alone
    s = T1Sugeno(inputs=[Input("x", (-2, 4), [("t", Triangle(0, 1, 3))])], rules=[Rule(["t"], y)])
    b_yl, b_yr, b_u = float_error_bound(s, [[1.0], [2.0]])
    a = arith(1, abs(y))
    assert b_yl.tolist() == b_yr.tolist() == pytest.approx([a, a], rel=1e-12)
    assert b_u.tolist() == pytest.approx([a + EPS * abs(y)] * 2, rel=1e-12)


@pytest.mark.parametrize(("reducer", "factor"), [(EXHAUSTIVE, 1.0), (KM, 2.0), (EKM, 2.0),
                                                (EIASC, 2.0)])
def test_the_arithmetic_doubles_for_the_iterative_reducers(reducer, factor):
    s = IT2Sugeno(inputs=[Input("x", (-2, 4), [IT2Set.type1(Triangle(0, 1, 3), "t")])],
                  rules=[Rule(["t"], (2.0, 5.0))], reducer=reducer)
    b_yl, b_yr, b_u = float_error_bound(s, [[1.5]])
    a = factor * arith(1, 5.0)
    assert (b_yl[0], b_yr[0]) == pytest.approx((a, a), rel=1e-12)
    assert b_u[0] == pytest.approx(a + EPS * 5.0, rel=1e-12)


A_SET, B_SET = Triangle(0, 1, 3), Triangle(1, 3, 4)
# on the universe (0, 4), U = 4: e_a = eps (2 (4 + 3) / 1 + 8), e_b = eps (2 (4 + 4) / 1 + 8)
E_A, E_B = 22.0 * EPS, 24.0 * EPS
Y_A, Y_B = -1.0, 2.0


def weighted(f, big_e, y):
    """``sum E |y - c| / (sum f - 3 sum E)`` with ``c`` the firing-weighted mean."""
    c = sum(fi * yi for fi, yi in zip(f, y, strict=True)) / sum(f)
    num = sum(e * abs(yi - c) for e, yi in zip(big_e, y, strict=True))
    return num / (sum(f) - 3.0 * sum(big_e))


def test_two_rules_one_input_by_hand():
    s = T1Sugeno(inputs=[Input("x", (0, 4), [("a", A_SET), ("b", B_SET)])],
                 rules=[Rule(["a"], Y_A), Rule(["b"], Y_B)])
    # x = 1.5: mu_a = 0.75, mu_b = 0.25; E_r = e_r + eps f_r (the width's rounding)
    f = [0.75, 0.25]
    big_e = [E_A + EPS * f[0], E_B + EPS * f[1]]
    b = weighted(f, big_e, [Y_A, Y_B]) + arith(2, 2.0)
    b_yl, b_yr, b_u = float_error_bound(s, [[1.5]])
    assert (b_yl[0], b_yr[0]) == pytest.approx((b, b), rel=1e-9)
    assert b_u[0] == pytest.approx(b + EPS * 2.0, rel=1e-9)


@pytest.mark.parametrize("tnorm", [TNorm.PRODUCT, TNorm.MINIMUM])
def test_two_inputs_firing_error_by_hand(tnorm):
    x1 = Input("x1", (0, 4), [("a", A_SET), ("b", B_SET)])
    x2 = Input("x2", (0, 4), [("a", A_SET), ("b", B_SET)])
    s = T1Sugeno(inputs=[x1, x2], rules=[Rule(["a", "a"], Y_A), Rule(["b", "b"], Y_B)],
                 tnorm=tnorm)
    m = [0.75, 0.25]  # both inputs at 1.5
    e = [E_A, E_B]
    if tnorm is TNorm.PRODUCT:
        f = [mi * mi for mi in m]
        # sum_i e_i prod_{j != i} (mu_j + e_j) + (n - 1) eps prod_j (mu_j + e_j), n = 2
        fire = [2.0 * ei * (mi + ei) + EPS * (mi + ei) ** 2 for mi, ei in zip(m, e, strict=True)]
    else:
        f = m
        fire = e  # max_i e_i: the same row twice
    big_e = [fe + EPS * fi for fe, fi in zip(fire, f, strict=True)]
    b = weighted(f, big_e, [Y_A, Y_B]) + arith(2, 2.0)
    b_yl, _, _ = float_error_bound(s, [[1.5, 1.5]])
    assert b_yl[0] == pytest.approx(b, rel=1e-9)


def test_three_inputs_count_n_minus_one_roundings():
    xs = [Input(f"x{i}", (0, 4), [("a", A_SET), ("b", B_SET)]) for i in range(3)]
    s = T1Sugeno(inputs=xs, rules=[Rule(["a"] * 3, Y_A), Rule(["b"] * 3, Y_B)])
    m, e = [0.75, 0.25], [E_A, E_B]
    f = [mi**3 for mi in m]
    fire = [3.0 * ei * (mi + ei) ** 2 + 2.0 * EPS * (mi + ei) ** 3
            for mi, ei in zip(m, e, strict=True)]
    big_e = [fe + EPS * fi for fe, fi in zip(fire, f, strict=True)]
    b = weighted(f, big_e, [Y_A, Y_B]) + arith(2, 2.0)
    assert float_error_bound(s, [[1.5] * 3])[0][0] == pytest.approx(b, rel=1e-9)


def test_weights_and_not_take_the_general_firing_bound():
    # rules: a WITH 0.5 -> -1, NOT a -> 2. One input (n_in = 1): E = (sum of the antecedents'
    # row errors + 3 n_in eps) w + eps f, the negated row's error e + eps; then + eps f again
    s = T1Sugeno(inputs=[Input("x", (0, 4), [("a", A_SET), ("b", B_SET)])],
                 rules=[Rule(["a"], Y_A, weight=0.5), Rule(["a"], Y_B, negated=[True])])
    f = [0.5 * 0.75, 1.0 - 0.75]
    fire = [(E_A + 3.0 * EPS) * 0.5 + EPS * f[0], (E_A + EPS + 3.0 * EPS) + EPS * f[1]]
    big_e = [fe + EPS * fi for fe, fi in zip(fire, f, strict=True)]
    b = weighted(f, big_e, [Y_A, Y_B]) + arith(2, 2.0)
    assert float_error_bound(s, [[1.5]])[0][0] == pytest.approx(b, rel=1e-9)


def test_nie_tan_bounds_one_centroid_of_the_summed_firing():
    x = Input("x", (0, 4), [IT2Set.type1(A_SET, "a"), IT2Set.type1(B_SET, "b")])
    # consequents of different widths, so that the midpoints are not the left ends shifted
    s = IT2Sugeno(inputs=[x], rules=[Rule(["a"], (Y_A, 0.0)), Rule(["b"], (Y_B, 4.0))],
                  reducer=NIE_TAN)
    f = [0.75, 0.25]
    big_e = [E_A + EPS * f[0], E_B + EPS * f[1]]
    # weights fl + fu = 2 f perturbed by 2 E, consequents' midpoints -0.5 and 3
    b = weighted([2 * fi for fi in f], [2 * be for be in big_e], [-0.5, 3.0]) + arith(2, 4.0)
    b_yl, b_yr, b_u = float_error_bound(s, [[1.5]])
    assert (b_yl[0], b_yr[0]) == pytest.approx((b, b), rel=1e-9)
    assert b_u[0] == pytest.approx(b + EPS * 4.0, rel=1e-9)


def test_no_bound_where_nothing_fires():
    s = T1Sugeno(inputs=[Input("x", (0, 4), [("a", A_SET), ("b", B_SET)])],
                 rules=[Rule(["a"], Y_A), Rule(["b"], Y_B)], on_zero_firing=0.0)
    # x = 0: mu_a = 0 (its left foot), mu_b = 0: the total lower firing is 0
    b_yl, b_yr, b_u = float_error_bound(s, [[0.0], [1.5]])
    assert math.isinf(b_yl[0]) and math.isinf(b_yr[0]) and math.isinf(b_u[0])
    assert np.isfinite([b_yl[1], b_yr[1], b_u[1]]).all()


def test_inputs_are_clipped_to_the_universe_first():
    s = T1Sugeno(inputs=[Input("x", (0, 2), [("a", A_SET), ("b", B_SET)])],
                 rules=[Rule(["a"], Y_A), Rule(["b"], Y_B)])
    # x = 9 is evaluated at the edge 2, where both rules fire 1/2 (unclipped nothing fires)
    edge = float_error_bound(s, [[2.0]])
    beyond = float_error_bound(s, [[9.0]])
    assert np.isfinite(edge[2][0])
    assert [b[0] for b in beyond] == [b[0] for b in edge]


def test_a_batch_bounds_each_point_alone():
    # per-point sums (over rules, not over the batch): two points, each by hand
    s = T1Sugeno(inputs=[Input("x", (0, 4), [("a", A_SET), ("b", B_SET)])],
                 rules=[Rule(["a"], Y_A), Rule(["b"], Y_B)])
    want = []
    for f in ([0.75, 0.25], [0.5, 0.5]):  # x = 1.5 and x = 2
        big_e = [E_A + EPS * f[0], E_B + EPS * f[1]]
        want.append(weighted(f, big_e, [Y_A, Y_B]) + arith(2, 2.0))
    b_yl, b_yr, _ = float_error_bound(s, [[1.5], [2.0]])
    assert b_yl.tolist() == pytest.approx(want, rel=1e-9)
    assert b_yr.tolist() == pytest.approx(want, rel=1e-9)


def test_inputs_below_the_universe_are_clipped_too():
    s = T1Sugeno(inputs=[Input("x", (1, 2), [("a", A_SET), ("b", B_SET)])],
                 rules=[Rule(["a"], Y_A), Rule(["b"], Y_B)])
    # x = -3 is evaluated at 1, where a fires 1 (unclipped nothing fires)
    assert [b[0] for b in float_error_bound(s, [[-3.0]])] == [
        b[0] for b in float_error_bound(s, [[1.0]])]
    assert np.isfinite(float_error_bound(s, [[-3.0]])[2][0])


def test_interval_firing_upper_and_lower_errors_by_hand():
    # IT2 set a: upper triangle 0, 1, 3 (e = 22 eps), lower the same at height 1/2 (15 eps).
    # Rule 1: a WITH 0.5 -> -1, its upper firing error the larger; rule 2: NOT a -> 2, whose
    # upper firing 1 - lower(a) carries the lower row's error and its lower firing the upper's.
    a = IT2Set(Triangle(0, 1, 3), Triangle(0, 1, 3, h=0.5), "a")
    s = IT2Sugeno(inputs=[Input("x", (0, 4), [a])], reducer=EXHAUSTIVE,
                  rules=[Rule(["a"], Y_A, weight=0.5), Rule(["a"], Y_B, negated=[True])])
    e_up, e_lo = 22.0 * EPS, 15.0 * EPS
    up, lo = 0.75, 0.375  # at x = 1.5
    fu = [0.5 * up, 1.0 - lo]
    fl = [0.5 * lo, 1.0 - up]
    eu = [(e_up + 3 * EPS) * 0.5 + EPS * fu[0], (e_lo + EPS + 3 * EPS) + EPS * fu[1]]
    el = [(e_lo + 3 * EPS) * 0.5 + EPS * fl[0], (e_up + EPS + 3 * EPS) + EPS * fl[1]]
    assert eu[0] > el[0] and el[1] > eu[1]  # each side is the larger once
    big_e = [max(u, v) + EPS * f for u, v, f in zip(eu, el, fu, strict=True)]
    # exact interval of rule outputs -1 and 2: yl weights -1 up and 2 down, yr the reverse
    yl = (fu[0] * Y_A + fl[1] * Y_B) / (fu[0] + fl[1])
    yr = (fl[0] * Y_A + fu[1] * Y_B) / (fl[0] + fu[1])
    sl = sum(fl)

    def bound(c):
        num = sum(e * abs(y - c) for e, y in zip(big_e, [Y_A, Y_B], strict=True))
        return num / (sl - 3.0 * sum(big_e)) + arith(2, 2.0)

    b_yl, b_yr, b_u = float_error_bound(s, [[1.5]])
    assert (b_yl[0], b_yr[0]) == pytest.approx((bound(yl), bound(yr)), rel=1e-9)
    assert b_u[0] == pytest.approx(0.5 * (bound(yl) + bound(yr)) + EPS * 2.0, rel=1e-9)


def test_or_rules_and_unmentioned_inputs_in_the_general_bound():
    # rule 1: x1 a OR x2 a -> -1 (max); rule 2: x1 b, x2 unmentioned -> 2 (the constant 1 row,
    # error 0). Each rule: (sum of its rows' errors + 3 n_in eps) + eps f, n_in = 2.
    x1 = Input("x1", (0, 4), [("a", A_SET), ("b", B_SET)])
    x2 = Input("x2", (0, 4), [("a", A_SET), ("b", B_SET)])
    s = T1Sugeno(inputs=[x1, x2], rules=[Rule(["a", "a"], Y_A, connective="or"),
                                         Rule(["b", None], Y_B)])
    f = [max(0.75, 0.5), 0.25]  # x1 = 1.5, x2 = 2
    fire = [(E_A + E_A + 6 * EPS) + EPS * f[0], (E_B + 6 * EPS) + EPS * f[1]]
    big_e = [fe + EPS * fi for fe, fi in zip(fire, f, strict=True)]
    b = weighted(f, big_e, [Y_A, Y_B]) + arith(2, 2.0)
    assert float_error_bound(s, [[1.5, 2.0]])[0][0] == pytest.approx(b, rel=1e-9)


@pytest.mark.parametrize("rule_kw", [{"weight": 0.5}, {"negated": [True]}])
def test_weights_alone_or_not_alone_take_the_general_bound(rule_kw):
    s = T1Sugeno(inputs=[Input("x", (0, 4), [("a", A_SET), ("b", B_SET)])],
                 rules=[Rule(["a"], Y_A, **rule_kw), Rule(["b"], Y_B)])
    if "weight" in rule_kw:
        f = [0.5 * 0.75, 0.25]
        fire = [(E_A + 3 * EPS) * 0.5 + EPS * f[0], (E_B + 3 * EPS) + EPS * f[1]]
    else:
        f = [1.0 - 0.75, 0.25]
        fire = [(E_A + EPS + 3 * EPS) + EPS * f[0], (E_B + 3 * EPS) + EPS * f[1]]
    big_e = [fe + EPS * fi for fe, fi in zip(fire, f, strict=True)]
    b = weighted(f, big_e, [Y_A, Y_B]) + arith(2, 2.0)
    assert float_error_bound(s, [[1.5]])[0][0] == pytest.approx(b, rel=1e-9)

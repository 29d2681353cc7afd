"""The rule language of Sugeno/TSK systems: NOT, OR (max / probabilistic OR), weights,
first-order consequents (crisp and interval), several outputs -- against hand computations,
an independent vertex enumeration, and the SystemTables contract."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest

from it2track.fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    Input,
    IT2Set,
    IT2Sugeno,
    Linear,
    Rule,
    SNorm,
    T1Sugeno,
    TNorm,
    Triangle,
    ZeroFiringError,
)

EXACT = [KM, EKM, EIASC, EXHAUSTIVE]


def _t1_two_inputs() -> tuple[Input, Input]:
    a = Input("a", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    b = Input("b", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    return a, b


# -- NOT, OR, weights: hand computations ---------------------------------------------------------


def test_not_or_weights_type1_by_hand() -> None:
    a, b = _t1_two_inputs()
    rules = [
        Rule(["lo", "hi"], 10.0, connective="or"),          # max(0.7, 0.6) = 0.7
        Rule(["hi", None], 0.0, negated=[True, False]),     # 1 - 0.3 = 0.7
        Rule(["lo", "lo"], 4.0, weight=0.5),                # 0.7 * 0.4 * 0.5 = 0.14
    ]
    fls = T1Sugeno(inputs=[a, b], rules=rules)
    lower, upper = fls.firing(0.3, 0.6)
    np.testing.assert_allclose(upper, [0.7, 0.7, 0.14], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(lower, upper)
    expected = (0.7 * 10 + 0.7 * 0 + 0.14 * 4) / (0.7 + 0.7 + 0.14)
    assert float(fls(0.3, 0.6)) == pytest.approx(expected, abs=1e-14)
    probor = T1Sugeno(inputs=[a, b], rules=rules, snorm=SNorm.PROBOR)
    f = probor.firing(0.3, 0.6)[1]
    assert f[0] == pytest.approx(0.7 + 0.6 - 0.42, abs=1e-15)
    # min t-norm in the weighted AND rule: min(0.7, 0.4) * 0.5
    assert T1Sugeno(inputs=[a, b], rules=rules, tnorm=TNorm.MINIMUM).firing(0.3, 0.6)[1][2] == \
        pytest.approx(0.2, abs=1e-15)


def test_negated_interval_set_swaps_bounds() -> None:
    s = IT2Set(Triangle(-1.5, 0, 1.5), Triangle(-1, 0, 1), "Z")
    x = Input("x", (-2, 2), [s])
    fls = IT2Sugeno(inputs=[x], rules=[Rule(["Z"], 1.0, negated=[True]), Rule(["Z"], 0.0)])
    lower, upper = fls.firing(0.5)
    up, lo = 1 - 0.5 / 1.5, 0.5  # upper(0.5), lower(0.5)
    assert lower[0] == pytest.approx(1 - up, abs=1e-15)
    assert upper[0] == pytest.approx(1 - lo, abs=1e-15)
    assert (lower[1], upper[1]) == pytest.approx((lo, up), abs=1e-15)


def test_or_rule_ignores_inputs_it_does_not_mention() -> None:
    """Unmentioned inputs are the s-norm's identity 0 (not the t-norm's 1)."""
    c = Input("c", (0, 1), [("lo", Triangle(0, 0, 1))])
    a, b = _t1_two_inputs()
    fls = T1Sugeno(inputs=[a, b, c], rules=[Rule(["lo", "hi", None], 1.0, connective="or"),
                                            Rule(["hi", None, None], 0.0)])
    assert fls.firing(0.9, 0.2, 0.5)[1][0] == pytest.approx(0.2, abs=1e-15)
    assert fls.tables.is_or.tolist() == [True, False]


def test_one_antecedent_or_rule_is_lowered_as_and() -> None:
    a, b = _t1_two_inputs()
    fls = T1Sugeno(inputs=[a, b], rules=[Rule(["lo", None], 1.0, connective="or"),
                                         Rule(["hi", None], 0.0)])
    assert fls.tables.features == frozenset()
    assert float(fls(0.25, 0.0)) == pytest.approx(0.75, abs=1e-15)


def test_features_name_what_is_used() -> None:
    a, b = _t1_two_inputs()
    base = [Rule(["lo", "lo"], 0.0), Rule(["hi", "hi"], 1.0)]

    def feats(rules: list[Rule]) -> frozenset[str]:
        return T1Sugeno(inputs=[a, b], rules=rules).tables.features

    assert feats(base) == frozenset()
    assert feats([*base, Rule(["lo", "hi"], 1.0, negated=[True, False])]) == {"not"}
    assert feats([*base, Rule(["lo", "hi"], 1.0, connective="or")]) == {"or"}
    assert feats([*base, Rule(["lo", "hi"], 1.0, weight=0.25)]) == {"weights"}
    assert feats([*base, Rule(["lo", "hi"], Linear([1.0, 2.0], 0.0))]) == {"linear"}
    multi = [Rule(["lo", "lo"], consequents=[0.0, 1.0]),
             Rule(["hi", "hi"], consequents=[1.0, None])]
    assert feats(multi) == {"outputs"}


def test_rule_rejects_bad_options() -> None:
    with pytest.raises(ValueError, match="weight"):
        Rule(["a"], 1.0, weight=1.5)
    with pytest.raises(ValueError, match="weight"):
        Rule(["a"], 1.0, weight=True)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="rule connective"):
        Rule(["a"], 1.0, connective="xor")
    with pytest.raises(ValueError, match="does not mention"):
        Rule(["a", None], 1.0, negated=[False, True])
    with pytest.raises(ValueError, match="one bool per antecedent"):
        Rule(["a", "b"], 1.0, negated=[True])
    with pytest.raises(ValueError, match="either consequent"):
        Rule(["a"], 1.0, consequents=[1.0])
    with pytest.raises(ValueError, match="at least one output"):
        Rule(["a"], consequents=[None, None])
    with pytest.raises(ValueError, match="coefficient c2"):
        Linear([1.0, (2.0, 1.0)], 0.0)


# -- first-order TSK -----------------------------------------------------------------------------


def test_first_order_type1_by_hand_in_fractions() -> None:
    a, b = _t1_two_inputs()
    rules = [Rule(["lo", None], Linear([2.0, -1.0], 0.5)),
             Rule(["hi", "hi"], Linear([0.0, 4.0], -1.0))]
    fls = T1Sugeno(inputs=[a, b], rules=rules)
    x1, x2 = Fraction(1, 4), Fraction(1, 2)
    f1, f2 = 1 - x1, x1 * x2
    y1, y2 = 2 * x1 - x2 + Fraction(1, 2), 4 * x2 - 1
    expected = (f1 * y1 + f2 * y2) / (f1 + f2)
    assert float(fls(0.25, 0.5)) == pytest.approx(float(expected), abs=1e-15)


def _vertex_interval(fl: np.ndarray, fu: np.ndarray, ylo: np.ndarray, yhi: np.ndarray
                     ) -> tuple[float, float]:
    """Centroid interval by enumerating every vertex of the firing box (2^R cases)."""
    best_l, best_r = np.inf, -np.inf
    for pick in itertools.product((0, 1), repeat=fl.size):
        f = np.where(np.array(pick, dtype=bool), fu, fl)
        if f.sum() <= 0:
            continue
        best_l = min(best_l, float(f @ ylo / f.sum()))
        best_r = max(best_r, float(f @ yhi / f.sum()))
    return best_l, best_r


def _random_tsk(rng: np.random.Generator) -> IT2Sugeno:
    sets = []
    for k, centre in enumerate(np.linspace(-1, 1, 3)):
        w = rng.uniform(0.0, 0.4)
        sets.append(IT2Set.from_fou(Triangle(centre - 1.2, centre, centre + 1.2), w, f"S{k}"))
    inputs = [Input("x1", (-1, 1), sets), Input("x2", (-1, 1), sets)]
    rules = []
    for i, j in itertools.product(range(3), repeat=2):
        coef = [tuple(sorted(rng.normal(size=2))) if rng.random() < 0.5 else float(rng.normal())
                for _ in range(2)]
        const = tuple(sorted(rng.normal(size=2)))
        rules.append(Rule([f"S{i}", f"S{j}"], Linear(coef, const),
                          negated=[bool(rng.random() < 0.2), False],
                          weight=float(rng.uniform(0.3, 1.0))))
    return IT2Sugeno(inputs=inputs, rules=rules)


@pytest.mark.parametrize("seed", range(6))
def test_first_order_interval_tsk_equals_vertex_enumeration(seed: int) -> None:
    rng = np.random.default_rng(seed)
    fls = _random_tsk(rng)
    x = rng.uniform(-1, 1, size=(40, 2))
    lower, upper = fls.firing(x[:, 0], x[:, 1])
    for reducer in EXACT:
        sys_r = IT2Sugeno(inputs=fls.inputs, rules=fls.rules, reducer=reducer)
        yl, yr = sys_r.interval(x[:, 0], x[:, 1])
        for n in range(x.shape[0]):
            ylo = np.array([r.consequent.interval(x[n])[0] for r in fls.rules])  # type: ignore[union-attr]
            yhi = np.array([r.consequent.interval(x[n])[1] for r in fls.rules])  # type: ignore[union-attr]
            ref = _vertex_interval(lower[n], upper[n], ylo, yhi)
            assert (yl[n], yr[n]) == pytest.approx(ref, abs=1e-12), (reducer.name, seed, n)


def test_first_order_approximations_use_the_per_sample_consequents() -> None:
    rng = np.random.default_rng(7)
    fls = _random_tsk(rng)
    x = rng.uniform(-1, 1, size=(25, 2))
    lower, upper = fls.firing(x[:, 0], x[:, 1])
    nt = IT2Sugeno(inputs=fls.inputs, rules=fls.rules, reducer=NIE_TAN)(x[:, 0], x[:, 1])
    for n in range(x.shape[0]):
        ys = np.array([r.consequent.interval(x[n]) for r in fls.rules])  # type: ignore[union-attr]
        w = lower[n] + upper[n]
        assert nt[n] == pytest.approx(float(w @ ys.mean(axis=1) / w.sum()), abs=1e-13)
    wm = IT2Sugeno(inputs=fls.inputs, rules=fls.rules, reducer=WU_MENDEL)
    exact = IT2Sugeno(inputs=fls.inputs, rules=fls.rules).interval(x[:, 0], x[:, 1])
    approx = wm.interval(x[:, 0], x[:, 1])
    # The Wu-Mendel bounds bracket nothing exactly but stay within the outer bounds.
    ylo = np.array([[r.consequent.interval(p)[0] for r in fls.rules] for p in x])  # type: ignore[union-attr]
    assert np.all(approx[0] >= ylo.min(axis=1) - 1e-12)
    assert np.all(np.abs(approx[0] - exact[0]) < 2.0)


def test_crisp_linear_equals_zero_order_when_coefficients_vanish() -> None:
    sets = [IT2Set.from_fou(Triangle(0, 0, 1), 0.2, "lo"),
            IT2Set.from_fou(Triangle(0, 1, 1), 0.2, "hi")]
    ins = [Input("a", (0, 1), sets), Input("b", (0, 1), sets)]
    zero = IT2Sugeno(inputs=ins, rules=[Rule(["lo", "hi"], (-1, 2)), Rule(["hi", "lo"], 3.0)])
    lin = IT2Sugeno(inputs=ins, rules=[Rule(["lo", "hi"], Linear([0, 0], (-1, 2))),
                                       Rule(["hi", "lo"], Linear([0, 0], 3.0))])
    x = np.random.default_rng(3).uniform(0, 1, size=(2, 500))
    np.testing.assert_allclose(lin(*x), zero(*x), rtol=0, atol=1e-13)


# -- several outputs -----------------------------------------------------------------------------


def test_several_outputs_equal_their_single_output_systems() -> None:
    a, b = _t1_two_inputs()
    rules = [Rule(["lo", "lo"], consequents=[1.0, Linear([1.0, 1.0], 0.0)]),
             Rule(["hi", None], consequents=[5.0, None]),
             Rule([None, "hi"], consequents=[None, -2.0], weight=0.5)]
    fls = T1Sugeno(inputs=[a, b], rules=rules, outputs=("u", "v"))
    x = np.random.default_rng(0).uniform(0, 1, size=(2, 100))
    out = fls(*x)
    assert out.shape == (100, 2)
    u = T1Sugeno(inputs=[a, b], rules=[Rule(["lo", "lo"], 1.0), Rule(["hi", None], 5.0)])
    v = T1Sugeno(inputs=[a, b], rules=[Rule(["lo", "lo"], Linear([1.0, 1.0], 0.0)),
                                       Rule([None, "hi"], -2.0, weight=0.5)])
    np.testing.assert_array_equal(out[:, 0], u(*x))
    np.testing.assert_array_equal(out[:, 1], v(*x))
    np.testing.assert_array_equal(fls.select_output("v")(*x), v(*x))
    np.testing.assert_array_equal(fls.select_output(0)(*x), u(*x))
    # by hand at (0.25, 0.5): u = (0.375*1 + 0.25*5)/(0.625); v = (0.375*0.75 + 0.25*-2)/0.625
    assert fls(0.25, 0.5).tolist() == pytest.approx([1.625 / 0.625, (0.28125 - 0.5) / 0.625])
    assert fls.tables.outputs[1].rule_index.tolist() == [0, 2]
    with pytest.raises(ValueError, match="outputs are"):
        fls.select_output("w")


def test_several_outputs_zero_firing_per_output() -> None:
    a, b = _t1_two_inputs()
    rules = [Rule(["lo", "lo"], consequents=[1.0, 2.0])]
    fls = T1Sugeno(inputs=[a, b], rules=rules, outputs=("u", "v"), on_zero_firing=(7.0, 8.0))
    assert fls(1.0, 1.0).tolist() == [7.0, 8.0]
    with pytest.raises(ZeroFiringError):
        T1Sugeno(inputs=[a, b], rules=rules, outputs=("u", "v"))(1.0, 1.0)
    with pytest.raises(ValueError, match="one finite number per output"):
        T1Sugeno(inputs=[a, b], rules=rules, on_zero_firing=(1.0, 2.0, 3.0))


def test_scalar_call_with_features_matches_array_path() -> None:
    a, b = _t1_two_inputs()
    fls = T1Sugeno(inputs=[a, b], rules=[Rule(["lo", "hi"], 2.0, connective="or"),
                                         Rule(["hi", "lo"], -1.0, weight=0.3)])
    assert fls(0.2, 0.9) == float(fls(np.array([0.2]), np.array([0.9]))[0])

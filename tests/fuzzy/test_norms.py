"""fuzzylite's t-norms and s-norms (fuzzy.norms) as rule connectives, implications and
aggregations; weighted-sum Sugeno; Tsukamoto and hybrid systems; fuzzylite's midpoint
sampling. Checked against the norms' axioms, closed forms and pyfuzzylite's engine."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from it2track.fuzzy import (
    Aggregation,
    HybridSystem,
    Implication,
    Input,
    Linear,
    Output,
    Ramp,
    Rule,
    Sampling,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TNorm,
    Triangle,
    WeightedDefuzzifier,
    ZeroFiringError,
    from_fuzzylite,
    output_grid,
)

GRID = np.concatenate([[0.0, 1.0, 0.5, 1e-17, 1 - 2**-53], np.linspace(0, 1, 23)])
A, B = (v.ravel() for v in np.meshgrid(GRID, GRID))

FUZZYLITE_T = {TNorm.MINIMUM: "Minimum", TNorm.PRODUCT: "AlgebraicProduct",
               TNorm.BOUNDED_DIFFERENCE: "BoundedDifference",
               TNorm.DRASTIC_PRODUCT: "DrasticProduct", TNorm.EINSTEIN_PRODUCT: "EinsteinProduct",
               TNorm.HAMACHER_PRODUCT: "HamacherProduct",
               TNorm.NILPOTENT_MINIMUM: "NilpotentMinimum"}
FUZZYLITE_S = {SNorm.MAXIMUM: "Maximum", SNorm.PROBOR: "AlgebraicSum",
               SNorm.BOUNDED_SUM: "BoundedSum", SNorm.DRASTIC_SUM: "DrasticSum",
               SNorm.EINSTEIN_SUM: "EinsteinSum", SNorm.HAMACHER_SUM: "HamacherSum",
               SNorm.NILPOTENT_MAXIMUM: "NilpotentMaximum", SNorm.NORMALIZED_SUM: "NormalizedSum",
               SNorm.UNBOUNDED_SUM: "UnboundedSum"}


def same(a, b):
    return np.array_equal(np.asarray(a, dtype=np.float64).view(np.int64),
                          np.asarray(b, dtype=np.float64).view(np.int64))


def fuzzylite():
    return pytest.importorskip("fuzzylite", reason="pyfuzzylite not installed (pip install "
                                                   "pyfuzzylite)")


def test_every_fuzzylite_norm_has_a_member_found_by_its_fuzzylite_name():
    assert set(FUZZYLITE_T) == set(TNorm) and set(FUZZYLITE_S) == set(SNorm)
    for member, name in {**FUZZYLITE_T, **FUZZYLITE_S}.items():
        assert type(member).from_name(name) is member
    assert Implication.from_name("EinsteinProduct").tnorm is TNorm.EINSTEIN_PRODUCT
    assert Aggregation.from_name("UnboundedSum") is Aggregation.SUM
    assert Aggregation.from_name("AlgebraicSum").snorm is SNorm.PROBOR
    assert {a.snorm for a in Aggregation} == set(SNorm)
    assert {i.tnorm for i in Implication} == set(TNorm)
    with pytest.raises(ValueError, match="unknown t-norm 'yager'; choose one of 'product'"):
        TNorm.from_name("yager")


def test_norm_axioms_pinned():
    for t in TNorm:
        got = t.pair(A, B)
        assert same(got, t.pair(B, A)), t  # commutative to the bit
        assert (t.pair(GRID, 0.0 * GRID) == 0).all(), t  # T(a, 0) = 0
        np.testing.assert_allclose(t.pair(GRID, 1.0 + 0 * GRID), GRID, atol=2.3e-16, err_msg=t)
        assert ((got >= 0) & (got <= np.minimum(A, B) + 2.3e-16)).all(), t  # T <= min
    for s in SNorm:
        got = s.pair(A, B)
        assert same(got, s.pair(B, A)), s
        assert same(s.pair(GRID, 0.0 * GRID), GRID), s  # S(a, 0) = a exactly
        assert (got >= np.maximum(A, B) - 1e-15).all(), s  # S >= max
    # the formulas at a = b = 1/2
    half = np.array([0.5])
    assert [float(t.pair(half, half)[0]) for t in TNorm] == [0.25, 0.5, 0.0, 0.0, 0.2, 1 / 3, 0.0]
    assert [float(s.pair(half, half)[0]) for s in SNorm] == [0.5, 0.75, 1.0, 1.0, 0.8,
                                                             2 / 3, 1.0, 1.0, 1.0]


def test_norms_equal_pyfuzzylite_to_the_bit():
    fl = fuzzylite()
    for member, name in FUZZYLITE_T.items():
        assert same(member.pair(A, B), fl.TNormFactory().construct(name).compute(A, B)), name
    for member, name in FUZZYLITE_S.items():
        assert same(member.pair(A, B), fl.SNormFactory().construct(name).compute(A, B)), name


def test_and_fold_leaves_out_inputs_a_rule_does_not_mention():
    """T(m, 1) != m for the bounded difference at tiny m: a rule on one of two inputs fires
    with that input's membership itself."""
    sets = [("A", Triangle(0, 1, 2)), ("B", Triangle(0, 1, 2))]
    inputs = [Input("x", (0, 2), sets), Input("y", (0, 2), sets)]
    rules = [Rule(["A", None], 1.0), Rule([None, "B"], 2.0), Rule(["A", "B"], 3.0)]
    x = np.array([1e-17, 0.3, 1.0])
    for t in TNorm:
        fls = T1Sugeno(inputs=inputs, rules=rules, tnorm=t)
        _, fu = fls.firing(x, x[::-1])
        assert same(fu[:, 0], x) and same(fu[:, 1], x[::-1]), t
        assert same(fu[:, 2], t.pair(x, x[::-1])), t


FLL_INPUTS = """
InputVariable: x
  enabled: true
  range: 0.000 10.000
  term: low Triangle 0.000 0.000 5.000
  term: mid Bell 5.000 2.000 2.000
  term: high SShape 4.000 10.000
InputVariable: y
  enabled: true
  range: 0.000 10.000
  term: low ZShape 0.000 6.000
  term: high Sigmoid 5.000 1.500
"""
OUR_INPUTS = [
    Input("x", (0, 10), [("low", Triangle(0, 0, 5)), ("mid", from_fuzzylite("Bell", [5, 2, 2])),
                         ("high", from_fuzzylite("SShape", [4, 10]))]),
    Input("y", (0, 10), [("low", from_fuzzylite("ZShape", [0, 6])),
                         ("high", from_fuzzylite("Sigmoid", [5, 1.5]))]),
]
RULES = [("if x is low and y is low then z is a", Rule(["low", "low"], "a")),
         ("if x is mid or y is high then z is b", Rule(["mid", "high"], "b", connective="or")),
         ("if x is high and y is high then z is c with 0.7", Rule(["high", "high"], "c",
                                                                   weight=0.7)),
         ("if x is high then z is b", Rule(["high", None], "b"))]


def fll_engine(fl, output, rules, *, conjunction, disjunction, implication="none"):
    text = (f"Engine: test\n{FLL_INPUTS}{output}RuleBlock:\n  enabled: true\n"
            f"  conjunction: {conjunction}\n  disjunction: {disjunction}\n"
            f"  implication: {implication}\n  activation: General\n"
            + "".join(f"  rule: {r}\n" for r in rules))
    return fl.FllImporter().from_string(text)


def run_engine(engine, x, y):
    engine.input_variable("x").value = x
    engine.input_variable("y").value = y
    engine.process()
    return np.asarray(engine.output_variable("z").value, dtype=np.float64)


@pytest.mark.parametrize("tnorm", list(TNorm), ids=lambda t: t.name)
def test_mamdani_with_every_norm_equals_pyfuzzylite(tnorm):
    """Conjunction, disjunction, implication and aggregation from fuzzylite's norms; the
    centroid on fuzzylite's 1000 midpoints."""
    fl = fuzzylite()
    k = list(TNorm).index(tnorm)
    snorm = list(SNorm)[k + 1]
    # (implications that give a non-empty set at most points: drastic, bounded and nilpotent
    # ones leave most aggregated sets zero, for fuzzylite and us alike)
    imp = [Implication.MINIMUM, Implication.PRODUCT, Implication.EINSTEIN_PRODUCT,
           Implication.HAMACHER_PRODUCT][k % 4]
    agg = Aggregation(snorm.value) if snorm is not SNorm.UNBOUNDED_SUM else Aggregation.SUM
    out = ("OutputVariable: z\n  enabled: true\n  range: 0.000 1.000\n"
           f"  aggregation: {FUZZYLITE_S[snorm]}\n  defuzzifier: Centroid 1000\n"
           "  default: nan\n  term: a Ramp 0.500 0.000\n  term: b Cosine 0.500 0.600\n"
           "  term: c Concave 0.700 1.000\n")
    engine = fll_engine(fl, out, [r for r, _ in RULES], conjunction=FUZZYLITE_T[tnorm],
                        disjunction=FUZZYLITE_S[snorm], implication=FUZZYLITE_T[imp.tnorm])
    z = Output("z", (0, 1), [("a", Ramp(0.5, 0)), ("b", from_fuzzylite("Cosine", [0.5, 0.6])),
                             ("c", from_fuzzylite("Concave", [0.7, 1.0]))])
    fls = T1Mamdani(inputs=OUR_INPUTS, outputs=[z], rules=[r for _, r in RULES], tnorm=tnorm,
                    snorm=snorm, implication=imp, aggregation=agg, resolution=1000,
                    sampling=Sampling.MIDPOINTS)
    rng = np.random.default_rng(len(tnorm.value))
    x, y = rng.uniform(0, 10, 300), rng.uniform(0, 10, 300)
    want = run_engine(engine, x, y)
    ok = np.isfinite(want)  # NaN: no output (for both engines: the aggregated set is 0)
    assert ok.sum() > 100
    np.testing.assert_allclose(fls(x[ok], y[ok]), want[ok], rtol=0, atol=1e-12)


@pytest.mark.parametrize("defuzzifier", list(WeightedDefuzzifier), ids=lambda d: d.name)
def test_sugeno_weighted_average_and_sum_equal_pyfuzzylite(defuzzifier):
    fl = fuzzylite()
    name = {WeightedDefuzzifier.AVERAGE: "WeightedAverage",
            WeightedDefuzzifier.SUM: "WeightedSum"}[defuzzifier]
    out = ("OutputVariable: z\n  enabled: true\n  range: -10.000 10.000\n  aggregation: none\n"
           f"  defuzzifier: {name} TakagiSugeno\n  default: nan\n  term: a Constant -3.000\n"
           "  term: b Linear 0.500 -1.000 2.000\n  term: c Constant 7.000\n")
    engine = fll_engine(fl, out, [r for r, _ in RULES[:3]], conjunction="EinsteinProduct",
                        disjunction="HamacherSum")
    cons = {"a": -3.0, "b": Linear([0.5, -1.0], 2.0), "c": 7.0}
    rules = [Rule(r.antecedent, cons[str(r.consequent)], weight=r.weight,
                  connective=r.connective) for _, r in RULES[:3]]
    fls = T1Sugeno(inputs=OUR_INPUTS, rules=rules, tnorm=TNorm.EINSTEIN_PRODUCT,
                   snorm=SNorm.HAMACHER_SUM, defuzzifier=defuzzifier)
    rng = np.random.default_rng(3)
    x, y = rng.uniform(0, 10, 300), rng.uniform(0, 10, 300)
    np.testing.assert_allclose(fls(x, y), run_engine(engine, x, y), rtol=1e-13, atol=1e-13)


def test_weighted_sum_closed_form_and_zero_firing():
    x = Input("x", (0, 2), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0.5, 1, 1.5))])
    fls = T1Sugeno(inputs=[x], rules=[Rule(["lo"], 4.0), Rule(["hi"], -2.0)],
                   defuzzifier=WeightedDefuzzifier.SUM)
    assert float(fls(0.75)) == 0.25 * 4.0 + 0.5 * -2.0  # not divided by the total firing
    assert fls(np.array([0.75]))[0] == 0.0
    with pytest.raises(ZeroFiringError, match="no rule"):
        fls(np.array([1.8]))
    assert float(T1Sugeno(inputs=[x], rules=fls.rules, defuzzifier=WeightedDefuzzifier.SUM,
                          on_zero_firing=-1.0)(1.8)) == -1.0
    with pytest.raises(ValueError, match="defuzzifier='wtsum' must be a WeightedDefuzzifier"):
        T1Sugeno(inputs=[x], rules=fls.rules, defuzzifier="wtsum")


def test_midpoint_sampling_is_fuzzylites_grid():
    fl = fuzzylite()
    for lo, hi, n in ((0.0, 1.0, 1000), (-3.3, 7.1, 101), (0.02, 1.0, 7)):
        assert same(output_grid((lo, hi), n, Sampling.MIDPOINTS), fl.Op.midpoints(lo, hi, n))
        assert same(output_grid((lo, hi), n, Sampling.ENDPOINTS), np.linspace(lo, hi, n))
    assert Sampling.from_name("fuzzylite") is Sampling.MIDPOINTS
    with pytest.raises(ValueError, match="sampling='fuzzylite' must be a Sampling member"):
        T1Mamdani(inputs=OUR_INPUTS, outputs=[Output("z", (0, 1), [("a", Ramp(0, 1))])],
                  rules=[Rule(["low", "low"], "a")], sampling="fuzzylite")


# -- Tsukamoto and hybrid systems against fuzzylite's own examples ----------------------------
def example_engine(fl, path):
    return fl.FllImporter().from_file(os.path.join(os.path.dirname(fl.__file__), "examples",
                                                   path))


def test_tsukamoto_example_equals_pyfuzzylite():
    fl = fuzzylite()
    engine = example_engine(fl, "tsukamoto/tsukamoto.fll")
    x = np.linspace(-10, 10, 401)
    engine.input_variable("X").value = x
    engine.process()
    bells = [("small", [-10, 5, 3]), ("medium", [0, 5, 3]), ("large", [10, 5, 3])]
    inp = Input("X", (-10, 10), [(n, from_fuzzylite("Bell", p)) for n, p in bells])
    outputs = {"Ramps": (0, 1, [("b", "Ramp", [0.6, 0.4]), ("a", "Ramp", [0, 0.25]),
                                ("c", "Ramp", [0.7, 1])]),
               "Sigmoids": (0.02, 1, [("b", "Sigmoid", [0.5, -30]), ("a", "Sigmoid", [0.13, 30]),
                                      ("c", "Sigmoid", [0.83, 30])]),
               "ZSShapes": (0, 1, [("b", "ZShape", [0.3, 0.6]), ("a", "SShape", [0, 0.25]),
                                   ("c", "SShape", [0.7, 1])]),
               "Concaves": (0, 1, [("b", "Concave", [0.5, 0.4]), ("a", "Concave", [0.24, 0.25]),
                                   ("c", "Concave", [0.9, 1])])}
    for name, (lo, hi, terms) in outputs.items():
        out = Output(name, (lo, hi), [(n, from_fuzzylite(k, p)) for n, k, p in terms])
        fls = T1Tsukamoto(inputs=[inp], outputs=[out], rules=[
            Rule(["small"], "a"), Rule(["medium"], "b"), Rule(["large"], "c")])
        want = np.asarray(engine.output_variable(name).value, dtype=np.float64)
        ok = np.isfinite(want)  # fuzzylite's inf where a sigmoid fires fully: we refuse
        np.testing.assert_allclose(fls(x[ok]), want[ok], rtol=0, atol=1e-14, err_msg=name)
        if not ok.all():
            with pytest.raises(ValueError, match=r"set '[abc]' fires 1\.0 at \(X=(-?10|0)\), "
                                                 r"which its membership never reaches"):
                fls(x[~ok])


def test_tsukamoto_groups_the_rules_of_a_set_and_refuses_non_monotonic_sets():
    x = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    y = Output("y", (0, 10), [("up", Ramp(0, 10))])
    rules = [Rule(["lo"], "up"), Rule(["hi"], "up")]
    # sum of the two firings is 1 everywhere: z = inverse(1) = 10 whatever x
    assert T1Tsukamoto(inputs=[x], outputs=[y], rules=rules)(np.linspace(0, 1, 5)).tolist() == [
        10.0] * 5
    # with maximum: w = max(1 - x, x), z = 10 w, output z (one set)
    got = T1Tsukamoto(inputs=[x], outputs=[y], rules=rules,
                      aggregation=Aggregation.MAXIMUM)(np.array([0.25, 0.5]))
    assert got.tolist() == [7.5, 5.0]
    tri = Output("y", (0, 10), [("up", Triangle(0, 5, 10))])
    with pytest.raises(ValueError, match=r"set 'up' \(Triangle.*must be a type-1 monotonic"):
        T1Tsukamoto(inputs=[x], outputs=[tri], rules=rules)


def test_hybrid_tipper_example_equals_pyfuzzylite():
    fl = fuzzylite()
    engine = example_engine(fl, "hybrid/tipper.fll")
    rng = np.random.default_rng(11)
    service, food = rng.uniform(0, 10, 200), rng.uniform(0, 10, 200)
    engine.input_variable("service").value = service
    engine.input_variable("food").value = food
    engine.process()
    inputs = [
        Input("service", (0, 10), [("poor", from_fuzzylite("Trapezoid", [0, 0, 2.5, 5])),
                                   ("good", Triangle(2.5, 5, 7.5)),
                                   ("excellent", from_fuzzylite("Trapezoid", [5, 7.5, 10, 10]))]),
        Input("food", (0, 10), [("rancid", from_fuzzylite("Trapezoid", [0, 0, 2.5, 7.5])),
                                ("delicious", from_fuzzylite("Trapezoid", [2.5, 7.5, 10, 10]))]),
    ]
    ante = [(["poor", "rancid"], "or", 1.0, 0), (["good", None], "and", 1.0, 1),
            (["excellent", "delicious"], "or", 0.5, 2), (["excellent", "delicious"], "and", 1.0, 2)]
    labels = ["cheap", "average", "generous"]
    m_tip = Output("mTip", (0, 30), [(n, Triangle(10 * k, 10 * k + 5, 10 * k + 10))
                                     for k, n in enumerate(labels)])
    mamdani = T1Mamdani(
        inputs=inputs, outputs=[m_tip], tnorm=TNorm.PRODUCT, snorm=SNorm.PROBOR,
        rules=[Rule(a, labels[k], connective=c, weight=w) for a, c, w, k in ante],
        resolution=1000, sampling=Sampling.MIDPOINTS)
    sugeno = T1Sugeno(
        inputs=inputs, tnorm=TNorm.PRODUCT, snorm=SNorm.PROBOR, outputs=("tsTip",),
        rules=[Rule(a, 5.0 + 10 * k, connective=c, weight=w) for a, c, w, k in ante])
    fls = HybridSystem((mamdani, sugeno))
    got = fls(service, food)
    assert got.shape == (200, 2) and fls.output_names == ("mTip", "tsTip")
    for k, name in enumerate(fls.output_names):
        want = np.asarray(engine.output_variable(name).value, dtype=np.float64)
        np.testing.assert_allclose(got[:, k], want, rtol=0, atol=1e-12, err_msg=name)
    assert fls.select_output("tsTip") is sugeno
    assert same(fls.evaluate(np.stack([service, food], axis=-1)), got)
    with pytest.raises(ValueError, match="other inputs than system 0"):
        HybridSystem((mamdani, T1Sugeno(inputs=inputs[:1], rules=[Rule(["good"], 1.0)])))
    with pytest.raises(ValueError, match=r"output names \['mTip', 'mTip'\] must be distinct"):
        HybridSystem((mamdani, mamdani))


def test_einstein_aggregation_is_folded_in_rule_order_of_each_set():
    """With a non-idempotent aggregation two rules on the same set add up (probor would give
    1 - (1 - a)(1 - b)); Einstein sum (a + b) / (1 + a b) pinned at one grid point."""
    x = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    y = Output("y", (0, 1), [("s", Triangle(0, 0.5, 1))])
    fls = T1Mamdani(inputs=[x], outputs=[y], rules=[Rule(["lo"], "s"), Rule(["hi"], "s")],
                    aggregation=Aggregation.EINSTEIN_SUM, resolution=3)
    _, upper = fls.aggregated(0.5)
    assert upper.tolist() == [0.0, 0.8, 0.0]  # (0.5 + 0.5) / (1 + 0.25)
    assert math.isclose(float(fls(0.5)), 0.5)

"""fuzzylite's FuzzyLite Language: hand-computed values (fuzzylite's midpoint centroid, the
weighted average), bit-exact round trips of every system kind FLL carries, and refusals that
name the line and the feature."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from io_systems import random_system

from it2track.fuzzy import (
    Aggregation,
    Defuzzifier,
    FootedTrapezoid,
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
)
from it2track.io import FisFormatError, FisFormatWarning, UnsupportedFeatureError, dumps, loads

DATA = Path(__file__).parent / "data"
MAMDANI = (DATA / "dimmer.fll").read_text()

SUGENO = """Engine: tsk
InputVariable: a
  range: 0 10
  term: lo Ramp 10 0
  term: hi Ramp 0 10
InputVariable: b
  range: 0 10
  term: lo Ramp 10 0
  term: hi Ramp 0 10
OutputVariable: y
  range: -100 100
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: 3.5
  term: flat Constant 7
  term: plane Linear 2 -1 0.5
OutputVariable: z
  range: 0 1
  aggregation: none
  defuzzifier: WeightedAverage Automatic
  default: 0
  term: one Constant 1
RuleBlock:
  conjunction: AlgebraicProduct
  disjunction: AlgebraicSum
  implication: none
  rule: if (a is lo or b is hi) then y is flat and z is one
  rule: if a is hi and b is not hi then y is plane with 0.25
"""


def error_of(text: str) -> FisFormatError:
    with pytest.raises(FisFormatError) as info:
        loads(text, "fll", path="f.fll")
    return info.value


def line_with(text: str, needle: str) -> int:
    return next(i for i, line in enumerate(text.split("\n"), 1) if needle in line)


def test_mamdani_centroid_is_fuzzylites_midpoint_rule() -> None:
    fls = loads(MAMDANI, "fll")
    assert isinstance(fls, T1Mamdani) and fls.name == "dimmer" and fls.on_zero_firing is None
    assert (fls.resolution, fls.sampling) == (8, Sampling.MIDPOINTS)
    # at ambient 0.3: dark 0.5, bright 0; the output set is min(0.5, high), sampled at the
    # middles of 8 cells of [0, 2]
    y = (np.arange(8) + 0.5) * 0.25
    high = np.clip((y - 0.8) / 1.2, 0.0, 1.0)
    mu = np.minimum(0.5, high)
    assert float(fls(0.3)) == pytest.approx(float((y * mu).sum() / mu.sum()), rel=1e-15)


def test_sugeno_with_parentheses_not_two_outputs_and_weights() -> None:
    fls = loads(SUGENO, "fll")
    assert isinstance(fls, T1Sugeno) and fls.output_names == ("y", "z")
    assert fls.on_zero_firing == (3.5, 0.0)
    assert (fls.tnorm, fls.snorm) == (TNorm.PRODUCT, SNorm.PROBOR)
    assert fls.rules[1].consequents[0] == Linear([2.0, -1.0], 0.5)
    # at (a, b) = (8, 4): rule 1 = probor(0.2, 0.4) = 0.52 (y = 7); rule 2 =
    # 0.25 * 0.8 * (1 - 0.4) = 0.12 (y = 2 * 8 - 4 + 0.5 = 12.5); z: only rule 1 -> 1
    y, z = fls(8.0, 4.0)
    assert y == pytest.approx((0.52 * 7 + 0.12 * 12.5) / 0.64, rel=1e-15)
    assert z == 1.0


@pytest.mark.parametrize("seed", range(3))
def test_random_type1_round_trip_is_bit_exact(seed: int) -> None:
    system = random_system(seed, type1=True, identifiers=True)
    text = dumps(system, "fll")
    again = loads(text, "fll")
    points = [np.linspace(*i.universe, 41) for i in system.inputs]
    assert np.array_equal(again(*points), system(*points))
    assert dumps(again, "fll") == text


def _kinds() -> list:
    x = Input("x", (0.0, 1.0), [("lo", Triangle(0.0, 0.0, 1.0)), ("hi", Triangle(0.0, 1.0, 1.0))])
    out = Output("m", (0.0, 1.0), [("a", Triangle(0.0, 0.0, 1.0)), ("b", Ramp(0.2, 1.0))])
    mamdani = T1Mamdani(inputs=[x], outputs=[out], rules=[Rule(["lo"], "a"),
                                                          Rule(["hi"], "b", weight=0.5)],
                        tnorm=TNorm.HAMACHER_PRODUCT, implication=Implication.PRODUCT,
                        aggregation=Aggregation.EINSTEIN_SUM, defuzzifier=Defuzzifier.MOM,
                        resolution=333, sampling=Sampling.MIDPOINTS, on_zero_firing=0.25)
    tsukamoto = T1Tsukamoto(inputs=[x], rules=[Rule(["lo"], "d"), Rule(["hi"], "u")],
                            outputs=[Output("t", (0.0, 1.0), [("d", Ramp(1.0, 0.0)),
                                                              ("u", Ramp(0.0, 1.0))])],
                            aggregation=Aggregation.MAXIMUM,
                            defuzzifier=WeightedDefuzzifier.SUM)
    sugeno = T1Sugeno(inputs=[x], rules=[Rule(["lo"], 1.0), Rule(["hi"], Linear([3.0], -1.0))],
                      outputs=("s",))
    return [mamdani, tsukamoto, HybridSystem((mamdani, sugeno, tsukamoto), name="all")]


@pytest.mark.parametrize("system", _kinds(), ids=["mamdani", "tsukamoto", "hybrid"])
def test_every_kind_round_trips_bit_exactly(system) -> None:
    text = dumps(system, "fll")
    again = loads(text, "fll")
    assert type(again) is type(system)
    x = np.linspace(0.0, 1.0, 29)
    assert np.array_equal(again(x), system(x))
    assert dumps(again, "fll") == text
    if not isinstance(system, HybridSystem):
        assert again == system


def test_the_writer_refuses_what_fll_cannot_carry() -> None:
    with pytest.raises(UnsupportedFeatureError, match="no type-2"):
        dumps(random_system(0), "fll")
    with pytest.raises(UnsupportedFeatureError, match="not a fuzzylite identifier"):
        dumps(random_system(0, type1=True), "fll")  # a set named "P2 'quoted'"
    mamdani = _kinds()[0]
    with pytest.raises(UnsupportedFeatureError, match="midpoints of N cells"):
        dumps(dataclasses.replace(mamdani, sampling=Sampling.ENDPOINTS), "fll")


MALFORMED = [
    ("term: dark Triangle 0.0 0.0 0.6", "term: dark Function 1 + x *", "term: dark",
     "Function '1 + x *': ends where a number, name or '(' should follow (at the end)"),
    ("term: dark Triangle 0.0 0.0 0.6", "term: dark Function lt(x, y)", "term: dark",
     "Function 'lt(x, y)': unknown name 'y' (the formula may read: x;"),
    ("term: dark Triangle 0.0 0.0 0.6", "term: dark Triangle 0.0 0.0", "term: dark",
     "Triangle needs 3 parameters"),
    ("term: dark Triangle 0.0 0.0 0.6", "term: dark Triangle 0.0 0.0 x", "term: dark",
     "bad number 'x'"),
    ("activation: General", "activation: Highest 2", "activation:", "Highest 2 is not supported"),
    ("lock-previous: false", "lock-previous: yes", "lock-previous", "expected true or false"),
    ("  enabled: true\n  range: 0.0 1.0", "  enabled: false\n  range: 0.0 1.0", "enabled: false",
     "a disabled variable"),
    ("range: 0.0 1.0", "range: 1.0 0.0", "range: 1.0 0.0", "lo < hi"),
    ("defuzzifier: Centroid 8", "defuzzifier: Centroid 2", "defuzzifier", "resolution 2"),
    ("defuzzifier: Centroid 8", "defuzzifier: Median", "defuzzifier", "'Median' is not"),
    ("conjunction: Minimum", "conjunction: Lukasiewicz", "conjunction", "'Lukasiewicz' is not"),
    ("rule: if ambient is dark then power is high",
     "rule: if ambient is very then power is high", "is very then",
     "expected a term after 'ambient' is, got 'then'"),
    ("rule: if ambient is dark then power is high",
     "rule: if power is low then power is high", "if power is low", "no rule before it"),
    ("rule: if ambient is dark then power is high",
     "rule: if ambient is dark then power is medium", "power is medium", "no term 'medium'"),
    ("rule: if ambient is dark then power is high",
     "rule: if ambient is dark then power is high with 1.5", "with 1.5", "weight 1.5"),
    ("rule: if ambient is dark then power is high", "rule: ambient is dark", "rule: ambient",
     "expected 'if'"),
    ("  lock-range: false\n  aggregation", "  colour: red\n  aggregation", "colour",
     "unknown key 'colour'"),
    ("Engine: dimmer", "Engine: dimmer\nEngine: again", "Engine: again", "a second Engine"),
]


@pytest.mark.parametrize(("old", "new", "needle", "problem"), MALFORMED,
                         ids=[m[3] for m in MALFORMED])
def test_malformed_fll_names_the_line(old: str, new: str, needle: str, problem: str) -> None:
    assert old in MAMDANI, old
    text = MAMDANI.replace(old, new, 1)
    err = error_of(text)
    assert problem in err.message, err
    assert err.line == line_with(text, needle), err


def test_a_shared_term_aggregated_by_maximum_is_refused_for_takagi_sugeno() -> None:
    text = SUGENO.replace("then y is plane with 0.25", "then y is flat with 0.25")
    assert loads(text, "fll") is not None  # aggregation: none sums them: a weighted average
    err = error_of(text.replace("  aggregation: none\n  defuzzifier: WeightedAverage "
                                "TakagiSugeno", "  aggregation: Maximum\n  defuzzifier: "
                                "WeightedAverage TakagiSugeno"))
    assert "term 'flat' (several rules conclude it)" in err.message


def test_a_rule_needing_an_operator_its_block_lacks_is_refused() -> None:
    err = error_of(SUGENO.replace("conjunction: AlgebraicProduct", "conjunction: none"))
    assert err.line == line_with(SUGENO, "a is hi and b") and "conjunction: none" in err.message
    err = error_of(MAMDANI.replace("implication: Minimum", "implication: none"))
    assert "needs an implication" in err.message


def test_a_duplicated_term_name_binds_the_last_with_a_warning() -> None:
    # MATLAB's juggler.fll as fuzzylite wrote it names nine planes out1mf; pyfuzzylite 8 binds
    # a rule's out1mf to the last of them (fuzzylite 6 bound the first)
    text = SUGENO.replace("  term: plane Linear 2 -1 0.5",
                          "  term: plane Linear 2 -1 0.5\n  term: flat Constant 9")
    with pytest.warns(FisFormatWarning, match=r"duplicate term 'flat' \(first at line 15\)"):
        twice = loads(text, "fll")
    once = loads(SUGENO.replace("term: flat Constant 7", "term: flat Constant 9"), "fll")
    x = np.linspace(0, 1, 11)
    np.testing.assert_array_equal(twice(x, x[::-1]), once(x, x[::-1]))


def test_a_shoulder_inside_the_range_is_zero_beyond_its_foot_as_in_fuzzylite() -> None:
    text = MAMDANI.replace("term: dark Triangle 0.0 0.0 0.6", "term: dark Triangle 0.2 0.2 0.6")
    fls = loads(text, "fll")
    dark = fls.inputs[0].sets[0].upper
    assert isinstance(dark, FootedTrapezoid)
    np.testing.assert_allclose(dark(np.array([0.1, 0.2, 0.4, 0.7])), [0.0, 1.0, 0.5, 0.0],
                               rtol=0, atol=1e-15)
    again = loads(dumps(fls, "fll"), "fll")
    assert again.inputs == fls.inputs


def test_function_terms_are_formulas_of_x_and_of_the_inputs() -> None:
    # Mamdani: 'high' as fuzzylite's Function of x, negative below 0.8 (floored at 0, as the
    # Maximum aggregation starting from 0 makes it in fuzzylite): the same system as the
    # triangle's.
    text = MAMDANI.replace("term: high Triangle 0.8 2.0 2.0",
                           "term: high Function min((x - 0.8) / 1.2, 1)")
    fls, same = loads(text, "fll"), loads(MAMDANI, "fll")
    x = np.linspace(0.0, 1.0, 11)
    np.testing.assert_allclose(fls(x), same(x), rtol=1e-15, atol=0)
    for agg, imp in [("AlgebraicSum", "Minimum"), ("Maximum", "EinsteinProduct")]:
        other = text.replace("aggregation: Maximum", f"aggregation: {agg}").replace(
            "implication: Minimum", f"implication: {imp}")
        err = error_of(other)
        assert err.line == line_with(other, "term: high Function")
        assert err.message.startswith("term 'high': a Function output term needs aggregation: "
                                      "Maximum and implication: Minimum or AlgebraicProduct")
    # Takagi-Sugeno: a formula of the inputs by name
    tsk = SUGENO.replace("term: plane Linear 2 -1 0.5", "term: plane Function 2*a - b^2 + 0.5")
    fls = loads(tsk, "fll")
    a, b = np.meshgrid(np.linspace(0, 10, 5), np.linspace(0, 10, 5))
    a, b = a.ravel(), b.ravel()
    lo_a, hi_a, hi_b = 1 - a / 10, a / 10, b / 10
    f1 = 1 - (1 - lo_a) * (1 - hi_b)  # AlgebraicSum of (a is lo or b is hi)
    f2 = 0.25 * hi_a * (1 - hi_b)
    expected = (f1 * 7 + f2 * (2 * a - b**2 + 0.5)) / (f1 + f2)
    np.testing.assert_allclose(fls(a, b)[:, 0], expected, rtol=1e-14, atol=0)
    chained = SUGENO.replace("term: plane Linear 2 -1 0.5", "term: plane Function a + z")
    err = error_of(chained)
    assert err.line == line_with(chained, "term: plane Function")
    assert err.message == ("term 'plane': Function 'a + z' reads the output 'z', which "
                           "fuzzylite defuzzifies after 'y' (its value of the previous "
                           "evaluation, NaN after a restart): it2track reads only the outputs "
                           "declared before this one (none)")

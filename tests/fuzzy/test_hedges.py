"""Hedges (fuzzylite's very, somewhat, extremely, seldom, any, not; Octave's powers): their
closed forms, their place in a rule (before NOT; on a conclusion, after the weight), interval
bounds (a 'not' among the hedges swaps them), and the readers' and writers' handling of them
(fuzzylite's carry-over of a hedged conclusion's degree; formats that cannot carry them refuse).
"""

from __future__ import annotations

import numpy as np
import pytest

from it2track.fuzzy import (
    Hedge,
    Hedged,
    Input,
    IT2Set,
    IT2Sugeno,
    Rule,
    T1Sugeno,
    TNorm,
    Triangle,
)
from it2track.io import UnsupportedFeatureError, dumps, loads


@pytest.mark.parametrize(("name", "mu", "want"), [
    ("very", [0.0, 0.5, 0.3, 1.0], [0.0, 0.25, 0.09, 1.0]),
    ("somewhat", [0.0, 0.25, 0.81, 1.0], [0.0, 0.5, 0.9, 1.0]),
    ("extremely", [0.0, 0.25, 0.5, 0.75, 1.0], [0.0, 0.125, 0.5, 0.875, 1.0]),
    ("seldom", [0.0, 0.125, 0.5, 0.875, 1.0], [0.0, 0.25, 0.5, 0.75, 1.0]),
    ("any", [0.0, 0.4, 1.0], [1.0, 1.0, 1.0]),
    ("not", [0.0, 0.25, 1.0], [1.0, 0.75, 0.0]),
])
def test_fuzzylite_hedges_closed_forms(name: str, mu: list[float], want: list[float]) -> None:
    np.testing.assert_allclose(Hedge(name)(np.array(mu)), want, rtol=0, atol=1e-15)


def test_extremely_and_seldom_branches_meet_at_one_half() -> None:
    # extremely: 2 mu^2 below 1/2, 1 - 2 (1 - mu)^2 above; seldom its inverse
    mu = np.array([0.4, 0.6])
    np.testing.assert_allclose(Hedge("extremely")(mu), [0.32, 0.68], rtol=0, atol=1e-15)
    np.testing.assert_allclose(Hedge("seldom")(Hedge("extremely")(mu)), mu, rtol=0, atol=1e-15)


def test_octave_power_hedges_and_validation() -> None:
    np.testing.assert_allclose(Hedge.power(3)(np.array([0.5, 0.2])), [0.125, 0.008], atol=1e-16)
    np.testing.assert_allclose(Hedge.power(0.5)(np.array([0.25])), [0.5])
    with pytest.raises(ValueError, match="exponent"):
        Hedge.power(0)
    with pytest.raises(ValueError, match="'quite'"):
        Hedge("quite")
    with pytest.raises(ValueError, match="takes no exponent"):
        Hedge("very", 2.0)


def _x() -> Input:
    return Input("x", (0, 4), [("lo", Triangle(0, 0, 4)), ("hi", Triangle(0, 4, 4))])


def test_hedged_antecedent_then_not_in_a_sugeno_system() -> None:
    # at x = 1: lo = 0.75, hi = 0.25
    rules = [Rule(["lo"], 10.0, hedges=[[Hedge("very")]]),
             Rule(["hi"], 20.0, negated=[True], hedges=[[Hedge("extremely")]])]
    fls = T1Sugeno(inputs=[_x()], rules=rules)
    f1 = 0.75**2
    f2 = 1 - 2 * 0.25**2  # not (extremely 0.25)
    assert float(fls(1.0)) == pytest.approx((10 * f1 + 20 * f2) / (f1 + f2), rel=1e-15)
    assert "hedges" in fls._c.features


def test_conclusion_hedge_acts_on_the_weighted_firing_of_its_output_only() -> None:
    rules = [Rule(["lo"], consequents=[10.0, 10.0], weight=0.5,
                  consequent_hedges=[[Hedge("very")], []]),
             Rule(["hi"], consequents=[20.0, 20.0])]
    fls = T1Sugeno(inputs=[_x()], rules=rules, tnorm=TNorm.PRODUCT)
    y = fls(1.0)
    w1, w2 = 0.5 * 0.75, 0.25
    assert float(y[0]) == pytest.approx((10 * w1**2 + 20 * w2) / (w1**2 + w2), rel=1e-15)
    assert float(y[1]) == pytest.approx((10 * w1 + 20 * w2) / (w1 + w2), rel=1e-15)


def test_interval_bounds_under_hedges_and_a_not_among_them() -> None:
    s = IT2Set(Triangle(0, 2, 4), Triangle(1, 2, 3, 0.5), "mid")
    x = Input("x", (0, 4), [s])
    up, lo = 0.75, 0.25  # at x = 1.5: upper (1.5 - 0)/2, lower 0.5 (1.5 - 1)/1
    # "very not mid": very(1 - mu); its upper bound is very(1 - lower)
    rule = Rule(["mid"], (0.0, 0.0), hedges=[[Hedge("very"), Hedge("not")]])
    fls = IT2Sugeno(inputs=[x], rules=[rule, Rule(["mid"], (1.0, 1.0))])
    fl, fu = fls._c.firing_block(np.array([[1.5]]), TNorm.MINIMUM)
    got = sorted(zip(fl[:, 0].tolist(), fu[:, 0].tolist(), strict=True))
    assert got == sorted([((1 - up) ** 2, (1 - lo) ** 2), (lo, up)])


def test_rule_refuses_hedges_where_the_rule_does_not_act() -> None:
    with pytest.raises(ValueError, match="does not mention cannot have hedges"):
        Rule(["lo", None], 1.0, hedges=[[], [Hedge("very")]])
    with pytest.raises(ValueError, match="a sequence of Hedge per output"):
        Rule(["lo"], 1.0, consequent_hedges=[[], []])
    assert Hedged(Triangle(0, 1, 2), (Hedge("very"),))(np.array([0.5])).tolist() == [0.25]


FLL = """Engine: hedged
InputVariable: x
  enabled: true
  range: 0.000 4.000
  term: lo Triangle 0.000 0.000 4.000
  term: hi Triangle 0.000 4.000 4.000
OutputVariable: a
  enabled: true
  range: 0.000 30.000
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  term: A Constant 10.000
  term: B Constant 20.000
OutputVariable: b
  enabled: true
  range: 0.000 30.000
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  term: A Constant 10.000
  term: B Constant 20.000
RuleBlock: rules
  enabled: true
  conjunction: Minimum
  disjunction: Maximum
  implication: none
  activation: General
  rule: if x is somewhat lo then a is very A and b is A
  rule: if x is not seldom hi then a is B and b is B
"""


def test_fll_conclusion_hedges_carry_on_as_fuzzylite_does_and_round_trip() -> None:
    fls = loads(FLL, "fll")
    # at x = 1: lo = 0.75, hi = 0.25. Rule 1 fires sqrt(0.75); fuzzylite hands the degree
    # "very" made for a on to b (Consequent.modify), so both outputs see 0.75.
    f1 = 0.75
    f2 = 1 - np.sqrt(0.5 * 0.25)  # not (seldom 0.25)
    want = (10 * f1 + 20 * f2) / (f1 + f2)
    np.testing.assert_allclose(fls(1.0), [want, want], rtol=1e-15)
    again = loads(dumps(fls, "fll"), "fll")
    x = np.linspace(0, 3.9, 40)  # at 4 no rule fires (not seldom 1 = 0)
    np.testing.assert_array_equal(again(x), fls(x))


@pytest.mark.parametrize("fmt", ["fis", "t2fis", "toml", "fml"])
def test_formats_without_hedges_refuse_them(fmt: str) -> None:
    fls = loads(FLL, "fll")
    with pytest.raises(UnsupportedFeatureError, match="hedges"):
        dumps(fls, fmt)


def test_fll_writer_refuses_octave_power_hedges() -> None:
    rule = Rule(["lo"], 1.0, hedges=[[Hedge.power(3)]])
    fls = T1Sugeno(inputs=[_x()], rules=[rule])
    with pytest.raises(UnsupportedFeatureError, match="power"):
        dumps(fls, "fll")

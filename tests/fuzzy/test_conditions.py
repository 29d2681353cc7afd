"""General rule conditions (nested AND/OR/NOT, explicit norms, weighted and hedged degrees):
closed forms, interval bounds under negation, agreement with the flat rule form, validation,
and the readers that build them: FCL's and fuzzylite's nested conditions, fuzzylite's chained
propositions on outputs (the degree of the rules before them), and a rule concluding one
output twice (jFuzzyLogic)."""

from __future__ import annotations

import numpy as np
import pytest

from it2track.fuzzy import (
    Hedge,
    Input,
    IT2Set,
    IT2Sugeno,
    Output,
    Rule,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Triangle,
)
from it2track.fuzzy.conditions import Is, Join, Modified, Not
from it2track.io import FisFormatError, UnsupportedFeatureError, dumps, loads


def _inputs() -> list[Input]:
    return [Input(n, (0, 4), [("lo", Triangle(0, 0, 4)), ("hi", Triangle(0, 4, 4))])
            for n in ("a", "b", "c")]


def test_and_of_or_with_explicit_norms_closed_form() -> None:
    # at (1, 2, 3): a lo 0.75, b hi 0.5, c hi 0.75
    cond = Join("and", (Is(0, "lo"), Join("or", (Is(1, "hi"), Not(Is(2, "hi"))),
                                          SNorm.PROBOR)), TNorm.PRODUCT)
    fls = T1Sugeno(inputs=_inputs(), rules=[
        Rule([None] * 3, 10.0, condition=cond, weight=0.5),
        Rule(["hi", None, None], 20.0)])
    f1 = 0.5 * 0.75 * (0.5 + 0.25 - 0.5 * 0.25)
    f2 = 0.25
    assert float(fls(1.0, 2.0, 3.0)) == pytest.approx((10 * f1 + 20 * f2) / (f1 + f2), rel=1e-15)
    assert "tree" in fls._c.features


def test_system_norms_where_a_join_names_none_and_modified_degrees() -> None:
    cond = Modified(Join("or", (Is(0, "lo"), Is(1, "lo"))), 0.5, (Hedge("very"),))
    fls = T1Sugeno(inputs=_inputs(), rules=[Rule([None] * 3, 1.0, condition=cond),
                                            Rule(["hi", None, None], 0.0)],
                   snorm=SNorm.MAXIMUM)
    f1 = (0.5 * max(0.75, 0.5)) ** 2
    assert float(fls(1.0, 2.0, 0.0)) == pytest.approx(f1 / (f1 + 0.25), rel=1e-15)


def test_a_tree_rule_equals_its_flat_form_bit_for_bit() -> None:
    out = Output("y", (0, 10), [("s", Triangle(0, 0, 10)), ("l", Triangle(0, 10, 10))])
    flat = [Rule(["lo", "hi", None], "s"), Rule(["hi", None, None], "l")]
    tree = [Rule([None] * 3, "s", condition=Join("and", (Is(0, "lo"), Is(1, "hi")))),
            flat[1]]
    x = np.linspace(0, 4, 9)
    a = T1Mamdani(inputs=_inputs(), outputs=[out], rules=flat, tnorm=TNorm.MINIMUM)
    b = T1Mamdani(inputs=_inputs(), outputs=[out], rules=tree, tnorm=TNorm.MINIMUM)
    np.testing.assert_array_equal(a(x, x[::-1], x), b(x, x[::-1], x))


def test_interval_bounds_swap_under_not() -> None:
    s = IT2Set(Triangle(0, 2, 4), Triangle(1, 2, 3, 0.5), "mid")
    x = Input("x", (0, 4), [s])
    fls = IT2Sugeno(inputs=[x], rules=[Rule([None], (0.0, 0.0), condition=Not(Is(0, "mid"))),
                                       Rule(["mid"], (1.0, 1.0))])
    fl, fu = fls._c.firing_block(np.array([[1.5]]), TNorm.PRODUCT)
    got = sorted(zip(fl[:, 0].tolist(), fu[:, 0].tolist(), strict=True))
    assert got == sorted([(1 - 0.75, 1 - 0.25), (0.25, 0.75)])


def test_conditions_are_validated() -> None:
    with pytest.raises(ValueError, match="antecedent as None"):
        Rule(["lo", None, None], 1.0, condition=Is(0, "lo"))
    with pytest.raises(ValueError, match="names input 3"):
        Rule([None] * 3, 1.0, condition=Is(3, "lo"))
    with pytest.raises(ValueError, match="must be a TNorm"):
        Join("and", (Is(0, "lo"), Is(1, "lo")), SNorm.MAXIMUM)
    with pytest.raises(ValueError, match="two or more"):
        Join("or", (Is(0, "lo"),))
    with pytest.raises(ValueError, match="weight"):
        Modified(Is(0, "lo"), 1.5)
    with pytest.raises(ValueError, match="no set 'mid'"):
        T1Sugeno(inputs=_inputs(), rules=[Rule([None] * 3, 1.0, condition=Is(0, "mid"))])


CHAINED = """Engine: chained
InputVariable: x
  range: 0 4
  term: lo Triangle 0 0 4
  term: hi Triangle 0 4 4
OutputVariable: p
  range: 0 10
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  term: A Constant 2
  term: B Constant 8
OutputVariable: q
  range: 0 10
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  term: C Constant 1
  term: D Constant 9
RuleBlock:
  conjunction: Minimum
  disjunction: Maximum
  implication: none
  rule: if x is lo then p is A
  rule: if x is hi then p is A with 0.5
  rule: if x is hi then p is B
  rule: if p is A then q is C
  rule: if p is very B then q is D
"""


def test_fll_chained_propositions_read_the_earlier_rules() -> None:
    fls = loads(CHAINED, "fll")
    lo, hi = 0.75, 0.25  # at x = 1
    a = lo + 0.5 * hi  # 'p is A' after rules 1 and 2, by p's aggregation (none: their sum)
    d = hi**2  # 'p is very B'
    p = (2 * lo + 2 * 0.5 * hi + 8 * hi) / (lo + 0.5 * hi + hi)
    q = (1 * a + 9 * d) / (a + d)
    np.testing.assert_allclose(fls(1.0), [p, q], rtol=1e-15)
    with pytest.raises(UnsupportedFeatureError, match="general condition"):
        dumps(fls, "fll")


def test_a_chained_term_no_earlier_rule_concludes_is_refused_with_its_line() -> None:
    text = CHAINED.replace("if p is A then q is C", "if p is B then q is C")
    text = text.replace("  rule: if x is hi then p is B\n", "")
    with pytest.raises(FisFormatError, match="no rule before it") as info:
        loads(text, "fll")
    assert info.value.line == text.split("\n").index("  rule: if p is B then q is C") + 1


FCL = """FUNCTION_BLOCK f
VAR_INPUT a : REAL; b : REAL; END_VAR
VAR_OUTPUT y : REAL; END_VAR
FUZZIFY a
    TERM lo := (0, 1) (4, 0);
    TERM hi := (0, 0) (4, 1);
END_FUZZIFY
FUZZIFY b
    TERM lo := (0, 1) (4, 0);
    TERM hi := (0, 0) (4, 1);
END_FUZZIFY
DEFUZZIFY y
    TERM s := 2;
    TERM l := 8;
    METHOD : COGS;
END_DEFUZZIFY
RULEBLOCK r
    AND : PROD;
    OR : MAX;
    RULE 1 : IF a IS lo AND (b IS hi OR a IS hi) THEN y IS s;
    RULE 2 : IF b IS lo THEN y IS l, y IS s WITH 0.5;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


def test_fcl_nested_condition_and_a_second_conclusion_on_one_output() -> None:
    fls = loads(FCL, "fcl")
    a_lo, a_hi, b_lo, b_hi = 0.75, 0.25, 0.5, 0.5  # at (1, 2)
    f1 = a_lo * max(b_hi, a_hi)
    # rule 2 concludes y twice: two rules (jFuzzyLogic), both of weight 0.5
    num = 2 * f1 + 8 * 0.5 * b_lo + 2 * 0.5 * b_lo
    den = f1 + 0.5 * b_lo + 0.5 * b_lo
    assert float(fls(1.0, 2.0)) == pytest.approx(num / den, rel=1e-15)
    assert len(fls.rules) == 3


def test_fis_show_writes_conditions_and_hedges() -> None:
    from it2track.cli.fis import rule_text

    fls = loads(CHAINED, "fll")
    assert rule_text(fls, fls.rules[4]) == "if very ((x is hi)) then q = 9"  # p is very B
    hedged = fls.rules[4].condition
    assert isinstance(hedged, Modified) and [str(h) for h in hedged.hedges] == ["very"]
    tree = T1Sugeno(inputs=_inputs(), rules=[Rule([None] * 3, 1.0, condition=Join(
        "or", (Is(0, "lo", (Hedge("very"),)), Not(Is(1, "hi"))), SNorm.PROBOR))])
    assert rule_text(tree, tree.rules[0]) == (
        "if (a is very lo) or [probor] (not (b is hi)) then 1")


def test_c_generation_and_kernels_refuse_trees_and_hedges_naming_them() -> None:
    from it2track.codegen.generate import check_supported
    from it2track.fuzzy.kernels import supported

    tree = T1Sugeno(inputs=_inputs(), rules=[
        Rule([None] * 3, 1.0, condition=Join("and", (Is(0, "lo"), Is(1, "hi")))),
        Rule(["hi", None, None], 0.0)])
    hedged = T1Sugeno(inputs=_inputs(), rules=[
        Rule(["lo", None, None], 1.0, hedges=[[Hedge("very")], [], []]),
        Rule(["hi", None, None], 0.0)])
    for fls, feature in ((tree, "tree"), (hedged, "hedges")):
        with pytest.raises(UnsupportedFeatureError, match=feature):
            check_supported(fls)
        assert feature in (supported(fls) or "")

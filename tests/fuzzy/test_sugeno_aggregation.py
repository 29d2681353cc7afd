"""A T1Sugeno whose rules concluding one value form one term (jFuzzyLogic's ``ACCU`` of
singletons, grouped by value): closed forms, first-order values grouped where they coincide,
the FCL reader's use of it, and the refusals of the compiled kernels and the writers."""

from __future__ import annotations

import numpy as np
import pytest

from it2track.fuzzy import (
    Aggregation,
    Input,
    Linear,
    Rule,
    T1Sugeno,
    TNorm,
    Triangle,
    WeightedDefuzzifier,
)
from it2track.fuzzy.kernels import supported
from it2track.io import UnsupportedFeatureError, dumps, loads


def _x() -> Input:
    return Input("x", (0, 4), [("lo", Triangle(0, 0, 4)), ("mid", Triangle(0, 2, 4)),
                               ("hi", Triangle(0, 4, 4))])


RULES = [Rule(["lo"], 10.0), Rule(["mid"], 10.0), Rule(["hi"], 20.0)]


@pytest.mark.parametrize(("aggregation", "combine"), [
    (Aggregation.MAXIMUM, max),
    (Aggregation.PROBOR, lambda a, b: a + b - a * b),
    (None, lambda a, b: a + b),
])
def test_rules_of_one_value_are_one_term(aggregation, combine) -> None:
    fls = T1Sugeno(inputs=[_x()], rules=RULES, aggregation=aggregation)
    lo, mid, hi = 0.75, 0.5, 0.25  # at x = 1
    w = combine(lo, mid)
    assert float(fls(1.0)) == pytest.approx((10 * w + 20 * hi) / (w + hi), rel=1e-15)


def test_weighted_sum_with_maximum() -> None:
    fls = T1Sugeno(inputs=[_x()], rules=RULES, aggregation=Aggregation.MAXIMUM,
                   defuzzifier=WeightedDefuzzifier.SUM)
    assert float(fls(1.0)) == pytest.approx(10 * 0.75 + 20 * 0.25, rel=1e-15)


def test_first_order_values_are_grouped_where_they_coincide() -> None:
    # y = x and y = 2x meet at x = 0 only: there the two rules are one term (max), elsewhere two
    rules = [Rule(["lo"], Linear([1.0], 0.0)), Rule(["lo"], Linear([2.0], 0.0)),
             Rule(["hi"], 5.0)]
    fls = T1Sugeno(inputs=[_x()], rules=rules, aggregation=Aggregation.MAXIMUM,
                   on_zero_firing=0.0)
    plain = T1Sugeno(inputs=[_x()], rules=rules)
    assert float(fls(1.0)) == pytest.approx(float(plain(1.0)), rel=1e-15)
    # at x = 0: lo = 1, hi = 0 -> (0 * 1 + 5 * 0) / (1 + 0) either way; check the denominators
    # through x = 2: lo = hi = 0.5, values 2, 4, 5 (all distinct): the plain average
    assert float(fls(2.0)) == pytest.approx((2 + 4 + 5) / 3, rel=1e-15)
    shared = [Rule(["lo"], Linear([1.0], 1.0)), Rule(["mid"], Linear([0.0], 2.0)),
              Rule(["hi"], 0.0)]
    fls = T1Sugeno(inputs=[_x()], rules=shared, aggregation=Aggregation.MAXIMUM)
    # at x = 1 both linear rules give 2: one term of degree max(0.75, 0.5)
    want = (2 * 0.75 + 0 * 0.25) / (0.75 + 0.25)
    assert float(fls(1.0)) == pytest.approx(want, rel=1e-15)


def test_aggregation_is_numpy_only_and_validated() -> None:
    fls = T1Sugeno(inputs=[_x()], rules=RULES, aggregation=Aggregation.MAXIMUM,
                   tnorm=TNorm.PRODUCT)
    assert "aggregation" in (supported(fls) or "")
    assert supported(T1Sugeno(inputs=[_x()], rules=RULES)) is None
    with pytest.raises(ValueError, match="aggregation="):
        T1Sugeno(inputs=[_x()], rules=RULES, aggregation="max")  # type: ignore[arg-type]


FCL = """FUNCTION_BLOCK f
VAR_INPUT x : REAL; END_VAR
VAR_OUTPUT y : REAL; END_VAR
FUZZIFY x
    TERM lo := (0, 1) (4, 0);
    TERM mid := (0, 0) (2, 1) (4, 0);
    TERM hi := (0, 0) (4, 1);
END_FUZZIFY
DEFUZZIFY y
    TERM a := 10;
    TERM b := 10;
    TERM c := 20;
    METHOD : COGS;
END_DEFUZZIFY
RULEBLOCK r
    ACCU : MAX;
    RULE 1 : IF x IS lo THEN y IS a;
    RULE 2 : IF x IS mid THEN y IS b;
    RULE 3 : IF x IS hi THEN y IS c;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


def test_fcl_singletons_of_one_value_accumulate_by_accu() -> None:
    fls = loads(FCL, "fcl")
    assert fls.aggregation is Aggregation.MAXIMUM
    assert float(fls(1.0)) == pytest.approx((10 * 0.75 + 20 * 0.25) / (0.75 + 0.25), rel=1e-15)
    summed = loads(FCL.replace("ACCU : MAX;", "ACCU : NSUM;"), "fcl")
    assert summed.aggregation is None
    alone = loads(FCL.replace("TERM b := 10;", "TERM b := 11;"), "fcl")
    assert alone.aggregation is None  # no value shared: a plain weighted average
    x = np.linspace(0, 4, 9)
    np.testing.assert_array_equal(alone(x), T1Sugeno(
        inputs=alone.inputs, rules=alone.rules, tnorm=alone.tnorm, name="f")(x))


@pytest.mark.parametrize("fmt", ["fis", "fll", "fml", "toml", "t2fis"])
def test_writers_refuse_the_aggregation(fmt: str) -> None:
    with pytest.raises(UnsupportedFeatureError, match="aggregation"):
        dumps(loads(FCL, "fcl"), fmt)


def test_c_generation_refuses_the_aggregation() -> None:
    from it2track.codegen.fixedpoint import check_fixed_supported
    from it2track.codegen.generate import check_supported

    fls = T1Sugeno(inputs=[Input("x", (0, 4), [("lo", Triangle(0, 0, 4)),
                                               ("hi", Triangle(0, 4, 4))])],
                   rules=[Rule(["lo"], 1.0), Rule(["hi"], 1.0)],
                   aggregation=Aggregation.MAXIMUM)
    with pytest.raises(UnsupportedFeatureError, match="consequent value"):
        check_supported(fls)
    with pytest.raises(UnsupportedFeatureError, match="consequent value"):
        check_fixed_supported(fls, "exhaustive")
    check_supported(T1Sugeno(inputs=fls.inputs, rules=fls.rules))  # without it: generated

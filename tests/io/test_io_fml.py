"""IEEE 1855 FML: a hand-written file evaluates to hand-computed values, round trips are bit
exact, hostile XML is refused before anything is expanded, and what FML cannot say is refused
naming the line or the feature."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from io_systems import random_system

from it2track.fuzzy import (
    Aggregation,
    Defuzzifier,
    Discrete,
    GaussianProduct,
    HybridSystem,
    Input,
    Output,
    Ramp,
    Rule,
    Sampling,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Triangle,
)
from it2track.io import FisFormatError, UnsupportedFeatureError, dumps, loads

DATA = Path(__file__).parent / "data"
TIPPER = (DATA / "tipper.fml").read_text()


def error_of(text: str) -> FisFormatError:
    with pytest.raises(FisFormatError) as info:
        loads(text, "fml", path="t.fml")
    return info.value


def line_with(text: str, needle: str) -> int:
    return next(i for i, line in enumerate(text.split("\n"), 1) if needle in line)


def test_hand_computed_tipper() -> None:
    fls = loads(TIPPER, "fml")
    assert isinstance(fls, T1Sugeno) and fls.name == "tipper" and fls.on_zero_firing == 15.0
    assert fls.inputs[0].sets[0].upper == Ramp(5.0, 0.0)  # leftLinear: 1 up to 0, 0 from 5
    # at (food, service) = (8, 4): rancid 0, poor is complemented: 1 - 0.4 = 0.6;
    # r1 = max(0, 0.6) * 0.5 = 0.3 (cheap 5); r2 = delicious 0.6 * good 0.8 = 0.48
    # (rising: 10 + 1 * 8 + 0.5 * 4 = 20, the constant first as JFML reads it)
    expected = (0.3 * 5 + 0.48 * 20) / (0.3 + 0.48)
    assert float(fls(8.0, 4.0)) == pytest.approx(expected, rel=1e-15)
    assert fls.rules[0].negated == (False, True) and fls.rules[1].connective.value == "and"
    assert fls.tnorm is TNorm.PRODUCT and fls.snorm is SNorm.MAXIMUM


def test_round_trips_are_bit_exact_and_the_text_a_fixed_point() -> None:
    for seed in range(3):
        system = random_system(seed, type1=True)
        text = dumps(system, "fml")
        again = loads(text, "fml")
        assert again.rules == system.rules  # shoulders come back as trapezoids widened to the
        points = [np.linspace(*i.universe, 57) for i in system.inputs]  # universe's end
        assert np.array_equal(again(*points), system(*points))
        assert dumps(again, "fml") == text
    x = np.linspace(-1.0, 1.0, 41)
    out = Output("y", (0.0, 1.0), [("lo", Triangle(0.0, 0.0, 0.7)),
                                   ("hi", Discrete([(0.2, 0.0), (0.5, 0.4), (1.0, 1.0)]))])
    inp = Input("x", (-1.0, 1.0), [("n", GaussianProduct(-1.0, 0.3, -0.2, 0.3)),
                                   ("p", GaussianProduct(0.4, 0.3, 1.0, 0.3))])
    mamdani = T1Mamdani(inputs=[inp], outputs=[out], rules=[Rule(["n"], "lo"),
                                                              Rule(["p"], "hi", weight=0.25)],
                        tnorm=TNorm.EINSTEIN_PRODUCT, snorm=SNorm.EINSTEIN_SUM,
                        aggregation=Aggregation.PROBOR, defuzzifier=Defuzzifier.BISECTOR,
                        on_zero_firing=0.5)
    again = loads(dumps(mamdani, "fml"), "fml")
    assert again == mamdani and np.array_equal(again(x), mamdani(x))
    sugeno = T1Sugeno(inputs=[inp], rules=[Rule(["n"], -1.0), Rule(["p"], 2.0)], outputs=("s",))
    hybrid = HybridSystem((mamdani, sugeno), name="both")
    again = loads(dumps(hybrid, "fml"), "fml")
    assert isinstance(again, HybridSystem)
    assert np.array_equal(again(x), hybrid(x))
    # no value where no rule fires is written as xs:float's NaN
    assert loads(dumps(dataclasses.replace(sugeno, on_zero_firing=None), "fml"),
                 "fml").on_zero_firing is None


def test_the_writer_refuses_what_fml_cannot_say() -> None:
    with pytest.raises(UnsupportedFeatureError, match="type-1"):
        dumps(random_system(1), "fml")
    base = loads(TIPPER, "fml")
    with pytest.raises(UnsupportedFeatureError, match="complements terms, not"):
        dumps(base, "fml")  # rule 1 names a complemented term: a NOT
    x = Input("x", (0.0, 1.0), [("a", Triangle(0.0, 0.5, 1.0, 0.5))])
    with pytest.raises(UnsupportedFeatureError, match="height"):
        dumps(T1Sugeno(inputs=[x], rules=[Rule(["a"], 1.0)]), "fml")
    m = T1Mamdani(inputs=[Input("x", (0.0, 1.0), [("a", Triangle(0.0, 0.5, 1.0))])],
                  outputs=[Output("y", (0.0, 1.0), [("b", Triangle(0.0, 0.5, 1.0))])],
                  rules=[Rule(["a"], "b")])
    with pytest.raises(UnsupportedFeatureError, match="samples 1001"):
        dumps(dataclasses.replace(m, resolution=1001), "fml")
    with pytest.raises(UnsupportedFeatureError, match="midpoints"):
        dumps(dataclasses.replace(m, sampling=Sampling.MIDPOINTS), "fml")


BILLION_LAUGHS = """<?xml version="1.0"?>
<!DOCTYPE lolz [
 <!ENTITY lol "lol">
 <!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
]>
<fuzzySystem name="&lol3;"/>
"""
EXTERNAL = """<?xml version="1.0"?>
<!DOCTYPE foo [<!ENTITY xxe SYSTEM "file:///etc/passwd">]>
<fuzzySystem name="&xxe;"/>
"""


@pytest.mark.parametrize("text", [BILLION_LAUGHS, EXTERNAL], ids=["entities", "external"])
def test_hostile_xml_is_refused_before_expansion(text: str) -> None:
    err = error_of(text)
    assert err.line == 2 and "document type declaration" in err.message


def test_depth_is_bounded() -> None:
    deep = "<fuzzySystem name='x'>" + "<a>" * 100 + "</a>" * 100 + "</fuzzySystem>"
    assert "nested deeper than 64" in error_of(deep).message


MALFORMED = [
    ('<tskValue>5.0</tskValue>', '<tskValue>5.0.0</tskValue>', "<tskValue>5.0.0",
     "bad number '5.0.0'"),
    ('<tskValue>5.0</tskValue>', '<tskValue>inf</tskValue>', "<tskValue>inf", "bad number"),
    ('param2="5.0"/>', 'param2="5.0" />\n<gaussianShape param1="1" param2="1"/>',
     'name="rancid"', "needs one shape"),
    ('<leftLinearShape param1="0.0" param2="5.0"/>', '<leftLinearShape param1="0.0"/>',
     "<leftLinearShape", "needs the attribute 'param2'"),
    ('<tskVariable name="tip"', '<tskVariable nYme="tip"', "<tskVariable",
     "needs the attribute 'name'"),  # found by the fuzzer
    ('<triangularShape param1="0.0"', '<triangularShape param1="9.0"', "<triangularShape",
     "a <= b <= c"),
    ('<triangularShape param1="0.0" param2="5.0" param3="10.0"/>',
     '<triangularShape param1="2.0" param2="2.0" param3="10.0"/>', "<triangularShape",
     "left shoulder at x=2"),
    ('<tskRule name="r2" connector="AND">', '<tskRule name="r2" connector="xor">', 'name="r2"',
     "connector='xor'"),
    ('<tskRule name="r2" connector="AND">', '<tskRule name="r2" connector="AND" andMethod="MIN">',
     'name="r2"', "differs from its rule base's"),
    ('andMethod="PROD"', 'andMethod="LUKA"', "<tskRuleBase", "andMethod='LUKA'"),
    ('<clause><variable>food</variable><term>delicious</term></clause>',
     '<clause modifier="very"><variable>food</variable><term>delicious</term></clause>',
     'modifier="very"', "the modifier 'very' (a hedge)"),
    ('<term>delicious</term>', '<term>tasty</term>', "<term>tasty", "no term 'tasty'"),
    ('order="1">', 'order="2">', 'order="2"', "order='2'"),
    ('combination="WA"', 'combination="MEAN"', "<tskVariable", "combination must be WA"),
    ('<fuzzyVariable name="service"', '<fuzzyVariable  name="food"', 'Variable  name',
     "variable 'food' declared twice"),
    ('domainright="10.0" type="input">\n      <fuzzyTerm name="poor"',
     'domainright="-1.0" type="input">\n      <fuzzyTerm name="poor"', 'domainright="-1.0"',
     "domainleft=0 must be below"),
    ("</fuzzySystem>", "", "", "malformed XML"),
]


@pytest.mark.parametrize(("old", "new", "needle", "problem"), MALFORMED,
                         ids=[m[3] for m in MALFORMED])
def test_malformed_fml_names_the_line(old: str, new: str, needle: str, problem: str) -> None:
    assert old in TIPPER, old
    text = TIPPER.replace(old, new, 1)
    err = error_of(text)
    assert problem in err.message, err
    if needle:
        assert err.line == line_with(text, needle), err
        assert str(err).startswith(f"t.fml:{err.line}: ")


def test_unsupported_rule_bases_and_variables_name_themselves() -> None:
    text = TIPPER.replace("tskRuleBase", "anYaRuleBase")
    assert "<anYaRuleBase> is not supported" in error_of(text).message
    text = TIPPER.replace("<tskVariable", "<tsukamotoVariable").replace("</tskVariable",
                                                                       "</tsukamotoVariable")
    assert "<tsukamotoVariable> is not supported" in error_of(text).message
    assert "expected IEEE 1855's <fuzzySystem>" in error_of("<fis/>").message


def test_a_leftgaussian_is_flat_to_the_end_of_the_domain() -> None:
    text = TIPPER.replace('<leftLinearShape param1="0.0" param2="5.0"/>',
                          '<leftGaussianShape param1="3.0" param2="2.0"/>')
    fls = loads(text, "fml")
    mf = fls.inputs[0].sets[0].upper
    assert float(mf(0.0)) == 1.0 and float(mf(3.0)) == 1.0
    assert float(mf(5.0)) == math.exp(-0.5)

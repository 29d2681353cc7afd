"""fuzzylite's chained Function -- a Takagi-Sugeno term reading an output -- in its three
formats: read where the output is declared before the term's (its value at this evaluation,
as committed), refused where it is the term's own or declared after (fuzzylite's value of the
previous evaluation), naming the line, the term and the output.

The values are pyfuzzylite 8.0.6's ``Engine.process`` of ``CHAIN`` (rows processed in order
from a restart), and by hand (``tests/fuzzy/test_chain.py``).
"""

from __future__ import annotations

import contextlib
import math

import numpy as np
import pytest

from it2track.fuzzy import T1Sugeno, ZeroFiringError
from it2track.fuzzy.sequence import chain_outputs
from it2track.io import FisFormatError, loads

CHAIN = """Engine: chain
InputVariable: u
  range: 0 10
  term: lo Triangle 0 0 10
  term: hi Triangle 0 10 10
OutputVariable: a
  range: -10 10
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  lock-previous: true
  term: six Constant 6
OutputVariable: b
  range: -100 100
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  lock-previous: false
  term: one Constant 1
  term: tenfold Function a*10 - u
  term: plus Function a + u
OutputVariable: c
  range: -100 100
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  lock-previous: false
  term: diff Function b - a
RuleBlock:
  conjunction: none
  disjunction: none
  implication: none
  activation: General
  rule: if u is hi then a is six
  rule: if u is lo then b is plus
  rule: if u is hi then b is tenfold
  rule: if u is hi then c is diff
"""

CHAIN_FIS = """[System]
Name='chain'
Type='sugeno'
NumInputs=1
NumOutputs=3
NumRules=4
AndMethod='min'
OrMethod='max'
ImpMethod='min'
AggMethod='max'
DefuzzMethod='wtaver'

[Input1]
Name='u'
Range=[0 10]
NumMFs=2
MF1='lo':'trimf',[0 0 10]
MF2='hi':'trimf',[0 10 10]

[Output1]
Name='a'
Range=[-10 10]
Default=nan
LockPrevious=1
NumMFs=1
MF1='six':'constant',[6]

[Output2]
Name='b'
Range=[-100 100]
Default=nan
LockPrevious=0
NumMFs=3
MF1='one':'constant',[1]
MF2='tenfold':'function',[a*10 - u]
MF3='plus':'function',[a + u]

[Output3]
Name='c'
Range=[-100 100]
Default=nan
LockPrevious=0
NumMFs=1
MF1='diff':'function',[b - a]

[Rules]
2, 1 0 0 (1) : 1
1, 0 3 0 (1) : 1
2, 0 2 0 (1) : 1
2, 0 0 1 (1) : 1
"""

CHAIN_FCL = """FUNCTION_BLOCK chain
VAR_INPUT
  u: REAL;
END_VAR
VAR_OUTPUT
  a: REAL;
  b: REAL;
  c: REAL;
END_VAR
FUZZIFY u
  RANGE := (0 .. 10);
  TERM lo := Triangle 0 0 10;
  TERM hi := Triangle 0 10 10;
END_FUZZIFY
DEFUZZIFY a
  RANGE := (-10 .. 10);
  TERM six := 6;
  METHOD : COGS;
  DEFAULT := nan | NC;
END_DEFUZZIFY
DEFUZZIFY b
  RANGE := (-100 .. 100);
  TERM one := 1;
  TERM tenfold := Function a*10 - u;
  TERM plus := Function a + u;
  METHOD : COGS;
  DEFAULT := nan;
END_DEFUZZIFY
DEFUZZIFY c
  RANGE := (-100 .. 100);
  TERM diff := Function b - a;
  METHOD : COGS;
  DEFAULT := nan;
END_DEFUZZIFY
RULEBLOCK
  RULE 1 : if u is hi then a is six
  RULE 2 : if u is lo then b is plus
  RULE 3 : if u is hi then b is tenfold
  RULE 4 : if u is hi then c is diff
END_RULEBLOCK
END_FUNCTION_BLOCK
"""

TEXTS = {"fll": CHAIN, "fis": CHAIN_FIS, "fcl": CHAIN_FCL}
#: pyfuzzylite, the rows in order from a restart: a keeps 6 at u = 0 and b reads it
ROWS = np.array([[2.5], [0.0], [0.0], [5.0], [0.0]])
IN_ORDER = [[6.0, 20.75, 14.75], [6.0, 6.0, math.nan], [6.0, 6.0, math.nan],
            [6.0, 33.0, 27.0], [6.0, 6.0, math.nan]]


@pytest.mark.parametrize("fmt", TEXTS)
def test_each_format_reads_a_chained_function_as_fuzzylite_evaluates_it(fmt: str) -> None:
    fls = loads(TEXTS[fmt], fmt)
    assert isinstance(fls, T1Sugeno) and fls.output_names == ("a", "b", "c")
    assert fls.lock_previous == (True, False, False) and fls.on_zero_firing is None
    np.testing.assert_array_equal(chain_outputs(fls, ROWS, sequence=True), IN_ORDER)
    # each row alone (fuzzylite after a restart): nothing at u = 0, a has no previous value
    alone = chain_outputs(fls, ROWS)
    assert np.isnan(alone[[1, 2, 4]]).all()
    np.testing.assert_array_equal(alone[[0, 3]], [IN_ORDER[0], IN_ORDER[3]])
    assert fls(2.5).tolist() == [6.0, 20.75, 14.75]
    with pytest.raises(ZeroFiringError):
        fls.evaluate_sequence(ROWS)  # c has no value at u = 0
    y, _ = fls.evaluate_sequence(ROWS[:1])
    assert y.tolist() == [IN_ORDER[0]]


@pytest.mark.parametrize(("fmt", "old", "new", "where", "message"), [
    ("fll", "term: diff Function b - a", "term: diff Function b - c", "term: diff",
     "term 'diff': Function 'b - c' reads its own output 'c' (fuzzylite's value of the "
     "previous evaluation, NaN after a restart): it2track reads only the outputs declared "
     "before this one ('a', 'b')"),
    ("fll", "term: plus Function a + u", "term: plus Function c + u", "term: plus",
     "term 'plus': Function 'c + u' reads the output 'c', which fuzzylite defuzzifies after "
     "'b' (its value of the previous evaluation, NaN after a restart): it2track reads only "
     "the outputs declared before this one ('a')"),
    ("fis", "[a + u]", "[a + c]", "MF3='plus'",
     "MF 'plus': function 'a + c' reads the output 'c', which fuzzylite defuzzifies after "
     "'b' (its value of the previous evaluation, NaN after a restart): it2track reads only "
     "the outputs declared before this one ('a')"),
    ("fcl", "Function a + u;", "Function a + c;", "TERM plus",
     "term 'plus': Function 'a + c' reads the output 'c', which fuzzylite defuzzifies after "
     "'b' (its value of the previous evaluation, NaN after a restart): it2track reads only "
     "the outputs declared before this one ('a')"),
    # jFuzzyLogic's FUNCTION (its grammar): it defuzzifies in another order, not read
    ("fcl", "Function a + u;", "FUNCTION a + u;", "TERM plus",
     "term 'plus': FUNCTION 'a + u' reads the output 'a': it2track reads a jFuzzyLogic "
     "FUNCTION of the inputs only (fuzzylite's chained Function, in its own grammar, reads "
     "the outputs declared before its own)"),
])
def test_a_read_of_a_later_or_its_own_output_is_refused_naming_it(
        fmt: str, old: str, new: str, where: str, message: str) -> None:
    text = TEXTS[fmt].replace(old, new)
    assert text != TEXTS[fmt]
    with pytest.raises(FisFormatError) as info:
        loads(text, fmt, path=f"chain.{fmt}")
    assert info.value.message == message
    assert info.value.line == next(i for i, line in enumerate(text.split("\n"), 1)
                                   if where in line)
    assert str(info.value).startswith(f"chain.{fmt}:{info.value.line}")


def test_a_function_reading_an_output_of_another_part_is_refused_naming_it() -> None:
    # a Mamdani output and a Takagi-Sugeno one are two systems (a HybridSystem) in it2track;
    # fuzzylite defuzzifies m first and s reads it (pyfuzzylite at u = 5: m 5, s 10)
    hybrid = CHAIN.split("OutputVariable: a")[0] + """OutputVariable: m
  range: 0 10
  aggregation: Maximum
  defuzzifier: Centroid 100
  default: nan
  term: small Triangle 0 0 10
  term: big Triangle 0 10 10
OutputVariable: s
  range: -100 100
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  term: twice Function 2*m
RuleBlock:
  conjunction: none
  disjunction: none
  implication: Minimum
  activation: General
  rule: if u is lo then m is small
  rule: if u is hi then m is big
  rule: if u is hi then s is twice
"""
    with pytest.raises(FisFormatError) as info:
        loads(hybrid, "fll", path="hybrid.fll")
    assert info.value.line == hybrid.split("\n").index("  term: twice Function 2*m") + 1
    assert info.value.message == ("term 'twice': Function '2*m' reads the output 'm' "
                                  "(mamdani), which it2track evaluates apart from 's': it "
                                  "chains formulas among Takagi-Sugeno outputs declared one "
                                  "after another")
    # s reading the input only: the file loads, a HybridSystem of the two
    plain = hybrid.replace("twice Function 2*m", "twice Function 2*u")
    assert loads(plain, "fll").output_names == ("m", "s")


@pytest.mark.parametrize(("fmt", "old", "new", "message"), [
    ("fis", "MF1='six':'constant',[6]", "MF1='six':'rampmf',[0 10]",
     "MF 'tenfold': function 'a*10 - u' reads the output 'a' (tsukamoto), which it2track "
     "evaluates apart from 'b': it chains formulas among Takagi-Sugeno outputs declared one "
     "after another"),
    ("fcl", "TERM six := 6;\n  METHOD : COGS;", "TERM six := Triangle 0 5 10;\n  METHOD : COG;",
     "term 'tenfold': Function 'a * 10 - u' reads the output 'a', of another kind, which "
     "it2track evaluates apart from 'b': it chains formulas among Takagi-Sugeno outputs "
     "declared one after another"),
])
def test_fis_and_fcl_refuse_a_function_reading_another_parts_output(
        fmt: str, old: str, new: str, message: str) -> None:
    text = TEXTS[fmt].replace(old, new)
    assert text != TEXTS[fmt]
    with pytest.raises(FisFormatError) as info:
        with pytest.warns(Warning) if fmt == "fis" else contextlib.nullcontext():
            loads(text, fmt, path=f"chain.{fmt}")
    assert info.value.message == message
    assert info.value.line == next(i for i, line in enumerate(text.split("\n"), 1)
                                   if "tenfold" in line)

"""fuzzylite's ``lock-previous`` / ``LockPrevious`` and FCL's ``DEFAULT := ... NC`` read as the
system's ``lock_previous`` (per output), written back to ``.fll`` and refused by the formats
that cannot carry it; fuzzylite's ``x is any`` (no term) read by the ``.fll``, FCL and fuzzylite
``.fis`` readers."""

from __future__ import annotations

import numpy as np
import pytest

from it2track.fuzzy import ZeroFiringError
from it2track.io import FisFormatError, UnsupportedFeatureError, dumps, loads

FLL = """Engine: gaps
InputVariable: x
  enabled: true
  range: 0.000 10.000
  lock-range: false
  term: a Triangle 0.000 1.000 2.000
  term: b Triangle 4.000 5.000 6.000
OutputVariable: p
  enabled: true
  range: 0.000 10.000
  lock-range: false
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  lock-previous: true
  term: one Constant 1.000
  term: five Constant 5.000
OutputVariable: q
  enabled: true
  range: 0.000 10.000
  lock-range: false
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  lock-previous: false
  term: two Constant 2.000
RuleBlock: rules
  enabled: true
  conjunction: none
  disjunction: none
  implication: none
  activation: General
  rule: if x is a then p is one
  rule: if x is b then p is five
  rule: if x is any then q is two
"""

FCL = """FUNCTION_BLOCK gaps
VAR_INPUT
  x : REAL;
END_VAR
VAR_OUTPUT
  p : REAL;
END_VAR
FUZZIFY x
  RANGE := (0 .. 10);
  TERM a := Triangle 0 1 2;
  TERM b := Triangle 4 5 6;
END_FUZZIFY
DEFUZZIFY p
  RANGE := (0 .. 10);
  TERM one := 1;
  TERM five := 5;
  METHOD : COGS;
  DEFAULT := nan | NC;
END_DEFUZZIFY
RULEBLOCK rules
  RULE 1 : IF x IS a THEN p IS one;
  RULE 2 : IF x IS b THEN p IS five;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""

X = np.array([[1.0], [3.0], [5.0], [8.0], [0.5], [9.0]])


def test_fll_lock_previous_per_output_read_evaluated_in_order_and_written_back() -> None:
    fls = loads(FLL, "fll")
    assert fls.lock_previous == (True, False)
    y, state = fls.evaluate_sequence(X)
    assert y[:, 0].tolist() == [1.0, 1.0, 5.0, 5.0, 1.0, 1.0]
    assert y[:, 1].tolist() == [2.0] * 6  # 'x is any' fires everywhere
    assert state.tolist() == [1.0, 2.0]
    text = dumps(fls, "fll")
    assert text.count("lock-previous: true") == 1 and text.count("lock-previous: false") == 1
    assert loads(text, "fll") == fls
    with pytest.raises(ZeroFiringError):  # __call__ is stateless: nothing fires at 3
        fls(3.0)


@pytest.mark.parametrize(("default", "zero"), [("nan | NC", None), ("NC", None),
                                               ("0.5 | NC", 0.5)])
def test_fcl_nc_is_lock_previous(default: str, zero: float | None) -> None:
    fls = loads(FCL.replace("nan | NC", default), "fcl")
    assert fls.lock_previous is True and fls.on_zero_firing == zero
    y, _ = fls.evaluate_sequence(X[1:] if zero is not None else X)
    if zero is None:
        assert y.tolist() == [1.0, 1.0, 5.0, 5.0, 1.0, 1.0]
    else:  # nothing fired yet at 3: the default
        assert y.tolist() == [0.5, 5.0, 5.0, 1.0, 1.0]
    plain = loads(FCL.replace("DEFAULT := nan | NC;", "DEFAULT := nan;"), "fcl")
    assert plain.lock_previous is False


def test_fis_lock_previous_and_fuzzylites_any() -> None:
    fis = """[System]
Name='gaps'
Type='sugeno'
NumInputs=1
NumOutputs=2
NumRules=3
AndMethod=''
DefuzzMethod='wtaver'

[Input1]
Name='x'
Range=[0 10]
NumMFs=2
MF1='a':'trimf',[0 1 2]
MF2='b':'trimf',[4 5 6]

[Output1]
Name='p'
Range=[0 10]
Default=nan
LockPrevious=1
LockRange=0
NumMFs=2
MF1='one':'constant',[1]
MF2='five':'constant',[5]

[Output2]
Name='q'
Range=[0 10]
Default=nan
LockPrevious=0
LockRange=0
NumMFs=1
MF1='two':'constant',[2]

[Rules]
1 , 1 0 (1) : 1
2 , 2 0 (1) : 1
0.99 , 0 1 (1) : 1
"""
    fls = loads(fis, "fis")
    assert fls.lock_previous == (True, False)
    y, _ = fls.evaluate_sequence(X)
    assert y.tolist() == loads(FLL, "fll").evaluate_sequence(X)[0].tolist()
    # without fuzzylite's keys (or its header) a fraction is Octave's hedge: 0.99 is refused
    octave = fis.replace("LockPrevious=1\nLockRange=0\n", "").replace(
        "LockPrevious=0\nLockRange=0\n", "")
    with pytest.raises(FisFormatError, match=r"rule index 0\.99 has a fraction"):
        loads(octave, "fis")


def test_fcl_any_names_no_term() -> None:
    text = FCL.replace("RULE 2 : IF x IS b THEN p IS five;",
                       "RULE 2 : IF x IS b THEN p IS five;\n  RULE 3 : IF x IS any THEN p IS one;")
    fls = loads(text, "fcl")
    # rule 3 fires 1 everywhere: at 3 (nothing else fires) p is 1, at 5 (1 + 5) / 2
    assert fls(3.0) == 1.0 and fls(5.0) == 3.0


@pytest.mark.parametrize("fmt", ["fis", "t2fis", "toml", "fml"])
def test_formats_without_lock_previous_refuse_it(fmt: str) -> None:
    fls = loads(FCL, "fcl")
    with pytest.raises(UnsupportedFeatureError, match="lock_previous"):
        dumps(fls, fmt)

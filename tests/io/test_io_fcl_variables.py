"""FCL terms whose parameters are other variables (jFuzzyLogic's membership functions with
variables, io/_fclvars.py): jFuzzyLogic's recorded memberships of on_line_variable.fcl, closed
forms per sample, the universes, and each refusal naming its line and term."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from it2track.fuzzy import Gaussian, Parametric, Ref
from it2track.io import FisFormatError, load, loads

JFL = Path(__file__).parents[1] / "conformance" / "files" / "jfuzzylogic"

#: on_line_variable.fcl has no output (jFuzzyLogic's tests read the memberships): one
#: singleton rule per term makes each rule's firing that term's membership
_PROBE = """
VAR_OUTPUT
    y : REAL;
END_VAR
DEFUZZIFY y
    TERM p := 1; TERM g := 2; TERM e := 3;
    METHOD : COGS;
    DEFAULT := 0;
END_DEFUZZIFY
RULEBLOCK probe
    RULE 1 : IF inVar IS poor THEN y IS p;
    RULE 2 : IF inVar IS good THEN y IS g;
    RULE 3 : IF inVar IS excellent THEN y IS e;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


@pytest.mark.parametrize("i", [4, 5, 6])
def test_jfuzzylogic_recorded_memberships_of_on_line_variable(i: int) -> None:
    # jFuzzyLogic's TestCaseJfuzzy.testMembershipFunctionOnLine{4,5,6}: inputZeroMin, Med, Max
    # = i - 1, i, i + 1; the file's memberships * 100 rounded (Java's Math.round)
    text = (JFL / "tests" / "on_line_variable.fcl").read_text()
    system = loads(text.replace("END_FUNCTION_BLOCK", _PROBE), "fcl")
    assert [inp.name for inp in system.inputs] == ["inputZeroMin", "inputZeroMed",
                                                  "inputZeroMax", "inVar"]
    assert system.inputs[3].universe == (0.0, 10.0)  # poor's first x, excellent's last
    assert all(inp.universe == (0.0, 10.0) for inp in system.inputs[:3])
    table = np.loadtxt(JFL / "tests" / f"on_line_variable_{i}.txt", skiprows=1)
    v = table[:, 0] / 100.0
    _, upper = system.firing(np.full_like(v, i - 1.0), np.full_like(v, float(i)),
                             np.full_like(v, i + 1.0), v)
    got = np.floor(np.asarray(upper) * 100.0 + 0.5)
    np.testing.assert_array_equal(got, table[:, 1:])
    assert (table[:, 2] > 0).sum() == 19  # the variable triangle is met, not only its feet


_SYSTEM = """FUNCTION_BLOCK f
VAR_INPUT
    v : REAL;
    lo : REAL;
    mid : REAL; RANGE := (2 .. 6);
END_VAR
VAR_OUTPUT
    y : REAL;
END_VAR
FUZZIFY v
    TERM good := (lo, 0) (mid, 1) (8, 0);
    TERM all := (0, 1) (8, 1);
END_FUZZIFY
DEFUZZIFY y
    TERM ten := 10; TERM zero := 0;
    METHOD : COGS;
END_DEFUZZIFY
RULEBLOCK r
    RULE 1 : IF v IS good THEN y IS ten;
    RULE 2 : IF v IS all THEN y IS zero;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


def test_a_rule_on_a_variable_term_in_closed_form() -> None:
    system = loads(_SYSTEM, "fcl", path="v.fcl")
    good = system.inputs[0].sets[0].upper
    assert good == Parametric("points", (Ref(1, "lo"), 0.0, Ref(2, "mid"), 1.0, 8.0, 0.0),
                              "good")
    # lo without terms: the universe of v, which reads it (its fixed ends 0 and 8); mid: RANGE
    assert [inp.universe for inp in system.inputs] == [(0.0, 8.0), (0.0, 8.0), (2.0, 6.0)]
    # y = 10 g / (g + 1): g = 1/4 at v = 1 (lo 0, mid 4) -> 2; g = 1/2 at v = 6 -> 10/3;
    # mid clipped to its RANGE: 9 is 6, so at v = 6 g = 1 -> 5
    x = np.array([[1.0, 0.0, 4.0], [6.0, 0.0, 4.0], [6.0, 0.0, 9.0], [0.5, 1.0, 4.0]])
    got = system.evaluate(x)
    assert got[0] == 2.0 and got[2] == 5.0 and got[3] == 0.0
    assert math.isclose(got[1], 10.0 / 3.0, rel_tol=1e-15)
    assert [system(*row) for row in x.tolist()] == got.tolist()
    # hedged: very good = g^2 = 1/16 at v = 1 -> 10 / 17
    very = loads(_SYSTEM.replace("IF v IS good", "IF v IS VERY good"), "fcl")
    assert math.isclose(very(1.0, 0.0, 4.0), 10.0 / 17.0, rel_tol=1e-15)
    assert very.evaluate(x[:1]).tolist() == [very(1.0, 0.0, 4.0)]


def test_cinthia_reads_gauss_with_variables() -> None:
    system = load(JFL / "fcl" / "cinthia.fcl")
    names = [inp.name for inp in system.inputs]
    assert names == ["meanGood", "stdGood", "inVar"]
    sets = {s.name: s.upper for s in system.inputs[2].sets}
    assert sets["good"] == Parametric("gauss", (Ref(0, "meanGood"), Ref(1, "stdGood")), "good")
    assert sets["poor"] == Gaussian(1.0, 2.0)
    # inVar: poor 1 -+ 4 * 2 and excellent 9 -+ 4 * 1; meanGood and stdGood: inVar's
    assert [inp.universe for inp in system.inputs] == [(-7.0, 13.0)] * 3
    assert system(2.0, 1.0, 3.0) == 3.0 * 3.5  # its one rule: poor -> FUNCTION inVar * 3.5


def _gauss(params: str) -> str:
    """good := GAUSS params (reading mid), lo read by the term all"""
    return _SYSTEM.replace("(lo, 0) (mid, 1) (8, 0)", params).replace("(0, 1) (8, 1)",
                                                                    "(lo, 1) (8, 1)")


def _refused(text: str) -> FisFormatError:
    with pytest.raises(FisFormatError) as info:
        loads(text, "fcl", path="w.fcl")
    return info.value


def test_refusals_name_the_line_and_the_term() -> None:
    err = _refused(_SYSTEM.replace("TERM ten := 10;", "TERM ten := (lo, 0) (8, 1);")
                   .replace("METHOD : COGS;", "METHOD : COG;"))
    assert (err.path, err.line) == ("w.fcl", 15)
    assert err.message == ("term 'ten' of 'y': an output term with values given by variables "
                           "(lo); it2track reads variable parameters on input terms only (an "
                           "output's sets are fixed when the system is built)")
    err = _refused(_SYSTEM.replace("(lo, 0) (mid, 1)", "(y, 0) (mid, 1)"))
    assert (err.line, err.message) == (11, "term 'good' of 'v': parameter 'y' is an output; "
                                       "variable parameters read inputs only")
    err = _refused(_SYSTEM.replace("(lo, 0) (mid, 1)", "(low, 0) (mid, 1)"))
    assert (err.line, err.message) == (11, "term 'good' of 'v': parameter 'low' is not a "
                                       "declared variable")
    err = _refused(_SYSTEM.replace("(lo, 0) (mid, 1) (8, 0)", "TRIAN lo mid 8"))
    assert (err.line, err.message) == (11, "term 'good' of 'v': TRIAN with values given by "
                                       "variables (lo, mid); it2track reads variable "
                                       "parameters in point lists and GAUSS")
    err = _refused(_SYSTEM.replace("(0, 1) (8, 1)", "(lo, 1) (mid, 1)")
                   .replace("(mid, 1) (8, 0)", "(mid, 1) (mid, 0)"))
    assert (err.line, err.message) == (10, "'v': give a RANGE (its terms' ends are given by "
                                       "variables, from which no universe can be estimated)")
    err = _refused(_SYSTEM.replace("(mid, 1)", "(mid, 1.5)"))
    assert (err.line, err.message) == (11, "term 'good': memberships must lie in [0, 1]")
    err = _refused(_SYSTEM.replace("(lo, 0) (mid, 1) (8, 0)", "(lo, 0) (mid, 1) (9, 1) (8, 0)"))
    assert (err.line, err.message) == (11, "term 'good': the points must have increasing x")
    err = _refused(_gauss("GAUSS mid 0"))
    assert (err.line, err.message) == (11, "term 'good': GAUSS sigma 0.0 must be > 0")
    err = _refused(_gauss("GAUSS mid 1 2"))
    assert (err.line, err.message) == (11, "term 'good': GAUSS needs 2 parameters, got 3")
    err = _refused(_gauss("GAUSS mid -lo"))
    assert (err.line, err.message) == (11, "term 'good': unexpected 'lo' in the parameters")
    # an input no term reads and without terms is still refused as before
    err = _refused(_SYSTEM.replace("(lo, 0)", "(0, 0)"))
    assert (err.line, err.message) == (4, "variable 'lo' has no FUZZIFY block")


def test_parameters_without_a_valid_shape_are_named_at_evaluation() -> None:
    system = loads(_SYSTEM.replace("(lo, 0) (mid, 1) (8, 0)", "GAUSS mid lo"), "fcl")
    assert system(3.0, 1.0, 3.0) == 10.0 / 2.0  # g = 1 at the mean, all = 1
    with pytest.raises(ValueError, match=r"'good': lo = 0\.0 at sample 0 must be > 0"):
        system(3.0, 0.0, 3.0)

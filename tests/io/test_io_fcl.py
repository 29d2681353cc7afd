"""FCL (IEC 61131-7) reading: hand-written fixtures evaluate to hand-computed values, and
malformed or unsupported text gives ``file:line``."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from it2track.fuzzy import Aggregation, Defuzzifier, Implication, SNorm, T1Mamdani, T1Sugeno, TNorm
from it2track.io import FisFormatError, UnsupportedFeatureError, dumps, load, loads

DATA = Path(__file__).parent / "data"


def test_singleton_fixture_by_hand() -> None:
    fls = load(DATA / "heater.fcl")
    assert isinstance(fls, T1Sugeno) and fls.name == "heater"
    assert fls.inputs[0].universe == (0.0, 40.0)
    assert fls([15.0, 25.0, 40.0]).tolist() == pytest.approx([75.0, 25.0, 0.0], abs=1e-12)
    assert fls.on_zero_firing == 0.0
    assert fls.rules[1].weight == 0.5


def test_mamdani_fixture_by_hand() -> None:
    fls = load(DATA / "valve.fcl")
    assert isinstance(fls, T1Mamdani)
    assert (fls.tnorm, fls.snorm, fls.implication, fls.aggregation, fls.defuzzifier) == (
        TNorm.PRODUCT, SNorm.PROBOR, Implication.MINIMUM, Aggregation.MAXIMUM,
        Defuzzifier.CENTROID)
    # firing at (2, 6), see the fixture: 0.88 (low), 0.12 and 0.3 (high); grid y = k / 100
    # (jFuzzyLogic's 1000 intervals of the RANGE)
    assert fls.resolution == 1001
    f_low, f_high = Fraction(88, 100), max(Fraction(12, 100), Fraction(3, 10))
    num = den = Fraction(0)
    for k in range(1001):
        y = Fraction(k, 100)
        mu = max(min(f_low, 1 - y / 10), min(f_high, y / 10))
        num += mu * y
        den += mu
    assert float(fls(2.0, 6.0)) == pytest.approx(float(num / den), abs=1e-12)


MINIMAL = """FUNCTION_BLOCK f
VAR_INPUT
    x : REAL;
END_VAR
VAR_OUTPUT
    y : REAL;
END_VAR
FUZZIFY x
    TERM lo := (0, 1) (1, 0);
    TERM hi := (0, 0) (1, 1);
END_FUZZIFY
DEFUZZIFY y
    TERM a := (0, 0) (5, 1) (10, 0);
    METHOD : COG;
END_DEFUZZIFY
RULEBLOCK r
    AND : MIN;
    RULE 1 : IF x IS lo THEN y IS a;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""

MALFORMED = [
    # (old, new, needle for the line, message fragment)
    ("TERM lo := (0, 1) (1, 0);", "TERM lo := (0, 1) (1, 1.5) (2, 0);", "TERM lo",
     "memberships must lie in [0, 1]"),
    ("TERM lo := (0, 1) (1, 0);", "TERM lo := (1, 1) (0, 0);", "TERM lo", "increasing x"),
    ("TERM lo := (0, 1) (1, 0);", "TERM lo := ;", "TERM lo", "expected points"),
    ("TERM lo := (0, 1) (1, 0);", "TERM lo := TRIAN 0 1;", "TERM lo", "TRIAN needs 3"),
    ("TERM lo := (0, 1) (1, 0);", "TERM lo := GAUSS m 1;", "TERM lo",
     "parameter 'm' is not a declared variable"),
    ("TERM lo := (0, 1) (1, 0);", "TERM lo := BLOB 1 2;", "TERM lo", "unknown shape 'BLOB'"),
    ("TERM a := (0, 0) (5, 1) (10, 0);", "TERM a := 3;", "TERM a", "not a membership function"),
    ("METHOD : COG;", "METHOD : MEAN;", "METHOD", "METHOD MEAN is not supported"),
    ("METHOD : COG;", "METHOD : COG;\n    DEFAULT := NC 1;", "DEFAULT", "expected ';'"),
    ("AND : MIN;", "AND : LUKA;", "AND :", "AND : LUKA is not supported"),
    ("AND : MIN;", "AND : MIN;\n    ACCU : FOO;", "ACCU", "ACCU : FOO is not supported"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS mid THEN y IS a;", "RULE 1",
     "no term 'mid'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF z IS lo THEN y IS a;", "RULE 1",
     "not an input"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo THEN y IS a WITH 2;", "RULE 1",
     "weight 2 must be in [0, 1]"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo THEN y IS a WITH 0.5 x;",
     "RULE 1", "expected ';' after the rule"),
    ("    x : REAL;", "    x : INT;", "x : INT", "only REAL"),
    ("FUZZIFY x", "FUZZIFY w", "FUZZIFY w", "not declared in VAR_INPUT"),
    ("END_FUZZIFY", "RANGE := (1 .. 0);\nEND_FUZZIFY", "RANGE", "lo < hi"),
    ("(0, 0) (5, 1) (10, 0)", "(0, 0) (5, 1) (10, 0) (*", "TERM a", "unterminated comment"),
    ("END_FUNCTION_BLOCK\n", "END_FUNCTION_BLOCK\nextra\n", "extra", "after END_FUNCTION_BLOCK"),
    ("RULEBLOCK r", "RULEBLOCK r\n    AND : PROD;", "AND : MIN", "differs from the earlier"),
]


@pytest.mark.parametrize(("old", "new", "needle", "problem"), MALFORMED,
                         ids=[m[3] for m in MALFORMED])
def test_malformed_fcl_gives_file_and_line(old: str, new: str, needle: str, problem: str,
                                           tmp_path) -> None:
    assert old in MINIMAL
    text = MINIMAL.replace(old, new, 1)
    path = tmp_path / "ctrl.fcl"
    path.write_text(text)
    with pytest.raises(FisFormatError) as info:
        load(path)
    err = info.value
    assert problem in err.message, err
    expected = next(i for i, line in enumerate(text.split("\n"), 1) if needle in line)
    assert err.line == expected, f"{err} (expected line {expected})"
    assert str(err).startswith(f"{path}:{expected}: ")


def test_minimal_fcl_loads_and_is_read_only() -> None:
    fls = loads(MINIMAL, "fcl")
    assert float(fls(0.0)) == pytest.approx(5.0, abs=1e-12)  # the symmetric triangle's centroid
    with pytest.raises(UnsupportedFeatureError, match="does not write"):
        dumps(fls, "fcl")
    again = loads(dumps(fls, "toml"), "toml")
    x = np.linspace(0, 0.9, 10)  # (at x = 1 no rule fires)
    np.testing.assert_array_equal(again(x), fls(x))


def test_shared_singleton_with_accu_max_takes_the_largest_activation() -> None:
    text = (DATA / "heater.fcl").read_text().replace("IF temp IS hot THEN power IS off;",
                                                     "IF temp IS warm THEN power IS high;")
    # at 15: high by rule 1 (cold 0.25) and rule 3 (warm 0.5); medium 0.5 * 0.5
    fls = loads(text, "fcl", path="h.fcl")
    assert float(fls(15.0)) == pytest.approx((0.5 * 100 + 0.25 * 50) / 0.75, abs=1e-12)
    nsum = loads(text.replace("ACCU : MAX;", "ACCU : NSUM;"), "fcl")
    assert float(nsum(15.0)) == pytest.approx((0.75 * 100 + 0.25 * 50) / 1.0, abs=1e-12)

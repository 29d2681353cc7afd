"""FCL reader edges: each refusal's line and message to the letter, each setting's default and
each boundary -- what the mutation run of ``io/fcl.py`` and its parts (``_fclparse``,
``_fclbuild``, ``_fclsystem``) showed no other test pinned."""

from __future__ import annotations

import sys
import warnings

import numpy as np
import pytest

from it2track.io import FisFormatError, loads

TINY = sys.float_info.min  # 2.2250738585072014e-308, the smallest normal float


def fcl(fuzzify: str, defuzzify: str, rules: str = "    RULE 1 : IF x IS a THEN y IS b;",
        *, block: str = "", inputs: str = "x : REAL;", outputs: str = "y : REAL;") -> str:
    """Line 1 FUNCTION_BLOCK f, 2 VAR_INPUT, 3 ``inputs``, 4 END_VAR, 5 VAR_OUTPUT,
    6 ``outputs``, 7 END_VAR, then ``fuzzify``, ``defuzzify``, RULEBLOCK r, ``block``,
    ``rules``."""
    return (f"FUNCTION_BLOCK f\nVAR_INPUT\n{inputs}\nEND_VAR\nVAR_OUTPUT\n{outputs}\nEND_VAR\n"
            f"{fuzzify}\n{defuzzify}\nRULEBLOCK r\n{block}{rules}\nEND_RULEBLOCK\n"
            "END_FUNCTION_BLOCK\n")


def refusal(text: str) -> FisFormatError:
    with pytest.raises(FisFormatError) as info:
        loads(text, "fcl", path="e.fcl")
    return info.value


IN_A = "FUZZIFY x\n    TERM a := (0, 1) (1, 0);\nEND_FUZZIFY"  # lines 8-10
OUT_B = "DEFUZZIFY y\n    TERM b := (0, 0) (1, 1);\n    METHOD : COG;\nEND_DEFUZZIFY"  # 11-14


# -- a polyline narrower than the smallest normal float ----------------------------------------
SUBNORMAL = "term 'a': the points at x = 0.0 and x = 1e-320 are closer than the smallest " \
    "normal float (2.2250738585072014e-308): the slope between them overflows"


@pytest.mark.parametrize("range_", ["", "\n    RANGE := (0 .. 1);"])
@pytest.mark.parametrize("points", ["(0, 1) (1e-320, 0)", "(0, 0) (1e-320, 1) (1, 0)",
                                    "(0, 0) (1e-320, 1) (1e-320, 0.5) (1, 0)"])
def test_a_subnormal_width_polyline_is_refused_naming_the_line_and_term(
        points: str, range_: str) -> None:
    text = fcl(f"FUZZIFY x\n    TERM a := {points};{range_}\nEND_FUZZIFY", OUT_B)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning on the way
        err = refusal(text)
    assert (err.line, err.message) == (9, SUBNORMAL)
    assert str(err) == f"e.fcl:9: {SUBNORMAL}"


def test_a_subnormal_width_output_term_is_refused_too() -> None:
    out = "DEFUZZIFY y\n    TERM b := (0, 0) (1, 1) (1.00000000001, 0);\n    METHOD : COG;\n" \
        "    TERM a := (0, 1) (1e-320, 0);\nEND_DEFUZZIFY"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        err = refusal(fcl(IN_A, out, "    RULE 1 : IF x IS a THEN y IS b;"))
    assert (err.line, err.message) == (14, SUBNORMAL)


def test_a_polyline_as_narrow_as_the_smallest_normal_float_is_read() -> None:
    # the boundary: 1 / TINY = 4.5e307 is finite, so no slope overflows on a unit universe
    text = fcl(f"FUZZIFY x\n    TERM a := (0, 1) ({TINY!r}, 0);\n    RANGE := (0 .. 1);\n"
               "END_FUZZIFY", OUT_B)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fls = loads(text, "fcl")
    mf = fls.inputs[0].sets[0].upper
    assert mf(np.array([0.0, TINY / 2, TINY, 1.0])).tolist() == [1.0, 0.5, 0.0, 0.0]
    below = float(np.nextafter(TINY, 0.0))  # subnormal: refused
    err = refusal(text.replace(repr(TINY), repr(below)))
    assert err.line == 9 and err.message.startswith(
        f"term 'a': the points at x = 0.0 and x = {below!r} are closer than")

"""``load_terms``/``loads_terms``: a file's input variables and their terms, for an FCL
function block with or without outputs and rules (jFuzzyLogic's membership-function files),
read as ``load`` reads them; refusals name the file, the line and the term."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from it2track.fuzzy import Input
from it2track.io import FisFormatError, FisFormatWarning, load, load_terms, loads, loads_terms

DATA = Path(__file__).parent / "data"

TERMS_ONLY = """FUNCTION_BLOCK lib
VAR_INPUT
    b : REAL;
    a : REAL;
END_VAR
FUZZIFY b
    TERM low := TRIAN 0 2 4;
    TERM high := (2, 0) (6, 1);
END_FUZZIFY
FUZZIFY a
    TERM bell := GAUSS 5 2;
    RANGE := (-1 .. 11);
END_FUZZIFY
END_FUNCTION_BLOCK
"""


def _mu(variable: Input, term: str, x: float) -> float:
    lower, upper = variable.sets[variable.set_index(term)](x)
    assert float(lower) == float(upper)  # type-1 terms
    return float(upper)


def test_a_block_without_outputs_gives_its_inputs_in_declared_order() -> None:
    with pytest.raises(FisFormatError, match="no VAR_OUTPUT"):
        loads(TERMS_ONLY, "fcl")
    got = loads_terms(TERMS_ONLY, "fcl")
    assert list(got) == ["b", "a"]  # the file's order, not sorted
    b, a = got["b"], got["a"]
    assert isinstance(b, Input) and b.name == "b"
    assert [s.name for s in b.sets] == ["low", "high"]
    assert b.universe == (0.0, 6.0)  # jFuzzyLogic's estimate: the terms' span
    assert a.universe == (-1.0, 11.0)  # RANGE
    assert [_mu(b, "low", x) for x in (0.0, 1.0, 2.0, 3.0, 4.0)] == [0.0, 0.5, 1.0, 0.5, 0.0]
    assert [_mu(b, "high", x) for x in (2.0, 4.0, 6.0)] == [0.0, 0.5, 1.0]
    assert _mu(a, "bell", 5.0) == 1.0
    assert _mu(a, "bell", 7.0) == pytest.approx(math.exp(-0.5), rel=1e-15)


def test_a_systems_terms_are_the_inputs_load_builds() -> None:
    path = DATA / "heater.fcl"
    system = load(path)
    got = load_terms(path)
    assert list(got) == [v.name for v in system.inputs]
    x = np.linspace(-50.0, 150.0, 41)
    for ours, theirs in zip(got.values(), system.inputs, strict=True):
        assert ours.universe == theirs.universe
        assert [s.name for s in ours.sets] == [s.name for s in theirs.sets]
        for s, t in zip(ours.sets, theirs.sets, strict=True):
            np.testing.assert_array_equal(s(x)[1], t(x)[1])


def test_an_output_without_terms_or_rules_does_not_stop_the_inputs() -> None:
    text = TERMS_ONLY.replace("END_VAR\nFUZZIFY b", "END_VAR\nVAR_OUTPUT\n    y : REAL;\n"
                              "END_VAR\nFUZZIFY b", 1)
    with pytest.raises(FisFormatError, match="'y' has no DEFUZZIFY block"):
        loads(text, "fcl")
    assert list(loads_terms(text, "fcl")) == ["b", "a"]
    # an output term given by variables is refused by load, not read by load_terms
    text = text.replace("END_FUNCTION_BLOCK", "DEFUZZIFY y\n    TERM m := (a, 0) (b, 1);\n"
                        "END_DEFUZZIFY\nEND_FUNCTION_BLOCK")
    with pytest.raises(FisFormatError, match="an output term with values given by variables"):
        loads(text, "fcl")
    assert list(loads_terms(text, "fcl")) == ["b", "a"]


@pytest.mark.parametrize(("change", "line", "message"), [
    (("TERM low := TRIAN 0 2 4;", "TERM low := FUNCTION 1;"), 7,
     "term 'low': its variable needs a RANGE"),
    (("TERM high := (2, 0) (6, 1);", "TERM high := (2, 0) (6, 1.5);"), 8, "high"),
    (("TERM bell := GAUSS 5 2;", "TERM bell := GAUSS 5 0;"), 11, "bell"),
    (("FUZZIFY a\n", "FUZZIFY c\n"), 10, "c"),
    (("FUZZIFY a\n    TERM bell := GAUSS 5 2;\n    RANGE := (-1 .. 11);\nEND_FUZZIFY\n", ""),
     4, "variable 'a' has no FUZZIFY block"),
])
def test_refusals_name_the_file_the_line_and_the_term(change, line, message) -> None:
    text = TERMS_ONLY.replace(*change)
    assert text != TERMS_ONLY
    with pytest.raises(FisFormatError) as info:
        loads_terms(text, "fcl", path="lib.fcl")
    assert info.value.path == "lib.fcl" and info.value.line == line, str(info.value)
    assert message in str(info.value) and str(info.value).startswith(f"lib.fcl:{line}: ")


def test_a_block_without_inputs_is_refused() -> None:
    with pytest.raises(FisFormatError, match=r"^e.fcl:1: no VAR_INPUT variables"):
        loads_terms("FUNCTION_BLOCK e\nEND_FUNCTION_BLOCK\n", "fcl", path="e.fcl")


def test_block_selects_and_several_blocks_warn_as_load_does(tmp_path) -> None:
    second = TERMS_ONLY.replace("FUNCTION_BLOCK lib", "FUNCTION_BLOCK other").replace(
        "TRIAN 0 2 4", "TRIAN 0 1 2")
    path = tmp_path / "two.fcl"
    path.write_text(TERMS_ONLY + second)
    with pytest.warns(FisFormatWarning, match=r"2 FUNCTION_BLOCKs \('lib', 'other'\); read the "
                      "first"):
        first = load_terms(path)
    assert first["b"].universe == (0.0, 6.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        other = load_terms(path, block="other")
    assert _mu(other["b"], "low", 1.0) == 1.0 and _mu(first["b"], "low", 1.0) == 0.5
    with pytest.raises(FisFormatError, match="no FUNCTION_BLOCK 'third'"):
        load_terms(path, block="third")


def test_terms_given_by_variables_are_read_as_load_reads_them() -> None:
    text = """FUNCTION_BLOCK f
VAR_INPUT
    lo : REAL;
    x : REAL;
END_VAR
FUZZIFY x
    TERM up := (lo, 0) (10, 1);
    RANGE := (0 .. 20);
END_FUZZIFY
END_FUNCTION_BLOCK
"""
    got = loads_terms(text, "fcl")
    assert list(got) == ["lo", "x"] and got["lo"].sets == ()
    assert got["x"].universe == got["lo"].universe == (0.0, 20.0)  # lo: as the term it feeds
    up = got["x"].sets[0].upper  # each evaluation reads lo: a row per input, a column a sample
    samples = np.array([[0.0, 4.0, 4.0], [5.0, 5.0, 12.0]])  # lo, x
    assert up.evaluate(samples, 1).tolist() == [0.5, pytest.approx(1 / 6, rel=1e-15), 1.0]


@pytest.mark.parametrize("name", ["tipper.fis", "dimmer.fll", "one_input.toml", "tipper.fml"])
def test_other_formats_give_their_systems_inputs(name) -> None:
    path = DATA / name
    system = load(path)
    got = load_terms(path)
    assert list(got) == [v.name for v in system.inputs]
    assert all(got[v.name] == v for v in system.inputs)
    assert loads_terms(path.read_text(), name.rsplit(".", 1)[1]).keys() == got.keys()


def test_a_block_for_another_format_is_refused() -> None:
    with pytest.raises(ValueError, match="block= names an FCL FUNCTION_BLOCK"):
        load_terms(DATA / "tipper.fis", block="x")

"""``load(..., dialect="octave")``: a ``.fis`` read as the Octave fuzzy-logic-toolkit (0.6.2)
evaluates it where that differs from MATLAB -- Sugeno rules concluding the same value merged
with ``AggMethod`` (``aggregate_output_sugeno``), and ``DefuzzMethod='centroid_integral'``
(``defuzz.m``: ``trapz(x, x.*y) / trapz(x, y)``) -- while the default reading stays MATLAB's.
Octave's own outputs for the toolkit's example files are checked in tests/conformance."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from click.testing import CliRunner

from it2track.cli.fis import fis
from it2track.codegen import generate_c
from it2track.fuzzy import Aggregation, Defuzzifier, T1Mamdani, T1Sugeno, defuzzify
from it2track.io import FisFormatError, UnsupportedFeatureError, dumps, load, loads

SUGENO = """\
[System]
Name='merge'
Type='sugeno'
NumInputs=1
NumOutputs=1
NumRules=3
AndMethod='min'
OrMethod='max'
ImpMethod='prod'
AggMethod='max'
DefuzzMethod='wtaver'

[Input1]
Name='x'
Range=[0 1]
NumMFs=2
MF1='lo':'trimf',[-1 0 1]
MF2='hi':'trimf',[0 1 2]

[Output1]
Name='y'
Range=[0 10]
NumMFs=2
MF1='a':'constant',[2]
MF2='b':'constant',[8]

[Rules]
1, 1 (1) : 1
2, 1 (1) : 1
2, 2 (1) : 1
"""
MAMDANI = """\
[System]
Name='integral'
Type='mamdani'
NumInputs=1
NumOutputs=1
NumRules=2
AndMethod='min'
OrMethod='max'
ImpMethod='min'
AggMethod='max'
DefuzzMethod='centroid_integral'

[Input1]
Name='x'
Range=[0 1]
NumMFs=2
MF1='lo':'trimf',[-1 0 1]
MF2='hi':'trimf',[0 1 2]

[Output1]
Name='y'
Range=[0 10]
NumMFs=2
MF1='small':'trimf',[-10 0 10]
MF2='large':'trimf',[0 10 20]

[Rules]
1, 1 (1) : 1
2, 2 (1) : 1
"""


def test_octave_merges_sugeno_rules_of_equal_conclusions_with_aggmethod() -> None:
    # at x = 0.25: lo fires 0.75 and hi 0.25; rules 1 and 2 conclude 2, rule 3 concludes 8
    matlab = loads(SUGENO, "fis")
    octave = loads(SUGENO, "fis", dialect="octave")
    assert isinstance(octave, T1Sugeno) and octave.aggregation is Aggregation.MAXIMUM
    assert float(matlab(0.25)) == 3.2  # (0.75*2 + 0.25*2 + 0.25*8) / 1.25: every rule
    assert float(octave(0.25)) == 3.5  # (max(0.75, 0.25)*2 + 0.25*8) / 1.0
    assert loads(SUGENO, "fis", dialect="matlab") == matlab  # the default, named


@pytest.mark.parametrize(("method", "expected"), [
    ("probor", 3.625 / 1.0625),  # 0.75 + 0.25 - 0.75*0.25 = 0.8125 at 2
    ("sum", 3.2),  # the sum of equal conclusions: MATLAB's reading
    ("bounded_sum", 3.2),  # min(1, 0.75 + 0.25) = 1: the sum here
])
def test_octave_merges_with_the_files_aggmethod(method: str, expected: float) -> None:
    octave = loads(SUGENO.replace("AggMethod='max'", f"AggMethod='{method}'"), "fis",
                   dialect="octave")
    assert float(octave(0.25)) == pytest.approx(expected, rel=1e-15, abs=0)


def test_octave_without_aggmethod_merges_with_max_as_newfis() -> None:
    octave = loads(SUGENO.replace("AggMethod='max'\n", ""), "fis", dialect="octave")
    assert float(octave(0.25)) == 3.5


def test_centroid_integral_is_the_toolkits_trapezoid_rule() -> None:
    # defuzz.m's own test: defuzz([1 2 3 4], [1 2 3 4], 'centroid_integral') = 2.8667
    # (trapz: 21.5 / 7.5 = 43/15); the centroid weights the end points fully (3.0)
    y = np.array([1.0, 2.0, 3.0, 4.0])
    mu = y[:, None].copy()
    assert float(defuzzify(mu, y, Defuzzifier.CENTROID_INTEGRAL)[0]) == 21.5 / 7.5
    assert float(defuzzify(mu, y, Defuzzifier.CENTROID)[0]) == 3.0
    assert np.isnan(defuzzify(np.zeros((4, 1)), y, Defuzzifier.CENTROID_INTEGRAL)[0])


def test_centroid_integral_file_reads_as_octave_only() -> None:
    with pytest.raises(FisFormatError, match=r":11: DefuzzMethod='centroid_integral' is the "
                       r"Octave toolkit's .*dialect='octave'"):
        loads(MAMDANI, "fis")
    octave = loads(MAMDANI, "fis", dialect="octave")
    assert isinstance(octave, T1Mamdani) and octave.defuzzifier is Defuzzifier.CENTROID_INTEGRAL
    _, mu = octave.aggregated(np.array([0.25]))
    grid = np.linspace(0.0, 10.0, 101)
    expected = np.trapezoid(mu[0] * grid, grid) / np.trapezoid(mu[0], grid)
    assert float(octave(0.25)) == pytest.approx(float(expected), rel=1e-14)
    centroid = loads(MAMDANI.replace("'centroid_integral'", "'centroid'"), "fis")
    assert abs(float(octave(0.25)) - float(centroid(0.25))) > 0.01  # the ends' half weight


def test_writers_map_or_refuse_centroid_integral() -> None:
    octave = loads(MAMDANI, "fis", dialect="octave")
    text = dumps(octave, "fis")
    assert "DefuzzMethod='centroid_integral'" in text
    again = loads(text, "fis", dialect="octave")
    x = np.linspace(0.0, 1.0, 17)[:, None]
    assert np.array_equal(again.evaluate(x), octave.evaluate(x))
    assert np.array_equal(loads(dumps(octave, "toml"), "toml").evaluate(x), octave.evaluate(x))
    for fmt, name in (("fll", "fuzzylite has no defuzzifier 'centroid_integral'"),
                      ("fml", "IEEE 1855 has no defuzzifier 'centroid_integral'")):
        with pytest.raises(UnsupportedFeatureError, match=name):
            dumps(octave, fmt)
    with pytest.raises(UnsupportedFeatureError, match="defuzzifier='centroid_integral'"):
        dumps(dataclasses.replace(octave, on_zero_firing=None), "t2fis")
    with pytest.raises(UnsupportedFeatureError, match="'centroid_integral' has no C impl"):
        generate_c(octave)


@pytest.mark.parametrize(("edit", "message"), [
    (("Type='sugeno'", "Type='tsukamoto'"), r":3: Type='tsukamoto' is fuzzylite's"),
    (("DefuzzMethod='wtaver'", "DefuzzMethod='wtaver'\nTypeReductionMethod='karnikmendel'"),
     r":12: a type-2 system"),
    (("MF1='a':'constant',[2]", "MF1='a':'trimf',[0 2 4]"), r"\[Output1\] of a Type='sugeno'"),
])
def test_octave_refuses_what_the_toolkit_has_not(edit: tuple[str, str], message: str) -> None:
    text = SUGENO.replace(*edit)
    if "trimf" in edit[1]:
        text = text.replace("MF2='b':'constant',[8]", "MF2='b':'trimf',[6 8 10]")
    with pytest.raises(FisFormatError, match=message):
        loads(text, "fis", dialect="octave")


def test_dialect_is_checked() -> None:
    with pytest.raises(ValueError, match=r"dialect='scilab': a .fis is read as one of"):
        loads(SUGENO, "fis", dialect="scilab")
    with pytest.raises(ValueError, match="format 'fll' has none"):
        loads("", "fll", dialect="octave")


def test_cli_reads_with_the_dialect(tmp_path) -> None:
    path = tmp_path / "merge.fis"
    path.write_text(SUGENO)
    runner = CliRunner()
    assert runner.invoke(fis, ["eval", str(path), "0.25"]).output == "u = 3.2\n"
    assert runner.invoke(fis, ["eval", str(path), "0.25", "--dialect", "octave"]
                         ).output == "u = 3.5\n"
    integral = tmp_path / "integral.fis"
    integral.write_text(MAMDANI)
    target = tmp_path / "integral.toml"
    assert runner.invoke(fis, ["convert", str(integral), str(target)]).exit_code != 0
    done = runner.invoke(fis, ["convert", str(integral), str(target), "--dialect", "octave"])
    assert done.exit_code == 0, done.output
    assert float(load(target)(0.25)) == float(loads(MAMDANI, "fis", dialect="octave")(0.25))
    wrong = runner.invoke(fis, ["show", str(target), "--dialect", "octave"])
    assert wrong.exit_code != 0 and "--dialect octave: " in wrong.output

"""The IT2FLS toolbox ``.t2fis`` format: reducer names, type-1 detection, what is rejected."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from it2track import heading_fls
from it2track.fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    Gaussian,
    Input,
    IT2Set,
    IT2Sugeno,
    Rule,
    ScaledLagged,
    T1Sugeno,
)
from it2track.io import FisFormatError, UnsupportedFeatureError, dumps, loads

BASE = (Path(__file__).parent / "data" / "one_input.t2fis").read_text()
TWO = (Path(__file__).parent / "data" / "two_inputs_interval.t2fis").read_text()


def edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def error_of(text: str) -> FisFormatError:
    with pytest.raises(FisFormatError) as info:
        loads(text, "t2fis", path="x.t2fis")
    return info.value


def line_with(text: str, needle: str) -> int:
    return next(i for i, line in enumerate(text.split("\n"), 1) if needle in line)


@pytest.mark.parametrize(
    ("method", "reducer"),
    [("Karnik-Mendel", KM), ("KM", KM), ("km", KM), ("EKM", EKM), ("IASC", EIASC),
     ("EIASC", EIASC), ("EODS", EXHAUSTIVE), ("NT", NIE_TAN), ("WM", WU_MENDEL)],
)
def test_type_reduction_names(method: str, reducer) -> None:
    fls = loads(edit(BASE, "'Karnik-Mendel'", f"'{method}'"), "t2fis")
    assert isinstance(fls, IT2Sugeno) and fls.reducer == reducer


def test_missing_type_red_method_defaults_to_km_like_the_toolbox() -> None:
    fls = loads(edit(BASE, "TypeRedMethod='Karnik-Mendel'\n", ""), "t2fis")
    assert isinstance(fls, IT2Sugeno) and fls.reducer == KM


@pytest.mark.parametrize(("reducer", "name"), [(KM, "KM"), (EKM, "EKM"), (EIASC, "EIASC"),
                                               (EXHAUSTIVE, "EODS"), (NIE_TAN, "NT"),
                                               (WU_MENDEL, "WM")])
def test_writer_reducer_names(reducer, name: str) -> None:
    assert f"TypeRedMethod='{name}'" in dumps(heading_fls(0.2, reducer=reducer), "t2fis")


def test_equal_upper_and_lower_with_crisp_consequents_is_type1() -> None:
    text = edit(edit(BASE, "[-1 0 1 0.5]", "[-1 0 1 1]"), "[0 1 2 0.5]", "[0 1 2 1]")
    fls = loads(text, "t2fis")
    assert isinstance(fls, T1Sugeno)
    assert float(fls(0.25)) == pytest.approx(0.25)
    # an interval consequent keeps it interval type-2
    fls2 = loads(edit(text, "[1 1]", "[1 2]"), "t2fis")
    assert isinstance(fls2, IT2Sugeno)


def test_set_names_from_upper_lower_pairs() -> None:
    text = edit(BASE, "MF2L='highL'", "MF2L='other'")
    fls = loads(text, "t2fis")
    assert [s.name for s in fls.inputs[0].sets] == ["low", "highU"]


def test_the_toolboxs_own_example_shape_loads() -> None:
    # The layout of the toolbox's Examples/3_2 IT2_FPID.t2fis (our own numbers).
    text = """[System]
Name='TezTest'
Type='sugeno'
Version=2.0
NumInputs=1
NumOutputs=1
NumRules=2
AndMethod='prod'
OrMethod='probor'
ImpMethod='prod'
AggMethod='sum'
DefuzzMethod='wtaver'
TypeRedMethod='Karnik-Mendel'
outputType='interval'

[Input1]
Name='input1'
Range=[-1 1]
NumMFs=2
MF1U='mf1U':'trimf',[-2.5 -1 1 1]
MF1L='mf1L':'trimf',[-2 -1 0.5 0.4]
MF2U='mf2U':'trimf',[-1 1 2.5 1]
MF2L='mf2L':'trimf',[-0.5 1 2 0.4]

[Output1]
Name='output1'
Range=[-1 1]
NumMFs=2
MF1='mf1':'constant',[-1 -1]
MF2='mf2':'constant',[1 1]

[Rules]
1, 1 (1) : 1
2, 2 (1) : 1
"""
    fls = loads(text, "t2fis")
    assert isinstance(fls, IT2Sugeno)
    assert float(fls(0.0)) == pytest.approx(0.0, abs=1e-15)
    assert float(fls(1.0)) > 0.5


MALFORMED = [
    # (old, new, line needle (in the edited text), message fragment)
    ("1, 1 (1) : 1", "-3, 1 (1) : 1", "-3, 1", "MF -3 of input 'x', which has only 2"),
    ("1, 1 (1) : 1", "1, -1 (1) : 1", "1, -1", "negated consequent"),
    ("1, 1 (1) : 1", "1, 1 (1.5) : 1", "(1.5)", "rule weight 1.5 must be in [0, 1]"),
    ("1, 1 (1) : 1", "1, 1 (1) : 3", "(1) : 3", "must be 1 (AND) or 2 (OR)"),
    ("1, 1 (1) : 1", "1, 0 (1) : 1", "1, 0 (1)", "no consequent"),
    ("1, 1 (1) : 1", "1, 3 (1) : 1", "1, 3 (1)", "output MF 3"),
    ("1, 1 (1) : 1", "1 1, 1 (1) : 1", "1 1, 1", "2 antecedent indices for 1 inputs"),
    ("1, 1 (1) : 1", "0, 1 (1) : 1", "0, 1 (1)", "mentions no input"),
    ("1, 1 (1) : 1", "1; 1 (1) : 1", "1; 1", "bad rule"),
    ("1, 1 (1) : 1", "1, 1 (x) : 1", "(x)", "bad rule weight"),
    ("Type='sugeno'", "Type='tsukamoto'", "Type=", "'tsukamoto' is not supported"),
    ("OrMethod='probor'", "OrMethod='bsum'", "OrMethod", "'bsum' is not supported"),
    ("AndMethod='prod'", "AndMethod='lukasiewicz'", "AndMethod", "not supported"),
    ("'Karnik-Mendel'", "'BMM(0.5,0.5)'", "TypeRedMethod", "BMM reducer is not supported"),
    ("'Karnik-Mendel'", "'myReducer'", "TypeRedMethod", "unknown TypeRedMethod"),
    ("NumOutputs=1", "NumOutputs=2", "NumOutputs", "missing section [Output2]"),
    ("NumRules=2", "NumRules=3", "NumRules", "NumRules=3 but [Rules] has 2"),
    ("NumRules=2", "NumRules=two", "NumRules", "must be an integer"),
    ("NumInputs=1", "NumInputs=0", "NumInputs", "must be at least 1"),
    ("NumMFs=2\n", "NumMFs=3\n", "NumMFs=3", "missing MF3U"),
    ("'trimf',[-1 0 1 1]", "'bellmf',[1 2 0 1]", "bellmf", "unknown MF type 'bellmf'"),
    ("'trimf',[-1 0 1 1]", "'rampmf',[0 1 1]", "rampmf", "unknown MF type 'rampmf'"),
    ("'trimf',[-1 0 1 1]", "'trimf',[-1 0 1]", "MF1U=", "trimf needs 4 parameters"),
    ("'trimf',[-1 0 1 1]", "'trimf',[1 0 -1 1]", "MF1U=", "a <= b <= c"),
    ("'trimf',[-1 0 1 1]", "'trimf',[-1 0 1 Inf]", "MF1U=", "bad number 'Inf'"),
    ("'trimf',[-1 0 1 1]", "'trimf',[-1 0 1 1e999]", "MF1U=", "out of range"),
    ("'trimf',[-1 0 1 1]", "'trimf',[-1 0 1 2]", "MF1U=", "0 < h <= 1"),
    ("'trimf',[-1 0 1 1]", "'trimf',[-1 0 1; 1 1 1]", "MF1U=", "row vector"),
    ("MF1U='lowU'", "MF1U='lowU", "MF1U=", "unterminated string"),
    ("MF1U='lowU':", "MF1U='lowU',", "MF1U=", "must look like 'name':'type',[params]"),
    ("MF2U='highU':'trimf',[0 1 2 1]\nMF2L='highL'", "MF2U='lowU':'trimf',[0 1 2 1]\nMF2L='lowL'",
     "MF2U=", "duplicate MF name 'low'"),
    ("Range=[0 1]\nNumMFs=2", "Range=[1 0]\nNumMFs=2", "Range=[1 0]", "lo < hi"),
    ("Range=[0 1]\nNumMFs=2", "Range=[0 1 2]\nNumMFs=2", "Range=[0 1 2]", "2 numbers"),
    ("'constant',[1 1]", "'linear',[1 1 1]", "'linear'", "'linear' needs 2 numbers"),
    ("'constant',[1 1]", "'linear',[1 1 0 0]", "'linear'", "must satisfy lower <= upper"),
    ("'constant',[1 1]", "'constant',[2 1]", "'constant',[2 1]", "lower <= upper"),
    ("Name='x'", "Name='x'\nColour='red'", "Colour", "unknown key 'Colour'"),
    ("Name='x'", "Name='x'\nName='y'", "Name='y'", "duplicate key 'Name'"),
    ("Name='x'", "Name=x", "Name=x", "must be a quoted string"),
    ("[Input1]", "[Inputs1]", "[Inputs1]", "unknown section [Inputs1]"),
    ("[Input1]", "[Input2]", "[Input2]", "unexpected section [Input2] (NumInputs=1)"),
    ("[Output1]", "[Output3]", "[Output3]", "unexpected section [Output3]"),
    ("[Rules]\n1, 1 (1) : 1\n2, 2 (1) : 1\n", "", "NumRules", "missing section [Rules]"),
    ("[Output1]", "[Output1]\n[Output1]", "[Output1]", "duplicate section"),
    ("Name='y'", "Name y", "Name y", "expected Key=value"),
    ("[Rules]", "[Input2]\nName='z'\n\n[Rules]", "[Input2]", "unexpected section [Input2]"),
]


@pytest.mark.parametrize(("old", "new", "needle", "problem"), MALFORMED,
                         ids=[m[3] for m in MALFORMED])
def test_malformed(old: str, new: str, needle: str, problem: str) -> None:
    text = edit(BASE, old, new)
    err = error_of(text)
    assert problem in err.message, err
    if needle == "[Output1]":  # the duplicate is the second one
        expected = [i for i, line in enumerate(text.split("\n"), 1) if needle in line][1]
    else:
        expected = line_with(text, needle)
    assert err.line == expected, f"{err} (expected line {expected})"
    assert str(err).startswith(f"x.t2fis:{expected}: ")


def test_text_before_system_and_missing_system() -> None:
    err = error_of("Name='x'\n" + BASE)
    assert err.line == 1 and "before the first section" in err.message
    err = error_of(BASE.replace("[System]", "% no system\n[Rules]", 1))
    assert "duplicate section [Rules]" in err.message or "missing section" in err.message
    err = error_of("% nothing\n")
    assert err.line is None and "missing section [System]" in err.message


def test_or_not_and_weights_are_read() -> None:
    text = edit(TWO, "1 1, 1 (1) : 1", "1 -1, 1 (0.5) : 2")
    fls = loads(text, "t2fis")
    rule = fls.rules[0]
    assert (rule.connective.value, rule.negated, rule.weight) == ("or", (False, True), 0.5)
    assert fls.tables.features == {"or", "not", "weights"}
    # one antecedent: OR and AND agree, and the lowering says so
    fls = loads(edit(TWO, "2 0, 3 (1) : 1", "2 0, 3 (1) : 2"), "t2fis")
    assert fls.rules[2].antecedent == ("B", None)
    assert fls.tables.features == frozenset()


def test_gauss2mf_reads_as_uncertain_mean_gaussian() -> None:
    text = edit(edit(TWO, "'gaussmf',[0.5 0 1]", "'gauss2mf',[0.5 -0.1 0.5 0.1 1]"),
                "'gaussmf',[0.5 0 0.6]", "'gaussmf',[0.5 0 0.6]")
    fls = loads(text, "t2fis")
    upper = fls.inputs[1].sets[0].upper
    assert float(upper(0.05)) == 1.0
    assert float(upper(0.6)) == pytest.approx(np.exp(-0.5 * (0.5 / 0.5) ** 2))
    # other sigmas: MATLAB's two-sided Gaussian (fuzzylite's GaussianProduct), checked as usual
    text = edit(TWO, "'gaussmf',[0.5 0 1]", "'gauss2mf',[0.5 0 0.4 0.1 1]")
    err = error_of(text)
    assert "exceeds upper MF GaussianProduct" in err.message, err
    fls = loads(edit(text, "'gaussmf',[0.5 0 0.6]", "'gaussmf',[0.3 0 0.6]"), "t2fis")
    upper = fls.inputs[1].sets[0].upper
    assert float(upper(0.05)) == 1.0
    assert float(upper(0.5)) == np.exp(-0.5 * ((0.5 - 0.1) / 0.4) ** 2)


def test_writer_rejects_what_the_format_cannot_carry() -> None:
    fls = heading_fls(0.2)
    with pytest.raises(UnsupportedFeatureError, match="on_zero_firing"):
        dumps(dataclasses.replace(fls, on_zero_firing=0.0), "t2fis")
    with pytest.raises(UnsupportedFeatureError, match="max_iter"):
        dumps(dataclasses.replace(fls, reducer=KM.with_max_iter(7)), "t2fis")
    um = IT2Set.gaussian_uncertain_mean(-0.1, 0.1, 0.5, "U")
    system = IT2Sugeno(inputs=[Input("x", (-1, 1), [um])], rules=[Rule(["U"], 1.0)])
    with pytest.raises(UnsupportedFeatureError, match="UncertainMeanGaussianLower"):
        dumps(system, "t2fis")

    class Bump:
        def __call__(self, x):
            return np.clip(1 - np.abs(np.asarray(x, dtype=float)), 0, 1)

    odd = IT2Sugeno(inputs=[Input("x", (-1, 1), [("B", Bump())])], rules=[Rule(["B"], 1.0)])
    with pytest.raises(UnsupportedFeatureError, match="Bump"):
        dumps(odd, "t2fis")
    with pytest.raises(UnsupportedFeatureError, match="line break"):
        dumps(dataclasses.replace(fls, name="two\nlines"), "t2fis")


def test_scaled_gaussian_without_lag_is_written_as_a_gaussian_height() -> None:
    g = Gaussian(0.0, 0.4)
    s = IT2Set(g, ScaledLagged(g, 0.6, 0.0), "S")
    system = IT2Sugeno(inputs=[Input("x", (-1, 1), [s])], rules=[Rule(["S"], (0.0, 1.0))])
    text = dumps(system, "t2fis")
    assert "'gaussmf',[0.4 0 0.6]" in text
    again = loads(text, "t2fis")
    x = np.linspace(-1, 1, 101)
    assert np.array_equal(system(x), again(x))

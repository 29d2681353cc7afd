"""``.fis`` as MATLAB, Octave and fuzzylite write it: comments, spaced keys, float rule indices,
fuzzylite's extra keys and MF names, MATLAB's oddities (extra parameters, a repeated ``MF2``,
``pi`` in ranges), operators beyond min/prod, ``wtsum`` -- each read as its tool reads it, or
refused naming the line, or read with a :class:`FisFormatWarning` naming the line."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from it2track.fuzzy import (
    Aggregation,
    Hedge,
    Implication,
    Ramp,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TNorm,
    WeightedDefuzzifier,
)
from it2track.io import FisFormatError, FisFormatWarning, dumps, loads

DATA = Path(__file__).parent / "data"
TIPPER = (DATA / "tipper.fis").read_text()
X = np.linspace(0.0, 10.0, 7)
GRID = np.stack(np.meshgrid(X, X), axis=-1).reshape(-1, 2)


def edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def line_with(text: str, needle: str, nth: int = 0) -> int:
    return [i for i, line in enumerate(text.split("\n"), 1) if needle in line][nth]


def load(text: str):
    return loads(text, "fis", path="t.fis")


def error_of(text: str) -> FisFormatError:
    with pytest.raises(FisFormatError) as info:
        load(text)
    return info.value


def warning_of(text: str):
    with pytest.warns(FisFormatWarning) as record:
        fls = load(text)
    assert len(record) == 1, [str(w.message) for w in record]
    warning = record[0].message
    assert isinstance(warning, FisFormatWarning)
    return fls, warning


def same_outputs(a, b) -> bool:
    return bool(np.array_equal(a.evaluate(GRID), b.evaluate(GRID)))


BASE = load(TIPPER)


def test_octave_layout_comments_and_spaced_keys_read_as_the_plain_file() -> None:
    octave = "## Copyright (C) 2011 someone\n##\n# a comment\n" + "\n".join(
        "  " + line.replace("=", " = ", 1) if "=" in line else line
        for line in TIPPER.split("\n")
    )
    octave = edit(octave, "[Input2]", "% MATLAB comment\n\n[Input2]")
    octave = edit(octave, "[Output1]", "[Output1]\n#Range=[0 99]")  # a commented-out key
    fls = load(octave)
    assert fls == BASE


def test_float_rule_indices_are_read_as_integers() -> None:
    text = edit(TIPPER, "1 1, 1 (1) : 1", "1.000 1.000 , 1.000 (1.000) : 1")
    assert load(text) == BASE


@pytest.mark.parametrize(("index", "power"), [("1.2", 2.0), ("1.05", 0.5), ("-1.3", 3.0),
                                              ("1.40", 4.0), ("1.7", 7.0)])
def test_octave_hedges_are_powers(index: str, power: float) -> None:
    # fuzzy-logic-toolkit: the fraction in hundredths over 10 is the power (custom ones too)
    text = edit(TIPPER, "3 2, 3 (1) : 1", f"3 {index}, 3 (1) : 1")
    rule = load(text).rules[2]
    assert rule.hedges[1] == (Hedge.power(power),)
    assert rule.negated[1] is index.startswith("-")


def test_fuzzylite_exports_mean_fuzzylites_hedges() -> None:
    header = "#Code automatically generated with fuzzylite 6.0.\n\n"
    rule = load(header + edit(TIPPER, "3 2, 3 (1) : 1", "3 -1.3, 3 (1) : 1")).rules[2]
    assert rule.hedges[1] == (Hedge("extremely"),) and rule.negated[1]
    rule = load(header + edit(TIPPER, "3 2, 3 (1) : 1", "3 1.4, 3 (1) : 1")).rules[2]
    assert rule.hedges[1] == (Hedge("very"), Hedge("very"))
    text = header + edit(TIPPER, "3 2, 3 (1) : 1", "3 1.7, 3 (1) : 1")
    err = error_of(text)
    assert err.line == line_with(text, "3 1.7,")
    assert "rule index 1.7 has a fraction: hedges are not supported" in err.message


def test_a_hedged_octave_sugeno_conclusion_is_the_firing_to_the_power_one_over_p() -> None:
    text = """[System]
Name='s'
Type='sugeno'
NumInputs=1
NumOutputs=1
NumRules=2
AndMethod='prod'
OrMethod='max'
ImpMethod='prod'
AggMethod='sum'
DefuzzMethod='wtaver'

[Input1]
Name='x'
Range=[0 4]
NumMFs=2
MF1='lo':'trimf',[-4 0 4]
MF2='hi':'trimf',[0 4 8]

[Output1]
Name='y'
Range=[0 10]
NumMFs=2
MF1='a':'constant',[2]
MF2='b':'constant',[8]

[Rules]
1, 1.3 (0.5) : 1
2, -2.2 (1) : 1
"""
    fls = loads(text, "fis")
    f1 = (0.5 * 0.75) ** (1 / 3)  # at x = 1: the weighted firing to the power 1/3
    f2 = 1 - 0.25 ** 0.5  # not, after the power 1/2
    assert float(fls(1.0)) == pytest.approx((2 * f1 + 8 * f2) / (f1 + f2), rel=1e-15)
    assert fls.rules[1].consequent_hedges[0] == (Hedge("not"), Hedge.power(0.5))
    mamdani = (DATA / "tipper_mamdani.fis").read_text()
    for conclusion in ("3.2", "-3"):  # Octave hedges the output set itself: refused
        err = error_of(edit(mamdani, "3 2, 3 (1) : 2", f"3 2, {conclusion} (1) : 2"))
        assert "conclusion of a Mamdani output" in err.message


def test_unknown_key_warns_with_its_line_and_is_ignored() -> None:
    text = edit(TIPPER, "NumRules=3", "NumRules=3\nColour='red'")
    fls, warning = warning_of(text)
    assert warning.line == line_with(text, "Colour") and warning.path == "t.fis"
    assert "unknown key 'Colour' in [System] ignored" in warning.message
    assert fls == BASE


def test_extra_mf_parameters_are_ignored_as_matlab_does() -> None:
    # MATLAB's shower.fis has trimf [-10 0 10 0]; its slcp1.fis gaussmf [0.2 0.5 0 0]
    text = edit(TIPPER, "'gaussmf',[1.5 5]", "'gaussmf',[1.5 5 0 0]")
    fls, warning = warning_of(text)
    assert warning.line == line_with(text, "[1.5 5 0 0]")
    assert "read as [1.5 5]" in warning.message
    assert fls == BASE
    err = error_of(edit(TIPPER, "'gaussmf',[1.5 5]", "'gaussmf',[1.5]"))
    assert "gaussmf needs 2 parameters" in err.message


def test_a_repeated_mf_key_is_the_next_mf_as_in_matlabs_slcp1() -> None:
    text = edit(TIPPER, "MF3='excellent'", "MF2='excellent'")
    fls, warning = warning_of(text)
    assert warning.line == line_with(text, "MF2='excellent'")
    assert "read as MF3" in warning.message
    assert [s.name for s in fls.inputs[0].sets] == ["poor", "good", "excellent"]
    assert fls == BASE
    err = error_of(edit(TIPPER, "NumMFs=3\nMF1='poor'", "NumMFs=4\nMF1='poor'"))
    assert "has 3 MF lines but NumMFs=4" in err.message


def test_more_mf_lines_and_rules_than_counted_are_read_as_fuzzylite_does() -> None:
    # fuzzylite's export of its AllTerms example says NumMFs=16 and NumRules=16 over 20 of each
    text = edit(TIPPER, "NumMFs=3\nMF1='poor'", "NumMFs=2\nMF1='poor'")
    fls, warning = warning_of(text)
    assert warning.line == line_with(text, "MF3='excellent'")
    assert "all 3 MF lines read, as fuzzylite reads them" in warning.message
    assert fls == BASE
    text = edit(TIPPER, "NumRules=3", "NumRules=2")
    fls, warning = warning_of(text)
    assert warning.line == line_with(text, "NumRules=2")
    assert "[Rules] has 3 rules: all read" in warning.message
    assert fls == BASE
    err = error_of(edit(TIPPER, "NumRules=3", "NumRules=4"))
    assert "NumRules=4 but [Rules] has 3 rules" in err.message


def test_a_sugeno_file_with_monotonic_output_mfs_is_tsukamoto_as_fuzzylite_reads_it() -> None:
    # fuzzylite's examples/original/tsukamoto/tsukamoto.fis: Type='sugeno', 'rampmf' outputs
    text = edit(TIPPER, """MF1='cheap':'constant',[5]
MF2='average':'constant',[15]
MF3='generous':'constant',[25]""", """MF1='cheap':'rampmf',[10 0]
MF2='average':'rampmf',[0 30]
MF3='generous':'rampmf',[20 30]""")
    fls, warning = warning_of(text)
    assert isinstance(fls, T1Tsukamoto)
    assert warning.line == line_with(text, "[Output1]") and "a Tsukamoto output" in warning.message
    # at (5, 8) (see the fixture): r2 = 1 puts 'average' at 30, r3 'generous' at 20 + 10 r3
    r3 = math.exp(-50 / 9) * 0.5
    assert float(fls(5.0, 8.0)) == pytest.approx((30.0 + r3 * (20 + 10 * r3)) / (1 + r3),
                                                 abs=1e-12)


def test_matlab_pi_expressions_in_a_range() -> None:
    text = edit(TIPPER, "Range=[0 30]", "Range=[-pi/4 pi*9.5]")
    fls = load(text)
    assert fls.on_zero_firing == (-math.pi / 4 + math.pi * 9.5) / 2
    for bad, problem in [("[pi/0 1]", "division by zero"), ("[2pi 7]", "bad number '2pi'"),
                         ("[pi^2 7]", "bad number 'pi^2'"), ("[1e308*1e308 0]", "out of range")]:
        err = error_of(edit(TIPPER, "Range=[0 30]", f"Range={bad}"))
        assert problem in err.message and err.line == line_with(TIPPER, "Range=[0 30]"), err


def test_fuzzylite_keys_at_harmless_values_are_read_others_refused() -> None:
    text = edit(TIPPER, "Name='service'", "Enabled=1\nName='service'")
    text = edit(text, "Name='tip'", "Enabled=1\nName='tip'\nDefault=nan\nLockPrevious=0\n"
                "LockRange=0")
    fls = load(text)
    assert fls.on_zero_firing is None  # fuzzylite's nan: no value where nothing fires
    assert same_outputs(fls, BASE)
    assert load(edit(text, "Default=nan", "Default=2.5")).on_zero_firing == 2.5
    locked = load(edit(text, "LockPrevious=0", "LockPrevious=1"))
    assert fls.lock_previous is False and locked.lock_previous is True
    assert locked == dataclasses.replace(fls, lock_previous=True)
    for key, value, meaning in [("Enabled", "0", "a disabled variable"),
                                ("LockPrevious", "2", "must be 0 or 1"),
                                ("LockRange", "1", "clipping")]:
        bad = edit(text, f"{key}={'1' if key == 'Enabled' else '0'}", f"{key}={value}")
        err = error_of(bad)
        assert err.line == line_with(bad, f"{key}={value}") and meaning in err.message, err


def test_empty_operator_is_none_and_refused_where_a_rule_needs_it() -> None:
    text = edit(TIPPER, "AndMethod='prod'", "AndMethod=''")
    err = error_of(text)
    assert err.line == line_with(text, "1 1, 1 (1)")
    assert f"AndMethod='' (line {line_with(text, 'AndMethod')})" in err.message
    one_input = edit(edit(edit(text, "1 1, 1", "1 0, 1"), "3 2, 3", "3 0, 3"), "OrMethod='probor'",
                     "OrMethod=''")
    fls = load(one_input)
    assert fls.tnorm is TNorm.PRODUCT and fls.snorm is SNorm.MAXIMUM


def test_octave_and_fuzzylite_operator_names() -> None:
    text = edit(edit(TIPPER, "AndMethod='prod'", "AndMethod='einstein_product'"),
                "OrMethod='probor'", "OrMethod='einstein_sum'")
    fls = load(text)
    assert (fls.tnorm, fls.snorm) == (TNorm.EINSTEIN_PRODUCT, SNorm.EINSTEIN_SUM)
    again = dumps(fls, "fis")
    assert "AndMethod='einstein_product'" in again and "OrMethod='einstein_sum'" in again
    assert load(again) == fls
    err = error_of(edit(TIPPER, "AndMethod='prod'", "AndMethod='lukasiewicz'"))
    assert "'lukasiewicz' is not supported ('prod', 'min', 'bounded_difference'" in err.message


def test_mamdani_implication_and_aggregation_names() -> None:
    text = (DATA / "tipper_mamdani.fis").read_text()
    text = edit(edit(text, "ImpMethod='min'", "ImpMethod='hamacher_product'"),
                "AggMethod='max'", "AggMethod='bounded_sum'")
    fls = load(text)
    assert isinstance(fls, T1Mamdani)
    assert (fls.implication, fls.aggregation) == (Implication.HAMACHER_PRODUCT,
                                                  Aggregation.BOUNDED_SUM)
    assert load(dumps(fls, "fis")) == fls


def test_wtsum_is_the_weighted_sum() -> None:
    fls = load(edit(TIPPER, "DefuzzMethod='wtaver'", "DefuzzMethod='wtsum'"))
    assert isinstance(fls, T1Sugeno) and fls.defuzzifier is WeightedDefuzzifier.SUM
    f = fls.firing(5.0, 8.0)[1]
    assert float(fls(5.0, 8.0)) == pytest.approx(float(f @ np.array([5.0, 15.0, 25.0])),
                                                 rel=1e-15)
    assert load(dumps(fls, "fis")) == fls
    assert "defuzzifier = \"wtsum\"" in dumps(fls, "toml")


def test_fuzzylite_term_names_in_fis() -> None:
    text = edit(TIPPER, "'trapmf',[0 0 1 3]", "'rampmf',[3 0]")
    fls = load(text)
    assert fls.inputs[1].sets[0].upper == Ramp(3.0, 0.0)
    text = edit(TIPPER, "'trapmf',[0 0 1 3]", "'function',[x*2]")
    err = error_of(text)
    assert err.line == line_with(text, "'function',[x*2]")
    assert err.message == ("MF 'rancid': fuzzylite's 'function' (a formula) is read in a .fis "
                           "as a Takagi-Sugeno output's consequent only (a membership Function "
                           "is read from fuzzylite's .fll)")


def test_fuzzylites_function_consequent_in_fis() -> None:
    # fuzzylite's export of a Function term (fuzzylite/examples/takagi-sugeno/approximation.fis)
    text = edit(TIPPER, "'constant',[25]", "'function',[25 + sqrt(service) * food ^ 2]")
    fls = load(text)
    f = fls.firing(GRID[:, 0], GRID[:, 1])[1]
    y = np.stack([np.full(len(GRID), 5.0), np.full(len(GRID), 15.0),
                  25.0 + np.sqrt(GRID[:, 0]) * GRID[:, 1] ** 2], axis=-1)
    np.testing.assert_allclose(fls(GRID[:, 0], GRID[:, 1]),
                               (f * y).sum(1) / f.sum(1), rtol=1e-15, atol=0)
    for formula, message in [
        ("25 + tip", "function '25 + tip' reads its own output 'tip' (fuzzylite's value of the "
         "previous evaluation, NaN after a restart): it2track reads only the outputs declared "
         "before this one (none)"),
        ("25 + ", "function '25 +': ends where a number, name or '(' should follow (at the "
         "end)"),
    ]:
        bad = edit(TIPPER, "'constant',[25]", f"'function',[{formula}]")
        err = error_of(bad)
        assert err.line == line_with(bad, "'function'")
        assert message in err.message and err.message.startswith("MF 'generous': function")
    err = error_of(edit(TIPPER, "'constant',[25]", "'function',[service],'Height',1"))
    assert err.message == "unexpected text after the formula of MF3"


def test_an_input_without_mfs_feeds_linear_consequents_as_in_matlabs_slcp1() -> None:
    text = edit(TIPPER, "NumInputs=2", "NumInputs=3")
    text = edit(text, "[Output1]", "[Input3]\nName='z'\nRange=[-1 1]\nNumMFs=0\n\n[Output1]")
    text = edit(text, "MF1='cheap':'constant',[5]", "MF1='cheap':'linear',[0 0 2 5]")
    for old, new in [("1 1, 1", "1 1 0, 1"), ("2 0, 2", "2 0 0, 2"), ("3 2, 3", "3 2 0, 3")]:
        text = edit(text, old, new)
    fls = load(text)
    assert fls.inputs[2].sets == ()
    # at (0, 0, z): rule 1 fires 1 (plane 2 z + 5), rule 2 fires g = exp(-25 / 4.5) (15)
    g = math.exp(-25 / 4.5)
    for z in (-1.0, 0.5):
        assert float(fls(0.0, 0.0, z)) == pytest.approx((2 * z + 5 + 15 * g) / (1 + g), rel=1e-14)
    again = loads(dumps(fls, "toml"), "toml")
    assert again == fls and "sets = []" in dumps(fls, "toml")
    assert load(dumps(fls, "fis")) == fls
    err = error_of(edit(text, "NumMFs=3\nMF1='cheap'", "NumMFs=0\nMF1='cheap'"))
    assert "NumMFs=0 must be at least 1" in err.message

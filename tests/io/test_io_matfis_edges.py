"""MATLAB ``.fis`` reader edges (``io/matfis.py``): fuzzylite's hybrid systems cut into their
runs of outputs, ``Default`` per output, the norms fuzzylite leaves empty, every refusal's line
and message to the letter -- what the mutation run of the module showed no other test pinned."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from it2track.fuzzy import (
    KM,
    Aggregation,
    Defuzzifier,
    Hedge,
    HybridSystem,
    Implication,
    IT2Mamdani,
    Linear,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TNorm,
    Triangle,
    WeightedDefuzzifier,
)
from it2track.fuzzy.formula import Formula
from it2track.io import FisFormatError, FisFormatWarning, loads, matfis

DATA = Path(__file__).parent / "data"
SYSTEM = """[System]
Name='hy'
Type='hybrid'
NumInputs=1
NumOutputs=3
NumRules=2
AndMethod='min'
OrMethod='max'
ImpMethod='min'
AggMethod='max'
DefuzzMethod='centroid'
"""  # lines 1-11
INPUT = """
[Input1]
Name='x'
Range=[0 10]
NumMFs=2
MF1='lo':'trimf',[0 0 10]
MF2='hi':'trimf',[0 10 10]
"""  # lines 13-18


def constants(k: int, name: str, values: list[float], extra: str = "") -> str:
    mfs = "".join(f"MF{j}='{name}{j}':'constant',[{v}]\n" for j, v in enumerate(values, 1))
    return (f"\n[Output{k}]\nName='{name}'\nRange=[0 10]\n{extra}NumMFs={len(values)}\n"
            f"{mfs}")


def sets(k: int, name: str, extra: str = "") -> str:
    return (f"\n[Output{k}]\nName='{name}'\nRange=[0 10]\n{extra}NumMFs=2\n"
            "MF1='low':'trimf',[0 0 10]\nMF2='high':'trimf',[0 10 10]\n")


def fis(outputs: str, rules: str, system: str = SYSTEM) -> str:
    n = rules.count("\n")
    return (system.replace("NumRules=2", f"NumRules={n}") + INPUT + outputs + "\n[Rules]\n"
            + rules)


SUGENO = SYSTEM.replace("hybrid", "sugeno").replace("NumOutputs=3", "NumOutputs=1").replace(
    "centroid", "wtaver")


def refusal(text: str) -> FisFormatError:
    with pytest.raises(FisFormatError) as info:
        loads(text, "fis", path="h.fis")
    return info.value


def line_of(text: str, needle: str, nth: int = 0) -> int:
    return [i for i, line in enumerate(text.split("\n"), 1) if needle in line][nth]


HYBRID = fis(constants(1, "a", [2, 8]) + sets(2, "m") + constants(3, "c", [1]),
             "1, 1 1 1.2 (1) : 1\n2, 2 2 0 (1) : 1\n")


def test_a_hybrid_system_is_one_system_per_run_of_outputs_of_a_kind() -> None:
    fls = loads(HYBRID, "fis")
    assert isinstance(fls, HybridSystem) and fls.name == "hy"
    a, m, c = fls.systems
    assert (type(a), type(m), type(c)) == (T1Sugeno, T1Mamdani, T1Sugeno)
    assert a.outputs == ("a",) and c.outputs == ("c",)
    assert [o.name for o in m.outputs] == ["m"]
    # each part keeps the rules acting on its outputs, with their conclusions' hedges
    assert [r.consequents for r in a.rules] == [((2.0, 2.0),), ((8.0, 8.0),)]
    assert [r.consequents for r in m.rules] == [("low",), ("high",)]
    assert [r.consequents for r in c.rules] == [((1.0, 1.0),)]
    assert [r.consequent_hedges for r in a.rules + m.rules] == [((),), ((),), ((),), ((),)]
    assert [r.consequent_hedges for r in c.rules] == [((Hedge.power(0.5),),)]
    # the Sugeno parts take no Mamdani options and the weighted average; the midpoints
    assert (a.defuzzifier, c.defuzzifier) == (WeightedDefuzzifier.AVERAGE,) * 2
    assert (m.defuzzifier, m.implication, m.aggregation) == (
        Defuzzifier.CENTROID, Implication.MINIMUM, Aggregation.MAXIMUM)
    assert (a.on_zero_firing, m.on_zero_firing, c.on_zero_firing) == (5.0, 5.0, 5.0)
    assert (a.name, m.name, c.name) == ("hy", "hy", "hy")
    assert (a.aggregation, c.aggregation) == (None, None)  # AggMethod is the Mamdani part's


def test_a_run_of_several_outputs_is_one_system_with_a_default_each() -> None:
    text = fis(sets(1, "m", "Default=1\n") + sets(2, "n", "Default=2\n")
               + constants(3, "c", [1], "Default=3\n"), "1, 1 2 1 (1) : 1\n")
    m, c = loads(text, "fis").systems
    assert [o.name for o in m.outputs] == ["m", "n"]
    assert [r.consequents for r in m.rules] == [("low", "high")]
    assert (m.on_zero_firing, c.on_zero_firing) == ((1.0, 2.0), 3.0)


def test_a_sugeno_output_named_output1_is_the_plain_single_output() -> None:
    text = fis(constants(1, "output1", [2, 8]), "1, 1 (1) : 1\n", SUGENO)
    assert loads(text, "fis").outputs == ()  # the default: one output, unnamed
    text = fis(constants(1, "output2", [2, 8]), "1, 1 (1) : 1\n", SUGENO)
    assert loads(text, "fis").outputs == ("output2",)


def test_an_output_no_rule_acts_on() -> None:
    text = fis(constants(1, "a", [2, 8]) + sets(2, "m") + constants(3, "c", [1]),
               "1, 1 1 0 (1) : 1\n2, 2 2 0 (1) : 1\n")
    err = refusal(text)
    assert (err.line, err.message) == (1, "no rule acts on output 3")
    text = fis(constants(1, "a", [2, 8]) + sets(2, "m") + constants(3, "c", [1]),
               "1, 1 0 1 (1) : 1\n")
    err = refusal(text)
    assert (err.line, err.message) == (1, "no rule acts on output 2")


@pytest.mark.parametrize("defaults", [("nan", None, None), (None, "nan", None),
                                      ("nan", "2", "nan"), ("1", "nan", "nan")])
def test_default_nan_for_some_outputs_names_the_first_such_line(defaults) -> None:
    extra = ["" if d is None else f"Default={d}\n" for d in defaults]
    text = fis(sets(1, "m", extra[0]) + sets(2, "n", extra[1]) + sets(3, "o", extra[2]),
               "1, 1 1 1 (1) : 1\n")
    err = refusal(text)
    assert (err.line, err.message) == (line_of(text, "Default=nan"),
                                       "Default=nan for some outputs and not others")


def test_default_nan_everywhere_is_no_default() -> None:
    text = fis(sets(1, "m", "Default=NaN\n") + sets(2, "n", "Default= nan \n")
               + sets(3, "o", "Default=nan\n"), "1, 1 1 1 (1) : 1\n")
    assert loads(text, "fis").on_zero_firing is None


def test_linear_outputs_are_takagi_sugeno_in_a_hybrid_and_a_sugeno_system() -> None:
    linear = constants(3, "c", [1]).replace("'constant',[1]", "'linear',[0.5 1]")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no "read as Tsukamoto" warning
        fls = loads(fis(constants(1, "a", [2, 8]) + sets(2, "m") + linear,
                        "1, 1 1 1 (1) : 1\n"), "fis")
        assert [type(p) for p in fls.systems] == [T1Sugeno, T1Mamdani, T1Sugeno]
        assert fls.systems[2].rules[0].consequents == (Linear([0.5], 1.0),)
        one = loads(fis(linear.replace("Output3", "Output1"), "1, 1 (1) : 1\n", SUGENO), "fis")
        assert isinstance(one, T1Sugeno) and one.rules[0].consequents == (Linear([0.5], 1.0),)


def test_function_outputs_are_takagi_sugeno_in_a_hybrid_and_a_sugeno_system() -> None:
    function = constants(3, "c", [1]).replace("'constant',[1]", "'function',[x * 2]")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no "read as Tsukamoto" warning
        fls = loads(fis(constants(1, "a", [2, 8]) + sets(2, "m") + function,
                        "1, 1 1 1 (1) : 1\n"), "fis")
        assert [type(p) for p in fls.systems] == [T1Sugeno, T1Mamdani, T1Sugeno]
        assert fls.systems[2].rules[0].consequents == (Formula("x * 2", "fuzzylite", ("x",)),)
        one = loads(fis(function.replace("Output3", "Output1"), "1, 1 (1) : 1\n", SUGENO),
                    "fis")
        assert isinstance(one, T1Sugeno)
        assert one.rules[0].consequents == (Formula("x * 2", "fuzzylite", ("x",)),)


def test_lock_previous_is_read_per_output_and_refused_naming_its_line() -> None:
    text = fis(constants(1, "a", [2, 8], "LockPrevious=1\n") + sets(2, "m")
               + constants(3, "c", [1], "LockPrevious=0\n"), "1, 1 1 1 (1) : 1\n")
    fls = loads(text, "fis")
    assert [p.lock_previous for p in fls.systems] == [True, False, False]
    bad = text.replace("LockPrevious=0", "LockPrevious=0.5")
    err = refusal(bad)
    assert (err.line, err.message) == (line_of(bad, "LockPrevious=0.5"),
                                       "LockPrevious=0.5 must be 0 or 1")


def test_monotonic_sugeno_outputs_are_read_as_tsukamoto_with_a_warning() -> None:
    ramps = sets(1, "y").replace("'trimf',[0 0 10]", "'rampmf',[0 10]").replace(
        "'trimf',[0 10 10]", "'rampmf',[10 0]")
    text = fis(ramps, "1, 1 (1) : 1\n2, 2 (1) : 1\n", SUGENO)
    with pytest.warns(FisFormatWarning) as record:
        fls = loads(text, "fis", path="t.fis")
    assert [str(w.message) for w in record] == [
        "t.fis:20: [Output1] of a Type='sugeno' system has membership functions, not "
        "'constant'/'linear' ones: read as fuzzylite reads it, a Tsukamoto output"]
    assert isinstance(fls, T1Tsukamoto)
    assert (fls.tnorm, fls.snorm) == (TNorm.MINIMUM, SNorm.MAXIMUM)


def test_a_sugeno_output_range_may_be_a_point_its_midpoint_the_default() -> None:
    text = fis(constants(1, "a", [2]).replace("Range=[0 10]", "Range=[4 4]"), "1, 1 (1) : 1\n",
               SUGENO)
    assert loads(text, "fis").on_zero_firing == 4.0


def test_an_output_range_whose_midpoint_overflows_is_refused() -> None:
    text = fis(constants(1, "a", [2]).replace("Range=[0 10]", "Range=[1e308 1.7e308]"),
               "1, 1 (1) : 1\n", SUGENO)
    err = refusal(text)
    assert (err.line, err.message) == (22, "output Range is too wide")
    with_default = text.replace("Range=[1e308 1.7e308]", "Range=[1e308 1.7e308]\nDefault=3")
    assert loads(with_default, "fis").on_zero_firing == 3.0


TIPPER = (DATA / "tipper.fis").read_text()


def edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


@pytest.mark.parametrize(("old", "new", "line", "message"), [
    ("AndMethod='prod'", "AndMethod=''", 41,
     "this rule joins 2 inputs with AND, but AndMethod='' (line 11) names no operator"),
    ("OrMethod='probor'", "OrMethod=''\n", 42,
     "this rule joins 2 inputs with OR, but OrMethod='' (line 12) names no operator"),
])
def test_an_empty_norm_is_refused_where_a_rule_joins_inputs_with_it(old: str, new: str,
                                                                    line: int,
                                                                    message: str) -> None:
    text = edit(TIPPER, old, new)
    if "OrMethod" in old:  # the first rule joins its inputs with OR
        text = edit(text, "1 1, 1 (1) : 1", "1 1, 1 (1) : 2")
    err = refusal(text)
    assert (err.line, err.message) == (line, message)


def test_an_empty_norm_no_rule_needs_is_read() -> None:
    fls = loads(edit(TIPPER, "OrMethod='probor'", "OrMethod=''"), "fis")  # AND rules only
    assert fls.snorm is SNorm.MAXIMUM  # the default, unused
    one = edit(edit(TIPPER, "AndMethod='prod'", "AndMethod=''"), "1 1, 1 (1) : 1",
               "1 0, 1 (1) : 1")
    err = refusal(one)  # rule 3 still joins two inputs with AND
    assert (err.line, err.message) == (43, "this rule joins 2 inputs with AND, but "
                                       "AndMethod='' (line 11) names no operator")


@pytest.mark.parametrize(("old", "new", "line", "message"), [
    ("[0 0 1 3]", "[1 1 2 3]", 29, "trapmf [1 1 2 3] has a left shoulder at x=1 inside the range "
     "[0 10]: MATLAB's trapmf drops to 0 beyond it, which it2track's shoulders (constant "
     "beyond the peak) cannot represent; move the shoulder to the range end"),
    ("[7 9 10 10]", "[7 9 9.5 9.5]", 30, "trapmf [7 9 9.5 9.5] has a right shoulder at x=9.5 "
     "inside the range [0 10]: MATLAB's trapmf drops to 0 beyond it, which it2track's shoulders "
     "(constant beyond the peak) cannot represent; move the shoulder to the range end"),
])
def test_a_shoulder_inside_the_range_is_refused_naming_the_mf(old: str, new: str, line: int,
                                                              message: str) -> None:
    err = refusal(edit(TIPPER, old, new))
    assert (err.line, err.message) == (line, message)


def test_a_type2_mamdani_file_is_an_it2_mamdani_system() -> None:
    system = SYSTEM.replace("hybrid", "mamdani").replace("NumOutputs=3", "NumOutputs=1") + \
        "TypeReductionMethod='karnikmendel'\n"
    lower = ",'LowerScale',0.5,'LowerLag',0"
    text = fis(sets(1, "m"), "1, 1 (1) : 1\n2, 2 (1) : 1\n", system)
    text = text.replace("[0 0 10]\n", f"[0 0 10]{lower}\n").replace("[0 10 10]\n",
                                                                   f"[0 10 10]{lower}\n")
    fls = loads(text, "fis")
    assert isinstance(fls, IT2Mamdani) and fls.reducer is KM
    assert fls.outputs[0].sets[0].lower == Triangle(0.0, 0.0, 10.0, 0.5)


def test_a_type2_hybrid_or_tsukamoto_file_is_refused() -> None:
    for kind in ("hybrid", "tsukamoto"):
        text = fis(sets(1, "m"), "1, 1 (1) : 1\n", SYSTEM.replace("hybrid", kind).replace(
            "NumOutputs=3", "NumOutputs=1") + "TypeReductionMethod='karnikmendel'\n")
        err = refusal(text)
        assert (err.line, err.message) == (3, f"a type-2 system of Type={kind!r}")


def test_a_hybrid_whose_parts_share_an_output_name_is_refused_at_the_system() -> None:
    text = fis(constants(1, "a", [2, 8]) + sets(2, "a"), "1, 1 1 (1) : 1\n",
               SYSTEM.replace("NumOutputs=3", "NumOutputs=2"))
    err = refusal(text)
    assert (err.line, err.message) == (1, "HybridSystem: output names ['a', 'a'] must be distinct")


def test_an_unknown_type_is_refused_naming_the_known_ones() -> None:
    err = refusal(SYSTEM.replace("'hybrid'", "'Fuzzy'") + INPUT)
    assert (err.line, err.message) == (3, "Type='fuzzy' is not supported ('sugeno', 'mamdani', "
                                       "and fuzzylite's 'tsukamoto' and 'hybrid')")


def test_a_tsukamoto_file_and_its_aggregation() -> None:
    ramps = sets(1, "y").replace("'trimf',[0 0 10]", "'rampmf',[0 10]").replace(
        "'trimf',[0 10 10]", "'rampmf',[10 0]")
    system = SYSTEM.replace("'hybrid'", "'Tsukamoto'").replace("NumOutputs=3", "NumOutputs=1")
    system = system.replace("centroid", "wtaver")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fls = loads(fis(ramps, "1, 1 (1) : 1\n2, 2 (1) : 1\n", system), "fis")
        assert isinstance(fls, T1Tsukamoto) and fls.aggregation is Aggregation.MAXIMUM
        plain = loads(fis(ramps, "1, 1 (1) : 1\n", system.replace("AggMethod='max'\n", "")),
                      "fis")
        assert plain.aggregation is Aggregation.SUM


@pytest.mark.parametrize(("kind", "tnorm"), [("sugeno", TNorm.PRODUCT),
                                             ("mamdani", TNorm.MINIMUM),
                                             ("hybrid", TNorm.MINIMUM)])
def test_the_and_method_left_out_is_the_types_default(kind: str, tnorm: TNorm) -> None:
    system = SYSTEM.replace("'hybrid'", f"'{kind}'").replace("NumOutputs=3", "NumOutputs=1")
    system = system.replace("AndMethod='min'\n", "").replace("OrMethod='max'\n", "")
    if kind == "sugeno":
        system = system.replace("centroid", "wtaver")
    out = constants(1, "a", [2]) if kind == "sugeno" else sets(1, "m")
    fls = loads(fis(out, "1, 1 (1) : 1\n", system), "fis")
    assert (fls.tnorm, fls.snorm) == (tnorm, SNorm.MAXIMUM)


def test_a_type2_mamdani_file_is_reduced_by_its_centroid_only() -> None:
    system = SYSTEM.replace("hybrid", "mamdani").replace("NumOutputs=3", "NumOutputs=1") + \
        "TypeReductionMethod='karnikmendel'\n"
    text = fis(sets(1, "m"), "1, 1 (1) : 1\n", system.replace("'centroid'", "'bisector'"))
    lower = ",'LowerScale',0.5,'LowerLag',0"
    text = text.replace("[0 0 10]\n", f"[0 0 10]{lower}\n").replace("[0 10 10]\n",
                                                                   f"[0 10 10]{lower}\n")
    err = refusal(text)
    assert (err.line, err.message) == (11, "DefuzzMethod='bisector' is not supported "
                                       "('centroid')")
    one = fis(sets(1, "m"), "1, 1 (1) : 1\n", SYSTEM.replace("hybrid", "mamdani").replace(
        "NumOutputs=3", "NumOutputs=1").replace("'centroid'", "'bisector'"))
    assert loads(one, "fis").defuzzifier is Defuzzifier.BISECTOR


def test_a_mamdani_file_without_defuzz_method_takes_the_centroid() -> None:
    system = SYSTEM.replace("hybrid", "mamdani").replace("NumOutputs=3", "NumOutputs=1")
    system = system.replace("DefuzzMethod='centroid'\n", "")
    assert loads(fis(sets(1, "m"), "1, 1 (1) : 1\n", system), "fis").defuzzifier is (
        Defuzzifier.CENTROID)
    lower = ",'LowerScale',0.5,'LowerLag',0"
    text = fis(sets(1, "m"), "1, 1 (1) : 1\n", system + "TypeReductionMethod='ekm'\n")
    text = text.replace("[0 0 10]\n", f"[0 0 10]{lower}\n").replace("[0 10 10]\n",
                                                                   f"[0 10 10]{lower}\n")
    assert isinstance(loads(text, "fis"), IT2Mamdani)


@pytest.mark.parametrize(("old", "new", "line", "message"), [
    ("ImpMethod='min'", "ImpMethod=7", 9, "ImpMethod must be a quoted string, e.g. 'text'; "
     "got '7'"),
    ("AggMethod='max'", "AggMethod=7", 10, "AggMethod must be a quoted string, e.g. 'text'; "
     "got '7'"),
])
def test_a_sugeno_files_imp_and_agg_methods_are_ignored_but_must_be_strings(
        old: str, new: str, line: int, message: str) -> None:
    err = refusal(fis(constants(1, "a", [2]), "1, 1 (1) : 1\n", SUGENO.replace(old, new)))
    assert (err.line, err.message) == (line, message)


def test_a_sugeno_file_without_imp_agg_or_defuzz_method_is_read() -> None:
    bare = SUGENO.replace("ImpMethod='min'\n", "").replace("AggMethod='max'\n", "").replace(
        "DefuzzMethod='wtaver'\n", "")
    fls = loads(fis(constants(1, "a", [2, 8]), "1, 1 (1) : 1\n", bare), "fis")
    assert isinstance(fls, T1Sugeno) and fls.defuzzifier is WeightedDefuzzifier.AVERAGE
    summed = loads(fis(constants(1, "a", [2, 8]), "1, 1 (1) : 1\n",
                       SUGENO.replace("'wtaver'", "'wtsum'")), "fis")
    assert summed.defuzzifier is WeightedDefuzzifier.SUM


def test_a_part_that_cannot_be_built_is_refused_at_the_system() -> None:
    system = SYSTEM.replace("hybrid", "mamdani").replace("NumOutputs=3", "NumOutputs=2")
    err = refusal(fis(sets(1, "m") + sets(2, "m"), "1, 1 1 (1) : 1\n", system))
    assert (err.line, err.message) == (1, "output names ['m', 'm'] must be distinct and "
                                       "non-empty")


def test_an_unknown_type_reduction_method_names_the_known_ones() -> None:
    text = (DATA / "scale_lag.fis").read_text().replace("'karnikmendel'", "'km9'")
    err = refusal(text)
    assert (err.line, err.message) == (17, "unknown TypeReductionMethod 'km9' (known: "
                                       "karnikmendel, ekm, iasc, eiasc, exhaustive, nietan, "
                                       "wumendel)")


def test_the_reader_names_a_string_without_a_path() -> None:
    with pytest.raises(FisFormatError) as info:
        matfis.loads("[System]\nName='x'\nType='fuzzy'\n")
    assert str(info.value) == "<string>:3: Type='fuzzy' is not supported ('sugeno', 'mamdani', " \
        "and fuzzylite's 'tsukamoto' and 'hybrid')"

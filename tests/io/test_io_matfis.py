"""MATLAB ``.fis``: type-1 and type-2 reading/writing, shoulders, LowerScale/LowerLag, ranges."""

from __future__ import annotations

import dataclasses
from fractions import Fraction
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
    Trapezoid,
    Triangle,
)
from it2track.io import FisFormatError, UnsupportedFeatureError, dumps, loads
from it2track.io.matfis import lag_foot

DATA = Path(__file__).parent / "data"
TIPPER = (DATA / "tipper.fis").read_text()
T2 = (DATA / "scale_lag.fis").read_text()


def edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def error_of(text: str) -> FisFormatError:
    with pytest.raises(FisFormatError) as info:
        loads(text, "fis", path="m.fis")
    return info.value


def line_with(text: str, needle: str) -> int:
    return next(i for i, line in enumerate(text.split("\n"), 1) if needle in line)


def one_input(sets, rules, **kw) -> IT2Sugeno:
    return IT2Sugeno(inputs=[Input("x", (-1.0, 1.0), sets)], rules=rules, **kw)


@pytest.mark.parametrize(
    ("method", "reducer"),
    [("karnikmendel", KM), ("ekm", EKM), ("iasc", EIASC), ("eiasc", EIASC), ("EIASC", EIASC),
     ("exhaustive", EXHAUSTIVE), ("nietan", NIE_TAN), ("wumendel", WU_MENDEL)],
)
def test_type_reduction_method(method: str, reducer) -> None:
    fls = loads(edit(T2, "'karnikmendel'", f"'{method}'"), "fis")
    assert isinstance(fls, IT2Sugeno) and fls.reducer == reducer


def test_type1_and_type2_are_told_apart_by_type_reduction_method() -> None:
    assert isinstance(loads(TIPPER, "fis"), T1Sugeno)
    assert isinstance(loads(T2, "fis"), IT2Sugeno)
    assert "TypeReductionMethod" not in dumps(heading_fls(0.0), "fis")
    assert "TypeReductionMethod='exhaustive'" in dumps(heading_fls(0.2), "fis")


def test_scale_one_lag_zero_is_a_type1_set() -> None:
    text = edit(T2, "'LowerScale',0.8,'LowerLag',0.5", "'LowerScale',1,'LowerLag',0")
    fls = loads(text, "fis")
    assert fls.inputs[0].sets[0].is_type1


def test_gaussian_scale_and_lag() -> None:
    text = edit(T2, "'trimf',[2 5 8],'LowerScale',0.8,'LowerLag',0.5",
                "'gaussmf',[1.5 5],'LowerScale',0.8,'LowerLag',0.25")
    fls = loads(text, "fis")
    s = fls.inputs[0].sets[0]
    assert s.lower == ScaledLagged(Gaussian(5.0, 1.5), 0.8, 0.25)
    again = loads(dumps(fls, "fis"), "fis")
    x = np.linspace(0, 10, 201)
    assert np.array_equal(fls(x), again(x))
    err = error_of(edit(text, "'LowerLag',0.25", "'LowerLag',[0.25 0.5]"))
    assert err.message.startswith("a two-sided LowerLag needs a trimf or trapmf"), err


def test_lag_foot_is_exact_and_the_writer_finds_a_lag_for_any_foot() -> None:
    assert lag_foot(2.0, 5.0, Fraction("0.5")) == 3.5
    assert lag_foot(8.0, 5.0, Fraction("0.5")) == 6.5
    assert lag_foot(-1.0, -1.0, Fraction("0.7")) == -1.0  # shoulder
    rng = np.random.default_rng(3)
    for _ in range(300):
        a, b, c = np.sort(rng.uniform(-50, 50, 3))
        la, ld = float(rng.uniform(a, b)), float(rng.uniform(b, c))
        s = IT2Set(Triangle(a, b, c), Triangle(la, b, ld, 0.5), "T")
        system = one_input([s], [Rule(["T"], 1.0)])
        system = dataclasses.replace(system, inputs=[Input("x", (a, c), [s])])
        again = loads(dumps(system, "fis"), "fis")
        assert again.inputs[0].sets[0].lower == Triangle(la, b, ld, 0.5)


def test_shoulder_inside_the_range_is_rejected_on_read_and_widened_on_write() -> None:
    text = edit(TIPPER, "'trapmf',[0 0 1 3]", "'trapmf',[0.5 0.5 1 3]")
    err = error_of(text)
    assert err.line == line_with(text, "[0.5 0.5 1 3]")
    assert "left shoulder at x=0.5 inside the range" in err.message
    err = error_of(edit(TIPPER, "'trapmf',[7 9 10 10]", "'trapmf',[7 9 9.5 9.5]"))
    assert "right shoulder at x=9.5" in err.message
    # ours: shoulders inside the universe are written out to its ends
    s = IT2Set.type1(Triangle(-0.5, -0.5, 0.5), "L")
    r = IT2Set.type1(Trapezoid(-0.2, 0.3, 0.6, 0.6), "R")
    system = T1Sugeno(inputs=[Input("x", (-1.0, 1.0), [s, r])],
                      rules=[Rule(["L"], -1.0), Rule(["R"], 1.0)])
    text = dumps(system, "fis")
    assert "MF1='L':'trapmf',[-1 -1 -0.5 0.5]" in text
    assert "MF2='R':'trapmf',[-0.2 0.3 1 1]" in text
    again = loads(text, "fis")
    x = np.linspace(-1.2, 1.2, 1001)
    assert np.array_equal(system(x), again(x))


def test_on_zero_firing_is_the_range_midpoint() -> None:
    fls = heading_fls(0.2)
    assert loads(dumps(fls, "fis"), "fis").on_zero_firing == 0.0
    for value in (0.0, 2.5, 0.1, -7.3, 1e-300):
        text = dumps(dataclasses.replace(fls, on_zero_firing=value), "fis")
        assert loads(text, "fis").on_zero_firing == value, value
    # a range that covers the consequents when the midpoint allows it
    assert "Range=[-12 12]" in dumps(dataclasses.replace(fls, on_zero_firing=0.0), "fis")
    assert "Range=[-12 17]" in dumps(dataclasses.replace(fls, on_zero_firing=2.5), "fis")


@pytest.mark.parametrize(
    ("system", "match"),
    [
        (one_input([IT2Set.type1(Triangle(-1, 0, 1, 0.5), "T")], [Rule(["T"], 1.0)]),
         "height h=0.5"),
        (one_input([IT2Set.from_fou(Triangle(-1, 0, 1), 0.2, "T")], [Rule(["T"], (0.0, 1.0))]),
         "interval consequents"),
        (one_input([IT2Set.gaussian_uncertain_std(0.0, 0.3, 0.5, "G")], [Rule(["G"], 1.0)]),
         "not a LowerScale/LowerLag image"),
        (one_input([IT2Set(Triangle(-1, 0, 1), Triangle(-0.5, 0.1, 0.5, 0.5), "T")],
                   [Rule(["T"], 1.0)]), "not a LowerScale/LowerLag image"),
        (one_input([IT2Set(Triangle(-1, 0, 1), ScaledLagged(Triangle(-1, 0, 1), 0.5, 0.2), "T")],
                   [Rule(["T"], 1.0)]), "ScaledLagged lower MF of a triangle"),
        (one_input([IT2Set.from_fou(Triangle(-1, 0, 1), 0.2, "T")], [Rule(["T"], 1.0)],
                   reducer=EKM.with_max_iter(5)), "max_iter"),
    ],
    ids=["height", "interval", "uncertain-std", "other-peak", "scaled-triangle", "max-iter"],
)
def test_writer_rejects(system, match: str) -> None:
    with pytest.raises(UnsupportedFeatureError, match=match):
        dumps(system, "fis")


MALFORMED = [
    (TIPPER, "DefuzzMethod='wtaver'", "DefuzzMethod='wtmean'", "DefuzzMethod",
     "'wtmean' is not supported"),
    (T2, "DefuzzMethod='wtaver'", "DefuzzMethod='wtsum'", "DefuzzMethod",
     "'wtsum' is not supported"),
    (TIPPER, "'constant',[5]", "'constant',[5 6]", "'constant',[5 6]", "needs one number"),
    (TIPPER, "'gaussmf',[1.5 0]", "'gaussmf',[1.5]", "[1.5]", "gaussmf needs 2"),
    (TIPPER, "'gaussmf',[1.5 0]", "'gaussmf',[0 0]", "[0 0]", "sigma"),
    (TIPPER, "'gaussmf',[1.5 0]", "'gaussmf',[1.5 0],'LowerScale',1", "LowerScale",
     "unknown MF property 'LowerScale'"),
    (TIPPER, "Range=[0 30]", "Range=[0 3O]", "Range=[0 3O]", "bad number '3O'"),
    (T2, ",'LowerScale',0.8,'LowerLag',0.5", ",'LowerScale',0.8", "MF1=",
     "missing 'LowerLag'"),
    (T2, "'LowerScale',0.8", "'LowerScale',1.8", "MF1=", "LowerScale=1.8 must satisfy"),
    (T2, "'LowerLag',0.5", "'LowerLag',1", "MF1=", "LowerLag=1 must satisfy"),
    (T2, "'LowerLag',0.5", "'LowerLag',[0.1 0.2 0.3]", "MF1=", "one number or two"),
    (T2, "'LowerLag',0.5", "'LowerLag',0.5,'LowerLag',0.5", "MF1=", "duplicate MF property"),
    (T2, "'LowerLag',0.5", "'LowerLag',0.5,7", "MF1=", "unexpected text after the parameters"),
    (T2, "'karnikmendel'", "'typereducer9'", "TypeReductionMethod",
     "unknown TypeReductionMethod"),
]


@pytest.mark.parametrize(("base", "old", "new", "needle", "problem"), MALFORMED,
                         ids=[m[4] for m in MALFORMED])
def test_malformed(base: str, old: str, new: str, needle: str, problem: str) -> None:
    text = edit(base, old, new)
    err = error_of(text)
    assert problem in err.message, err
    assert err.line == line_with(text, needle), err

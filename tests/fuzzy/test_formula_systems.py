"""Formula consequents and outputs no rule concludes, in the systems: the numpy evaluation
gives the formula's value per sample (or the zero-firing value), and the compiled kernels, the
code generator and the writers refuse what they do not implement rather than guess."""

from __future__ import annotations

import math

import numpy as np
import pytest

from it2track.codegen.generate import check_supported
from it2track.fuzzy import (
    Input,
    IT2Mamdani,
    IT2Set,
    Linear,
    Output,
    Rule,
    T1Mamdani,
    T1Sugeno,
    Triangle,
    ZeroFiringError,
    kernels,
)
from it2track.fuzzy.formula import Formula, FormulaMembership
from it2track.io import UnsupportedFeatureError, dumps

X = Input("x", (0.0, 10.0), [("lo", Triangle(0, 0, 10)), ("hi", Triangle(0, 10, 10))])
SINE = Formula("3 * x + 5 * sin(x)", "fuzzylite", ("x",))


def _system(**kwargs: object) -> T1Sugeno:
    return T1Sugeno(inputs=[X], rules=[Rule(["lo"], Linear([2.0], 1.0)), Rule(["hi"], SINE)],
                    **kwargs)  # type: ignore[arg-type]


def test_a_formula_consequent_is_evaluated_per_sample() -> None:
    fls = _system()
    x = np.array([0.0, 2.5, 4.0, 10.0])
    lo, hi = 1.0 - x / 10.0, x / 10.0
    expected = (lo * (2.0 * x + 1.0) + hi * (3.0 * x + 5.0 * np.sin(x))) / (lo + hi)
    np.testing.assert_allclose(fls(x), expected, rtol=0, atol=1e-13)
    assert float(fls(4.0)) == pytest.approx(expected[2], abs=1e-13)  # the scalar path agrees
    assert {"formula", "linear"} <= fls.tables.features


def test_a_formula_must_read_one_name_per_input() -> None:
    with pytest.raises(ValueError, match=r"rule 1: formula 'x' reads 2 names for 1 inputs"):
        T1Sugeno(inputs=[X], rules=[Rule(["lo"], 1.0),
                                    Rule(["hi"], Formula("x", "fuzzylite", ("x", "y")))])


def test_kernels_codegen_and_writers_refuse_formulas() -> None:
    fls = _system()
    assert kernels.supported(fls) == "rule features ['formula', 'linear'] are not compiled"
    with pytest.raises(UnsupportedFeatureError, match=r"feature\(s\) a formula consequent "
                       r"\(fuzzylite's Function, jFuzzyLogic's FUNCTION\) that C generation"):
        check_supported(fls)
    for fmt in ("toml", "fis", "fll", "fml", "t2fis"):
        with pytest.raises(UnsupportedFeatureError, match=r"the consequent formula "
                           r"'3 \* x \+ 5 \* sin\(x\)' cannot be written to \." + fmt):
            dumps(fls, fmt)
    tri = FormulaMembership(Formula("1 - abs(x - 5) / 5", "fuzzylite", ("x",)))
    mam = T1Mamdani(inputs=[X], outputs=[Output("y", (0.0, 10.0), [("mid", tri)])],
                    rules=[Rule(["lo"], "mid")])
    with pytest.raises(UnsupportedFeatureError, match=r"set 'mid' of 'y' is a formula"):
        dumps(mam, "fll")
    # the formula set is the triangle it describes
    same = T1Mamdani(inputs=[X], outputs=[Output("y", (0.0, 10.0), [("mid", Triangle(0, 5, 10))])],
                     rules=[Rule(["lo"], "mid")])
    x = np.linspace(0.0, 9.0, 7)
    np.testing.assert_allclose(mam(x), same(x), rtol=0, atol=1e-12)


def test_an_output_no_rule_concludes_is_its_zero_firing_value() -> None:
    rules = [Rule(["lo"], consequents=[(2.0, 2.0), None]),
             Rule(["hi"], consequents=[(8.0, 8.0), None])]
    fls = T1Sugeno(inputs=[X], rules=rules, outputs=("y", "z"), on_zero_firing=(0.0, 5.0))
    assert "idle" in fls.tables.features
    assert kernels.supported(fls) == "rule features ['idle', 'outputs'] are not compiled"
    with pytest.raises(UnsupportedFeatureError, match=r"feature\(s\) an output no rule "
                       r"concludes, several outputs"):
        check_supported(fls)
    out = fls(np.array([0.0, 2.5, 10.0]))
    np.testing.assert_array_equal(out[:, 1], [5.0, 5.0, 5.0])
    np.testing.assert_allclose(out[:, 0], [2.0, 3.5, 8.0], rtol=0, atol=1e-12)
    silent = T1Sugeno(inputs=[X], rules=rules, outputs=("y", "z"))
    with pytest.raises(ZeroFiringError, match="no rule of T1Sugeno '' concludes output 2, and "
                       "it has no on_zero_firing value"):
        silent(1.0)
    first = [r.with_consequents([None, r.consequents[0]]) for r in rules]
    with pytest.raises(ValueError, match="no rule has a consequent for output 1"):
        T1Sugeno(inputs=[X], rules=first, outputs=("y", "z"), on_zero_firing=(0.0, 5.0))
    # a Mamdani output likewise
    sets = [("a", Triangle(0, 2, 4)), ("b", Triangle(6, 8, 10))]
    mam = T1Mamdani(inputs=[X], outputs=[Output("y", (0.0, 10.0), sets),
                                         Output("z", (0.0, 10.0), sets)],
                    rules=[Rule(["lo"], consequents=["a", None])], on_zero_firing=(1.0, 7.0))
    assert mam(2.0)[1] == 7.0 and math.isclose(mam(2.0)[0], 2.0, abs_tol=1e-12)
    it2 = IT2Mamdani(inputs=[X], outputs=[
        Output("y", (0.0, 10.0), [IT2Set(Triangle(0, 2, 4), Triangle(1, 2, 3), "a")]),
        Output("z", (0.0, 10.0), [IT2Set(Triangle(0, 2, 4), Triangle(1, 2, 3), "a")])],
        rules=[Rule(["lo"], consequents=["a", None])], on_zero_firing=(1.0, 7.0))
    assert it2(2.0)[1] == 7.0

"""Writers and the C generator refuse the operators they cannot carry (fuzzylite's norms,
``wtsum``, fuzzylite's midpoint sampling) instead of writing MATLAB's defaults in their place."""

from __future__ import annotations

import dataclasses

import pytest

from it2track.codegen.generate import generate_c
from it2track.fuzzy import (
    Aggregation,
    Implication,
    Input,
    Output,
    Rule,
    Sampling,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Triangle,
    WeightedDefuzzifier,
)
from it2track.io import UnsupportedFeatureError, dumps

X = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
SUGENO = T1Sugeno(inputs=[X], rules=[Rule(["lo"], 0.0), Rule(["hi"], 1.0)])
MAMDANI = T1Mamdani(inputs=[X], outputs=[Output("y", (0, 1), [("a", Triangle(0, 0, 1)),
                                                               ("b", Triangle(0, 1, 1))])],
                    rules=[Rule(["lo"], "a"), Rule(["hi"], "b")])


@pytest.mark.parametrize(("system", "what"), [
    (dataclasses.replace(SUGENO, tnorm=TNorm.EINSTEIN_PRODUCT), "t-norm"),
    (dataclasses.replace(SUGENO, snorm=SNorm.BOUNDED_SUM), "s-norm"),
    (dataclasses.replace(SUGENO, defuzzifier=WeightedDefuzzifier.SUM), "defuzzifier"),
    (dataclasses.replace(MAMDANI, implication=Implication.HAMACHER_PRODUCT), "implication"),
    (dataclasses.replace(MAMDANI, aggregation=Aggregation.EINSTEIN_SUM), "aggregation"),
    (dataclasses.replace(MAMDANI, sampling=Sampling.MIDPOINTS), "sampling"),
], ids=["tnorm", "snorm", "wtsum", "implication", "aggregation", "sampling"])
def test_matlab_formats_refuse_what_they_cannot_name(system, what):
    for fmt in ("fis", "t2fis"):
        with pytest.raises(UnsupportedFeatureError, match=f"cannot carry the {what}"):
            dumps(system, fmt)
    assert dumps(SUGENO, "fis") and dumps(MAMDANI, "fis")  # the defaults still write


def test_toml_refuses_wtsum_and_midpoints_and_keeps_the_norms():
    for system in (dataclasses.replace(SUGENO, defuzzifier=WeightedDefuzzifier.SUM),
                   dataclasses.replace(MAMDANI, sampling=Sampling.MIDPOINTS)):
        with pytest.raises(UnsupportedFeatureError, match=r"\.toml format cannot carry"):
            dumps(system, "toml")
    einstein = dataclasses.replace(SUGENO, tnorm=TNorm.EINSTEIN_PRODUCT)
    assert 'tnorm = "einstein_product"' in dumps(einstein, "toml")


def test_c_generation_refuses_wtsum():
    with pytest.raises(UnsupportedFeatureError, match=r"defuzzifier.*has no C implementation"):
        generate_c(dataclasses.replace(SUGENO, defuzzifier=WeightedDefuzzifier.SUM))

"""Writers and the C generator refuse the operators they cannot carry (fuzzylite's norms,
``wtsum``, fuzzylite's midpoint sampling) instead of writing MATLAB's defaults in their place;
the formats that carry them write them."""

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
from it2track.io import UnsupportedFeatureError, dumps, loads

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
def test_the_toolbox_format_refuses_what_it_cannot_name(system, what):
    with pytest.raises(UnsupportedFeatureError, match=f"cannot carry the {what}"):
        dumps(system, "t2fis")
    assert dumps(SUGENO, "t2fis") and dumps(MAMDANI, "t2fis")  # the defaults still write
    # .fis names the norms and wtsum as Octave and fuzzylite write them; .toml carries all
    if what == "sampling":
        with pytest.raises(UnsupportedFeatureError, match="sampling='midpoints'"):
            dumps(system, "fis")
    else:
        attribute = {"t-norm": "tnorm", "s-norm": "snorm"}.get(what, what)
        again = loads(dumps(system, "fis"), "fis")
        assert getattr(again, attribute) == getattr(system, attribute)
        assert dataclasses.replace(again, on_zero_firing=None) == system
    assert loads(dumps(system, "toml"), "toml") == system


def test_c_generation_refuses_wtsum():
    with pytest.raises(UnsupportedFeatureError, match=r"defuzzifier.*has no C implementation"):
        generate_c(dataclasses.replace(SUGENO, defuzzifier=WeightedDefuzzifier.SUM))

"""Every membership term of the fuzzy core is carried by the formats that can name it: TOML
all of them, ``.fis`` MATLAB's, with bit-exact round trips."""

from __future__ import annotations

import math

import numpy as np
import pytest

import it2track.fuzzy as fz
from it2track.fuzzy import Input, Output, Rule, T1Mamdani, T1Sugeno
from it2track.fuzzy.membership import Term
from it2track.io import UnsupportedFeatureError, dumps, loads

#: one instance of every term class, with a height below 1 where the class has one
TERMS = [
    fz.Bell(0.2, 0.3, 2.0, 0.9), fz.Sigmoid(0.1, 12.0), fz.SigmoidDifference(-0.5, 8.0, 9.0, 0.5),
    fz.SigmoidProduct(-0.6, 9.0, -7.0, 0.6, 0.8), fz.SShape(-0.4, 0.3), fz.ZShape(-0.3, 0.4),
    fz.PiShape(-0.9, -0.2, 0.1, 0.8), fz.GaussianProduct(-0.1, 0.2, 0.3, 0.25),
    fz.Cosine(0.0, 1.2), fz.Spike(0.1, 0.9, 0.7), fz.LinearSShape(-0.5, 0.5),
    fz.LinearZShape(-0.6, 0.2), fz.Ramp(0.7, -0.3), fz.Rectangle(-0.4, 0.45),
    fz.Binary(0.2, math.inf), fz.Concave(0.3, 0.9), fz.Arc(-0.8, 0.1), fz.SemiEllipse(-0.7, 0.6),
    fz.Discrete([(-1.0, 0.0), (-0.2, 1.0), (0.3, 0.25), (1.0, 0.5)], 0.95),
    fz.FootedTrapezoid(-0.5, -0.5, 0.2, 0.6, 0.9), fz.Point(0.25, 0.8),
]


def concrete_terms() -> set[type]:
    found, todo = set(), list(Term.__subclasses__())
    while todo:
        cls = todo.pop()
        todo += cls.__subclasses__()
        if not cls.__name__.startswith("_"):
            found.add(cls)
    return found


def system_of(mfs) -> T1Sugeno:
    sets = [(f"s{k}", mf) for k, mf in enumerate(mfs)]
    rules = [Rule([f"s{k}"], float(k)) for k in range(len(mfs))]
    return T1Sugeno(inputs=[Input("x", (-1.0, 1.0), sets)], rules=rules, on_zero_firing=0.0)


def test_the_list_covers_every_term_class() -> None:
    assert {type(t) for t in TERMS} == concrete_terms()


def test_toml_carries_every_term_bit_exactly() -> None:
    fls = system_of(TERMS)
    again = loads(dumps(fls, "toml"), "toml")
    assert again == fls
    x = np.linspace(-1.0, 1.0, 257)
    assert np.array_equal(again(x), fls(x))
    assert dumps(again, "toml") == dumps(fls, "toml")
    assert 'direction = inf' in dumps(fls, "toml")


def test_fis_carries_matlabs_terms_and_refuses_the_others() -> None:
    matlab = [t for t in TERMS if getattr(t, "MATLAB", None) and getattr(t, "h", 1.0) == 1.0]
    assert len(matlab) >= 6
    fls = system_of(matlab)
    assert loads(dumps(fls, "fis"), "fis") == fls
    with pytest.raises(UnsupportedFeatureError, match="Ramp, which has no MATLAB MF"):
        dumps(system_of([fz.Ramp(0.7, -0.3)]), "fis")
    with pytest.raises(UnsupportedFeatureError, match=r"height h=0\.9"):
        dumps(system_of([fz.Bell(0.2, 0.3, 2.0, 0.9)]), "fis")


def test_mamdani_output_terms_in_toml() -> None:
    out = Output("y", (0.0, 1.0), [("lo", fz.ZShape(0.2, 0.6)), ("hi", fz.SShape(0.4, 0.8))])
    fls = T1Mamdani(inputs=[Input("x", (-1.0, 1.0), [("a", fz.Sigmoid(0.0, -5.0)),
                                                      ("b", fz.Sigmoid(0.0, 5.0))])],
                    rules=[Rule(["a"], "lo"), Rule(["b"], "hi")], outputs=[out])
    again = loads(dumps(fls, "toml"), "toml")
    assert again == fls
    x = np.linspace(-1.0, 1.0, 33)
    assert np.array_equal(again(x), fls(x))

"""it2track's TOML format: validation with paths and lines, and what it carries."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from it2track import heading_fls
from it2track.fuzzy import Gaussian, Input, IT2Set, IT2Sugeno, Rule, ScaledLagged
from it2track.io import FisFormatError, UnsupportedFeatureError, dumps, loads

BASE = (Path(__file__).parent / "data" / "one_input.toml").read_text()


def edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def error_of(text: str) -> FisFormatError:
    with pytest.raises(FisFormatError) as info:
        loads(text, "toml", path="s.toml")
    return info.value


def line_with(text: str, needle: str) -> int:
    return next(i for i, line in enumerate(text.split("\n"), 1) if needle in line)


MALFORMED = [
    ('kind = "it2"', 'kind = "it2"\ncolour = "red"', "colour", "unknown key 'colour'"),
    ('format = "it2track-fuzzy-system"', 'format = "other"', "format", "expected"),
    ("version = 1", "version = 2", "version", "not supported"),
    ('kind = "it2"', 'kind = "it3"', "kind", "must be 'it2' or 't1'"),
    ('kind = "it2"', 'kind = "t1"', "reducer", "applies only to kind = 'it2'"),
    ('reducer = "km"', 'reducer = "fast"', "reducer", "unknown type reducer"),
    ('reducer = "km"', 'reducer = "km"\nreducer_max_iter = 0', "reducer_max_iter",
     "positive integer"),
    ('tnorm = "product"', 'tnorm = "lukasiewicz"', "tnorm", "unknown t-norm"),
    ("universe = [0, 1]", "universe = [1, 0]", "universe", "lo < hi"),
    ("universe = [0, 1]", 'universe = [0, "1"]', "universe", "expected a number"),
    ("universe = [0, 1]", "universe = [0, inf]", "universe", "must be finite"),
    ('type = "triangle", a = -1, b = 0, c = 1 }', 'type = "blob", a = -1, b = 0, c = 1 }',
     "upper =", "unknown MF type 'blob'"),
    ("a = -1, b = 0, c = 1 }", "a = -1, b = 0 }", "upper =", "missing key 'c'"),
    ("a = -1, b = 0, c = 1 }", "a = -1, b = 0, c = 1, e = 2 }", "upper =", "unknown key 'e'"),
    ("a = -1, b = 0, c = 1 }", "a = 1, b = 0, c = -1 }", "upper =", "a <= b <= c"),
    ('if = { x = "low" }', 'if = { y = "low" }', 'y = "low"', "unknown input 'y'"),
    ('if = { x = "low" }', "if = {}", "if = {}", "at least one antecedent"),
    ("then = 0\n", "then = [1, 0]\n", "then = [1, 0]", "lo <= hi"),
    ("then = 0\n", 'then = "zero"\n', 'then = "zero"', "expected a number"),
    ("then = 0\n", "then = [1, 2, 3]\n", "then = [1, 2, 3]", "interval [lo, hi]"),
    ('name = "high"', 'name = "low"', 'name = "low"\nupper', "non-empty and unique"),
    ('lower = { type = "scaled-lagged", scale = 0.5, lag = 0.0 }',
     'mf = { type = "triangle", a = 0, b = 1, c = 2 }\nlower = { type = "triangle", '
     "a = 0, b = 1, c = 2 }", "mf = {", "either 'mf'"),
    ("then = 0\n", "then = 0\nthen = 1\n", "then = 1", "invalid TOML"),
    ('name = "x"', "name = x", "name = x", "invalid TOML"),
]


@pytest.mark.parametrize(("old", "new", "needle", "problem"), MALFORMED,
                         ids=[m[3] for m in MALFORMED])
def test_malformed(old: str, new: str, needle: str, problem: str) -> None:
    text = edit(BASE, old, new)
    err = error_of(text)
    assert problem in err.message, err
    first_line = needle.split("\n")[0]
    expected = line_with(text, first_line)
    if "\n" in needle:  # the second set's name
        expected = [i for i, line in enumerate(text.split("\n"), 1) if first_line in line][1]
    assert err.line == expected, f"{err} (expected line {expected})"


def test_error_messages_name_the_path_inside_the_file() -> None:
    err = error_of(edit(BASE, 'if = { x = "low" }', 'if = { x = "medium" }'))
    assert err.message.startswith("rules[0].if: rule names set 'medium' of input 'x'")
    err = error_of(edit(BASE, "a = -1, b = 0, c = 1, h = 0.5", "a = -1, b = 0, c = 1, h = 2"))
    assert err.message.startswith("inputs[0].sets[0].lower: ")


def test_missing_top_level_keys() -> None:
    err = error_of('format = "it2track-fuzzy-system"\nversion = 1\nkind = "t1"\nrules = []\n')
    assert "missing key 'inputs'" in err.message
    err = error_of(BASE.replace("[[rules]]", "[[other]]"))
    assert "unknown key 'other'" in err.message


def test_written_text_is_valid_toml_and_escapes_strings() -> None:
    fls = heading_fls(0.1)
    odd = IT2Sugeno(
        inputs=[Input('in "1"\t\\', (-1, 1), [IT2Set.from_fou(fls.inputs[0].sets[1].upper,
                                                              0.1, "z\x01é")])],
        rules=[Rule(["z\x01é"], 1.0)], name="a\nb",
    )
    text = dumps(odd, "toml")
    data = tomllib.loads(text)
    assert data["name"] == "a\nb"
    assert data["inputs"][0]["name"] == 'in "1"\t\\'
    again = loads(text, "toml")
    assert again.name == "a\nb" and again.inputs[0].sets[0].name == "z\x01é"


def test_scaled_lagged_of_another_mf_is_nested() -> None:
    g = Gaussian(0.0, 0.5)
    other = Gaussian(0.0, 0.3)
    s = IT2Set(g, ScaledLagged(other, 0.5, 0.1), "S")
    system = IT2Sugeno(inputs=[Input("x", (-1, 1), [s])], rules=[Rule(["S"], (0.0, 1.0))])
    text = dumps(system, "toml")
    assert 'upper = { type = "gaussian", mean = 0.0, sigma = 0.3 }' in text
    again = loads(text, "toml")
    assert again.inputs[0].sets[0].lower == ScaledLagged(other, 0.5, 0.1)
    x = np.linspace(-1, 1, 51)
    assert np.array_equal(system(x), again(x))


def test_unknown_mf_class_is_not_written() -> None:
    class Bump:
        def __call__(self, x):
            return np.clip(1 - np.abs(np.asarray(x, dtype=float)), 0, 1)

    system = IT2Sugeno(inputs=[Input("x", (-1, 1), [("B", Bump())])], rules=[Rule(["B"], 1.0)])
    with pytest.raises(UnsupportedFeatureError, match="Bump"):
        dumps(system, "toml")


def test_negative_zero_survives() -> None:
    fls = heading_fls(0.2)
    rules = list(fls.rules)
    rules[4] = Rule(rules[4].antecedent, -0.0)
    import dataclasses

    system = dataclasses.replace(fls, rules=rules)
    for fmt in ("toml", "t2fis", "fis"):
        again = loads(dumps(system, fmt), fmt)
        assert str(again.rules[4].consequent[0]) == "-0.0", fmt

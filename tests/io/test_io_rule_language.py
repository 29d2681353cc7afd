"""Every new rule-language feature and system kind through every format that can carry it:
NOT, OR (max / probor), weights, first-order consequents, several outputs, Mamdani (type-1
and IT2, centroid and centre-of-sets). Random systems round-trip bit for bit; hand-written
fixtures load to hand-computed values; what a format cannot carry is refused before writing.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from it2track.fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    Aggregation,
    Defuzzifier,
    Gaussian,
    Implication,
    Input,
    IT2Mamdani,
    IT2Set,
    IT2Sugeno,
    Linear,
    Output,
    Rule,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
    TypeReduction,
)
from it2track.io import UnsupportedFeatureError, dumps, load, loads, save

DATA = Path(__file__).parent / "data"


def _input(rng: np.random.Generator, name: str, *, type2: bool) -> Input:
    """Two Gaussians covering the universe (every point fires) and a piecewise set."""
    lo = float(rng.uniform(-2, 0))
    hi = lo + float(rng.uniform(1, 3))
    sets = []
    for k in range(2):
        g = Gaussian(float(rng.uniform(lo, hi)), float(rng.uniform(0.5, 1.0) * (hi - lo)))
        lower = Gaussian(g.mean, g.sigma, float(rng.uniform(0.4, 1.0))) if type2 else g
        sets.append(IT2Set(g, lower, f"G{k}"))
    a, b, c = sorted(float(v) for v in rng.uniform(lo, hi, 3))
    upper = Triangle(a - 0.5, b, c + 0.5)
    lower = Triangle(a - 0.5 + 0.25, b, c + 0.5 - 0.25, 0.8) if type2 else upper
    sets.append(IT2Set(upper, lower, "T"))
    return Input(name, (lo, hi), sets)


def _output(rng: np.random.Generator, name: str, *, type2: bool) -> Output:
    sets = []
    for k, centre in enumerate((-4.0, 0.0, 4.0)):
        w = float(rng.uniform(2.5, 4.0))
        upper = Trapezoid(centre - w, centre - 0.5, centre + 0.5, centre + w)
        lag = float(rng.uniform(0.1, 0.5))
        lower = Trapezoid(centre - w + lag * (w - 0.5), centre - 0.5, centre + 0.5,
                          centre + w - lag * (w - 0.5), 0.7) if type2 else upper
        sets.append(IT2Set(upper, lower, f"O{k}"))
    return Output(name, (-6, 6), sets)


def _rules(rng: np.random.Generator, inputs: list[Input], consequent, n_out: int) -> list[Rule]:
    rules = []
    labels = [[s.name for s in inp.sets] for inp in inputs]
    for k in range(8):
        ant: list[str | None] = [str(rng.choice(lab)) for lab in labels]
        if k < n_out:  # one plain all-Gaussian rule per output: every point has an output
            ant = ["G0"] * len(inputs)
            cons = [consequent(rng) if j == k else None for j in range(n_out)]
            rules.append(Rule(ant, consequents=cons))
            continue
        if rng.random() < 0.3:
            ant[int(rng.integers(len(ant)))] = None
        neg = [bool(rng.random() < 0.3) and a is not None for a in ant]
        cons = [consequent(rng) if rng.random() < 0.8 or j == 0 else None for j in range(n_out)]
        rules.append(Rule(ant, consequents=cons, negated=neg,
                          connective="or" if rng.random() < 0.4 else "and",
                          weight=float(rng.choice([1.0, 0.5, 0.125]))))
    return rules


def sugeno(seed: int, *, type2: bool, interval: bool, n_out: int):
    rng = np.random.default_rng(seed)
    inputs = [_input(rng, f"x{i}", type2=type2) for i in range(2)]

    def consequent(rng: np.random.Generator):
        if rng.random() < 0.5:
            if interval:
                return Linear([(-1.0, float(rng.uniform(-1, 2))), float(rng.normal())],
                              (0.0, float(rng.uniform(0, 1))))
            return Linear([float(rng.normal()), float(rng.normal())], float(rng.normal()))
        y = float(rng.normal(0, 5))
        return (y, y + float(rng.uniform(0, 1))) if interval else y

    rules = _rules(rng, inputs, consequent, n_out)
    opts = {"inputs": inputs, "rules": rules, "name": f"tsk {seed}",
            "tnorm": TNorm.MINIMUM if rng.random() < 0.5 else TNorm.PRODUCT,
            "snorm": SNorm.PROBOR if rng.random() < 0.5 else SNorm.MAXIMUM,
            "outputs": tuple(f"y{k}" for k in range(n_out)) if n_out > 1 else ()}
    if type2 or interval:
        return IT2Sugeno(reducer=[KM, EKM, EIASC, EXHAUSTIVE, NIE_TAN][seed % 5], **opts)
    return T1Sugeno(**opts)


def mamdani(seed: int, *, type2: bool, n_out: int, cos: bool = False,
            defuzzifier: Defuzzifier = Defuzzifier.CENTROID):
    rng = np.random.default_rng(seed)
    inputs = [_input(rng, f"x{i}", type2=type2) for i in range(2)]
    outputs = [_output(rng, f"y{k}", type2=type2) for k in range(n_out)]
    rules = _rules(rng, inputs, lambda r: f"O{int(r.integers(3))}", n_out)
    opts = {"inputs": inputs, "outputs": outputs, "rules": rules, "name": f"mamdani {seed}",
            "tnorm": TNorm.MINIMUM if rng.random() < 0.5 else TNorm.PRODUCT,
            "snorm": SNorm.PROBOR if rng.random() < 0.5 else SNorm.MAXIMUM,
            "implication": [Implication.MINIMUM, Implication.PRODUCT][seed % 2],
            "aggregation": [Aggregation.MAXIMUM, Aggregation.SUM, Aggregation.PROBOR][seed % 3]}
    if type2:
        return IT2Mamdani(reducer=[KM, EKM, EIASC, EXHAUSTIVE, NIE_TAN][seed % 5],
                          type_reduction=TypeReduction.CENTRE_OF_SETS if cos
                          else TypeReduction.CENTROID, **opts)
    return T1Mamdani(defuzzifier=defuzzifier, **opts)


def _points(system, n: int = 400) -> list[np.ndarray]:
    rng = np.random.default_rng(9)
    return [rng.uniform(inp.universe[0] - 0.2, inp.universe[1] + 0.2, n) for inp in system.inputs]


def assert_same_outputs(a, b) -> None:
    x = _points(a)
    yl_a, yr_a = a.interval(*x)
    yl_b, yr_b = b.interval(*x)
    np.testing.assert_array_equal(yl_a, yl_b)
    np.testing.assert_array_equal(yr_a, yr_b)
    assert b.output_names == a.output_names
    assert b.tables.features == a.tables.features


CASES = {
    "toml": [
        lambda s: sugeno(s, type2=True, interval=True, n_out=2),
        lambda s: sugeno(s, type2=False, interval=False, n_out=1),
        lambda s: mamdani(s, type2=True, n_out=2, cos=bool(s % 2)),
        lambda s: mamdani(s, type2=False, n_out=1, defuzzifier=list(Defuzzifier)[s % 5]),
    ],
    "t2fis": [
        lambda s: sugeno(s, type2=True, interval=True, n_out=2),
        lambda s: sugeno(s, type2=True, interval=False, n_out=1),
        lambda s: mamdani(s, type2=True, n_out=1, cos=bool(s % 2)),
        lambda s: mamdani(s, type2=False, n_out=2),
    ],
    "fis": [
        lambda s: sugeno(s, type2=False, interval=False, n_out=2),
        lambda s: mamdani(s, type2=False, n_out=1, defuzzifier=list(Defuzzifier)[s % 5]),
        lambda s: mamdani(s, type2=True, n_out=2),
    ],
}


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize(("fmt", "case"), [(f, k) for f, cases in CASES.items()
                                           for k in range(len(cases))])
def test_round_trip_every_feature(fmt: str, case: int, seed: int) -> None:
    system = CASES[fmt][case](seed)
    text = dumps(system, fmt)
    again = loads(text, fmt)
    assert type(again) is type(system) or (fmt == "t2fis" and not isinstance(
        system, IT2Sugeno | IT2Mamdani))
    assert_same_outputs(system, again)
    if fmt == "fis":  # loads back with on_zero_firing = the middle of the output range
        text = dumps(again, fmt)
        assert_same_outputs(system, loads(text, fmt))
    assert dumps(loads(text, fmt), fmt) == text  # the text is a fixed point
    assert [(r.antecedent, r.negated, r.connective, r.weight) for r in again.rules] == \
        [(r.antecedent, r.negated, r.connective, r.weight) for r in system.rules]
    if fmt == "toml":
        assert again == system


def test_matlab_tipper_fis_file() -> None:
    """MATLAB's tipper.fis loads as a type-1 Mamdani system and gives the evalfis values
    printed in MATLAB's documentation (see the fixture's header)."""
    fls = load(DATA / "tipper_mamdani.fis")
    assert isinstance(fls, T1Mamdani)
    got = fls(np.array([2.0, 4.0, 7.0]), np.array([1.0, 5.0, 8.0]))
    assert np.round(got, 4).tolist() == [7.0169, 14.4585, 20.3414]
    assert float(load(DATA / "tipper_mamdani.fis")(5.0, 5.0)) == pytest.approx(15.0, abs=1e-12)


def test_rule_language_fis_fixture_by_hand() -> None:
    fls = load(DATA / "rule_language.fis")
    assert isinstance(fls, T1Sugeno) and fls.output_names == ("u", "v")
    assert fls.tables.features == {"or", "not", "weights", "linear", "outputs"}
    u, v = fls(0.25, 0.5)
    assert u == pytest.approx(10 / 7, abs=1e-14)
    assert v == pytest.approx(5.2, abs=1e-14)
    assert fls.on_zero_firing == (5.0, 0.0)


@pytest.mark.parametrize(("fmt", "build", "problem"), [
    ("fis", lambda: sugeno(0, type2=True, interval=True, n_out=1), "interval"),
    ("fis", lambda: mamdani(1, type2=True, n_out=1, cos=True), "centre-of-sets"),
    ("fis", lambda: _replace(mamdani(0, type2=False, n_out=1), resolution=51), "resolution"),
    ("fis", lambda: _replace(mamdani(0, type2=False, n_out=1), on_zero_firing=3.0),
     "middle of the output range"),
    ("t2fis", lambda: _replace(mamdani(0, type2=True, n_out=1), resolution=51), "resolution"),
    ("t2fis", lambda: mamdani(0, type2=False, n_out=1, defuzzifier=Defuzzifier.MOM),
     "defuzzifier='mom'"),
    ("t2fis", lambda: _replace(sugeno(0, type2=True, interval=True, n_out=2),
                               on_zero_firing=1.0), "on_zero_firing"),
])
def test_what_a_format_cannot_carry_is_refused_before_writing(
    fmt: str, build, problem: str, tmp_path
) -> None:
    system = build()
    target = tmp_path / f"x.{fmt}"
    with pytest.raises(UnsupportedFeatureError, match=problem):
        save(system, target)
    assert not target.exists()
    save(system, tmp_path / "x.toml")  # TOML carries it
    assert_same_outputs(system, load(tmp_path / "x.toml"))


def _replace(system, **changes):
    import dataclasses

    return dataclasses.replace(system, **changes)


def test_mamdani_t2fis_layout() -> None:
    text = dumps(mamdani(2, type2=True, n_out=1), "t2fis")
    assert "Type='mamdani'" in text and "DefuzzMethod='centroid'" in text
    assert "MF1U='O0U':'trapmf'" in text and "MF1L='O0L':'trapmf'" in text
    cos = dumps(mamdani(3, type2=True, n_out=1, cos=True), "t2fis")
    assert "DefuzzMethod='cos'" in cos


def test_toml_rule_keys_are_checked() -> None:
    text = dumps(sugeno(1, type2=False, interval=False, n_out=1), "toml")
    bad = text.replace('connective = "or"', 'connective = "xor"', 1)
    assert bad != text
    with pytest.raises(ValueError, match="rule connective"):
        loads(bad, "toml")
    bad = text.replace("[[rules]]\n", "[[rules]]\nnot = [\"nope\"]\n", 1)
    with pytest.raises(ValueError, match="'nope' is not an input this rule mentions"):
        loads(bad, "toml")

"""Hand-written files in each format load and evaluate to hand-computed values; malformed ones
fail with ``path:line: problem``."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from it2track.fuzzy import EIASC, KM, IT2Sugeno, T1Sugeno, TNorm, Trapezoid, Triangle
from it2track.io import FisFormatError, load

DATA = Path(__file__).parent / "data"


def line_of(path: Path, needle: str) -> int:
    """1-based number of the first line of ``path`` containing ``needle``."""
    for number, line in enumerate(path.read_text().split("\n"), start=1):
        if needle in line:
            return number
    raise AssertionError(f"{needle!r} not in {path}")


def test_one_input_t2fis() -> None:
    fls = load(DATA / "one_input.t2fis")
    assert isinstance(fls, IT2Sugeno)
    assert fls.name == "one input" and fls.reducer == KM and fls.tnorm is TNorm.PRODUCT
    assert [s.name for s in fls.inputs[0].sets] == ["low", "high"]
    yl, yr = fls.interval(0.25)
    assert float(yl) == pytest.approx(1 / 7, abs=1e-15)
    assert float(yr) == pytest.approx(2 / 5, abs=1e-15)
    assert float(fls(0.25)) == pytest.approx(19 / 70, abs=1e-15)
    assert float(fls(0.5)) == pytest.approx(0.5, abs=1e-15)
    assert float(fls(0.0)) == 0.0
    assert float(fls(-3.0)) == 0.0  # clipped to the universe


def test_two_inputs_interval_t2fis() -> None:
    fls = load(DATA / "two_inputs_interval.t2fis")
    assert isinstance(fls, IT2Sugeno)
    assert fls.reducer == EIASC and fls.tnorm is TNorm.MINIMUM
    assert [r.consequent for r in fls.rules] == [(1.0, 2.0), (3.0, 4.0), (5.0, 5.0)]
    assert fls.rules[2].antecedent == ("B", None)
    lower, upper = fls.firing(4.5, 0.5)
    assert lower.tolist() == pytest.approx([0.2, 0.0, 0.0], abs=1e-15)
    assert upper.tolist() == pytest.approx([math.exp(-0.5), 0.25, 0.25], abs=1e-15)
    yl, yr = fls.interval(4.5, 0.5)
    assert float(yl) == pytest.approx(1.0, abs=1e-14)
    assert float(yr) == pytest.approx(53 / 14, abs=1e-14)
    assert float(fls(4.5, 0.5)) == pytest.approx(67 / 28, abs=1e-14)


def test_tipper_fis() -> None:
    fls = load(DATA / "tipper.fis")
    assert isinstance(fls, T1Sugeno)
    r3 = math.exp(-50 / 9) * 0.5
    assert float(fls(5.0, 8.0)) == pytest.approx((15 + 25 * r3) / (1 + r3), abs=1e-13)
    assert fls.on_zero_firing == 15.0  # MATLAB: mean of the output range


def test_scale_lag_fis() -> None:
    fls = load(DATA / "scale_lag.fis")
    assert isinstance(fls, IT2Sugeno) and fls.reducer == KM
    mid, high = fls.inputs[0].sets
    assert mid.lower == Triangle(3.5, 5.0, 6.5, 0.8)
    assert high.lower == Trapezoid(5.75, 8.0, 10.0, 10.0, 1.0)
    yl, yr = fls.interval(6.0)
    assert float(yl) == pytest.approx(10 / 7, abs=1e-14)
    assert float(yr) == pytest.approx(50 / 9, abs=1e-14)
    assert float(fls(6.0)) == pytest.approx(220 / 63, abs=1e-14)


def test_one_input_toml_matches_the_t2fis() -> None:
    fls = load(DATA / "one_input.toml")
    assert isinstance(fls, IT2Sugeno) and fls.reducer == KM
    assert float(fls(0.25)) == pytest.approx(19 / 70, abs=1e-15)
    same = load(DATA / "one_input.t2fis")
    for x in (0.0, 0.1, 0.25, 0.5, 0.75, 1.0):
        assert float(fls(x)) == pytest.approx(float(same(x)), abs=1e-15)


def test_type1_toml() -> None:
    fls = load(DATA / "type1.toml")
    assert isinstance(fls, T1Sugeno) and fls.tnorm is TNorm.MINIMUM
    assert float(fls(0.0, 1.0)) == 2.0
    assert float(fls(0.0, 2.0)) == -1.5  # no rule fires: on_zero_firing
    a = math.exp(-0.5 * 1.75**2)
    assert float(fls(1.75, 0.5)) == pytest.approx((2 * a - 4 * 0.5) / (a + 0.5), abs=1e-14)


BAD = [
    ("missing_section.t2fis", "NumInputs=2", "missing section [Input2]"),
    ("bad_number.fis", "Range=[0 1O]", "bad number '1O' in Range"),
    ("unknown_mf.t2fis", "'foo'", "unknown MF type 'foo'"),
    ("missing_set.fis", "3 1, 1", "rule names MF 3 of input 'x', which has only 2"),
    ("lower_above_upper.t2fis", "MF1L=", "lower MF Triangle(a=-0.2"),
    ("missing_set.toml", 'x = "Q"', "rule names set 'Q' of input 'x'"),
    ("lower_above_upper.toml", "lower =", "exceeds upper MF"),
]


@pytest.mark.parametrize(("name", "needle", "problem"), BAD, ids=[b[0] for b in BAD])
def test_malformed_file_names_path_line_and_problem(name: str, needle: str, problem: str) -> None:
    path = DATA / "bad" / name
    with pytest.raises(FisFormatError) as info:
        load(path)
    err = info.value
    line = line_of(path, needle)
    assert err.path == str(path)
    assert err.line == line, f"{name}: error at line {err.line}, expected {line}: {err}"
    assert problem in err.message, f"{name}: {err.message!r} lacks {problem!r}"
    assert str(err).startswith(f"{path}:{line}: ")


def test_error_is_a_value_error_and_pickles() -> None:
    import pickle

    err = FisFormatError("f.t2fis", 12, "unknown MF type 'foo'")
    assert isinstance(err, ValueError)
    assert str(err) == "f.t2fis:12: unknown MF type 'foo'"
    again = pickle.loads(pickle.dumps(err))
    assert (again.path, again.line, again.message) == ("f.t2fis", 12, "unknown MF type 'foo'")
    assert str(FisFormatError("f.toml", None, "bad")) == "f.toml: bad"

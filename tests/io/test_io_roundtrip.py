"""Round trips ours -> file -> ours: bit-identical outputs (paper controllers, random systems)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from io_systems import REDUCERS, random_points, random_system

from it2track import heading_fls
from it2track.fuzzy import IT2Sugeno, T1Sugeno, TNorm
from it2track.io import FORMATS, TYPE2, dumps, load, loads, save

PAPER_FOUS = (0.0, 0.1, 0.2, 0.3)


def assert_same_outputs(a: IT2Sugeno | T1Sugeno, b: IT2Sugeno | T1Sugeno, label: str) -> None:
    x = random_points(a, 10_000, seed=7)
    ua, ub = a(*x), b(*x)
    assert np.array_equal(ua, ub), (
        f"{label}: outputs differ, max |diff| = {np.max(np.abs(ua - ub)):.3g}"
    )
    # the scalar fast path as well
    for i in range(0, 10_000, 997):
        point = [float(c[i]) for c in x]
        assert a(*point) == b(*point), f"{label}: scalar output differs at {point}"
    if isinstance(a, IT2Sugeno):
        la, ra = a.interval(*x)
        lb, rb = b.interval(*x)
        assert np.array_equal(la, lb) and np.array_equal(ra, rb), f"{label}: [yl, yr] differ"


@pytest.mark.parametrize("fmt", sorted(FORMATS))
@pytest.mark.parametrize("fou", PAPER_FOUS)
def test_paper_controller_round_trip(fmt: str, fou: float, tmp_path) -> None:
    fls = heading_fls(fou)
    if fmt not in TYPE2 and not isinstance(fls, T1Sugeno):
        pytest.skip(f"{fmt} is type-1 only")
    path = tmp_path / f"paper{FORMATS[fmt][0]}"
    save(fls, path)
    again = load(path)
    assert type(again) is type(fls), f"{fmt}, FoU {fou}: came back as {type(again).__name__}"
    assert again.name == fls.name
    assert again.tnorm is fls.tnorm
    if isinstance(fls, IT2Sugeno):
        assert isinstance(again, IT2Sugeno)
        assert again.reducer == fls.reducer
    assert_same_outputs(fls, again, f"{fmt}, FoU {fou}")


@pytest.mark.parametrize("fmt", sorted(TYPE2))
@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_paper_controller_every_reducer_and_min_tnorm(fmt: str, reducer) -> None:
    fls = heading_fls(0.2, reducer=reducer, tnorm=TNorm.MINIMUM)
    again = loads(dumps(fls, fmt), fmt)
    assert isinstance(again, IT2Sugeno)
    assert again.reducer == reducer and again.tnorm is TNorm.MINIMUM
    assert_same_outputs(fls, again, f"{fmt}, {reducer.name}")


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("fmt", sorted(TYPE2))
def test_random_three_input_system(fmt: str, seed: int) -> None:
    system = random_system(seed)
    again = loads(dumps(system, fmt), fmt)
    assert [i.name for i in again.inputs] == [i.name for i in system.inputs]
    assert [s.name for i in again.inputs for s in i.sets] == [
        s.name for i in system.inputs for s in i.sets
    ]
    assert_same_outputs(system, again, f"{fmt}, seed {seed}")


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_random_type1_system(fmt: str, seed: int) -> None:
    system = random_system(seed, type1=True, identifiers=fmt not in TYPE2)
    again = loads(dumps(system, fmt), fmt)
    assert isinstance(again, T1Sugeno)
    assert_same_outputs(system, again, f"{fmt}, type-1 seed {seed}")


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("fmt", ["toml", "t2fis"])
def test_random_interval_consequents(fmt: str, seed: int) -> None:
    system = random_system(seed, interval=True)
    again = loads(dumps(system, fmt), fmt)
    assert [r.consequent for r in again.rules] == [r.consequent for r in system.rules]
    assert_same_outputs(system, again, f"{fmt}, interval seed {seed}")


@pytest.mark.parametrize("seed", range(3))
def test_toml_carries_everything(seed: int) -> None:
    system = random_system(seed, interval=True, rich=True)
    system = dataclasses.replace(system, on_zero_firing=-0.25,
                                 reducer=system.reducer.with_max_iter(77))
    again = loads(dumps(system, "toml"), "toml")
    assert isinstance(again, IT2Sugeno)
    assert again.on_zero_firing == -0.25
    assert again.reducer.max_iter == 77
    assert again.inputs == system.inputs
    assert again.rules == system.rules
    assert_same_outputs(system, again, f"toml rich seed {seed}")


def test_toml_text_is_a_fixed_point() -> None:
    system = random_system(11, interval=True, rich=True)
    text = dumps(system, "toml")
    assert dumps(loads(text, "toml"), "toml") == text


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_text_is_a_fixed_point_for_the_paper_controller(fmt: str) -> None:
    text = dumps(heading_fls(0.3 if fmt in TYPE2 else 0.0), fmt)
    assert dumps(loads(text, fmt), fmt) == text

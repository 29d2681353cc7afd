"""A SweepPlan built in Python (not from a TOML file) checks its noise levels and seeds when it
is made, as load_sweep_config does: before a store is created or a chunk runs. Before, a NaN or
negative level or a negative seed failed only inside the first chunk, seed 2**63 ended in an
OverflowError, and a seed 1.5 or True was run silently as seed 1."""

from __future__ import annotations

import math

import numpy as np
import pytest

from it2track.experiments.specs import ControllerSpec
from it2track.experiments.sweep import SweepPlan
from it2track.experiments.sweep.refs import TrajectoryRef
from it2track.plant import RobotParams
from it2track.tracking import LoopConfig

BASE = dict(config=LoopConfig(duration=0.2), robots=(RobotParams(),), robot_columns={},
            controllers=(ControllerSpec.from_table({"kind": "flc"}, where="w"),),
            trajectory_refs=(TrajectoryRef("straight"),))
LEVELS = "must be a number in [0, 1e+06] rad (a heading-noise standard deviation)"
SEEDS = "must be an integer in [0, 2**63 - 1] (a seed index)"


def plan(noise_std=(0.1,), seeds=(0,)) -> SweepPlan:
    return SweepPlan(noise_std=noise_std, seeds=seeds, **BASE)


@pytest.mark.parametrize(
    ("noise_std", "message"),
    [
        ((0.1, math.nan), f"SweepPlan.noise_std value nan {LEVELS}"),
        ((-1.0,), f"SweepPlan.noise_std value -1.0 {LEVELS}"),
        ((-5e-324,), f"SweepPlan.noise_std value -5e-324 {LEVELS}"),
        ((math.nextafter(1e6, 2e6),), f"SweepPlan.noise_std value 1000000.0000000001 {LEVELS}"),
        ((math.inf,), f"SweepPlan.noise_std value inf {LEVELS}"),
        ((True,), f"SweepPlan.noise_std value True {LEVELS}"),
        (("0.1",), f"SweepPlan.noise_std value '0.1' {LEVELS}"),
        ((0.1, 0.2, 0.1), "SweepPlan.noise_std=(0.1, 0.2, 0.1) must not repeat a value"),
    ],
)
def test_bad_noise_levels_are_refused_when_the_plan_is_made(noise_std, message: str) -> None:
    with pytest.raises(ValueError) as info:
        plan(noise_std=noise_std)
    assert str(info.value) == message


@pytest.mark.parametrize(
    ("seeds", "message"),
    [
        ((0, -1), f"SweepPlan.seeds value -1 {SEEDS}"),
        ((2**63,), f"SweepPlan.seeds value 9223372036854775808 {SEEDS}"),
        ((1.5,), f"SweepPlan.seeds value 1.5 {SEEDS}"),
        ((1.0,), f"SweepPlan.seeds value 1.0 {SEEDS}"),
        ((True,), f"SweepPlan.seeds value True {SEEDS}"),
        ((1, 2, 1), "SweepPlan.seeds=(1, 2, 1) must not repeat a value"),
    ],
)
def test_bad_seeds_are_refused_when_the_plan_is_made(seeds, message: str) -> None:
    with pytest.raises(ValueError) as info:
        plan(seeds=seeds)
    assert str(info.value) == message


def test_the_boundaries_and_numpy_scalars_are_accepted() -> None:
    p = plan(noise_std=(0.0, 1e6, np.float64(0.5), 2), seeds=(0, 2**63 - 1, np.int64(4)))
    assert p.noise_std == (0.0, 1e6, 0.5, 2.0) and p.seeds == (0, 2**63 - 1, 4)
    assert [type(v) for v in p.noise_std] == [float] * 4  # plain values: JSON, the hash
    assert [type(v) for v in p.seeds] == [int] * 3
    assert len(p.config_hash()) == 64

"""Input checks of the closed loop: LoopConfig, RunTable, run_grid, simulate(_metrics)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from it2track.paper import heading_fls
from it2track.plant import RobotParams
from it2track.tracking import (
    METRIC_NAMES,
    TRACE_FIELDS,
    FuzzyHeadingController,
    LoopConfig,
    PDHeadingController,
    RunTable,
    run_grid,
    simulate,
    simulate_metrics,
    straight,
)

CTRL = [FuzzyHeadingController(fls=heading_fls(0.0))]
TRAJ = [straight()]
TINY = LoopConfig(duration=0.05)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"duration": 0.0}, "duration"),
        ({"duration": -1.0}, "duration"),
        ({"duration": float("nan")}, "duration"),
        ({"duration": "10"}, "duration"),
        ({"duration": True}, "duration"),
        ({"ts": 0.0}, "ts"),
        ({"ts": float("inf")}, "ts"),
        ({"noise_rate": -100.0}, "noise_rate"),
        ({"duration": 1.005, "ts": 0.01}, "duration"),
        ({"duration": 10.0, "ts": 0.03}, "duration"),
        ({"start_pose": (0.0, 0.0)}, "start_pose"),
        ({"start_pose": (0.0, float("nan"), 0.0)}, "start_pose"),
        ({"start_pose": ("a", 0.0, 0.0)}, "start_pose"),
        ({"start_pose": 3.0}, "start_pose"),
        ({"seed": -1}, "seed"),
        ({"seed": 1.5}, "seed"),
        ({"seed": True}, "seed"),
        ({"robot": "paper"}, "robot"),
        ({"quadrature_nodes": 0}, "quadrature_nodes"),
        ({"quadrature_nodes": 2.0}, "quadrature_nodes"),
    ],
)
def test_loop_config_rejects_and_names_the_field(kwargs, field):
    with pytest.raises(ValueError, match=field):
        LoopConfig(**kwargs)


def test_loop_config_accepts_and_normalises():
    cfg = LoopConfig(duration=3, ts=0.02, seed=np.int64(5), start_pose=[1, 2, 0.5])
    assert cfg.n_steps == 150
    assert cfg.seed == 5 and type(cfg.seed) is int
    assert cfg.start_pose == (1.0, 2.0, 0.5)
    assert isinstance(cfg.duration, float)
    assert np.array_equal(cfg.times, np.arange(151) * 0.02)
    assert LoopConfig(duration=10.0, ts=0.01).n_steps == 1000  # 10 / 0.01 is 1000.0000000000001
    assert isinstance(LoopConfig().robot, RobotParams)
    assert dataclasses.replace(cfg, seed=6).seed == 6
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.seed = 1  # type: ignore[misc]


def test_start_pose_is_used():
    cfg = LoopConfig(duration=0.02, start_pose=(1.0, -2.0, 0.25))
    trace = simulate(CTRL, TRAJ, RunTable(0, 0, 0.0, 0), cfg)
    assert (trace["x"][0, 0], trace["y"][0, 0], trace["theta"][0, 0]) == (1.0, -2.0, 0.25)


@pytest.mark.parametrize(
    ("args", "field"),
    [
        ((-1, 0, 0.0, 0), "controller"),
        ((0.5, 0, 0.0, 0), "controller"),
        ((0, [0, -2], 0.0, 0), "trajectory"),
        ((0, 0, -0.1, 0), "noise_std"),
        ((0, 0, np.nan, 0), "noise_std"),
        ((0, 0, np.inf, 0), "noise_std"),
        ((0, 0, 0.0, -3), "seed"),
        ((0, 0, 0.0, [1.0, 2.0]), "seed"),
        ((0, 0, 0.0, [True]), "seed"),
    ],
)
def test_run_table_rejects_and_names_the_field(args, field):
    with pytest.raises(ValueError, match=f"RunTable.{field}"):
        RunTable(*args)


def test_run_table_broadcasts_and_takes():
    runs = RunTable(1, [0, 1, 2], 0.05, 7)
    assert len(runs) == 3
    assert runs.controller.tolist() == [1, 1, 1]
    assert runs.noise_std.dtype == np.float64 and runs.seed.dtype == np.int64
    sub = runs.take([2, 0])
    assert sub.trajectory.tolist() == [2, 0]
    assert len(runs.take(slice(1, None))) == 2
    with pytest.raises(ValueError):
        RunTable([0, 1], [0, 1, 2], 0.0, 0)  # shapes do not broadcast


def test_run_grid_order():
    grid = run_grid(2, 3, [0.0, 0.1], [5, 9])
    assert len(grid) == 24
    # seed fastest, then noise, trajectory, controller
    assert grid.seed[:4].tolist() == [5, 9, 5, 9]
    assert grid.noise_std[:4].tolist() == [0.0, 0.0, 0.1, 0.1]
    assert grid.trajectory[:8].tolist() == [0, 0, 0, 0, 1, 1, 1, 1]
    assert grid.controller.tolist() == [0] * 12 + [1] * 12
    assert run_grid(1, 1, [0.0], 3).seed.tolist() == [0, 1, 2]


@pytest.mark.parametrize("fn", [simulate, simulate_metrics])
def test_simulate_rejects_mismatched_inputs(fn):
    with pytest.raises(ValueError, match="controller 1 but only 1 given"):
        fn(CTRL, TRAJ, RunTable([0, 1], 0, 0.0, 0), TINY)
    with pytest.raises(ValueError, match="trajectory 2 but only 1 given"):
        fn(CTRL, TRAJ, RunTable(0, [0, 2], 0.0, 0), TINY)
    with pytest.raises(ValueError, match="runs must be a RunTable"):
        fn(CTRL, TRAJ, {"controller": [0]}, TINY)
    with pytest.raises(ValueError, match=r"controllers\[1\]"):
        fn([CTRL[0], heading_fls(0.2)], TRAJ, RunTable(0, 0, 0.0, 0), TINY)
    with pytest.raises(ValueError, match=r"trajectories\[0\]"):
        fn(CTRL, ["straight"], RunTable(0, 0, 0.0, 0), TINY)


@pytest.mark.parametrize("batch_size", [0, -1, 2.0, True, None])
def test_simulate_metrics_rejects_bad_batch_size(batch_size):
    with pytest.raises(ValueError, match="batch_size"):
        simulate_metrics(CTRL, TRAJ, RunTable(0, 0, 0.0, 0), TINY, batch_size=batch_size)


def test_empty_run_table():
    runs = RunTable([], [], [], [])
    m = simulate_metrics(CTRL, TRAJ, runs, TINY)
    assert set(m) == set(METRIC_NAMES) and all(v.shape == (0,) for v in m.values())
    trace = simulate(CTRL, TRAJ, runs, TINY)
    assert all(trace[name].shape == (0, TINY.n_steps + 1) for name in TRACE_FIELDS)


def test_simulate_shapes_and_progress():
    runs = RunTable([0, 1], 0, 0.0, [0, 1])
    ctrls = [*CTRL, PDHeadingController(kp=1.0)]
    trace = simulate(ctrls, TRAJ, runs, TINY)
    assert trace.t.shape == (TINY.n_steps + 1,)
    assert set(trace.series) == set(TRACE_FIELDS)
    assert all(trace[name].shape == (2, TINY.n_steps + 1) for name in TRACE_FIELDS)
    assert all(v.shape == (2,) for v in trace.metrics.values())
    assert set(trace.run(1)) == {"t", *TRACE_FIELDS}
    seen: list[int] = []
    simulate_metrics(ctrls, TRAJ, run_grid(2, 1, [0.0], 3), TINY, batch_size=4,
                     progress=seen.append)  # fmt: skip
    assert seen == [4, 2]


def test_runtable_equality_compares_contents():
    from it2track.tracking import RunTable

    a = RunTable([0, 1], 0, 0.1, [3, 4])
    assert a == RunTable([0, 1], [0, 0], [0.1, 0.1], [3, 4])
    assert a != RunTable([0, 1], 0, 0.1, [3, 5])
    assert a != "not a table"


def test_run_grid_takes_numpy_integer_seed_counts():
    import numpy as np

    from it2track.tracking import run_grid

    assert len(run_grid(1, 2, [0.0], np.int64(3))) == 6
    assert len(run_grid(1, 2, [0.0], [np.int64(3)])) == 2

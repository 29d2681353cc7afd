"""Batch independence and common random numbers of the closed loop.

A run's numbers must not depend on the batch it is computed in: its position in the RunTable,
the other runs, the batch size or the chunking of :func:`simulate_metrics`. Everything here is
compared bit for bit (the float64 bit patterns, so even -0.0 vs 0.0 would fail).
"""

from __future__ import annotations

import numpy as np
import pytest

from it2track.paper import heading_fls
from it2track.plant import held_sample_index, noise_samples_needed, run_generator
from it2track.tracking import (
    METRIC_NAMES,
    TRACE_FIELDS,
    FuzzyHeadingController,
    LoopConfig,
    PDHeadingController,
    RunTable,
    curved,
    run_grid,
    simulate,
    simulate_metrics,
    sinusoidal,
    straight,
)

CONTROLLERS = (
    FuzzyHeadingController(fls=heading_fls(0.0), name="FLC"),
    FuzzyHeadingController(fls=heading_fls(0.2), name="IT2 0.2"),
    PDHeadingController(kp=10.0, kd=0.5, name="PD"),
)
TRAJECTORIES = (straight(), curved(), sinusoidal())
# 2 s keeps one-run-at-a-time cheap and still covers the saturated start of the curved case.
SHORT = LoopConfig(duration=2.0, seed=7)


def bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and np.array_equal(bits(a), bits(b))


def describe(runs: RunTable, i: int) -> str:
    return (
        f"run {i} ({CONTROLLERS[runs.controller[i]].name}, "
        f"{TRAJECTORIES[runs.trajectory[i]].name}, sigma={runs.noise_std[i]:g}, "
        f"seed={runs.seed[i]})"
    )


def mixed_runs() -> RunTable:
    """Every controller x trajectory x noise level (incl. 0 and a large 0.6) x 2 seeds,
    shuffled so that neighbours in the table differ in everything."""
    grid = run_grid(len(CONTROLLERS), len(TRAJECTORIES), [0.0, 0.05, 0.6], [0, 3])
    return grid.take(np.random.default_rng(1).permutation(len(grid)))


@pytest.fixture(scope="module")
def mixed():
    runs = mixed_runs()
    return runs, simulate(CONTROLLERS, TRAJECTORIES, runs, SHORT)


def test_batch_equals_runs_one_at_a_time(mixed):
    runs, batch = mixed
    assert len(runs) == 54
    for i in range(len(runs)):
        single = simulate(CONTROLLERS, TRAJECTORIES, runs.take([i]), SHORT)
        case = describe(runs, i)
        for name in TRACE_FIELDS:
            assert same_bits(batch[name][i], single[name][0]), f"{case}: series {name!r}"
        for name in METRIC_NAMES:
            assert same_bits(batch.metrics[name][i : i + 1], single.metrics[name]), (
                f"{case}: metric {name!r}"
            )


@pytest.mark.parametrize("batch_size", [1, 7, 4096])
def test_simulate_metrics_independent_of_batch_size(mixed, batch_size):
    runs, batch = mixed
    got = simulate_metrics(CONTROLLERS, TRAJECTORIES, runs, SHORT, batch_size=batch_size)
    assert set(got) == set(METRIC_NAMES)
    for name in METRIC_NAMES:
        assert same_bits(got[name], batch.metrics[name]), (
            f"batch_size={batch_size}: metric {name!r} differs from simulate()"
        )


def test_result_independent_of_position_and_company():
    """The same (controller, trajectory, sigma, seed index) anywhere in any batch."""
    target = RunTable(1, 2, 0.05, 11)  # IT2 0.2 on the sinusoid, seed index 11
    alone = simulate_metrics(CONTROLLERS, TRAJECTORIES, target, SHORT)
    rng = np.random.default_rng(5)
    for size, pos in ((2, 0), (9, 4), (30, 29), (30, 0)):
        others = RunTable(
            rng.integers(0, 3, size), rng.integers(0, 3, size), rng.uniform(0, 0.5, size),
            rng.integers(0, 10_000, size),
        )  # fmt: skip
        fields = [others.controller, others.trajectory, others.noise_std, others.seed]
        for arr, value in zip(fields, (1, 2, 0.05, 11), strict=True):
            arr[pos] = value
        table = RunTable(*fields)
        got = simulate_metrics(CONTROLLERS, TRAJECTORIES, table, SHORT, batch_size=size)
        for name in METRIC_NAMES:
            assert same_bits(got[name][pos : pos + 1], alone[name]), (
                f"batch of {size}, position {pos}: metric {name!r} differs from the run alone"
            )


def test_big_batch_across_fuzzy_blocks_and_chunks():
    # 4100 runs in one chunk cross the fuzzy system's internal 4096-sample blocks; chunks of
    # 1000 cross simulate_metrics' chunking. A few runs recomputed alone must match.
    cfg = LoopConfig(duration=0.3, seed=3)
    n = 4100
    runs = RunTable(np.arange(n) % 3, np.arange(n) % 2 + 1, 0.2, np.arange(n))
    whole = simulate_metrics(CONTROLLERS, TRAJECTORIES, runs, cfg, batch_size=8192)
    chunked = simulate_metrics(CONTROLLERS, TRAJECTORIES, runs, cfg, batch_size=1000)
    for name in METRIC_NAMES:
        assert same_bits(whole[name], chunked[name]), f"chunks of 1000: metric {name!r}"
    picks = [0, 1, 999, 1000, 4095, 4096, 4099]
    alone = simulate_metrics(CONTROLLERS, TRAJECTORIES, runs.take(picks), cfg, batch_size=1)
    for name in METRIC_NAMES:
        assert same_bits(whole[name][picks], alone[name]), f"runs {picks}: metric {name!r}"


@pytest.mark.parametrize("noise_rate", [100.0, 50.0, 30.0])
def test_common_random_numbers_across_sigma_controller_and_trajectory(noise_rate):
    # noise_rate < 1 / ts: each noise sample is held over several control periods.
    cfg = LoopConfig(duration=2.0, seed=7, noise_rate=noise_rate)
    seed_index = 4
    sigmas = np.array([0.01, 0.05, 0.3, 1.0])
    runs = RunTable([0, 1, 2, 1], [0, 1, 2, 2], sigmas, seed_index)
    trace = simulate(CONTROLLERS, TRAJECTORIES, runs, cfg)
    z = run_generator(cfg.seed, seed_index).standard_normal(
        noise_samples_needed(cfg.duration, cfg.noise_rate)
    )
    hold = held_sample_index(trace.t, cfg.noise_rate)
    if noise_rate == 50.0:
        assert hold[:5].tolist() == [0, 0, 1, 1, 2]
    for i, sigma in enumerate(sigmas):
        case = describe(runs, i)
        theta, meas = trace["theta"][i], trace["theta_meas"][i]
        # At k = 0 the heading is exactly 0, so the measurement is exactly sigma z0.
        assert meas[0] == sigma * z[0], f"{case}: theta_meas - theta at k=0 is not sigma z0"
        # Later: theta + sigma z_j, up to the rounding of that sum.
        noise = meas - theta
        tol = 4e-16 * (1.0 + np.abs(theta) + np.abs(meas))
        assert np.all(np.abs(noise - sigma * z[hold]) <= tol), f"{case}: noise is not sigma z"


def test_noise_free_measurement_is_exact_and_seeds_differ(mixed):
    runs, trace = mixed
    for i in np.flatnonzero(runs.noise_std == 0.0):
        assert same_bits(trace["theta_meas"][i], trace["theta"][i]), describe(runs, i)
        assert same_bits(trace["e_meas"][i], trace["e_true"][i]), describe(runs, i)
    # Different seed indices, or a different base seed, give different noise.
    base = RunTable(0, 0, 0.05, [0, 1])
    a = simulate(CONTROLLERS, TRAJECTORIES, base, SHORT)
    b = simulate(CONTROLLERS, TRAJECTORIES, base, LoopConfig(duration=2.0, seed=8))
    assert not np.array_equal(a["theta_meas"][0], a["theta_meas"][1]), "seed index ignored"
    assert not np.array_equal(a["theta_meas"][0], b["theta_meas"][0]), "LoopConfig.seed ignored"

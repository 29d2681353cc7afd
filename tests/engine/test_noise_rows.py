"""Noise rows are drawn once per distinct seed and call, never for sigma = 0 runs, and sharing
them changes no bit (common random numbers: a run's noise depends on its seed index only)."""

import sys

import numpy as np
import pytest

import it2track.plant.noise as noise_mod
from it2track.paper import heading_fls
from it2track.plant.noise import NoiseRows, standard_noise
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    PDHeadingController,
    RunTable,
    run_grid,
    simulate,
    simulate_metrics,
    sinusoidal,
    straight,
)
from it2track.tracking.simulate import _Engine

simulate_mod = sys.modules["it2track.tracking.simulate"]  # the package re-exports simulate()

CTRLS = [FuzzyHeadingController(fls=heading_fls(0.2)), PDHeadingController(kp=25.0, kd=1.5)]
TRAJS = [straight(), sinusoidal()]
CFG = LoopConfig(duration=0.5, seed=3)


def test_rows_are_standard_noise_and_a_zero_row():
    table = NoiseRows(5, [9, 2, 9, 4], 50)
    assert table.seeds.tolist() == [2, 4, 9]
    np.testing.assert_array_equal(table.rows[:3], standard_noise(5, [2, 4, 9], 50))
    assert table.rows.shape == (4, 50) and not table.rows[3].any()
    _, index = table.lookup([4, 9, 7, 2], [0.1, 1.0, 0.0, 0.3])
    assert index.tolist() == [1, 2, 3, 0]  # seed 7 is noiseless: the zero row
    with pytest.raises(ValueError, match="not drawn"):
        table.lookup([5], [0.1])
    with pytest.raises(ValueError, match="not drawn"):
        NoiseRows(5, [], 50).lookup([0], [0.1])


def test_standard_noise_out_is_filled_with_the_same_draws():
    out = np.full((2, 30), np.nan)
    assert standard_noise(1, [0, 8], 30, out=out) is out
    np.testing.assert_array_equal(out, standard_noise(1, [0, 8], 30))
    with pytest.raises(ValueError, match="out must be"):
        standard_noise(1, [0], 30, out=np.empty((1, 29)))


@pytest.fixture
def draws(monkeypatch):
    """Seed indices of every generator created while the test runs."""
    made: list[int] = []
    real = noise_mod.run_generator

    def counting(seed, index):
        made.append(index)
        return real(seed, index)

    monkeypatch.setattr(noise_mod, "run_generator", counting)
    return made


def test_noiseless_runs_draw_nothing(draws):
    simulate_metrics(CTRLS, TRAJS, run_grid(2, 2, [0.0], 5), CFG)
    simulate(CTRLS, TRAJS, run_grid(2, 2, [0.0], 2), CFG)
    _Engine(TRAJS, CFG).run(CTRLS, run_grid(2, 2, [0.0], 2), record=False)
    assert draws == []


def test_each_seed_is_drawn_once_per_call_across_chunks(draws):
    runs = run_grid(2, 2, [0.0, 0.05, 0.2], [4, 1, 6])  # 36 runs, 3 noisy seeds
    simulate_metrics(CTRLS, TRAJS, runs, CFG, batch_size=5)
    assert sorted(draws) == [1, 4, 6]


def test_beyond_the_table_bound_chunks_draw_their_own(draws, monkeypatch):
    monkeypatch.setattr(simulate_mod, "NOISE_TABLE_BYTES", 0)
    runs = run_grid(1, 1, [0.1], [0, 1])
    simulate_metrics(CTRLS, TRAJS, runs.take([0, 1, 0]), CFG, batch_size=1)
    assert draws == [0, 1, 0]


@pytest.mark.parametrize("bound", [0, 64 << 20])
def test_shared_rows_give_the_chunked_and_the_reference_bits(monkeypatch, bound):
    monkeypatch.setattr(simulate_mod, "NOISE_TABLE_BYTES", bound)
    runs = run_grid(2, 2, [0.0, 0.1, 0.7], [3, 0, 5])
    ref, _ = _Engine(TRAJS, CFG).run(CTRLS, runs, record=False)
    got = simulate_metrics(CTRLS, TRAJS, runs, CFG, batch_size=7)
    for name, value in ref.items():
        assert np.array_equal(got[name].view(np.int64), value.view(np.int64)), name


def test_noiseless_measurement_adds_positive_zero():
    """sigma = 0: theta_meas = theta + 0.0 on both engines (a start heading of -0.0 is
    measured as +0.0, whatever the sign of an undrawn random number)."""
    cfg = LoopConfig(duration=0.05, start_pose=(0.0, 0.0, -0.0))
    runs = RunTable([0, 1], 0, 0.0, [0, 1])
    trace = simulate(CTRLS, TRAJS, runs, cfg)
    _, ref = _Engine(TRAJS, cfg).run(CTRLS, runs, record=True)
    assert np.signbit(trace["theta"][:, 0]).all()
    assert not np.signbit(trace["theta_meas"][:, 0]).any()
    assert not np.signbit(ref["theta_meas"][:, 0]).any()

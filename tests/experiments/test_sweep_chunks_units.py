"""Pieces of work of a grid (sweep/chunks.py) on tiny inputs: which controllers a range of runs
needs, how a chunk decodes its runs (seed fastest), and what the worker function returns for a
two-run chunk. Fast: the mutation run of ``sweep.chunks`` uses these."""

from __future__ import annotations

import os
import pickle
import socket
import time

import numpy as np
import pytest

from it2track.experiments.executors import peak_rss_bytes
from it2track.experiments.specs import ControllerSpec
from it2track.experiments.sweep import chunks as chunks_module
from it2track.experiments.sweep.chunks import (
    DEFAULT_BATCH_SIZE,
    ChunkResult,
    GridChunk,
    grid_chunks,
    simulate_grid_chunk,
)
from it2track.tracking import METRIC_NAMES, LoopConfig, RunTable, get_trajectory, simulate_metrics

CONFIG = LoopConfig(duration=0.2, seed=5)
SPECS = tuple(ControllerSpec.from_table(t, where="w") for t in (
    {"kind": "flc"}, {"kind": "it2", "fou": 0.2}, {"kind": "pd", "kp": 2.0}))
TRAJ = (get_trajectory("straight"), get_trajectory("curved"))


def chunks_of(bounds, **kw) -> list[GridChunk]:
    """A grid of 3 controllers x 2 trajectories x 1 noise level x 2 seeds: 4 runs a
    controller."""
    args = dict(config=CONFIG, controllers=SPECS, trajectories=TRAJ, noise_std=[0.1],
                seeds=[7, 3], bounds=bounds)
    return grid_chunks(**{**args, **kw})


def test_default_batch_size() -> None:
    assert DEFAULT_BATCH_SIZE == 4096
    (chunk,) = chunks_of([(0, 1)])
    assert chunk.batch_size == 4096
    assert GridChunk(0, CONFIG, SPECS, 0, 3, TRAJ, (0.1,), (7, 3), 0, 1).batch_size == 4096


@pytest.mark.parametrize(
    ("bounds", "offset", "n_used"),
    [
        ((0, 4), 0, 1),  # exactly controller 0's runs
        ((4, 8), 1, 1),  # exactly controller 1's
        ((3, 5), 0, 2),  # the last run of 0 and the first of 1
        ((4, 5), 1, 1),
        ((3, 4), 0, 1),
        ((7, 12), 1, 2),  # the last run of 1, all of 2
        ((8, 12), 2, 1),
        ((0, 12), 0, 3),
        ((11, 12), 2, 1),
    ],
)
def test_a_range_carries_only_the_controllers_it_runs(bounds, offset, n_used) -> None:
    (chunk,) = chunks_of([bounds])
    assert chunk.controller_offset == offset
    assert chunk.controllers == SPECS[offset:offset + n_used]
    assert chunk.n_controllers == 3
    assert (chunk.start, chunk.stop, chunk.size) == (*bounds, bounds[1] - bounds[0])
    runs = chunk.runs()
    assert runs.controller.min() == 0 and runs.controller.max() == n_used - 1


def test_chunks_keep_the_grid_and_number_from_first_id() -> None:
    out = chunks_of([(0, 5), (5, 9), (9, 12)], batch_size=3, first_id=10,
                    noise_std=np.array([0, 1]), seeds=np.array([7, 3], dtype=np.int64))
    assert [c.chunk_id for c in out] == [10, 11, 12]
    assert [(c.start, c.stop) for c in out] == [(0, 5), (5, 9), (9, 12)]
    for c in out:
        assert c.config is CONFIG and c.trajectories == TRAJ and c.batch_size == 3
        assert c.n_controllers == 3
        assert c.noise_std == (0, 1) and c.seeds == (7, 3)  # as given (RunTable converts)
        assert all(isinstance(x, tuple) for x in (c.controllers, c.trajectories, c.noise_std,
                                                  c.seeds))
        assert c.runs().noise_std.dtype == np.float64 and c.runs().seed.dtype == np.int64
        pickle.loads(pickle.dumps(c))  # plain data: what worker processes receive
    assert [c.chunk_id for c in chunks_of([(0, 1), (1, 2)])] == [0, 1]
    assert chunks_of([]) == []


def test_a_chunk_decodes_its_runs_seed_fastest() -> None:
    (chunk,) = chunks_of([(3, 9)], noise_std=[0.0, 0.5])  # 8 runs a controller
    runs = chunk.runs()
    # runs 3..8: controller 0 (3..7) then 1 (8); trajectory, noise, seed of each
    assert runs.controller.tolist() == [0, 0, 0, 0, 0, 1]
    assert runs.trajectory.tolist() == [0, 1, 1, 1, 1, 0]
    assert runs.noise_std.tolist() == [0.5, 0.0, 0.0, 0.5, 0.5, 0.0]
    assert runs.seed.tolist() == [3, 7, 3, 7, 3, 7]
    assert runs.noise_std.dtype == np.float64 and runs.seed.dtype == np.int64
    (later,) = chunks_of([(9, 17)], noise_std=[0.0, 0.5])
    assert later.controller_offset == 1
    assert later.runs().controller.tolist() == [0, 0, 0, 0, 0, 0, 0, 1]  # relative to offset


def test_a_chunk_built_by_hand_decodes_int_levels_as_floats() -> None:
    chunk = GridChunk(0, CONFIG, SPECS[1:], 1, 3, TRAJ[:1], (0, 2), (4,), 2, 6)
    runs = chunk.runs()
    assert runs.controller.tolist() == [0, 0, 1, 1]
    assert runs.noise_std.tolist() == [0.0, 2.0, 0.0, 2.0]
    assert runs.noise_std.dtype == np.float64 and runs.seed.tolist() == [4, 4, 4, 4]


def test_the_worker_runs_the_chunk_as_one_simulate_metrics_call(monkeypatch) -> None:
    calls: list[tuple[int, int]] = []

    def recording(controllers, trajectories, runs, config, *, batch_size):
        calls.append((len(runs), batch_size))
        return simulate_metrics(controllers, trajectories, runs, config, batch_size=batch_size)

    monkeypatch.setattr(chunks_module, "simulate_metrics", recording)
    (chunk,) = chunks_of([(3, 5)], batch_size=1, first_id=4)
    before = time.perf_counter()
    result = simulate_grid_chunk(chunk)
    elapsed = time.perf_counter() - before
    assert calls == [(2, 1)]
    assert isinstance(result, ChunkResult) and result.chunk_id == 4
    assert result.worker == f"{socket.gethostname()}:{os.getpid()}"
    assert 0 < result.peak_rss <= peak_rss_bytes()
    assert 0 < result.seconds <= elapsed
    direct = simulate_metrics([SPECS[0].build(), SPECS[1].build()], TRAJ,
                              RunTable([0, 1], [1, 0], [0.1, 0.1], [3, 7]), CONFIG)
    assert list(result.metrics) == list(METRIC_NAMES)
    for name in METRIC_NAMES:
        np.testing.assert_array_equal(result.metrics[name], direct[name], err_msg=name)
    assert np.all(np.isfinite(result.metrics["IAE"])) and result.metrics["IAE"][0] > 0


@pytest.mark.parametrize(
    ("noise_std", "seeds", "message"),
    [
        ((0.1,), (1.5,), "RunTable.seed must hold integers >= 0, got float64 values (e.g. 1.5)"),
        ((0.1,), (True,), "RunTable.seed must hold integers >= 0, got bool values (e.g. True)"),
        ((0.1,), (2**63,),
         "RunTable.seed value 9223372036854775808 is outside the allowed range [0, 2**63 - 1]"),
        ((0.1,), (-1,), "RunTable.seed must hold integers >= 0, got -1"),
        ((float("nan"),), (0,), "RunTable.noise_std value nan must be finite"),
    ],
)
def test_a_chunk_passes_its_values_to_the_run_table_unchanged(noise_std, seeds, message) -> None:
    """Nothing is rounded or cast on the way (a seed 1.5 is not run as seed 1, 2**63 is not an
    OverflowError): the run table refuses what is not a valid run, naming it."""
    for chunk in (GridChunk(0, CONFIG, SPECS, 0, 3, TRAJ, noise_std, seeds, 0, 2),
                  *chunks_of([(0, 2)], noise_std=noise_std, seeds=seeds)):
        with pytest.raises(ValueError) as info:
            chunk.runs()
        assert str(info.value) == message

"""Resumable parameter sweeps: cartesian products of configuration axes, simulated in chunks.

A sweep is the cartesian product of

- **plant parameter sets** ("groups"): every ``[robot]`` / ``[robot.motor]`` key given as a
  list is an axis (``half_track = [5.6, 0.3]``);
- **controllers**: every ``[[controllers]]`` entry is a :class:`~.specs.ControllerSpec` table
  in which any key given as a list is an axis (``kind = "it2"``, ``fou = [0.1, 0.2]``,
  ``ke = [0.5, 1, 2]``); the controller axis is the union of the entries' expansions. Every
  controller is built once while the configuration is parsed, so a bad value or an unreadable
  or malformed controller file is a :class:`~.specs.ConfigError` before anything is written;
- **trajectories**, **noise standard deviations** and **seed indices** (``[sweep]``).

Run order (the row order of ``results.csv``) is group, controller, trajectory, noise, seed,
the seed varying fastest; run ``r`` has the same meaning in every executor and chunk layout.
The noise of a run depends only on ``(sweep.seed, seed index)`` (common random numbers: every
controller, trajectory, noise level and plant sees the same standard-normal sequence for a given
seed index), so a run's metrics are the same whatever the executor, chunk size or worker count.

Runs are split into chunks of at most ``chunk_size`` consecutive runs, never mixing plant
parameter sets; one chunk is one :func:`~it2track.tracking.simulate_metrics` call. A chunk
travels to its worker as a :class:`.GridChunk` -- the specs, trajectories and an index range,
never arrays of runs -- and comes back as metric arrays; only the driver writes the store.

The results store, its files and why it is built that way: :mod:`.store`.
"""

from .chunks import (
    DEFAULT_BATCH_SIZE,
    BuildableSpec,
    ChunkResult,
    GridChunk,
    grid_chunks,
    simulate_grid_chunk,
)
from .config import (
    check_targets,
    expand_axes,
    load_sweep_config,
    parse_noise_levels,
    parse_seeds,
    parse_trajectories,
)
from .plan import DEFAULT_CHUNK_SIZE, STORE_FORMAT, ChunkSpec, SweepPlan
from .refs import ControllerRef, TrajectoryRef
from .runner import SweepSummary, run_sweep
from .store import StoreError, chunk_path, read_results
from .store import digest_path as digest_path

__all__ = [
    "DEFAULT_BATCH_SIZE",
    "DEFAULT_CHUNK_SIZE",
    "STORE_FORMAT",
    "BuildableSpec",
    "ChunkResult",
    "ChunkSpec",
    "ControllerRef",
    "GridChunk",
    "StoreError",
    "SweepPlan",
    "SweepSummary",
    "TrajectoryRef",
    "check_targets",
    "chunk_path",
    "expand_axes",
    "grid_chunks",
    "load_sweep_config",
    "parse_noise_levels",
    "parse_seeds",
    "parse_trajectories",
    "read_results",
    "run_sweep",
    "simulate_grid_chunk",
]

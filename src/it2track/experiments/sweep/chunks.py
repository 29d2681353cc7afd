"""A piece of work and its result: :class:`GridChunk` (a range of runs of one grid, small and
picklable: specs, not arrays), :func:`simulate_grid_chunk` (the worker function) and
:class:`ChunkResult`. Used by sweeps and by the optimiser.
"""

from __future__ import annotations

import os
import socket
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from ...tracking import HeadingController, LoopConfig, RunTable, Target, simulate_metrics
from ..executors import peak_rss_bytes

__all__ = [
    "DEFAULT_BATCH_SIZE",
    "BuildableSpec",
    "ChunkResult",
    "GridChunk",
    "grid_chunks",
    "simulate_grid_chunk",
]

FloatArray = NDArray[np.float64]


DEFAULT_BATCH_SIZE = 4096


class BuildableSpec(Protocol):
    """Anything that describes a controller as plain, picklable data."""

    @property
    def label(self) -> str: ...

    def build(self) -> HeadingController: ...

    def to_dict(self) -> dict[str, Any]: ...


@dataclass(frozen=True)
class GridChunk:
    """A self-contained piece of work: runs ``[start, stop)`` of the grid
    ``controllers x trajectories x noise_std x seeds`` (seed fastest) under ``config``.

    ``controllers`` holds only the specs this range uses: grid controller ``controller_offset
    + i`` is ``controllers[i]``. Small and picklable (specs, not arrays): this is what is
    shipped to worker processes and Dask workers.
    """

    chunk_id: int
    config: LoopConfig
    controllers: tuple[BuildableSpec, ...]
    controller_offset: int
    n_controllers: int
    trajectories: tuple[Target, ...]
    noise_std: tuple[float, ...]
    seeds: tuple[int, ...]
    start: int
    stop: int
    batch_size: int = DEFAULT_BATCH_SIZE

    @property
    def size(self) -> int:
        return self.stop - self.start

    def runs(self) -> RunTable:
        """The chunk's runs, controller indices relative to ``controllers``; the noise levels
        and seeds as given (:class:`~it2track.tracking.RunTable` checks and converts them: a
        seed 1.5 is refused, not run as seed 1)."""
        shape = (self.n_controllers, len(self.trajectories), len(self.noise_std), len(self.seeds))
        c, t, n, s = np.unravel_index(np.arange(self.start, self.stop), shape)
        return RunTable(
            c - self.controller_offset,
            t,
            np.asarray(self.noise_std)[n],
            np.asarray(self.seeds)[s],
        )


@dataclass(frozen=True)
class ChunkResult:
    """Metrics of a :class:`GridChunk` (arrays of shape ``(chunk size,)``, in run order) and
    where/how it was computed."""

    chunk_id: int
    metrics: dict[str, FloatArray]
    worker: str
    peak_rss: int
    seconds: float


def simulate_grid_chunk(chunk: GridChunk) -> ChunkResult:
    """Worker function: build the chunk's controllers and run one ``simulate_metrics`` call."""
    t0 = time.perf_counter()
    controllers = [spec.build() for spec in chunk.controllers]
    metrics = simulate_metrics(
        controllers, chunk.trajectories, chunk.runs(), chunk.config, batch_size=chunk.batch_size
    )
    return ChunkResult(
        chunk_id=chunk.chunk_id,
        metrics=metrics,
        worker=f"{socket.gethostname()}:{os.getpid()}",
        peak_rss=peak_rss_bytes(),
        seconds=time.perf_counter() - t0,
    )


def grid_chunks(
    *,
    config: LoopConfig,
    controllers: Sequence[BuildableSpec],
    trajectories: Sequence[Target],
    noise_std: Sequence[float],
    seeds: Sequence[int],
    bounds: Sequence[tuple[int, int]],
    batch_size: int = DEFAULT_BATCH_SIZE,
    first_id: int = 0,
) -> list[GridChunk]:
    """Tasks for the index ranges ``bounds`` of one grid (used by sweeps and the optimiser)."""
    per_controller = len(trajectories) * len(noise_std) * len(seeds)
    out: list[GridChunk] = []
    for k, (start, stop) in enumerate(bounds):
        c0 = start // per_controller
        c1 = (stop - 1) // per_controller + 1
        out.append(
            GridChunk(
                chunk_id=first_id + k,
                config=config,
                controllers=tuple(controllers[c0:c1]),
                controller_offset=c0,
                n_controllers=len(controllers),
                trajectories=tuple(trajectories),
                noise_std=tuple(noise_std),
                seeds=tuple(seeds),
                start=start,
                stop=stop,
                batch_size=batch_size,
            )
        )
    return out

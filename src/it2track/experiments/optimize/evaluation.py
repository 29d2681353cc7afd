"""Simulating candidates: the metrics of many controllers on one grid of runs
(:func:`evaluate_metrics`) and the training objective of a batch of candidates, logged
(:class:`_Evaluator`).
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...tracking import METRIC_NAMES, LoopConfig, Target
from ..executors import Executor, InProcessExecutor
from ..sweep import DEFAULT_BATCH_SIZE, BuildableSpec, grid_chunks, simulate_grid_chunk
from .config import OptimizeConfig

__all__ = ["evaluate_metrics"]

FloatArray = NDArray[np.float64]


def evaluate_metrics(
    specs: Sequence[BuildableSpec],
    *,
    config: LoopConfig,
    trajectories: Sequence[Target],
    noise_std: Sequence[float],
    seeds: Sequence[int],
    executor: Executor | None = None,
    batch_size: int = DEFAULT_BATCH_SIZE,
) -> dict[str, FloatArray]:
    """Metrics of every spec on the grid trajectories x noise levels x seeds.

    All specs share the seed indices (common random numbers). The specs are split into at most
    ``executor.n_workers`` tasks of whole candidates; each task is one ``simulate_metrics``
    call with many controllers. Results do not depend on the executor.

    Returns
    -------
    dict of str -> ndarray, shape (n_specs, n_trajectories, n_noise, n_seeds)
    """
    executor = executor or InProcessExecutor()
    n = len(specs)
    per = len(trajectories) * len(noise_std) * len(seeds)
    parts = max(1, min(executor.n_workers, n))
    edges = np.linspace(0, n, parts + 1).round().astype(int).tolist()
    bounds = [(a * per, b * per) for a, b in itertools.pairwise(edges) if b > a]
    tasks = grid_chunks(
        config=config, controllers=specs, trajectories=trajectories, noise_std=noise_std,
        seeds=seeds, bounds=bounds, batch_size=batch_size,
    )  # fmt: skip
    out = {name: np.empty(n * per) for name in METRIC_NAMES}
    for task, result in executor.imap_unordered(simulate_grid_chunk, tasks):
        for name in METRIC_NAMES:
            out[name][task.start : task.stop] = result.metrics[name]
    shape = (n, len(trajectories), len(noise_std), len(seeds))
    return {name: value.reshape(shape) for name, value in out.items()}


class _Evaluator:
    """Training objective of candidate batches, with a log of every evaluation."""

    def __init__(self, cfg: OptimizeConfig, executor: Executor) -> None:
        self.cfg = cfg
        self.executor = executor
        self.history: list[dict[str, Any]] = []
        self.seconds = 0.0
        self.runs = 0

    def __call__(
        self, specs: Sequence[BuildableSpec], widths: Sequence[Sequence[float]], phase: str
    ) -> FloatArray:
        cfg = self.cfg
        t0 = time.perf_counter()
        metrics = evaluate_metrics(
            specs, config=cfg.config, trajectories=cfg.trajectories, noise_std=cfg.noise_std,
            seeds=cfg.train_seeds, executor=self.executor, batch_size=cfg.batch_size,
        )  # fmt: skip
        self.seconds += time.perf_counter() - t0
        values = cfg.objective.per_run(metrics).reshape(len(specs), -1).mean(axis=1)
        self.runs += values.size * len(cfg.trajectories) * len(cfg.noise_std) * len(
            cfg.train_seeds
        )
        for w, v in zip(widths, values.tolist(), strict=True):
            self.history.append(
                {"eval": len(self.history), "phase": phase, "widths": list(w), "objective": v}
            )
        return values

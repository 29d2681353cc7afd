"""Running the whole study (:func:`run_study`): tuning, then every run of the plan
(:mod:`~it2track.experiments.study.plan`) in this process or through an executor, then the
rows, the robustness verdicts and the Morris screening.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ...tracking import (
    HeadingController,
    LoopConfig,
    RunTable,
    Trajectory,
    get_trajectory,
    simulate_metrics,
)
from ..analysis import evaluate_claims, ordering_probability
from ..executors import Executor
from ..robustness import judge_variants, morris_analysis
from .config import StudyConfig
from .plan import (
    _experiments,
    _Plan,
    _plan,
    _robustness_experiments,
    _rows_of,
    _sensitivity_experiments,
    _sensitivity_outputs,
)
from .results import StudyResult, figure_data
from .tuning import tune_fuzzy, tune_pd

__all__ = ["run_study"]


@dataclass(frozen=True)
class _Chunk:
    """A slice of one loop's runs with the controllers and trajectories themselves (built and
    read here, once), so a worker needs none of the caller's files."""

    controllers: tuple[HeadingController, ...]
    trajectories: tuple[Trajectory, ...]
    loop: LoopConfig
    runs: RunTable
    batch_size: int
    start: int
    loop_index: int = 0


def _simulate_chunk(chunk: _Chunk) -> dict[str, np.ndarray]:
    """Worker side of :func:`run_study` with an executor (module level: picklable)."""
    return simulate_metrics(chunk.controllers, chunk.trajectories, chunk.runs, chunk.loop,
                            batch_size=chunk.batch_size)


def _simulate_plan(
    plan: _Plan, config: StudyConfig, executor: Executor | None,
    progress: Callable[[int], object] | None,
) -> list[dict[str, np.ndarray]]:
    """Metrics of every run of the plan, per loop (in ``plan.runs`` order)."""
    controllers = tuple(spec.build() for spec in plan.specs)
    trajectories = tuple(get_trajectory(t) for t in config.trajectories)
    if executor is None:
        return [simulate_metrics(controllers, trajectories, runs, loop,
                                 batch_size=config.batch_size, progress=progress)
                for loop, runs in zip(plan.loops, plan.runs, strict=True)]
    chunks = (
        _Chunk(controllers, trajectories, loop,
               runs.take(slice(a, min(a + config.batch_size, len(runs)))), config.batch_size,
               a, li)
        for li, (loop, runs) in enumerate(zip(plan.loops, plan.runs, strict=True))
        for a in range(0, len(runs), config.batch_size)
    )
    out: list[dict[str, np.ndarray]] = [{} for _ in plan.loops]
    for chunk, metrics in executor.imap_unordered(_simulate_chunk, chunks):
        n = len(plan.runs[chunk.loop_index])
        for name, values in metrics.items():
            out[chunk.loop_index].setdefault(name, np.empty(n))[
                chunk.start:chunk.start + values.size] = values
        if progress is not None:
            progress(len(chunk.runs))
    return out


def run_study(
    config: StudyConfig,
    *,
    progress: Callable[[int], object] | None = None,
    executor: Executor | None = None,
    early: StudyResult | None = None,
) -> StudyResult:
    """Run every experiment of the study (see the module docstring).

    Parameters
    ----------
    executor : Executor, optional
        Where the experiments' runs go, in chunks of ``config.batch_size`` (local processes,
        a Dask cluster; see :mod:`it2track.experiments.executors`). Default: this process.
        The numbers do not depend on it. Tuning, traces and surfaces run here.
    progress : callable, optional
        Called with the number of runs finished, as they finish (for a progress bar sized by
        :func:`.study_run_count`).
    early : StudyResult, optional
        :func:`.figure_data` of this ``config``, already computed (``it2track reproduce`` draws
        its figures early): reused instead of simulated again.
    """
    if early is not None and not isinstance(early, StudyResult):
        raise ValueError(f"run_study: early= must be figure_data(config), got {early!r:.80}")
    if early is not None and early.config != config:
        raise ValueError("run_study: early= is figure_data of another config")
    if config.pd is not None:
        pd, pd_record = tune_pd(config, progress)
    else:
        pd, pd_record = None, {}
    tuned, tuning_records = tune_fuzzy(config, pd_record, progress)
    study_exps = _experiments(config, pd, list(tuned.values()))
    variants, rob_exps = _robustness_experiments(config, tuned)
    x_morris, morris_exps = _sensitivity_experiments(config)
    plan = _plan(config, [*study_exps, *rob_exps, *morris_exps])
    metrics = _simulate_plan(plan, config, executor, progress)
    rows = _rows_of(plan, metrics, config.trajectories, names=("paper", "noise", "fou"))

    robustness = None
    if config.robustness is not None:
        variant_rows = [_rows_of(plan, metrics, config.trajectories, experiment=e)
                        for e in rob_exps]
        for r in variant_rows:
            r["experiment"] = np.full(len(r["seed"]), "robustness", dtype=object)
        robustness = judge_variants(
            variants, variant_rows, config=config.robustness, fous=config.fous,
            main_fou=config.main_fou, trajectories=config.trajectories,
            reference_sigma=config.noise_std)
        if x_morris is not None and config.robustness.sensitivity is not None:
            outputs = _sensitivity_outputs(config, plan, metrics, morris_exps)
            sens, ranking = morris_analysis(config.robustness.sensitivity, x_morris, outputs)
            robustness = replace(robustness, sensitivity=sens, sensitivity_ranking=ranking,
                                 sensitivity_points=len(morris_exps))

    tuned_claims: list[Any] = []
    if tuned:
        paper = rows["experiment"] == "paper"
        sub = {k: v[paper] for k, v in rows.items()}
        keep = np.isin(sub["controller"], [s.label for s in tuned.values()])
        sub = {k: v[keep] for k, v in sub.items()}
        back = {s.label: role for role, s in tuned.items()}
        sub["controller"] = np.array([back[c] for c in sub["controller"]], dtype=object)
        tuned_fous = [w for w in config.fous if f"IT2FLC FoU {w:g}" in tuned]
        if "FLC" in tuned and config.main_fou in tuned_fous:
            tuned_claims = [c for c in evaluate_claims(
                sub, fous=tuned_fous, main_fou=config.main_fou,
                trajectories=config.trajectories, experiment="paper")
                if c.id in ("C1", "C2", "C3")]
    ordering = ordering_probability(rows, fous=config.fous, trajectories=config.trajectories)

    return replace(
        early if early is not None else figure_data(config), rows=rows, pd=pd,
        pd_tuning=pd_record, tuned=tuned, tuning=tuning_records, tuned_claims=tuned_claims,
        ordering=ordering, robustness=robustness,
    )

"""Running the whole study (:func:`run_study`): tuning, then every run of the plan
(:mod:`~it2track.experiments.study.plan`) in this process or through an executor, then the
rows, the robustness verdicts and the Morris screening.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ...tracking import (
    FuzzyHeadingController,
    HeadingController,
    LoopConfig,
    RunTable,
    SurfaceTableController,
    Trajectory,
    get_trajectory,
    simulate_metrics,
)
from ..analysis import evaluate_claims, ordering_probability
from ..claimcells import claim_definitions
from ..executors import Executor
from ..replication import replicate_claims
from ..robustness import judge_variants, morris_analysis
from ..sequential import SeedBatch, SettledResult, concat_rows, settle
from ..specs import ControllerKind, ControllerSpec
from ..verdicts import verdict_rows
from .config import StudyConfig
from .plan import (
    _Experiment,
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

__all__ = ["noise_simulator", "run_study"]


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
    """Metrics of every run of the plan, per loop (in ``plan.runs`` order). Each loop's runs
    go with only the controllers they use (a run does not depend on its batch's other
    controllers), so the engine prepares no others."""
    built: dict[int, HeadingController] = {}
    trajectories = tuple(get_trajectory(t) for t in config.trajectories)
    per_loop = []
    for runs in plan.runs:
        used, local = np.unique(runs.controller, return_inverse=True)
        for i in used.tolist():
            if i not in built:
                built[i] = plan.specs[i].build()
        per_loop.append((tuple(built[i] for i in used.tolist()),
                         RunTable(local.reshape(-1).astype(np.int64), runs.trajectory,
                                  runs.noise_std, runs.seed)))
    if executor is None:
        return [simulate_metrics(ctrls, trajectories, runs, loop,
                                 batch_size=config.batch_size, progress=progress)
                for loop, (ctrls, runs) in zip(plan.loops, per_loop, strict=True)]
    chunks = (
        _Chunk(ctrls, trajectories, loop,
               runs.take(slice(a, min(a + config.batch_size, len(runs)))), config.batch_size,
               a, li)
        for li, (loop, (ctrls, runs)) in enumerate(zip(plan.loops, per_loop, strict=True))
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
    grow: Callable[[int], object] | None = None,
    rows_ready: Callable[[StudyResult], object] | None = None,
) -> StudyResult:
    """Run every experiment of the study (see the module docstring).

    The ``noise`` experiment gets its seeds by need (:mod:`~..sequential`): after the plan's
    first round, the (path, sigma) units behind unsettled levels get more realisations, up to
    ``config.verdicts.cap``; the claims are judged on all of them, with the replication
    probability of every level.

    Parameters
    ----------
    executor : Executor, optional
        Where the experiments' runs go, in chunks of ``config.batch_size`` (local processes,
        a Dask cluster; see :mod:`it2track.experiments.executors`). Default: this process.
        The numbers do not depend on it. Tuning, traces and surfaces run here.
    progress : callable, optional
        Called with the number of runs finished, as they finish (for a progress bar sized by
        :func:`.study_run_count`, the runs before any extension round).
    early : StudyResult, optional
        :func:`.figure_data` of this ``config``, already computed (``it2track reproduce`` draws
        its figures early): reused instead of simulated again.
    grow : callable, optional
        Called with the number of runs an extension round of the sequential design adds,
        before they are simulated (to grow a progress bar).
    rows_ready : callable, optional
        Called once the rows are final, before the verdicts are judged, with the result so far
        (rows, tuning, traces and surfaces; no claims or robustness): ``it2track reproduce``
        draws the figures of the rows meanwhile. The returned result has the same rows.
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
    noise_exp = next(e for e in study_exps if e.name == "noise")
    settled, defs, extra_runs = _settle_noise(config, noise_exp, rows, executor, progress,
                                              grow)
    is_noise = rows["experiment"] == "noise"
    rows = concat_rows([{k: v[~is_noise] for k, v in rows.items()}, settled.rows])
    design = config.verdicts
    base = early if early is not None else figure_data(config)
    if rows_ready is not None:
        rows_ready(replace(base, rows=rows, pd=pd, pd_tuning=pd_record, tuned=tuned,
                           tuning=tuning_records))

    robustness = None
    if config.robustness is not None:
        variant_rows = [_rows_of(plan, metrics, config.trajectories, experiment=e)
                        for e in rob_exps]
        for r in variant_rows:
            r["experiment"] = np.full(len(r["seed"]), "robustness", dtype=object)
        robustness = judge_variants(
            variants, variant_rows[:len(variants)], config=config.robustness, fous=config.fous,
            main_fou=config.main_fou, trajectories=config.trajectories,
            reference_sigma=config.noise_std, baseline_batches=variant_rows[len(variants):],
            target=design.target, resamples=design.resamples, seed=design.seed)
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
            tdefs = [d for d in claim_definitions(
                fous=tuned_fous, main_fou=config.main_fou, trajectories=config.trajectories,
                available=sorted(set(sub["controller"]))) if d.id in ("C1", "C2", "C3")]
            tuned_claims = replicate_claims(
                sub, tdefs, evaluate_claims(sub, fous=tuned_fous, main_fou=config.main_fou,
                                            trajectories=config.trajectories,
                                            experiment="paper", claims=tdefs),
                experiment="paper", resamples=design.resamples, seed=design.seed,
                target=design.target)
    ordering = ordering_probability(rows, fous=config.fous, trajectories=config.trajectories)

    return replace(
        base, rows=rows, pd=pd,
        pd_tuning=pd_record, tuned=tuned, tuning=tuning_records, tuned_claims=tuned_claims,
        ordering=ordering, robustness=robustness, claims=settled.claims,
        verdict_rows=verdict_rows(defs, settled.claims),
        seeds_by_level=dict(settled.n), rounds=settled.rounds,
        surface_copy=_surface_copy(config), extra_runs=extra_runs,
    )


def noise_simulator(config: StudyConfig, specs: Sequence[ControllerSpec], *,
                    executor: Executor | None = None,
                    progress: Callable[[int], object] | None = None,
                    grow: Callable[[int], object] | None = None
                    ) -> Callable[[Sequence[SeedBatch]], dict[str, np.ndarray]]:
    """The ``simulate`` callable :func:`~..sequential.settle` takes, for the noise experiment
    of ``config`` (its loop, paths and batch size) on these controllers: each
    :class:`~..sequential.SeedBatch` becomes rows with ``experiment = "noise"``.

    Parameters
    ----------
    config : StudyConfig
        The loop (its plant included), trajectories and batch size.
    specs : sequence of ControllerSpec
        The controllers, found by their labels in the batches' cells.
    executor : Executor, optional
        Where the runs go (default: this process).
    progress : callable, optional
        Called with the number of runs finished, as they finish.
    grow : callable, optional
        Called with the number of runs of each call, before they are simulated.

    Returns
    -------
    callable
        ``simulate(batches) -> rows``.
    """
    spec_of = {s.label: s for s in specs}
    path_index = {t: i for i, t in enumerate(config.trajectories)}

    def simulate(batches: Sequence[SeedBatch]) -> dict[str, np.ndarray]:
        exps = []
        for b in batches:
            cells = list(b.cells)
            path, sigma = cells[0][1], cells[0][2]
            exps.append(_Experiment("noise", tuple(spec_of[c] for c, _, _ in cells), (sigma,),
                                    b.stop - b.start, seed_start=b.start,
                                    trajectories=(path_index[path],)))
        plan = _plan(config, exps)
        if grow is not None:
            grow(plan.n_runs)
        metrics = _simulate_plan(plan, config, executor, progress)
        return _rows_of(plan, metrics, config.trajectories, names=("noise",))

    return simulate


def _settle_noise(config: StudyConfig, noise: _Experiment, rows: dict[str, np.ndarray],
                  executor: Executor | None, progress: Callable[[int], object] | None,
                  grow: Callable[[int], object] | None
                  ) -> tuple[SettledResult, list[Any], int]:
    """The noise experiment's sequential design, from the plan's first round; also the
    number of runs its extension rounds simulated."""
    labels = [s.label for s in noise.specs]
    path_index = {t: i for i, t in enumerate(config.trajectories)}
    defs = claim_definitions(fous=config.fous, main_fou=config.main_fou,
                             trajectories=config.trajectories, available=labels)
    done = [0]

    def counted(n: int) -> None:
        done[0] += n
        if grow is not None:
            grow(n)

    simulate = noise_simulator(config, noise.specs, executor=executor, progress=progress,
                               grow=counted)
    first = {k: v[rows["experiment"] == "noise"] for k, v in rows.items()}
    settled = settle(simulate, claims=defs, controllers=labels,
                     trajectories=config.trajectories, levels=config.noise_levels,
                     design=config.verdicts, rows=first, fous=config.fous,
                     main_fou=config.main_fou)
    # Rows in the grid's order (controller, path, level, seed) whatever the rounds were.
    r = settled.rows
    order = np.lexsort((
        r["seed"], np.array([config.noise_levels.index(s) for s in r["noise_std"].tolist()]),
        np.array([path_index[t] for t in r["trajectory"]]),
        np.array([labels.index(c) for c in r["controller"]])))
    settled.rows = {k: v[order] for k, v in r.items()}
    return settled, defs, done[0]


def _surface_copy(config: StudyConfig) -> dict[str, Any]:
    """The main IT2FLC's surface table and its surface error (D3), if the study has it."""
    copies = config.surface_copies([config.main_fou])
    if not copies:
        return {}
    spec = copies[0]
    table = spec.build()
    assert isinstance(table, SurfaceTableController)
    it2 = ControllerSpec(kind=ControllerKind.IT2, fou=config.main_fou).build()
    assert isinstance(it2, FuzzyHeadingController)
    err = table.surface_error(it2.fls, points=601)
    return {"label": spec.label, "grid": int(table.e_nodes.size), **err}

"""The study's experiments as one plan of distinct runs.

An experiment (:class:`_Experiment`) is a grid of controllers x trajectories x noise levels x
seeds under one loop: the ``paper``, ``noise`` and ``fou`` experiments, one per robustness
variant and one per Morris design point. :func:`_plan` merges them: each distinct (loop,
controller, trajectory, sigma, seed) is simulated once and shared by the rows that need it;
:func:`_rows_of` gives an experiment's rows back. :func:`experiment_sizes` and
:func:`study_run_count` size them without simulating anything.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...tracking import LoopConfig, RunTable, run_grid
from ..baselines import tuned_label
from ..choices import Variant, apply_settings
from ..robustness import morris_design, robustness_variants
from ..specs import ControllerKind, ControllerSpec
from .config import StudyConfig

__all__ = ["experiment_sizes", "study_run_count"]


_FOU_KINDS = (ControllerKind.IT2, ControllerKind.T1_MATCHED, ControllerKind.T1_SLOPE_MATCHED,
              ControllerKind.T1_SURFACE)


def _specs_fou(spec: ControllerSpec) -> float:
    return spec.fou if spec.kind in _FOU_KINDS else 0.0


@dataclass(frozen=True)
class _Experiment:
    """Runs of a grid of controllers x trajectories x noise levels x seeds under one loop.

    ``labels`` (default: the specs' labels) name the controllers in the rows, e.g. the paper
    label of a controller run with other gains in a robustness variant. The seeds are
    ``seed_start .. seed_start + n_seeds - 1`` (an independent batch, or a sequential
    round's extension); ``trajectories`` (indices into the study's; default all) restricts
    the paths.
    """

    name: str
    specs: tuple[ControllerSpec, ...]
    noise_levels: tuple[float, ...]
    n_seeds: int
    loop: LoopConfig | None = None
    labels: tuple[str, ...] | None = None
    seed_start: int = 0
    trajectories: tuple[int, ...] | None = None


def _experiments(config: StudyConfig, pd: ControllerSpec | None,
                 tuned: Sequence[ControllerSpec] = ()) -> list[_Experiment]:
    return [
        _Experiment("paper", tuple(config.paper_controllers(pd, tuned)), (config.noise_std,),
                    config.seeds),
        _Experiment("noise", tuple(config.noise_controllers(pd)), config.noise_levels,
                    config.sweep_seeds),
        _Experiment("fou", tuple(config.fou_controllers()), (config.noise_std,),
                    config.sweep_seeds),
    ]


@dataclass(frozen=True)
class _Plan:
    """The distinct runs behind every row of every experiment.

    The experiments overlap (the paper experiment's controllers at the study's sigma reappear
    in both sweeps with the same seeds, the robustness baseline repeats sweep runs), and
    without noise every seed gives the same run; each distinct (loop, controller, trajectory,
    sigma, seed) is simulated once and its metrics are shared by the rows that need it -- bit
    for bit what separate simulations would give, since a run does not depend on its batch.

    Attributes
    ----------
    specs : tuple of ControllerSpec
        Every controller of the plan (``RunTable.controller`` indexes it).
    loops : tuple of LoopConfig
        Every loop configuration of the plan.
    runs : tuple of RunTable
        The distinct runs of each loop.
    rows : tuple of (experiment, grid, loop index, run index)
        Each experiment's row grid and, per row, the index of its run in ``runs[loop]``.
    """

    specs: tuple[ControllerSpec, ...]
    loops: tuple[LoopConfig, ...]
    runs: tuple[RunTable, ...]
    rows: tuple[tuple[_Experiment, RunTable, int, NDArray[np.intp]], ...]

    @property
    def n_runs(self) -> int:
        return sum(len(r) for r in self.runs)


def _grid(exp: _Experiment, n_traj: int) -> RunTable:
    """The experiment's rows: every seed at noisy levels, seed 0 alone at sigma = 0."""
    paths = np.arange(n_traj) if exp.trajectories is None else np.asarray(exp.trajectories)
    seeds = list(range(exp.seed_start, exp.seed_start + exp.n_seeds))
    parts = []
    for sigma in exp.noise_levels:  # keep the levels' order
        if sigma > 0.0:
            part = run_grid(len(exp.specs), paths.size, [sigma], seeds)
        else:
            part = run_grid(len(exp.specs), paths.size, [0.0], 1)
        parts.append(RunTable(part.controller, paths[part.trajectory], part.noise_std,
                              part.seed))
    if len(parts) == 1:
        return parts[0]
    # Order rows controller, trajectory, level, seed as run_grid does.
    cols = [np.concatenate([getattr(p, k) for p in parts])
            for k in ("controller", "trajectory", "noise_std", "seed")]
    level_pos = {s: i for i, s in enumerate(exp.noise_levels)}
    lev = np.array([level_pos[s] for s in cols[2].tolist()])
    order = np.lexsort((cols[3], lev, cols[1], cols[0]))
    return RunTable(cols[0][order], cols[1][order], cols[2][order], cols[3][order])


def _plan(config: StudyConfig, experiments: Sequence[_Experiment]) -> _Plan:
    spec_index: dict[ControllerSpec, int] = {}
    loop_index: dict[LoopConfig, int] = {}
    keys: list[dict[tuple[int, int, float, int], int]] = []
    rows = []
    n_traj = len(config.trajectories)
    for exp in experiments:
        loop = exp.loop or config.loop
        li = loop_index.setdefault(loop, len(loop_index))
        if li == len(keys):
            keys.append({})
        grid = _grid(exp, n_traj)
        ctrl = [spec_index.setdefault(spec, len(spec_index)) for spec in exp.specs]
        index = np.empty(len(grid), dtype=np.intp)
        table = keys[li]
        for r, (c, t, sigma, seed) in enumerate(zip(
            grid.controller.tolist(), grid.trajectory.tolist(), grid.noise_std.tolist(),
            grid.seed.tolist(), strict=True,
        )):
            key = (ctrl[c], t, sigma, seed if sigma > 0.0 else 0)
            index[r] = table.setdefault(key, len(table))
        rows.append((exp, grid, li, index))
    runs = []
    for table in keys:
        arr = np.array(list(table), dtype=np.float64).reshape(-1, 4)
        runs.append(RunTable(arr[:, 0].astype(np.int64), arr[:, 1].astype(np.int64),
                             arr[:, 2], arr[:, 3].astype(np.int64)))
    return _Plan(specs=tuple(spec_index), loops=tuple(loop_index), runs=tuple(runs),
                 rows=tuple(rows))


def _rows_of(plan: _Plan, metrics: Sequence[dict[str, np.ndarray]],
             trajectories: Sequence[str], names: Sequence[str] | None = None,
             experiment: _Experiment | None = None) -> dict[str, np.ndarray]:
    """The rows of the experiments called ``names`` (or of the one ``experiment``)."""
    parts = []
    for exp, grid, li, index in plan.rows:
        if experiment is not None and exp is not experiment:
            continue
        if names is not None and exp.name not in names:
            continue
        n = len(grid)
        specs = exp.specs
        labels = exp.labels or tuple(s.label for s in specs)
        part: dict[str, np.ndarray] = {
            "experiment": np.full(n, exp.name, dtype=object),
            "trajectory": np.array([trajectories[i] for i in grid.trajectory], dtype=object),
            "controller": np.array([labels[i] for i in grid.controller], dtype=object),
            "kind": np.array([specs[i].kind.value for i in grid.controller], dtype=object),
            "fou": np.array([_specs_fou(specs[i]) for i in grid.controller]),
            "noise_std": grid.noise_std.copy(),
            "seed": grid.seed.copy(),
        }
        part.update({name: values[index] for name, values in metrics[li].items()})
        parts.append(part)
    return {key: np.concatenate([p[key] for p in parts]) for key in parts[0]}


def _variant_specs(config: StudyConfig, variant: Variant,
                   tuned: Mapping[str, ControllerSpec]) -> tuple[list[ControllerSpec], list[str]]:
    """The controllers a variant judges the claims on, and their paper labels."""
    paper = config.paper_fuzzy()
    if variant.tuned:
        specs = [tuned.get(s.label, s) for s in paper]
        return specs, [s.label for s in paper]
    base = paper + config.matched_baselines([config.main_fou])
    # replace() re-derives the label from the new gains (e.g. "FLC Ke 0.5 Kde 1")
    specs = [replace(s, ke=variant.ke, kde=variant.kde, output_gain=variant.output_gain,
                     label="") for s in base]
    return specs, [s.label for s in base]


def _robustness_experiments(config: StudyConfig, tuned: Mapping[str, ControllerSpec]
                            ) -> tuple[list[Variant], list[_Experiment]]:
    """One experiment per variant (the baseline first), then the baseline's other
    independent seed batches (``robustness:batch:j``, seeds ``j n .. (j + 1) n - 1``)."""
    rob = config.robustness
    if rob is None:
        return [], []
    variants = robustness_variants(rob, config.loop)
    exps = []
    for i, v in enumerate(variants):
        specs, labels = _variant_specs(config, v, tuned)
        exps.append(_Experiment(f"robustness:{i}", tuple(specs), v.noise_levels, rob.seeds,
                                loop=v.loop, labels=tuple(labels)))
    base = exps[0]
    for j in range(1, rob.baseline_batches):
        exps.append(replace(base, name=f"robustness:batch:{j}", seed_start=j * rob.seeds))
    return variants, exps


def _sensitivity_roles(config: StudyConfig) -> tuple[str, str, str, str]:
    """Labels of the FLC, narrowest, main and widest IT2FLC (the outputs' controllers)."""
    ws = sorted(config.fous)
    return ("FLC", f"IT2FLC FoU {ws[0]:g}", f"IT2FLC FoU {config.main_fou:g}",
            f"IT2FLC FoU {ws[-1]:g}")


def _sensitivity_experiments(config: StudyConfig) -> tuple[np.ndarray | None, list[_Experiment]]:
    rob = config.robustness
    if rob is None or rob.sensitivity is None:
        return None, []
    sens = rob.sensitivity
    x, points = morris_design(sens)
    roles = _sensitivity_roles(config)
    by_label = {s.label: s for s in config.paper_fuzzy()}
    base = [by_label[r] for r in dict.fromkeys(roles)]
    exps = []
    for j, point in enumerate(points):
        v = apply_settings(config.loop, [config.noise_std], point, choice="morris",
                           value=str(j))
        specs = [replace(s, ke=v.ke, kde=v.kde, label="") for s in base]
        exps.append(_Experiment(f"morris:{j}", tuple(specs), v.noise_levels, sens.seeds,
                                loop=v.loop, labels=tuple(s.label for s in base)))
    return x, exps


def _sensitivity_outputs(config: StudyConfig, plan: _Plan, metrics: Sequence[dict[str, Any]],
                         exps: Sequence[_Experiment]) -> dict[tuple[str, str], np.ndarray]:
    flc, narrow, main, wide = _sensitivity_roles(config)
    outputs: dict[tuple[str, str], list[float]] = {}
    names = (f"ISE {main} - {flc}", f"ISE {wide} - {narrow}")
    for exp in exps:
        rows = _rows_of(plan, metrics, config.trajectories, experiment=exp)
        for traj in config.trajectories:
            mean = {}
            for label in (flc, narrow, main, wide):
                sel = (rows["trajectory"] == traj) & (rows["controller"] == label)
                mean[label] = float(np.mean(rows["ISE"][sel]))
            outputs.setdefault((names[0], traj), []).append(mean[main] - mean[flc])
            outputs.setdefault((names[1], traj), []).append(mean[wide] - mean[narrow])
    return {k: np.asarray(v) for k, v in outputs.items()}


def study_run_count(config: StudyConfig) -> int:
    """Number of simulations :func:`.run_study` performs (tuning, plus the distinct runs of the
    experiments, robustness variants and sensitivity design points), for sizing a progress
    bar."""
    placeholder = None if config.pd is None else ControllerSpec(
        kind=ControllerKind.PD, kp=1.0, label="PD (tuned)")
    tuned = {s.label: replace(s, label=tuned_label(s.label)) for s in config.tuned_roles()}
    plan = _plan(config, _all_experiments(config, placeholder, tuned))
    sizes = experiment_sizes(config)
    return sizes["pd_tuning"] + sizes["fuzzy_tuning"] + plan.n_runs


def _all_experiments(config: StudyConfig, pd: ControllerSpec | None,
                     tuned: Mapping[str, ControllerSpec]) -> list[_Experiment]:
    exps = _experiments(config, pd, list(tuned.values()))
    exps += _robustness_experiments(config, tuned)[1]
    exps += _sensitivity_experiments(config)[1]
    return exps


def experiment_sizes(config: StudyConfig) -> dict[str, int]:
    """Number of rows of each experiment of ``metrics.csv`` (``"noise"``: its first round;
    ``"noise_cap"``: at most, every unit at the sequential design's cap), and of tuning runs
    (``"pd_tuning"``, ``"fuzzy_tuning"``)."""
    pd = None if config.pd is None else ControllerSpec(kind=ControllerKind.PD, kp=1.0)
    tuned = [replace(s, label=tuned_label(s.label)) for s in config.tuned_roles()]
    n_t = len(config.trajectories)

    def per_level(levels: Sequence[float], seeds: int) -> int:
        return sum(seeds if s > 0.0 else 1 for s in levels)

    tunes_pd = config.pd is not None and config.pd.kp is None
    n_fuzzy = 1 + len(config.fous)
    fuzzy_tuning = 0
    if config.tuning is not None and config.pd is not None:
        fuzzy_tuning = (len(config.tuning.candidates) * len(config.tuned_roles())
                        * n_t * config.pd.seeds)
    return {
        "pd_tuning": 0 if not tunes_pd or config.pd is None
        else (len(config.pd.kp_grid) * len(config.pd.kd_grid)
              + n_fuzzy * (config.pd.match_effort or config.tuning is not None))
        * n_t * config.pd.seeds,
        "fuzzy_tuning": fuzzy_tuning,
        "paper": len(config.paper_controllers(pd, tuned)) * n_t
        * per_level((config.noise_std,), config.seeds),
        "noise": len(config.noise_controllers(pd)) * n_t
        * per_level(config.noise_levels, config.sweep_seeds),
    "noise_cap": len(config.noise_controllers(pd)) * n_t
        * per_level(config.noise_levels, config.verdicts.cap),
        "fou": len(config.fou_controllers()) * n_t
        * per_level((config.noise_std,), config.sweep_seeds),
    }

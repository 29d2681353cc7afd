"""The paper's study, reproduced and extended (DESIGN.md sec. 6). Returns data; never plots.

Experiments (all with common random numbers: seed index ``i`` is the same noise realisation for
every controller, trajectory and noise level):

``paper``
    Monte Carlo at the study's noise level ``noise_std``: the FLC, the IT2FLCs of the paper's FoU
    widths, the fair baselines (type-1 FLCs with the IT2FLCs' dead zones, a tuned PD) and any
    extra controllers, on every trajectory, over ``seeds`` realisations.
``noise``
    Noise-level sweep: FLC, the IT2FLCs, the dead-zone-matched type-1 FLC of ``main_fou`` and
    the PD over ``noise_levels``, ``sweep_seeds`` realisations each.
``fou``
    Continuous FoU sweep: IT2FLC(w) and the dead-zone-matched type-1 FLC(w) for every ``w`` in
    ``fou_sweep`` (``w = 0`` is the FLC), at ``noise_std``, ``sweep_seeds`` realisations.

Plus the time series of one realisation (``figure_seed``) for the paper's figures 7-10, and the
control surfaces of every fuzzy controller. The PD baseline is tuned on seed indices disjoint
from the evaluation seeds (see :func:`tune_pd`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..fuzzy import control_surface
from ..tracking import (
    FuzzyHeadingController,
    HeadingController,
    LoopConfig,
    PDHeadingController,
    RunTable,
    Trace,
    Trajectory,
    get_trajectory,
    run_grid,
    simulate,
    simulate_metrics,
)
from .executors import Executor
from .specs import (
    ConfigError,
    ControllerKind,
    ControllerSpec,
    Table,
    loop_config_from_table,
    read_toml,
    robot_from_table,
)

__all__ = [
    "PDTuning",
    "StudyConfig",
    "StudyResult",
    "experiment_sizes",
    "load_study_config",
    "run_study",
    "study_run_count",
    "tune_pd",
]

FloatArray = NDArray[np.float64]

#: Offset of the seed indices used to tune the PD baseline (disjoint from evaluation seeds).
TUNING_SEED_OFFSET = 1_000_000


@dataclass(frozen=True, kw_only=True)
class PDTuning:
    """How the PD baseline is tuned (documented procedure, reported in the study).

    A grid search over ``kp`` x ``kd`` (log-spaced; all candidates simulated in one batch) on
    ``seeds`` tuning realisations (seed indices ``1_000_000 + i``, never used for evaluation)
    at the study's noise level, over the study's trajectories: the gains with the smallest
    mean ISE of the true heading error among those whose mean control effort (integral of
    ``u^2``) is at most the limit. With ``match_effort`` (default) the limit is the largest mean
    effort of the paper's fuzzy controllers (FLC and the IT2FLCs) on the same tuning runs: the
    PD may work as hard as the most active of them, not harder. Otherwise it is
    ``effort_limit`` V^2 s (``None``: unconstrained -- the ISE-optimal PD then chatters between
    the voltage limits, ~400 V^2 s, which is no fair comparison). ``kp``/``kd`` set explicitly
    skip tuning.

    Parameters
    ----------
    seeds : int
        Tuning realisations (>= 1).
    kp_grid, kd_grid : tuple of float
        Candidate gains (non-empty, finite, >= 0; ``kp`` > 0).
    tf : float
        Derivative filter time constant, s (>= 0).
    match_effort : bool
        Limit the effort to the fuzzy controllers' (see above).
    effort_limit : float or None
        Fixed effort limit, V^2 s (> 0), used only with ``match_effort = False``.
    kp, kd : float or None
        Given gains (skip tuning); ``kd`` needs ``kp``.
    """

    seeds: int = 16
    kp_grid: tuple[float, ...] = tuple(float(round(v, 4)) for v in np.geomspace(1.0, 640.0, 15))
    kd_grid: tuple[float, ...] = (
        0.0, *(float(round(v, 4)) for v in np.geomspace(0.01, 8.0, 10))
    )
    tf: float = 0.02
    match_effort: bool = True
    effort_limit: float | None = None
    kp: float | None = None
    kd: float | None = None

    def __post_init__(self) -> None:
        def bad(key: str, why: str) -> ValueError:
            return ValueError(f"pd {key}={getattr(self, key)!r}: {why}")

        if isinstance(self.seeds, bool) or not isinstance(self.seeds, int) or self.seeds < 1:
            raise bad("seeds", "must be an integer >= 1")
        for key, positive in (("kp_grid", True), ("kd_grid", False)):
            grid = getattr(self, key)
            if not grid or not all(math.isfinite(v) and (v > 0 if positive else v >= 0)
                                   for v in grid):
                raise bad(key, "must be a non-empty list of finite gains "
                          + ("> 0" if positive else ">= 0"))
        if not math.isfinite(self.tf) or self.tf < 0:
            raise bad("tf", "must be finite and >= 0")
        if self.effort_limit is not None:
            if not math.isfinite(self.effort_limit) or self.effort_limit <= 0:
                raise bad("effort_limit", "must be finite and > 0")
            if self.match_effort:
                raise bad("effort_limit", "is used only with match_effort = false")
        if self.kd is not None and self.kp is None:
            raise bad("kd", "given without kp (give both to skip tuning)")


@dataclass(frozen=True, kw_only=True)
class StudyConfig:
    """Everything the study runs; ``configs/paper.toml`` holds the defaults.

    Parameters
    ----------
    loop : LoopConfig
        Duration, period, robot, noise rate, start pose and base seed.
    trajectories : tuple of str
        Built-in names or CSV waypoint files.
    fous : tuple of float
        The IT2FLC widths compared (the paper's 0.1, 0.2, 0.3).
    main_fou : float
        The paper's main IT2FLC (Table 1), shown against the FLC in Figs. 7-9.
    noise_std : float
        Heading-noise standard deviation of the Monte Carlo and the figures, rad.
    noise_levels : tuple of float
        Noise sweep levels, rad.
    fou_sweep : tuple of float
        FoU widths of the continuous sweep.
    seeds, sweep_seeds : int
        Realisations per cell in the ``paper`` experiment and in the sweeps.
    figure_seed : int
        Seed index of the time series shown in the figures.
    matched_baseline : bool
        Include the dead-zone-matched type-1 FLCs.
    pd : PDTuning or None
        PD baseline tuning (None: no PD baseline).
    extra_controllers : tuple of ControllerSpec
        The user's own controllers (e.g. ``kind = "file"``), added to every experiment.
    batch_size : int
        Runs per simulation chunk (memory vs speed; results do not depend on it).
    """

    loop: LoopConfig = field(default_factory=LoopConfig)
    trajectories: tuple[str, ...] = ("straight", "curved", "sinusoidal")
    fous: tuple[float, ...] = (0.1, 0.2, 0.3)
    main_fou: float = 0.2
    noise_std: float = 0.05
    noise_levels: tuple[float, ...] = (0.0, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5)
    fou_sweep: tuple[float, ...] = tuple(round(0.02 * i, 2) for i in range(21))
    seeds: int = 200
    sweep_seeds: int = 100
    figure_seed: int = 0
    matched_baseline: bool = True
    pd: PDTuning | None = field(default_factory=PDTuning)
    extra_controllers: tuple[ControllerSpec, ...] = ()
    batch_size: int = 4096

    def __post_init__(self) -> None:
        def bad(key: str, why: str) -> ValueError:
            return ValueError(f"study {key}={getattr(self, key)!r}: {why}")

        if not self.trajectories:
            raise bad("trajectories", "needs at least one trajectory")
        if not self.fous or any(not 0.0 < w < 1.6 for w in self.fous):
            raise bad("fous", "needs widths in (0, 1.6)")
        if self.main_fou not in self.fous:
            raise bad("main_fou", f"must be one of fous={self.fous}")
        for key in ("noise_std",):
            v = getattr(self, key)
            if not math.isfinite(v) or v < 0:
                raise bad(key, "must be finite and >= 0")
        if not self.noise_levels or any(not math.isfinite(v) or v < 0 for v in self.noise_levels):
            raise bad("noise_levels", "needs finite levels >= 0")
        if not self.fou_sweep or any(not 0.0 <= w < 1.6 for w in self.fou_sweep):
            raise bad("fou_sweep", "needs widths in [0, 1.6)")
        for key in ("seeds", "sweep_seeds", "batch_size"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise bad(key, "must be an integer >= 1")
        if self.figure_seed < 0:
            raise bad("figure_seed", "must be >= 0")
        for key in ("trajectories", "fous", "noise_levels", "fou_sweep"):
            values = list(getattr(self, key))
            if len(set(values)) != len(values):
                dup = next(v for v in values if values.count(v) > 1)
                raise bad(key, f"lists {dup!r} twice (repeats would pool as extra samples)")
        labels = [s.label for s in self.extra_controllers]
        if len(set(labels)) != len(labels):
            raise bad("extra_controllers", "labels must be unique")
        # Every label the study (and evaluate_claims) may give its own controllers, whether or
        # not this configuration uses it.
        own = [ControllerSpec(kind=ControllerKind.FLC)] + [
            ControllerSpec(kind=k, fou=w)
            for w in {*self.fous, *(w for w in self.fou_sweep if w > 0.0)}
            for k in (ControllerKind.IT2, ControllerKind.T1_MATCHED)
        ]
        builtin = {s.label for s in own} | {"PD (tuned)", "PD (given)"}
        clash = sorted(set(labels) & builtin)
        if clash:
            raise bad("extra_controllers", f"label(s) {clash} are used by the study's own "
                      "controllers; set a distinct label")

    # -- controller line-ups -------------------------------------------------------------------
    def paper_controllers(self, pd: ControllerSpec | None) -> list[ControllerSpec]:
        specs = [ControllerSpec(kind=ControllerKind.FLC)]
        specs += [ControllerSpec(kind=ControllerKind.IT2, fou=w) for w in self.fous]
        if self.matched_baseline:
            specs += [ControllerSpec(kind=ControllerKind.T1_MATCHED, fou=w) for w in self.fous]
        if pd is not None:
            specs.append(pd)
        return specs + list(self.extra_controllers)

    def noise_controllers(self, pd: ControllerSpec | None) -> list[ControllerSpec]:
        specs = [ControllerSpec(kind=ControllerKind.FLC)]
        specs += [ControllerSpec(kind=ControllerKind.IT2, fou=w) for w in self.fous]
        if self.matched_baseline:
            specs.append(ControllerSpec(kind=ControllerKind.T1_MATCHED, fou=self.main_fou))
        if pd is not None:
            specs.append(pd)
        return specs + list(self.extra_controllers)

    def fou_controllers(self) -> list[ControllerSpec]:
        specs = []
        for w in self.fou_sweep:
            if w == 0.0:
                specs.append(ControllerSpec(kind=ControllerKind.FLC))
            else:
                specs.append(ControllerSpec(kind=ControllerKind.IT2, fou=w))
                if self.matched_baseline:
                    specs.append(ControllerSpec(kind=ControllerKind.T1_MATCHED, fou=w))
        return specs

    def to_dict(self) -> dict[str, Any]:
        """Plain values for the manifest."""
        simulation = self.loop.to_dict()
        robot = simulation.pop("robot")
        return {
            "simulation": simulation,
            "robot": robot,
            "study": {
                "trajectories": list(self.trajectories), "fous": list(self.fous),
                "main_fou": self.main_fou, "noise_std": self.noise_std,
                "noise_levels": list(self.noise_levels), "fou_sweep": list(self.fou_sweep),
                "seeds": self.seeds, "sweep_seeds": self.sweep_seeds,
                "figure_seed": self.figure_seed, "matched_baseline": self.matched_baseline,
                "batch_size": self.batch_size,
            },
            "pd": None if self.pd is None else {
                "seeds": self.pd.seeds, "kp_grid": list(self.pd.kp_grid),
                "kd_grid": list(self.pd.kd_grid), "tf": self.pd.tf,
                "match_effort": self.pd.match_effort, "effort_limit": self.pd.effort_limit,
                "kp": self.pd.kp, "kd": self.pd.kd,
            },
            "controllers": [s.to_dict() for s in self.extra_controllers],
        }  # fmt: skip


def load_study_config(path: str | Path, **overrides: Any) -> StudyConfig:
    """Read a study TOML file (see ``configs/paper.toml``).

    Sections: ``[simulation]``, ``[robot]`` (+ ``[robot.motor]``), ``[study]``, ``[pd]`` (or
    ``pd_baseline = false`` in ``[study]``), ``[[controllers]]`` (extra controllers).
    ``overrides`` replace ``[study]`` values (e.g. ``seeds`` from the command line).

    Raises
    ------
    ConfigError
        Naming the file, section, key and value of anything unknown or invalid.
    """
    path = Path(path)
    data = read_toml(path)
    root = Table(data, str(path), path.parent)
    study_t = root.sub("study")
    seed = study_t.get("seed", int, 0)
    if seed < 0:
        raise ConfigError(f"{study_t.where}: seed={seed!r} must be >= 0")
    robot = robot_from_table(root.sub("robot"))
    loop = loop_config_from_table(root.sub("simulation"), robot, seed=seed)
    values: dict[str, Any] = {"loop": loop}
    for key in ("trajectories",):
        if key in study_t:
            values[key] = tuple(study_t.get_list(key, str))
    for key in ("fous", "noise_levels", "fou_sweep"):
        if key in study_t:
            values[key] = tuple(study_t.get_list(key, float))
    for key in ("main_fou", "noise_std"):
        if key in study_t:
            values[key] = study_t.get(key, float)
    for key in ("seeds", "sweep_seeds", "figure_seed", "batch_size"):
        if key in study_t:
            values[key] = study_t.get(key, int)
    if "matched_baseline" in study_t:
        values["matched_baseline"] = study_t.get("matched_baseline", bool)
    use_pd = study_t.get("pd_baseline", bool, True)
    study_t.done()
    pd_t = root.sub("pd")
    if use_pd:
        pd_values: dict[str, Any] = {}
        for key in ("seeds",):
            if key in pd_t:
                pd_values[key] = pd_t.get(key, int)
        for key in ("kp_grid", "kd_grid"):
            if key in pd_t:
                pd_values[key] = tuple(pd_t.get_list(key, float))
        for key in ("tf", "kp", "kd", "effort_limit"):
            if key in pd_t:
                pd_values[key] = pd_t.get(key, float)
        if "match_effort" in pd_t:
            pd_values["match_effort"] = pd_t.get("match_effort", bool)
        try:
            values["pd"] = PDTuning(**pd_values)
        except ValueError as exc:
            raise ConfigError(f"{pd_t.where}: {exc}") from None
    else:
        values["pd"] = None
    pd_t.done()
    extra = []
    if "controllers" in root:
        ctrl_list = root.get("controllers", list)
        for i, entry in enumerate(ctrl_list):
            where = f"{path} [[controllers]] #{i + 1}"
            spec = ControllerSpec.from_table(entry, where=where, base_dir=path.parent)
            try:  # build once now: a bad file or value fails here, not after minutes of runs
                spec.build()
            except (ValueError, OSError) as exc:
                raise ConfigError(f"{where}: {exc}") from None
            extra.append(spec)
    values["extra_controllers"] = tuple(extra)
    root.done()
    values.update(overrides)
    if "trajectories" in values:
        values["trajectories"] = tuple(
            _resolve_trajectory(name, path) for name in values["trajectories"]
        )
    try:
        return StudyConfig(**values)
    except ValueError as exc:
        raise ConfigError(f"{path}: {exc}") from None


def _resolve_trajectory(name: str, path: Path) -> str:
    """A built-in name as is; a CSV file relative to the config file's folder, checked."""
    if name.lower().endswith(".csv") and not Path(name).is_absolute():
        name = str(path.parent / name)
    try:
        get_trajectory(name)
    except ValueError as exc:
        raise ConfigError(f"{path} [study] trajectories: {exc}") from None
    return name


# --------------------------------------------------------------------------------------------
# Results
# --------------------------------------------------------------------------------------------


@dataclass
class StudyResult:
    """Everything the study produced, as data.

    Attributes
    ----------
    config : StudyConfig
    rows : dict of str -> ndarray
        The metrics table, one entry per run: columns ``experiment``, ``trajectory``,
        ``controller``, ``kind`` (str arrays), ``fou``, ``noise_std`` (float), ``seed`` (int),
        then every metric of :data:`~it2track.tracking.METRIC_NAMES`.
    traces : dict of str -> Trace
        Time series at ``noise_std`` for ``figure_seed``, by trajectory; the trace's runs are
        the controllers of ``trace_controllers`` in order.
    trace_controllers : list of str
        Labels of the traced controllers.
    trace_specs : list of ControllerSpec
        The traced controllers themselves, in trace run order.
    surfaces : dict of str -> (e, de, u)
        Control surfaces of the fuzzy controllers by label (``(101, 101)`` grids).
    surface_specs : dict of str -> ControllerSpec
        The controller behind each surface (its ``kind`` and ``fou``), by label.
    pd : ControllerSpec or None
        The (tuned) PD baseline.
    pd_tuning : dict
        The tuning record: grid objective values and the chosen gains.
    """

    config: StudyConfig
    rows: dict[str, np.ndarray]
    traces: dict[str, Trace]
    trace_controllers: list[str]
    trace_specs: list[ControllerSpec]
    surfaces: dict[str, tuple[FloatArray, FloatArray, FloatArray]]
    surface_specs: dict[str, ControllerSpec]
    pd: ControllerSpec | None
    pd_tuning: dict[str, Any]

    def select(self, **where: Any) -> dict[str, np.ndarray]:
        """Rows matching every ``column=value`` (floats compared exactly)."""
        mask = np.ones(len(self.rows["seed"]), dtype=bool)
        for key, value in where.items():
            mask &= self.rows[key] == value
        return {k: v[mask] for k, v in self.rows.items()}


ROW_KEYS = ("experiment", "trajectory", "controller", "kind", "fou", "noise_std", "seed")


def _specs_fou(spec: ControllerSpec) -> float:
    return spec.fou if spec.kind in (ControllerKind.IT2, ControllerKind.T1_MATCHED) else 0.0


@dataclass(frozen=True)
class _Experiment:
    name: str
    specs: tuple[ControllerSpec, ...]
    noise_levels: tuple[float, ...]
    n_seeds: int


def _experiments(config: StudyConfig, pd: ControllerSpec | None) -> list[_Experiment]:
    return [
        _Experiment("paper", tuple(config.paper_controllers(pd)), (config.noise_std,),
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
    in both sweeps with the same seeds), and without noise every seed gives the same run; each
    distinct (controller, trajectory, sigma, seed) is simulated once and its metrics are shared
    by the rows that need it -- bit for bit what separate simulations would give, since a run
    does not depend on its batch.
    """

    specs: tuple[ControllerSpec, ...]
    runs: RunTable
    rows: tuple[tuple[_Experiment, RunTable, NDArray[np.intp]], ...]


def _plan(config: StudyConfig, experiments: Sequence[_Experiment]) -> _Plan:
    spec_index: dict[ControllerSpec, int] = {}
    keys: dict[tuple[int, int, float, int], int] = {}
    rows = []
    n_traj = len(config.trajectories)
    for exp in experiments:
        grid = run_grid(len(exp.specs), n_traj, exp.noise_levels, exp.n_seeds)
        ctrl = [spec_index.setdefault(spec, len(spec_index)) for spec in exp.specs]
        index = np.empty(len(grid), dtype=np.intp)
        for r, (c, t, sigma, seed) in enumerate(zip(
            grid.controller.tolist(), grid.trajectory.tolist(), grid.noise_std.tolist(),
            grid.seed.tolist(), strict=True,
        )):
            key = (ctrl[c], t, sigma, seed if sigma > 0.0 else 0)
            index[r] = keys.setdefault(key, len(keys))
        rows.append((exp, grid, index))
    table = np.array(list(keys), dtype=np.float64).reshape(-1, 4)
    runs = RunTable(table[:, 0].astype(np.int64), table[:, 1].astype(np.int64), table[:, 2],
                    table[:, 3].astype(np.int64))
    return _Plan(specs=tuple(spec_index), runs=runs, rows=tuple(rows))


def _rows_of(plan: _Plan, metrics: dict[str, np.ndarray],
             trajectories: Sequence[str]) -> dict[str, np.ndarray]:
    parts = []
    for exp, grid, index in plan.rows:
        n = len(grid)
        specs = exp.specs
        part: dict[str, np.ndarray] = {
            "experiment": np.full(n, exp.name, dtype=object),
            "trajectory": np.array([trajectories[i] for i in grid.trajectory], dtype=object),
            "controller": np.array([specs[i].label for i in grid.controller], dtype=object),
            "kind": np.array([specs[i].kind.value for i in grid.controller], dtype=object),
            "fou": np.array([_specs_fou(specs[i]) for i in grid.controller]),
            "noise_std": grid.noise_std.copy(),
            "seed": grid.seed.copy(),
        }
        part.update({name: values[index] for name, values in metrics.items()})
        parts.append(part)
    return {key: np.concatenate([p[key] for p in parts]) for key in parts[0]}


@dataclass(frozen=True)
class _Chunk:
    """A slice of the plan's runs with the controllers and trajectories themselves (built and
    read here, once), so a worker needs none of the caller's files."""

    controllers: tuple[HeadingController, ...]
    trajectories: tuple[Trajectory, ...]
    loop: LoopConfig
    runs: RunTable
    batch_size: int
    start: int


def _simulate_chunk(chunk: _Chunk) -> dict[str, np.ndarray]:
    """Worker side of :func:`run_study` with an executor (module level: picklable)."""
    return simulate_metrics(chunk.controllers, chunk.trajectories, chunk.runs, chunk.loop,
                            batch_size=chunk.batch_size)


def _simulate_plan(
    plan: _Plan, config: StudyConfig, executor: Executor | None,
    progress: Callable[[int], object] | None,
) -> dict[str, np.ndarray]:
    controllers = tuple(spec.build() for spec in plan.specs)
    trajectories = tuple(get_trajectory(t) for t in config.trajectories)
    if executor is None:
        return simulate_metrics(controllers, trajectories, plan.runs, config.loop,
                                batch_size=config.batch_size, progress=progress)
    n = len(plan.runs)
    chunks = (
        _Chunk(controllers, trajectories, config.loop,
               plan.runs.take(slice(a, min(a + config.batch_size, n))), config.batch_size, a)
        for a in range(0, n, config.batch_size)
    )
    out: dict[str, np.ndarray] = {}
    for chunk, metrics in executor.imap_unordered(_simulate_chunk, chunks):
        for name, values in metrics.items():
            out.setdefault(name, np.empty(n))[chunk.start:chunk.start + values.size] = values
        if progress is not None:
            progress(len(chunk.runs))
    return out


def study_run_count(config: StudyConfig) -> int:
    """Number of simulations :func:`run_study` performs (PD tuning plus the distinct runs of
    the experiments), for sizing a progress bar."""
    placeholder = None if config.pd is None else ControllerSpec(
        kind=ControllerKind.PD, kp=1.0, label="PD (tuned)")
    plan = _plan(config, _experiments(config, placeholder))
    return experiment_sizes(config)["pd_tuning"] + len(plan.runs)


def experiment_sizes(config: StudyConfig) -> dict[str, int]:
    """Number of rows of each experiment, and of PD tuning runs (``"pd_tuning"``)."""
    pd_count = 0 if config.pd is None else 1
    n_t = len(config.trajectories)
    return {
        "pd_tuning": 0 if config.pd is None or config.pd.kp is not None
        else (len(config.pd.kp_grid) * len(config.pd.kd_grid)
              + (1 + len(config.fous)) * config.pd.match_effort) * n_t * config.pd.seeds,
        "paper": len(config.paper_controllers(None) if pd_count == 0 else
                     config.paper_controllers(ControllerSpec(kind=ControllerKind.PD, kp=1.0)))
        * n_t * config.seeds,
        "noise": len(config.noise_controllers(None) if pd_count == 0 else
                     config.noise_controllers(ControllerSpec(kind=ControllerKind.PD, kp=1.0)))
        * n_t * len(config.noise_levels) * config.sweep_seeds,
        "fou": len(config.fou_controllers()) * n_t * config.sweep_seeds,
    }


def tune_pd(
    config: StudyConfig, progress: Callable[[int], object] | None = None
) -> tuple[ControllerSpec, dict[str, Any]]:
    """Tune the PD baseline by the procedure of :class:`PDTuning`.

    Returns the PD spec and a record: ``grid`` (rows ``[kp, kd, mean ISE, mean effort]``, see
    ``grid_columns``), the chosen ``kp``, ``kd``, its ``objective`` (mean ISE) and ``effort``,
    the ``effort_limit`` applied and the rule behind it (``effort_limit_rule``), and
    ``on_grid_edge``.
    """
    tuning = config.pd
    assert tuning is not None
    if tuning.kp is not None:
        spec = ControllerSpec(kind=ControllerKind.PD, kp=tuning.kp, kd=tuning.kd or 0.0,
                              tf=tuning.tf, label="PD (given)")
        return spec, {"grid": [], "kp": spec.kp, "kd": spec.kd, "objective": None,
                      "on_grid_edge": False}
    trajs = [get_trajectory(t) for t in config.trajectories]
    seeds = TUNING_SEED_OFFSET + np.arange(tuning.seeds)

    def evaluate(ctrls: Sequence[HeadingController]) -> tuple[FloatArray, FloatArray]:
        runs = run_grid(len(ctrls), len(trajs), [config.noise_std], seeds.tolist())
        m = simulate_metrics(ctrls, trajs, runs, config.loop, batch_size=config.batch_size,
                             progress=progress)
        shape = (len(ctrls), -1)
        return m["ISE"].reshape(shape).mean(axis=1), m["effort"].reshape(shape).mean(axis=1)

    grid = [(kp, kd) for kp in tuning.kp_grid for kd in tuning.kd_grid]
    ise, effort = evaluate([PDHeadingController(kp=kp, kd=kd, tf=tuning.tf) for kp, kd in grid])
    if tuning.match_effort:
        fuzzy = [ControllerSpec(kind=ControllerKind.FLC)] + [
            ControllerSpec(kind=ControllerKind.IT2, fou=w) for w in config.fous
        ]
        _, fuzzy_effort = evaluate([s.build() for s in fuzzy])
        limit = float(fuzzy_effort.max())
        rule = "largest mean effort of the FLC and the IT2FLCs on the tuning runs"
    else:
        limit = math.inf if tuning.effort_limit is None else tuning.effort_limit
        rule = "fixed" if tuning.effort_limit is not None else "none"
    feasible = effort <= limit
    if not feasible.any():
        raise ValueError(
            f"PD tuning: no gains on the grid keep the mean effort within "
            f"{limit:.3g} V^2 s (smallest {effort.min():.3g}); "
            "raise the limit or extend the grid towards smaller gains"
        )
    best = int(np.argmin(np.where(feasible, ise, np.inf)))
    kp, kd = grid[best]
    best_value = float(ise[best])
    edge = bool(kp in (tuning.kp_grid[0], tuning.kp_grid[-1]) or kd == tuning.kd_grid[-1])
    spec = ControllerSpec(kind=ControllerKind.PD, kp=kp, kd=kd,
                          tf=tuning.tf, label="PD (tuned)")
    record = {
        "grid": [[g[0], g[1], float(v), float(f)]
                 for g, v, f in zip(grid, ise, effort, strict=True)],
        "grid_columns": ["kp", "kd", "mean ISE", "mean effort"],
        "kp": spec.kp, "kd": spec.kd, "objective": best_value, "on_grid_edge": edge,
        "effort": float(effort[best]),
        "effort_limit": None if math.isinf(limit) else limit, "effort_limit_rule": rule,
        "seed_indices": [int(seeds[0]), int(seeds[-1])],
        "noise_std": config.noise_std, "criterion": "mean ISE over trajectories",
    }
    return spec, record


def run_study(
    config: StudyConfig,
    *,
    progress: Callable[[int], object] | None = None,
    executor: Executor | None = None,
) -> StudyResult:
    """Run every experiment of the study (see the module docstring).

    Parameters
    ----------
    executor : Executor, optional
        Where the experiments' runs go, in chunks of ``config.batch_size`` (local processes,
        a Dask cluster; see :mod:`it2track.experiments.executors`). Default: this process.
        The numbers do not depend on it. PD tuning, traces and surfaces run here.
    progress : callable, optional
        Called with the number of runs finished, as they finish (for a progress bar sized by
        :func:`study_run_count`).
    """
    if config.pd is not None:
        pd, pd_record = tune_pd(config, progress)
    else:
        pd, pd_record = None, {}
    plan = _plan(config, _experiments(config, pd))
    metrics = _simulate_plan(plan, config, executor, progress)
    rows = _rows_of(plan, metrics, config.trajectories)

    # Time series of one realisation for the figures.
    traced = [ControllerSpec(kind=ControllerKind.FLC)] + [
        ControllerSpec(kind=ControllerKind.IT2, fou=w) for w in config.fous
    ]
    controllers = [s.build() for s in traced]
    traces: dict[str, Trace] = {}
    for name in config.trajectories:
        runs = RunTable(np.arange(len(controllers)), 0, config.noise_std, config.figure_seed)
        traces[name] = simulate(controllers, [get_trajectory(name)], runs, config.loop)

    surface_specs = {s.label: s for s in [
        ControllerSpec(kind=ControllerKind.FLC),
        *(ControllerSpec(kind=ControllerKind.IT2, fou=w) for w in config.fous),
        *(ControllerSpec(kind=ControllerKind.T1_MATCHED, fou=w)
          for w in (config.fous if config.matched_baseline else ())),
    ]}
    surfaces: dict[str, tuple[FloatArray, FloatArray, FloatArray]] = {}
    for label, spec in surface_specs.items():
        controller = spec.build()
        assert isinstance(controller, FuzzyHeadingController)
        surfaces[label] = control_surface(controller.fls)
    return StudyResult(
        config=config, rows=rows, traces=traces, trace_controllers=[s.label for s in traced],
        trace_specs=traced, surfaces=surfaces, surface_specs=surface_specs, pd=pd,
        pd_tuning=pd_record,
    )


"""The paper's study, reproduced and extended (DESIGN.md sec. 6). Returns data; never plots.

Experiments (all with common random numbers: seed index ``i`` is the same noise realisation for
every controller, trajectory and noise level):

``paper``
    Monte Carlo at the study's noise level ``noise_std``: the FLC, the IT2FLCs of the paper's FoU
    widths, the fair baselines (type-1 FLCs with the IT2FLCs' dead zones, with their dead zones
    and edge slopes, a tuned PD), the tuned fuzzy controllers and any extra controllers, on
    every trajectory, over ``seeds`` realisations.
``noise``
    Noise-level sweep: FLC, the IT2FLCs, the two matched type-1 FLCs of ``main_fou`` and the PD
    over ``noise_levels``, ``sweep_seeds`` realisations each (one run at sigma = 0: without
    noise every seed is the same run).
``fou``
    Continuous FoU sweep: IT2FLC(w) and the dead-zone-matched type-1 FLC(w) for every ``w`` in
    ``fou_sweep`` (``w = 0`` is the FLC), at ``noise_std``, ``sweep_seeds`` realisations.

Plus the time series of one realisation (``figure_seed``) for the paper's figures 7-10, and the
control surfaces of every fuzzy controller. The PD baseline and the tuned fuzzy controllers
are tuned on seed indices disjoint from the evaluation seeds (see :func:`tune_pd`,
:func:`tune_fuzzy`), and the robustness experiment (:mod:`it2track.experiments.robustness`)
re-judges the claims under the paper's open modelling choices.

Every run of every experiment goes through one plan (:func:`_plan`): each distinct (loop,
controller, trajectory, sigma, seed) is simulated once, in batches per loop configuration,
through the same engine and executor, and shared by the rows that need it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..fuzzy import control_surface
from ..tracking import (
    METRIC_NAMES,
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
from .analysis import evaluate_claims, ordering_probability
from .baselines import FuzzyTuning, choose, tuned_label
from .choices import DEFAULT_CHOICES, Variant, apply_settings, choices_from_list
from .executors import Executor
from .robustness import (
    RobustnessConfig,
    RobustnessResult,
    SensitivityConfig,
    check_defaults,
    check_factor_levels,
    judge_variants,
    morris_analysis,
    morris_design,
    rebase,
    robustness_config_from_table,
    robustness_variants,
)
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
    "FuzzyTuning",
    "PDTuning",
    "StudyConfig",
    "StudyResult",
    "experiment_sizes",
    "figure_data",
    "load_study_config",
    "quick_config",
    "run_study",
    "study_run_count",
    "tune_fuzzy",
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
    """Everything the study runs; the packaged config ``paper`` holds the defaults.

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
        Include the matched type-1 FLCs (dead zone; dead zone and edge slope).
    pd : PDTuning or None
        PD baseline tuning (None: no PD baseline).
    tuning : FuzzyTuning or None
        Tuning of the fuzzy controllers with the PD's budget, seeds and effort limit (None:
        none; needs ``pd``).
    robustness : RobustnessConfig or None
        The robustness experiment over the open modelling choices (None: none).
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
    tuning: FuzzyTuning | None = field(default_factory=FuzzyTuning)
    robustness: RobustnessConfig | None = field(default_factory=RobustnessConfig)
    extra_controllers: tuple[ControllerSpec, ...] = ()
    batch_size: int = 4096

    def __post_init__(self) -> None:
        def bad(key: str, why: str) -> ValueError:
            value = getattr(self, key)
            shown = "..." if key in ("robustness", "tuning", "pd") else repr(value)
            return ValueError(f"study {key}={shown}: {why}")

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
        if self.tuning is not None and (self.pd is None or self.pd.kp is not None):
            # The fuzzy tuning uses the PD tuning's seeds and effort limit: without a PD
            # tuning there is none (load_study_config refuses an explicit [tuning] then).
            object.__setattr__(self, "tuning", None)
        if self.robustness is not None:
            if self.robustness.choices == DEFAULT_CHOICES:  # the implied list: rebase it
                implied = rebase(DEFAULT_CHOICES, self.loop)
                if self.tuning is None:  # nothing tuned: no "tuned" alternative
                    implied = tuple(c for c in implied if "controllers.tuned" not in c.sets)
                implied = _valid_alternatives(implied, self.loop)
                object.__setattr__(self, "robustness", replace(self.robustness, choices=implied))
            sens = self.robustness.sensitivity
            if sens is not None and sens.factors == SensitivityConfig().factors:
                # the implied screening: without the factors this loop cannot run
                object.__setattr__(self, "robustness", replace(
                    self.robustness, sensitivity=_valid_factors(sens, self.loop)))
            if self.noise_std not in self.robustness.noise_levels:
                raise bad("robustness", f"noise_levels {list(self.robustness.noise_levels)} "
                          f"must include the study's noise_std={self.noise_std:g} (the level a "
                          "noise reading is compared at)")
            try:
                check_defaults(self.robustness.choices, self.loop, "study")
                robustness_variants(self.robustness, self.loop)  # every variant is a valid loop
                if self.robustness.sensitivity is not None:
                    check_factor_levels(self.robustness.sensitivity, self.loop)
            except (ConfigError, ValueError) as exc:
                raise bad("robustness", str(exc)) from None
            if self.tuning is None and any("controllers.tuned" in c.sets
                                           for c in self.robustness.choices):
                raise bad("robustness", "a choice sets controllers.tuned but the study tunes "
                          "no fuzzy controllers (tuning = false)")
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
        builtin |= {tuned_label(x) for x in builtin}
        builtin |= {f"T1 slope-matched {w:g}" for w in self.fous}
        clash = sorted(set(labels) & builtin)
        if clash:
            raise bad("extra_controllers", f"label(s) {clash} are used by the study's own "
                      "controllers; set a distinct label")

    # -- controller line-ups -------------------------------------------------------------------
    def paper_fuzzy(self) -> list[ControllerSpec]:
        """The paper's fuzzy controllers: the FLC and the IT2FLCs."""
        return [ControllerSpec(kind=ControllerKind.FLC)] + [
            ControllerSpec(kind=ControllerKind.IT2, fou=w) for w in self.fous]

    def tuned_roles(self) -> list[ControllerSpec]:
        """The paper's fuzzy controllers that :attr:`tuning` tunes."""
        if self.tuning is None:
            return []
        kinds = {"flc": ControllerKind.FLC, "it2": ControllerKind.IT2}
        wanted = {kinds[c] for c in self.tuning.controllers}
        return [s for s in self.paper_fuzzy() if s.kind in wanted]

    def matched_baselines(self, widths: Sequence[float]) -> list[ControllerSpec]:
        """The slope-matched and dead-zone-matched type-1 FLCs of ``widths`` (none without
        ``matched_baseline``)."""
        if not self.matched_baseline:
            return []
        return [ControllerSpec(kind=k, fou=w)
                for k in (ControllerKind.T1_SLOPE_MATCHED, ControllerKind.T1_MATCHED)
                for w in widths]

    def paper_controllers(self, pd: ControllerSpec | None,
                          tuned: Sequence[ControllerSpec] = ()) -> list[ControllerSpec]:
        specs = self.paper_fuzzy() + self.matched_baselines(self.fous)
        if pd is not None:
            specs.append(pd)
        return specs + list(tuned) + list(self.extra_controllers)

    def noise_controllers(self, pd: ControllerSpec | None) -> list[ControllerSpec]:
        specs = self.paper_fuzzy() + self.matched_baselines([self.main_fou])
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
            "tuning": None if self.tuning is None else self.tuning.to_dict(),
            "robustness": None if self.robustness is None else self.robustness.to_dict(),
            "pd": None if self.pd is None else {
                "seeds": self.pd.seeds, "kp_grid": list(self.pd.kp_grid),
                "kd_grid": list(self.pd.kd_grid), "tf": self.pd.tf,
                "match_effort": self.pd.match_effort, "effort_limit": self.pd.effort_limit,
                "kp": self.pd.kp, "kd": self.pd.kd,
            },
            "controllers": [s.to_dict() for s in self.extra_controllers],
        }  # fmt: skip


def _valid_alternatives(choices: Sequence[Any], loop: LoopConfig) -> tuple[Any, ...]:
    """The implied choices without the alternatives this loop cannot run (e.g. an integral
    window starting after a short run ends); choices left without alternatives are dropped."""
    out = []
    for c in choices:
        alts = []
        for a in c.alternatives:
            try:
                apply_settings(loop, (1.0,), c.settings(a), choice=c.name, value="")
            except ValueError:
                continue
            alts.append(a)
        if alts:
            out.append(replace(c, alternatives=tuple(alts)))
    return tuple(out)


def _valid_factors(sens: SensitivityConfig, loop: LoopConfig) -> SensitivityConfig | None:
    """The implied screening without the factors whose levels this loop cannot run (e.g. an
    integral window starting after a short run ends), dropped from the last; None if none
    is left."""
    factors = list(sens.factors)
    while factors:
        candidate = replace(sens, factors=tuple(factors))
        try:
            check_factor_levels(candidate, loop)
            return candidate
        except ValueError:
            pass
        bad = next((f for f in reversed(factors) if f.path.startswith(("simulation.", "robot."))
                    and not _levels_valid(f, loop)), None)
        factors.remove(bad if bad is not None else next(
            f for f in reversed(factors) if f.path.startswith(("simulation.", "robot."))))
    return None


def _levels_valid(factor: Any, loop: LoopConfig) -> bool:
    try:
        for v in factor.levels:
            apply_settings(loop, (1.0,), {factor.path: v}, choice=factor.name, value="")
    except ValueError:
        return False
    return True


def load_study_config(path: str | Path, **overrides: Any) -> StudyConfig:
    """Read a study TOML file (see the packaged config ``paper``, :mod:`it2track.configs`).

    Sections: ``[simulation]``, ``[robot]`` (+ ``[robot.motor]``), ``[study]``, ``[pd]`` (or
    ``pd_baseline = false`` in ``[study]``), ``[tuning]`` (or ``tuning = false``),
    ``[[choices]]`` (the open modelling choices), ``[robustness]`` (+
    ``[robustness.sensitivity]``; or ``robustness = false``), ``[[controllers]]`` (extra
    controllers).
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
    use_tuning = study_t.get("tuning", bool, True)
    use_robustness = study_t.get("robustness", bool, True)
    study_t.done()
    tuning_t = root.sub("tuning")
    pd_tuned = use_pd and "kp" not in root.sub("pd")
    if not pd_tuned and use_tuning:
        if "tuning" in study_t or "tuning" in root:
            raise ConfigError(f"{study_t.where}: tuning needs the PD tuning (its seeds and "
                              "effort limit): set [pd] without kp/kd and pd_baseline = true, "
                              "or tuning = false")
        use_tuning = False  # the fuzzy tuning needs the PD's: off with it unless asked for
    if use_tuning:
        tv: dict[str, Any] = {}
        if "controllers" in tuning_t:
            tv["controllers"] = tuple(tuning_t.get_list("controllers", str))
        for key in ("ke_grid", "kde_grid", "gain_grid"):
            if key in tuning_t:
                tv[key] = tuple(tuning_t.get_list(key, float))
        try:
            values["tuning"] = FuzzyTuning(**tv)
        except ValueError as exc:
            raise ConfigError(f"{tuning_t.where}: {exc}") from None
    else:
        values["tuning"] = None
    tuning_t.done()
    choices = (choices_from_list(root.get("choices", list), str(path)) if "choices" in root
               else RobustnessConfig().choices)
    rob_t = root.sub("robustness")
    if use_robustness:
        values["robustness"] = robustness_config_from_table(rob_t, choices)
        if "choices" in root:
            check_defaults(choices, loop, str(path))
    else:
        values["robustness"] = None
        rob_t.done()
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
        The metrics table (``metrics.csv``), one entry per run of the ``paper``, ``noise`` and
        ``fou`` experiments: columns ``experiment``, ``trajectory``, ``controller``, ``kind``
        (str arrays), ``fou``, ``noise_std`` (float), ``seed`` (int), then every metric of
        :data:`~it2track.tracking.METRIC_NAMES`. A noise-free cell has one row (seed 0).
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
        The PD tuning record: grid objective values and the chosen gains.
    tuned : dict of str -> ControllerSpec
        The tuned fuzzy controllers by the label of the paper controller they tune (e.g.
        ``"IT2FLC FoU 0.2"`` -> the spec labelled ``"IT2FLC FoU 0.2 (tuned)"``, with its
        ``ke``, ``kde`` and ``output_gain``); empty without tuning.
    tuning : dict of str -> dict
        One tuning record per tuned controller (same keys as ``tuned``): ``grid`` (rows
        ``[ke, kde, gain, mean ISE, mean effort]``, see ``grid_columns``), the chosen ``ke``,
        ``kde``, ``gain``, its ``objective`` (mean ISE) and ``effort``, the ``effort_limit``
        (the PD's), ``on_grid_edge``, ``seed_indices``, ``noise_std``, ``criterion``; and
        ``"untuned"``: the paper controller's own mean ISE and effort on the same runs.
    tuned_claims : list of ClaimResult
        C1-C3 judged on the tuned fuzzy controllers (``paper`` experiment, ``noise_std``,
        ``seeds`` realisations): the tuned-vs-tuned comparison. Empty without tuning.
    ordering : list of dict
        The probability that a single realisation shows the paper's strict ordering
        FLC > FoU 0.1 > 0.2 > 0.3 on all four integrals (``trajectory = "all"``: on every
        trajectory at once; or per trajectory), per noise level of the ``noise`` experiment,
        with exact intervals (:func:`~.analysis.ordering_probability`).
    robustness : RobustnessResult or None
        The robustness experiment (verdict table, robustness.csv cells, flips, ranking,
        Morris sensitivity indices and ranking); None when the study has none.
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
    tuned: dict[str, ControllerSpec] = field(default_factory=dict)
    tuning: dict[str, dict[str, Any]] = field(default_factory=dict)
    tuned_claims: list[Any] = field(default_factory=list)
    ordering: list[dict[str, Any]] = field(default_factory=list)
    robustness: RobustnessResult | None = None

    def select(self, **where: Any) -> dict[str, np.ndarray]:
        """Rows matching every ``column=value`` (floats compared exactly)."""
        mask = np.ones(len(self.rows["seed"]), dtype=bool)
        for key, value in where.items():
            mask &= self.rows[key] == value
        return {k: v[mask] for k, v in self.rows.items()}


ROW_KEYS = ("experiment", "trajectory", "controller", "kind", "fou", "noise_std", "seed")
_FOU_KINDS = (ControllerKind.IT2, ControllerKind.T1_MATCHED, ControllerKind.T1_SLOPE_MATCHED)


def _specs_fou(spec: ControllerSpec) -> float:
    return spec.fou if spec.kind in _FOU_KINDS else 0.0


@dataclass(frozen=True)
class _Experiment:
    """Runs of a grid of controllers x trajectories x noise levels x seeds under one loop.

    ``labels`` (default: the specs' labels) name the controllers in the rows, e.g. the paper
    label of a controller run with other gains in a robustness variant.
    """

    name: str
    specs: tuple[ControllerSpec, ...]
    noise_levels: tuple[float, ...]
    n_seeds: int
    loop: LoopConfig | None = None
    labels: tuple[str, ...] | None = None


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
    parts = []
    for sigma in exp.noise_levels:  # keep the levels' order
        if sigma > 0.0:
            parts.append(run_grid(len(exp.specs), n_traj, [sigma], exp.n_seeds))
        else:
            parts.append(run_grid(len(exp.specs), n_traj, [0.0], 1))
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


# --------------------------------------------------------------------------------------------
# Robustness and sensitivity experiments (their runs join the plan)
# --------------------------------------------------------------------------------------------


def _variant_specs(config: StudyConfig, variant: Variant,
                   tuned: Mapping[str, ControllerSpec]) -> tuple[list[ControllerSpec], list[str]]:
    """The controllers a variant judges the claims on, and their paper labels."""
    paper = config.paper_fuzzy()
    if variant.tuned:
        specs = [tuned.get(s.label, s) for s in paper]
        return specs, [s.label for s in paper]
    base = paper + config.matched_baselines([config.main_fou])
    # replace() re-derives the label from the new gains (e.g. "FLC Ke 0.5 Kde 1")
    specs = [replace(s, ke=variant.ke, kde=variant.kde, label="") for s in base]
    return specs, [s.label for s in base]


def _robustness_experiments(config: StudyConfig, tuned: Mapping[str, ControllerSpec]
                            ) -> tuple[list[Variant], list[_Experiment]]:
    rob = config.robustness
    if rob is None:
        return [], []
    variants = robustness_variants(rob, config.loop)
    exps = []
    for i, v in enumerate(variants):
        specs, labels = _variant_specs(config, v, tuned)
        exps.append(_Experiment(f"robustness:{i}", tuple(specs), v.noise_levels, rob.seeds,
                                loop=v.loop, labels=tuple(labels)))
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


# --------------------------------------------------------------------------------------------
# Tuning
# --------------------------------------------------------------------------------------------


def _tuning_evaluate(config: StudyConfig, ctrls: Sequence[HeadingController],
                     progress: Callable[[int], object] | None) -> tuple[FloatArray, FloatArray]:
    """Mean ISE and mean effort of each controller over the tuning runs."""
    assert config.pd is not None
    trajs = [get_trajectory(t) for t in config.trajectories]
    seeds = TUNING_SEED_OFFSET + np.arange(config.pd.seeds)
    runs = run_grid(len(ctrls), len(trajs), [config.noise_std], seeds.tolist())
    m = simulate_metrics(ctrls, trajs, runs, config.loop, batch_size=config.batch_size,
                         progress=progress)
    shape = (len(ctrls), -1)
    return m["ISE"].reshape(shape).mean(axis=1), m["effort"].reshape(shape).mean(axis=1)


def study_run_count(config: StudyConfig) -> int:
    """Number of simulations :func:`run_study` performs (tuning, plus the distinct runs of the
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
    """Number of rows of each experiment of ``metrics.csv``, and of tuning runs
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
        "fou": len(config.fou_controllers()) * n_t
        * per_level((config.noise_std,), config.sweep_seeds),
    }


def tune_pd(
    config: StudyConfig, progress: Callable[[int], object] | None = None
) -> tuple[ControllerSpec, dict[str, Any]]:
    """Tune the PD baseline by the procedure of :class:`PDTuning`.

    Returns the PD spec and a record: ``grid`` (rows ``[kp, kd, mean ISE, mean effort]``, see
    ``grid_columns``), the chosen ``kp``, ``kd``, its ``objective`` (mean ISE) and ``effort``,
    the ``effort_limit`` applied and the rule behind it (``effort_limit_rule``),
    ``on_grid_edge``, and ``fuzzy_effort`` (label -> mean effort of each paper fuzzy
    controller on the tuning runs, also their ``fuzzy_ise``) when they were simulated.
    """
    tuning = config.pd
    assert tuning is not None
    if tuning.kp is not None:
        spec = ControllerSpec(kind=ControllerKind.PD, kp=tuning.kp, kd=tuning.kd or 0.0,
                              tf=tuning.tf, label="PD (given)")
        return spec, {"grid": [], "kp": spec.kp, "kd": spec.kd, "objective": None,
                      "on_grid_edge": False}
    seeds = TUNING_SEED_OFFSET + np.arange(tuning.seeds)
    grid = [(kp, kd) for kp in tuning.kp_grid for kd in tuning.kd_grid]
    ise, effort = _tuning_evaluate(
        config, [PDHeadingController(kp=kp, kd=kd, tf=tuning.tf) for kp, kd in grid], progress)
    record_extra: dict[str, Any] = {}
    if tuning.match_effort or config.tuning is not None:
        fuzzy = config.paper_fuzzy()
        fuzzy_ise, fuzzy_effort = _tuning_evaluate(config, [s.build() for s in fuzzy], progress)
        record_extra = {
            "fuzzy_effort": {s.label: float(v) for s, v in zip(fuzzy, fuzzy_effort,
                                                               strict=True)},
            "fuzzy_ise": {s.label: float(v) for s, v in zip(fuzzy, fuzzy_ise, strict=True)},
        }
    if tuning.match_effort:
        limit = float(max(record_extra["fuzzy_effort"].values()))
        rule = "largest mean effort of the FLC and the IT2FLCs on the tuning runs"
    else:
        limit = math.inf if tuning.effort_limit is None else tuning.effort_limit
        rule = "fixed" if tuning.effort_limit is not None else "none"
    best = choose(ise, effort, limit)
    if best is None:
        raise ValueError(
            f"PD tuning: no gains on the grid keep the mean effort within "
            f"{limit:.3g} V^2 s (smallest {effort.min():.3g}); "
            "raise the limit or extend the grid towards smaller gains"
        )
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
        **record_extra,
    }
    return spec, record


def tune_fuzzy(
    config: StudyConfig, pd_record: Mapping[str, Any],
    progress: Callable[[int], object] | None = None,
) -> tuple[dict[str, ControllerSpec], dict[str, dict[str, Any]]]:
    """Tune the fuzzy controllers of :meth:`StudyConfig.tuned_roles` by :class:`FuzzyTuning`:
    the PD's tuning runs, the PD's budget and the PD's effort limit (``pd_record``, from
    :func:`tune_pd`; without a limit there, the largest mean effort of the paper's fuzzy
    controllers on the same runs).

    Returns ``(tuned, records)``, both keyed by the paper controller's label (see
    :class:`StudyResult`).
    """
    tuning = config.tuning
    if tuning is None or config.pd is None:
        return {}, {}
    limit = pd_record.get("effort_limit")
    if limit is None:
        limit = float(max(pd_record["fuzzy_effort"].values()))
    candidates = tuning.candidates
    tuned: dict[str, ControllerSpec] = {}
    records: dict[str, dict[str, Any]] = {}
    seeds = TUNING_SEED_OFFSET + np.arange(config.pd.seeds)
    for role in config.tuned_roles():
        specs = [replace(role, ke=ke, kde=kde, output_gain=g, label="")
                 for ke, kde, g in candidates]
        ise, effort = _tuning_evaluate(config, [s.build() for s in specs], progress)
        best = choose(ise, effort, limit)
        if best is None:
            raise ValueError(
                f"tuning {role.label}: no candidate keeps the mean effort within the PD's "
                f"limit {limit:.3g} V^2 s (smallest {effort.min():.3g}); extend the grid "
                "towards smaller gains"
            )
        ke, kde, gain = candidates[best]
        spec = replace(role, ke=ke, kde=kde, output_gain=gain, label=tuned_label(role.label))
        tuned[role.label] = spec
        records[role.label] = {
            "grid": [[c[0], c[1], c[2], float(v), float(f)]
                     for c, v, f in zip(candidates, ise, effort, strict=True)],
            "grid_columns": ["ke", "kde", "gain", "mean ISE", "mean effort"],
            "ke": ke, "kde": kde, "gain": gain, "objective": float(ise[best]),
            "effort": float(effort[best]), "effort_limit": limit,
            "on_grid_edge": tuning.on_edge(ke, kde, gain),
            "untuned": {"ise": pd_record.get("fuzzy_ise", {}).get(role.label),
                        "effort": pd_record.get("fuzzy_effort", {}).get(role.label)},
            "seed_indices": [int(seeds[0]), int(seeds[-1])],
            "noise_std": config.noise_std, "criterion": "mean ISE over trajectories",
        }
    return tuned, records


# --------------------------------------------------------------------------------------------
# The whole study
# --------------------------------------------------------------------------------------------


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
        :func:`study_run_count`).
    early : StudyResult, optional
        :func:`figure_data` of this ``config``, already computed (``it2track reproduce`` draws
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


def figure_data(config: StudyConfig) -> StudyResult:
    """The part of the study that needs no Monte Carlo, as a :class:`StudyResult` without rows:
    the time series of one realisation (``traces``) and the control surfaces.

    :func:`run_study` returns the same traces and surfaces; ``it2track reproduce`` draws their
    figures from this while the experiments still run.
    """
    # Time series of one realisation for the figures.
    traced = config.paper_fuzzy()
    controllers = [s.build() for s in traced]
    traces: dict[str, Trace] = {}
    for name in config.trajectories:
        runs = RunTable(np.arange(len(controllers)), 0, config.noise_std, config.figure_seed)
        traces[name] = simulate(controllers, [get_trajectory(name)], runs, config.loop)

    surface_specs = {s.label: s for s in [
        *config.paper_fuzzy(), *config.matched_baselines(config.fous),
    ]}
    surfaces: dict[str, tuple[FloatArray, FloatArray, FloatArray]] = {}
    for label, spec in surface_specs.items():
        controller = spec.build()
        assert isinstance(controller, FuzzyHeadingController)
        surfaces[label] = control_surface(controller.fls)
    kinds = {"experiment": object, "trajectory": object, "controller": object, "kind": object,
             "seed": np.int64}
    no_rows = {k: np.empty(0, dtype=kinds.get(k, np.float64)) for k in (*ROW_KEYS, *METRIC_NAMES)}
    return StudyResult(
        config=config, rows=no_rows, traces=traces,
        trace_controllers=[s.label for s in traced], trace_specs=traced, surfaces=surfaces,
        surface_specs=surface_specs, pd=None, pd_tuning={},
    )


def quick_config(config: StudyConfig) -> StudyConfig:
    """A seconds-long smoke version of ``config`` that still runs every part of the study.

    Fewer seeds, levels and widths; runs of at most 3 s; the PD and the fuzzy controllers tuned
    on tiny grids (the user's given PD gains kept); the robustness experiment with 3
    realisations at two levels, without the expensive control periods below 5 ms, and a
    two-trajectory Morris screening without the period factor.
    """
    pd = config.pd
    if pd is not None and pd.kp is None:  # keep the user's PD settings, tune on a small grid
        pd = replace(pd, seeds=2, kp_grid=(2.0, 6.0, 20.0), kd_grid=(0.0, 0.2, 1.0))
    tuning = config.tuning
    if tuning is not None:
        tuning = replace(tuning, ke_grid=(1.0, 2.0), kde_grid=(0.0, 1.0), gain_grid=(1.0,))
    loop = config.loop
    if loop.duration > 3.0:
        loop = replace(loop, duration=3.0)
    rob = config.robustness
    if rob is not None:
        choices = []
        for c in rob.choices:
            if "simulation.ts" in c.sets:
                k = c.sets.index("simulation.ts")
                alts = tuple(a for a in c.alternatives if a[k] >= 0.005)
                if not alts:
                    continue
                c = replace(c, alternatives=alts)
            choices.append(c)
        names = {c.name for c in choices}
        factorial = tuple(n for n in rob.factorial if n in names)
        sens = rob.sensitivity
        if sens is not None:
            factors = tuple(f for f in sens.factors if f.path != "simulation.ts")
            sens = replace(sens, trajectories=2, seeds=2, factors=factors) if factors else None
        levels = tuple(sorted({config.noise_std, max(rob.noise_levels)}))
        rob = replace(rob, choices=tuple(choices), seeds=3, noise_levels=levels,
                      factorial=factorial if len(factorial) > 1 else (), sensitivity=sens)
    return replace(config, loop=loop, seeds=6, sweep_seeds=4, noise_levels=(0.0, 0.05, 0.2),
                   fou_sweep=(0.0, 0.1, 0.2, 0.3), pd=pd, tuning=tuning, robustness=rob)

"""The study's configuration: :class:`StudyConfig` (what the study runs), :class:`PDTuning`
(how the PD baseline is tuned), and :func:`quick_config`, its seconds-long smoke version.

Validated on construction (a ``ValueError`` naming the field);
:mod:`~it2track.experiments.study.loader` maps ``configs/paper.toml`` onto them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ...tracking import LoopConfig
from ..baselines import FuzzyTuning, tuned_label
from ..choices import DEFAULT_CHOICES, apply_settings
from ..robustness import (
    RobustnessConfig,
    SensitivityConfig,
    check_defaults,
    check_factor_levels,
    rebase,
    robustness_variants,
)
from ..sequential import SequentialDesign
from ..specs import ConfigError, ControllerKind, ControllerSpec

__all__ = ["PDTuning", "StudyConfig", "quick_config"]


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
        Realisations per cell in the ``paper`` experiment and in the sweeps (the ``noise``
        sweep's first round: :attr:`verdicts`).
    figure_seed : int
        Seed index of the time series shown in the figures.
    matched_baseline : bool
        Include the matched type-1 FLCs (dead zone; dead zone and edge slope) and, in the
        noise sweep, the type-1 table of the main IT2FLC's control surface (D3).
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
    verdicts : SequentialDesign
        Seeds by need in the noise sweep and the replication probability of every level
        (:mod:`it2track.experiments.sequential`); its ``first`` round is ``sweep_seeds``.
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
    verdicts: SequentialDesign = field(default_factory=SequentialDesign)

    def __post_init__(self) -> None:
        def bad(key: str, why: str) -> ValueError:
            value = getattr(self, key)
            shown = "..." if key in ("robustness", "tuning", "pd", "verdicts") else repr(value)
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
        if not isinstance(self.verdicts, SequentialDesign):
            raise bad("verdicts", "must be a SequentialDesign")
        if self.verdicts.cap < self.sweep_seeds:
            raise bad("verdicts", f"cap={self.verdicts.cap} must be >= sweep_seeds="
                      f"{self.sweep_seeds} (the first round)")
        if self.verdicts.first != self.sweep_seeds:
            object.__setattr__(self, "verdicts", replace(self.verdicts, first=self.sweep_seeds))
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
        builtin |= {f"T1 surface copy {w:g}" for w in self.fous}
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

    def surface_copies(self, widths: Sequence[float]) -> list[ControllerSpec]:
        """The type-1 tables of the control surfaces of the IT2FLCs of ``widths`` (none
        without ``matched_baseline``)."""
        if not self.matched_baseline:
            return []
        return [ControllerSpec(kind=ControllerKind.T1_SURFACE, fou=w) for w in widths]

    def noise_controllers(self, pd: ControllerSpec | None) -> list[ControllerSpec]:
        specs = (self.paper_fuzzy() + self.matched_baselines([self.main_fou])
                 + self.surface_copies([self.main_fou]))
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
            "verdicts": self.verdicts.to_dict(),
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


def quick_config(config: StudyConfig) -> StudyConfig:
    """A seconds-long smoke version of ``config`` that still runs every part of the study.

    Fewer seeds, levels and widths; runs of at most 3 s; the PD and the fuzzy controllers tuned
    on tiny grids (the user's given PD gains kept); the robustness experiment with 3
    realisations at two levels and two baseline batches, without the expensive control periods
    below 5 ms, and a two-trajectory Morris screening without the period factor; seeds by need
    from 4 to at most 8 per (path, sigma), 200 bootstrap resamples.
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
                      factorial=factorial if len(factorial) > 1 else (), sensitivity=sens,
                      baseline_batches=2)
    verdicts = replace(config.verdicts, first=4, batch=4, cap=max(4, min(config.verdicts.cap, 8)),
                       resamples=200)
    return replace(config, loop=loop, seeds=6, sweep_seeds=4, noise_levels=(0.0, 0.05, 0.2),
                   fou_sweep=(0.0, 0.1, 0.2, 0.3), pd=pd, tuning=tuning, robustness=rob,
                   verdicts=verdicts)

"""Do the verdicts survive the paper's open modelling choices? (docs/model.md, "Robustness")

Three parts, all simulated through the study's shared run plan (:mod:`.study`):

1. **One at a time**: every alternative of every :class:`~.choices.Choice`, the others at their
   defaults, re-judges every claim (C1-C3, D1, D2, :func:`~.analysis.evaluate_claims`) at the
   robustness noise levels with ``seeds`` realisations per cell (common random numbers).
2. **Factorial**: every combination of the values of the choices named in ``factorial``
   (the combinations with two or more non-default values; the others are part 1).
3. **Global sensitivity** (SALib, Morris elementary effects) of the key paired differences
   -- ISE of IT2FLC(main) - FLC and of IT2FLC(widest) - IT2FLC(narrowest), per trajectory --
   over the continuous choices (:class:`SensitivityConfig`), ranked.

A claim's *status* at a noise level is ``holds``, ``contradicted`` or ``not shown`` (over all
trajectories, and per trajectory). Against the baseline (the study's own choices, judged the
same way), a variant leaves a claim *unchanged* (the same status at every level), *changes* it
(a level moves to or from "not shown") or *flips* it (a level goes from holds to contradicted
or back). A variant that judges at other noise levels (the noise readings) is compared with
the baseline at the study's noise level ``noise_std``.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .analysis import (
    CONTRADICTED,
    HOLDS,
    INTEGRALS,
    MEASURED_INTEGRALS,
    ClaimResult,
    evaluate_claims,
)
from .choices import (
    DEFAULT_CHOICES,
    PATHS,
    Choice,
    Variant,
    apply_settings,
    baseline_value,
    format_value,
)
from .specs import ConfigError, Table

__all__ = [
    "CHANGE_ORDER",
    "RobustnessConfig",
    "RobustnessResult",
    "SensitivityConfig",
    "SensitivityFactor",
    "judge_variants",
    "morris_analysis",
    "robustness_variants",
]

UNCHANGED, CHANGED, FLIPPED = "unchanged", "changed", "flipped"
#: Severity order of the change categories.
CHANGE_ORDER = (UNCHANGED, CHANGED, FLIPPED)


@dataclass(frozen=True, kw_only=True)
class SensitivityFactor:
    """A continuous choice varied by the Morris screening: a path and its grid of levels
    (as many as the screening's ``num_levels``, in increasing order)."""

    name: str
    path: str
    levels: tuple[float, ...]

    def __post_init__(self) -> None:
        if self.path not in PATHS:
            raise ValueError(f"factor {self.name!r}: path {self.path!r} is not a known path")
        if self.path in ("metrics.heading", "controllers.tuned", "simulation.start_pose",
                         "simulation.desired_heading_pose"):
            raise ValueError(f"factor {self.name!r}: {self.path!r} is not continuous")
        for v in self.levels:
            PATHS[self.path](v, f"factor {self.name!r} levels")
        if len(self.levels) < 2 or list(self.levels) != sorted(set(self.levels)):
            raise ValueError(f"factor {self.name!r}: levels={list(self.levels)!r} must be >= 2 "
                             "distinct values in increasing order")


@dataclass(frozen=True, kw_only=True)
class SensitivityConfig:
    """Morris screening (SALib) of the key paired differences over continuous choices.

    Parameters
    ----------
    factors : tuple of SensitivityFactor
        The choices varied, each on the same number of grid levels (SALib's ``num_levels``,
        even).
    trajectories : int
        Morris trajectories ``r``: the screening simulates ``r (k + 1)`` design points for
        ``k`` factors.
    seeds : int
        Noise realisations per design point (common random numbers across points).
    seed : int
        Seed of SALib's sampling and of its bootstrap intervals.
    """

    factors: tuple[SensitivityFactor, ...] = (
        SensitivityFactor(name="half_track", path="robot.half_track",
                          levels=(0.056, 0.26, 1.2, 5.6)),
        SensitivityFactor(name="ts", path="simulation.ts", levels=(0.001, 0.0025, 0.005, 0.01)),
        SensitivityFactor(name="sigma", path="noise.sigma", levels=(0.05, 0.1, 0.2, 0.32)),
        SensitivityFactor(name="ke", path="controllers.ke", levels=(0.5, 0.8, 1.25, 2.0)),
        SensitivityFactor(name="kde", path="controllers.kde", levels=(0.5, 0.8, 1.25, 2.0)),
        SensitivityFactor(name="metric_start", path="simulation.metric_start",
                          levels=(0.0, 0.5, 1.0, 2.0)),
    )
    trajectories: int = 6
    seeds: int = 8
    seed: int = 0

    def __post_init__(self) -> None:
        if not self.factors:
            raise ValueError("sensitivity factors: needs at least one factor")
        names = [f.name for f in self.factors]
        if len(set(names)) != len(names):
            raise ValueError(f"sensitivity factors: names {names} must be unique")
        if len({len(f.levels) for f in self.factors}) != 1 or len(self.factors[0].levels) % 2:
            raise ValueError("sensitivity factors: every factor needs the same, even number of "
                             "levels (Morris num_levels)")
        for key in ("trajectories", "seeds"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, int) or v < 2:
                raise ValueError(f"sensitivity {key}={v!r} must be an integer >= 2")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"sensitivity seed={self.seed!r} must be an integer >= 0")

    @property
    def num_levels(self) -> int:
        return len(self.factors[0].levels)

    def to_dict(self) -> dict[str, Any]:
        return {"trajectories": self.trajectories, "seeds": self.seeds, "seed": self.seed,
                "factors": [{"name": f.name, "path": f.path, "levels": list(f.levels)}
                            for f in self.factors]}


@dataclass(frozen=True, kw_only=True)
class RobustnessConfig:
    """The robustness experiment (see the module docstring).

    Parameters
    ----------
    choices : tuple of Choice
        The open choices (``[[choices]]``).
    noise_levels : tuple of float
        Levels (> 0) at which every variant is judged (a noise reading judges at its own).
    seeds : int
        Realisations per cell (>= 2).
    factorial : tuple of str
        Choices crossed in the factorial (none: no factorial).
    sensitivity : SensitivityConfig or None
        The Morris screening (None: none).
    """

    choices: tuple[Choice, ...] = DEFAULT_CHOICES
    noise_levels: tuple[float, ...] = (0.05, 0.1, 0.2)
    seeds: int = 40
    factorial: tuple[str, ...] = ("input_gains", "half_track")
    sensitivity: SensitivityConfig | None = field(default_factory=SensitivityConfig)

    def __post_init__(self) -> None:
        if not self.noise_levels or any(not math.isfinite(s) or s <= 0
                                        for s in self.noise_levels):
            raise ValueError(f"robustness noise_levels={list(self.noise_levels)!r} must be "
                             "noise levels > 0")
        if len(set(self.noise_levels)) != len(self.noise_levels):
            raise ValueError(f"robustness noise_levels={list(self.noise_levels)!r} lists a "
                             "level twice")
        if isinstance(self.seeds, bool) or not isinstance(self.seeds, int) or self.seeds < 2:
            raise ValueError(f"robustness seeds={self.seeds!r} must be an integer >= 2 (a "
                             "single realisation shows nothing)")
        names = [c.name for c in self.choices]
        for name in self.factorial:
            if name not in names:
                raise ValueError(f"robustness factorial names {name!r}, not a choice; "
                                 f"choices: {names}")
        if len(set(self.factorial)) != len(self.factorial) or len(self.factorial) == 1:
            raise ValueError(f"robustness factorial={list(self.factorial)!r} needs none or "
                             "at least two distinct choices")

    def to_dict(self) -> dict[str, Any]:
        return {"noise_levels": list(self.noise_levels), "seeds": self.seeds,
                "factorial": list(self.factorial),
                "sensitivity": None if self.sensitivity is None else self.sensitivity.to_dict(),
                "choices": [c.to_dict() for c in self.choices]}


def robustness_config_from_table(t: Table, choices: tuple[Choice, ...]) -> RobustnessConfig:
    """``[robustness]`` (+ ``[robustness.sensitivity]`` and its ``[[...factors]]``)."""
    values: dict[str, Any] = {"choices": choices}
    if "noise_levels" in t:
        values["noise_levels"] = tuple(t.get_list("noise_levels", float))
    if "seeds" in t:
        values["seeds"] = t.get("seeds", int)
    if "factorial" in t:
        values["factorial"] = tuple(t.get_list("factorial", str))
    else:  # the default crossing, if the (possibly user-given) choices have it
        names = {c.name for c in choices}
        default = RobustnessConfig.__dataclass_fields__["factorial"].default
        assert isinstance(default, tuple)
        values["factorial"] = default if all(n in names for n in default) else ()
    use_sens = t.get("sensitivity_analysis", bool, True)
    st = t.sub("sensitivity")
    if use_sens:
        sv: dict[str, Any] = {}
        for key in ("trajectories", "seeds", "seed"):
            if key in st:
                sv[key] = st.get(key, int)
        if "factors" in st:
            factors = []
            for i, entry in enumerate(st.get("factors", list)):
                ft = Table(entry, f"{st.where}.factors #{i + 1}")
                name = ft.get("name", str)
                path = ft.get("path", str)
                levels = tuple(ft.get_list("levels", float))
                ft.done()
                try:
                    factors.append(SensitivityFactor(name=name, path=path, levels=levels))
                except ValueError as exc:
                    raise ConfigError(f"{ft.where}: {exc}") from None
            sv["factors"] = tuple(factors)
        try:
            values["sensitivity"] = SensitivityConfig(**sv)
        except ValueError as exc:
            raise ConfigError(f"{st.where}: {exc}") from None
    else:
        values["sensitivity"] = None
    st.done()
    t.done()
    try:
        return RobustnessConfig(**values)
    except ValueError as exc:
        raise ConfigError(f"{t.where}: {exc}") from None


def check_defaults(choices: Sequence[Choice], loop: Any, where: str) -> None:
    """Every choice's default must be the study's own setting (the baseline of the robustness
    experiment), so that the table of choices cannot misstate what was run."""
    for c in choices:
        for path, value in zip(c.sets, c.default, strict=True):
            own = baseline_value(path, loop)
            if value != own:
                raise ConfigError(
                    f"{where} [[choices]] {c.name!r}: default {path} = {format_value(value)} "
                    f"but the study runs {format_value(own)}; the default must be the study's "
                    "own setting"
                )


def check_factor_levels(sens: SensitivityConfig, loop: Any) -> None:
    """Every combination of the screening's loop levels must be a valid loop (e.g. each
    integral window a whole number of every period)."""
    loop_factors = [f for f in sens.factors if f.path.split(".")[0] in ("robot", "simulation")]
    for combo in itertools.product(*(f.levels for f in loop_factors)):
        settings = {f.path: v for f, v in zip(loop_factors, combo, strict=True)}
        apply_settings(loop, (1.0,), settings, choice="sensitivity",
                       value=", ".join(f"{f.name}={v:g}"
                                       for f, v in zip(loop_factors, combo, strict=True)))


def rebase(choices: Sequence[Choice], loop: Any) -> tuple[Choice, ...]:
    """The choices with the study's own settings as defaults: a choice whose default differs
    (e.g. the study sets ``half_track = 0.3``) gets the study's value as its default and its
    former default among the alternatives. Used for the implied list (no ``[[choices]]``
    given); an explicit list must match (:func:`check_defaults`)."""
    out = []
    for c in choices:
        own = tuple(baseline_value(p, loop) for p in c.sets)
        if own == c.default:
            out.append(c)
            continue
        alternatives = tuple(a for a in (c.default, *c.alternatives) if a != own)
        out.append(dataclasses.replace(c, default=own, alternatives=alternatives))
    return tuple(out)


# --------------------------------------------------------------------------------------------
# Variants
# --------------------------------------------------------------------------------------------


def robustness_variants(config: RobustnessConfig, loop: Any) -> list[Variant]:
    """The baseline, then every one-at-a-time alternative, then the factorial cells."""
    levels = config.noise_levels
    out = [apply_settings(loop, levels, {}, choice="baseline", value="paper")]
    for c in config.choices:
        for alt in c.alternatives:
            out.append(apply_settings(loop, levels, c.settings(alt), choice=c.name,
                                      value=c.label(alt)))
    if config.factorial:
        chosen = [next(c for c in config.choices if c.name == n) for n in config.factorial]
        name = " x ".join(c.name for c in chosen)
        for combo in itertools.product(*([c.default, *c.alternatives] for c in chosen)):
            moved = sum(v != c.default for c, v in zip(chosen, combo, strict=True))
            if moved < 2:
                continue
            settings: dict[str, Any] = {}
            for c, v in zip(chosen, combo, strict=True):
                settings.update(c.settings(v))
            label = " x ".join(c.label(v) for c, v in zip(chosen, combo, strict=True))
            out.append(apply_settings(loop, levels, settings, choice=name, value=label))
    return out


# --------------------------------------------------------------------------------------------
# Judging
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class RobustnessResult:
    """What the robustness experiment found, as data (the report renders it).

    Attributes
    ----------
    config : RobustnessConfig
    variants : list of Variant
        The baseline first, then the one-at-a-time alternatives, then the factorial cells.
    claims : list of list of ClaimResult
        The claims judged under each variant (same order as ``variants``).
    verdicts : list of dict
        One row per (claim, variant): ``claim, choice, value, part`` (``"baseline"``,
        ``"one-at-a-time"``, ``"factorial"``), ``noise_levels`` (text), ``verdict`` (over
        the variant's levels), ``status`` (per-level statuses ``"holds"``/``"contradicted"``/
        ``"not shown"``, ``;``-joined in level order), ``baseline_status`` (the baseline's at
        the compared levels), ``change`` (``"unchanged"``, ``"changed"``, ``"flipped"``),
        ``per_trajectory`` (``traj: verdict`` pairs, ``;``-joined). The heat-map's data.
    cells : list of dict
        robustness.csv: one row per claim, variant and evidence cell: ``claim, choice,
        value, sigma, trajectory, verdict`` (the claim's status at this level on this
        trajectory), ``level_verdict`` (at this level over all trajectories),
        ``baseline_level_verdict``, ``change``, ``metric, comparison, n, estimate, ci_low,
        ci_high, p_holm, outcome``.
    flips : dict of str -> dict
        Per claim: ``{"unchanged": [...], "changed": [...], "flipped": [...]}`` of
        ``"choice = value"`` labels (one-at-a-time and factorial).
    ranking : list of dict
        Choices ranked by how many (claim, level) statuses their alternatives move in the
        one-at-a-time part: ``choice, flipped, changed, score`` (score = 2 flipped + changed).
    sensitivity : list of dict
        Morris indices: ``output, trajectory, factor, mu_star, mu_star_conf, mu, sigma``.
    sensitivity_ranking : list of dict
        ``factor, score, rank``: the mean over outputs of ``mu_star / max mu_star``.
    sensitivity_points : int
        Design points the screening simulated.
    """

    config: RobustnessConfig
    variants: list[Variant]
    claims: list[list[ClaimResult]]
    verdicts: list[dict[str, Any]]
    cells: list[dict[str, Any]]
    flips: dict[str, dict[str, list[str]]]
    ranking: list[dict[str, Any]]
    sensitivity: list[dict[str, Any]] = field(default_factory=list)
    sensitivity_ranking: list[dict[str, Any]] = field(default_factory=list)
    sensitivity_points: int = 0


def _part(v: Variant) -> str:
    if v.choice == "baseline":
        return "baseline"
    return "factorial" if " x " in v.choice else "one-at-a-time"


def _change(status: Sequence[str], base: Sequence[str]) -> str:
    if list(status) == list(base):
        return UNCHANGED
    opposite = {(HOLDS, CONTRADICTED), (CONTRADICTED, HOLDS)}
    if any((a, b) in opposite for a, b in zip(status, base, strict=True)):
        return FLIPPED
    return CHANGED


def judge_variants(
    variants: Sequence[Variant],
    rows: Sequence[Mapping[str, np.ndarray]],
    *,
    config: RobustnessConfig,
    fous: Sequence[float],
    main_fou: float,
    trajectories: Sequence[str],
    reference_sigma: float,
) -> RobustnessResult:
    """Judge every claim under every variant and compare with the baseline (``variants[0]``).

    ``rows[i]`` are the metrics rows of variant ``i`` (experiment ``"robustness"``,
    controllers under their paper labels). ``reference_sigma`` is the baseline level a
    variant with other noise levels is compared with.
    """
    if not variants or variants[0].choice != "baseline":
        raise ValueError("judge_variants: the first variant must be the baseline")
    all_claims = []
    for v, r in zip(variants, rows, strict=True):
        metrics = MEASURED_INTEGRALS if v.heading == "measured" else INTEGRALS
        all_claims.append(evaluate_claims(r, fous=fous, main_fou=main_fou,
                                          trajectories=trajectories, experiment="robustness",
                                          metrics=metrics))
    base = {c.id: c for c in all_claims[0]}
    verdicts, cells = [], []
    flips: dict[str, dict[str, list[str]]] = {
        c.id: {UNCHANGED: [], CHANGED: [], FLIPPED: []} for c in all_claims[0]}
    moves: dict[str, list[int]] = {}
    for v, claims in zip(variants, all_claims, strict=True):
        for c in claims:
            b = base[c.id]
            if not c.level_status:  # not evaluated (e.g. no baseline controller)
                continue
            levels = sorted(c.level_status)
            status = [c.level_status[s] for s in levels]
            compared = [s if s in b.level_status else reference_sigma for s in levels]
            base_status = [b.level_status.get(s, "") for s in compared]
            change = _change(status, base_status)
            label = f"{v.choice} = {v.value}"
            if v.choice != "baseline":
                flips[c.id][change].append(label)
                if _part(v) == "one-at-a-time":
                    m = moves.setdefault(v.choice, [0, 0])
                    for a, bb in zip(status, base_status, strict=True):
                        if a != bb:
                            m[0 if _change([a], [bb]) == FLIPPED else 1] += 1
            verdicts.append({
                "claim": c.id, "choice": v.choice, "value": v.value, "part": _part(v),
                "noise_levels": ", ".join(f"{s:g}" for s in levels), "verdict": c.verdict,
                "status": ";".join(status), "baseline_status": ";".join(base_status),
                "change": change,
                "per_trajectory": ";".join(f"{t}: {p['verdict']}"
                                           for t, p in c.per_trajectory.items()),
            })
            base_of = dict(zip(levels, base_status, strict=True))
            change_of = {s: _change([c.level_status[s]], [base_of[s]]) for s in levels}
            traj_status = _trajectory_status(c, levels)
            for e in c.evidence:
                s = e["sigma"]
                cells.append(_cell_row(c.id, v, e, traj_status.get((s, e.get("trajectory",
                                                                             "straight")), ""),
                                       c.level_status[s], base_of[s], change_of[s]))
    order = [c.name for c in config.choices]
    ranked = sorted(moves.items(), key=lambda kv: (-(2 * kv[1][0] + kv[1][1]),
                                                   order.index(kv[0])))
    ranking: list[dict[str, Any]] = [
        {"choice": k, "flipped": f, "changed": ch, "score": 2 * f + ch}
        for k, (f, ch) in ranked]
    return RobustnessResult(config=config, variants=list(variants), claims=all_claims,
                            verdicts=verdicts, cells=cells, flips=flips, ranking=ranking)


def _trajectory_status(c: ClaimResult, levels: Sequence[float]) -> dict[tuple[float, str], str]:
    """Status per (level, trajectory) from the cells' outcomes (the per-trajectory verdicts'
    building blocks)."""
    out: dict[tuple[float, str], str] = {}
    groups: dict[tuple[float, str], list[str]] = {}
    for e in c.evidence:
        groups.setdefault((e["sigma"], e.get("trajectory", "straight")), []).append(e["outcome"])
    for key, outcomes in groups.items():
        if "deterministic" in outcomes:
            out[key] = "deterministic"
        elif all(o == "supports" for o in outcomes):
            out[key] = HOLDS
        elif "contradicts" in outcomes:
            out[key] = CONTRADICTED
        else:
            out[key] = "not shown"
    return out


def _cell_row(claim: str, v: Variant, e: Mapping[str, Any], traj_status: str,
              level_status: str, base_status: str, change: str) -> dict[str, Any]:
    low, high = e["ci_low"], e["ci_high"]
    if "comparison" in e:
        metric, comparison, estimate = e["metric"], e["comparison"], e["diff_mean"]
    else:  # C3
        key = next(k for k in e if k.startswith("mean "))
        metric = key.split(" ", 1)[1]
        comparison = f"smallest mean ({e['best controller']}) vs band"
        estimate = e[key]
    return {
        "claim": claim, "choice": v.choice, "value": v.value, "sigma": e["sigma"],
        "trajectory": e.get("trajectory", "straight"), "verdict": traj_status,
        "level_verdict": level_status, "baseline_level_verdict": base_status,
        "change": change, "metric": metric, "comparison": comparison, "n": e["n"],
        "estimate": estimate, "ci_low": low, "ci_high": high, "p_holm": e["p_holm"],
        "outcome": e["outcome"],
    }


# --------------------------------------------------------------------------------------------
# Global sensitivity (Morris)
# --------------------------------------------------------------------------------------------


def morris_design(sens: SensitivityConfig) -> tuple[np.ndarray, list[dict[str, Any]]]:
    """SALib's Morris sample on the unit grid and the path values of each design point.

    Returns ``(X, points)``: ``X`` of shape ``(r (k + 1), k)`` in ``[0, 1]`` (grid
    ``i / (num_levels - 1)``), ``points[j] = {path: value}``.
    """
    from SALib.sample import morris as morris_sample

    problem = _problem(sens)
    x = morris_sample.sample(problem, sens.trajectories, num_levels=sens.num_levels,
                             seed=sens.seed)
    p = sens.num_levels - 1
    points = []
    for row in x:
        idx = np.rint(row * p).astype(int)
        points.append({f.path: f.levels[i] for f, i in zip(sens.factors, idx, strict=True)})
    return x, points


def _problem(sens: SensitivityConfig) -> dict[str, Any]:
    return {"num_vars": len(sens.factors), "names": [f.name for f in sens.factors],
            "bounds": [[0.0, 1.0]] * len(sens.factors)}


def morris_analysis(sens: SensitivityConfig, x: np.ndarray,
                    outputs: Mapping[tuple[str, str], np.ndarray]
                    ) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """Morris indices of every output (``(name, trajectory) -> y``, one value per design
    point) and the overall ranking (mean over outputs of ``mu_star / max mu_star``).

    ``mu_star`` is in the output's unit per unit of the normalised grid (the full range of a
    factor's levels is 1).
    """
    from SALib.analyze import morris as morris_analyze

    problem = _problem(sens)
    rows = []
    scores = dict.fromkeys(problem["names"], 0.0)
    for (name, traj), y in outputs.items():
        res = morris_analyze.analyze(problem, x, np.asarray(y, dtype=np.float64),
                                     num_levels=sens.num_levels, seed=sens.seed)
        top = float(np.max(res["mu_star"])) or 1.0
        for i, factor in enumerate(problem["names"]):
            rows.append({"output": name, "trajectory": traj, "factor": factor,
                         "mu_star": float(res["mu_star"][i]),
                         "mu_star_conf": float(res["mu_star_conf"][i]),
                         "mu": float(res["mu"][i]), "sigma": float(res["sigma"][i])})
            scores[factor] += float(res["mu_star"][i]) / top / len(outputs)
    ranked = sorted(scores.items(), key=lambda kv: -kv[1])
    ranking = [{"factor": f, "score": s, "rank": i + 1} for i, (f, s) in enumerate(ranked)]
    return rows, ranking

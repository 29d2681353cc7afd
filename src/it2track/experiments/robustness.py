"""Do the verdicts survive the paper's open modelling choices? (docs/model.md, "Robustness")

Three parts, all simulated through the study's shared run plan (:mod:`.study`):

1. **One at a time**: every alternative of every :class:`~.choices.Choice`, the others at their
   defaults, re-judges every claim (C1-C3, D1, D2, :func:`~.analysis.evaluate_claims`) at the
   robustness noise levels with ``seeds`` realisations per cell (common random numbers).
2. **Factorial**: every combination of the values of the choices named in ``factorial``
   (restricted to ``factorial_levels`` where given; the combinations with two or more
   non-default values, the others being part 1).
3. **Global sensitivity** (SALib, Morris elementary effects) of the key paired differences
   -- ISE of IT2FLC(main) - FLC and of IT2FLC(widest) - IT2FLC(narrowest), per trajectory --
   over the continuous choices (:class:`SensitivityConfig`), ranked.

A claim's *status* at a noise level is ``holds``, ``contradicted`` or ``not shown`` (over all
trajectories, and per trajectory), with its replication probability (:mod:`.replication`).
With ``seeds`` realisations per cell, a status moves with the seed set by itself: the
baseline (the study's own choices) is therefore judged on ``baseline_batches`` independent
seed batches of the same size (batch 0 the variants' own seeds), and its *spread* at a level
is the set of statuses those batches give. Against it, a variant's level is

- *unsettled* when the variant's status there has a replication probability below the
  target (it could be seed noise);
- *unchanged* when its (settled) status is among the baseline's spread;
- *flipped* when the spread holds the opposite status (holds vs contradicted) and not its own;
- *changed* otherwise (a settled status the baseline never showed, e.g. not shown vs holds).

A variant *flips* a claim when it flips some level, else *changes* it when it changes some
level, else leaves it *unchanged* when every level is unchanged, else leaves it *unsettled*.
A variant that judges at other noise levels (the noise readings) is compared with the
baseline at the study's noise level ``noise_std``.
"""

from __future__ import annotations

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
from .choices import Variant
from .claimcells import claim_definitions
from .replication import replicate_claims
from .robustness_config import (
    RobustnessConfig,
    check_defaults,
    check_factor_levels,
    rebase,
    robustness_config_from_table,
    robustness_variants,
)
from .sensitivity import SensitivityConfig, SensitivityFactor, morris_analysis, morris_design

__all__ = [
    "CHANGE_ORDER",
    "RobustnessConfig",
    "RobustnessResult",
    "SensitivityConfig",
    "SensitivityFactor",
    "check_defaults",
    "check_factor_levels",
    "claim_change",
    "judge_variants",
    "level_change",
    "morris_analysis",
    "morris_design",
    "rebase",
    "robustness_config_from_table",
    "robustness_variants",
    "spread_text",
]

UNCHANGED, CHANGED, FLIPPED, UNSETTLED = "unchanged", "changed", "flipped", "unsettled"
#: Severity order of the change categories.
CHANGE_ORDER = (UNSETTLED, UNCHANGED, CHANGED, FLIPPED)


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
        One row per (claim, variant): ``claim, choice, value, label`` (the value in the
        reader's words), ``part`` (``"baseline"``, ``"one-at-a-time"``, ``"factorial"``),
        ``noise_levels`` (text), ``verdict`` (over the variant's settled levels), ``status``
        (per-level statuses ``"holds"``/``"contradicted"``/``"not shown"``, ``;``-joined in
        level order), ``replication`` and ``settled`` (per level), ``baseline_spread`` (the
        baseline's statuses over its batches at the compared levels), ``level_change`` (per
        level, :func:`level_change`), ``change`` (the claim's, :func:`claim_change`;
        ``"baseline"`` for the baseline), ``per_trajectory`` (``traj: verdict`` pairs,
        ``;``-joined). The heat-map's data.
    cells : list of dict
        robustness.csv: one row per claim, variant and evidence cell: ``claim, choice,
        value, label, sigma, trajectory, verdict`` (the claim's status at this level on this
        trajectory), ``level_verdict`` (at this level over all trajectories), ``replication``
        and ``settled`` (of that level status), ``baseline_spread``, ``change`` (the level's),
        ``metric, comparison, n, estimate, ci_low, ci_high, p_holm, outcome``.
    flips : dict of str -> dict
        Per claim: ``{"unchanged": [...], "changed": [...], "flipped": [...],
        "unsettled": [...]}`` of variant labels (one-at-a-time and factorial).
    ranking : list of dict
        Choices ranked by how many (claim, level) statuses their alternatives move beyond
        the baseline's spread in the one-at-a-time part: ``choice, flipped, changed, score``
        (score = 2 flipped + changed).
    spread : list of dict
        The baseline over its independent seed batches, per claim and noisy level:
        ``claim, sigma, batches, spread`` (``"holds 2, not shown 8"``), ``statuses`` (batch
        order), ``agreement`` (fraction of pairs of batches with the same status: the
        observed replication rate) and ``replication_mean`` (the bootstrap's estimate of it,
        averaged over the batches).
    target : float
        The replication probability that settles a level.
    seeds_per_batch : int
        Realisations per cell of every variant and baseline batch.
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
    spread: list[dict[str, Any]] = field(default_factory=list)
    target: float = 0.95
    seeds_per_batch: int = 0
    sensitivity: list[dict[str, Any]] = field(default_factory=list)
    sensitivity_ranking: list[dict[str, Any]] = field(default_factory=list)
    sensitivity_points: int = 0


def _part(v: Variant) -> str:
    if v.choice == "baseline":
        return "baseline"
    return "factorial" if " x " in v.choice else "one-at-a-time"


_OPPOSITE = {HOLDS: CONTRADICTED, CONTRADICTED: HOLDS}


def level_change(status: str, settled: bool, spread: Sequence[str]) -> str:
    """How a variant's status at one level compares with the baseline's spread over
    independent seed batches (module docstring).

    Examples
    --------
    >>> level_change("holds", True, ["holds", "not shown"])
    'unchanged'
    >>> level_change("contradicted", True, ["holds", "not shown"])
    'flipped'
    >>> level_change("contradicted", False, ["holds"])
    'unsettled'
    """
    if not spread:
        raise ValueError("level_change: the baseline spread is empty")
    if not settled:
        return UNSETTLED
    if status in spread:
        return UNCHANGED
    if _OPPOSITE.get(status) in spread:
        return FLIPPED
    return CHANGED


def claim_change(levels: Sequence[str]) -> str:
    """A claim's change under a variant from its levels' (:func:`level_change`): flipped if
    any level flips, else changed if any changes, else unchanged if every level is, else
    unsettled."""
    for how in (FLIPPED, CHANGED):
        if how in levels:
            return how
    return UNCHANGED if all(x == UNCHANGED for x in levels) else UNSETTLED


def spread_text(spread: Sequence[str]) -> str:
    """``"holds 2, not shown 8"``: the baseline's statuses over its batches."""
    counts = {st: spread.count(st) for st in dict.fromkeys(spread)}
    return ", ".join(f"{st} {k}" for st, k in counts.items())


def _judge_all(rows: Mapping[str, np.ndarray], *, fous: Sequence[float], main_fou: float,
               trajectories: Sequence[str], heading: str, target: float, resamples: int,
               seed: int) -> list[ClaimResult]:
    metrics = MEASURED_INTEGRALS if heading == "measured" else INTEGRALS
    defs = claim_definitions(fous=fous, main_fou=main_fou, trajectories=trajectories,
                             metrics=metrics, available=sorted(set(rows["controller"])))
    results = evaluate_claims(rows, fous=fous, main_fou=main_fou, trajectories=trajectories,
                              experiment="robustness", claims=defs)
    return replicate_claims(rows, defs, results, experiment="robustness",
                            resamples=resamples, seed=seed, target=target)


def judge_variants(
    variants: Sequence[Variant],
    rows: Sequence[Mapping[str, np.ndarray]],
    *,
    config: RobustnessConfig,
    fous: Sequence[float],
    main_fou: float,
    trajectories: Sequence[str],
    reference_sigma: float,
    baseline_batches: Sequence[Mapping[str, np.ndarray]] = (),
    target: float = 0.95,
    resamples: int = 1000,
    seed: int = 0,
) -> RobustnessResult:
    """Judge every claim under every variant, with replication probabilities, and compare
    each with the baseline's spread over independent seed batches (module docstring).

    ``rows[i]`` are the metrics rows of variant ``i`` (experiment ``"robustness"``,
    controllers under their paper labels); ``variants[0]`` is the baseline, and its rows are
    the first of its batches, ``baseline_batches`` the others (the same controllers and size,
    other seeds). ``reference_sigma`` is the baseline level a variant with other noise levels
    is compared with. ``target``, ``resamples``, ``seed``: the replication probability that
    settles a level and its bootstrap (:mod:`.replication`).
    """
    if not variants or variants[0].choice != "baseline":
        raise ValueError("judge_variants: the first variant must be the baseline")
    def judge(r: Mapping[str, np.ndarray], heading: str, b: int) -> list[ClaimResult]:
        return _judge_all(r, fous=fous, main_fou=main_fou, trajectories=trajectories,
                          heading=heading, target=target, resamples=b, seed=seed)

    all_claims = [judge(r, v.heading, resamples) for v, r in zip(variants, rows, strict=True)]
    # The other batches' statuses make the spread; their replication probabilities only enter
    # the spread table's average, whose Monte Carlo error averages over the batches.
    spare = max(100, resamples // 5)
    batches = [all_claims[0]] + [judge(r, variants[0].heading, spare)
                                 for r in baseline_batches]
    spread: dict[tuple[str, float], list[str]] = {}
    rep_of: dict[tuple[str, float], list[float]] = {}
    for claims in batches:
        for c in claims:
            for s, st in c.level_status.items():
                spread.setdefault((c.id, s), []).append(st)
                rep_of.setdefault((c.id, s), []).append(c.replication[("all", s)])
    verdicts, cells = [], []
    flips: dict[str, dict[str, list[str]]] = {
        c.id: {UNCHANGED: [], CHANGED: [], FLIPPED: [], UNSETTLED: []}
        for c in all_claims[0] if c.level_status}
    moves: dict[str, list[int]] = {}
    for v, claims in zip(variants, all_claims, strict=True):
        for c in claims:
            if not c.level_status:  # not evaluated (e.g. no baseline controller)
                continue
            levels = sorted(c.level_status)
            status = [c.level_status[s] for s in levels]
            compared = [s if (c.id, s) in spread else reference_sigma for s in levels]
            spreads = [spread.get((c.id, s), []) for s in compared]
            settled = [c.settled("all", s) for s in levels]
            if v.choice == "baseline":
                changes = [UNCHANGED] * len(levels)
                change = "baseline"
            else:
                changes = [level_change(st, ok, sp)
                           for st, ok, sp in zip(status, settled, spreads, strict=True)]
                change = claim_change(changes)
                flips[c.id][change].append(v.label)
                if _part(v) == "one-at-a-time":
                    m = moves.setdefault(v.choice, [0, 0])
                    m[0] += changes.count(FLIPPED)
                    m[1] += changes.count(CHANGED)
            verdicts.append({
                "claim": c.id, "choice": v.choice, "value": v.value, "label": v.label,
                "part": _part(v), "noise_levels": ", ".join(f"{s:g}" for s in levels),
                "verdict": c.verdict, "status": ";".join(status),
                "replication": ";".join(f"{c.replication[('all', s)]:.3f}"
                                        for s in levels),
                "settled": ";".join("yes" if ok else "no" for ok in settled),
                "baseline_spread": ";".join(spread_text(sp) for sp in spreads),
                "level_change": ";".join(changes), "change": change,
                "per_trajectory": ";".join(f"{t}: {p['verdict']}"
                                           for t, p in c.per_trajectory.items()),
            })
            traj_status = _trajectory_status(c)
            at = dict(zip(levels, zip(changes, spreads, settled, strict=True), strict=True))
            for e in c.evidence:
                s = e["sigma"]
                how, sp, ok = at[s]
                path = e.get("trajectory", "straight")  # (C3's cells: the straight line)
                cells.append(_cell_row(c.id, v, e, traj_status[(s, path)],
                                       c.level_status[s], c.replication[("all", s)],
                                       ok, spread_text(sp), how))
    order = [c.name for c in config.choices]
    ranked = sorted(moves.items(), key=lambda kv: (-(2 * kv[1][0] + kv[1][1]),
                                                   order.index(kv[0])))
    ranking: list[dict[str, Any]] = [
        {"choice": k, "flipped": f, "changed": ch, "score": 2 * f + ch}
        for k, (f, ch) in ranked]
    spread_rows = []
    for (cid, s), sts in spread.items():
        if s == 0.0:
            continue
        k = len(sts)
        pairs = k * (k - 1) / 2
        same = sum(sts[i] == sts[j] for i in range(k) for j in range(i + 1, k))
        spread_rows.append({
            "claim": cid, "sigma": s, "batches": k, "spread": spread_text(sts),
            "statuses": list(sts), "agreement": same / pairs if pairs else 1.0,
            "replication_mean": float(np.mean(rep_of[(cid, s)])),
        })
    return RobustnessResult(config=config, variants=list(variants), claims=all_claims,
                            verdicts=verdicts, cells=cells, flips=flips, ranking=ranking,
                            spread=spread_rows, target=target,
                            seeds_per_batch=config.seeds)


def _trajectory_status(c: ClaimResult) -> dict[tuple[float, str], str]:
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
              level_status: str, replication: float, settled: bool, spread: str,
              change: str) -> dict[str, Any]:
    low, high = e["ci_low"], e["ci_high"]
    if "comparison" in e:
        metric, comparison, estimate = e["metric"], e["comparison"], e["diff_mean"]
    else:  # C3
        key = next(k for k in e if k.startswith("mean "))
        metric = key.removeprefix("mean ")
        comparison = f"smallest mean ({e['best controller']}) vs band"
        estimate = e[key]
    return {
        "claim": claim, "choice": v.choice, "value": v.value, "label": v.label,
        "sigma": e["sigma"], "trajectory": e.get("trajectory", "straight"),
        "verdict": traj_status, "level_verdict": level_status, "replication": replication,
        "settled": settled, "baseline_spread": spread, "change": change, "metric": metric,
        "comparison": comparison, "n": e["n"], "estimate": estimate, "ci_low": low,
        "ci_high": high, "p_holm": e["p_holm"], "outcome": e["outcome"],
    }

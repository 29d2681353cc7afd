"""From the study's metrics table to summary statistics and verdicts on the paper's claims.

Nothing here is written by hand: every verdict is computed from the rows it is given, so
feeding other data (synthetic rows in the tests, another robot, another controller) changes the
verdicts accordingly.

Claims (DESIGN.md sec. 6), evaluated at every noise level of the ``noise`` experiment:

C1  The IT2FLC beats the FLC on all four integral errors on all trajectories: for every
    trajectory and metric the paired mean difference IT2FLC - FLC has its 95 % interval below 0.
C2  Errors fall as the FoU grows (0.1 -> 0.2 -> 0.3): every consecutive pair of the study's
    widths has its paired difference (wider - narrower) with a 95 % interval below 0, for every
    trajectory and metric.
C3  The smallest straight-line ISE (over the FLC and the IT2FLCs) is "of order 0.003": its mean
    lies within a factor sqrt(10) of 0.003, i.e. in [0.00095, 0.0095].
D1  (Not a paper claim; the question the fair baseline answers.) The IT2FLC beats the type-1
    FLC that has the same dead zone: same test as C1 against the dead-zone-matched FLC. Where
    C1 holds and D1 does not, the gain comes from the narrower dead zone, not from the FoU.

Every comparison cell *supports* a claim (interval on the claimed side of 0), *contradicts*
it (interval on the other side) or is *inconclusive* (interval containing 0, e.g. exact ties,
or a single realisation, which has no interval).
A level holds when every cell supports the claim and is contradicted when any cell contradicts
it. Each verdict reads "holds" (at every level), "does not hold" (contradicted somewhere,
holding nowhere), "not shown" (inconclusive everywhere) or "holds only for sigma in ..."
(listing where it holds), with a detail naming where it is contradicted or not shown.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .stats import mean_interval, paired_comparison

__all__ = [
    "INTEGRALS",
    "SUMMARY_METRICS",
    "ClaimResult",
    "evaluate_claims",
    "summarise",
    "verdict_text",
]

INTEGRALS = ("IAE", "ITAE", "ISE", "ITSE")
SUMMARY_METRICS = (*INTEGRALS, "pos_rms", "pos_max", "effort", "u_tv", "sat_time")
C3_TARGET = 0.003
C3_FACTOR = math.sqrt(10.0)

Rows = Mapping[str, np.ndarray]


def _group_index(rows: Rows, keys: Sequence[str]) -> dict[tuple[Any, ...], np.ndarray]:
    """Row indices of each distinct combination of ``keys`` (in first-seen order), each sorted
    by seed so that groups sharing seeds align for paired comparisons."""
    groups: dict[tuple[Any, ...], list[int]] = {}
    cols = [rows[k] for k in keys]
    for i in range(len(rows["seed"])):
        groups.setdefault(tuple(c[i] for c in cols), []).append(i)
    seed = rows["seed"]
    return {
        key: np.asarray(sorted(idx, key=lambda j: seed[j]), dtype=np.intp)
        for key, idx in groups.items()
    }


def summarise(rows: Rows, *, reference: str = "FLC") -> list[dict[str, Any]]:
    """One row per (experiment, trajectory, controller, noise level, metric).

    Columns: ``experiment, trajectory, controller, kind, fou, noise_std, metric, n, mean,
    ci_low, ci_high`` and, against ``reference`` on the same seeds, ``diff_mean, diff_low,
    diff_high, win_rate, ties`` (empty for the reference itself or where it is absent; the win
    rate counts ties as half, see :func:`~it2track.experiments.stats.paired_comparison`).
    """
    keys = ("experiment", "trajectory", "controller", "noise_std")
    groups = _group_index(rows, keys)
    out: list[dict[str, Any]] = []
    for (exp, traj, ctrl, sigma), idx in groups.items():
        ref_idx = groups.get((exp, traj, reference, sigma))
        paired = (
            ref_idx is not None
            and ctrl != reference
            and np.array_equal(rows["seed"][idx], rows["seed"][ref_idx])
        )
        for metric in SUMMARY_METRICS:
            values = rows[metric][idx]
            iv = mean_interval(values)
            row: dict[str, Any] = {
                "experiment": exp, "trajectory": traj, "controller": ctrl,
                "kind": rows["kind"][idx[0]], "fou": float(rows["fou"][idx[0]]),
                "noise_std": float(sigma), "metric": metric, "n": iv.n, "mean": iv.mean,
                "ci_low": iv.low, "ci_high": iv.high,
                "diff_mean": "", "diff_low": "", "diff_high": "", "win_rate": "", "ties": "",
            }  # fmt: skip
            if paired:
                assert ref_idx is not None
                cmp = paired_comparison(values, rows[metric][ref_idx])
                row.update(
                    diff_mean=cmp.diff.mean, diff_low=cmp.diff.low, diff_high=cmp.diff.high,
                    win_rate=cmp.win_rate, ties=cmp.ties,
                )
            out.append(row)
    return out


SUPPORTS, CONTRADICTS, INCONCLUSIVE = "supports", "contradicts", "inconclusive"


@dataclass(frozen=True)
class ClaimResult:
    """The verdict on one claim, with the evidence behind it.

    Every cell of evidence (a trajectory x metric x comparison at one noise level) has an
    ``outcome``: ``"supports"`` (the 95 % interval lies on the claimed side of zero),
    ``"contradicts"`` (it lies on the other side) or ``"inconclusive"`` (it contains zero, e.g.
    exact ties). A level *holds* when every cell supports the claim and is *contradicted* when
    any cell contradicts it; otherwise the claim is *not shown* there.

    Attributes
    ----------
    id, statement, criterion : str
    verdict : str
        ``"holds"``, ``"does not hold"`` (contradicted somewhere, holding nowhere),
        ``"not shown"`` (inconclusive everywhere), ``"holds only for sigma in ..."`` or
        ``"not evaluated: <why>"``.
    detail : str
        Where the claim is contradicted and where it is not shown, e.g.
        ``"contradicted at sigma = 0.5 rad; not shown at sigma = 0, 0.02 rad"`` (may be empty).
    levels : tuple of float
        Noise levels examined.
    holds_at, contradicted_at : tuple of float
        Levels at which the claim holds / is contradicted.
    evidence : list of dict
        One row per level and cell with the numbers and the ``outcome``.
    """

    id: str
    statement: str
    criterion: str
    verdict: str
    levels: tuple[float, ...]
    holds_at: tuple[float, ...]
    contradicted_at: tuple[float, ...] = ()
    detail: str = ""
    evidence: list[dict[str, Any]] = field(default_factory=list)

    def to_markdown(self) -> str:
        detail = f" ({self.detail})" if self.detail else ""
        lines = [
            f"## {self.id}: {self.statement}",
            "",
            f"**Verdict: {self.verdict}**{detail}.",
            "",
            f"Criterion: {self.criterion}",
            "",
        ]
        if self.evidence:
            cols = list(self.evidence[0])
            lines.append("| " + " | ".join(cols) + " |")
            lines.append("|" + "---|" * len(cols))
            for row in self.evidence:
                lines.append("| " + " | ".join(_fmt(row[c]) for c in cols) + " |")
            lines.append("")
        return "\n".join(lines)


def _fmt(v: Any) -> str:
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def _levels_text(values: Sequence[float]) -> str:
    if len(values) == 1:
        return f"sigma = {values[0]:g} rad"
    return "sigma = " + ", ".join(f"{v:g}" for v in values) + " rad"


def verdict_text(levels: Sequence[float], holds_at: Sequence[float],
                 contradicted_at: Sequence[float] | None = None) -> str:
    """Verdict wording from the noise levels examined, those where the claim holds and those
    where it is contradicted (``None``: every level that does not hold is contradicted).

    Examples
    --------
    >>> verdict_text([0.0, 0.1, 0.2, 0.3], [0.1, 0.2])
    'holds only for sigma in [0.1, 0.2] rad'
    >>> verdict_text([0.0, 0.1], [], contradicted_at=[])
    'not shown'
    """
    lv = sorted(levels)
    hv = sorted(holds_at)
    cv = [v for v in lv if v not in hv] if contradicted_at is None else sorted(contradicted_at)
    if not lv:
        return "not evaluated: no noise levels"
    if hv == lv:
        return "holds"
    if not hv:
        return "does not hold" if cv else "not shown"
    if len(hv) == 1:
        return f"holds only for sigma = {hv[0]:g} rad"
    positions = [lv.index(h) for h in hv]
    if positions == list(range(positions[0], positions[-1] + 1)):
        return f"holds only for sigma in [{hv[0]:g}, {hv[-1]:g}] rad"
    return "holds only for sigma in {" + ", ".join(f"{h:g}" for h in hv) + "} rad"


def _detail(levels: Sequence[float], holds_at: Sequence[float],
            contradicted_at: Sequence[float]) -> str:
    """Where a claim that does not hold everywhere is contradicted, and where it is not shown
    (omitted when it would just repeat the verdict)."""
    everything = sorted(levels)
    unshown = [v for v in everything if v not in holds_at and v not in contradicted_at]
    parts = []
    if contradicted_at and sorted(contradicted_at) != everything:
        parts.append("contradicted at " + _levels_text(sorted(contradicted_at)))
    if unshown and unshown != everything:
        parts.append("not shown at " + _levels_text(unshown))
    return "; ".join(parts)


def _paired(rows: Rows, groups: dict[tuple[Any, ...], np.ndarray], a: tuple[Any, ...],
            b: tuple[Any, ...], metric: str) -> tuple[float, float, float, float, int] | None:
    ia, ib = groups.get(a), groups.get(b)
    if ia is None or ib is None or not np.array_equal(rows["seed"][ia], rows["seed"][ib]):
        return None
    cmp = paired_comparison(rows[metric][ia], rows[metric][ib])
    return cmp.diff.mean, cmp.diff.low, cmp.diff.high, cmp.win_rate, cmp.diff.n


def _level_outcome(outcomes: Sequence[str]) -> str:
    if outcomes and all(o == SUPPORTS for o in outcomes):
        return SUPPORTS
    if any(o == CONTRADICTS for o in outcomes):
        return CONTRADICTS
    return INCONCLUSIVE


def _better_everywhere(
    rows: Rows,
    groups: dict[tuple[Any, ...], np.ndarray],
    experiment: str,
    trajectories: Sequence[str],
    pairs: Sequence[tuple[str, str]],
    sigma: float,
) -> tuple[str, list[dict[str, Any]]]:
    """Outcome at one level of "``better`` has smaller errors than ``worse``" over every
    trajectory, integral metric and pair, from the paired differences ``better - worse``."""
    outcomes = []
    evidence = []
    for traj in trajectories:
        for metric in INTEGRALS:
            for better, worse in pairs:
                res = _paired(rows, groups, (experiment, traj, better, sigma),
                              (experiment, traj, worse, sigma), metric)
                if res is None:
                    raise ValueError(
                        f"no paired data for {better!r} vs {worse!r} on {traj!r} at sigma "
                        f"{sigma:g}"
                    )
                mean, low, high, win, n = res
                if n < 2:  # one realisation has no interval: it can show nothing
                    outcome = INCONCLUSIVE
                else:
                    outcome = (SUPPORTS if high < 0.0 else CONTRADICTS if low > 0.0
                               else INCONCLUSIVE)
                outcomes.append(outcome)
                evidence.append({
                    "sigma": sigma, "trajectory": traj, "metric": metric,
                    "comparison": f"{better} - {worse}", "diff_mean": mean,
                    "ci95": f"[{low:.3g}, {high:.3g}]", "win_rate": win, "outcome": outcome,
                })  # fmt: skip
    return _level_outcome(outcomes), evidence


def _claim(id_: str, statement: str, criterion: str, levels: tuple[float, ...],
           per_level: dict[float, str], evidence: list[dict[str, Any]]) -> ClaimResult:
    holds = tuple(v for v in levels if per_level[v] == SUPPORTS)
    contra = tuple(v for v in levels if per_level[v] == CONTRADICTS)
    return ClaimResult(
        id=id_, statement=statement, criterion=criterion,
        verdict=verdict_text(levels, holds, contra), detail=_detail(levels, holds, contra),
        levels=levels, holds_at=holds, contradicted_at=contra, evidence=evidence,
    )


def evaluate_claims(
    rows: Rows,
    *,
    fous: Sequence[float],
    main_fou: float,
    trajectories: Sequence[str],
    experiment: str = "noise",
) -> list[ClaimResult]:
    """Verdicts on C1, C2, C3 and D1 from the rows of ``experiment`` (see module docstring).

    Controllers are found by their labels: ``"FLC"``, ``"IT2FLC FoU {w:g}"`` and
    ``"T1 dead-zone-matched {w:g}"``.
    """
    mask = rows["experiment"] == experiment
    sub = {k: v[mask] for k, v in rows.items()}
    if not mask.any():
        raise ValueError(f"no rows of experiment {experiment!r} to evaluate the claims on")
    groups = _group_index(sub, ("experiment", "trajectory", "controller", "noise_std"))
    levels = tuple(sorted({float(s) for s in sub["noise_std"]}))
    it2 = {w: f"IT2FLC FoU {w:g}" for w in fous}
    main = it2[main_fou]
    matched = f"T1 dead-zone-matched {main_fou:g}"
    results = []

    def comparison_claim(id_: str, statement: str, criterion: str,
                         pairs: Sequence[tuple[str, str]]) -> ClaimResult:
        per_level, evidence = {}, []
        for sigma in levels:
            per_level[sigma], ev = _better_everywhere(sub, groups, experiment, trajectories,
                                                      pairs, sigma)
            evidence += ev
        return _claim(id_, statement, criterion, levels, per_level, evidence)

    results.append(comparison_claim(
        "C1",
        f"The IT2FLC (FoU {main_fou:g}) beats the FLC on IAE, ITAE, ISE and ITSE on all "
        f"{len(trajectories)} trajectories",
        "for every trajectory and metric, the 95 % interval of the paired mean difference "
        "IT2FLC - FLC (same noise realisations) lies below 0; an interval above 0 contradicts "
        "the claim, one containing 0 leaves it not shown",
        [(main, "FLC")],
    ))

    ordered = sorted(fous)
    pairs = [(it2[b], it2[a]) for a, b in itertools.pairwise(ordered)]
    statement = "The integral errors fall as the FoU grows " + " -> ".join(
        f"{w:g}" for w in ordered)
    criterion = ("for every trajectory, metric and consecutive pair of widths, the 95 % "
                 "interval of the paired difference (wider - narrower) lies below 0")
    if pairs:
        results.append(comparison_claim("C2", statement, criterion, pairs))
    else:
        results.append(ClaimResult(
            id="C2", statement=statement, criterion=criterion, levels=levels, holds_at=(),
            verdict="not evaluated: needs at least two FoU widths",
        ))

    lo, hi = C3_TARGET / C3_FACTOR, C3_TARGET * C3_FACTOR
    statement = "The smallest straight-line ISE is of order 0.003"
    criterion = (
        f"the smallest mean straight-line ISE over the FLC and the IT2FLCs lies in "
        f"[{lo:.2g}, {hi:.2g}] (within a factor sqrt(10) of 0.003); its 95 % interval lying "
        "wholly outside that band contradicts the claim"
    )
    if "straight" in trajectories:
        per_level, evidence = {}, []
        for sigma in levels:
            best_label, best_iv = "", None
            for label in ["FLC", *it2.values()]:
                idx = groups.get((experiment, "straight", label, sigma))
                if idx is None:
                    continue
                iv = mean_interval(sub["ISE"][idx])
                if best_iv is None or iv.mean < best_iv.mean:
                    best_label, best_iv = label, iv
            if best_iv is None:
                raise ValueError(f"no straight-line ISE at sigma {sigma:g}")
            if best_iv.n < 2:
                outcome = INCONCLUSIVE
            elif lo <= best_iv.mean <= hi:
                outcome = SUPPORTS
            elif best_iv.high < lo or best_iv.low > hi:
                outcome = CONTRADICTS
            else:
                outcome = INCONCLUSIVE
            position = ("below the band" if best_iv.mean < lo else
                        "above the band" if best_iv.mean > hi else "in the band")
            per_level[sigma] = outcome
            evidence.append({
                "sigma": sigma, "best controller": best_label, "mean ISE": best_iv.mean,
                "ci95": f"[{best_iv.low:.3g}, {best_iv.high:.3g}]", "position": position,
                "outcome": outcome,
            })  # fmt: skip
        results.append(_claim("C3", statement, criterion, levels, per_level, evidence))
    else:
        results.append(ClaimResult(
            id="C3", statement=statement, criterion=criterion, levels=levels, holds_at=(),
            verdict="not evaluated: the study has no straight trajectory",
        ))

    statement = (f"(beyond the paper) The IT2FLC (FoU {main_fou:g}) beats the type-1 FLC with "
                 "the same dead zone, i.e. the FoU helps beyond narrowing the dead zone")
    criterion = "as C1, against the dead-zone-matched type-1 FLC instead of the FLC"
    if any(k[2] == matched for k in groups):
        results.append(comparison_claim("D1", statement, criterion, [(main, matched)]))
    else:
        results.append(ClaimResult(
            id="D1", statement=statement, criterion=criterion, levels=levels, holds_at=(),
            verdict="not evaluated: the study has no dead-zone-matched baseline",
        ))
    return results

"""Judging a claim from its cells: each cell's outcome, each level's status, the verdict.

Cells and outcomes (:mod:`.claimcells`). With noise, a cell:

- *supports* the claim when the 95 % Student-t interval of its statistic lies on the claimed
  side (``below``: below 0; ``band``/``equal``: inside the band). A level *holds* when every
  cell supports the claim: an intersection-union test, whose error rate is that of one cell,
  so no multiplicity correction is needed;
- *contradicts* it when the one-sided t test of the opposite direction (``band``/``equal``:
  of lying outside the band) rejects at family-wise level 2.5 % (the one-sided level of the
  95 % intervals) after the Holm-Bonferroni correction over all the claim's noisy, testable
  cells (every level and path);
- is *inconclusive* otherwise (an interval containing 0, exact ties, a single realisation).

Without noise (sigma = 0) a cell is one run, not a sample: its outcome is *deterministic* (the
exact sign of the difference, never an interval), and such levels are kept out of "holds" and
"contradicted".

A level's status can be *settled* or not: settled when an independent seed set of the same
size would give it again with probability at least a target (the replication probability,
:mod:`.replication`). Verdicts then speak of settled levels only and call the rest
"unsettled" (:func:`verdict_text`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .claimcells import BAND, BELOW, CellData, ClaimDef
from .stats import holm_adjust, interval_text, mean_interval, paired_comparison, t_tail

__all__ = [
    "ALPHA",
    "CONTRADICTED",
    "DETERMINISTIC",
    "HOLDS",
    "NOT_SHOWN",
    "ClaimResult",
    "evidence_texts",
    "judge_claim",
    "levels_text",
    "verdict_text",
]

#: Family-wise level of "contradicted" (one-sided; the 95 % intervals' one-sided level).
ALPHA = 0.025

SUPPORTS, CONTRADICTS, INCONCLUSIVE, DETERMINISTIC = (
    "supports", "contradicts", "inconclusive", "deterministic")
#: Status of a claim at one noise level (or one level and trajectory).
HOLDS, CONTRADICTED, NOT_SHOWN = "holds", "contradicted", "not shown"
#: The path key of a level judged over every trajectory together.
ALL = "all"


@dataclass(frozen=True)
class ClaimResult:
    """The verdict on one claim, with the evidence behind it (see the module docstring).

    Attributes
    ----------
    id, statement, criterion : str
    verdict : str
        ``"holds"``, ``"holds only for σ ∈ {...} rad"``, ``"holds at σ ∈ {...} rad"`` (the
        other levels unsettled), ``"does not hold"`` (contradicted somewhere, holding
        nowhere), ``"not shown"``, ``"unsettled"`` (no level settled) or
        ``"not evaluated: <why>"``, over the noisy levels (the settled ones, once
        :attr:`replication` is known).
    detail : str
        Where the claim is contradicted, not shown or unsettled, and what the noise-free run
        shows, e.g. ``"contradicted at σ = 0.5 rad; deterministic at σ = 0 rad (one
        noise-free run): as claimed in 8 of 12 cells, tied in 4"`` (may be empty).
    levels : tuple of float
        Noisy levels examined (sigma > 0).
    holds_at, contradicted_at : tuple of float
        Noisy levels at which the claim holds / is contradicted (settled ones only, once the
        replication probabilities are known).
    deterministic_at : tuple of float
        Noise-free levels (judged deterministically, one run per cell).
    deterministic : str
        What the noise-free run shows (``""`` without a noise-free level).
    per_trajectory : dict of str -> dict
        The same judgement from each trajectory's cells alone: ``verdict``, ``detail``,
        ``holds_at``, ``contradicted_at``, ``deterministic``, ``status`` (per level)
        (empty for C3, which is about the straight line only).
    level_status : dict of float -> str
        ``"holds"``, ``"contradicted"``, ``"not shown"`` or ``"deterministic"`` per level,
        over every trajectory (whether settled or not).
    evidence : list of dict
        One row per cell: ``sigma, trajectory, metric, comparison, n, diff_mean, ci_low,
        ci_high, p_holm, win_rate, exact, outcome`` (C3: ``sigma, best controller, n,
        mean ISE, ci_low, ci_high, position, p_holm, exact, outcome``; D3 adds ``margin``):
        the 95 % interval, the Holm-adjusted one-sided p-value of the contradiction test (both
        empty for noise-free and single-realisation cells) and, for noise-free cells,
        ``exact``: "as claimed", "tie" or "opposite".
    correction : str
        How "contradicted" is multiplicity-controlled.
    replication : dict of (str, float) -> float
        Replication probability of each level's status, by ``(path, sigma)`` with path a
        trajectory or ``"all"`` (empty until :func:`with_replication`).
    target : float
        The replication probability that settles a level (0: not applied).
    unsettled_at : tuple of float
        Noisy levels (over every trajectory) whose status is not settled.
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
    deterministic_at: tuple[float, ...] = ()
    deterministic: str = ""
    per_trajectory: dict[str, dict[str, Any]] = field(default_factory=dict)
    level_status: dict[float, str] = field(default_factory=dict)
    correction: str = ""
    replication: dict[tuple[str, float], float] = field(default_factory=dict)
    target: float = 0.0
    unsettled_at: tuple[float, ...] = ()

    def settled(self, path: str, sigma: float) -> bool:
        """Whether the status at ``(path, sigma)`` is settled (always, without replication
        probabilities; a noise-free level always is)."""
        if not self.target or sigma == 0.0:
            return True
        return self.replication.get((path, sigma), 0.0) >= self.target

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
        if self.correction:
            lines += [f"Multiplicity: {self.correction}", ""]
        if self.per_trajectory:
            lines += ["| trajectory | verdict |", "|---|---|"]
            for traj, v in self.per_trajectory.items():
                extra = f" ({v['detail']})" if v["detail"] else ""
                lines.append(f"| {traj} | {v['verdict']}{extra} |")
            lines.append("")
        if self.evidence:
            cols = list(self.evidence[0])
            lines.append("| " + " | ".join(cols) + " |")
            lines.append("|" + "---|" * len(cols))
            for row in self.evidence:
                text = evidence_texts(row)
                lines.append("| " + " | ".join(text[c] for c in cols) + " |")
            lines.append("")
        return "\n".join(lines)


def evidence_texts(row: Mapping[str, Any], digits: int = 4) -> dict[str, str]:
    """An evidence row as text: numbers to ``digits`` significant digits, except that the
    estimate and its interval (``diff_mean`` or ``mean ...``, ``ci_low``, ``ci_high``) get the
    digits that keep the printed estimate inside the printed interval
    (:func:`~.stats.interval_text`)."""
    out = {k: _fmt(v) for k, v in row.items()}
    key = "diff_mean" if "diff_mean" in row else next(
        (k for k in row if k.startswith("mean ")), None)
    low, high = row.get("ci_low", ""), row.get("ci_high", "")
    if key is not None and low != "" and high != "" and isinstance(row[key], float):
        mean, lo, hi = float(row[key]), float(low), float(high)
        if lo <= mean <= hi:
            text = interval_text(mean, lo, hi, digits)
            m, rest = text.split(" [")
            a, b = rest.rstrip("]").split(", ")
            out.update({key: m, "ci_low": a, "ci_high": b})
    return out


def _fmt(v: Any) -> str:
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def levels_text(values: Sequence[float]) -> str:
    """Discrete noise levels in one notation: ``σ = 0.1 rad`` or ``σ ∈ {0.1, 0.2} rad``.

    Examples
    --------
    >>> levels_text([0.2, 0.1])
    'σ ∈ {0.1, 0.2} rad'
    """
    v = sorted(values)
    if len(v) == 1:
        return f"σ = {v[0]:g} rad"
    return "σ ∈ {" + ", ".join(f"{x:g}" for x in v) + "} rad"


def verdict_text(levels: Sequence[float], holds_at: Sequence[float],
                 contradicted_at: Sequence[float] | None = None,
                 unsettled_at: Sequence[float] = ()) -> str:
    """Verdict wording from the noise levels examined, those where the claim holds, those
    where it is contradicted (``None``: every level that does not hold is contradicted) and
    those whose status is unsettled (never counted as holding or contradicted).

    Examples
    --------
    >>> verdict_text([0.05, 0.1, 0.2, 0.3], [0.1, 0.2])
    'holds only for σ ∈ {0.1, 0.2} rad'
    >>> verdict_text([0.05, 0.1], [0.1], [], unsettled_at=[0.05])
    'holds at σ = 0.1 rad'
    >>> verdict_text([0.05, 0.1], [], contradicted_at=[])
    'not shown'
    """
    lv = sorted(levels)
    unsettled = set(unsettled_at)
    hv = sorted(h for h in holds_at if h not in unsettled)
    if contradicted_at is None:
        cv = [v for v in lv if v not in hv and v not in unsettled]
    else:
        cv = sorted(c for c in contradicted_at if c not in unsettled)
    if not lv:
        return "not evaluated: no noisy levels"
    if hv == lv:
        return "holds"
    if hv:
        rest_unsettled = all(v in unsettled for v in lv if v not in hv)
        return ("holds at " if rest_unsettled else "holds only for ") + levels_text(hv)
    if cv:
        return "does not hold"
    if all(v in unsettled for v in lv):
        return "unsettled"
    return "not shown"


def _detail(levels: Sequence[float], holds_at: Sequence[float],
            contradicted_at: Sequence[float], deterministic: str = "",
            unsettled_at: Sequence[float] = ()) -> str:
    """Where a claim that does not hold everywhere is contradicted (also when that is every
    level), where it is not shown, where it is unsettled, and what the noise-free run shows."""
    everything = sorted(levels)
    unsettled = sorted(unsettled_at)
    contra = sorted(c for c in contradicted_at if c not in unsettled)
    unshown = [v for v in everything
               if v not in holds_at and v not in contra and v not in unsettled]
    parts = []
    if contra:
        parts.append("contradicted at every noisy level" if contra == everything
                     else "contradicted at " + levels_text(contra))
    if unshown and not (unshown == everything):
        parts.append("not shown at " + levels_text(unshown))
    if unsettled and unsettled != everything:
        parts.append("unsettled at " + levels_text(unsettled))
    if deterministic:
        parts.append(deterministic)
    return "; ".join(parts)


@dataclass
class _Cell:
    """One cell's outcome before and after the family's multiplicity correction."""

    data: CellData
    row: dict[str, Any]
    support: bool  # interval on the claimed side (noisy cells)
    p_contra: float  # one-sided p of the contradiction test (noisy cells)
    deterministic: int | None = None  # -1 as claimed, 0 tie, +1 opposite (noise-free cells)
    testable: bool = True  # False: a single realisation (no interval, no test)
    outcome: str = ""

    @property
    def sigma(self) -> float:
        return self.data.sigma

    @property
    def trajectory(self) -> str:
        return self.data.trajectory


def _band_p(values: np.ndarray, lo: float, hi: float) -> float:
    """One-sided p of "the mean lies outside [lo, hi]" (two disjoint one-sided
    alternatives: below lo or above hi)."""
    return min(1.0, t_tail(values, lo, side="less"), t_tail(values, hi, side="greater"))


def _paired_cell(c: CellData) -> _Cell:
    a, b = c.values
    cmp = paired_comparison(a, b)
    d = a - b
    row: dict[str, Any] = {
        "sigma": c.sigma, "trajectory": c.trajectory, "metric": c.metric,
        "comparison": c.comparison, "n": cmp.diff.n, "diff_mean": cmp.diff.mean,
    }
    equal = c.kind != BELOW
    lo, hi = c.band
    if equal:
        row["margin"] = hi
    if c.sigma == 0.0:
        if equal:
            sign = -1 if lo <= cmp.diff.mean <= hi else 1
        else:
            sign = int(np.sign(cmp.diff.mean))
        row.update(ci_low="", ci_high="", p_holm="", win_rate=cmp.win_rate)
        return _Cell(c, row, False, 1.0, deterministic=sign)
    if cmp.diff.n < 2:
        row.update(ci_low="", ci_high="", p_holm="", win_rate=cmp.win_rate)
        return _Cell(c, row, False, 1.0, testable=False)
    row.update(ci_low=cmp.diff.low, ci_high=cmp.diff.high, p_holm=1.0, win_rate=cmp.win_rate)
    if equal:
        return _Cell(c, row, bool(cmp.diff.low >= lo and cmp.diff.high <= hi),
                     _band_p(d, lo, hi))
    return _Cell(c, row, bool(cmp.diff.high < 0.0), t_tail(d, 0.0, side="greater"))


def _band_cell(c: CellData) -> _Cell:
    lo, hi = c.band
    values = c.sample()
    iv = mean_interval(values)
    position = ("below the band" if iv.mean < lo else
                "above the band" if iv.mean > hi else "in the band")
    row: dict[str, Any] = {
        "sigma": c.sigma, "best controller": c.labels[c.best], "n": iv.n,
        f"mean {c.metric}": iv.mean,
    }
    if c.sigma == 0.0:
        row.update(ci_low="", ci_high="", position=position, p_holm="")
        # -1: in the band (as claimed), +1: outside
        return _Cell(c, row, False, 1.0, deterministic=-1 if lo <= iv.mean <= hi else 1)
    if iv.n < 2:
        row.update(ci_low="", ci_high="", position=position, p_holm="")
        return _Cell(c, row, False, 1.0, testable=False)
    row.update(ci_low=iv.low, ci_high=iv.high, position=position, p_holm=1.0)
    return _Cell(c, row, bool(iv.low >= lo and iv.high <= hi), _band_p(values, lo, hi))


def _finish(cells: Sequence[_Cell]) -> None:
    """Holm-Bonferroni over the family's testable noisy cells, then every cell's outcome."""
    noisy = [c for c in cells if c.deterministic is None and c.testable]
    adjusted = holm_adjust([c.p_contra for c in noisy])
    for c, p in zip(noisy, adjusted, strict=True):
        c.row["p_holm"] = float(p)
        c.outcome = SUPPORTS if c.support else CONTRADICTS if p <= ALPHA else INCONCLUSIVE
    for c in cells:
        if c.deterministic is not None:
            c.outcome = DETERMINISTIC
        elif not c.testable:
            c.outcome = INCONCLUSIVE
        c.row["exact"] = ("" if c.deterministic is None
                          else ("as claimed", "tie", "opposite")[c.deterministic + 1])
        c.row["outcome"] = c.outcome


def _status(cells: Sequence[_Cell]) -> str:
    if any(c.deterministic is not None for c in cells):
        return DETERMINISTIC
    if cells and all(c.outcome == SUPPORTS for c in cells):
        return HOLDS
    if any(c.outcome == CONTRADICTS for c in cells):
        return CONTRADICTED
    return NOT_SHOWN


def _deterministic_text(cells: Sequence[_Cell]) -> str:
    det = [c for c in cells if c.deterministic is not None]
    if not det:
        return ""
    levels = sorted({c.sigma for c in det})
    n = len(det)
    counts = {s: sum(c.deterministic == s for c in det) for s in (-1, 0, 1)}
    if counts[-1] == n:
        how = "as claimed in every cell"
    else:
        parts = [f"as claimed in {counts[-1]} of {n} cells"]
        if counts[1]:
            parts.append(f"opposite in {counts[1]}")
        if counts[0]:
            parts.append(f"tied in {counts[0]}")
        how = ", ".join(parts)
    return f"deterministic at {levels_text(levels)} (one noise-free run): {how}"


def _judge(cells: Sequence[_Cell], levels: Sequence[float],
           unsettled: Sequence[float] = ()) -> dict[str, Any]:
    """Verdict, detail and per-level status of a set of finished cells."""
    status = {s: _status([c for c in cells if c.sigma == s]) for s in levels}
    return _verdict_of(status, _deterministic_text(cells), unsettled)


def _verdict_of(status: Mapping[float, str], det: str,
                unsettled: Sequence[float] = ()) -> dict[str, Any]:
    levels = list(status)
    noisy = tuple(s for s in levels if status[s] != DETERMINISTIC)
    unsettled = tuple(s for s in noisy if s in unsettled)
    holds = tuple(s for s in noisy if status[s] == HOLDS and s not in unsettled)
    contra = tuple(s for s in noisy if status[s] == CONTRADICTED and s not in unsettled)
    verdict = (verdict_text(noisy, holds, contra, unsettled) if noisy
               else "not evaluated: no noisy levels")
    return {
        "verdict": verdict, "detail": _detail(noisy, holds, contra, det, unsettled),
        "holds_at": holds, "contradicted_at": contra, "deterministic": det,
        "levels": noisy, "deterministic_at": tuple(s for s in levels if s not in noisy),
        "status": dict(status), "unsettled_at": unsettled,
    }


_CORRECTION = (
    "a cell contradicts the claim when the one-sided t test of the opposite direction "
    f"rejects at family-wise level {ALPHA:g} after Holm-Bonferroni over all {{m}} noisy cells of "
    "this claim; 'holds' needs every cell to support it (an intersection-union test, which "
    "needs no correction)"
)


def judge_claim(claim: ClaimDef, cells: Sequence[CellData],
                levels: Sequence[float]) -> ClaimResult:
    """The :class:`ClaimResult` of ``claim`` from its cells (:func:`~.claimcells.claim_cells`)
    at ``levels`` (without replication probabilities: every level counts as settled)."""
    judged = [_band_cell(c) if c.kind == BAND else _paired_cell(c) for c in cells]
    _finish(judged)
    overall = _judge(judged, levels)
    per_traj = {}
    if claim.kind != BAND:
        for traj in claim.trajectories:
            mine = [c for c in judged if c.trajectory == traj]
            if mine:
                j = _judge(mine, levels)
                per_traj[traj] = {k: j[k] for k in ("verdict", "detail", "holds_at",
                                                    "contradicted_at", "deterministic",
                                                    "status")}
    m = sum(c.deterministic is None and c.testable for c in judged)
    return ClaimResult(
        id=claim.id, statement=claim.statement, criterion=claim.criterion,
        verdict=overall["verdict"], levels=overall["levels"], holds_at=overall["holds_at"],
        contradicted_at=overall["contradicted_at"], detail=overall["detail"],
        evidence=[c.row for c in judged], deterministic_at=overall["deterministic_at"],
        deterministic=overall["deterministic"], per_trajectory=per_traj,
        level_status=overall["status"], correction=_CORRECTION.format(m=m),
    )


def with_replication(result: ClaimResult, replication: Mapping[tuple[str, float], float],
                     target: float) -> ClaimResult:
    """``result`` with its replication probabilities, its verdicts (overall and per
    trajectory) restated over the settled levels only (``replication >= target``)."""
    if not result.level_status:
        return result
    rep = dict(replication)

    def unsettled(path: str, status: Mapping[float, str]) -> tuple[float, ...]:
        return tuple(s for s, st in status.items()
                     if st != DETERMINISTIC and rep.get((path, s), 0.0) < target)

    overall = _verdict_of(result.level_status, result.deterministic,
                          unsettled(ALL, result.level_status))
    per_traj = {}
    for traj, v in result.per_trajectory.items():
        j = _verdict_of(v["status"], v["deterministic"], unsettled(traj, v["status"]))
        per_traj[traj] = {k: j[k] for k in ("verdict", "detail", "holds_at",
                                            "contradicted_at", "deterministic", "status")}
        per_traj[traj]["unsettled_at"] = j["unsettled_at"]
    return replace(result, verdict=overall["verdict"], detail=overall["detail"],
                   holds_at=overall["holds_at"], contradicted_at=overall["contradicted_at"],
                   per_trajectory=per_traj, replication=rep, target=target,
                   unsettled_at=overall["unsettled_at"])

"""From the study's metrics table to summary statistics and verdicts on the paper's claims.

Nothing here is written by hand: every verdict is computed from the rows it is given, so
feeding other data (synthetic rows in the tests, another robot, another controller) changes the
verdicts accordingly. The modelling choices behind the rows are documented in ``docs/model.md``.

Claims (DESIGN.md sec. 6), evaluated at every noise level of the ``noise`` experiment:

C1  The IT2FLC beats the FLC on all four integral errors on all trajectories: for every
    trajectory and metric, the paired mean difference IT2FLC - FLC is below 0.
C2  Errors fall as the FoU grows (0.1 -> 0.2 -> 0.3): every consecutive pair of the study's
    widths has its paired difference (wider - narrower) below 0, for every trajectory and metric.
C3  The smallest straight-line ISE (over the FLC and the IT2FLCs) is "of order 0.003": within a
    factor sqrt(10) of 0.003, i.e. in the band [0.00095, 0.0095].
D1  (Not a paper claim; what the fair baseline answers.) The IT2FLC beats the type-1 FLC with
    the same dead zone *and* the same slope just outside it
    (:mod:`it2track.experiments.baselines`): what is left is the effect of the footprint itself.
D2  (Not a paper claim.) The IT2FLC beats the type-1 FLC with the same dead zone only (its
    upper membership functions, about twice as steep outside the dead zone). Where C1 holds and
    D2 does not, the gain comes from the narrower dead zone, not from the FoU.

Cells and outcomes. A claim's evidence is a family of *cells* (noise level x trajectory x
metric x compared pair; for C3 one cell per level). With noise, a cell:

- *supports* the claim when the 95 % Student-t interval of its paired mean difference lies on
  the claimed side of 0 (C3: inside the band). A level *holds* when every cell supports the
  claim: an intersection-union test, whose error rate is that of one cell, so no multiplicity
  correction is needed;
- *contradicts* it when the one-sided paired t test of the opposite direction (C3: of lying
  outside the band) rejects at family-wise level 2.5 % (the one-sided level of the 95 %
  intervals) after the Holm-Bonferroni correction over all the claim's noisy cells;
- is *inconclusive* otherwise (an interval containing 0, exact ties, a single realisation).

Without noise (sigma = 0) a cell is one run, not a sample: its outcome is *deterministic*
(the exact sign of the difference is reported, never an interval), and such levels are kept out
of "holds"/"contradicted". Each verdict reads "holds" (at every noisy level), "does not hold"
(contradicted somewhere, holding nowhere), "not shown" (inconclusive everywhere) or "holds only
for sigma in ...", with a detail naming where it is contradicted or not shown and what the
noise-free run shows. The same cell outcomes also give a verdict per trajectory.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .stats import binomial_interval, holm_adjust, mean_interval, paired_comparison, t_tail

__all__ = [
    "ALPHA",
    "INTEGRALS",
    "MEASURED_INTEGRALS",
    "SUMMARY_METRICS",
    "ClaimResult",
    "c3_sigma_range",
    "evaluate_claims",
    "ordering_probability",
    "summarise",
    "verdict_text",
]

INTEGRALS = ("IAE", "ITAE", "ISE", "ITSE")
#: The same integrals on the measured heading error (the open choice "integrals on the true
#: or the measured heading", docs/model.md).
MEASURED_INTEGRALS = tuple(f"{m}_meas" for m in INTEGRALS)
SUMMARY_METRICS = (*INTEGRALS, "pos_rms", "pos_max", "effort", "u_tv", "sat_time")
C3_TARGET = 0.003
C3_FACTOR = math.sqrt(10.0)
#: Family-wise level of "contradicted" (one-sided; the 95 % intervals' one-sided level).
ALPHA = 0.025

Rows = Mapping[str, np.ndarray]

SUPPORTS, CONTRADICTS, INCONCLUSIVE, DETERMINISTIC = (
    "supports", "contradicts", "inconclusive", "deterministic")
#: Status of a claim at one noise level (or one level and trajectory).
HOLDS, CONTRADICTED, NOT_SHOWN = "holds", "contradicted", "not shown"


def _group_index(rows: Rows, keys: Sequence[str]) -> dict[tuple[Any, ...], np.ndarray]:
    """Row indices of each distinct combination of ``keys`` (in first-seen order), each sorted
    by seed so that groups sharing seeds align for paired comparisons. A noise-free group
    (``noise_std == 0``) keeps only its lowest seed: every seed is the same run."""
    groups: dict[tuple[Any, ...], list[int]] = {}
    cols = [rows[k] for k in keys]
    for i in range(len(rows["seed"])):
        groups.setdefault(tuple(c[i] for c in cols), []).append(i)
    seed = rows["seed"]
    sigma = rows["noise_std"]
    out = {}
    for key, idx in groups.items():
        ordered = sorted(idx, key=lambda j: seed[j])
        if sigma[ordered[0]] == 0.0:
            ordered = ordered[:1]
        out[key] = np.asarray(ordered, dtype=np.intp)
    return out


def summarise(rows: Rows, *, reference: str = "FLC") -> list[dict[str, Any]]:
    """One row per (experiment, trajectory, controller, noise level, metric).

    Columns: ``experiment, trajectory, controller, kind, fou, noise_std, metric, n, mean,
    ci_low, ci_high`` and, against ``reference`` on the same seeds, ``diff_mean, diff_low,
    diff_high, win_rate, ties`` (empty for the reference itself or where it is absent; the win
    rate counts ties as half, see :func:`~it2track.experiments.stats.paired_comparison`).
    A noise-free cell is one deterministic run: ``n = 1`` and no interval (``ci_*`` and
    ``diff_low/high`` empty); its ``diff_mean`` and ``win_rate`` (0, 0.5 or 1) are exact.
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
            single = iv.n == 1
            row: dict[str, Any] = {
                "experiment": exp, "trajectory": traj, "controller": ctrl,
                "kind": rows["kind"][idx[0]], "fou": float(rows["fou"][idx[0]]),
                "noise_std": float(sigma), "metric": metric, "n": iv.n, "mean": iv.mean,
                "ci_low": "" if single else iv.low, "ci_high": "" if single else iv.high,
                "diff_mean": "", "diff_low": "", "diff_high": "", "win_rate": "", "ties": "",
            }  # fmt: skip
            if paired:
                assert ref_idx is not None
                cmp = paired_comparison(values, rows[metric][ref_idx])
                row.update(
                    diff_mean=cmp.diff.mean, diff_low="" if single else cmp.diff.low,
                    diff_high="" if single else cmp.diff.high, win_rate=cmp.win_rate,
                    ties=cmp.ties,
                )
            out.append(row)
    return out


@dataclass(frozen=True)
class ClaimResult:
    """The verdict on one claim, with the evidence behind it (see the module docstring).

    Attributes
    ----------
    id, statement, criterion : str
    verdict : str
        ``"holds"``, ``"does not hold"`` (contradicted somewhere, holding nowhere),
        ``"not shown"`` (inconclusive everywhere), ``"holds only for sigma in ..."`` or
        ``"not evaluated: <why>"``, over the noisy levels.
    detail : str
        Where the claim is contradicted and where it is not shown, and what the noise-free run
        shows, e.g. ``"contradicted at sigma = 0.5 rad; deterministic at sigma = 0: as claimed
        in 8 of 12 cells, tied in 4"`` (may be empty).
    levels : tuple of float
        Noisy levels examined (sigma > 0).
    holds_at, contradicted_at : tuple of float
        Noisy levels at which the claim holds / is contradicted.
    deterministic_at : tuple of float
        Noise-free levels (judged deterministically, one run per cell).
    deterministic : str
        What the noise-free run shows (``""`` without a noise-free level).
    per_trajectory : dict of str -> dict
        The same judgement from each trajectory's cells alone: ``verdict``, ``detail``,
        ``holds_at``, ``contradicted_at``, ``deterministic`` (empty for C3, which is about the
        straight line only).
    level_status : dict of float -> str
        ``"holds"``, ``"contradicted"``, ``"not shown"`` or ``"deterministic"`` per level.
    evidence : list of dict
        One row per cell: ``sigma, trajectory, metric, comparison, n, diff_mean, ci_low,
        ci_high, p_holm, win_rate, exact, outcome`` (C3: ``sigma, best controller, n,
        mean ISE, ci_low, ci_high, position, p_holm, exact, outcome``): the 95 % interval,
        the Holm-adjusted one-sided p-value of the contradiction test (both empty for
        noise-free and single-realisation cells) and, for noise-free cells, ``exact``: "as
        claimed", "tie" or "opposite".
    correction : str
        How "contradicted" is multiplicity-controlled.
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
    >>> verdict_text([0.05, 0.1, 0.2, 0.3], [0.1, 0.2])
    'holds only for sigma in [0.1, 0.2] rad'
    >>> verdict_text([0.05, 0.1], [], contradicted_at=[])
    'not shown'
    """
    lv = sorted(levels)
    hv = sorted(holds_at)
    cv = [v for v in lv if v not in hv] if contradicted_at is None else sorted(contradicted_at)
    if not lv:
        return "not evaluated: no noisy levels"
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
            contradicted_at: Sequence[float], deterministic: str = "") -> str:
    """Where a claim that does not hold everywhere is contradicted, where it is not shown
    (omitted when it would just repeat the verdict), and what the noise-free run shows."""
    everything = sorted(levels)
    unshown = [v for v in everything if v not in holds_at and v not in contradicted_at]
    parts = []
    if contradicted_at and sorted(contradicted_at) != everything:
        parts.append("contradicted at " + _levels_text(sorted(contradicted_at)))
    if unshown and unshown != everything:
        parts.append("not shown at " + _levels_text(unshown))
    if deterministic:
        parts.append(deterministic)
    return "; ".join(parts)


@dataclass
class _Cell:
    """One comparison cell before the family's multiplicity correction."""

    sigma: float
    trajectory: str
    row: dict[str, Any]
    support: bool  # interval on the claimed side (noisy cells)
    p_contra: float  # one-sided p of the contradiction test (noisy cells)
    deterministic: int | None = None  # -1 as claimed, 0 tie, +1 opposite (noise-free cells)
    testable: bool = True  # False: a single realisation (no interval, no test)
    outcome: str = ""


def _paired_cell(rows: Rows, ia: np.ndarray, ib: np.ndarray, metric: str, sigma: float,
                 traj: str, comparison: str) -> _Cell:
    a, b = rows[metric][ia], rows[metric][ib]
    cmp = paired_comparison(a, b)
    d = a - b
    row: dict[str, Any] = {
        "sigma": sigma, "trajectory": traj, "metric": metric, "comparison": comparison,
        "n": cmp.diff.n, "diff_mean": cmp.diff.mean,
    }
    if sigma == 0.0:
        sign = int(np.sign(cmp.diff.mean))
        row.update(ci_low="", ci_high="", p_holm="", win_rate=cmp.win_rate)
        return _Cell(sigma, traj, row, False, 1.0, deterministic=sign)
    if cmp.diff.n < 2:
        row.update(ci_low="", ci_high="", p_holm="", win_rate=cmp.win_rate)
        return _Cell(sigma, traj, row, False, 1.0, testable=False)
    row.update(ci_low=cmp.diff.low, ci_high=cmp.diff.high, p_holm=1.0, win_rate=cmp.win_rate)
    return _Cell(sigma, traj, row, bool(cmp.diff.high < 0.0), t_tail(d, 0.0, side="greater"))


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
    return f"deterministic at {_levels_text(levels)} (one noise-free run): {how}"


def _judge(cells: Sequence[_Cell], levels: Sequence[float]) -> dict[str, Any]:
    """Verdict, detail and per-level status of a set of finished cells."""
    status = {s: _status([c for c in cells if c.sigma == s]) for s in levels}
    noisy = tuple(s for s in levels if status[s] != DETERMINISTIC)
    holds = tuple(s for s in noisy if status[s] == HOLDS)
    contra = tuple(s for s in noisy if status[s] == CONTRADICTED)
    det = _deterministic_text(cells)
    verdict = verdict_text(noisy, holds, contra) if noisy else "not evaluated: no noisy levels"
    return {
        "verdict": verdict, "detail": _detail(noisy, holds, contra, det),
        "holds_at": holds, "contradicted_at": contra, "deterministic": det,
        "levels": noisy, "deterministic_at": tuple(s for s in levels if s not in noisy),
        "status": status,
    }


_CORRECTION = (
    "a cell contradicts the claim when the one-sided paired t test of the opposite direction "
    f"rejects at family-wise level {ALPHA:g} after Holm-Bonferroni over all {{m}} noisy cells of "
    "this claim; 'holds' needs every cell to support it (an intersection-union test, which "
    "needs no correction)"
)


def _claim_from_cells(id_: str, statement: str, criterion: str, levels: Sequence[float],
                      cells: list[_Cell], trajectories: Sequence[str]) -> ClaimResult:
    _finish(cells)
    overall = _judge(cells, levels)
    per_traj = {}
    for traj in trajectories:
        mine = [c for c in cells if c.trajectory == traj]
        if mine:
            j = _judge(mine, levels)
            per_traj[traj] = {k: j[k] for k in ("verdict", "detail", "holds_at",
                                                "contradicted_at", "deterministic")}
    m = sum(c.deterministic is None and c.testable for c in cells)
    return ClaimResult(
        id=id_, statement=statement, criterion=criterion, verdict=overall["verdict"],
        levels=overall["levels"], holds_at=overall["holds_at"],
        contradicted_at=overall["contradicted_at"], detail=overall["detail"],
        evidence=[c.row for c in cells], deterministic_at=overall["deterministic_at"],
        deterministic=overall["deterministic"], per_trajectory=per_traj,
        level_status=overall["status"], correction=_CORRECTION.format(m=m),
    )


def _comparison_cells(rows: Rows, groups: dict[tuple[Any, ...], np.ndarray], experiment: str,
                      trajectories: Sequence[str], metrics: Sequence[str],
                      pairs: Sequence[tuple[str, str]], levels: Sequence[float]) -> list[_Cell]:
    """Cells of "``better`` has smaller errors than ``worse``" over every level, trajectory,
    metric and pair, from the paired differences ``better - worse``."""
    cells = []
    for sigma in levels:
        for traj in trajectories:
            for metric in metrics:
                for better, worse in pairs:
                    ia = groups.get((experiment, traj, better, sigma))
                    ib = groups.get((experiment, traj, worse, sigma))
                    if (ia is None or ib is None
                            or not np.array_equal(rows["seed"][ia], rows["seed"][ib])):
                        raise ValueError(
                            f"no paired data for {better!r} vs {worse!r} on {traj!r} at sigma "
                            f"{sigma:g}"
                        )
                    cells.append(_paired_cell(rows, ia, ib, metric, sigma, traj,
                                              f"{better} - {worse}"))
    return cells


def _c3_cells(rows: Rows, groups: dict[tuple[Any, ...], np.ndarray], experiment: str,
              labels: Sequence[str], metric: str, levels: Sequence[float]) -> list[_Cell]:
    lo, hi = C3_TARGET / C3_FACTOR, C3_TARGET * C3_FACTOR
    cells = []
    for sigma in levels:
        best_label, best_idx, best_mean = "", None, math.inf
        for label in labels:
            idx = groups.get((experiment, "straight", label, sigma))
            if idx is None:
                continue
            mean = float(np.mean(rows[metric][idx]))
            if best_idx is None or mean < best_mean:
                best_label, best_idx, best_mean = label, idx, mean
        if best_idx is None:
            raise ValueError(f"no straight-line {metric} at sigma {sigma:g}")
        values = rows[metric][best_idx]
        iv = mean_interval(values)
        position = ("below the band" if iv.mean < lo else
                    "above the band" if iv.mean > hi else "in the band")
        row: dict[str, Any] = {
            "sigma": sigma, "best controller": best_label, "n": iv.n, f"mean {metric}": iv.mean,
        }
        if sigma == 0.0:
            row.update(ci_low="", ci_high="", position=position, p_holm="")
            # -1: in the band (as claimed), +1: outside
            cells.append(_Cell(sigma, "straight", row, False, 1.0,
                               deterministic=-1 if lo <= iv.mean <= hi else 1))
            continue
        if iv.n < 2:
            row.update(ci_low="", ci_high="", position=position, p_holm="")
            cells.append(_Cell(sigma, "straight", row, False, 1.0, testable=False))
            continue
        row.update(ci_low=iv.low, ci_high=iv.high, position=position, p_holm=1.0)
        # Outside the band: below lo or above hi (two disjoint one-sided alternatives).
        p_out = min(t_tail(values, lo, side="less"), t_tail(values, hi, side="greater"))
        cells.append(_Cell(sigma, "straight", row, bool(iv.low >= lo and iv.high <= hi),
                           min(1.0, p_out)))
    return cells


def evaluate_claims(
    rows: Rows,
    *,
    fous: Sequence[float],
    main_fou: float,
    trajectories: Sequence[str],
    experiment: str = "noise",
    metrics: Sequence[str] = INTEGRALS,
) -> list[ClaimResult]:
    """Verdicts on C1, C2, C3, D1 and D2 from the rows of ``experiment`` (module docstring).

    Controllers are found by their labels: ``"FLC"``, ``"IT2FLC FoU {w:g}"``,
    ``"T1 slope-matched {w:g}"`` and ``"T1 dead-zone-matched {w:g}"``. ``metrics`` are the
    four integrals compared (default on the true heading error; :data:`MEASURED_INTEGRALS` for
    the measured one); C3 uses the third (ISE).
    """
    mask = rows["experiment"] == experiment
    sub = {k: v[mask] for k, v in rows.items()}
    if not mask.any():
        raise ValueError(f"no rows of experiment {experiment!r} to evaluate the claims on")
    if len(metrics) != len(INTEGRALS):
        raise ValueError(f"metrics={tuple(metrics)!r} must name the four integrals "
                         "(IAE, ITAE, ISE, ITSE forms)")
    groups = _group_index(sub, ("experiment", "trajectory", "controller", "noise_std"))
    levels = tuple(sorted({float(s) for s in sub["noise_std"]}))
    it2 = {w: f"IT2FLC FoU {w:g}" for w in fous}
    main = it2[main_fou]
    heading = "measured" if metrics[0].endswith("_meas") else "true"
    names = ", ".join(metrics)
    results = []

    def comparison_claim(id_: str, statement: str, criterion: str,
                         pairs: Sequence[tuple[str, str]]) -> ClaimResult:
        cells = _comparison_cells(sub, groups, experiment, trajectories, metrics, pairs, levels)
        return _claim_from_cells(id_, statement, criterion, levels, cells, trajectories)

    results.append(comparison_claim(
        "C1",
        f"The IT2FLC (FoU {main_fou:g}) beats the FLC on IAE, ITAE, ISE and ITSE on all "
        f"{len(trajectories)} trajectories",
        f"for every trajectory and metric ({names}, on the {heading} heading error), the 95 % "
        "interval of the paired mean difference IT2FLC - FLC (same noise realisations) lies "
        "below 0",
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
    ise = metrics[2]
    statement = "The smallest straight-line ISE is of order 0.003"
    criterion = (
        f"the 95 % interval of the smallest mean straight-line {ise} over the FLC and the "
        f"IT2FLCs lies inside [{lo:.2g}, {hi:.2g}] (within a factor sqrt(10) of 0.003); it "
        "contradicts the claim when the test of lying outside the band (below or above) rejects"
    )
    if "straight" in trajectories:
        cells = _c3_cells(sub, groups, experiment, ["FLC", *it2.values()], ise, levels)
        c3 = _claim_from_cells("C3", statement, criterion, levels, cells, ())
        results.append(c3)
    else:
        results.append(ClaimResult(
            id="C3", statement=statement, criterion=criterion, levels=levels, holds_at=(),
            verdict="not evaluated: the study has no straight trajectory",
        ))

    for id_, label, what in (
        ("D1", f"T1 slope-matched {main_fou:g}",
         "the same dead zone and the same slope just outside it"),
        ("D2", f"T1 dead-zone-matched {main_fou:g}", "the same dead zone only"),
    ):
        statement = (f"(beyond the paper) The IT2FLC (FoU {main_fou:g}) beats the type-1 FLC "
                     f"with {what}")
        criterion = f"as C1, against the type-1 FLC with {what} instead of the FLC"
        if any(k[2] == label for k in groups):
            results.append(comparison_claim(id_, statement, criterion, [(main, label)]))
        else:
            results.append(ClaimResult(
                id=id_, statement=statement, criterion=criterion, levels=levels, holds_at=(),
                verdict=f"not evaluated: the study has no {label!r} baseline",
            ))
    return results


def c3_sigma_range(claim: ClaimResult) -> dict[str, Any]:
    """The noise range in which C3's best straight-line ISE lies in the band, by log-log
    interpolation of the per-level means (and of their interval bounds) between noisy levels.

    Returns ``{"band": (lo, hi), "levels_in_band": [...], "enters": ..., "leaves": ...}``
    where ``enters``/``leaves`` are ``None`` or ``{"sigma": s, "range": (s_a, s_b)}``: the
    interpolated sigma at which the mean ISE crosses into / out of the band (rising with
    sigma), and the sigmas at which the interval bounds cross it (the crossing's interval).
    """
    lo, hi = C3_TARGET / C3_FACTOR, C3_TARGET * C3_FACTOR
    pts = []
    for row in claim.evidence:
        if row["sigma"] == 0.0 or row.get("ci_low", "") == "":
            continue
        mean = next(v for k, v in row.items() if k.startswith("mean "))
        pts.append((row["sigma"], mean, row["ci_low"], row["ci_high"]))
    pts.sort()

    def crossing(col: int, level: float) -> float | None:
        """First sigma at which column ``col`` rises through ``level`` (log-log linear, exact
        for a power law ``ISE = c sigma^k``; linear from a value of 0, e.g. a controller that
        never leaves its dead zone)."""
        for (s0, *v0), (s1, *v1) in itertools.pairwise(pts):
            a, b = v0[col], v1[col]
            if not a < level <= b:
                continue
            if a > 0.0:
                f = (math.log(level) - math.log(a)) / (math.log(b) - math.log(a))
                return math.exp(math.log(s0) + f * (math.log(s1) - math.log(s0)))
            return s0 + (level - a) / (b - a) * (s1 - s0)
        return None

    def with_range(level: float) -> dict[str, Any] | None:
        mid = crossing(0, level)
        if mid is None:
            return None
        # The upper bound reaches the level first (smaller sigma), the lower bound last.
        return {"sigma": mid, "range": (crossing(2, level), crossing(1, level))}

    return {
        "band": (lo, hi),
        "levels_in_band": [p[0] for p in pts if lo <= p[1] <= hi],
        "enters": with_range(lo),
        "leaves": with_range(hi),
    }


def ordering_probability(
    rows: Rows,
    *,
    fous: Sequence[float],
    trajectories: Sequence[str],
    experiment: str = "noise",
    metrics: Sequence[str] = INTEGRALS,
    level: float = 0.95,
) -> list[dict[str, Any]]:
    """Probability that a *single* noise realisation shows the paper's strict ordering
    FLC > IT2FLC(w_1) > IT2FLC(w_2) > ... (widths ascending) on every metric, per noise level:
    over all trajectories together (``trajectory = "all"``, as the paper's single-run figures
    show) and on each trajectory alone.

    Returns rows ``sigma, trajectory, n, k, p, ci_low, ci_high, deterministic``: ``k`` of
    ``n`` realisations (seed indices) show the ordering, ``p = k / n`` with its exact
    Clopper-Pearson ``level`` interval. A noise-free level is one run (``n = 1``,
    ``deterministic = True``, no interval).
    """
    mask = rows["experiment"] == experiment
    sub = {k: v[mask] for k, v in rows.items()}
    groups = _group_index(sub, ("trajectory", "controller", "noise_std"))
    labels = ["FLC", *(f"IT2FLC FoU {w:g}" for w in sorted(fous))]
    levels = sorted({float(s) for s in sub["noise_std"]})
    out = []
    for sigma in levels:
        per_traj = {}
        seeds = None
        for traj in trajectories:
            idx = [groups.get((traj, label, sigma)) for label in labels]
            if any(i is None for i in idx):
                raise ValueError(f"ordering_probability: missing controllers on {traj!r} at "
                                 f"sigma {sigma:g}")
            s0 = sub["seed"][idx[0]]
            if any(not np.array_equal(sub["seed"][i], s0) for i in idx):
                raise ValueError("ordering_probability: controllers saw different seeds")
            if seeds is not None and not np.array_equal(seeds, s0):
                raise ValueError("ordering_probability: trajectories saw different seeds")
            seeds = s0
            ok = np.ones(len(s0), dtype=bool)
            for metric in metrics:
                v = np.stack([sub[metric][i] for i in idx])  # (controllers, seeds)
                ok &= np.all(v[:-1] > v[1:], axis=0)
            per_traj[traj] = ok
        everywhere = np.logical_and.reduce(list(per_traj.values()))
        for name, ok in [("all", everywhere), *per_traj.items()]:
            n, k = int(ok.size), int(ok.sum())
            det = sigma == 0.0
            low, high = ("", "") if det else binomial_interval(k, n, level)
            out.append({"sigma": sigma, "trajectory": name, "n": n, "k": k, "p": k / n,
                        "ci_low": low, "ci_high": high, "deterministic": det})
    return out

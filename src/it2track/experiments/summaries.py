"""Summaries of the metrics table: per-cell means and paired differences (summary.csv), the
noise range of C3's band, and the probability that one realisation shows the paper's ordering.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .claimcells import C3_FACTOR, C3_TARGET, INTEGRALS, _common
from .claimcells import group_index as _group_index
from .judgement import ClaimResult
from .stats import binomial_interval, mean_interval, paired_comparison

__all__ = ["SUMMARY_METRICS", "c3_sigma_range", "ordering_probability", "summarise"]

SUMMARY_METRICS = (*INTEGRALS, "pos_rms", "pos_max", "effort", "u_tv", "sat_time")

Rows = Mapping[str, np.ndarray]


def summarise(rows: Rows, *, reference: str = "FLC") -> list[dict[str, Any]]:
    """One row per (experiment, trajectory, controller, noise level, metric).

    Columns: ``experiment, trajectory, controller, kind, fou, noise_std, metric, n, mean,
    ci_low, ci_high`` and, against ``reference`` on the same seeds, ``diff_mean, diff_low,
    diff_high, win_rate, ties`` (empty for the reference itself or where it is absent; the win
    rate counts ties as half, see :func:`~it2track.experiments.stats.paired_comparison`),
    over the seeds both have (``diff_n`` of them).
    A noise-free cell is one deterministic run: ``n = 1`` and no interval (``ci_*`` and
    ``diff_low/high`` empty); its ``diff_mean`` and ``win_rate`` (0, 0.5 or 1) are exact.
    """
    keys = ("experiment", "trajectory", "controller", "noise_std")
    groups = _group_index(rows, keys)
    out: list[dict[str, Any]] = []
    for (exp, traj, ctrl, sigma), idx in groups.items():
        ref_idx = groups.get((exp, traj, reference, sigma))
        paired = ref_idx is not None and ctrl != reference
        if paired:
            assert ref_idx is not None
            mine, ref_idx = _common(rows["seed"], [idx, ref_idx])
            paired = mine.size > 0
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
                "diff_n": "",
            }  # fmt: skip
            if paired:
                assert ref_idx is not None
                cmp = paired_comparison(rows[metric][mine], rows[metric][ref_idx])
                row.update(
                    diff_mean=cmp.diff.mean, diff_low="" if single else cmp.diff.low,
                    diff_high="" if single else cmp.diff.high, win_rate=cmp.win_rate,
                    ties=cmp.ties, diff_n=cmp.diff.n,
                )
            out.append(row)
    return out


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
    ``deterministic = True``, no interval). Controllers and trajectories may have different
    seeds (seeds by need); each count uses the seeds all its controllers (and, for ``"all"``,
    all trajectories) have.
    """
    mask = rows["experiment"] == experiment
    sub = {k: v[mask] for k, v in rows.items()}
    groups = _group_index(sub, ("trajectory", "controller", "noise_std"))
    labels = ["FLC", *(f"IT2FLC FoU {w:g}" for w in sorted(fous))]
    levels = sorted({float(s) for s in sub["noise_std"]})
    out = []
    for sigma in levels:
        per_traj = {}
        seeds_of = {}
        for traj in trajectories:
            found = [groups.get((traj, label, sigma)) for label in labels]
            if any(i is None for i in found):
                raise ValueError(f"ordering_probability: missing controllers on {traj!r} at "
                                 f"sigma {sigma:g}")
            idx = _common(sub["seed"], [i for i in found if i is not None])
            s0 = sub["seed"][idx[0]]
            seeds_of[traj] = s0
            ok = np.ones(len(s0), dtype=bool)
            for metric in metrics:
                v = np.stack([sub[metric][i] for i in idx])  # (controllers, seeds)
                ok &= np.all(v[:-1] > v[1:], axis=0)
            per_traj[traj] = ok
        common = set(seeds_of[trajectories[0]].tolist())
        for traj in trajectories[1:]:
            common &= set(seeds_of[traj].tolist())
        everywhere = np.logical_and.reduce([
            ok[np.isin(seeds_of[traj], sorted(common))] for traj, ok in per_traj.items()])
        for name, ok in [("all", everywhere), *per_traj.items()]:
            n, k = int(ok.size), int(ok.sum())
            det = sigma == 0.0
            low, high = ("", "") if det else binomial_interval(k, n, level)
            out.append({"sigma": sigma, "trajectory": name, "n": n, "k": k, "p": k / n,
                        "ci_low": low, "ci_high": high, "deterministic": det})
    return out

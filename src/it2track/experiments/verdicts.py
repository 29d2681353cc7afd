"""``verdicts.csv``: one row per claim x path (and all paths) x noise level, with its status,
the realisations behind it, the statistic that decided it and its replication probability.

The *decisive cell* of a level is the one its status hinges on:

- *holds*: the supporting cell closest to not supporting (``below``: the largest
  ``mean / (ci_high - ci_low)``, i.e. the largest t statistic; ``band``/``equal``: the
  smallest distance of the interval from a band edge, in interval widths);
- *contradicted*: the contradicting cell with the smallest Holm-adjusted p-value;
- *not shown*: the cell furthest from supporting, by the same measure;
- *deterministic* (no noise): none; ``decisive`` says how many cells went as claimed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from .claimcells import BAND, BELOW, ClaimDef
from .judgement import ALL, CONTRADICTED, DETERMINISTIC, HOLDS, ClaimResult

__all__ = ["VERDICT_COLUMNS", "compare_verdicts", "verdict_rows"]

VERDICT_COLUMNS = ("claim", "path", "sigma", "status", "settled", "replication", "n", "cells",
                   "supporting", "contradicting", "decisive", "estimate", "ci_low", "ci_high",
                   "p_holm")


def _estimate(row: Mapping[str, Any]) -> float:
    if "diff_mean" in row:
        return float(row["diff_mean"])
    return float(next(v for k, v in row.items() if k.startswith("mean ")))


def _weakness(claim: ClaimDef, row: Mapping[str, Any]) -> float:
    """How far a cell is from supporting, in interval widths (larger: weaker)."""
    low, high = row["ci_low"], row["ci_high"]
    if low == "" or high == "":
        return math.inf
    width = float(high) - float(low)
    if claim.kind == BELOW:
        mean = _estimate(row)
        return mean / width if width > 0 else math.copysign(math.inf, mean)
    lo, hi = claim.band if claim.kind == BAND else (-float(row["margin"]), float(row["margin"]))
    margin = min(float(low) - lo, hi - float(high))
    return -margin / width if width > 0 else -math.copysign(math.inf, margin)


def _describe(claim: ClaimDef, row: Mapping[str, Any]) -> str:
    if claim.kind == BAND:
        return f"{row.get('trajectory', 'straight')} best: {row['best controller']}"
    return f"{row['trajectory']} {row['metric']}: {row['comparison']}"


def verdict_rows(claims: Sequence[ClaimDef],
                 results: Sequence[ClaimResult]) -> list[dict[str, Any]]:
    """The rows of ``verdicts.csv`` (columns :data:`VERDICT_COLUMNS`) for judged claims with
    replication probabilities (:func:`~.replication.replicate_claims`). ``n`` is the fewest
    realisations behind any cell of the level (1 without noise). Claims not evaluated have no
    rows. A level without replication probabilities (none computed) is reported as settled
    with an empty ``replication``."""
    out: list[dict[str, Any]] = []
    for d, r in zip(claims, results, strict=True):
        if d.missing or not r.level_status:
            continue
        paths = [ALL] if d.kind == BAND else [ALL, *r.per_trajectory]
        for path in paths:
            status_of = (r.level_status if path == ALL
                         else r.per_trajectory[path]["status"])
            for sigma, status in status_of.items():
                mine = [e for e in r.evidence if e["sigma"] == sigma
                        and (path == ALL or e.get("trajectory") == path)]
                rep = r.replication.get((path, sigma))
                row: dict[str, Any] = {
                    "claim": d.id, "path": path, "sigma": sigma, "status": status,
                    "settled": r.settled(path, sigma),
                    "replication": "" if rep is None else rep,
                    "n": min((int(e["n"]) for e in mine), default=0), "cells": len(mine),
                    "supporting": sum(e["outcome"] == "supports" for e in mine),
                    "contradicting": sum(e["outcome"] == "contradicts" for e in mine),
                    "decisive": "", "estimate": "", "ci_low": "", "ci_high": "",
                    "p_holm": "",
                }
                if status == DETERMINISTIC:
                    as_claimed = sum(e["exact"] == "as claimed" for e in mine)
                    row["decisive"] = f"{as_claimed} of {len(mine)} cells as claimed"
                    out.append(row)
                    continue
                if status == CONTRADICTED:
                    pick = min((e for e in mine if e["outcome"] == "contradicts"),
                               key=lambda e: float(e["p_holm"]))
                elif status == HOLDS:
                    pick = max(mine, key=lambda e: _weakness(d, e))
                else:
                    pool = [e for e in mine if e["outcome"] != "supports"] or mine
                    pick = max(pool, key=lambda e: _weakness(d, e))
                row.update(decisive=_describe(d, pick), estimate=_estimate(pick),
                           ci_low=pick["ci_low"], ci_high=pick["ci_high"],
                           p_holm=pick["p_holm"])
                out.append(row)
    return out


def compare_verdicts(a: Sequence[Mapping[str, Any]],
                     b: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """Two runs' ``verdicts.csv`` rows (e.g. two base seeds) compared level by level.

    Returns ``{"levels": k, "settled_either": m, "agree": j, "disagree": [...]}``: of the
    ``k`` noisy levels both runs judged, the ``m`` that either run reports as settled and,
    of those, how many have the same status in both runs; ``disagree`` lists the others as
    ``(claim, path, sigma, status_a, replication_a, status_b, replication_b)``. A settled
    status is a verdict: the done-when of the replication probability is an empty
    ``disagree``.

    Raises
    ------
    ValueError
        If the runs judged different levels.
    """
    def key(r: Mapping[str, Any]) -> tuple[str, str, float]:
        return (str(r["claim"]), str(r["path"]), float(r["sigma"]))

    ka = {key(r): r for r in a}
    kb = {key(r): r for r in b}
    if set(ka) != set(kb):
        raise ValueError(f"compare_verdicts: the runs judged different levels "
                         f"({sorted(set(ka) ^ set(kb))[:4]} ...)")
    levels = settled = agree = 0
    disagree = []
    for k in sorted(ka):
        ra, rb = ka[k], kb[k]
        if k[2] == 0.0:
            continue
        levels += 1

        def settled_of(r: Mapping[str, Any]) -> bool:
            v = r["settled"]
            return v is True or str(v) == "True"

        if not (settled_of(ra) or settled_of(rb)):
            continue
        settled += 1
        if ra["status"] == rb["status"]:
            agree += 1
        else:
            disagree.append((*k, ra["status"], float(ra["replication"]), rb["status"],
                             float(rb["replication"])))
    return {"levels": levels, "settled_either": settled, "agree": agree,
            "disagree": disagree}

"""The verdicts on the paper's claims: at a glance (top of the page) and in full, with the
evidence cells behind each."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from markupsafe import Markup

from ...experiments.judgement import evidence_texts
from ...experiments.stats import interval_text
from .env import fmt, render

__all__ = ["claims_section", "glance", "verdict_class"]

#: Outcome of one evidence cell -> CSS class (a tie is inconclusive, never a loss).
_OUTCOME_CLASS = {"supports": "o-sup", "contradicts": "o-con", "inconclusive": "o-inc"}


def verdict_class(verdict: str) -> str:
    """CSS class of a verdict: green "holds", red "does not hold", amber "holds only for …",
    grey "not shown" / "not evaluated" (any parenthetical detail after the verdict is ignored)."""
    v = verdict.strip().lower()
    if v.startswith(("holds only", "holds at")):
        return "v-partial"
    if v == "holds" or v.startswith(("holds ", "holds(", "holds;", "holds,")):
        return "v-holds"
    if v.startswith("does not hold"):
        return "v-not"
    return "v-na"


def _claim_attr(claim: Any, name: str, default: Any = "") -> Any:
    if isinstance(claim, Mapping):
        return claim.get(name, default)
    return getattr(claim, name, default)


def _claim_detail(claim: Any) -> str:
    """Where the claim is contradicted / not shown (``ClaimResult.detail``), unless the verdict
    already says it."""
    detail = str(_claim_attr(claim, "detail", "") or "").strip()
    return "" if not detail or detail in str(_claim_attr(claim, "verdict")) else detail


def _outcome(row: Mapping[str, Any]) -> tuple[str, str]:
    """(text, CSS class) of an evidence row's outcome: the ``outcome`` column, or the older
    boolean ``passes`` (where "no" may be a tie, so it is grey, not red)."""
    if "outcome" in row:
        text = str(row["outcome"])
        return text, _OUTCOME_CLASS.get(text.strip().lower(), "o-inc")
    if "passes" in row:
        ok = bool(row["passes"])
        return ("supports" if ok else "not shown"), ("o-sup" if ok else "o-inc")
    return "", ""


def _evidence(evidence: Sequence[Mapping[str, Any]]) -> dict[str, Any] | None:
    """Header and rows of a claim's evidence table (None without evidence)."""
    if not evidence:
        return None
    first = evidence[0]
    cols = [k for k in first if k not in ("outcome", "passes")]
    numeric = [isinstance(first[k], float | int | np.floating | np.integer)
               and not isinstance(first[k], bool | np.bool_) for k in cols]
    has_outcome = "outcome" in first or "passes" in first
    rows = []
    for row in evidence:
        text, cls = _outcome(row)
        shown = evidence_texts(row) if "ci_low" in row else {}
        rows.append({"cells": [(shown.get(k, fmt(row.get(k, ""))), is_num)
                               for k, is_num in zip(cols, numeric, strict=True)],
                     "outcome": text, "outcome_cls": cls})
    return {"header": [*cols, "outcome"] if has_outcome else cols, "rows": rows,
            "has_outcome": has_outcome}


def _claim(claim: Any) -> dict[str, Any]:
    verdict = str(_claim_attr(claim, "verdict"))
    per = _claim_attr(claim, "per_trajectory", {}) or {}
    return {
        "id": _claim_attr(claim, "id"),
        "statement": _claim_attr(claim, "statement"),
        "criterion": _claim_attr(claim, "criterion"),
        "verdict": verdict,
        "detail": _claim_detail(claim),
        "cls": verdict_class(verdict),
        "evidence": _evidence(list(_claim_attr(claim, "evidence", []) or [])),
        "per_trajectory": {t: {"verdict": str(v.get("verdict", "")),
                               "detail": str(v.get("detail", "") or ""),
                               "cls": verdict_class(str(v.get("verdict", "")))}
                           for t, v in per.items()},
        "correction": str(_claim_attr(claim, "correction", "") or ""),
    }


def glance(claims: Sequence[Any], *, smoke: bool = False) -> Markup:
    """The verdicts in a box at the top of the page (empty without claims); ``smoke``: a
    ``--quick`` run's, marked as such."""
    return render("sections/glance.html.j2", claims=[_claim(c) for c in claims], smoke=smoke)


def _levels(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """``verdicts.csv``'s rows over all paths, per claim: one cell per noise level with the
    status, its replication probability and the realisations behind it."""
    out: dict[str, dict[str, Any]] = {}
    for r in rows:
        if r["path"] != "all":
            continue
        c = out.setdefault(str(r["claim"]), {"id": r["claim"], "cells": []})
        det = r["status"] == "deterministic"
        c["cells"].append({
            "sigma": f"{float(r['sigma']):g}", "status": str(r["status"]),
            "settled": bool(r["settled"]),
            "replication": "" if det else f"{float(r['replication']):.2f}",
            "n": r["n"], "decisive": r["decisive"] if det else "",
        })
    return list(out.values())


def _c3_range(claims: Sequence[Any]) -> dict[str, Any] | None:
    """C3 as what it is: the noise range in which the smallest straight-line ISE lies in the
    band (:func:`~it2track.experiments.analysis.c3_sigma_range`), or None without C3 data."""
    from ...experiments.analysis import c3_sigma_range

    c3 = next((c for c in claims if _claim_attr(c, "id") == "C3"
               and not isinstance(c, Mapping) and _claim_attr(c, "evidence")), None)
    if c3 is None:
        return None
    rng = c3_sigma_range(c3)
    lo, hi = rng["band"]
    crossings = []
    for key in ("enters", "leaves"):
        cross = rng[key]
        if cross is not None:
            a, b = cross["range"]
            crossings.append({"what": key, "sigma": fmt(cross["sigma"], 3),
                              "range": None if a is None or b is None
                              else (fmt(a, 3), fmt(b, 3))})
    return {"band": (fmt(lo, 2), fmt(hi, 2)),
            "levels": ", ".join(f"{s:g}" for s in rng["levels_in_band"]),
            "crossings": crossings}


def _ordering(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """The single-realisation probability table (``StudyResult.ordering``)."""
    out = []
    for r in rows:
        out.append({"sigma": f"{float(r['sigma']):g}", "trajectory": r["trajectory"],
                    "k": r["k"], "n": r["n"], "p": fmt(r["p"], 3),
                    "interval": "deterministic (one run)" if r["deterministic"]
                    else interval_text(r["p"], r["ci_low"], r["ci_high"]).split(" ", 1)[1]})
    return out


def claims_section(claims: Sequence[Any], *, trajectories: Sequence[str] = (),
                   ordering: Sequence[Mapping[str, Any]] = (),
                   fous: Sequence[float] = (), levels: Sequence[Mapping[str, Any]] = (),
                   target: float = 0.95) -> Markup:
    """The claims table (statement, verdict, criterion), every level's status with its
    replication probability (``levels``: ``verdicts.csv``'s rows), the verdicts per
    trajectory, how "contradicted" is multiplicity-controlled, C3 as a noise range, the
    probability that one realisation shows the paper's ordering, and each claim's evidence
    cells."""
    rows = [_claim(c) for c in claims]
    per_traj = [r for r in rows if r["per_trajectory"]]
    corrections = [(r["id"], r["correction"]) for r in rows if r["correction"]]
    return render("sections/claims.html.j2", claims=rows, trajectories=list(trajectories),
                  per_trajectory=per_traj, corrections=corrections, c3=_c3_range(claims),
                  ordering=_ordering(ordering), levels=_levels(levels), target=f"{target:g}",
                  order=" > ".join(["FLC", *(f"FoU {w:g}" for w in sorted(fous))]))

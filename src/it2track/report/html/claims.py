"""The verdicts on the paper's claims: at a glance (top of the page) and in full, with the
evidence cells behind each."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from markupsafe import Markup

from .env import fmt, render

__all__ = ["claims_section", "glance", "verdict_class"]

#: Outcome of one evidence cell -> CSS class (a tie is inconclusive, never a loss).
_OUTCOME_CLASS = {"supports": "o-sup", "contradicts": "o-con", "inconclusive": "o-inc"}


def verdict_class(verdict: str) -> str:
    """CSS class of a verdict: green "holds", red "does not hold", amber "holds only for …",
    grey "not shown" / "not evaluated" (any parenthetical detail after the verdict is ignored)."""
    v = verdict.strip().lower()
    if v.startswith("holds only"):
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
        rows.append({"cells": [(fmt(row.get(k, "")), is_num)
                               for k, is_num in zip(cols, numeric, strict=True)],
                     "outcome": text, "outcome_cls": cls})
    return {"header": [*cols, "outcome"] if has_outcome else cols, "rows": rows,
            "has_outcome": has_outcome}


def _claim(claim: Any) -> dict[str, Any]:
    verdict = str(_claim_attr(claim, "verdict"))
    return {
        "id": _claim_attr(claim, "id"),
        "statement": _claim_attr(claim, "statement"),
        "criterion": _claim_attr(claim, "criterion"),
        "verdict": verdict,
        "detail": _claim_detail(claim),
        "cls": verdict_class(verdict),
        "evidence": _evidence(list(_claim_attr(claim, "evidence", []) or [])),
    }


def glance(claims: Sequence[Any]) -> Markup:
    """The verdicts in a box at the top of the page (empty without claims)."""
    return render("sections/glance.html.j2", claims=[_claim(c) for c in claims])


def claims_section(claims: Sequence[Any]) -> Markup:
    """The claims table (statement, verdict, criterion) and each claim's evidence cells."""
    return render("sections/claims.html.j2", claims=[_claim(c) for c in claims])

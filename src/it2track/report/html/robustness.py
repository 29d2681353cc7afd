"""The page's robustness section: every claim re-judged under the paper's open modelling choices
(docs/model.md), which choices flip or change its verdict, the heat map, and the global
sensitivity ranking."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from markupsafe import Markup

from ...experiments.study import StudyResult
from ..counts import count_text
from .env import render

__all__ = ["MODEL_DOC", "robustness_section"]

#: The repository's document of the modelling choices, which the page cites.
MODEL_DOC = "docs/model.md"


def _choice_rows(rob: Any) -> list[dict[str, str]]:
    rows = []
    for c in rob.config.choices:
        rows.append({
            "name": c.name, "sets": ", ".join(c.sets), "default": c.describe(c.default),
            "alternatives": "; ".join(c.describe(a) for a in c.alternatives),
            "description": c.description,
            "doc": f"{MODEL_DOC}#{c.doc}" if c.doc else MODEL_DOC,
        })
    return rows


def claim_robustness(rob: Any) -> list[dict[str, Any]]:
    """Per claim: the baseline verdict and the variants (in the reader's words) that flip,
    change, leave unchanged and leave unsettled its verdict (in the order of ``rob.flips``)."""
    out = []
    for cid, groups in rob.flips.items():
        base = next((v for v in rob.verdicts if v["claim"] == cid and v["part"] == "baseline"),
                    None)
        if base is None:
            continue
        out.append({"id": cid, "baseline": base["verdict"],
                    "flipped": list(groups.get("flipped", [])),
                    "changed": list(groups.get("changed", [])),
                    "unchanged": list(groups.get("unchanged", [])),
                    "unsettled": list(groups.get("unsettled", []))})
    return out


def robustness_section(result: StudyResult, figures: Mapping[str, Mapping[str, Any]]) -> Markup:
    """The robustness section (a short note when the study ran no robustness experiment).

    ``figures`` maps the keys ``robustness`` and ``sensitivity`` (when drawn) to their
    ``number, title, caption, src, name`` on the page.
    """
    rob = getattr(result, "robustness", None)
    if rob is None:
        return render("sections/robustness.html.j2", rob=None)
    sens = rob.config.sensitivity
    levels = {f.name: ", ".join(f"{x:g}" for x in f.levels) for f in sens.factors} if (
        sens is not None) else {}
    ranking = [{"rank": r["rank"], "factor": r["factor"], "levels": levels.get(r["factor"], ""),
                "score": f"{float(r['score']):.2f}"} for r in rob.sensitivity_ranking]
    spread = [{"claim": r["claim"], "sigma": f"{float(r['sigma']):g}", "spread": r["spread"],
               "agreement": f"{float(r['agreement']):.2f}",
               "estimate": f"{float(r['replication_mean']):.2f}"} for r in rob.spread]
    return render(
        "sections/robustness.html.j2",
        rob=rob,
        model_doc=MODEL_DOC,
        levels=", ".join(f"{s:g}" for s in rob.config.noise_levels),
        seeds=count_text(int(c["n"]) for c in rob.cells if float(c["sigma"]) > 0.0),
        batches=rob.config.baseline_batches,
        target=f"{rob.target:g}",
        spread=spread,
        noise_std=f"{result.config.noise_std:g}",
        choices=_choice_rows(rob),
        claims=claim_robustness(rob),
        ranking_text=", ".join(f"{r['choice']} ({r['score']})" for r in rob.ranking),
        factorial=" × ".join(rob.config.factorial),
        heat_map=figures.get("robustness"),
        sensitivity=figures.get("sensitivity"),
        sensitivity_ranking=ranking,
        sensitivity_points=rob.sensitivity_points,
        sensitivity_config=sens,
    )

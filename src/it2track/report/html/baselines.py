"""The page's fair-baselines section: the type-1 FLCs matched to the IT2FLC in dead zone (D2)
and in dead zone and slope (D1), the type-1 table of its own surface (D3), the surfaces
compared, and every fuzzy controller tuned like the PD baseline, with the claims judged tuned
against tuned (docs/model.md, "Fair baselines")."""

from __future__ import annotations

from typing import Any

import numpy as np
from markupsafe import Markup

from ...experiments.specs import ControllerKind
from ...experiments.study import StudyResult
from ..counts import count_text
from ..identity import controller_specs
from .claims import _claim
from .env import fmt, render
from .robustness import MODEL_DOC

__all__ = ["baselines_section"]


def _tuning_rows(result: StudyResult) -> list[dict[str, Any]]:
    rows = []
    for label, rec in result.tuning.items():
        spec = result.tuned.get(label)
        untuned = rec.get("untuned", {})
        rows.append({
            "controller": label, "tuned": spec.label if spec is not None else "",
            "ke": fmt(rec.get("ke")), "kde": fmt(rec.get("kde")), "gain": fmt(rec.get("gain")),
            "ise": fmt(rec.get("objective"), 3), "untuned_ise": fmt(untuned.get("ise"), 3),
            "effort": fmt(rec.get("effort"), 3), "limit": fmt(rec.get("effort_limit"), 3),
            "edge": "yes" if rec.get("on_grid_edge") else "no",
        })
    return rows


def _surfaces(result: StudyResult) -> dict[str, Any] | None:
    """RMS differences of the matched baselines' surfaces from the main IT2FLC's, and each
    controller's u(0.5, 0), from the stored surfaces and the controllers themselves."""
    main = f"IT2FLC FoU {result.config.main_fou:g}"
    if main not in result.surfaces:
        return None
    u_main = result.surfaces[main][2]
    rows = []
    for label in (main, "FLC", f"T1 slope-matched {result.config.main_fou:g}",
                  f"T1 dead-zone-matched {result.config.main_fou:g}"):
        if label not in result.surfaces:
            continue
        d = result.surfaces[label][2] - u_main
        spec = result.surface_specs.get(label)
        u = ""
        if spec is not None:
            c = spec.build()
            u = fmt(float(c.output(np.array([0.5]), np.array([0.0]),
                                   c.initial_state(1, 0.01))[0]), 3)
        rows.append({"label": label, "rms": fmt(float(np.sqrt(np.mean(d * d))), 3), "u": u})
    return {"main": main, "grid": f"{u_main.shape[0]} × {u_main.shape[1]}", "rows": rows}


def _replication(c: Any) -> str:
    """Each noisy level's status with its replication probability, e.g. "not shown (0.86)"."""
    reps = [(s, p) for (path, s), p in sorted(getattr(c, "replication", {}).items())
            if path == "all" and s > 0.0]
    return ", ".join(f"{c.level_status[s]} ({p:.2f})" for s, p in reps)


def baselines_section(result: StudyResult) -> Markup:
    """The matched type-1 baselines present in the study, the tuning of every fuzzy
    controller and the tuned-vs-tuned verdicts (each part only when the study has it)."""
    kinds = {s.kind for s in controller_specs(result).values()}
    pd = result.pd_tuning or {}
    pd_row = None
    if result.pd is not None and pd.get("objective") is not None:
        pd_row = {"controller": result.pd.label, "kp": fmt(result.pd.kp),
                  "kd": fmt(result.pd.kd), "ise": fmt(pd.get("objective"), 3),
                  "effort": fmt(pd.get("effort"), 3), "limit": fmt(pd.get("effort_limit"), 3),
                  "edge": "yes" if pd.get("on_grid_edge") else "no"}
    tuning = result.config.tuning
    budget = None if tuning is None else {
        "ke": len(tuning.ke_grid), "kde": len(tuning.kde_grid), "gain": len(tuning.gain_grid),
        "total": len(tuning.ke_grid) * len(tuning.kde_grid) * len(tuning.gain_grid)}
    copy = None
    if result.surface_copy:
        sc = result.surface_copy
        copy = {"main": f"IT2FLC FoU {result.config.main_fou:g}", "grid": sc["grid"],
                "max": fmt(sc["max"], 2), "rms": fmt(sc["rms"], 2)}
    return render(
        "sections/baselines.html.j2",
        model_doc=MODEL_DOC,
        copy=copy,
        surfaces=_surfaces(result),
        dead_zone=ControllerKind.T1_MATCHED in kinds,
        slope=ControllerKind.T1_SLOPE_MATCHED in kinds,
        main_fou=f"{result.config.main_fou:g}",
        tuning=_tuning_rows(result),
        budget=budget,
        pd=pd_row,
        sigma=f"{result.config.noise_std:g}",
        seeds=count_text(int(e["n"]) for c in result.tuned_claims for e in c.evidence
                         if float(e["sigma"]) > 0.0),
        claims=[{**_claim(c), "replication": _replication(c)} for c in result.tuned_claims],
    )

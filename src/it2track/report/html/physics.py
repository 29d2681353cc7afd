"""The page's physics section: the claims re-judged on the MuJoCo robot per surface beside the
kinematic robot's verdicts, and the robots tracking side by side (an embedded GIF); or why the
check was skipped and how to run it."""

from __future__ import annotations

from typing import Any

from markupsafe import Markup

from ..physics import (
    GIF_NAME,
    INSTALL,
    METRICS_NAME,
    VERDICTS_NAME,
    PhysicsOutcome,
    survivor_counts,
    survivors_text,
)
from .env import data_uri, render

__all__ = ["physics_section"]


def _cell(row: dict[str, Any], key: str) -> dict[str, Any]:
    if key not in row:
        return {"text": "—", "settled": False, "same": False}
    if key == "kinematic":
        return {"text": row["kinematic"] or "—", "settled": row["kinematic_settled"],
                "same": False}
    return {"text": f"{row[key]} {row[f'{key}_replication']:.2f} (n {row[f'{key}_n']})",
            "settled": row[f"{key}_settled"], "same": row[f"{key}_same"]}


def physics_section(outcome: PhysicsOutcome) -> Markup:
    """The section for ``outcome`` (a run check, or a skipped one with its reason)."""
    r = outcome.result
    if r is None:
        return render("sections/physics.html.j2", ran=False, reason=outcome.reason,
                      install=INSTALL)
    names = [s.surface for s in r.surfaces]
    rows = [{"claim": row["claim"], "sigma": f"{row['sigma']:g}",
             "cells": [_cell(row, "kinematic"), *(_cell(row, s) for s in names)]}
            for row in outcome.survival]
    noisy = [n for s in r.surfaces for k, n in s.settled.n.items() if k[2] > 0.0]
    d = r.design
    return render(
        "sections/physics.html.j2", ran=True, smoke=outcome.smoke,
        surfaces=[{"name": s.surface, "mu": f"{s.mu:g}"} for s in r.surfaces],
        controllers=", ".join(r.controllers), first=d.first, batch=d.batch, cap=d.cap,
        used=f"{min(noisy)}–{max(noisy)}", target=f"{d.target:g}", resamples=d.resamples,
        runs=f"{r.runs:,}", seconds=f"{outcome.seconds:.0f}", cached=outcome.cached, rows=rows,
        survivors=survivors_text(outcome.survival, names).replace("**", ""),
        counts=[{"claim": c["claim"], "levels": c["levels"],
                 "cells": [f"{c[s]['same']} / {c[s]['different']} / {c[s]['unsettled']}"
                           for s in names]}
                for c in survivor_counts(outcome.survival, names)],
        gif=None if outcome.gif is None else data_uri(outcome.gif), gif_name=GIF_NAME,
        verdicts_name=VERDICTS_NAME, metrics_name=METRICS_NAME)

"""The page's summary table: the main experiment's integral errors with intervals and the ISE
win rate against the FLC."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from markupsafe import Markup

from ...experiments.analysis import INTEGRALS
from ...experiments.stats import interval_text
from ...experiments.study import StudyResult
from ..counts import count_text
from ..identity import INTEGRAL_UNITS
from .env import fmt, num, render

__all__ = ["summary_section"]


def _win_cell(row: Mapping[str, Any] | None) -> str:
    """A win rate (ties counting ½) with the share of ties, if any."""
    if row is None or row.get("win_rate") in ("", None):
        return ""
    text = fmt(num(row["win_rate"]), 3)
    ties = num(row.get("ties"))
    if math.isfinite(ties) and ties > 0:
        text += f" (ties {ties:.0%})"
    return text


def _interval(row: Mapping[str, Any]) -> str:
    """Mean [95 % interval], with the digits that keep the printed mean inside it."""
    if row.get("ci_low") in ("", None):
        return fmt(num(row["mean"]))
    return interval_text(num(row["mean"]), num(row["ci_low"]), num(row["ci_high"]))


def summary_section(result: StudyResult, summary: Sequence[Mapping[str, Any]]) -> Markup:
    """Mean [95 % interval] of each integral error per trajectory and controller in the
    ``paper`` experiment, and the ISE win rate against the FLC."""
    rows = [r for r in summary if r.get("experiment") == "paper"]
    if not rows:
        return render("sections/summary.html.j2", table=None)
    index = {(r["trajectory"], r["controller"], r["metric"]): r for r in rows}
    trajs = [t for t in result.config.trajectories if any(k[0] == t for k in index)]
    ctrls: list[str] = []
    for r in rows:
        if r["controller"] not in ctrls:
            ctrls.append(str(r["controller"]))
    header = ["trajectory", "controller"] + [f"{m} ({INTEGRAL_UNITS[m]})" for m in INTEGRALS]
    header.append("ISE win rate vs FLC (ties ½)")
    body = []
    for t in trajs:
        for c in ctrls:
            cells: list[Any] = [t, c]
            for m in INTEGRALS:
                cell = index.get((t, c, m))
                cells.append("" if cell is None else _interval(cell))
            cells.append(_win_cell(index.get((t, c, "ISE"))))
            body.append(cells)
    return render("sections/summary.html.j2", table=body, header=header,
                  n=count_text(int(r["n"]) for r in rows),
                  sigma=f"{num(rows[0]['noise_std']):g}",
                  numeric=[False, False] + [True] * (len(INTEGRALS) + 1))

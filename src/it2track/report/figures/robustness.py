"""Robustness of the verdicts to the paper's open modelling choices, and the global sensitivity
ranking (issue 9; the data: :class:`~it2track.experiments.robustness.RobustnessResult`).

``robustness``
    A heat map a reader takes in at a glance: one row per variant (the paper-faithful baseline,
    each alternative of each open choice one at a time, the factorial cells), one column per
    claim, each cell split into the noise levels it was judged at and coloured by the claim's
    status there (holds / contradicted / not shown / deterministic), pale and hatched where that
    status is unsettled (replication probability below the target). A thick outline marks a
    variant that *flips* the claim beyond the baseline's spread over independent seed batches,
    a dashed one a variant that *changes* it. Facets: all trajectories together, then each
    trajectory alone.
``sensitivity``
    Morris screening (SALib) of the key paired differences over the continuous choices: the
    factors ranked by their normalised mean elementary effect, and ``mu*`` per output.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle

from ..counts import count_text

__all__ = ["STATUS_COLORS", "robustness_cells"]

#: Colour of a claim's status at one noise level (the page's green / red / grey).
STATUS_COLORS = {
    "holds": "#1b7f3b",
    "contradicted": "#b3261e",
    "not shown": "#d0d0d6",
    "deterministic": "#8fb3e0",
}
_MISSING = "#ffffff"
#: The facet that pools every trajectory.
ALL = "all trajectories"


@dataclass(frozen=True)
class _Cell:
    """One coloured strip: a claim's status under one variant at one level, in one facet."""

    facet: str
    row: int
    claim: str
    sigma: float
    index: int  # position of the level among the variant's levels
    count: int  # number of levels of the variant
    status: str
    settled: bool = True


def _levels(text: str) -> list[float]:
    return [float(s) for s in str(text).split(",") if s.strip()]


def _variant_label(v: Mapping[str, Any]) -> str:
    if v["part"] == "baseline":
        return "baseline (the paper's choices)"
    return str(v.get("label") or f"{v['choice']} = {v['value']}")


def robustness_cells(
    verdicts: Sequence[Mapping[str, Any]],
    cells: Sequence[Mapping[str, Any]],
    trajectories: Sequence[str],
) -> tuple[list[str], list[str], list[_Cell], dict[tuple[int, str], str]]:
    """The heat map's content from the robustness experiment's rows.

    Parameters
    ----------
    verdicts : list of dict
        ``RobustnessResult.verdicts``: ``claim, choice, value, part, noise_levels`` (comma
        separated), ``status`` (``;``-separated, one per level), ``change``.
    cells : list of dict
        ``RobustnessResult.cells``: ``claim, choice, value, sigma, trajectory, verdict`` (the
        status at that level on that trajectory).
    trajectories : list of str
        The facets after :data:`ALL`.

    Returns
    -------
    rows : list of str
        Variant labels, top to bottom (in the order of ``verdicts``).
    claims : list of str
        Claim ids, left to right.
    strips : list of _Cell
    change : dict of (row, claim) -> str
        ``"unchanged"``, ``"changed"`` or ``"flipped"`` against the baseline.
    """
    rows: list[str] = []
    row_of: dict[tuple[str, str], int] = {}
    claims: list[str] = []
    levels_of: dict[tuple[int, str], list[float]] = {}
    strips: list[_Cell] = []
    change: dict[tuple[int, str], str] = {}
    for v in verdicts:
        key = (str(v["choice"]), str(v["value"]))
        if key not in row_of:
            row_of[key] = len(rows)
            rows.append(_variant_label(v))
        if v["claim"] not in claims:
            claims.append(str(v["claim"]))
        row, claim = row_of[key], str(v["claim"])
        levels = _levels(v["noise_levels"])
        status = str(v["status"]).split(";")
        if len(status) != len(levels):
            raise ValueError(f"robustness verdict {claim} / {key}: {len(status)} statuses for "
                             f"{len(levels)} noise levels")
        levels_of[(row, claim)] = levels
        change[(row, claim)] = str(v["change"])
        settled = [x == "yes" for x in str(v.get("settled", "")).split(";")]
        if len(settled) != len(levels):
            settled = [True] * len(levels)
        strips += [_Cell(ALL, row, claim, s, i, len(levels), st, ok)
                   for i, (s, st, ok) in enumerate(zip(levels, status, settled, strict=True))]
    seen: set[tuple[str, int, str, str]] = set()
    for c in cells:
        key = (str(c["choice"]), str(c["value"]))
        traj = str(c["trajectory"])
        if key not in row_of or traj not in trajectories:
            continue
        row, claim = row_of[key], str(c["claim"])
        levels = levels_of.get((row, claim), [])
        # The verdicts write their levels with %g: match the cells' sigma the same way.
        names = [f"{s:g}" for s in levels]
        name = f"{float(c['sigma']):g}"
        if name not in names or (traj, row, claim, name) in seen:
            continue
        seen.add((traj, row, claim, name))
        i = names.index(name)
        strips.append(_Cell(traj, row, claim, levels[i], i, len(levels), str(c["verdict"])))
    return rows, claims, strips, change


def _draw_facet(a: Axes, facet: str, rows: Sequence[str], claims: Sequence[str],
                strips: Sequence[_Cell], change: Mapping[tuple[int, str], str],
                own_levels: Mapping[int, list[float]], groups: Sequence[int]) -> None:
    gap = 0.08
    for c in strips:
        if c.facet != facet:
            continue
        x0 = claims.index(c.claim) + gap / 2
        width = (1.0 - gap) / c.count
        rect = Rectangle((x0 + c.index * width, c.row + gap / 2), width, 1.0 - gap,
                         facecolor=STATUS_COLORS.get(c.status, _MISSING), edgecolor="white",
                         linewidth=0.4, alpha=1.0 if c.settled else 0.35,
                         hatch=None if c.settled else "////")
        rect.set_gid(f"robustness|{facet}|{c.claim}|{rows[c.row]}|{c.sigma:g}")
        a.add_patch(rect)
    if facet == ALL:
        for (row, claim), how in change.items():
            if how not in ("flipped", "changed"):
                continue
            a.add_patch(Rectangle(
                (claims.index(claim) + gap / 2, row + gap / 2), 1.0 - gap, 1.0 - gap,
                fill=False, edgecolor="black", linewidth=1.8 if how == "flipped" else 1.0,
                linestyle="-" if how == "flipped" else (0, (2, 1.5)), zorder=3,
                gid=f"change|{claim}|{rows[row]}|{how}"))
        for row, levels in own_levels.items():  # variants judged at their own noise level
            a.text(len(claims) + 0.05, row + 0.5, "σ = " + ", ".join(f"{s:g}" for s in levels),
                   va="center", ha="left", fontsize=6.5, color="#555555")
    for y in groups:
        a.axhline(y, color="#888888", lw=0.6)
    a.set_xlim(0, len(claims))
    a.set_ylim(len(rows), 0)
    a.set_xticks([i + 0.5 for i in range(len(claims))], claims)
    a.xaxis.tick_top()
    a.tick_params(axis="both", length=0)
    a.grid(False)
    for side in ("top", "right", "bottom", "left"):
        a.spines[side].set_visible(False)
    a.set_title(facet, fontsize=9, pad=16)


def _fig_robustness(rob: Any, trajectories: Sequence[str]) -> Figure:
    rows, claims, strips, change = robustness_cells(rob.verdicts, rob.cells, trajectories)
    levels = [float(s) for s in rob.config.noise_levels]
    row_levels: dict[int, set[float]] = {}
    for c in strips:
        if c.facet == ALL:
            row_levels.setdefault(c.row, set()).add(c.sigma)
    # Variants judged at their own noise level (the noise readings) say which.
    own = {row: sorted(s) for row, s in row_levels.items() if sorted(s) != sorted(levels)}
    facets = [ALL, *trajectories]
    keys = list(dict.fromkeys((str(v["choice"]), str(v["value"])) for v in rob.verdicts))
    choice_of = [k[0] for k in keys]
    groups = [i for i in range(1, len(rows)) if choice_of[i] != choice_of[i - 1]]
    fig = Figure(figsize=(2.3 + 2.2 * len(facets), 1.6 + 0.24 * len(rows)),
                 layout="constrained")
    ax = np.asarray(fig.subplots(1, len(facets), sharey=True, squeeze=False))[0]
    for a, facet in zip(ax, facets, strict=True):
        _draw_facet(a, facet, rows, claims, strips, change, own if facet == ALL else {},
                    groups)
    ax[0].set_yticks([i + 0.5 for i in range(len(rows))], rows, fontsize=7.5)
    present = {c.status for c in strips}
    handles: list[Any] = [Patch(facecolor=color, label=status)
                          for status, color in STATUS_COLORS.items() if status in present]
    if present - set(STATUS_COLORS):
        handles.append(Patch(facecolor=_MISSING, edgecolor="#999999", label="not evaluated"))
    if any(not c.settled for c in strips):
        handles.append(Patch(facecolor="#d0d0d6", alpha=0.35, hatch="////",
                             label="unsettled (replication < target)"))
    handles += [
        Line2D([], [], color="black", lw=1.8,
               label="flips it beyond the baseline's seed spread"),
        Line2D([], [], color="black", lw=1.0, ls=(0, (2, 1.5)),
               label="changes it beyond that spread"),
    ]
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), frameon=False,
               fontsize=7.5)
    level_text = ", ".join(f"{s:g}" for s in levels)
    n = count_text(int(c["n"]) for c in rob.cells if float(c["sigma"]) > 0.0)
    fig.suptitle("Do the verdicts survive the paper's open modelling choices?\nEach cell: a "
                 f"claim under one variant, split into σ = {level_text} rad (left to right; "
                 f"{n} realisations per cell)", fontsize=10)
    return fig


def _fig_sensitivity(rob: Any) -> Figure:
    ranking = sorted(rob.sensitivity_ranking, key=lambda r: int(r["rank"]))
    factors = [str(r["factor"]) for r in ranking]
    outputs: dict[str, list[Mapping[str, Any]]] = {}
    for r in rob.sensitivity:
        outputs.setdefault(f"{r['output']} ({r['trajectory']})", []).append(r)
    fig = Figure(figsize=(11.0, 1.8 + 0.38 * max(len(factors), 1)), layout="constrained")
    a_rank, a_mu = fig.subplots(1, 2, sharey=True, width_ratios=(1.0, 1.6))
    y = np.arange(len(factors))
    scores = [float(r["score"]) for r in ranking]
    bars = a_rank.barh(y, scores, color="#4c72b0", height=0.6)
    for bar, factor in zip(bars, factors, strict=True):
        bar.set_gid(f"sensitivity|{factor}")
    for yi, s in zip(y, scores, strict=True):
        a_rank.text(s, yi, f" {s:.2f}", va="center", ha="left", fontsize=7.5)
    a_rank.set_yticks(y, [f"{int(r['rank'])}. {f}" for r, f in zip(ranking, factors,
                                                                    strict=True)])
    a_rank.set_ylim(len(factors) - 0.5, -0.5)
    a_rank.set_xlim(0.0, 1.15 * max(scores, default=1.0) or 1.0)
    a_rank.set_xlabel("score: mean over outputs of μ* / max μ*")
    a_rank.set_title("(a) ranking")
    a_rank.grid(axis="y", visible=False)
    colors = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
              "#7f7f7f", "#bcbd22", "#17becf")
    n_out = max(len(outputs), 1)
    for k, (name, recs) in enumerate(outputs.items()):
        by_factor = {str(r["factor"]): r for r in recs}
        dy = (k - (n_out - 1) / 2) * min(0.7 / n_out, 0.15)
        xs, ys, err = [], [], []
        for i, f in enumerate(factors):
            r = by_factor.get(f)
            if r is None:
                continue
            xs.append(float(r["mu_star"]))
            ys.append(i + dy)
            err.append(float(r["mu_star_conf"]))
        a_mu.errorbar(xs, ys, xerr=err, fmt="o", ms=3.5, color=colors[k % len(colors)],
                      elinewidth=0.8, capsize=2, label=name)
    mus = [float(r["mu_star"]) for r in rob.sensitivity]
    positive = [m for m in mus if m > 0]
    log = bool(positive) and len(positive) == len(mus) and max(mus) > 20 * min(positive)
    if log:  # effects spanning decades; a zero effect would have no place on a log axis
        a_mu.set_xscale("log")
    a_mu.set_xlabel("μ*: mean |elementary effect| on the paired mean ISE difference (rad²·s)"
                    + (" [log]" if log else ""))
    a_mu.set_title("(b) μ* per output, with its 95 % bootstrap interval"
                   + (" (bars running off the left edge reach 0)" if log else ""), fontsize=9)
    a_mu.grid(axis="y", visible=False)
    handles, labels = a_mu.get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=min(len(labels), 3),
               frameon=False, fontsize=7.5)
    sens = rob.config.sensitivity
    fig.suptitle(f"Global sensitivity (Morris screening, SALib): {rob.sensitivity_points} "
                 f"design points, {sens.trajectories} trajectories over {len(sens.factors)} "
                 f"factors, {sens.seeds} realisations per point", fontsize=10)
    return fig

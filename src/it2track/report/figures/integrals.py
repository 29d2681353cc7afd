"""Paper Fig. 11 with Monte Carlo statistics: the integral errors per controller, with 95 %
intervals and the fair baselines beside the paper's controllers.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle

from ...experiments.analysis import INTEGRALS
from ...experiments.study import StudyResult
from ..counts import count_text
from ..identity import (
    _FLC,
    _IT2,
    _MATCHED,
    _PAPER_FUZZY,
    _T1M,
    _T1S,
    _Ctrl,
    _info,
    _num,
    _order_key,
    _Summary,
)
from .style import _FLC_COLOR, _metric_label, _Palette

# ---------------------------------------------------------------------------------------------
# Figure 11: integral errors with Monte Carlo intervals
# ---------------------------------------------------------------------------------------------


def _bar_groups(labels: Sequence[str], ctrls: Mapping[str, _Ctrl]) -> list[tuple[str, list[str]]]:
    """FLC | one group per FoU width (IT2FLC and its matched type-1 baselines side by side) |
    the tuned fuzzy controllers | PD | others."""
    groups: list[tuple[str, list[str]]] = []
    infos = sorted((_info(ctrls, c) for c in labels), key=_order_key)
    by_fou: dict[float, list[str]] = {}
    for c in infos:
        if c.kind in (_IT2, *_MATCHED) and not c.tuned:
            by_fou.setdefault(round(c.fou, 12), []).append(c.label)
    for c in infos:
        if c.kind is _FLC and not c.tuned:
            groups.append((c.label, [c.label]))
    for w in sorted(by_fou):
        members = sorted(by_fou[w], key=lambda lb: _order_key(_info(ctrls, lb)))
        groups.append((f"w = {w:g}", members))
    tuned = [c.label for c in infos if c.tuned]
    if tuned:
        groups.append(("tuned", tuned))
    for c in infos:
        if c.kind not in _PAPER_FUZZY and not c.tuned:
            groups.append((c.label, [c.label]))
    return groups


def _short_bars(a: Axes, top: float, fraction: float = 0.08) -> list[tuple[float, float]]:
    """Centres and heights of the bars of ``a`` shorter than ``fraction * top``."""
    out = []
    for patch in a.patches:
        if isinstance(patch, Rectangle):
            h = patch.get_height()
            if 0 <= h < fraction * top:
                out.append((patch.get_x() + patch.get_width() / 2.0, h))
    return out


def _fig_integral_errors(result: StudyResult, summ: _Summary, ctrls: Mapping[str, _Ctrl],
                         pal: _Palette, trajs: Sequence[str] | None = None) -> Figure:
    cfg = result.config
    trajs = list(cfg.trajectories if trajs is None else trajs)
    sigma = summ.levels("paper")[0] if summ.levels("paper") else cfg.noise_std
    labels = summ.controllers("paper")
    groups = _bar_groups(labels, ctrls)
    n = len(trajs)
    fig = Figure(figsize=(13.5, 2.7 * n + 1.0), layout="constrained")
    ax = np.asarray(fig.subplots(n, len(INTEGRALS), squeeze=False))
    for i, traj in enumerate(trajs):
        for j, metric in enumerate(INTEGRALS):
            a = ax[i, j]
            values: list[float] = []
            # One bar call and one errorbar call per panel (one per bar cost ~3x the time).
            xs: list[float] = []
            widths: list[float] = []
            faces: list[str] = []
            edges: list[str] = []
            hatches: list[str | None] = []
            below: list[float] = []
            above: list[float] = []
            for g, (_, members) in enumerate(groups):
                width = 0.8 / len(members)
                for k, label in enumerate(members):
                    r = summ.get("paper", traj, label, sigma, metric)
                    if r is None:
                        continue
                    st = pal.style(_info(ctrls, label))
                    mean, lo, hi = _num(r["mean"]), _num(r["ci_low"]), _num(r["ci_high"])
                    xs.append(g - 0.4 + width * (k + 0.5))
                    widths.append(width * 0.92)
                    faces.append(st.color if st.hatch is None else "white")
                    edges.append(st.color)
                    hatches.append(st.hatch)
                    below.append(mean - lo)
                    above.append(hi - mean)
                    values += [mean, lo, hi]
            if xs:
                means = values[0::3]
                bars = a.bar(xs, means, width=widths, color=faces, edgecolor=edges,
                             linewidth=1.0)
                for patch, hatch in zip(bars, hatches, strict=True):
                    patch.set_hatch(hatch)
                a.errorbar(xs, means, yerr=[below, above], fmt="none", ecolor="black",
                           elinewidth=0.9, capsize=2)
            flc = summ.get("paper", traj, "FLC", sigma, metric)
            if flc is not None:
                a.axhline(_num(flc["mean"]), color=_FLC_COLOR, lw=0.7, ls=":")
            # Linear scale throughout (bars on a log axis mislead); bars too short to read
            # carry their value.
            top = max((v for v in values if math.isfinite(v)), default=1.0)
            a.set_ylim(0.0, 1.12 * top if top > 0 else 1.0)
            for x, mean in _short_bars(a, top):
                a.annotate(f"{mean:.2g}", (x, mean), xytext=(0, 3), textcoords="offset points",
                           ha="center", va="bottom", fontsize=6.5, rotation=90)
            a.set_xticks(range(len(groups)), [name for name, _ in groups], rotation=30,
                         ha="right", rotation_mode="anchor")
            a.set_xlim(-0.6, len(groups) - 0.4)
            a.grid(axis="x", visible=False)
            a.set_ylabel(_metric_label(metric))
            a.set_title(f"{traj}: {metric}")
    handles: list[Any] = [Patch(facecolor=_FLC_COLOR, edgecolor=_FLC_COLOR, label="FLC")]
    for w in cfg.fous:
        handles.append(Patch(facecolor=pal.fou_color(w), label=f"IT2FLC FoU {w:g}"))
    shown = [c for c in (ctrls.get(lb) for lb in labels) if c]
    for kind, hatch, name in ((_T1M, "///", "T1 dead-zone-matched"),
                              (_T1S, "xx", "T1 dead-zone- and slope-matched")):
        if any(c.kind is kind for c in shown):
            handles.append(Patch(facecolor="white", edgecolor="#444444", hatch=hatch,
                                 label=f"{name} (same colour = same w)"))
    if any(c.tuned for c in shown):
        handles.append(Patch(facecolor="white", edgecolor="#444444", hatch="++",
                             label="tuned Ke, Kde, gain (colour: the untuned one's)"))
    for lb in labels:
        c = _info(ctrls, lb)
        if c.kind not in _PAPER_FUZZY and not c.tuned:
            st = pal.style(c)
            handles.append(Patch(facecolor="white", edgecolor=st.color, hatch=st.hatch,
                                 label=lb))
    handles.append(Line2D([], [], color="black", marker="|", ls="none", ms=8,
                          label="95 % interval of the mean"))
    fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 5),
               frameon=False)
    n_seeds = count_text(int(r["n"]) for k, r in summ.rows.items()
                         if k[0] == "paper" and k[3] == sigma)
    fig.suptitle(f"Integral heading errors (cf. paper Fig. 11): mean over {n_seeds} noise "
                 f"realisations at σ = {sigma:g} rad, with 95 % intervals; dotted line = FLC mean",
                 fontsize=10.5)
    return fig

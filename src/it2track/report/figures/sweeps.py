"""The integral errors against the heading-noise level and against the FoU width (the latter
beside the type-1 FLC with the same dead zone).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ...experiments.analysis import INTEGRALS
from ...experiments.study import StudyResult
from ..counts import count_text
from ..identity import _FLC, _IT2, _T1M, _Ctrl, _info, _num, _order_key, _Summary
from .style import _FLC_COLOR, _metric_label, _Palette, _Style


def _choose_yscale(ax: Axes, values: Iterable[float], *, ratio: float = 20.0) -> str:
    """Log scale when the positive values span more than ``ratio``; symlog when zeros also
    occur; linear otherwise. Returns the scale name."""
    v = np.asarray([x for x in values if math.isfinite(x)], dtype=float)
    pos = v[v > 0]
    if pos.size == 0 or pos.max() / pos.min() <= ratio:
        return "linear"
    if (v <= 0).any():
        thresh = 10.0 ** math.floor(math.log10(pos.min()))
        ax.set_yscale("symlog", linthresh=thresh, linscale=0.5)
        ax.set_ylim(bottom=0.0)
        return "symlog"
    ax.set_yscale("log")
    return "log"


def _sqrt(x: np.ndarray) -> np.ndarray:
    return np.sqrt(np.maximum(x, 0.0))


# ---------------------------------------------------------------------------------------------
# Sweeps
# ---------------------------------------------------------------------------------------------


def _band(a: Axes, x: Sequence[float], rows: Sequence[Mapping[str, Any] | None], st: _Style,
          label: str, values: list[float], *, marker: bool = True) -> None:
    pts = [(xi, r) for xi, r in zip(x, rows, strict=True) if r is not None]
    if not pts:
        return
    xs = np.array([p[0] for p in pts])
    mean = np.array([_num(p[1]["mean"]) for p in pts])
    # The integrals are non-negative: an interval reaching below 0 is drawn from 0.
    lo = np.maximum(np.array([_num(p[1]["ci_low"]) for p in pts]), 0.0)
    hi = np.array([_num(p[1]["ci_high"]) for p in pts])
    a.plot(xs, mean, color=st.color, ls=st.ls, marker=st.marker if marker else None, ms=3.5,
           label=label)
    a.fill_between(xs, lo, hi, color=st.color, alpha=0.15, lw=0)
    values += [*mean.tolist(), *lo.tolist(), *hi.tolist()]


def _fig_noise_sweep(result: StudyResult, summ: _Summary, ctrls: Mapping[str, _Ctrl],
                     pal: _Palette, trajs: Sequence[str] | None = None) -> Figure:
    cfg = result.config
    trajs = list(cfg.trajectories if trajs is None else trajs)
    levels = summ.levels("noise")
    labels = sorted(summ.controllers("noise"),
                    key=lambda lb: _order_key(_info(ctrls, lb)))
    n = len(trajs)
    fig = Figure(figsize=(max(4.2 * n, 6.5), 10.0), layout="constrained")
    ax = np.asarray(fig.subplots(len(INTEGRALS), n, squeeze=False))
    for i, metric in enumerate(INTEGRALS):
        for j, traj in enumerate(trajs):
            a = ax[i, j]
            values: list[float] = []
            for label in labels:
                st = pal.style(_info(ctrls, label))
                rows = [summ.get("noise", traj, label, s, metric) for s in levels]
                _band(a, levels, rows, st, label, values)
            a.axvline(cfg.noise_std, color="#999999", lw=0.8, ls=":")
            scale = _choose_yscale(a, values)
            if min(levels) >= 0.0:  # square-root axis: spreads the small levels
                a.set_xscale("function", functions=(_sqrt, np.square))
                a.set_xticks(levels, [f"{v:g}" for v in levels])
                a.set_xlim(0.0, max(levels) * 1.03)
            a.set_xlabel("heading noise σ (rad), √ scale")
            a.set_ylabel(_metric_label(metric) + (" [log]" if scale != "linear" else ""))
            a.set_title(f"{traj}: {metric}")
    handles, hl = ax[0, 0].get_legend_handles_labels()
    fig.legend(handles, hl, loc="outside lower center", ncols=min(len(hl), 6), frameon=False)
    n_seeds = count_text(int(r["n"]) for k, r in summ.rows.items()
                         if k[0] == "noise" and k[3] > 0.0)
    fig.suptitle(f"Integral errors vs heading-noise level: mean and 95 % band over {n_seeds} "
                 "realisations per point (σ = 0: one noise-free run; dotted: the study's "
                 f"σ = {cfg.noise_std:g} rad)", fontsize=10.5)
    return fig


def _fig_fou_sweep(result: StudyResult, summ: _Summary, ctrls: Mapping[str, _Ctrl],
                   pal: _Palette, trajs: Sequence[str] | None = None) -> Figure:
    cfg = result.config
    trajs = list(cfg.trajectories if trajs is None else trajs)
    sigma = summ.levels("fou")[0] if summ.levels("fou") else cfg.noise_std
    labels = summ.controllers("fou")
    infos = [_info(ctrls, lb) for lb in labels]
    flc = next((c.label for c in infos if c.kind is _FLC), None)
    it2 = sorted((c for c in infos if c.kind is _IT2), key=lambda c: c.fou)
    t1m = sorted((c for c in infos if c.kind is _T1M), key=lambda c: c.fou)
    metrics = ("ISE", "IAE")
    n = len(trajs)
    it2_style = _Style("#1f77b4", "-", None, "s")
    t1m_style = _Style("#ff7f0e", "--", None, "^")
    fig = Figure(figsize=(max(4.2 * n, 6.5), 5.6), layout="constrained")
    ax = np.asarray(fig.subplots(len(metrics), n, squeeze=False))
    for i, metric in enumerate(metrics):
        for j, traj in enumerate(trajs):
            a = ax[i, j]
            values: list[float] = []
            for w in cfg.fous:
                a.axvline(w, color="#bbbbbb", lw=0.8, ls=":")
            for series, st, name in ((it2, it2_style, "IT2FLC(w)"),
                                     (t1m, t1m_style, "T1 dead-zone-matched FLC(w)")):
                xs = [c.fou for c in series]
                rows = [summ.get("fou", traj, c.label, sigma, metric) for c in series]
                if flc is not None:
                    xs = [0.0, *xs]
                    rows = [summ.get("fou", traj, flc, sigma, metric), *rows]
                _band(a, xs, rows, st, name, values, marker=False)
            if flc is not None:
                r = summ.get("fou", traj, flc, sigma, metric)
                if r is not None:
                    a.plot(0.0, _num(r["mean"]), "o", color=_FLC_COLOR, ms=6, zorder=5,
                           label="FLC (w = 0)")
            scale = _choose_yscale(a, values)
            a.set_xlabel("FoU width w (dead zone 0.2 − w/2)")
            a.set_ylabel(_metric_label(metric) + (" [log]" if scale != "linear" else ""))
            a.set_title(f"{traj}: {metric}")
    handles, _ = ax[0, 0].get_legend_handles_labels()
    handles.append(Line2D([], [], color="#bbbbbb", ls=":", label="the paper's FoU widths"))
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), frameon=False)
    n_seeds = count_text(int(r["n"]) for k, r in summ.rows.items()
                         if k[0] == "fou" and k[3] == sigma)
    fig.suptitle(f"FoU sweep at σ = {sigma:g} rad: IT2FLC(w) vs the type-1 FLC with the same "
                 f"dead zone; mean and 95 % band over {n_seeds} realisations", fontsize=10.5)
    return fig

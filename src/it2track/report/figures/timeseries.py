"""Time-series figures of one noise realisation: paper Figs. 7-9 (one trajectory, FLC vs the
main IT2FLC) and Fig. 10 (every FoU width).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ...experiments.study import StudyResult
from ..identity import _FLC, _IT2, PAPER_FIGURE_NUMBER, _Ctrl, _trace_index, _trace_info
from .style import _REF_COLOR, _Palette


def _reference_heading(x: np.ndarray, y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Heading of the reference path's tangent, unwrapped."""
    return np.unwrap(np.arctan2(np.gradient(y, t), np.gradient(x, t)))


def _sigma_text(result: StudyResult) -> str:
    """The noise of the traced runs, from the runs themselves."""
    runs = [t.runs for t in result.traces.values()]
    sigmas = sorted({float(s) for r in runs for s in r.noise_std})
    seeds = sorted({int(s) for r in runs for s in r.seed})
    sigma = ", ".join(f"{s:g}" for s in sigmas)
    seed = ", ".join(str(s) for s in seeds)
    return (f"heading noise σ = {sigma} rad (held at {result.config.loop.noise_rate:g} Hz), "
            f"noise seed index {seed}")


# ---------------------------------------------------------------------------------------------
# Figures 7-9: one trajectory, FLC vs the main IT2FLC
# ---------------------------------------------------------------------------------------------


def _fig_paper(result: StudyResult, traj: str, ctrls: Mapping[str, _Ctrl],
               pal: _Palette) -> Figure:
    cfg = result.config
    trace = result.traces[traj]
    t = trace.t
    s = trace.series
    shown = [i for i in (_trace_index(result, _FLC),
                         _trace_index(result, _IT2, cfg.main_fou)) if i is not None]
    fig = Figure(figsize=(10.5, 7.6), layout="constrained")
    ax = fig.subplots(2, 2)
    a_pos, a_head, a_v, a_w = ax[0, 0], ax[0, 1], ax[1, 0], ax[1, 1]
    xr, yr = s["x_ref"][0], s["y_ref"][0]
    a_pos.plot(xr, yr, color=_REF_COLOR, ls="--", lw=1.1)
    a_pos.plot(xr[0], yr[0], "o", color=_REF_COLOR, ms=4, zorder=5)
    a_head.plot(t, _reference_heading(xr, yr, t), color=_REF_COLOR, ls=":", lw=1.1)
    speed = np.hypot(np.gradient(xr, t), np.gradient(yr, t))
    a_v.plot(t, speed, color=_REF_COLOR, ls="--", lw=1.0)
    # Inset: speed error after the start-up, where the controllers could differ.
    late = t >= min(1.0, 0.25 * t[-1])
    inset = a_v.inset_axes((0.5, 0.1, 0.47, 0.42))
    inset.axhline(0.0, color=_REF_COLOR, lw=0.6, ls="--")
    handles: list[Any] = [
        Line2D([], [], color=_REF_COLOR, ls="--", label="reference path / speed |ṗd|"),
        Line2D([], [], color=_REF_COLOR, ls=":", label="path-tangent heading"),
    ]
    for i in shown:
        label = result.trace_controllers[i]
        st = pal.style(_trace_info(result, i))
        a_pos.plot(s["x"][i], s["y"][i], color=st.color)
        a_pos.plot(s["x"][i][0], s["y"][i][0], st.marker, color=st.color, ms=4)
        a_head.plot(t, s["theta"][i], color=st.color)
        a_head.plot(t, s["theta_d"][i], color=st.color, ls="-.", lw=0.8, alpha=0.8)
        a_v.plot(t, s["v"][i], color=st.color, lw=1.0)
        inset.plot(t[late], s["v"][i][late] - speed[late], color=st.color, lw=0.8)
        a_w.plot(t, s["omega"][i], color=st.color, lw=0.8, alpha=0.85)
        handles.append(Line2D([], [], color=st.color, label=label))
    handles += [
        Line2D([], [], color="#666666", ls="-", label="θ (solid)"),
        Line2D([], [], color="#666666", ls="-.", lw=0.8,
               label="θd = atan2 to reference (dash-dot)"),
    ]
    inset.set_title(f"v − |ṗd| (m/s), t ≥ {float(t[late][0]):g} s", fontsize=7.5)
    inset.tick_params(labelsize=6.5)
    inset.ticklabel_format(axis="y", style="sci", scilimits=(-2, 2))
    inset.yaxis.get_offset_text().set_fontsize(6.5)
    a_pos.set(xlabel="x (m)", ylabel="y (m)", title="(a) robot position")
    a_head.set(xlabel="t (s)", ylabel="heading (rad)", title="(b) heading angle θ and θd")
    a_v.set(xlabel="t (s)", ylabel="v (m/s)", title="(c) translational speed")
    a_w.set(xlabel="t (s)", ylabel="ω (rad/s)", title="(d) rotational speed")
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), frameon=False,
               fontsize=7.5)
    num = PAPER_FIGURE_NUMBER.get(traj)
    ref = f" (cf. paper Fig. {num})" if num else ""
    fig.suptitle(f"{traj.capitalize()} trajectory{ref}: FLC vs IT2FLC FoU {cfg.main_fou:g}; "
                 f"{_sigma_text(result)}", fontsize=10.5)
    return fig


# ---------------------------------------------------------------------------------------------
# Figure 10: FoU comparison
# ---------------------------------------------------------------------------------------------


def _fig_fou_comparison(result: StudyResult, ctrls: Mapping[str, _Ctrl],
                        pal: _Palette, trajs: Sequence[str] | None = None) -> Figure:
    cfg = result.config
    trajs = list(cfg.trajectories if trajs is None else trajs)
    n = len(trajs)
    fig = Figure(figsize=(max(4.0 * n, 6.0), 6.6), layout="constrained")
    ax = np.asarray(fig.subplots(2, n, squeeze=False))
    idx = [_trace_index(result, _IT2, w) for w in cfg.fous]
    for j, traj in enumerate(trajs):
        trace = result.traces[traj]
        s, t = trace.series, trace.t
        xr, yr = s["x_ref"][0], s["y_ref"][0]
        ax[0, j].plot(xr, yr, color=_REF_COLOR, ls="--", lw=1.0, label="reference path")
        ax[1, j].plot(t, _reference_heading(xr, yr, t), color=_REF_COLOR, ls="--", lw=1.0,
                      label="path tangent")
        for i in idx:
            if i is None:
                continue
            label = result.trace_controllers[i]
            st = pal.style(_trace_info(result, i))
            ax[0, j].plot(s["x"][i], s["y"][i], color=st.color, lw=1.1, label=label)
            ax[1, j].plot(t, s["theta"][i], color=st.color, lw=0.9, label=label)
        letter = "abcdefghij"[j % 10]
        ax[0, j].set(xlabel="x (m)", ylabel="y (m)", title=f"({letter}) {traj}: position")
        ax[1, j].set(xlabel="t (s)", ylabel="θ (rad)", title=f"({letter}) {traj}: heading")
    handles, labels = ax[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=len(labels), frameon=False)
    fig.suptitle(f"FoU comparison (cf. paper Fig. 10); {_sigma_text(result)}", fontsize=10.5)
    return fig

"""The study's figures (paper Figs. 7-11 and beyond), drawn from a :class:`StudyResult`.

Every figure is a :class:`matplotlib.figure.Figure` created directly (no pyplot, so no global
figure registry and no backend state leaks into the caller) and saved twice, as PNG and SVG,
each written atomically. Styles are applied with :func:`matplotlib.rc_context`, so the caller's
rcParams are untouched; SVG ids and metadata are fixed so that reruns are byte-identical.

Figures (keys of :func:`write_figures`):

``paper_<trajectory>``
    Paper Figs. 7-9: position, heading, translational and rotational speed, FLC vs the main
    IT2FLC, for one noise realisation at the study's noise level.
``fou_comparison``
    Paper Fig. 10: position and heading of the IT2FLCs of every FoU width.
``integral_errors``
    Paper Fig. 11 with Monte Carlo means and 95 % intervals, plus the fair baselines.
``noise_sweep``, ``fou_sweep``
    The integral errors against the noise level and against the FoU width.
``control_surfaces``, ``dead_zone``
    ``u(e, de)`` of every fuzzy controller and its slice ``u(e, 0)``: the dead zone
    ``|e| < 0.2 - w/2`` that the FoU narrows.
``win_rates``
    Paired win rate against the FLC: the fraction of noise realisations with a smaller error,
    ties counting half (0.5 = no difference).

Controllers are identified by their :class:`~it2track.experiments.specs.ControllerSpec` (the
study's ``trace_specs``, ``surface_specs``, PD and extra controllers) or by the ``kind`` and
``fou`` columns of the metrics table, never by the text of their labels.
"""

from __future__ import annotations

import io
import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
import PIL.Image
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle

from ..atomicfile import atomic_open
from ..experiments.analysis import INTEGRALS
from ..experiments.specs import ControllerKind, ControllerSpec
from ..experiments.study import StudyResult
from ..tracking import FuzzyHeadingController

__all__ = [
    "FIGURE_DPI",
    "INTEGRAL_UNITS",
    "controller_specs",
    "figure_keys",
    "slug",
    "surface_limit",
    "write_figures",
]

#: Resolution of the PNG files, dots per inch.
FIGURE_DPI = 110
#: Units of the integral criteria (the heading error in rad, time in s).
INTEGRAL_UNITS = {"IAE": "rad·s", "ITAE": "rad·s²", "ISE": "rad²·s", "ITSE": "rad²·s²"}
#: Paper figure numbers of the built-in trajectories.
PAPER_FIGURE_NUMBER = {"straight": 7, "curved": 8, "sinusoidal": 9}

_RC: dict[str, Any] = {
    "font.size": 9,
    "axes.titlesize": 9.5,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.6,
    "lines.linewidth": 1.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "svg.hashsalt": "it2track",
    "svg.fonttype": "path",
    "figure.facecolor": "white",
    "savefig.facecolor": "white",
}

_FLC_COLOR = "#d62728"
_PD_COLOR = "#7f7f7f"
_REF_COLOR = "#222222"
_EXTRA_COLORS = ("#ff7f0e", "#8c564b", "#e377c2", "#bcbd22", "#17becf", "#1f77b4")


def slug(name: str) -> str:
    """File-name-safe form of a trajectory name (CSV paths become their stem).

    Examples
    --------
    >>> slug("curved"), slug("data/my path.csv")
    ('curved', 'my_path')
    """
    text = re.split(r"[\\/]", name)[-1]
    if text.lower().endswith(".csv"):
        text = text[:-4]
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_") or "trajectory"


def figure_keys(result: StudyResult) -> list[str]:
    """The keys :func:`write_figures` produces for ``result`` (in report order)."""
    keys = [f"paper_{slug(t)}" for t in result.config.trajectories]
    keys += ["fou_comparison", "integral_errors", "noise_sweep", "fou_sweep"]
    keys += ["control_surfaces", "dead_zone", "win_rates"]
    return keys


# ---------------------------------------------------------------------------------------------
# Controllers: identity and style
# ---------------------------------------------------------------------------------------------


def controller_specs(result: StudyResult) -> dict[str, ControllerSpec]:
    """Label -> :class:`ControllerSpec` of every controller ``result`` knows the spec of: the
    traced ones, those with a control surface, the PD baseline and the user's extras.

    Controllers seen only in the metrics table (e.g. the FoU sweep's widths) have no entry;
    their ``kind`` and ``fou`` are columns of ``result.rows``.
    """
    specs: dict[str, ControllerSpec] = {}
    for spec in result.config.extra_controllers:
        specs[spec.label] = spec
    if result.pd is not None:
        specs[result.pd.label] = result.pd
    for label, spec in result.surface_specs.items():
        specs[label] = spec
    for label, spec in zip(result.trace_controllers, result.trace_specs, strict=False):
        specs[label] = spec
    return specs


@dataclass(frozen=True)
class _Ctrl:
    label: str
    kind: ControllerKind | None  # None: unknown
    fou: float
    spec: ControllerSpec | None = None


@dataclass(frozen=True)
class _Style:
    color: str
    ls: str
    hatch: str | None
    marker: str


_FLC, _IT2, _T1M, _PD = (ControllerKind.FLC, ControllerKind.IT2, ControllerKind.T1_MATCHED,
                         ControllerKind.PD)
#: The paper's fuzzy controllers (the sets of DESIGN.md sec. 3, dead zone 0.2 - w/2).
_PAPER_FUZZY = (_FLC, _IT2, _T1M)


def _kind_of(value: Any) -> ControllerKind | None:
    if isinstance(value, ControllerKind):
        return value
    try:
        return ControllerKind(str(value))
    except ValueError:
        return None


def _controller_table(result: StudyResult) -> dict[str, _Ctrl]:
    """Label -> identity, from the controllers' specs and the metrics table's ``kind`` and
    ``fou`` columns (labels are names only: nothing is inferred from their text)."""
    table: dict[str, _Ctrl] = {}
    rows = result.rows
    labels = np.asarray(rows["controller"]).astype(str)
    _, first = np.unique(labels, return_index=True)
    for i in sorted(first):
        table[labels[i]] = _Ctrl(labels[i], _kind_of(rows["kind"][i]), float(rows["fou"][i]))
    for label, spec in controller_specs(result).items():
        fou = spec.fou if spec.kind in (_IT2, _T1M) else 0.0
        table[label] = _Ctrl(label, spec.kind, fou, spec)
    return table


def _info(ctrls: Mapping[str, _Ctrl], label: str) -> _Ctrl:
    return ctrls.get(label) or _Ctrl(label, None, 0.0)


def _trace_info(result: StudyResult, i: int) -> _Ctrl:
    """Identity of the controller of trace run ``i`` (from ``trace_specs``)."""
    spec = result.trace_specs[i]
    return _Ctrl(result.trace_controllers[i], spec.kind,
                 spec.fou if spec.kind in (_IT2, _T1M) else 0.0, spec)


def _surface_info(result: StudyResult, ctrls: Mapping[str, _Ctrl], label: str) -> _Ctrl:
    """Identity of the controller behind a stored surface: its ``surface_specs`` entry first."""
    spec = result.surface_specs.get(label)
    if spec is None:
        return _info(ctrls, label)
    return _Ctrl(label, spec.kind, spec.fou if spec.kind in (_IT2, _T1M) else 0.0, spec)


class _Palette:
    """Consistent colours: FLC red, IT2FLC(w) along viridis by width (the matched type-1 of the
    same width shares the colour, dashed / hatched), PD grey, other controllers tab colours."""

    def __init__(self, fous: Iterable[float]) -> None:
        self.fous = sorted({float(w) for w in fous if w > 0})
        self.extra: dict[str, str] = {}

    def fou_color(self, w: float) -> str:
        cmap = matplotlib.colormaps["viridis"]
        if not self.fous or len(self.fous) == 1:
            pos = 0.35
        else:
            lo, hi = self.fous[0], self.fous[-1]
            pos = 0.05 + 0.7 * (min(max(w, lo), hi) - lo) / (hi - lo)
        r, g, b, _ = cmap(pos)
        return f"#{round(r * 255):02x}{round(g * 255):02x}{round(b * 255):02x}"

    def style(self, c: _Ctrl) -> _Style:
        if c.kind is _FLC:
            return _Style(_FLC_COLOR, "-", None, "o")
        if c.kind is _IT2:
            return _Style(self.fou_color(c.fou), "-", None, "s")
        if c.kind is _T1M:
            return _Style(self.fou_color(c.fou), "--", "///", "^")
        if c.kind is _PD:
            return _Style(_PD_COLOR, "-.", "..", "D")
        if c.label not in self.extra:
            self.extra[c.label] = _EXTRA_COLORS[len(self.extra) % len(_EXTRA_COLORS)]
        return _Style(self.extra[c.label], ":", "xx", "v")


def _order_key(c: _Ctrl) -> tuple[int, float, str]:
    rank = {_FLC: 0, _IT2: 1, _T1M: 2, _PD: 3}.get(c.kind, 4) if c.kind is not None else 4
    return rank, c.fou, c.label


# ---------------------------------------------------------------------------------------------
# Summary access
# ---------------------------------------------------------------------------------------------


class _Summary:
    """Index of the summary rows by (experiment, trajectory, controller, noise_std, metric)."""

    def __init__(self, summary: Sequence[Mapping[str, Any]]) -> None:
        self.rows: dict[tuple[str, str, str, float, str], Mapping[str, Any]] = {}
        for r in summary:
            key = (
                str(r["experiment"]), str(r["trajectory"]), str(r["controller"]),
                float(r["noise_std"]), str(r["metric"]),
            )  # fmt: skip
            self.rows[key] = r

    def controllers(self, experiment: str) -> list[str]:
        seen: dict[str, None] = {}
        for e, _, c, _, _ in self.rows:
            if e == experiment:
                seen.setdefault(c)
        return list(seen)

    def levels(self, experiment: str) -> list[float]:
        return sorted({s for e, _, _, s, _ in self.rows if e == experiment})

    def get(self, experiment: str, traj: str, ctrl: str, sigma: float,
            metric: str) -> Mapping[str, Any] | None:
        return self.rows.get((experiment, traj, ctrl, float(sigma), metric))

    def has(self, experiment: str) -> bool:
        return any(k[0] == experiment for k in self.rows)


def _num(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


# ---------------------------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------------------------


def _save(fig: Figure, out_dir: Path, stem: str) -> Path:
    png = out_dir / f"{stem}.png"
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=FIGURE_DPI, pil_kwargs={"compress_level": 0})
    with atomic_open(png, "wb") as fh:
        fh.write(_compact_png(buf.getvalue()))
    # The constrained layout has been computed by the PNG draw; freeze it for the SVG (the
    # layout is in figure fractions, so it does not depend on the dpi).
    fig.set_layout_engine("none")
    with atomic_open(out_dir / f"{stem}.svg", "wb") as fh:
        fig.savefig(fh, format="svg", metadata={"Date": None, "Creator": None})
    fig.clear()
    return png


def _compact_png(data: bytes) -> bytes:
    """Re-encode as a 256-colour palette PNG (about a third of the size, visually identical for
    these line and surface plots; the HTML report embeds the PNGs)."""
    with PIL.Image.open(io.BytesIO(data)) as im:
        pal = im.convert("RGB").quantize(
            colors=256, method=PIL.Image.Quantize.MEDIANCUT, dither=PIL.Image.Dither.NONE
        )
    out = io.BytesIO()
    pal.save(out, format="PNG", compress_level=9)
    return out.getvalue()


def _metric_label(metric: str) -> str:
    unit = INTEGRAL_UNITS.get(metric)
    return f"{metric} ({unit})" if unit else metric


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


def _reference_heading(x: np.ndarray, y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Heading of the reference path's tangent, unwrapped."""
    return np.unwrap(np.arctan2(np.gradient(y, t), np.gradient(x, t)))


def _sigma_text(result: StudyResult) -> str:
    cfg = result.config
    return (f"heading noise σ = {cfg.noise_std:g} rad (held at {cfg.loop.noise_rate:g} Hz), "
            f"noise seed index {cfg.figure_seed}")


def _trace_index(result: StudyResult, kind: ControllerKind,
                 fou: float | None = None) -> int | None:
    """Run index in the traces of the first traced controller of ``kind`` (and width ``fou``)."""
    for i, spec in enumerate(result.trace_specs):
        if spec.kind is kind and (fou is None or math.isclose(spec.fou, fou, abs_tol=1e-12)):
            return i
    return None


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
                        pal: _Palette) -> Figure:
    cfg = result.config
    trajs = list(cfg.trajectories)
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


# ---------------------------------------------------------------------------------------------
# Figure 11: integral errors with Monte Carlo intervals
# ---------------------------------------------------------------------------------------------


def _bar_groups(labels: Sequence[str], ctrls: Mapping[str, _Ctrl]) -> list[tuple[str, list[str]]]:
    """FLC | one group per FoU width (IT2FLC and matched type-1 side by side) | PD | others."""
    groups: list[tuple[str, list[str]]] = []
    infos = sorted((_info(ctrls, c) for c in labels), key=_order_key)
    by_fou: dict[float, list[str]] = {}
    for c in infos:
        if c.kind in (_IT2, _T1M):
            by_fou.setdefault(round(c.fou, 12), []).append(c.label)
    for c in infos:
        if c.kind is _FLC:
            groups.append((c.label, [c.label]))
    for w in sorted(by_fou):
        members = sorted(by_fou[w], key=lambda lb: _order_key(_info(ctrls, lb)))
        groups.append((f"w = {w:g}", members))
    for c in infos:
        if c.kind not in _PAPER_FUZZY:
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
                         pal: _Palette) -> Figure:
    cfg = result.config
    trajs = list(cfg.trajectories)
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
            for g, (_, members) in enumerate(groups):
                width = 0.8 / len(members)
                for k, label in enumerate(members):
                    r = summ.get("paper", traj, label, sigma, metric)
                    if r is None:
                        continue
                    st = pal.style(_info(ctrls, label))
                    mean, lo, hi = _num(r["mean"]), _num(r["ci_low"]), _num(r["ci_high"])
                    x = g - 0.4 + width * (k + 0.5)
                    a.bar(x, mean, width=width * 0.92, color=st.color if st.hatch is None
                          else "white", edgecolor=st.color, hatch=st.hatch, linewidth=1.0)
                    a.errorbar(x, mean, yerr=[[mean - lo], [hi - mean]], fmt="none",
                               ecolor="black", elinewidth=0.9, capsize=2)
                    values += [mean, lo, hi]
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
    if any(c.kind is _T1M for c in (ctrls.get(lb) for lb in labels) if c):
        handles.append(Patch(facecolor="white", edgecolor="#444444", hatch="///",
                             label="T1 dead-zone-matched (same colour = same w)"))
    for lb in labels:
        c = _info(ctrls, lb)
        if c.kind not in _PAPER_FUZZY:
            st = pal.style(c)
            handles.append(Patch(facecolor="white", edgecolor=st.color, hatch=st.hatch,
                                 label=lb))
    handles.append(Line2D([], [], color="black", marker="|", ls="none", ms=8,
                          label="95 % interval of the mean"))
    fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 7),
               frameon=False)
    n_seeds = next((int(r["n"]) for k, r in summ.rows.items() if k[0] == "paper"), 0)
    fig.suptitle(f"Integral heading errors (cf. paper Fig. 11): mean over {n_seeds} noise "
                 f"realisations at σ = {sigma:g} rad, with 95 % intervals; dotted line = FLC mean",
                 fontsize=10.5)
    return fig


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
                     pal: _Palette) -> Figure:
    cfg = result.config
    trajs = list(cfg.trajectories)
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
    n_seeds = next((int(r["n"]) for k, r in summ.rows.items() if k[0] == "noise"), 0)
    fig.suptitle(f"Integral errors vs heading-noise level: mean and 95 % band over {n_seeds} "
                 f"realisations per point (dotted: the study's σ = {cfg.noise_std:g} rad)",
                 fontsize=10.5)
    return fig


def _fig_fou_sweep(result: StudyResult, summ: _Summary, ctrls: Mapping[str, _Ctrl],
                   pal: _Palette) -> Figure:
    cfg = result.config
    trajs = list(cfg.trajectories)
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
    n_seeds = next((int(r["n"]) for k, r in summ.rows.items() if k[0] == "fou"), 0)
    fig.suptitle(f"FoU sweep at σ = {sigma:g} rad: IT2FLC(w) vs the type-1 FLC with the same "
                 f"dead zone; mean and 95 % band over {n_seeds} realisations", fontsize=10.5)
    return fig


# ---------------------------------------------------------------------------------------------
# Control surfaces and dead zone
# ---------------------------------------------------------------------------------------------


def _surface_layout(result: StudyResult, ctrls: Mapping[str, _Ctrl]) -> list[list[str | None]]:
    """Columns by FoU width (0 = FLC); row 0 the IT2FLCs, row 1 the matched type-1 FLCs;
    anything else in a further row."""
    infos = [_surface_info(result, ctrls, lb) for lb in result.surfaces]
    widths = sorted({round(c.fou, 12) for c in infos if c.kind in (_IT2, _T1M)})
    cols = [0.0, *widths]
    top: list[str | None] = [None] * len(cols)
    bottom: list[str | None] = [None] * len(cols)
    others: list[str] = []
    for c in infos:
        if c.kind is _FLC and top[0] is None:
            top[0] = c.label
        elif c.kind is _IT2:
            top[cols.index(round(c.fou, 12))] = c.label
        elif c.kind is _T1M:
            bottom[cols.index(round(c.fou, 12))] = c.label
        else:
            others.append(c.label)
    grid = [top]
    if any(b is not None for b in bottom):
        grid.append(bottom)
    ncol = len(cols)
    for k in range(0, len(others), ncol):
        row: list[str | None] = list(others[k:k + ncol])
        grid.append(row + [None] * (ncol - len(row)))
    return grid


def _dead_zone(c: _Ctrl) -> float | None:
    """Half-width of the dead zone of the paper's fuzzy controllers in the fuzzy system's input
    units (``Ke e``, ``Kde de``): only the Z sets fire while both inputs are below it."""
    if c.kind in _PAPER_FUZZY:
        return 0.2 - c.fou / 2.0
    return None


def _input_gains(specs: Iterable[ControllerSpec | None]) -> tuple[float, float] | None:
    """The (Ke, Kde) shared by every fuzzy controller among ``specs`` (None if they differ)."""
    gains = {(s.ke, s.kde) for s in specs if s is not None and s.kind is not _PD}
    return next(iter(gains)) if len(gains) == 1 else None


def surface_limit(result: StudyResult) -> float:
    """The largest ``|u|`` over the stored control surfaces, V (the paper's rules: 12)."""
    return max((float(np.max(np.abs(u))) for _, _, u in result.surfaces.values()), default=0.0)


def _input_names(c: _Ctrl) -> tuple[str, str]:
    spec = c.spec
    if spec is None or (spec.ke, spec.kde) == (1.0, 1.0):
        return "e (rad)", "Δe (rad)"
    return f"Ke·e (Ke = {spec.ke:g})", f"Kde·Δe (Kde = {spec.kde:g})"


def _fig_control_surfaces(result: StudyResult, ctrls: Mapping[str, _Ctrl]) -> Figure:
    grid = _surface_layout(result, ctrls)
    nrow, ncol = len(grid), len(grid[0])
    fig = Figure(figsize=(2.9 * ncol + 1.0, 2.8 * nrow + 0.6), layout="constrained")
    ax = np.asarray(fig.subplots(nrow, ncol, squeeze=False))
    image = None
    vlim = surface_limit(result) or 1.0
    step = vlim / 3.0
    levels = [k * step / 2.0 for k in (-5, -3, -1, 1, 3, 5)]
    for i, row in enumerate(grid):
        for j, label in enumerate(row):
            a = ax[i, j]
            if label is None:
                a.set_axis_off()
                continue
            e, de, u = result.surfaces[label]
            extent = (float(e.min()), float(e.max()), float(de.min()), float(de.max()))
            image = a.imshow(u.T, origin="lower", extent=extent, cmap="RdBu_r", vmin=-vlim,
                             vmax=vlim, interpolation="nearest", aspect="equal")
            cs = a.contour(e, de, u, levels=levels, colors="k", linewidths=0.5, alpha=0.6)
            a.clabel(cs, fontsize=6, fmt="%g")
            c = _surface_info(result, ctrls, label)
            d = _dead_zone(c)
            if d is not None and d > 0:
                a.add_patch(Rectangle((-d, -d), 2 * d, 2 * d, fill=False, ec="black", lw=1.0,
                                      ls="--"))
                a.set_title(f"{label}\ndead zone |e|, |Δe| < {d:g}", fontsize=8.5)
            else:
                a.set_title(label, fontsize=8.5)
            a.grid(False)
            x_name, y_name = _input_names(c)
            a.set_xlabel(x_name)
            a.set_ylabel(y_name)
    if image is not None:
        cb = fig.colorbar(image, ax=ax.ravel().tolist(), shrink=0.8, pad=0.02)
        cb.set_label("u (V)")
    gains = _input_gains(_surface_info(result, ctrls, lb).spec for lb in result.surfaces)
    gain_text = ("inputs Ke·e, Kde·Δe" if gains is None
                 else f"Ke = {gains[0]:g}, Kde = {gains[1]:g}")
    fig.suptitle(f"Control surfaces u(e, Δe) ({gain_text}; contours every {step:.3g} V; dashed "
                 "square: only the Z×Z rule fires, u = 0)", fontsize=10)
    return fig


def _zero_de_slice(result: StudyResult, c: _Ctrl) -> tuple[np.ndarray, np.ndarray]:
    """``(x, u(x, 0))`` of a fuzzy controller, ``x`` its first input (``Ke e``).

    The paper's controllers are rebuilt from their specs (with their reducer and t-norm) and
    evaluated on a fine grid, so that the zoomed dead-zone edges are exact; any other controller
    gets the ``de = 0`` column of its stored surface.
    """
    spec = c.spec
    if spec is not None and spec.kind in _PAPER_FUZZY:
        controller = spec.build()
        if isinstance(controller, FuzzyHeadingController):
            x = np.linspace(-1.0, 1.0, 2001)
            return x, np.asarray(controller.fls(x, np.zeros_like(x)), dtype=float)
    ge, gde, gu = result.surfaces[c.label]
    k = int(np.argmin(np.abs(gde[0, :])))
    return ge[:, k], gu[:, k]


def _fig_dead_zone(result: StudyResult, ctrls: Mapping[str, _Ctrl], pal: _Palette) -> Figure:
    infos = sorted((_surface_info(result, ctrls, lb) for lb in result.surfaces), key=_order_key)
    fig = Figure(figsize=(11.0, 4.3), layout="constrained")
    a_full, a_zoom = fig.subplots(1, 2)
    zoom = 0.35
    for c in infos:
        st = pal.style(c)
        x, u = _zero_de_slice(result, c)
        a_full.plot(x, u, color=st.color, ls=st.ls, label=c.label)
        a_zoom.plot(x, u, color=st.color, ls=st.ls, label=c.label)
        d = _dead_zone(c)
        if d is not None and c.kind is not _T1M:
            for sgn in (-1.0, 1.0):
                a_zoom.axvline(sgn * d, color=st.color, lw=0.8, ls=":")
            a_zoom.annotate(f"{d:g}", (d, 1.0), xycoords=("data", "axes fraction"),
                            xytext=(2, -2), textcoords="offset points", color=st.color,
                            fontsize=7.5, va="top", ha="left")
    gains = _input_gains(c.spec for c in infos)
    x_name = "heading error e (rad)" if gains is not None and gains[0] == 1.0 else "Ke·e"
    for a in (a_full, a_zoom):
        a.axhline(0.0, color="#999999", lw=0.6)
        a.set_xlabel(f"{x_name}, Δe = 0")
        a.set_ylabel("u (V)")
    a_full.set_title("u(e, Δe = 0) over the universe")
    a_zoom.set_xlim(-zoom, zoom)
    a_zoom.set_ylim(-3.0, 3.0)
    a_zoom.set_title("zoom: dead-zone edges ±(0.2 − w/2) dotted")
    a_full.legend(loc="upper left", fontsize=7.5)
    fig.suptitle("Dead zone: near e = 0 only the Z sets fire and u = 0; the FoU narrows the dead "
                 "zone from 0.2 to 0.2 − w/2 (dashed: type-1 FLC with the same dead zone)",
                 fontsize=10)
    return fig


# ---------------------------------------------------------------------------------------------
# Win rates
# ---------------------------------------------------------------------------------------------


def _fig_win_rates(result: StudyResult, summ: _Summary, ctrls: Mapping[str, _Ctrl]) -> Figure:
    cfg = result.config
    trajs = list(cfg.trajectories)
    sigma = summ.levels("paper")[0] if summ.levels("paper") else cfg.noise_std
    labels = sorted((lb for lb in summ.controllers("paper") if lb != "FLC"),
                    key=lambda lb: _order_key(_info(ctrls, lb)))
    n = len(trajs)
    fig = Figure(figsize=(max(3.3 * n + 2.5, 6.0), 0.5 * max(len(labels), 1) + 1.9),
                 layout="constrained")
    ax = np.asarray(fig.subplots(1, n, squeeze=False, sharey=True))[0]
    image = None
    any_ties = False
    for j, traj in enumerate(trajs):
        a = ax[j]
        m = np.full((len(labels), len(INTEGRALS)), np.nan)
        ties = np.zeros_like(m)
        for i, label in enumerate(labels):
            for k, metric in enumerate(INTEGRALS):
                r = summ.get("paper", traj, label, sigma, metric)
                if r is not None:
                    m[i, k] = _num(r["win_rate"])
                    t = _num(r.get("ties"))
                    ties[i, k] = t if math.isfinite(t) else 0.0
        image = a.imshow(m, cmap="RdBu", vmin=0.0, vmax=1.0, aspect="auto")
        for i in range(m.shape[0]):
            for k in range(m.shape[1]):
                if not math.isfinite(m[i, k]):
                    continue
                color = "white" if abs(m[i, k] - 0.5) > 0.3 else "black"
                if ties[i, k] > 0:  # a tie is no loss: say how much of the 0.5 is ties
                    any_ties = True
                    a.text(k, i - 0.12, f"{m[i, k]:.2f}", ha="center", va="center",
                           fontsize=7.5, color=color)
                    a.text(k, i + 0.22, f"ties {ties[i, k]:.0%}", ha="center", va="center",
                           fontsize=6, color=color)
                else:
                    a.text(k, i, f"{m[i, k]:.2f}", ha="center", va="center", fontsize=7.5,
                           color=color)
        a.set_xticks(range(len(INTEGRALS)), INTEGRALS)
        a.set_yticks(range(len(labels)), labels)
        a.tick_params(axis="y", labelleft=(j == 0))
        a.grid(False)
        a.set_title(traj)
    if image is not None:
        cb = fig.colorbar(image, ax=ax.tolist(), shrink=0.9, pad=0.02)
        cb.set_label("win rate vs FLC (ties count ½)")
        cb.set_ticks([0.0, 0.25, 0.5, 0.75, 1.0],
                     labels=["0 worse", "0.25", "0.5 no diff.", "0.75", "1 better"])
    tie_note = "; 'ties': share of exact ties" if any_ties else ""
    fig.suptitle(f"Paired win rate vs the FLC at σ = {sigma:g} rad: P(smaller error than the "
                 f"FLC) + ½ P(equal error), over the noise realisations (0.5: no difference; "
                 f"blue: better{tie_note})", fontsize=10)
    return fig


# ---------------------------------------------------------------------------------------------
# Entry point
# ---------------------------------------------------------------------------------------------


def write_figures(
    result: StudyResult, summary: Sequence[Mapping[str, Any]], out_dir: Path
) -> dict[str, Path]:
    """Draw every figure of the study and write each as PNG and SVG.

    Parameters
    ----------
    result : StudyResult
        From :func:`it2track.experiments.study.run_study`.
    summary : list of dict
        From :func:`it2track.experiments.analysis.summarise` ``(result.rows)``.
    out_dir : Path
        Folder for ``<key>.png`` and ``<key>.svg`` (created if missing).

    Returns
    -------
    dict of str -> Path
        Figure key -> PNG path, in report order (see :func:`figure_keys`). Figures whose data
        are absent (e.g. no ``noise`` rows in ``summary``) are skipped.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    cfg = result.config
    ctrls = _controller_table(result)
    pal = _Palette(cfg.fous)
    summ = _Summary(summary)
    out: dict[str, Path] = {}
    with matplotlib.rc_context(_RC):  # type: ignore[arg-type]
        for traj in cfg.trajectories:
            if traj in result.traces:
                key = f"paper_{slug(traj)}"
                out[key] = _save(_fig_paper(result, traj, ctrls, pal), out_dir, key)
        if all(t in result.traces for t in cfg.trajectories):
            out["fou_comparison"] = _save(_fig_fou_comparison(result, ctrls, pal), out_dir,
                                          "fou_comparison")
        if summ.has("paper"):
            out["integral_errors"] = _save(_fig_integral_errors(result, summ, ctrls, pal),
                                           out_dir, "integral_errors")
        if summ.has("noise"):
            out["noise_sweep"] = _save(_fig_noise_sweep(result, summ, ctrls, pal), out_dir,
                                       "noise_sweep")
        if summ.has("fou"):
            out["fou_sweep"] = _save(_fig_fou_sweep(result, summ, ctrls, pal), out_dir,
                                     "fou_sweep")
        if result.surfaces:
            out["control_surfaces"] = _save(_fig_control_surfaces(result, ctrls), out_dir,
                                            "control_surfaces")
            out["dead_zone"] = _save(_fig_dead_zone(result, ctrls, pal), out_dir, "dead_zone")
        if summ.has("paper") and len(summ.controllers("paper")) > 1:
            out["win_rates"] = _save(_fig_win_rates(result, summ, ctrls), out_dir, "win_rates")
    return out

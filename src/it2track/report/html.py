"""The study's self-contained HTML report: one file, figures embedded, no script, no network.

The page holds the setup, every assumption the study makes where the paper is silent or
misprinted (DESIGN.md), the figures with captions, the verdicts on the paper's claims with their
criteria and evidence, a summary table and the command that regenerates it all. Every piece of
text is escaped; the file is written atomically.
"""

from __future__ import annotations

import base64
import html
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..atomicfile import atomic_write_text
from ..experiments.analysis import C3_FACTOR, C3_TARGET, INTEGRALS
from ..experiments.specs import ControllerKind, ControllerSpec
from ..experiments.study import StudyResult
from ..fuzzy import Reducer
from ..tracking import PDHeadingController
from .figures import INTEGRAL_UNITS, PAPER_FIGURE_NUMBER, controller_specs, slug, surface_limit

__all__ = ["figure_captions", "render_html", "write_html"]

_MIME = {".png": "image/png", ".svg": "image/svg+xml", ".jpg": "image/jpeg",
         ".jpeg": "image/jpeg", ".gif": "image/gif", ".webp": "image/webp"}

_TRAJECTORY_FORMULA = {
    "straight": "x_d = 2t, y_d = 0 (paper §III-A)",
    "curved": "x_d = 2t, y_d = 0.2t² − 4 (paper §III-B)",
    "sinusoidal": "x_d = 2t, y_d = 0.2 − 0.2 cos 2t (paper §III-C)",
}

_CSS = """
:root { --fg: #1d1d1f; --muted: #5a5a5f; --line: #d9d9de; --bg-alt: #f5f5f7;
        --ok: #1b7f3b; --bad: #b3261e; --part: #9a6700; --na: #6e6e73; }
* { box-sizing: border-box; }
body { margin: 0; color: var(--fg); background: #fff;
       font: 15px/1.5 -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif; }
main { max-width: 1180px; margin: 0 auto; padding: 24px 28px 64px; }
h1 { font-size: 1.7em; margin: 0.2em 0 0.3em; line-height: 1.25; }
h2 { font-size: 1.3em; margin: 2.0em 0 0.6em; padding-bottom: 0.2em;
     border-bottom: 1px solid var(--line); }
h3 { font-size: 1.05em; margin: 1.4em 0 0.4em; }
p, li { max-width: 62em; }
.subtitle { color: var(--muted); margin-top: 0; }
nav ol { columns: 2; padding-left: 1.4em; margin: 0.4em 0; }
code, pre { font-family: ui-monospace, "SFMono-Regular", Menlo, Consolas, monospace;
            font-size: 0.88em; }
pre { background: var(--bg-alt); border: 1px solid var(--line); border-radius: 6px;
      padding: 10px 12px; overflow-x: auto; white-space: pre-wrap; word-break: break-word; }
table { border-collapse: collapse; margin: 0.6em 0 1.2em; font-size: 0.88em; }
th, td { border: 1px solid var(--line); padding: 4px 8px; text-align: left; vertical-align: top; }
th { background: var(--bg-alt); font-weight: 600; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
tbody tr:nth-child(even) td { background: #fbfbfd; }
.kv th { width: 16em; }
.verdict { font-weight: 600; white-space: nowrap; }
.v-holds { color: var(--ok); } .v-not { color: var(--bad); } .v-partial { color: var(--part); }
.v-na { color: var(--na); }
.detail { display: block; font-weight: normal; color: var(--muted); font-size: 0.9em;
          white-space: normal; }
td.o-sup { color: var(--ok); font-weight: 600; } td.o-con { color: var(--bad); font-weight: 600; }
td.o-inc { color: var(--na); }
.glance { border: 1px solid var(--line); border-radius: 8px; padding: 10px 16px;
          background: var(--bg-alt); }
.glance ul { margin: 0.3em 0; padding-left: 1.2em; }
figure { margin: 1.2em 0 2.2em; }
figure img { display: block; max-width: 100%; height: auto; border: 1px solid var(--line);
             border-radius: 4px; }
figcaption { color: var(--muted); font-size: 0.92em; margin-top: 0.5em; max-width: 62em; }
figcaption b { color: var(--fg); }
details { margin: 0.3em 0 1em; }
summary { cursor: pointer; color: var(--muted); }
.scroll { overflow-x: auto; }
.assumptions li { margin-bottom: 0.45em; }
footer { margin-top: 3em; color: var(--muted); font-size: 0.85em; }
@media print { nav { display: none; } figure { break-inside: avoid; } }
"""


# ---------------------------------------------------------------------------------------------
# Small helpers
# ---------------------------------------------------------------------------------------------


def _e(x: Any) -> str:
    return html.escape(str(x), quote=True)


def _plain(v: Any) -> Any:
    """JSON-ready copy (numpy scalars and arrays, tuples, paths)."""
    if isinstance(v, Mapping):
        return {str(k): _plain(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [_plain(x) for x in v]
    if isinstance(v, np.ndarray):
        return [_plain(x) for x in v.tolist()]
    if isinstance(v, np.bool_):
        return bool(v)
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, np.floating):
        return float(v)
    if isinstance(v, Path):
        return str(v)
    return v


def _fmt(v: Any, digits: int = 4) -> str:
    if isinstance(v, bool | np.bool_):
        return "yes" if v else "no"
    if isinstance(v, int | np.integer):
        return str(int(v))
    if isinstance(v, float | np.floating):
        f = float(v)
        if not math.isfinite(f):
            return str(f)
        return f"{f:.{digits}g}"
    if v is None:
        return "—"
    return str(v)


def _num(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def _verdict_class(verdict: str) -> str:
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


#: Outcome of one evidence cell -> CSS class (a tie is inconclusive, never a loss).
_OUTCOME_CLASS = {"supports": "o-sup", "contradicts": "o-con", "inconclusive": "o-inc"}


def _table(header: Sequence[str], rows: Sequence[Sequence[Any]], *, numeric: Sequence[bool]
           | None = None, cls: str = "") -> str:
    numeric = list(numeric or [False] * len(header))
    out = [f'<div class="scroll"><table class="{_e(cls)}"><thead><tr>']
    out += [f"<th>{_e(h)}</th>" for h in header]
    out.append("</tr></thead><tbody>")
    for row in rows:
        out.append("<tr>")
        for cell, is_num in zip(row, numeric, strict=False):
            out.append(f'<td class="num">{_e(_fmt(cell))}</td>' if is_num
                       else f"<td>{_e(_fmt(cell))}</td>")
        out.append("</tr>")
    out.append("</tbody></table></div>")
    return "".join(out)


def _kv(rows: Sequence[tuple[str, Any]]) -> str:
    body = "".join(f"<tr><th>{_e(k)}</th><td>{_e(_fmt(v))}</td></tr>" for k, v in rows)
    return f'<table class="kv"><tbody>{body}</tbody></table>'


def _data_uri(path: Path) -> str:
    mime = _MIME.get(path.suffix.lower(), "application/octet-stream")
    return f"data:{mime};base64," + base64.b64encode(path.read_bytes()).decode("ascii")


# ---------------------------------------------------------------------------------------------
# Facts derived from the result (never hard-coded: the configuration can change them)
# ---------------------------------------------------------------------------------------------

#: The paper's heading-noise power, W (read as Simulink band-limited white noise).
PAPER_NOISE_POWER = 0.1
#: The paper's noise rate, Hz.
PAPER_NOISE_RATE = 100.0
_PAPER_FUZZY = (ControllerKind.FLC, ControllerKind.IT2, ControllerKind.T1_MATCHED)


def _fuzzy_specs(result: StudyResult) -> list[ControllerSpec]:
    return [s for s in controller_specs(result).values() if s.kind is not ControllerKind.PD]


def _gains_text(result: StudyResult) -> str:
    """``Ke = 1, Kde = 1`` when every fuzzy controller shares its input gains, else a list."""
    gains = sorted({(s.ke, s.kde) for s in _fuzzy_specs(result)})
    if not gains:
        return "Ke, Kde per controller"
    if len(gains) == 1:
        ke, kde = gains[0]
        return f"Ke = {ke:g}, Kde = {kde:g}"
    return "per controller: " + "; ".join(f"Ke = {a:g}, Kde = {b:g}" for a, b in gains)


def _electrical_pole(result: StudyResult) -> float:
    """The fast (electrical) pole of the motor model, 1/s."""
    m = result.config.loop.robot.motor
    a = np.array([[-m.resistance / m.inductance, -m.torque_constant / m.inductance],
                  [m.torque_constant / m.inertia, -m.friction / m.inertia]])
    return float(np.min(np.linalg.eigvals(a).real))


def _pd_limit(result: StudyResult) -> float:
    """The PD controller's output limit, V."""
    if result.pd is None:
        return math.nan
    controller = result.pd.build()
    return float(controller.u_max) if isinstance(controller, PDHeadingController) else math.nan


def _gaps(result: StudyResult, traj: str) -> tuple[float, float, float] | None:
    """Distance robot - reference point at t = 0, and the smallest and largest at the end over
    the traced controllers, m (None without a trace)."""
    trace = result.traces.get(traj)
    if trace is None:
        return None
    s = trace.series
    gap = np.hypot(s["x"] - s["x_ref"], s["y"] - s["y_ref"])
    return float(gap[0, 0]), float(gap[:, -1].min()), float(gap[:, -1].max())


def _gap_sentence(result: StudyResult, traj: str) -> str:
    """For a trajectory whose reference starts away from the robot: the gap never closes."""
    g = _gaps(result, traj)
    if g is None or g[0] < 0.05:
        return ""
    start, lo, hi = g
    end = f"{lo:.2g} m" if math.isclose(lo, hi, rel_tol=0.05) else f"{lo:.2g}–{hi:.2g} m"
    t_end = float(result.traces[traj].t[-1])
    return (f"The reference point starts {start:.3g} m from the robot. The controllers only "
            "steer: the speed is the feed-forward V0 for the reference speed (the paper's scheme "
            "does not regulate speed), so the robot never catches up and the gap does not close "
            f"(still {end} at t = {t_end:g} s).")


# ---------------------------------------------------------------------------------------------
# Captions
# ---------------------------------------------------------------------------------------------


def _n_of(summary: Sequence[Mapping[str, Any]], experiment: str) -> int:
    return next((int(r["n"]) for r in summary if r.get("experiment") == experiment), 0)


def figure_captions(result: StudyResult, summary: Sequence[Mapping[str, Any]]
                    ) -> dict[str, tuple[str, str]]:
    """Figure key -> (title, caption) for the figures of :func:`~.figures.write_figures`."""
    cfg = result.config
    sigma = f"σ = {cfg.noise_std:g} rad"
    seed = f"noise realisation with seed index {cfg.figure_seed}"
    fous = ", ".join(f"{w:g}" for w in cfg.fous)
    n_paper, n_noise, n_fou = (_n_of(summary, e) for e in ("paper", "noise", "fou"))
    caps: dict[str, tuple[str, str]] = {}
    for traj in cfg.trajectories:
        num = PAPER_FIGURE_NUMBER.get(traj)
        title = f"{traj.capitalize()} trajectory" + (f" (paper Fig. {num})" if num else "")
        caps[f"paper_{slug(traj)}"] = (
            title,
            f"FLC vs IT2FLC FoU {cfg.main_fou:g} on the {traj} trajectory, one {seed} at "
            f"{sigma}. (a) Position with the reference path (dashed; dots mark the start "
            "points). (b) True heading θ (solid) and the desired heading θd = atan2 towards "
            "the current reference point (dash-dot), with the tangent heading of the path "
            "(dotted). (c) Translational speed and the reference speed |ṗd|; the inset shows "
            "v − |ṗd| after start-up. With the motor mixing V0 ± u and identical motors, v does "
            "not depend on u unless a wheel voltage saturates, so (c) is the same for every "
            "controller. (d) Rotational speed. " + _gap_sentence(result, traj),
        )
    caps["fou_comparison"] = (
        "FoU comparison (paper Fig. 10)",
        f"Position (top) and heading θ (bottom) of the IT2FLCs with FoU widths {fous} on each "
        f"trajectory, same {seed} at {sigma}. Dashed: the reference path (top) and the tangent "
        "heading of the path (bottom). One realisation only: the Monte Carlo figures below say "
        "whether the differences are systematic.",
    )
    caps["integral_errors"] = (
        "Integral errors (paper Fig. 11, with Monte Carlo statistics)",
        f"IAE, ITAE, ISE and ITSE of the true heading error θd − θ, mean over {n_paper} noise "
        f"realisations at {sigma} (the same realisations for every controller), with 95 % "
        "Student-t intervals of the mean. For each FoU width w the solid bar is the IT2FLC and "
        "the hatched bar the type-1 FLC with the same dead zone 0.2 − w/2; dotted red line: the "
        "FLC's mean. Bars too short to read carry their value.",
    )
    caps["noise_sweep"] = (
        "Noise-level sweep",
        f"The four integral errors against the heading-noise standard deviation σ (square-root "
        f"axis), mean and 95 % band over {n_noise} realisations per point; the dotted vertical "
        f"marks the study's {sigma}. Panels marked [log] use a log (or, where errors are "
        "exactly zero, symmetric-log) axis. On the straight line the robot starts on the path, "
        "so with σ below the dead zone a fuzzy controller never acts and its error is 0.",
    )
    caps["fou_sweep"] = (
        "FoU-width sweep: footprint vs dead zone",
        f"ISE and IAE against the FoU width w at {sigma}, mean and 95 % band over {n_fou} "
        "realisations, for the IT2FLC(w) (solid) and the type-1 FLC with the same dead zone "
        "0.2 − w/2 (dashed); both start from the FLC at w = 0 (red dot). Dotted verticals: "
        "the paper's widths. Where the dashed curve lies at or below the solid one, narrowing "
        "the dead zone alone explains the improvement over the FLC.",
    )
    vlim = surface_limit(result)
    step = vlim / 3.0
    contours = ", ".join(f"±{k * step / 2:.3g}" for k in (1, 3, 5))
    gains = _gains_text(result)
    unit_note = ", so the inputs are in rad" if gains == "Ke = 1, Kde = 1" else ""
    caps["control_surfaces"] = (
        "Control surfaces",
        f"u(e, Δe) of each fuzzy controller over the input universe [−1, 1]² ({gains}"
        f"{unit_note}), one colour scale for all (±{vlim:.3g} V, the largest consequent), "
        f"contours at {contours} V. Top: the FLC and the IT2FLCs; bottom: the type-1 FLCs whose "
        "dead zone matches the IT2FLC above them. Dashed square: the dead zone, where only the "
        "Z×Z rule fires and u = 0.",
    )
    caps["dead_zone"] = (
        "The dead zone (why a wider FoU helps)",
        "The slice u(e, Δe = 0) of each controller as built from its specification (reducer and "
        "t-norm included). Left: the whole universe; right: zoom with the dead-zone edges "
        "±(0.2 − w/2) dotted. The FLC does nothing while |Ke·e| < 0.2 (0.2 rad = 11.5° for "
        "Ke = 1); an FoU of width w shrinks this to 0.2 − w/2 (DESIGN.md §3). Dashed: the "
        "type-1 FLCs with the same dead zones; just outside the dead zone they are steeper than "
        "the IT2FLCs, whose type-reduced output averages the lower and upper firing.",
    )
    caps["win_rates"] = (
        "Paired win rates",
        f"Per trajectory and criterion, over the {n_paper} noise realisations at {sigma}: the "
        "fraction in which the controller's error is smaller than the FLC's on the same "
        "realisation, ties counting ½ (win rate = P(smaller) + ½ P(equal)). 0.5: no "
        "difference — including exact ties, e.g. when neither controller leaves its dead zone, "
        "which are not losses; blue: better than the FLC; red: worse. Cells with ties give "
        "their share.",
    )
    return caps


_FIGURE_ORDER_TAIL = ("fou_comparison", "integral_errors", "win_rates", "noise_sweep",
                      "fou_sweep", "control_surfaces", "dead_zone")


def _ordered_keys(figures: Mapping[str, Path], result: StudyResult) -> list[str]:
    preferred = [f"paper_{slug(t)}" for t in result.config.trajectories]
    preferred += list(_FIGURE_ORDER_TAIL)
    keys = [k for k in preferred if k in figures]
    keys += [k for k in figures if k not in keys]
    return keys


# ---------------------------------------------------------------------------------------------
# Sections
# ---------------------------------------------------------------------------------------------


def _fuzzy_options(spec: ControllerSpec | None) -> str:
    """t-norm, input gains and (IT2) reducer of a fuzzy controller's spec."""
    if spec is None:
        return ""
    out = [f"{spec.tnorm} t-norm"]
    if (spec.ke, spec.kde) != (1.0, 1.0):
        out.append(f"Ke = {spec.ke:g}, Kde = {spec.kde:g}")
    return ", " + ", ".join(out)


def _reducer_text(spec: ControllerSpec | None) -> str:
    if spec is None:
        return "type reduction to [yl, yr]"
    reducer = Reducer.from_name(spec.reducer).value
    if reducer.exact:
        return f"exact type reduction ({reducer.name}, KM-equivalent)"
    return f"approximate type reduction ({reducer.name}, not exact)"


def _controller_rows(result: StudyResult) -> list[tuple[str, str]]:
    rows = result.rows
    mask = rows["experiment"] == "paper"
    labels = rows["controller"][mask] if mask.any() else rows["controller"]
    kinds = rows["kind"][mask] if mask.any() else rows["kind"]
    fous = rows["fou"][mask] if mask.any() else rows["fou"]
    seen: dict[str, tuple[str, float]] = {}
    for lb, k, w in zip(labels, kinds, fous, strict=True):
        seen.setdefault(str(lb), (str(k), float(w)))
    specs = controller_specs(result)
    out = []
    for lb, (kind, w) in seen.items():
        spec = specs.get(lb)
        if spec is not None:
            kind = spec.kind.value
            w = spec.fou if spec.kind in (ControllerKind.IT2, ControllerKind.T1_MATCHED) else 0.0
        opts = _fuzzy_options(spec)
        if kind == ControllerKind.FLC.value:
            desc = ("the paper's type-1 FLC: sets N [−1 −1 −0.2], Z [−0.8 0 0.8], P [0.2 1 1] "
                    f"on e and Δe, nine rules of Table 2 (±4, ±8, ±12 V){opts}")
        elif kind == ControllerKind.IT2.value:
            desc = (f"interval type-2 FLC, FoU width w = {w:g}: every sloped side of the FLC's "
                    f"sets widened by ±w/2 (upper/lower MF), same rules, {_reducer_text(spec)}, "
                    f"u = (yl + yr)/2{opts}")
        elif kind == ControllerKind.T1_MATCHED.value:
            desc = (f"fair baseline: type-1 FLC built from the upper MFs of the IT2FLC with "
                    f"w = {w:g}, so its dead zone (|e| < {0.2 - w / 2:g}) equals the "
                    f"IT2FLC's{opts}")
        elif kind == ControllerKind.PD.value:
            pd = spec if spec is not None else result.pd
            gains = "" if pd is None else (
                f": u = clip(Kp·e + Kd·D, ±{_fmt(_pd_limit(result))} V), D the derivative of e "
                f"through the filter 1/(Tf s + 1), Tf = {_fmt(pd.tf)} s; Kp = {_fmt(pd.kp)} "
                f"V/rad, Kd = {_fmt(pd.kd)} V·s/rad")
            desc = "PD heading controller baseline" + gains + " (tuning below)"
        elif kind == ControllerKind.FILE.value and spec is not None:
            desc = f"user-supplied fuzzy system from {spec.path}{opts}"
        else:
            desc = f"user-supplied controller (kind {kind})"
        out.append((lb, desc))
    return out


def _setup_section(result: StudyResult, summary: Sequence[Mapping[str, Any]]) -> str:
    cfg = result.config
    d = _plain(cfg.to_dict())
    sim, robot, study = d["simulation"], d["robot"], d["study"]
    motor = robot["motor"]
    parts = ['<h2 id="setup">Setup</h2>', "<h3>Controllers</h3>"]
    parts.append(_table(["controller", "definition"], _controller_rows(result)))
    parts.append("<h3>Trajectories</h3><ul>")
    for t in cfg.trajectories:
        formula = _TRAJECTORY_FORMULA.get(t, "user trajectory (waypoints)")
        parts.append(f"<li><b>{_e(t)}</b>: {_e(formula)}</li>")
    parts.append(f"</ul><p>Duration {_e(_fmt(sim['duration']))} s, control period "
                 f"{_e(_fmt(sim['ts']))} s, start pose (x, y, θ) = "
                 f"{_e(tuple(sim['start_pose']))}, robot at rest at t = 0.</p>")
    parts.append("<h3>Robot and motors (paper Table 3)</h3>")
    parts.append(_kv([
        ("half wheel track l", f"{_fmt(robot['half_track'])} m"),
        ("wheel radius r", f"{_fmt(robot['wheel_radius'])} m"),
        ("armature resistance R", f"{_fmt(motor['resistance'])} Ω"),
        ("armature inductance L", f"{_fmt(motor['inductance'])} H"),
        ("rotor inertia J", f"{_fmt(motor['inertia'])} kg·m²"),
        ("viscous friction b", f"{_fmt(motor['friction'])} N·m·s"),
        ("motor constant K", f"{_fmt(motor['torque_constant'])} N·m/A = V·s/rad"),
        ("voltage limit", f"±{_fmt(motor['voltage_limit'])} V"),
    ]))
    parts.append("<h3>Noise and Monte Carlo</h3>")
    parts.append(_kv([
        ("heading noise of the main experiment and figures", f"σ = {_fmt(study['noise_std'])} rad"),
        ("noise held (resampled) at", f"{_fmt(sim['noise_rate'])} Hz"),
        ("noise-sweep levels σ", ", ".join(_fmt(v) for v in study["noise_levels"]) + " rad"),
        ("FoU widths compared (paper)", ", ".join(_fmt(v) for v in study["fous"])),
        ("main IT2FLC (paper Table 1)", f"FoU {_fmt(study['main_fou'])}"),
        ("FoU sweep", f"{_fmt(min(study['fou_sweep']))} … {_fmt(max(study['fou_sweep']))} "
                      f"({len(study['fou_sweep'])} widths)"),
        ("realisations per cell, main experiment", study["seeds"]),
        ("realisations per cell, sweeps", study["sweep_seeds"]),
        ("seed index of the time-series figures", study["figure_seed"]),
        ("base seed", sim["seed"]),
        ("runs in the metrics table", len(result.rows["seed"])),
    ]))
    parts.append("<h3>PD baseline tuning</h3>")
    parts.append(_pd_section(result, summary))
    return "".join(parts)


def _fuzzy_effort_range(summary: Sequence[Mapping[str, Any]]
                        ) -> tuple[float, float, float] | None:
    """The paper's fuzzy controllers' mean control effort in the ``paper`` experiment, V²·s:
    smallest and largest average over the trajectories (as the PD tuning averages), and the
    largest on any one trajectory (None if the summary has none)."""
    fuzzy = {k.value for k in _PAPER_FUZZY}
    per: dict[str, list[float]] = {}
    for r in summary:
        if (r.get("experiment") == "paper" and r.get("metric") == "effort"
                and str(r.get("kind")) in fuzzy):
            v = _num(r.get("mean"))
            if math.isfinite(v):
                per.setdefault(str(r.get("controller")), []).append(v)
    if not per:
        return None
    means = [sum(v) / len(v) for v in per.values()]
    return min(means), max(means), max(max(v) for v in per.values())


def _pd_section(result: StudyResult, summary: Sequence[Mapping[str, Any]]) -> str:
    rec = _plain(result.pd_tuning or {})
    cfg = result.config
    if cfg.pd is None or result.pd is None:
        return "<p>No PD baseline in this study.</p>"
    fuzzy = _fuzzy_effort_range(summary)
    compare = "" if fuzzy is None else (
        " For comparison, the fuzzy controllers' mean effort in the main experiment, averaged "
        f"over the trajectories in the same way, is {_e(_fmt(fuzzy[0], 3))}–"
        f"{_e(_fmt(fuzzy[1], 3))} V²·s (up to {_e(_fmt(fuzzy[2], 3))} V²·s on one trajectory).")
    if not rec.get("grid"):
        return (f"<p>Gains given in the configuration (no tuning): Kp = {_e(_fmt(rec.get('kp')))}"
                f", Kd = {_e(_fmt(rec.get('kd')))}.{compare}</p>")
    grid = [list(g) for g in rec["grid"]]
    kps = sorted({g[0] for g in grid})
    kds = sorted({g[1] for g in grid})
    limit = rec.get("effort_limit")
    effort = rec.get("effort")
    has_effort = all(len(g) >= 4 for g in grid)
    candidates = grid
    if has_effort and limit is not None:
        candidates = [g for g in grid if _num(g[3]) <= _num(limit)]
    best = sorted(candidates, key=lambda g: _num(g[2]))[:5]
    seeds = rec.get("seed_indices") or ["?", "?"]
    rule = rec.get("effort_limit_rule")
    why = (f"the {_e(rule)}" if rule and rule not in ("fixed", "none")
           else "comparable to the fuzzy controllers")
    constraint = "" if limit is None else (
        f", among the gains whose mean control effort ∫u² dt stays within "
        f"{_e(_fmt(limit))} V²·s ({why}; without a limit the ISE-optimal PD chatters between "
        "its voltage limits)")
    chosen_effort = "" if effort is None else f", mean effort {_e(_fmt(effort, 3))} V²·s"
    edge = "; on the edge of the grid (a wider grid might do better)" if rec.get(
        "on_grid_edge") else ""
    text = (
        f"<p>Grid search over {len(kps)} Kp values ({_e(_fmt(kps[0]))} … {_e(_fmt(kps[-1]))} "
        f"V/rad) × {len(kds)} Kd values ({_e(_fmt(kds[0]))} … {_e(_fmt(kds[-1]))} V·s/rad), "
        f"derivative filter Tf = {_e(_fmt(cfg.pd.tf))} s, minimising "
        f"{_e(rec.get('criterion', 'mean ISE'))} at σ = {_e(_fmt(rec.get('noise_std')))} rad on "
        f"{cfg.pd.seeds} tuning realisations (seed indices {_e(seeds[0])}–{_e(seeds[-1])}, "
        f"disjoint from the evaluation seeds){constraint}. Chosen: "
        f"Kp = {_e(_fmt(rec.get('kp')))}, Kd = {_e(_fmt(rec.get('kd')))}, objective "
        f"{_e(_fmt(rec.get('objective')))} rad²·s{chosen_effort}{edge}.{compare}</p>"
    )
    header = ["Kp (V/rad)", "Kd (V·s/rad)", "mean ISE (rad²·s)"]
    if has_effort:
        header.append("mean effort (V²·s)")
    best = [g[:len(header)] for g in best]
    caption = "<p>The best gains" + (" within the effort limit" if limit is not None
                                     and has_effort else "") + ":</p>"
    return text + caption + _table(header, [tuple(g) for g in best],
                                   numeric=[True] * len(header))


def _noise_item(result: StudyResult) -> str:
    cfg = result.config
    rate = cfg.loop.noise_rate
    paper_sigma = math.sqrt(PAPER_NOISE_POWER * PAPER_NOISE_RATE)
    text = (f"θ̂ = θ + n, n Gaussian with standard deviation σ, held for 1/{rate:g} s "
            f"(zero-order hold at {rate:g} Hz, the paper's 'frequency'); positions are measured "
            f"without noise. The paper's '{PAPER_NOISE_POWER:g} W, {PAPER_NOISE_RATE:g} Hz' read "
            "as Simulink band-limited white noise (σ = √(P/Ts) = √(P·f)) is "
            f"σ = √({PAPER_NOISE_POWER:g} × {PAPER_NOISE_RATE:g}) ≈ {paper_sigma:.3g} rad")
    if not math.isclose(rate, PAPER_NOISE_RATE):
        own = math.sqrt(PAPER_NOISE_POWER * rate)
        text += (f" (at this study's noise rate of {rate:g} Hz the same power would be "
                 f"σ ≈ {own:.3g} rad)")
    if paper_sigma > 1.0:
        text += (" — a heading error spread over the whole circle, which no controller "
                 "survives")
    return text + (f"; so the study states σ per figure (main: {cfg.noise_std:g} rad) and "
                   "sweeps it.")


def _speed_item(result: StudyResult) -> str:
    text = ("the controllers only steer (u is the differential voltage); the common-mode "
            "voltage V0 is the feed-forward for the reference speed, so nothing regulates the "
            "distance along the path: a robot that starts behind the reference point, or loses "
            "ground while turning, never catches up (the paper's scheme is the same).")
    notes = []
    for traj in result.config.trajectories:
        g = _gaps(result, traj)
        if g is None or g[0] < 0.05:
            continue
        start, lo, hi = g
        end = f"{lo:.2g} m" if math.isclose(lo, hi, rel_tol=0.05) else f"{lo:.2g}–{hi:.2g} m"
        t_end = float(result.traces[traj].t[-1])
        notes.append(f"the {traj} reference starts {start:.3g} m from the robot and the gap is "
                     f"still {end} at t = {t_end:g} s")
    if notes:
        text += " Here " + "; ".join(notes) + " (the heading errors measure steering only)."
    return text


def _pd_item(result: StudyResult) -> str:
    tuning = result.config.pd
    if tuning is None:
        return "none in this study."
    if tuning.kp is not None:
        return ("a PD heading controller with a filtered derivative, gains given in the "
                "configuration.")
    limit = getattr(tuning, "effort_limit", None)
    if getattr(tuning, "match_effort", False):
        constraint = (" among the gains whose mean control effort ∫u² dt is at most that of "
                      "the most active of the FLC and the IT2FLCs on the same tuning runs "
                      "(the ISE-optimal PD without this limit chatters between the voltage "
                      "limits, no fair comparison)")
    else:
        constraint = "" if limit is None else (
            f" among the gains whose mean control effort ∫u² dt stays within {limit:g} V²·s "
            "(the ISE-optimal PD without this limit chatters between the voltage limits, no "
            "fair comparison)")
    return ("a PD heading controller with a filtered derivative, tuned by a log-spaced grid "
            "search on Kp × Kd for the lowest mean ISE over the trajectories at the study's σ"
            f"{constraint}, on tuning seeds disjoint from the evaluation seeds.")


def _assumptions(result: StudyResult) -> str:
    cfg = result.config
    loop = cfg.loop
    robot, motor = loop.robot, loop.robot.motor
    v_lim = f"±{motor.voltage_limit:g} V"
    v_dc = motor.torque_constant / (motor.resistance * motor.friction
                                    + motor.torque_constant ** 2)
    track = (f"l = {robot.half_track:g} m, as printed in Table 3 (large for a small robot, "
             "possibly a misprint; kept as the default, configurable)."
             if math.isclose(robot.half_track, 5.6) else
             f"l = {robot.half_track:g} m (Table 3 prints 5.6 m, large for a small robot and "
             "possibly a misprint; this study sets its own value).")
    items = [
        ("FoU sets", "for FoU width w each set's sloped sides move by ±w/2: N upper "
         "[−1, −1, −0.2 + w/2], lower [−1, −1, −0.2 − w/2]; Z upper [−0.8 − w/2, 0, 0.8 + w/2], "
         "lower [−0.8 + w/2, 0, 0.8 − w/2]; P upper [0.2 − w/2, 1, 1], lower [0.2 + w/2, 1, 1]. "
         "This reproduces the paper's Table 1 (w = 0.2) and Table 4 (w = 0.1, 0.3) exactly; "
         "w = 0 is the paper's type-1 FLC."),
        ("Half wheel track", track),
        ("Motor model", "L di/dt = V − R i − K ω, J dω/dt = K i − b ω per wheel, discretised "
         "exactly (zero-order hold, matrix exponential): the electrical pole (≈ "
         f"{_electrical_pole(result):.3g} s⁻¹ for these parameters) makes a fixed-step explicit "
         "integrator inaccurate at the control period.".replace("≈ -", "≈ −")),
        ("Kinematics", "the standard differential-drive form v = r(ωR + ωL)/2, "
         "ω = r(ωR − ωL)/(2l) instead of the paper's misprinted eq. 9 matrix; the pose is "
         "integrated accurately to < 1e-6 m over 10 s against a tight ODE reference."),
        ("Desired heading", "θd = atan2(yd(t_k) − y_k, xd(t_k) − x_k) from the pose produced by "
         "the previous period (the paper's 'k − 1'); the paper's printed θd formulas for the "
         "curved and sinusoidal paths are inconsistent and are not used."),
        ("Heading noise", _noise_item(result)),
        ("Error wrapping", "e = wrap(θd − θ̂) to (−π, π] and, departing from DESIGN.md §5 "
         "(which writes Δe_k = e_k − e_{k−1}), Δe = wrap(e_k − e_{k−1}) to (−π, π] as well, "
         "Δe_0 = 0: the two differ only when e crosses ±π, where the unwrapped difference would "
         "be a spurious jump of about 2π. Controller inputs Ke·e and Kde·Δe "
         f"({_gains_text(result)}) clipped to the universe [−1, 1]."),
        ("Motor mixing", "the paper's Fig. 5 is not in the text; here V_R = V0 + u, "
         f"V_L = V0 − u, each saturated to {v_lim}, with the feed-forward V0 that makes the "
         "wheels turn at the reference speed |ṗd|/r in steady state (DC gain K/(Rb + K²) = "
         f"{v_dc:.4g} rad/s per V)."),
        ("Speed", _speed_item(result)),
        ("Integral criteria", "IAE, ITAE, ISE, ITSE of the true heading error θd − θ "
         "(also reported on the measured one), by the trapezoid rule over the control instants "
         f"t_k = k·{loop.ts:g} s, k = 0 … N; ITAE and ITSE weight sample k by t_k."),
        ("Common random numbers", "seed index i is the same noise realisation for every "
         "controller, trajectory and noise level, so controllers are compared pairwise "
         "(paired 95 % intervals of differences, win rates with ties counting ½); the "
         "time-series figures show one realisation (seed index "
         f"{cfg.figure_seed}), the statistics many."),
        ("PD baseline", _pd_item(result)),
        ("Dead-zone-matched baseline", "near the origin only the Z sets fire, so the FLC has a "
         "dead zone |e| < 0.2 (Δe small) and the IT2FLC one of 0.2 − w/2. The type-1 FLC built "
         "from the IT2FLC's upper MFs has the same dead zone; comparing against it separates the "
         "effect of the footprint from the effect of a narrower dead zone."),
        ("Claims", "each claim is tested at every noise level of the sweep, cell by cell "
         "(trajectory × criterion × comparison). A cell supports the claim when the 95 % "
         "interval of the paired difference lies on the claimed side of zero, contradicts it "
         "when it lies on the other side, and is inconclusive when it contains zero (e.g. exact "
         "ties). A level holds when every cell supports the claim and is contradicted when any "
         "cell contradicts it; otherwise the claim is not shown there. Verdicts: holds / does "
         "not hold / not shown / holds only for σ in …, with where it is contradicted or not "
         f"shown. C3 ('of order {C3_TARGET:g}') is read as within a factor "
         f"{'√10' if math.isclose(C3_FACTOR, math.sqrt(10.0)) else f'{C3_FACTOR:.3g}'} of "
         f"{C3_TARGET:g}."),
    ]
    body = "".join(f"<li><b>{_e(k)}.</b> {_e(v)}</li>" for k, v in items)
    return ('<h2 id="assumptions">Assumptions</h2><p>What DESIGN.md fixes where the paper is '
            'silent, ambiguous or misprinted, and where this study departs from DESIGN.md:</p>'
            f'<ul class="assumptions">{body}</ul>')


def _claim_attr(claim: Any, name: str, default: Any = "") -> Any:
    if isinstance(claim, Mapping):
        return claim.get(name, default)
    return getattr(claim, name, default)


def _claim_detail(claim: Any) -> str:
    """Where the claim is contradicted / not shown (``ClaimResult.detail``), unless the verdict
    already says it."""
    detail = str(_claim_attr(claim, "detail", "") or "").strip()
    return "" if not detail or detail in str(_claim_attr(claim, "verdict")) else detail


def _verdict_html(claim: Any) -> str:
    verdict = str(_claim_attr(claim, "verdict"))
    detail = _claim_detail(claim)
    extra = f' <span class="detail">({_e(detail)})</span>' if detail else ""
    return f"{_e(verdict)}{extra}"


def _glance(claims: Sequence[Any]) -> str:
    if not claims:
        return ""
    items = []
    for c in claims:
        verdict = str(_claim_attr(c, "verdict"))
        items.append(
            f'<li><b>{_e(_claim_attr(c, "id"))}</b> {_e(_claim_attr(c, "statement"))}: '
            f'<span class="verdict {_verdict_class(verdict)}">{_verdict_html(c)}</span></li>'
        )
    return (f'<div class="glance"><b>Verdicts at a glance</b> (details in '
            f'<a href="#claims">Claims</a>)<ul>{"".join(items)}</ul></div>')


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


def _evidence_table(evidence: Sequence[Mapping[str, Any]]) -> str:
    cols = [k for k in evidence[0] if k not in ("outcome", "passes")]
    first = evidence[0]
    numeric = [isinstance(first[k], float | int | np.floating | np.integer)
               and not isinstance(first[k], bool | np.bool_) for k in cols]
    has_outcome = "outcome" in first or "passes" in first
    header = [*cols, "outcome"] if has_outcome else cols
    out = ['<div class="scroll"><table><thead><tr>']
    out += [f"<th>{_e(h)}</th>" for h in header]
    out.append("</tr></thead><tbody>")
    for row in evidence:
        out.append("<tr>")
        for k, is_num in zip(cols, numeric, strict=True):
            cell = _e(_fmt(row.get(k, "")))
            out.append(f'<td class="num">{cell}</td>' if is_num else f"<td>{cell}</td>")
        if has_outcome:
            text, cls = _outcome(row)
            out.append(f'<td class="{cls}">{_e(text)}</td>')
        out.append("</tr>")
    out.append("</tbody></table></div>")
    return "".join(out)


def _claims_section(claims: Sequence[Any]) -> str:
    parts = ['<h2 id="claims">Claims</h2>']
    if not claims:
        return parts[0] + "<p>No claims were evaluated.</p>"
    parts.append('<div class="scroll"><table><thead><tr><th>id</th><th>statement</th>'
                 "<th>verdict</th><th>criterion</th></tr></thead><tbody>")
    for c in claims:
        verdict = str(_claim_attr(c, "verdict"))
        parts.append(
            f'<tr><td><b>{_e(_claim_attr(c, "id"))}</b></td>'
            f'<td>{_e(_claim_attr(c, "statement"))}</td>'
            f'<td class="verdict {_verdict_class(verdict)}">{_verdict_html(c)}</td>'
            f'<td>{_e(_claim_attr(c, "criterion"))}</td></tr>'
        )
    parts.append("</tbody></table></div>")
    parts.append("<p>Evidence outcome per cell: <b>supports</b> (the 95 % interval lies on the "
                 "claimed side of zero), <b>contradicts</b> (it lies on the other side), "
                 "<b>inconclusive</b> (it contains zero, e.g. exact ties). Win rates count ties "
                 "as ½.</p>")
    for c in claims:
        evidence = list(_claim_attr(c, "evidence", []) or [])
        if not evidence:
            continue
        parts.append(f"<details><summary>Evidence for {_e(_claim_attr(c, 'id'))} "
                     f"({len(evidence)} rows)</summary>")
        parts.append(_evidence_table(evidence))
        parts.append("</details>")
    return "".join(parts)


def _win_cell(row: Mapping[str, Any] | None) -> str:
    """A win rate (ties counting ½) with the share of ties, if any."""
    if row is None or row.get("win_rate") in ("", None):
        return ""
    text = _fmt(_num(row["win_rate"]), 3)
    ties = _num(row.get("ties"))
    if math.isfinite(ties) and ties > 0:
        text += f" (ties {ties:.0%})"
    return text


def _summary_section(result: StudyResult, summary: Sequence[Mapping[str, Any]]) -> str:
    rows = [r for r in summary if r.get("experiment") == "paper"]
    head = ('<h2 id="summary">Summary table</h2>')
    if not rows:
        return head + "<p>No rows of the <code>paper</code> experiment.</p>"
    index = {(r["trajectory"], r["controller"], r["metric"]): r for r in rows}
    sigma = _num(rows[0]["noise_std"])
    n = int(rows[0]["n"])
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
                cells.append("" if cell is None else f"{_fmt(cell['mean'])} "
                             f"[{_fmt(cell['ci_low'], 3)}, {_fmt(cell['ci_high'], 3)}]")
            cells.append(_win_cell(index.get((t, c, "ISE"))))
            body.append(cells)
    intro = (f"<p>The <code>paper</code> experiment: mean [95 % interval] over {n} noise "
             f"realisations at σ = {sigma:g} rad of the integral errors of the true heading "
             "error; win rate: fraction of realisations with a smaller ISE than the FLC on the "
             "same realisation, ties counting ½ (0.5: no difference; the share of exact ties "
             "is given where there are any). The full table (all experiments, more metrics) is "
             "<code>summary.csv</code>.</p>")
    return head + intro + _table(header, body,
                                 numeric=[False, False] + [True] * (len(INTEGRALS) + 1))


def _rerun_section(result: StudyResult, manifest: Mapping[str, Any], elapsed_s: float) -> str:
    command = str(manifest.get("command", "")) or "(command not recorded)"
    config_json = json.dumps(_plain(result.config.to_dict()), indent=2, ensure_ascii=False)
    parts = ['<h2 id="rerun">How to rerun</h2>',
             "<p>The command that produced this report:</p>",
             f"<pre>{_e(command)}</pre>",
             "<p>Its configuration (the whole study is a function of it; seeds included):</p>",
             f"<details><summary>configuration</summary><pre>{_e(config_json)}</pre></details>"]
    prov: list[tuple[str, Any]] = []
    for key in ("git_revision", "platform"):
        if key in manifest:
            prov.append((key.replace("_", " "), manifest[key]))
    versions = manifest.get("versions")
    if isinstance(versions, Mapping):
        prov += [(f"version: {k}", v) for k, v in versions.items()]
    for key, value in manifest.items():
        if key in ("command", "config", "versions", "git_revision", "platform", "elapsed_s"):
            continue
        prov.append((key, value if not isinstance(value, Mapping | list | tuple)
                     else json.dumps(_plain(value), ensure_ascii=False, default=str)))
    prov.append(("elapsed", f"{elapsed_s:.1f} s"))
    parts.append("<h3>Provenance</h3>" + _kv(prov))
    return "".join(parts)


def _figures_section(result: StudyResult, summary: Sequence[Mapping[str, Any]],
                     figures: Mapping[str, Path]) -> str:
    caps = figure_captions(result, summary)
    parts = ['<h2 id="results">Results</h2>']
    if not figures:
        parts.append("<p>No figures.</p>")
    for i, key in enumerate(_ordered_keys(figures, result), start=1):
        path = Path(figures[key])
        title, caption = caps.get(key, (key.replace("_", " "), ""))
        parts.append(
            f'<figure id="fig-{_e(key)}"><img src="{_data_uri(path)}" alt="{_e(title)}">'
            f"<figcaption><b>Figure {i}. {_e(title)}.</b> {_e(caption)} "
            f'<span class="file">[{_e(path.name)}]</span></figcaption></figure>'
        )
    return "".join(parts)


# ---------------------------------------------------------------------------------------------
# Entry points
# ---------------------------------------------------------------------------------------------


def render_html(
    *,
    result: StudyResult,
    summary: Sequence[Mapping[str, Any]],
    claims: Sequence[Any],
    manifest: Mapping[str, Any],
    figures: Mapping[str, Path],
    elapsed_s: float,
) -> str:
    """The report as one HTML string (see :func:`write_html`)."""
    cfg = result.config
    title = "it2track: interval type-2 fuzzy trajectory tracking with a noisy heading sensor"
    intro = (
        "<p>A reproduction and extension of <i>Trajectory Tracking Control Design for Mobile "
        "Robot Using Interval Type-2 Fuzzy Logic</i>: an interval type-2 fuzzy controller "
        "(IT2FLC) steers a differential-drive robot along a reference path while its heading "
        "sensor is noisy, compared with the ordinary type-1 FLC and across Footprint-of-"
        "Uncertainty (FoU) widths. Past the paper: many noise realisations with paired "
        "statistics, a noise-level sweep, a continuous FoU sweep and two fair baselines (a "
        "type-1 FLC with the IT2FLC's dead zone and a tuned PD controller).</p>"
    )
    sub = (f"Study run in {elapsed_s:.1f} s · {len(cfg.trajectories)} trajectories · "
           f"main noise level σ = {cfg.noise_std:g} rad · {cfg.seeds} realisations per cell")
    nav = ('<nav><ol><li><a href="#setup">Setup</a></li><li><a href="#assumptions">Assumptions'
           '</a></li><li><a href="#results">Results</a></li><li><a href="#claims">Claims</a>'
           '</li><li><a href="#summary">Summary table</a></li><li><a href="#rerun">How to rerun'
           "</a></li></ol></nav>")
    body = "".join([
        f"<h1>{_e(title)}</h1>",
        f'<p class="subtitle">{_e(sub)}</p>',
        intro,
        _glance(claims),
        nav,
        _setup_section(result, summary),
        _assumptions(result),
        _figures_section(result, summary, figures),
        _claims_section(claims),
        _summary_section(result, summary),
        _rerun_section(result, manifest, elapsed_s),
        "<footer>Self-contained page: figures embedded, no scripts, no network access. "
        "The figures also exist as PNG and SVG files next to this page.</footer>",
    ])
    return (
        "<!DOCTYPE html>\n"
        '<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>{_e(title)}</title>\n<style>{_CSS}</style>\n</head>\n"
        f"<body>\n<main>\n{body}\n</main>\n</body>\n</html>\n"
    )


def write_html(
    path: Path,
    *,
    result: StudyResult,
    summary: Sequence[Mapping[str, Any]],
    claims: Sequence[Any],
    manifest: Mapping[str, Any],
    figures: Mapping[str, Path],
    elapsed_s: float,
) -> Path:
    """Write the study's self-contained HTML report.

    Parameters
    ----------
    path : Path
        Destination (written atomically: a reader sees the old file or the whole new one).
    result : StudyResult
    summary : list of dict
        From :func:`it2track.experiments.analysis.summarise`.
    claims : list of ClaimResult
        From :func:`it2track.experiments.analysis.evaluate_claims`.
    manifest : dict
        Provenance; ``manifest["command"]`` is shown as the command to rerun.
    figures : dict of str -> Path
        From :func:`it2track.report.figures.write_figures`; each file is embedded as a base64
        data URI, so the page needs nothing else.
    elapsed_s : float
        Wall time of the run, s.

    Returns
    -------
    Path
        ``path``.
    """
    text = render_html(result=result, summary=summary, claims=claims, manifest=manifest,
                       figures=figures, elapsed_s=elapsed_s)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, text)
    return path

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
from ..experiments.analysis import INTEGRALS
from ..experiments.study import StudyResult
from .figures import INTEGRAL_UNITS, PAPER_FIGURE_NUMBER, slug

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
    v = verdict.strip().lower()
    if v == "holds":
        return "v-holds"
    if v.startswith("does not hold"):
        return "v-not"
    if v.startswith("holds only"):
        return "v-partial"
    return "v-na"


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
            "controller. (d) Rotational speed.",
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
    caps["control_surfaces"] = (
        "Control surfaces",
        "u(e, Δe) of each fuzzy controller over the input universe [−1, 1]² (Ke = Kde = 1, so "
        "the inputs are in rad), one colour scale for all (±12 V), contours at ±2, ±6, ±10 V. "
        "Top: the FLC and the IT2FLCs; bottom: the type-1 FLCs whose dead zone matches the "
        "IT2FLC above them. Dashed square: the dead zone, where only the Z×Z rule fires and "
        "u = 0.",
    )
    caps["dead_zone"] = (
        "The dead zone (why a wider FoU helps)",
        "The slice u(e, Δe = 0). Left: the whole universe; right: zoom with the dead-zone edges "
        "±(0.2 − w/2) dotted. The FLC does nothing while |e| < 0.2 rad (11.5°); an FoU of width "
        "w shrinks this to 0.2 − w/2 (DESIGN.md §3). Dashed: the type-1 FLCs with the same dead "
        "zones; just outside the dead zone they are steeper than the IT2FLCs, whose type-reduced "
        "output averages the lower and upper firing.",
    )
    caps["win_rates"] = (
        "Paired win rates",
        f"Fraction of the {n_paper} noise realisations at {sigma} in which each controller's "
        "error is smaller than the FLC's on the same realisation, per trajectory and criterion. "
        "0.5: no systematic difference; blue: better than the FLC; red: worse.",
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


def _controller_rows(result: StudyResult) -> list[tuple[str, str]]:
    rows = result.rows
    mask = rows["experiment"] == "paper"
    labels = rows["controller"][mask] if mask.any() else rows["controller"]
    kinds = rows["kind"][mask] if mask.any() else rows["kind"]
    fous = rows["fou"][mask] if mask.any() else rows["fou"]
    seen: dict[str, tuple[str, float]] = {}
    for lb, k, w in zip(labels, kinds, fous, strict=True):
        seen.setdefault(str(lb), (str(k), float(w)))
    out = []
    for lb, (kind, w) in seen.items():
        if kind == "flc":
            desc = ("the paper's type-1 FLC: sets N [−1 −1 −0.2], Z [−0.8 0 0.8], P [0.2 1 1] "
                    "on e and Δe, nine rules of Table 2 (±4, ±8, ±12 V), product t-norm")
        elif kind == "it2":
            desc = (f"interval type-2 FLC, FoU width w = {w:g}: every sloped side of the FLC's "
                    "sets widened by ±w/2 (upper/lower MF), same rules, exact type reduction "
                    "(KM-equivalent), u = (yl + yr)/2")
        elif kind == "t1-matched":
            desc = (f"fair baseline: type-1 FLC built from the upper MFs of the IT2FLC with "
                    f"w = {w:g}, so its dead zone (|e| < {0.2 - w / 2:g}) equals the IT2FLC's")
        elif kind == "pd":
            pd = result.pd
            gains = "" if pd is None else (
                f": u = clip(Kp·e + Kd·D, ±12 V), D the derivative of e through the filter "
                f"1/(Tf s + 1), Tf = {_fmt(pd.tf)} s; Kp = {_fmt(pd.kp)} V/rad, "
                f"Kd = {_fmt(pd.kd)} V·s/rad")
            desc = "PD heading controller baseline" + gains + " (tuning below)"
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
    parts.append(_pd_section(result))
    return "".join(parts)


def _pd_section(result: StudyResult) -> str:
    rec = _plain(result.pd_tuning or {})
    cfg = result.config
    if cfg.pd is None or result.pd is None:
        return "<p>No PD baseline in this study.</p>"
    if not rec.get("grid"):
        return (f"<p>Gains given in the configuration (no tuning): Kp = {_e(_fmt(rec.get('kp')))}"
                f", Kd = {_e(_fmt(rec.get('kd')))}.</p>")
    grid = rec["grid"]
    kps = sorted({g[0] for g in grid})
    kds = sorted({g[1] for g in grid})
    best = sorted(grid, key=lambda g: g[2])[:5]
    seeds = rec.get("seed_indices") or ["?", "?"]
    text = (
        f"<p>Grid search over {len(kps)} Kp values ({_e(_fmt(kps[0]))} … {_e(_fmt(kps[-1]))} "
        f"V/rad) × {len(kds)} Kd values ({_e(_fmt(kds[0]))} … {_e(_fmt(kds[-1]))} V·s/rad), "
        f"derivative filter Tf = {_e(_fmt(cfg.pd.tf))} s, minimising "
        f"{_e(rec.get('criterion', 'mean ISE'))} at σ = {_e(_fmt(rec.get('noise_std')))} rad on "
        f"{cfg.pd.seeds} tuning realisations (seed indices {_e(seeds[0])}–{_e(seeds[-1])}, "
        f"disjoint from the evaluation seeds). Chosen: Kp = {_e(_fmt(rec.get('kp')))}, "
        f"Kd = {_e(_fmt(rec.get('kd')))}, objective {_e(_fmt(rec.get('objective')))}"
        f"{'; on the edge of the grid' if rec.get('on_grid_edge') else ''}.</p>"
    )
    return text + _table(["Kp (V/rad)", "Kd (V·s/rad)", "objective (rad²·s)"],
                         [tuple(g) for g in best], numeric=[True] * 3)


def _assumptions(result: StudyResult) -> str:
    cfg = result.config
    loop = cfg.loop
    v_dc = loop.robot.motor.torque_constant / (
        loop.robot.motor.resistance * loop.robot.motor.friction
        + loop.robot.motor.torque_constant ** 2)
    items = [
        ("FoU sets", "for FoU width w each set's sloped sides move by ±w/2: N upper "
         "[−1, −1, −0.2 + w/2], lower [−1, −1, −0.2 − w/2]; Z upper [−0.8 − w/2, 0, 0.8 + w/2], "
         "lower [−0.8 + w/2, 0, 0.8 − w/2]; P upper [0.2 − w/2, 1, 1], lower [0.2 + w/2, 1, 1]. "
         "This reproduces the paper's Table 1 (w = 0.2) and Table 4 (w = 0.1, 0.3) exactly; "
         "w = 0 is the paper's type-1 FLC."),
        ("Half wheel track", f"l = {loop.robot.half_track:g} m, as printed in Table 3 (large for "
         "a small robot, possibly a misprint; kept as the default, configurable)."),
        ("Motor model", "L di/dt = V − R i − K ω, J dω/dt = K i − b ω per wheel, discretised "
         "exactly (zero-order hold, matrix exponential): the electrical pole (≈ −926 s⁻¹) "
         "makes a fixed-step explicit integrator inaccurate at the control period."),
        ("Kinematics", "the standard differential-drive form v = r(ωR + ωL)/2, "
         "ω = r(ωR − ωL)/(2l) instead of the paper's misprinted eq. 9 matrix; the pose is "
         "integrated accurately to < 1e-6 m over 10 s against a tight ODE reference."),
        ("Desired heading", "θd = atan2(yd(t_k) − y_k, xd(t_k) − x_k) from the pose produced by "
         "the previous period (the paper's 'k − 1'); the paper's printed θd formulas for the "
         "curved and sinusoidal paths are inconsistent and are not used."),
        ("Heading noise", f"θ̂ = θ + n, n Gaussian with standard deviation σ, held for "
         f"1/{loop.noise_rate:g} s (zero-order hold at {loop.noise_rate:g} Hz, the paper's "
         "'frequency'); positions are measured without noise. The paper's '0.1 W, 100 Hz' read as "
         "Simulink band-limited white noise (σ = √(P/Ts)) is σ ≈ 3.16 rad — a uniformly random "
         "heading that no controller survives — so the study states σ per figure "
         f"(main: {cfg.noise_std:g} rad) and sweeps it."),
        ("Error wrapping", "e = wrap(θd − θ̂) and Δe = wrap(e_k − e_{k−1}) to (−π, π], Δe_0 = 0; "
         "controller inputs Ke·e and Kde·Δe (Ke = Kde = 1) clipped to the universe [−1, 1]."),
        ("Motor mixing", "the paper's Fig. 5 is not in the text; here V_R = V0 + u, "
         "V_L = V0 − u, each saturated to ±12 V, with the feed-forward V0 that makes the wheels "
         f"turn at the reference speed |ṗd|/r in steady state (DC gain K/(Rb + K²) = "
         f"{v_dc:.4g} rad/s per V)."),
        ("Integral criteria", "IAE, ITAE, ISE, ITSE of the true heading error θd − θ "
         "(also reported on the measured one), by the trapezoid rule over the control instants "
         f"t_k = k·{loop.ts:g} s, k = 0 … N; ITAE and ITSE weight sample k by t_k."),
        ("Common random numbers", "seed index i is the same noise realisation for every "
         "controller, trajectory and noise level, so controllers are compared pairwise "
         "(paired 95 % intervals of differences, win rates); the time-series figures show one "
         f"realisation (seed index {cfg.figure_seed}), the statistics many."),
        ("PD baseline", "a PD heading controller with a filtered derivative, tuned by a "
         "log-spaced grid search on Kp × Kd minimising the mean ISE over the trajectories at the "
         "study's σ, on tuning seeds disjoint from the evaluation seeds."),
        ("Dead-zone-matched baseline", "near the origin only the Z sets fire, so the FLC has a "
         "dead zone |e| < 0.2 (Δe small) and the IT2FLC one of 0.2 − w/2. The type-1 FLC built "
         "from the IT2FLC's upper MFs has the same dead zone; comparing against it separates the "
         "effect of the footprint from the effect of a narrower dead zone."),
        ("Claims", "'holds' means the 95 % interval of the paired difference excludes zero in "
         "the stated direction for every trajectory and criterion; each claim is tested at "
         "every noise level of the sweep and reported as holds / does not hold / holds only for "
         "σ in …. C3 ('of order 0.003') is read as within a factor √10 of 0.003."),
    ]
    body = "".join(f"<li><b>{_e(k)}.</b> {_e(v)}</li>" for k, v in items)
    return ('<h2 id="assumptions">Assumptions</h2><p>What DESIGN.md fixes where the paper is '
            f'silent, ambiguous or misprinted:</p><ul class="assumptions">{body}</ul>')


def _claim_attr(claim: Any, name: str, default: Any = "") -> Any:
    if isinstance(claim, Mapping):
        return claim.get(name, default)
    return getattr(claim, name, default)


def _glance(claims: Sequence[Any]) -> str:
    if not claims:
        return ""
    items = []
    for c in claims:
        verdict = str(_claim_attr(c, "verdict"))
        items.append(
            f'<li><b>{_e(_claim_attr(c, "id"))}</b> {_e(_claim_attr(c, "statement"))}: '
            f'<span class="verdict {_verdict_class(verdict)}">{_e(verdict)}</span></li>'
        )
    return (f'<div class="glance"><b>Verdicts at a glance</b> (details in '
            f'<a href="#claims">Claims</a>)<ul>{"".join(items)}</ul></div>')


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
            f'<td class="verdict {_verdict_class(verdict)}">{_e(verdict)}</td>'
            f'<td>{_e(_claim_attr(c, "criterion"))}</td></tr>'
        )
    parts.append("</tbody></table></div>")
    for c in claims:
        evidence = list(_claim_attr(c, "evidence", []) or [])
        if not evidence:
            continue
        cols = list(evidence[0])
        numeric = [isinstance(evidence[0][k], float | int | np.floating | np.integer)
                   and not isinstance(evidence[0][k], bool | np.bool_) for k in cols]
        rows = [[r.get(k, "") for k in cols] for r in evidence]
        parts.append(f"<details><summary>Evidence for {_e(_claim_attr(c, 'id'))} "
                     f"({len(rows)} rows)</summary>")
        parts.append(_table(cols, rows, numeric=numeric))
        parts.append("</details>")
    return "".join(parts)


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
    header.append("ISE win rate vs FLC")
    body = []
    for t in trajs:
        for c in ctrls:
            cells: list[Any] = [t, c]
            for m in INTEGRALS:
                cell = index.get((t, c, m))
                cells.append("" if cell is None else f"{_fmt(cell['mean'])} "
                             f"[{_fmt(cell['ci_low'], 3)}, {_fmt(cell['ci_high'], 3)}]")
            ise = index.get((t, c, "ISE"))
            win = "" if ise is None or ise.get("win_rate") in ("", None) else _fmt(
                _num(ise["win_rate"]), 3)
            cells.append(win)
            body.append(cells)
    intro = (f"<p>The <code>paper</code> experiment: mean [95 % interval] over {n} noise "
             f"realisations at σ = {sigma:g} rad of the integral errors of the true heading "
             "error; win rate: fraction of realisations with a smaller ISE than the FLC on the "
             "same realisation. The full table (all experiments, more metrics) is "
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

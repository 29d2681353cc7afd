"""The page's setup section: the controllers, trajectories, robot, noise and Monte Carlo
settings, and how the PD baseline was tuned."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from markupsafe import Markup

from ...experiments.specs import ControllerKind, ControllerSpec
from ...experiments.study import StudyResult
from ...fuzzy import Reducer
from ..identity import controller_specs
from .env import fmt, num, plain, render
from .facts import _PAPER_FUZZY, _pd_limit

__all__ = ["pd_section", "setup_section"]

_TRAJECTORY_FORMULA = {
    "straight": "x_d = 2t, y_d = 0 (paper §III-A)",
    "curved": "x_d = 2t, y_d = 0.2t² − 4 (paper §III-B)",
    "sinusoidal": "x_d = 2t, y_d = 0.2 − 0.2 cos 2t (paper §III-C)",
}


def _fuzzy_options(spec: ControllerSpec | None) -> str:
    """t-norm, input gains and (IT2) reducer of a fuzzy controller's spec."""
    if spec is None:
        return ""
    out = [f"{spec.tnorm} t-norm"]
    if (spec.ke, spec.kde) != (1.0, 1.0):
        out.append(f"Ke = {spec.ke:g}, Kde = {spec.kde:g}")
    if spec.output_gain != 1.0:
        out.append(f"output gain {spec.output_gain:g} on the consequents")
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
    tuned = {s.label for s in result.tuned.values()}
    out = []
    for lb, (kind, w) in seen.items():
        spec = specs.get(lb)
        if spec is not None:
            kind = spec.kind.value
            w = spec.fou if spec.kind in (ControllerKind.IT2, ControllerKind.T1_MATCHED,
                                            ControllerKind.T1_SLOPE_MATCHED) else 0.0
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
        elif kind == ControllerKind.T1_SLOPE_MATCHED.value:
            desc = (f"fair baseline: type-1 FLC with the dead zone (|e| < {0.2 - w / 2:g}) and "
                    f"the slope just outside it of the IT2FLC with w = {w:g} (docs/model.md"
                    f"#fair-baselines){opts}")
        elif kind == ControllerKind.PD.value:
            pd = spec if spec is not None else result.pd
            gains = "" if pd is None else (
                f": u = clip(Kp·e + Kd·D, ±{fmt(_pd_limit(result))} V), D the derivative of e "
                f"through the filter 1/(Tf s + 1), Tf = {fmt(pd.tf)} s; Kp = {fmt(pd.kp)} "
                f"V/rad, Kd = {fmt(pd.kd)} V·s/rad")
            desc = "PD heading controller baseline" + gains + " (tuning below)"
        elif kind == ControllerKind.FILE.value and spec is not None:
            desc = f"user-supplied fuzzy system from {spec.path}{opts}"
        else:
            desc = f"user-supplied controller (kind {kind})"
        if lb in tuned:
            desc = ("tuned like the PD baseline (same tuning realisations, budget and effort "
                    "limit; see Fair baselines): " + desc.replace("the paper's ", "", 1))
        out.append((lb, desc))
    return out


def setup_section(result: StudyResult, summary: Sequence[Mapping[str, Any]]) -> Markup:
    """Controllers, trajectories, robot and motors, noise and Monte Carlo, PD tuning."""
    cfg = result.config
    d = plain(cfg.to_dict())
    sim, robot, study = d["simulation"], d["robot"], d["study"]
    motor = robot["motor"]
    trajectories = [(t, _TRAJECTORY_FORMULA.get(t, "user trajectory (waypoints)"))
                    for t in cfg.trajectories]
    robot_rows = [
        ("half wheel track l", f"{fmt(robot['half_track'])} m"),
        ("wheel radius r", f"{fmt(robot['wheel_radius'])} m"),
        ("armature resistance R", f"{fmt(motor['resistance'])} Ω"),
        ("armature inductance L", f"{fmt(motor['inductance'])} H"),
        ("rotor inertia J", f"{fmt(motor['inertia'])} kg·m²"),
        ("viscous friction b", f"{fmt(motor['friction'])} N·m·s"),
        ("motor constant K", f"{fmt(motor['torque_constant'])} N·m/A = V·s/rad"),
        ("voltage limit", f"±{fmt(motor['voltage_limit'])} V"),
    ]
    noise_rows = [
        ("heading noise of the main experiment and figures", f"σ = {fmt(study['noise_std'])} rad"),
        ("noise held (resampled) at", f"{fmt(sim['noise_rate'])} Hz"),
        ("noise-sweep levels σ", ", ".join(fmt(v) for v in study["noise_levels"]) + " rad"),
        ("FoU widths compared (paper)", ", ".join(fmt(v) for v in study["fous"])),
        ("main IT2FLC (paper Table 1)", f"FoU {fmt(study['main_fou'])}"),
        ("FoU sweep", f"{fmt(min(study['fou_sweep']))} … {fmt(max(study['fou_sweep']))} "
                      f"({len(study['fou_sweep'])} widths)"),
        ("realisations per cell, main experiment", study["seeds"]),
        ("realisations per cell, sweeps", study["sweep_seeds"]),
        ("seed index of the time-series figures", study["figure_seed"]),
        ("base seed", sim["seed"]),
        ("runs in the metrics table", len(result.rows["seed"])),
    ]
    return render(
        "sections/setup.html.j2",
        controllers=_controller_rows(result),
        trajectories=trajectories,
        duration=fmt(sim["duration"]),
        ts=fmt(sim["ts"]),
        start_pose=str(tuple(sim["start_pose"])),
        robot_rows=robot_rows,
        noise_rows=noise_rows,
        pd=pd_section(result, summary),
    )


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
            v = num(r.get("mean"))
            if math.isfinite(v):
                per.setdefault(str(r.get("controller")), []).append(v)
    if not per:
        return None
    means = [sum(v) / len(v) for v in per.values()]
    return min(means), max(means), max(max(v) for v in per.values())


def pd_section(result: StudyResult, summary: Sequence[Mapping[str, Any]]) -> Markup:
    """How the PD baseline got its gains: the grid, the objective, the effort limit, the best
    candidates (or the gains the configuration gave)."""
    rec = plain(result.pd_tuning or {})
    cfg = result.config
    if cfg.pd is None or result.pd is None:
        return render("sections/pd.html.j2", text="No PD baseline in this study.", best=None)
    fuzzy = _fuzzy_effort_range(summary)
    compare = "" if fuzzy is None else (
        " For comparison, the fuzzy controllers' mean effort in the main experiment, averaged "
        f"over the trajectories in the same way, is {fmt(fuzzy[0], 3)}–"
        f"{fmt(fuzzy[1], 3)} V²·s (up to {fmt(fuzzy[2], 3)} V²·s on one trajectory).")
    if not rec.get("grid"):
        return render("sections/pd.html.j2", best=None,
                      text=f"Gains given in the configuration (no tuning): "
                           f"Kp = {fmt(rec.get('kp'))}, Kd = {fmt(rec.get('kd'))}.{compare}")
    grid = [list(g) for g in rec["grid"]]
    kps = sorted({g[0] for g in grid})
    kds = sorted({g[1] for g in grid})
    limit = rec.get("effort_limit")
    effort = rec.get("effort")
    has_effort = all(len(g) >= 4 for g in grid)
    candidates = grid
    if has_effort and limit is not None:
        candidates = [g for g in grid if num(g[3]) <= num(limit)]
    best = sorted(candidates, key=lambda g: num(g[2]))[:5]
    seeds = rec.get("seed_indices") or ["?", "?"]
    rule = rec.get("effort_limit_rule")
    why = (f"the {rule}" if rule and rule not in ("fixed", "none")
           else "comparable to the fuzzy controllers")
    constraint = "" if limit is None else (
        f", among the gains whose mean control effort ∫u² dt stays within "
        f"{fmt(limit)} V²·s ({why}; without a limit the ISE-optimal PD chatters between "
        "its voltage limits)")
    chosen_effort = "" if effort is None else f", mean effort {fmt(effort, 3)} V²·s"
    edge = "; on the edge of the grid (a wider grid might do better)" if rec.get(
        "on_grid_edge") else ""
    text = (
        f"Grid search over {len(kps)} Kp values ({fmt(kps[0])} … {fmt(kps[-1])} "
        f"V/rad) × {len(kds)} Kd values ({fmt(kds[0])} … {fmt(kds[-1])} V·s/rad), "
        f"derivative filter Tf = {fmt(cfg.pd.tf)} s, minimising "
        f"{rec.get('criterion', 'mean ISE')} at σ = {fmt(rec.get('noise_std'))} rad on "
        f"{cfg.pd.seeds} tuning realisations (seed indices {seeds[0]}–{seeds[-1]}, "
        f"disjoint from the evaluation seeds){constraint}. Chosen: "
        f"Kp = {fmt(rec.get('kp'))}, Kd = {fmt(rec.get('kd'))}, objective "
        f"{fmt(rec.get('objective'))} rad²·s{chosen_effort}{edge}.{compare}"
    )
    header = ["Kp (V/rad)", "Kd (V·s/rad)", "mean ISE (rad²·s)"]
    if has_effort:
        header.append("mean effort (V²·s)")
    return render("sections/pd.html.j2", text=text, header=header,
                  best=[tuple(g[:len(header)]) for g in best],
                  within_limit=limit is not None and has_effort)

"""Titles and captions of the figures, and their order on the page."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ...experiments.specs import ControllerKind
from ...experiments.study import StudyResult
from ..counts import count_text, realisations_text
from ..identity import PAPER_FIGURE_NUMBER, slug, surface_limit
from .facts import _gains_text, _gap_sentence

__all__ = ["figure_captions"]


def _trace_noise(result: StudyResult) -> tuple[str, str]:
    """σ and seed index of the traced runs, from the runs themselves."""
    runs = [t.runs for t in result.traces.values()]
    sigmas = sorted({float(s) for r in runs for s in r.noise_std})
    seeds = sorted({int(s) for r in runs for s in r.seed})
    return (", ".join(f"{s:g}" for s in sigmas), ", ".join(str(s) for s in seeds))


def figure_captions(result: StudyResult, summary: Sequence[Mapping[str, Any]]
                    ) -> dict[str, tuple[str, str]]:
    """Figure key -> (title, caption) for the figures of :func:`~.figures.write_figures`."""
    cfg = result.config
    trace_sigma, trace_seed = _trace_noise(result)
    sigma = f"σ = {trace_sigma} rad"
    seed = f"noise realisation with seed index {trace_seed}"
    fous = ", ".join(f"{w:g}" for w in cfg.fous)
    n_paper, n_noise, n_fou = (realisations_text(summary, e) for e in ("paper", "noise", "fou"))
    paper_sigma = ", ".join(f"{s:g}" for s in sorted(
        {float(r["noise_std"]) for r in summary if r.get("experiment") == "paper"}))
    fou_sigma = ", ".join(f"{s:g}" for s in sorted(
        {float(r["noise_std"]) for r in summary if r.get("experiment") == "fou"}))
    by_need = ("" if "–" not in n_noise else " (more where a verdict needed them: "
               "docs/model.md#seeds-by-need)")
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
        f"realisations at σ = {paper_sigma} rad (the same realisations for every controller), "
        "with 95 % "
        "Student-t intervals of the mean. For each FoU width w the solid bar is the IT2FLC and "
        "the hatched bar the type-1 FLC with the same dead zone 0.2 − w/2; dotted red line: the "
        "FLC's mean. Bars too short to read carry their value.",
    )
    caps["noise_sweep"] = (
        "Noise-level sweep",
        f"The four integral errors against the heading-noise standard deviation σ (square-root "
        f"axis), mean and 95 % band over {n_noise} realisations per point{by_need}; σ = 0 is one "
        "noise-free run (no band). The dotted vertical marks the study's "
        f"σ = {cfg.noise_std:g} rad. Panels marked [log] use a log (or, where errors are "
        "exactly zero, symmetric-log) axis. On the straight line the robot starts on the path, "
        "so with σ below the dead zone a fuzzy controller never acts and its error is 0.",
    )
    caps["fou_sweep"] = (
        "FoU-width sweep: footprint vs dead zone",
        f"ISE and IAE against the FoU width w at σ = {fou_sigma} rad, mean and 95 % band over "
        f"{n_fou} "
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
        "Ke = 1); an FoU of width w shrinks this to 0.2 − w/2 (docs/model.md). Dashed: the "
        "type-1 FLCs with the same dead zones; just outside the dead zone they are steeper than "
        "the IT2FLCs, whose type-reduced output averages the lower and upper firing."
        + (" Dotted: the type-1 FLCs with the same dead zone and the same slope just outside "
           "it (docs/model.md#fair-baselines)." if any(
               s.kind is ControllerKind.T1_SLOPE_MATCHED for s in result.surface_specs.values())
           else ""),
    )
    caps["win_rates"] = (
        "Paired win rates",
        f"Per trajectory and criterion, over the {n_paper} noise realisations at "
        f"σ = {paper_sigma} rad: the "
        "fraction in which the controller's error is smaller than the FLC's on the same "
        "realisation, ties counting ½ (win rate = P(smaller) + ½ P(equal)). 0.5: no "
        "difference — including exact ties, e.g. when neither controller leaves its dead zone, "
        "which are not losses; blue: better than the FLC; red: worse. Cells with ties give "
        "their share.",
    )
    rob = result.robustness
    if rob is not None:
        levels = ", ".join(f"{s:g}" for s in rob.config.noise_levels)
        trajs = ", ".join(cfg.trajectories)
        caps["robustness"] = (
            "Robustness of the verdicts to the open modelling choices",
            "One row per variant: the paper-faithful baseline, each alternative of each open "
            "choice one at a time (docs/model.md), and the factorial cells (rows with ' x '). "
            f"One column per claim; each cell is split into the noise levels σ = {levels} rad "
            "(left to right) and coloured by the claim's status there: holds (green), "
            "contradicted (red, Holm-controlled), not shown (grey); white: not evaluated "
            "under that variant. A noise reading is judged at its own σ (one strip, its σ "
            "beside the row). Thick outline: the variant flips the claim beyond the baseline's "
            "spread over independent seed batches (a settled status the baseline never gave, "
            "whose opposite it did); dashed: it changes it beyond that spread (a settled status "
            "the baseline never gave). Left: all trajectories together, as "
            f"the verdicts; then each trajectory alone ({trajs}; C3 concerns the straight "
            f"line only). {count_text(int(c['n']) for c in rob.cells if float(c['sigma']) > 0)} "
            "realisations per cell; pale hatched strips: statuses whose replication probability "
            "is below the target (unsettled), which never count as a change.",
        )
        sens = rob.config.sensitivity
        if sens is not None and rob.sensitivity_ranking:
            caps["sensitivity"] = (
                "Global sensitivity of the key paired differences (Morris screening)",
                f"Morris elementary effects (SALib) over {len(sens.factors)} continuous "
                f"choices, {rob.sensitivity_points} design points ({sens.trajectories} Morris "
                f"trajectories, {sens.seeds} realisations per point). Outputs: the paired mean "
                "ISE differences IT2FLC − FLC and widest − narrowest FoU, per trajectory. "
                "(a) The factors ranked by the mean over outputs of μ* / max μ*. (b) μ* (mean "
                "absolute elementary effect) per output with its bootstrap 95 % interval.",
            )
    return caps


_FIGURE_ORDER_TAIL = ("fou_comparison", "integral_errors", "win_rates", "noise_sweep",
                      "fou_sweep", "control_surfaces", "dead_zone", "robustness", "sensitivity")


def _ordered_keys(figures: Mapping[str, Path], result: StudyResult) -> list[str]:
    preferred = [f"paper_{slug(t)}" for t in result.config.trajectories]
    preferred += list(_FIGURE_ORDER_TAIL)
    keys = [k for k in preferred if k in figures]
    keys += [k for k in figures if k not in keys]
    return keys


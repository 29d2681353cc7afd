"""The page's assumptions: what the study fixes where the paper is silent, ambiguous or
misprinted, formatted from the configuration, each citing docs/model.md (the repository's
document of every modelling decision, its alternatives and the verdicts that depend on it)."""

from __future__ import annotations

import math

from markupsafe import Markup

from ...experiments.analysis import C3_FACTOR, C3_TARGET
from ...experiments.study import StudyResult
from .env import render
from .facts import PAPER_NOISE_POWER, PAPER_NOISE_RATE, _electrical_pole, _gains_text, _gaps

__all__ = ["assumption_items", "assumptions_section"]


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


def assumption_items(result: StudyResult) -> list[tuple[str, str]]:
    """(topic, text) of every assumption the study makes where the paper is silent, ambiguous
    or misprinted, formatted from the configuration."""
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
        ("Error wrapping", "e = wrap(θd − θ̂) to (−π, π] and Δe = wrap(e_k − e_{k−1}) to "
         "(−π, π] as well, Δe_0 = 0 (docs/model.md, decisions not varied): the wrapped and the "
         "plain difference differ only when e crosses ±π, where the unwrapped difference would "
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
        ("Fair baselines", "near the origin only the Z sets fire, so the FLC has a dead "
         "zone |e| < 0.2 (Δe small) and the IT2FLC one of 0.2 − w/2. The type-1 FLC built from "
         "the IT2FLC's upper MFs has the same dead zone but is about twice as steep just outside "
         "it; the type-1 FLC matched in dead zone and slope separates the footprint's effect "
         "from both (docs/model.md#fair-baselines)."),
        ("Claims", "each claim is judged at every noise level of the sweep, cell by cell "
         "(trajectory × criterion × comparison), on paired differences over common noise "
         "realisations. A cell supports the claim when the 95 % interval lies on the claimed "
         "side of zero; a level holds when every cell supports it. A cell contradicts the claim "
         "when the one-sided paired test of the opposite direction rejects after "
         "Holm–Bonferroni over the claim's noisy cells. A noise-free level is one deterministic "
         "run per cell, reported as such and kept out of the verdicts. C3 ('of order "
         f"{C3_TARGET:g}') is symmetric: the interval inside the band within a factor "
         f"{'√10' if math.isclose(C3_FACTOR, math.sqrt(10.0)) else f'{C3_FACTOR:.3g}'} of "
         f"{C3_TARGET:g} supports it, wholly below or above contradicts it "
         "(docs/model.md#statistics)."),
    ]
    if result.robustness is not None:
        choices = "; ".join(f"{c.name}: {c.describe(c.default)} (docs/model.md#{c.doc})"
                            for c in result.robustness.config.choices)
        items.append(("Open modelling choices", "every choice the paper leaves open or "
                      "misprints is data (the [[choices]] of the study's configuration), here at "
                      f"its paper-faithful value: {choices}. The Robustness section shows "
                      "which verdicts each alternative leaves unchanged and which it flips."))
    return items


def assumptions_section(result: StudyResult) -> Markup:
    """The assumptions as a list (see :func:`assumption_items`)."""
    return render("sections/assumptions.html.j2", items=assumption_items(result))

"""Facts the page states, derived from the result (never hard-coded: the configuration can
change them): input gains, the motor's electrical pole, the PD limit, the start-up gap."""

from __future__ import annotations

import math

import numpy as np

from ...experiments.specs import ControllerKind, ControllerSpec
from ...experiments.study import StudyResult
from ...tracking import PDHeadingController
from ..identity import controller_specs

__all__ = ["PAPER_NOISE_POWER", "PAPER_NOISE_RATE"]

#: The paper's heading-noise power, W (read as Simulink band-limited white noise).
PAPER_NOISE_POWER = 0.1
#: The paper's noise rate, Hz.
PAPER_NOISE_RATE = 100.0
_PAPER_FUZZY = (ControllerKind.FLC, ControllerKind.IT2, ControllerKind.T1_MATCHED)


def _fuzzy_specs(result: StudyResult) -> list[ControllerSpec]:
    """The untuned fuzzy controllers (the tuned ones have their own gains by design)."""
    tuned = {s.label for s in result.tuned.values()}
    return [s for s in controller_specs(result).values()
            if s.kind is not ControllerKind.PD and s.label not in tuned]


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


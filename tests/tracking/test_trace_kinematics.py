"""The recorded speed series agree with the recorded pose: ``omega`` is the heading's rate of
change and ``v`` the path speed (finite differences of the trace, not the formulas that
produced the series), so a sign or scale slip in either is caught."""

from __future__ import annotations

import math

import numpy as np
import pytest

from it2track import heading_fls
from it2track.plant import RobotParams
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    PDHeadingController,
    RunTable,
    curved,
    simulate,
    sinusoidal,
)
from it2track.tracking.trajectories import FunctionTrajectory


def _circle(t):
    return np.stack([np.cos(2.0 * t), np.sin(2.0 * t), -2.0 * np.sin(2.0 * t),
                     2.0 * np.cos(2.0 * t)], axis=-1)


CASES = {
    # paper robot, IT2FLC, heading noise: slow turns (|omega| ~ 0.1 rad/s)
    "sinusoidal-noisy": (sinusoidal(), LoopConfig(duration=4.0), 0.1,
                         FuzzyHeadingController(fls=heading_fls(0.2))),
    # paper robot turning hard from a -pi/2 heading error, wheels saturated
    "curved": (curved(), LoopConfig(duration=2.0), 0.0,
               PDHeadingController(kp=10.0, kd=0.5, tf=0.02)),
    # a nimble robot (l = 0.3 m) turning round and circling (|omega| up to ~40 rad/s)
    "circle": (FunctionTrajectory("circle", _circle),
               LoopConfig(duration=2.0, robot=RobotParams(half_track=0.3),
                          start_pose=(1.0, 0.0, 1.5 * math.pi - 0.3)), 0.0,
               PDHeadingController(kp=10.0, kd=0.5, tf=0.02)),
}


@pytest.mark.parametrize("name", list(CASES))
def test_omega_is_the_rate_of_the_heading_and_v_the_path_speed(name: str) -> None:
    traj, config, sigma, ctrl = CASES[name]
    run = simulate([ctrl], [traj], RunTable(0, 0, sigma, 3), config).run(0)
    ts = config.ts
    # Over one period, theta_(k+1) - theta_k is the integral of omega: compare with the
    # trapezoid of the recorded omega at both ends (error O(ts^2) of the fast motor lag).
    rate = np.diff(run["theta"]) / ts
    omega = (run["omega"][1:] + run["omega"][:-1]) / 2.0
    scale = np.abs(run["omega"]).max()
    assert scale > 0.0
    assert np.abs(rate - omega).max() <= 0.05 * scale, (
        f"{name}: omega disagrees with d(theta)/dt by {np.abs(rate - omega).max():.3g} rad/s "
        f"(max |omega| {scale:.3g})"
    )
    assert np.corrcoef(rate, omega)[0, 1] > 0.99
    # The chord travelled in a period is the integral of v, up to the arc's curvature.
    speed = np.hypot(np.diff(run["x"]), np.diff(run["y"])) / ts
    v = (run["v"][1:] + run["v"][:-1]) / 2.0
    assert np.abs(speed - np.abs(v)).max() <= 0.05 * np.abs(run["v"]).max(), name

"""The batched closed loop against an independent, naive re-implementation.

The reference is written from DESIGN.md sec. 5 alone: one run, per-step Python with floats,
``math.atan2``, its own angle wrap (``math.remainder``), its own PD recursion and feed-forward,
and the plant advanced over each period by ``scipy.integrate.solve_ivp`` (rtol 1e-10) on
:func:`it2track.plant.continuous_rhs` with the voltages held. It shares no code with
:mod:`it2track.tracking.simulate` and none with the exact-ZOH plant step it relies on.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from it2track.plant import RobotParams, continuous_rhs
from it2track.tracking import (
    LoopConfig,
    PDHeadingController,
    RunTable,
    curved,
    simulate,
    sinusoidal,
)

KP, KD, TF = 10.0, 0.5, 0.02


def _wrap(a: float) -> float:
    w = math.remainder(a, 2.0 * math.pi)  # exact, in [-pi, pi]
    return math.pi if w <= -math.pi else w


def reference_loop(traj_fn, config: LoopConfig, *, control=None, noise=None,
                   start=None, previous_pose=False) -> dict[str, np.ndarray]:
    """Naive closed loop of one run: a PD heading controller (or ``control(e, de) -> u`` on
    Python floats) and heading noise ``noise[j]`` held for sample ``j = floor(t * rate)``.

    ``start`` overrides the start pose; ``previous_pose`` computes theta_d from the pose one
    period older (the paper's literal y(k - 1))."""
    robot: RobotParams = config.robot
    motor = robot.motor
    ts, n = config.ts, config.n_steps
    dc_gain = motor.torque_constant / (
        motor.resistance * motor.friction + motor.torque_constant**2
    )
    state = np.zeros(7)  # x, y, theta, i_R, omega_R, i_L, omega_L
    state[:3] = config.start_pose if start is None else start
    out = {name: np.empty(n + 1) for name in ("x", "y", "theta", "e", "u", "v_right", "v_left")}
    e_prev = 0.0
    older = (float(state[0]), float(state[1]))
    deriv = 0.0
    for k in range(n + 1):
        t = k * ts
        xr, yr, vx, vy = (float(v) for v in np.asarray(traj_fn(np.array([t])))[0])
        x, y, th = (float(v) for v in state[:3])
        px, py = older if previous_pose else (x, y)
        older = (x, y)
        theta_d = math.atan2(yr - py, xr - px)
        held = math.floor(k * ts * config.noise_rate + 1e-9)  # sample active at t_k
        measured = th if noise is None else th + float(noise[held])
        e = _wrap(theta_d - measured)
        de = _wrap(e - e_prev) if k else 0.0
        e_prev = e
        deriv = (TF * deriv + de) / (TF + ts)
        if control is None:
            u = min(max(KP * e + KD * deriv, -12.0), 12.0)
        else:
            u = control(e, de)
        v0 = math.hypot(vx, vy) / robot.wheel_radius / dc_gain
        lim = motor.voltage_limit
        v_r = min(max(v0 + u, -lim), lim)
        v_l = min(max(v0 - u, -lim), lim)
        for name, value in (("x", x), ("y", y), ("theta", th), ("e", e), ("u", u),
                            ("v_right", v_r), ("v_left", v_l)):  # fmt: skip
            out[name][k] = value
        if k < n:
            volts = np.array([v_r, v_l])
            sol = solve_ivp(
                lambda _t, s, volts=volts: continuous_rhs(s, volts, robot),
                (0.0, ts),
                state,
                method="DOP853",
                rtol=1e-10,
                atol=1e-12,
            )
            assert sol.success, f"solve_ivp failed at k={k}: {sol.message}"
            state = sol.y[:, -1].copy()
    return out


@pytest.mark.parametrize(
    ("traj_factory", "duration"),
    [(sinusoidal, 10.0), (curved, 4.0)],
    ids=["sinusoidal-10s", "curved-4s"],
)
def test_simulate_matches_naive_ode_loop(traj_factory, duration):
    # The curved case starts 4 m off the path with a -pi/2 heading error: large turns and
    # saturated wheel voltages during the first ~0.15 s.
    traj = traj_factory()
    config = LoopConfig(duration=duration)
    ctrl = PDHeadingController(kp=KP, kd=KD, tf=TF)
    trace = simulate([ctrl], [traj], RunTable(0, 0, 0.0, 0), config)
    ref = reference_loop(traj, config)
    got = trace.run(0)
    # Measured: positions and heading agree to ~4e-10 (m, rad), u and voltages to ~7e-9 V; the
    # bounds keep a factor ~20 of margin (the design asks for 1e-6 m on positions).
    for name, got_name, tol in (
        ("x", "x", 1e-8),
        ("y", "y", 1e-8),
        ("theta", "theta", 1e-8),
        ("e", "e_true", 1e-8),
        ("u", "u", 2e-7),
        ("v_right", "v_right", 2e-7),
        ("v_left", "v_left", 2e-7),
    ):
        err = np.abs(got[got_name] - ref[name])
        k = int(np.argmax(err))
        assert err[k] <= tol, (
            f"{traj.name}: {got_name} differs from the naive ODE loop by {err[k]:.3g} "
            f"(> {tol:g}) at t={got['t'][k]:.2f} s"
        )
    if traj.name == "curved":  # the case must really exercise saturation
        assert np.max(np.abs(ref["v_right"])) == 12.0 or np.max(np.abs(ref["v_left"])) == 12.0


def test_noisy_fuzzy_loop_matches_naive_ode_loop():
    # Heading noise (held at 50 Hz, half the control rate) and the IT2FLC, evaluated in the
    # reference through its scalar path on Python floats: checks the noise indexing and hold,
    # the common-random-number row, the measured error and the controller wiring.
    from it2track import heading_fls
    from it2track.plant import standard_noise
    from it2track.tracking import FuzzyHeadingController

    sigma, seed_index = 0.1, 7
    config = LoopConfig(duration=3.0, noise_rate=50.0, seed=3)
    fls = heading_fls(0.2)
    noise = sigma * standard_noise(3, [seed_index], 151)[0]
    traj = sinusoidal()
    trace = simulate([FuzzyHeadingController(fls=fls)], [traj],
                     RunTable(0, 0, sigma, seed_index), config)
    ref = reference_loop(traj, config, control=lambda e, de: fls(e, de), noise=noise)
    got = trace.run(0)
    for name, got_name, tol in (("x", "x", 1e-8), ("y", "y", 1e-8), ("theta", "theta", 1e-8),
                                ("e", "e_meas", 1e-8), ("u", "u", 1e-6)):
        err = np.abs(got[got_name] - ref[name])
        k = int(np.argmax(err))
        assert err[k] <= tol, f"{got_name} differs by {err[k]:.3g} at t={got['t'][k]:.2f} s"


def _circle(t):
    """Unit circle, counter-clockwise at 2 rad/s (2 m/s): the heading keeps turning."""
    return np.stack([np.cos(2.0 * t), np.sin(2.0 * t), -2.0 * np.sin(2.0 * t),
                     2.0 * np.cos(2.0 * t)], axis=-1)


def test_circling_past_pi_wraps_e_and_de_like_the_naive_loop():
    # A robot (l = 0.3 m) that starts on a circle facing nearly backwards and then circles:
    # the measured error starts near -pi and crosses +-pi while the robot turns round (de must
    # be wrapped there), and the unwrapped heading theta runs far past pi (e must be wrapped,
    # since theta_d = atan2(...) stays in (-pi, pi]). An implementation that skips either wrap
    # feeds the controller an error off by 2 pi and departs from the naive loop by volts.
    from it2track.tracking.trajectories import FunctionTrajectory

    traj = FunctionTrajectory("circle", _circle)
    start = (1.0, 0.0, math.pi / 2 + math.pi - 0.3)
    config = LoopConfig(duration=2.0, robot=RobotParams(half_track=0.3), start_pose=start)
    ctrl = PDHeadingController(kp=KP, kd=KD, tf=TF)
    got = simulate([ctrl], [traj], RunTable(0, 0, 0.0, 0), config).run(0)
    ref = reference_loop(traj, config)
    # The case exercises both wraps (checked on the independent reference):
    assert np.max(ref["theta"]) > math.pi + 1.0, "the heading never passed pi"
    assert np.any(np.abs(np.diff(ref["e"])) > math.pi), "e never crossed +-pi"
    assert np.all(np.abs(got["e_true"]) <= math.pi) and np.all(np.abs(got["de"]) <= math.pi)
    for name, got_name, tol in (("theta", "theta", 1e-7), ("e", "e_true", 1e-7),
                                ("u", "u", 1e-6), ("x", "x", 1e-7), ("y", "y", 1e-7)):
        err = np.abs(got[got_name] - ref[name])
        k = int(np.argmax(err))
        assert err[k] <= tol, (
            f"circle: {got_name} differs from the naive ODE loop by {err[k]:.3g} (> {tol:g}) "
            f"at t={got['t'][k]:.2f} s"
        )

"""The paper's heading loop built entirely in python-control equals it2track's closed loop.

Four discrete-time python-control systems at the control period, joined by ``interconnect``
and simulated with ``input_output_response``:

* ``drive`` -- the robot of DESIGN.md sec. 4 (two DC motors, unicycle kinematics), its update
  an ODE solution over the period with the voltages held (``solve_ivp``, tight tolerances);
  written here from the equations, not from it2track's plant;
* ``heading`` -- the desired heading ``atan2`` of the reference point minus the measured
  heading, wrapped, and its change (state: the previous error);
* ``flc`` -- the paper's IT2FLC, :func:`it2track.io.control.to_control`;
* ``mix`` -- ``V0 +- u`` saturated to +-12 V.

External inputs: the reference point and its feed-forward voltage from the paper's formulas,
and the heading noise. it2track's loop runs with 8 quadrature nodes per period: with the
default 4 its position integral differs from the ODE by ~3e-10 m over 10 s, which the loop's
gain turns into ~1e-7 V on the sinusoid; with 8 the plant agrees to ~1e-13 m.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate

ct = pytest.importorskip("control", reason="python-control is not installed (PyPI: control)")

from it2track.io.control import to_control  # noqa: E402
from it2track.paper import heading_fls  # noqa: E402
from it2track.plant import held_sample_index, standard_noise  # noqa: E402
from it2track.tracking import (  # noqa: E402
    FuzzyHeadingController,
    LoopConfig,
    RunTable,
    get_trajectory,
    simulate,
)

R, L, J, B, K = 5.0, 0.0054, 0.00015, 0.0001, 0.1  # paper Table 3
RW, HALF = 0.2, 5.6
TS, T = 0.01, 10.0


def robot_rhs(t, s, vr, vl):
    _x, _y, th, ir, wr, il, wl = s
    v, w = RW * (wr + wl) / 2, RW * (wr - wl) / (2 * HALF)
    return [v * math.cos(th), v * math.sin(th), w, (vr - R * ir - K * wr) / L,
            (K * ir - B * wr) / J, (vl - R * il - K * wl) / L, (K * il - B * wl) / J]


def drive_update(t, s, u, params):
    sol = scipy.integrate.solve_ivp(robot_rhs, (t, t + TS), s, args=(u[0], u[1]),
                                    method="DOP853", rtol=1e-12, atol=1e-13)
    return sol.y[:, -1]


def wrap(a: float) -> float:
    while a > math.pi:
        a -= 2 * math.pi
    while a <= -math.pi:
        a += 2 * math.pi
    return a


def heading_error(u) -> float:
    xd, yd, x, y, th, n = u
    return wrap(math.atan2(yd - y, xd - x) - (th + n))


def python_control_loop(fou: float):
    drive = ct.nlsys(drive_update, lambda t, s, u, p: s[:3], states=7,
                     inputs=["v_right", "v_left"], outputs=["x", "y", "theta"], dt=TS,
                     name="drive")
    heading = ct.nlsys(
        lambda t, s, u, p: np.array([heading_error(u), 1.0]),
        lambda t, s, u, p: np.array([heading_error(u),
                                     wrap(heading_error(u) - s[0]) if s[1] else 0.0]),
        states=2, inputs=["xd", "yd", "x", "y", "theta", "n"], outputs=["e", "de"], dt=TS,
        name="heading")
    flc = to_control(heading_fls(fou), TS, name="flc", outputs=["u"])
    mix = ct.nlsys(None, lambda t, s, u, p: np.clip([u[1] + u[0], u[1] - u[0]], -12.0, 12.0),
                   inputs=["u", "v0"], outputs=["v_right", "v_left"], dt=TS, name="mix")
    return ct.interconnect([drive, heading, flc, mix], inplist=["xd", "yd", "v0", "n"],
                           outlist=["x", "y", "theta", "u"], dt=TS)


PAPER_PATHS = {  # x_d, y_d, x_d', y_d' (paper sec. III)
    "straight": lambda t: (2 * t, 0 * t, 2 + 0 * t, 0 * t),
    "curved": lambda t: (2 * t, 0.2 * t * t - 4, 2 + 0 * t, 0.4 * t),
    "sinusoidal": lambda t: (2 * t, 0.2 - 0.2 * np.cos(2 * t), 2 + 0 * t, 0.4 * np.sin(2 * t)),
}


@pytest.mark.slow
@pytest.mark.parametrize(("path", "sigma"), [("straight", 0.0), ("curved", 0.0),
                                             ("sinusoidal", 0.0), ("straight", 0.05),
                                             ("sinusoidal", 0.05)])
def test_heading_loop_in_python_control_equals_it2track(path: str, sigma: float) -> None:
    fou, seed = 0.2, 3
    cfg = LoopConfig(duration=T, ts=TS, quadrature_nodes=8)
    t = cfg.times
    xd, yd, vx, vy = PAPER_PATHS[path](t)
    v0 = np.hypot(vx, vy) / (RW * K / (R * B + K * K))  # wheels at the reference speed
    hold = held_sample_index(t, cfg.noise_rate)
    noise = sigma * standard_noise(cfg.seed, [seed], int(hold[-1]) + 1)[0][hold]
    resp = ct.input_output_response(python_control_loop(fou), t, [xd, yd, v0, noise])

    trace = simulate([FuzzyHeadingController(fls=heading_fls(fou))], [get_trajectory(path)],
                     RunTable(0, 0, sigma, seed), cfg)
    np.testing.assert_array_equal(trace["theta_meas"][0] - trace["theta"][0] == 0.0,
                                  noise == 0.0)  # the same noise went in
    outputs = np.asarray(resp.outputs)
    for i, name in enumerate(("x", "y", "theta", "u")):
        diff = np.abs(outputs[i] - trace[name][0]).max()
        assert diff <= 1e-9, f"{path}, sigma={sigma}: {name} differs by {diff:.3g}"
    if path != "straight" or sigma:  # on the straight line without noise, e = u = 0
        assert np.abs(trace["u"][0]).max() > 1.0  # the controller acted

"""Fuzzy systems as python-control systems (io/control.py).

The nlsys must be the fuzzy system (same numbers on a grid, names from its variables), and a
loop built from it in python-control (``interconnect`` + ``input_output_response``) must equal
it2track's own closed loop: here a fuzzy PI speed loop on the paper's DC motor (the heading loop
of the robot is tests/tracking/test_python_control_loop.py).
"""

from __future__ import annotations

import numpy as np
import pytest

ct = pytest.importorskip("control", reason="python-control is not installed (PyPI: control)")

from it2track.fuzzy import Input, IT2Mamdani, IT2Set, Output, Rule, Triangle  # noqa: E402
from it2track.io.control import to_control  # noqa: E402
from it2track.paper import heading_fls  # noqa: E402
from it2track.plant.control import from_control  # noqa: E402
from it2track.tracking import (  # noqa: E402
    FuzzyHeadingController,
    IncrementalController,
    LoopConfig,
    StepReference,
    run_grid,
    simulate,
)


def test_the_nlsys_is_the_fuzzy_system_on_a_grid() -> None:
    fls = heading_fls(0.2)
    sys_ = to_control(fls, 0.01)
    assert sys_.dt == 0.01 and sys_.nstates == 0
    assert sys_.input_labels == ["e", "de"] and sys_.output_labels == list(fls.output_names)
    assert sys_.name == fls.name.replace(".", "_")  # python-control refuses '.' in names
    g = np.linspace(-1.5, 1.5, 31)  # beyond the universe too: clipped like the system
    e, de = (v.ravel() for v in np.meshgrid(g, g))
    resp = ct.input_output_response(sys_, np.arange(e.size) * 0.01, np.stack([e, de]))
    np.testing.assert_array_equal(np.asarray(resp.outputs).reshape(-1), fls(e, de))


def test_several_outputs_and_chosen_names() -> None:
    x = Input("x", (0, 1), [IT2Set(Triangle(0, 0, 1), Triangle(0, 0, 0.5), "lo"),
                            IT2Set(Triangle(0, 1, 1), Triangle(0.5, 1, 1), "hi")])
    y = Output("y", (0, 4), [IT2Set(Triangle(0, 0, 4), Triangle(0, 0, 2), "small"),
                             IT2Set(Triangle(0, 4, 4), Triangle(2, 4, 4), "big")])
    z = Output("z", (-1, 1), [IT2Set(Triangle(-1, -1, 0), Triangle(-1, -1, -0.5), "neg"),
                              IT2Set(Triangle(0, 1, 1), Triangle(0.5, 1, 1), "pos")])
    fls = IT2Mamdani(inputs=[x], outputs=[y, z], resolution=21,
                     rules=[Rule(["lo"], consequents=["small", "neg"]),
                            Rule(["hi"], consequents=["big", "pos"])])
    sys_ = to_control(fls, True, name="m", inputs=["a"], outputs=["p", "q"])
    assert sys_.isdtime(strict=True) and sys_.name == "m"
    assert sys_.input_labels == ["a"] and sys_.output_labels == ["p", "q"]
    pts = np.linspace(0.0, 1.0, 9)
    resp = ct.input_output_response(sys_, np.arange(9), pts[None, :])
    np.testing.assert_array_equal(resp.outputs.T, fls(pts))


def test_bad_arguments() -> None:
    fls = heading_fls(0.2)
    for dt in (0.0, -1.0, float("nan"), False, "0.01"):
        with pytest.raises(ValueError, match="must be a finite number > 0"):
            to_control(fls, dt)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="inputs=\\['e'\\] must be 2 distinct"):
        to_control(fls, 0.01, inputs=["e"])
    with pytest.raises(ValueError, match="outputs=\\['u', 'v'\\] must be 1 distinct"):
        to_control(fls, 0.01, outputs=["u", "v"])
    with pytest.raises(ValueError, match=r"name='a\.b' must be a non-empty string without"):
        to_control(fls, 0.01, name="a.b")
    with pytest.raises(ValueError, match="must be an it2track fuzzy system"):
        to_control(object(), 0.01)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"NaN or inf|finite"):
        to_control(fls, 0.01).output(0.0, [], [float("nan"), 0.0])


# --- a fuzzy PI speed loop on the paper's DC motor, built in python-control --------------------
R, L, J, B, K = 5.0, 0.0054, 0.00015, 0.0001, 0.1
TS, KE, KDE, GAIN, R_SPEED = 0.001, 1 / 20, 1 / 2, 0.2, 40.0


def python_control_speed_loop(motor_d, fou: float):
    """Error/difference block -> fuzzy nlsys -> incremental accumulator -> motor, closed."""
    def err_out(t, x, u, p):
        e = u[0] - u[1]  # r - omega
        de = e - x[0] if x[1] else 0.0
        return np.array([KE * e, KDE * de])

    def err_upd(t, x, u, p):
        return np.array([u[0] - u[1], 1.0])

    error = ct.nlsys(err_upd, err_out, states=2, inputs=["r", "omega"], outputs=["e", "de"],
                     dt=TS, name="error")
    flc = to_control(heading_fls(fou), TS, name="flc", outputs=["du"])

    def acc(t, x, u, p):
        return np.clip(x + GAIN * u[0], -12.0, 12.0)

    pi = ct.nlsys(lambda t, x, u, p: acc(t, x, u, p), lambda t, x, u, p: acc(t, x, u, p),
                  states=1, inputs=["du"], outputs=["V"], dt=TS, name="pi")
    return ct.interconnect([error, flc, pi, motor_d], inplist=["r"], outlist=["omega", "V"],
                           dt=TS)


@pytest.mark.parametrize("fou", [0.0, 0.2])
def test_fuzzy_pi_speed_loop_equals_it2tracks_reference_task(fou: float) -> None:
    motor = ct.ss([[-R / L, -K / L], [K / J, -B / J]], [[1 / L], [0.0]], [[0.0, 1.0]], 0.0,
                  inputs="V", outputs="omega", name="motor")
    loop = python_control_speed_loop(ct.c2d(motor, TS), fou)
    t = np.arange(301) * TS
    resp = ct.input_output_response(loop, t, np.full(t.size, R_SPEED))

    flc = FuzzyHeadingController(fls=heading_fls(fou), ke=KE, kde=KDE)
    ctrl = IncrementalController(inner=flc, gain=GAIN, u_min=-12.0, u_max=12.0)
    cfg = LoopConfig(duration=0.3, ts=TS, plant=from_control(motor))
    trace = simulate([ctrl], [StepReference(amplitude=R_SPEED)], run_grid(1, 1, [0.0], 1), cfg)
    omega, volts = trace["y"][0], trace["u"][0]
    assert np.abs(volts).max() == 12.0  # saturates at the start: the clip is exercised
    assert np.abs(resp.outputs[0] - omega).max() <= 1e-9 * R_SPEED
    assert np.abs(resp.outputs[1] - volts).max() <= 1e-9 * 12.0

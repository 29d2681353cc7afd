"""python-control systems as it2track plants (plant/control.py).

Differential tests: the paper's DC motor written in python-control from its equations (not from
it2track's ``MotorParams``) against it2track's exact motor; python-control's own ``c2d`` and
``forced_response`` against the adapter; a nonlinear system that is secretly linear, integrated
by the adapter, against the exact LTI solution.
"""

from __future__ import annotations

import math
import subprocess
import sys
import textwrap

import numpy as np
import pytest

ct = pytest.importorskip("control", reason="python-control is not installed (PyPI: control)")

from it2track.plant import MotorParams  # noqa: E402
from it2track.plant.base import check_plant  # noqa: E402
from it2track.plant.control import NonlinearPlant, NonlinearSpec, from_control  # noqa: E402
from it2track.plant.linear import LinearSpec  # noqa: E402

R, L, J, B, K = 5.0, 0.0054, 0.00015, 0.0001, 0.1  # paper Table 3, typed from the paper


def paper_motor_ss():
    """L di/dt = V - R i - K w ; J dw/dt = K i - b w ; outputs (i, w)."""
    return ct.ss([[-R / L, -K / L], [K / J, -B / J]], [[1 / L], [0.0]], np.eye(2),
                 np.zeros((2, 1)), inputs=["V"], outputs=["i", "omega"], states=["i", "omega"],
                 name="motor")  # fmt: skip


def drive(plant, u: np.ndarray) -> np.ndarray:
    state = plant.initial_state(u.shape[2])
    ys = [plant.outputs(state)]
    for k in range(u.shape[0]):
        state = plant.step(state, u[k], k * plant.ts)
        ys.append(plant.outputs(state))
    return np.stack(ys)


def it2track_motor(ts: float, volts: np.ndarray) -> np.ndarray:
    """(i, omega) at t_0..t_N by it2track's own exact motor, ``volts`` (N, B)."""
    ad, bd = MotorParams().discrete_matrices(ts)
    x = np.zeros((2, volts.shape[1]))
    out = [x]
    for v in volts:
        x = ad @ x + np.outer(bd, v)
        out.append(x)
    return np.stack(out)


@pytest.mark.parametrize("ts", [0.0005, 0.01])
def test_paper_motor_in_python_control_equals_it2tracks_motor(ts: float) -> None:
    spec = from_control(paper_motor_ss(), input_limits=[(-12.0, 12.0)])
    assert isinstance(spec, LinearSpec)
    assert spec.input_names == ("V",) and spec.output_names == ("i", "omega")
    plant = spec.build(ts=ts)
    check_plant(plant, ts)
    volts = np.random.default_rng(0).uniform(-12, 12, size=(300, 4))
    ours = drive(plant, volts[:, None, :])
    ref = it2track_motor(ts, volts)
    for row in range(2):
        scale = np.abs(ref[:, row]).max()
        assert np.abs(ours[:, row] - ref[:, row]).max() <= 1e-9 * scale


def test_python_controls_c2d_and_forced_response_agree() -> None:
    """python-control's own ZOH discretisation and simulation give it2track's motor too."""
    ts = 0.01
    disc = ct.c2d(paper_motor_ss(), ts, method="zoh")
    ad, bd = MotorParams().discrete_matrices(ts)
    np.testing.assert_allclose(disc.A, ad, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(disc.B[:, 0], bd, rtol=1e-9, atol=1e-12)
    t = np.arange(101) * ts
    volts = 12.0 * np.sign(np.sin(3 * t))
    resp = ct.forced_response(disc, t, volts)
    ref = it2track_motor(ts, volts[:-1, None])[:, :, 0]
    assert np.abs(resp.outputs[1] - ref[:, 1]).max() <= 1e-9 * np.abs(ref[:, 1]).max()
    # and the adapter given the discrete system (dt = ts) steps it as given
    plant = from_control(disc).build(ts=ts)
    ours = drive(plant, volts[:-1, None, None])[:, 1, 0]
    assert np.abs(ours - resp.outputs[1]).max() <= 1e-12 * np.abs(ref[:, 1]).max()


def test_transfer_function_motor() -> None:
    motor = ct.tf([K], [J * L, J * R + B * L, B * R + K * K], inputs="V", outputs="omega")
    spec = from_control(motor)
    assert spec.output_names == ("omega",) and spec.n_states == 2
    plant = spec.build(ts=0.01)
    volts = np.full((150, 1, 1), 6.0)
    ours = drive(plant, volts)[:, 0, 0]
    ref = it2track_motor(0.01, volts[:, 0])[:, 1, 0]
    assert np.abs(ours - ref).max() <= 1e-9 * np.abs(ref).max()
    assert ours[-1] == pytest.approx(6.0 * MotorParams().dc_gain, rel=1e-6)  # settled


def linear_motor_nlsys(dt: float = 0.0):
    a = np.array([[-R / L, -K / L], [K / J, -B / J]])
    bvec = np.array([1 / L, 0.0])
    if dt:
        disc = ct.c2d(paper_motor_ss(), dt)
        a, bvec = disc.A, disc.B[:, 0]
    return ct.nlsys(lambda t, x, u, p: a @ x + bvec * u[0], lambda t, x, u, p: x[1:],
                    states=2, inputs=["V"], outputs=["omega"], dt=dt, name="nlmotor")


def test_continuous_nlsys_is_integrated_with_the_input_held() -> None:
    """A nonlinear system that is the linear motor: solve_ivp per period equals exact ZOH."""
    spec = from_control(linear_motor_nlsys(), method="DOP853", rtol=1e-11, atol=1e-12)
    assert isinstance(spec, NonlinearSpec)
    plant = spec.build(ts=0.01)
    assert isinstance(plant, NonlinearPlant) and plant.continuous
    volts = np.random.default_rng(4).uniform(-12, 12, size=(60, 1, 2))
    ours = drive(plant, volts)[:, 0, :]
    ref = it2track_motor(0.01, volts[:, 0])[:, 1]
    assert np.abs(ours - ref).max() <= 1e-8 * np.abs(ref).max()


def test_discrete_nlsys_is_stepped_by_its_update() -> None:
    spec = from_control(linear_motor_nlsys(dt=0.01))
    plant = spec.build(ts=0.01)
    assert not plant.continuous
    volts = np.random.default_rng(5).uniform(-12, 12, size=(60, 1, 3))
    ours = drive(plant, volts)[:, 0, :]
    ref = it2track_motor(0.01, volts[:, 0])[:, 1]
    assert np.abs(ours - ref).max() <= 1e-9 * np.abs(ref).max()
    with pytest.raises(ValueError, match=r"discrete with dt=0\.01, but the loop's period is "
                                         r"ts=0\.02"):
        spec.build(ts=0.02)


def pendulum_rhs(t, x, u, params):
    g_over_l = params.get("g_over_l", 9.81)
    return np.array([x[1], -g_over_l * math.sin(x[0]) + u[0]])


def test_nonlinear_pendulum_conserves_energy_unforced_and_params_reach_it() -> None:
    """Unforced, undamped pendulum from 2 rad: the energy w^2/2 - (g/l) cos th stays."""
    sys_ = ct.nlsys(pendulum_rhs, None, states=["theta", "w"], inputs=["tau"],
                    outputs=["theta", "w"], name="pendulum", params={"g_over_l": 9.81})
    plant = from_control(sys_, x0=[2.0, 0.0], method="DOP853", rtol=1e-11,
                         atol=1e-12, params={"g_over_l": 4.0}).build(ts=0.05)
    y = drive(plant, np.zeros((100, 1, 1)))[:, :, 0]
    energy = 0.5 * y[:, 1] ** 2 - 4.0 * np.cos(y[:, 0])
    assert np.abs(energy - energy[0]).max() < 1e-8
    assert y[:, 0].min() == pytest.approx(-2.0, abs=2e-3)  # swings to the other side


def test_nonlinear_batch_independence() -> None:
    plant = from_control(linear_motor_nlsys()).build(ts=0.01)
    volts = np.random.default_rng(6).uniform(-12, 12, size=(10, 1, 5))
    together = drive(plant, volts)
    alone = drive(plant, volts[:, :, 3:4])
    np.testing.assert_array_equal(alone[:, :, 0], together[:, :, 3])


def test_bad_systems_and_options() -> None:
    with pytest.raises(ValueError, match="is not a python-control system"):
        from_control("motor")
    with pytest.raises(ValueError, match="static gain"):
        from_control(ct.tf([2.0], [1.0]))
    nl = linear_motor_nlsys()
    for kwargs, message in (({"method": "Euler"}, "method='Euler' must be one of"),
                            ({"rtol": 0.0}, "rtol=0.0 must be a finite number > 0"),
                            ({"x0": [1.0]}, r"x0=\[1.0\] must be 2 finite numbers"),
                            ({"input_limits": [(1.0, -1.0)]}, "low < high"),
                            ({"input_limits": [(0.0, 1.0), (0.0, 1.0)]}, r"per input \(1\)"),
                            ({"params": [1]}, "params=.* must be a mapping")):
        with pytest.raises(ValueError, match=message):
            from_control(nl, **kwargs)
    with pytest.raises(ValueError, match="must be a python-control NonlinearIOSystem"):
        NonlinearSpec(system=paper_motor_ss())


def test_records_describe_the_nonlinear_system() -> None:
    spec = from_control(linear_motor_nlsys(), input_limits=[(-12.0, 12.0)])
    d = spec.to_dict()
    assert d["kind"] == "nlsys" and d["name"] == "nlmotor" and d["inputs"] == ["V"]
    assert d["input_limits"] == [[-12.0, 12.0]] and d["states"] == ["x[0]", "x[1]"]


HIDDEN = textwrap.dedent("""
    import sys
    sys.modules["control"] = None  # as if python-control were not installed
    import it2track.plant.control as pc
    import it2track.io.control as ic
    from it2track.paper import heading_fls
    for call in (lambda: pc.from_control(object()), lambda: ic.to_control(heading_fls(0.2))):
        try:
            call()
        except ImportError as exc:
            print(type(exc).__name__, exc)
""")


def test_without_python_control_the_adapters_name_the_extra() -> None:
    proc = subprocess.run([sys.executable, "-c", HIDDEN], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.strip().splitlines()
    assert len(lines) == 2
    for line in lines:
        assert line.startswith("MissingExtraError ")
        assert "pip install 'it2track[control]'" in line

"""Linear plants (plant/linear.py): exact zero-order hold, output timing, configuration.

References: closed forms (first-order lag, double integrator), the paper's DC motor written
from its equations and compared with it2track's own motor (``MotorParams.discrete_matrices``),
and an ODE solver for a stiff third-order system.
"""

from __future__ import annotations

import json
import math
import pickle

import numpy as np
import pytest
import scipy.integrate

from it2track.plant import MotorParams
from it2track.plant.base import Plant, check_plant
from it2track.plant.linear import MAX_LTI_ORDER, LinearPlant, LinearSpec
from it2track.plant.specs import load_plant, plant_from_dict


def run(plant: LinearPlant, u: np.ndarray) -> np.ndarray:
    """Outputs at t_0 ... t_N for inputs u (n_steps, m, B) held over each period."""
    state = plant.initial_state(u.shape[2])
    ys = [plant.outputs(state)]
    for k in range(u.shape[0]):
        state = plant.step(state, u[k], k * plant.ts)
        ys.append(plant.outputs(state))
    return np.stack(ys)


def test_first_order_lag_step_is_exact() -> None:
    """1 / (tau s + 1), unit step: y(t_k) = 1 - exp(-t_k / tau) exactly (ZOH of a constant)."""
    tau, ts = 0.3, 0.05
    plant = LinearSpec(a=[[-1 / tau]], b=[[1 / tau]], c=[[1.0]]).build(ts=ts)
    assert isinstance(plant, Plant)
    y = run(plant, np.ones((40, 1, 1)))[:, 0, 0]
    t = np.arange(41) * ts
    np.testing.assert_allclose(y, 1 - np.exp(-t / tau), rtol=0, atol=2e-15)


def test_double_integrator_ramp_input() -> None:
    """x'' = u with u_k = k held: the ZOH discretisation is exact for piecewise-constant u."""
    ts = 0.1
    plant = LinearSpec(a=[[0, 1], [0, 0]], b=[[0], [1]], c=[[1, 0], [0, 1]]).build(ts=ts)
    np.testing.assert_allclose(plant.ad, [[1, ts], [0, 1]], atol=1e-15)
    np.testing.assert_allclose(plant.bd, [[ts * ts / 2], [ts]], atol=1e-15)
    u = np.arange(10.0).reshape(10, 1, 1)
    y = run(plant, u)
    pos, vel = 0.0, 0.0
    for k in range(10):
        pos += vel * ts + u[k, 0, 0] * ts * ts / 2
        vel += u[k, 0, 0] * ts
    assert y[-1, 0, 0] == pytest.approx(pos, rel=1e-14)
    assert y[-1, 1, 0] == pytest.approx(vel, rel=1e-14)


@pytest.mark.parametrize("ts", [0.001, 0.01, 0.1])
def test_paper_motor_as_transfer_function_equals_it2tracks_motor(ts: float) -> None:
    """omega(s)/V(s) = K / ((J s + b)(L s + R) + K^2) from the paper's equations; any input
    sequence gives it2track's own exact motor speeds to 1e-9 (relative)."""
    m = MotorParams()
    r, ind, j, b, k = 5.0, 0.0054, 0.00015, 0.0001, 0.1  # paper Table 3, typed independently
    spec = LinearSpec.from_tf([k], [j * ind, j * r + b * ind, b * r + k * k])
    plant = spec.build(ts=ts)
    rng = np.random.default_rng(1)
    u = rng.uniform(-12, 12, size=(200, 1, 3))
    y = run(plant, u)[:, 0, :]
    ad, bd = m.discrete_matrices(ts)
    x = np.zeros((2, 3))
    ref = [x[1].copy()]
    for kk in range(200):
        x = ad @ x + np.outer(bd, u[kk, 0])
        ref.append(x[1].copy())
    ref_arr = np.array(ref)
    scale = np.abs(ref_arr).max()
    assert np.abs(y - ref_arr).max() <= 1e-9 * scale


def test_stiff_system_matches_an_ode_solver() -> None:
    """A stiff 3-state system (poles -1, -50, -2000) under a held random input: the exact
    discretisation equals a tight Radau solution."""
    a = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [-1e5, -102050.0, -2051.0]])
    bvec = np.array([0.0, 0.0, 1e5])
    c = np.array([[1.0, 0.0, 0.0]])
    ts = 0.02
    plant = LinearSpec(a=a, b=bvec[:, None], c=c).build(ts=ts)
    rng = np.random.default_rng(2)
    u = rng.uniform(-1, 1, size=(8, 1, 1))
    y = run(plant, u)[:, 0, 0]
    x = np.zeros(3)
    for k in range(8):
        sol = scipy.integrate.solve_ivp(lambda t, s, v=u[k, 0, 0]: a @ s + bvec * v,
                                        (0, ts), x, method="Radau", jac=a, rtol=1e-12,
                                        atol=1e-14)
        x = sol.y[:, -1]
        assert y[k + 1] == pytest.approx(x[0], abs=1e-9)


def test_feedthrough_output_uses_the_previous_input() -> None:
    """y_k = C x_k + D u_(k-1): the output is read before the new input is applied."""
    plant = LinearSpec(a=[[-1.0]], b=[[1.0]], c=[[0.0]], d=[[2.0]]).build(ts=0.1)
    state = plant.initial_state(1)
    assert plant.outputs(state)[0, 0] == 0.0
    state = plant.step(state, np.array([[3.0]]), 0.0)
    assert plant.outputs(state)[0, 0] == 6.0


def test_x0_and_discrete_systems() -> None:
    spec = LinearSpec(a=[[0.5]], b=[[1.0]], c=[[1.0]], dt=0.1, x0=[4.0])
    plant = spec.build(ts=0.1)
    state = plant.initial_state(2)
    assert plant.outputs(state).tolist() == [[4.0, 4.0]]
    state = plant.step(state, np.array([[1.0, 2.0]]), 0.0)
    assert plant.outputs(state).tolist() == [[3.0, 4.0]]  # 0.5 * 4 + u, as given
    with pytest.raises(ValueError, match=r"discrete with dt=0\.1, but the loop's period is "
                                         r"ts=0\.2"):
        spec.build(ts=0.2)
    anyrate = LinearSpec(a=[[0.5]], b=[[1.0]], c=[[1.0]], dt=True)
    assert anyrate.build(ts=0.37).ad.tolist() == [[0.5]]


def test_steps_are_independent_of_the_batch() -> None:
    """Every run's bits are the same alone and inside a batch (no BLAS across runs)."""
    rng = np.random.default_rng(3)
    a = rng.normal(size=(6, 6)) - 3 * np.eye(6)
    spec = LinearSpec(a=a, b=rng.normal(size=(6, 2)), c=rng.normal(size=(3, 6)),
                      d=rng.normal(size=(3, 2)))
    plant = spec.build(ts=0.05)
    u = rng.normal(size=(30, 2, 33))
    together = run(plant, u)
    for r in (0, 17, 32):
        alone = run(plant, u[:, :, r:r + 1])
        np.testing.assert_array_equal(alone[:, :, 0], together[:, :, r])


def test_spec_roundtrips_through_its_table_and_pickle() -> None:
    spec = LinearSpec(a=[[-1.0, 2.0], [0.0, -3.0]], b=[[0.0], [1.0]], c=[[1.0, 0.0]],
                      input_limits=[(0.0, math.inf)], x0=[1.0, 2.0], output_names=["level"],
                      name="tank")
    table = spec.to_dict()
    assert table["input_limits"] == [[0.0, "inf"]]  # JSON has no infinity
    json.dumps(table, allow_nan=False)
    again = plant_from_dict(table)
    assert again == spec
    assert pickle.loads(pickle.dumps(spec)) == spec
    assert hash(again) == hash(spec)
    plant = spec.build(ts=0.1)
    check_plant(plant, 0.1)
    assert plant.input_limits == ((0.0, math.inf),)
    assert plant.output_names == ("level",) and plant.input_names == ("u",)


def test_transfer_function_table(tmp_path) -> None:
    path = tmp_path / "motor.toml"
    path.write_text('[plant]\nkind = "lti"\nnum = [0.1]\nden = [8.1e-7, 7.5e-4, 0.0105]\n'
                    'input_limits = [[-12.0, 12.0]]\noutput_names = ["omega"]\n')
    spec = load_plant(path)
    assert isinstance(spec, LinearSpec)
    assert spec.output_names == ("omega",) and spec.n_states == 2
    gain = -np.array(spec.c) @ np.linalg.solve(np.array(spec.a), np.array(spec.b))
    assert gain[0, 0] == pytest.approx(0.1 / 0.0105, rel=1e-12)  # DC gain num/den at s = 0
    bare = tmp_path / "bare.toml"
    bare.write_text('kind = "lti"\nA = [[-1.0]]\nB = [[1.0]]\nC = [[1.0]]\n')
    assert load_plant(bare) == LinearSpec(a=[[-1.0]], b=[[1.0]], c=[[1.0]])
    kin = tmp_path / "kin.toml"
    kin.write_text('[plant]\nkind = "kinematic"\n')
    assert load_plant(kin) is None


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0]]}, r"missing key\(s\) \['C'\]"),
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0]], "C": [[1.0]], "E": 1},
         r"unknown key\(s\) \['E'\]"),
        ({"kind": "lti", "num": [1.0]}, r"missing key\(s\) \['den'\]"),
        ({"kind": "lti", "num": [1.0, 2.0, 3.0], "den": [1.0, 1.0]}, "improper"),
        ({"kind": "lti", "num": [1.0], "den": [0.0, 1.0]}, "non-zero leading"),
        ({"kind": "lti", "A": [[1.0, 0.0]], "B": [[1.0]], "C": [[1.0]]}, "square"),
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0, 2.0]], "C": [[1.0]], "D": [[0.0]]},
         r"d has shape \(1, 1\), expected \(1, 2\)"),
        ({"kind": "lti", "A": [[float("nan")]], "B": [[1.0]], "C": [[1.0]]}, "finite"),
        ({"kind": "lti", "A": [["x"]], "B": [[1.0]], "C": [[1.0]]}, "real numbers"),
        ({"kind": "lti", "A": [[True]], "B": [[1.0]], "C": [[1.0]]}, "real numbers"),
        ({"kind": "lti", "A": "1", "B": [[1.0]], "C": [[1.0]]}, "matrix of numbers"),
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0]], "C": [[1.0]], "dt": -0.1}, "dt=-0.1"),
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0]], "C": [[1.0]], "dt": "fast"}, "dt='fast'"),
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0]], "C": [[1.0]],
          "input_limits": [[1.0, -1.0]]}, "low < high"),
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0]], "C": [[1.0]],
          "input_limits": [[-1.0, 1.0], [-1.0, 1.0]]}, "per input"),
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0]], "C": [[1.0]],
          "input_limits": [["-big", 1.0]]}, "low < high"),
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0]], "C": [[1.0]], "x0": [1.0, 2.0]},
         r"x0 has shape \(1, 2\)"),
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0]], "C": [[1.0]], "output_names": ["a", "b"]},
         "1 distinct"),
        ({"kind": "lti", "A": [[1.0]], "B": [[1.0]], "C": [[1.0]], "name": ""}, "name=''"),
        ({"kind": "lti", "A": [[0.0] * (MAX_LTI_ORDER + 1)] * (MAX_LTI_ORDER + 1),
          "B": [[1.0]], "C": [[1.0]]}, f"at most {MAX_LTI_ORDER}"),
        ({"kind": "kinematic", "A": 1}, "takes no other keys"),
        ({"kind": "nlsys"}, "is code and cannot be read from a file"),
        ({"kind": "pid"}, "kind='pid' must be one of"),
        ({}, "kind=None must be one of"),
    ],
)
def test_bad_tables_are_refused_naming_the_problem(table, message) -> None:
    with pytest.raises(ValueError, match=message) as info:
        plant_from_dict(table, where="cfg.toml [plant]")
    if table.get("kind") == "lti":
        assert str(info.value).startswith("cfg.toml [plant]: ")


def test_bad_plant_files(tmp_path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text("kind = \n")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_plant(bad)
    extra = tmp_path / "extra.toml"
    extra.write_text('seed = 1\n[plant]\nkind = "kinematic"\n')
    with pytest.raises(ValueError, match=r"unknown key\(s\) \['seed'\] beside \[plant\]"):
        load_plant(extra)
    with pytest.raises(ValueError, match=r"not a regular file|is a directory"):
        load_plant(tmp_path)


def test_unstable_beyond_float_range_is_refused() -> None:
    with pytest.raises(ValueError, match="overflows"):
        LinearSpec(a=[[1e6]], b=[[1.0]], c=[[1.0]]).build(ts=1.0)

"""Tests of it2track.plant.motor: exact ZOH motor vs an ODE solver, DC gain, poles."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp

from it2track.plant import MotorParams

TS = 0.01


def motor_ode(params: MotorParams, volts: float):
    """Right-hand side of L di/dt = V - R i - K w, J dw/dt = K i - b w, written out."""
    r, l_, j = params.resistance, params.inductance, params.inertia
    b, k = params.friction, params.torque_constant

    def rhs(_t, x):
        i, w = x
        return [(volts - r * i - k * w) / l_, (k * i - b * w) / j]

    return rhs


def ode_period(params: MotorParams, x0, volts: float, ts: float = TS) -> np.ndarray:
    sol = solve_ivp(motor_ode(params, volts), (0.0, ts), x0, method="Radau", rtol=1e-10, atol=1e-12)
    assert sol.success
    return sol.y[:, -1]


def test_state_matrices_by_hand():
    a, b = MotorParams().state_matrices()
    assert a.shape == (2, 2) and b.shape == (2,)
    # -R/L = -5/0.0054, -K/L = -0.1/0.0054, K/J = 0.1/0.00015, -b/J = -0.0001/0.00015
    assert_allclose(a, [[-925.925925925926, -18.518518518518519], [666.6666666666667, -2 / 3]])
    assert_allclose(b, [1 / 0.0054, 0.0])


@pytest.mark.parametrize(
    ("x0", "volts"),
    [((0.0, 0.0), 12.0), ((1.5, -40.0), -7.0), ((-2.0, 90.0), 3.3), ((0.3, 10.0), 0.0)],
)
def test_one_period_matches_ode(x0, volts):
    m = MotorParams()
    ad, bd = m.discrete_matrices(TS)
    assert ad.shape == (2, 2) and bd.shape == (2,)
    got = ad @ np.array(x0) + bd * volts
    ref = ode_period(m, x0, volts)
    assert_allclose(got, ref, rtol=1e-8, atol=1e-9)


def test_many_periods_piecewise_constant_voltage_match_ode():
    m = MotorParams()
    ad, bd = m.discrete_matrices(TS)
    rng = np.random.default_rng(20240601)
    volts = rng.uniform(-12.0, 12.0, 150)
    volts[40:70] = 12.0  # a stretch at the supply limit
    x_d = np.zeros(2)
    x_ref = np.zeros(2)
    for v in volts:
        x_d = ad @ x_d + bd * v
        x_ref = ode_period(m, x_ref, v)
        # currents ~ A, speeds ~ 100 rad/s: relative accuracy 1e-8 of the solver
        assert_allclose(x_d, x_ref, rtol=1e-8, atol=1e-8)


def test_dc_gain_closed_form_and_long_simulation():
    m = MotorParams()
    # Steady state: 0 = V - R i - K w and 0 = K i - b w  =>  i = b w / K,
    # V = (R b / K + K) w  =>  w / V = K / (R b + K^2) = 0.1 / 0.0105.
    assert m.dc_gain == pytest.approx(0.1 / 0.0105, rel=1e-15)
    volts = 7.0
    # slow pole ~ -14.2 /s: after 3 s the transient is ~ e^-42 of the step
    sol = solve_ivp(
        motor_ode(m, volts), (0.0, 3.0), [0.0, 0.0], method="Radau", rtol=1e-10, atol=1e-12
    )
    assert sol.y[1, -1] / volts == pytest.approx(m.dc_gain, rel=1e-8)
    ad, bd = m.discrete_matrices(TS)
    x = np.zeros(2)
    for _ in range(300):
        x = ad @ x + bd * volts
    assert x[1] / volts == pytest.approx(m.dc_gain, rel=1e-10)


def test_poles_of_table3_motor():
    m = MotorParams()
    a, _ = m.state_matrices()
    # Characteristic polynomial of A: s^2 + (R/L + b/J) s + (R b + K^2) / (L J) = 0, with
    # R/L + b/J = 925.926 + 0.667 = 926.593 and (R b + K^2)/(L J) = 0.0105 / 8.1e-7
    # = 12962.96, so s = (-926.593 +- sqrt(926.593^2 - 4 * 12962.96)) / 2
    #                 = (-926.593 +- 898.177) / 2 = -14.21 and -912.38 per second.
    tr = m.resistance / m.inductance + m.friction / m.inertia
    det = (m.resistance * m.friction + m.torque_constant**2) / (m.inductance * m.inertia)
    disc = math.sqrt(tr * tr - 4.0 * det)
    by_formula = sorted([(-tr - disc) / 2.0, (-tr + disc) / 2.0])
    eig = np.sort(np.linalg.eigvals(a).real)
    assert_allclose(eig, by_formula, rtol=1e-12)
    assert eig[0] == pytest.approx(-912.38, abs=0.01)
    assert eig[1] == pytest.approx(-14.21, abs=0.01)


def test_saturate_clips_and_keeps_shape():
    m = MotorParams(voltage_limit=12.0)
    v = np.array([[-30.0, -12.0, -11.9], [0.0, 12.0, 1e9]])
    before = v.copy()
    out = m.saturate(v)
    assert out.dtype == np.float64
    assert out.shape == v.shape
    assert_allclose(out, [[-12.0, -12.0, -11.9], [0.0, 12.0, 12.0]], rtol=0, atol=0)
    assert np.array_equal(v, before)  # input untouched
    assert MotorParams(voltage_limit=5.0).saturate(7).tolist() == 5.0
    assert m.saturate([-13, 13]).tolist() == [-12.0, 12.0]


FIELDS = [f.name for f in dataclasses.fields(MotorParams)]


@pytest.mark.parametrize("name", FIELDS)
@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, "1.0", True, None])
def test_bad_params_raise_naming_field(name, bad):
    with pytest.raises(ValueError, match=name) as info:
        MotorParams(**{name: bad})
    assert repr(bad) in str(info.value)


def test_params_are_frozen_keyword_only_and_coerced():
    m = MotorParams(resistance=4)
    assert isinstance(m.resistance, float) and m.resistance == 4.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.resistance = 3.0  # type: ignore[misc]
    with pytest.raises(TypeError):
        MotorParams(5.0)  # type: ignore[misc]
    assert dataclasses.replace(m, inertia=0.001).inertia == 0.001


@pytest.mark.parametrize("ts", [0.0, -0.01, math.nan, math.inf])
def test_discrete_matrices_rejects_bad_period(ts):
    with pytest.raises(ValueError, match="ts"):
        MotorParams().discrete_matrices(ts)

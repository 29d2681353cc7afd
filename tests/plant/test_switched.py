"""SwitchedDrive: the robot over a period whose voltages switch once (output latency).

References: DifferentialDrive built for the sub-period's length (its coefficients), the
drive's own step at the two ends of the period (bit for bit), and an ODE solution of the
continuous model with the voltage switched inside each period."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from it2track.plant import DifferentialDrive, MotorParams, RobotParams, continuous_rhs
from it2track.plant.switched import SwitchedDrive, sub_period_maps

TS = 0.01


def _coefficients(drive: DifferentialDrive) -> np.ndarray:
    out = [*drive._wheel, *drive._heading]
    for speed, heading in zip(drive._node_speed, drive._node_heading, strict=True):
        out += [*speed, *heading]
    return np.array(out)


@pytest.mark.parametrize("nodes", [1, 4, 9])
@pytest.mark.parametrize("robot", [RobotParams(), RobotParams(
    half_track=0.28, wheel_radius=0.05, motor=MotorParams(inductance=0.5, friction=0.01))],
    ids=["table3", "slow-motor"])
def test_maps_equal_a_drive_built_for_that_length(nodes, robot):
    drive = DifferentialDrive(robot, TS, quadrature_nodes=nodes)
    lengths = np.array([TS, 0.0073, 0.0031, 3.03125e-4, 6.25e-8])
    maps = sub_period_maps(drive, lengths)
    assert maps.shape == (5, 9 + 6 * nodes)
    for tau, row in zip(lengths, maps, strict=True):
        ref = _coefficients(DifferentialDrive(robot, float(tau), quadrature_nodes=nodes))
        np.testing.assert_allclose(row, ref, rtol=1e-12, atol=1e-15 * np.abs(ref).max(),
                                   err_msg=f"length {tau}")


def _batch(rng, b):
    pose = np.stack([rng.normal(0, 3, b), rng.normal(0, 3, b), rng.uniform(-7, 7, b)])
    wheels = np.stack([rng.normal(0, 1, b), rng.normal(0, 40, b), rng.normal(0, 1, b),
                       rng.normal(0, 40, b)])
    return pose, wheels, rng.uniform(-12, 12, (2, b)), rng.uniform(-12, 12, (2, b))


def test_the_ends_of_the_period_are_the_plain_step_bit_for_bit():
    drive = DifferentialDrive(RobotParams(), TS)
    switched = SwitchedDrive(drive)
    rng = np.random.default_rng(4)
    pose, wheels, before, after = _batch(rng, 6)
    switch = np.array([0.0, TS, 0.004, 0.0, TS, 1e-9])
    p, w = switched.step(pose, wheels, before, after, switch)
    pa, wa = drive.step(pose, wheels, after)
    pb, wb = drive.step(pose, wheels, before)
    for j in (0, 3):
        assert np.array_equal(p[:, j], pa[:, j]) and np.array_equal(w[:, j], wa[:, j])
    for j in (1, 4):
        assert np.array_equal(p[:, j], pb[:, j]) and np.array_equal(w[:, j], wb[:, j])
    for j in (2, 5):  # inside: neither
        assert not np.array_equal(w[:, j], wa[:, j]) and not np.array_equal(w[:, j], wb[:, j])
    # Each run's result is the same alone as in the batch.
    for j in range(6):
        pj, wj = switched.step(pose[:, j:j + 1], wheels[:, j:j + 1], before[:, j:j + 1],
                               after[:, j:j + 1], switch[j:j + 1])
        assert np.array_equal(pj[:, 0], p[:, j]) and np.array_equal(wj[:, 0], w[:, j])


def test_all_runs_at_the_ends_take_one_plain_step():
    drive = DifferentialDrive(RobotParams(), TS)
    pose, wheels, before, after = _batch(np.random.default_rng(5), 3)
    p, w = SwitchedDrive(drive).step(pose, wheels, before, after, np.array([0.0, 0.0, 0.0]))
    pa, wa = drive.step(pose, wheels, after)
    assert np.array_equal(p, pa) and np.array_equal(w, wa)


def _ode_period(state, v_before, v_after, switch, robot):
    for (a, b, v) in ((0.0, switch, v_before), (switch, TS, v_after)):
        if b > a:
            sol = solve_ivp(lambda _t, z, v=v: continuous_rhs(z, v, robot), (0.0, b - a), state,
                            method="DOP853", rtol=1e-11, atol=1e-13)
            assert sol.success
            state = sol.y[:, -1]
    return state


def test_switched_periods_follow_the_ode_reference():
    """60 periods of random voltages, each applied after a random latency (whole 16 MHz
    cycles, some periods at 0 and ts): pose and wheels against the continuous model."""
    robot = RobotParams()
    switched = SwitchedDrive(DifferentialDrive(robot, TS))
    rng = np.random.default_rng(11)
    n = 60
    volts = rng.uniform(-12, 12, (n + 1, 2))
    delay = rng.integers(0, 160_001, n) / 16e6
    delay[[3, 17]] = 0.0
    delay[[8, 40]] = TS
    pose, wheels = np.zeros((3, 1)), np.zeros((4, 1))
    state = np.zeros(7)
    for k in range(n):
        pose, wheels = switched.step(pose, wheels, volts[k][:, None], volts[k + 1][:, None],
                                     delay[k:k + 1])
        state = _ode_period(state, volts[k], volts[k + 1], delay[k], robot)
    np.testing.assert_allclose(pose[:, 0], state[:3], rtol=0, atol=1e-8)
    np.testing.assert_allclose(wheels[:, 0], state[3:], rtol=1e-9, atol=1e-9)
    # The switch matters: applying the new voltages at once ends elsewhere.
    plain = DifferentialDrive(robot, TS)
    p2, _ = np.zeros((3, 1)), np.zeros((4, 1))
    w2 = np.zeros((4, 1))
    for k in range(n):
        p2, w2 = plain.step(p2, w2, volts[k + 1][:, None])
    assert np.abs(p2[:, 0] - state[:3]).max() > 1e-4


@pytest.mark.parametrize("bad", [-1e-12, TS * (1 + 1e-12), np.nan, np.inf])
def test_a_switch_outside_the_period_is_refused(bad):
    switched = SwitchedDrive(DifferentialDrive(RobotParams(), TS))
    z = np.zeros((2, 2))
    with pytest.raises(ValueError, match=r"switch=.* must be in \[0, ts=0.01\]"):
        switched.step(np.zeros((3, 2)), np.zeros((4, 2)), z, z, np.array([0.0, bad]))


def test_shapes_are_checked():
    switched = SwitchedDrive(DifferentialDrive(RobotParams(), TS))
    z = np.zeros((2, 2))
    with pytest.raises(ValueError, match="v_before must have shape"):
        switched.step(np.zeros((3, 2)), np.zeros((4, 2)), np.zeros((2, 3)), z, np.zeros(2))
    with pytest.raises(ValueError, match="switch must have shape"):
        switched.step(np.zeros((3, 2)), np.zeros((4, 2)), z, z, np.zeros(3))
    with pytest.raises(ValueError, match="drive must be a DifferentialDrive"):
        SwitchedDrive("drive")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="lengths must be finite and > 0"):
        sub_period_maps(DifferentialDrive(RobotParams(), TS), [0.001, 0.0])


def test_pickles_and_keeps_stepping_the_same():
    switched = SwitchedDrive(DifferentialDrive(RobotParams(), TS))
    pose, wheels, before, after = _batch(np.random.default_rng(2), 2)
    d = np.array([0.002, 0.007])
    a = switched.step(pose, wheels, before, after, d)
    b = pickle.loads(pickle.dumps(switched)).step(pose, wheels, before, after, d)
    assert all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))

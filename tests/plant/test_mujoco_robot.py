"""The robot in MuJoCo: its motors against the exact motor, its reproducibility across threads
and batches, its geometry, and its slip."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from it2track.plant import MotorParams, RobotParams
from it2track.plant.base import check_robot_plant
from it2track.plant.mujoco_model import PhysicsParams
from it2track.plant.mujoco_plant import MujocoPlant, MujocoSpec
from it2track.plant.mujoco_robot import (
    MujocoRobot,
    PhysicsDivergedError,
    _advance_run,
    scheme_matrix,
    scheme_spectral_radius,
)

ROBOT = RobotParams()

pytest.importorskip(
    "mujoco", reason="needs the mujoco PyPI package: pip install 'it2track[mujoco]'")


def _bench_errors(robot: RobotParams, physics: PhysicsParams, periods: int = 200) -> float:
    """Largest wheel-speed error of the bench robot against the exact zero-order-hold motor
    (MotorParams with the wheel's spin inertia added to J), relative to the speed range."""
    bench = MujocoRobot(robot, physics, 0.01, bench=True)
    exact = MotorParams(**{**dataclasses.asdict(robot.motor),
                           "inertia": robot.motor.inertia + physics.wheel_inertia(robot)[0]})
    ad, bd = exact.discrete_matrices(0.01)
    rng = np.random.default_rng(7)
    volts = rng.uniform(-12.0, 12.0, size=(periods, 2))
    x = np.zeros((2, 2))  # (i, omega) x (right, left)
    err, span = 0.0, 0.0
    with bench.batch(np.zeros((3, 1)), threads=1) as runs:
        for v in volts:
            runs.step(v.reshape(2, 1))
            x = ad @ x + np.outer(bd, v)
            got = runs.wheels[[1, 3], 0]
            err = max(err, float(np.max(np.abs(got - x[1]))))
            span = max(span, float(np.max(np.abs(x[1]))))
            assert runs.pose[:, 0].tolist() == [0.0, 0.0, 0.0]  # the bench does not move
    return err / span


def test_motor_bench_matches_the_exact_motor():
    """Each wheel in the air is the paper's motor, J plus the wheel's spin inertia: the exact
    current integration per physics step leaves 2e-4 of the speed range (the rotor alone,
    the stiffest case) after 2 s of random voltages; dropping the back-emf's slope, using the
    step-end current or the step-start current as the torque would leave 1e-3 or more."""
    light = PhysicsParams(wheel_mass=1e-8)
    assert _bench_errors(ROBOT, light) < 5e-4
    assert _bench_errors(ROBOT, PhysicsParams()) < 3e-4  # with the wheel: slower, easier


def test_stability_check_models_the_scheme():
    """The 3x3 map behind the stability check is the scheme the robot runs: the bench's free
    decay at 0 V (MuJoCo's step included) follows the map step for step."""
    physics = PhysicsParams(wheel_mass=1e-8)
    bench = MujocoRobot(ROBOT, physics, 0.01, bench=True)
    data = bench._mujoco.MjData(bench.model)
    dof = bench.dofs[0]
    data.qvel[dof] = 50.0
    state = (1.5, 0.0, 0.0, 0.0)  # i_R = 1.5 A at 50 rad/s, no slope yet
    inertia = ROBOT.motor.inertia + physics.wheel_inertia(ROBOT)[0]
    step = scheme_matrix(ROBOT, inertia, bench.timestep)
    x = np.array([1.5, 50.0, 50.0])
    for _ in range(3):
        state = _advance_run(bench, data, 0.0, 0.0, state)
        x = np.linalg.matrix_power(step, bench.substeps) @ x
        got = np.array([state[0], float(data.qvel[dof]), float(data.qvel[dof]) - state[2]
                        * bench.timestep])
        np.testing.assert_allclose(got, x, rtol=1e-9, atol=1e-12)
    assert 0.0 < scheme_spectral_radius(ROBOT, inertia, bench.timestep) < 1.0
    # an absurdly light rotor against its back-emf is refused before anything runs
    tiny = RobotParams(motor=MotorParams(inertia=1e-9))
    assert scheme_spectral_radius(tiny, 1e-9, bench.timestep) > 1.0
    with pytest.raises(ValueError, match="max_timestep"):
        MujocoRobot(tiny, physics, 0.01)


def test_runs_are_bit_identical_whatever_the_threads_or_batch():
    robot = MujocoRobot(ROBOT, PhysicsParams(surface="wet"), 0.01)
    rng = np.random.default_rng(3)
    starts = np.vstack([rng.uniform(-1, 1, 5), rng.uniform(-1, 1, 5), rng.uniform(-3, 3, 5)])
    volts = rng.uniform(-12.0, 12.0, size=(30, 2, 5))
    results = []
    for threads, order in ((1, slice(None)), (3, slice(None)), (5, slice(None, None, -1))):
        with robot.batch(starts[:, order], threads=threads) as runs:
            for v in volts:
                runs.step(v[:, order])
            out = np.vstack([runs.pose, runs.wheels, *runs.body_velocity()])
            results.append(out[:, order])  # back to the original order
    alone = []
    for j in range(5):
        with robot.batch(starts[:, j:j + 1], threads=1) as runs:
            for v in volts:
                runs.step(v[:, j:j + 1])
            alone.append(np.vstack([runs.pose, runs.wheels, *runs.body_velocity()])[:, 0])
    for other in (*results[1:], np.array(alone).T):
        assert np.array_equal(results[0], other)  # all 64 bits


def test_start_pose_heading_and_turn_direction():
    robot = MujocoRobot(ROBOT, PhysicsParams(), 0.01)
    start = np.array([[1.0, -2.0], [2.0, 0.5], [0.7, -2.9]])
    with robot.batch(start, threads=1) as runs:
        assert np.array_equal(runs.pose, start)  # exactly where asked
        for _ in range(100):
            runs.step(np.full((2, 2), 6.0))  # equal voltages: straight ahead
        moved = runs.pose[:2] - start[:2]
        heading = np.arctan2(moved[1], moved[0])
        np.testing.assert_allclose(heading, start[2], atol=1e-6)
        np.testing.assert_allclose(runs.pose[2], start[2], atol=1e-6)
        assert np.all(np.hypot(*moved) > 1.0)
    with robot.batch(np.zeros((3, 1)), threads=1) as runs:
        for _ in range(50):
            runs.step(np.array([[8.0], [2.0]]))  # right wheel faster: turn left (theta grows)
        assert runs.pose[2, 0] > 0.01
        v, w = runs.body_velocity()
        assert w[0] > 0 and v[0] > 0


def test_heading_is_unwrapped_continuously():
    physics = PhysicsParams.no_slip_limit()
    robot = MujocoRobot(ROBOT, physics, 0.01)
    with robot.batch(np.array([[0.0], [0.0], [3.0]]), threads=1) as runs:
        for _ in range(300):
            runs.step(np.array([[12.0], [-12.0]]))  # spin on the spot, counter-clockwise
        assert runs.pose[2, 0] > 3.0 + 2 * math.pi  # more than a full turn, not wrapped


def test_wheels_slip_on_ice_not_in_the_no_slip_limit():
    """Full voltage from rest: in the no-slip limit the chassis moves at the wheels' rolling
    speed r omega; on ice the wheels spin far faster than the robot moves."""
    def slip(physics: PhysicsParams) -> float:
        robot = MujocoRobot(ROBOT, physics, 0.01)
        with robot.batch(np.zeros((3, 1)), threads=1) as runs:
            for _ in range(20):
                runs.step(np.full((2, 1), 12.0))
            rolling = ROBOT.wheel_radius * runs.wheels[1, 0]
            v, _ = runs.body_velocity()
            return float(1.0 - v[0] / rolling)
    assert abs(slip(PhysicsParams.no_slip_limit())) < 0.005
    assert slip(PhysicsParams(surface="icy")) > 0.5
    # the light default robot spins its wheels at full voltage even on dry ground, less so
    # than on wet ground
    assert 0.5 < slip(PhysicsParams(surface="dry")) < slip(PhysicsParams(surface="wet"))


@pytest.mark.parametrize("surface", ["dry", "icy"])
def test_spinning_wheels_do_not_launch_the_robot(surface):
    """Turning on the spot at full voltage, the light robot's wheels slip; MuJoCo's convex
    contact can only start sliding by moving apart, and with a rigid grip (friction time
    constant 2 ms) the robot hops by 19 cm. With the default tyre relaxation it stays on the
    ground within 5 mm (its axle at the end of every period)."""
    def rise(physics: PhysicsParams) -> float:
        robot = MujocoRobot(ROBOT, physics, 0.01)
        z0 = robot.rest_qpos[2]
        top = 0.0
        with robot.batch(np.zeros((3, 1)), threads=1) as runs:
            for _ in range(100):
                runs.step(np.array([[12.0], [-12.0]]))
                top = max(top, float(runs.data(0).qpos[2]) - z0)
        return top
    assert rise(PhysicsParams(surface=surface)) < 0.005
    assert rise(PhysicsParams(surface=surface, friction_timeconst=0.002)) > 0.05


def test_a_batch_that_would_not_fit_in_memory_is_refused(monkeypatch):
    from it2track._limits import ResourceLimitError

    robot = MujocoRobot(ROBOT, PhysicsParams(), 0.01)
    monkeypatch.setenv("IT2TRACK_MEMORY_LIMIT", "10M")
    with robot.batch(np.zeros((3, 100)), threads=1) as runs:  # ~9 MB
        assert runs.data(99).narena == 64 * 1024
    with pytest.raises(ResourceLimitError, match="a batch of 200 MuJoCo runs"):
        robot.batch(np.zeros((3, 200)))


def test_divergence_is_reported_naming_the_run():
    robot = MujocoRobot(ROBOT, PhysicsParams(), 0.01)
    with robot.batch(np.zeros((3, 2)), threads=1) as runs:
        with pytest.raises(PhysicsDivergedError, match="run 1"):
            for _ in range(5):
                runs.step(np.array([[1.0, 1e300], [1.0, -1e300]]))


def test_plant_protocol_and_input_checks():
    plant = MujocoSpec(physics=PhysicsParams(surface="icy")).build(ts=0.01, robot=ROBOT)
    assert isinstance(plant, MujocoPlant)
    check_robot_plant(plant, 0.01)
    assert plant.input_limits == ((-12.0, 12.0), (-12.0, 12.0))
    state = plant.initial_state(2, pose=np.array([[0.0, 1.0], [0.0, 0.0], [0.0, 0.5]]))
    y0 = plant.outputs(state)
    assert y0.shape == (7, 2) and np.array_equal(y0[:3], [[0.0, 1.0], [0.0, 0.0], [0.0, 0.5]])
    assert np.all(np.abs(y0[3:]) < 1e-6)  # at rest
    state = plant.step(state, np.full((2, 2), 6.0), 0.0)
    assert plant.outputs(state)[5].min() > 0.0
    for bad in (-1, 1.5, True):
        with pytest.raises(ValueError, match="n="):
            plant.initial_state(bad)
    with pytest.raises(ValueError, match="pose"):
        plant.initial_state(2, pose=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="finite"):
        plant.initial_state(1, pose=np.array([[0.0], [math.nan], [0.0]]))
    with pytest.raises(ValueError, match="volts"):
        state.step(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="finite"):
        state.step(np.array([[math.inf, 0.0], [0.0, 0.0]]))
    for bad in (0, 257, 2.0):
        with pytest.raises(ValueError, match="threads"):
            plant.mujoco_robot.batch(np.zeros((3, 1)), threads=bad)
    assert plant.initial_state(0).pose.shape == (3, 0)

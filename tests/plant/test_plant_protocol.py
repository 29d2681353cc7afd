"""The plant protocol (plant/base.py) and the kinematic robot as its first implementation.

The closed loop run through the protocol on the numpy engine (any plant that is not the
built-in kinematic one) must give the compiled engine's bits when the plant *is* the kinematic
robot in disguise: that pins the protocol's step/outputs contract (timing, rows, inputs held)
to the reference loop.
"""

from __future__ import annotations

import dataclasses
import pickle
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest

from it2track.paper import heading_fls
from it2track.plant import (
    DifferentialDrive,
    KinematicPlant,
    MotorParams,
    RobotParams,
    check_plant,
    check_robot_plant,
)
from it2track.plant.base import ROBOT_INPUTS, ROBOT_OUTPUTS, Plant, PlantSpec, RobotPlant
from it2track.tracking import (
    PAPER_TRAJECTORIES,
    FuzzyHeadingController,
    LoopConfig,
    PDHeadingController,
    RunTable,
    get_trajectory,
    run_grid,
    simulate,
    simulate_metrics,
)


class DisguisedRobot:
    """The kinematic robot behind the protocol, but not a KinematicPlant (so the loop cannot
    take the compiled path); optionally with a scaled motor voltage (a different plant)."""

    input_names = ROBOT_INPUTS
    output_names = ROBOT_OUTPUTS

    def __init__(self, robot: RobotParams, ts: float, gain: float = 1.0) -> None:
        self.inner = KinematicPlant(robot, ts)
        self.ts = ts
        self.input_limits = self.inner.input_limits
        self.gain = gain
        self.calls: list[float] = []

    def initial_state(self, n: int, pose: Any = None) -> Any:
        return self.inner.initial_state(n, pose)

    def step(self, state: Any, u: np.ndarray, t: float) -> Any:
        self.calls.append(t)
        return self.inner.step(state, u * self.gain if self.gain != 1.0 else u, t)

    def outputs(self, state: Any) -> np.ndarray:
        return self.inner.outputs(state)


@dataclass(frozen=True)
class DisguisedSpec:
    gain: float = 1.0
    kind: str = "disguised"

    def build(self, *, ts: float, robot: RobotParams) -> DisguisedRobot:
        return DisguisedRobot(robot, ts, self.gain)

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "gain": self.gain}


TRAJS = [get_trajectory(n) for n in PAPER_TRAJECTORIES]
CTRLS = [
    FuzzyHeadingController(fls=heading_fls(0.2)),
    PDHeadingController(kp=6.0, kd=0.2),
]


def test_kinematic_plant_is_the_drive_bit_for_bit() -> None:
    robot = RobotParams()
    plant = KinematicPlant(robot, 0.01)
    drive = DifferentialDrive(robot, 0.01)
    assert isinstance(plant, RobotPlant) and isinstance(plant, Plant)
    rng = np.random.default_rng(5)
    pose0 = rng.normal(size=(3, 6))
    state = plant.initial_state(6, pose=pose0)
    pose, wheels = pose0.copy(), np.zeros((4, 6))
    for k in range(50):
        volts = rng.uniform(-12, 12, size=(2, 6))
        state = plant.step(state, volts, k * 0.01)
        pose, wheels = drive.step(pose, wheels, volts)
    y = plant.outputs(state)
    assert y.shape == (7, 6)
    np.testing.assert_array_equal(y[:3], pose)
    np.testing.assert_array_equal(y[3], wheels[1])
    np.testing.assert_array_equal(y[4], wheels[3])
    r, half_track = robot.wheel_radius, robot.half_track
    np.testing.assert_allclose(y[5], r * (wheels[1] + wheels[3]) / 2, rtol=1e-15)
    np.testing.assert_allclose(y[6], r * (wheels[1] - wheels[3]) / (2 * half_track),
                               rtol=1e-15)
    assert plant.input_limits == ((-12.0, 12.0), (-12.0, 12.0))
    assert pickle.loads(pickle.dumps(plant)).outputs(state).tolist() == y.tolist()


def test_kinematic_plant_initial_state() -> None:
    plant = KinematicPlant(RobotParams(), 0.01)
    pose, wheels = plant.initial_state(3)
    assert pose.shape == (3, 3) and not pose.any() and wheels.shape == (4, 3) and not wheels.any()
    given = np.arange(6.0).reshape(3, 2)
    pose, _ = plant.initial_state(2, pose=given)
    pose[0, 0] = 99.0
    assert given[0, 0] == 0.0  # copied, not aliased
    for bad in (np.zeros((3, 3)), np.full((3, 2), np.nan)):
        with pytest.raises(ValueError, match="pose must be finite of shape"):
            plant.initial_state(2, pose=bad)
    with pytest.raises(ValueError, match="n=-1"):
        plant.initial_state(-1)
    with pytest.raises(ValueError, match="quadrature_nodes=0"):
        KinematicPlant(RobotParams(), 0.01, quadrature_nodes=0)


@pytest.mark.parametrize("record", [True, False])
def test_loop_through_the_protocol_equals_the_default_engine(record: bool) -> None:
    """Noise, both controllers, the three paths: every bit of every metric (and series)."""
    runs = run_grid(2, 3, [0.0, 0.1], [0, 3])
    base = LoopConfig(duration=2.0)
    via = dataclasses.replace(base, plant=DisguisedSpec())
    if record:
        a, b = simulate(CTRLS, TRAJS, runs, base), simulate(CTRLS, TRAJS, runs, via)
        assert set(a.series) == set(b.series)
        for name in a.series:
            np.testing.assert_array_equal(a.series[name], b.series[name], err_msg=name)
        ma, mb = a.metrics, b.metrics
    else:
        ma = simulate_metrics(CTRLS, TRAJS, runs, base, batch_size=5)
        mb = simulate_metrics(CTRLS, TRAJS, runs, via, batch_size=7)
    for name in ma:
        np.testing.assert_array_equal(ma[name], mb[name], err_msg=name)


def test_the_loop_steps_the_plant_once_per_period_at_t_k() -> None:
    spec = DisguisedSpec()
    plants: list[DisguisedRobot] = []

    @dataclass(frozen=True)
    class Recording(DisguisedSpec):
        def build(self, *, ts: float, robot: RobotParams) -> DisguisedRobot:
            plants.append(DisguisedRobot(robot, ts))
            return plants[-1]

    cfg = LoopConfig(duration=0.05, ts=0.01, plant=Recording())
    simulate(CTRLS[:1], TRAJS[:1], RunTable(0, 0, 0.0, 0), cfg)
    assert plants[0].calls == [k * 0.01 for k in range(5)]
    assert spec.to_dict()["kind"] == "disguised"


def test_a_different_plant_changes_the_results() -> None:
    runs = RunTable(0, 1, 0.0, 0)
    a = simulate_metrics(CTRLS, TRAJS, runs, LoopConfig(duration=2.0))
    b = simulate_metrics(CTRLS, TRAJS, runs,
                         LoopConfig(duration=2.0, plant=DisguisedSpec(gain=0.5)))
    assert a["pos_rms"][0] < b["pos_rms"][0]  # half the voltage: the robot falls behind


def test_loopconfig_plant_field() -> None:
    assert "plant" not in LoopConfig().to_dict()  # unchanged tables for the default robot
    cfg = LoopConfig(plant=DisguisedSpec(gain=2.0))
    assert cfg.to_dict()["plant"] == {"kind": "disguised", "gain": 2.0}
    assert isinstance(DisguisedSpec(), PlantSpec)
    for bad in ("kinematic", 3, KinematicPlant(RobotParams(), 0.01)):
        with pytest.raises(ValueError, match=r"LoopConfig\.plant=.* must be a PlantSpec"):
            LoopConfig(plant=bad)  # type: ignore[arg-type]


class _Bare:
    ts = 0.01
    input_names = ("u",)
    output_names = ("y",)
    input_limits = ((-1.0, 1.0),)

    def initial_state(self, n: int) -> Any:
        return np.zeros((1, n))

    def step(self, state: Any, u: np.ndarray, t: float) -> Any:
        return state + u

    def outputs(self, state: Any) -> np.ndarray:
        return state


def _bare(**attrs: Any) -> _Bare:
    p = _Bare()
    for k, v in attrs.items():
        setattr(p, k, v)
    return p


def test_check_plant_accepts_a_minimal_plant_and_names_what_is_wrong() -> None:
    assert check_plant(_bare(), 0.01) is not None
    every = "ts, input_names, output_names, input_limits, initial_state, step, outputs"
    with pytest.raises(ValueError, match=f"lacks {every}$"):
        check_plant(object(), 0.01)
    cases = [
        (dict(input_names=()), "input_names"),
        (dict(input_names=["u"]), "input_names"),
        (dict(output_names=("y", "y")), "output_names"),
        (dict(output_names=("",)), "output_names"),
        (dict(input_limits=((1.0, 1.0),)), "input_limits"),  # low == high
        (dict(input_limits=((float("nan"), 1.0),)), "input_limits"),
        (dict(input_limits=((-1.0, 1.0), (-1.0, 1.0))), "input_limits"),  # 2 pairs, 1 input
        (dict(input_limits=((True, 2.0),)), "input_limits"),
        (dict(ts=0.02), "differs from the loop's control period"),
    ]
    for attrs, message in cases:
        with pytest.raises(ValueError, match=message):
            check_plant(_bare(**attrs), 0.01, what="P")


def test_check_robot_plant_requires_the_robot_names() -> None:
    check_robot_plant(KinematicPlant(RobotParams(), 0.01), 0.01)
    with pytest.raises(ValueError, match="needs a robot plant"):
        check_robot_plant(_bare(), 0.01)


def test_heading_task_refuses_a_plant_that_is_not_a_robot() -> None:
    @dataclass(frozen=True)
    class BareSpec:
        kind: str = "bare"

        def build(self, *, ts: float, robot: RobotParams) -> _Bare:
            return _bare(ts=ts)

        def to_dict(self) -> dict[str, Any]:
            return {"kind": self.kind}

    cfg = LoopConfig(duration=0.1, plant=BareSpec())
    with pytest.raises(ValueError, match=r"LoopConfig\.plant \('bare'\) has inputs"):
        simulate(CTRLS[:1], TRAJS[:1], RunTable(0, 0, 0.0, 0), cfg)


def test_heading_task_refuses_asymmetric_or_unequal_wheel_limits() -> None:
    @dataclass(frozen=True)
    class Lopsided(DisguisedSpec):
        def build(self, *, ts: float, robot: RobotParams) -> DisguisedRobot:
            p = DisguisedRobot(robot, ts)
            p.input_limits = ((-12.0, 12.0), (-6.0, 12.0))
            return p

    cfg = LoopConfig(duration=0.1, plant=Lopsided())
    with pytest.raises(ValueError, match="same symmetric"):
        simulate(CTRLS[:1], TRAJS[:1], RunTable(0, 0, 0.0, 0), cfg)


def test_robot_plant_voltage_limit_comes_from_the_plant() -> None:
    """A robot with a 6 V supply saturates at 6 V in the loop (the plant's input_limits)."""
    robot = RobotParams(motor=MotorParams(voltage_limit=6.0))
    cfg = LoopConfig(duration=0.5, robot=robot, plant=DisguisedSpec())
    trace = simulate(CTRLS[:1], TRAJS, RunTable(0, 1, 0.0, 0), cfg)  # curved: turns hard
    assert trace["v_left"].max() == 6.0 and trace["v_right"].min() == -6.0
    assert trace.metrics["sat_time"][0] > 0.0

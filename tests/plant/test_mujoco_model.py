"""The physical robot's parameters and MJCF text (no MuJoCo needed: the model is plain text)."""

from __future__ import annotations

import dataclasses
import math
import pickle
import sys
import xml.etree.ElementTree as ET

import pytest

from it2track._extras import MissingExtraError
from it2track.plant import MotorParams, RobotParams
from it2track.plant.mujoco_model import (
    GRAVITY,
    MAX_MU,
    SURFACES,
    PhysicsParams,
    Surface,
    robot_mjcf,
    substeps_per_period,
)
from it2track.plant.mujoco_plant import MujocoSpec
from it2track.plant.mujoco_robot import import_mujoco
from it2track.plant.specs import plant_from_dict
from it2track.tracking import LoopConfig


def _floats(text: str) -> list[float]:
    return [float(v) for v in text.split()]


def _parse(robot: RobotParams, physics: PhysicsParams, timestep: float = 0.001,
           **kw: bool) -> ET.Element:
    return ET.fromstring(robot_mjcf(robot, physics, timestep, **kw))


def test_surfaces_are_the_documented_coefficients():
    # Wong, Theory of Ground Vehicles: peak adhesion, lower end (dry 0.8-0.9, wet 0.5-0.7, ice 0.1)
    assert {k: s.mu for k, s in SURFACES.items()} == {"dry": 0.8, "wet": 0.5, "icy": 0.1}
    assert all(s.name == k for k, s in SURFACES.items())
    assert PhysicsParams().surface is SURFACES["dry"]
    assert PhysicsParams(surface="icy").surface is SURFACES["icy"]
    assert PhysicsParams(surface=0.35).surface == Surface(mu=0.35, name="mu=0.35")


@pytest.mark.parametrize("bad", ["snowy", "", "DRY", None, True, [0.8]])
def test_unknown_surfaces_are_refused_naming_the_choices(bad):
    with pytest.raises(ValueError, match="surface") as info:
        PhysicsParams(surface=bad)
    if isinstance(bad, str):
        assert "['dry', 'icy', 'wet']" in str(info.value)


def test_friction_coefficient_bounds():
    assert Surface(mu=MAX_MU).mu == MAX_MU
    assert Surface(mu=5e-324).mu == 5e-324
    for bad in (0.0, -0.1, math.nextafter(MAX_MU, math.inf), math.inf, math.nan, "0.8", True):
        with pytest.raises(ValueError, match=r"Surface\.mu"):
            Surface(mu=bad)


@pytest.mark.parametrize("name", [f.name for f in dataclasses.fields(PhysicsParams)
                                  if f.name != "surface"])
def test_every_field_is_validated_by_name(name):
    for bad in (math.nan, math.inf, -1.0, "1", None, True):
        with pytest.raises(ValueError, match=f"PhysicsParams.{name}="):
            PhysicsParams(**{name: bad})


def test_field_boundaries():
    # rolling resistance and the centre of mass's drop may be 0; the others must be > 0
    assert PhysicsParams(rolling_resistance=0.0).rolling_resistance == 0.0
    assert PhysicsParams(com_below_axle=0.0).com_below_axle == 0.0
    with pytest.raises(ValueError, match="chassis_mass"):
        PhysicsParams(chassis_mass=0.0)
    with pytest.raises(ValueError, match="rolling_resistance"):
        PhysicsParams(rolling_resistance=-5e-324)
    assert PhysicsParams(rolling_resistance=1.0).rolling_resistance == 1.0
    with pytest.raises(ValueError, match="rolling_resistance"):
        PhysicsParams(rolling_resistance=math.nextafter(1.0, 2.0))
    # MuJoCo resolves a contact only if its time constant spans two steps
    for name in ("contact_timeconst", "friction_timeconst"):
        assert getattr(PhysicsParams(**{name: 0.002}, max_timestep=0.001), name) == 0.002
        with pytest.raises(ValueError, match=name):
            PhysicsParams(**{name: math.nextafter(0.002, 0.0)}, max_timestep=0.001)


def test_substeps_per_period():
    assert substeps_per_period(0.01, 0.001) == 10  # 0.01 / 0.001 = 9.999999999999998
    assert substeps_per_period(0.01, 0.003) == 4  # ceil, so the step stays <= max_timestep
    assert substeps_per_period(0.01, 0.01) == 1
    assert substeps_per_period(0.001, 0.01) == 1
    assert substeps_per_period(0.01, 0.0025) == 4
    assert substeps_per_period(0.01 * (1 + 2e-9), 0.001) == 11  # beyond the 1e-9 tolerance
    with pytest.raises(ValueError, match="1e6"):
        substeps_per_period(1.0, 1e-7)
    for bad in (0.0, -1.0, math.nan, True):
        with pytest.raises(ValueError, match="ts="):
            substeps_per_period(bad, 0.001)


def test_mjcf_carries_the_robot_and_motor_parameters():
    motor = MotorParams(inertia=2.5e-4, friction=3e-4)
    robot = RobotParams(motor=motor, half_track=0.28, wheel_radius=0.05)
    physics = PhysicsParams(surface="wet", rolling_resistance=0.02, contact_patch_radius=0.004,
                            chassis_length=0.3, com_below_axle=0.01)
    root = _parse(robot, physics, 0.0005)
    assert root.find("size").get("memory") == "64K"  # not MuJoCo's 13 MB per run
    opt = root.find("option")
    assert float(opt.get("timestep")) == 0.0005
    assert _floats(opt.get("gravity")) == [0.0, 0.0, -GRAVITY]
    assert opt.get("cone") == "elliptic"
    assert opt.find("flag").get("autoreset") == "disable"  # divergence is reported, not reset
    chassis = root.find("worldbody/body[@name='chassis']")
    assert chassis.find("freejoint") is not None
    assert _floats(chassis.get("pos")) == [0.0, 0.0, 0.05]
    inertial = chassis.find("inertial")
    assert _floats(inertial.get("pos")) == [-0.075, 0.0, -0.01]
    assert float(inertial.get("mass")) == physics.chassis_mass
    assert tuple(_floats(inertial.get("diaginertia"))) == physics.chassis_inertia(robot)
    for side, y in (("right", -0.28), ("left", 0.28)):
        wheel = chassis.find(f"body[@name='wheel_{side}']")
        assert _floats(wheel.get("pos")) == [0.0, y, 0.0]
        joint = wheel.find("joint")
        assert joint.get("name") == side and _floats(joint.get("axis")) == [0.0, 1.0, 0.0]
        assert float(joint.get("armature")) == 2.5e-4  # the rotor's J
        assert float(joint.get("damping")) == 3e-4  # the motor's b
        spin, diam = physics.wheel_inertia(robot)
        assert _floats(wheel.find("inertial").get("diaginertia")) == [diam, spin, diam]
        tyre = wheel.find(f"geom[@name='tyre_{side}']")
        assert tyre.get("type") == "sphere" and float(tyre.get("size")) == 0.05
    caster = chassis.find("geom[@name='caster']")
    assert _floats(caster.get("pos")) == [-3 * 0.3 / 4, 0.0, 0.0]
    assert float(caster.get("size")) == 0.05
    pairs = {p.get("geom2"): p for p in root.findall("contact/pair")}
    assert set(pairs) == {"tyre_right", "tyre_left", "caster"}
    for side in ("right", "left"):
        pair = pairs[f"tyre_{side}"]
        assert pair.get("condim") == "6"
        assert _floats(pair.get("friction")) == [0.5, 0.5, 2 / 3 * 0.5 * 0.004, 0.02 * 0.05,
                                                0.02 * 0.05]
        assert _floats(pair.get("solref")) == [0.002, 1.0]
        assert _floats(pair.get("solreffriction")) == [0.02, 1.0]
    assert pairs["caster"].get("condim") == "1"  # frictionless
    # nothing else collides: every geom has contype = conaffinity = 0
    assert all(g.get("contype") == "0" and g.get("conaffinity") == "0"
               for g in root.iter("geom"))


def test_bench_fixes_the_chassis_in_the_air():
    root = _parse(RobotParams(), PhysicsParams(), bench=True)
    chassis = root.find("worldbody/body[@name='chassis']")
    assert chassis.find("freejoint") is None
    assert _floats(chassis.get("pos")) == [0.0, 0.0, 0.2 + 2 * 0.2]  # tyres 0.4 m clear


def test_geometry_that_cannot_be_built_is_refused():
    robot = RobotParams(wheel_radius=0.1)
    with pytest.raises(ValueError, match="com_below_axle"):
        robot_mjcf(robot, PhysicsParams(com_below_axle=0.1), 0.001)
    assert robot_mjcf(robot, PhysicsParams(com_below_axle=math.nextafter(0.1, 0.0)), 0.001)
    with pytest.raises(ValueError, match="wheel_width"):
        robot_mjcf(RobotParams(half_track=0.02), PhysicsParams(wheel_width=0.04), 0.001)
    with pytest.raises(ValueError, match="timestep"):
        robot_mjcf(robot, PhysicsParams(), 0.0)
    with pytest.raises(ValueError, match="RobotParams"):
        robot_mjcf(PhysicsParams(), PhysicsParams(), 0.001)  # type: ignore[arg-type]


def test_inertias_in_closed_form():
    robot = RobotParams(half_track=1.0, wheel_radius=0.5)
    p = PhysicsParams(chassis_mass=12.0, chassis_length=2.0, chassis_height=1.0,
                      wheel_mass=2.0, wheel_width=0.2)
    # box 2 x 1.8 x 1 m of 12 kg: (w^2 + h^2) m / 12 etc.
    assert p.chassis_inertia(robot) == pytest.approx((4.24, 5.0, 7.24), rel=1e-15)
    assert p.wheel_inertia(robot) == pytest.approx((0.25, 2.0 * (0.75 + 0.04) / 12), rel=1e-15)
    common, differential = p.reflected_inertia(robot)
    assert common == pytest.approx(0.25 + 16.0 * 0.25 / 2, rel=1e-15)
    yaw = 7.24 + 12.0 * 0.25 + 2 * (2.0 * 0.79 / 12 + 2.0)  # box + offset 0.5 m + wheels at 1 m
    assert differential == pytest.approx(0.25 + yaw * 0.25 / 2, rel=1e-15)


def test_no_slip_limit_reflects_one_percent_of_the_rotor():
    robot = RobotParams()
    common, differential = PhysicsParams.no_slip_limit(robot).reflected_inertia(robot)
    assert 0.0 < differential < common <= 0.014 * robot.motor.inertia
    assert PhysicsParams.no_slip_limit(robot).com_below_axle == pytest.approx(0.18)


def test_spec_table_round_trips_and_refuses_unknown_keys():
    pytest.importorskip(
        "mujoco", reason="needs the mujoco PyPI package: pip install 'it2track[mujoco]'")
    spec = MujocoSpec(physics=PhysicsParams(surface="icy", chassis_mass=0.5))
    table = spec.to_dict()
    assert table["kind"] == "mujoco" and table["surface"] == "icy"
    assert MujocoSpec.from_dict(table) == spec
    custom = MujocoSpec(physics=PhysicsParams(surface=0.3))
    assert custom.to_dict()["surface"] == 0.3
    assert MujocoSpec.from_dict(custom.to_dict()) == custom
    assert MujocoSpec(threads=1) == MujocoSpec(threads=4)  # threads do not change results
    # sent to worker processes (sweeps) by pickling
    assert pickle.loads(pickle.dumps(spec)) == spec
    loop = LoopConfig(duration=1.0, plant=spec)
    assert pickle.loads(pickle.dumps(loop)) == loop
    assert loop.to_dict()["plant"] == table
    with pytest.raises(ValueError, match=r"unknown key\(s\) \['chasis_mass'\]"):
        MujocoSpec.from_dict({"kind": "mujoco", "chasis_mass": 1.0})
    with pytest.raises(ValueError, match="kind='kinematic'"):
        MujocoSpec.from_dict({"kind": "kinematic"})
    with pytest.raises(ValueError, match=r"\[plant\]: PhysicsParams.wheel_mass=-1"):
        MujocoSpec.from_dict({"kind": "mujoco", "wheel_mass": -1})
    with pytest.raises(ValueError, match="surface"):
        MujocoSpec.from_dict({"kind": "mujoco", "surface": ["dry"]})
    for bad in (0, 257, 1.5, True):
        with pytest.raises(ValueError, match="threads"):
            MujocoSpec(threads=bad)


def test_missing_mujoco_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco -> ImportError
    with pytest.raises(MissingExtraError, match=r"pip install 'it2track\[mujoco\]'"):
        import_mujoco()
    with pytest.raises(ImportError, match=r"it2track\[mujoco\]"):
        MujocoSpec(physics=PhysicsParams(surface=0.123)).build(ts=0.0123, robot=RobotParams())
    # a configuration naming the MuJoCo robot is refused when read, as a ValueError
    with pytest.raises(ValueError, match=r"\[plant\]: kind = 'mujoco': .*it2track\[mujoco\]"):
        MujocoSpec.from_dict({"kind": "mujoco", "surface": "wet"})
    with pytest.raises(ValueError, match=r"it2track\[mujoco\]"):
        plant_from_dict({"kind": "mujoco"}, where="sweep.toml [plant]")

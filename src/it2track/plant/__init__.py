"""Plain physics: the plant protocol, the paper's robot (motors, drive), heading noise.

Imports numpy and scipy only; knows nothing of fuzzy logic or tracking. The closed loop drives
any plant through the protocol of :mod:`.base` (``Plant``, ``RobotPlant``, ``PlantSpec``);
:class:`KinematicPlant` is the paper's robot, :class:`MujocoPlant` the robot as a physical body in
MuJoCo (``MujocoSpec``; MuJoCo itself is imported only when one is built).
"""

from .base import check_plant, check_robot_plant
from .drive import DifferentialDrive, RobotParams, body_velocity, continuous_rhs
from .kinematic import KinematicPlant
from .motor import MotorParams
from .mujoco_model import PhysicsParams, Surface
from .mujoco_plant import MujocoPlant, MujocoSpec
from .mujoco_robot import MujocoRobot
from .noise import (
    HeadingNoise,
    held_sample_index,
    noise_samples_needed,
    run_generator,
    standard_noise,
)

__all__ = [
    "DifferentialDrive",
    "HeadingNoise",
    "KinematicPlant",
    "MotorParams",
    "MujocoPlant",
    "MujocoRobot",
    "MujocoSpec",
    "PhysicsParams",
    "RobotParams",
    "Surface",
    "body_velocity",
    "check_plant",
    "check_robot_plant",
    "continuous_rhs",
    "held_sample_index",
    "noise_samples_needed",
    "run_generator",
    "standard_noise",
]

"""Plain physics of the differential-drive robot: motors, drive, heading noise.

Imports numpy and scipy only; knows nothing of fuzzy logic or tracking.
"""

from .drive import DifferentialDrive, RobotParams, body_velocity, continuous_rhs
from .motor import MotorParams
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
    "MotorParams",
    "RobotParams",
    "body_velocity",
    "continuous_rhs",
    "held_sample_index",
    "noise_samples_needed",
    "run_generator",
    "standard_noise",
]

"""Trajectories, heading controllers, the batched closed loop and its metrics.

Builds on :mod:`it2track.fuzzy` (controllers) and :mod:`it2track.plant` (physics).
"""

from .controllers import FuzzyHeadingController, HeadingController, PDHeadingController
from .metrics import METRIC_NAMES, MetricAccumulator, integral_errors
from .simulate import (
    ON_PATH,
    TRACE_FIELDS,
    LoopConfig,
    PoseTiming,
    RunTable,
    Trace,
    run_grid,
    simulate,
    simulate_metrics,
    wrap_angle,
)
from .surface_table import SurfaceTableController
from .trajectories import (
    PAPER_TRAJECTORIES,
    FunctionTrajectory,
    Trajectory,
    WaypointTrajectory,
    curved,
    get_trajectory,
    load_waypoints_csv,
    sinusoidal,
    straight,
)

__all__ = [
    "METRIC_NAMES",
    "ON_PATH",
    "PAPER_TRAJECTORIES",
    "TRACE_FIELDS",
    "FunctionTrajectory",
    "FuzzyHeadingController",
    "HeadingController",
    "LoopConfig",
    "MetricAccumulator",
    "PDHeadingController",
    "PoseTiming",
    "RunTable",
    "SurfaceTableController",
    "Trace",
    "Trajectory",
    "WaypointTrajectory",
    "curved",
    "get_trajectory",
    "integral_errors",
    "load_waypoints_csv",
    "run_grid",
    "simulate",
    "simulate_metrics",
    "sinusoidal",
    "straight",
    "wrap_angle",
]

"""Trajectories and reference signals, controllers, the batched closed loop and its metrics.

Builds on :mod:`it2track.fuzzy` (controllers) and :mod:`it2track.plant` (physics). Two tasks
share the loop: a robot tracking trajectories by its heading (the paper's, :mod:`.heading`) and
a single-input plant tracking reference signals (:mod:`.siso`).
"""

from .controllers import (
    FuzzyHeadingController,
    HeadingController,
    IncrementalController,
    PDHeadingController,
)
from .metrics import METRIC_NAMES, MetricAccumulator, integral_errors
from .references import FunctionReference, Reference, StepReference, reference_from_dict
from .simulate import (
    ON_PATH,
    TRACE_FIELDS,
    LoopConfig,
    PoseTiming,
    RunTable,
    Target,
    Trace,
    check_task,
    run_grid,
    simulate,
    simulate_metrics,
    wrap_angle,
)
from .siso import REFERENCE_FIELDS
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
    "REFERENCE_FIELDS",
    "TRACE_FIELDS",
    "FunctionReference",
    "FunctionTrajectory",
    "FuzzyHeadingController",
    "HeadingController",
    "IncrementalController",
    "LoopConfig",
    "MetricAccumulator",
    "PDHeadingController",
    "PoseTiming",
    "Reference",
    "RunTable",
    "StepReference",
    "SurfaceTableController",
    "Target",
    "Trace",
    "Trajectory",
    "WaypointTrajectory",
    "check_task",
    "curved",
    "get_trajectory",
    "integral_errors",
    "load_waypoints_csv",
    "reference_from_dict",
    "run_grid",
    "simulate",
    "simulate_metrics",
    "sinusoidal",
    "straight",
    "wrap_angle",
]

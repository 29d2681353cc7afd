"""
Track your own waypoint trajectory
==================================

Track your own trajectory, given as timed waypoints in a CSV file, with the paper's IT2FLC
and its type-1 FLC, over 20 noise realisations (common random numbers).

Run: ``python examples/custom_waypoint_trajectory.py``
"""

import tempfile
from pathlib import Path

import numpy as np

from it2track import heading_fls
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    load_waypoints_csv,
    run_grid,
    simulate_metrics,
)

# An S-shaped path: waypoints every 2 s.
t = np.arange(0.0, 12.1, 2.0)
rows = ["t,x,y"] + [f"{ti},{2.0 * ti},{1.5 * np.sin(ti / 2.0)}" for ti in t]
path = Path(tempfile.mkdtemp()) / "s_curve.csv"
path.write_text("\n".join(rows) + "\n")

trajectory = load_waypoints_csv(path)  # cubic spline through the waypoints
controllers = [
    FuzzyHeadingController(fls=heading_fls(0.0), name="FLC"),
    FuzzyHeadingController(fls=heading_fls(0.3), name="IT2FLC FoU 0.3"),
]
runs = run_grid(len(controllers), 1, noise_stds=[0.1], seeds=20)
metrics = simulate_metrics(controllers, [trajectory], runs, LoopConfig(duration=12.0))
for i, c in enumerate(controllers):
    sel = runs.controller == i
    print(f"{c.name:16s} ISE {metrics['ISE'][sel].mean():.4f}  "
          f"position RMS {metrics['pos_rms'][sel].mean():.3f} m")

"""
The paper's controller rebuilt as an IT2 Mamdani system
=======================================================

The paper's IT2FLC (Tables 1 and 2) is a zero-order Sugeno system: each rule outputs a
voltage. Here the same inputs and rule table drive an interval type-2 *Mamdani* system whose
output sets are triangles centred on the paper's voltages (-12, -8, -4, 0, 4, 8, 12 V), each
with a footprint of uncertainty, reduced by centroid type reduction (KM) on a 101-point grid.
The script saves it as an IT2FLS-toolbox ``.t2fis`` file, loads it back, and compares it with
the paper's IT2 Sugeno controller in the closed loop on the paper's three trajectories,
over 10 noise seeds (common random numbers).

Run: ``python examples/mamdani_heading_controller.py``
"""

import tempfile
from pathlib import Path

import numpy as np

from it2track import heading_fls, load, save
from it2track.fuzzy import KM, IT2Mamdani, IT2Set, Output, Rule, TNorm, Triangle
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    curved,
    run_grid,
    simulate_metrics,
    sinusoidal,
    straight,
)

sugeno = heading_fls(0.2)  # the paper's IT2FLC, FoU 0.2 (Tables 1 and 2)

# Output sets: a triangle around each of the paper's voltages, 4 V wide on each side, widened
# into an IT2 set with a FoU of 2 V (the end sets are shoulders at +-12 V).
volts = {"NH": -12.0, "NM": -8.0, "NL": -4.0, "Z": 0.0, "PL": 4.0, "PM": 8.0, "PH": 12.0}
sets = []
for label, v in volts.items():
    left = v if v == -12.0 else v - 4.0
    right = v if v == 12.0 else v + 4.0
    sets.append(IT2Set.from_fou(Triangle(left, v, right), 2.0, label))
u = Output("u", (-12.0, 12.0), sets)

# The paper's Table 2, with each voltage replaced by the set around it.
label_of = {v: k for k, v in volts.items()}
rules = [Rule(r.antecedent, label_of[r.consequent[0]]) for r in sugeno.rules]
mamdani = IT2Mamdani(inputs=sugeno.inputs, outputs=[u], rules=rules, tnorm=TNorm.PRODUCT,
                     reducer=KM, name="IT2 Mamdani (FoU 0.2)")

# Save in the IT2FLS toolbox format and load it back: the same system, bit for bit.
path = Path(tempfile.mkdtemp()) / "mamdani_heading.t2fis"
save(mamdani, path)
again = load(path)
e, de = np.random.default_rng(0).uniform(-1, 1, (2, 1000))
assert np.array_equal(again(e, de), mamdani(e, de))
print(f"saved and reloaded {path.name}: {type(again).__name__}, {again.n_rules} rules")

# The two control surfaces side by side at a few points.
for point in [(0.0, 0.0), (0.15, 0.0), (0.5, 0.0), (-0.3, 0.7), (1.0, 1.0)]:
    print(f"u{point} = {float(mamdani(*point)):7.3f} V (Mamdani)   "
          f"{float(sugeno(*point)):7.3f} V (Sugeno)")

# Closed loop: both controllers, three trajectories, sigma = 0.05 rad, 10 seeds.
controllers = [FuzzyHeadingController(fls=sugeno, name="IT2 Sugeno (paper)"),
               FuzzyHeadingController(fls=again, name="IT2 Mamdani")]
trajectories = [straight(), curved(), sinusoidal()]
runs = run_grid(len(controllers), len(trajectories), noise_stds=[0.05], seeds=10)
metrics = simulate_metrics(controllers, trajectories, runs, LoopConfig())
print(f"\n{'controller':20s} {'trajectory':11s} {'ISE':>8s} {'IAE':>8s} {'pos RMS':>8s}")
for i, c in enumerate(controllers):
    for j, traj in enumerate(trajectories):
        sel = (runs.controller == i) & (runs.trajectory == j)
        print(f"{c.name:20s} {traj.name:11s} {metrics['ISE'][sel].mean():8.4f} "
              f"{metrics['IAE'][sel].mean():8.4f} {metrics['pos_rms'][sel].mean():8.3f}")

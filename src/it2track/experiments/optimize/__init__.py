"""FoU optimisation: the Footprint-of-Uncertainty widths that minimise a tracking objective.

The paper closes with "optimization of FoU selection can be applied"; this module does it for
the paper's controller (:mod:`it2track.paper`), in two variants:

- **symmetric**: one width ``w`` for every set of both inputs (the paper's family). A coarse
  grid of widths is simulated in one batched call, then bounded Brent
  (``scipy.optimize.minimize_scalar(method="bounded")``) refines between the best grid point's
  neighbours. The grid guards against the objective's several local minima; Brent gives the
  last digits cheaply.
- **asymmetric**: a width per set (N, Z, P) and per input (e, de), six in all
  (:class:`.AsymmetricFouSpec`), by differential evolution with a fixed seed
  (``scipy.optimize.differential_evolution``, ``vectorized=True``, ``updating="deferred"``):
  each generation is evaluated as one batch of candidates, it needs no gradients (the objective
  is piecewise smooth: dead zones, clipping, saturation), it respects the bounds natively, it is
  global, and a fixed seed makes it reproducible. Its initial population contains the symmetric
  optimum, so it can only improve on it (on the training seeds). Nelder-Mead or Powell would
  evaluate one point at a time (no batching) and stop at the first local minimum.

Objective: a weighted sum of metrics (:data:`~it2track.tracking.METRIC_NAMES`), averaged over
the training seeds, noise levels and trajectories of the configuration. Every candidate sees the
same seed indices (common random numbers), so differences between candidates are not noise
draws, and the objective is a deterministic function of the widths.

Verdict: the optima, FoU 0.1/0.2/0.3 (configurable) and the type-1 FLC are re-simulated on a
disjoint set of **held-out** seed indices. Per seed, the objective is averaged over noise levels
and trajectories (the seed is the independent unit); reported are the mean with a 95 % Student-t
interval (:func:`~.stats.mean_interval`) and, for each optimum against each baseline, the paired
difference with its interval and the fraction of seeds on which the optimum wins, ties counting
half (:func:`~.stats.paired_comparison`).

Bounds: a width within :data:`.BOUND_TOLERANCE` of the search range of one of its bounds is
flagged (``on_bound`` in the result, a sentence in ``warnings`` and in the Markdown): the
objective may keep falling beyond the range, so the optimum is only the best *inside* it.
"""

from .config import (
    WIDTH_NAMES,
    AsymmetricFouSpec,
    AsymmetricSettings,
    Objective,
    OptimizeConfig,
    SymmetricSettings,
)
from .evaluation import evaluate_metrics
from .loader import load_optimize_config
from .result import OptimizeResult
from .runner import run_optimization
from .search import BOUND_TOLERANCE

__all__ = [
    "BOUND_TOLERANCE",
    "WIDTH_NAMES",
    "AsymmetricFouSpec",
    "AsymmetricSettings",
    "Objective",
    "OptimizeConfig",
    "OptimizeResult",
    "SymmetricSettings",
    "evaluate_metrics",
    "load_optimize_config",
    "run_optimization",
]

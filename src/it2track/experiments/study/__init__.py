"""The paper's study, reproduced and extended (DESIGN.md sec. 6). Returns data; never plots.

Experiments (all with common random numbers: seed index ``i`` is the same noise realisation for
every controller, trajectory and noise level):

``paper``
    Monte Carlo at the study's noise level ``noise_std``: the FLC, the IT2FLCs of the paper's FoU
    widths, the fair baselines (type-1 FLCs with the IT2FLCs' dead zones, with their dead zones
    and edge slopes, a tuned PD), the tuned fuzzy controllers and any extra controllers, on
    every trajectory, over ``seeds`` realisations.
``noise``
    Noise-level sweep: FLC, the IT2FLCs, the two matched type-1 FLCs of ``main_fou`` and the PD
    over ``noise_levels``, ``sweep_seeds`` realisations each (one run at sigma = 0: without
    noise every seed is the same run).
``fou``
    Continuous FoU sweep: IT2FLC(w) and the dead-zone-matched type-1 FLC(w) for every ``w`` in
    ``fou_sweep`` (``w = 0`` is the FLC), at ``noise_std``, ``sweep_seeds`` realisations.

Plus the time series of one realisation (``figure_seed``) for the paper's figures 7-10, and the
control surfaces of every fuzzy controller. The PD baseline and the tuned fuzzy controllers
are tuned on seed indices disjoint from the evaluation seeds (see :func:`.tune_pd`,
:func:`.tune_fuzzy`), and the robustness experiment (:mod:`it2track.experiments.robustness`)
re-judges the claims under the paper's open modelling choices.

Every run of every experiment goes through one plan (:func:`~.plan._plan`): each distinct (loop,
controller, trajectory, sigma, seed) is simulated once, in batches per loop configuration,
through the same engine and executor, and shared by the rows that need it.
"""

from ..baselines import FuzzyTuning
from .config import PDTuning, StudyConfig, quick_config
from .loader import load_study_config
from .plan import experiment_sizes, study_run_count
from .results import ROW_KEYS as ROW_KEYS
from .results import StudyResult, figure_data
from .runner import run_study
from .tuning import TUNING_SEED_OFFSET as TUNING_SEED_OFFSET
from .tuning import tune_fuzzy, tune_pd

__all__ = [
    "FuzzyTuning",
    "PDTuning",
    "StudyConfig",
    "StudyResult",
    "experiment_sizes",
    "figure_data",
    "load_study_config",
    "quick_config",
    "run_study",
    "study_run_count",
    "tune_fuzzy",
    "tune_pd",
]

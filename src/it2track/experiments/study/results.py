"""What the study returns: :class:`StudyResult`, and :func:`figure_data`, the part of it that
needs no Monte Carlo (the time series of the figures and the control surfaces).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...fuzzy import control_surface
from ...tracking import (
    METRIC_NAMES,
    FuzzyHeadingController,
    RunTable,
    Trace,
    get_trajectory,
    simulate,
)
from ..robustness import RobustnessResult
from ..specs import ControllerSpec
from .config import StudyConfig

__all__ = ["ROW_KEYS", "StudyResult", "figure_data"]

FloatArray = NDArray[np.float64]


@dataclass
class StudyResult:
    """Everything the study produced, as data.

    Attributes
    ----------
    config : StudyConfig
    rows : dict of str -> ndarray
        The metrics table (``metrics.csv``), one entry per run of the ``paper``, ``noise`` and
        ``fou`` experiments: columns ``experiment``, ``trajectory``, ``controller``, ``kind``
        (str arrays), ``fou``, ``noise_std`` (float), ``seed`` (int), then every metric of
        :data:`~it2track.tracking.METRIC_NAMES`. A noise-free cell has one row (seed 0).
    traces : dict of str -> Trace
        Time series at ``noise_std`` for ``figure_seed``, by trajectory; the trace's runs are
        the controllers of ``trace_controllers`` in order.
    trace_controllers : list of str
        Labels of the traced controllers.
    trace_specs : list of ControllerSpec
        The traced controllers themselves, in trace run order.
    surfaces : dict of str -> (e, de, u)
        Control surfaces of the fuzzy controllers by label (``(101, 101)`` grids).
    surface_specs : dict of str -> ControllerSpec
        The controller behind each surface (its ``kind`` and ``fou``), by label.
    pd : ControllerSpec or None
        The (tuned) PD baseline.
    pd_tuning : dict
        The PD tuning record: grid objective values and the chosen gains.
    tuned : dict of str -> ControllerSpec
        The tuned fuzzy controllers by the label of the paper controller they tune (e.g.
        ``"IT2FLC FoU 0.2"`` -> the spec labelled ``"IT2FLC FoU 0.2 (tuned)"``, with its
        ``ke``, ``kde`` and ``output_gain``); empty without tuning.
    tuning : dict of str -> dict
        One tuning record per tuned controller (same keys as ``tuned``): ``grid`` (rows
        ``[ke, kde, gain, mean ISE, mean effort]``, see ``grid_columns``), the chosen ``ke``,
        ``kde``, ``gain``, its ``objective`` (mean ISE) and ``effort``, the ``effort_limit``
        (the PD's), ``on_grid_edge``, ``seed_indices``, ``noise_std``, ``criterion``; and
        ``"untuned"``: the paper controller's own mean ISE and effort on the same runs.
    tuned_claims : list of ClaimResult
        C1-C3 judged on the tuned fuzzy controllers (``paper`` experiment, ``noise_std``,
        ``seeds`` realisations): the tuned-vs-tuned comparison. Empty without tuning.
    ordering : list of dict
        The probability that a single realisation shows the paper's strict ordering
        FLC > FoU 0.1 > 0.2 > 0.3 on all four integrals (``trajectory = "all"``: on every
        trajectory at once; or per trajectory), per noise level of the ``noise`` experiment,
        with exact intervals (:func:`~.analysis.ordering_probability`).
    robustness : RobustnessResult or None
        The robustness experiment (verdict table, robustness.csv cells, flips, ranking,
        Morris sensitivity indices and ranking); None when the study has none.
    claims : list of ClaimResult
        The verdicts on C1-C3 and D1-D3 from the ``noise`` experiment, with the replication
        probability of every level and verdicts over the settled levels (the headline).
    verdict_rows : list of dict
        ``verdicts.csv``: one row per claim x path (and all) x noise level
        (:func:`~it2track.experiments.verdicts.verdict_rows`).
    seeds_by_level : dict of (str, str, float) -> int
        Realisations each (controller, path, sigma) of the ``noise`` experiment got (the
        sequential design's outcome).
    rounds : list of dict
        The sequential design's extension rounds (:class:`~..sequential.SettledResult`).
    extra_runs : int
        Simulations the sequential design's extension rounds added to the plan's.
    surface_copy : dict
        The type-1 table of the main IT2FLC's surface (D3): ``label``, ``grid`` (nodes per
        axis), ``points`` (check grid), ``max`` and ``rms`` surface error, V (empty without
        it).
    """

    config: StudyConfig
    rows: dict[str, np.ndarray]
    traces: dict[str, Trace]
    trace_controllers: list[str]
    trace_specs: list[ControllerSpec]
    surfaces: dict[str, tuple[FloatArray, FloatArray, FloatArray]]
    surface_specs: dict[str, ControllerSpec]
    pd: ControllerSpec | None
    pd_tuning: dict[str, Any]
    tuned: dict[str, ControllerSpec] = field(default_factory=dict)
    tuning: dict[str, dict[str, Any]] = field(default_factory=dict)
    tuned_claims: list[Any] = field(default_factory=list)
    ordering: list[dict[str, Any]] = field(default_factory=list)
    robustness: RobustnessResult | None = None
    claims: list[Any] = field(default_factory=list)
    verdict_rows: list[dict[str, Any]] = field(default_factory=list)
    seeds_by_level: dict[tuple[str, str, float], int] = field(default_factory=dict)
    rounds: list[dict[str, Any]] = field(default_factory=list)
    surface_copy: dict[str, Any] = field(default_factory=dict)
    extra_runs: int = 0

    def select(self, **where: Any) -> dict[str, np.ndarray]:
        """Rows matching every ``column=value`` (floats compared exactly)."""
        mask = np.ones(len(self.rows["seed"]), dtype=bool)
        for key, value in where.items():
            mask &= self.rows[key] == value
        return {k: v[mask] for k, v in self.rows.items()}


ROW_KEYS = ("experiment", "trajectory", "controller", "kind", "fou", "noise_std", "seed")


def figure_data(config: StudyConfig) -> StudyResult:
    """The part of the study that needs no Monte Carlo, as a :class:`StudyResult` without rows:
    the time series of one realisation (``traces``) and the control surfaces.

    :func:`.run_study` returns the same traces and surfaces; ``it2track reproduce`` draws their
    figures from this while the experiments still run.
    """
    # Time series of one realisation for the figures.
    traced = config.paper_fuzzy()
    controllers = [s.build() for s in traced]
    traces: dict[str, Trace] = {}
    for name in config.trajectories:
        runs = RunTable(np.arange(len(controllers)), 0, config.noise_std, config.figure_seed)
        traces[name] = simulate(controllers, [get_trajectory(name)], runs, config.loop)

    surface_specs = {s.label: s for s in [
        *config.paper_fuzzy(), *config.matched_baselines(config.fous),
    ]}
    surfaces: dict[str, tuple[FloatArray, FloatArray, FloatArray]] = {}
    for label, spec in surface_specs.items():
        controller = spec.build()
        assert isinstance(controller, FuzzyHeadingController)
        surfaces[label] = control_surface(controller.fls)
    kinds = {"experiment": object, "trajectory": object, "controller": object, "kind": object,
             "seed": np.int64}
    no_rows = {k: np.empty(0, dtype=kinds.get(k, np.float64)) for k in (*ROW_KEYS, *METRIC_NAMES)}
    return StudyResult(
        config=config, rows=no_rows, traces=traces,
        trace_controllers=[s.label for s in traced], trace_specs=traced, surfaces=surfaces,
        surface_specs=surface_specs, pd=None, pd_tuning={},
    )

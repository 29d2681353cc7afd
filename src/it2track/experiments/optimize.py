"""FoU optimisation: the Footprint-of-Uncertainty widths that minimise a tracking objective.

The paper closes with "optimization of FoU selection can be applied"; this module does it for
the paper's controller (:mod:`it2track.paper`), in two variants:

- **symmetric**: one width ``w`` for every set of both inputs (the paper's family). A coarse
  grid of widths is simulated in one batched call, then bounded Brent
  (``scipy.optimize.minimize_scalar(method="bounded")``) refines between the best grid point's
  neighbours. The grid guards against the objective's several local minima; Brent gives the
  last digits cheaply.
- **asymmetric**: a width per set (N, Z, P) and per input (e, de), six in all
  (:class:`AsymmetricFouSpec`), by differential evolution with a fixed seed
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

Bounds: a width within :data:`BOUND_TOLERANCE` of the search range of one of its bounds is
flagged (``on_bound`` in the result, a sentence in ``warnings`` and in the Markdown): the
objective may keep falling beyond the range, so the optimum is only the best *inside* it.
"""

from __future__ import annotations

import inspect
import itertools
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import scipy.optimize
from numpy.typing import NDArray
from tqdm import tqdm

from .. import __version__
from .._limits import check_memory, loop_bytes
from ..fuzzy import Reducer, TNorm
from ..paper import LABELS, MAX_FOU, heading_fls_widths
from ..tracking import METRIC_NAMES, FuzzyHeadingController, LoopConfig, Trajectory
from .executors import Executor, InProcessExecutor
from .specs import (
    ConfigError,
    ControllerKind,
    ControllerSpec,
    Table,
    loop_config_from_table,
    read_toml,
    robot_from_table,
)
from .stats import Interval, mean_interval, paired_comparison
from .sweep import (
    DEFAULT_BATCH_SIZE,
    BuildableSpec,
    TrajectoryRef,
    grid_chunks,
    parse_noise_levels,
    parse_seeds,
    parse_trajectories,
    simulate_grid_chunk,
)

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

FloatArray = NDArray[np.float64]

#: Order of the six widths of :class:`AsymmetricFouSpec` (input, set).
WIDTH_NAMES: tuple[str, ...] = tuple(f"{inp}.{lab}" for inp in ("e", "de") for lab in LABELS)
#: An optimal width closer than this fraction of the search range to a bound is "on the bound".
BOUND_TOLERANCE = 0.01


def _widths3(value: Sequence[float], name: str) -> tuple[float, float, float]:
    try:
        widths = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"AsymmetricFouSpec.{name}={value!r} must be 3 numbers") from None
    if len(widths) != 3:
        raise ValueError(f"AsymmetricFouSpec.{name}={value!r} must be 3 widths (N, Z, P)")
    for lab, w in zip(LABELS, widths, strict=True):
        if not (math.isfinite(w) and 0.0 <= w < MAX_FOU):
            raise ValueError(
                f"AsymmetricFouSpec.{name}: width of {lab}={w!r} must satisfy 0 <= w < {MAX_FOU}"
            )
    return widths[0], widths[1], widths[2]


@dataclass(frozen=True, kw_only=True)
class AsymmetricFouSpec:
    """The paper's IT2 heading controller with a FoU width per set and per input.

    Set ``L`` of input ``x`` is ``IT2Set.from_fou(CENTRE_SETS[L], w[x][L], L)``; rules, universes
    and consequents are the paper's (:mod:`it2track.paper`). With all six widths equal to ``w``
    it is the same controller as ``ControllerSpec(kind="it2", fou=w)`` (bit-for-bit); a width of 0
    makes that set type-1.

    Parameters
    ----------
    e, de : (float, float, float)
        Widths of the sets (N, Z, P) of the error input and of the change-of-error input,
        each ``0 <= w < 1.6``.
    ke, kde : float
        Input gains.
    reducer, tnorm : str
        As in :class:`~.specs.ControllerSpec`.
    label : str
        Name in results; derived from the widths when empty.

    Examples
    --------
    >>> spec = AsymmetricFouSpec.from_widths([0.2, 0.4, 0.2, 0.1, 0.3, 0.1])
    >>> spec.label
    'IT2FLC FoU e(0.2,0.4,0.2) de(0.1,0.3,0.1)'
    >>> round(float(spec.build().fls(0.5, 0.0)), 6)
    4.363636
    """

    e: tuple[float, float, float]
    de: tuple[float, float, float]
    ke: float = 1.0
    kde: float = 1.0
    reducer: str = "exhaustive"
    tnorm: str = "product"
    label: str = ""

    kind = "it2-asymmetric"

    def __post_init__(self) -> None:
        object.__setattr__(self, "e", _widths3(self.e, "e"))
        object.__setattr__(self, "de", _widths3(self.de, "de"))
        for key in ("ke", "kde"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ValueError(f"AsymmetricFouSpec.{key}={value!r} must be a number")
            if not math.isfinite(value):
                raise ValueError(f"AsymmetricFouSpec.{key}={value!r} must be finite")
            object.__setattr__(self, key, float(value))
        Reducer.from_name(self.reducer)
        TNorm.from_name(self.tnorm)
        if not self.label:
            e = ",".join(f"{w:.3g}" for w in self.e)
            de = ",".join(f"{w:.3g}" for w in self.de)
            gains = "" if (self.ke, self.kde) == (1.0, 1.0) else f" Ke {self.ke:g} Kde {self.kde:g}"
            object.__setattr__(self, "label", f"IT2FLC FoU e({e}) de({de}){gains}")

    @classmethod
    def from_widths(cls, widths: Sequence[float], **kwargs: Any) -> AsymmetricFouSpec:
        """From six widths in the order of :data:`WIDTH_NAMES` (e: N Z P, then de: N Z P)."""
        w = [float(v) for v in widths]
        if len(w) != 6:
            names = ", ".join(WIDTH_NAMES)
            raise ValueError(f"widths={list(widths)!r} must be 6 numbers ({names})")
        return cls(e=(w[0], w[1], w[2]), de=(w[3], w[4], w[5]), **kwargs)

    @property
    def widths(self) -> tuple[float, ...]:
        """The six widths in the order of :data:`WIDTH_NAMES`."""
        return (*self.e, *self.de)

    def build(self) -> FuzzyHeadingController:
        """The controller (raises ``ValueError`` if a width is too large for its set)."""
        fls = heading_fls_widths(
            self.e, self.de, reducer=Reducer.from_name(self.reducer).value,
            tnorm=TNorm.from_name(self.tnorm), name=self.label,
        )
        return FuzzyHeadingController(fls=fls, ke=self.ke, kde=self.kde, name=self.label)

    def to_dict(self) -> dict[str, Any]:
        """Plain values (JSON-ready)."""
        return {
            "kind": self.kind, "label": self.label, "fou_e": list(self.e),
            "fou_de": list(self.de), "ke": self.ke, "kde": self.kde, "reducer": self.reducer,
            "tnorm": self.tnorm,
        }  # fmt: skip


@dataclass(frozen=True)
class Objective:
    """``sum_m weight_m * metric_m`` for each run (then averaged by the caller).

    Examples
    --------
    >>> obj = Objective((("ISE", 1.0), ("effort", 0.001)))
    >>> str(obj)
    'ISE + 0.001 effort'
    >>> float(obj.per_run({"ISE": np.array([0.5]), "effort": np.array([100.0])})[0])
    0.6
    """

    weights: tuple[tuple[str, float], ...]

    def __post_init__(self) -> None:
        if not self.weights:
            raise ValueError("objective needs at least one metric")
        for name, w in self.weights:
            if name not in METRIC_NAMES:
                raise ValueError(f"objective metric {name!r} is not one of {list(METRIC_NAMES)}")
            if not (math.isfinite(w) and w > 0):
                raise ValueError(f"objective weight of {name}={w!r} must be finite and > 0")

    def per_run(self, metrics: Mapping[str, FloatArray]) -> FloatArray:
        out = np.zeros(np.shape(metrics[self.weights[0][0]]))
        for name, w in self.weights:
            out += w * np.asarray(metrics[name], dtype=np.float64)
        return out

    def __str__(self) -> str:
        return " + ".join(n if w == 1.0 else f"{w:g} {n}" for n, w in self.weights)


@dataclass(frozen=True, kw_only=True)
class SymmetricSettings:
    """Grid + bounded-Brent search of one width."""

    grid: int = 25
    xatol: float = 1e-3
    maxiter: int = 40

    def __post_init__(self) -> None:
        if isinstance(self.grid, bool) or not isinstance(self.grid, int) or self.grid < 3:
            raise ValueError(f"symmetric grid={self.grid!r} must be an integer >= 3")
        if not (math.isfinite(self.xatol) and self.xatol > 0):
            raise ValueError(f"symmetric xatol={self.xatol!r} must be > 0")
        if isinstance(self.maxiter, bool) or not isinstance(self.maxiter, int) or self.maxiter < 1:
            raise ValueError(f"symmetric maxiter={self.maxiter!r} must be an integer >= 1")


@dataclass(frozen=True, kw_only=True)
class AsymmetricSettings:
    """Differential evolution over the six widths (scipy's parameter names)."""

    enabled: bool = True
    popsize: int = 6
    maxiter: int = 20
    tol: float = 0.01
    seed: int = 1
    mutation: tuple[float, float] = (0.5, 1.0)
    recombination: float = 0.7
    init: str = "latinhypercube"

    def __post_init__(self) -> None:
        for key in ("popsize", "maxiter"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise ValueError(f"asymmetric {key}={v!r} must be an integer >= 1")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"asymmetric seed={self.seed!r} must be an integer >= 0")
        if not (math.isfinite(self.tol) and self.tol >= 0):
            raise ValueError(f"asymmetric tol={self.tol!r} must be >= 0")
        m = tuple(float(v) for v in self.mutation)
        if len(m) != 2 or not (0 <= m[0] <= m[1] < 2):
            raise ValueError(f"asymmetric mutation={self.mutation!r} must be [lo, hi], 0<=lo<=hi<2")
        object.__setattr__(self, "mutation", m)
        if not 0 <= self.recombination <= 1:
            raise ValueError(f"asymmetric recombination={self.recombination!r} must be in [0, 1]")
        if self.init not in ("latinhypercube", "sobol", "halton", "random"):
            raise ValueError(
                f"asymmetric init={self.init!r} must be latinhypercube, sobol, halton or random"
            )


@dataclass(frozen=True)
class OptimizeConfig:
    """A parsed optimisation problem (see :func:`load_optimize_config`)."""

    config: LoopConfig
    trajectory_refs: tuple[TrajectoryRef, ...]
    noise_std: tuple[float, ...]
    train_seeds: tuple[int, ...]
    holdout_seeds: tuple[int, ...]
    objective: Objective
    bounds: tuple[float, float] = (0.0, 1.5)
    compare: tuple[float, ...] = (0.1, 0.2, 0.3)
    compare_flc: bool = True
    ke: float = 1.0
    kde: float = 1.0
    reducer: str = "exhaustive"
    tnorm: str = "product"
    symmetric: SymmetricSettings = field(default_factory=SymmetricSettings)
    asymmetric: AsymmetricSettings = field(default_factory=AsymmetricSettings)
    batch_size: int = DEFAULT_BATCH_SIZE
    source: str = ""
    trajectories: tuple[Trajectory, ...] = field(default=(), compare=False, repr=False)

    def __post_init__(self) -> None:
        if not self.trajectories:
            object.__setattr__(
                self, "trajectories", tuple(r.load() for r in self.trajectory_refs)
            )
        lo, hi = (float(v) for v in self.bounds)
        if not (0.0 <= lo < hi < MAX_FOU):
            raise ValueError(f"bounds={self.bounds!r} must satisfy 0 <= lo < hi < {MAX_FOU}")
        object.__setattr__(self, "bounds", (lo, hi))
        overlap = sorted(set(self.train_seeds) & set(self.holdout_seeds))
        if overlap:
            raise ValueError(
                f"holdout_seeds must be disjoint from train_seeds; both hold {overlap[:5]}"
            )
        if len(self.holdout_seeds) < 2:
            raise ValueError("holdout_seeds needs at least 2 seeds for an interval")
        for w in self.compare:
            if not 0.0 < w < MAX_FOU:
                raise ValueError(f"compare width {w!r} must satisfy 0 < w < {MAX_FOU}")
        self._check_memory()
        # Build every kind of controller the run will build, now: bad gains, reducer or t-norm
        # fail here (ValueError naming the field), not after minutes of optimisation.
        widths = {lo, hi, 0.0, *self.compare}
        for w in sorted(widths):
            self.symmetric_spec(w).build()
        for w in (lo, hi):
            self.asymmetric_spec([w] * len(WIDTH_NAMES)).build()

    def _check_memory(self) -> None:
        """One evaluation holds every run's metrics (~300 bytes per run, driver and worker
        side) for all candidates of a generation, plus one simulation batch."""
        candidates = max(self.symmetric.grid, 6 * self.asymmetric.popsize,
                         len(self.compare) + 3)
        per = len(self.trajectory_refs) * len(self.noise_std)
        seeds = max(len(self.train_seeds), len(self.holdout_seeds))
        runs = candidates * per * seeds
        need = 300 * runs + loop_bytes(
            n_steps=self.config.n_steps, runs=min(self.batch_size, runs),
            trajectories=len(self.trajectory_refs),
            noise_samples=int(self.config.duration * self.config.noise_rate) + 1)
        check_memory(
            need,
            what=(f"an evaluation of {candidates} candidates x {per} trajectory/noise cells x "
                  f"{seeds} seeds ({runs} runs, batch_size={self.batch_size})"),
            hint="use fewer seeds, a smaller grid/popsize or a smaller batch_size",
        )

    def symmetric_spec(self, w: float) -> ControllerSpec:
        """The paper's controller with FoU ``w`` (``w == 0``: the type-1 FLC)."""
        common: dict[str, Any] = {"ke": self.ke, "kde": self.kde, "tnorm": self.tnorm}
        if w == 0.0:
            return ControllerSpec(kind=ControllerKind.FLC, **common)
        return ControllerSpec(kind=ControllerKind.IT2, fou=float(w), reducer=self.reducer, **common)

    def asymmetric_spec(self, widths: Sequence[float]) -> AsymmetricFouSpec:
        return AsymmetricFouSpec.from_widths(
            widths, ke=self.ke, kde=self.kde, reducer=self.reducer, tnorm=self.tnorm
        )

    def normalised(self) -> dict[str, Any]:
        """The problem as plain JSON data (``simulation``: :meth:`LoopConfig.to_dict`, with the
        base seed and the robot)."""
        return {
            "it2track_version": __version__,
            "simulation": self.config.to_dict(),
            "trajectories": [r.to_dict() for r in self.trajectory_refs],
            "noise_std": list(self.noise_std),
            "train_seeds": list(self.train_seeds),
            "holdout_seeds": list(self.holdout_seeds),
            "objective": dict(self.objective.weights),
            "bounds": list(self.bounds),
            "compare": list(self.compare),
            "compare_flc": self.compare_flc,
            "controller": {
                "ke": self.ke, "kde": self.kde, "reducer": self.reducer, "tnorm": self.tnorm,
            },
            "symmetric": {
                "grid": self.symmetric.grid, "xatol": self.symmetric.xatol,
                "maxiter": self.symmetric.maxiter,
            },
            "asymmetric": {
                "enabled": self.asymmetric.enabled, "popsize": self.asymmetric.popsize,
                "maxiter": self.asymmetric.maxiter, "tol": self.asymmetric.tol,
                "seed": self.asymmetric.seed, "mutation": list(self.asymmetric.mutation),
                "recombination": self.asymmetric.recombination, "init": self.asymmetric.init,
            },
        }  # fmt: skip


# -- configuration file --------------------------------------------------------------------------


def _parse_objective(t: Table) -> Objective:
    key = "objective"
    raw = t.data.get(key, ...)
    if raw is ...:
        raise ConfigError(f"{t.where}: missing key 'objective' (a metric name or {{ISE = 1.0}})")
    if isinstance(raw, str):
        name = t.get(key, str)
        weights: list[tuple[str, float]] = [(name, 1.0)]
    elif isinstance(raw, Mapping):
        sub = t.sub(key)
        if not raw:
            raise ConfigError(f"{sub.where}: empty objective (give weights, e.g. ISE = 1.0)")
        weights = [(name, sub.get(name, float)) for name in raw]
        sub.done()
    else:
        raise ConfigError(f"{t.where}: objective={raw!r} must be a metric name or a table")
    for name, w in weights:
        if name not in METRIC_NAMES:
            raise ConfigError(
                f"{t.where}: objective metric {name!r} unknown; choose from {list(METRIC_NAMES)}"
            )
        if w <= 0:
            raise ConfigError(f"{t.where}: objective weight {name}={w!r} must be > 0")
    return Objective(tuple(weights))


def _settings(t: Table, cls: type, spec: dict[str, type]) -> Any:
    values = {}
    for key, kind in spec.items():
        if key in t:
            values[key] = tuple(t.get_list(key, float)) if kind is list else t.get(key, kind)
    t.done()
    try:
        return cls(**values)
    except ValueError as exc:
        raise ConfigError(f"{t.where}: {exc}") from None


def load_optimize_config(path: str | Path) -> OptimizeConfig:
    """Parse an optimisation TOML file (see the packaged config ``optimize``).

    The packaged configs are described in :mod:`it2track.configs`.

    Sections: ``[optimize]`` (``seed``, ``objective``, ``train_seeds``, ``holdout_seeds``,
    ``noise_std``, ``trajectories``, ``bounds``, ``compare``, ``compare_flc``, ``batch_size``),
    ``[optimize.symmetric]``, ``[optimize.asymmetric]``, ``[controller]`` (``ke``, ``kde``,
    ``reducer``, ``tnorm``), ``[simulation]``, ``[robot]`` / ``[robot.motor]``.

    Raises
    ------
    ConfigError
        Naming the file, section, key and value of an unknown key, a bad value or an empty list.
    """
    path = Path(path)
    file = str(path)
    root = Table(read_toml(path), file, path.parent)
    ot = root.sub("optimize")
    seed = ot.get("seed", int, 0)
    if seed < 0:
        raise ConfigError(f"{ot.where}: seed={seed!r} must be an integer >= 0")
    objective = _parse_objective(ot)
    train = parse_seeds(ot, "train_seeds")
    holdout = parse_seeds(ot, "holdout_seeds")
    noise = parse_noise_levels(ot, "noise_std")
    refs, trajectories = parse_trajectories(ot, "trajectories", path.parent)
    bounds = tuple(ot.get_list("bounds", float, [0.0, 1.5]))
    if len(bounds) != 2:
        raise ConfigError(f"{ot.where}: bounds={list(bounds)!r} must be [lo, hi]")
    compare = tuple(ot.get_list("compare", float, [0.1, 0.2, 0.3]))
    compare_flc = ot.get("compare_flc", bool, True)
    batch_size = ot.get("batch_size", int, DEFAULT_BATCH_SIZE)
    if batch_size < 1:
        raise ConfigError(f"{ot.where}: batch_size={batch_size!r} must be an integer >= 1")
    symmetric = _settings(
        ot.sub("symmetric"), SymmetricSettings, {"grid": int, "xatol": float, "maxiter": int}
    )
    asymmetric = _settings(
        ot.sub("asymmetric"),
        AsymmetricSettings,
        {
            "enabled": bool, "popsize": int, "maxiter": int, "tol": float, "seed": int,
            "mutation": list, "recombination": float, "init": str,
        },
    )  # fmt: skip
    ot.done()
    ct = root.sub("controller")
    ctrl = {k: ct.get(k, float) for k in ("ke", "kde") if k in ct}
    ctrl.update({k: ct.get(k, str) for k in ("reducer", "tnorm") if k in ct})
    ct.done()
    robot = robot_from_table(root.sub("robot"))
    config = loop_config_from_table(root.sub("simulation"), robot, seed=seed)
    root.done()
    try:
        return OptimizeConfig(
            config=config,
            trajectory_refs=refs,
            trajectories=trajectories,
            noise_std=noise,
            train_seeds=train,
            holdout_seeds=holdout,
            objective=objective,
            bounds=(bounds[0], bounds[1]),
            compare=compare,
            compare_flc=compare_flc,
            symmetric=symmetric,
            asymmetric=asymmetric,
            batch_size=batch_size,
            source=file,
            **ctrl,
        )
    except ValueError as exc:
        raise ConfigError(f"{ot.where}: {exc}") from None


# -- evaluation ----------------------------------------------------------------------------------


def evaluate_metrics(
    specs: Sequence[BuildableSpec],
    *,
    config: LoopConfig,
    trajectories: Sequence[Trajectory],
    noise_std: Sequence[float],
    seeds: Sequence[int],
    executor: Executor | None = None,
    batch_size: int = DEFAULT_BATCH_SIZE,
) -> dict[str, FloatArray]:
    """Metrics of every spec on the grid trajectories x noise levels x seeds.

    All specs share the seed indices (common random numbers). The specs are split into at most
    ``executor.n_workers`` tasks of whole candidates; each task is one ``simulate_metrics``
    call with many controllers. Results do not depend on the executor.

    Returns
    -------
    dict of str -> ndarray, shape (n_specs, n_trajectories, n_noise, n_seeds)
    """
    executor = executor or InProcessExecutor()
    n = len(specs)
    per = len(trajectories) * len(noise_std) * len(seeds)
    parts = max(1, min(executor.n_workers, n))
    edges = np.linspace(0, n, parts + 1).round().astype(int).tolist()
    bounds = [(a * per, b * per) for a, b in itertools.pairwise(edges) if b > a]
    tasks = grid_chunks(
        config=config, controllers=specs, trajectories=trajectories, noise_std=noise_std,
        seeds=seeds, bounds=bounds, batch_size=batch_size,
    )  # fmt: skip
    out = {name: np.empty(n * per) for name in METRIC_NAMES}
    for task, result in executor.imap_unordered(simulate_grid_chunk, tasks):
        for name in METRIC_NAMES:
            out[name][task.start : task.stop] = result.metrics[name]
    shape = (n, len(trajectories), len(noise_std), len(seeds))
    return {name: value.reshape(shape) for name, value in out.items()}


class _Evaluator:
    """Training objective of candidate batches, with a log of every evaluation."""

    def __init__(self, cfg: OptimizeConfig, executor: Executor) -> None:
        self.cfg = cfg
        self.executor = executor
        self.history: list[dict[str, Any]] = []
        self.seconds = 0.0
        self.runs = 0

    def __call__(
        self, specs: Sequence[BuildableSpec], widths: Sequence[Sequence[float]], phase: str
    ) -> FloatArray:
        cfg = self.cfg
        t0 = time.perf_counter()
        metrics = evaluate_metrics(
            specs, config=cfg.config, trajectories=cfg.trajectories, noise_std=cfg.noise_std,
            seeds=cfg.train_seeds, executor=self.executor, batch_size=cfg.batch_size,
        )  # fmt: skip
        self.seconds += time.perf_counter() - t0
        values = cfg.objective.per_run(metrics).reshape(len(specs), -1).mean(axis=1)
        self.runs += values.size * len(cfg.trajectories) * len(cfg.noise_std) * len(
            cfg.train_seeds
        )
        for w, v in zip(widths, values.tolist(), strict=True):
            self.history.append(
                {"eval": len(self.history), "phase": phase, "widths": list(w), "objective": v}
            )
        return values


def _bar(progress: bool, total: int | None, desc: str) -> Any:
    return tqdm(total=total, desc=desc, unit="cand", disable=not progress, dynamic_ncols=True)


def _optimise_symmetric(cfg: OptimizeConfig, ev: _Evaluator, progress: bool) -> dict[str, Any]:
    s = cfg.symmetric
    lo, hi = cfg.bounds
    grid = np.linspace(lo, hi, s.grid).tolist()
    cache: dict[float, float] = {}
    with _bar(progress, s.grid, "symmetric grid") as bar:
        values = ev([cfg.symmetric_spec(w) for w in grid], [[w] for w in grid], "symmetric-grid")
        bar.update(s.grid)
    cache.update(zip(grid, values.tolist(), strict=True))
    i = int(np.argmin(values))
    bracket = (grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)])

    with _bar(progress, None, "symmetric refine") as bar:

        def f(w: float) -> float:
            w = float(w)
            if w not in cache:
                cache[w] = float(ev([cfg.symmetric_spec(w)], [[w]], "symmetric-refine")[0])
                bar.update(1)
            return cache[w]

        res = scipy.optimize.minimize_scalar(
            f, bounds=bracket, method="bounded",
            options={"xatol": s.xatol, "maxiter": s.maxiter},
        )  # fmt: skip
    best_w = min(cache, key=lambda w: (cache[w], w))
    side = _bound_side(best_w, cfg.bounds)
    return {
        "width": best_w,
        "train_objective": cache[best_w],
        "on_bound": side is not None,
        "bound": side,
        "grid": grid,
        "grid_objective": values.tolist(),
        "bracket": list(bracket),
        "brent": {"x": float(res.x), "fun": float(res.fun), "nfev": int(res.nfev),
                  "success": bool(res.success), "message": str(res.message)},
        "n_evaluations": len(cache),
    }  # fmt: skip


def _optimise_asymmetric(
    cfg: OptimizeConfig, ev: _Evaluator, start: float, progress: bool
) -> dict[str, Any]:
    a = cfg.asymmetric
    lo, hi = cfg.bounds
    n_pop = a.popsize * len(WIDTH_NAMES)

    with _bar(progress, (a.maxiter + 1) * n_pop, "asymmetric DE") as bar:

        def f(x: FloatArray) -> FloatArray:
            cols = np.atleast_2d(np.asarray(x, dtype=np.float64).T)  # (S, 6)
            widths = [[float(v) for v in row] for row in cols]
            out = ev([cfg.asymmetric_spec(w) for w in widths], widths, "asymmetric")
            bar.update(len(widths))
            return out

        res = scipy.optimize.differential_evolution(
            f,
            bounds=[(lo, hi)] * len(WIDTH_NAMES),
            maxiter=a.maxiter,
            popsize=a.popsize,
            tol=a.tol,
            mutation=a.mutation,
            recombination=a.recombination,
            **_de_rng(np.random.default_rng(a.seed)),
            init=a.init,
            polish=False,
            updating="deferred",
            vectorized=True,
            x0=np.full(len(WIDTH_NAMES), min(max(start, lo), hi)),
        )
        # DE stops early once the population converges: the bar ends at the real count
        # (100 %), not at the budget's fraction.
        bar.total = bar.n
        bar.refresh()
    asym = [h for h in ev.history if h["phase"] == "asymmetric"]
    best = min(asym, key=lambda h: h["objective"])
    widths = dict(zip(WIDTH_NAMES, best["widths"], strict=True))
    sides = {name: _bound_side(w, cfg.bounds) for name, w in widths.items()}
    return {
        "widths": widths,
        "train_objective": best["objective"],
        "on_bound": {n: side is not None for n, side in sides.items()},
        "bound": sides,
        "de": {"x": [float(v) for v in res.x], "fun": float(res.fun),
               "batches": int(res.nfev), "generations": int(res.nit),
               "success": bool(res.success), "message": str(res.message),
               "population": n_pop},
        "n_evaluations": len(asym),
    }  # fmt: skip


def _de_rng(rng: np.random.Generator) -> dict[str, np.random.Generator]:
    """The generator as ``differential_evolution``'s keyword: ``rng`` (SciPy >= 1.15) or
    ``seed`` (older SciPy). Both use the generator as given: the same population either way."""
    params = inspect.signature(scipy.optimize.differential_evolution).parameters
    return {"rng": rng} if "rng" in params else {"seed": rng}


def _bound_side(width: float, bounds: tuple[float, float]) -> str | None:
    """``"lower"`` / ``"upper"`` if ``width`` is within :data:`BOUND_TOLERANCE` of the search
    range of that bound, else ``None``."""
    lo, hi = bounds
    tol = BOUND_TOLERANCE * (hi - lo)
    if width - lo <= tol:
        return "lower"
    if hi - width <= tol:
        return "upper"
    return None


def _bound_warnings(
    bounds: tuple[float, float], sym: Mapping[str, Any], asym: Mapping[str, Any] | None
) -> list[str]:
    """One sentence per optimal width that sits on a bound of the search range."""
    lo, hi = bounds

    def advice(side: str) -> str:
        if side == "lower" and lo == 0.0:
            return "0 is the smallest width (a type-1 set), so the optimum is at the edge"
        if side == "upper" and hi >= MAX_FOU - BOUND_TOLERANCE * (hi - lo):
            return f"widths must stay below {MAX_FOU}, so the optimum is at the edge"
        limit = f"0 <= lo < hi < {MAX_FOU}"
        return f"the objective may keep falling beyond it: widen bounds ({limit}) and rerun"

    out = []
    if sym.get("bound"):
        side = sym["bound"]
        value = lo if side == "lower" else hi
        out.append(
            f"The symmetric optimum FoU {sym['width']:.4g} lies on the {side} bound {value:g} "
            f"of the search range [{lo:g}, {hi:g}]; {advice(side)}."
        )
    if asym is not None:
        for name, side in asym["bound"].items():
            if side:
                value = lo if side == "lower" else hi
                out.append(
                    f"The asymmetric optimum width {name} = {asym['widths'][name]:.4g} lies on "
                    f"the {side} bound {value:g} of the search range [{lo:g}, {hi:g}]; "
                    f"{advice(side)}."
                )
    return out


def _interval(iv: Interval) -> dict[str, float]:
    """An :class:`~.stats.Interval` as JSON-ready values."""
    return {"n": iv.n, "mean": iv.mean, "lo": iv.low, "hi": iv.high}


@dataclass(frozen=True)
class OptimizeResult:
    """Everything :func:`run_optimization` found; JSON-ready via :meth:`to_dict`."""

    config: dict[str, Any]
    objective: str
    symmetric: dict[str, Any]
    asymmetric: dict[str, Any] | None
    verdict: dict[str, Any]
    history: list[dict[str, Any]]
    timing: dict[str, float]
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {
            "objective": self.objective, "config": self.config, "symmetric": self.symmetric,
            "asymmetric": self.asymmetric, "warnings": list(self.warnings),
            "holdout": self.verdict, "timing": self.timing, "history": self.history,
        }  # fmt: skip

    def to_markdown(self) -> str:
        """The held-out verdict as Markdown tables."""
        v = self.verdict
        lines = [
            f"# FoU optimisation: minimise {self.objective}",
            "",
            f"Objective averaged over {v['n_noise']} noise level(s) x {v['n_trajectories']} "
            f"trajectory(ies) per seed; training on {v['n_train_seeds']} seed(s), verdict on "
            f"{v['n_holdout_seeds']} held-out seed(s) (disjoint, seed indices "
            f"{v['holdout_seed_range']}). Intervals: 95 % Student-t over seeds.",
            "",
        ]
        if self.warnings:
            lines += ["**Optimum on a bound of the search range:**", ""]
            lines += [f"- {w}" for w in self.warnings]
            lines.append("")
        lines += [
            "| controller | FoU widths | train objective | held-out mean | 95 % interval |",
            "|---|---|---:|---:|---|",
        ]
        for c in v["controllers"]:
            h = c["holdout"]
            lines.append(
                f"| {c['name']} | {c['widths']} | {c['train']:.5g} | {h['mean']:.5g} | "
                f"[{h['lo']:.5g}, {h['hi']:.5g}] |"
            )
        lines += [
            "",
            "Paired differences on the held-out seeds (optimum minus baseline; negative = the "
            "optimum is better; wins: share of seeds on which the optimum is better, ties "
            "counting half):",
            "",
            "| optimum | baseline | mean difference | 95 % interval | optimum wins | verdict |",
            "|---|---|---:|---|---:|---|",
        ]
        for d in v["paired"]:
            lines.append(
                f"| {d['optimum']} | {d['baseline']} | {d['mean']:.4g} | "
                f"[{d['lo']:.4g}, {d['hi']:.4g}] | {100 * d['win_rate']:.0f} % | {d['verdict']} |"
            )
        shown = ("IAE", "ITAE", "ISE", "ITSE", "pos_rms", "effort", "sat_time")
        lines += [
            "",
            "Held-out means of the metrics (over seeds, noise levels and trajectories), to see "
            "what the objective trades away:",
            "",
            "| controller | " + " | ".join(shown) + " |",
            "|---|" + "---:|" * len(shown),
        ]
        for c in v["controllers"]:
            cells = " | ".join(f"{c['holdout_metrics'][m]:.4g}" for m in shown)
            lines.append(f"| {c['name']} | {cells} |")
        t = self.timing
        lines += [
            "",
            f"Evaluations: {len(self.history)} candidates "
            f"({self.symmetric['n_evaluations']} symmetric"
            + (f", {self.asymmetric['n_evaluations']} asymmetric" if self.asymmetric else "")
            + f"); {t['total_s']:.1f} s in all.",
            "",
        ]
        return "\n".join(lines)


def _verdict(cfg: OptimizeConfig, ev: _Evaluator, sym: dict[str, Any],
             asym: dict[str, Any] | None) -> dict[str, Any]:  # fmt: skip
    entries: list[tuple[str, BuildableSpec, str, bool]] = []
    w = sym["width"]
    entries.append((f"symmetric optimum (FoU {w:.4g})", cfg.symmetric_spec(w), f"{w:.4g}", True))
    if asym is not None:
        ws = list(asym["widths"].values())
        text = "e " + "/".join(f"{x:.3g}" for x in ws[:3]) + ", de " + "/".join(
            f"{x:.3g}" for x in ws[3:]
        )
        entries.append(("asymmetric optimum", cfg.asymmetric_spec(ws), text, True))
    for c in cfg.compare:
        entries.append((f"IT2FLC FoU {c:g}", cfg.symmetric_spec(c), f"{c:g}", False))
    if cfg.compare_flc:
        entries.append(("FLC (type-1)", cfg.symmetric_spec(0.0), "0", False))
    specs = [e[1] for e in entries]

    def metrics(seeds: Sequence[int]) -> dict[str, FloatArray]:
        return evaluate_metrics(
            specs, config=cfg.config, trajectories=cfg.trajectories, noise_std=cfg.noise_std,
            seeds=seeds, executor=ev.executor, batch_size=cfg.batch_size,
        )  # fmt: skip

    train_m = metrics(cfg.train_seeds)
    hold_m = metrics(cfg.holdout_seeds)
    train = cfg.objective.per_run(train_m).reshape(len(specs), -1).mean(axis=1)
    # Per seed: mean over trajectories and noise levels -> (n_specs, n_holdout_seeds).
    per_seed = cfg.objective.per_run(hold_m).mean(axis=(1, 2))
    controllers = []
    for k, (name, spec, widths, is_opt) in enumerate(entries):
        controllers.append({
            "name": name, "optimum": is_opt, "widths": widths, "spec": spec.to_dict(),
            "train": float(train[k]),
            "holdout": _interval(mean_interval(per_seed[k])),
            "holdout_metrics": {m: float(hold_m[m][k].mean()) for m in METRIC_NAMES},
        })  # fmt: skip
    optima = [k for k, e in enumerate(entries) if e[3]]
    baselines = [k for k, e in enumerate(entries) if not e[3]]
    pairs = [(i, j) for i in optima for j in baselines]
    if len(optima) == 2:
        pairs.insert(len(baselines), (optima[1], optima[0]))  # asymmetric vs symmetric
    paired = []
    for i, j in pairs:
        cmp = paired_comparison(per_seed[i], per_seed[j])  # optimum minus baseline
        if cmp.diff.high < 0:
            verdict = "optimum better"
        elif cmp.diff.low > 0:
            verdict = "optimum worse"
        else:
            verdict = "no significant difference"
        paired.append({
            "optimum": entries[i][0], "baseline": entries[j][0], **_interval(cmp.diff),
            "win_rate": cmp.win_rate, "ties": cmp.ties, "verdict": verdict,
        })  # fmt: skip
    hs = cfg.holdout_seeds
    return {
        "n_train_seeds": len(cfg.train_seeds),
        "n_holdout_seeds": len(hs),
        "holdout_seed_range": f"{min(hs)}-{max(hs)}",
        "n_noise": len(cfg.noise_std),
        "n_trajectories": len(cfg.trajectories),
        "controllers": controllers,
        "paired": paired,
    }


def run_optimization(
    cfg: OptimizeConfig,
    *,
    executor: Executor | None = None,
    progress: bool = True,
    log: Callable[[str], object] | None = None,
) -> OptimizeResult:
    """Optimise the FoU widths of ``cfg`` and verify the optima on the held-out seeds.

    Parameters
    ----------
    cfg : OptimizeConfig
    executor : Executor, optional
        Where candidate batches run (default: this process). Results do not depend on it.
    progress : bool
        tqdm bars on stderr.
    log : callable, optional
        Receives one line per finished phase.
    """
    executor = executor or InProcessExecutor()
    t0 = time.perf_counter()
    ev = _Evaluator(cfg, executor)
    sym = _optimise_symmetric(cfg, ev, progress)
    t_sym = time.perf_counter() - t0
    if log:
        log(f"symmetric optimum: FoU {sym['width']:.4g}, train objective "
            f"{sym['train_objective']:.5g} ({sym['n_evaluations']} evaluations, {t_sym:.1f} s)")
    asym = None
    if cfg.asymmetric.enabled:
        asym = _optimise_asymmetric(cfg, ev, sym["width"], progress)
        if log:
            ws = ", ".join(f"{k} {v:.3g}" for k, v in asym["widths"].items())
            log(f"asymmetric optimum: {ws}; train objective {asym['train_objective']:.5g} "
                f"({asym['n_evaluations']} evaluations, {time.perf_counter() - t0 - t_sym:.1f} s)")
    t_opt = time.perf_counter() - t0
    verdict = _verdict(cfg, ev, sym, asym)
    total = time.perf_counter() - t0
    warnings = _bound_warnings(cfg.bounds, sym, asym)
    if log:
        for w in warnings:
            log(f"warning: {w}")
    return OptimizeResult(
        config=cfg.normalised(),
        objective=str(cfg.objective),
        symmetric=sym,
        asymmetric=asym,
        verdict=verdict,
        history=ev.history,
        warnings=tuple(warnings),
        timing={"symmetric_s": t_sym, "optimisation_s": t_opt, "holdout_s": total - t_opt,
                "total_s": total, "simulation_s": ev.seconds, "train_runs": ev.runs},
    )  # fmt: skip

"""The optimisation problem: :class:`OptimizeConfig` and its parts, the objective
(:class:`Objective`), the settings of both searches (:class:`SymmetricSettings`,
:class:`AsymmetricSettings`) and the controller with a width per set
(:class:`AsymmetricFouSpec`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ... import __version__
from ..._limits import check_memory, loop_bytes
from ...fuzzy import Reducer, TNorm
from ...paper import LABELS, MAX_FOU, heading_fls_widths
from ...tracking import METRIC_NAMES, FuzzyHeadingController, LoopConfig, Target
from ..specs import ControllerKind, ControllerSpec
from ..sweep import DEFAULT_BATCH_SIZE, TrajectoryRef

__all__ = [
    "WIDTH_NAMES",
    "AsymmetricFouSpec",
    "AsymmetricSettings",
    "Objective",
    "OptimizeConfig",
    "SymmetricSettings",
]

FloatArray = NDArray[np.float64]


#: Order of the six widths of :class:`AsymmetricFouSpec` (input, set).
WIDTH_NAMES: tuple[str, ...] = tuple(f"{inp}.{lab}" for inp in ("e", "de") for lab in LABELS)


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
    """A parsed optimisation problem (see :func:`.load_optimize_config`)."""

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
    trajectories: tuple[Target, ...] = field(default=(), compare=False, repr=False)

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

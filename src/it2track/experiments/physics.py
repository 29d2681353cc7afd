"""The physics check: the study's claims re-judged with the robot simulated in MuJoCo.

The kinematic robot of the paper has wheels that never slip and no mass. This experiment runs
the study's noise experiment -- the same controllers (those the claims compare), paths, noise
levels, duration and control period -- on the MuJoCo robot
(:class:`~it2track.plant.mujoco_plant.MujocoSpec`) on each ground surface of
:class:`PhysicsCheck` (dry, wet and icy by default:
:data:`~it2track.plant.mujoco_model.SURFACES`), and judges every claim with the study's own
machinery: the sequential design (:func:`~.sequential.settle`, with the study's replication
target, bootstrap resamples and seed, and a smaller ``first``/``batch``/``cap``), the
replication probabilities (:mod:`.replication`) and the verdict rows (:mod:`.verdicts`).
Nothing is judged here that the study does not judge the same way.

The MuJoCo robot is far slower to simulate than the kinematic one
(``benchmarks/bench_plants.py``), hence the small seed cap; ``benchmarks/bench_physics_check.py``
prints what the check costs. Each call of the design's ``simulate`` can be kept in a cache folder
(:class:`RowCache`): an interrupted check, run again with the same cache, re-simulates only
the batches it had not finished, and gives the same numbers bit for bit.
"""

from __future__ import annotations

import hashlib
import json
import math
import zipfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, cast

import numpy as np

from ..atomicfile import atomic_open
from ..plant.base import PlantSpec
from ..plant.mujoco_model import SURFACES, PhysicsParams, Surface
from ..plant.mujoco_plant import MujocoSpec
from ..tracking import RunTable, Trace, get_trajectory, simulate
from .claimcells import claim_definitions
from .executors import Executor
from .judgement import ALL
from .sequential import SeedBatch, SequentialDesign, SettledResult, settle
from .specs import ControllerSpec
from .study import StudyConfig
from .study.runner import noise_simulator
from .verdicts import VERDICT_COLUMNS, verdict_rows

__all__ = ["PHYSICS_COLUMNS", "PhysicsCheck", "PhysicsResult", "RowCache", "SurfaceResult",
           "mujoco_missing", "physics_config", "physics_traces", "run_physics", "survival"]

#: Columns of ``physics_verdicts.csv``: the surface, its friction coefficient, then
#: :data:`~.verdicts.VERDICT_COLUMNS`.
PHYSICS_COLUMNS = ("surface", "mu", *VERDICT_COLUMNS)
#: Most realisations per cell the check allows (the MuJoCo robot is far slower to simulate).
MAX_CAP = 200
_CACHE_VERSION = 1


def mujoco_missing() -> str | None:
    """Why the MuJoCo robot cannot run here (the message names the extra), or None."""
    from ..plant.mujoco_robot import import_mujoco

    try:
        import_mujoco()
    except ImportError as exc:
        return str(exc)
    return None


def _count(v: Any, key: str, least: int, most: int) -> None:
    if isinstance(v, bool) or not isinstance(v, int) or not least <= v <= most:
        raise ValueError(f"PhysicsCheck.{key}={v!r} must be an integer in [{least}, {most}]")


@dataclass(frozen=True, kw_only=True)
class PhysicsCheck:
    """What the physics check runs.

    Parameters
    ----------
    surfaces : tuple of str, default ("dry", "wet", "icy")
        Ground surfaces, names of :data:`~it2track.plant.mujoco_model.SURFACES`, each once.
    first : int, default 4
        Realisations of every noisy (path, sigma) unit in the first round (2 to ``cap``).
    batch : int, default 2
        Realisations added per round to the cells behind an unsettled level (>= 1).
    cap : int, default 6
        Most realisations per cell (``first`` to 200).

    Raises
    ------
    ValueError
        If a surface is unknown or repeated, or a count is out of range (naming the field).

    Examples
    --------
    >>> PhysicsCheck().design(SequentialDesign()).cap
    6
    """

    surfaces: tuple[str, ...] = ("dry", "wet", "icy")
    first: int = 4
    batch: int = 2
    cap: int = 6

    def __post_init__(self) -> None:
        s = self.surfaces
        if isinstance(s, str) or not isinstance(s, tuple) or not s:
            raise ValueError(f"PhysicsCheck.surfaces={s!r} must be a non-empty tuple of "
                             f"{sorted(SURFACES)}")
        for name in s:
            if name not in SURFACES:
                raise ValueError(f"PhysicsCheck.surfaces: {name!r} is not one of "
                                 f"{sorted(SURFACES)}")
        if len(set(s)) != len(s):
            raise ValueError(f"PhysicsCheck.surfaces={s!r} names a surface twice")
        _count(self.cap, "cap", 2, MAX_CAP)
        _count(self.first, "first", 2, self.cap)
        _count(self.batch, "batch", 1, MAX_CAP)

    def design(self, study: SequentialDesign) -> SequentialDesign:
        """The study's design (target, resamples, bootstrap seed) with this check's
        ``first``, ``batch`` and ``cap``.

        Parameters
        ----------
        study : SequentialDesign
            The study's (``StudyConfig.verdicts``).

        Returns
        -------
        SequentialDesign
        """
        return replace(study, first=self.first, batch=self.batch, cap=self.cap)

    def to_dict(self) -> dict[str, Any]:
        """Plain values for the manifest."""
        return {"surfaces": list(self.surfaces), "first": self.first, "batch": self.batch,
                "cap": self.cap}


def physics_config(config: StudyConfig, check: PhysicsCheck, surface: str) -> StudyConfig:
    """The study's configuration with the MuJoCo robot on ``surface`` as its plant and the
    check's design; only the noise experiment of it is run (no tuning, PD or robustness).

    Parameters
    ----------
    config : StudyConfig
        The study's.
    check : PhysicsCheck
    surface : str
        One of ``check.surfaces``.

    Returns
    -------
    StudyConfig
    """
    # MujocoSpec is a PlantSpec (its ``kind`` a class constant, which mypy's protocol check
    # reads as a mismatch)
    spec = cast("PlantSpec", MujocoSpec(physics=PhysicsParams(surface=Surface.named(surface))))
    return replace(config, loop=replace(config.loop, plant=spec), sweep_seeds=check.first,
                   verdicts=check.design(config.verdicts), pd=None, tuning=None,
                   robustness=None)


def claim_controllers(config: StudyConfig) -> list[ControllerSpec]:
    """The noise experiment's controllers that some claim compares (its PD and extra
    controllers are in no claim)."""
    specs = config.noise_controllers(None)
    defs = claim_definitions(fous=config.fous, main_fou=config.main_fou,
                             trajectories=config.trajectories,
                             available=[s.label for s in specs])
    used = {c for d in defs if not d.missing
            for c in (*d.controllers, *d.candidates)}
    return [s for s in specs if s.label in used]


class RowCache:
    """The rows of each ``simulate`` call, kept in ``folder`` as ``rows-<key>.npz``.

    The key is a SHA-256 of everything the rows depend on (the loop with its plant, the paths,
    the controllers' specifications, the cells and seed indices), so a cache written for
    another configuration is never read. A file that cannot be read is simulated again.

    Parameters
    ----------
    folder : Path
        Created if missing.
    """

    PREFIX = "rows-"

    def __init__(self, folder: Path) -> None:
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.hits = 0
        self.misses = 0

    def key(self, config: StudyConfig, specs: Mapping[str, ControllerSpec],
            batches: Sequence[SeedBatch]) -> str:
        """The key of these batches under ``config``'s loop."""
        used = sorted({c for b in batches for c, _, _ in b.cells})
        text = json.dumps({
            "version": _CACHE_VERSION, "loop": config.loop.to_dict(),
            "trajectories": list(config.trajectories),
            "specs": {c: specs[c].to_dict() for c in used},
            "batches": [[list(map(list, b.cells)), b.start, b.stop] for b in batches],
        }, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:40]

    def wrap(self, simulate: Callable[[Sequence[SeedBatch]], dict[str, np.ndarray]],
             config: StudyConfig, specs: Mapping[str, ControllerSpec]
             ) -> Callable[[Sequence[SeedBatch]], dict[str, np.ndarray]]:
        """``simulate`` reading and writing this cache."""
        def cached(batches: Sequence[SeedBatch]) -> dict[str, np.ndarray]:
            path = self.folder / f"{self.PREFIX}{self.key(config, specs, batches)}.npz"
            want = sum(len(b.cells) * (b.stop - b.start) for b in batches)
            rows = self._read(path, want)
            if rows is not None:
                self.hits += 1
                return rows
            self.misses += 1
            rows = simulate(batches)
            arrays: dict[str, Any] = {k: (v.astype(str) if v.dtype == object else v)
                                      for k, v in rows.items()}
            with atomic_open(path, "wb") as fh:
                np.savez(fh, **arrays)
            return rows

        return cached

    @staticmethod
    def _read(path: Path, want: int) -> dict[str, np.ndarray] | None:
        try:
            with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as z:
                rows = {k: z[k] for k in z.files}
        except (OSError, ValueError, KeyError, zipfile.BadZipFile, EOFError):
            return None
        if not rows or any(len(v) != want for v in rows.values()):
            return None
        return {k: (v.astype(object) if v.dtype.kind == "U" else v) for k, v in rows.items()}

    def files(self) -> list[Path]:
        """The cache's own files (none other is ever touched)."""
        return sorted(self.folder.glob(f"{self.PREFIX}*.npz"))


@dataclass
class SurfaceResult:
    """One surface's outcome: the settled design and its verdict rows."""

    surface: str
    mu: float
    settled: SettledResult
    verdict_rows: list[dict[str, Any]]
    runs: int


@dataclass
class PhysicsResult:
    """The physics check's outcome, per surface in ``check.surfaces`` order."""

    check: PhysicsCheck
    design: SequentialDesign
    controllers: tuple[str, ...]
    surfaces: list[SurfaceResult] = field(default_factory=list)

    def rows(self) -> dict[str, np.ndarray]:
        """Every run's metrics, with ``surface`` and ``mu`` columns first."""
        parts = []
        for s in self.surfaces:
            r = s.settled.rows
            n = len(r["seed"])
            parts.append({"surface": np.full(n, s.surface, dtype=object),
                          "mu": np.full(n, s.mu), **r})
        return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}

    def verdict_rows(self) -> list[dict[str, Any]]:
        """``physics_verdicts.csv``'s rows (columns :data:`PHYSICS_COLUMNS`)."""
        return [{"surface": s.surface, "mu": s.mu, **r} for s in self.surfaces
                for r in s.verdict_rows]

    @property
    def runs(self) -> int:
        """Simulations run (cached ones included)."""
        return sum(s.runs for s in self.surfaces)


def _sorted(rows: Mapping[str, np.ndarray], config: StudyConfig,
            labels: Sequence[str]) -> dict[str, np.ndarray]:
    """Rows in the grid's order (controller, path, level, seed), as the study's."""
    path_index = {t: i for i, t in enumerate(config.trajectories)}
    order = np.lexsort((
        rows["seed"],
        np.array([config.noise_levels.index(s) for s in rows["noise_std"].tolist()]),
        np.array([path_index[t] for t in rows["trajectory"]]),
        np.array([labels.index(c) for c in rows["controller"]])))
    return {k: np.asarray(v)[order] for k, v in rows.items()}


def run_physics(
    config: StudyConfig,
    check: PhysicsCheck,
    *,
    cache: RowCache | None = None,
    executor: Executor | None = None,
    progress: Callable[[int], object] | None = None,
    grow: Callable[[int], object] | None = None,
    on_surface: Callable[[str], object] | None = None,
) -> PhysicsResult:
    """Run the physics check (module docstring).

    Parameters
    ----------
    config : StudyConfig
        The study (paths, noise levels, FoU widths, loop, replication target).
    check : PhysicsCheck
    cache : RowCache, optional
        Keeps each round's rows, so an interrupted check resumes where it stopped.
    executor : Executor, optional
        Where the runs go (default: this process; MuJoCo steps a batch on threads).
    progress : callable, optional
        Called with the number of runs finished, as they finish (cached runs included).
    grow : callable, optional
        Called with the number of runs of each round before they run (a progress bar's total).
    on_surface : callable, optional
        Called with each surface's name before it starts.

    Returns
    -------
    PhysicsResult

    Raises
    ------
    it2track._extras.MissingExtraError
        If MuJoCo is not installed (an ``ImportError`` naming the extra).
    """
    specs = claim_controllers(config)
    labels = [s.label for s in specs]
    result = PhysicsResult(check=check, design=check.design(config.verdicts),
                           controllers=tuple(labels))
    spec_of = {s.label: s for s in specs}
    for surface in check.surfaces:
        if on_surface is not None:
            on_surface(surface)
        cfg = physics_config(config, check, surface)
        done = [0]

        def counted(n: int, done: list[int] = done) -> None:
            done[0] += n
            if grow is not None:
                grow(n)

        simulate = noise_simulator(cfg, specs, executor=executor, progress=progress,
                                   grow=counted)
        if cache is not None:
            simulate = cache.wrap(simulate, cfg, spec_of)
        counting = _counting(simulate, progress, grow, done)
        defs = claim_definitions(fous=cfg.fous, main_fou=cfg.main_fou,
                                 trajectories=cfg.trajectories, available=labels)
        settled = settle(counting, claims=defs, controllers=labels,
                         trajectories=cfg.trajectories, levels=cfg.noise_levels,
                         design=cfg.verdicts, fous=cfg.fous, main_fou=cfg.main_fou)
        settled.rows = _sorted(settled.rows, cfg, labels)
        result.surfaces.append(SurfaceResult(
            surface=surface, mu=SURFACES[surface].mu, settled=settled,
            verdict_rows=verdict_rows(defs, settled.claims), runs=done[0]))
    return result


def _counting(simulate: Callable[[Sequence[SeedBatch]], dict[str, np.ndarray]],
              progress: Callable[[int], object] | None, grow: Callable[[int], object] | None,
              done: list[int]) -> Callable[[Sequence[SeedBatch]], dict[str, np.ndarray]]:
    """``simulate`` that also counts and reports the runs a cache answered (the simulator
    counts those it runs)."""
    def run(batches: Sequence[SeedBatch]) -> dict[str, np.ndarray]:
        before = done[0]
        rows = simulate(batches)
        if done[0] == before:  # answered from the cache
            n = len(rows["seed"])
            done[0] += n
            if grow is not None:
                grow(n)
            if progress is not None:
                progress(n)
        return rows

    return run


def survival(kinematic: Sequence[Mapping[str, Any]],
             physics: PhysicsResult) -> list[dict[str, Any]]:
    """Each claim's noisy levels over all paths: the kinematic robot's status beside each
    surface's (status, replication probability, realisations, settled).

    Parameters
    ----------
    kinematic : sequence of dict
        The study's ``verdicts.csv`` rows.
    physics : PhysicsResult

    Returns
    -------
    list of dict
        ``claim, sigma, kinematic, kinematic_settled`` and, per surface ``s``, the keys
        ``s`` (status), ``s_replication``, ``s_n``, ``s_settled`` and ``s_same`` (settled on
        both robots with the same status).
    """
    def key(r: Mapping[str, Any]) -> tuple[str, float]:
        return str(r["claim"]), float(r["sigma"])

    kin = {key(r): r for r in kinematic if r["path"] == ALL and float(r["sigma"]) > 0.0}
    per = {s.surface: {key(r): r for r in s.verdict_rows if r["path"] == ALL}
           for s in physics.surfaces}
    out = []
    for k in sorted(set().union(*[set(v) for v in per.values()]),
                    key=lambda k: (k[0], k[1])):
        if k[1] == 0.0:
            continue
        base = kin.get(k)
        row: dict[str, Any] = {"claim": k[0], "sigma": k[1],
                               "kinematic": "" if base is None else base["status"],
                               "kinematic_settled": base is not None and bool(base["settled"])}
        for s, rows in per.items():
            r = rows.get(k)
            if r is None:
                continue
            rep = r["replication"]
            row[s] = r["status"]
            row[f"{s}_replication"] = float(rep) if rep != "" else math.nan
            row[f"{s}_n"] = int(r["n"])
            row[f"{s}_settled"] = bool(r["settled"])
            row[f"{s}_same"] = bool(row["kinematic_settled"] and r["settled"]
                                    and r["status"] == row["kinematic"])
        out.append(row)
    return out


def physics_traces(config: StudyConfig, check: PhysicsCheck,
                   path: str | None = None) -> list[tuple[str, Trace, tuple[str, ...]]]:
    """One realisation (``figure_seed`` at ``noise_std``) of the FLC and the main IT2FLC on
    ``path`` (default: ``"curved"`` if studied, else the first path), on the kinematic robot
    and on each surface: ``(title, trace, labels)`` per panel, for the animation.

    Parameters
    ----------
    config : StudyConfig
    check : PhysicsCheck
    path : str, optional
        One of ``config.trajectories``.

    Returns
    -------
    list of (str, Trace, tuple of str)

    Raises
    ------
    ValueError
        If ``path`` is not one of the study's.
    """
    if path is None:
        path = "curved" if "curved" in config.trajectories else config.trajectories[0]
    if path not in config.trajectories:
        raise ValueError(f"path={path!r} is not one of the study's {list(config.trajectories)}")
    fuzzy = [s for s in config.paper_fuzzy() if s.label == "FLC"
             or s.label == f"IT2FLC FoU {config.main_fou:g}"]
    ctrls = [s.build() for s in fuzzy]
    labels = tuple(s.label for s in fuzzy)
    runs = RunTable(np.arange(len(ctrls)), 0, config.noise_std, config.figure_seed)
    traj = [get_trajectory(path)]
    panels = [(f"kinematic robot, {path}", simulate(ctrls, traj, runs, config.loop), labels)]
    for surface in check.surfaces:
        loop = physics_config(config, check, surface).loop
        mu = SURFACES[surface].mu
        panels.append((f"MuJoCo, {surface} (μ {mu:g})", simulate(ctrls, traj, runs, loop),
                       labels))
    return panels

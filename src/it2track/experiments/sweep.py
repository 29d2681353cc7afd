"""Resumable parameter sweeps: cartesian products of configuration axes, simulated in chunks.

A sweep is the cartesian product of

- **plant parameter sets** ("groups"): every ``[robot]`` / ``[robot.motor]`` key given as a
  list is an axis (``half_track = [5.6, 0.3]``);
- **controllers**: every ``[[controllers]]`` entry is a :class:`~.specs.ControllerSpec` table
  in which any key given as a list is an axis (``kind = "it2"``, ``fou = [0.1, 0.2]``,
  ``ke = [0.5, 1, 2]``); the controller axis is the union of the entries' expansions. Every
  controller is built once while the configuration is parsed, so a bad value or an unreadable
  or malformed controller file is a :class:`~.specs.ConfigError` before anything is written;
- **trajectories**, **noise standard deviations** and **seed indices** (``[sweep]``).

Run order (the row order of ``results.csv``) is group, controller, trajectory, noise, seed,
the seed varying fastest; run ``r`` has the same meaning in every executor and chunk layout.
The noise of a run depends only on ``(sweep.seed, seed index)`` (common random numbers: every
controller, trajectory, noise level and plant sees the same standard-normal sequence for a given
seed index), so a run's metrics are the same whatever the executor, chunk size or worker count.

Runs are split into chunks of at most ``chunk_size`` consecutive runs, never mixing plant
parameter sets; one chunk is one :func:`~it2track.tracking.simulate_metrics` call. A chunk
travels to its worker as a :class:`GridChunk` -- the specs, trajectories and an index range,
never arrays of runs -- and comes back as metric arrays; only the driver writes the store.

Results store (directory ``DIR``)::

    DIR/sweep.json                       normalised configuration, its SHA-256, layout, columns
    DIR/chunks/chunk-000042.csv          one CSV per finished chunk (header + its rows)
    DIR/chunks/chunk-000042.csv.sha256   its SHA-256 (``sha256sum -c`` format)
    DIR/results.csv                      all rows in run order, assembled when every chunk is done
    DIR/.lock                            advisory lock held while a process works on DIR

Every file is written to a temporary name (:mod:`it2track.atomicfile`), flushed, ``fsync``-ed
and renamed (then the directory is ``fsync``-ed), so a chunk file exists only if it is complete:
killing the process at any moment loses at most the chunks being computed. ``resume`` checks the
configuration hash and skips the chunks on disk whose bytes still hash to their stored SHA-256
(an edited, torn or unverifiable chunk is computed again); temporaries are removed only if they
carry this package's temporary naming and their writer is dead, never a user's ``.*.tmp``. The
hash covers everything that determines the numbers and the chunk
layout -- including the it2track version and the bytes (not the paths) of controller and
trajectory files -- so a store is never extended with results of another configuration, an
edited file or another version of it2track. Floats are written with ``repr``, which
round-trips exactly, so ``results.csv`` is byte-identical however the sweep was interrupted,
chunked or distributed.

Why one CSV per chunk: appending to one file cannot be made atomic (a kill mid-append leaves a
torn row that a resume must detect and cut), while a rename is atomic on POSIX filesystems; a
chunk's file is its own completion marker, so no index file can disagree with the data; CSV needs
no extra dependency and opens anywhere; out-of-order completion (workers, Dask) needs no
coordination; and the final assembly is a plain concatenation in chunk order.
"""

from __future__ import annotations

import contextlib
import csv
import hashlib
import io
import itertools
import json
import math
import os
import socket
import stat
import sys
import time
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray
from tqdm import tqdm

from .. import __version__
from .._files import read_bytes
from .._limits import ResourceLimitError, check_memory, loop_bytes
from ..atomicfile import atomic_open, atomic_write_bytes, remove_stale_temporaries
from ..plant import RobotParams
from ..plant.noise import MAX_NOISE_STD
from ..tracking import (
    METRIC_NAMES,
    HeadingController,
    LoopConfig,
    RunTable,
    Trajectory,
    get_trajectory,
    simulate_metrics,
)
from ..tracking.simulate import MAX_INDEX
from ..tracking.trajectories import PAPER_TRAJECTORIES, WaypointTrajectory
from .executors import Executor, InProcessExecutor, peak_rss_bytes
from .specs import (
    ConfigError,
    ControllerKind,
    ControllerSpec,
    Table,
    loop_config_from_table,
    read_toml,
    robot_from_table,
)

__all__ = [
    "DEFAULT_BATCH_SIZE",
    "DEFAULT_CHUNK_SIZE",
    "STORE_FORMAT",
    "BuildableSpec",
    "ChunkResult",
    "ChunkSpec",
    "ControllerRef",
    "GridChunk",
    "StoreError",
    "SweepPlan",
    "SweepSummary",
    "TrajectoryRef",
    "chunk_path",
    "expand_axes",
    "grid_chunks",
    "load_sweep_config",
    "parse_noise_levels",
    "parse_seeds",
    "parse_trajectories",
    "read_results",
    "run_sweep",
    "simulate_grid_chunk",
]

FloatArray = NDArray[np.float64]

#: Identifies the store layout in ``sweep.json``.
STORE_FORMAT = "it2track-sweep/2"
#: Default number of runs per chunk (one ``simulate_metrics`` call, about 1-2 s of work).
DEFAULT_CHUNK_SIZE = 2000
DEFAULT_BATCH_SIZE = 4096


class StoreError(RuntimeError):
    """A results directory cannot be used: another sweep, a changed config, a held lock."""


class BuildableSpec(Protocol):
    """Anything that describes a controller as plain, picklable data."""

    @property
    def label(self) -> str: ...

    def build(self) -> HeadingController: ...

    def to_dict(self) -> dict[str, Any]: ...


# -- configuration helpers (shared with the optimiser) -------------------------------------------


def expand_axes(data: Mapping[str, Any], where: str) -> list[dict[str, Any]]:
    """Cartesian expansion of a table whose list values are axes.

    Keys keep their order; the first list-valued key varies slowest. Nested tables are returned
    untouched (expand them separately). An empty list is a :class:`ConfigError`.

    Examples
    --------
    >>> expand_axes({"kind": "it2", "fou": [0.1, 0.2], "ke": [1, 2]}, "f.toml")
    ... # doctest: +NORMALIZE_WHITESPACE
    [{'kind': 'it2', 'fou': 0.1, 'ke': 1}, {'kind': 'it2', 'fou': 0.1, 'ke': 2},
     {'kind': 'it2', 'fou': 0.2, 'ke': 1}, {'kind': 'it2', 'fou': 0.2, 'ke': 2}]
    """
    axes = {k: v for k, v in data.items() if isinstance(v, list)}
    for key, values in axes.items():
        if not values:
            raise ConfigError(f"{where}: {key}=[] is an empty axis (give at least one value)")
    combos = itertools.product(*axes.values()) if axes else [()]
    out = []
    for combo in combos:
        chosen = dict(zip(axes, combo, strict=True))
        out.append({k: chosen.get(k, v) for k, v in data.items()})
    return out


def parse_seeds(t: Table, key: str, default: Any = ...) -> tuple[int, ...]:
    """Seed indices: a count ``n`` (``0, 1, ..., n-1``), a list, or ``{start = s, count = n}``."""
    if key not in t:
        if default is ...:
            raise ConfigError(f"{t.where}: missing key {key!r}")
        return tuple(default)
    raw = t.data[key]
    what = f"{t.where}: {key}"
    if isinstance(raw, Mapping):
        sub = t.sub(key)
        start = sub.get("start", int, 0)
        count = sub.get("count", int)
        sub.done()
        if start < 0 or count < 1:
            raise ConfigError(f"{what}={dict(raw)!r} needs start >= 0 and count >= 1")
        if start + count - 1 > MAX_INDEX:
            raise ConfigError(
                f"{what}={dict(raw)!r}: seed indices must lie in [0, 2**63 - 1] (the last "
                f"would be {start + count - 1})"
            )
        _check_seed_count(count, what)
        return tuple(range(start, start + count))
    if isinstance(raw, list):
        seeds = t.get_list(key, int)
        if not seeds:
            raise ConfigError(f"{what}=[] is an empty axis (give at least one seed index)")
        bad = [s for s in seeds if s < 0]
        if bad:
            raise ConfigError(f"{what}={seeds!r}: seed indices must be >= 0 (got {bad[0]})")
        big = [s for s in seeds if s > MAX_INDEX]
        if big:
            raise ConfigError(
                f"{what}: seed index {big[0]!r} is larger than 2**63 - 1, the largest allowed"
            )
        if len(set(seeds)) != len(seeds):
            raise ConfigError(f"{what}={seeds!r}: seed indices must not repeat")
        return tuple(seeds)
    count = t.get(key, int)
    if count < 1:
        raise ConfigError(f"{what}={count!r} must be a seed count >= 1, a list or a table")
    if count - 1 > MAX_INDEX:
        raise ConfigError(f"{what}={count!r}: seed indices must lie in [0, 2**63 - 1]")
    _check_seed_count(count, what)
    return tuple(range(count))


def _check_seed_count(count: int, what: str) -> None:
    """The seed indices are held in memory several times (a tuple of ints, sets to compare
    them, the run tables: ~100 bytes per index): refuse counts that would not fit."""
    try:
        check_memory(100 * count, what=f"{what}: {count} seed indices",
                     hint="give fewer seeds")
    except ResourceLimitError as exc:
        raise ConfigError(str(exc)) from None


def parse_noise_levels(t: Table, key: str) -> tuple[float, ...]:
    """Heading-noise standard deviations (rad): a number or a non-empty list, each >= 0."""
    raw = t.data.get(key, ...)
    values = t.get_list(key, float) if isinstance(raw, list) else [t.get(key, float)]
    if not values:
        raise ConfigError(f"{t.where}: {key}=[] is an empty axis (give at least one value)")
    for v in values:
        if v < 0:
            raise ConfigError(f"{t.where}: {key} value {v!r} must be >= 0")
        if v > MAX_NOISE_STD:
            raise ConfigError(
                f"{t.where}: {key} value {v!r} exceeds {MAX_NOISE_STD:g} rad, the largest "
                "heading-noise standard deviation allowed (beyond it theta + noise loses all "
                "precision, and far beyond it overflows)"
            )
    if len(set(values)) != len(values):
        raise ConfigError(f"{t.where}: {key}={values!r}: values must not repeat")
    return tuple(values)


@dataclass(frozen=True)
class TrajectoryRef:
    """A trajectory named in a config: a built-in name or a CSV waypoint file.

    ``sha256`` (of the file's bytes) makes the configuration hash follow the file's content.
    """

    name: str
    path: str = ""
    sha256: str = ""

    def load(self) -> Trajectory:
        traj = get_trajectory(self.path or self.name)
        if isinstance(traj, WaypointTrajectory) and traj.name != self.name:
            traj = WaypointTrajectory(self.name, traj.times, traj.points, traj.kind)
        return traj

    def to_dict(self) -> dict[str, str]:
        """What identifies the trajectory (not where the file lives)."""
        if not self.path:
            return {"name": self.name, "source": "builtin"}
        return {"name": self.name, "source": "csv", "sha256": self.sha256}


def _file_sha256(path: str | Path) -> str:
    """SHA-256 of a regular file's bytes (hex); ``OSError`` if it cannot be read,
    :class:`~it2track._files.InputFileError` (a ``ValueError``) if it is not a regular file or
    too big."""
    return hashlib.sha256(read_bytes(path, what="input file")).hexdigest()


@dataclass(frozen=True)
class ControllerRef:
    """A controller of a sweep: its spec and, for kind ``file``, the SHA-256 of the file's bytes.

    The digest, not the path, identifies a file controller: the same file reached by another
    path (a relative or an absolute one, a moved checkout) is the same controller, an edited
    file is another. Small and picklable; :meth:`build` re-reads the file and refuses content
    that no longer matches the digest (a file edited while the sweep runs).

    Build with :meth:`from_spec`, which reads, hashes and builds the controller once.
    """

    spec: ControllerSpec
    sha256: str = ""

    def __post_init__(self) -> None:
        is_file = self.spec.kind is ControllerKind.FILE
        if is_file != bool(self.sha256):
            raise ValueError(
                "ControllerRef.sha256 is the digest of a 'file' controller's file "
                f"(and empty for other kinds); got kind {self.spec.kind.value!r}, "
                f"sha256={self.sha256!r}"
            )

    @classmethod
    def from_spec(cls, spec: ControllerSpec) -> ControllerRef:
        """Hash the controller's file (kind ``file``) and build the controller once.

        Raises
        ------
        ValueError
            If the controller cannot be built (a value its class rejects, a malformed file:
            :class:`~it2track.io.FisFormatError`, an unknown file suffix).
        OSError
            If the file cannot be read.
        """
        digest = _file_sha256(spec.path) if spec.kind is ControllerKind.FILE else ""
        ref = cls(spec, digest)
        ref.build()
        return ref

    @property
    def label(self) -> str:
        return self.spec.label

    @property
    def path(self) -> str:
        """The controller's file (kind ``file``), else ``""``."""
        return self.spec.path if self.sha256 else ""

    def build(self) -> HeadingController:
        """The controller; for a file, only if the file still has the planned content."""
        controller = self.spec.build()
        if self.sha256:
            now = _file_sha256(self.spec.path)
            if now != self.sha256:
                raise ValueError(
                    f"controller file {self.spec.path!r} changed since the sweep was planned "
                    f"(sha256 {self.sha256[:12]}, now {now[:12]}); results of the old and the "
                    "new controller must not be mixed: restore the file or start a new sweep"
                )
        return controller

    def to_dict(self) -> dict[str, Any]:
        """What identifies the controller: the spec's values, a file's digest for its path."""
        out = self.spec.to_dict()
        if self.sha256:
            del out["path"]
            out["file_sha256"] = self.sha256
        return out


def parse_trajectories(
    t: Table, key: str, base_dir: Path | None
) -> tuple[tuple[TrajectoryRef, ...], tuple[Trajectory, ...]]:
    """Trajectory names or CSV paths (relative to ``base_dir``); returns refs and the loaded
    trajectories. Unknown names, unreadable files and repeats are :class:`ConfigError`."""
    raw = t.data.get(key, ...)
    names = t.get_list(key, str) if isinstance(raw, list) else [t.get(key, str)]
    if not names:
        raise ConfigError(f"{t.where}: {key}=[] is an empty axis (give at least one trajectory)")
    refs: list[TrajectoryRef] = []
    loaded: list[Trajectory] = []
    for name in names:
        if name in PAPER_TRAJECTORIES:
            ref = TrajectoryRef(name)
        elif name.lower().endswith(".csv"):
            p = Path(name)
            if not p.is_absolute() and base_dir is not None:
                p = base_dir / p
            try:
                digest = _file_sha256(p)
            except OSError as exc:
                raise ConfigError(
                    f"{t.where}: {key}: cannot read {str(p)!r}: {exc.strerror or exc}"
                ) from None
            except ValueError as exc:
                raise ConfigError(f"{t.where}: {key}: {exc}") from None
            ref = TrajectoryRef(p.stem, str(p), digest)
        else:
            raise ConfigError(
                f"{t.where}: {key}: unknown trajectory {name!r}; use one of "
                f"{sorted(PAPER_TRAJECTORIES)} or a .csv waypoint file"
            )
        refs.append(ref)
    refs = _unique_trajectory_names(refs, f"{t.where}: {key}")
    for ref in refs:
        try:
            loaded.append(ref.load())
        except ValueError as exc:
            raise ConfigError(f"{t.where}: {key}: {exc}") from None
    return tuple(refs), tuple(loaded)


def _unique_trajectory_names(refs: list[TrajectoryRef], where: str) -> list[TrajectoryRef]:
    """Give CSV trajectories that share a file name distinct names (the name is their identity
    in rows, figures and hashes): ``a/path.csv`` and ``b/path.csv`` become ``a-path`` and
    ``b-path``, with as many parent folders as it takes. The same file or built-in twice is a
    :class:`ConfigError`."""
    keys = [(r.path and str(Path(r.path).resolve())) or r.name for r in refs]
    for i, k in enumerate(keys):
        if k in keys[:i]:
            raise ConfigError(
                f"{where}: {refs[i].path or refs[i].name!r} is listed twice (trajectories must "
                "not repeat)"
            )
    names = [r.name for r in refs]
    for depth in range(1, 64):
        clash = {n for n in names if names.count(n) > 1}
        if not clash:
            break
        for i, r in enumerate(refs):
            if names[i] in clash and r.path:
                parts = Path(keys[i]).parent.parts[-depth:]
                names[i] = "-".join([*(p.strip("/") or "root" for p in parts), r.name])
    else:  # pragma: no cover - needs 64 nested folders of identical names
        raise ConfigError(f"{where}: cannot give the trajectories distinct names: {names}")
    return [replace(r, name=n) for r, n in zip(refs, names, strict=True)]


def _positive_int(t: Table, key: str, default: int) -> int:
    value = t.get(key, int, default)
    if value < 1:
        raise ConfigError(f"{t.where}: {key}={value!r} must be an integer >= 1")
    return int(value)


def _parse_controllers(
    entries: Any, file: str, base_dir: Path | None
) -> tuple[ControllerRef, ...]:
    """The ``[[controllers]]`` entries, expanded, each built once (errors name the entry)."""
    if not isinstance(entries, list) or not entries:
        raise ConfigError(f"{file}: [[controllers]] must list at least one controller table")
    refs: list[ControllerRef] = []
    origin: dict[str, str] = {}
    for i, entry in enumerate(entries):
        where = f"{file} [controllers][{i}]"
        if not isinstance(entry, Mapping):
            raise ConfigError(f"{where}: expected a table, got {entry!r}")
        expanded = expand_axes(entry, where)
        if "label" in entry and len(expanded) > 1:
            raise ConfigError(
                f"{where}: label={entry['label']!r} cannot name {len(expanded)} controllers; "
                "drop it (labels are derived from the values) or split the entry"
            )
        for values in expanded:
            if isinstance(values.get("path"), str) and base_dir is not None:
                p = Path(values["path"])
                values["path"] = str(p if p.is_absolute() else base_dir / p)
            spec = ControllerSpec.from_table(values, where=where)
            if spec.label in origin:
                raise ConfigError(
                    f"{where}: controller {spec.label!r} repeats one of {origin[spec.label]}; "
                    "every controller of a sweep needs a distinct label"
                )
            origin[spec.label] = where
            try:
                ref = ControllerRef.from_spec(spec)
            except OSError as exc:
                raise ConfigError(
                    f"{where}: controller {spec.label!r}: cannot read {spec.path!r}: "
                    f"{exc.strerror or exc}"
                ) from None
            except ValueError as exc:
                raise ConfigError(f"{where}: controller {spec.label!r}: {exc}") from None
            refs.append(ref)
    return tuple(refs)


def _parse_robots(
    t: Table,
) -> tuple[tuple[RobotParams, ...], dict[str, tuple[float, ...]]]:
    """Plant parameter sets from ``[robot]`` / ``[robot.motor]`` with list-valued axes."""
    raw = dict(t.data)
    motor = raw.pop("motor", {})
    if not isinstance(motor, Mapping):
        raise ConfigError(f"{t.where}: motor={motor!r} must be a table [robot.motor]")
    flat = {**raw, **{f"motor.{k}": v for k, v in motor.items()}}
    axis_keys = [k for k, v in flat.items() if isinstance(v, list)]
    robots: list[RobotParams] = []
    columns: dict[str, list[float]] = {k: [] for k in axis_keys}
    for values in expand_axes(flat, t.where):
        top = {k: v for k, v in values.items() if not k.startswith("motor.")}
        mot = {k[6:]: v for k, v in values.items() if k.startswith("motor.")}
        table = Table({**top, **({"motor": mot} if mot or "motor" in t else {})}, t.file,
                      section="robot")
        robots.append(robot_from_table(table))
        for k in axis_keys:
            columns[k].append(values[k])
    return tuple(robots), {k: tuple(float(x) for x in v) for k, v in columns.items()}


# -- the plan: what to run, in which order, in which chunks --------------------------------------


@dataclass(frozen=True)
class ChunkSpec:
    """Chunk ``id`` covers runs ``group * runs_per_group + [start, stop)`` of its group."""

    id: int
    group: int
    start: int
    stop: int

    @property
    def size(self) -> int:
        return self.stop - self.start


@dataclass(frozen=True)
class GridChunk:
    """A self-contained piece of work: runs ``[start, stop)`` of the grid
    ``controllers x trajectories x noise_std x seeds`` (seed fastest) under ``config``.

    ``controllers`` holds only the specs this range uses: grid controller ``controller_offset
    + i`` is ``controllers[i]``. Small and picklable (specs, not arrays): this is what is
    shipped to worker processes and Dask workers.
    """

    chunk_id: int
    config: LoopConfig
    controllers: tuple[BuildableSpec, ...]
    controller_offset: int
    n_controllers: int
    trajectories: tuple[Trajectory, ...]
    noise_std: tuple[float, ...]
    seeds: tuple[int, ...]
    start: int
    stop: int
    batch_size: int = DEFAULT_BATCH_SIZE

    @property
    def size(self) -> int:
        return self.stop - self.start

    def runs(self) -> RunTable:
        """The chunk's runs, controller indices relative to ``controllers``."""
        shape = (self.n_controllers, len(self.trajectories), len(self.noise_std), len(self.seeds))
        c, t, n, s = np.unravel_index(np.arange(self.start, self.stop), shape)
        return RunTable(
            c - self.controller_offset,
            t,
            np.asarray(self.noise_std, dtype=np.float64)[n],
            np.asarray(self.seeds, dtype=np.int64)[s],
        )


@dataclass(frozen=True)
class ChunkResult:
    """Metrics of a :class:`GridChunk` (arrays of shape ``(chunk size,)``, in run order) and
    where/how it was computed."""

    chunk_id: int
    metrics: dict[str, FloatArray]
    worker: str
    peak_rss: int
    seconds: float


def simulate_grid_chunk(chunk: GridChunk) -> ChunkResult:
    """Worker function: build the chunk's controllers and run one ``simulate_metrics`` call."""
    t0 = time.perf_counter()
    controllers = [spec.build() for spec in chunk.controllers]
    metrics = simulate_metrics(
        controllers, chunk.trajectories, chunk.runs(), chunk.config, batch_size=chunk.batch_size
    )
    return ChunkResult(
        chunk_id=chunk.chunk_id,
        metrics=metrics,
        worker=f"{socket.gethostname()}:{os.getpid()}",
        peak_rss=peak_rss_bytes(),
        seconds=time.perf_counter() - t0,
    )


def grid_chunks(
    *,
    config: LoopConfig,
    controllers: Sequence[BuildableSpec],
    trajectories: Sequence[Trajectory],
    noise_std: Sequence[float],
    seeds: Sequence[int],
    bounds: Sequence[tuple[int, int]],
    batch_size: int = DEFAULT_BATCH_SIZE,
    first_id: int = 0,
) -> list[GridChunk]:
    """Tasks for the index ranges ``bounds`` of one grid (used by sweeps and the optimiser)."""
    per_controller = len(trajectories) * len(noise_std) * len(seeds)
    out: list[GridChunk] = []
    for k, (start, stop) in enumerate(bounds):
        c0 = start // per_controller
        c1 = (stop - 1) // per_controller + 1
        out.append(
            GridChunk(
                chunk_id=first_id + k,
                config=config,
                controllers=tuple(controllers[c0:c1]),
                controller_offset=c0,
                n_controllers=len(controllers),
                trajectories=tuple(trajectories),
                noise_std=tuple(float(v) for v in noise_std),
                seeds=tuple(int(s) for s in seeds),
                start=start,
                stop=stop,
                batch_size=batch_size,
            )
        )
    return out


def _fmt(value: Any) -> str:
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float):
        return repr(value)
    return str(value)


@dataclass(frozen=True)
class SweepPlan:
    """A parsed, validated sweep: the axes, the run order and the chunk layout.

    Build with :func:`load_sweep_config` (from TOML) or directly. ``config`` carries the
    simulation settings and the base seed; its ``robot`` is replaced by each of ``robots``.
    ``controllers`` are :class:`ControllerRef`; plain :class:`~.specs.ControllerSpec` entries
    are wrapped (hashed and built) by :meth:`ControllerRef.from_spec` on construction.
    """

    config: LoopConfig
    robots: tuple[RobotParams, ...]
    robot_columns: dict[str, tuple[float, ...]]
    controllers: tuple[ControllerRef, ...]
    trajectory_refs: tuple[TrajectoryRef, ...]
    noise_std: tuple[float, ...]
    seeds: tuple[int, ...]
    chunk_size: int = DEFAULT_CHUNK_SIZE
    batch_size: int = DEFAULT_BATCH_SIZE
    source: str = ""
    trajectories: tuple[Trajectory, ...] = field(default=(), compare=False, repr=False)

    def __post_init__(self) -> None:
        if not self.trajectories:
            object.__setattr__(
                self, "trajectories", tuple(r.load() for r in self.trajectory_refs)
            )
        object.__setattr__(self, "controllers", tuple(
            ControllerRef.from_spec(c) if isinstance(c, ControllerSpec) else c
            for c in self.controllers
        ))  # fmt: skip
        for name, seq in (
            ("robots", self.robots), ("controllers", self.controllers),
            ("trajectory_refs", self.trajectory_refs), ("noise_std", self.noise_std),
            ("seeds", self.seeds),
        ):  # fmt: skip
            if not seq:
                raise ValueError(f"SweepPlan.{name} must not be empty")
        for key, values in self.robot_columns.items():
            if len(values) != len(self.robots):
                raise ValueError(f"SweepPlan.robot_columns[{key!r}] needs one value per robot")
        for key in ("chunk_size", "batch_size"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f"SweepPlan.{key}={value!r} must be an integer >= 1")
        for group in range(len(self.robots)):  # each plant set with the simulation settings
            try:
                self.group_config(group)
            except ValueError as exc:
                raise ValueError(f"plant set {group} ([robot] values of run group {group}): "
                                 f"{exc}") from None
        self._check_memory()

    def _check_memory(self) -> None:
        """The chunk layout (~200 bytes per chunk) and one chunk in flight (its rows as text and
        lists, ~2 kB per run, plus one simulation batch) must fit in memory."""
        per_group = self.runs_per_group
        n_chunks = len(self.robots) * -(-per_group // self.chunk_size)
        chunk = min(self.chunk_size, per_group)
        need = 200 * n_chunks + 2048 * chunk + loop_bytes(
            n_steps=self.config.n_steps, runs=min(self.batch_size, chunk),
            trajectories=len(self.trajectory_refs),
            noise_samples=int(self.config.duration * self.config.noise_rate) + 1)
        check_memory(
            need,
            what=(f"the sweep of {self.n_runs} runs in {n_chunks} chunks of up to {chunk} runs "
                  f"(chunk_size={self.chunk_size}, batch_size={self.batch_size})"),
            hint="use fewer runs, or a chunk_size/batch_size that fits",
        )

    # -- sizes and order --------------------------------------------------------------------
    @property
    def runs_per_group(self) -> int:
        return (
            len(self.controllers) * len(self.trajectory_refs) * len(self.noise_std)
            * len(self.seeds)
        )  # fmt: skip

    @property
    def n_runs(self) -> int:
        return len(self.robots) * self.runs_per_group

    def chunks(self) -> list[ChunkSpec]:
        """The chunk layout: consecutive runs of one group, at most ``chunk_size`` each."""
        out: list[ChunkSpec] = []
        m = self.runs_per_group
        for g in range(len(self.robots)):
            for start in range(0, m, self.chunk_size):
                out.append(ChunkSpec(len(out), g, start, min(start + self.chunk_size, m)))
        return out

    def group_config(self, group: int) -> LoopConfig:
        return replace(self.config, robot=self.robots[group])

    def task(self, chunk: ChunkSpec) -> GridChunk:
        """The picklable work description of ``chunk``."""
        (task,) = grid_chunks(
            config=self.group_config(chunk.group),
            controllers=self.controllers,
            trajectories=self.trajectories,
            noise_std=self.noise_std,
            seeds=self.seeds,
            bounds=[(chunk.start, chunk.stop)],
            batch_size=self.batch_size,
            first_id=chunk.id,
        )
        return task

    # -- identity ---------------------------------------------------------------------------
    def normalised(self) -> dict[str, Any]:
        """Everything that determines the results and the chunk layout, as plain JSON data.

        Includes the it2track version and the SHA-256 of every controller and trajectory file.
        Excludes what cannot change a number: ``batch_size``, the executor, and where files
        live (the config's own path and the paths of the files it names).
        """
        simulation = self.config.to_dict()
        del simulation["robot"]  # the plant varies by group: "robots"
        return {
            "format": STORE_FORMAT,
            "it2track_version": __version__,
            "simulation": simulation,
            "robots": [asdict(r) for r in self.robots],
            "robot_columns": {k: list(v) for k, v in self.robot_columns.items()},
            "controllers": [c.to_dict() for c in self.controllers],
            "trajectories": [r.to_dict() for r in self.trajectory_refs],
            "noise_std": list(self.noise_std),
            "seeds": list(self.seeds),
            "chunk_size": self.chunk_size,
        }

    def config_hash(self) -> str:
        """SHA-256 of :meth:`normalised` (canonical JSON; floats by ``repr``, exact)."""
        return _hash_json(self.normalised())

    # -- rows -------------------------------------------------------------------------------
    def _controller_fields(self) -> list[str]:
        present: list[str] = []
        for ref in self.controllers:
            for key in ref.to_dict():
                if key not in ("kind", "label") and key not in present:
                    present.append(key)
        order = [f.name for f in ControllerSpec.__dataclass_fields__.values()]
        return sorted(present, key=lambda k: order.index(k) if k in order else len(order))

    @property
    def columns(self) -> list[str]:
        """Header of the chunk files and ``results.csv``."""
        return [
            "run", "group", *self.robot_columns, "controller", "label", "kind",
            *self._controller_fields(), "trajectory", "noise_std", "seed", *METRIC_NAMES,
        ]  # fmt: skip

    def header_csv(self) -> str:
        """The header line of the chunk files and ``results.csv``."""
        return ",".join(_csv_cell(c) for c in self.columns) + "\n"

    def rows_csv(self, chunk: ChunkSpec, metrics: Mapping[str, FloatArray]) -> str:
        """CSV text (no header) of ``chunk``'s rows; floats by ``repr`` (exact round-trip).

        Built column by column (the text cells of a controller are formatted once), the
        same bytes ``csv.writer`` would write, several times faster.
        """
        missing = [m for m in METRIC_NAMES if m not in metrics]
        if missing:
            raise ValueError(f"chunk {chunk.id}: metrics {missing} missing from the result")
        values = [np.asarray(metrics[m], dtype=np.float64) for m in METRIC_NAMES]
        if any(v.shape != (chunk.size,) for v in values):
            raise ValueError(f"chunk {chunk.id}: expected {chunk.size} values per metric")
        shape = (
            len(self.controllers), len(self.trajectory_refs), len(self.noise_std),
            len(self.seeds),
        )  # fmt: skip
        local = np.arange(chunk.start, chunk.stop)
        c, t, n, s = (a.tolist() for a in np.unravel_index(local, shape))
        base = chunk.group * self.runs_per_group
        fields = self._controller_fields()
        ctrl_text = []
        for k, spec in enumerate(self.controllers):
            d = spec.to_dict()
            cells = [str(k), spec.label, d["kind"], *(_fmt(d.get(f, "")) for f in fields)]
            ctrl_text.append(",".join(_csv_cell(x) for x in cells))
        robot = [_csv_cell(_fmt(v[chunk.group])) for v in self.robot_columns.values()]
        group_text = ",".join([str(chunk.group), *robot])
        traj = [_csv_cell(r.name) for r in self.trajectory_refs]
        noise = [_fmt(float(v)) for v in self.noise_std]
        seeds = [str(v) for v in self.seeds]
        columns = [
            [str(base + i) for i in local.tolist()],
            [group_text] * chunk.size,
            [ctrl_text[i] for i in c],
            [traj[i] for i in t],
            [noise[i] for i in n],
            [seeds[i] for i in s],
            *([repr(x) for x in v.tolist()] for v in values),
        ]
        return "".join(",".join(row) + "\n" for row in zip(*columns, strict=True))


def _csv_cell(text: str) -> str:
    """``text`` as ``csv.writer`` (QUOTE_MINIMAL, ``\\n`` line ends) writes a cell."""
    if not text:
        return ""  # (alone on a row, csv.writer would write '""')
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([text])
    return buf.getvalue()[:-1]


def _hash_json(data: Any) -> str:
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def load_sweep_config(path: str | Path) -> SweepPlan:
    """Parse a sweep TOML file (see the packaged config ``sweep``, :mod:`it2track.configs`).

    Sections: ``[sweep]`` (``seed``, ``seeds``, ``noise_std``, ``trajectories``, ``chunk_size``,
    ``batch_size``), ``[simulation]`` (:class:`~it2track.tracking.LoopConfig` fields),
    ``[robot]`` / ``[robot.motor]`` (list values are axes), ``[[controllers]]`` (list values
    are axes).

    Raises
    ------
    ConfigError
        Naming the file, the section and the key of an unknown key, a bad value or an empty
        axis.
    """
    path = Path(path)
    file = str(path)
    data = read_toml(path)
    root = Table(data, file, path.parent)
    st = root.sub("sweep")
    seed = st.get("seed", int, 0)
    if seed < 0:
        raise ConfigError(f"{st.where}: seed={seed!r} must be an integer >= 0")
    seeds = parse_seeds(st, "seeds")
    noise = parse_noise_levels(st, "noise_std")
    refs, trajectories = parse_trajectories(st, "trajectories", path.parent)
    chunk_size = _positive_int(st, "chunk_size", DEFAULT_CHUNK_SIZE)
    batch_size = _positive_int(st, "batch_size", DEFAULT_BATCH_SIZE)
    st.done()
    robots, robot_columns = _parse_robots(root.sub("robot"))
    config = loop_config_from_table(root.sub("simulation"), RobotParams(), seed=seed)
    if "controllers" not in data:
        raise ConfigError(f"{file}: missing [[controllers]] (at least one controller table)")
    root.used.add("controllers")
    controllers = _parse_controllers(data["controllers"], file, path.parent)
    root.done()
    try:
        return SweepPlan(
            config=config,
            robots=robots,
            robot_columns=robot_columns,
            controllers=controllers,
            trajectory_refs=refs,
            noise_std=noise,
            seeds=seeds,
            chunk_size=chunk_size,
            batch_size=batch_size,
            source=file,
            trajectories=trajectories,
        )
    except ValueError as exc:  # e.g. the plan would not fit in memory
        raise ConfigError(f"{file}: {exc}") from None


# -- the store -----------------------------------------------------------------------------------


@contextlib.contextmanager
def _locked(out: Path) -> Iterator[None]:
    """Hold an exclusive advisory lock on ``out/.lock`` (POSIX; released if we die)."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows: no locking
        yield
        return
    flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(out / ".lock", flags, 0o644)
    except OSError as exc:
        raise StoreError(f"{out / '.lock'}: cannot open the sweep's lock file: {exc}") from None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            raise StoreError(f"{out}: another process is working on this sweep") from None
        yield
    finally:
        os.close(fd)


def chunk_path(out: Path, chunk_id: int) -> Path:
    return out / "chunks" / f"chunk-{chunk_id:06d}.csv"


def digest_path(chunk_file: Path) -> Path:
    """The checksum file of a chunk: ``chunk-000042.csv.sha256`` (``sha256sum -c`` format)."""
    return chunk_file.with_name(chunk_file.name + ".sha256")


def _digest_line(chunk_file: Path, digest: str) -> bytes:
    return f"{digest}  {chunk_file.name}\n".encode("ascii")


def _write_chunk(path: Path, data: bytes) -> None:
    """The chunk file, then its checksum file (each atomically): a chunk counts as done only
    when both exist and agree, so a kill between the two only costs a recomputation."""
    atomic_write_bytes(path, data)
    atomic_write_bytes(digest_path(path), _digest_line(path, hashlib.sha256(data).hexdigest()))


def _read_regular(path: Path) -> bytes | None:
    """The bytes of a regular file (never following a symbolic link), or None."""
    try:
        st = os.lstat(path)
        if not stat.S_ISREG(st.st_mode):
            return None
        return path.read_bytes()
    except OSError:
        return None


def _chunk_digest(path: Path, header: str, size: int) -> str | None:
    """The SHA-256 of ``path`` if it is a complete, unaltered chunk, else None.

    Complete: our header and ``size`` rows; unaltered: its bytes hash to the digest stored in
    its ``.sha256`` file when it was written. A missing, torn or edited chunk (or checksum
    file) gives None: the chunk is computed again.
    """
    data = _read_regular(path)
    stored = _read_regular(digest_path(path))
    if data is None or stored is None:
        return None
    digest = hashlib.sha256(data).hexdigest()
    if stored != _digest_line(path, digest):
        return None
    if not (
        data.startswith(header.encode("utf-8"))
        and data.endswith(b"\n")
        and data.count(b"\n") == size + 1
    ):
        return None
    return digest


def _describe_change(old: Mapping[str, Any], new: Mapping[str, Any]) -> str:
    keys = sorted(k for k in set(old) | set(new) if old.get(k) != new.get(k))
    return ", ".join(keys) or "(store format)"


def _changed_files(meta: Mapping[str, Any], plan: SweepPlan) -> list[str]:
    """Sentences naming the controller and trajectory files whose content changed."""
    old = meta.get("config", {})

    def digests(section: str, key: str, digest_key: str) -> dict[str, str]:
        entries = old.get(section, [])
        return {
            str(e[key]): str(e[digest_key])
            for e in entries if isinstance(e, Mapping) and key in e and digest_key in e
        }  # fmt: skip

    controllers = digests("controllers", "label", "file_sha256")
    trajectories = digests("trajectories", "name", "sha256")
    out: list[str] = []
    for c in plan.controllers:
        before = controllers.get(c.label)
        if c.path and before is not None and before != c.sha256:
            out.append(
                f"controller file {c.path!r} ([[controllers]] {c.label!r}) has changed: sha256 "
                f"{before[:12]} when the sweep started, now {c.sha256[:12]}"
            )
    for r in plan.trajectory_refs:
        before = trajectories.get(r.name)
        if r.path and before is not None and before != r.sha256:
            out.append(
                f"trajectory file {r.path!r} has changed: sha256 {before[:12]} when the sweep "
                f"started, now {r.sha256[:12]}"
            )
    return out


@dataclass(frozen=True)
class SweepSummary:
    """What :func:`run_sweep` did."""

    out: Path
    n_runs: int
    n_chunks: int
    chunks_computed: int
    chunks_skipped: int
    runs_computed: int
    seconds: float
    driver_peak_rss: int
    worker_peak_rss: int
    workers: tuple[str, ...]

    @property
    def runs_per_second(self) -> float:
        return self.runs_computed / self.seconds if self.seconds > 0 else math.nan


def _prepare_store(plan: SweepPlan, out: Path, *, resume: bool) -> None:
    meta_path = out / "sweep.json"
    normalised = plan.normalised()
    digest = _hash_json(normalised)
    if meta_path.exists():
        if not resume:
            raise StoreError(
                f"{out} already holds a sweep; pass resume (--resume) to continue it, "
                "or choose another directory"
            )
        try:
            meta = json.loads(meta_path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise StoreError(f"{meta_path}: unreadable sweep metadata: {exc}") from None
        if meta.get("format") != STORE_FORMAT:
            raise StoreError(f"{meta_path}: format {meta.get('format')!r} is not {STORE_FORMAT}")
        version = meta.get("it2track_version")
        if version != __version__:
            raise StoreError(
                f"{out}: the sweep was started by it2track {version}, this is it2track "
                f"{__version__}; results of two versions must not be mixed in one store: "
                f"finish it with it2track {version} or use another directory"
            )
        if meta.get("hash") != digest:
            changed = _describe_change(meta.get("config", {}), normalised)
            details = "".join(f"; {s}" for s in _changed_files(meta, plan))
            raise StoreError(
                f"{out}: the configuration changed since the sweep started (stored hash "
                f"{str(meta.get('hash'))[:12]}, now {digest[:12]}; differs in: {changed})"
                f"{details}; resume with the original config and files or use another "
                "directory"
            )
        return
    leftovers = sorted(p.name for p in (out / "chunks").glob("chunk-*.csv"))
    if leftovers:
        raise StoreError(
            f"{out}: chunks/ holds {len(leftovers)} chunk file(s) (e.g. {leftovers[0]}) but no "
            "sweep.json; they belong to an unknown sweep: remove them or use another directory"
        )
    meta = {
        "format": STORE_FORMAT,
        "hash": digest,
        "config": normalised,
        "n_runs": plan.n_runs,
        "n_chunks": len(plan.chunks()),
        "columns": plan.columns,
        "run_order": ["group", "controller", "trajectory", "noise_std", "seed"],
        "source": plan.source,
        "trajectory_files": {r.name: r.path for r in plan.trajectory_refs if r.path},
        "controller_files": {c.label: c.path for c in plan.controllers if c.path},
        "it2track_version": __version__,
    }
    text = json.dumps(meta, indent=1, allow_nan=False) + "\n"
    atomic_write_bytes(meta_path, text.encode("utf-8"))


def _assemble(plan: SweepPlan, out: Path, header: str, digests: Mapping[int, str]) -> None:
    """``results.csv``: the header, then every chunk's rows in run order (streamed).

    Each chunk is hashed while it is copied and must still have the digest it had when it was
    verified or written (``digests``): a chunk changed meanwhile stops the assembly.
    """
    with atomic_open(out / "results.csv", "wb") as dst:
        dst.write(header.encode("utf-8"))
        for chunk in plan.chunks():
            path = chunk_path(out, chunk.id)
            h = hashlib.sha256()
            with open(path, "rb") as src:
                first = src.readline()  # the chunk's header
                h.update(first)
                while block := src.read(1 << 20):
                    h.update(block)
                    dst.write(block)
            if h.hexdigest() != digests[chunk.id]:
                raise StoreError(
                    f"{path} changed while the sweep was assembling results.csv (sha256 "
                    f"{digests[chunk.id][:12]} expected, {h.hexdigest()[:12]} found); "
                    "rerun with --resume to recompute it"
                )


def run_sweep(
    plan: SweepPlan,
    out: str | Path,
    *,
    executor: Executor | None = None,
    resume: bool = False,
    progress: bool = True,
    max_pending: int | None = None,
) -> SweepSummary:
    """Run (or resume) ``plan`` into the store ``out``; see the module docstring.

    Parameters
    ----------
    plan : SweepPlan
    out : path
        Store directory (created if missing).
    executor : Executor, optional
        Where chunks run; default :class:`~.executors.InProcessExecutor`. Not closed here.
    resume : bool
        Continue the sweep already in ``out`` (its configuration hash must match); without it,
        an existing sweep in ``out`` is an error.
    progress : bool
        Show a tqdm bar with ETA on stderr.

    Raises
    ------
    StoreError
        If ``out`` holds another sweep, a different configuration, or is locked.
    """
    executor = executor or InProcessExecutor()
    out = Path(out)
    (out / "chunks").mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    with _locked(out):
        _prepare_store(plan, out, resume=resume)
        header_line = plan.header_csv()
        chunks = plan.chunks()
        # Temporaries a killed run of ours left (our naming, dead writer); nothing else.
        remove_stale_temporaries(out, ("sweep.json", "results.csv"))
        names = {chunk_path(out, c.id).name for c in chunks}
        remove_stale_temporaries(out / "chunks", names | {n + ".sha256" for n in names})
        digests: dict[int, str] = {}
        todo = []
        for c in chunks:
            digest = _chunk_digest(chunk_path(out, c.id), header_line, c.size)
            if digest is None:
                todo.append(c)
            else:
                digests[c.id] = digest
        done_runs = plan.n_runs - sum(c.size for c in todo)
        by_id = {c.id: c for c in todo}
        workers: set[str] = set()
        worker_rss = 0
        runs_computed = 0
        bar = tqdm(
            total=plan.n_runs, initial=done_runs, unit="run", desc="sweep",
            disable=not progress, file=sys.stderr, dynamic_ncols=True,
        )  # fmt: skip
        try:
            tasks = (plan.task(c) for c in todo)
            for task, result in executor.imap_unordered(
                simulate_grid_chunk, tasks, max_pending=max_pending
            ):
                chunk = by_id[task.chunk_id]
                data = (header_line + plan.rows_csv(chunk, result.metrics)).encode("utf-8")
                _write_chunk(chunk_path(out, chunk.id), data)
                digests[chunk.id] = hashlib.sha256(data).hexdigest()
                workers.add(result.worker)
                worker_rss = max(worker_rss, result.peak_rss)
                runs_computed += chunk.size
                bar.update(chunk.size)
        finally:
            bar.close()
        _assemble(plan, out, header_line, digests)
    return SweepSummary(
        out=out,
        n_runs=plan.n_runs,
        n_chunks=len(chunks),
        chunks_computed=len(todo),
        chunks_skipped=len(chunks) - len(todo),
        runs_computed=runs_computed,
        seconds=time.perf_counter() - t0,
        driver_peak_rss=peak_rss_bytes(),
        worker_peak_rss=worker_rss,
        workers=tuple(sorted(workers)),
    )


def read_results(path: str | Path) -> tuple[list[str], list[list[str]]]:
    """Header and rows of a results or chunk CSV file (strings; ``float(cell)`` is exact)."""
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    return rows[0], rows[1:]

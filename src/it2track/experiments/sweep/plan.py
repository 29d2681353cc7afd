"""A parsed sweep, :class:`SweepPlan`: its axes, the run order, the chunk layout
(:class:`ChunkSpec`), its identity (the configuration hash) and the CSV text of its rows.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, replace
from numbers import Integral, Real
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ... import __version__
from ..._limits import check_memory, loop_bytes
from ...plant import RobotParams
from ...plant.noise import MAX_NOISE_STD
from ...tracking import METRIC_NAMES, LoopConfig, Target
from ...tracking.simulate import MAX_INDEX
from ..specs import ControllerSpec
from .chunks import DEFAULT_BATCH_SIZE, GridChunk, grid_chunks
from .refs import ControllerRef, TrajectoryRef

__all__ = ["DEFAULT_CHUNK_SIZE", "STORE_FORMAT", "ChunkSpec", "SweepPlan"]

FloatArray = NDArray[np.float64]


#: Identifies the store layout in ``sweep.json``.
STORE_FORMAT = "it2track-sweep/2"


#: Default number of runs per chunk (one ``simulate_metrics`` call, about 1-2 s of work).
DEFAULT_CHUNK_SIZE = 2000


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


def _fmt(value: Any) -> str:
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float):
        return repr(value)
    return str(value)


@dataclass(frozen=True)
class SweepPlan:
    """A parsed, validated sweep: the axes, the run order and the chunk layout.

    Build with :func:`.load_sweep_config` (from TOML) or directly. ``config`` carries the
    simulation settings and the base seed; its ``robot`` is replaced by each of ``robots``.
    ``controllers`` are :class:`.ControllerRef`; plain :class:`~.specs.ControllerSpec` entries
    are wrapped (hashed and built) by :meth:`.ControllerRef.from_spec` on construction.
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
    trajectories: tuple[Target, ...] = field(default=(), compare=False, repr=False)

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
        self._check_axes()
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

    def _check_axes(self) -> None:
        """Noise levels in ``[0, MAX_NOISE_STD]`` and seed indices in ``[0, 2**63 - 1]``, each
        once (as :func:`.load_sweep_config` checks a file's); stored as plain floats and ints."""
        for v in self.noise_std:
            if isinstance(v, bool) or not isinstance(v, Real) or not 0 <= v <= MAX_NOISE_STD:
                raise ValueError(f"SweepPlan.noise_std value {v!r} must be a number in "
                                 f"[0, {MAX_NOISE_STD:g}] rad (a heading-noise standard deviation)")
        for s in self.seeds:
            if isinstance(s, bool) or not isinstance(s, Integral) or not 0 <= s <= MAX_INDEX:
                raise ValueError(f"SweepPlan.seeds value {s!r} must be an integer in "
                                 "[0, 2**63 - 1] (a seed index)")
        for name, seq in (("noise_std", self.noise_std), ("seeds", self.seeds)):
            if len(set(seq)) != len(seq):
                raise ValueError(f"SweepPlan.{name}={seq!r} must not repeat a value")
        object.__setattr__(self, "noise_std", tuple(float(v) for v in self.noise_std))
        object.__setattr__(self, "seeds", tuple(int(s) for s in self.seeds))

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

    def row_keys(self, chunk: ChunkSpec) -> list[str]:
        """The identifying cells of ``chunk``'s rows as CSV text, one string per run: run id,
        group, plant columns, controller columns, trajectory, noise level and seed (every
        column before the metrics). What a resume checks a stored chunk's rows against."""
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
        return [
            f"{base + i},{group_text},{ctrl_text[ci]},{traj[ti]},{noise[ni]},{seeds[si]}"
            for i, ci, ti, ni, si in zip(local.tolist(), c, t, n, s, strict=True)
        ]

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
        columns = [self.row_keys(chunk), *([repr(x) for x in v.tolist()] for v in values)]
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

"""Batched closed-loop simulation of the paper's control scheme (Fig. 3, DESIGN.md sec. 5).

One call advances ``B`` runs in lock-step as numpy arrays. A run is one combination of a
heading controller, a reference trajectory, a noise level and a noise realisation (seed index);
:class:`RunTable` lists them and :func:`run_grid` builds the cartesian product. Shared physics
(period, duration, robot, noise rate, start pose, base seed) lives in :class:`LoopConfig`.

At control instant ``k`` (``t_k = k ts``, ``k = 0 ... N``) every run:

1. computes ``theta_d = atan2(y_d(t_k) - y_k, x_d(t_k) - x_k)`` from the pose the previous period
   produced and the reference point at ``t_k`` (or, with ``LoopConfig.desired_heading_pose =
   PoseTiming.PREVIOUS``, from the pose one period older, the paper's literal ``y(k - 1)``);
2. measures ``theta_hat = theta_k + sigma z[j(t_k)]`` (Gaussian noise held at the noise rate)
   and forms ``e_k = wrap(theta_d - theta_hat)`` in ``(-pi, pi]`` and
   ``de_k = wrap(e_k - e_(k-1))`` (``de_0 = 0``);
3. evaluates its controller, ``u = controller.output(e, de, state)``;
4. sets ``V_R = sat(V0 + u)``, ``V_L = sat(V0 - u)`` with the feed-forward ``V0`` that runs the
   wheels at the reference speed ``|p_d'(t_k)| / r`` in steady state;
5. advances motors and pose by one period with the voltages held (``k < N``).

Noise uses common random numbers: the standard-normal sequence ``z`` of a run depends only on
``(config.seed, run seed index)``, so every controller, trajectory and noise level with the same
seed index sees the same sequence, scaled by its ``sigma``; each distinct seed's sequence is
drawn once per call (:class:`~it2track.plant.noise.NoiseRows`), and not at all for
``sigma = 0`` runs, whose noise is ``+0.0``. Every operation is elementwise over
the batch, so a run's numbers are bit-for-bit the same whatever the batch it is computed in.

Outputs: :func:`simulate` returns a :class:`Trace` of time series (arrays ``(B, N+1)``, runs
first, then time); :func:`simulate_metrics` streams runs through in chunks of ``batch_size`` and
keeps only the metrics (``dict`` of ``(B,)`` arrays), so memory stays flat as ``B`` grows.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from numbers import Integral, Real
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._limits import ResourceLimitError, check_memory, loop_bytes
from ..plant import DifferentialDrive, RobotParams, held_sample_index
from ..plant.drive import MAX_QUADRATURE_NODES, check_stiffness
from ..plant.noise import MAX_NOISE_STD, NoiseRows
from . import compiled as _compiled
from .actuation import Actuation
from .controllers import HeadingController
from .libm import atan2
from .loopdefs import TRACE_FIELDS, PoseTiming, noise_rows
from .metrics import MetricAccumulator
from .trajectories import Trajectory

__all__ = [
    "ON_PATH",
    "TRACE_FIELDS",
    "LoopConfig",
    "PoseTiming",
    "RunTable",
    "Trace",
    "run_grid",
    "simulate",
    "simulate_metrics",
    "wrap_angle",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

TWO_PI = 2.0 * math.pi
#: Upper bound on the control periods (and held noise samples) of one run: 1e12 instants are
#: 8 TB per recorded row; anything near it is refused by the memory estimate first.
_MAX_STEPS = 1e12


def wrap_angle(a: ArrayLike) -> FloatArray:
    """Wrap angles to ``(-pi, pi]`` (a new array; the input is not modified).

    Angles already in ``(-pi, pi]`` are returned unchanged (bit for bit); ``-pi`` maps to
    ``pi``. Others are reduced modulo the float ``2 pi`` (an absolute rounding error of a few
    ulp of ``|a|``).

    Examples
    --------
    >>> import numpy as np
    >>> wrap_angle(np.array([np.pi, -np.pi, 3 * np.pi / 2])).round(6).tolist()
    [3.141593, 3.141593, -1.570796]
    """
    return _wrap_inplace(np.array(a, dtype=np.float64, copy=True))


def _wrap_inplace(a: FloatArray) -> FloatArray:
    """:func:`wrap_angle` in place on a float64 array (elementwise, so batch-independent)."""
    outside = a <= -math.pi
    outside |= a > math.pi
    if outside.any():
        w = math.pi - np.mod(math.pi - a[outside], TWO_PI)
        w[w <= -math.pi] = math.pi  # np.mod may round up to 2 pi (a just above pi + 2 pi m)
        a[outside] = w
    return a


#: ``LoopConfig.start_pose`` value that starts each run on its reference path (see there).
ON_PATH = "on_path"


@dataclass(frozen=True, kw_only=True)
class LoopConfig:
    """Physics and timing shared by every run of a batch.

    Parameters
    ----------
    duration : float
        Simulated time T, s (default 10).
    ts : float
        Control period, s (default 0.01); ``T / ts`` must be an integer N.
    robot : RobotParams
        Robot and motor parameters (paper Table 3 by default).
    noise_rate : float
        Rate at which the heading noise is resampled and held, Hz (default 100).
    start_pose : (float, float, float) or "on_path"
        Initial ``(x, y, theta)``; the robot starts at rest. :data:`ON_PATH` (``"on_path"``)
        starts every run at its reference point at ``t = 0`` with the reference's tangent
        heading ``atan2(y_d'(0), x_d'(0))``.
    seed : int
        Base seed of the noise realisations (>= 0).
    quadrature_nodes : int
        Nodes per period of the position integral, 1 to 64 (see :class:`DifferentialDrive`).
    desired_heading_pose : PoseTiming or str
        Pose ``theta_d`` is computed from (see :class:`.PoseTiming`; default ``"current"``).
    metric_start : float
        Start of the window of the heading-error integrals (IAE ... ITSE and their ``_meas``
        forms), s: they integrate over ``[metric_start, duration]`` (ITAE/ITSE still weight
        by the absolute time ``t``). A whole number of periods in ``[0, duration)``;
        default 0 (the whole run).
    """

    duration: float = 10.0
    ts: float = 0.01
    robot: RobotParams = field(default_factory=RobotParams)
    noise_rate: float = 100.0
    start_pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    seed: int = 0
    quadrature_nodes: int = 4
    desired_heading_pose: PoseTiming = PoseTiming.CURRENT
    metric_start: float = 0.0

    def __post_init__(self) -> None:
        for key in ("duration", "ts", "noise_rate"):
            value = getattr(self, key)
            if (
                isinstance(value, bool)
                or not isinstance(value, Real)
                or not math.isfinite(value)
                or value <= 0
            ):
                raise ValueError(f"LoopConfig.{key}={value!r} must be a finite number > 0")
            object.__setattr__(self, key, float(value))
        n = self.duration / self.ts
        if not n <= _MAX_STEPS:  # also inf: round() would overflow
            raise ResourceLimitError(
                f"LoopConfig: duration={self.duration!r} s at ts={self.ts!r} s is {n:.3g} "
                f"control periods, more than the {_MAX_STEPS:.0e} any run can hold in memory"
            )
        if abs(n - round(n)) > 1e-9 * max(1.0, n):
            raise ValueError(
                f"LoopConfig: duration={self.duration!r} must be a whole number of periods "
                f"ts={self.ts!r}"
            )
        if isinstance(self.start_pose, str):
            if self.start_pose != ON_PATH:
                raise ValueError(f"LoopConfig.start_pose={self.start_pose!r} must be 3 finite "
                                 f"numbers or {ON_PATH!r}")
        else:
            try:
                pose = tuple(float(v) for v in self.start_pose)
            except (TypeError, ValueError):
                pose = ()
            if len(pose) != 3 or not all(math.isfinite(v) for v in pose):
                raise ValueError(f"LoopConfig.start_pose={self.start_pose!r} must be 3 finite "
                                 f"numbers or {ON_PATH!r}")
            object.__setattr__(self, "start_pose", pose)
        timing = self.desired_heading_pose
        if not isinstance(timing, PoseTiming):
            try:
                timing = PoseTiming(timing)
            except ValueError:
                raise ValueError(
                    f"LoopConfig.desired_heading_pose={timing!r} must be one of "
                    f"{[t.value for t in PoseTiming]}"
                ) from None
            object.__setattr__(self, "desired_heading_pose", timing)
        start = self.metric_start
        if isinstance(start, bool) or not isinstance(start, Real) or not math.isfinite(start):
            raise ValueError(f"LoopConfig.metric_start={start!r} must be a finite number")
        start = float(start)
        k0 = start / self.ts
        if not 0.0 <= start < self.duration or abs(k0 - round(k0)) > 1e-9 * max(1.0, k0):
            raise ValueError(
                f"LoopConfig.metric_start={start!r} must be a whole number of periods "
                f"ts={self.ts!r} in [0, duration={self.duration!r})"
            )
        object.__setattr__(self, "metric_start", start)
        if isinstance(self.seed, bool) or not isinstance(self.seed, Integral) or self.seed < 0:
            raise ValueError(f"LoopConfig.seed={self.seed!r} must be an integer >= 0")
        object.__setattr__(self, "seed", int(self.seed))
        q = self.quadrature_nodes
        if (isinstance(q, bool) or not isinstance(q, Integral)
                or not 1 <= q <= MAX_QUADRATURE_NODES):
            raise ValueError(
                f"LoopConfig.quadrature_nodes={q!r} must be an integer in "
                f"[1, {MAX_QUADRATURE_NODES}]"
            )
        object.__setattr__(self, "quadrature_nodes", int(q))
        if not isinstance(self.robot, RobotParams):
            raise ValueError(f"LoopConfig.robot={self.robot!r} must be a RobotParams")
        self._check_memory()
        check_stiffness(self.robot, self.ts)  # the plant's precomputation must terminate

    def _check_memory(self) -> None:
        """One run of this config must fit in memory (the arrays grow with duration/ts and
        duration*noise_rate): refuse now rather than with a MemoryError mid-run."""
        samples = self.duration * self.noise_rate + 1
        if not samples <= _MAX_STEPS:
            raise ResourceLimitError(
                f"LoopConfig: noise_rate={self.noise_rate!r} Hz over duration={self.duration!r} s "
                f"is {samples:.3g} held noise samples per run, more than the {_MAX_STEPS:.0e} "
                "any run can hold in memory"
            )
        check_memory(
            loop_bytes(n_steps=self.n_steps, runs=1, noise_samples=int(samples)),
            what=(f"LoopConfig: duration={self.duration!r} s at ts={self.ts!r} s "
                  f"({self.n_steps} control periods, noise_rate={self.noise_rate!r} Hz)"),
            hint="one run of it would not fit: shorten duration or lengthen ts",
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain values (JSON/TOML-ready), the robot as a nested dict."""
        return {
            "duration": self.duration, "ts": self.ts, "noise_rate": self.noise_rate,
            "start_pose": (self.start_pose if isinstance(self.start_pose, str)
                           else list(self.start_pose)),
            "seed": self.seed, "quadrature_nodes": self.quadrature_nodes,
            "desired_heading_pose": self.desired_heading_pose.value,
            "metric_start": self.metric_start, "robot": dataclasses.asdict(self.robot),
        }  # fmt: skip

    @property
    def n_steps(self) -> int:
        """Number of control periods N (instants ``k = 0 ... N``)."""
        return round(self.duration / self.ts)

    @property
    def metric_start_index(self) -> int:
        """First control instant ``k`` inside the error-integral window."""
        return round(self.metric_start / self.ts)

    @property
    def times(self) -> FloatArray:
        """Control instants ``t_k = k ts``, shape ``(N+1,)``."""
        times: FloatArray = np.arange(self.n_steps + 1, dtype=np.float64)
        times *= self.ts
        return times


@dataclass(frozen=True, eq=False)
class RunTable:
    """The runs of a batch, one entry per run (all arrays shape ``(B,)``).

    Attributes
    ----------
    controller : ndarray of int
        Index into the ``controllers`` sequence given to :func:`simulate`.
    trajectory : ndarray of int
        Index into the ``trajectories`` sequence.
    noise_std : ndarray of float
        Heading-noise standard deviation, rad (>= 0).
    seed : ndarray of int
        Noise realisation index (>= 0) under ``LoopConfig.seed``.
    """

    controller: IntArray
    trajectory: IntArray
    noise_std: FloatArray
    seed: IntArray

    def __init__(
        self,
        controller: ArrayLike,
        trajectory: ArrayLike,
        noise_std: ArrayLike,
        seed: ArrayLike,
    ) -> None:
        given = {
            name: _plain_array(value, name)
            for name, value in (("controller", controller), ("trajectory", trajectory),
                                ("noise_std", noise_std), ("seed", seed))
        }
        try:
            arrays = np.broadcast_arrays(*given.values())
        except ValueError:
            shapes = ", ".join(f"{k} {v.shape}" for k, v in given.items())
            raise ValueError(
                f"RunTable: the columns must broadcast together; got {shapes}"
            ) from None
        c, t, s, z = (np.ascontiguousarray(a).reshape(-1) for a in arrays)
        c, t, z = (_index_column(a, name) for a, name in
                   ((c, "controller"), (t, "trajectory"), (z, "seed")))
        s = _noise_column(s)
        object.__setattr__(self, "controller", c.astype(np.int64))
        object.__setattr__(self, "trajectory", t.astype(np.int64))
        object.__setattr__(self, "noise_std", s)
        object.__setattr__(self, "seed", z.astype(np.int64))

    def __len__(self) -> int:
        return int(self.controller.size)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, RunTable):
            return NotImplemented
        return all(
            np.array_equal(getattr(self, k), getattr(other, k))
            for k in ("controller", "trajectory", "noise_std", "seed")
        )

    __hash__ = None  # type: ignore[assignment]  # mutable arrays inside

    def take(self, index: ArrayLike | slice) -> RunTable:
        """The runs at ``index`` (an int array or a slice object)."""
        idx = index if isinstance(index, slice) else np.asarray(index)
        return RunTable(
            self.controller[idx], self.trajectory[idx], self.noise_std[idx], self.seed[idx]
        )


#: Largest seed index or controller/trajectory index a run may have (int64).
MAX_INDEX = 2**63 - 1


def _plain_array(value: ArrayLike, name: str) -> NDArray[Any]:
    """``np.asarray`` that refuses what it would silently change: masked entries."""
    if isinstance(value, np.ma.MaskedArray):
        if np.ma.getmaskarray(value).any():
            raise ValueError(
                f"RunTable.{name} is a masked array with masked entries; give plain values "
                "(the mask would be dropped)"
            )
        value = value.data
    try:
        return np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged nested sequences
        raise ValueError(f"RunTable.{name}={value!r} is not an array of numbers: {exc}") from None


def _index_column(arr: NDArray[Any], name: str) -> NDArray[Any]:
    """Integers in ``[0, MAX_INDEX]``; Python ints beyond int64 are named, not truncated."""
    if not arr.size:
        return arr.astype(np.int64)
    if arr.dtype == object:
        bad = next((v for v in arr.tolist()
                    if isinstance(v, bool) or not isinstance(v, Integral)), None)
        if bad is not None:
            raise ValueError(f"RunTable.{name} must hold integers >= 0, got {bad!r}")
        out = next((v for v in arr.tolist() if not 0 <= v <= MAX_INDEX), None)
        if out is not None:
            raise ValueError(
                f"RunTable.{name} value {out!r} is outside the allowed range [0, 2**63 - 1]"
            )
        return arr.astype(np.int64)
    if arr.dtype.kind not in "iu":
        example = arr.reshape(-1)[:1].tolist()[0]
        raise ValueError(
            f"RunTable.{name} must hold integers >= 0, got {arr.dtype} values (e.g. {example!r})"
        )
    low, high = arr.min(), arr.max()
    if low < 0:
        raise ValueError(f"RunTable.{name} must hold integers >= 0, got {int(low)}")
    if int(high) > MAX_INDEX:
        raise ValueError(
            f"RunTable.{name} value {int(high)} is outside the allowed range [0, 2**63 - 1]"
        )
    return arr


def _noise_column(arr: NDArray[Any]) -> FloatArray:
    """Real noise levels in ``[0, MAX_NOISE_STD]`` rad as float64."""
    if arr.size and arr.dtype.kind not in "iuf":
        example = arr.reshape(-1)[:1].tolist()[0]
        raise ValueError(
            f"RunTable.noise_std must hold real numbers, got {arr.dtype} values "
            f"(e.g. {example!r})"
        )
    s = arr.astype(np.float64)
    if s.size:
        if not np.isfinite(s).all():
            bad = float(s[~np.isfinite(s)][0])
            raise ValueError(f"RunTable.noise_std value {bad!r} must be finite")
        if s.min() < 0:
            raise ValueError(f"RunTable.noise_std value {float(s.min())!r} must be >= 0")
        if s.max() > MAX_NOISE_STD:
            raise ValueError(
                f"RunTable.noise_std value {float(s.max())!r} exceeds the largest heading-noise "
                f"standard deviation allowed, {MAX_NOISE_STD:g} rad (beyond it theta + noise "
                "loses the heading's precision, and far beyond it overflows)"
            )
    return s


def run_grid(
    n_controllers: int,
    n_trajectories: int,
    noise_stds: Sequence[float],
    seeds: Sequence[int] | int,
) -> RunTable:
    """Cartesian product of controllers x trajectories x noise levels x seeds.

    ``n_controllers`` and ``n_trajectories`` are the lengths of the sequences the runs index;
    ``noise_stds`` the noise levels (rad); ``seeds`` the seed indices, or a count ``n``
    (seed indices ``0 ... n-1``). Runs are ordered with the seed varying fastest, then noise,
    trajectory, controller.

    Examples
    --------
    >>> len(run_grid(2, 3, [0.0, 0.1], 5))
    60
    """
    seed_list = np.arange(int(seeds)) if isinstance(seeds, Integral) else np.asarray(seeds)
    c, t, s, z = np.meshgrid(
        np.arange(n_controllers), np.arange(n_trajectories), np.asarray(noise_stds, float),
        seed_list, indexing="ij",
    )
    return RunTable(c, t, s, z)


@dataclass(frozen=True)
class Trace:
    """Time series of a batch of runs.

    Attributes
    ----------
    t : ndarray, shape (N+1,)
        Control instants.
    runs : RunTable
        The runs, in the order of the first axis below.
    series : dict of str -> ndarray, shape (B, N+1)
        One array per name in :data:`.TRACE_FIELDS` (axis 0: run, axis 1: time), then one per
        name the controllers report (their ``trace_series``, e.g. the processor-in-the-loop
        controller's ``cycles``; NaN for runs of the other controllers).
    metrics : dict of str -> ndarray, shape (B,)
        The metrics of :mod:`it2track.tracking.metrics`.
    """

    t: FloatArray
    runs: RunTable
    series: dict[str, FloatArray]
    metrics: dict[str, FloatArray]

    def __getitem__(self, name: str) -> FloatArray:
        return self.series[name]

    def run(self, i: int) -> dict[str, FloatArray]:
        """The time series of run ``i``, each of shape ``(N+1,)``, plus ``"t"``."""
        return {"t": self.t, **{k: v[i] for k, v in self.series.items()}}


def _check_inputs(
    controllers: Sequence[HeadingController],
    trajectories: Sequence[Trajectory],
    runs: RunTable,
    config: LoopConfig | None = None,
    *,
    record: bool = False,
    batch_size: int | None = None,
) -> None:
    """Types and indices of a simulation call; with ``config``, also that its arrays fit in
    memory (``record``: the full trace of every run; else one batch of ``batch_size``)."""
    if not isinstance(runs, RunTable):
        raise ValueError(f"runs must be a RunTable, got {type(runs).__name__}")
    for name, seq in (("controllers", controllers), ("trajectories", trajectories)):
        if not isinstance(seq, list | tuple):
            raise ValueError(f"{name} must be a list or tuple, got {type(seq).__name__}")
    for i, c in enumerate(controllers):
        if not isinstance(c, HeadingController):
            raise ValueError(f"controllers[{i}]={c!r} is not a HeadingController")
    for i, tr in enumerate(trajectories):
        if not isinstance(tr, Trajectory):
            raise ValueError(f"trajectories[{i}]={tr!r} is not a Trajectory")
    if len(runs):
        if runs.controller.max() >= len(controllers):
            raise ValueError(
                f"runs name controller {runs.controller.max()} but only {len(controllers)} given"
            )
        if runs.trajectory.max() >= len(trajectories):
            raise ValueError(
                f"runs name trajectory {runs.trajectory.max()} but only {len(trajectories)} given"
            )
    if config is None:
        return
    if not isinstance(config, LoopConfig):
        raise ValueError(f"config must be a LoopConfig, got {type(config).__name__}")
    n = len(runs) if record or batch_size is None else min(len(runs), batch_size)
    check_memory(
        loop_bytes(n_steps=config.n_steps, runs=n, trajectories=max(1, len(trajectories)),
                   noise_samples=int(config.duration * config.noise_rate) + 1, record=record),
        what=(f"simulating {len(runs)} run(s) of {config.n_steps} periods"
              + (" with their time series" if record else f" in batches of {n}")),
        hint=("use simulate_metrics (metrics only) or fewer runs" if record
              else "lower batch_size"),
    )


#: Most bytes :func:`simulate_metrics` keeps for the noise rows its chunks share (each distinct
#: seed index of a noisy run drawn once per call: 8 kB per seed at 1001 samples, so 64 MiB is
#: ~8000 seeds). Beyond it every chunk draws its own seeds' rows.
NOISE_TABLE_BYTES = 64 << 20


@functools.lru_cache(maxsize=32)
def _drive(robot: RobotParams, ts: float, nodes: int) -> DifferentialDrive:
    """Plant maps for one robot and period, built once (about 30 small matrix exponentials,
    slow when a busy BLAS spins up threads) and shared: ``DifferentialDrive`` is immutable
    and keeps its scratch buffers per thread."""
    return DifferentialDrive(robot, ts, quadrature_nodes=nodes)


class _Engine:
    """Precomputed, batch-independent pieces of a simulation (plant maps, references)."""

    def __init__(self, trajectories: Sequence[Trajectory], config: LoopConfig) -> None:
        self.config = config
        self.drive = _drive(config.robot, config.ts, config.quadrature_nodes)
        t = config.times
        ref = np.stack([tr.sample(t) for tr in trajectories])  # (n_traj, N+1, 4)
        motor = config.robot.motor
        gain = config.robot.wheel_radius * motor.dc_gain
        # Rows indexed by time so that row k is contiguous: (N+1, n_traj).
        self.x_ref = np.ascontiguousarray(ref[:, :, 0].T)
        self.y_ref = np.ascontiguousarray(ref[:, :, 1].T)
        self.v0 = np.ascontiguousarray((np.hypot(ref[:, :, 2], ref[:, :, 3]) / gain).T)
        if config.start_pose == ON_PATH:
            # (x, y, tangent heading) of each reference at t = 0: (n_traj, 3)
            self.start = np.stack([ref[:, 0, 0], ref[:, 0, 1],
                                   atan2(ref[:, 0, 3], ref[:, 0, 2])], axis=1)
        else:
            self.start = np.tile(np.asarray(config.start_pose, dtype=np.float64),
                                 (len(trajectories), 1))
        self.hold = held_sample_index(t, config.noise_rate)
        self.n_noise = int(self.hold[-1]) + 1
        self.v_lim = motor.voltage_limit

    def run(
        self,
        controllers: Sequence[HeadingController],
        runs: RunTable,
        *,
        record: bool,
        noise: NoiseRows | None = None,
    ) -> tuple[dict[str, FloatArray], dict[str, FloatArray] | None]:
        """Simulate ``runs`` (the reference engine); ``noise``: rows drawn beforehand for
        their noisy runs' seeds (:func:`noise_rows`)."""
        cfg = self.config
        n = len(runs)
        n_steps = cfg.n_steps
        # Work in controller-sorted order so each controller sees one contiguous slice.
        order = np.argsort(runs.controller, kind="stable")
        ctrl = runs.controller[order]
        tidx = runs.trajectory[order]
        one_traj = bool((tidx == tidx[0]).all()) if n else True
        std = runs.noise_std[order]
        seeds = runs.seed[order]
        z_rows, inverse = noise_rows(cfg.seed, self.n_noise, seeds, std, noise)
        # z[j] = std * z_rows[inverse, j]: (n_noise, B), row j contiguous. Built in blocks
        # of runs so the transposing copy stays in cache (~3x faster than one big gather).
        z = np.empty((self.n_noise, n))
        for a in range(0, n, 256):
            b = min(a + 256, n)
            np.multiply(z_rows[inverse[a:b]].T, std[a:b], out=z[:, a:b])  # noise in rad
        del z_rows
        bounds = np.flatnonzero(np.diff(ctrl)) + 1
        starts = np.concatenate([[0], bounds])
        stops = np.concatenate([bounds, [n]])
        groups = [
            (controllers[int(ctrl[a])], slice(int(a), int(b)))
            for a, b in zip(starts, stops, strict=True)
        ] if n else []
        states = [c.initial_state(s.stop - s.start, cfg.ts) for c, s in groups]
        actuation = Actuation(groups, self.drive, n_steps, record=record)

        pose = np.ascontiguousarray(self.start[tidx].T) if n else np.empty((3, 0))
        previous = cfg.desired_heading_pose is PoseTiming.PREVIOUS
        prev_xy = pose[:2].copy()  # pose at t_(k-1) for PoseTiming.PREVIOUS (t_0 at k = 0)
        wheels = np.zeros((4, n))
        volts = np.empty((2, n))
        u = np.empty(n)
        acc = MetricAccumulator(n, cfg.ts, n_steps, self.v_lim,
                                start_index=cfg.metric_start_index)
        rec = {f: np.empty((n_steps + 1, n)) for f in TRACE_FIELDS} if record else None
        half_r = 0.5 * cfg.robot.wheel_radius
        w_scale = cfg.robot.wheel_radius / (2.0 * cfg.robot.half_track)
        # Work rows reused every step (fresh temporaries would cost allocations and page
        # faults). Every operation on them is elementwise: runs stay batch-independent.
        dx, dy, theta_d, theta_meas, e_true, dist, tmp, vr_req, vl_req = np.empty((9, n))
        if previous:
            dxp, dyp = np.empty(n), np.empty(n)
        e_meas, e_prev = np.empty(n), np.empty(n)  # swapped each step
        de = np.zeros(n)  # de_0 = 0
        if not one_traj:
            xr, yr, v0 = np.empty(n), np.empty(n), np.empty(n)

        for k in range(n_steps + 1):
            if one_traj:
                j = int(tidx[0]) if n else 0
                xr, yr, v0 = self.x_ref[k, j], self.y_ref[k, j], self.v0[k, j]
            else:
                np.take(self.x_ref[k], tidx, out=xr)
                np.take(self.y_ref[k], tidx, out=yr)
                np.take(self.v0[k], tidx, out=v0)
            np.subtract(xr, pose[0], out=dx)
            np.subtract(yr, pose[1], out=dy)
            # atan2 of .libm, not np.arctan2 (SIMD on some CPUs): the compiled engine's bits
            if previous:
                np.subtract(xr, prev_xy[0], out=dxp)
                np.subtract(yr, prev_xy[1], out=dyp)
                theta_d[:] = atan2(dyp, dxp)
            else:
                theta_d[:] = atan2(dy, dx)
            np.add(pose[2], z[self.hold[k]], out=theta_meas)
            _wrap_inplace(np.subtract(theta_d, pose[2], out=e_true))
            _wrap_inplace(np.subtract(theta_d, theta_meas, out=e_meas))
            if k:
                _wrap_inplace(np.subtract(e_meas, e_prev, out=de))
            for (c, sl), state in zip(groups, states, strict=True):
                u[sl] = c.output(e_meas[sl], de[sl], state)
                actuation.after_output(k, c, sl, state)
            np.add(v0, u, out=vr_req)
            np.subtract(v0, u, out=vl_req)
            np.clip(vr_req, -self.v_lim, self.v_lim, out=volts[0])
            np.clip(vl_req, -self.v_lim, self.v_lim, out=volts[1])
            np.multiply(dx, dx, out=dist)
            np.multiply(dy, dy, out=tmp)
            dist += tmp
            np.sqrt(dist, out=dist)
            acc.update(
                k, e_true=e_true, e_meas=e_meas, distance=dist, u=u,
                v_requested=(vr_req, vl_req),
            )
            if rec is not None:
                row = {
                    "x": pose[0], "y": pose[1], "theta": pose[2], "x_ref": xr, "y_ref": yr,
                    "theta_d": theta_d, "theta_meas": theta_meas, "e_true": e_true,
                    "e_meas": e_meas, "de": de, "u": u, "v_right": volts[0],
                    "v_left": volts[1], "omega_right": wheels[1], "omega_left": wheels[3],
                    "v": half_r * (wheels[1] + wheels[3]),
                    "omega": w_scale * (wheels[1] - wheels[3]),
                }  # fmt: skip
                for name, value in row.items():
                    rec[name][k] = value
            if k < n_steps:
                if previous:
                    prev_xy[:] = pose[:2]
                pose, wheels = actuation.step(pose, wheels, volts)
            e_prev, e_meas = e_meas, e_prev

        inv = np.empty_like(order)
        inv[order] = np.arange(n)
        metrics = {name: value[inv] for name, value in acc.result().items()}
        series = None
        if rec is not None:
            rec.update(actuation.recorded())
            series = {name: np.ascontiguousarray(value.T[inv]) for name, value in rec.items()}
        return metrics, series


def _run(
    engine: _Engine,
    controllers: Sequence[HeadingController],
    runs: RunTable,
    *,
    record: bool,
    noise: NoiseRows | None = None,
) -> tuple[dict[str, FloatArray], dict[str, FloatArray] | None]:
    """``engine.run`` with every run the compiled engine supports done by it (same bits);
    ``noise``: rows drawn beforehand for the noisy runs' seeds (else drawn here)."""
    jit = _compiled.load() if len(runs) else None
    if jit is None:
        return engine.run(controllers, runs, record=record, noise=noise)
    fast = np.array([_compiled.supported(c) is None for c in controllers], dtype=bool)
    fast_run = fast[runs.controller]
    if not fast_run.any():
        return engine.run(controllers, runs, record=record, noise=noise)
    idx = np.flatnonzero(fast_run)
    metrics, series, status = _compiled.run(jit, engine, controllers, runs.take(idx),
                                            record=record, noise=noise)  # fmt: skip
    slow = np.flatnonzero(~fast_run)
    if status.any():  # the fuzzy reference raises on these runs: let it
        slow = np.sort(np.concatenate([slow, idx[status != 0]]))
    if slow.size == 0:
        return metrics, series
    m_slow, s_slow = engine.run(controllers, runs.take(slow), record=record, noise=noise)
    n = len(runs)
    out = {name: np.empty(n) for name in metrics}
    for name, value in metrics.items():
        out[name][idx] = value
        out[name][slow] = m_slow[name]
    if series is None or s_slow is None:
        return out, None
    rec = {name: np.full((n, engine.config.n_steps + 1), np.nan) for name in
           (*series, *(k for k in s_slow if k not in series))}  # fmt: skip
    for name, value in series.items():
        rec[name][idx] = value
    for name, value in s_slow.items():  # with the series only slow-engine controllers report
        rec[name][slow] = value
    return out, rec


def simulate(
    controllers: Sequence[HeadingController],
    trajectories: Sequence[Trajectory],
    runs: RunTable,
    config: LoopConfig | None = None,
) -> Trace:
    """Simulate a batch of runs and keep their time series.

    Parameters
    ----------
    controllers : sequence of HeadingController
        Indexed by ``runs.controller``.
    trajectories : sequence of Trajectory
        Indexed by ``runs.trajectory``.
    runs : RunTable
        The ``B`` runs.
    config : LoopConfig, optional
        Defaults to ``LoopConfig()`` (10 s at 100 Hz, paper Table 3 robot).

    Returns
    -------
    Trace
        Series of shape ``(B, N+1)`` and metrics of shape ``(B,)``, in the order of ``runs``.
        Memory is ``17 * 8 * B * (N+1)`` bytes; use :func:`simulate_metrics` for big batches.
    """
    config = config or LoopConfig()
    _check_inputs(controllers, trajectories, runs, config, record=True)
    engine = _Engine(trajectories, config)
    metrics, series = _run(engine, controllers, runs, record=True)
    assert series is not None
    return Trace(t=config.times, runs=runs, series=series, metrics=metrics)


def simulate_metrics(
    controllers: Sequence[HeadingController],
    trajectories: Sequence[Trajectory],
    runs: RunTable,
    config: LoopConfig | None = None,
    *,
    batch_size: int = 4096,
    progress: Callable[[int], object] | None = None,
) -> dict[str, FloatArray]:
    """Simulate runs in chunks of ``batch_size`` and return only their metrics.

    The time series are never stored: memory grows with ``batch_size``, not with ``len(runs)``.
    Results are bit-for-bit independent of ``batch_size``.

    Parameters
    ----------
    controllers, trajectories, runs, config
        As for :func:`simulate`.
    batch_size : int
        Runs advanced together (memory vs speed).
    progress : callable, optional
        Called with the number of runs finished after each chunk (e.g. ``tqdm.update``).

    Returns
    -------
    dict of str -> ndarray, shape (B,)
        Every metric of :data:`~it2track.tracking.metrics.METRIC_NAMES`, in the order of ``runs``.
    """
    config = config or LoopConfig()
    if isinstance(batch_size, bool) or not isinstance(batch_size, int) or batch_size < 1:
        raise ValueError(f"batch_size={batch_size!r} must be a positive integer")
    _check_inputs(controllers, trajectories, runs, config, batch_size=batch_size)
    engine = _Engine(trajectories, config)
    n = len(runs)
    # Common random numbers: draw each noisy seed's row once for all chunks (memory bounded
    # by NOISE_TABLE_BYTES; beyond it each chunk draws its own, as simulate does).
    table = None
    if n > batch_size:
        noisy = np.unique(runs.seed[runs.noise_std > 0.0])
        if NoiseRows.nbytes(noisy.size, engine.n_noise) <= NOISE_TABLE_BYTES:
            table = NoiseRows(config.seed, noisy, engine.n_noise)
    out: dict[str, FloatArray] | None = None
    for start in range(0, n, batch_size):
        stop = min(start + batch_size, n)
        metrics, _ = _run(engine, controllers, runs.take(slice(start, stop)), record=False,
                          noise=table)  # fmt: skip
        if out is None:
            out = {name: np.empty(n) for name in metrics}
        for name, value in metrics.items():
            out[name][start:stop] = value
        if progress is not None:
            progress(stop - start)
    if out is None:
        from .metrics import METRIC_NAMES

        out = {name: np.empty(0) for name in METRIC_NAMES}
    return out

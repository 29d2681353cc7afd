"""Configuration shared by every run of a batch: :class:`LoopConfig` (period, duration, robot,
noise rate, start pose, base seed, metric window, plant) and :class:`PoseTiming`."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from numbers import Integral, Real
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._limits import ResourceLimitError, check_memory, loop_bytes
from ..plant import RobotParams
from ..plant.base import PlantSpec
from ..plant.drive import MAX_QUADRATURE_NODES, check_stiffness
from .loopdefs import PoseTiming

__all__ = ["ON_PATH", "LoopConfig", "PoseTiming"]

FloatArray = NDArray[np.float64]

#: Upper bound on the control periods (and held noise samples) of one run: 1e12 instants are
#: 8 TB per recorded row; anything near it is refused by the memory estimate first.
_MAX_STEPS = 1e12


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
        Pose ``theta_d`` is computed from (see :class:`PoseTiming`; default ``"current"``).
    metric_start : float
        Start of the window of the heading-error integrals (IAE ... ITSE and their ``_meas``
        forms), s: they integrate over ``[metric_start, duration]`` (ITAE/ITSE still weight
        by the absolute time ``t``). A whole number of periods in ``[0, duration)``;
        default 0 (the whole run).
    plant : PlantSpec, optional
        The plant the loop drives (:mod:`it2track.plant.base`), built for ``ts`` and
        ``robot``. ``None`` (default): the paper's kinematic robot from ``robot`` and
        ``quadrature_nodes``, run by the compiled engine where available; any other plant
        runs on the numpy engine through the plant protocol.
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
    plant: PlantSpec | None = None

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
        if self.plant is not None and not isinstance(self.plant, PlantSpec):
            raise ValueError(f"LoopConfig.plant={self.plant!r} must be a PlantSpec (a plant "
                             "description with kind, build() and to_dict()) or None")
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
        """Plain values (JSON/TOML-ready), the robot as a nested dict; ``"plant"`` (the
        plant's own table) only when a plant other than the kinematic robot is set."""
        out = {
            "duration": self.duration, "ts": self.ts, "noise_rate": self.noise_rate,
            "start_pose": (self.start_pose if isinstance(self.start_pose, str)
                           else list(self.start_pose)),
            "seed": self.seed, "quadrature_nodes": self.quadrature_nodes,
            "desired_heading_pose": self.desired_heading_pose.value,
            "metric_start": self.metric_start, "robot": dataclasses.asdict(self.robot),
        }  # fmt: skip
        if self.plant is not None:
            out["plant"] = self.plant.to_dict()
        return out

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

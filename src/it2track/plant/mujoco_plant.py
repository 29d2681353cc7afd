"""The MuJoCo robot as a :class:`~it2track.plant.base.RobotPlant`, and its configuration.

:class:`MujocoSpec` is the :class:`~it2track.plant.base.PlantSpec` a
:class:`~it2track.tracking.LoopConfig` names (``[plant] kind = "mujoco"`` in TOML); its
:meth:`~MujocoSpec.build` gives a :class:`MujocoPlant`, which the closed loop drives like the
kinematic robot: wheel voltages in, pose and speeds out. The state of a batch is a
:class:`~it2track.plant.mujoco_robot.RobotBatch` (one ``mujoco.MjData`` per run), updated in
place by :meth:`MujocoPlant.step`.

This module imports MuJoCo only when a plant is built or read from a configuration: without
it, :meth:`MujocoSpec.build` raises ``it2track._extras.MissingExtraError``
(an ``ImportError``) and :meth:`MujocoSpec.from_dict` a ``ValueError``, both naming the extra
to install.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping
from dataclasses import dataclass, field
from numbers import Integral
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .base import ROBOT_INPUTS, ROBOT_OUTPUTS
from .drive import RobotParams
from .mujoco_model import SURFACES, PhysicsParams, Surface
from .mujoco_robot import MAX_THREADS, MujocoRobot, RobotBatch, import_mujoco

__all__ = ["MujocoPlant", "MujocoSpec"]

FloatArray = NDArray[np.float64]


@functools.lru_cache(maxsize=16)
def _robot(robot: RobotParams, physics: PhysicsParams, ts: float) -> MujocoRobot:
    """The compiled, settled model for one robot, physics and period, built once: compiling
    and settling take a fraction of a second, and the model is read-only once built."""
    return MujocoRobot(robot, physics, ts)


class MujocoPlant:
    """The differential-drive robot in MuJoCo, as a robot plant of the closed loop.

    Parameters
    ----------
    robot : MujocoRobot
        The compiled model (shared by every batch this plant starts).
    threads : int, optional
        Threads stepping a batch (default: the CPUs this process may use). The results do not
        depend on it.

    Attributes
    ----------
    ts : float
        The control period, s.
    input_names, output_names : tuple of str
        :data:`~it2track.plant.base.ROBOT_INPUTS`, :data:`~it2track.plant.base.ROBOT_OUTPUTS`.
    input_limits : tuple of (float, float)
        ``(-V_max, V_max)`` per wheel (the motors' ``voltage_limit``).
    mujoco_robot : MujocoRobot
        The model.

    Examples
    --------
    >>> plant = MujocoSpec(physics=PhysicsParams(surface="wet")).build(  # doctest: +SKIP
    ...     ts=0.01, robot=RobotParams())
    >>> state = plant.initial_state(2)  # doctest: +SKIP
    >>> state = plant.step(state, np.full((2, 2), 3.0), 0.0)  # doctest: +SKIP
    >>> plant.outputs(state).shape  # doctest: +SKIP
    (7, 2)
    """

    input_names = ROBOT_INPUTS
    output_names = ROBOT_OUTPUTS

    def __init__(self, robot: MujocoRobot, *, threads: int | None = None) -> None:
        if not isinstance(robot, MujocoRobot):
            raise ValueError(f"robot={robot!r} must be a MujocoRobot")
        self.mujoco_robot = robot
        self.ts = robot.ts
        lim = robot.robot.motor.voltage_limit
        self.input_limits = ((-lim, lim), (-lim, lim))
        self.threads = threads

    def __repr__(self) -> str:
        return f"MujocoPlant({self.mujoco_robot!r})"

    def initial_state(self, n: int, pose: ArrayLike | None = None) -> RobotBatch:
        """``n`` robots at rest on the ground (motors off, wheels still) at ``pose``.

        Parameters
        ----------
        n : int
            Number of runs (>= 0).
        pose : array_like, shape (3, n), optional
            Rows x (m), y (m), theta (rad) of the axle centre and heading; default zeros.

        Returns
        -------
        RobotBatch
            The batch (one ``MjData`` per run); :meth:`step` updates it in place.

        Raises
        ------
        ValueError
            If ``n`` is not an integer >= 0 or ``pose`` not finite of shape ``(3, n)``.
        """
        if isinstance(n, bool) or not isinstance(n, Integral) or n < 0:
            raise ValueError(f"n={n!r} must be an integer >= 0")
        start = np.zeros((3, int(n))) if pose is None else np.asarray(pose, dtype=np.float64)
        if start.shape != (3, n):
            raise ValueError(f"pose must be finite of shape (3, {n}), got shape {start.shape}")
        return self.mujoco_robot.batch(start, threads=self.threads)

    def step(self, state: RobotBatch, u: FloatArray, t: float) -> RobotBatch:
        """One control period with the wheel voltages ``u`` held (``t`` unused).

        Parameters
        ----------
        state : RobotBatch
            From :meth:`initial_state`; updated in place.
        u : ndarray, shape (2, B)
            ``V_R``, ``V_L`` in V (used as given; the loop saturates them).
        t : float
            Start of the period, s.

        Returns
        -------
        RobotBatch
            ``state``.

        Raises
        ------
        PhysicsDivergedError
            If a run's physics diverged (a ``ValueError``, naming the run).
        """
        state.step(u)
        return state

    def outputs(self, state: RobotBatch) -> FloatArray:
        """:data:`~it2track.plant.base.ROBOT_OUTPUTS` of the runs, shape ``(7, B)``.

        Parameters
        ----------
        state : RobotBatch
            The batch.

        Returns
        -------
        ndarray, shape (7, B)
            x, y, theta (axle centre and unwrapped heading), the wheel joints' speeds
            omega_R, omega_L, and the chassis' true speed along its heading ``v`` and yaw rate
            ``omega`` (from the physics: with slip they differ from the wheels' kinematics).
        """
        out = np.empty((7, state.n))
        out[:3] = state.pose
        out[3] = state.wheels[1]
        out[4] = state.wheels[3]
        out[5], out[6] = state.body_velocity()
        return out


#: The ``[plant]`` keys of a MuJoCo plant besides ``kind``: ``surface`` and the fields of
#: :class:`PhysicsParams`.
_PHYSICS_KEYS = tuple(f.name for f in dataclasses.fields(PhysicsParams) if f.name != "surface")


@dataclass(frozen=True, kw_only=True)
class MujocoSpec:
    """The MuJoCo robot as a plant description (a :class:`~it2track.plant.base.PlantSpec`).

    Parameters
    ----------
    physics : PhysicsParams, default ``PhysicsParams()``
        Masses, contact, surface and physics step; geometry and motors come from the loop's
        ``robot``.
    threads : int, optional
        Threads stepping a batch (default: the CPUs this process may use). Not part of the
        description's identity (equality, :meth:`to_dict`): results do not depend on it.

    Attributes
    ----------
    kind : str
        ``"mujoco"``.

    Raises
    ------
    ValueError
        If ``physics`` is not a :class:`PhysicsParams` or ``threads`` not an integer in
        ``[1, 256]``.

    Examples
    --------
    >>> spec = MujocoSpec(physics=PhysicsParams(surface="icy"))
    >>> spec.physics.surface.mu, spec.to_dict()["surface"]
    (0.1, 'icy')
    """

    kind: ClassVar[str] = "mujoco"
    physics: PhysicsParams = field(default_factory=PhysicsParams)
    threads: int | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.physics, PhysicsParams):
            raise ValueError(f"MujocoSpec.physics={self.physics!r} must be a PhysicsParams")
        t = self.threads
        if t is not None and (isinstance(t, bool) or not isinstance(t, Integral)
                              or not 1 <= t <= MAX_THREADS):
            raise ValueError(f"MujocoSpec.threads={t!r} must be an integer in [1, {MAX_THREADS}]")

    def build(self, *, ts: float, robot: RobotParams) -> MujocoPlant:
        """The plant for control period ``ts`` and the loop's ``robot``.

        Parameters
        ----------
        ts : float
            Control period, s.
        robot : RobotParams
            Geometry (half-track, wheel radius) and motors.

        Returns
        -------
        MujocoPlant

        Raises
        ------
        it2track._extras.MissingExtraError
            If MuJoCo is not installed (an ``ImportError``; the message names the extra).
        ValueError
            If the robot cannot be built at this period (see :class:`MujocoRobot`).
        """
        return MujocoPlant(_robot(robot, self.physics, float(ts)), threads=self.threads)

    def to_dict(self) -> dict[str, Any]:
        """The ``[plant]`` table: ``kind``, ``surface`` (a name of :data:`SURFACES` or the
        friction coefficient) and every other :class:`PhysicsParams` field.

        Returns
        -------
        dict
            Plain values; :meth:`from_dict` reads it back.
        """
        s = self.physics.surface
        surface: str | float = s.name if SURFACES.get(s.name) == s else s.mu
        out: dict[str, Any] = {"kind": self.kind, "surface": surface}
        out.update({k: getattr(self.physics, k) for k in _PHYSICS_KEYS})
        return out

    @classmethod
    def from_dict(cls, table: Mapping[str, Any], *, where: str = "[plant]") -> MujocoSpec:
        """The spec of a ``[plant]`` table (``kind = "mujoco"``; other keys optional).

        Parameters
        ----------
        table : mapping
            ``kind`` and any of ``surface`` (``"dry"``, ``"wet"``, ``"icy"`` or a friction
            coefficient) and the :class:`PhysicsParams` fields.
        where : str
            How error messages name the table.

        Returns
        -------
        MujocoSpec

        Raises
        ------
        ValueError
            If ``kind`` is not ``"mujoco"``, a key is unknown (the message lists the allowed
            ones) or a value is invalid (naming the key and the value), or MuJoCo is not
            installed (naming the extra): a configuration that names the MuJoCo robot is
            refused when it is read, not halfway through a run.
        """
        if not isinstance(table, Mapping):
            raise ValueError(f"{where} must be a table, got {table!r}")
        if table.get("kind") != cls.kind:
            raise ValueError(f"{where}: kind={table.get('kind')!r} is not {cls.kind!r}")
        allowed = ("kind", "surface", *_PHYSICS_KEYS)
        unknown = sorted(set(table) - set(allowed))
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {unknown}; allowed: {list(allowed)}")
        kwargs = {k: v for k, v in table.items() if k != "kind"}
        surface = kwargs.get("surface")
        if surface is not None and not isinstance(surface, str | int | float | Surface):
            raise ValueError(f"{where}: surface={surface!r} must be one of {sorted(SURFACES)} "
                             "or a friction coefficient")
        try:
            physics = PhysicsParams(**kwargs)
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from None
        try:
            import_mujoco()
        except ImportError as exc:
            raise ValueError(f"{where}: kind = 'mujoco': {exc}") from None
        return cls(physics=physics)

"""The paper's kinematic robot (DESIGN.md sec. 4) as a :class:`~it2track.plant.base.RobotPlant`.

A thin adapter over :class:`~it2track.plant.drive.DifferentialDrive`: the state is the pair
``(pose (3, B), wheels (4, B))`` and one step is exactly ``DifferentialDrive.step``, so the
closed loop's numbers through this protocol are bit-identical to the drive's own.
"""

from __future__ import annotations

from numbers import Integral

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .base import ROBOT_INPUTS, ROBOT_OUTPUTS
from .drive import MAX_QUADRATURE_NODES, DifferentialDrive, RobotParams
from .switched import SwitchedDrive

__all__ = ["KinematicPlant"]

FloatArray = NDArray[np.float64]
KinematicState = tuple[FloatArray, FloatArray]


class KinematicPlant:
    """The paper's differential-drive robot: exact-ZOH DC motors and unicycle kinematics.

    Parameters
    ----------
    robot : RobotParams
        Geometry and motors (paper Table 3 by default).
    ts : float
        Control period, s (finite, > 0).
    quadrature_nodes : int
        Nodes per period of the position integral, 1 to 64 (see :class:`DifferentialDrive`).

    Attributes
    ----------
    drive : DifferentialDrive
        The discretised robot this plant steps.
    ts : float
        The control period, s.
    input_names : tuple of str
        :data:`~it2track.plant.base.ROBOT_INPUTS`.
    output_names : tuple of str
        :data:`~it2track.plant.base.ROBOT_OUTPUTS`.
    input_limits : tuple of (float, float)
        ``(-V_max, V_max)`` per wheel, the motors' ``voltage_limit``.

    Raises
    ------
    ValueError
        If ``robot`` is not a :class:`RobotParams`, ``ts`` not a finite number > 0, or
        ``quadrature_nodes`` not an integer in [1, 64].

    Examples
    --------
    >>> import numpy as np
    >>> plant = KinematicPlant(RobotParams(), 0.01)
    >>> state = plant.initial_state(2, pose=np.array([[0.0, 1.0], [0.0, 0.0], [0.0, 0.0]]))
    >>> for k in range(100):
    ...     state = plant.step(state, np.full((2, 2), 6.0), k * 0.01)
    >>> y = plant.outputs(state)
    >>> y.shape, float(y[1, 0]), round(float(y[0, 1] - y[0, 0]), 12)   # straight ahead, 1 m apart
    ((7, 2), 0.0, 1.0)
    """

    input_names = ROBOT_INPUTS
    output_names = ROBOT_OUTPUTS
    drive: DifferentialDrive
    ts: float
    input_limits: tuple[tuple[float, float], ...]
    _half_r: float
    _w_scale: float
    _switched: SwitchedDrive

    def __init__(self, robot: RobotParams, ts: float, *, quadrature_nodes: int = 4) -> None:
        if (isinstance(quadrature_nodes, bool) or not isinstance(quadrature_nodes, Integral)
                or not 1 <= quadrature_nodes <= MAX_QUADRATURE_NODES):
            raise ValueError(f"quadrature_nodes={quadrature_nodes!r} must be an integer in "
                             f"[1, {MAX_QUADRATURE_NODES}]")
        self._attach(DifferentialDrive(robot, ts, quadrature_nodes=int(quadrature_nodes)))

    def _attach(self, drive: DifferentialDrive) -> None:
        robot = drive.params
        self.drive = drive
        self.ts = drive.ts
        lim = robot.motor.voltage_limit
        self.input_limits = ((-lim, lim), (-lim, lim))
        self._half_r = 0.5 * robot.wheel_radius
        self._w_scale = robot.wheel_radius / (2.0 * robot.half_track)

    @classmethod
    def from_drive(cls, drive: DifferentialDrive) -> KinematicPlant:
        """The plant stepping an existing (already discretised) ``drive``.

        Parameters
        ----------
        drive : DifferentialDrive
            Shared, not copied (it is immutable).

        Returns
        -------
        KinematicPlant
        """
        if not isinstance(drive, DifferentialDrive):
            raise ValueError(f"drive must be a DifferentialDrive, got {drive!r}")
        plant = cls.__new__(cls)
        plant._attach(drive)
        return plant

    def __repr__(self) -> str:
        return f"KinematicPlant.from_drive({self.drive!r})"

    def initial_state(self, n: int, pose: ArrayLike | None = None) -> KinematicState:
        """``n`` robots at rest (currents and wheel speeds 0) at ``pose``.

        Parameters
        ----------
        n : int
            Number of runs (>= 0).
        pose : array_like, shape (3, n), optional
            Rows x (m), y (m), theta (rad); default all zeros.

        Returns
        -------
        tuple of ndarray
            ``(pose (3, n), wheels (4, n))``, new arrays.

        Raises
        ------
        ValueError
            If ``n`` is not an integer >= 0, or ``pose`` is not finite of shape ``(3, n)``.
        """
        if isinstance(n, bool) or not isinstance(n, Integral) or n < 0:
            raise ValueError(f"n={n!r} must be an integer >= 0")
        if pose is None:
            p = np.zeros((3, int(n)))
        else:
            p = np.array(pose, dtype=np.float64, copy=True)
            if p.shape != (3, n) or not np.isfinite(p).all():
                raise ValueError(f"pose must be finite of shape (3, {n}), got shape {p.shape}")
        return p, np.zeros((4, int(n)))

    def step(self, state: KinematicState, u: FloatArray, t: float) -> KinematicState:
        """One period with wheel voltages ``u`` ``(2, B)`` held (``t`` unused: time-invariant).

        Parameters
        ----------
        state : tuple of ndarray
            ``(pose, wheels)`` from :meth:`initial_state` or a previous step.
        u : ndarray, shape (2, B)
            ``V_R``, ``V_L`` in V (used as given; the loop saturates them).
        t : float
            Start of the period, s.

        Returns
        -------
        tuple of ndarray
            The new ``(pose, wheels)`` (new arrays; ``state`` is not modified).
        """
        pose, wheels = state
        return self.drive.step(pose, wheels, u)

    def step_switched(self, state: KinematicState, u_before: FloatArray, u_after: FloatArray,
                      switch: FloatArray, t: float) -> KinematicState:
        """One period whose voltages switch once per run: ``u_before`` over ``[t, t + switch)``,
        ``u_after`` over the rest, both parts exact (:class:`~.switched.SwitchedDrive`).

        Parameters
        ----------
        state : tuple of ndarray
            ``(pose, wheels)``.
        u_before, u_after : ndarray, shape (2, B)
            ``V_R``, ``V_L`` in V before and after the switch (used as given).
        switch : ndarray, shape (B,)
            Each run's switching instant after ``t``, s, in ``[0, ts]``; at 0 this is
            :meth:`step` with ``u_after``, at ``ts`` with ``u_before``, bit for bit.
        t : float
            Start of the period, s.

        Returns
        -------
        tuple of ndarray
            The new ``(pose, wheels)``.
        """
        switched = self.__dict__.get("_switched")
        if switched is None:
            switched = self._switched = SwitchedDrive(self.drive)
        pose, wheels = state
        return switched.step(pose, wheels, u_before, u_after, switch)

    def outputs(self, state: KinematicState) -> FloatArray:
        """:data:`~it2track.plant.base.ROBOT_OUTPUTS` of the runs, shape ``(7, B)``.

        Parameters
        ----------
        state : tuple of ndarray
            ``(pose, wheels)``.

        Returns
        -------
        ndarray, shape (7, B)
            x, y, theta, omega_R, omega_L, ``v = (r/2)(omega_R + omega_L)``,
            ``omega = (r / 2l)(omega_R - omega_L)``.
        """
        pose, wheels = state
        out = np.empty((7, *pose.shape[1:]))
        out[:3] = pose
        out[3] = wheels[1]
        out[4] = wheels[3]
        np.add(wheels[1], wheels[3], out=out[5])
        out[5] *= self._half_r
        np.subtract(wheels[1], wheels[3], out=out[6])
        out[6] *= self._w_scale
        return out

"""The differential-drive robot in MuJoCo: the paper's DC motors driving a physical body.

:class:`MujocoRobot` compiles the MJCF of :func:`~it2track.plant.mujoco_model.robot_mjcf` once
(one ``MjModel``, read-only and shared); :meth:`MujocoRobot.batch` starts ``B`` runs (one
``MjData`` each) and :meth:`RobotBatch.step` advances them by one control period with the
wheel voltages held (zero-order hold), on a pool of threads: MuJoCo releases the GIL inside
``mj_step``. Each run is stepped by the same operations in the same order whatever the thread
count or batch, so its numbers are bit-for-bit the same.

Motor model (paper §II.A), per wheel, with ``omega`` the wheel joint's speed::

    L di/dt = V - R i - K omega          (integrated here, per physics step)
    torque on the joint = K i            (applied to the hinge; its reaction acts on the chassis)

The motor's rotor inertia J is the joint's *armature* and its viscous friction b the joint's
*damping*: MuJoCo then integrates ``(J + wheel + load) domega/dt = K i - b omega - load`` with
the load (tyre forces, the chassis' inertia, rolling resistance) from the physics, the
damping implicitly, and the rotor rigidly coupled to the wheel (no lag between them).

The electrical pole ``-R/L`` (about -926 s^-1) is stiff against a 1 ms physics step, so the
current is not stepped explicitly: over each physics step of length h it is integrated exactly
for the voltage held and a back-emf ``K omega(s)`` varying linearly, ``omega(s) = omega_n +
beta s``, with ``beta`` the joint's acceleration over the previous step (zero at a run's first
step). The torque applied over the step is K times the exact *mean* current, so the impulse
the motor delivers is exact for that back-emf. The remaining error (``omega`` is not exactly
linear within a step, and MuJoCo's step is first order) is measured against the exact
zero-order-hold motor by the motor bench test: 2e-4 of the speed range with the paper's J
alone at 1 ms steps. The scheme's stability is checked when the model is built.
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from numbers import Integral
from types import TracebackType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._extras import require
from .._limits import check_memory
from .drive import RobotParams
from .motor import _check_period
from .mujoco_model import PhysicsParams, robot_mjcf, substeps_per_period

__all__ = [
    "MujocoRobot",
    "PhysicsDivergedError",
    "RobotBatch",
    "import_mujoco",
]

FloatArray = NDArray[np.float64]

#: Bytes a run's ``MjData`` holds besides MuJoCo's buffer and arena (Python object, views).
_DATA_OVERHEAD = 16 * 1024

#: Most threads a batch uses (each extra thread costs a stack; the GIL-free part of a step is
#: MuJoCo's, ~20-40 us, so beyond the core count threads only contend).
MAX_THREADS = 256


class PhysicsDivergedError(ValueError):
    """A run's physics became unstable (MuJoCo's accelerations or state not finite)."""


def import_mujoco() -> Any:
    """The ``mujoco`` module, or ``it2track._extras.MissingExtraError`` naming the extra.

    Raises
    ------
    it2track._extras.MissingExtraError
        If the ``mujoco`` package cannot be imported (an ``ImportError``).
    """
    return require("mujoco", "mujoco", "the MuJoCo robot")


def _motor_step_coefficients(robot: RobotParams, h: float) -> tuple[float, float, float]:
    """``(alpha, mean, a)`` of the exact current update over a step ``h``:
    ``alpha = exp(-a h)``, ``mean = (1 - alpha) / (a h)``, ``a = R / L``."""
    m = robot.motor
    a = m.resistance / m.inductance
    x = a * h
    one_minus = -math.expm1(-x)
    return 1.0 - one_minus, one_minus / x, a


def scheme_matrix(robot: RobotParams, inertia: float, h: float) -> FloatArray:
    """One physics step of the motor scheme on an unloaded wheel, as a matrix.

    The unloaded wheel (joint inertia ``inertia`` = J plus the wheel's spin inertia, damping b,
    MuJoCo's implicit damping) at 0 V under the scheme of the module docstring is a linear map
    of ``(i, omega, omega_prev)``, with ``omega_prev`` the speed one step earlier.

    Parameters
    ----------
    robot : RobotParams
        Motor parameters.
    inertia : float
        Joint inertia about the axle, kg m^2 (> 0).
    h : float
        Physics step, s (> 0).

    Returns
    -------
    ndarray, shape (3, 3)
        ``x_{n+1} = M x_n`` for ``x = (i, omega, omega_prev)``.
    """
    m = robot.motor
    k, rr, b = m.torque_constant, m.resistance, m.friction
    alpha, mean, a = _motor_step_coefficients(robot, h)
    cols = []
    for state in np.eye(3):
        i, w0, wp = (float(v) for v in state)
        u0 = -k * w0 / rr
        u1 = -k * (w0 - wp) / h / rr
        cur = u0 + u1 * h / 2 - u1 / a + (i - u0 + u1 / a) * mean
        w1 = (inertia * w0 + h * k * cur) / (inertia + h * b)  # MuJoCo: implicit damping
        i1 = u0 + u1 * h - u1 / a + (i - u0 + u1 / a) * alpha
        cols.append((i1, w1, w0))
    return np.array(cols).T


def scheme_spectral_radius(robot: RobotParams, inertia: float, h: float) -> float:
    """Spectral radius of :func:`scheme_matrix`: the scheme is stable when it is below 1.

    A load only adds inertia and damping to the wheel, so the unloaded wheel is the worst case.

    Parameters
    ----------
    robot : RobotParams
        Motor parameters.
    inertia : float
        Joint inertia about the axle, kg m^2 (> 0).
    h : float
        Physics step, s (> 0).

    Returns
    -------
    float
        The largest eigenvalue magnitude of the 3x3 step map.
    """
    return float(np.max(np.abs(np.linalg.eigvals(scheme_matrix(robot, inertia, h)))))


class MujocoRobot:
    """The robot's compiled MuJoCo model for one control period.

    Parameters
    ----------
    robot : RobotParams, optional
        Geometry and motors (default: paper Table 3).
    physics : PhysicsParams, optional
        Masses, contact, surface, physics step (default: :class:`PhysicsParams`).
    ts : float, default 0.01
        Control period, s: split into :attr:`substeps` equal physics steps of
        :attr:`timestep` s.
    bench : bool, default False
        A motor bench test: the chassis is fixed in the air (:func:`robot_mjcf`), so each
        wheel is a motor loaded only by its own inertia and damping; runs keep their start
        pose and report zero body speeds.

    Attributes
    ----------
    robot, physics, ts
        As given.
    substeps : int
        Physics steps per control period.
    timestep : float
        ``ts / substeps``, s.
    mjcf : str
        The model's MJCF text.
    model : mujoco.MjModel
        The compiled model (shared, read-only, by every run).
    bench : bool
        As given.
    rest_qpos : ndarray, shape (nq,)
        The robot at rest on the ground at the origin, heading 0 (found by letting it settle
        once with the motors off); every run starts from it, moved to its start pose.

    Raises
    ------
    it2track._extras.MissingExtraError
        If MuJoCo is not installed (an ``ImportError`` naming the extra).
    ValueError
        If a parameter has the wrong type or value, or the motor scheme would be unstable at
        this physics step (an extremely light rotor against its back-emf), or the robot does
        not come to rest on the ground.

    Examples
    --------
    >>> robot = MujocoRobot(ts=0.01)  # doctest: +SKIP
    >>> with robot.batch([[0.0, 0.0, 0.0]]) as runs:  # doctest: +SKIP
    ...     runs.step([[3.0], [3.0]])
    """

    #: Longest settling time before giving up, s.
    SETTLE_TIME = 3.0
    #: Joint speeds below which the robot counts as at rest, rad/s or m/s.
    SETTLE_SPEED = 1e-6

    def __init__(
        self,
        robot: RobotParams | None = None,
        physics: PhysicsParams | None = None,
        ts: float = 0.01,
        *,
        bench: bool = False,
    ) -> None:
        robot = RobotParams() if robot is None else robot
        physics = PhysicsParams() if physics is None else physics
        if not isinstance(robot, RobotParams):
            raise ValueError(f"robot={robot!r} must be a RobotParams")
        if not isinstance(physics, PhysicsParams):
            raise ValueError(f"physics={physics!r} must be a PhysicsParams")
        ts = _check_period(ts)
        mujoco = import_mujoco()
        if mujoco.get_mju_user_warning() is None:
            # MuJoCo would append its warnings to MUJOCO_LOG.TXT in the working directory; the
            # batches check MuJoCo's warning counters and raise instead.
            mujoco.set_mju_user_warning(_no_log)
        self._bad = tuple(int(getattr(mujoco.mjtWarning, w))
                          for w in ("mjWARN_BADQPOS", "mjWARN_BADQVEL", "mjWARN_BADQACC",
                                    "mjWARN_CONTACTFULL", "mjWARN_CNSTRFULL"))
        self.robot, self.physics, self.ts = robot, physics, ts
        self.substeps = substeps_per_period(ts, physics.max_timestep)
        self.timestep = ts / self.substeps
        inertia = robot.motor.inertia + physics.wheel_inertia(robot)[0]
        radius = scheme_spectral_radius(robot, inertia, self.timestep)
        if not radius < 1.0:
            raise ValueError(
                f"motor inertia={robot.motor.inertia!r} (+ wheel {inertia - robot.motor.inertia:g})"
                f" kg m^2 is too light for its back-emf at the physics step {self.timestep:g} s "
                f"(the motor scheme's spectral radius is {radius:.3g} >= 1): lower "
                "PhysicsParams.max_timestep or check the motor parameters"
            )
        if not isinstance(bench, bool):
            raise ValueError(f"bench={bench!r} must be True or False")
        self.bench = bench
        self.mjcf = robot_mjcf(robot, physics, self.timestep, bench=bench)
        self.model = mujoco.MjModel.from_xml_string(self.mjcf)
        self._mujoco = mujoco
        model = self.model
        self.dofs = tuple(int(model.jnt_dofadr[model.joint(n).id]) for n in ("right", "left"))
        self.qpos_wheels = tuple(
            int(model.jnt_qposadr[model.joint(n).id]) for n in ("right", "left")
        )
        self._alpha, self._mean, self._rate = _motor_step_coefficients(robot, self.timestep)
        self.rest_qpos = self._settle()

    def _settle(self) -> FloatArray:
        """Let the robot come to rest on the ground, motors at 0 V (their back-emf brakes the
        wheels); its ``qpos``."""
        data = self._mujoco.MjData(self.model)
        state = (0.0, 0.0, 0.0, 0.0)
        for _ in range(math.ceil(self.SETTLE_TIME / self.ts)):
            state = _advance_run(self, data, 0.0, 0.0, state)
            if not np.isfinite(data.qpos).all():
                break
            if float(np.max(np.abs(data.qvel))) < self.SETTLE_SPEED:
                qpos: FloatArray = data.qpos.copy()
                return qpos
        raise ValueError(
            f"the robot ({self.physics!r}) does not come to rest on the ground within "
            f"{self.SETTLE_TIME:g} s with the motors at 0 V; check the masses and contact "
            "parameters"
        )

    def batch(self, start: ArrayLike, *, threads: int | None = None) -> RobotBatch:
        """Start runs at rest at the poses ``start``.

        Parameters
        ----------
        start : array_like, shape (3, B)
            ``(x, y, theta)`` of each run's axle centre and heading, m, m, rad (finite).
        threads : int, optional
            Threads stepping the runs (default: the CPUs this process may use, at most B).

        Returns
        -------
        RobotBatch
            Close it (or use it as a context manager) to stop its threads.

        Raises
        ------
        ValueError
            If ``start`` is not finite of shape (3, B) or ``threads`` not an integer in
            ``[1, 256]``.
        """
        return RobotBatch(self, start, threads=threads)

    def __repr__(self) -> str:
        return (f"MujocoRobot(ts={self.ts!r}, substeps={self.substeps}, "
                f"surface={self.physics.surface.name!r})")  # fmt: skip


def _no_log(message: str) -> None:
    """MuJoCo warning handler that writes no log file (the warning counters are checked)."""


def default_threads() -> int:
    """The CPUs this process may run on (its affinity mask), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def _advance_run(
    rb: MujocoRobot, data: Any, v_r: float, v_l: float,
    state: tuple[float, float, float, float],
) -> tuple[float, float, float, float]:
    """Advance one run's ``data`` by one control period at voltages ``(v_r, v_l)``.

    ``state`` and the result: ``(i_R, i_L, beta_R, beta_L)``, the motor currents and the
    joints' accelerations over the last physics step (the back-emf's slope).
    """
    mj_step = rb._mujoco.mj_step
    model = rb.model
    motor = rb.robot.motor
    k, res = motor.torque_constant, motor.resistance
    alpha, mean, rate = rb._alpha, rb._mean, rb._rate
    h = rb.timestep
    half_h = 0.5 * h
    dof_r, dof_l = rb.dofs
    qvel, qfrc = data.qvel, data.qfrc_applied
    i_r, i_l, b_r, b_l = state
    for _ in range(rb.substeps):
        w_r, w_l = float(qvel[dof_r]), float(qvel[dof_l])
        # Quasi-static current (V - K omega(s)) / R = u0 + u1 s over the step, and the
        # exact current u0 + u1 s - u1 / a + (i - u0 + u1 / a) exp(-a s).
        u0_r, u0_l = (v_r - k * w_r) / res, (v_l - k * w_l) / res
        u1_r, u1_l = -k * b_r / res, -k * b_l / res
        c_r, c_l = u1_r / rate, u1_l / rate
        d_r, d_l = i_r - u0_r + c_r, i_l - u0_l + c_l
        qfrc[dof_r] = k * (u0_r + u1_r * half_h - c_r + d_r * mean)  # K * mean current
        qfrc[dof_l] = k * (u0_l + u1_l * half_h - c_l + d_l * mean)
        mj_step(model, data)
        i_r = u0_r + u1_r * h - c_r + d_r * alpha
        i_l = u0_l + u1_l * h - c_l + d_l * alpha
        b_r = (float(qvel[dof_r]) - w_r) / h
        b_l = (float(qvel[dof_l]) - w_l) / h
    return i_r, i_l, b_r, b_l


def _yaw(q: Sequence[float]) -> float:
    """Heading (rotation about z) of the unit quaternion ``(w, x, y, z)``."""
    w, x, y, z = q
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


class RobotBatch:
    """``B`` runs of a :class:`MujocoRobot`, advanced together one control period at a time.

    Create with :meth:`MujocoRobot.batch`.

    Attributes
    ----------
    pose : ndarray, shape (3, B)
        ``(x, y, theta)`` now: the axle centre (m) and the heading (rad, unwrapped: it
        accumulates continuously from the start heading).
    wheels : ndarray, shape (4, B)
        ``(i_R, omega_R, i_L, omega_L)`` now: motor currents (A) and wheel joint speeds
        (rad/s, relative to the chassis), the layout of the kinematic plant's wheel state.
    """

    robot: MujocoRobot
    n: int
    pose: FloatArray
    wheels: FloatArray
    threads: int
    _beta: FloatArray
    _data: list[Any]
    _pool: ThreadPoolExecutor | None
    _chunks: list[tuple[int, int]]

    def __init__(self, robot: MujocoRobot, start: ArrayLike, *, threads: int | None) -> None:
        mujoco = robot._mujoco
        pose = np.array(start, dtype=np.float64, copy=True)
        if pose.ndim != 2 or pose.shape[0] != 3:
            raise ValueError(f"start must have shape (3, B), got {pose.shape}")
        if not np.isfinite(pose).all():
            raise ValueError("start must hold finite poses")
        n = pose.shape[1]
        if threads is None:
            threads = default_threads()
        if isinstance(threads, bool) or not isinstance(threads, Integral) or not (
                1 <= threads <= MAX_THREADS):
            raise ValueError(f"threads={threads!r} must be an integer in [1, {MAX_THREADS}]")
        probe = mujoco.MjData(robot.model)
        check_memory(n * (probe.nbuffer + probe.narena + _DATA_OVERHEAD),
                     what=f"a batch of {n} MuJoCo runs",
                     hint="simulate fewer runs at a time (batch_size)")
        self.robot = robot
        self.n = n
        self.pose = pose
        self.wheels = np.zeros((4, n))
        self._beta = np.zeros((2, n))  # joint accelerations over the last physics step
        self._data = []
        rest = robot.rest_qpos
        for j in range(n):
            data = mujoco.MjData(robot.model)
            qpos = rest.copy()
            if not robot.bench:
                qpos[0], qpos[1] = pose[0, j], pose[1, j]
                # heading: rotate the settled orientation about the vertical
                half = 0.5 * float(pose[2, j])
                yaw = np.array([math.cos(half), 0.0, 0.0, math.sin(half)])
                mujoco.mju_mulQuat(qpos[3:7], yaw, rest[3:7].copy())
            data.qpos[:] = qpos
            mujoco.mj_forward(robot.model, data)
            self._data.append(data)
        self.threads = min(int(threads), max(1, n))
        self._pool = (
            ThreadPoolExecutor(self.threads, thread_name_prefix="it2track-mujoco")
            if self.threads > 1 else None
        )
        bounds = np.linspace(0, n, self.threads + 1).round().astype(int)
        self._chunks = [(int(a), int(b)) for a, b in itertools.pairwise(bounds)
                        if b > a]

    def __enter__(self) -> RobotBatch:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

    def close(self) -> None:
        """Stop the worker threads (idempotent)."""
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None

    def step(self, volts: ArrayLike) -> None:
        """Advance every run by one control period with the voltages held.

        Parameters
        ----------
        volts : array_like, shape (2, B)
            ``(V_R, V_L)`` per run, V, applied as given (the caller saturates them).

        Raises
        ------
        ValueError
            If ``volts`` has the wrong shape or is not finite.
        PhysicsDivergedError
            If a run's physics diverged (the message names the run).
        """
        v = np.asarray(volts, dtype=np.float64)
        if v.shape != (2, self.n):
            raise ValueError(f"volts must have shape (2, {self.n}), got {v.shape}")
        if not np.isfinite(v).all():
            raise ValueError("volts must be finite")
        if self._pool is None or len(self._chunks) == 1:
            for a, b in self._chunks:
                self._advance(a, b, v)
            return
        futures = [self._pool.submit(self._advance, a, b, v) for a, b in self._chunks]
        for fut in futures:
            fut.result()

    def _advance(self, first: int, stop: int, volts: FloatArray) -> None:
        """Step runs ``first ... stop - 1`` by one control period (one thread's share)."""
        rb = self.robot
        dof_r, dof_l = rb.dofs
        pose, wheels, beta = self.pose, self.wheels, self._beta
        for j in range(first, stop):
            data = self._data[j]
            i_r, i_l, b_r, b_l = _advance_run(
                rb, data, float(volts[0, j]), float(volts[1, j]),
                (float(wheels[0, j]), float(wheels[2, j]), float(beta[0, j]), float(beta[1, j])),
            )
            qpos, qvel = data.qpos, data.qvel
            warned = any(data.warning[w].number for w in rb._bad)
            if warned or not (math.isfinite(i_r) and math.isfinite(i_l)
                              and np.isfinite(qpos).all() and np.isfinite(qvel).all()):
                raise PhysicsDivergedError(
                    f"run {j}: the physics failed by t = {data.time:g} s (MuJoCo found "
                    "non-finite or huge positions, speeds or accelerations, or ran out of room "
                    "for contacts)"
                )
            wheels[0, j], wheels[1, j] = i_r, float(qvel[dof_r])
            wheels[2, j], wheels[3, j] = i_l, float(qvel[dof_l])
            beta[0, j], beta[1, j] = b_r, b_l
            if rb.bench:
                continue
            theta = float(pose[2, j])
            yaw = _yaw((float(qpos[3]), float(qpos[4]), float(qpos[5]), float(qpos[6])))
            pose[0, j], pose[1, j] = float(qpos[0]), float(qpos[1])
            pose[2, j] = theta + math.remainder(yaw - theta, 2.0 * math.pi)

    def body_velocity(self) -> tuple[FloatArray, FloatArray]:
        """The chassis' true speeds now (from the physics, slip included).

        Returns
        -------
        v : ndarray, shape (B,)
            Speed of the axle centre along the heading, m/s.
        omega : ndarray, shape (B,)
            Yaw rate, rad/s.
        """
        v = np.zeros(self.n)
        w = np.zeros(self.n)
        if self.robot.bench:
            return v, w
        for j, data in enumerate(self._data):
            theta = float(self.pose[2, j])
            vx, vy = float(data.qvel[0]), float(data.qvel[1])
            v[j] = vx * math.cos(theta) + vy * math.sin(theta)
            w[j] = _yaw_rate(data)
        return v, w

    def data(self, j: int) -> Any:
        """Run ``j``'s ``mujoco.MjData`` (for rendering; do not modify it)."""
        return self._data[j]


def _yaw_rate(data: Any) -> float:
    """World-frame yaw rate of the free body: ``R @ omega_local``, z component."""
    q = data.qpos
    w, x, y, z = (float(q[3]), float(q[4]), float(q[5]), float(q[6]))
    ox, oy, oz = float(data.qvel[3]), float(data.qvel[4]), float(data.qvel[5])
    # third row of the rotation matrix of (w, x, y, z)
    r20 = 2.0 * (x * z - w * y)
    r21 = 2.0 * (y * z + w * x)
    r22 = 1.0 - 2.0 * (x * x + y * y)
    return r20 * ox + r21 * oy + r22 * oz

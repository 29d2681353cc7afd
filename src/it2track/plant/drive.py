"""Differential-drive robot: two DC-motor wheels plus unicycle kinematics.

Continuous model (paper §II.A, eqs. 9-10 in their standard form)::

    v     = r (omega_R + omega_L) / 2          translational speed, m/s
    w     = r (omega_R - omega_L) / (2 l)      rotational speed, rad/s
    dx/dt = v cos(theta),  dy/dt = v sin(theta),  dtheta/dt = w

with each wheel speed ``omega`` the shaft speed of a :class:`~it2track.plant.motor.MotorParams`
motor (no gearbox).

:class:`DifferentialDrive` advances it over one control period with the motor
voltages held (zero-order hold):

* wheel currents and speeds: exact (matrix exponential);
* heading: exact, since ``theta`` is a linear function of ``int omega``, itself an exact
  linear map of the wheel state and the voltages (a larger augmented exponential);
* position: ``x_{k+1} = x_k + int_0^ts v(s) cos(theta(s)) ds`` (``sin`` for ``y``) with a
  product quadrature rule on the Gauss-Legendre nodes of the period (see
  :class:`DifferentialDrive`).
"""

from __future__ import annotations

import functools
import math
import threading
from dataclasses import dataclass, field
from numbers import Integral, Real
from typing import Any

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike, NDArray

from ._sincos import _N_WORK, _sincos, _sincos_small
from .motor import MotorParams, _check_period

__all__ = [
    "GEOMETRY_RANGE",
    "MAX_PANELS",
    "MAX_QUADRATURE_NODES",
    "DifferentialDrive",
    "RobotParams",
    "body_velocity",
    "check_stiffness",
    "continuous_rhs",
    "discretisation_panels",
]

#: Most quadrature nodes per period. The product rule is exact for polynomial headings of
#: degree < n and already at rounding level with a handful (4 is the default); the
#: precomputation costs O(n^2) time and memory, so a million nodes would need terabytes.
MAX_QUADRATURE_NODES = 64


@functools.cache
def _blas_controller() -> Any:
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()  # (the BLAS libraries loaded now: numpy's and scipy's)


def single_threaded_blas() -> Any:
    """A context in which BLAS runs on the calling thread alone (threadpoolctl).

    OpenBLAS hands part of even a 5x5 LAPACK solve to its helper threads (its row
    interchanges have no size threshold), and ``scipy.linalg.expm`` solves one per call. When
    every core is busy -- ``it2track reproduce`` runs its figure workers beside the
    simulation -- each hand-over waits for a time slice: a robot's ~30 exponentials took
    0.3-0.5 s there instead of 2 ms. The numbers are the same bits (the helper threads only
    split the columns a row interchange moves). For small matrices only."""
    return _blas_controller().limit(limits=1, user_api="blas")


#: Range of ``half_track`` and ``wheel_radius`` accepted, m: from a micrometre to a thousand
#: kilometres. Outside it the turn rate ``r / (2 l)`` or the speed ``r omega`` overflows.
GEOMETRY_RANGE = (1e-6, 1e6)


@dataclass(frozen=True, kw_only=True)
class RobotParams:
    """Geometry of the differential-drive robot and its (identical) wheel motors.

    Parameters
    ----------
    motor : MotorParams, default ``MotorParams()``
        Parameters shared by both wheel motors.
    half_track : float, default 5.6
        Half the distance between the wheels, l, in m. The paper's Table 3 prints
        5.6 m; it is kept as the default.
    wheel_radius : float, default 0.2
        Wheel radius r in m.

    Raises
    ------
    ValueError
        If ``motor`` is not a :class:`MotorParams`, or ``half_track`` or ``wheel_radius``
        is not a real number in ``[1e-6, 1e6]`` m (:data:`GEOMETRY_RANGE`); the message names
        the field and value.
    """

    motor: MotorParams = field(default_factory=MotorParams)
    half_track: float = 5.6
    wheel_radius: float = 0.2

    def __post_init__(self) -> None:
        if not isinstance(self.motor, MotorParams):
            raise ValueError(f"motor must be a MotorParams, got {self.motor!r}")
        for name in ("half_track", "wheel_radius"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, Real):
                raise ValueError(f"{name} must be a real number, got {value!r}")
            value = float(value)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be finite and > 0, got {value!r}")
            if not GEOMETRY_RANGE[0] <= value <= GEOMETRY_RANGE[1]:
                raise ValueError(
                    f"{name}={value!r} m is outside [{GEOMETRY_RANGE[0]:g}, "
                    f"{GEOMETRY_RANGE[1]:g}] m (no robot is that size, and the kinematics "
                    "would overflow)"
                )
            object.__setattr__(self, name, value)


def body_velocity(
    params: RobotParams, omega_r: ArrayLike, omega_l: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Translational and rotational body speeds from the wheel speeds.

    Parameters
    ----------
    params : RobotParams
        Robot geometry (``wheel_radius`` r, ``half_track`` l).
    omega_r, omega_l : array_like
        Right and left wheel speeds in rad/s; broadcast against each other.

    Returns
    -------
    v : ndarray
        ``r (omega_r + omega_l) / 2`` in m/s, broadcast shape.
    w : ndarray
        ``r (omega_r - omega_l) / (2 l)`` in rad/s, broadcast shape.
    """
    wr = np.asarray(omega_r, dtype=np.float64)
    wl = np.asarray(omega_l, dtype=np.float64)
    r = params.wheel_radius
    v = r * (wr + wl) / 2.0
    w = r * (wr - wl) / (2.0 * params.half_track)
    return v, w


def continuous_rhs(
    state: ArrayLike, voltages: ArrayLike, params: RobotParams
) -> NDArray[np.float64]:
    """Time derivative of the full continuous robot state.

    Meant for reference ODE solutions (e.g. ``scipy.integrate.solve_ivp`` with the
    voltage held over each period) and for users building their own integrators.

    Parameters
    ----------
    state : array_like, shape (..., 7)
        ``[x, y, theta, i_R, omega_R, i_L, omega_L]`` (m, m, rad, A, rad/s, A, rad/s).
        Note the state axis is last here, unlike :meth:`DifferentialDrive.step`.
    voltages : array_like, shape (..., 2)
        ``[V_R, V_L]`` in V, applied as given (no saturation); broadcast against
        ``state[..., 0]``.
    params : RobotParams
        Robot and motor parameters.

    Returns
    -------
    ndarray, shape (..., 7)
        ``d state / dt`` in the same layout, over the broadcast batch shape.

    Raises
    ------
    ValueError
        If the last axis of ``state`` is not 7 long or that of ``voltages`` not 2.
    """
    s = np.asarray(state, dtype=np.float64)
    u = np.asarray(voltages, dtype=np.float64)
    if s.ndim < 1 or s.shape[-1] != 7:
        raise ValueError(f"state must have shape (..., 7), got {s.shape}")
    if u.ndim < 1 or u.shape[-1] != 2:
        raise ValueError(f"voltages must have shape (..., 2), got {u.shape}")
    m = params.motor
    theta = s[..., 2]
    i_r, w_r, i_l, w_l = s[..., 3], s[..., 4], s[..., 5], s[..., 6]
    v_r, v_l = u[..., 0], u[..., 1]
    v, w = body_velocity(params, w_r, w_l)
    rr, ll, jj, bb, kk = m.resistance, m.inductance, m.inertia, m.friction, m.torque_constant
    parts = (
        v * np.cos(theta),
        v * np.sin(theta),
        w,
        (v_r - rr * i_r - kk * w_r) / ll,
        (kk * i_r - bb * w_r) / jj,
        (v_l - rr * i_l - kk * w_l) / ll,
        (kk * i_l - bb * w_l) / jj,
    )
    return np.stack(np.broadcast_arrays(*parts), axis=-1)


def _augmented_motor_matrix(motor: MotorParams) -> NDArray[np.float64]:
    """5x5 generator of ``z = (i, omega, int i, int omega, V)`` with ``dV/dt = 0``."""
    a, b = motor.state_matrices()
    m = np.zeros((5, 5))
    m[:2, :2] = a
    m[:2, 4] = b
    m[2:4, :2] = np.eye(2)
    return m


#: Most integration panels the exact discretisation may need per period (about 1 ms each):
#: the panel count is ``ts`` times the motor's fastest rate, so an absurdly fast electrical
#: pole (``inductance = 1e-300``) would otherwise never finish.
MAX_PANELS = 20_000


def discretisation_panels(params: RobotParams, ts: float) -> float:
    """Panels :func:`_product_weights` uses for ``params`` at period ``ts``: the 1-norm of the
    motor generator times ``ts`` (about ``ts * (R + K) / L``), rounded up."""
    gen = _augmented_motor_matrix(params.motor)[[0, 1, 4]][:, [0, 1, 4]]
    with np.errstate(over="ignore", invalid="ignore"):
        norm = float(np.linalg.norm(gen * float(ts), 1))
    return math.ceil(norm) if math.isfinite(norm) else math.inf


def check_stiffness(params: RobotParams, ts: float) -> None:
    """Refuse motor parameters whose time constants are so short against ``ts`` that the
    exact discretisation could not be computed in reasonable time (or at all).

    Raises
    ------
    ValueError
        Naming the motor parameters, ``ts`` and the limit.
    """
    panels = discretisation_panels(params, ts)
    if panels > MAX_PANELS:
        m = params.motor
        raise ValueError(
            f"motor resistance={m.resistance!r}, inductance={m.inductance!r}, "
            f"inertia={m.inertia!r}, friction={m.friction!r}, "
            f"torque_constant={m.torque_constant!r} with ts={ts!r}: the motor's fastest rate "
            f"times the period is about {panels:.3g}, more than the {MAX_PANELS} the exact "
            "discretisation can integrate; check these values (e.g. an inductance far too "
            "small) or shorten ts"
        )


def _product_weights(
    generator: NDArray[np.float64], ts: float, nodes: NDArray[np.float64]
) -> NDArray[np.float64]:
    """:func:`_product_weights_of`, computed once per process for each generator, period and
    set of nodes (a robot built again -- every controller and variant of a study builds one --
    costs about 0.15 s of quadrature otherwise). The same numbers as computing them afresh,
    read-only."""
    g = np.ascontiguousarray(generator, dtype=np.float64)
    x = np.ascontiguousarray(nodes, dtype=np.float64)
    return _product_weights_cached(g.tobytes(), g.shape, float(ts), x.tobytes())


@functools.lru_cache(maxsize=64)
def _product_weights_cached(generator: bytes, shape: tuple[int, ...], ts: float,
                            nodes: bytes) -> NDArray[np.float64]:
    out = _product_weights_of(np.frombuffer(generator).reshape(shape), ts,
                              np.frombuffer(nodes))
    out.flags.writeable = False
    return out


def _product_weights_of(
    generator: NDArray[np.float64], ts: float, nodes: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Moments ``int_0^ts l_j(s) expm(generator s) ds`` for the Lagrange basis ``l_j``.

    ``l_j`` is the Lagrange polynomial of the interpolation nodes ``nodes`` (fractions of
    the period in (0, 1)). The integrals are computed once, by composite Gauss-Legendre
    quadrature with panels short enough for the fastest mode (``|generator| h <= 1``) and
    more points per panel than the polynomial degree needs, which makes them accurate
    to rounding for any number of nodes, period or stiffness.

    Returns
    -------
    ndarray, shape (n_nodes, dim, dim)
    """
    n = nodes.size
    dim = generator.shape[0]
    g = generator * ts  # dimensionless time u = s / ts in [0, 1]
    panels = max(1, math.ceil(np.linalg.norm(g, 1)))
    width = 1.0 / panels
    q = n + 20
    xq, wq = np.polynomial.legendre.leggauss(q)
    local = (xq + 1.0) / 2.0 * width  # points inside one panel
    e_local = np.stack([scipy.linalg.expm(g * t) for t in local])  # (q, dim, dim)
    e_panel = scipy.linalg.expm(g * width)
    out = np.zeros((n, dim, dim))
    e_start = np.eye(dim)
    for p in range(panels):
        u = p * width + local  # (q,) points of this panel
        basis = np.ones((q, n))  # l_j(u), product form (safe if u hits a node)
        for j in range(n):
            for k in range(n):
                if k != j:
                    basis[:, j] *= (u - nodes[k]) / (nodes[j] - nodes[k])
        exps = e_start[None, :, :] @ e_local  # expm(g u) at the panel points
        out += np.einsum("q,qj,qab->jab", wq * (width / 2.0), basis, exps)
        e_start = e_start @ e_panel
    return out * ts


_N_SCRATCH = 14 + _N_WORK  # buffers per batch shape used by DifferentialDrive.step


class _Scratch(threading.local):
    """Per-thread work buffers of :meth:`DifferentialDrive.step`, keyed by batch shape."""

    def __init__(self) -> None:
        self.buffers: dict[tuple[int, ...], NDArray[np.float64]] = {}

    def get(self, batch: tuple[int, ...], count: int) -> NDArray[np.float64]:
        buf = self.buffers.get(batch)
        if buf is None:
            if len(self.buffers) >= 4:  # keep memory bounded when batch shapes vary
                self.buffers.clear()
            buf = self.buffers[batch] = np.empty((count, *batch))
        return buf


class DifferentialDrive:
    """Exact-ZOH discrete plant for one control period ``ts``.

    All maps are precomputed in ``__init__``; :meth:`step` is then elementwise numpy
    arithmetic on ``(B,)`` rows: a handful of scalar-times-row sums per node, one sine and
    cosine of the heading and ``quadrature_nodes`` small-angle sine/cosine evaluations.

    Parameters
    ----------
    params : RobotParams
        Robot and motor parameters.
    ts : float
        Control period in s (the voltages are held constant over it), finite and > 0.
    quadrature_nodes : int, default 4
        Number of nodes n per period for the position integral, 1 to
        :data:`MAX_QUADRATURE_NODES` (64).

    Attributes
    ----------
    params : RobotParams
    ts : float
    quadrature_nodes : int
    nodes : ndarray, shape (quadrature_nodes,)
        Quadrature nodes as fractions of the period (Gauss-Legendre nodes on (0, 1)).

    Raises
    ------
    ValueError
        If ``ts`` is not finite and > 0, or ``quadrature_nodes`` is not an integer in
        ``[1, 64]``.

    Notes
    -----
    Over a period, ``v(s)`` and ``theta(s)`` are exact linear functions of the wheel
    state and the voltages at the start of the period. The position increment
    ``int_0^ts v(s) cos(theta(s)) ds`` is evaluated with the *product* rule on the n
    Gauss-Legendre nodes ``s_j``::

        sum_j W_j cos(theta(s_j)),   W_j = int_0^ts l_j(s) v(s) ds

    where ``l_j`` is the Lagrange polynomial of the nodes. ``W_j`` is itself an exact
    linear map of (wheels, voltages), precomputed per node. The rule is exact whenever
    ``cos(theta(s))`` is a polynomial of degree < n, and ``v(s)`` enters exactly, fast
    electrical transient included (about 9 time constants per 10 ms period for the
    Table-3 motor). Plain Gauss-Legendre (``w_j v(s_j) cos(theta(s_j))``) would need that
    transient to be polynomial too; with 4 nodes it leaves ~1.7e-6 m of error after 10 s
    of random voltages, against ~6e-9 m for this rule at the same cost. Because the
    weights sum to ``int v``, straight-line motion is integrated exactly.

    ``cos(theta(s_j))`` is formed as ``cos(theta_k) cos(D_j) - sin(theta_k) sin(D_j)``
    with ``D_j = theta(s_j) - theta_k``, using a vectorised sine/cosine that is within
    1 ulp of the C library and several times faster than ``np.sin``/``np.cos``.

    The heading is not wrapped: ``theta`` accumulates continuously.

    Every operation in :meth:`step` is elementwise over the batch (no BLAS, no
    reductions across runs), so the result for a run is bit-for-bit the same whether it
    is advanced alone or inside any batch. Work buffers (21 rows of the batch shape) are
    kept per thread and per batch shape, for up to 4 shapes; an instance may be shared
    between threads and pickled.

    Examples
    --------
    >>> import numpy as np
    >>> plant = DifferentialDrive(RobotParams(), 0.01)
    >>> pose, wheels = np.zeros((3, 2)), np.zeros((4, 2))
    >>> volts = np.array([[12.0, 6.0], [12.0, -6.0]])
    >>> for _ in range(100):
    ...     pose, wheels = plant.step(pose, wheels, volts)
    >>> pose.shape, wheels.shape
    ((3, 2), (4, 2))
    >>> bool(pose[2, 0] == 0.0 and pose[0, 1] == 0.0)  # straight line / turn on the spot
    True
    """

    params: RobotParams
    ts: float
    quadrature_nodes: int
    nodes: NDArray[np.float64]
    _scratch: _Scratch
    _wheel: tuple[float, ...]
    _heading: tuple[float, ...]
    _node_speed: tuple[tuple[float, ...], ...]
    _node_heading: tuple[tuple[float, ...], ...]

    def __init__(self, params: RobotParams, ts: float, *, quadrature_nodes: int = 4) -> None:
        if not isinstance(params, RobotParams):
            raise ValueError(f"params must be a RobotParams, got {params!r}")
        ts = _check_period(ts)
        if (
            isinstance(quadrature_nodes, bool)
            or not isinstance(quadrature_nodes, Integral)
            or not 1 <= quadrature_nodes <= MAX_QUADRATURE_NODES
        ):
            raise ValueError(
                f"quadrature_nodes must be an integer in [1, {MAX_QUADRATURE_NODES}], got "
                f"{quadrature_nodes!r}"
            )
        n = int(quadrature_nodes)
        self.params = params
        self.ts = ts
        self.quadrature_nodes = n
        self._scratch = _Scratch()

        r = params.wheel_radius
        turn = r / (2.0 * params.half_track)  # heading change per (rad of wheel difference)
        gen = _augmented_motor_matrix(params.motor)  # state (i, w, int i, int w, V)
        check_stiffness(params, ts)

        # ~30 exponentials of 5x5 matrices, without BLAS threads (the same bits, without
        # waiting for a busy core at each: see single_threaded_blas)
        with single_threaded_blas():
            # One period: wheel state (exact ZOH) and heading increment (exact).
            e = scipy.linalg.expm(gen * ts)
            self._wheel = tuple(
                float(e[a, b]) for a, b in ((0, 0), (0, 1), (0, 4), (1, 0), (1, 1), (1, 4))
            )
            self._heading = tuple(float(turn * e[3, b]) for b in (0, 1, 4))

            # Quadrature nodes on (0, 1) and per-node linear maps; the maps act on the wheel
            # sums (i_R+i_L, w_R+w_L, V_R+V_L) for v and differences for theta.
            x, _ = np.polynomial.legendre.leggauss(n)
            self.nodes = (x + 1.0) / 2.0
            self.nodes.setflags(write=False)
            heading_nodes = np.empty((3, n))
            for j, frac in enumerate(self.nodes):
                ej = scipy.linalg.expm(gen * (frac * ts))
                heading_nodes[:, j] = turn * ej[3, 0], turn * ej[3, 1], turn * ej[3, 4]
            mom = _product_weights(gen[[0, 1, 4]][:, [0, 1, 4]], ts, self.nodes)  # (n, 3, 3)
        speed_nodes = (r / 2.0) * mom[:, 1, :].T  # row of omega -> v per unit wheel sum
        self._node_speed = tuple(tuple(float(c) for c in col) for col in speed_nodes.T)
        self._node_heading = tuple(tuple(float(c) for c in col) for col in heading_nodes.T)

    def __getstate__(self) -> dict[str, object]:
        state = self.__dict__.copy()
        del state["_scratch"]  # per-thread work buffers: neither picklable nor needed
        return state

    def __setstate__(self, state: dict[str, object]) -> None:
        self.__dict__.update(state)
        self._scratch = _Scratch()

    def __repr__(self) -> str:
        return (
            f"DifferentialDrive({self.params!r}, ts={self.ts!r}, "
            f"quadrature_nodes={self.quadrature_nodes})"
        )

    def step(
        self, pose: ArrayLike, wheels: ArrayLike, voltages: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Advance a batch of robots by one period with the voltages held.

        Parameters
        ----------
        pose : array_like, shape (3, B)
            Rows x (m), y (m), theta (rad) at the start of the period.
        wheels : array_like, shape (4, B)
            Rows i_R (A), omega_R (rad/s), i_L (A), omega_L (rad/s).
        voltages : array_like, shape (2, B)
            Rows V_R, V_L in V, held over the period. Used as given: saturate them
            beforehand (:meth:`MotorParams.saturate`); ``step`` does not clip.

        Returns
        -------
        pose_next : ndarray, shape (3, B)
            Pose at the end of the period (theta not wrapped).
        wheels_next : ndarray, shape (4, B)
            Wheel state at the end of the period.

        Raises
        ------
        ValueError
            If the leading axes are not 3, 4 and 2 long, or the batch shapes differ.

        Notes
        -----
        B may be any size, including 1; any trailing batch shape ``(3, ...)`` works the
        same way. The inputs are not modified; new arrays are returned.
        """
        p = np.asarray(pose, dtype=np.float64)
        w = np.asarray(wheels, dtype=np.float64)
        u = np.asarray(voltages, dtype=np.float64)
        if p.ndim < 2 or p.shape[0] != 3:
            raise ValueError(f"pose must have shape (3, B), got {p.shape}")
        if w.ndim < 2 or w.shape[0] != 4:
            raise ValueError(f"wheels must have shape (4, B), got {w.shape}")
        if u.ndim < 2 or u.shape[0] != 2:
            raise ValueError(f"voltages must have shape (2, B), got {u.shape}")
        batch = p.shape[1:]
        if w.shape[1:] != batch or u.shape[1:] != batch:
            raise ValueError(
                "pose, wheels and voltages must share the batch shape, got "
                f"{p.shape}, {w.shape}, {u.shape}"
            )
        x, y, th = p[0], p[1], p[2]
        i_r, w_r, i_l, w_l = w[0], w[1], w[2], w[3]
        v_r, v_l = u[0], u[1]
        scratch = self._scratch.get(batch, _N_SCRATCH)
        s_i, s_w, s_v, d_i, d_w, d_v, sin0, cos0, acc_c, acc_s = scratch[:10]
        weight, delta, sn, cs = scratch[10:14]
        work = list(scratch[14:])
        # Every operation below is elementwise over the batch (no BLAS, no reductions):
        # a run's result is bit-identical whatever batch it is computed in.

        # Wheel sums drive the translational speed, differences the heading.
        np.add(i_r, i_l, out=s_i)
        np.add(w_r, w_l, out=s_w)
        np.add(v_r, v_l, out=s_v)
        np.subtract(i_r, i_l, out=d_i)
        np.subtract(w_r, w_l, out=d_w)
        np.subtract(v_r, v_l, out=d_v)

        # Position increment sum_j W_j (cos, sin)(theta_k + D_j), with the angle-sum formula
        # (cos, sin)(theta_k + D_j) from (cos, sin) theta_k and (cos, sin) D_j.
        _sincos(th, sin0, cos0, work)
        for j, ((w0, w1, w2), (a0, a1, a2)) in enumerate(
            zip(self._node_speed, self._node_heading, strict=True)
        ):
            np.multiply(s_i, w0, out=weight)  # W_j: metres per unit of cos/sin
            np.multiply(s_w, w1, out=sn)
            weight += sn
            np.multiply(s_v, w2, out=sn)
            weight += sn
            np.multiply(d_i, a0, out=delta)  # D_j = theta(s_j) - theta_k
            np.multiply(d_w, a1, out=sn)
            delta += sn
            np.multiply(d_v, a2, out=sn)
            delta += sn
            _sincos_small(delta, sn, cs, work)
            if j == 0:
                np.multiply(cs, weight, out=acc_c)
                np.multiply(sn, weight, out=acc_s)
            else:
                cs *= weight
                acc_c += cs
                sn *= weight
                acc_s += sn

        pose_next = np.empty(p.shape)
        # x += cos0 C - sin0 S ; y += sin0 C + cos0 S
        np.multiply(cos0, acc_c, out=cs)
        np.multiply(sin0, acc_s, out=sn)
        cs -= sn
        np.add(x, cs, out=pose_next[0])
        np.multiply(sin0, acc_c, out=cs)
        np.multiply(cos0, acc_s, out=sn)
        cs += sn
        np.add(y, cs, out=pose_next[1])
        h0, h1, h2 = self._heading
        np.multiply(d_i, h0, out=delta)
        np.multiply(d_w, h1, out=sn)
        delta += sn
        np.multiply(d_v, h2, out=sn)
        delta += sn
        np.add(th, delta, out=pose_next[2])

        a00, a01, b0, a10, a11, b1 = self._wheel
        wheels_next = np.empty(w.shape)
        for row, (cur, spd, volt) in enumerate(((i_r, w_r, v_r), (i_l, w_l, v_l))):
            out_i, out_w = wheels_next[2 * row], wheels_next[2 * row + 1]
            np.multiply(cur, a00, out=out_i)
            np.multiply(spd, a01, out=sn)
            out_i += sn
            np.multiply(volt, b0, out=sn)
            out_i += sn
            np.multiply(cur, a10, out=out_w)
            np.multiply(spd, a11, out=sn)
            out_w += sn
            np.multiply(volt, b1, out=sn)
            out_w += sn
        return pose_next, wheels_next

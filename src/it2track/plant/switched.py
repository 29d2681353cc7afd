"""The kinematic robot over a period in which the wheel voltages change once: input latency.

A controller that needs time to compute applies its output late: over a control period
``[t_k, t_k + ts)`` the motors keep the previous voltages for the first ``d_k`` seconds and get
the new ones after. :class:`SwitchedDrive` advances the robot of
:class:`~it2track.plant.drive.DifferentialDrive` exactly over such a period: two zero-order-hold
sub-periods, ``[0, d)`` with ``v_before`` and ``[d, ts)`` with ``v_after``, each with the
drive's own exact discretisation (matrix exponentials for the wheels and the heading, the
product quadrature rule on the sub-period's Gauss-Legendre nodes for the position), computed
for that sub-period's length. ``d`` is per run, so every run of a batch can switch at its own
instant.

A switch at ``d = 0`` is the drive's step with ``v_after`` and one at ``d = ts`` its step with
``v_before``, bit for bit (those runs take exactly that path). The maps of a sub-period length
are computed once, vectorised over all new lengths of a call, and cached (a controller's
latencies repeat: they are whole clock cycles).
"""

from __future__ import annotations

import copy
import functools
import math
import threading
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .drive import DifferentialDrive, _augmented_motor_matrix

__all__ = ["SwitchedDrive", "sub_period_maps"]

FloatArray = NDArray[np.float64]

#: Most sub-period lengths whose maps a :class:`SwitchedDrive` keeps (each is
#: ``6 + 3 + 6 n`` floats for ``n`` quadrature nodes: 264 bytes at the default 4).
CACHE_SIZE = 200_000


_TAYLOR_DEGREE = 18  # after scaling to a 1-norm <= 1/2: truncation below 1e-22 (relative)


def _expm(a: FloatArray) -> FloatArray:
    """Matrix exponentials of a stack of small matrices ``(..., d, d)``, vectorised (scipy's
    ``expm`` loops over a stack in Python: ~30 us a matrix).

    Scaling and squaring with a Taylor polynomial: each matrix is scaled by ``2^-s`` to a
    1-norm of at most 1/2, where the degree-18 Taylor polynomial is exact to far below
    rounding, then squared ``s`` times.
    """
    norm = np.abs(a).sum(axis=-2).max(axis=-1)
    with np.errstate(divide="ignore"):
        s = np.maximum(0, np.ceil(np.log2(norm / 0.5))).astype(np.int64)
    x = a / np.ldexp(1.0, s)[..., None, None]
    eye = np.broadcast_to(np.eye(a.shape[-1]), a.shape)
    result = eye.copy()
    for k in range(_TAYLOR_DEGREE, 0, -1):
        result = x @ result
        result /= k
        result += eye
    for it in range(int(s.max(initial=0))):
        sel = s > it
        if sel.all():
            result = result @ result
        else:
            result[sel] = result[sel] @ result[sel]
    return result


@functools.lru_cache(maxsize=64)
def _rule(panels: int, nodes: tuple[float, ...]) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The composite Gauss-Legendre rule of :class:`DifferentialDrive`'s own precomputation on
    ``panels`` panels of ``[0, 1]``: the points within one panel ``(q,)``, the weights times
    each panel's Lagrange basis of ``nodes``, ``(panels, q, n)``, and the panel width."""
    n = len(nodes)
    x = np.array(nodes)
    width = 1.0 / panels
    q = n + 20
    xq, wq = np.polynomial.legendre.leggauss(q)
    local = (xq + 1.0) / 2.0 * width
    weighted = np.empty((panels, q, n))
    for p in range(panels):
        u = p * width + local
        basis = np.ones((q, n))
        for j in range(n):
            for k in range(n):
                if k != j:
                    basis[:, j] *= (u - x[k]) / (x[j] - x[k])
        weighted[p] = basis * (wq * (width / 2.0))[:, None]
    return local, weighted, np.array(width)


def sub_period_maps(drive: DifferentialDrive, lengths: ArrayLike) -> FloatArray:
    """The coefficients :meth:`DifferentialDrive.step` uses, for periods of other lengths.

    Computed as the drive computes its own (matrix exponentials for the wheels and the
    heading at the period's end and at its quadrature nodes; the product rule's weights
    ``int l_j(s) expm(g s) ds`` by composite Gauss-Legendre on panels short enough for the
    fastest mode), vectorised over the lengths: every exponential of a call in one stacked
    evaluation, all lengths on the panels the longest needs.

    Parameters
    ----------
    drive : DifferentialDrive
        Robot, motors and quadrature nodes.
    lengths : array_like, shape (m,)
        Sub-period lengths, s, each finite and > 0.

    Returns
    -------
    ndarray, shape (m, 9 + 6 n)
        Per length: the wheel map ``(a00, a01, b0, a10, a11, b1)``, the heading map (3), then
        per node ``j`` its speed weights (3) and heading map (3), in the order of
        ``drive``'s own coefficients (``n = drive.quadrature_nodes``). For ``drive.ts`` they
        equal ``drive``'s to rounding.

    Raises
    ------
    ValueError
        If a length is not finite and > 0.
    """
    tau = np.asarray(lengths, dtype=np.float64).reshape(-1)
    if tau.size and not (np.isfinite(tau).all() and (tau > 0).all()):
        raise ValueError(f"lengths must be finite and > 0, got {tau[~(tau > 0)][:3].tolist()}")
    params = drive.params
    n = drive.quadrature_nodes
    nodes = np.asarray(drive.nodes)
    r = params.wheel_radius
    turn = r / (2.0 * params.half_track)
    gen = _augmented_motor_matrix(params.motor)  # (i, w, int i, int w, V)
    m = tau.size
    out = np.empty((m, 9 + 6 * n))
    if m == 0:
        return out
    # The (i, w, V) block of expm(gen t) is expm of gen's (i, w, V) block (the integrals do not
    # feed back): one stacked evaluation serves the wheels, the heading and the moments.
    sub = [0, 1, 4]
    g3 = gen[np.ix_(sub, sub)]
    panels = max(1, math.ceil(float(np.linalg.norm(g3 * tau.max(), 1))))
    local, weighted, width = _rule(panels, tuple(float(v) for v in nodes))
    q = local.size
    fractions = np.concatenate([local, [float(width), 1.0], nodes])  # of each length
    e_all = _expm(gen[None, None] * (tau[:, None] * fractions[None, :])[:, :, None, None])
    e = e_all[:, q + 1]  # (m, 5, 5): the whole sub-period
    out[:, 0:6] = e[:, [0, 0, 0, 1, 1, 1], [0, 1, 4, 0, 1, 4]]
    out[:, 6:9] = turn * e[:, 3, sub]
    e_local = e_all[:, :q][:, :, sub][:, :, :, sub]  # (m, q, 3, 3)
    e_panel = e_all[:, q][:, sub][:, :, sub]  # (m, 3, 3)
    mom = np.zeros((m, n, 3))  # only the speed row (w) of the moments is needed
    e_start = np.broadcast_to(np.eye(3), (m, 3, 3)).copy()
    for p in range(panels):
        rows = np.einsum("mb,mqbc->mqc", e_start[:, 1, :], e_local)  # w row at the points
        mom += np.einsum("qj,mqc->mjc", weighted[p], rows)
        e_start = e_start @ e_panel
    mom *= tau[:, None, None]
    ej = e_all[:, q + 2:]  # (m, n, 5, 5)
    for j in range(n):
        base = 9 + 6 * j
        out[:, base:base + 3] = (r / 2.0) * mom[:, j, :]
        out[:, base + 3:base + 6] = turn * ej[:, j, 3, sub]
    return out


def _with_maps(drive: DifferentialDrive, maps: FloatArray) -> DifferentialDrive:
    """A view of ``drive`` whose step uses per-run coefficients: ``maps`` ``(B, 9 + 6 n)``.

    :meth:`DifferentialDrive.step` multiplies its rows by its coefficients elementwise, so
    with ``(B,)`` arrays in their place it steps each run over its own period length.
    """
    view = copy.copy(drive)
    cols = [np.ascontiguousarray(maps[:, c]) for c in range(maps.shape[1])]
    n = drive.quadrature_nodes
    coefficients: dict[str, Any] = {
        "_wheel": tuple(cols[0:6]),
        "_heading": tuple(cols[6:9]),
        "_node_speed": tuple(tuple(cols[9 + 6 * j:12 + 6 * j]) for j in range(n)),
        "_node_heading": tuple(tuple(cols[12 + 6 * j:15 + 6 * j]) for j in range(n)),
    }
    vars(view).update(coefficients)
    return view


class SwitchedDrive:
    """Exact step of the kinematic robot over a period whose voltages switch once per run.

    Parameters
    ----------
    drive : DifferentialDrive
        The robot discretised for the control period ``drive.ts``.

    Examples
    --------
    >>> import numpy as np
    >>> from it2track.plant import DifferentialDrive, RobotParams
    >>> drive = DifferentialDrive(RobotParams(), 0.01)
    >>> switched = SwitchedDrive(drive)
    >>> pose, wheels = np.zeros((3, 3)), np.zeros((4, 3))
    >>> before, after = np.zeros((2, 3)), np.full((2, 3), 6.0)
    >>> p, w = switched.step(pose, wheels, before, after, np.array([0.0, 0.004, 0.01]))
    >>> p0, w0 = drive.step(pose[:, :1], wheels[:, :1], after[:, :1])
    >>> bool((p[:, 0] == p0[:, 0]).all() and w[1, 2] == 0.0)  # d = 0: at once; d = ts: never
    True
    >>> bool(0.0 < w[1, 1] < w[1, 0])  # d = 4 ms: part of the way
    True
    """

    def __init__(self, drive: DifferentialDrive) -> None:
        if not isinstance(drive, DifferentialDrive):
            raise ValueError(f"drive must be a DifferentialDrive, got {drive!r}")
        self.drive = drive
        self.ts = drive.ts
        self._lock = threading.Lock()
        self._cache: dict[float, FloatArray] = {}

    def __repr__(self) -> str:
        return f"SwitchedDrive({self.drive!r})"

    def __getstate__(self) -> dict[str, object]:
        return {"drive": self.drive}

    def __setstate__(self, state: dict[str, object]) -> None:
        drive = state["drive"]
        assert isinstance(drive, DifferentialDrive)
        self.__init__(drive)  # type: ignore[misc]

    def maps(self, lengths: FloatArray) -> FloatArray:
        """:func:`sub_period_maps` of ``lengths`` ``(m,)``, through the cache."""
        with self._lock:
            missing = [v for v in np.unique(lengths).tolist() if v not in self._cache]
        if missing:
            new = sub_period_maps(self.drive, np.array(missing))
            with self._lock:
                if len(self._cache) + len(missing) > CACHE_SIZE:
                    self._cache.clear()
                for v, row in zip(missing, new, strict=True):
                    self._cache[v] = row
        with self._lock:
            got = [self._cache.get(v) for v in lengths.tolist()]
        rows = [row for row in got if row is not None]
        if len(rows) < len(got):  # evicted by another thread meanwhile
            return sub_period_maps(self.drive, lengths)
        return np.stack(rows) if rows else np.empty((0, 9 + 6 * self.drive.quadrature_nodes))

    def step(self, pose: ArrayLike, wheels: ArrayLike, v_before: ArrayLike, v_after: ArrayLike,
             switch: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Advance a batch by one period, ``v_before`` held over ``[0, switch)`` and
        ``v_after`` over ``[switch, ts)``.

        Parameters
        ----------
        pose : array_like, shape (3, B)
            x (m), y (m), theta (rad) at the start of the period.
        wheels : array_like, shape (4, B)
            i_R (A), omega_R (rad/s), i_L (A), omega_L (rad/s).
        v_before, v_after : array_like, shape (2, B)
            V_R, V_L (V) before and after the switch (used as given: saturate beforehand).
        switch : array_like, shape (B,)
            The switching instant of each run, s after the period's start, in ``[0, ts]``.

        Returns
        -------
        pose_next : ndarray, shape (3, B)
        wheels_next : ndarray, shape (4, B)

        Raises
        ------
        ValueError
            If the shapes disagree, or a switch is NaN or outside ``[0, ts]``.
        """
        p = np.asarray(pose, dtype=np.float64)
        w = np.asarray(wheels, dtype=np.float64)
        vb = np.asarray(v_before, dtype=np.float64)
        va = np.asarray(v_after, dtype=np.float64)
        d = np.asarray(switch, dtype=np.float64)
        if p.ndim != 2 or p.shape[0] != 3:
            raise ValueError(f"pose must have shape (3, B), got {p.shape}")
        b = p.shape[1]
        for name, arr, rows in (("wheels", w, 4), ("v_before", vb, 2), ("v_after", va, 2)):
            if arr.shape != (rows, b):
                raise ValueError(f"{name} must have shape ({rows}, {b}), got {arr.shape}")
        if d.shape != (b,):
            raise ValueError(f"switch must have shape ({b},), got {d.shape}")
        ok = (d >= 0.0) & (d <= self.ts)
        if not ok.all():
            bad = float(d[~ok][0])
            raise ValueError(f"switch={bad!r} s must be in [0, ts={self.ts!r}]")
        mid = (d > 0.0) & (d < self.ts)
        held = np.where(d == 0.0, va, vb)  # a switch at 0 is v_after all along, at ts never
        if not mid.any():
            return self.drive.step(p, w, held)
        pose_next, wheels_next = np.empty((3, b)), np.empty((4, b))
        ends = np.flatnonzero(~mid)
        if ends.size:
            pose_next[:, ends], wheels_next[:, ends] = self.drive.step(
                p[:, ends], w[:, ends], held[:, ends])
        inside = np.flatnonzero(mid)
        if inside.size:
            di = d[inside]
            both = self.maps(np.concatenate([di, self.ts - di]))  # one call for both parts
            first = _with_maps(self.drive, both[:di.size])
            second = _with_maps(self.drive, both[di.size:])
            pm, wm = first.step(p[:, inside], w[:, inside], vb[:, inside])
            pm, wm = second.step(pm, wm, va[:, inside])
            pose_next[:, inside] = pm
            wheels_next[:, inside] = wm
        return pose_next, wheels_next

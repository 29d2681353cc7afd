"""The heading-tracking task: the paper's loop (Fig. 3, DESIGN.md sec. 5) on a robot plant.

At control instant ``k`` every run computes ``theta_d`` from its pose and the reference point,
measures the heading with noise, forms ``e``, ``de``, evaluates its controller and drives the
wheels with ``V0 +- u`` (saturated), then the robot plant advances one period (see
:mod:`.simulate` for the whole description). :class:`_Engine` is the numpy reference engine; it
reaches the robot only through the plant protocol (:mod:`it2track.plant.base`), so any
:class:`~it2track.plant.base.RobotPlant` runs here, and the kinematic robot also on the compiled
engine (:mod:`.compiled`), bit for bit the same.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..plant import DifferentialDrive, RobotParams, held_sample_index
from ..plant.base import RobotPlant, check_robot_plant
from ..plant.kinematic import KinematicPlant
from ..plant.noise import NoiseRows
from .actuation import Actuation
from .config import ON_PATH, LoopConfig, PoseTiming
from .controllers import HeadingController
from .libm import atan2
from .loopdefs import NOISE_TABLE_BYTES, controller_groups, held_noise, noise_rows
from .metrics import MetricAccumulator
from .runs import TRACE_FIELDS, RunTable
from .trajectories import Trajectory

__all__ = ["NOISE_TABLE_BYTES", "build_robot_plant", "noise_rows", "wrap_angle"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

TWO_PI = 2.0 * math.pi


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


@functools.lru_cache(maxsize=32)
def _kinematic(robot: RobotParams, ts: float, nodes: int) -> KinematicPlant:
    """Plant maps for one robot and period, built once (about 30 small matrix exponentials,
    slow when a busy BLAS spins up threads) and shared: ``DifferentialDrive`` is immutable
    and keeps its scratch buffers per thread."""
    return KinematicPlant(robot, ts, quadrature_nodes=nodes)


def build_robot_plant(config: LoopConfig) -> RobotPlant:
    """The robot plant ``config`` names (the kinematic robot for ``plant=None``), checked
    against the plant protocol and the heading task's inputs and outputs."""
    if config.plant is None:
        return _kinematic(config.robot, config.ts, config.quadrature_nodes)
    plant = config.plant.build(ts=config.ts, robot=config.robot)
    what = f"LoopConfig.plant ({config.plant.kind!r})"
    plant = check_robot_plant(plant, config.ts, what=what)
    if any(lim != plant.input_limits[0] or lim[0] != -lim[1] for lim in plant.input_limits):
        raise ValueError(f"{what}: input_limits={plant.input_limits!r} must be the same "
                         "symmetric (-V, V) range for both wheels")
    return plant


class _Engine:
    """Precomputed, batch-independent pieces of a simulation (plant maps, references)."""

    def __init__(self, trajectories: Sequence[Trajectory], config: LoopConfig) -> None:
        self.config = config
        self.plant = build_robot_plant(config)
        #: The kinematic robot's discretisation (what the compiled engine runs), or None.
        self.drive: DifferentialDrive | None = (
            self.plant.drive if isinstance(self.plant, KinematicPlant) else None)
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
        self.v_lim = float(self.plant.input_limits[0][1])

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
        z = held_noise(cfg.seed, self.n_noise, seeds, std, noise)  # noise in rad
        groups, states = controller_groups(controllers, ctrl, cfg.ts)

        plant = self.plant
        actuation = Actuation(groups, plant, 2, n_steps, record=record)
        plant_state = plant.initial_state(
            n, pose=np.ascontiguousarray(self.start[tidx].T) if n else np.empty((3, 0)))
        out = plant.outputs(plant_state)  # ROBOT_OUTPUTS rows: x, y, theta, omega_R/L, v, omega
        pose = out[:3]
        previous = cfg.desired_heading_pose is PoseTiming.PREVIOUS
        prev_xy = pose[:2].copy()  # pose at t_(k-1) for PoseTiming.PREVIOUS (t_0 at k = 0)
        volts = np.empty((2, n))
        u = np.empty(n)
        acc = MetricAccumulator(n, cfg.ts, n_steps, self.v_lim,
                                start_index=cfg.metric_start_index)
        rec = {f: np.empty((n_steps + 1, n)) for f in TRACE_FIELDS} if record else None
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
                    "v_left": volts[1], "omega_right": out[3], "omega_left": out[4],
                    "v": out[5], "omega": out[6],
                }  # fmt: skip
                for name, value in row.items():
                    rec[name][k] = value
            if k < n_steps:
                if previous:
                    prev_xy[:] = pose[:2]
                plant_state = actuation.step(plant_state, volts, k * cfg.ts)
                out = plant.outputs(plant_state)
                pose = out[:3]
            e_prev, e_meas = e_meas, e_prev

        inv = np.empty_like(order)
        inv[order] = np.arange(n)
        metrics = {name: value[inv] for name, value in acc.result().items()}
        series = None
        if rec is not None:
            rec.update(actuation.recorded())
            series = {name: np.ascontiguousarray(value.T[inv]) for name, value in rec.items()}
        return metrics, series

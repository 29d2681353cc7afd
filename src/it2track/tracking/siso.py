"""The reference-tracking task: a controller holds a single-input plant's output at ``r(t)``.

Chosen by giving :func:`~it2track.tracking.simulate` (or ``simulate_metrics``) a sequence of
:class:`~it2track.tracking.references.Reference` instead of trajectories, with a single-input
plant in ``LoopConfig.plant`` (a DC motor's speed, a pendulum, a tank level...). The plant's
*first* output ``y`` is the controlled one (its other outputs are recorded). At control instant
``k`` (``t_k = k ts``, ``k = 0 ... N``) every run:

1. measures ``y_meas = y_k + sigma z[j(t_k)]`` (the noise of :mod:`.simulate`: Gaussian, held at
   ``LoopConfig.noise_rate``, common random numbers across controllers and references);
2. forms ``e_k = r(t_k) - y_meas`` and ``de_k = e_k - e_(k-1)`` (``de_0 = 0``);
3. evaluates its controller, ``u = controller.output(e, de, state)``;
4. applies ``sat(u)``, the plant's ``input_limits``, held over the period (``k < N``).

Metrics have the names of :data:`~it2track.tracking.metrics.METRIC_NAMES` with ``e = r - y``
(see :mod:`.metrics`). Series (:data:`REFERENCE_FIELDS`, plus ``"y.<name>"`` for each plant
output) have shape ``(B, N+1)``. The robot-only options of :class:`LoopConfig` (``robot``,
``start_pose``, ``quadrature_nodes``, ``desired_heading_pose``) do not apply here.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..plant import held_sample_index
from ..plant.base import Plant, check_plant
from ..plant.noise import NoiseRows
from .actuation import Actuation
from .config import LoopConfig
from .controllers import HeadingController
from .loopdefs import controller_groups, held_noise
from .metrics import MetricAccumulator
from .references import Reference
from .runs import RunTable

__all__ = ["REFERENCE_FIELDS", "build_siso_plant"]

FloatArray = NDArray[np.float64]

#: Time-series fields of a reference-tracking :class:`~it2track.tracking.Trace` (besides
#: ``"y.<name>"``, every output of the plant).
REFERENCE_FIELDS: tuple[str, ...] = (
    "r",                    # reference r(t_k)
    "y",                    # controlled (first) plant output
    "y_meas",               # y + noise
    "e_true", "e_meas",     # r - y, r - y_meas
    "de",                   # change of the measured error
    "u",                    # controller output (the requested plant input)
    "u_applied",            # the input applied: u saturated to the plant's input_limits
)  # fmt: skip


def build_siso_plant(config: LoopConfig) -> Plant:
    """The single-input plant ``config.plant`` describes, built and checked.

    Parameters
    ----------
    config : LoopConfig
        Its ``plant`` must be set (``None`` is the robot, which tracks trajectories).

    Returns
    -------
    Plant
        One input; at least one output.

    Raises
    ------
    ValueError
        If ``config.plant`` is None, breaks the plant protocol, or has several inputs.
    """
    if config.plant is None:
        raise ValueError(
            "tracking a reference signal needs a single-input plant: LoopConfig.plant is None "
            "(the paper's robot, which tracks trajectories); set LoopConfig.plant, e.g. "
            "it2track.plant.linear.LinearSpec or it2track.plant.control.from_control(sys)"
        )
    what = f"LoopConfig.plant ({config.plant.kind!r})"
    plant = check_plant(config.plant.build(ts=config.ts, robot=config.robot), config.ts,
                        what=what)  # fmt: skip
    if len(plant.input_names) != 1:
        raise ValueError(
            f"{what} has {len(plant.input_names)} inputs {plant.input_names}; a reference "
            "signal drives a single-input plant (trajectories drive a robot)"
        )
    return plant


class ReferenceEngine:
    """Precomputed, batch-independent pieces of a reference-tracking simulation.

    Parameters
    ----------
    references : sequence of Reference
        Indexed by ``runs.trajectory``.
    config : LoopConfig
        Period, duration, noise rate, seed, metric window and the plant.
    """

    def __init__(self, references: Sequence[Reference], config: LoopConfig) -> None:
        self.config = config
        self.plant = build_siso_plant(config)
        t = config.times
        # Rows indexed by time so that row k is contiguous: (N+1, n_ref).
        self.r = np.ascontiguousarray(np.stack([ref.sample(t) for ref in references]).T)
        self.hold = held_sample_index(t, config.noise_rate)
        self.n_noise = int(self.hold[-1]) + 1
        low, high = self.plant.input_limits[0]
        self.limits = (float(low), float(high))
        self.fields = REFERENCE_FIELDS + tuple(f"y.{n}" for n in self.plant.output_names)

    def run(
        self,
        controllers: Sequence[HeadingController],
        runs: RunTable,
        *,
        record: bool,
        noise: NoiseRows | None = None,
    ) -> tuple[dict[str, FloatArray], dict[str, FloatArray] | None]:
        """Simulate ``runs`` (``runs.trajectory`` indexes the references).

        Parameters
        ----------
        controllers : sequence of HeadingController
            Indexed by ``runs.controller``.
        runs : RunTable
            The runs.
        record : bool
            Keep the time series.
        noise : NoiseRows, optional
            Rows drawn beforehand for the noisy runs' seeds (else drawn here).

        Returns
        -------
        metrics : dict of str -> ndarray, shape (B,)
        series : dict of str -> ndarray, shape (B, N+1), or None
            In the order of ``runs``.
        """
        cfg = self.config
        n = len(runs)
        n_steps = cfg.n_steps
        order = np.argsort(runs.controller, kind="stable")
        ctrl = runs.controller[order]
        ridx = runs.trajectory[order]
        std = runs.noise_std[order]
        z = held_noise(cfg.seed, self.n_noise, runs.seed[order], std, noise)
        groups, states = controller_groups(controllers, ctrl, cfg.ts)

        plant = self.plant
        actuation = Actuation(groups, plant, 1, n_steps, record=record)
        pstate = plant.initial_state(n)
        y_all = plant.outputs(pstate)
        low, high = self.limits
        acc = MetricAccumulator(n, cfg.ts, n_steps, high, start_index=cfg.metric_start_index,
                                limits=self.limits)  # fmt: skip
        rec = ({f: np.empty((n_steps + 1, n)) for f in self.fields} if record else None)
        r, y_meas, e_true, dist = np.empty((4, n))
        e_meas, e_prev = np.empty(n), np.empty(n)  # swapped each step
        de = np.zeros(n)  # de_0 = 0
        u = np.empty(n)
        u_in = np.empty((1, n))
        for k in range(n_steps + 1):
            np.take(self.r[k], ridx, out=r)
            y = y_all[0]
            np.add(y, z[self.hold[k]], out=y_meas)
            np.subtract(r, y, out=e_true)
            np.subtract(r, y_meas, out=e_meas)
            if k:
                np.subtract(e_meas, e_prev, out=de)
            for (c, sl), state in zip(groups, states, strict=True):
                u[sl] = c.output(e_meas[sl], de[sl], state)
                actuation.after_output(k, c, sl, state)
            np.clip(u, low, high, out=u_in[0])
            np.abs(e_true, out=dist)
            acc.update(k, e_true=e_true, e_meas=e_meas, distance=dist, u=u, v_requested=(u,))
            if rec is not None:
                row = {"r": r, "y": y, "y_meas": y_meas, "e_true": e_true, "e_meas": e_meas,
                       "de": de, "u": u, "u_applied": u_in[0]}  # fmt: skip
                for name, value in row.items():
                    rec[name][k] = value
                for i, name in enumerate(plant.output_names):
                    rec[f"y.{name}"][k] = y_all[i]
            if k < n_steps:
                pstate = actuation.step(pstate, u_in, k * cfg.ts)
                y_all = plant.outputs(pstate)
            e_prev, e_meas = e_meas, e_prev

        inv = np.empty_like(order)
        inv[order] = np.arange(n)
        metrics = {name: value[inv] for name, value in acc.result().items()}
        series = None
        if rec is not None:
            rec.update(actuation.recorded())
            series = {name: np.ascontiguousarray(value.T[inv]) for name, value in rec.items()}
        return metrics, series

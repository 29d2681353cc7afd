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

The robot is a plant (:mod:`it2track.plant.base`): ``LoopConfig.plant = None`` is the paper's
kinematic robot, which the compiled engine runs (:mod:`.compiled`; the numpy engine of
:mod:`.heading` is its bit-for-bit reference); any other robot plant (e.g. a physics model)
runs on the numpy engine. Given reference signals (:mod:`.references`) instead of
trajectories, the same calls run the reference-tracking task of :mod:`.siso` on a
single-input plant (``e = r - y``): a DC motor's speed, a pendulum, a tank level.

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

from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from .._limits import check_memory, loop_bytes
from ..plant.noise import NoiseRows
from . import compiled as _compiled
from .config import ON_PATH, LoopConfig, PoseTiming
from .controllers import HeadingController
from .heading import (  # noqa: F401  (_Engine, noise_rows, _wrap_inplace: engine tests use them)
    NOISE_TABLE_BYTES,
    _Engine,
    _wrap_inplace,
    noise_rows,
    wrap_angle,
)
from .references import Reference
from .runs import MAX_INDEX, TRACE_FIELDS, RunTable, Trace, run_grid  # noqa: F401
from .siso import ReferenceEngine
from .trajectories import Trajectory

__all__ = [
    "ON_PATH",
    "TRACE_FIELDS",
    "LoopConfig",
    "PoseTiming",
    "RunTable",
    "Target",
    "Trace",
    "check_task",
    "run_grid",
    "simulate",
    "simulate_metrics",
    "wrap_angle",
]

FloatArray = NDArray[np.float64]

#: What a run follows: a trajectory (the robot, by heading) or a reference signal (a
#: single-input plant).
Target = Trajectory | Reference


def _check_inputs(
    controllers: Sequence[HeadingController],
    trajectories: Sequence[Target],
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
    if not _references(trajectories):
        for i, tr in enumerate(trajectories):
            if not isinstance(tr, Trajectory):
                mixed = (" (reference signals and trajectories cannot be mixed in one call)"
                         if isinstance(tr, Reference) else "")
                raise ValueError(f"trajectories[{i}]={tr!r} is not a Trajectory{mixed}")
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


def check_task(trajectories: Sequence[Target], config: LoopConfig) -> None:
    """Check, before any simulation, that ``config.plant`` fits the task ``trajectories``
    selects: trajectories need a robot plant (or None), reference signals a single-input plant.

    Parameters
    ----------
    trajectories : sequence of Trajectory, or sequence of Reference
        The targets of the runs (all of one kind).
    config : LoopConfig
        Its plant is built (for ``config.ts`` and ``config.robot``) and checked.

    Raises
    ------
    ValueError
        If the targets mix trajectories and references, the plant does not fit, or a
        target cannot be sampled; the message names the plant and what it lacks.
    """
    _check_inputs([], trajectories, RunTable([], [], [], []))
    if not trajectories:
        raise ValueError("no trajectories or references given")
    _engine(trajectories, config)


def _references(targets: Sequence[Trajectory | Reference]) -> bool:
    """Whether ``targets`` selects the reference-tracking task (all references)."""
    return bool(targets) and all(isinstance(t, Reference) for t in targets)


def _engine(
    targets: Sequence[Trajectory | Reference], config: LoopConfig
) -> _Engine | ReferenceEngine:
    """The numpy engine of the task ``targets`` selects: trajectories are tracked by heading
    with a robot plant (:mod:`.heading`), reference signals by a single-input plant
    (:mod:`.siso`)."""
    if _references(targets):
        return ReferenceEngine(targets, config)  # type: ignore[arg-type]
    return _Engine(targets, config)  # type: ignore[arg-type]


def _run(
    engine: _Engine | ReferenceEngine,
    controllers: Sequence[HeadingController],
    runs: RunTable,
    *,
    record: bool,
    noise: NoiseRows | None = None,
) -> tuple[dict[str, FloatArray], dict[str, FloatArray] | None]:
    """``engine.run`` with every run the compiled engine supports done by it (same bits);
    ``noise``: rows drawn beforehand for the noisy runs' seeds (else drawn here)."""
    if isinstance(engine, ReferenceEngine):
        return engine.run(controllers, runs, record=record, noise=noise)
    if not len(runs) or engine.drive is None:
        return engine.run(controllers, runs, record=record, noise=noise)
    fast = np.array([_compiled.supported(c) is None for c in controllers], dtype=bool)
    fast_run = fast[runs.controller]
    # (the size lets a small call run on numpy while a long job waits for the compiled loop)
    jit = (_compiled.load(run_steps=float(np.count_nonzero(fast_run)) * engine.config.n_steps)
           if fast_run.any() else None)
    if jit is None:
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
    trajectories: Sequence[Target],
    runs: RunTable,
    config: LoopConfig | None = None,
) -> Trace:
    """Simulate a batch of runs and keep their time series.

    Parameters
    ----------
    controllers : sequence of HeadingController
        Indexed by ``runs.controller``.
    trajectories : sequence of Trajectory, or sequence of Reference
        Indexed by ``runs.trajectory``. Trajectories: the robot tracks them by heading
        (``config.plant`` a robot plant or None). References: the reference-tracking task
        (:mod:`.siso`; ``config.plant`` a single-input plant).
    runs : RunTable
        The ``B`` runs.
    config : LoopConfig, optional
        Defaults to ``LoopConfig()`` (10 s at 100 Hz, paper Table 3 robot).

    Returns
    -------
    Trace
        Series of shape ``(B, N+1)`` and metrics of shape ``(B,)``, in the order of ``runs``
        (series :data:`TRACE_FIELDS` for trajectories, :data:`~.siso.REFERENCE_FIELDS` and the
        plant's outputs for references). Memory is ``17 * 8 * B * (N+1)`` bytes for the robot;
        use :func:`simulate_metrics` for big batches.

    Raises
    ------
    ValueError
        For arguments of the wrong type, indices out of range, trajectories mixed with
        references, a plant that does not fit the task, or a run that cannot be computed.
    """
    config = config or LoopConfig()
    _check_inputs(controllers, trajectories, runs, config, record=True)
    engine = _engine(trajectories, config)
    metrics, series = _run(engine, controllers, runs, record=True)
    assert series is not None
    return Trace(t=config.times, runs=runs, series=series, metrics=metrics)


def simulate_metrics(
    controllers: Sequence[HeadingController],
    trajectories: Sequence[Target],
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
    engine = _engine(trajectories, config)
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

"""The compiled closed-loop engine: which runs it serves, and how they are handed to it.

:func:`~.simulate.simulate` and :func:`~.simulate.simulate_metrics` send every run whose
controller :func:`supported` accepts to the numba kernel (``._jit``) and the others to the numpy
engine (``._Engine.run``), which stays the reference: both give the same bits (tests compare
them), so which engine ran a run never shows in its results.

Supported controllers (an allow-list): :class:`.PDHeadingController`, and
:class:`.FuzzyHeadingController` over a system that :func:`it2track.fuzzy.kernels.supported`
accepts (IT2Sugeno/T1Sugeno with compiled membership kinds, no rule-language features, a
built-in reducer). Exactly these classes: a subclass may change the behaviour, so it goes to
numpy. ``IT2TRACK_ENGINE=numpy`` sends everything to numpy.

Every option of :class:`.LoopConfig` is implemented (start pose or ``"on_path"``, desired
heading timing, metric window, period, noise rate, robot, quadrature nodes), with the numpy
engine's precomputed references, noise and plant maps. Runs that would raise in the fuzzy
reference (zero firing without ``on_zero_firing``, no convergence) are re-run by the numpy
engine, which raises its own error.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..fuzzy import kernels as fuzzy_kernels
from ..plant.noise import NoiseRows
from .controllers import FuzzyHeadingController, HeadingController, PDHeadingController

if TYPE_CHECKING:
    from .simulate import RunTable, _Engine

__all__ = ["run", "supported"]

FloatArray = NDArray[np.float64]


def supported(controller: HeadingController) -> str | None:
    """``None`` if the compiled loop implements ``controller``, else why not."""
    if type(controller) is PDHeadingController:
        return None
    if type(controller) is FuzzyHeadingController:
        why = fuzzy_kernels.supported(controller.fls)
        if why is None and fuzzy_kernels.extended(controller.fls):
            why = ("its membership kinds, t-norm or defuzzifier need the fuzzy kernels' "
                   "extended specialisation, which the closed-loop kernel does not compile")
        return None if why is None else f"its fuzzy system: {why}"
    return f"{type(controller).__name__} is not a built-in heading controller"


def load(run_steps: float = math.inf) -> Any:
    """The compiled loop module, or None (numba missing, ``IT2TRACK_ENGINE=numpy``, or the
    loop being compiled in the background: :func:`it2track.fuzzy.kernels.deferred`, which a
    call of ``run_steps`` (runs x steps) may wait for)."""
    if fuzzy_kernels.engine() == "numpy" or fuzzy_kernels.deferred("loop", run_steps):
        return None
    if fuzzy_kernels.import_jit() is None:
        return None
    from . import _jit

    return _jit


def _pack_controllers(controllers: Sequence[HeadingController]) -> tuple[FloatArray, NDArray[Any]]:
    parts: list[FloatArray] = []
    for c in controllers:
        if isinstance(c, PDHeadingController) and type(c) is PDHeadingController:
            parts.append(np.array([1.0, c.kp, c.kd, c.tf, c.u_max]))
        elif type(c) is FuzzyHeadingController and supported(c) is None:
            parts.append(np.concatenate([[0.0, c.ke, c.kde], fuzzy_kernels.pack(c.fls)]))
        else:
            parts.append(np.array([-1.0]))  # never referenced by a block
    offsets = np.zeros(len(parts) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([p.size for p in parts])
    packed = np.concatenate(parts) if parts else np.zeros(0)
    # read-only like a fuzzy system's own packing: the kernels then share one specialisation
    packed.setflags(write=False)
    return packed, offsets


def _plant_vector(engine: _Engine) -> FloatArray:
    d = engine.drive
    if d is None:
        raise ValueError("the compiled engine runs the kinematic robot only")
    nodes = [v for speed, head in zip(d._node_speed, d._node_heading, strict=True)
             for v in (*speed, *head)]  # fmt: skip
    return np.array([*d._wheel, *d._heading, *nodes], dtype=np.float64)


def run(
    jit: Any,
    engine: _Engine,
    controllers: Sequence[HeadingController],
    runs: RunTable,
    *,
    record: bool,
    noise: NoiseRows | None = None,
) -> tuple[dict[str, FloatArray], dict[str, FloatArray] | None, NDArray[np.int8]]:
    """Simulate ``runs`` (all with supported controllers) with the compiled kernel.

    Returns the metrics and (if ``record``) the series like ``_Engine.run``, in the order of
    ``runs``, and a status per run: not 0 where the fuzzy reference would raise (that run's
    numbers are then meaningless and the caller re-runs it with numpy). ``noise``: rows drawn
    beforehand for the noisy runs' seeds (else drawn here; runs with sigma = 0 draw none).
    """
    from .loopdefs import TRACE_FIELDS, PoseTiming, noise_rows
    from .metrics import METRIC_NAMES

    cfg = engine.config
    n = len(runs)
    n_steps = cfg.n_steps
    # Blocks hold one controller; sorted by path within it, most blocks follow one path.
    order = np.lexsort((runs.trajectory, runs.controller))
    ctrl = runs.controller[order]
    traj = runs.trajectory[order]
    std = np.ascontiguousarray(runs.noise_std[order])
    z, inverse = noise_rows(cfg.seed, engine.n_noise, runs.seed[order], std, noise)
    blocks = []
    lanes = jit.LANES
    a = 0
    while a < n:
        b = a
        while b < n and b - a < lanes and ctrl[b] == ctrl[a]:
            b += 1
        blocks.append((a, b, int(ctrl[a]), int(traj[a])))
        a = b
    packed, offsets = _pack_controllers(controllers)
    robot = cfg.robot
    vec = np.array([
        cfg.ts, engine.v_lim, 0.5 * robot.wheel_radius,
        robot.wheel_radius / (2.0 * robot.half_track), n_steps, cfg.metric_start_index,
        1.0 if cfg.desired_heading_pose is PoseTiming.PREVIOUS else 0.0,
    ])  # fmt: skip
    metrics = np.empty((n, jit.N_METRICS))
    rec = np.empty((jit.N_FIELDS, n, n_steps + 1) if record else (jit.N_FIELDS, 0, 0))
    status = np.zeros(n, dtype=np.int8)
    blocks_arr = np.array(blocks, dtype=np.int64).reshape(-1, 4)
    shared = (
        np.ascontiguousarray(traj),
        std, inverse, z,
        np.ascontiguousarray(engine.hold, dtype=np.int64), engine.x_ref, engine.y_ref,
        engine.v0, np.ascontiguousarray(engine.start), _plant_vector(engine), vec,
        metrics, rec, record, status,
    )  # fmt: skip
    parts = max(1, min(fuzzy_kernels.threads(), len(blocks)))
    fuzzy_kernels.run_threads([
        (jit.loop, (packed, offsets, np.ascontiguousarray(blocks_arr[i::parts]), *shared))
        for i in range(parts)
    ])  # fmt: skip
    inv = np.empty_like(order)
    inv[order] = np.arange(n)
    out = {name: np.ascontiguousarray(metrics[inv, i]) for i, name in enumerate(METRIC_NAMES)}
    series = None
    if record:
        series = {name: rec[i][inv] for i, name in enumerate(TRACE_FIELDS)}
    return out, series, status[inv]

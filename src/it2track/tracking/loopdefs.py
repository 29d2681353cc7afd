"""What the closed-loop engines share: the numpy engines of both tasks (:mod:`.heading`,
:mod:`.siso`) and the compiled loop (:mod:`.compiled`).

The timing of the desired heading, the names of the recorded series, the noise rows of a batch
of runs, its held noise and its controller groups. They live apart from :mod:`.simulate`
because :mod:`.simulate` imports :mod:`.compiled`, which needs them: with them here, neither
imports the other back.
"""

from __future__ import annotations

import enum
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..plant.noise import NoiseRows
from .controllers import HeadingController

__all__ = [
    "NOISE_TABLE_BYTES",
    "TRACE_FIELDS",
    "PoseTiming",
    "controller_groups",
    "held_noise",
    "noise_rows",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


class PoseTiming(enum.Enum):
    """Which pose the desired heading ``theta_d`` at instant ``k`` is computed from.

    ``CURRENT`` (default): the pose at ``t_k``, i.e. the one the previous period produced
    (DESIGN.md sec. 5). ``PREVIOUS``: the pose at ``t_(k-1)`` (one more period of delay), the
    paper's eqs. 20-21 read literally (``y_d(k) - y(k - 1)``); at ``k = 0`` the start pose.
    """

    CURRENT = "current"
    PREVIOUS = "previous"


#: Time-series fields of a :class:`~.simulate.Trace`, each an array of shape ``(B, N+1)``.
TRACE_FIELDS: tuple[str, ...] = (
    "x", "y", "theta",          # pose at t_k (theta unwrapped), m, m, rad
    "x_ref", "y_ref",           # reference point at t_k, m
    "theta_d",                  # desired heading atan2(...), rad
    "theta_meas",               # measured heading theta + noise, rad
    "e_true", "e_meas",         # wrapped heading errors (true / measured), rad
    "de",                       # change of the measured error, rad
    "u",                        # controller output, V
    "v_right", "v_left",        # wheel voltages applied (saturated), V
    "omega_right", "omega_left",  # wheel speeds at t_k, rad/s
    "v", "omega",               # body translational (m/s) and rotational (rad/s) speed
)  # fmt: skip


def noise_rows(
    seed: int, n_noise: int, seeds: IntArray, std: FloatArray, table: NoiseRows | None = None
) -> tuple[FloatArray, IntArray]:
    """Standard-noise rows for runs with seed indices ``seeds`` and noise levels ``std``:
    ``(rows, index)``, run ``r``'s row ``rows[index[r]]`` (zeros where ``std[r] == 0``, which
    draws nothing). ``table``: rows drawn beforehand for these seeds (else drawn here)."""
    if table is None:
        table = NoiseRows(seed, seeds[std > 0.0], n_noise)
    return table.lookup(seeds, std)


#: Most bytes :func:`~.simulate.simulate_metrics` keeps for the noise rows its chunks share (each
#: distinct seed index of a noisy run drawn once per call: 8 kB per seed at 1001 samples, so
#: 64 MiB is ~8000 seeds). Beyond it every chunk draws its own seeds' rows.
NOISE_TABLE_BYTES = 64 << 20


def held_noise(
    seed: int, n_noise: int, seeds: IntArray, std: FloatArray, table: NoiseRows | None
) -> FloatArray:
    """The scaled noise ``z[j, r] = std[r] * row_r[j]`` of every run, shape ``(n_noise, B)``
    (row ``j`` contiguous: the loop reads one held sample of every run at a time)."""
    n = std.size
    z_rows, inverse = noise_rows(seed, n_noise, seeds, std, table)
    # Built in blocks of runs so the transposing copy stays in cache (~3x faster than one
    # big gather).
    z = np.empty((n_noise, n))
    for a in range(0, n, 256):
        b = min(a + 256, n)
        np.multiply(z_rows[inverse[a:b]].T, std[a:b], out=z[:, a:b])
    return z


def controller_groups(
    controllers: Sequence[HeadingController], ctrl: IntArray, ts: float
) -> tuple[list[tuple[HeadingController, slice]], list[FloatArray]]:
    """``(groups, states)`` for runs sorted by controller index ``ctrl``: one
    ``(controller, slice)`` per controller present and its runs' initial state."""
    n = ctrl.size
    bounds = np.flatnonzero(np.diff(ctrl)) + 1
    starts = np.concatenate([[0], bounds])
    stops = np.concatenate([bounds, [n]])
    groups = [
        (controllers[int(ctrl[a])], slice(int(a), int(b)))
        for a, b in zip(starts, stops, strict=True)
    ] if n else []
    states = [c.initial_state(s.stop - s.start, ts) for c, s in groups]
    return groups, states

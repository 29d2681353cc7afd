"""What both closed-loop engines share: the numpy reference (:mod:`.simulate`) and the
compiled loop (:mod:`.compiled`).

The timing of the desired heading, the names of the recorded series and the noise rows of a
batch of runs. They live apart from :mod:`.simulate` because :mod:`.simulate` imports
:mod:`.compiled`, which needs them: with them here, neither imports the other back.
"""

from __future__ import annotations

import enum

import numpy as np
from numpy.typing import NDArray

from ..plant.noise import NoiseRows

__all__ = ["TRACE_FIELDS", "PoseTiming", "noise_rows"]

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

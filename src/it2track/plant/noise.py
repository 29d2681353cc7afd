"""Heading-sensor noise: Gaussian, zero-order held, seeded per run.

The measured heading is ``theta_hat(t) = theta(t) + n(t)`` with
``n(t) = std * z[held_sample_index(t, rate)]``, where ``z`` is the run's row of
:func:`standard_noise`. A run's ``z`` depends only on ``(seed, index)``, so every
controller, trajectory or noise level that shares a seed index sees the same sequence,
scaled by ``std`` (common random numbers), however the runs are batched or distributed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Integral, Real

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "MAX_NOISE_STD",
    "HeadingNoise",
    "NoiseRows",
    "held_sample_index",
    "noise_samples_needed",
    "run_generator",
    "standard_noise",
]

#: Largest heading-noise standard deviation accepted, rad. Beyond about 10 rad the wrapped
#: noise is already uniform on the circle; at 1e6 rad ``theta + n`` keeps ~1e-10 rad of
#: resolution, and far beyond it ``sigma * z`` loses the heading entirely, then overflows.
MAX_NOISE_STD = 1e6

#: Relative tolerance of :func:`held_sample_index`: ``t * rate`` within this of an
#: integer ``k`` counts as ``k`` (absorbs the rounding of ``k * ts * rate``).
_INDEX_TOL = 1e-9


def _real(value: object, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, Real):
        raise ValueError(f"{name} must be a real number, got {value!r}")
    out = float(value)
    if not math.isfinite(out):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return out


def _nonneg_int(value: object, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, Integral) or value < 0:
        raise ValueError(f"{name} must be an integer >= 0, got {value!r}")
    return int(value)


@dataclass(frozen=True, kw_only=True)
class HeadingNoise:
    """Gaussian heading noise held constant for ``1 / rate`` seconds at a time.

    Parameters
    ----------
    std : float, default 0.0
        Standard deviation in rad, finite and >= 0 (0: no noise).
    rate : float, default 100.0
        Noise sample rate in Hz, finite and > 0; each value is held (zero-order hold)
        for ``1 / rate`` s.

    Raises
    ------
    ValueError
        If ``std`` < 0 or ``rate`` <= 0 or either is not finite; the message names the
        field and the value.

    Examples
    --------
    >>> HeadingNoise.from_band_limited_power(0.1, 0.01)  # the paper's 0.1 W at 100 Hz
    HeadingNoise(std=3.1622776601683795, rate=100.0)
    """

    std: float = 0.0
    rate: float = 100.0

    def __post_init__(self) -> None:
        std = _real(self.std, "std")
        if not 0.0 <= std <= MAX_NOISE_STD:
            raise ValueError(
                f"std must be in [0, {MAX_NOISE_STD:g}] rad, got {self.std!r}"
                + (" (the noise power and sample time give that)" if std > 0 else "")
            )
        rate = _real(self.rate, "rate")
        if rate <= 0.0:
            raise ValueError(f"rate must be > 0, got {self.rate!r}")
        object.__setattr__(self, "std", std)
        object.__setattr__(self, "rate", rate)

    @classmethod
    def from_band_limited_power(cls, power: float, sample_time: float) -> HeadingNoise:
        """Noise equivalent to Simulink's "Band-Limited White Noise" block.

        That block outputs Gaussian samples of variance ``power / sample_time`` held for
        ``sample_time``.

        Parameters
        ----------
        power : float
            Noise power P (the block's "noise power"), finite and >= 0.
        sample_time : float
            Sample time Ts in s, finite and > 0.

        Returns
        -------
        HeadingNoise
            With ``std = sqrt(power / sample_time)`` and ``rate = 1 / sample_time``.

        Raises
        ------
        ValueError
            If ``power`` < 0 or ``sample_time`` <= 0 or either is not finite.
        """
        p = _real(power, "power")
        if p < 0.0:
            raise ValueError(f"power must be >= 0, got {power!r}")
        ts = _real(sample_time, "sample_time")
        if ts <= 0.0:
            raise ValueError(f"sample_time must be > 0, got {sample_time!r}")
        variance = p / ts
        if not variance <= MAX_NOISE_STD**2:  # also inf (overflow)
            raise ValueError(
                f"power={power!r} with sample_time={sample_time!r} gives a noise std "
                f"sqrt(power / sample_time) = {math.sqrt(variance):.3g} rad, above the largest "
                f"allowed, {MAX_NOISE_STD:g} rad"
            )
        return cls(std=math.sqrt(variance), rate=1.0 / ts)


def run_generator(seed: int, index: int) -> np.random.Generator:
    """Generator of run number ``index`` under base ``seed``.

    ``default_rng(SeedSequence(seed, spawn_key=(index,)))``, identical to the generator
    of ``SeedSequence(seed).spawn(n)[index]`` for any ``n > index``: a run's random
    numbers depend only on ``(seed, index)``, never on the worker, batch or chunk.

    Parameters
    ----------
    seed : int
        Base seed, >= 0.
    index : int
        Run index, >= 0.

    Returns
    -------
    numpy.random.Generator

    Raises
    ------
    ValueError
        If ``seed`` or ``index`` is not an integer >= 0.
    """
    s = _nonneg_int(seed, "seed")
    i = _nonneg_int(index, "index")
    return np.random.default_rng(np.random.SeedSequence(s, spawn_key=(i,)))


def standard_noise(
    seed: int, indices: ArrayLike, n_samples: int, *, out: NDArray[np.float64] | None = None
) -> NDArray[np.float64]:
    """Standard-normal noise rows for the given runs.

    Parameters
    ----------
    seed : int
        Base seed, >= 0.
    indices : array_like of int, shape (n_runs,)
        Run indices, each >= 0 (repeats allowed).
    n_samples : int
        Samples per run, >= 0.
    out : ndarray, shape (n_runs, n_samples), optional
        C-contiguous float64 array to fill (and return) instead of a new one.

    Returns
    -------
    ndarray, shape (n_runs, n_samples)
        Row ``j`` is ``run_generator(seed, indices[j]).standard_normal(n_samples)``, so it
        does not depend on which other indices are in the call.

    Raises
    ------
    ValueError
        If ``indices`` is not 1-D of integers >= 0, or ``seed`` or ``n_samples`` is not an
        integer >= 0.
    """
    s = _nonneg_int(seed, "seed")
    n = _nonneg_int(n_samples, "n_samples")
    idx = np.asarray(indices)
    if idx.ndim != 1:
        raise ValueError(f"indices must be 1-D, got shape {idx.shape}")
    if idx.size and (not np.issubdtype(idx.dtype, np.integer) or idx.min() < 0):
        raise ValueError(f"indices must be integers >= 0, got {indices!r}")
    if out is None:
        out = np.empty((idx.size, n))
    elif out.shape != (idx.size, n) or out.dtype != np.float64 or not out.flags.c_contiguous:
        raise ValueError(f"out must be a C-contiguous float64 array of shape {(idx.size, n)}, "
                         f"got {out.dtype} {out.shape}")
    for row, i in enumerate(idx.tolist()):
        run_generator(s, i).standard_normal(out=out[row])  # the same draws as (n)
    return out


class NoiseRows:
    """The standard-normal rows of a set of seed indices, drawn once and shared.

    Common random numbers: every run with seed index ``i`` uses the row
    ``standard_noise(seed, [i], n_samples)[0]`` scaled by its own ``std``, so a study of many
    controllers, trajectories and noise levels on the same seeds needs each row once. Runs
    with ``std == 0`` use a row of zeros (no draw): their noise ``0 * 0.0`` is ``+0.0``.

    Parameters
    ----------
    seed : int
        Base seed, >= 0.
    indices : array_like of int, shape (n,)
        Seed indices to draw (repeats allowed; each distinct index is drawn once).
    n_samples : int
        Samples per row, >= 0.

    Attributes
    ----------
    seeds : ndarray of int64, shape (m,)
        The distinct indices, sorted.
    rows : ndarray, shape (m + 1, n_samples)
        Row ``j < m`` is seed ``seeds[j]``'s noise; row ``m`` is zeros. Memory
        ``8 (m + 1) n_samples`` bytes.

    Examples
    --------
    >>> table = NoiseRows(7, [3, 1, 3], 4)
    >>> rows, index = table.lookup([3, 9], [0.1, 0.0])
    >>> index.tolist(), bool((rows[index[0]] == standard_noise(7, [3], 4)[0]).all())
    ([1, 2], True)
    """

    def __init__(self, seed: int, indices: ArrayLike, n_samples: int) -> None:
        idx = np.asarray(indices)
        if idx.ndim != 1:
            raise ValueError(f"indices must be 1-D, got shape {idx.shape}")
        self.seeds: NDArray[np.int64] = np.unique(idx).astype(np.int64)
        n = _nonneg_int(n_samples, "n_samples")
        self.rows: NDArray[np.float64] = np.empty((self.seeds.size + 1, n))
        standard_noise(seed, self.seeds, n, out=self.rows[: self.seeds.size])
        self.rows[self.seeds.size] = 0.0

    @staticmethod
    def nbytes(n_indices: int, n_samples: int) -> int:
        """Bytes of the rows of ``n_indices`` distinct indices."""
        return 8 * (n_indices + 1) * n_samples

    def lookup(
        self, indices: ArrayLike, std: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
        """Rows for runs: ``(rows, index)`` with ``rows[index[r]]`` run ``r``'s standard noise
        (the zero row where ``std[r] == 0``).

        Raises
        ------
        ValueError
            If a run with ``std > 0`` has an index this table did not draw.
        """
        idx = np.asarray(indices, dtype=np.int64)
        noisy = np.asarray(std) > 0.0
        index = np.full(idx.size, self.seeds.size, dtype=np.int64)
        pos = np.searchsorted(self.seeds, idx[noisy])
        pos_ok = np.minimum(pos, max(self.seeds.size - 1, 0))
        if pos.size and (self.seeds.size == 0 or (self.seeds[pos_ok] != idx[noisy]).any()):
            raise ValueError("NoiseRows.lookup: a noisy run's seed index was not drawn")
        index[noisy] = pos
        return self.rows, index


def held_sample_index(times: ArrayLike, rate: float) -> NDArray[np.int64]:
    """Index of the held noise sample active at each time.

    ``floor(t * rate)``, rounded so that a time on a sample boundary (``t = k / rate``
    up to floating-point rounding, e.g. ``t = k * ts`` with ``ts = 1 / rate``) gives
    ``k`` and never ``k - 1``: ``t * rate`` within a relative 1e-9 of an integer counts
    as that integer.

    Parameters
    ----------
    times : array_like of float, any shape
        Times in s, finite and >= 0.
    rate : float
        Noise sample rate in Hz, finite and > 0.

    Returns
    -------
    ndarray of int64, same shape as ``times``

    Raises
    ------
    ValueError
        If any time is negative or not finite, or ``rate`` is not finite and > 0.

    Examples
    --------
    >>> held_sample_index([0.0, 0.01, 0.02, 0.03, 0.3], 50.0).tolist()
    [0, 0, 1, 1, 15]
    """
    r = _real(rate, "rate")
    if r <= 0.0:
        raise ValueError(f"rate must be > 0, got {rate!r}")
    t = np.asarray(times, dtype=np.float64)
    if not np.all(np.isfinite(t)) or np.any(t < 0.0):
        raise ValueError("times must be finite and >= 0")
    u = t * r
    return np.floor(u + _INDEX_TOL * np.maximum(1.0, u)).astype(np.int64)


def noise_samples_needed(duration: float, rate: float) -> int:
    """Number of held samples that cover the times ``0 <= t <= duration``.

    Parameters
    ----------
    duration : float
        Simulated time in s, finite and >= 0.
    rate : float
        Noise sample rate in Hz, finite and > 0.

    Returns
    -------
    int
        ``held_sample_index(duration, rate) + 1`` (e.g. 1001 for 10 s at 100 Hz).

    Raises
    ------
    ValueError
        If ``duration`` < 0 or ``rate`` <= 0 or either is not finite.
    """
    d = _real(duration, "duration")
    if d < 0.0:
        raise ValueError(f"duration must be >= 0, got {duration!r}")
    return int(held_sample_index(d, rate)) + 1

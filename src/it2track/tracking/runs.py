"""The runs of a batch (:class:`RunTable`, :func:`run_grid`) and their time series
(:class:`Trace`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from numbers import Integral
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..plant.noise import MAX_NOISE_STD
from .loopdefs import TRACE_FIELDS

__all__ = ["MAX_INDEX", "TRACE_FIELDS", "RunTable", "Trace", "run_grid"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class RunTable:
    """The runs of a batch, one entry per run (all arrays shape ``(B,)``).

    Attributes
    ----------
    controller : ndarray of int
        Index into the ``controllers`` sequence given to :func:`simulate`.
    trajectory : ndarray of int
        Index into the ``trajectories`` sequence.
    noise_std : ndarray of float
        Heading-noise standard deviation, rad (>= 0).
    seed : ndarray of int
        Noise realisation index (>= 0) under ``LoopConfig.seed``.
    """

    controller: IntArray
    trajectory: IntArray
    noise_std: FloatArray
    seed: IntArray

    def __init__(
        self,
        controller: ArrayLike,
        trajectory: ArrayLike,
        noise_std: ArrayLike,
        seed: ArrayLike,
    ) -> None:
        given = {
            name: _plain_array(value, name)
            for name, value in (("controller", controller), ("trajectory", trajectory),
                                ("noise_std", noise_std), ("seed", seed))
        }
        try:
            arrays = np.broadcast_arrays(*given.values())
        except ValueError:
            shapes = ", ".join(f"{k} {v.shape}" for k, v in given.items())
            raise ValueError(
                f"RunTable: the columns must broadcast together; got {shapes}"
            ) from None
        c, t, s, z = (np.ascontiguousarray(a).reshape(-1) for a in arrays)
        c, t, z = (_index_column(a, name) for a, name in
                   ((c, "controller"), (t, "trajectory"), (z, "seed")))
        s = _noise_column(s)
        object.__setattr__(self, "controller", c.astype(np.int64))
        object.__setattr__(self, "trajectory", t.astype(np.int64))
        object.__setattr__(self, "noise_std", s)
        object.__setattr__(self, "seed", z.astype(np.int64))

    def __len__(self) -> int:
        return int(self.controller.size)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, RunTable):
            return NotImplemented
        return all(
            np.array_equal(getattr(self, k), getattr(other, k))
            for k in ("controller", "trajectory", "noise_std", "seed")
        )

    __hash__ = None  # type: ignore[assignment]  # mutable arrays inside

    def take(self, index: ArrayLike | slice) -> RunTable:
        """The runs at ``index`` (an int array or a slice object)."""
        idx = index if isinstance(index, slice) else np.asarray(index)
        return RunTable(
            self.controller[idx], self.trajectory[idx], self.noise_std[idx], self.seed[idx]
        )


#: Largest seed index or controller/trajectory index a run may have (int64).
MAX_INDEX = 2**63 - 1


def _plain_array(value: ArrayLike, name: str) -> NDArray[Any]:
    """``np.asarray`` that refuses what it would silently change: masked entries."""
    if isinstance(value, np.ma.MaskedArray):
        if np.ma.getmaskarray(value).any():
            raise ValueError(
                f"RunTable.{name} is a masked array with masked entries; give plain values "
                "(the mask would be dropped)"
            )
        value = value.data
    try:
        return np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged nested sequences
        raise ValueError(f"RunTable.{name}={value!r} is not an array of numbers: {exc}") from None


def _index_column(arr: NDArray[Any], name: str) -> NDArray[Any]:
    """Integers in ``[0, MAX_INDEX]``; Python ints beyond int64 are named, not truncated."""
    if not arr.size:
        return arr.astype(np.int64)
    if arr.dtype == object:
        bad = next((v for v in arr.tolist()
                    if isinstance(v, bool) or not isinstance(v, Integral)), None)
        if bad is not None:
            raise ValueError(f"RunTable.{name} must hold integers >= 0, got {bad!r}")
        out = next((v for v in arr.tolist() if not 0 <= v <= MAX_INDEX), None)
        if out is not None:
            raise ValueError(
                f"RunTable.{name} value {out!r} is outside the allowed range [0, 2**63 - 1]"
            )
        return arr.astype(np.int64)
    if arr.dtype.kind not in "iu":
        example = arr.reshape(-1)[:1].tolist()[0]
        raise ValueError(
            f"RunTable.{name} must hold integers >= 0, got {arr.dtype} values (e.g. {example!r})"
        )
    low, high = arr.min(), arr.max()
    if low < 0:
        raise ValueError(f"RunTable.{name} must hold integers >= 0, got {int(low)}")
    if int(high) > MAX_INDEX:
        raise ValueError(
            f"RunTable.{name} value {int(high)} is outside the allowed range [0, 2**63 - 1]"
        )
    return arr


def _noise_column(arr: NDArray[Any]) -> FloatArray:
    """Real noise levels in ``[0, MAX_NOISE_STD]`` rad as float64."""
    if arr.size and arr.dtype.kind not in "iuf":
        example = arr.reshape(-1)[:1].tolist()[0]
        raise ValueError(
            f"RunTable.noise_std must hold real numbers, got {arr.dtype} values "
            f"(e.g. {example!r})"
        )
    s = arr.astype(np.float64)
    if s.size:
        if not np.isfinite(s).all():
            bad = float(s[~np.isfinite(s)][0])
            raise ValueError(f"RunTable.noise_std value {bad!r} must be finite")
        if s.min() < 0:
            raise ValueError(f"RunTable.noise_std value {float(s.min())!r} must be >= 0")
        if s.max() > MAX_NOISE_STD:
            raise ValueError(
                f"RunTable.noise_std value {float(s.max())!r} exceeds the largest heading-noise "
                f"standard deviation allowed, {MAX_NOISE_STD:g} rad (beyond it theta + noise "
                "loses the heading's precision, and far beyond it overflows)"
            )
    return s


def run_grid(
    n_controllers: int,
    n_trajectories: int,
    noise_stds: Sequence[float],
    seeds: Sequence[int] | int,
) -> RunTable:
    """Cartesian product of controllers x trajectories x noise levels x seeds.

    ``n_controllers`` and ``n_trajectories`` are the lengths of the sequences the runs index;
    ``noise_stds`` the noise levels (rad); ``seeds`` the seed indices, or a count ``n``
    (seed indices ``0 ... n-1``). Runs are ordered with the seed varying fastest, then noise,
    trajectory, controller.

    Examples
    --------
    >>> len(run_grid(2, 3, [0.0, 0.1], 5))
    60
    """
    seed_list = np.arange(int(seeds)) if isinstance(seeds, Integral) else np.asarray(seeds)
    c, t, s, z = np.meshgrid(
        np.arange(n_controllers), np.arange(n_trajectories), np.asarray(noise_stds, float),
        seed_list, indexing="ij",
    )
    return RunTable(c, t, s, z)


@dataclass(frozen=True)
class Trace:
    """Time series of a batch of runs.

    Attributes
    ----------
    t : ndarray, shape (N+1,)
        Control instants.
    runs : RunTable
        The runs, in the order of the first axis below.
    series : dict of str -> ndarray, shape (B, N+1)
        One array per name in :data:`TRACE_FIELDS` (axis 0: run, axis 1: time); for runs
        following reference signals, :data:`~it2track.tracking.siso.REFERENCE_FIELDS` and
        ``"y.<name>"`` per plant output. Then one per name the controllers report (their
        ``trace_series``, e.g. the processor-in-the-loop controller's ``cycles``; NaN for runs
        of the other controllers).
    metrics : dict of str -> ndarray, shape (B,)
        The metrics of :mod:`it2track.tracking.metrics`.
    """

    t: FloatArray
    runs: RunTable
    series: dict[str, FloatArray]
    metrics: dict[str, FloatArray]

    def __getitem__(self, name: str) -> FloatArray:
        return self.series[name]

    def run(self, i: int) -> dict[str, FloatArray]:
        """The time series of run ``i``, each of shape ``(N+1,)``, plus ``"t"``."""
        return {"t": self.t, **{k: v[i] for k, v in self.series.items()}}

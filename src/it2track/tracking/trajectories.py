"""Reference trajectories: position and velocity of the reference point as functions of time.

A :class:`Trajectory` maps a time array ``t`` (shape ``(n,)``) to an array of shape ``(n, 4)``
with columns ``x, y, vx, vy``. The velocity feeds the motors' feed-forward voltage (the reference
speed ``|p'_d(t)|``). Built-in: the paper's three trajectories (sec. III). Users add their own
from a Python callable (:class:`FunctionTrajectory`) or from waypoints
(:class:`WaypointTrajectory`, e.g. read from a CSV file with :func:`load_waypoints_csv`).
Configuration files never evaluate strings as code: they name a built-in or a CSV file.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._files import read_text

__all__ = [
    "PAPER_TRAJECTORIES",
    "FunctionTrajectory",
    "Trajectory",
    "WaypointTrajectory",
    "curved",
    "get_trajectory",
    "load_waypoints_csv",
    "sinusoidal",
    "straight",
]

FloatArray = NDArray[np.float64]


class Trajectory:
    """Base class: ``traj(t) -> ndarray (n, 4)`` with columns ``x, y, vx, vy``."""

    name: str

    def __call__(self, t: ArrayLike) -> FloatArray:
        raise NotImplementedError

    def sample(self, t: ArrayLike) -> FloatArray:
        """Evaluate on ``t`` and check the result: shape ``(n, 4)``, all finite."""
        tt = np.atleast_1d(np.asarray(t, dtype=np.float64))
        out = np.asarray(self(tt), dtype=np.float64)
        if out.shape != (tt.size, 4):
            raise ValueError(
                f"trajectory {self.name!r} returned shape {out.shape}, expected ({tt.size}, 4)"
            )
        if not np.isfinite(out).all():
            raise ValueError(f"trajectory {self.name!r} returned NaN or inf")
        return out


def _straight(t: FloatArray) -> FloatArray:
    z = np.zeros_like(t)
    return np.stack([2.0 * t, z, np.full_like(t, 2.0), z], axis=-1)


def _curved(t: FloatArray) -> FloatArray:
    return np.stack([2.0 * t, 0.2 * t * t - 4.0, np.full_like(t, 2.0), 0.4 * t], axis=-1)


def _sinusoidal(t: FloatArray) -> FloatArray:
    return np.stack(
        [2.0 * t, 0.2 - 0.2 * np.cos(2.0 * t), np.full_like(t, 2.0), 0.4 * np.sin(2.0 * t)],
        axis=-1,
    )


@dataclass(frozen=True)
class FunctionTrajectory(Trajectory):
    """A trajectory from a callable ``fn(t) -> (n, 4)`` array ``[x, y, vx, vy]``.

    ``name`` labels it in results; ``fn`` receives times of shape ``(n,)`` in s.

    Use a module-level function (not a lambda) if the trajectory must travel to worker
    processes or a Dask cluster (it is pickled).

    Examples
    --------
    >>> import numpy as np
    >>> def circle(t):
    ...     return np.stack([np.cos(t), np.sin(t), -np.sin(t), np.cos(t)], axis=-1)
    >>> FunctionTrajectory("circle", circle).sample([0.0]).tolist()
    [[1.0, 0.0, -0.0, 1.0]]
    """

    name: str
    fn: Callable[[FloatArray], ArrayLike]

    def __call__(self, t: ArrayLike) -> FloatArray:
        return np.asarray(self.fn(np.asarray(t, dtype=np.float64)), dtype=np.float64)


def straight() -> FunctionTrajectory:
    """Paper sec. III-A: ``(2t, 0)``."""
    return FunctionTrajectory("straight", _straight)


def curved() -> FunctionTrajectory:
    """Paper sec. III-B: ``(2t, 0.2 t^2 - 4)``."""
    return FunctionTrajectory("curved", _curved)


def sinusoidal() -> FunctionTrajectory:
    """Paper sec. III-C: ``(2t, 0.2 - 0.2 cos 2t)``."""
    return FunctionTrajectory("sinusoidal", _sinusoidal)


PAPER_TRAJECTORIES: dict[str, Callable[[], FunctionTrajectory]] = {
    "straight": straight,
    "curved": curved,
    "sinusoidal": sinusoidal,
}


@dataclass(frozen=True)
class WaypointTrajectory(Trajectory):
    """Reference through timed waypoints, interpolated by a cubic spline or linearly.

    Parameters
    ----------
    name : str
    times : array_like, shape (n,)
        Strictly increasing times, s (at least 2; 4 for ``"cubic"``).
    points : array_like, shape (n, 2)
        Waypoint positions ``x, y`` in m.
    kind : {"cubic", "linear"}
        ``"cubic"``: not-a-knot cubic spline (smooth velocity); ``"linear"``: piecewise-linear
        position with piecewise-constant velocity. Outside ``[times[0], times[-1]]`` the
        reference holds its end position with zero velocity.
    """

    name: str
    times: tuple[float, ...]
    points: tuple[tuple[float, float], ...]
    kind: str = "cubic"
    _spline: object = field(init=False, repr=False, compare=False, default=None)

    def __init__(
        self, name: str, times: ArrayLike, points: ArrayLike, kind: str = "cubic"
    ) -> None:
        t = np.asarray(times, dtype=np.float64)
        p = np.asarray(points, dtype=np.float64)
        if t.ndim != 1 or p.shape != (t.size, 2):
            raise ValueError(
                f"trajectory {name!r}: times shape {t.shape} and points shape {p.shape} must be "
                "(n,) and (n, 2)"
            )
        if kind not in ("cubic", "linear"):
            raise ValueError(f"trajectory {name!r}: kind={kind!r} must be 'cubic' or 'linear'")
        need = 4 if kind == "cubic" else 2
        if t.size < need:
            raise ValueError(f"trajectory {name!r}: {kind} needs at least {need} waypoints")
        if not (np.isfinite(t).all() and np.isfinite(p).all()):
            raise ValueError(f"trajectory {name!r}: waypoints must be finite")
        if np.any(np.diff(t) <= 0):
            i = int(np.argmax(np.diff(t) <= 0))
            raise ValueError(
                f"trajectory {name!r}: times must increase strictly (row {i + 1}: "
                f"{t[i]} then {t[i + 1]})"
            )
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "times", tuple(t.tolist()))
        object.__setattr__(self, "points", tuple(map(tuple, p.tolist())))
        object.__setattr__(self, "kind", kind)
        if kind == "cubic":
            from scipy.interpolate import CubicSpline

            object.__setattr__(self, "_spline", CubicSpline(t, p, axis=0))

    def __call__(self, t: ArrayLike) -> FloatArray:
        tt = np.asarray(t, dtype=np.float64)
        times = np.asarray(self.times)
        pts = np.asarray(self.points)
        tc = np.clip(tt, times[0], times[-1])
        inside = (tt >= times[0]) & (tt <= times[-1])
        if self.kind == "cubic":
            spline = self._spline
            pos = spline(tc)  # type: ignore[operator]
            vel = spline(tc, 1)  # type: ignore[operator]
        else:
            pos = np.stack([np.interp(tc, times, pts[:, 0]), np.interp(tc, times, pts[:, 1])], -1)
            seg = np.clip(np.searchsorted(times, tc, side="right") - 1, 0, times.size - 2)
            slope = np.diff(pts, axis=0) / np.diff(times)[:, None]
            vel = slope[seg]
        vel = np.where(inside[..., None], vel, 0.0)
        return np.concatenate([pos, vel], axis=-1)


def load_waypoints_csv(path: str | Path, *, kind: str = "cubic") -> WaypointTrajectory:
    """Read a waypoint trajectory from a CSV file with header ``t,x,y``.

    Parameters
    ----------
    path : str or Path
        The CSV file; the trajectory is named after its stem.
    kind : {"cubic", "linear"}
        Interpolation, as in :class:`WaypointTrajectory`.

    Raises
    ------
    ValueError
        Naming the file and line of a missing column, a bad number or non-increasing time.
    """
    path = Path(path)
    try:
        text = read_text(path, what="waypoint CSV file")
    except OSError as exc:
        raise ValueError(f"{path}: cannot read waypoints: {exc.strerror or exc}") from None
    reader = csv.reader(text.splitlines())
    rows = list(reader)
    if not rows:
        raise ValueError(f"{path}: empty waypoint file (expected a header t,x,y)")
    header = [h.strip().lower() for h in rows[0]]
    missing = [c for c in ("t", "x", "y") if c not in header]
    if missing:
        raise ValueError(f"{path}:1: header {rows[0]!r} lacks column(s) {missing}")
    cols = [header.index(c) for c in ("t", "x", "y")]
    values: list[list[float]] = []
    lines: list[int] = []
    for lineno, row in enumerate(rows[1:], start=2):
        if not row or all(not cell.strip() for cell in row):
            continue
        try:
            values.append([float(row[c]) for c in cols])
        except (ValueError, IndexError):
            raise ValueError(f"{path}:{lineno}: expected numbers for t,x,y, got {row!r}") from None
        if not all(math.isfinite(v) for v in values[-1]):
            raise ValueError(f"{path}:{lineno}: non-finite value in {row!r}")
        if lines and values[-1][0] <= values[-2][0]:
            raise ValueError(
                f"{path}:{lineno}: time t={values[-1][0]!r} does not increase (line "
                f"{lines[-1]} has t={values[-2][0]!r})"
            )
        lines.append(lineno)
    arr = np.asarray(values, dtype=np.float64).reshape(-1, 3)
    try:
        return WaypointTrajectory(path.stem, arr[:, 0], arr[:, 1:], kind)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


def get_trajectory(spec: str | Trajectory) -> Trajectory:
    """The trajectory ``spec`` names: a built-in name (``"straight"``, ``"curved"``,
    ``"sinusoidal"``), a CSV waypoint file (path ending in ``.csv``), or a Trajectory as is."""
    if isinstance(spec, Trajectory):
        return spec
    if spec in PAPER_TRAJECTORIES:
        return PAPER_TRAJECTORIES[spec]()
    if spec.lower().endswith(".csv"):
        return load_waypoints_csv(spec)
    raise ValueError(
        f"unknown trajectory {spec!r}: use one of {sorted(PAPER_TRAJECTORIES)} or a .csv file"
    )

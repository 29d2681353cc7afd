"""Control surfaces: a two-input system's output on a grid (the data; plotting is in
:mod:`it2track.report.surface`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["control_surface"]

FloatArray = NDArray[np.float64]


def control_surface(
    system: Any,
    *,
    points: int = 101,
    ranges: Mapping[str, tuple[float, float]] | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Output of a two-input system on a grid.

    Parameters
    ----------
    system : IT2Sugeno, T1Sugeno, IT2Mamdani or T1Mamdani
        A system with exactly two inputs and one output.
    points : int
        Grid points per axis.
    ranges : mapping, optional
        Input name -> (lo, hi); defaults to each input's universe.

    Returns
    -------
    x1, x2, u : ndarray, shape (points, points)
        Meshgrid (``indexing="ij"``: ``x1`` varies along axis 0) and the output on it.
    """
    if system.n_inputs != 2:
        raise ValueError(f"control_surface needs a two-input system, got {system.n_inputs}")
    if points < 2:
        raise ValueError(f"points={points!r} must be >= 2")
    ranges = dict(ranges or {})
    axes = []
    for inp in system.inputs:
        lo, hi = ranges.pop(inp.name, inp.universe)
        axes.append(np.linspace(lo, hi, points))
    if ranges:
        raise ValueError(f"ranges names unknown inputs {sorted(ranges)}")
    x1, x2 = np.meshgrid(axes[0], axes[1], indexing="ij")
    return x1, x2, np.asarray(system(x1, x2))

"""Figures of a fuzzy system: control surface, and footprints of uncertainty of its inputs.

Clean functions: each takes a system (:class:`~it2track.fuzzy.IT2Sugeno` or
:class:`~it2track.fuzzy.T1Sugeno`) and returns a :class:`matplotlib.figure.Figure`. Give
``path_or_ax`` as a file path to also save the figure (atomically; the format follows the
suffix), as an existing Axes to draw into it, or ``None`` to just get the figure. Figures are
made with :class:`~matplotlib.figure.Figure`, not ``pyplot``, so nothing global is kept.

This is the only module that imports matplotlib for fuzzy systems.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib.colors as mcolors
import mpl_toolkits.mplot3d  # noqa: F401  (registers the "3d" projection)
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator
from numpy.typing import NDArray

from .._limits import check_memory, fuzzy_batch_bytes
from ..atomicfile import atomic_open
from ..fuzzy import AnySystem, ZeroFiringError

__all__ = ["plot_control_surface", "plot_footprints", "plot_system", "surface_grid"]

FuzzySystem = AnySystem  # Sugeno, TSK or Mamdani (one output: see select_output)
PathLike = str | os.PathLike[str]


#: Floating-point flags ignored while matplotlib draws. Its 3-D projection multiplies finite
#: 4 x N arrays with ``np.dot``; OpenBLAS kernels on some CPUs leave spurious overflow/invalid
#: flags that numpy 2 reports as RuntimeWarnings (numpy issues 28687, 29820), depending on what
#: ran before in the process. Our own values are computed (and checked) outside this scope.
def _drawing_errstate() -> np.errstate:
    return np.errstate(over="ignore", invalid="ignore", divide="ignore")


def _save(fig: Figure, path: PathLike) -> None:
    suffix = Path(path).suffix.lstrip(".").lower() or "png"
    with atomic_open(path, "wb") as fh, _drawing_errstate():
        fig.savefig(fh, format=suffix)


def _evaluate(system: FuzzySystem, args: Sequence[NDArray[np.float64]]) -> NDArray[np.float64]:
    """``system(*args)`` with NaN where no rule fires (instead of ZeroFiringError)."""
    try:
        return np.asarray(system(*args), dtype=np.float64)
    except ZeroFiringError:
        _, upper = system.firing(*args)
        dead = upper.sum(axis=-1) == 0.0
        patched = dataclasses.replace(system, on_zero_firing=0.0)
        out = np.asarray(patched(*args), dtype=np.float64)
        out[dead] = np.nan
        return out


def surface_grid(
    system: FuzzySystem,
    *,
    inputs: Sequence[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    points: int = 101,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The output on a grid over two inputs, the others held fixed.

    Parameters
    ----------
    system : IT2Sugeno or T1Sugeno
        At least two inputs.
    inputs : (str, str), optional
        Names of the inputs on the x and y axes; default the first two.
    fixed : mapping, optional
        Values of the other inputs; default the middle of their universes.
    points : int
        Grid points per axis.

    Returns
    -------
    x, y, u : ndarray, shape (points, points)
        ``indexing="ij"`` meshgrid and the output, NaN where no rule fires.
    """
    if system.n_inputs < 2:
        raise ValueError("a surface needs a system with at least two inputs")
    if isinstance(points, bool) or not isinstance(points, int) or points < 2:
        raise ValueError(f"points={points!r} must be an integer >= 2")
    check_memory(  # the grids (x, y, u) plus the evaluation, before any allocation
        3 * 8 * points**2 + fuzzy_batch_bytes(points**2, system.n_inputs),
        what=f"points={points} ({points}^2 = {points**2} grid points)",
        hint="use fewer points (e.g. 101-501 per axis)",
    )
    names = [inp.name for inp in system.inputs]
    pair = list(inputs) if inputs is not None else names[:2]
    if len(pair) != 2 or pair[0] == pair[1] or any(p not in names for p in pair):
        raise ValueError(f"inputs={inputs!r} must name two different inputs of {names}")
    fixed = dict(fixed or {})
    unknown = set(fixed) - set(names)
    if unknown or set(fixed) & set(pair):
        raise ValueError(f"fixed={fixed!r} must name inputs of {names} other than {pair}")
    ix, iy = names.index(pair[0]), names.index(pair[1])
    x = np.linspace(*system.inputs[ix].universe, points)
    y = np.linspace(*system.inputs[iy].universe, points)
    gx, gy = np.meshgrid(x, y, indexing="ij")
    args = []
    for i, inp in enumerate(system.inputs):
        if i == ix:
            args.append(gx)
        elif i == iy:
            args.append(gy)
        else:
            lo, hi = inp.universe
            args.append(np.full_like(gx, float(fixed.get(inp.name, 0.5 * (lo + hi)))))
    return gx, gy, _evaluate(system, args)


def plot_control_surface(
    system: FuzzySystem,
    path_or_ax: PathLike | Axes | None = None,
    *,
    inputs: Sequence[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    points: int = 101,
    style: str = "3d",
    title: str | None = None,
    cmap: str = "viridis",
) -> Figure:
    """Plot ``u`` over two inputs (or over the one input of a one-input system).

    Parameters
    ----------
    system : IT2Sugeno or T1Sugeno
    path_or_ax : path, Axes or None
        Save to this file, draw into this Axes (``projection="3d"`` for ``style="3d"``), or
        make a new figure.
    inputs, fixed, points
        See :func:`surface_grid`.
    style : {"3d", "contour"}
        A 3-D surface, or filled contours (which show a dead zone plainly).
    title : str, optional
        Default: the system's name.
    cmap : str
        Colormap.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if style not in ("3d", "contour"):
        raise ValueError(f"style={style!r} must be '3d' or 'contour'")
    ax, fig = _axes(path_or_ax, projection="3d" if style == "3d" and system.n_inputs > 1 else None)
    label = title if title is not None else (system.name or type(system).__name__)
    if system.n_inputs == 1:
        inp = system.inputs[0]
        x = np.linspace(*inp.universe, max(points, 2))
        ax.plot(x, _evaluate(system, [x]))
        ax.set_xlabel(inp.name)
        ax.set_ylabel("u")
        ax.grid(True, alpha=0.3)
    else:
        gx, gy, u = surface_grid(system, inputs=inputs, fixed=fixed, points=points)
        names = list(inputs) if inputs is not None else [i.name for i in system.inputs[:2]]
        if style == "3d":
            with _drawing_errstate():
                ax.plot_surface(gx, gy, np.ma.masked_invalid(u), cmap=cmap, linewidth=0,
                                antialiased=True)
            ax.set_zlabel("u")
            for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
                axis.set_major_locator(MaxNLocator(5))
        else:
            finite = u[np.isfinite(u)]
            lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
            levels: NDArray[np.float64]
            if hi > lo:
                ticks = np.asarray(MaxNLocator(nbins=20).tick_values(lo, hi), dtype=np.float64)
                tol = 1e-9 * (hi - lo)  # no sliver bins from rounding at the extremes
                inner = ticks[(ticks > lo + tol) & (ticks < hi - tol)]
                levels = np.concatenate(([lo], inner, [hi]))
            else:
                levels = np.array([lo - 0.5, lo + 0.5])
            filled = ax.contourf(gx, gy, u, levels=levels, cmap=cmap)
            if hi > lo:
                ax.contour(gx, gy, u, levels=levels[::3], colors="k", linewidths=0.4, alpha=0.5)
            fig.colorbar(filled, ax=ax, label="u")
        ax.set_xlabel(names[0])
        ax.set_ylabel(names[1])
    ax.set_title(label)
    if path_or_ax is not None and not isinstance(path_or_ax, Axes):
        _save(fig, path_or_ax)
    return fig


def plot_footprints(
    system: FuzzySystem,
    path_or_axes: PathLike | Sequence[Axes] | None = None,
    *,
    inputs: Sequence[str] | None = None,
    points: int = 501,
) -> Figure:
    """Each input's sets: upper MF (solid), lower MF (dashed), FoU shaded between them.

    Type-1 sets are drawn as one line.

    Parameters
    ----------
    system : IT2Sugeno or T1Sugeno
    path_or_axes : path, sequence of Axes or None
        Save to this file, draw into these Axes (one per plotted input), or make a new figure
        with one row per input.
    inputs : sequence of str, optional
        Inputs to plot; default all.
    points : int
        Evaluation points per input.

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = [inp.name for inp in system.inputs]
    chosen = list(inputs) if inputs is not None else names
    if not chosen or any(n not in names for n in chosen):
        raise ValueError(f"inputs={inputs!r} must name inputs of {names}")
    if path_or_axes is None or isinstance(path_or_axes, str | os.PathLike):
        fig = Figure(figsize=(6.0, 1.9 * len(chosen) + 0.6), layout="constrained")
        axes: list[Any] = list(fig.subplots(len(chosen), 1, squeeze=False)[:, 0])
    else:
        axes = list(path_or_axes)
        if len(axes) != len(chosen):
            raise ValueError(f"got {len(axes)} Axes for {len(chosen)} inputs")
        fig = axes[0].figure
    colors = list(mcolors.TABLEAU_COLORS.values())
    for ax, name in zip(axes, chosen, strict=True):
        inp = system.inputs[names.index(name)]
        x = np.linspace(*inp.universe, max(points, 2))
        for k, s in enumerate(inp.sets):
            color = colors[k % len(colors)]
            upper = np.asarray(s.upper(x), dtype=np.float64)
            if s.is_type1:
                ax.plot(x, upper, color=color, label=s.name)
                continue
            lower = np.asarray(s.lower(x), dtype=np.float64)
            ax.fill_between(x, lower, upper, color=color, alpha=0.25, linewidth=0)
            ax.plot(x, upper, color=color, label=s.name)
            ax.plot(x, lower, color=color, linestyle="--", linewidth=1.0)
        ax.set_xlim(*inp.universe)
        ax.set_ylim(-0.02, 1.05)
        ax.set_xlabel(inp.name)
        ax.set_ylabel("membership")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize="small",
                  frameon=False)
    kind = "membership functions" if all(s.is_type1 for i in system.inputs for s in i.sets) \
        else "footprints of uncertainty"
    axes[0].set_title(kind)
    if path_or_axes is not None and isinstance(path_or_axes, str | os.PathLike):
        _save(fig, path_or_axes)
    return fig


def plot_system(
    system: FuzzySystem,
    path: PathLike | None = None,
    *,
    inputs: Sequence[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    points: int = 101,
    style: str = "3d",
) -> Figure:
    """One figure: the control surface (left) and every input's sets / FoUs (right).

    Parameters are those of :func:`plot_control_surface`; ``path`` saves the figure.
    """
    n = system.n_inputs
    fig = Figure(figsize=(11.0, max(4.5, 1.9 * n + 0.6)), layout="constrained")
    grid = fig.add_gridspec(n, 2, width_ratios=(1.25, 1.0))
    projection = "3d" if style == "3d" and n > 1 else None
    surface_ax = fig.add_subplot(grid[:, 0], projection=projection)
    plot_control_surface(system, surface_ax, inputs=inputs, fixed=fixed, points=points,
                         style=style)
    set_axes = [fig.add_subplot(grid[i, 1]) for i in range(n)]
    plot_footprints(system, set_axes)
    if path is not None:
        _save(fig, path)
    return fig


def _axes(path_or_ax: PathLike | Axes | None, *, projection: str | None) -> tuple[Any, Figure]:
    if isinstance(path_or_ax, Axes):
        if projection == "3d" and getattr(path_or_ax, "name", "") != "3d":
            raise ValueError("style='3d' needs an Axes made with projection='3d'")
        fig = path_or_ax.figure
        assert isinstance(fig, Figure)
        return path_or_ax, fig
    fig = Figure(figsize=(6.4, 5.0), layout="constrained")
    return fig.add_subplot(projection=projection), fig

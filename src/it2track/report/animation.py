"""Robots tracking their paths side by side, animated (a GIF the HTML report embeds).

:func:`tracking_gif` draws one panel per :class:`AnimationPanel` (e.g. the kinematic robot and
the MuJoCo robot on dry, wet and icy ground, each with the same controllers on the same path):
a top view with the reference path, the moving reference point, and each robot's trail, position
and heading, frame by frame. Frames are drawn with matplotlib's Agg canvas (no pyplot, no
display) and assembled by Pillow into an animated GIF, which browsers play inline; the bytes
depend only on the data (same traces, same file).
"""

from __future__ import annotations

import io
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import PIL.Image
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..atomicfile import atomic_open
from ..tracking import Trace

__all__ = ["AnimationPanel", "tracking_gif"]

#: Colours of the robots, in the order their labels first appear (colour-blind safe, Okabe-Ito).
ROBOT_COLORS = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9")
_REF = "#555555"
#: Most frames a GIF may have (each is a full image in memory while the file is assembled).
MAX_FRAMES = 500


@dataclass(frozen=True)
class AnimationPanel:
    """One panel: runs of a trace, all on the same path, with a label per run.

    Parameters
    ----------
    title : str
        The panel's title (e.g. ``"MuJoCo, icy"``).
    trace : Trace
        Its runs' time series (``x``, ``y``, ``theta``, ``x_ref``, ``y_ref``).
    labels : tuple of str
        A legend label per run of ``trace``, in order (a label names the same controller in
        every panel, and gets the same colour).
    """

    title: str
    trace: Trace
    labels: tuple[str, ...]


def _check(panels: Sequence[AnimationPanel], frames: int, fps: float) -> np.ndarray:
    if not panels:
        raise ValueError("panels must hold at least one AnimationPanel")
    for i, p in enumerate(panels):
        if not isinstance(p, AnimationPanel):
            raise ValueError(f"panels[{i}] is a {type(p).__name__}, not an AnimationPanel")
        if len(p.labels) != len(p.trace.runs):
            raise ValueError(f"panels[{i}] ({p.title!r}): {len(p.labels)} labels for "
                             f"{len(p.trace.runs)} runs")
        if len(set(p.trace.runs.trajectory.tolist())) > 1:
            raise ValueError(f"panels[{i}] ({p.title!r}): its runs follow different paths")
    t = panels[0].trace.t
    for i, p in enumerate(panels[1:], 1):
        if not np.array_equal(p.trace.t, t):
            raise ValueError(f"panels[{i}] ({p.title!r}) has another time grid than panels[0]")
    if isinstance(frames, bool) or not isinstance(frames, int) or not 2 <= frames <= MAX_FRAMES:
        raise ValueError(f"frames={frames!r} must be an integer in [2, {MAX_FRAMES}]")
    if isinstance(fps, bool) or not isinstance(fps, int | float) or not 0.5 <= fps <= 50:
        raise ValueError(f"fps={fps!r} must be a number in [0.5, 50]")
    return t


def _limits(panel: AnimationPanel) -> tuple[tuple[float, float], tuple[float, float]]:
    """A square window (equal scales on a square panel) around the path and the robots."""
    s = panel.trace.series
    xs = np.concatenate([s["x"].ravel(), s["x_ref"].ravel()])
    ys = np.concatenate([s["y"].ravel(), s["y_ref"].ravel()])
    xs, ys = xs[np.isfinite(xs)], ys[np.isfinite(ys)]
    half = 0.53 * max(float(xs.max() - xs.min()), float(ys.max() - ys.min()), 1.0)
    cx, cy = (xs.max() + xs.min()) / 2, (ys.max() + ys.min()) / 2
    return (cx - half, cx + half), (cy - half, cy + half)


def tracking_gif(
    panels: Sequence[AnimationPanel],
    path: str | Path,
    *,
    frames: int = 60,
    fps: float = 10.0,
    panel_size: float = 3.2,
    dpi: int = 80,
) -> Path:
    """Write an animated GIF of the panels' robots tracking their paths, side by side.

    Parameters
    ----------
    panels : sequence of AnimationPanel
        One panel each, left to right; every trace on the same time grid.
    path : str or Path
        The GIF to write (atomically: a reader never sees half a file).
    frames : int, default 60
        Frames, at evenly spaced control instants from the first to the last (2 to 500).
    fps : float, default 10
        Frames per second when played (0.5 to 50); the last frame is held for 1.5 s more.
    panel_size : float, default 3.2
        Width and height of a panel, inches.
    dpi : int, default 80
        Pixels per inch.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If there is no panel, a panel's labels do not match its runs or its runs follow several
        paths, the time grids differ, or ``frames`` or ``fps`` is out of range.
    """
    t = _check(panels, frames, fps)
    colors: dict[str, str] = {}
    for p in panels:
        for label in p.labels:
            colors.setdefault(label, ROBOT_COLORS[len(colors) % len(ROBOT_COLORS)])
    fig = Figure(figsize=(panel_size * len(panels), panel_size + 0.5), dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    moving = []
    for ax, p in zip(axes, panels, strict=True):
        s = p.trace.series
        ax.plot(s["x_ref"][0], s["y_ref"][0], color=_REF, ls="--", lw=0.9)
        (ref_dot,) = ax.plot([], [], "o", color="black", ms=4)
        xlim, ylim = _limits(p)
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.set_aspect("equal", adjustable="box")
        ax.set_title(p.title, fontsize=10)
        ax.tick_params(labelsize=7)
        ax.set_xlabel("x (m)", fontsize=8)
        arrow = 0.07 * (xlim[1] - xlim[0])
        robots = []
        for i, label in enumerate(p.labels):
            (trail,) = ax.plot([], [], color=colors[label], lw=1.3, label=label)
            (head,) = ax.plot([], [], color=colors[label], lw=2.2)
            (dot,) = ax.plot([], [], "o", color=colors[label], ms=5)
            robots.append((i, trail, head, dot))
        moving.append((s, ref_dot, robots, arrow))
    axes[0].set_ylabel("y (m)", fontsize=8)
    axes[0].legend(fontsize=7, loc="upper left", handlelength=1.2)
    clock = fig.text(0.5, 0.01, "", ha="center", fontsize=9)
    fig.subplots_adjust(left=0.06, right=0.99, top=0.9, bottom=0.16, wspace=0.25)

    images = []
    for k in np.linspace(0, t.size - 1, frames).round().astype(int):
        for s, ref_dot, robots, arrow in moving:
            ref_dot.set_data([s["x_ref"][0, k]], [s["y_ref"][0, k]])
            for i, trail, head, dot in robots:
                x, y, th = s["x"][i, k], s["y"][i, k], s["theta"][i, k]
                trail.set_data(s["x"][i, :k + 1], s["y"][i, :k + 1])
                dot.set_data([x], [y])
                head.set_data([x, x + arrow * math.cos(th)], [y, y + arrow * math.sin(th)])
        clock.set_text(f"t = {t[k]:.1f} s")
        canvas.draw()
        rgb = PIL.Image.frombuffer("RGBA", canvas.get_width_height(), canvas.buffer_rgba(),
                                   "raw", "RGBA", 0, 1).convert("RGB")
        images.append(rgb.quantize(colors=64, method=PIL.Image.Quantize.MEDIANCUT,
                                   dither=PIL.Image.Dither.NONE))
    fig.clear()
    step = round(1000.0 / fps)
    buf = io.BytesIO()
    images[0].save(buf, format="GIF", save_all=True, append_images=images[1:], loop=0,
                   duration=[step] * (frames - 1) + [step + 1500], disposal=1)
    out = Path(path)
    with atomic_open(out, "wb") as fh:
        fh.write(buf.getvalue())
    return out

"""Convergence plot of the FoU optimisation (:mod:`it2track.experiments.optimize`).

One PNG: the training objective of every evaluated candidate against the evaluation number
(dots, one colour per phase: symmetric grid, symmetric refinement, asymmetric differential
evolution) and the best value so far (a step line), with optional horizontal reference lines
(e.g. the FLC and FoU 0.2 on the same training seeds). The figure is a plain
:class:`matplotlib.figure.Figure` (no pyplot state), written atomically.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ..atomicfile import atomic_open

__all__ = ["plot_convergence"]

_PHASES = {
    "symmetric-grid": ("symmetric: grid", "tab:blue"),
    "symmetric-refine": ("symmetric: bounded Brent", "tab:green"),
    "asymmetric": ("asymmetric: differential evolution", "tab:orange"),
}


def plot_convergence(
    history: Sequence[Mapping[str, Any]],
    path: str | Path,
    *,
    objective: str = "objective",
    references: Mapping[str, float] | None = None,
    dpi: int = 120,
) -> Path:
    """Write the convergence plot of ``history`` to ``path`` (PNG).

    Parameters
    ----------
    history : sequence of mappings
        One entry per evaluation, in order, with keys ``"phase"`` and ``"objective"`` (as in
        ``optimize.json``'s ``history``).
    path : path
        Output file (``.png``); written atomically.
    objective : str
        Axis label (the objective's formula).
    references : mapping of str -> float, optional
        Horizontal reference lines, e.g. ``{"FLC": 0.59, "FoU 0.2": 0.55}``.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If ``history`` is empty.
    """
    if not history:
        raise ValueError("history is empty: nothing to plot")
    path = Path(path)
    values = np.array([float(h["objective"]) for h in history])
    idx = np.arange(values.size)
    best = np.minimum.accumulate(values)
    fig = Figure(figsize=(9.5, 4.8), layout="constrained")
    ax = fig.add_subplot()
    phases = [str(h["phase"]) for h in history]
    for key in dict.fromkeys(phases):
        label, colour = _PHASES.get(key, (key, "tab:gray"))
        sel = np.array([p == key for p in phases])
        ax.scatter(idx[sel], values[sel], s=12, alpha=0.5, color=colour, label=label,
                   linewidths=0)
    ax.step(idx, best, where="post", color="black", lw=1.6, label="best so far")
    for k, (name, value) in enumerate((references or {}).items()):
        ax.axhline(value, color=f"C{(k + 4) % 10}", lw=1.0, ls="--", label=f"{name} (train)")
    if np.all(values > 0):
        ax.set_yscale("log")
    ax.set_xlabel("evaluation (candidate number)")
    ax.set_ylabel(f"training objective: {objective}")
    ax.set_title(f"FoU optimisation: best {best[-1]:.4g} after {values.size} evaluations")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_open(path, "wb") as fh:  # exclusive, unpredictable temporary; never follows links
        fig.savefig(fh, format="png", dpi=dpi, metadata={"Software": None})
    return path

"""The study's figures (paper Figs. 7-11 and beyond), drawn from a :class:`StudyResult`.

Every figure is a :class:`matplotlib.figure.Figure` created directly (no pyplot) and saved twice,
as PNG and SVG, each written atomically (see :mod:`.style`). One module per figure family:

:mod:`.timeseries`
    ``paper_<trajectory>`` (paper Figs. 7-9: position, heading, translational and rotational
    speed, FLC vs the main IT2FLC, for one noise realisation at the study's noise level) and
    ``fou_comparison`` (paper Fig. 10: position and heading of the IT2FLCs of every FoU width).
:mod:`.integrals`
    ``integral_errors``: paper Fig. 11 with Monte Carlo means and 95 % intervals, plus the fair
    baselines.
:mod:`.sweeps`
    ``noise_sweep``, ``fou_sweep``: the integral errors against the noise level and against the
    FoU width.
:mod:`.surfaces`
    ``control_surfaces``, ``dead_zone``: ``u(e, de)`` of every fuzzy controller and its slice
    ``u(e, 0)``: the dead zone ``|e| < 0.2 - w/2`` that the FoU narrows.
:mod:`.claims`
    ``win_rates``: paired win rate against the FLC, the fraction of noise realisations with a
    smaller error, ties counting half (0.5 = no difference).
:mod:`.robustness`
    ``robustness``: every claim's status under each alternative of the paper's open modelling
    choices (a heat map, per noise level and trajectory); ``sensitivity``: the Morris ranking
    of the continuous choices.

Controllers are identified by their :class:`~it2track.experiments.specs.ControllerSpec` or by
the ``kind`` and ``fou`` columns of the metrics table, never by the text of their labels (see
:mod:`it2track.report.identity`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib
from matplotlib.figure import Figure

from ...experiments.study import StudyResult
from ..identity import (
    INTEGRAL_UNITS,
    PAPER_FIGURE_NUMBER,
    _controller_table,
    _Ctrl,
    _Summary,
    controller_specs,
    slug,
    surface_limit,
)
from ..plan import figure_keys, figure_plan, paper_figures
from .claims import _fig_win_rates
from .integrals import _fig_integral_errors
from .robustness import _fig_robustness, _fig_sensitivity
from .style import _DRAFT_RC, _RC, FIGURE_DPI, _Palette, _save
from .surfaces import _fig_control_surfaces, _fig_dead_zone
from .sweeps import _fig_fou_sweep, _fig_noise_sweep
from .timeseries import _fig_fou_comparison, _fig_paper

__all__ = [
    "FIGURE_DPI",
    "INTEGRAL_UNITS",
    "PAPER_FIGURE_NUMBER",
    "PER_TRAJECTORY",
    "controller_specs",
    "draw_figure",
    "figure_keys",
    "figure_plan",
    "slug",
    "surface_limit",
    "write_figure",
    "write_figures",
]


@dataclass(frozen=True)
class _Inputs:
    """What every figure function takes: the result, the summary index, the controllers'
    identities, the palette and the trajectories to draw (a draft's first one, else all)."""

    result: StudyResult
    summ: _Summary
    ctrls: Mapping[str, _Ctrl]
    pal: _Palette
    trajs: tuple[str, ...]
    draft: bool = False

    @classmethod
    def of(cls, result: StudyResult, summary: Sequence[Mapping[str, Any]], *,
           draft: bool = False) -> _Inputs:
        ctrls = _controller_table(result)
        trajs = tuple(result.config.trajectories)
        return cls(result, _Summary(summary), ctrls, _Palette(result.config.fous, ctrls.values()),
                   trajs[:1] if draft else trajs, draft)


_DRAW: dict[str, Callable[[_Inputs], Figure]] = {
    "fou_comparison": lambda i: _fig_fou_comparison(i.result, i.ctrls, i.pal, i.trajs),
    "integral_errors": lambda i: _fig_integral_errors(i.result, i.summ, i.ctrls, i.pal, i.trajs),
    "noise_sweep": lambda i: _fig_noise_sweep(i.result, i.summ, i.ctrls, i.pal, i.trajs),
    "fou_sweep": lambda i: _fig_fou_sweep(i.result, i.summ, i.ctrls, i.pal, i.trajs),
    "control_surfaces": lambda i: _fig_control_surfaces(i.result, i.ctrls, draft=i.draft),
    "dead_zone": lambda i: _fig_dead_zone(i.result, i.ctrls, i.pal),
    "win_rates": lambda i: _fig_win_rates(i.result, i.summ, i.ctrls, i.trajs),
    "robustness": lambda i: _fig_robustness(i.result.robustness, i.trajs),
    "sensitivity": lambda i: _fig_sensitivity(i.result.robustness),
}

#: The figures with a panel (row or column) per trajectory: a draft draws the first only.
PER_TRAJECTORY = frozenset({"fou_comparison", "integral_errors", "noise_sweep", "fou_sweep",
                            "win_rates", "robustness"})


def draw_figure(key: str, result: StudyResult,
                summary: Sequence[Mapping[str, Any]], *, draft: bool = False) -> Figure:
    """The figure ``key`` (see :func:`figure_plan`) as a matplotlib figure, not yet drawn.

    Call it inside ``matplotlib.rc_context(figures.style._RC)`` for the study's look;
    :func:`write_figure` does. ``draft``: a smoke run's figure, whose panels per trajectory
    (:data:`PER_TRAJECTORY`) show the study's first trajectory only, and whose control surfaces
    the first row only (the FLC and the IT2FLCs), and a note says so.

    Raises
    ------
    KeyError
        ``key`` is not a figure of this study, or its data are absent.
    """
    if key not in figure_plan(result, summary):
        raise KeyError(f"no figure {key!r} for this result (have: "
                       f"{', '.join(figure_plan(result, summary)) or 'none'})")
    inputs = _Inputs.of(result, summary, draft=draft)
    traj = paper_figures(result).get(key)
    if traj is not None:
        return _fig_paper(result, traj, inputs.ctrls, inputs.pal)
    fig = _DRAW[key](inputs)
    left_out = len(result.config.trajectories) - len(inputs.trajs)
    if key in PER_TRAJECTORY and left_out:
        fig.text(0.995, 0.005, f"draft (reproduce --quick): trajectory {inputs.trajs[0]} only; "
                 f"{left_out} more in the full run", ha="right", va="bottom", fontsize=8,
                 color="#b00000")
    return fig


def write_figure(key: str, result: StudyResult, summary: Sequence[Mapping[str, Any]],
                 out_dir: Path, *, svg: bool = True, draft: bool = False) -> Path:
    """Draw the figure ``key`` and write ``<key>.png`` (and ``<key>.svg``) into ``out_dir``.

    A module-level function of picklable arguments, so that figures can be written by worker
    processes; the files do not depend on the process that writes them. ``draft``: a smoke
    run's PNG (:data:`~.style.DRAFT_DPI`, unhinted text, no palette quantisation).

    Returns
    -------
    Path
        The PNG file.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rc = {**_RC, **_DRAFT_RC} if draft else _RC
    with matplotlib.rc_context(rc):  # type: ignore[arg-type]
        return _save(draw_figure(key, result, summary, draft=draft), out_dir, key, svg=svg,
                     draft=draft)


def write_figures(
    result: StudyResult, summary: Sequence[Mapping[str, Any]], out_dir: Path, *,
    svg: bool = True,
) -> dict[str, Path]:
    """Draw every figure of the study and write each as PNG (and SVG).

    Parameters
    ----------
    result : StudyResult
        From :func:`it2track.experiments.study.runner.run_study`.
    summary : list of dict
        From :func:`it2track.experiments.analysis.summarise` ``(result.rows)``.
    out_dir : Path
        Folder for ``<key>.png`` and ``<key>.svg`` (created if missing).
    svg : bool, default True
        Also write each figure as SVG.

    Returns
    -------
    dict of str -> Path
        Figure key -> PNG path, in report order (see :func:`figure_keys`). Figures whose data
        are absent (e.g. no ``noise`` rows in ``summary``) are skipped.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    return {key: write_figure(key, result, summary, out_dir, svg=svg)
            for key in figure_plan(result, summary)}

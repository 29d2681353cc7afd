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

Controllers are identified by their :class:`~it2track.experiments.specs.ControllerSpec` or by
the ``kind`` and ``fou`` columns of the metrics table, never by the text of their labels (see
:mod:`it2track.report.identity`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib

from ...experiments.study import StudyResult
from ..identity import (
    INTEGRAL_UNITS,
    PAPER_FIGURE_NUMBER,
    _controller_table,
    _Summary,
    controller_specs,
    slug,
    surface_limit,
)
from .claims import _fig_win_rates
from .integrals import _fig_integral_errors
from .style import _RC, FIGURE_DPI, _Palette, _save
from .surfaces import _fig_control_surfaces, _fig_dead_zone
from .sweeps import _fig_fou_sweep, _fig_noise_sweep
from .timeseries import _fig_fou_comparison, _fig_paper

__all__ = [
    "FIGURE_DPI",
    "INTEGRAL_UNITS",
    "PAPER_FIGURE_NUMBER",
    "controller_specs",
    "figure_keys",
    "slug",
    "surface_limit",
    "write_figures",
]


def figure_keys(result: StudyResult) -> list[str]:
    """The keys :func:`write_figures` produces for ``result`` (in report order)."""
    keys = [f"paper_{slug(t)}" for t in result.config.trajectories]
    keys += ["fou_comparison", "integral_errors", "noise_sweep", "fou_sweep"]
    keys += ["control_surfaces", "dead_zone", "win_rates"]
    return keys


def write_figures(
    result: StudyResult, summary: Sequence[Mapping[str, Any]], out_dir: Path
) -> dict[str, Path]:
    """Draw every figure of the study and write each as PNG and SVG.

    Parameters
    ----------
    result : StudyResult
        From :func:`it2track.experiments.study.run_study`.
    summary : list of dict
        From :func:`it2track.experiments.analysis.summarise` ``(result.rows)``.
    out_dir : Path
        Folder for ``<key>.png`` and ``<key>.svg`` (created if missing).

    Returns
    -------
    dict of str -> Path
        Figure key -> PNG path, in report order (see :func:`figure_keys`). Figures whose data
        are absent (e.g. no ``noise`` rows in ``summary``) are skipped.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    cfg = result.config
    ctrls = _controller_table(result)
    pal = _Palette(cfg.fous)
    summ = _Summary(summary)
    out: dict[str, Path] = {}
    with matplotlib.rc_context(_RC):  # type: ignore[arg-type]
        for traj in cfg.trajectories:
            if traj in result.traces:
                key = f"paper_{slug(traj)}"
                out[key] = _save(_fig_paper(result, traj, ctrls, pal), out_dir, key)
        if all(t in result.traces for t in cfg.trajectories):
            out["fou_comparison"] = _save(_fig_fou_comparison(result, ctrls, pal), out_dir,
                                          "fou_comparison")
        if summ.has("paper"):
            out["integral_errors"] = _save(_fig_integral_errors(result, summ, ctrls, pal),
                                           out_dir, "integral_errors")
        if summ.has("noise"):
            out["noise_sweep"] = _save(_fig_noise_sweep(result, summ, ctrls, pal), out_dir,
                                       "noise_sweep")
        if summ.has("fou"):
            out["fou_sweep"] = _save(_fig_fou_sweep(result, summ, ctrls, pal), out_dir,
                                     "fou_sweep")
        if result.surfaces:
            out["control_surfaces"] = _save(_fig_control_surfaces(result, ctrls), out_dir,
                                            "control_surfaces")
            out["dead_zone"] = _save(_fig_dead_zone(result, ctrls, pal), out_dir, "dead_zone")
        if summ.has("paper") and len(summ.controllers("paper")) > 1:
            out["win_rates"] = _save(_fig_win_rates(result, summ, ctrls), out_dir, "win_rates")
    return out

"""Which figures a study result can have, in report order: numpy only, so that the process that
hands figures to workers (:mod:`.render`) never imports matplotlib itself.

The drawing functions for these keys are in :mod:`it2track.report.figures`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

from ..experiments.study import StudyConfig, StudyResult
from .identity import _Summary, slug

__all__ = ["figure_keys", "figure_plan", "possible_figure_keys"]

#: Figure key -> does the data hold what the figure shows (for the keys that are not per
#: trajectory), in report order after the per-trajectory ``paper_<trajectory>`` figures.
_AVAILABLE: dict[str, Callable[[StudyResult, _Summary], bool]] = {
    "fou_comparison": lambda r, s: all(t in r.traces for t in r.config.trajectories),
    "integral_errors": lambda r, s: s.has("paper"),
    "noise_sweep": lambda r, s: s.has("noise"),
    "fou_sweep": lambda r, s: s.has("fou"),
    "control_surfaces": lambda r, s: bool(r.surfaces),
    "dead_zone": lambda r, s: bool(r.surfaces),
    "win_rates": lambda r, s: s.has("paper") and len(s.controllers("paper")) > 1,
    "robustness": lambda r, s: r.robustness is not None and bool(r.robustness.verdicts),
    "sensitivity": lambda r, s: (r.robustness is not None
                                 and bool(r.robustness.sensitivity_ranking)),
}


def paper_figures(result: StudyResult) -> dict[str, str]:
    """Key -> trajectory of the per-trajectory figures ``paper_<slug>`` (paper Figs. 7-9)."""
    return {f"paper_{slug(t)}": t for t in result.config.trajectories}


#: Figures whose data are in the result itself, not in the summary.
_FROM_RESULT = ("robustness", "sensitivity")


def figure_keys(result: StudyResult) -> list[str]:
    """Every key :func:`~it2track.report.figures.write_figures` can produce for ``result``, in
    report order (the robustness figures only when ``result`` has their data)."""
    empty = _Summary([])
    return [*paper_figures(result), *(k for k, ok in _AVAILABLE.items()
                                      if k not in _FROM_RESULT or ok(result, empty))]


def possible_figure_keys(config: StudyConfig) -> list[str]:
    """Every key a study of ``config`` may draw, known before it runs: a superset of what
    :func:`figure_plan` gives for its result (the names ``reproduce`` checks in ``--out``
    before any work)."""
    keys = [f"paper_{slug(t)}" for t in config.trajectories]
    keys += [k for k in _AVAILABLE if k not in _FROM_RESULT]
    if config.robustness is not None:
        keys.append("robustness")
        if config.robustness.sensitivity is not None:
            keys.append("sensitivity")
    return keys


def figure_plan(result: StudyResult, summary: Sequence[Mapping[str, Any]]) -> list[str]:
    """The keys of the figures whose data ``result`` and ``summary`` hold, in report order.

    A result with traces and surfaces but no rows, and an empty summary, plans exactly the
    figures that need no Monte Carlo (the time series, control surfaces and dead zone): they
    can be drawn while the experiments still run.
    """
    summ = _Summary(summary)
    keys = [k for k, t in paper_figures(result).items() if t in result.traces]
    return keys + [k for k, ok in _AVAILABLE.items() if ok(result, summ)]

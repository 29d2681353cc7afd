"""The page's section "The verdicts on the chip" (:mod:`it2track.experiments.chip`), or why it
was not run."""

from __future__ import annotations

from markupsafe import Markup

from ..chip import ChipOutcome, chip_summary, replay_sentence
from .env import render

__all__ = ["chip_section"]


def chip_section(outcome: ChipOutcome) -> Markup:
    """The section for ``outcome``.

    Parameters
    ----------
    outcome : ChipOutcome
        The chip experiment's result, or the reason it did not run.
    """
    if outcome.result is None:
        return render("sections/chip.html.j2", ran=False, reason=outcome.reason)
    s = chip_summary(outcome.result)
    replay = replay_sentence(s).replace("**", "")
    return render("sections/chip.html.j2", ran=True, s=s, replay=replay, smoke=outcome.smoke)

"""The study's self-contained HTML report: one file, figures embedded, no script, no network.

The page holds the setup, every assumption the study makes where the paper is silent or
misprinted (docs/model.md), the figures with captions, the verdicts on the paper's claims with their
criteria and evidence, a summary table and the command that regenerates it all. It is built from
Jinja2 templates (``it2track/report/templates``, autoescaped) by one module per page section:
:mod:`.study_setup`, :mod:`.assumptions`, :mod:`.results` (with :mod:`.captions`),
:mod:`.claims`, :mod:`.baselines`, :mod:`.robustness`, :mod:`.mcu` (the microcontroller cost,
when measured or asked for), :mod:`.summary`, :mod:`.rerun`. The file is written atomically.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ...atomicfile import atomic_write_text
from ...experiments.study import StudyResult
from ..chip import ChipOutcome
from ..counts import count_text
from ..mcu_job import McuCosts
from ..physics import PhysicsOutcome
from .assumptions import assumptions_section
from .baselines import baselines_section
from .captions import figure_captions
from .chip import chip_section
from .claims import claims_section, glance
from .env import render
from .mcu import mcu_section
from .physics import physics_section
from .rerun import rerun_section
from .results import figure_refs, results_section
from .robustness import robustness_section
from .study_setup import setup_section
from .summary import summary_section

__all__ = ["figure_captions", "render_html", "write_html"]

#: The page's sections in order: (anchor, heading) for the navigation.
SECTIONS = (("setup", "Setup"), ("assumptions", "Assumptions"), ("results", "Results"),
            ("claims", "Claims"), ("baselines", "Fair baselines"),
            ("robustness", "Robustness to the open modelling choices"),
            ("physics", "Physics check (MuJoCo)"),
            ("mcu", "Microcontroller cost"), ("chip", "The verdicts on the chip"),
            ("summary", "Summary table"),
            ("rerun", "How to rerun"))


def render_html(
    *,
    result: StudyResult,
    summary: Sequence[Mapping[str, Any]],
    claims: Sequence[Any],
    manifest: Mapping[str, Any],
    figures: Mapping[str, Path],
    elapsed_s: float,
    mcu: McuCosts | None = None,
    smoke: bool = False,
    physics: PhysicsOutcome | None = None,
    chip: ChipOutcome | None = None,
) -> str:
    """The report as one HTML string (see :func:`write_html`)."""
    cfg = result.config
    paper_n = count_text(int(r["n"]) for r in summary
                         if r.get("experiment") == "paper" and float(r["noise_std"]) > 0.0)
    sub = (f"Study run in {elapsed_s:.1f} s · {len(cfg.trajectories)} trajectories · "
           f"main noise level σ = {cfg.noise_std:g} rad · {paper_n} realisations per cell of "
           "the Monte Carlo comparison" + (" · smoke run — not evidence" if smoke else ""))
    refs = figure_refs(result, summary, figures)
    sections = [
        setup_section(result, summary),
        assumptions_section(result),
        results_section(refs),
        claims_section(claims, trajectories=cfg.trajectories, ordering=result.ordering,
                       fous=cfg.fous, levels=result.verdict_rows,
                       target=cfg.verdicts.target),
        baselines_section(result),
        robustness_section(result, refs),
        *([] if physics is None else [physics_section(physics)]),
        *([] if mcu is None else [mcu_section(mcu, refs.get("mcu_costs"))]),
        *([] if chip is None else [chip_section(chip)]),
        summary_section(result, summary),
        rerun_section(result, manifest, elapsed_s),
    ]
    nav = [s for s in SECTIONS if (mcu is not None or s[0] != "mcu")
           and (physics is not None or s[0] != "physics")
           and (chip is not None or s[0] != "chip")]
    return str(render("page.html.j2", subtitle=sub, glance=glance(claims, smoke=smoke),
                      nav=nav, sections=sections, smoke=smoke))


def write_html(
    path: Path,
    *,
    result: StudyResult,
    summary: Sequence[Mapping[str, Any]],
    claims: Sequence[Any],
    manifest: Mapping[str, Any],
    figures: Mapping[str, Path],
    elapsed_s: float,
    mcu: McuCosts | None = None,
    smoke: bool = False,
    physics: PhysicsOutcome | None = None,
    chip: ChipOutcome | None = None,
) -> Path:
    """Write the study's self-contained HTML report.

    Parameters
    ----------
    path : Path
        Destination (written atomically: a reader sees the old file or the whole new one).
    result : StudyResult
    summary : list of dict
        From :func:`it2track.experiments.analysis.summarise`.
    claims : list of ClaimResult
        The study's verdicts (``result.claims``, with replication probabilities).
    manifest : dict
        Provenance; ``manifest["command"]`` is shown as the command to rerun.
    figures : dict of str -> Path
        From :func:`it2track.report.figures.write_figures`; each file is embedded as a base64
        data URI, so the page needs nothing else.
    elapsed_s : float
        Wall time of the run, s.
    mcu : McuCosts, optional
        The microcontroller measurement (:mod:`it2track.report.mcu_job`); its figure, if any,
        is ``figures["mcu_costs"]``. Without it the page has no microcontroller section.
    smoke : bool
        A ``--quick`` run: the page says "smoke run — not evidence" at the top and beside
        the verdicts.
    physics : PhysicsOutcome, optional
        The physics check (:mod:`it2track.report.physics`), run or skipped with its reason.
        Without it the page has no physics section.
    chip : ChipOutcome, optional
        The verdicts on the chip (:mod:`it2track.experiments.chip`) or why they were not
        judged; without it the page has no such section.

    Returns
    -------
    Path
        ``path``.
    """
    text = render_html(result=result, summary=summary, claims=claims, manifest=manifest,
                       figures=figures, elapsed_s=elapsed_s, mcu=mcu, smoke=smoke,
                       physics=physics, chip=chip)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, text)
    return path

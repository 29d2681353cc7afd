"""Every figure's caption and title state the n, sigma and counts of the rows they describe:
each is recomputed here from the data and compared with the text (one check per figure; a
figure without a check fails the coverage test)."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

from it2track.cli.reproduce import _quick
from it2track.experiments.analysis import summarise
from it2track.experiments.study import StudyConfig, run_study
from it2track.report.figures import draw_figure, figure_plan
from it2track.report.figures.style import _RC
from it2track.report.html import figure_captions


def _count(values) -> str:
    v = sorted(set(values))
    return str(v[0]) if len(v) == 1 else f"{v[0]}–{v[-1]}"


@pytest.fixture(scope="module")
def study():
    result = run_study(_quick(StudyConfig()))
    summary = summarise(result.rows)
    captions = figure_captions(result, summary)
    titles = {}
    with matplotlib.rc_context(_RC):
        for key in figure_plan(result, summary):
            fig = draw_figure(key, result, summary)
            titles[key] = fig._suptitle.get_text() if fig._suptitle is not None else ""
    return result, summary, captions, titles


def _rows(summary, experiment):
    return [r for r in summary if r["experiment"] == experiment and r["noise_std"] > 0.0]


def _trace_noise(result):
    runs = [t.runs for t in result.traces.values()]
    sigma = sorted({float(s) for r in runs for s in r.noise_std})
    seed = sorted({int(s) for r in runs for s in r.seed})
    return ", ".join(f"{s:g}" for s in sigma), ", ".join(map(str, seed))


def check_traces(key, result, summary, caption, title):
    sigma, seed = _trace_noise(result)
    assert f"σ = {sigma} rad" in caption and f"seed index {seed}" in caption
    assert f"σ = {sigma} rad" in title and f"seed index {seed}" in title


def check_integral_errors(key, result, summary, caption, title):
    rows = _rows(summary, "paper")
    n, sigma = _count(r["n"] for r in rows), _count(r["noise_std"] for r in rows)
    assert f"mean over {n} noise realisations at σ = {sigma} rad" in caption
    assert f"mean over {n} noise realisations at σ = {sigma} rad" in title


def check_win_rates(key, result, summary, caption, title):
    rows = _rows(summary, "paper")
    n, sigma = _count(r["n"] for r in rows), _count(r["noise_std"] for r in rows)
    assert f"over the {n} noise realisations at σ = {sigma} rad" in caption
    assert f"at σ = {sigma} rad" in title


def check_noise_sweep(key, result, summary, caption, title):
    counts = [r["n"] for r in _rows(summary, "noise")]
    n = _count(counts)
    # Seeds by need: the counts vary, and the text says so (never the noise-free row's 1).
    assert len(set(counts)) > 1 and "–" in n
    assert f"over {n} realisations per point" in caption
    assert f"over {n} realisations per point" in title
    assert "over 1 realisations" not in caption + title
    assert f"σ = {result.config.noise_std:g} rad" in caption


def check_fou_sweep(key, result, summary, caption, title):
    rows = _rows(summary, "fou")
    n, sigma = _count(r["n"] for r in rows), _count(r["noise_std"] for r in rows)
    assert f"at σ = {sigma} rad, mean and 95 % band over {n} realisations" in caption
    assert f"at σ = {sigma} rad" in title and f"over {n} realisations" in title


def check_control_surfaces(key, result, summary, caption, title):
    vlim = max(float(np.abs(u).max()) for _, _, u in result.surfaces.values())
    assert f"(±{vlim:.3g} V, the largest consequent)" in caption


def check_dead_zone(key, result, summary, caption, title):
    assert "realisations" not in caption  # a noise-free slice: no sample to count


def check_robustness(key, result, summary, caption, title):
    rob = result.robustness
    n = _count(int(c["n"]) for c in rob.cells if c["sigma"] > 0)
    assert f"{n} realisations per cell" in caption and f"{n} realisations per cell" in title
    levels = ", ".join(f"{s:g}" for s in rob.config.noise_levels)
    assert f"σ = {levels} rad" in caption and f"σ = {levels} rad" in title
    assert {c["sigma"] for c in rob.cells} >= set(rob.config.noise_levels)


def check_sensitivity(key, result, summary, caption, title):
    rob = result.robustness
    sens = rob.config.sensitivity
    points = sens.trajectories * (len(sens.factors) + 1)  # Morris: r (k + 1)
    assert rob.sensitivity_points == points
    assert f"{points} design points" in caption and f"{points} design points" in title


CHECKS = {
    "fou_comparison": check_traces, "integral_errors": check_integral_errors,
    "win_rates": check_win_rates, "noise_sweep": check_noise_sweep,
    "fou_sweep": check_fou_sweep, "control_surfaces": check_control_surfaces,
    "dead_zone": check_dead_zone, "robustness": check_robustness,
    "sensitivity": check_sensitivity,
}


def _check_of(key):
    return check_traces if key.startswith("paper_") else CHECKS[key]


def test_every_figure_has_a_check(study):
    result, summary, captions, _ = study
    keys = set(figure_plan(result, summary))
    assert keys <= set(captions)
    for key in keys:
        assert _check_of(key) is not None, key


@pytest.mark.parametrize("key", ["paper_straight", "paper_curved", "paper_sinusoidal",
                                 *CHECKS])
def test_caption_and_title_state_the_datas_numbers(study, key):
    result, summary, captions, titles = study
    _check_of(key)(key, result, summary, captions[key][1], titles[key])

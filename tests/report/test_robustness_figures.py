"""The robustness heat map and the sensitivity ranking show exactly the data given to them."""

from __future__ import annotations

import itertools
from types import SimpleNamespace

import matplotlib
import matplotlib.colors
import pytest
from matplotlib.patches import Rectangle

from it2track.report.figures.robustness import (
    ALL,
    STATUS_COLORS,
    _fig_robustness,
    _fig_sensitivity,
    robustness_cells,
)
from it2track.report.figures.style import _RC

TRAJS = ("straight", "curved")
STATUSES = ("holds", "contradicted", "not shown", "deterministic")


def _rob() -> SimpleNamespace:
    """Three variants (the baseline, a one-at-a-time alternative, a noise reading judged at its
    own level) x two claims, with every status and change category somewhere, each
    (level, trajectory) in the cells several times (one per metric)."""
    cycle = itertools.cycle(STATUSES)
    variants = [("baseline", "paper", "baseline", "0.05, 0.1"),
                ("half_track", "0.28", "one-at-a-time", "0.05, 0.1"),
                ("noise_reading", "0.316228", "one-at-a-time", "0.316228")]
    labels = {"paper": "the paper's choices", "0.28": "l = 0.28 m",
              "0.316228": "σ = 0.316 rad"}
    changes = itertools.cycle(("unchanged", "flipped", "changed"))
    verdicts, cells = [], []
    for (choice, value, part, levels), claim in itertools.product(variants, ("C1", "C3")):
        # The verdicts write levels with %g; the cells keep the exact sigma (sqrt(0.1)).
        sig = [0.1 ** 0.5 if s.strip() == "0.316228" else float(s) for s in levels.split(",")]
        status = [next(cycle) for _ in sig]
        settled = ["no" if (claim, value) == ("C1", "0.28") and i == 0 else "yes"
                   for i in range(len(sig))]
        verdicts.append({"claim": claim, "choice": choice, "value": value, "part": part,
                         "label": labels[value], "settled": ";".join(settled),
                         "noise_levels": levels, "status": ";".join(status),
                         "change": "unchanged" if part == "baseline" else next(changes),
                         "verdict": "v"})
        for s, traj in itertools.product(sig, TRAJS):
            if claim == "C3" and traj != "straight":
                continue
            for metric in ("IAE", "ISE"):  # several cells per (level, trajectory): one status
                cells.append({"claim": claim, "choice": choice, "value": value, "sigma": s,
                              "trajectory": traj, "verdict": STATUSES[(len(cells) // 2) % 4],
                              "metric": metric, "n": 7})
    sens = SimpleNamespace(trajectories=4, factors=(1, 2, 3), seeds=2)
    return SimpleNamespace(
        verdicts=verdicts, cells=cells,
        config=SimpleNamespace(noise_levels=(0.05, 0.1), seeds=7, sensitivity=sens),
        sensitivity_ranking=[{"factor": "kde", "score": 0.25, "rank": 2},
                             {"factor": "half_track", "score": 1.0, "rank": 1},
                             {"factor": "noise_rate", "score": 0.0, "rank": 3}],
        sensitivity=[{"output": o, "trajectory": "straight", "factor": f, "mu_star": m,
                      "mu_star_conf": m / 10, "mu": m, "sigma": m}
                     for o in ("IT2 - FLC", "FoU 0.3 - 0.1")
                     for f, m in (("half_track", 1e-3), ("kde", 2e-4), ("noise_rate", 0.0))],
        sensitivity_points=32,
    )


def _label(v: dict) -> str:
    return "baseline (the paper's choices)" if v["part"] == "baseline" else v["label"]


def test_every_heat_map_cell_has_the_colour_of_its_status():
    rob = _rob()
    with matplotlib.rc_context(_RC):
        fig = _fig_robustness(rob, TRAJS)
    drawn = {p.get_gid(): p for p in fig.findobj(Rectangle)
             if (p.get_gid() or "").startswith("robustness|")}
    expected = {}
    for v in rob.verdicts:
        for s, st in zip(v["noise_levels"].split(","), v["status"].split(";"), strict=True):
            expected[f"robustness|{ALL}|{v['claim']}|{_label(v)}|{float(s):g}"] = st
    for c in rob.cells:
        v = next(v for v in rob.verdicts if (v["choice"], v["value"], v["claim"])
                 == (c["choice"], c["value"], c["claim"]))
        expected[f"robustness|{c['trajectory']}|{c['claim']}|{_label(v)}|{c['sigma']:g}"] = (
            c["verdict"])
    assert set(drawn) == set(expected), set(drawn) ^ set(expected)
    for gid, status in expected.items():
        assert matplotlib.colors.same_color(drawn[gid].get_facecolor()[:3],
                                            STATUS_COLORS[status]), gid
    # A variant's levels share its cell's width; the noise reading's single level fills it.
    one = drawn[f"robustness|{ALL}|C1|σ = 0.316 rad|0.316228"]
    two = drawn[f"robustness|{ALL}|C1|l = 0.28 m|0.05"]
    assert one.get_width() == pytest.approx(2 * two.get_width())
    rows = [t.get_text() for t in fig.axes[0].get_yticklabels()]
    assert rows == list(dict.fromkeys(_label(v) for v in rob.verdicts))
    # Unsettled statuses are pale and hatched; settled ones solid.
    assert two.get_hatch() == "////" and two.get_alpha() == pytest.approx(0.35)
    other = drawn[f"robustness|{ALL}|C1|l = 0.28 m|0.1"]
    assert other.get_hatch() is None and other.get_alpha() == 1.0
    # The title's count is the cells' own.
    assert "7 realisations per cell" in fig._suptitle.get_text()


def test_flips_and_changes_are_outlined_and_nothing_else():
    rob = _rob()
    with matplotlib.rc_context(_RC):
        fig = _fig_robustness(rob, TRAJS)
    marks = {p.get_gid() for p in fig.findobj(Rectangle) if (p.get_gid() or "").startswith(
        "change|")}
    assert marks == {f"change|{v['claim']}|{_label(v)}|{v['change']}" for v in rob.verdicts
                     if v["change"] in ("flipped", "changed")}
    assert any(m.endswith("|flipped") for m in marks) and any(m.endswith("|changed")
                                                              for m in marks)


def test_robustness_cells_refuses_a_status_list_that_does_not_match_its_levels():
    bad = [{"claim": "C1", "choice": "x", "value": "1", "part": "one-at-a-time",
            "noise_levels": "0.05, 0.1", "status": "holds", "change": "unchanged"}]
    with pytest.raises(ValueError, match="1 statuses for 2 noise levels"):
        robustness_cells(bad, [], TRAJS)


def test_sensitivity_bars_follow_the_ranking():
    rob = _rob()
    with matplotlib.rc_context(_RC):
        fig = _fig_sensitivity(rob)
    bars = {p.get_gid(): p for p in fig.findobj(Rectangle)
            if (p.get_gid() or "").startswith("sensitivity|")}
    assert {k: b.get_width() for k, b in bars.items()} == {
        "sensitivity|half_track": 1.0, "sensitivity|kde": 0.25, "sensitivity|noise_rate": 0.0}
    ys = {k: b.get_y() for k, b in bars.items()}
    assert ys["sensitivity|half_track"] < ys["sensitivity|kde"] < ys["sensitivity|noise_rate"]
    labels = [t.get_text() for t in fig.axes[0].get_yticklabels()]
    assert labels == ["1. half_track", "2. kde", "3. noise_rate"]

"""The study's figures: every expected file is written, valid and not blank; no global
matplotlib state leaks."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import replace

import matplotlib
import matplotlib.image
import matplotlib.text
import numpy as np
import pytest

from it2track.experiments.analysis import summarise
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.experiments.study import PDTuning, StudyConfig, StudyResult, run_study
from it2track.report.figures import (
    PER_TRAJECTORY,
    draw_figure,
    figure_keys,
    figure_plan,
    slug,
    write_figure,
    write_figures,
)
from it2track.report.figures.claims import _fig_win_rates
from it2track.report.figures.style import _Palette
from it2track.report.figures.surfaces import _zero_de_slice
from it2track.report.identity import (
    _controller_table,
    _Ctrl,
    _Summary,
    _surface_info,
    _trace_index,
)
from it2track.tracking import LoopConfig

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
EXPECTED = {
    "paper_straight", "paper_curved", "paper_sinusoidal", "fou_comparison", "integral_errors",
    "noise_sweep", "fou_sweep", "control_surfaces", "dead_zone", "win_rates",
}  # fmt: skip


def small_config() -> StudyConfig:
    return StudyConfig(
        seeds=3,
        sweep_seeds=3,
        fou_sweep=(0.0, 0.2),
        noise_levels=(0.0, 0.1),
        loop=LoopConfig(duration=2.0),
        pd=PDTuning(seeds=2, kp_grid=(5.0, 20.0), kd_grid=(0.0, 0.1)),
        tuning=None,  # the fuzzy tuning and the robustness experiment have their own tests
        robustness=None,
    )


@pytest.fixture(scope="module")
def study() -> StudyResult:
    return run_study(small_config())


@pytest.fixture(scope="module")
def written(study: StudyResult, tmp_path_factory: pytest.TempPathFactory):
    out = tmp_path_factory.mktemp("figures")
    rc_before = dict(matplotlib.rcParams)
    figures = write_figures(study, summarise(study.rows), out)
    rc_after = dict(matplotlib.rcParams)
    return out, figures, rc_before, rc_after


def test_every_expected_figure_is_written(study, written):
    out, figures, _, _ = written
    assert set(figures) == EXPECTED
    assert list(figures) == figure_keys(study), "figures come back in report order"
    for key, png in figures.items():
        assert png == out / f"{key}.png", key
        assert png.is_file(), f"{key}: PNG missing"
        assert png.with_suffix(".svg").is_file(), f"{key}: SVG missing"
    leftovers = [p.name for p in out.iterdir() if p.suffix not in (".png", ".svg")]
    assert not leftovers, f"temporary files left behind: {leftovers}"


@pytest.mark.parametrize("key", sorted(EXPECTED))
def test_png_is_valid_and_not_blank(written, key):
    _, figures, _, _ = written
    png = figures[key]
    assert png.read_bytes()[:8] == PNG_SIGNATURE, f"{key}: not a PNG"
    img = matplotlib.image.imread(png)
    assert img.ndim == 3 and img.shape[2] in (3, 4), f"{key}: shape {img.shape}"
    h, w = img.shape[:2]
    assert 300 <= h <= 2500 and 500 <= w <= 2500, f"{key}: implausible size {w}x{h}"
    rgb = img[..., :3]
    ink = (rgb < 0.9).any(axis=2).mean()
    assert ink > 0.02, f"{key}: only {ink:.1%} of the pixels are not white"
    assert float(rgb.std()) > 0.05, f"{key}: nearly uniform image"
    assert png.stat().st_size < 1_000_000, f"{key}: PNG larger than 1 MB"


@pytest.mark.parametrize("key", sorted(EXPECTED))
def test_svg_is_well_formed(written, key):
    _, figures, _, _ = written
    svg = figures[key].with_suffix(".svg")
    root = ET.parse(svg).getroot()
    assert root.tag.endswith("svg"), f"{key}: root element {root.tag}"
    assert len(root) > 0, f"{key}: empty SVG"


def test_no_global_matplotlib_state_leaks(written):
    _, _, rc_before, rc_after = written
    assert rc_before == rc_after, "write_figures changed matplotlib.rcParams"
    import matplotlib.pyplot as plt  # imported only to inspect its registry

    assert plt.get_fignums() == [], "write_figures left pyplot figures open"


def test_without_fair_baselines(study, tmp_path):
    """A study without the PD and the dead-zone-matched FLCs still gets every figure."""
    keep = np.isin(study.rows["kind"], ["flc", "it2"])
    rows = {k: v[keep] for k, v in study.rows.items()}
    surfaces = {k: v for k, v in study.surfaces.items() if not k.startswith("T1")}
    lean = replace(study, rows=rows, surfaces=surfaces, pd=None, pd_tuning={},
                   config=replace(study.config, pd=None, matched_baseline=False))
    figures = write_figures(lean, summarise(rows), tmp_path)
    assert set(figures) == EXPECTED
    for key, png in figures.items():
        assert png.read_bytes()[:8] == PNG_SIGNATURE, key


def test_partial_summary_nested_dir_and_determinism(study, written, tmp_path):
    """Figures whose data are absent are skipped; the folder is created; the others are
    byte-identical to the first run (fixed SVG ids, no dates in the metadata)."""
    out, _, _, _ = written
    summary = [r for r in summarise(study.rows) if r["experiment"] == "paper"]
    target = tmp_path / "nested" / "figs"
    figures = write_figures(study, summary, target)
    assert set(figures) == EXPECTED - {"noise_sweep", "fou_sweep"}
    for key, png in figures.items():
        assert png.parent == target, key
        for suffix in (".png", ".svg"):
            a = (out / key).with_suffix(suffix).read_bytes()
            b = png.with_suffix(suffix).read_bytes()
            assert a == b, f"{key}{suffix} differs between two runs on the same data"


@pytest.mark.parametrize(
    ("name", "expected"),
    [("straight", "straight"), ("data/my path.csv", "my_path"), ("a b", "a_b"),
     ("C:\\x\\y.csv", "y")],
)
def test_slug(name, expected):
    assert slug(name) == expected


def _relabelled(study: StudyResult) -> tuple[StudyResult, dict[str, str]]:
    """The study with every controller renamed to an opaque label."""
    names = sorted({str(c) for c in study.rows["controller"]} | set(study.surfaces)
                   | set(study.trace_controllers))
    new = {name: f"controller #{i}" for i, name in enumerate(names)}
    rows = dict(study.rows)
    rows["controller"] = np.array([new[str(c)] for c in study.rows["controller"]], dtype=object)
    trace_specs = [replace(s, label=new[s.label]) for s in study.trace_specs]
    return replace(
        study, rows=rows, trace_specs=trace_specs,
        trace_controllers=[s.label for s in trace_specs],
        surfaces={new[k]: v for k, v in study.surfaces.items()},
        surface_specs={new[k]: replace(s, label=new[k]) for k, s in study.surface_specs.items()},
        pd=None if study.pd is None else replace(study.pd, label=new[study.pd.label]),
    ), new


def test_identity_from_specs_not_labels(study):
    """Kinds and widths come from the specs and the rows' kind/fou columns: opaque labels
    change nothing."""
    other, new = _relabelled(study)
    table = _controller_table(other)
    for label, spec in study.surface_specs.items():
        c = table[new[label]]
        assert c.kind is spec.kind and c.fou == spec.fou, label
        assert c.spec is not None and c.spec.kind is spec.kind
    for label in {str(c) for c in study.rows["controller"]}:
        kind = str(study.rows["kind"][np.flatnonzero(study.rows["controller"] == label)[0]])
        assert table[new[label]].kind is ControllerKind(kind), label
    for w in study.config.fous:
        assert _trace_index(other, ControllerKind.IT2, w) == _trace_index(
            study, ControllerKind.IT2, w) is not None
    assert _trace_index(other, ControllerKind.FLC) == 0


def test_dead_zone_slice_from_the_spec(study):
    """The u(e, 0) slice of a paper controller is rebuilt from its spec (reducer included),
    whatever its label says; a controller without a spec gets its stored surface's column."""
    spec = ControllerSpec(kind=ControllerKind.IT2, fou=0.2, reducer="nie-tan",
                          label="IT2FLC FoU 0.2")
    other = replace(study, surface_specs={**study.surface_specs, spec.label: spec})
    c = _surface_info(other, _controller_table(other), spec.label)
    assert c.spec == spec
    x, u = _zero_de_slice(other, c)
    fls = spec.build().fls
    np.testing.assert_allclose(u, fls(x, np.zeros_like(x)), atol=1e-12)
    exact = ControllerSpec(kind=ControllerKind.IT2, fou=0.2).build().fls
    assert np.abs(u - exact(x, np.zeros_like(x))).max() > 0.05, "reducer ignored"
    assert x.size > 1000, "the zoomed panel needs a finer grid than the stored surface"
    assert np.all(u[np.abs(x) < 0.1 - 1e-9] == 0.0) and np.all(u[np.abs(x) > 0.11] != 0.0)

    orphan = replace(study, surfaces={**study.surfaces, "mystery": study.surfaces[spec.label]})
    c = _surface_info(orphan, _controller_table(orphan), "mystery")
    assert c.kind is None and c.spec is None
    x, u = _zero_de_slice(orphan, c)
    ge, gde, gu = study.surfaces["IT2FLC FoU 0.2"]
    mid = gde.shape[1] // 2
    assert gde[0, mid] == 0.0
    np.testing.assert_array_equal(x, ge[:, mid])
    np.testing.assert_array_equal(u, gu[:, mid])


def test_win_rate_figure_counts_ties_half(study):
    """At sigma = 0 on the straight line nothing acts: every pair ties, win rate 0.5, and the
    figure says so rather than showing a loss."""
    rows = {k: v[(study.rows["experiment"] == "noise") & (study.rows["noise_std"] == 0.0)]
            for k, v in study.rows.items()}
    rows["experiment"] = np.full(len(rows["seed"]), "paper", dtype=object)
    summary = summarise(rows)
    straight = [r for r in summary if r["trajectory"] == "straight" and r["win_rate"] != ""]
    assert straight and all(r["win_rate"] == 0.5 and r["ties"] == 1.0 for r in straight)
    other = replace(study, config=replace(study.config, noise_std=0.0))
    fig = _fig_win_rates(other, _Summary(summary), _controller_table(other))
    texts = [t.get_text() for t in fig.findobj(matplotlib.text.Text)]
    assert any("ties count ½" in t for t in texts), "colour scale must say ties count half"
    assert any("½ P(equal error)" in t for t in texts)
    assert "ties 100%" in texts
    assert "0.5 no diff." in texts


def test_extra_controllers_keep_one_colour_whatever_the_drawing_order():
    a = _Ctrl("mine A", ControllerKind.FILE, 0.0)
    b = _Ctrl("mine B", None, 0.0)
    first, second = _Palette((0.1, 0.2), [a, b]), _Palette((0.1, 0.2), [b, a])
    assert second.style(b) == first.style(b) and second.style(a) == first.style(a)
    assert first.style(a).color != first.style(b).color


def test_figures_without_monte_carlo_can_be_drawn_early_and_are_identical(study, written,
                                                                           tmp_path):
    """Traces and surfaces alone (no rows, no summary): the plan is the figures that need no
    Monte Carlo, and they are byte-identical to those drawn from the whole result."""
    out, _, _, _ = written
    empty = {k: v[:0] for k, v in study.rows.items()}
    early = replace(study, rows=empty, pd=None, pd_tuning={})
    plan = figure_plan(early, [])
    assert plan == [*(f"paper_{slug(t)}" for t in study.config.trajectories),
                    "fou_comparison", "control_surfaces", "dead_zone"]
    for key in plan:
        png = write_figure(key, early, [], tmp_path)
        assert png.read_bytes() == (out / f"{key}.png").read_bytes(), key
        assert png.with_suffix(".svg").read_bytes() == (out / f"{key}.svg").read_bytes(), key
    with pytest.raises(KeyError, match="integral_errors"):
        draw_figure("integral_errors", early, [])


def test_svg_is_optional(study, tmp_path):
    summary = summarise(study.rows)
    figures = write_figures(study, summary, tmp_path, svg=False)
    assert set(figures) == EXPECTED
    assert sorted(p.suffix for p in tmp_path.iterdir()) == [".png"] * len(EXPECTED)


def test_tuned_and_slope_matched_controllers_have_their_own_place_and_look(study):
    """Tuned controllers are known from ``StudyResult.tuned`` (not their labels) and grouped
    apart; the slope-matched type-1 FLC sits with the IT2FLC of its width, styled apart from
    the dead-zone-matched one."""
    from it2track.report.figures.integrals import _bar_groups

    tuned_flc = ControllerSpec(kind=ControllerKind.FLC, ke=2.0, kde=0.5, output_gain=0.5,
                               label="opaque A")
    tuned_it2 = ControllerSpec(kind=ControllerKind.IT2, fou=0.2, ke=2.0, label="opaque B")
    slope = ControllerSpec(kind=ControllerKind.T1_SLOPE_MATCHED, fou=0.2, label="opaque C")
    other = replace(study, tuned={"FLC": tuned_flc, "IT2FLC FoU 0.2": tuned_it2},
                    surface_specs={**study.surface_specs, slope.label: slope},
                    surfaces={**study.surfaces, slope.label: study.surfaces["FLC"]})
    ctrls = _controller_table(other)
    assert ctrls["opaque A"].tuned and ctrls["opaque B"].tuned and not ctrls["FLC"].tuned
    labels = ["FLC", "IT2FLC FoU 0.2", "T1 dead-zone-matched 0.2", "opaque C", "opaque A",
              "opaque B", study.pd.label]
    groups = dict(_bar_groups(labels, ctrls))
    assert groups["w = 0.2"] == ["IT2FLC FoU 0.2", "T1 dead-zone-matched 0.2", "opaque C"]
    assert groups["tuned"] == ["opaque A", "opaque B"]
    assert list(groups) == ["FLC", "w = 0.2", "tuned", study.pd.label]
    pal = _Palette(study.config.fous, ctrls.values())
    flc, it2 = pal.style(ctrls["FLC"]), pal.style(ctrls["IT2FLC FoU 0.2"])
    t_flc, t_it2 = pal.style(ctrls["opaque A"]), pal.style(ctrls["opaque B"])
    assert (t_flc.color, t_it2.color) == (flc.color, it2.color), "tuned keeps its colour"
    assert t_flc.hatch == t_it2.hatch == "++" and flc.hatch is None
    s = pal.style(ctrls["opaque C"])
    dz = pal.style(ctrls["T1 dead-zone-matched 0.2"])
    assert s.color == dz.color == it2.color and s.hatch != dz.hatch and s.ls != dz.ls
    from it2track.report.figures.surfaces import _surface_layout

    grid = _surface_layout(other, ctrls)
    assert ["opaque C" in row for row in grid] == [False, False, True], grid
    assert grid[2][grid[0].index("IT2FLC FoU 0.2")] == "opaque C", "under its IT2FLC"


def test_draft_figures_are_smaller_and_the_same_drawing(study, written, tmp_path):
    """A smoke run's drafts: the same figure at DRAFT_DPI, RGB(A) straight from matplotlib (the
    published PNG is a 256-colour palette at FIGURE_DPI); rcParams untouched."""
    import PIL.Image

    from it2track.report.figures.style import DRAFT_DPI, FIGURE_DPI
    from it2track.report.render import FigureRenderer

    _, figures, _, _ = written
    summary = summarise(study.rows)
    rc_before = dict(matplotlib.rcParams)
    with FigureRenderer(tmp_path, workers=0, svg=False, draft=True) as renderer:
        renderer.submit(study, summary)
        drafts = renderer.results(study)
    assert dict(matplotlib.rcParams) == rc_before
    assert set(drafts) == set(figures)
    for key, png in drafts.items():
        fig = draw_figure(key, study, summary, draft=True)
        width, height = fig.get_size_inches()
        final_width, final_height = draw_figure(key, study, summary).get_size_inches()
        with PIL.Image.open(png) as draft, PIL.Image.open(figures[key]) as final:
            assert draft.mode in ("RGB", "RGBA") and final.mode == "P", key
            assert draft.size == (round(width * DRAFT_DPI), round(height * DRAFT_DPI)), key
            assert final.size == (round(final_width * FIGURE_DPI),
                                  round(final_height * FIGURE_DPI)), key
    assert sorted(p.suffix for p in tmp_path.iterdir()) == [".png"] * len(figures)


def test_a_draft_draws_the_first_trajectory_of_a_per_trajectory_figure(study):
    """A draft of a figure with panels per trajectory draws the study's first trajectory only
    (a third of the panels: the smoke run's figures cost about half) and says so in red; the
    other figures are drawn whole, with no note."""
    summary = summarise(study.rows)
    trajs = list(study.config.trajectories)
    assert len(trajs) == 3
    note = (f"draft (reproduce --quick): trajectory {trajs[0]} only; 2 more in the full run")

    def titles(fig):
        return " ".join(a.get_title() for a in fig.axes)

    def texts(fig):
        return [t.get_text() for t in fig.texts]

    for key in figure_plan(study, summary):
        full = draw_figure(key, study, summary)
        draft = draw_figure(key, study, summary, draft=True)
        if key in PER_TRAJECTORY:
            assert all(t in titles(full) for t in trajs), key
            assert trajs[0] in titles(draft), key
            assert not any(t in titles(draft) for t in trajs[1:]), key
            assert len(draft.axes) < len(full.axes), key
            assert note in texts(draft) and note not in texts(full), key
            assert next(t for t in draft.texts if t.get_text() == note).get_color() == "#b00000"
        elif key != "control_surfaces":  # (its draft: the next test)
            assert len(draft.axes) == len(full.axes), key
            assert texts(draft) == texts(full), key
    assert PER_TRAJECTORY == {"fou_comparison", "integral_errors", "noise_sweep", "fou_sweep",
                              "win_rates", "robustness"}


def test_a_draft_of_the_control_surfaces_draws_their_first_row(study):
    """A draft draws the surfaces of the FLC and the IT2FLCs only (half the figure's CPU, at
    the end of a smoke run), in the full figure's order, and says how many it left out; a study
    whose surfaces fill one row gets the whole figure and no note."""
    summary = summarise(study.rows)

    def panels(fig):
        return [a.get_title().split("\n")[0] for a in fig.axes if a.images]

    full = draw_figure("control_surfaces", study, summary)
    draft = draw_figure("control_surfaces", study, summary, draft=True)
    fous = study.config.fous
    assert panels(full)[:1 + len(fous)] == panels(draft) == [
        "FLC", *(f"IT2FLC FoU {w:g}" for w in fous)]
    left = len(panels(full)) - len(panels(draft))
    assert left == 2 * len(fous)  # the dead-zone- and slope-matched type-1 FLCs
    note = [t for t in draft.texts if t.get_text().startswith("draft")]
    assert [t.get_text() for t in note] == [
        f"draft (reproduce --quick): the first row only; {left} more surfaces in the full run"]
    assert note[0].get_color() == "#b00000"
    assert draft.get_size_inches()[1] < full.get_size_inches()[1]
    assert not [t for t in full.texts if t.get_text().startswith("draft")]

    one_row = replace(study, surfaces={k: v for k, v in study.surfaces.items()
                                       if k in panels(draft)})
    whole = draw_figure("control_surfaces", one_row, summary, draft=True)
    assert panels(whole) == panels(draft)
    assert not [t for t in whole.texts if t.get_text().startswith("draft")]
    one = replace(study, surfaces={k: v for k, v in study.surfaces.items()
                                   if k in ("FLC", "T1 slope-matched 0.2")})
    assert [t.get_text() for t in draw_figure("control_surfaces", one, summary,
                                              draft=True).texts if t.get_text().startswith(
        "draft")] == ["draft (reproduce --quick): the first row only; 1 more surface in the "
                      "full run"]


def test_a_draft_has_the_fixed_spacing_and_no_constrained_layout(tmp_path):
    """A draft skips the constrained layout (it measures every label twice: a fifth of a
    smoke run's figure CPU) and spaces its grid by _DRAFT_SPACING instead; a published figure
    keeps its constrained layout."""
    from matplotlib.figure import Figure
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    from it2track.report.figures.style import _DRAFT_SPACING, _save

    assert _DRAFT_SPACING == {"left": 0.08, "right": 0.96, "bottom": 0.12, "top": 0.88,
                              "wspace": 0.4, "hspace": 0.6}
    figs = {}
    for draft in (True, False):
        fig = Figure(figsize=(4.0, 3.0), layout="constrained")
        grid = fig.add_gridspec(2, 2)
        axes = [fig.add_subplot(grid[i, j]) for i in range(2) for j in range(2)]
        inner = grid[1, 1].subgridspec(1, 2)  # a nested grid: its outer grid is spaced
        title = fig.suptitle("a title much wider than the four-inch figure it is the title of")
        _save(fig, tmp_path, f"draft_{draft}", svg=False, draft=draft)
        figs[draft] = (fig, grid, axes, inner)
        assert title.get_wrap() is draft  # a draft's title wraps at the figure's edges
    fig, grid, _, _ = figs[True]
    assert not isinstance(fig.get_layout_engine(), ConstrainedLayoutEngine)
    params = grid.get_subplot_params(fig)
    assert {k: getattr(params, k) for k in _DRAFT_SPACING} == _DRAFT_SPACING
    fig, grid, _, _ = figs[False]
    assert isinstance(fig.get_layout_engine(), ConstrainedLayoutEngine)
    assert grid.hspace is None and grid.wspace is None  # untouched: the layout places them

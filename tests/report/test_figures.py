"""The study's figures: every expected file is written, valid and not blank; no global
matplotlib state leaks."""

from __future__ import annotations

import time
import xml.etree.ElementTree as ET
from dataclasses import replace

import matplotlib
import matplotlib.image
import numpy as np
import pytest

from it2track.experiments.analysis import summarise
from it2track.experiments.study import PDTuning, StudyConfig, StudyResult, run_study
from it2track.report.figures import figure_keys, slug, write_figures
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
    )


@pytest.fixture(scope="module")
def study() -> StudyResult:
    return run_study(small_config())


@pytest.fixture(scope="module")
def written(study: StudyResult, tmp_path_factory: pytest.TempPathFactory):
    out = tmp_path_factory.mktemp("figures")
    rc_before = dict(matplotlib.rcParams)
    t0 = time.perf_counter()
    figures = write_figures(study, summarise(study.rows), out)
    elapsed = time.perf_counter() - t0
    rc_after = dict(matplotlib.rcParams)
    return out, figures, elapsed, rc_before, rc_after


def test_every_expected_figure_is_written(study, written):
    out, figures, _, _, _ = written
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
    _, figures, _, _, _ = written
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
    _, figures, _, _, _ = written
    svg = figures[key].with_suffix(".svg")
    root = ET.parse(svg).getroot()
    assert root.tag.endswith("svg"), f"{key}: root element {root.tag}"
    assert len(root) > 0, f"{key}: empty SVG"


def test_no_global_matplotlib_state_leaks(written):
    _, _, _, rc_before, rc_after = written
    assert rc_before == rc_after, "write_figures changed matplotlib.rcParams"
    import matplotlib.pyplot as plt  # imported only to inspect its registry

    assert plt.get_fignums() == [], "write_figures left pyplot figures open"


def test_fast_enough(written):
    _, _, elapsed, _, _ = written
    assert elapsed < 60.0, f"write_figures took {elapsed:.1f} s"


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
    out, _, _, _, _ = written
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

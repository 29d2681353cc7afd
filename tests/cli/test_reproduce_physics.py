"""`it2track reproduce` runs the physics check when MuJoCo is installed: its CSVs, claims.md
and report sections and the embedded animation; --no-physics and a missing MuJoCo leave no
physics output (the latter naming the extra); an interrupted check resumes from its cache."""

from __future__ import annotations

import csv
import json
import math
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from scipy import stats

from it2track.cli.main import main
from it2track.experiments.physics import PhysicsCheck
from it2track.experiments.sequential import SequentialDesign
from it2track.experiments.study import StudyConfig

INSTALL = "pip install 'it2track[mujoco]'"
PHYSICS_FILES = {"physics_verdicts.csv", "physics_metrics.csv", "physics_tracking.gif"}


def _tiny_study() -> StudyConfig:
    from it2track.tracking import LoopConfig

    return replace(StudyConfig(), loop=LoopConfig(duration=0.3), seeds=2, sweep_seeds=2,
                   trajectories=("straight", "curved"), noise_levels=(0.0, 0.05),
                   fou_sweep=(0.0, 0.2), pd=None, tuning=None, robustness=None,
                   verdicts=SequentialDesign(first=2, cap=4, resamples=200))


def _invoke(out: Path, *args: str):
    return CliRunner().invoke(main, ["reproduce", "--no-progress", "--no-mcu", *args, "--out",
                                     str(out)], prog_name="it2track")


@pytest.fixture
def tiny(monkeypatch):
    import it2track.cli.reproduce as cli

    monkeypatch.setattr(cli, "_default_study_config", _tiny_study)
    monkeypatch.setattr(cli, "PHYSICS_GIF_FRAMES", 3)
    # the default check, on two surfaces and a smaller cap (the test's time)
    monkeypatch.setattr(cli, "_default_physics_check", lambda: PhysicsCheck(
        surfaces=("dry", "icy"), first=2, batch=1, cap=3))
    return cli


def _read(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_physics_outputs_are_derived_from_the_data(tiny, tmp_path):
    pytest.importorskip(
        "mujoco", reason="needs the mujoco PyPI package: pip install 'it2track[mujoco]'")
    out = tmp_path / "on"
    result = _invoke(out)
    assert result.exit_code == 0, result.output
    assert PHYSICS_FILES <= {p.name for p in out.iterdir()}
    assert not (out / ".physics-cache").exists()  # the cache goes once the run is published
    verdicts = _read(out / "physics_verdicts.csv")
    assert list(verdicts[0])[:4] == ["surface", "mu", "claim", "path"]
    assert {(r["surface"], r["mu"]) for r in verdicts} == {("dry", "0.8"), ("icy", "0.1")}
    assert {"C1", "C2", "D1"} <= {r["claim"] for r in verdicts}
    metrics = _read(out / "physics_metrics.csv")
    # one cell's statistic again, from the metrics file alone
    v = next(r for r in verdicts if r["claim"] == "D1" and r["path"] == "curved"
             and r["sigma"] == "0.05" and r["surface"] == "icy")
    path, rest = v["decisive"].split(" ", 1)
    metric, pair = rest.split(": ")
    a, b = pair.split(" - ")
    cell = [r for r in metrics if r["surface"] == "icy" and r["trajectory"] == path
            and r["noise_std"] == "0.05"]
    xa = {r["seed"]: float(r[metric]) for r in cell if r["controller"] == a}
    xb = {r["seed"]: float(r[metric]) for r in cell if r["controller"] == b}
    diff = np.array([xa[s] - xb[s] for s in sorted(set(xa) & set(xb))])
    half = stats.t.ppf(0.975, diff.size - 1) * diff.std(ddof=1) / math.sqrt(diff.size)
    assert float(v["estimate"]) == pytest.approx(diff.mean(), rel=1e-9)
    assert float(v["ci_high"]) == pytest.approx(diff.mean() + half, rel=1e-9)
    assert int(v["n"]) == diff.size and 2 <= diff.size <= 3
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["physics"]["status"] == "run"
    assert manifest["physics"]["runs"] == len(metrics)
    assert PHYSICS_FILES <= set(manifest["files"])
    claims = (out / "claims.md").read_text()
    section = claims[claims.index("## Physics check"):]
    assert "| claim | σ | kinematic | dry | icy |" in section
    page = (out / "report.html").read_text()
    html = page[page.index('<h2 id="physics">'):page.index('<h2 id="mcu">')]
    assert '<img src="data:image/gif;base64,' in html
    assert "dry (μ 0.8)" in html and "icy (μ 0.1)" in html
    assert 'href="#physics"' in page
    # the kinematic status beside each surface's is the one verdicts.csv gives
    kin = {(r["claim"], r["sigma"]): r["status"] for r in _read(out / "verdicts.csv")
           if r["path"] == "all"}
    assert f"| D1 | 0.05 | {_md(kin[('D1', '0.05')], out)} |" in section


def _md(status: str, out: Path) -> str:
    row = next(r for r in _read(out / "verdicts.csv") if r["claim"] == "D1"
               and r["path"] == "all" and r["sigma"] == "0.05")
    return status if row["settled"] == "True" else f"*{status}*"


def test_no_physics_leaves_no_physics_output(tiny, tmp_path):
    out = tmp_path / "off"
    result = _invoke(out, "--no-physics")
    assert result.exit_code == 0, result.output
    names = {p.name for p in out.iterdir()}
    assert not names & PHYSICS_FILES and ".physics-cache" not in names
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["physics"] == {"status": "skipped", "reason": "skipped with --no-physics"}
    assert "skipped with --no-physics" in (out / "claims.md").read_text()


def test_quick_skips_the_check_unless_asked(tiny, tmp_path):
    result = _invoke(tmp_path / "q", "--quick")
    assert result.exit_code == 0, result.output
    page = (tmp_path / "q" / "report.html").read_text()
    assert "skipped with --quick" in page[page.index('<h2 id="physics">'):]
    assert not {p.name for p in (tmp_path / "q").iterdir()} & PHYSICS_FILES


def test_without_mujoco_the_extra_is_named(tiny, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)
    result = _invoke(tmp_path / "none")
    assert result.exit_code == 0, result.output
    assert f"physics check was skipped (MuJoCo is not installed: {INSTALL})" in result.output
    page = (tmp_path / "none" / "report.html").read_text()
    assert "pip install &#39;it2track[mujoco]&#39;" in page  # escaped quotes
    assert not {p.name for p in (tmp_path / "none").iterdir()} & PHYSICS_FILES
    refused = _invoke(tmp_path / "refused", "--physics")
    assert refused.exit_code == 1 and INSTALL in refused.output
    assert "Traceback" not in refused.output


def test_an_interrupted_check_resumes_from_its_cache(tiny, tmp_path, monkeypatch):
    pytest.importorskip(
        "mujoco", reason="needs the mujoco PyPI package: pip install 'it2track[mujoco]'")
    from it2track.experiments import physics

    real = physics.verdict_rows
    calls = []

    def interrupted(defs, claims):
        calls.append(1)
        if len(calls) == 2:  # the second surface's rounds are done: Ctrl-C
            raise KeyboardInterrupt
        return real(defs, claims)

    out = tmp_path / "resume"
    monkeypatch.setattr(physics, "verdict_rows", interrupted)
    stopped = _invoke(out)
    assert stopped.exit_code != 0
    assert not (out / "manifest.json").exists()  # nothing published
    kept = sorted((out / ".physics-cache").glob("rows-*.npz"))
    assert len(kept) >= 4  # both surfaces' first rounds and extensions
    monkeypatch.setattr(physics, "verdict_rows", real)
    result = _invoke(out)
    assert result.exit_code == 0, result.output
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["physics"]["rounds_from_cache"] == len(kept)
    fresh = tmp_path / "fresh"
    assert _invoke(fresh).exit_code == 0
    for name in ("physics_verdicts.csv", "physics_metrics.csv"):
        assert (out / name).read_bytes() == (fresh / name).read_bytes()
    assert not (out / ".physics-cache").exists()

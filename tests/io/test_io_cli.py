"""``it2track fis show|convert|eval`` and ``it2track surface`` through click's CliRunner."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from it2track import heading_fls
from it2track.cli.fis import describe, fis, surface
from it2track.io import load, save

DATA = Path(__file__).parent / "data"
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(autouse=True)
def agg_backend(monkeypatch) -> None:
    monkeypatch.setenv("MPLBACKEND", "Agg")


def test_show_prints_the_summary() -> None:
    result = CliRunner().invoke(fis, ["show", str(DATA / "two_inputs_interval.t2fis")])
    assert result.exit_code == 0, result.output
    out = result.output
    assert out.startswith("two inputs\n")
    assert "interval type-2 zero-order Sugeno (IT2Sugeno)" in out
    assert "t-norm       min" in out and "reducer      eiasc (exact)" in out
    assert "input 'a'  universe [0, 10]" in out
    assert "upper trapezoid [0 0 4 6]" in out and "lower trapezoid [0 0 3 5] h=0.8" in out
    assert "lower gaussian mean=0 sigma=0.5 h=0.6" in out
    assert "1  if a is A and b is S then [1, 2]" in out
    assert "3  if a is B then 5" in out


def test_show_type1_and_scaled_lagged() -> None:
    out = CliRunner().invoke(fis, ["show", str(DATA / "type1.toml")]).output
    assert "type-1 zero-order Sugeno (T1Sugeno)" in out
    assert "no firing    output -1.5" in out
    assert "A    gaussian mean=0 sigma=1" in out
    text = describe(load(DATA / "one_input.toml"))
    assert "lower scale 0.5, lag 0 of upper" in text


def test_show_reports_a_malformed_file() -> None:
    result = CliRunner().invoke(fis, ["show", str(DATA / "bad" / "unknown_mf.t2fis")])
    assert result.exit_code == 1
    assert "unknown_mf.t2fis:13: unknown MF type 'foo'" in result.output


def test_convert_and_eval(tmp_path) -> None:
    runner = CliRunner()
    src = tmp_path / "paper.t2fis"
    save(heading_fls(0.2), src)
    dst = tmp_path / "paper.toml"
    result = runner.invoke(fis, ["convert", str(src), str(dst)])
    assert result.exit_code == 0, result.output
    assert float(load(dst)(0.5, 0.0)) == 4.0
    result = runner.invoke(fis, ["eval", str(dst), "0.5", "0"])
    assert result.exit_code == 0, result.output
    assert "u = 4\n" in result.output and "[yl, yr] = [3.130434783, 4.869565217]" in result.output
    result = runner.invoke(fis, ["eval", str(dst), "0.5"])
    assert result.exit_code == 1 and "takes 2 VALUES (e, de), got 1" in result.output
    bad = runner.invoke(fis, ["convert", str(DATA / "two_inputs_interval.t2fis"),
                              str(tmp_path / "x.fis")])
    assert bad.exit_code == 1 and "interval consequents" in bad.output
    assert not (tmp_path / "x.fis").exists()


def test_surface_writes_a_png(tmp_path) -> None:
    runner = CliRunner()
    src = tmp_path / "paper.fis"
    save(heading_fls(0.2), src)
    out = tmp_path / "surface.png"
    result = runner.invoke(surface, [str(src), "--out", str(out), "--points", "21"])
    assert result.exit_code == 0, result.output
    assert out.read_bytes().startswith(PNG)
    out2 = tmp_path / "contour.png"
    result = runner.invoke(surface, [str(DATA / "tipper.fis"), "--out", str(out2),
                                     "--style", "contour", "--x", "food", "--points", "11"])
    assert result.exit_code == 0, result.output
    assert out2.read_bytes().startswith(PNG)
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_surface_options_and_errors(tmp_path) -> None:
    runner = CliRunner()
    out = tmp_path / "s.png"
    one = runner.invoke(surface, [str(DATA / "one_input.t2fis"), "--out", str(out)])
    assert one.exit_code == 0, one.output
    assert out.read_bytes().startswith(PNG)
    bad = runner.invoke(surface, [str(DATA / "tipper.fis"), "--out", str(out), "--x", "nope"])
    assert bad.exit_code == 2 and "--x" in bad.output
    assert "'nope': " in bad.output and "has no input of that name" in bad.output
    bad = runner.invoke(surface, [str(DATA / "tipper.fis"), "--out", str(out), "--x", "food",
                                  "--y", "food"])
    assert bad.exit_code == 2 and "--x and --y are both 'food'" in bad.output
    bad = runner.invoke(surface, [str(DATA / "tipper.fis"), "--out", str(out), "--fix", "x"])
    assert bad.exit_code == 2 and "NAME=VALUE" in bad.output
    missing = runner.invoke(surface, [str(tmp_path / "none.fis"), "--out", str(out)])
    assert missing.exit_code == 2

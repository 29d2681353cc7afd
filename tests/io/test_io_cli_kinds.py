"""``it2track fis`` and ``it2track surface`` on Mamdani, TSK, several-output and FCL files."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from it2track.cli.fis import fis, surface
from it2track.io import load

DATA = Path(__file__).parent / "data"
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(autouse=True)
def agg_backend(monkeypatch) -> None:
    monkeypatch.setenv("MPLBACKEND", "Agg")


def test_show_a_mamdani_file() -> None:
    result = CliRunner().invoke(fis, ["show", str(DATA / "tipper_mamdani.fis")])
    assert result.exit_code == 0, result.output
    out = result.output
    assert "type-1 Mamdani (T1Mamdani)" in out and "defuzzifier  centroid" in out
    assert "output 'tip'  universe [0, 30]" in out and "cheap     triangle [0 5 10]" in out
    assert "1  if service is poor or food is rancid then tip is cheap" in out


def test_show_and_eval_the_rule_language_file() -> None:
    path = str(DATA / "rule_language.fis")
    out = CliRunner().invoke(fis, ["show", path]).output
    assert "type-1 first-order (TSK) Sugeno" in out
    assert "if a is not lo and b is lo then u = 4 (weight 0.5)" in out
    assert "then u = 2*a + -1*b + 1, v = 10" in out
    result = CliRunner().invoke(fis, ["eval", path, "0.25", "0.5"])
    assert result.exit_code == 0, result.output
    assert result.output.splitlines() == ["u = 1.428571429", "v = 5.2"]


def test_convert_fcl_to_fis_keeps_the_values(tmp_path: Path) -> None:
    target = tmp_path / "valve.fis"
    result = CliRunner().invoke(fis, ["convert", str(DATA / "valve.fcl"), str(target)])
    assert result.exit_code == 0, result.output
    assert float(load(target)(2.0, 6.0)) == float(load(DATA / "valve.fcl")(2.0, 6.0))
    back = CliRunner().invoke(fis, ["convert", str(target), str(tmp_path / "x.fcl")])
    assert back.exit_code != 0 and "does not write" in back.output
    assert not (tmp_path / "x.fcl").exists()


def test_surface_of_a_system_with_two_outputs_needs_output(tmp_path: Path) -> None:
    path = str(DATA / "rule_language.fis")
    out = tmp_path / "s.png"
    result = CliRunner().invoke(surface, [path, "--out", str(out)])
    assert result.exit_code != 0 and "2 outputs (u, v); choose one" in result.output
    assert not out.exists()
    result = CliRunner().invoke(surface, [path, "--out", str(out), "--output", "v"])
    assert result.exit_code == 0, result.output
    assert out.read_bytes().startswith(PNG)
    result = CliRunner().invoke(surface, [path, "--out", str(out), "--output", "w"])
    assert result.exit_code != 0 and "the outputs are ['u', 'v']" in result.output


def test_surface_of_a_mamdani_file(tmp_path: Path) -> None:
    out = tmp_path / "t.png"
    result = CliRunner().invoke(surface, [str(DATA / "tipper_mamdani.fis"), "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert out.read_bytes().startswith(PNG)


def test_surface_survives_spurious_blas_flags_in_3d_drawing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # OpenBLAS can leave overflow flags in matplotlib's 3-D projection (np.dot of finite
    # arrays), which numpy 2 reports as a RuntimeWarning: the suite's warnings-as-errors made
    # `surface` fail depending on test order. Raise such a flag there on purpose.
    import mpl_toolkits.mplot3d.proj3d as proj3d

    original = proj3d._proj_transform_vec

    def flagging(vec: Any, M: Any) -> Any:
        np.multiply(np.float64(1e308), 10.0)  # sets the overflow flag, warns if not ignored
        return original(vec, M)

    monkeypatch.setattr(proj3d, "_proj_transform_vec", flagging)
    out = tmp_path / "s.png"
    result = CliRunner().invoke(surface, [str(DATA / "rule_language.fis"), "--out", str(out),
                                          "--output", "v"])
    assert result.exit_code == 0, result.output
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

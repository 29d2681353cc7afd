"""``it2track simulate --plant mujoco --friction ...``: the paper's scenarios on the physical
robot, and the extra named when MuJoCo is missing."""

from __future__ import annotations

import json
import math
import sys

import pytest
from click.testing import CliRunner

from it2track.cli.main import main


def _metrics(*args: str) -> dict[str, float]:
    result = CliRunner().invoke(main, ["simulate", "--duration", "0.5", "--json", *args])
    assert result.exit_code == 0, result.output
    return json.loads(result.output)


def test_mujoco_missing_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)
    result = CliRunner().invoke(main, ["simulate", "--plant", "mujoco"])
    assert result.exit_code == 1
    assert "pip install 'it2track[mujoco]'" in result.output
    assert "Traceback" not in result.output


def test_the_paper_scenarios_run_on_the_physical_robot(tmp_path):
    pytest.importorskip(
        "mujoco", reason="needs the mujoco PyPI package: pip install 'it2track[mujoco]'")
    kinematic = _metrics("--trajectory", "curved")
    runs = {f: _metrics("--trajectory", "curved", "--plant", "mujoco", "--friction", f)
            for f in ("dry", "icy", "0.8")}
    assert runs["dry"] == runs["0.8"]  # "dry" is mu = 0.8
    for values in runs.values():
        assert all(math.isfinite(v) for v in values.values())
    # the physical robot is not the kinematic one, and ice is not dry ground
    assert runs["dry"]["IAE"] != kinematic["IAE"]
    assert runs["icy"]["pos_final"] > runs["dry"]["pos_final"]
    trace = tmp_path / "run.csv"
    result = CliRunner().invoke(main, ["simulate", "--duration", "0.2", "--plant", "mujoco",
                                       "--trajectory", "sinusoidal", "--trace", str(trace)])
    assert result.exit_code == 0, result.output
    assert "plant mujoco" in result.output
    lines = trace.read_text().splitlines()
    assert len(lines) == 22 and lines[0].startswith("t,x,y,theta")

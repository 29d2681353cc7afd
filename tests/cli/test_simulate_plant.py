"""``it2track simulate --plant FILE --step R``: a linear plant from a TOML file, from the CLI."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from it2track.cli.main import main
from it2track.paper import heading_fls
from it2track.plant.specs import load_plant
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    RunTable,
    StepReference,
    simulate,
)

MOTOR = """[plant]
kind = "lti"
num = [0.1]
den = [8.1e-7, 7.5054e-4, 0.0105, 0.0]
input_limits = [[-12.0, 12.0]]
output_names = ["angle"]
"""


@pytest.fixture
def motor(tmp_path: Path) -> Path:
    path = tmp_path / "motor.toml"
    path.write_text(MOTOR)
    return path


def invoke(*args: str):
    return CliRunner().invoke(main, ["simulate", *args])


def test_simulate_a_linear_plant_from_a_file(motor: Path, tmp_path: Path) -> None:
    trace_path = tmp_path / "trace.csv"
    result = invoke("--plant", str(motor), "--step", "1.0", "--ke", "2", "--kde", "10",
                    "--noise-std", "0.01", "--seed", "3", "--duration", "1", "--json",
                    "--trace", str(trace_path))
    assert result.exit_code == 0, result.output
    got = json.loads(result.output)
    cfg = LoopConfig(duration=1.0, plant=load_plant(motor))
    ctrl = FuzzyHeadingController(fls=heading_fls(0.2), ke=2.0, kde=10.0)
    ref = simulate([ctrl], [StepReference(amplitude=1.0)], RunTable(0, 0, 0.01, 3), cfg)
    assert got == {k: float(v[0]) for k, v in ref.metrics.items()}
    with open(trace_path, newline="") as fh:
        rows = list(csv.reader(fh))
    header = rows[0]
    assert "y.angle" in header and "r" in header and "u_applied" in header
    angle = np.array([float(r[header.index("y.angle")]) for r in rows[1:]])
    np.testing.assert_array_equal(angle, ref["y.angle"][0])


def test_simulate_prints_the_plant(motor: Path) -> None:
    result = invoke("--plant", str(motor), "--step", "0.5", "--duration", "0.2")
    assert result.exit_code == 0, result.output
    assert "on step 0.5" in result.output and f"plant {motor}" in result.output


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("--step", "1"), "--plant kinematic with --step 1: tracking a reference signal needs a "
                          "single-input plant"),
        (("--plant", "{motor}"), "tracking a trajectory needs a robot plant"),
        (("--plant", "{motor}", "--step", "1", "--trajectory", "curved"),
         "give either --trajectory"),
        (("--plant", "nowhere.toml", "--step", "1"), "--plant nowhere.toml: cannot read"),
        (("--plant", "motor", "--step", "1"), "give kinematic, mujoco or a .toml plant file"),
        (("--plant", "{bad}", "--step", "1"), r"unknown key(s) ['gain']"),
    ],
)
def test_bad_plant_options_exit_1_naming_the_option(motor: Path, args, message) -> None:
    bad = motor.parent / "bad.toml"
    bad.write_text(MOTOR + "gain = 2.0\n")
    argv = [a.format(motor=motor, bad=bad) for a in args]
    result = invoke(*argv, "--duration", "0.2")
    assert result.exit_code == 1, result.output
    assert message in result.output
    assert "Traceback" not in result.output


def test_a_non_finite_step_is_refused_when_parsed(motor: Path) -> None:
    result = invoke("--plant", str(motor), "--step", "nan", "--duration", "0.2")
    assert result.exit_code == 2, result.output
    assert "Invalid value for '--step': 'nan' must be a finite number" in result.output

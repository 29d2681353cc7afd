"""A Mamdani IT2FLC in the closed loop: the heading controller, ``it2track simulate
--controller-file``, a sweep and the study config with ``kind = "file"``."""

from __future__ import annotations

import csv
import textwrap
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import it2track
from it2track.cli.main import main
from it2track.cli.sweep import sweep as sweep_command
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.experiments.study import load_study_config, run_study
from it2track.fuzzy import IT2Mamdani, IT2Set, Output, Rule, T1Sugeno, TNorm, Triangle
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    RunTable,
    curved,
    run_grid,
    simulate,
    simulate_metrics,
    straight,
)

VOLTS = {"NH": -12.0, "NM": -8.0, "NL": -4.0, "Z": 0.0, "PL": 4.0, "PM": 8.0, "PH": 12.0}


def mamdani(fou: float = 0.2) -> IT2Mamdani:
    """The paper's controller as an IT2 Mamdani system (as in the example script)."""
    sugeno = it2track.heading_fls(fou)
    sets = [IT2Set.from_fou(Triangle(v if v == -12 else v - 4, v, v if v == 12 else v + 4),
                            2.0, k) for k, v in VOLTS.items()]
    label = {v: k for k, v in VOLTS.items()}
    return IT2Mamdani(inputs=sugeno.inputs, outputs=[Output("u", (-12, 12), sets)],
                      rules=[Rule(r.antecedent, label[r.consequent[0]]) for r in sugeno.rules],
                      tnorm=TNorm.PRODUCT, name="mamdani")


def test_mamdani_controller_in_a_mixed_batch_equals_running_it_alone() -> None:
    """Mamdani controllers run on the numpy evaluation beside compiled Sugeno ones; neither
    changes the other's numbers."""
    ctrl_m = FuzzyHeadingController(fls=mamdani(), name="M")
    ctrl_s = FuzzyHeadingController(fls=it2track.heading_fls(0.2), name="S")
    cfg = LoopConfig(duration=2.0)
    runs = run_grid(2, 2, noise_stds=[0.0, 0.1], seeds=3)
    both = simulate_metrics([ctrl_m, ctrl_s], [straight(), curved()], runs, cfg)
    for k, ctrl in enumerate((ctrl_m, ctrl_s)):
        sel = runs.controller == k
        alone_runs = RunTable(np.zeros(sel.sum(), dtype=int), runs.trajectory[sel],
                              runs.noise_std[sel], runs.seed[sel])
        alone = simulate_metrics([ctrl], [straight(), curved()], alone_runs, cfg)
        for name, value in alone.items():
            np.testing.assert_array_equal(both[name][sel], value, err_msg=f"{ctrl.name} {name}")
    assert np.all(np.isfinite(both["ISE"]))


def test_mamdani_controller_tracks_the_straight_line() -> None:
    trace = simulate([FuzzyHeadingController(fls=mamdani())], [straight()],
                     RunTable(0, 0, 0.0, 0), LoopConfig(duration=10.0))
    # the heading error settles: the last second's error is small
    tail = trace.series["e_true"][0, -100:]
    assert abs(tail).max() < 0.05, tail


def test_several_outputs_need_a_choice() -> None:
    base = it2track.heading_fls(0.0)
    two = T1Sugeno(inputs=base.inputs, outputs=("u", "neg_u"), rules=[
        Rule(r.antecedent, consequents=[r.consequent[0], -r.consequent[0]]) for r in base.rules])
    with pytest.raises(ValueError, match="fls_output"):
        FuzzyHeadingController(fls=two)
    ctrl = FuzzyHeadingController(fls=two, fls_output="neg_u")
    assert ctrl.fls.n_outputs == 1
    neg = T1Sugeno(inputs=base.inputs, outputs=("neg_u",),
                   rules=[Rule(r.antecedent, -r.consequent[0]) for r in base.rules])
    x = np.linspace(-1, 1, 21)
    np.testing.assert_array_equal(ctrl.output(x, x[::-1].copy(), np.zeros((0, 21))),
                                  neg(x, x[::-1]))


@pytest.fixture()
def mamdani_file(tmp_path: Path) -> Path:
    path = tmp_path / "mamdani.t2fis"
    it2track.save(mamdani(), path)
    return path


def test_simulate_cli_with_a_mamdani_file(mamdani_file: Path) -> None:
    result = CliRunner().invoke(main, ["simulate", "--controller-file", str(mamdani_file),
                                       "--trajectory", "straight", "--duration", "2"])
    assert result.exit_code == 0, result.output
    assert "ISE" in result.output and "mamdani" in result.output


def test_sweep_with_a_mamdani_file(mamdani_file: Path, tmp_path: Path) -> None:
    config = tmp_path / "sweep.toml"
    config.write_text(textwrap.dedent(f"""
        [sweep]
        seeds = 2
        noise_std = [0.0, 0.1]
        trajectories = ["straight"]

        [simulation]
        duration = 1.0

        [[controllers]]
        kind = "file"
        path = "{mamdani_file.name}"
    """), encoding="utf-8")
    out = tmp_path / "out"
    result = CliRunner().invoke(sweep_command, ["--config", str(config), "--out", str(out)])
    assert result.exit_code == 0, result.output
    with (out / "results.csv").open(encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 4
    assert {(r["label"], r["kind"]) for r in rows} == {("mamdani.t2fis", "file")}
    assert all(np.isfinite(float(r["ISE"])) for r in rows)


def test_study_config_with_a_mamdani_file(mamdani_file: Path, tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text(f"[[controllers]]\nkind = 'file'\npath = '{mamdani_file.name}'\n")
    cfg = load_study_config(config)
    spec = cfg.extra_controllers[0]
    assert spec == ControllerSpec(kind=ControllerKind.FILE, path=str(mamdani_file))
    assert isinstance(spec.build().fls, IT2Mamdani)
    small = replace(cfg, loop=LoopConfig(duration=1.0), seeds=2, sweep_seeds=2,
                    noise_levels=(0.0, 0.1), fou_sweep=(0.0, 0.2), pd=None)
    rows = run_study(small).rows
    mine = np.asarray(rows["controller"]) == spec.label
    assert mine.any() and np.all(np.isfinite(np.asarray(rows["ISE"])[mine]))

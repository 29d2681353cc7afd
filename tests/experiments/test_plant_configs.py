"""Plants other than the robot in sweeps, the optimiser and the study: ``[plant]`` tables and
reference-signal targets, checked when the file is read; results equal the library's own."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

from it2track.experiments.optimize import load_optimize_config, run_optimization
from it2track.experiments.specs import ConfigError
from it2track.experiments.study import load_study_config
from it2track.experiments.sweep import load_sweep_config, run_sweep
from it2track.experiments.sweep.store import read_results
from it2track.paper import heading_fls
from it2track.plant.linear import LinearSpec
from it2track.tracking import (
    METRIC_NAMES,
    FuzzyHeadingController,
    LoopConfig,
    StepReference,
    run_grid,
    simulate_metrics,
)

ROOT = Path(__file__).resolve().parents[2]
MOTOR = """
[plant]
kind = "lti"
num = [0.1]
den = [8.1e-7, 7.5054e-4, 0.0105, 0.0]
input_limits = [[-12.0, 12.0]]
output_names = ["angle"]
"""
SWEEP = """
[sweep]
seeds = 3
noise_std = [0.0, 0.02]
trajectories = [{ kind = "step", amplitude = 1.0, name = "one" },
                { kind = "step", amplitude = -0.5, at = 0.2, name = "back" }]

[simulation]
duration = 0.6
ts = 0.01

[[controllers]]
kind = "it2"
fou = [0.2, 0.6]
ke = 2.0
kde = 10.0
""" + MOTOR


def write(tmp_path: Path, text: str, name: str = "c.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def test_sweep_on_a_linear_plant_equals_the_library(tmp_path: Path) -> None:
    plan = load_sweep_config(write(tmp_path, SWEEP))
    assert isinstance(plan.config.plant, LinearSpec)
    assert plan.config.plant.output_names == ("angle",)
    assert [r.name for r in plan.trajectory_refs] == ["one", "back"]
    assert plan.normalised()["simulation"]["plant"]["kind"] == "lti"
    out = tmp_path / "out"
    run_sweep(plan, out, progress=False)
    header, body = read_results(out / "results.csv")
    rows = {name: [row[i] for row in body] for i, name in enumerate(header)}
    refs = [StepReference(amplitude=1.0, name="one"),
            StepReference(amplitude=-0.5, at=0.2, name="back")]
    ctrls = [FuzzyHeadingController(fls=heading_fls(w), ke=2.0, kde=10.0) for w in (0.2, 0.6)]
    direct = simulate_metrics(ctrls, refs, run_grid(2, 2, [0.0, 0.02], 3), plan.config)
    for name in METRIC_NAMES:
        np.testing.assert_array_equal(np.asarray(rows[name], dtype=float), direct[name],
                                      err_msg=name)
    assert set(rows["trajectory"]) == {"one", "back"}


def test_the_example_dc_motor_sweep_parses() -> None:
    plan = load_sweep_config(ROOT / "configs" / "sweep_dc_motor.toml")
    spec = plan.config.plant
    assert isinstance(spec, LinearSpec) and spec.input_limits == ((-12.0, 12.0),)
    # the paper's motor (Table 3) from voltage to angle, K / (s ((J s + b)(L s + R) + K^2))
    r, ind, j, b, k = 5.0, 0.0054, 0.00015, 0.0001, 0.1
    ref = LinearSpec.from_tf([k], [j * ind, j * r + b * ind, b * r + k * k, 0.0])
    for key in ("a", "b", "c"):
        np.testing.assert_allclose(getattr(spec, key), getattr(ref, key), rtol=1e-12)
    assert plan.trajectory_refs[0].reference == StepReference(amplitude=1.0, name="step-1rad")


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("trajectories = [{", 'trajectories = ["straight", {'), "mixes trajectory names"),
        (('trajectories = [{ kind = "step", amplitude = 1.0, name = "one" },\n'
          '                { kind = "step", amplitude = -0.5, at = 0.2, name = "back" }]',
          'trajectories = ["straight"]'), "tracking a trajectory needs a robot plant"),
        (('kind = "lti"', 'kind = "lti"\ngain = 3'), r"\[plant\]: unknown key\(s\) \['gain'\]"),
        (('kind = "lti"', 'kind = "pid"'), r"\[plant\]: kind='pid' must be one of"),
        (('name = "back"', 'name = "one"'), "name='one' repeats"),
        (('amplitude = 1.0', 'amplitude = "big"'), r"trajectories\[0\]: StepReference: "
                                                   "amplitude='big'"),
    ],
)
def test_sweep_plant_errors_name_the_file_and_table(tmp_path: Path, change, message) -> None:
    text = SWEEP.replace(*change)
    assert text != SWEEP
    with pytest.raises(ConfigError, match=message) as info:
        load_sweep_config(write(tmp_path, text))
    assert str(tmp_path / "c.toml") in str(info.value)


def test_references_need_a_single_input_plant(tmp_path: Path) -> None:
    text = SWEEP.replace(MOTOR, "")
    with pytest.raises(ConfigError, match=r"\[sweep\]: tracking a reference signal needs a "
                                          "single-input plant"):
        load_sweep_config(write(tmp_path, text))


def test_optimize_on_a_linear_plant(tmp_path: Path) -> None:
    text = """
    [optimize]
    objective = "IAE"
    train_seeds = 2
    holdout_seeds = { start = 100, count = 3 }
    noise_std = 0.01
    trajectories = [{ kind = "step", amplitude = 1.0 }]
    bounds = [0.0, 1.2]
    compare = [0.2]

    [optimize.symmetric]
    grid = 4
    maxiter = 4

    [optimize.asymmetric]
    enabled = false

    [controller]
    ke = 2.0
    kde = 10.0

    [simulation]
    duration = 0.6
    """ + MOTOR
    cfg = load_optimize_config(write(tmp_path, text))
    assert isinstance(cfg.config.plant, LinearSpec)
    result = run_optimization(cfg, progress=False)
    sym = result.symmetric
    # the grid's objective values are the library's own IAE, mean over the training seeds
    ctrl = FuzzyHeadingController(fls=heading_fls(sym["width"]), ke=2.0, kde=10.0)
    direct = simulate_metrics([ctrl], [StepReference()], run_grid(1, 1, [0.01], 2), cfg.config)
    assert sym["train_objective"] == pytest.approx(float(direct["IAE"].mean()), rel=1e-12)
    # the dead zone shrinks with the FoU: the optimum is not the type-1 FLC
    assert sym["width"] > 0.0


def test_study_accepts_robot_plants_only(tmp_path: Path) -> None:
    text = "[study]\nseeds = 2\n" + MOTOR
    with pytest.raises(ConfigError, match=r"\[plant\]: LoopConfig\.plant \('lti'\) has "
                                          "inputs"):
        load_study_config(write(tmp_path, text))
    kin = load_study_config(write(tmp_path, '[study]\nseeds = 2\n[plant]\nkind = "kinematic"\n',
                                  "k.toml"))
    assert kin.loop.plant is None and kin.loop == LoopConfig(robot=kin.loop.robot)


def _lag(t, x, u, params):
    return np.array([-2.0 * x[0] + u[0]])


def test_sweep_of_a_python_control_nlsys_from_the_api(tmp_path: Path) -> None:
    """A nonlinear python-control plant is code: a sweep takes it from Python, and its rows are
    the library's own numbers."""
    ct = pytest.importorskip("control", reason="python-control is not installed (PyPI: control)")
    from it2track.experiments.specs import ControllerKind, ControllerSpec
    from it2track.experiments.sweep import SweepPlan, TrajectoryRef
    from it2track.plant import RobotParams
    from it2track.plant.control import from_control

    lag = ct.nlsys(_lag, None, states=1, inputs=["u"], outputs=["y"], name="lag")
    config = LoopConfig(duration=0.4, ts=0.05, plant=from_control(lag))
    step = StepReference(amplitude=0.5)
    plan = SweepPlan(config=config, robots=(RobotParams(),), robot_columns={},
                     controllers=(ControllerSpec(kind=ControllerKind.IT2, fou=0.2),),
                     trajectory_refs=(TrajectoryRef("step", reference=step),),
                     noise_std=(0.0, 0.1), seeds=(0, 1))
    assert plan.normalised()["simulation"]["plant"]["kind"] == "nlsys"
    run_sweep(plan, tmp_path / "out", progress=False)
    header, body = read_results(tmp_path / "out" / "results.csv")
    ctrl = FuzzyHeadingController(fls=heading_fls(0.2))
    direct = simulate_metrics([ctrl], [step], run_grid(1, 1, [0.0, 0.1], 2), config)
    got = np.array([float(row[header.index("IAE")]) for row in body])
    np.testing.assert_array_equal(got, direct["IAE"])

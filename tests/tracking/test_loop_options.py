"""The loop's open modelling choices (DESIGN.md sec. 8): theta_d from the previous period's
pose, a start pose on the path, and an error-integral window after the initial transient.

Each is checked against the naive per-period ODE loop of ``test_loop_reference`` (which
implements the option from its definition) or against integrals computed independently from
the recorded time series."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_loop_reference import KD, KP, TF, reference_loop

from it2track.tracking import (
    ON_PATH,
    FunctionTrajectory,
    LoopConfig,
    PDHeadingController,
    PoseTiming,
    RunTable,
    curved,
    simulate,
    sinusoidal,
)
from it2track.tracking.libm import atan2


def _diagonal(t):
    """(t, t/2) from (1, 2): tangent heading atan2(0.5, 1)."""
    t = np.asarray(t, float)
    one = np.ones_like(t)
    return np.stack([1.0 + t, 2.0 + 0.5 * t, one, 0.5 * one], axis=-1)


def _run(traj, config):
    ctrl = PDHeadingController(kp=KP, kd=KD, tf=TF)
    return simulate([ctrl], [traj], RunTable(0, 0, 0.0, 0), config).run(0)


def test_previous_pose_timing_matches_the_naive_loop_and_differs_from_current():
    traj = sinusoidal()
    config = LoopConfig(duration=3.0, desired_heading_pose="previous")
    assert config.desired_heading_pose is PoseTiming.PREVIOUS
    got = _run(traj, config)
    ref = reference_loop(traj, config, previous_pose=True)
    for name, got_name in (("x", "x"), ("y", "y"), ("theta", "theta"), ("e", "e_true")):
        np.testing.assert_allclose(got[got_name], ref[name], rtol=0, atol=1e-8,
                                   err_msg=f"{got_name} with theta_d from the previous pose")
    # theta_d_k really uses the pose at t_(k-1) (and the start pose at k = 0) ...
    # (the loop's atan2 is tracking.libm's: the same bits in the numpy and compiled engines)
    expected = atan2(got["y_ref"][1:] - got["y"][:-1], got["x_ref"][1:] - got["x"][:-1])
    np.testing.assert_array_equal(got["theta_d"][1:], expected)
    # ... which changes the run.
    current = _run(traj, LoopConfig(duration=3.0))
    assert np.max(np.abs(current["u"] - got["u"])) > 1e-3


@pytest.mark.parametrize("traj", [curved(), FunctionTrajectory("diagonal", _diagonal)],
                         ids=["curved", "diagonal"])
def test_on_path_start_pose_is_the_reference_point_and_tangent(traj):
    config = LoopConfig(duration=2.0, start_pose=ON_PATH)
    got = _run(traj, config)
    x0, y0, vx, vy = traj.sample([0.0])[0]
    start = (x0, y0, math.atan2(vy, vx))
    assert (got["x"][0], got["y"][0], got["theta"][0]) == start
    ref = reference_loop(traj, config, start=start)
    for name in ("x", "y", "theta"):
        np.testing.assert_allclose(got[name], ref[name], rtol=0, atol=1e-8, err_msg=name)


def test_on_path_start_is_per_trajectory_in_one_batch():
    config = LoopConfig(duration=1.0, start_pose=ON_PATH)
    trajs = [curved(), FunctionTrajectory("diagonal", _diagonal)]
    ctrl = PDHeadingController(kp=KP, kd=KD, tf=TF)
    trace = simulate([ctrl], trajs, RunTable(0, [0, 1], 0.0, 0), config)
    assert trace["y"][0, 0] == -4.0 and trace["y"][1, 0] == 2.0
    assert trace["theta"][1, 0] == math.atan2(0.5, 1.0)


def test_metric_window_integrates_only_after_its_start():
    traj = curved()
    ts, start = 0.01, 2.0
    full = simulate([PDHeadingController(kp=KP, kd=KD, tf=TF)], [traj], RunTable(0, 0, 0.1, 3),
                    LoopConfig(duration=5.0))
    windowed = simulate([PDHeadingController(kp=KP, kd=KD, tf=TF)], [traj],
                        RunTable(0, 0, 0.1, 3), LoopConfig(duration=5.0, metric_start=start))
    # The window changes only the error integrals, not the run.
    np.testing.assert_array_equal(full["u"], windowed["u"])
    t = full.t
    k0 = round(start / ts)
    for metric, series in (("", "e_true"), ("_meas", "e_meas")):
        e = full[series][0, k0:]
        tt = t[k0:]
        expected = {"IAE": np.abs(e), "ITAE": tt * np.abs(e), "ISE": e * e, "ITSE": tt * e * e}
        for name, integrand in expected.items():
            value = float(np.trapezoid(integrand, tt))
            assert windowed.metrics[name + metric][0] == pytest.approx(value, rel=1e-12), name
            assert windowed.metrics[name + metric][0] < full.metrics[name + metric][0]
    for name in ("pos_rms", "effort", "u_tv", "sat_time"):
        assert windowed.metrics[name][0] == full.metrics[name][0]


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"metric_start": 10.0}, r"metric_start=10.0 must be a whole number of periods"),
        ({"metric_start": 0.005}, r"metric_start=0.005"),
        ({"metric_start": -1.0}, r"metric_start=-1.0"),
        ({"metric_start": math.nan}, r"metric_start=nan must be a finite number"),
        ({"start_pose": "on_the_path"}, r"start_pose='on_the_path' must be 3 finite numbers or"),
        ({"desired_heading_pose": "later"}, r"desired_heading_pose='later' must be one of"),
    ],
)
def test_bad_options_are_refused_with_their_value(kwargs, message):
    with pytest.raises(ValueError, match=message):
        LoopConfig(**kwargs)


def test_options_round_trip_through_to_dict():
    config = LoopConfig(start_pose=ON_PATH, desired_heading_pose=PoseTiming.PREVIOUS,
                        metric_start=2.0)
    d = config.to_dict()
    assert d["start_pose"] == "on_path" and d["desired_heading_pose"] == "previous"
    assert d["metric_start"] == 2.0


def test_options_are_read_from_a_study_config(tmp_path):
    from it2track.experiments.specs import ConfigError
    from it2track.experiments.study import load_study_config

    path = tmp_path / "study.toml"
    path.write_text('[simulation]\nstart_pose = "on_path"\ndesired_heading_pose = "previous"\n'
                    "metric_start = 2.0\n")
    loop = load_study_config(path).loop
    assert loop.start_pose == ON_PATH and loop.desired_heading_pose is PoseTiming.PREVIOUS
    assert loop.metric_start == 2.0
    path.write_text('[simulation]\nstart_pose = "somewhere"\n')
    with pytest.raises(ConfigError, match=r"study.toml \[simulation\]: start_pose='somewhere'"):
        load_study_config(path)

"""Software in the loop: the compiled C controller in the closed loop reproduces the Python
controller's metrics (double to 1e-9 relative; float: the measured difference is stated)."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from codegen_helpers import skip_without

import it2track
from it2track.codegen import RealType
from it2track.codegen.controller import CHeadingController
from it2track.fuzzy import EIASC, ZeroFiringError
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    get_trajectory,
    run_grid,
    simulate_metrics,
)


@pytest.fixture(scope="module")
def build_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("c-builds")

TRAJECTORIES = ("straight", "curved", "sinusoidal")


@pytest.fixture(scope="module")
def loop_metrics(build_dir):
    """The paper's runs (3 paths; noise-free and noisy, 4 seeds) with FoU 0.2 and the type-1
    FLC, each as Python, C double and C float controllers."""
    skip_without("gcc")
    controllers = []
    for fou in (0.2, 0.0):
        fls = it2track.heading_fls(fou)
        controllers.append(FuzzyHeadingController(fls=fls))
        for real in (RealType.DOUBLE, RealType.FLOAT):  # indices below assume this order
            controllers.append(CHeadingController.from_system(
                fls, real=real, build_dir=str(build_dir)))
    trajectories = [get_trajectory(name) for name in TRAJECTORIES]
    runs = run_grid(len(controllers), len(trajectories), [0.0, 0.05], 4)
    metrics = simulate_metrics(controllers, trajectories, runs, LoopConfig())
    return runs, metrics


def _pairs(runs, metrics, python_index, c_index):
    a = runs.controller == python_index
    b = runs.controller == c_index
    return {name: (value[a], value[b]) for name, value in metrics.items()}


@pytest.mark.parametrize("python_index, c_index", [(0, 1), (3, 4)], ids=["fou0.2", "fou0"])
def test_c_double_reproduces_the_python_metrics(loop_metrics, python_index, c_index):
    runs, metrics = loop_metrics
    for name, (py, c) in _pairs(runs, metrics, python_index, c_index).items():
        np.testing.assert_allclose(c, py, rtol=1e-9, atol=1e-12, err_msg=name)


@pytest.mark.parametrize("python_index, c_index", [(0, 2), (3, 5)], ids=["fou0.2", "fou0"])
def test_c_float_metrics_stay_close(loop_metrics, python_index, c_index):
    """Measured on these 24 runs per controller: the float controller's integral errors, RMS
    position error and effort differ from the Python (double) controller's by at most 2e-6
    relative (README states it); 2e-5 guards against regressions."""
    runs, metrics = loop_metrics
    for name in ("IAE", "ITAE", "ISE", "ITSE", "pos_rms", "effort"):
        py, c = _pairs(runs, metrics, python_index, c_index)[name]
        np.testing.assert_allclose(c, py, rtol=2e-5, err_msg=name)
        assert not np.array_equal(c, py), "float arithmetic must show some difference"


def test_controller_pickles_and_rebuilds(build_dir):
    skip_without("gcc")
    ctrl = CHeadingController.from_system(it2track.heading_fls(0.3, reducer=EIASC),
                                          ke=0.8, build_dir=str(build_dir))
    e, de = np.array([0.3, -2.0]), np.array([0.05, 0.4])
    u = ctrl.output(e, de, ctrl.initial_state(2, 0.01))
    again = pickle.loads(pickle.dumps(ctrl))
    np.testing.assert_array_equal(again.output(e, de, again.initial_state(2, 0.01)), u)
    ref = FuzzyHeadingController(fls=it2track.heading_fls(0.3), ke=0.8)
    np.testing.assert_allclose(u, ref.output(e, de, ref.initial_state(2, 0.01)), atol=1e-12)


def test_error_status_raises_like_python(build_dir):
    skip_without("gcc")
    from it2track.fuzzy import Input, IT2Set, IT2Sugeno, Rule
    n = IT2Set.triangle([-1, -1, -0.1], [-1, -1, -0.5], "N")
    p = IT2Set.triangle([0.1, 1, 1], [0.5, 1, 1], "P")
    gap = IT2Sugeno(inputs=[Input("e", (-1, 1), [n, p]), Input("de", (-1, 1), [n, p])],
                    rules=[Rule(["N", None], -2.0), Rule(["P", None], 2.0)])
    ctrl = CHeadingController.from_system(gap, build_dir=str(build_dir))
    with pytest.raises(ZeroFiringError, match="no rule fires"):
        ctrl.output(np.array([0.5, 0.0]), np.array([0.0, 0.0]), np.zeros((0, 2)))
    with pytest.raises(ValueError, match="NaN or inf"):
        ctrl.output(np.array([np.nan]), np.array([0.0]), np.zeros((0, 1)))
    with pytest.raises(ValueError, match="2 inputs"):
        CHeadingController.from_system(
            IT2Sugeno(inputs=[Input("e", (-1, 1), [n, p])], rules=[Rule(["N"], 1.0)]))

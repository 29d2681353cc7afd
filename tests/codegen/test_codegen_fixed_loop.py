"""The q15 controller in the closed loop (the compiled C through ctypes): at every step of the
paper's runs -- three paths, noise-free and noisy -- its output is within the derived bound of
the double controller at the same inputs, and the runs' metrics differ from the double loop's
by less than a constant output error of the bound's size changes them (the bound's consequence
for the loop: a per-step error within the bound, whatever its pattern, measured against the
most damaging simple pattern, a bias)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pytest
from codegen_helpers import skip_without

import it2track
from it2track.codegen import RealType
from it2track.codegen.controller import CHeadingController
from it2track.codegen.errorbound import fixed_error_bound
from it2track.codegen.fixedpoint import fixed_plan
from it2track.tracking import (
    FuzzyHeadingController,
    HeadingController,
    LoopConfig,
    get_trajectory,
    run_grid,
    simulate_metrics,
)

TRAJECTORIES = ("straight", "curved", "sinusoidal")
METRICS = ("IAE", "ITAE", "ISE", "ITSE", "pos_rms", "effort")


@dataclass(frozen=True, kw_only=True, eq=False)
class Checked(HeadingController):
    """The C controller, and at every step its error against the double system and the
    bound there (kept in ``ratios``)."""

    c: CHeadingController
    plan: object
    name: str = "checked q15"
    ratios: list[float] = field(default_factory=list)

    def output(self, e, de, state):
        u = self.c.output(e, de, state)
        x = np.stack([e, de], axis=-1)
        fls = self.c_system
        ref = fls(np.clip(x[:, 0], -1, 1), np.clip(x[:, 1], -1, 1))
        bound = fixed_error_bound(fls, self.c.code.fixed, x, plan=self.plan).u
        self.ratios.append(float(np.max(np.abs(u - ref) / bound)))
        return u

    @property
    def c_system(self):
        return it2track.heading_fls(0.2)


@dataclass(frozen=True, kw_only=True, eq=False)
class Biased(HeadingController):
    """The double controller with a constant output error."""

    inner: FuzzyHeadingController
    bias: float
    name: str = "biased"

    def output(self, e, de, state):
        return self.inner.output(e, de, state) + self.bias


@pytest.fixture(scope="module")
def loop(tmp_path_factory):
    skip_without("gcc")
    build = str(tmp_path_factory.mktemp("c-builds"))
    fls = it2track.heading_fls(0.2)
    py = FuzzyHeadingController(fls=fls)
    checked = Checked(c=CHeadingController.from_system(fls, real=RealType.Q15,
                                                       build_dir=build),
                      plan=fixed_plan(fls, "exhaustive"))
    # the bound's largest value over the square at real inputs (input rounding included)
    axis = np.linspace(-1, 1, 201)
    sq = np.stack(np.meshgrid(axis, axis, indexing="ij"), -1).reshape(-1, 2)
    big = float(fixed_error_bound(fls, checked.c.code.fixed, sq).u.max())
    controllers = [py, checked, Biased(inner=py, bias=big), Biased(inner=py, bias=-big)]
    runs = run_grid(len(controllers), len(TRAJECTORIES), [0.0, 0.05], 4)
    metrics = simulate_metrics(controllers, [get_trajectory(t) for t in TRAJECTORIES], runs,
                               LoopConfig())
    return runs, metrics, checked, big


def test_every_step_is_within_the_bound(loop):
    _, _, checked, big = loop
    assert len(checked.ratios) >= 1000
    assert max(checked.ratios) <= 1.0
    assert 2e-4 < big < 3e-3


def test_metrics_differ_less_than_a_bias_of_the_bounds_size(loop):
    runs, metrics, _, _ = loop
    pick = {k: runs.controller == k for k in range(4)}
    for name in METRICS:
        py, fixed, up, down = (metrics[name][pick[k]] for k in range(4))
        envelope = np.maximum(np.abs(up - py), np.abs(down - py))
        diff = np.abs(fixed - py)
        assert np.all(diff <= envelope), (name, diff.max(), envelope.min())
        assert not np.array_equal(fixed, py), "fixed point must show some difference"


def test_q15_controller_names_and_pickles(tmp_path):
    skip_without("gcc")
    import pickle
    ctrl = CHeadingController.from_system(it2track.heading_fls(0.2), real=RealType.Q15,
                                          build_dir=str(tmp_path))
    assert ctrl.name == "C it2 (q15)"
    e, de = np.array([0.3, -2.0, 0.05]), np.array([0.05, 0.4, -0.3])
    u = ctrl.output(e, de, ctrl.initial_state(3, 0.01))
    again = pickle.loads(pickle.dumps(ctrl))
    np.testing.assert_array_equal(again.output(e, de, again.initial_state(3, 0.01)), u)
    # outputs are on the Q11 grid
    np.testing.assert_array_equal(u * 2048, np.round(u * 2048))
    with pytest.raises(ValueError, match="NaN"):
        ctrl.output(np.array([np.nan]), np.array([0.0]), np.zeros((0, 1)))

"""The output-gain choice (docs/model.md#output-gain): an output gain g on the fuzzy
controllers is the loop gain of a half-track l / g -- exactly while no wheel voltage saturates,
and not otherwise (the voltage limit acts on V0 +- g u, not on V0 +- u)."""

from dataclasses import replace

import numpy as np
import pytest

from it2track.experiments.choices import DEFAULT_CHOICES, apply_settings
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.tracking import LoopConfig, get_trajectory, run_grid, simulate_metrics

TRAJ = [get_trajectory(t) for t in ("straight", "curved", "sinusoidal")]


@pytest.mark.parametrize(("gain", "half_track"), [(0.5, 11.2), (2.0, 2.8)])
@pytest.mark.parametrize(("kind", "fou"), [(ControllerKind.FLC, 0.0), (ControllerKind.IT2, 0.2)])
def test_output_gain_equals_the_scaled_half_track_until_a_wheel_saturates(gain, half_track,
                                                                         kind, fou):
    base = LoopConfig()
    runs = run_grid(1, 3, [0.0, 0.05, 0.2], 6)
    scaled = simulate_metrics([ControllerSpec(kind=kind, fou=fou, output_gain=gain).build()],
                              TRAJ, runs, base)
    wide = simulate_metrics([ControllerSpec(kind=kind, fou=fou).build()], TRAJ, runs,
                            replace(base, robot=replace(base.robot, half_track=half_track)))
    free = (scaled["sat_time"] == 0.0) & (wide["sat_time"] == 0.0)
    saturated = ~free
    assert free.sum() >= 5 and saturated.sum() >= 5  # both regimes are exercised
    for m in ("IAE", "ITAE", "ISE", "ITSE", "pos_rms"):
        np.testing.assert_allclose(scaled[m][free], wide[m][free], rtol=1e-9, err_msg=m)
    # Where a wheel saturates, the two loops differ by far more than rounding.
    rel = np.abs(scaled["ISE"] - wide["ISE"]) / np.maximum(wide["ISE"], 1e-12)
    assert rel[saturated].max() > 1e-3


def test_the_output_gain_choice_scales_every_untuned_fuzzy_controller():
    choice = next(c for c in DEFAULT_CHOICES if c.name == "output_gain")
    assert choice.default == (1.0,) and choice.alternatives == ((0.5,), (2.0,))
    v = apply_settings(LoopConfig(), (0.05,), choice.settings((2.0,)), choice="output_gain",
                       value="2")
    assert v.output_gain == 2.0 and v.loop == LoopConfig() and v.label == "output gain 2"
    base = ControllerSpec(kind=ControllerKind.IT2, fou=0.2).build()
    doubled = ControllerSpec(kind=ControllerKind.IT2, fou=0.2, output_gain=2.0).build()
    e = np.linspace(-1.0, 1.0, 9)
    state = base.initial_state(e.size, 0.01)
    np.testing.assert_allclose(doubled.output(e, e[::-1], state),
                               2.0 * base.output(e, e[::-1], state), rtol=1e-12)

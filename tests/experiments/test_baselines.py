"""Fair baselines: the slope-matched type-1 FLC, scaled consequents and the fuzzy tuning."""

from dataclasses import replace

import numpy as np
import pytest

from it2track.experiments.baselines import (
    FuzzyTuning,
    edge_slope,
    scaled_consequents,
    slope_matched_fls,
)
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.paper import dead_zone_matched_fls, heading_fls


@pytest.mark.parametrize("w", [0.1, 0.2, 0.3, 0.4])
def test_slope_matched_flc_has_the_it2flcs_dead_zone_and_edge_slope(w):
    it2, t1 = heading_fls(w), slope_matched_fls(w)
    d = 0.2 - w / 2
    inside = np.linspace(-d, d, 41)
    # The dead zone along both input axes (and the whole square inside it).
    assert np.all(t1(inside, 0 * inside) == 0.0) and np.all(t1(0 * inside, inside) == 0.0)
    ee, dd = np.meshgrid(inside, inside)
    assert np.all(t1(ee, dd) == 0.0)
    # Just outside: the same first-order growth as the IT2FLC, on either axis and side.
    for h in (1e-4, 1e-5):
        for sign in (1.0, -1.0):
            e = sign * (d + h)
            assert float(t1(e, 0.0)) == pytest.approx(float(it2(e, 0.0)), rel=2e-3)
            assert float(t1(0.0, e)) == pytest.approx(float(it2(0.0, e)), rel=2e-3)
    assert edge_slope(t1, d) == pytest.approx(edge_slope(it2, d), rel=1e-8)
    # Large errors: the FLC's and the IT2FLC's output once Z no longer fires.
    big = np.array([min(0.8 + w / 2, 1.0), 1.0])
    assert np.allclose(t1(big, 0 * big), it2(big, 0 * big))


def test_the_dead_zone_matched_flc_is_about_twice_as_steep():
    # The reason for the slope-matched baseline (issue: u(0.15, 0) = 0.50 V vs 0.26 V).
    assert float(dead_zone_matched_fls(0.2)(0.15, 0.0)) == pytest.approx(0.5, abs=1e-12)
    assert float(heading_fls(0.2)(0.15, 0.0)) == pytest.approx(0.2642, abs=1e-4)
    assert float(slope_matched_fls(0.2)(0.15, 0.0)) == pytest.approx(0.2673, abs=1e-4)
    # Edge slope of the IT2FLC(0.2): 140/27 V/rad (exact rational output near the edge).
    assert edge_slope(heading_fls(0.2), 0.1) == pytest.approx(140 / 27, rel=1e-9)


def test_slope_matched_needs_a_dead_zone():
    with pytest.raises(ValueError, match=r"0 < fou <= 0\.4"):
        slope_matched_fls(0.5)
    with pytest.raises(ValueError, match="t1-slope-matched"):
        ControllerSpec(kind=ControllerKind.T1_SLOPE_MATCHED, fou=0.0)


@pytest.mark.parametrize("fls", [heading_fls(0.2), heading_fls(0.0), slope_matched_fls(0.3)])
def test_scaled_consequents_scale_the_output_exactly(fls):
    rng = np.random.default_rng(3)
    e, de = rng.uniform(-1.2, 1.2, (2, 2000))
    for gain in (0.5, 2.0, 3.7):
        scaled = scaled_consequents(fls, gain)
        assert type(scaled) is type(fls)
        np.testing.assert_allclose(scaled(e, de), gain * fls(e, de), rtol=1e-12, atol=1e-12)
    assert scaled_consequents(fls, 1.0) is fls
    with pytest.raises(ValueError, match="output gain"):
        scaled_consequents(fls, 0.0)


def test_output_gain_builds_a_scaled_system_not_a_controller_parameter():
    spec = ControllerSpec(kind=ControllerKind.IT2, fou=0.2, ke=2.0, output_gain=0.5)
    assert spec.label == "IT2FLC FoU 0.2 Ke 2 Kde 1 G 0.5"
    ctrl = spec.build()
    assert (ctrl.ke, ctrl.kde) == (2.0, 1.0)
    assert float(ctrl.fls(0.5, 0.1)) == pytest.approx(0.5 * float(heading_fls(0.2)(0.5, 0.1)))
    assert spec.to_dict()["output_gain"] == 0.5
    assert "output_gain" not in ControllerSpec(kind=ControllerKind.FLC).to_dict()
    with pytest.raises(ValueError, match=r"output_gain=2\.0 does not apply to kind 'pd'"):
        ControllerSpec(kind=ControllerKind.PD, kp=1.0, output_gain=2.0)


def test_fuzzy_tuning_has_the_pd_budget():
    from it2track.experiments.study import PDTuning

    pd = PDTuning()
    assert len(FuzzyTuning().candidates) == len(pd.kp_grid) * len(pd.kd_grid) == 165
    with pytest.raises(ValueError, match="controllers"):
        FuzzyTuning(controllers=("pd",))
    with pytest.raises(ValueError, match="ke_grid"):
        FuzzyTuning(ke_grid=(0.0, 1.0))


def test_tuned_fuzzy_controllers_obey_the_pds_effort_limit():
    from it2track.experiments.study import PDTuning, StudyConfig, tune_fuzzy, tune_pd
    from it2track.tracking import LoopConfig

    cfg = replace(StudyConfig(), loop=LoopConfig(duration=2.0), fous=(0.2,), main_fou=0.2,
                  pd=PDTuning(seeds=2, kp_grid=(2.0, 20.0), kd_grid=(0.0,)),
                  tuning=FuzzyTuning(ke_grid=(1.0, 4.0), kde_grid=(0.0, 1.0),
                                     gain_grid=(0.5, 2.0)), robustness=None)
    _, pd_rec = tune_pd(cfg)
    tuned, records = tune_fuzzy(cfg, pd_rec)
    assert set(tuned) == {"FLC", "IT2FLC FoU 0.2"}
    for label, rec in records.items():
        assert rec["effort_limit"] == pd_rec["effort_limit"]
        feasible = [g for g in rec["grid"] if g[4] <= rec["effort_limit"]]
        best = min(feasible, key=lambda g: g[3])
        assert (rec["ke"], rec["kde"], rec["gain"]) == tuple(best[:3])
        spec = tuned[label]
        assert spec.label == f"{label} (tuned)"
        assert (spec.ke, spec.kde, spec.output_gain) == tuple(best[:3])
        assert rec["untuned"]["effort"] == pd_rec["fuzzy_effort"][label]
        assert any(g[4] > rec["effort_limit"] for g in rec["grid"]), "limit binds nowhere"


def test_scaled_consequents_refuses_non_zero_order_consequents():
    from it2track.fuzzy import Input, Linear, Rule, T1Sugeno, Triangle

    fls = T1Sugeno(inputs=[Input("x", (-1, 1), [("A", Triangle(-1, 0, 1))])],
                   rules=[Rule(["A"], Linear([1.0]))])
    with pytest.raises(ValueError, match="not a zero-order Sugeno consequent"):
        scaled_consequents(fls, 2.0)

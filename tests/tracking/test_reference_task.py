"""The reference-tracking task (tracking/siso.py): a single-input plant following r(t).

Reference values are closed forms of a P-controlled first-order discrete plant, the noise
generator's own rows, and sums written out here.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from it2track.paper import heading_fls
from it2track.plant import held_sample_index, standard_noise
from it2track.plant.linear import LinearSpec
from it2track.tracking import (
    METRIC_NAMES,
    REFERENCE_FIELDS,
    FunctionReference,
    FuzzyHeadingController,
    IncrementalController,
    LoopConfig,
    PDHeadingController,
    RunTable,
    StepReference,
    get_trajectory,
    reference_from_dict,
    run_grid,
    simulate,
    simulate_metrics,
)

#: x+ = 0.9 x + 0.1 u, y = x, discrete at the loop's period.
LAG = LinearSpec(a=[[0.9]], b=[[0.1]], c=[[1.0]], dt=True, output_names=["level"])
P2 = PDHeadingController(kp=2.0, kd=0.0, tf=0.0, u_max=100.0)
CFG = LoopConfig(duration=1.0, ts=0.05, noise_rate=20.0, plant=LAG)


def test_p_control_of_a_first_order_plant_closed_form() -> None:
    """x_(k+1) = 0.9 x + 0.1 * 2 (r - x) = 0.7 x + 0.2 r, x_0 = 0: x_k = (2/3) r (1 - 0.7^k)."""
    r = 3.0
    trace = simulate([P2], [StepReference(amplitude=r)], RunTable(0, 0, 0.0, 0), CFG)
    k = np.arange(21)
    y = (2 / 3) * r * (1 - 0.7**k)
    np.testing.assert_allclose(trace["y"][0], y, rtol=0, atol=1e-14)
    np.testing.assert_allclose(trace["y.level"][0], y, rtol=0, atol=1e-14)
    np.testing.assert_allclose(trace["u"][0], 2 * (r - y), rtol=0, atol=1e-13)
    assert trace["u_applied"][0].tolist() == trace["u"][0].tolist()  # unbounded input
    e = r - y
    np.testing.assert_allclose(trace["e_true"][0], e, atol=1e-14)
    assert trace["de"][0, 0] == 0.0
    np.testing.assert_allclose(trace["de"][0, 1:], np.diff(trace["e_meas"][0]), atol=0)
    ts = 0.05
    iae = ts * (np.abs(e).sum() - 0.5 * (abs(e[0]) + abs(e[-1])))
    itse = ts * ((k * ts * e * e).sum() - 0.5 * (k[-1] * ts * e[-1] ** 2))
    m = trace.metrics
    assert m["IAE"][0] == pytest.approx(iae, rel=1e-13)
    assert m["ITSE"][0] == pytest.approx(itse, rel=1e-13)
    assert m["pos_final"][0] == pytest.approx(r / 3 + (2 / 3) * r * 0.7**20, rel=1e-12)
    assert m["pos_max"][0] == r  # at t = 0
    assert m["pos_rms"][0] == pytest.approx(np.sqrt((e * e).mean()), rel=1e-13)
    assert m["sat_time"][0] == 0.0
    assert set(trace.series) == {*REFERENCE_FIELDS, "y.level"}
    assert set(m) == set(METRIC_NAMES)


def test_noise_is_the_generator_row_held_at_the_noise_rate() -> None:
    sigma, seed = 0.3, 4
    cfg = dataclasses.replace(CFG, seed=11)
    trace = simulate([P2], [StepReference()], RunTable(0, 0, sigma, seed), cfg)
    hold = held_sample_index(cfg.times, cfg.noise_rate)
    z = standard_noise(11, [seed], int(hold[-1]) + 1)[0]
    np.testing.assert_array_equal(trace["y_meas"][0], trace["y"][0] + (sigma * z)[hold])
    np.testing.assert_allclose(trace["e_meas"][0], 1.0 - trace["y_meas"][0], atol=0)


def test_common_random_numbers_and_batch_independence() -> None:
    ctrls = [P2, PDHeadingController(kp=1.0, kd=0.1, tf=0.01, u_max=100.0)]
    refs = [StepReference(amplitude=1.0), StepReference(amplitude=-2.0, at=0.3, name="late")]
    runs = run_grid(2, 2, [0.0, 0.2], [0, 5])
    trace = simulate(ctrls, refs, runs, CFG)
    noise = trace["y_meas"] - trace["y"]
    for i in range(len(runs)):  # same seed index -> the same standard row, scaled
        for j in range(len(runs)):
            if runs.seed[i] == runs.seed[j] and runs.noise_std[i] == runs.noise_std[j]:
                np.testing.assert_allclose(noise[i], noise[j], rtol=0, atol=1e-15)
    assert np.abs(noise[runs.noise_std == 0.2]).min() > 0.0
    a = simulate_metrics(ctrls, refs, runs, CFG, batch_size=1)
    b = simulate_metrics(ctrls, refs, runs, CFG, batch_size=5)
    for name in METRIC_NAMES:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)
        np.testing.assert_array_equal(a[name], trace.metrics[name], err_msg=name)
    late = trace["r"][runs.trajectory == 1][0]
    assert late[5] == 0.0 and late[6] == -2.0  # steps at t = 0.3 = 6 ts


def test_asymmetric_input_limits_saturate_and_count() -> None:
    """A tank's inflow cannot be negative: u in [0, 1]; sat_time counts the periods k < N in
    which the requested input lay outside, u_applied is the clipped one."""
    tank = dataclasses.replace(LAG, input_limits=((0.0, 1.0),))
    cfg = dataclasses.replace(CFG, plant=tank)
    ref = FunctionReference("up-down", lambda t: np.where(t < 0.5, 2.0, 0.0))
    trace = simulate([P2], [ref], RunTable(0, 0, 0.0, 0), cfg)
    u, applied = trace["u"][0], trace["u_applied"][0]
    np.testing.assert_array_equal(applied, np.clip(u, 0.0, 1.0))
    outside = (u[:-1] < 0.0) | (u[:-1] > 1.0)
    assert outside.any() and (u[:-1] < 0.0).any() and (u[:-1] > 1.0).any()
    assert trace.metrics["sat_time"][0] == pytest.approx(outside.sum() * 0.05, rel=1e-15)
    x = 0.0  # the plant driven by the clipped input, written out
    for k in range(20):
        assert trace["y"][0, k] == pytest.approx(x, abs=1e-15)
        x = 0.9 * x + 0.1 * applied[k]


def test_incremental_fuzzy_controller_removes_the_steady_state_error() -> None:
    """The P controller leaves r/3 (closed form above); the fuzzy PI (incremental) drives the
    error into the FLC's dead zone |ke e| < 0.2 - w/2 and holds it there."""
    cfg = dataclasses.replace(CFG, duration=20.0)
    flc = FuzzyHeadingController(fls=heading_fls(0.2), ke=1.0, kde=1.0)
    pi = IncrementalController(inner=flc, gain=0.01, u_min=-50.0, u_max=50.0)
    m = simulate_metrics([P2, pi], [StepReference(amplitude=3.0)], run_grid(2, 1, [0.0], 1), cfg)
    assert m["pos_final"][0] == pytest.approx(1.0, rel=1e-9)
    assert m["pos_final"][1] < 0.1  # inside the dead zone 0.2 - 0.2/2 = 0.1


def test_incremental_controller_validation_and_state() -> None:
    inner = PDHeadingController(kp=1.0, kd=0.0, tf=0.0)
    for kwargs, message in (({"u_min": 1.0, "u_max": 1.0}, "u_min=1.0 must be < u_max"),
                            ({"u0": 20.0}, r"u0=20.0 must lie in"),
                            ({"gain": float("inf")}, "gain=inf must be a finite number")):
        with pytest.raises(ValueError, match=message):
            IncrementalController(inner=inner, **kwargs)
    with pytest.raises(ValueError, match="inner=3 must be a HeadingController"):
        IncrementalController(inner=3)  # type: ignore[arg-type]
    pi = IncrementalController(inner=PDHeadingController(kp=1.0, kd=1.0, tf=0.0), u0=0.5,
                               gain=2.0)
    assert pi.name == "PI(PD)"
    state = pi.initial_state(2, 0.1)
    assert state.shape == (3, 2) and state[0].tolist() == [0.5, 0.5]
    u = pi.output(np.array([1.0, -1.0]), np.array([0.1, 0.0]), state)
    # inner PD: kp e + kd de / ts = [1 + 1, -1]; u = 0.5 + 2 * that
    np.testing.assert_allclose(u, [4.5, -1.5], rtol=1e-15)
    u[0] = 99.0  # the returned array is the caller's; the state is not aliased
    assert state[0, 0] == 4.5


def test_tasks_refuse_plants_that_do_not_fit() -> None:
    step = [StepReference()]
    with pytest.raises(ValueError, match=r"needs a single-input plant: LoopConfig\.plant is None"):
        simulate([P2], step, RunTable(0, 0, 0.0, 0), LoopConfig(duration=0.1))
    two = LinearSpec(a=[[-1.0]], b=[[1.0, 1.0]], c=[[1.0]])
    with pytest.raises(ValueError, match=r"has 2 inputs \('u\[0\]', 'u\[1\]'\); a reference"):
        simulate([P2], step, RunTable(0, 0, 0.0, 0), LoopConfig(duration=0.1, plant=two))
    with pytest.raises(ValueError, match="tracking a trajectory needs a robot plant"):
        simulate([P2], [get_trajectory("straight")], RunTable(0, 0, 0.0, 0), CFG)
    with pytest.raises(ValueError, match="cannot be mixed"):
        simulate([P2], [get_trajectory("straight"), StepReference()], RunTable(0, 0, 0.0, 0),
                 CFG)
    with pytest.raises(ValueError, match="returned shape"):
        simulate([P2], [FunctionReference("bad", lambda t: np.zeros((t.size, 2)))],
                 RunTable(0, 0, 0.0, 0), CFG)
    with pytest.raises(ValueError, match="returned NaN"):
        simulate([P2], [FunctionReference("nan", lambda t: t * np.nan)],
                 RunTable(0, 0, 0.0, 0), CFG)


def test_step_reference_and_its_table() -> None:
    step = StepReference(amplitude=2.0, at=0.5, initial=-1.0, name="s")
    assert step.sample([0.0, 0.4999, 0.5, 7.0]).tolist() == [-1.0, -1.0, 2.0, 2.0]
    assert reference_from_dict(step.to_dict()) == step
    with pytest.raises(ValueError, match=r"ref\[0\]: kind='ramp' must be 'step'"):
        reference_from_dict({"kind": "ramp"}, "ref[0]")
    with pytest.raises(ValueError, match=r"unknown key\(s\) \['height'\]"):
        reference_from_dict({"kind": "step", "height": 1.0})
    with pytest.raises(ValueError, match="amplitude='1' must be a finite number"):
        reference_from_dict({"kind": "step", "amplitude": "1"})
    with pytest.raises(ValueError, match="at=nan"):
        StepReference(at=float("nan"))

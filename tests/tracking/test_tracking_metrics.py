"""Tracking metrics against closed forms and hand-made cases."""

from __future__ import annotations

import numpy as np
import pytest

from it2track.plant import MotorParams
from it2track.tracking import (
    METRIC_NAMES,
    LoopConfig,
    MetricAccumulator,
    PDHeadingController,
    RunTable,
    integral_errors,
    simulate,
    straight,
)

TS = 0.01


def _grid(duration: float) -> np.ndarray:
    return np.arange(round(duration / TS) + 1) * TS


@pytest.mark.parametrize("e0", [0.5, -0.3, 2.0])
@pytest.mark.parametrize("duration", [10.0, 3.0])
def test_constant_error_closed_forms(e0, duration):
    # Constant |e| and t|e| are polynomials of degree <= 1: the trapezoid rule is exact.
    t = _grid(duration)
    m = integral_errors(np.full(t.size, e0), TS)
    exact = {
        "IAE": abs(e0) * duration,
        "ITAE": abs(e0) * duration**2 / 2,
        "ISE": e0**2 * duration,
        "ITSE": e0**2 * duration**2 / 2,
    }
    for name, value in exact.items():
        assert m[name] == pytest.approx(value, rel=1e-12), f"e0={e0}, T={duration}: {name}"


@pytest.mark.parametrize("a", [0.2, -1.5])
def test_linear_error_closed_forms(a):
    """e = a t on [0, T]: |e| is linear (IAE exact); t|e|, e^2 are quadratic and t e^2 cubic.

    For a polynomial f of degree <= 3 the trapezoid rule is off by exactly
    (h^2 / 12) (f'(T) - f'(0)) (Euler-Maclaurin; the next term needs f'''' != 0), so
    the expected sums are the integrals plus that correction.
    """
    T, h = 10.0, TS
    t = _grid(T)
    m = integral_errors(a * t, h)
    b = abs(a)
    corr = h**2 / 12.0
    expected = {
        "IAE": b * T**2 / 2,  # exact
        "ITAE": b * T**3 / 3 + corr * (2 * b * T),  # f = |a| t^2, f' = 2|a| t
        "ISE": a**2 * T**3 / 3 + corr * (2 * a**2 * T),  # f = a^2 t^2
        "ITSE": a**2 * T**4 / 4 + corr * (3 * a**2 * T**2),  # f = a^2 t^3
    }
    for name, value in expected.items():
        assert m[name] == pytest.approx(value, rel=1e-12), f"a={a}: {name}"
    # and the correction matters: without it ITAE would be off by far more than rounding
    assert m["ITAE"] != pytest.approx(b * T**3 / 3, rel=1e-9)


def test_sign_change_off_grid_is_not_exact():
    # |e| has a kink where e changes sign; the trapezoid rule is exact only if the kink is on
    # a sample. e = t - 0.005 on [0, 1] changes sign between samples 0 and 1.
    t = _grid(1.0)
    exact_iae = 0.005**2 / 2 + 0.995**2 / 2
    on_grid = integral_errors(t - 0.5, TS)["IAE"]
    off_grid = integral_errors(t - 0.005, TS)["IAE"]
    assert on_grid == pytest.approx(0.25, rel=1e-12)
    # First panel: trapezoid 0.01 * 0.005 against two triangles of 0.005^2 / 2.
    assert off_grid == pytest.approx(exact_iae + 0.005**2, rel=1e-12)
    assert off_grid != pytest.approx(exact_iae, rel=1e-6)


def test_integral_errors_batch_shape():
    t = _grid(1.0)
    e = np.stack([np.full(t.size, 0.5), t, -t]).reshape(3, 1, t.size) * np.ones((3, 2, 1))
    m = integral_errors(e, TS)
    for name in ("IAE", "ITAE", "ISE", "ITSE"):
        assert m[name].shape == (3, 2), name
        assert np.array_equal(m[name][1], m[name][2]), f"{name}: sign of e matters"
    assert m["IAE"][0, 0] == pytest.approx(0.5)


def _feed(acc: MetricAccumulator, k: int, **over: np.ndarray) -> None:
    n = acc.n
    kw = dict(
        e_true=np.zeros(n), e_meas=np.zeros(n), distance=np.zeros(n), u=np.zeros(n),
        v_requested=(np.zeros(n), np.zeros(n)),
    )  # fmt: skip
    kw.update(over)
    acc.update(k, **kw)


def test_accumulator_rejects_out_of_order_and_incomplete():
    acc = MetricAccumulator(2, TS, 3, 12.0)
    with pytest.raises(RuntimeError, match="out of order"):
        _feed(acc, 1)
    _feed(acc, 0)
    with pytest.raises(RuntimeError, match="out of order"):
        _feed(acc, 0)
    with pytest.raises(RuntimeError, match="incomplete"):
        acc.result()


def test_accumulator_hand_made_case():
    # 2 runs, N = 3 (samples k = 0..3), ts = 0.5 s.
    ts, n_steps = 0.5, 3
    acc = MetricAccumulator(2, ts, n_steps, 12.0)
    dist = [np.array([3.0, 1.0]), np.array([4.0, 1.0]), np.array([0.0, 1.0]),
            np.array([1.0, 2.0])]  # fmt: skip
    u = [np.array([0.0, 2.0]), np.array([1.0, 2.0]), np.array([-1.0, 2.0]),
         np.array([0.0, 2.0])]  # fmt: skip
    # requested voltages: run 0 beyond the limit at k = 1 (right) and k = 2 (left, exactly
    # -12 is not beyond); k = 3 is not a control period, so its 50 V does not count.
    vr = [np.array([1.0, 0.0]), np.array([12.5, 0.0]), np.array([0.0, 0.0]),
          np.array([50.0, 0.0])]  # fmt: skip
    vl = [np.array([1.0, 0.0]), np.array([0.0, 0.0]), np.array([-12.0, -13.0]),
          np.array([0.0, 0.0])]  # fmt: skip
    e = [np.array([0.1, -0.2])] * 4
    for k in range(n_steps + 1):
        _feed(acc, k, distance=dist[k], u=u[k], v_requested=(vr[k], vl[k]), e_true=e[k],
              e_meas=2.0 * e[k])  # fmt: skip
    m = acc.result()
    assert set(m) == set(METRIC_NAMES)
    assert m["pos_rms"] == pytest.approx([np.sqrt((9 + 16 + 0 + 1) / 4), np.sqrt(7 / 4)])
    assert np.array_equal(m["pos_max"], [4.0, 2.0])
    assert np.array_equal(m["pos_final"], [1.0, 2.0])
    assert np.array_equal(m["u_tv"], [1.0 + 2.0 + 1.0, 0.0])
    # effort: trapezoid of u^2 = ts (u0^2/2 + u1^2 + u2^2 + u3^2/2)
    assert m["effort"] == pytest.approx([0.5 * (0 + 1 + 1 + 0), 0.5 * 4.0 * 3])
    assert m["sat_time"] == pytest.approx([1 * ts, 1 * ts])  # run 1: k = 2 (-13 V)
    T = n_steps * ts
    assert m["IAE"] == pytest.approx([0.1 * T, 0.2 * T])
    assert m["ISE_meas"] == pytest.approx([0.04 * T, 0.16 * T])
    assert m["ITAE_meas"] == pytest.approx([0.2 * T**2 / 2, 0.4 * T**2 / 2])


def test_loop_metrics_match_the_trace():
    """Loop metrics recomputed from the recorded series (and sat_time with a saturating PD)."""
    cfg = LoopConfig(duration=3.0)
    # A PD with a huge gain: any nonzero measured error asks for the full +-12 V, and with the
    # feed-forward V0 ~ 1.05 V one wheel then asks for |V0 + 12| > 12 V: every period saturates
    # under noise. Without noise on the straight line e is exactly 0: no period saturates.
    bang = PDHeadingController(kp=1e6, kd=0.0, name="bang-bang")
    trace = simulate([bang], [straight()], RunTable(0, 0, [0.05, 0.0], 2), cfg)
    ts, n = cfg.ts, cfg.n_steps
    assert trace.metrics["sat_time"][0] == pytest.approx(n * ts, rel=1e-12), "noisy bang-bang"
    assert trace.metrics["sat_time"][1] == 0.0, "noise-free bang-bang"
    v0 = 10.0 / MotorParams().dc_gain  # feed-forward for 2 m/s: 10 rad/s at the wheels
    for i in range(2):
        run = trace.run(i)
        beyond = (np.abs(v0 + run["u"]) > 12.0) | (np.abs(v0 - run["u"]) > 12.0)
        assert trace.metrics["sat_time"][i] == pytest.approx(beyond[:-1].sum() * ts), i
        ints = integral_errors(run["e_true"], ts)
        ints_meas = integral_errors(run["e_meas"], ts)
        for name in ("IAE", "ITAE", "ISE", "ITSE"):
            assert trace.metrics[name][i] == pytest.approx(ints[name], rel=1e-12, abs=1e-15)
            assert trace.metrics[f"{name}_meas"][i] == pytest.approx(
                ints_meas[name], rel=1e-12, abs=1e-15
            )
        dist = np.hypot(run["x_ref"] - run["x"], run["y_ref"] - run["y"])
        assert trace.metrics["pos_max"][i] == pytest.approx(dist.max(), rel=1e-15)
        assert trace.metrics["pos_final"][i] == pytest.approx(dist[-1], rel=1e-15)
        assert trace.metrics["pos_rms"][i] == pytest.approx(np.sqrt(np.mean(dist**2)))
        assert trace.metrics["u_tv"][i] == pytest.approx(np.abs(np.diff(run["u"])).sum())
        assert trace.metrics["effort"][i] == pytest.approx(
            integral_errors(run["u"], ts)["ISE"], rel=1e-12, abs=1e-15
        )

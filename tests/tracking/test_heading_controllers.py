"""Heading controllers: the PD recursion by hand, the fuzzy wrapper, parameter checks."""

from __future__ import annotations

import numpy as np
import pytest

from it2track.fuzzy import Input, IT2Set, Rule, T1Sugeno, Triangle
from it2track.paper import heading_fls
from it2track.tracking import (
    FuzzyHeadingController,
    HeadingController,
    LoopConfig,
    PDHeadingController,
    RunTable,
    Trajectory,
    simulate,
    sinusoidal,
)

TS = 0.01


def _run(ctrl: HeadingController, e: np.ndarray) -> np.ndarray:
    """Drive a controller over an error history (rows: time, columns: runs) as the loop does."""
    state = ctrl.initial_state(e.shape[1], TS)
    out = np.empty_like(e)
    prev = np.zeros(e.shape[1])
    for k, ek in enumerate(e):
        de = ek - prev if k else np.zeros_like(ek)
        prev = ek
        out[k] = ctrl.output(ek.copy(), de, state)
    return out


@pytest.mark.parametrize(("kp", "kd", "tf"), [(10.0, 0.5, 0.02), (3.0, 0.2, 0.0), (0.0, 1.0, 0.1)])
def test_pd_matches_hand_recursion(kp, kd, tf):
    rng = np.random.default_rng(0)
    e = rng.normal(0.0, 0.3, size=(50, 3))
    got = _run(PDHeadingController(kp=kp, kd=kd, tf=tf, u_max=5.0), e)
    for j in range(3):
        d, prev = 0.0, 0.0
        for k in range(50):
            de = e[k, j] - prev if k else 0.0
            prev = e[k, j]
            d = (tf * d + de) / (tf + TS)  # backward Euler of tf D' + D = e'
            expect = min(max(kp * e[k, j] + kd * d, -5.0), 5.0)
            assert got[k, j] == pytest.approx(expect, rel=1e-13, abs=1e-13), (
                f"kp={kp} kd={kd} tf={tf}: run {j}, step {k}"
            )
    if tf == 0.0:  # raw backward difference
        raw = kp * e[1:] + kd * np.diff(e, axis=0) / TS
        assert np.allclose(got[1:], np.clip(raw, -5.0, 5.0), rtol=1e-13, atol=1e-12)


def test_pd_step_response_of_the_filter():
    # A unit step of e at k = 1: D_k = de_1 (tf/(tf+ts))^(k-1) / (tf+ts) for k >= 1.
    tf = 0.05
    e = np.zeros((20, 1))
    e[1:] = 1.0
    got = _run(PDHeadingController(kp=0.0, kd=1.0, tf=tf, u_max=1e9), e)[:, 0]
    k = np.arange(1, 20)
    expect = (tf / (tf + TS)) ** (k - 1) / (tf + TS)
    assert got[0] == 0.0
    assert np.allclose(got[1:], expect, rtol=1e-12)


def test_pd_state_is_per_run():
    ctrl = PDHeadingController(kp=1.0, kd=1.0)
    e = np.array([[0.0, 0.0], [0.1, 0.0], [0.1, 0.0]])
    out = _run(ctrl, e)
    assert np.array_equal(out[:, 1], np.zeros(3)), "a run with no error got a derivative"
    assert ctrl.initial_state(4, TS).shape == (2, 4)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"kp": float("nan")}, "kp=nan"),
        ({"kp": 1.0, "kd": float("inf")}, "kd=inf"),
        ({"kp": "1"}, "kp='1'"),
        ({"kp": True}, "kp=True"),
        ({"kp": 1.0, "tf": -0.1}, "tf=-0.1 must be >= 0"),
        ({"kp": 1.0, "u_max": 0.0}, "u_max=0.0 must be > 0"),
        ({"kp": 1.0, "u_max": -12.0}, "u_max"),
    ],
)
def test_pd_rejects_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        PDHeadingController(**kwargs)


def test_fuzzy_controller_scales_and_clips_inputs():
    fls = heading_fls(0.2)
    ctrl = FuzzyHeadingController(fls=fls, ke=2.0, kde=0.5)
    assert ctrl.name == fls.name
    e = np.array([-3.0, -0.3, 0.0, 0.1, 0.45, 2.0])
    de = np.array([0.5, -4.0, 0.0, 0.2, 1.0, -0.1])
    state = ctrl.initial_state(e.size, TS)
    assert state.shape == (0, e.size)
    got = ctrl.output(e, de, state)
    expect = fls(np.clip(2.0 * e, -1, 1), np.clip(0.5 * de, -1, 1))
    assert np.array_equal(got, expect)
    # inputs beyond the universe are clipped: the corners give the extreme consequents
    assert ctrl.output(np.array([5.0]), np.array([5.0]), state[:, :1])[0] == 12.0
    assert ctrl.output(np.array([-5.0]), np.array([-5.0]), state[:, :1])[0] == -12.0


def test_fuzzy_controller_dead_zone():
    # The type-1 FLC does nothing for |e| < 0.2 with de = 0; the IT2 (FoU 0.2) acts from 0.1.
    flc = FuzzyHeadingController(fls=heading_fls(0.0))
    it2 = FuzzyHeadingController(fls=heading_fls(0.2))
    e = np.array([0.05, 0.15, 0.19])
    zero = np.zeros(3)
    assert np.array_equal(flc.output(e, zero, np.zeros((0, 3))), zero)
    u2 = it2.output(e, zero, np.zeros((0, 3)))
    assert u2[0] == 0.0 and u2[1] > 0.0 and u2[2] > u2[1]


def test_fuzzy_controller_rejects_bad_parameters():
    with pytest.raises(ValueError, match="must be an IT2Sugeno, T1Sugeno, IT2Mamdani or T1Mamdani"):
        FuzzyHeadingController(fls=lambda e, de: e)  # type: ignore[arg-type]
    one_input = T1Sugeno(
        inputs=[Input("e", (-1.0, 1.0), [IT2Set.type1(Triangle(-1, 0, 1), "Z")])],
        rules=[Rule(("Z",), 0.0)],
    )
    with pytest.raises(ValueError, match="must have 2 inputs"):
        FuzzyHeadingController(fls=one_input)
    with pytest.raises(ValueError, match="ke=nan"):
        FuzzyHeadingController(fls=heading_fls(0.1), ke=float("nan"))
    with pytest.raises(ValueError, match="kde='x'"):
        FuzzyHeadingController(fls=heading_fls(0.1), kde="x")  # type: ignore[arg-type]
    assert FuzzyHeadingController(fls=heading_fls(0.1), name="mine").name == "mine"



class _Integrating(HeadingController):
    """A user controller with its own per-run state: u = ki * sum(e) ts, clipped to 6 V."""

    name = "I"

    def __init__(self, ki: float) -> None:
        self.ki = ki
        self.ts = 0.0

    def initial_state(self, n: int, ts: float) -> np.ndarray:
        self.ts = ts
        return np.zeros((1, n))

    def output(self, e: np.ndarray, de: np.ndarray, state: np.ndarray) -> np.ndarray:
        state[0] += e * self.ts
        return np.clip(self.ki * state[0], -6.0, 6.0)


def test_user_controller_runs_through_the_loop():
    ctrl = _Integrating(ki=20.0)
    trace = simulate([ctrl, PDHeadingController(kp=10.0)], [sinusoidal()],
                     RunTable([0, 1, 0], 0, [0.0, 0.0, 0.05], [0, 0, 1]),
                     LoopConfig(duration=2.0))  # fmt: skip
    for i in (0, 2):
        e, u = trace["e_meas"][i], trace["u"][i]
        expect = np.clip(20.0 * np.cumsum(e * TS), -6.0, 6.0)
        assert np.allclose(u, expect, rtol=0, atol=1e-12), f"user controller, run {i}"
    assert not np.allclose(trace["u"][0], trace["u"][2]), "noise had no effect"


def test_base_classes_are_abstract():
    with pytest.raises(NotImplementedError):
        HeadingController().output(np.zeros(1), np.zeros(1), np.zeros((0, 1)))
    assert HeadingController().initial_state(3, TS).shape == (0, 3)
    with pytest.raises(NotImplementedError):
        Trajectory()(np.zeros(1))

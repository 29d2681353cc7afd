"""Tests of it2track.plant.drive: the exact-ZOH robot step against an ODE reference."""

from __future__ import annotations

import inspect
import math
import pickle
import re
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
import scipy.linalg
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp

import it2track.plant as plant
from it2track.plant import (
    DifferentialDrive,
    MotorParams,
    RobotParams,
    body_velocity,
    continuous_rhs,
)
from it2track.plant._sincos import _sincos

TS = 0.01


# --- helpers -----------------------------------------------------------------------------
def reference_run(params: RobotParams, ts: float, volts: np.ndarray) -> np.ndarray:
    """solve_ivp of continuous_rhs period by period with the voltage held; (N, 7) states."""
    state = np.zeros(7)
    out = np.empty((len(volts), 7))
    for k, v in enumerate(volts):
        sol = solve_ivp(
            lambda _t, z, v=v: continuous_rhs(z, v, params),
            (0.0, ts),
            state,
            method="DOP853",
            rtol=1e-10,
            atol=1e-12,
        )
        assert sol.success
        state = sol.y[:, -1]
        out[k] = state
    return out


def discrete_run(plant_: DifferentialDrive, volts: np.ndarray, pose0=(0.0, 0.0, 0.0)):
    """Chain of steps for one robot (B = 1); (N, 7) states in continuous_rhs layout."""
    pose = np.array(pose0, dtype=float).reshape(3, 1)
    wheels = np.zeros((4, 1))
    out = np.empty((len(volts), 7))
    for k, v in enumerate(volts):
        pose, wheels = plant_.step(pose, wheels, np.asarray(v, dtype=float).reshape(2, 1))
        out[k, :3] = pose[:, 0]
        out[k, 3:] = wheels[:, 0]
    return out


def rich_voltages(seed: int, n: int, limit: float = 12.0) -> np.ndarray:
    """Random per-period voltages, different on each wheel, plus stretches at the limit."""
    rng = np.random.default_rng(seed)
    volts = rng.uniform(-limit, limit, (n, 2))
    volts[n // 5 : n // 5 + n // 10] = [limit, -limit]  # spin at full voltage
    volts[n // 2 : n // 2 + n // 10] = [limit, limit]  # full speed ahead
    volts[7 * n // 10 : 7 * n // 10 + n // 20] = [-limit, limit]  # spin back
    volts[9 * n // 10 :] = [-limit, -limit * 0.5]  # reverse arc
    return volts


def exact_wheel_integrals(motor: MotorParams, tau: float, volts: float):
    """(omega(tau), int_0^tau omega) of one motor from rest, via an augmented expm."""
    a, b = motor.state_matrices()
    m = np.zeros((5, 5))
    m[:2, :2], m[:2, 4], m[2:4, :2] = a, b, np.eye(2)
    z = scipy.linalg.expm(m * tau) @ np.array([0.0, 0.0, 0.0, 0.0, volts])
    return z[1], z[3]


def position_error(got: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.hypot(got[:, 0] - ref[:, 0], got[:, 1] - ref[:, 1])))


# --- accuracy against the ODE reference --------------------------------------------------
@pytest.fixture(scope="module")
def ten_seconds():
    params = RobotParams()
    volts = rich_voltages(7, 1000)
    return params, volts, reference_run(params, TS, volts)


@pytest.mark.slow
def test_ten_seconds_match_ode_reference(ten_seconds):
    params, volts, ref = ten_seconds
    got = discrete_run(DifferentialDrive(params, TS), volts)
    # the run really goes somewhere and turns (guards against a vacuous comparison)
    assert np.ptp(ref[:, 0]) > 5.0 and np.ptp(ref[:, 2]) > 1.0
    assert position_error(got, ref) < 1e-6
    assert np.max(np.abs(got[:, 2] - ref[:, 2])) < 1e-6
    # wheel states: exact up to the solver's own tolerance (speeds ~ 100 rad/s)
    assert_allclose(got[:, 3:], ref[:, 3:], rtol=1e-8, atol=1e-7)


@pytest.mark.slow
def test_more_nodes_converge(ten_seconds):
    params, volts, ref = ten_seconds
    errors = [
        position_error(discrete_run(DifferentialDrive(params, TS, quadrature_nodes=n), volts), ref)
        for n in (1, 2, 3)
    ]
    assert errors[0] > errors[1] > errors[2], errors
    assert errors[2] < 1e-6


@pytest.mark.slow
@pytest.mark.parametrize(
    ("half_track", "ts", "duration", "nodes", "tol"),
    [
        (0.15, 0.01, 3.0, 4, 1e-6),  # fast turning: up to ~0.45 rad per period
        (0.15, 0.05, 3.0, 8, 2e-6),  # up to ~2.7 rad per period (large-angle code path)
    ],
)
def test_fast_turning_robot_matches_ode(half_track, ts, duration, nodes, tol):
    params = RobotParams(half_track=half_track)
    volts = rich_voltages(11, round(duration / ts))
    ref = reference_run(params, ts, volts)
    got = discrete_run(DifferentialDrive(params, ts, quadrature_nodes=nodes), volts)
    assert np.max(np.abs(np.diff(ref[:, 2]))) > 0.4
    assert position_error(got, ref) < tol
    assert np.max(np.abs(got[:, 2] - ref[:, 2])) < 1e-9


def test_wheels_follow_motor_zoh_matrices():
    params = RobotParams()
    ad, bd = params.motor.discrete_matrices(TS)
    rng = np.random.default_rng(3)
    wheels = rng.normal(size=(4, 5)) * [[1.0], [50.0], [1.0], [50.0]]
    volts = rng.uniform(-12, 12, (2, 5))
    _, nxt = DifferentialDrive(params, TS).step(np.zeros((3, 5)), wheels, volts)
    assert_allclose(nxt[:2], ad @ wheels[:2] + np.outer(bd, volts[0]), rtol=1e-13, atol=1e-12)
    assert_allclose(nxt[2:], ad @ wheels[2:] + np.outer(bd, volts[1]), rtol=1e-13, atol=1e-12)


# --- special motions ---------------------------------------------------------------------
@pytest.mark.parametrize("theta0", [0.0, 0.7, -2.5])
def test_equal_voltages_drive_straight(theta0):
    params = RobotParams()
    n = 150
    volts = np.tile([9.0, 9.0], (n, 1))
    got = discrete_run(DifferentialDrive(params, TS), volts, pose0=(0.0, 0.0, theta0))
    assert np.all(got[:, 2] == theta0)  # heading untouched, exactly
    _, int_w = exact_wheel_integrals(params.motor, n * TS, 9.0)
    dist = params.wheel_radius * int_w  # v = r (wR + wL) / 2 = r w
    assert_allclose(got[-1, 0], dist * math.cos(theta0), rtol=1e-12)
    assert_allclose(got[-1, 1], dist * math.sin(theta0), rtol=1e-12, atol=1e-15)
    if theta0 == 0.0:
        assert np.all(got[:, 1] == 0.0)


def test_opposite_voltages_turn_on_the_spot():
    params = RobotParams()
    n = 150
    volts = np.tile([6.0, -6.0], (n, 1))
    got = discrete_run(DifferentialDrive(params, TS), volts, pose0=(1.0, -2.0, 0.3))
    assert np.all(got[:, 0] == 1.0) and np.all(got[:, 1] == -2.0)
    _, int_w = exact_wheel_integrals(params.motor, n * TS, 6.0)
    # w = r (wR - wL) / (2 l) = r wR / l with wL = -wR
    expected = 0.3 + params.wheel_radius * int_w / params.half_track
    assert_allclose(got[-1, 2], expected, rtol=1e-12)
    assert np.all(np.diff(got[:, 2]) > 0.0)


def test_at_rest_with_zero_voltage_stays_put():
    plant_ = DifferentialDrive(RobotParams(), TS)
    pose = np.array([[1.0], [2.0], [3.0]])
    p, w = plant_.step(pose, np.zeros((4, 1)), np.zeros((2, 1)))
    assert np.array_equal(p, pose) and np.array_equal(w, np.zeros((4, 1)))


# --- kinematics and continuous model -----------------------------------------------------
def test_body_velocity_by_hand():
    params = RobotParams(half_track=5.6, wheel_radius=0.2)
    v, w = body_velocity(params, 10.0, 4.0)
    assert v == pytest.approx(0.2 * (10.0 + 4.0) / 2.0)  # 1.4 m/s
    assert w == pytest.approx(0.2 * (10.0 - 4.0) / (2.0 * 5.6))  # 0.10714 rad/s
    v, w = body_velocity(RobotParams(half_track=0.5, wheel_radius=0.1), [[1.0], [2.0]], [3.0, -3.0])
    assert v.shape == w.shape == (2, 2)
    assert_allclose(v, [[0.2, -0.1], [0.25, -0.05]])
    assert_allclose(w, [[-0.2, 0.4], [-0.1, 0.5]])


def test_continuous_rhs_by_hand_and_broadcasting():
    params = RobotParams()
    m = params.motor
    state = np.array([1.0, 2.0, math.pi / 2, 0.5, 20.0, -0.25, 10.0])
    d = continuous_rhs(state, [6.0, -3.0], params)
    v = 0.2 * 30.0 / 2.0
    w = 0.2 * 10.0 / (2.0 * 5.6)
    expected = [
        v * math.cos(math.pi / 2),
        v,
        w,
        (6.0 - m.resistance * 0.5 - m.torque_constant * 20.0) / m.inductance,
        (m.torque_constant * 0.5 - m.friction * 20.0) / m.inertia,
        (-3.0 + m.resistance * 0.25 - m.torque_constant * 10.0) / m.inductance,
        (-m.torque_constant * 0.25 - m.friction * 10.0) / m.inertia,
    ]
    assert_allclose(d, expected, atol=1e-12)
    batch = continuous_rhs(np.tile(state, (4, 3, 1)), [6.0, -3.0], params)
    assert batch.shape == (4, 3, 7)
    assert_allclose(batch[2, 1], d)
    with pytest.raises(ValueError, match="state"):
        continuous_rhs(np.zeros(6), [0.0, 0.0], params)
    with pytest.raises(ValueError, match="voltages"):
        continuous_rhs(np.zeros(7), [0.0], params)


# --- batching, determinism, layout -------------------------------------------------------
def random_batch(rng: np.random.Generator, n: int):
    pose = np.vstack([rng.uniform(-50, 50, (2, n)), rng.uniform(-40, 40, n)])
    wheels = rng.normal(size=(4, n)) * np.array([[2.0], [80.0], [2.0], [80.0]])
    volts = rng.uniform(-12, 12, (2, n))
    return pose, wheels, volts


@pytest.mark.parametrize(
    "params", [RobotParams(), RobotParams(half_track=0.05)], ids=["table3", "fast-turn"]
)
def test_run_alone_or_in_any_batch_is_bit_identical(params):
    plant_ = DifferentialDrive(params, TS if params.half_track > 1 else 0.05)
    rng = np.random.default_rng(99)
    pose, wheels, volts = random_batch(rng, 1000)
    pose[2, 5] = 3.0e6  # a heading so large the sine falls back to the C library
    steps = 5

    def advance(p, w, v):
        for _ in range(steps):
            p, w = plant_.step(p, w, v)
        return p, w

    full_p, full_w = advance(pose, wheels, volts)
    for size in (1, 7, 1000):
        for start in sorted({0, 5, 1000 - size, (13 * size) % (1001 - size)}):
            sl = slice(start, start + size)
            p, w = advance(pose[:, sl], wheels[:, sl], volts[:, sl])
            assert np.array_equal(p, full_p[:, sl]), f"pose differs: size {size}, start {start}"
            assert np.array_equal(w, full_w[:, sl]), f"wheels differ: size {size}, start {start}"
    # the same run embedded among other runs, in another order, in another batch
    perm = rng.permutation(1000)
    p, w = advance(pose[:, perm], wheels[:, perm], volts[:, perm])
    assert np.array_equal(p, full_p[:, perm]) and np.array_equal(w, full_w[:, perm])


def test_layout_and_inputs():
    plant_ = DifferentialDrive(RobotParams(), TS)
    rng = np.random.default_rng(4)
    pose, wheels, volts = random_batch(rng, 12)
    before = (pose.copy(), wheels.copy(), volts.copy())
    p, w = plant_.step(pose, wheels, volts)
    assert p.shape == (3, 12) and w.shape == (4, 12)
    assert p.dtype == w.dtype == np.float64
    assert np.array_equal(pose, before[0]) and np.array_equal(wheels, before[1])
    assert np.array_equal(volts, before[2])
    # non-contiguous views give the same numbers
    p2, w2 = plant_.step(
        np.asfortranarray(pose), np.ascontiguousarray(wheels.T).T, volts.T.copy().T
    )
    assert np.array_equal(p, p2) and np.array_equal(w, w2)
    # any trailing batch shape works elementwise
    p3, w3 = plant_.step(pose.reshape(3, 3, 4), wheels.reshape(4, 3, 4), volts.reshape(2, 3, 4))
    assert np.array_equal(p3.reshape(3, 12), p) and np.array_equal(w3.reshape(4, 12), w)


def test_step_is_thread_safe_and_picklable():
    plant_ = DifferentialDrive(RobotParams(), TS)
    rng = np.random.default_rng(8)
    batches = [random_batch(rng, 300) for _ in range(8)]
    serial = [plant_.step(*b) for b in batches]
    with ThreadPoolExecutor(max_workers=4) as pool:
        threaded = list(pool.map(lambda b: plant_.step(*b), batches))
    for (ps, ws), (pt, wt) in zip(serial, threaded, strict=True):
        assert np.array_equal(ps, pt) and np.array_equal(ws, wt)
    clone = pickle.loads(pickle.dumps(plant_))
    assert clone.ts == plant_.ts and clone.params == plant_.params
    pc, wc = clone.step(*batches[0])
    assert np.array_equal(pc, serial[0][0]) and np.array_equal(wc, serial[0][1])


# --- validation --------------------------------------------------------------------------
@pytest.mark.parametrize("nodes", [0, -3, 2.0, True, None])
def test_bad_quadrature_nodes_raise(nodes):
    with pytest.raises(ValueError, match="quadrature_nodes"):
        DifferentialDrive(RobotParams(), TS, quadrature_nodes=nodes)


@pytest.mark.parametrize("ts", [0.0, -1.0, math.nan, math.inf])
def test_bad_period_raises(ts):
    with pytest.raises(ValueError, match="ts"):
        DifferentialDrive(RobotParams(), ts)


def test_bad_shapes_raise():
    plant_ = DifferentialDrive(RobotParams(), TS)
    ok = (np.zeros((3, 2)), np.zeros((4, 2)), np.zeros((2, 2)))
    with pytest.raises(ValueError, match="pose"):
        plant_.step(np.zeros((2, 2)), ok[1], ok[2])
    with pytest.raises(ValueError, match="wheels"):
        plant_.step(ok[0], np.zeros((3, 2)), ok[2])
    with pytest.raises(ValueError, match="voltages"):
        plant_.step(ok[0], ok[1], np.zeros((3, 2)))
    with pytest.raises(ValueError, match="batch shape"):
        plant_.step(ok[0], np.zeros((4, 3)), ok[2])
    with pytest.raises(ValueError, match="pose"):
        plant_.step(np.zeros(3), np.zeros(4), np.zeros(2))


@pytest.mark.parametrize("name", ["half_track", "wheel_radius"])
@pytest.mark.parametrize("bad", [0.0, -0.2, math.nan, math.inf, "0.2"])
def test_bad_robot_params_raise_naming_field(name, bad):
    with pytest.raises(ValueError, match=name):
        RobotParams(**{name: bad})


def test_robot_params_defaults_and_motor_check():
    p = RobotParams()
    assert (p.half_track, p.wheel_radius, p.motor) == (5.6, 0.2, MotorParams())
    with pytest.raises(ValueError, match="motor"):
        RobotParams(motor={"resistance": 5.0})  # type: ignore[arg-type]


# --- the vectorised sine/cosine ----------------------------------------------------------
@pytest.mark.parametrize("scale", [1.0, 1e2, 1e5, 1e7])
def test_sincos_matches_c_library(scale):
    rng = np.random.default_rng(int(scale))
    x = rng.uniform(-scale, scale, 200_000)
    x[:9] = [0.0, -0.0, math.pi / 4, -math.pi / 4, math.pi / 2, math.pi, 1e-300, 5e-324, 2.5]
    work = [np.empty_like(x) for _ in range(7)]
    s, c = np.empty_like(x), np.empty_like(x)
    _sincos(x, s, c, work)
    # within one ulp of a value of magnitude <= 1
    assert np.max(np.abs(s - np.sin(x))) <= 2.0**-53 * 1.01
    assert np.max(np.abs(c - np.cos(x))) <= 2.0**-53 * 1.01
    assert s[6] == 1e-300 and s[7] == 5e-324 and c[0] == 1.0


# --- documentation -----------------------------------------------------------------------
def test_every_public_parameter_is_documented():
    for name in plant.__all__:
        obj = getattr(plant, name)
        targets = [obj]
        if inspect.isclass(obj):
            targets = [obj] + [
                f
                for n, f in vars(obj).items()
                if not n.startswith("_")
                and (inspect.isfunction(f) or isinstance(f, classmethod | staticmethod))
            ]
        for target in targets:
            func = target.__init__ if inspect.isclass(target) else target
            if isinstance(func, classmethod | staticmethod):
                func = func.__func__
            doc = inspect.getdoc(target) or ""
            for param in inspect.signature(func).parameters:
                if param in ("self", "cls"):
                    continue
                assert re.search(rf"\b{param}\b.*:", doc), f"{name}: {param} undocumented"


def test_product_weights_are_computed_once_and_equal_a_fresh_computation():
    """The quadrature moments are cached per (generator, period, nodes): a robot built again
    reuses them, read-only, bit for bit what a fresh computation gives; another period or
    another node set is computed anew."""
    from it2track.plant import drive

    gen = drive._augmented_motor_matrix(RobotParams().motor)[[0, 1, 4]][:, [0, 1, 4]]
    nodes = np.array([0.2, 0.5, 0.9])
    first = drive._product_weights(gen, 0.01, nodes)
    assert first is drive._product_weights(gen.copy(), 0.01, nodes.copy())
    assert not first.flags.writeable
    np.testing.assert_array_equal(first, drive._product_weights_of(gen, 0.01, nodes))
    other = drive._product_weights(gen, 0.02, nodes)
    np.testing.assert_array_equal(other, drive._product_weights_of(gen, 0.02, nodes))
    assert not np.array_equal(other, first)
    fewer = drive._product_weights(gen, 0.01, nodes[:2])
    assert fewer.shape == (2, 3, 3)
    np.testing.assert_array_equal(fewer, drive._product_weights_of(gen, 0.01, nodes[:2]))

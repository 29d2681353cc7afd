"""Every branch of the compiled closed loop (``it2track.tracking._jit``) on short runs, bit for
bit against the numpy engine.

``test_compiled_loop.py`` compares seconds-long runs of many controllers; these compare runs of
a few dozen steps chosen to reach each branch (a PD controller with and without its filter and
saturation, fuzzy controllers with a zero-firing value, errors that wrap past pi, noise, the
previous-pose timing, a metric window, blocks of one path and of two, full and short blocks),
so that they also run in seconds with the kernel as plain Python (``NUMBA_DISABLE_JIT=1``), as
the mutation testing of the kernel runs them (``tools/mutation.py it2track.tracking._jit
--no-jit``).
"""

import dataclasses
import math

import numpy as np
import pytest
from _lane_kernels import _atan2, _sc, _wrap, bits

from it2track.fuzzy import Input, IT2Set, IT2Sugeno, Reducer, Rule, Triangle, ZeroFiringError
from it2track.paper import heading_fls
from it2track.plant import RobotParams
from it2track.plant._sincos import _KERNEL_LIMIT, _SINCOS_LIMIT, _sincos, _sincos_small
from it2track.tracking import (
    ON_PATH,
    FuzzyHeadingController,
    LoopConfig,
    PDHeadingController,
    RunTable,
    WaypointTrajectory,
    _jit,
    compiled,
    simulate,
    simulate_metrics,
    sinusoidal,
    straight,
)
from it2track.tracking.heading import _wrap_inplace
from it2track.tracking.libm import atan2
from it2track.tracking.simulate import _Engine


def waypoints():
    t = np.linspace(0.0, 12.0, 13)
    return WaypointTrajectory("csv-like", t, np.stack([1.5 * t, np.sin(0.7 * t) * 2.0], 1))


TRAJS = [straight(), sinusoidal(), waypoints()]


def gap_fls():
    """Sets that leave |e| < 0.1 uncovered: zero firing there, output 0.5 V."""
    sets = [IT2Set.from_fou(Triangle(-1, -1, -0.1), 0.05, "N"),
            IT2Set.from_fou(Triangle(0.1, 1, 1), 0.05, "P")]
    inputs = [Input("e", (-1, 1), sets), Input("de", (-1, 1), [sets[0], sets[1]])]
    rules = [Rule(("N", None), -6.0), Rule(("P", None), 6.0)]
    return IT2Sugeno(inputs=inputs, rules=rules, on_zero_firing=0.5)


CONTROLLERS = {
    "flc": FuzzyHeadingController(fls=heading_fls(0.0)),
    "it2-gains": FuzzyHeadingController(fls=heading_fls(0.3), ke=0.8, kde=3.0),
    "zero-firing": FuzzyHeadingController(fls=gap_fls()),
    "pd": PDHeadingController(kp=25.0, kd=1.5, tf=0.02),
    "pd-raw": PDHeadingController(kp=8.0, kd=0.3, tf=0.0, u_max=5.0),
    "it2-km": FuzzyHeadingController(fls=heading_fls(0.2, reducer=Reducer.KM.value)),
}


def assert_bits(got, ref, name):
    """The same 64 bits (signed zeros told apart), not only equal values."""
    got, ref = np.asarray(got, dtype=np.float64), np.asarray(ref, dtype=np.float64)
    assert got.shape == ref.shape, name
    assert np.array_equal(got.view(np.int64), ref.view(np.int64)), (name, got, ref)


def compare(controllers, trajs, runs, config, *, series=True):
    """The kernel called directly (every run's status OK: the public calls re-run a run whose
    status is not with numpy, which would hide a kernel's failure) and the public calls,
    against the numpy engine."""
    assert all(compiled.supported(c) is None for c in controllers)
    engine = _Engine(trajs, config)
    ref_m, ref_s = engine.run(controllers, runs, record=series)
    got_m, got_s, status = compiled.run(compiled.load(), engine, controllers, runs,
                                        record=series)
    assert (status == 0).all(), status
    if series:
        assert set(got_s) == set(ref_s)
        for name, ref in ref_s.items():
            assert_bits(got_s[name], ref, name)
        public = simulate(controllers, trajs, runs, config).metrics
    else:
        assert got_s is None
        public = simulate_metrics(controllers, trajs, runs, config)
    assert set(got_m) == set(ref_m)
    for name, ref in ref_m.items():
        assert_bits(got_m[name], ref, name)
        assert_bits(public[name], ref, name)


def table(controller, trajectory, noise, seed):
    return RunTable(np.asarray(controller), np.asarray(trajectory), np.asarray(noise, float),
                    np.asarray(seed))


@pytest.mark.parametrize("name", list(CONTROLLERS))
def test_every_controller(name):
    """Each path, noise 0 and 0.6 rad, a start facing away (true and measured errors past pi,
    wrapped); then runs on one curved path, all noisy (a block on one path, none quiet)."""
    runs = table([0] * 4, [0, 1, 2, 1], [0.0, 0.0, 0.6, 0.05], [0, 1, 2, 3])
    config = LoopConfig(duration=0.12, start_pose=(0.3, -1.0, -2.9))
    compare([CONTROLLERS[name]], TRAJS, runs, config)
    compare([CONTROLLERS[name]], TRAJS, table([0, 0], [1, 1], [1.0, 1.0], [0, 1]),
            LoopConfig(duration=0.05, start_pose=(0.3, -1.0, -2.9)), series=False)


OPTIONS = {
    "on-path": dict(start_pose=ON_PATH),
    "previous-pose": dict(desired_heading_pose="previous", start_pose=(0.5, 0.2, -3.0)),
    "metric-window": dict(metric_start=0.05),
    "fast-period-noise-rate-2-nodes": dict(ts=0.005, noise_rate=50.0, seed=7, quadrature_nodes=2,
                                           robot=RobotParams(half_track=0.28)),
}


@pytest.mark.parametrize("option", list(OPTIONS))
def test_every_loop_option(option):
    # (the fuzzy controller second: its packing starts past the PD's; its block all noisy)
    ctrls = [CONTROLLERS["pd"], CONTROLLERS["it2-gains"]]
    runs = table([0, 0, 1, 1, 1], [1, 2, 1, 1, 0], [0.2, 0.0, 0.2, 1.0, 0.3], [3, 0, 1, 2, 0])
    config = LoopConfig(duration=0.1, **OPTIONS[option])
    compare(ctrls, TRAJS, runs, config)
    compare(ctrls, TRAJS, runs, config, series=False)


def test_full_and_short_blocks_on_one_and_two_paths():
    """More runs of one controller than a block's lanes: a full block on one path, then a
    short block straddling two paths (gathered per lane); runs of a second controller."""
    lanes = _jit.LANES
    n = lanes + 6
    traj = np.r_[np.zeros(lanes + 2, int), np.full(4, 1)]
    runs = table(np.r_[np.zeros(n, int), [1, 1]], np.r_[traj, [2, 0]],
                 np.tile([0.0, 0.3], (n + 2) // 2), np.arange(n + 2) % 5)
    compare([CONTROLLERS["flc"], CONTROLLERS["pd-raw"]], TRAJS, runs,
            LoopConfig(duration=0.05, seed=4))


def test_zero_firing_without_a_value_is_the_references_error():
    """The run that meets the gap stops with the kernels' status (ZERO_FIRING), the others
    run on; the public call raises the reference's error."""
    from it2track.fuzzy import _jit as fuzzy_jit

    strict = FuzzyHeadingController(fls=dataclasses.replace(gap_fls(), on_zero_firing=None))
    ctrls = [strict, CONTROLLERS["pd"]]  # (the failing block first: the next one still runs)
    runs = table([0, 0, 1], [0, 0, 0], [0.0, 0.0, 0.0], [0, 0, 0])
    config = LoopConfig(duration=0.05)
    with pytest.raises(ZeroFiringError, match="no rule"):
        simulate_metrics(ctrls, [straight()], runs, config)
    engine = _Engine([straight()], config)
    got, _, status = compiled.run(compiled.load(), engine, ctrls, runs, record=False)
    assert list(status) == [fuzzy_jit.ZERO_FIRING, fuzzy_jit.ZERO_FIRING, 0]
    ref, _ = engine.run(ctrls, runs.take([2]), record=False)
    for name, value in ref.items():
        assert_bits(got[name][2:], value, name)
    # a run that never meets the gap (it starts far off the path) is the reference's
    compare([strict], [straight()], table([0], [0], [0.0], [0]),
            LoopConfig(duration=0.05, start_pose=(0.0, 1.0, 0.0)))


# -- the lane helpers at the bounds of their branches ----------------------------------------
# (test_lanes.py draws random lanes; these put each bound and its neighbours in a block)




def around(v):
    return [np.nextafter(v, -np.inf), v, np.nextafter(v, np.inf)]


def test_atan2_lanes_at_the_interval_bounds():
    """|y / x| exactly at and next to each reduction interval's bound (7/16, 11/16, 19/16,
    39/16), at 2^60, zeros of either sign, every quadrant; with and without a non-finite
    lane in the block."""
    ratios = [r for b in (0.4375, 0.6875, 1.1875, 2.4375, 2.0**60) for r in around(b)]
    y = np.array([r * 16.0 for r in ratios] + [0.0, -0.0, 0.0, -0.0, 1.0, -1.0, 3.0])
    x = np.array([16.0] * len(ratios) + [1.0, 1.0, -0.0, -1.0, 0.0, -0.0, -5.0])
    for sx, sy in ((1, 1), (-1, 1), (1, -1), (-1, -1)):
        for odd in (False, True):
            yy, xx = sy * y, sx * x
            if odd:
                yy, xx = np.r_[yy, np.inf], np.r_[xx, np.nan]
            L = yy.size
            W = np.zeros((3, 64))
            W[0, :L], W[1, :L] = xx, yy
            _atan2(W, L)
            assert (bits(W[2, :L]) == bits(atan2(yy, xx))).all(), (sx, sy, odd)


def test_wrap_lanes_at_the_bounds():
    a = np.array([*around(math.pi), *around(-math.pi), *around(3 * math.pi),
                  *around(-3 * math.pi), 0.0, -0.0, 1e9, -7.0])
    for lanes in (a, a[:3], a[3:6]):
        L = lanes.size
        W = np.zeros((1, 64))
        W[0, :L] = lanes
        _wrap(W, L)
        assert (bits(W[0, :L]) == bits(_wrap_inplace(lanes.copy()))).all(), lanes


@pytest.mark.parametrize("small", [False, True])
def test_sincos_lanes_at_the_limits(small):
    limit = _KERNEL_LIMIT if small else _SINCOS_LIMIT
    x = np.array([*around(limit), *around(-limit), 0.5, -0.25, 0.0])
    ref = _sincos_small if small else _sincos
    for lanes in (x, x[[0, 3, 6]]):
        L = lanes.size
        W = np.zeros((3, 64))
        W[0, :L] = lanes
        _sc(W, L, small)
        s, c = np.empty(L), np.empty(L)
        ref(lanes, s, c, [np.empty(L) for _ in range(7)])
        assert (bits(W[1, :L]) == bits(s)).all() and (bits(W[2, :L]) == bits(c)).all()


def test_a_start_heading_of_minus_zero():
    """theta = -0.0: the measured heading of a run without noise is theta + 0.0 = +0.0 (the
    numpy engine adds its zero noise row)."""
    runs = table([0, 0], [0, 0], [0.0, 0.0], [0, 1])
    compare([CONTROLLERS["pd"]], [straight()], runs,
            LoopConfig(duration=0.03, start_pose=(0.0, 0.0, -0.0)))


def test_a_failing_run_that_is_not_the_first_of_its_block():
    """The block's first run (copied into its spare lanes) never meets the gap, the next does
    at once: only that one stops with ZERO_FIRING."""
    from it2track.fuzzy import _jit as fuzzy_jit

    strict = FuzzyHeadingController(fls=dataclasses.replace(gap_fls(), on_zero_firing=None))
    config = LoopConfig(duration=0.02)
    engine = _Engine([straight()], config)
    runs = table([0, 0], [0, 0], [0.6, 0.0], [SEED_AWAY, 0])
    _, _, status = compiled.run(compiled.load(), engine, [strict], runs, record=False)
    assert list(status) == [0, fuzzy_jit.ZERO_FIRING]
    compare([strict], [straight()], runs.take([0]), config)


#: A seed whose noise keeps the measured error outside the gap (|e| >= 0.1) for three steps.
SEED_AWAY = 0

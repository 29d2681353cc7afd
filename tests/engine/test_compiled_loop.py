"""The compiled closed loop (it2track.tracking.compiled) equals the numpy engine bit for bit.

``simulate``/``simulate_metrics`` run every supported run through the compiled kernel; the
reference is the numpy engine (``_Engine.run``) on the same runs. Compared: all 17 series and
all 14 metrics, exactly (``array_equal``), across controllers, reducers, trajectories, every
LoopConfig option and noise levels; and the compiled results across batch sizes, thread counts
and executors.
"""

import dataclasses
import functools

import numba
import numpy as np
import pytest

from it2track.experiments.executors import InProcessExecutor, ProcessExecutor
from it2track.fuzzy import Input, IT2Set, IT2Sugeno, Reducer, Rule, TNorm, Triangle, ZeroFiringError
from it2track.paper import dead_zone_matched_fls, heading_fls
from it2track.plant import RobotParams
from it2track.tracking import (
    ON_PATH,
    FuzzyHeadingController,
    LoopConfig,
    PDHeadingController,
    RunTable,
    WaypointTrajectory,
    compiled,
    curved,
    run_grid,
    simulate,
    simulate_metrics,
    sinusoidal,
    straight,
)
from it2track.tracking.simulate import _Engine


def waypoints():
    t = np.linspace(0.0, 12.0, 13)
    return WaypointTrajectory("csv-like", t, np.stack([1.5 * t, np.sin(0.7 * t) * 2.0], 1))


TRAJS = [straight(), curved(), sinusoidal(), waypoints()]


def gaussian_fls():
    sets = [IT2Set.gaussian_uncertain_mean(-1.0, -0.7, 0.3, "N"),
            IT2Set.gaussian_uncertain_std(0.0, 0.25, 0.4, "Z"),
            IT2Set.gaussian_uncertain_mean(0.7, 1.0, 0.3, "P")]  # fmt: skip
    rules = [Rule((a, b), (4.0 * (i + j - 2) - 1.0, 4.0 * (i + j - 2) + 1.0))
             for i, a in enumerate("NZP") for j, b in enumerate("NZP")]  # fmt: skip
    return IT2Sugeno(inputs=[Input("e", (-1, 1), sets), Input("de", (-1, 1), sets)],
                     rules=rules, reducer=Reducer.EKM.value)  # fmt: skip


def gap_fls():
    """Sets that leave |e| < 0.1 uncovered: zero firing there, output 0.5 V."""
    sets = [IT2Set.from_fou(Triangle(-1, -1, -0.1), 0.05, "N"),
            IT2Set.from_fou(Triangle(0.1, 1, 1), 0.05, "P")]
    inputs = [Input("e", (-1, 1), sets), Input("de", (-1, 1), [sets[0], sets[1]])]
    rules = [Rule(("N", None), -6.0), Rule(("P", None), 6.0)]
    return IT2Sugeno(inputs=inputs, rules=rules, on_zero_firing=0.5)


CONTROLLERS = {
    "flc": FuzzyHeadingController(fls=heading_fls(0.0)),
    "it2-0.1": FuzzyHeadingController(fls=heading_fls(0.1)),
    "it2-0.3-gains": FuzzyHeadingController(fls=heading_fls(0.3), ke=0.8, kde=3.0),
    "dead-zone-min": FuzzyHeadingController(fls=dead_zone_matched_fls(0.2, tnorm=TNorm.MINIMUM)),
    "gaussian-ekm": FuzzyHeadingController(fls=gaussian_fls()),
    "zero-firing": FuzzyHeadingController(fls=gap_fls()),
    "pd": PDHeadingController(kp=25.0, kd=1.5, tf=0.02),
    "pd-raw": PDHeadingController(kp=8.0, kd=0.3, tf=0.0, u_max=5.0),
}
for _red in Reducer:
    CONTROLLERS[f"it2-0.2-{_red.value.name}"] = FuzzyHeadingController(
        fls=heading_fls(0.2, reducer=_red.value, tnorm=TNorm.MINIMUM if _red is Reducer.KM
                        else TNorm.PRODUCT))  # fmt: skip


def assert_bits(got, ref, name):
    """The same 64 bits (signed zeros told apart), not only equal values."""
    np.testing.assert_array_equal(got, ref, err_msg=name)
    assert np.array_equal(np.asarray(got).view(np.int64), np.asarray(ref).view(np.int64)), name


def compare(controllers, trajs, runs, config, *, series=True):
    assert all(compiled.supported(c) is None for c in controllers)
    engine = _Engine(trajs, config)
    ref_m, ref_s = engine.run(controllers, runs, record=series)
    if series:
        trace = simulate(controllers, trajs, runs, config)
        got_m, got_s = trace.metrics, trace.series
        for name, ref in ref_s.items():
            assert_bits(got_s[name], ref, name)
    else:
        got_m = simulate_metrics(controllers, trajs, runs, config, batch_size=97)
    for name, ref in ref_m.items():
        assert_bits(got_m[name], ref, name)


@pytest.mark.parametrize("name", list(CONTROLLERS))
def test_every_controller_every_trajectory(name):
    runs = run_grid(1, len(TRAJS), [0.0, 0.05, 0.6], 2)  # 0.6 rad: errors wrap past pi
    compare([CONTROLLERS[name]], TRAJS, runs, LoopConfig(duration=2.0))


OPTIONS = {
    "on-path": dict(start_pose=ON_PATH),
    "previous-pose": dict(desired_heading_pose="previous"),
    "metric-window": dict(metric_start=0.5),
    "start-pose": dict(start_pose=(0.3, -1.0, 2.5)),
    "fast-period-noise-rate": dict(ts=0.005, noise_rate=50.0, seed=7),
    "short-track-2-nodes": dict(robot=RobotParams(half_track=0.28), quadrature_nodes=2),
}


@pytest.mark.parametrize("option", list(OPTIONS))
def test_every_loop_option(option):
    ctrls = [CONTROLLERS["it2-0.1"], CONTROLLERS["pd"], CONTROLLERS["flc"]]
    runs = run_grid(len(ctrls), len(TRAJS), [0.0, 0.2], 2)
    compare(ctrls, TRAJS, runs, LoopConfig(duration=1.5, **OPTIONS[option]))
    compare(ctrls, TRAJS, runs, LoopConfig(duration=1.5, **OPTIONS[option]), series=False)


def test_mixed_batch_with_an_unsupported_controller():
    @dataclasses.dataclass(frozen=True, kw_only=True)
    class Mine(FuzzyHeadingController):
        pass

    mine = Mine(fls=heading_fls(0.2))
    assert compiled.supported(mine) is not None
    ctrls = [CONTROLLERS["it2-0.1"], mine, CONTROLLERS["pd"]]
    runs = run_grid(3, 2, [0.1], 3)
    ref_m, _ = _Engine(TRAJS[:2], LoopConfig(duration=1.0)).run(ctrls, runs, record=False)
    got = simulate_metrics(ctrls, TRAJS[:2], runs, LoopConfig(duration=1.0))
    for name, ref in ref_m.items():
        np.testing.assert_array_equal(got[name], ref, err_msg=name)


def test_errors_are_the_references():
    strict = FuzzyHeadingController(fls=dataclasses.replace(gap_fls(), on_zero_firing=None))
    with pytest.raises(ZeroFiringError, match="no rule"):
        simulate_metrics([strict], [straight()], RunTable(0, 0, 0.0, 0), LoopConfig(duration=1))


def _metrics(runs, batch_size=4096):
    ctrls = [CONTROLLERS["it2-0.1"], CONTROLLERS["pd"], CONTROLLERS["it2-0.2-km"]]
    return simulate_metrics(ctrls, TRAJS, runs, LoopConfig(duration=1.0), batch_size=batch_size)


RUNS = run_grid(3, len(TRAJS), [0.0, 0.1], 12)  # 288 runs


def test_batch_sizes_and_threads_give_the_same_bits():
    expected = _metrics(RUNS, 4096)
    for batch in (1, 7):
        got = _metrics(RUNS.take(slice(0, 60)), batch)
        for name, value in got.items():
            np.testing.assert_array_equal(value, expected[name][:60], err_msg=f"{name} {batch}")
    before = numba.get_num_threads()
    try:
        for threads in (1, 2):
            numba.set_num_threads(threads)
            got = _metrics(RUNS)
            for name, value in got.items():
                np.testing.assert_array_equal(value, expected[name], err_msg=f"{name} {threads}")
    finally:
        numba.set_num_threads(before)
    # one run alone, in a reversed batch
    alone = _metrics(RUNS.take([200]))
    rev = _metrics(RUNS.take(np.arange(len(RUNS))[::-1]))
    for name, value in expected.items():
        assert alone[name][0] == value[200]
        np.testing.assert_array_equal(rev[name][::-1], value, err_msg=name)


def _by_executor(executor):
    parts = [RUNS.take(slice(a, a + 72)) for a in range(0, len(RUNS), 72)]
    fn = functools.partial(_metrics, batch_size=50)
    with executor as ex:
        done = dict((id(t), r) for t, r in ex.imap_unordered(fn, parts))
    return {name: np.concatenate([done[id(p)][name] for p in parts]) for name in done[id(parts[0])]}


@pytest.mark.slow
def test_executors_give_the_same_bits():
    expected = _metrics(RUNS)
    results = [_by_executor(InProcessExecutor()), _by_executor(ProcessExecutor(2))]
    distributed = pytest.importorskip("distributed")
    from it2track.experiments.executors import DaskExecutor

    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=True,
                                  dashboard_address=":0") as cluster:  # fmt: skip
        results.append(_by_executor(DaskExecutor(cluster.scheduler_address)))
    for got in results:
        for name, value in expected.items():
            np.testing.assert_array_equal(got[name], value, err_msg=name)


def test_full_and_partial_blocks_on_one_and_several_paths():
    """A controller's runs fill several blocks of compiled.LANES lanes: full blocks, a short
    last one (spare lanes compute copies of its first run), blocks on one path and blocks
    straddling two paths (their reference gathered per lane)."""
    from it2track.tracking import _jit

    lanes = _jit.LANES
    n = 2 * lanes + 37
    ctrls = [CONTROLLERS["it2-0.2-km"], CONTROLLERS["pd"]]
    runs = RunTable(np.repeat([0, 1], n), np.tile(np.repeat([0, 2], [lanes + 5, n - lanes - 5]), 2),
                    np.tile([0.0, 0.3, 0.05], 2 * n)[:2 * n], np.arange(2 * n) % 11)
    compare(ctrls, TRAJS, runs, LoopConfig(duration=0.3, seed=4), series=False)
    compare(ctrls, TRAJS, runs.take(np.arange(0, 2 * n, 3)), LoopConfig(duration=0.3))

"""The closed loop with the controller on the simulated ATmega328P (processor in the loop).

References: the host-compiled C in the loop (CHeadingController: float32 results equal the
AVR's bit for bit, DESIGN.md sec. 11), the cost benchmark's run for the cycles, a replay of the
plant from the trace's commanded voltages for the latency models, and an ODE solution of the
continuous robot with the voltage switched at each measured latency."""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import it2track
from it2track.codegen import CHeadingController, RealType, generate_c
from it2track.codegen.mcu import run_on_avr
from it2track.codegen.tools import PIL_TOOLS, missing_tools
from it2track.fuzzy import Input, IT2Set, IT2Sugeno, Reducer, Rule, Trapezoid
from it2track.plant import DifferentialDrive, continuous_rhs
from it2track.tracking import (
    TRACE_FIELDS,
    FuzzyHeadingController,
    LoopConfig,
    RunTable,
    get_trajectory,
    simulate,
    simulate_metrics,
)
from it2track.tracking.pil import Latency, PilHeadingController

TRAJ = [get_trajectory(name) for name in ("straight", "curved", "sinusoidal")]


def skip_without(*tools: str) -> None:
    missing = missing_tools(tools)
    if missing:
        pytest.skip(f"needs {', '.join(tools)}: install the Debian package(s) "
                    f"{', '.join(missing)}")


@pytest.fixture(scope="module")
def build_dir(tmp_path_factory):
    return str(tmp_path_factory.mktemp("pil-loop"))


def _trapezoid_system() -> IT2Sugeno:
    """A two-input IT2 system of trapezoids on other universes (no Gaussian: avr-libc's exp
    differs from the host's in the last bits)."""
    e = Input("e", (-2.0, 2.0), [
        IT2Set.from_fou(Trapezoid(-2.0, -2.0, -1.0, 0.2), 0.2, "N"),
        IT2Set.from_fou(Trapezoid(-1.2, -0.2, 0.3, 1.3), 0.3, "Z"),
        IT2Set.from_fou(Trapezoid(0.1, 1.1, 2.0, 2.0), 0.2, "P")])
    de = Input("de", (-0.5, 0.5), [
        IT2Set.from_fou(Trapezoid(-0.5, -0.5, -0.2, 0.1), 0.05, "N"),
        IT2Set.from_fou(Trapezoid(-0.1, 0.2, 0.5, 0.5), 0.05, "P")])
    rules = [Rule(["N", "N"], -11.0), Rule(["N", "P"], (-7.0, -5.0)), Rule(["Z", "N"], -2.0),
             Rule(["Z", "P"], (1.0, 2.5)), Rule(["P", "N"], 6.0), Rule(["P", "P"], 10.0)]
    return IT2Sugeno(inputs=[e, de], rules=rules, reducer=Reducer.EIASC.value, name="trap")


def _systems():
    base = it2track.heading_fls(0.2)
    out = [("flc", it2track.heading_fls(0.0), 1.0)]
    for red in (Reducer.EXHAUSTIVE, Reducer.KM, Reducer.EIASC):
        out.append((red.value.name, dataclasses.replace(base, reducer=red.value), 1.0))
    out.append(("trapezoids", _trapezoid_system(), 1.7))
    return out


def _same_trace(a, b, ia, ib, what):
    for name in TRACE_FIELDS:
        assert a[name][ia].tobytes() == b[name][ib].tobytes(), f"{what}: {name}"
    for name, value in a.metrics.items():
        assert value[ia].tobytes() == b.metrics[name][ib].tobytes(), f"{what}: {name}"


@pytest.mark.parametrize("real", [RealType.FLOAT, RealType.Q15], ids=lambda r: r.value)
def test_zero_latency_pil_loop_equals_the_host_c_loop(real, build_dir):
    """Every series and metric, bit for bit, on the three paths with noise: the paper's FLC,
    the IT2FLC with three reducers, and a trapezoid system with an input gain."""
    skip_without(*PIL_TOOLS)
    systems = [s for s in _systems() if not (real.fixed and s[0] == "trapezoids")]
    controllers = []
    for label, fls, ke in systems:
        controllers.append(CHeadingController.from_system(fls, real=real, ke=ke,
                                                          build_dir=build_dir, name=label))
        controllers.append(PilHeadingController.from_system(
            fls, real=real, ke=ke, build_dir=build_dir, name=f"pil {label}"))
    n = len(controllers)
    runs = RunTable(np.repeat(np.arange(n), 3), np.tile(np.arange(3), n), 0.05,
                    np.tile([1, 2, 3], n))
    trace = simulate(controllers, TRAJ, runs, LoopConfig(duration=1.5))
    for j in range(0, n, 2):
        host, pil = np.flatnonzero(runs.controller == j), np.flatnonzero(runs.controller == j + 1)
        _same_trace(trace, trace, host, pil, controllers[j].name)
        assert np.isnan(trace["cycles"][host]).all()
        assert (trace["cycles"][pil] > 0).all() and (trace["latency"][pil] == 0).all()


def test_trace_cycles_equal_the_benchmark_for_the_same_inputs(build_dir):
    """The cycles the loop records per step are those run_on_avr (the cost benchmark's
    measurement) gives for the inputs the controller saw at that step."""
    skip_without(*PIL_TOOLS, "simavr")
    fls = dataclasses.replace(it2track.heading_fls(0.2), reducer=Reducer.KM.value)
    for real in (RealType.FLOAT, RealType.Q15):
        pil = PilHeadingController.from_system(fls, real=real, kde=2.0, build_dir=build_dir,
                                               latency="measured")
        trace = simulate([pil], TRAJ[1:2], RunTable(0, 0, 0.1, 7), LoopConfig(duration=0.6))
        x = np.stack([trace["e_meas"][0], 2.0 * trace["de"][0]], axis=1)
        ref = run_on_avr(pil.code, x, build_dir=build_dir)
        assert np.array_equal(trace["cycles"][0], ref.cycles.astype(np.float64)), real
        assert np.array_equal(trace["latency"][0], ref.cycles / 16e6), real
        assert len(np.unique(ref.cycles)) > 10  # the cycles do depend on the inputs


def _replay(trace, run, drive, lag):
    """Pose and wheel speeds from stepping the drive with the trace's commanded voltages,
    ``lag`` periods late (0 V before the first command)."""
    volts = np.stack([trace["v_right"][run], trace["v_left"][run]])
    pose = np.array([[trace["x"][run, 0]], [trace["y"][run, 0]], [trace["theta"][run, 0]]])
    wheels = np.zeros((4, 1))
    out = [np.concatenate([pose[:, 0], wheels[[1, 3], 0]])]
    for k in range(volts.shape[1] - 1):
        v = volts[:, k - lag:k - lag + 1] if k >= lag else np.zeros((2, 1))
        pose, wheels = drive.step(pose, wheels, v)
        out.append(np.concatenate([pose[:, 0], wheels[[1, 3], 0]]))
    return np.array(out)


def _recorded(trace, run):
    return np.stack([trace[f][run] for f in ("x", "y", "theta", "omega_right",
                                             "omega_left")], axis=1)


@pytest.mark.parametrize("latency, lag", [("none", 0), ("period", 1)])
def test_none_and_period_latency_replay_exactly(latency, lag, build_dir):
    """``none``: the plant sees this period's command; ``period``: the previous one (0 V in
    the first period, so the wheels are still at t_1)."""
    skip_without(*PIL_TOOLS)
    pil = PilHeadingController.from_system(it2track.heading_fls(0.2), latency=latency,
                                           build_dir=build_dir)
    cfg = LoopConfig(duration=0.8)
    trace = simulate([pil], TRAJ, RunTable(0, [0, 1, 2], 0.05, 4), cfg)
    drive = DifferentialDrive(cfg.robot, cfg.ts)
    for run in range(3):
        assert np.array_equal(_recorded(trace, run), _replay(trace, run, drive, lag))
        assert np.array_equal(trace["latency"][run], np.full(81, cfg.ts * lag))
    if lag:
        assert (trace["omega_right"][:, 1] == 0).all() and (trace["omega_left"][:, 1] == 0).all()


def test_measured_latency_follows_the_ode_with_the_switch(build_dir):
    """The measured model: over period k the motors see command k-1 for latency[k] seconds,
    then command k. Checked against the continuous model integrated by an ODE solver."""
    skip_without(*PIL_TOOLS)
    pil = PilHeadingController.from_system(it2track.heading_fls(0.2), latency="measured",
                                           build_dir=build_dir)
    cfg = LoopConfig(duration=0.3)
    trace = simulate([pil], TRAJ[2:], RunTable(0, 0, 0.1, 5), cfg)
    volts = np.stack([trace["v_right"][0], trace["v_left"][0]], axis=1)
    delay = trace["latency"][0]
    assert (delay > 0).all() and (delay < 0.002).all()
    state = np.zeros(7)
    robot = cfg.robot
    for k in range(cfg.n_steps):
        before = volts[k - 1] if k else np.zeros(2)
        for a, b, v in ((0.0, delay[k], before), (delay[k], cfg.ts, volts[k])):
            sol = solve_ivp(lambda _t, z, v=v: continuous_rhs(z, v, robot), (0.0, b - a), state,
                            method="DOP853", rtol=1e-11, atol=1e-13)
            state = sol.y[:, -1]
        got = _recorded(trace, 0)[k + 1]
        np.testing.assert_allclose(got[:3], state[:3], rtol=0, atol=1e-9, err_msg=f"k={k}")
        np.testing.assert_allclose(got[3:], state[[4, 6]], rtol=1e-9, atol=1e-9)


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Delayed(FuzzyHeadingController):
    """A Python controller that reports a fixed output delay (no MCU needed)."""

    delay: float = 0.0
    delays_output = True
    trace_series = ("delay_used",)

    def initial_state(self, n, ts):
        return np.full((1, n), self.delay)

    def output_delay(self, state):
        return state[0]

    def step_series(self, state):
        return {"delay_used": state[0]}


def test_a_reported_delay_of_zero_is_no_latency_and_of_ts_is_one_period():
    fls = it2track.heading_fls(0.2)
    plain = FuzzyHeadingController(fls=fls)
    cfg = LoopConfig(duration=1.0)
    runs = RunTable([0, 1, 2, 0, 1, 2], [0, 0, 0, 1, 1, 1], 0.05, 3)
    trace = simulate([plain, _Delayed(fls=fls, delay=0.0), _Delayed(fls=fls, delay=cfg.ts)],
                     TRAJ, runs, cfg)
    _same_trace(trace, trace, [0, 3], [1, 4], "delay 0")
    assert np.isnan(trace["delay_used"][[0, 3]]).all()
    assert (trace["delay_used"][[1, 4]] == 0).all()
    assert (trace["delay_used"][[2, 5]] == cfg.ts).all()
    drive = DifferentialDrive(cfg.robot, cfg.ts)
    for run in (2, 5):
        assert np.array_equal(_recorded(trace, run), _replay(trace, run, drive, 1))
    assert not np.array_equal(trace["x"][0], trace["x"][2])
    # The metrics-only path agrees with the traced one.
    metrics = simulate_metrics([plain, _Delayed(fls=fls, delay=0.0),
                                _Delayed(fls=fls, delay=cfg.ts)], TRAJ, runs, cfg, batch_size=2)
    for name, value in metrics.items():
        assert value.tobytes() == trace.metrics[name].tobytes(), name


def test_pil_beside_other_controllers_leaves_them_untouched(build_dir):
    """A delaying PIL controller in the batch: the others' runs (on the compiled engine where
    it is available) are what they are alone, bit for bit."""
    skip_without(*PIL_TOOLS)
    fls = it2track.heading_fls(0.2)
    plain = FuzzyHeadingController(fls=fls)
    pil = PilHeadingController.from_system(fls, latency="measured", build_dir=build_dir)
    cfg = LoopConfig(duration=0.5)
    runs = RunTable([0, 1, 0], [0, 1, 2], 0.05, [1, 2, 3])
    both = simulate([plain, pil], TRAJ, runs, cfg)
    alone = simulate([plain], TRAJ, RunTable(0, [0, 2], 0.05, [1, 3]), cfg)
    _same_trace(both, alone, [0, 2], [0, 1], "plain beside PIL")
    assert np.isnan(both["cycles"][[0, 2]]).all() and (both["cycles"][1] > 0).all()
    assert (both["latency"][1] > 0).all()


def test_an_overrun_is_an_error(build_dir):
    skip_without(*PIL_TOOLS)
    pil = PilHeadingController.from_system(it2track.heading_fls(0.2), latency="period",
                                           build_dir=build_dir, name="slow")
    with pytest.raises(ValueError, match=r"slow: a call took \d+ cycles = .* longer than the "
                                         r"control period ts = 0.2 ms \(an overrun"):
        simulate([pil], TRAJ[:1], RunTable(0, 0, 0.05, 0), LoopConfig(duration=0.01, ts=2e-4))
    # Without latency the period is not enforced: the idealised loop.
    fast = dataclasses.replace(pil, latency=Latency.NONE)
    simulate([fast], TRAJ[:1], RunTable(0, 0, 0.05, 0), LoopConfig(duration=0.01, ts=2e-4))


def test_pickles_without_its_mcu_and_runs_after(build_dir):
    skip_without(*PIL_TOOLS)
    pil = PilHeadingController.from_system(it2track.heading_fls(0.2), build_dir=build_dir)
    e, de = np.array([0.3, -2.0]), np.array([0.01, 0.5])
    u = pil.output(e, de, pil.initial_state(2, 0.01))
    copy = pickle.loads(pickle.dumps(pil))
    assert copy._mcu is None
    assert np.array_equal(copy.output(e, de, copy.initial_state(2, 0.01)), u)


def test_parameters_are_checked():
    code = generate_c(it2track.heading_fls(0.2))
    with pytest.raises(ValueError, match=r"latency='late' must be one of \['none', 'measured'"):
        PilHeadingController(code=code, latency="late")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="threads=0 must be a positive integer"):
        PilHeadingController(code=code, threads=0)
    with pytest.raises(ValueError, match="ke=nan must be a finite number"):
        PilHeadingController(code=code, ke=float("nan"))
    with pytest.raises(ValueError, match="must be a CCode"):
        PilHeadingController(code="it2.c")  # type: ignore[arg-type]
    pil = PilHeadingController(code=code, latency="period")
    assert pil.latency is Latency.PERIOD and pil.delays_output
    assert not PilHeadingController(code=code).delays_output
    assert pil.name == "PIL it2 (double, latency period)"


def test_reference_task_records_cycles_and_refuses_latency_without_a_switching_plant(
        build_dir):
    """On a single-input linear plant the PIL controller runs (its cycles are traced); a
    latency needs ``step_switched``, which that plant does not have: a ValueError naming it."""
    skip_without(*PIL_TOOLS)
    from it2track.plant.linear import LinearSpec
    from it2track.tracking import StepReference

    lag = LinearSpec(a=[[0.9]], b=[[0.1]], c=[[1.0]], dt=True, output_names=["level"])
    cfg = LoopConfig(duration=0.2, ts=0.05, noise_rate=20.0, plant=lag)
    fls = it2track.heading_fls(0.2)
    pil = PilHeadingController.from_system(fls, build_dir=build_dir)
    host = CHeadingController.from_system(fls, real=RealType.FLOAT, build_dir=build_dir)
    trace = simulate([pil, host], [StepReference(amplitude=0.5)], RunTable([0, 1], 0, 0.0, 0),
                     cfg)
    assert (trace["cycles"][0] > 0).all() and np.isnan(trace["cycles"][1]).all()
    assert trace["u"][0].tobytes() == trace["u"][1].tobytes()
    late = dataclasses.replace(pil, latency=Latency.MEASURED)
    with pytest.raises(ValueError, match=r"applies its output late, which needs a plant that "
                                         r"can switch its inputs inside a period"):
        simulate([late], [StepReference(amplitude=0.5)], RunTable(0, 0, 0.0, 0), cfg)


def test_latency_table_lookup_is_nearest_and_clipped():
    from it2track.tracking.pil import LatencyTable

    cycles = np.arange(15, dtype=np.int64).reshape(3, 5) * 100  # e: -1, 0, 1; de: 0 .. 2
    table = LatencyTable(lo=(-1.0, 0.0), hi=(1.0, 2.0), cycles=cycles)
    x = np.array([[-1.0, 0.0], [0.49, 0.26], [0.51, 1.74], [5.0, -3.0], [-0.2, 9.0]])
    assert table.lookup(x).tolist() == [0, 600, 1300, 1000, 900]
    with pytest.raises(ValueError, match="must agree"):
        LatencyTable(lo=(-1.0,), hi=(1.0, 2.0), cycles=cycles)
    with pytest.raises(ValueError, match="lo < hi"):
        LatencyTable(lo=(1.0, 0.0), hi=(1.0, 2.0), cycles=cycles)
    with pytest.raises(ValueError, match="integers"):
        LatencyTable(lo=(-1.0, 0.0), hi=(1.0, 2.0), cycles=cycles * 1.0)


def test_tabled_latency_runs_the_host_c_with_the_measured_cycles(build_dir):
    """The host C with a latency table measured on the chip: every step's output is the host
    C's at that step's inputs, its cycles the table's at them, applied like ``measured``; at a
    table fine enough its runs stay close to the PIL loop's."""
    skip_without(*PIL_TOOLS)
    from it2track.tracking.pil import LatencyTable, TabledLatencyController

    fls = it2track.heading_fls(0.2)
    code = generate_c(fls, real=RealType.FLOAT)
    table = LatencyTable.measure(code, [(-1.0, 1.0), (-1.0, 1.0)], points=33,
                                 build_dir=build_dir)
    with pytest.raises(ValueError, match="points=1 must be an integer >= 2"):
        LatencyTable.measure(code, [(-1.0, 1.0), (-1.0, 1.0)], points=1, build_dir=build_dir)
    host = CHeadingController(code=code, build_dir=build_dir)
    tabled = TabledLatencyController(host=host, table=table)
    pil = PilHeadingController(code=code, latency="measured", build_dir=build_dir)
    cfg = LoopConfig(duration=1.0)
    trace = simulate([tabled, pil], TRAJ[1:2], RunTable([0, 1], 0, 0.05, 2), cfg)
    x = np.stack([trace["e_meas"][0], trace["de"][0]], axis=1)
    assert np.array_equal(trace["cycles"][0], table.lookup(x))
    assert np.array_equal(trace["latency"][0], table.lookup(x) / 16e6)
    assert trace["u"][0].tobytes() == host.output(x[:, 0], x[:, 1], np.zeros((0, 101))).tobytes()
    for name in ("IAE", "ISE", "pos_rms"):
        assert abs(trace.metrics[name][0] / trace.metrics[name][1] - 1) < 1e-2, name

"""Bad input through the Python API, in-process: every case must raise the documented
exception type (a ``ValueError`` family member, or ``OSError`` for a missing file) with a
message naming the argument and the bad value -- never another exception, never a silent
acceptance, never a hang (FIFOs and endless devices are refused before reading)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hostile_helpers import BINARY, assert_clean_error, make_device_link, make_fifo, make_sparse

import it2track
from it2track import heading_fls
from it2track._limits import ResourceLimitError
from it2track.atomicfile import NotRegularFileError, atomic_open, atomic_write_text
from it2track.experiments.executors import (
    DaskExecutor,
    ExecutorError,
    InProcessExecutor,
    ProcessExecutor,
    make_executor,
)
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.fuzzy import Input, Triangle
from it2track.io import FisFormatError, load, loads, save
from it2track.paper import dead_zone_matched_fls, heading_fls_widths
from it2track.plant import (
    DifferentialDrive,
    HeadingNoise,
    MotorParams,
    RobotParams,
    continuous_rhs,
    held_sample_index,
    run_generator,
    standard_noise,
)
from it2track.tracking import (
    LoopConfig,
    RunTable,
    get_trajectory,
    load_waypoints_csv,
    simulate,
    simulate_metrics,
    straight,
)
from it2track.tracking.trajectories import WaypointTrajectory

F = heading_fls(0.2)
T1 = heading_fls(0.0)
PD = ControllerSpec(kind=ControllerKind.PD, kp=6.0)
FLC = ControllerSpec(kind=ControllerKind.FLC)
WAYPOINTS = "t,x,y\n0,0,0\n1,1,0\n2,2,0\n3,3,0\n"

Case = tuple[str, Callable[[dict[str, Path]], Any], type[BaseException], tuple[str, ...]]


def _cases() -> list[Case]:
    c: list[Case] = []

    def add(name: str, fn: Callable[[dict[str, Path]], Any], exc: type[BaseException],
            *needles: str) -> None:
        c.append((name, fn, exc, needles))

    # -- fuzzy systems: inputs a conversion would silently change ---------------------------
    add("fls-None", lambda p: F(None, 0.0), ValueError, "input 'e'", "None")
    add("fls-None-de", lambda p: F(0.0, None), ValueError, "input 'de'", "None")
    add("fls-str", lambda p: F("0.3", 0.0), ValueError, "input 'e'", "strings", "0.3")
    add("fls-bool", lambda p: F(True, 0.0), ValueError, "input 'e'", "booleans")
    add("fls-bool-array", lambda p: F(np.array([True, False]), 0.0), ValueError, "booleans")
    add("fls-complex", lambda p: F(0.1 + 1j, 0.0), ValueError, "input 'e'", "complex")
    add("fls-complex-array", lambda p: F(np.array([0.1 + 0j]), 0.0), ValueError, "complex")
    add("fls-masked", lambda p: F(np.ma.masked_array([0.1, 0.2], mask=[0, 1]), 0.0),
        ValueError, "input 'e'", "masked")
    add("fls-object", lambda p: F(object(), 0.0), ValueError, "input 'e'", "Python objects")
    add("fls-ragged", lambda p: F([[0.1], [0.1, 0.2]], 0.0), ValueError, "input 'e'",
        "not an array of numbers")
    add("fls-nan", lambda p: F(np.nan, 0.0), ValueError, "input 'e'", "NaN or inf")
    add("fls-inf-de", lambda p: F(0.0, np.inf), ValueError, "input 'de'", "NaN or inf")
    add("fls-nan-array", lambda p: F(np.array([0.0, np.nan]), 0.0), ValueError, "'e'", "NaN")
    add("fls-one-input", lambda p: F(0.0), ValueError, "takes 2 inputs", "got 1")
    add("fls-three-inputs", lambda p: F(0.0, 0.0, 0.0), ValueError, "takes 2 inputs", "got 3")
    add("fls-broadcast", lambda p: F(np.zeros(3), np.zeros(4)), ValueError, "broadcast",
        "(3,)", "(4,)")
    add("fls-evaluate-shape", lambda p: F.evaluate(np.zeros((3, 3))), ValueError,
        "(..., 2)", "(3, 3)")
    add("fls-evaluate-str", lambda p: F.evaluate("ab"), ValueError, "stacked inputs",
        "strings")
    add("fls-interval-None", lambda p: F.interval(None, 0.0), ValueError, "'e'", "None")
    add("fls-firing-str", lambda p: F.firing("x", 0.0), ValueError, "'e'", "strings")
    add("t1-complex", lambda p: T1(0.0, 1j), ValueError, "input 'de'", "complex")
    add("t1-masked", lambda p: T1(np.ma.masked_array([1.0], mask=[1]), 0.0), ValueError,
        "masked")
    # -- the paper's controller: FoU widths --------------------------------------------------
    add("fou-str", lambda p: heading_fls("0.2"), ValueError, "fou='0.2'", "real number")
    add("fou-bool", lambda p: heading_fls(True), ValueError, "fou=True", "real number")
    add("fou-None", lambda p: heading_fls(None), ValueError, "fou=None")
    add("fou-negative", lambda p: heading_fls(-0.1), ValueError, "fou=-0.1", "0 <= fou")
    add("fou-too-wide", lambda p: heading_fls(1.6), ValueError, "fou=1.6", "< 1.6")
    add("fou-nan", lambda p: heading_fls(float("nan")), ValueError, "fou=nan")
    add("fou-reducer-str", lambda p: heading_fls(0.2, reducer="km"), ValueError,
        "reducer='km'", "TypeReducer")
    add("fou-tnorm-str", lambda p: heading_fls(0.2, tnorm="min"), ValueError, "tnorm='min'")
    add("widths-two", lambda p: heading_fls_widths([0.1, 0.1], [0.1] * 3), ValueError,
        "e_widths", "3 widths")
    add("widths-str", lambda p: heading_fls_widths("abc", [0.1] * 3), ValueError,
        "e_widths='abc'")
    add("widths-bool", lambda p: heading_fls_widths([0.1, True, 0.1], [0.1] * 3), ValueError,
        "e_widths=True")
    add("widths-negative", lambda p: heading_fls_widths([0.1] * 3, [0.1, -1, 0.1]),
        ValueError, "de set Z", "-1")
    add("matched-bool", lambda p: dead_zone_matched_fls(False), ValueError, "fou=False")
    add("matched-too-wide", lambda p: dead_zone_matched_fls(2.0), ValueError, "fou=2.0")
    # -- plant -------------------------------------------------------------------------------
    add("motor-zero-R", lambda p: MotorParams(resistance=0), ValueError, "resistance", "0")
    add("motor-negative-L", lambda p: MotorParams(inductance=-1), ValueError, "inductance",
        "-1")
    add("motor-nan-J", lambda p: MotorParams(inertia=float("nan")), ValueError, "inertia",
        "nan")
    add("motor-str-b", lambda p: MotorParams(friction="1"), ValueError, "friction", "'1'")
    add("motor-bool-K", lambda p: MotorParams(torque_constant=True), ValueError,
        "torque_constant", "True")
    add("motor-inf-limit", lambda p: MotorParams(voltage_limit=float("inf")), ValueError,
        "voltage_limit", "inf")
    add("robot-zero-track", lambda p: RobotParams(half_track=0), ValueError, "half_track")
    add("robot-negative-radius", lambda p: RobotParams(wheel_radius=-1), ValueError,
        "wheel_radius", "-1")
    add("robot-motor-str", lambda p: RobotParams(motor="x"), ValueError, "motor", "'x'")
    add("robot-tiny-track", lambda p: RobotParams(half_track=1e-300), ValueError,
        "half_track=1e-300", "overflow")
    add("robot-huge-wheel", lambda p: RobotParams(wheel_radius=1e300), ValueError,
        "wheel_radius=1e+300", "[1e-06, 1e+06]")
    # Used to hang: the exact discretisation's panel count grows with ts * R / L.
    add("loop-inductance-1e-300",
        lambda p: LoopConfig(robot=RobotParams(motor=MotorParams(inductance=1e-300))),
        ValueError, "inductance=1e-300", "ts=0.01", "shorten ts")
    add("loop-inertia-1e-12",
        lambda p: LoopConfig(robot=RobotParams(motor=MotorParams(inertia=1e-12))),
        ValueError, "inertia=1e-12")
    add("drive-resistance-1e300",
        lambda p: DifferentialDrive(RobotParams(motor=MotorParams(resistance=1e300)), 0.01),
        ValueError, "resistance must be at most 1e+12 (SI units), got 1e+300")
    add("drive-zero-ts", lambda p: DifferentialDrive(RobotParams(), 0.0), ValueError,
        "ts", "0.0")
    add("drive-million-nodes",
        lambda p: DifferentialDrive(RobotParams(), 0.01, quadrature_nodes=1_000_000),
        ValueError, "quadrature_nodes", "1000000", "[1, 64]")
    add("drive-zero-nodes", lambda p: DifferentialDrive(RobotParams(), 0.01,
                                                        quadrature_nodes=0),
        ValueError, "quadrature_nodes", "0")
    add("drive-float-nodes", lambda p: DifferentialDrive(RobotParams(), 0.01,
                                                         quadrature_nodes=2.5),
        ValueError, "quadrature_nodes", "2.5")
    add("drive-step-shape", lambda p: DifferentialDrive(RobotParams(), 0.01).step(
        np.zeros((2, 3)), np.zeros((4, 3)), np.zeros((2, 3))), ValueError, "pose", "(3, B)")
    add("noise-negative", lambda p: HeadingNoise(std=-1.0), ValueError, "std", "-1.0")
    add("noise-1e308", lambda p: HeadingNoise(std=1e308), ValueError, "std", "1e+308",
        "1e+06")
    add("noise-zero-rate", lambda p: HeadingNoise(rate=0), ValueError, "rate", "0")
    add("noise-power-negative", lambda p: HeadingNoise.from_band_limited_power(-1, 0.01),
        ValueError, "power", "-1")
    add("noise-power-huge", lambda p: HeadingNoise.from_band_limited_power(1e300, 1e-6),
        ValueError, "std", "power")
    add("noise-sample-time-zero", lambda p: HeadingNoise.from_band_limited_power(0.1, 0),
        ValueError, "sample_time", "0")
    add("std-noise-seed", lambda p: standard_noise(-1, [0], 3), ValueError, "seed", "-1")
    add("std-noise-2d", lambda p: standard_noise(0, [[0]], 3), ValueError, "indices", "1-D")
    add("std-noise-negative-index", lambda p: standard_noise(0, [-1], 3), ValueError,
        "indices", "-1")
    add("held-negative-time", lambda p: held_sample_index([-1.0], 100.0), ValueError,
        "times")
    add("held-zero-rate", lambda p: held_sample_index([0.0], 0.0), ValueError, "rate", "0")
    add("rng-float-seed", lambda p: run_generator(1.5, 0), ValueError, "seed", "1.5")
    add("rhs-shape", lambda p: continuous_rhs(np.zeros(6), np.zeros(2), RobotParams()),
        ValueError, "state", "(..., 7)")
    # -- closed loop: sizes, seeds, noise levels ----------------------------------------------
    add("loop-duration-1e9", lambda p: LoopConfig(duration=1e9), ValueError,
        "duration=1000000000.0", "0 < x <= 3600 s")
    add("loop-duration-3601", lambda p: LoopConfig(duration=3601, ts=1.0), ValueError,
        "duration=3601", "0 < x <= 3600 s")
    add("loop-duration-nan", lambda p: LoopConfig(duration=float("nan")), ValueError,
        "duration=nan", "finite")
    add("loop-heading-1e308", lambda p: LoopConfig(start_pose=(0.0, 0.0, 1e308)), ValueError,
        "start_pose heading=1e+308", "radians")
    add("loop-heading-degrees", lambda p: LoopConfig(start_pose=(0.0, 0.0, 90.0)), ValueError,
        "start_pose heading=90.0", "6.283185307")
    add("loop-x-1e308", lambda p: LoopConfig(start_pose=(1e308, 0.0, 0.0)), ValueError,
        "start_pose x=1e+308", "1000000 m")
    add("loop-y-minus-1e7", lambda p: LoopConfig(start_pose=(0.0, -1e7, 0.0)), ValueError,
        "start_pose y=-10000000.0", "-1000000 <= x")
    add("input-universe-overflows", lambda p: Input("e", (-1e308, 1e308), [("a", Triangle(
        -1.0, 0.0, 1.0))]), ValueError, "input 'e'", "(-1e+308, 1e+308)", "finite width")
    add("loop-ts-1e-7", lambda p: LoopConfig(ts=1e-7), ResourceLimitError, "ts=1e-07",
        "memory")
    add("loop-inf-steps", lambda p: LoopConfig(duration=3600.0, ts=1e-300),
        ResourceLimitError, "duration=3600.0", "ts=1e-300", "control periods")
    add("loop-noise-rate-1e15", lambda p: LoopConfig(noise_rate=1e15), ResourceLimitError,
        "noise_rate=1000000000000000.0", "noise samples")
    add("loop-million-nodes", lambda p: LoopConfig(quadrature_nodes=1_000_000), ValueError,
        "quadrature_nodes=1000000", "[1, 64]")
    add("loop-zero-ts", lambda p: LoopConfig(ts=0), ValueError, "ts=0", "> 0")
    add("loop-negative-duration", lambda p: LoopConfig(duration=-1), ValueError,
        "duration=-1")
    add("loop-nan-duration", lambda p: LoopConfig(duration=float("nan")), ValueError,
        "duration=nan")
    add("loop-not-whole", lambda p: LoopConfig(ts=0.003), ValueError, "whole number",
        "ts=0.003")
    add("loop-negative-seed", lambda p: LoopConfig(seed=-1), ValueError, "seed=-1")
    add("loop-float-seed", lambda p: LoopConfig(seed=1.5), ValueError, "seed=1.5")
    add("loop-pose-short", lambda p: LoopConfig(start_pose=(0, 0)), ValueError,
        "start_pose=(0, 0)")
    add("loop-pose-str", lambda p: LoopConfig(start_pose="foo"), ValueError,
        "start_pose='foo'")
    add("loop-robot-str", lambda p: LoopConfig(robot="x"), ValueError, "robot='x'")
    add("loop-metric-start", lambda p: LoopConfig(metric_start=-1.0), ValueError,
        "metric_start=-1.0")
    add("loop-timing", lambda p: LoopConfig(desired_heading_pose="later"), ValueError,
        "desired_heading_pose='later'")
    add("runs-noise-1e308", lambda p: RunTable(0, 0, [1e308], 0), ValueError, "noise_std",
        "1e+308", "largest")
    add("runs-seed-22-digits", lambda p: RunTable(0, 0, 0.1, [10**22]), ValueError,
        "seed", str(10**22), "2**63 - 1")
    add("runs-seed-uint64", lambda p: RunTable(0, 0, 0.1, np.array([2**63], np.uint64)),
        ValueError, "seed", str(2**63), "2**63 - 1")
    add("runs-seed-negative", lambda p: RunTable(0, 0, 0.1, [-1]), ValueError, "seed", "-1")
    add("runs-seed-float", lambda p: RunTable(0, 0, 0.1, [1.5]), ValueError, "seed",
        "float64", "1.5")
    add("runs-controller-bool", lambda p: RunTable([True], 0, 0.1, 0), ValueError,
        "controller", "bool")
    add("runs-noise-complex", lambda p: RunTable(0, 0, [0.1 + 1j], 0), ValueError,
        "noise_std", "complex")
    add("runs-noise-masked", lambda p: RunTable(0, 0, np.ma.masked_array([0.1], mask=[1]), 0),
        ValueError, "noise_std", "masked")
    add("runs-noise-nan", lambda p: RunTable(0, 0, [np.nan], 0), ValueError, "noise_std",
        "nan")
    add("runs-noise-negative", lambda p: RunTable(0, 0, [-0.1], 0), ValueError, "noise_std",
        "-0.1")
    add("runs-noise-str", lambda p: RunTable(0, 0, ["a"], 0), ValueError, "noise_std",
        "'a'")
    add("runs-broadcast", lambda p: RunTable([0, 0], [0, 0, 0], 0.1, 0), ValueError,
        "broadcast", "(2,)", "(3,)")
    add("simulate-bare-controller",
        lambda p: simulate(FLC.build(), [straight()], RunTable(0, 0, 0.0, 0)), ValueError,
        "controllers", "list or tuple")
    add("simulate-runs-list", lambda p: simulate([FLC.build()], [straight()], [0, 0, 0.0, 0]),
        ValueError, "RunTable", "list")
    add("simulate-controller-index",
        lambda p: simulate([FLC.build()], [straight()], RunTable(3, 0, 0.0, 0)), ValueError,
        "controller 3", "only 1")
    add("simulate-trajectory-index",
        lambda p: simulate([FLC.build()], [straight()], RunTable(0, 2, 0.0, 0)), ValueError,
        "trajectory 2", "only 1")
    add("simulate-config-str",
        lambda p: simulate([FLC.build()], [straight()], RunTable(0, 0, 0.0, 0), "fast"),
        ValueError, "config", "LoopConfig", "str")
    add("simulate-trace-memory",
        lambda p: simulate([FLC.build()], [straight()], RunTable(np.zeros(2000, int), 0, 0.0,
                                                                  0),
                           LoopConfig(duration=3600.0, ts=0.001)),
        ResourceLimitError, "2000 run(s)", "3600000 periods", "time series", "simulate_metrics")
    add("simulate-metrics-batch-memory",
        lambda p: simulate_metrics([FLC.build()], [straight()],
                                   RunTable(np.zeros(2000, int), 0, 0.0, 0),
                                   LoopConfig(duration=3600.0, ts=0.001, noise_rate=1000.0),
                                   batch_size=10**9),
        ResourceLimitError, "2000 run(s)", "batches of 2000", "lower batch_size")
    add("simulate-metrics-batch-zero",
        lambda p: simulate_metrics([FLC.build()], [straight()], RunTable(0, 0, 0.0, 0),
                                   batch_size=0),
        ValueError, "batch_size=0")
    add("simulate-metrics-batch-bool",
        lambda p: simulate_metrics([FLC.build()], [straight()], RunTable(0, 0, 0.0, 0),
                                   batch_size=True),
        ValueError, "batch_size=True")
    # -- trajectories ------------------------------------------------------------------------
    add("traj-unknown", lambda p: get_trajectory("nope"), ValueError, "'nope'", "straight")
    add("traj-missing-csv", lambda p: get_trajectory(str(p["dir"] / "missing.csv")),
        ValueError, "missing.csv", "cannot read")
    add("traj-binary-csv", lambda p: load_waypoints_csv(p["binary.csv"]), ValueError,
        "binary.csv", "binary")
    add("traj-latin1-csv", lambda p: load_waypoints_csv(p["latin1.csv"]), ValueError,
        "latin1.csv", "UTF-8")
    add("traj-fifo-csv", lambda p: load_waypoints_csv(p["fifo.csv"]), ValueError, "fifo.csv",
        "FIFO")
    add("traj-dir-csv", lambda p: load_waypoints_csv(p["dir.csv"]), ValueError, "dir.csv",
        "directory")
    add("traj-zero-csv", lambda p: load_waypoints_csv(p["zero.csv"]), ValueError, "zero.csv",
        "character device")
    add("traj-huge-csv", lambda p: load_waypoints_csv(p["huge.csv"]), ValueError, "huge.csv",
        "larger than")
    add("traj-no-header", lambda p: load_waypoints_csv(p["noheader.csv"]), ValueError,
        "noheader.csv:1", "lacks column")
    add("traj-not-increasing", lambda p: load_waypoints_csv(p["backwards.csv"]), ValueError,
        "backwards.csv:3", "does not increase")
    add("traj-nan", lambda p: load_waypoints_csv(p["nan.csv"]), ValueError, "nan.csv:2",
        "non-finite")
    add("traj-empty", lambda p: load_waypoints_csv(p["empty.csv"]), ValueError, "empty.csv",
        "empty")
    add("traj-too-few", lambda p: load_waypoints_csv(p["short.csv"]), ValueError,
        "short.csv", "at least 4")
    add("traj-kind", lambda p: WaypointTrajectory("w", [0, 1], [[0, 0], [1, 1]], "quad"),
        ValueError, "kind='quad'")
    # -- controller specs: nothing silently dropped -------------------------------------------
    add("spec-kind-str", lambda p: ControllerSpec(kind="flc"), ValueError, "kind='flc'")
    add("spec-pd-no-gains", lambda p: ControllerSpec(kind=ControllerKind.PD), ValueError,
        "kind 'pd'", "kp > 0", "kp=0.0")
    add("spec-pd-negative-kp", lambda p: ControllerSpec(kind=ControllerKind.PD, kp=-1.0),
        ValueError, "kp=-1.0")
    add("spec-pd-negative-kd", lambda p: ControllerSpec(kind=ControllerKind.PD, kp=1.0,
                                                        kd=-0.5),
        ValueError, "kd=-0.5", ">= 0")
    add("spec-pd-negative-tf", lambda p: ControllerSpec(kind=ControllerKind.PD, kp=1.0,
                                                        tf=-1.0),
        ValueError, "tf=-1.0")
    add("spec-pd-with-fou", lambda p: ControllerSpec(kind=ControllerKind.PD, kp=1.0, fou=0.2),
        ValueError, "fou=0.2", "does not apply to kind 'pd'")
    add("spec-pd-with-ke", lambda p: ControllerSpec(kind=ControllerKind.PD, kp=1.0, ke=2.0),
        ValueError, "ke=2.0", "kind 'pd'")
    add("spec-file-with-fou", lambda p: ControllerSpec(kind=ControllerKind.FILE, path="a.t2fis",
                                                       fou=0.2),
        ValueError, "fou=0.2", "kind 'file'")
    add("spec-file-with-reducer",
        lambda p: ControllerSpec(kind=ControllerKind.FILE, path="a.t2fis", reducer="km"),
        ValueError, "reducer='km'", "kind 'file'")
    add("spec-file-with-tnorm",
        lambda p: ControllerSpec(kind=ControllerKind.FILE, path="a.t2fis", tnorm="min"),
        ValueError, "tnorm='min'", "kind 'file'")
    add("spec-flc-with-kp", lambda p: ControllerSpec(kind=ControllerKind.FLC, kp=3.0),
        ValueError, "kp=3.0", "kind 'flc'")
    add("spec-t1-with-reducer",
        lambda p: ControllerSpec(kind=ControllerKind.T1_MATCHED, fou=0.2, reducer="km"),
        ValueError, "reducer='km'", "kind 't1-matched'")
    add("spec-it2-zero-fou", lambda p: ControllerSpec(kind=ControllerKind.IT2), ValueError,
        "fou > 0")
    add("spec-fou-2", lambda p: ControllerSpec(kind=ControllerKind.IT2, fou=2.0), ValueError,
        "fou=2.0")
    add("spec-reducer-unknown", lambda p: ControllerSpec(kind=ControllerKind.IT2, fou=0.2,
                                                         reducer="foo"),
        ValueError, "foo")
    add("spec-tnorm-unknown", lambda p: ControllerSpec(kind=ControllerKind.FLC, tnorm="max"),
        ValueError, "max")
    add("spec-ke-zero", lambda p: ControllerSpec(kind=ControllerKind.FLC, ke=0.0), ValueError,
        "ke=0.0", "> 0")
    add("spec-ke-nan", lambda p: ControllerSpec(kind=ControllerKind.FLC, ke=float("nan")),
        ValueError, "ke=nan")
    add("spec-kde-negative", lambda p: ControllerSpec(kind=ControllerKind.FLC, kde=-1.0),
        ValueError, "kde=-1.0")
    add("spec-ke-str", lambda p: ControllerSpec(kind=ControllerKind.FLC, ke="1"), ValueError,
        "ke='1'", "number")
    add("spec-file-no-path", lambda p: ControllerSpec(kind=ControllerKind.FILE), ValueError,
        "needs a path")
    add("spec-label-int", lambda p: ControllerSpec(kind=ControllerKind.FLC, label=5),
        ValueError, "label")
    add("spec-file-fifo",
        lambda p: ControllerSpec(kind=ControllerKind.FILE, path=str(p["fifo.t2fis"])).build(),
        FisFormatError, "fifo.t2fis", "FIFO")
    # -- fuzzy-system files -------------------------------------------------------------------
    add("load-missing", lambda p: load(p["dir"] / "missing.toml"), FileNotFoundError,
        "missing.toml")
    add("load-suffix", lambda p: load(p["dir"] / "x.json"), ValueError, "x.json", "suffix")
    add("load-binary-toml", lambda p: load(p["binary.toml"]), FisFormatError, "binary.toml",
        "binary")
    add("load-binary-fis", lambda p: load(p["binary.fis"]), FisFormatError, "binary.fis",
        "binary")
    add("load-binary-t2fis", lambda p: load(p["binary.t2fis"]), FisFormatError,
        "binary.t2fis", "binary")
    add("load-latin1-toml", lambda p: load(p["latin1.toml"]), FisFormatError, "latin1.toml",
        "UTF-8")
    add("load-fifo", lambda p: load(p["fifo.t2fis"]), FisFormatError, "fifo.t2fis", "FIFO")
    add("load-dir", lambda p: load(p["dir.fis"]), FisFormatError, "dir.fis", "directory")
    add("load-dev-zero", lambda p: load(p["zero.toml"]), FisFormatError, "zero.toml",
        "character device")
    add("load-huge", lambda p: load(p["huge.t2fis"]), FisFormatError, "huge.t2fis",
        "larger than")
    add("load-empty-t2fis", lambda p: load(p["empty.t2fis"]), FisFormatError, "empty.t2fis")
    add("loads-garbage", lambda p: loads("garbage", "t2fis"), FisFormatError, "<string>")
    add("loads-format", lambda p: loads("x", "xml"), ValueError, "'xml'")
    add("save-to-dir", lambda p: save(F, p["dir.fis"]), NotRegularFileError, "dir.fis",
        "directory")
    add("save-to-fifo", lambda p: save(F, p["fifo.t2fis"]), NotRegularFileError, "fifo.t2fis",
        "FIFO")
    add("save-to-device-link", lambda p: save(F, p["zero.toml"]), NotRegularFileError,
        "zero.toml", "symbolic link")
    add("save-empty-path", lambda p: save(F, ""), ValueError, "suffix")
    # -- executors and atomic writes -----------------------------------------------------------
    add("executor-negative-workers", lambda p: make_executor(workers=-1), ExecutorError,
        "workers=-1")
    add("executor-bool-workers", lambda p: make_executor(workers=True), ExecutorError,
        "workers=True")
    add("executor-zero-processes", lambda p: ProcessExecutor(0), ExecutorError, "workers=0")
    add("executor-dask-no-port", lambda p: DaskExecutor("foo"), ExecutorError, "'foo'",
        "port")
    add("executor-dask-port-0", lambda p: DaskExecutor("tcp://h:0"), ExecutorError, "port 0")
    add("executor-dask-timeout", lambda p: DaskExecutor("tcp://h:1", worker_timeout=0),
        ExecutorError, "worker_timeout=0")
    add("executor-max-pending",
        lambda p: list(InProcessExecutor().imap_unordered(abs, [1], max_pending=0)),
        ValueError, "max_pending=0")
    add("atomic-append-mode", lambda p: atomic_open(p["dir"] / "a.txt", "a").__enter__(),
        ValueError, "mode='a'")
    add("atomic-to-dir", lambda p: atomic_write_text(p["dir.fis"], "x"), NotRegularFileError,
        "directory")
    add("atomic-empty-path", lambda p: atomic_write_text("", "x"), ValueError, "empty")
    return c


CASES = _cases()


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    d = tmp_path_factory.mktemp("hostile-api")
    p: dict[str, Path] = {"dir": d}
    for suffix in ("csv", "toml", "fis", "t2fis"):
        (d / f"binary.{suffix}").write_bytes(BINARY)
        p[f"binary.{suffix}"] = d / f"binary.{suffix}"
        p[f"fifo.{suffix}"] = make_fifo(d / f"fifo.{suffix}")
        (d / f"dir.{suffix}").mkdir()
        p[f"dir.{suffix}"] = d / f"dir.{suffix}"
        p[f"zero.{suffix}"] = make_device_link(d / f"zero.{suffix}")
        p[f"huge.{suffix}"] = make_sparse(d / f"huge.{suffix}", (64 << 20) + 1)
        (d / f"empty.{suffix}").write_bytes(b"")
        p[f"empty.{suffix}"] = d / f"empty.{suffix}"
    (d / "latin1.csv").write_bytes(b"t,x,y\n0,0,0 # caf\xe9\n")
    (d / "latin1.toml").write_bytes(b'name = "caf\xe9"\n')
    (d / "noheader.csv").write_text("a,b,c\n0,0,0\n")
    (d / "backwards.csv").write_text("t,x,y\n0,0,0\n0,1,1\n")
    (d / "nan.csv").write_text("t,x,y\n0,nan,0\n")
    (d / "short.csv").write_text("t,x,y\n0,0,0\n1,1,1\n")
    for name in ("latin1.csv", "latin1.toml", "noheader.csv", "backwards.csv", "nan.csv",
                 "short.csv"):
        p[name] = d / name
    return p


@pytest.mark.parametrize(("fn", "exc", "needles"), [c[1:] for c in CASES],
                         ids=[c[0] for c in CASES])
def test_bad_api_input_is_a_clear_error(
    files: dict[str, Path], fn: Callable[[dict[str, Path]], Any],
    exc: type[BaseException], needles: tuple[str, ...],
) -> None:
    before = sorted(p.name for p in files["dir"].iterdir())
    with pytest.raises(Exception) as info:  # the exact type is checked below
        fn(files)
    assert_clean_error(info.value, exc, *needles)
    assert sorted(p.name for p in files["dir"].iterdir()) == before, "a file was written"


def test_fuzzy_input_checks_keep_what_is_valid() -> None:
    """The checks refuse only what a conversion would change: ints, floats, NumPy scalars,
    unmasked masked arrays and int arrays still evaluate, to the same numbers."""
    ref = F(0.5, -0.25)
    assert F(np.float32(0.5), np.int64(0)) == F(0.5, 0.0)
    assert F(np.array([0.5]), [-0.25])[0] == ref
    assert F(np.ma.masked_array([0.5], mask=[0]), -0.25)[0] == ref
    assert F(np.array([1]), np.array([0], np.uint8))[0] == F(1.0, 0.0)
    assert heading_fls(np.float64(0.2))(0.5, -0.25) == ref
    assert it2track.heading_fls(0)(0.5, 0.0) == T1(0.5, 0.0)

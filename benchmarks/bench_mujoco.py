"""The MuJoCo robot: its agreement with the kinematic robot, what its surfaces do, and its speed.

Prints, in one run:

0. **model facts**: the motor bench (chassis fixed in the air) against the exact
   zero-order-hold motor over 2 s of random voltages (largest wheel-speed error over the speed
   range), with the rotor alone and with the default wheel; the time constant with which each
   robot reaches a speed, ``(J + J_c) R / (R b + K^2)``; the steady creep ``1 - v / (r omega)``
   of the no-slip robot driving straight at 6 V; the wheels' slip after 0.2 s at 12 V from rest
   on each surface;
1. **no-slip agreement**: the paper's FLC and IT2FLC (FoU 0.2), noise-free, on the three paths,
   on the kinematic robot and on the MuJoCo robot in its no-slip limit
   (``PhysicsParams.no_slip_limit()``): every heading-error integral (IAE, ITAE, ISE, ITSE),
   and the largest relative difference; then against the kinematic robot whose motor inertia
   J is raised by the inertia the MuJoCo robot's body reflects onto each motor (the mean of
   ``PhysicsParams.reflected_inertia``), which explains most of the difference; and the same
   with the default robot's tyre relaxation (``friction_timeconst`` 0.02 s) instead of the
   rigid tyre's 0.002 s;
2. **surfaces**: the same runs on the default robot on dry, wet and icy ground: integrals,
   final distance to the reference point, and the wheels' mean slip (``1 - v / (r omega)`` of
   the mean of the two wheels' rolling speeds, over the samples where they roll faster than
   0.05 m/s); then, on dry and icy ground, the contact artefact of a rigid grip: the largest
   rise of the axle above its rest height and the fraction of period ends with both tyres
   touching, with the default tyre relaxation (``friction_timeconst`` 0.02 s) and with 0.002 s,
   and the largest relative change of the integrals between the two;
3. **speed**: wall-clock and process-CPU seconds per simulated run-second, the median of
   ``--repeats`` timed repeats of 6 noisy runs (10 s each unless ``--duration``) with 1 and 2
   threads, against the numpy engine on the kinematic robot and the compiled engine, measured
   in the same process; the load average.

Run from the repository root (needs ``pip install 'it2track[mujoco]'``)::

    .venv/bin/python benchmarks/bench_mujoco.py             # about a minute
    .venv/bin/python benchmarks/bench_mujoco.py --quick     # smoke test
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import statistics
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

from it2track.paper import heading_fls
from it2track.plant import MotorParams, RobotParams
from it2track.plant.mujoco_model import SURFACES, PhysicsParams
from it2track.plant.mujoco_plant import MujocoSpec
from it2track.plant.mujoco_robot import MujocoRobot
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    get_trajectory,
    run_grid,
    simulate,
    simulate_metrics,
)
from it2track.tracking.simulate import _Engine

INTEGRALS = ("IAE", "ITAE", "ISE", "ITSE")
PATHS = [get_trajectory(n) for n in ("straight", "curved", "sinusoidal")]
CONTROLLERS = [FuzzyHeadingController(fls=heading_fls(0.2), name="IT2FLC 0.2"),
               FuzzyHeadingController(fls=heading_fls(0.0), name="FLC")]


def integrals(config: LoopConfig) -> dict[str, np.ndarray]:
    runs = run_grid(len(CONTROLLERS), len(PATHS), [0.0], 1)
    return simulate_metrics(CONTROLLERS, PATHS, runs, config)


def largest_relative(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> float:
    """Largest |a - b| / |b| over the integrals of the bent paths (straight: both ~0)."""
    bent = np.array([t != 0 for _ in CONTROLLERS for t in range(len(PATHS))])
    return max(float(np.max(np.abs(a[k][bent] - b[k][bent]) / np.abs(b[k][bent])))
               for k in INTEGRALS)


def table(label: str, values: dict[str, np.ndarray]) -> None:
    i = 0
    for c in CONTROLLERS:
        for path in PATHS:
            cells = "  ".join(f"{k} {values[k][i]:9.5f}" for k in INTEGRALS)
            print(f"  {label:24s} {c.name:10s} {path.name:10s} {cells}")
            i += 1


def bench_error(physics: PhysicsParams) -> float:
    robot = RobotParams()
    bench = MujocoRobot(robot, physics, 0.01, bench=True)
    exact = dataclasses.replace(robot.motor, inertia=robot.motor.inertia
                                + physics.wheel_inertia(robot)[0])
    assert isinstance(exact, MotorParams)
    ad, bd = exact.discrete_matrices(0.01)
    volts = np.random.default_rng(7).uniform(-12.0, 12.0, size=(200, 2))
    x = np.zeros((2, 2))
    err = span = 0.0
    with bench.batch(np.zeros((3, 1)), threads=1) as runs:
        for v in volts:
            runs.step(v.reshape(2, 1))
            x = ad @ x + np.outer(bd, v)
            err = max(err, float(np.max(np.abs(runs.wheels[[1, 3], 0] - x[1]))))
            span = max(span, float(np.max(np.abs(x[1]))))
    return err / span


def drive(physics: PhysicsParams, volts: float, periods: int) -> float:
    """``1 - v / (r omega)`` after driving straight at ``volts`` from rest."""
    robot = RobotParams()
    with MujocoRobot(robot, physics, 0.01).batch(np.zeros((3, 1)), threads=1) as runs:
        for _ in range(periods):
            runs.step(np.full((2, 1), volts))
        v, _ = runs.body_velocity()
        return float(1.0 - v[0] / (robot.wheel_radius * runs.wheels[1, 0]))


def facts() -> None:
    print("0. model facts")
    robot = RobotParams()
    m = robot.motor
    print(f"  motor bench vs exact motor, rotor alone:   "
          f"{bench_error(PhysicsParams(wheel_mass=1e-8)):.2e} of the speed range")
    print(f"  motor bench vs exact motor, default wheel: "
          f"{bench_error(PhysicsParams()):.2e} of the speed range")
    gain = m.resistance / (m.resistance * m.friction + m.torque_constant ** 2)
    print(f"  speed time constant: kinematic robot {m.inertia * gain:.3f} s, default robot "
          f"{(m.inertia + PhysicsParams().reflected_inertia(robot)[0]) * gain:.3f} s")
    print(f"  no-slip robot, straight at 6 V for 2 s: 1 - v/(r omega) = "
          f"{drive(PhysicsParams.no_slip_limit(), 6.0, 200):.2e}")
    for name in SURFACES:
        print(f"  default robot on {name} ground, 0.2 s at 12 V from rest: wheel slip "
              f"{drive(PhysicsParams(surface=name), 12.0, 20):.3f}")


def agreement(duration: float) -> None:
    print("\n1. no-slip agreement (noise-free, FLC and IT2FLC 0.2, three paths, "
          f"{duration:g} s)")
    robot = RobotParams()
    base = LoopConfig(duration=duration)
    physics = PhysicsParams.no_slip_limit(robot)
    kin = integrals(base)
    mj = integrals(dataclasses.replace(base, plant=MujocoSpec(physics=physics)))
    table("kinematic", kin)
    table("MuJoCo no-slip limit", mj)
    straight = max(float(np.max(np.abs(mj[k][[0, 3]]))) for k in INTEGRALS)
    print(f"  straight path: largest |integral| on the MuJoCo robot {straight:.2e} "
          "(kinematic: 0 exactly)")
    common, differential = physics.reflected_inertia(robot)
    extra = (common + differential) / 2
    loaded = dataclasses.replace(robot, motor=dataclasses.replace(
        robot.motor, inertia=robot.motor.inertia + extra))
    kin_loaded = integrals(dataclasses.replace(base, robot=loaded))
    soft = dataclasses.replace(physics, friction_timeconst=0.02)
    mj_soft = integrals(dataclasses.replace(base, plant=MujocoSpec(physics=soft)))
    print(f"  reflected inertia per motor: straight {common:.3e}, turning {differential:.3e} "
          f"kg m^2 (J = {robot.motor.inertia:g}; mean {extra / robot.motor.inertia:.2%} of J)")
    print(f"  largest relative difference, MuJoCo vs kinematic:            "
          f"{largest_relative(mj, kin):.3%}")
    print(f"  largest relative difference, MuJoCo vs kinematic, J + mean:  "
          f"{largest_relative(mj, kin_loaded):.3%}")
    print(f"  largest relative difference, friction_timeconst 0.02 s:      "
          f"{largest_relative(mj_soft, kin):.3%}")


def surfaces(duration: float) -> None:
    print(f"\n2. the default robot on each surface (noise-free, {duration:g} s)")
    robot = RobotParams()
    base = LoopConfig(duration=duration)
    runs = run_grid(len(CONTROLLERS), len(PATHS), [0.0], 1)
    print(f"  default robot: {PhysicsParams()}")
    for name in ("kinematic", *SURFACES):
        config = base if name == "kinematic" else dataclasses.replace(
            base, plant=MujocoSpec(physics=PhysicsParams(surface=name)))
        trace = simulate(CONTROLLERS, PATHS, runs, config)
        rolling = robot.wheel_radius * (trace["omega_right"] + trace["omega_left"]) / 2
        moving = np.abs(rolling) > 0.05
        slip = 1.0 - trace["v"] / np.where(moving, rolling, 1.0)
        i = 0
        for c in CONTROLLERS:
            for path in PATHS:
                m = {k: float(v[i]) for k, v in trace.metrics.items()}
                s = float(np.mean(slip[i][moving[i]])) if moving[i].any() else float("nan")
                print(f"  {name:9s} {c.name:10s} {path.name:10s} IAE {m['IAE']:7.4f}  "
                      f"ISE {m['ISE']:7.4f}  final distance {m['pos_final']:7.3f} m  "
                      f"mean slip {s:6.3f}")
                i += 1
    contact_artefact(duration)


@dataclasses.dataclass(frozen=True)
class _Watched:
    """A MuJoCo plant spec whose batches record, after every period, the axle's rise above its
    rest height and whether both tyres touch (for the contact-artefact figures)."""

    spec: MujocoSpec
    log: list = dataclasses.field(default_factory=list, compare=False)
    kind = "mujoco"

    def build(self, *, ts, robot):
        plant = self.spec.build(ts=ts, robot=robot)
        log, step = self.log, plant.step
        z0 = plant.mujoco_robot.rest_qpos[2]
        tyres = {plant.mujoco_robot.model.geom(n).id for n in ("tyre_right", "tyre_left")}

        def watched(state, u, t):
            state = step(state, u, t)
            for j in range(state.n):
                d = state.data(j)
                touching = {int(d.contact[c].geom2) for c in range(d.ncon)} >= tyres
                log.append((float(d.qpos[2]) - z0, touching))
            return state

        plant.step = watched
        return plant

    def to_dict(self):
        return self.spec.to_dict()


def contact_artefact(duration: float) -> None:
    runs = run_grid(len(CONTROLLERS), len(PATHS), [0.0], 1)
    for surface in ("dry", "icy"):
        results = {}
        for tc in (0.02, 0.002):
            watched = _Watched(MujocoSpec(physics=PhysicsParams(surface=surface,
                                                                friction_timeconst=tc)))
            metrics = simulate_metrics(CONTROLLERS, PATHS, runs,
                                       LoopConfig(duration=duration, plant=watched))
            rise = max(r for r, _ in watched.log)
            touching = float(np.mean([t for _, t in watched.log]))
            results[tc] = metrics
            print(f"  {surface:4s} friction_timeconst {tc:5.3f} s: axle rises up to "
                  f"{rise * 1e3:6.1f} mm, both tyres touch at {touching:.0%} of period ends")
        change = max(float(np.max(np.abs(results[0.002][k] - results[0.02][k])
                                  / np.maximum(np.abs(results[0.02][k]), 1e-12)))
                     for k in INTEGRALS)
        print(f"  {surface:4s} largest relative change of an integral between the two: "
              f"{change:.2%}")


def timed(fn, repeats: int) -> tuple[float, float]:
    wall, cpu = [], []
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - w0)
        cpu.append(time.process_time() - c0)
    return statistics.median(wall), statistics.median(cpu)


def speed(duration: float, repeats: int) -> None:
    print(f"\n3. speed (6 runs of {duration:g} s, sigma 0.05 rad, median of {repeats})")
    runs = run_grid(len(CONTROLLERS), len(PATHS), [0.05], 1)
    run_seconds = len(runs) * duration
    kin = LoopConfig(duration=duration)
    simulate_metrics(CONTROLLERS, PATHS, runs, kin)  # compile / load the compiled engine
    engine = _Engine(PATHS, kin)
    rows = [("kinematic, compiled engine",
             lambda: simulate_metrics(CONTROLLERS, PATHS, runs, kin)),
            ("kinematic, numpy engine",
             lambda: engine.run(CONTROLLERS, runs, record=False))]
    for threads in (1, 2):
        config = dataclasses.replace(kin, plant=MujocoSpec(threads=threads))
        simulate_metrics(CONTROLLERS, PATHS, runs.take(slice(0, 1)),
                         dataclasses.replace(config, duration=0.1))  # build the model once
        rows.append((f"MuJoCo, {threads} thread(s)",
                     lambda c=config: simulate_metrics(CONTROLLERS, PATHS, runs, c)))
    measured = [(label, *timed(fn, repeats)) for label, fn in rows]
    compiled_cpu, numpy_cpu = measured[0][2], measured[1][2]
    for label, wall, cpu in measured:
        print(f"  {label:28s} wall {wall / run_seconds * 1e3:8.2f} ms  "
              f"CPU {cpu / run_seconds * 1e3:8.2f} ms per run-second  (CPU "
              f"{cpu / numpy_cpu:5.2f}x the numpy engine's, {cpu / compiled_cpu:6.0f}x the "
              "compiled engine's)")
    physics = PhysicsParams()
    steps = round(0.01 / physics.max_timestep)
    print(f"  ({steps} MuJoCo steps per 10 ms period; load average "
          f"{', '.join(f'{x:.2f}' for x in os.getloadavg())}; "
          f"{len(os.sched_getaffinity(0))} CPUs available)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="short runs, one repeat")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--duration", type=float, default=10.0)
    args = parser.parse_args()
    duration = 1.0 if args.quick else args.duration
    repeats = 1 if args.quick else args.repeats
    facts()
    agreement(duration)
    surfaces(duration)
    speed(duration, repeats)


if __name__ == "__main__":
    main()

"""What a plant costs in the closed loop: the robot on each engine and the other plant families.

Prints, for each case, the median over ``--repeats`` of the wall-clock and process CPU time of
one ``simulate_metrics`` call and the run-steps/s it makes (a run-step is one control period of
one run); the paper's IT2FLC (FoU 0.2), noise sigma = 0.05, 1000 periods per run:

1. the paper's kinematic robot on the compiled engine (``LoopConfig.plant = None``);
2. the same robot through the plant protocol on the numpy engine (a robot plant that is not the
   built-in one: the path any other robot, e.g. the MuJoCo one, takes), and the ratio 2/1;
3. a linear plant (the paper's DC motor, voltage -> speed, ``LinearSpec``) tracking a step
   (the reference task, numpy engine), as a fuzzy PI;
4. the same motor as a continuous python-control ``nlsys`` (``solve_ivp`` per run and period),
   on fewer runs (it is meant for small batches), if python-control is installed.

Run from the repository root::

    .venv/bin/python benchmarks/bench_plants.py            # a minute or two
    .venv/bin/python benchmarks/bench_plants.py --quick    # smoke test
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

from it2track.paper import heading_fls
from it2track.plant import RobotParams
from it2track.plant.kinematic import KinematicPlant
from it2track.plant.linear import LinearSpec
from it2track.tracking import (
    FuzzyHeadingController,
    IncrementalController,
    LoopConfig,
    RunTable,
    StepReference,
    simulate_metrics,
    straight,
)

SIGMA = 0.05
R, L, J, B, K = 5.0, 0.0054, 0.00015, 0.0001, 0.1  # the paper's Table 3


class _ProtocolRobot:
    """The kinematic robot behind the plant protocol only (so the numpy engine steps it)."""

    def __init__(self, robot: RobotParams, ts: float) -> None:
        self.inner = KinematicPlant(robot, ts)
        self.ts, self.input_limits = ts, self.inner.input_limits
        self.input_names, self.output_names = self.inner.input_names, self.inner.output_names

    def initial_state(self, n: int, pose: Any = None) -> Any:
        return self.inner.initial_state(n, pose)

    def step(self, state: Any, u: np.ndarray, t: float) -> Any:
        return self.inner.step(state, u, t)

    def outputs(self, state: Any) -> np.ndarray:
        return self.inner.outputs(state)


@dataclass(frozen=True)
class ProtocolRobotSpec:
    kind: str = "protocol-robot"

    def build(self, *, ts: float, robot: RobotParams) -> _ProtocolRobot:
        return _ProtocolRobot(robot, ts)

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind}


@dataclass
class Row:
    case: str
    runs: int
    wall: float
    cpu: float

    @property
    def rate(self) -> float:
        return self.runs * 1000 / self.wall / 1e6


def timed(case: str, fn: Callable[[], object], runs: int, repeats: int) -> Row:
    fn()  # warm caches (compiled kernels, plant maps)
    walls, cpus = [], []
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        cpus.append(time.process_time() - c0)
        walls.append(time.perf_counter() - w0)
    return Row(case, runs, statistics.median(walls), statistics.median(cpus))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer runs and repeats")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    repeats = 2 if args.quick else args.repeats
    n_robot = 200 if args.quick else 1000
    n_nl = 2 if args.quick else 8

    fuzzy = FuzzyHeadingController(fls=heading_fls(0.2))
    robot_runs = RunTable(0, 0, SIGMA, np.arange(n_robot))
    rows = [
        timed("robot, compiled engine (plant=None)",
              lambda: simulate_metrics([fuzzy], [straight()], robot_runs, LoopConfig()),
              n_robot, repeats),
        timed("robot through the plant protocol, numpy engine",
              lambda: simulate_metrics([fuzzy], [straight()], robot_runs,
                                       LoopConfig(plant=ProtocolRobotSpec())),
              n_robot, repeats),
    ]  # fmt: skip
    pi = IncrementalController(inner=FuzzyHeadingController(fls=heading_fls(0.2), ke=1 / 20,
                                                            kde=1 / 2), gain=0.2)
    motor = LinearSpec.from_tf([K], [J * L, J * R + B * L, B * R + K * K],
                               input_limits=[(-12.0, 12.0)])
    cfg = LoopConfig(duration=1.0, ts=0.001, plant=motor)
    step = [StepReference(amplitude=60.0)]
    rows.append(timed("DC motor LinearSpec, reference task (fuzzy PI)",
                      lambda: simulate_metrics([pi], step, RunTable(0, 0, SIGMA,
                                                                    np.arange(n_robot)), cfg),
                      n_robot, repeats))  # fmt: skip
    try:
        import control as ct
    except ImportError:
        ct = None
    if ct is not None:
        from it2track.plant.control import from_control

        a = np.array([[-R / L, -K / L], [K / J, -B / J]])
        bvec = np.array([1 / L, 0.0])
        nl = ct.nlsys(lambda t, x, u, p: a @ x + bvec * u[0], lambda t, x, u, p: x[1:],
                      states=2, inputs=1, outputs=1, name="motor")
        nl_cfg = LoopConfig(duration=1.0, ts=0.001,
                            plant=from_control(nl, input_limits=[(-12, 12)], method="LSODA"))
        rows.append(timed("DC motor python-control nlsys (LSODA per run and period)",
                          lambda: simulate_metrics([pi], step, RunTable(0, 0, SIGMA,
                                                                        np.arange(n_nl)),
                                                   nl_cfg),
                          n_nl, max(1, repeats // 2)))  # fmt: skip
    print(f"Each run: 1000 control periods; IT2FLC FoU 0.2, sigma = {SIGMA}. "
          f"Times: median of {repeats} repeats.")
    print("| case | runs | wall (s) | CPU (s) | run-steps/s (wall) |")
    print("|---|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r.case} | {r.runs} | {r.wall:.3f} | {r.cpu:.3f} | {r.rate:.3g} M |")
    print(f"Protocol path / compiled engine, robot: {rows[1].wall / rows[0].wall:.1f}x the "
          f"wall time, {rows[1].cpu / rows[0].cpu:.1f}x the CPU time.")
    print(f"Load average at the end: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print(f"Command: {sys.executable} {' '.join(sys.argv)}")


if __name__ == "__main__":
    main()

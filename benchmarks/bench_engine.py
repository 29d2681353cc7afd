"""The compiled engine against the numpy engine, side by side, in one run (issue #12).

Prints, each figure the median of ``--repeats`` timed repeats (wall clock and process CPU time,
which counts every thread of the process):

1. closed loop: run-steps/s of the numpy engine (the reference, ``_Engine.run``) and of the
   compiled engine (``simulate_metrics``) on the same runs (the paper's IT2FLC, FoU 0.2,
   sigma = 0.05 rad, 10 s at 100 Hz), and their ratio; the compiled engine with 1 and with 2
   threads (``numba.set_num_threads``);
2. JIT: the first call in a fresh process with an empty cache (``NUMBA_CACHE_DIR`` a new
   directory: compiles) and in a second fresh process with that cache (loads);
3. memory: peak resident size (``VmHWM``) of a fresh process running ``simulate_metrics`` on
   growing numbers of runs (flat: runs stream through in chunks);
4. fuzzy batch: samples/s of the numpy evaluation (``_prepare`` + ``_interval_blocks``, what
   ``fls(e, de)`` did before) and of the compiled one (``fls(e, de)``) at 10^3 and 10^6
   samples for every reducer, and their ratio;
5. the scalar call ``fls(0.3, -0.1)`` in microseconds, compiled and the numpy fast path.

Targets (issue #12): closed loop >= 10x, fuzzy batch >= 5x (exhaustive) and >= 3x (every exact
reducer) at 10^6, scalar <= 2 us. Run from the repository root::

    .venv/bin/python benchmarks/bench_engine.py            # a few minutes
    .venv/bin/python benchmarks/bench_engine.py --quick    # smoke test
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numba
import numpy as np

from it2track.fuzzy import EIASC, EKM, EXHAUSTIVE, KM, NIE_TAN, WU_MENDEL
from it2track.paper import heading_fls
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    RunTable,
    simulate_metrics,
    straight,
)
from it2track.tracking.simulate import _Engine

SIGMA = 0.05
REDUCERS = (KM, EKM, EIASC, EXHAUSTIVE, NIE_TAN, WU_MENDEL)

_CHILD_JIT = """
import time
t0 = time.perf_counter()
import numpy as np
from it2track.paper import heading_fls
from it2track.tracking import FuzzyHeadingController, LoopConfig, RunTable, simulate_metrics
from it2track.tracking import straight
t1 = time.perf_counter()
simulate_metrics([FuzzyHeadingController(fls=heading_fls(0.2))], [straight()],
                 RunTable(0, 0, 0.05, np.arange(4)), LoopConfig(duration=0.1))
t2 = time.perf_counter()
fls = heading_fls(0.2)
fls(0.3, -0.1)
t3 = time.perf_counter()
fls(np.zeros(20000), np.zeros(20000))
t4 = time.perf_counter()
print(t1 - t0, t2 - t1, t3 - t2, t4 - t3)
"""

_CHILD_MEMORY = """
import sys
import numpy as np
from it2track.paper import heading_fls
from it2track.tracking import FuzzyHeadingController, LoopConfig, RunTable, simulate_metrics
from it2track.tracking import straight
n = int(sys.argv[1])
simulate_metrics([FuzzyHeadingController(fls=heading_fls(0.2))], [straight()],
                 RunTable(0, 0, 0.05, np.arange(n)), LoopConfig(duration=2.0))
with open("/proc/self/status") as f:
    print(next(int(line.split()[1]) for line in f if line.startswith("VmHWM")))
"""


def timed(fn: Callable[[], object], repeats: int) -> tuple[float, float]:
    """Median wall and CPU seconds of ``fn`` (after one warm-up call)."""
    fn()
    wall, cpu = [], []
    for _ in range(repeats):
        w, c = time.perf_counter(), time.process_time()
        fn()
        cpu.append(time.process_time() - c)
        wall.append(time.perf_counter() - w)
    return statistics.median(wall), statistics.median(cpu)


def closed_loop(n_runs: int, repeats: int) -> None:
    ctrl = [FuzzyHeadingController(fls=heading_fls(0.2))]
    traj = [straight()]
    runs = RunTable(0, 0, SIGMA, np.arange(n_runs))
    cfg = LoopConfig()
    steps = n_runs * cfg.n_steps
    engine = _Engine(traj, cfg)
    print(f"\n## Closed loop: {n_runs} runs x {cfg.n_steps} steps (IT2FLC FoU 0.2, sigma {SIGMA})")
    print("| engine | threads | wall s | M run-steps/s (wall) | CPU s | ratio (wall) |")
    print("|---|---:|---:|---:|---:|---:|")
    nw, nc = timed(lambda: engine.run(ctrl, runs, record=False), max(1, repeats // 2))
    print(f"| numpy | 1 | {nw:.3f} | {steps / nw / 1e6:.2f} | {nc:.3f} | 1.0 |")
    before = numba.get_num_threads()
    for threads in sorted({1, before}):
        numba.set_num_threads(threads)
        w, c = timed(lambda: simulate_metrics(ctrl, traj, runs, cfg), repeats)
        print(f"| compiled | {threads} | {w:.3f} | {steps / w / 1e6:.2f} | {c:.3f} | "
              f"{nw / w:.1f} |")  # fmt: skip
    numba.set_num_threads(before)


def jit_times() -> None:
    print("\n## JIT: first call in a fresh process (s)")
    print("| cache | import | closed loop | scalar fls | batch fls |")
    print("|---|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        for label in ("cold (compiles)", "warm (loads)"):
            out = subprocess.run([sys.executable, "-c", _CHILD_JIT], env=env, check=True,
                                 capture_output=True, text=True).stdout.split()  # fmt: skip
            print(f"| {label} | " + " | ".join(f"{float(v):.2f}" for v in out) + " |")


def memory(counts: list[int]) -> None:
    print("\n## Peak resident memory of a fresh process (simulate_metrics, 2 s runs)")
    print("| runs | peak RSS MiB |")
    print("|---:|---:|")
    for n in counts:
        out = subprocess.run([sys.executable, "-c", _CHILD_MEMORY, str(n)], check=True,
                             capture_output=True, text=True).stdout  # fmt: skip
        print(f"| {n} | {int(out) / 1024:.0f} |")


def fuzzy(repeats: int, big: int) -> None:
    rng = np.random.default_rng(0)
    print("\n## Fuzzy batch (paper controller FoU 0.2), M samples/s (wall)")
    print("| reducer | samples | numpy | compiled | ratio |")
    print("|---|---:|---:|---:|---:|")
    for red in REDUCERS:
        fls = heading_fls(0.2, reducer=red)
        for n in (1_000, big):
            e, de = rng.uniform(-1.2, 1.2, (2, n))

            def numpy_call(fls=fls, e=e, de=de):  # the numpy path of fls(e, de)
                x, _ = fls._prepare((e, de))
                yl, yr = fls._interval_blocks(x)
                np.add(yl, yr, out=yl)
                yl *= 0.5

            reps = repeats if n == big else repeats * 20
            nw, _ = timed(numpy_call, reps)
            cw, _ = timed(lambda fls=fls, e=e, de=de: fls(e, de), reps)
            print(f"| {red.name} | {n} | {n / nw / 1e6:.2f} | {n / cw / 1e6:.2f} | "
                  f"{nw / cw:.1f} |")  # fmt: skip
    fls = heading_fls(0.2)
    calls = 200_000
    fls(0.3, -0.1)
    t = time.perf_counter()
    for _ in range(calls):
        fls(0.3, -0.1)
    compiled_us = (time.perf_counter() - t) / calls * 1e6
    scalars = fls._scalar_inputs((0.3, -0.1))
    t = time.perf_counter()
    for _ in range(calls // 10):
        fls._scalar_output(fls._scalar_inputs((0.3, -0.1)))
    numpy_us = (time.perf_counter() - t) / (calls // 10) * 1e6
    assert scalars is not None
    print(f"\nScalar call fls(0.3, -0.1): compiled {compiled_us:.2f} us, "
          f"numpy fast path {numpy_us:.2f} us")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes, fewer repeats")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    repeats = 2 if args.quick else args.repeats
    print(f"numba {numba.__version__}, numpy {np.__version__}, threads "
          f"{numba.get_num_threads()}, load average {os.getloadavg()[0]:.2f}")  # fmt: skip
    closed_loop(256 if args.quick else 4096, repeats)
    jit_times()
    memory([1_000, 4_000] if args.quick else [1_000, 10_000, 40_000])
    fuzzy(repeats, 100_000 if args.quick else 1_000_000)
    print(f"\nload average at the end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()

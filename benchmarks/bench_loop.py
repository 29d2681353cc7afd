"""Benchmark of the batched closed loop (issue #3).

Measures, on this machine, in one run:

1. throughput of :func:`it2track.tracking.simulate_metrics` in run-steps/s for B = 1, 100 and
   10^4 runs (10 s at 100 Hz each, the paper's IT2FLC with FoU 0.2, sigma = 0.05 rad; one
   chunk of B runs, and B = 10^4 also in the default chunks of 4096), by wall-clock and by
   process CPU time (steadier when other processes share the machine);
2. the time of a 12 000-run study: 4 controllers (FLC, IT2 0.1/0.2/0.3) x 3 trajectories x
   1000 seeds, through ``simulate_metrics`` with its default chunking;
3. a baseline: a straightforward per-run Python loop (one run at a time, scalar math, the
   fuzzy system called with Python floats, the plant stepped with B = 1) over a few runs,
   extrapolated to run-steps/s, and the speed-up of the batched loop over it;
4. peak memory of the streaming mode as the number of runs grows, to show it stays flat: a
   fresh subprocess per case reports its peak resident size (``VmHWM``) and the tracemalloc
   peak of the ``simulate_metrics`` call.

A run-step is one control period of one run (10 s at 100 Hz = 1000 run-steps per run).
Times are medians over repeats. ``simulate_metrics`` runs on the compiled engine (numba, every
thread ``numba.get_num_threads()`` allows) wherever it applies; ``IT2TRACK_ENGINE=numpy``
measures the numpy engine instead (``benchmarks/bench_engine.py`` shows both side by side).
Run it from the repository root::

    .venv/bin/python benchmarks/bench_loop.py            # ~1 min on an idle machine
    .venv/bin/python benchmarks/bench_loop.py --quick    # smaller, for a smoke test
    IT2TRACK_ENGINE=numpy .venv/bin/python benchmarks/bench_loop.py --quick
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import subprocess
import sys
import time
import tracemalloc
from dataclasses import dataclass, field

# The loop is elementwise numpy and uses no BLAS; only the one-off setup (a few small matrix
# exponentials) does, and OpenBLAS thread start-up makes it erratic on a busy machine.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

from it2track.paper import heading_fls
from it2track.plant import DifferentialDrive, held_sample_index, standard_noise
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    RunTable,
    curved,
    run_grid,
    simulate_metrics,
    sinusoidal,
    straight,
)

SIGMA = 0.05
CONFIG = LoopConfig()  # 10 s at 100 Hz, paper Table 3 robot


@dataclass
class Timing:
    """Wall-clock and process CPU seconds of repeated calls."""

    wall: list[float] = field(default_factory=list)
    cpu: list[float] = field(default_factory=list)

    def add(self, fn) -> None:
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        self.cpu.append(time.process_time() - c0)
        self.wall.append(time.perf_counter() - w0)

    @property
    def median_wall(self) -> float:
        return statistics.median(self.wall)

    @property
    def median_cpu(self) -> float:
        return statistics.median(self.cpu)


def _timed(fn, repeats: int) -> Timing:
    timing = Timing()
    for _ in range(repeats):
        timing.add(fn)
    return timing


def throughput(batch: int, repeats: int, *, batch_size: int | None = None) -> Timing:
    """Timing of ``batch`` runs of the FoU-0.2 IT2FLC (default: in one chunk)."""
    ctrl = [FuzzyHeadingController(fls=heading_fls(0.2))]
    traj = [straight()]
    runs = RunTable(0, 0, SIGMA, np.arange(batch))
    size = batch_size or batch
    simulate_metrics(ctrl, traj, RunTable(0, 0, SIGMA, np.arange(min(batch, 64))),
                     LoopConfig(duration=0.1), batch_size=size)  # fmt: skip  (warm caches)
    return _timed(lambda: simulate_metrics(ctrl, traj, runs, CONFIG, batch_size=size), repeats)


def study(n_seeds: int, repeats: int) -> tuple[Timing, int]:
    """Timing of the controllers x trajectories x seeds study."""
    ctrls = [FuzzyHeadingController(fls=heading_fls(w)) for w in (0.0, 0.1, 0.2, 0.3)]
    trajs = [straight(), curved(), sinusoidal()]
    runs = run_grid(len(ctrls), len(trajs), [SIGMA], n_seeds)
    return _timed(lambda: simulate_metrics(ctrls, trajs, runs, CONFIG), repeats), len(runs)


# --- baseline: one run at a time, scalar Python -----------------------------------------------


def _wrap(a: float) -> float:
    w = math.remainder(a, 2.0 * math.pi)
    return math.pi if w <= -math.pi else w


def naive_run(fls, ref: list[list[float]], drive: DifferentialDrive, z: np.ndarray,
              hold: list[int], sigma: float) -> float:  # fmt: skip
    """One run with scalar math; returns its IAE (used to check it agrees with the batch)."""
    cfg = CONFIG
    n, ts = cfg.n_steps, cfg.ts
    lim = cfg.robot.motor.voltage_limit
    gain = cfg.robot.wheel_radius * cfg.robot.motor.dc_gain
    pose = np.zeros((3, 1))
    wheels = np.zeros((4, 1))
    volts = np.zeros((2, 1))
    e_prev = 0.0
    iae = 0.0
    for k in range(n + 1):
        x, y, th = float(pose[0, 0]), float(pose[1, 0]), float(pose[2, 0])
        xr, yr, vx, vy = ref[k]
        theta_d = math.atan2(yr - y, xr - x)
        e_true = _wrap(theta_d - th)
        e = _wrap(theta_d - (th + sigma * float(z[hold[k]])))
        de = _wrap(e - e_prev) if k else 0.0
        e_prev = e
        u = fls(e, de)  # Python floats: the fuzzy system's scalar fast path
        v0 = math.hypot(vx, vy) / gain
        iae += (0.5 if k in (0, n) else 1.0) * abs(e_true) * ts
        if k < n:
            volts[0, 0] = min(max(v0 + u, -lim), lim)
            volts[1, 0] = min(max(v0 - u, -lim), lim)
            pose, wheels = drive.step(pose, wheels, volts)
    return iae


def baseline(n_runs: int) -> tuple[Timing, float]:
    """Timing per run of the naive loop, and its largest IAE difference to the batch."""
    fls = heading_fls(0.2)
    traj = straight()
    drive = DifferentialDrive(CONFIG.robot, CONFIG.ts, quadrature_nodes=CONFIG.quadrature_nodes)
    ref = traj.sample(CONFIG.times).tolist()
    hold = held_sample_index(CONFIG.times, CONFIG.noise_rate).tolist()
    z = standard_noise(CONFIG.seed, np.arange(n_runs), hold[-1] + 1)
    timing, iaes = Timing(), []
    for i in range(n_runs):
        timing.add(lambda i=i: iaes.append(naive_run(fls, ref, drive, z[i], hold, SIGMA)))
    batch = simulate_metrics([FuzzyHeadingController(fls=fls)], [traj],
                             RunTable(0, 0, SIGMA, np.arange(n_runs)), CONFIG)  # fmt: skip
    return timing, float(np.max(np.abs(np.array(iaes) - batch["IAE"])))


# --- memory: a fresh process per case ---------------------------------------------------------


def _proc_status_kib(key: str) -> int:
    """``VmRSS`` (resident now) or ``VmHWM`` (peak resident) of this process, KiB (Linux).

    ``ru_maxrss`` is no use here: Linux carries it over from the parent across fork/exec.
    """
    with open("/proc/self/status", encoding="ascii") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1])
    return -1


def memory_child(n_runs: int) -> None:
    ctrl = [FuzzyHeadingController(fls=heading_fls(0.2))]
    traj = [straight()]
    simulate_metrics(ctrl, traj, RunTable(0, 0, SIGMA, np.arange(4)), LoopConfig(duration=0.1))
    before = _proc_status_kib("VmRSS")
    tracemalloc.start()
    simulate_metrics(ctrl, traj, RunTable(0, 0, SIGMA, np.arange(n_runs)), CONFIG)
    traced_peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    print(before, _proc_status_kib("VmHWM"), traced_peak)


def memory(n_runs: int) -> tuple[float, float, float]:
    """(RSS before the call, peak RSS, tracemalloc peak during the call), MiB."""
    out = subprocess.run(
        [sys.executable, __file__, "--memory-child", str(n_runs)],
        check=True, capture_output=True, text=True,
    ).stdout.split()  # fmt: skip
    before, peak, traced = int(out[0]), int(out[1]), int(out[2])
    return before / 1024, peak / 1024, traced / 2**20


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes, fewer repeats")
    parser.add_argument("--repeats", type=int, default=5, help="repeats per timing (median)")
    parser.add_argument("--memory-child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.memory_child is not None:
        memory_child(args.memory_child)
        return

    quick = args.quick
    repeats = 2 if quick else args.repeats
    steps = CONFIG.n_steps
    rows: list[tuple[str, ...]] = []

    def row(case: str, runs: int, timing: Timing, *, label: str = "", unit: str = "") -> float:
        """Add a table row; return run-steps/s by wall-clock time."""
        wall, cpu = timing.median_wall, timing.median_cpu
        rate, cpu_rate = runs * steps / wall, runs * steps / cpu
        spread = f"{min(timing.wall):.3f}-{max(timing.wall):.3f}"
        digits = 4 if rate < 1e4 else 2
        rows.append((case, label or f"{runs:,}", f"{wall:.3f}{unit}", spread + unit,
                     f"{cpu:.3f}{unit}", f"{rate / 1e6:.{digits}f} M",
                     f"{cpu_rate / 1e6:.{digits}f} M"))  # fmt: skip
        return rate

    naive_runs = 2 if quick else 4
    naive, agree = baseline(naive_runs)
    base_rate = row("baseline: per-run Python loop (B=1 plant, scalar FLS)", 1, naive,
                    label=f"{naive_runs}, one at a time", unit=" / run")  # fmt: skip

    rates = {}
    for b in (1, 100, 1000) if quick else (1, 100, 10_000):
        rates[b] = row(f"simulate_metrics, one chunk, B={b:,}", b, throughput(b, repeats))
    big = max(rates)
    row(f"simulate_metrics, B={big:,} in default chunks of 4096", big,
        throughput(big, repeats, batch_size=4096))  # fmt: skip
    n_seeds = 100 if quick else 1000
    study_timing, n_study = study(n_seeds, max(1, repeats - 2))
    study_rate = row(f"study: 4 ctrl x 3 traj x {n_seeds} seeds (chunks of 4096)", n_study,
                     study_timing)  # fmt: skip
    load = os.getloadavg()

    mem_sizes = (1_000, 5_000) if quick else (1_000, 10_000, 40_000)
    mem = [(n, *memory(n)) for n in mem_sizes]

    print(f"\n## bench_loop ({platform.processor() or platform.machine()}, {os.cpu_count()} "
          f"CPUs, Python {platform.python_version()}, numpy {np.__version__}, "
          f"OPENBLAS_NUM_THREADS={os.environ['OPENBLAS_NUM_THREADS']}, engine "
          f"{os.environ.get('IT2TRACK_ENGINE', 'auto')})\n")  # fmt: skip
    print("Each run: 10 s at 100 Hz = 1000 run-steps; IT2FLC FoU 0.2 (study: FLC + IT2 "
          f"0.1/0.2/0.3), sigma = {SIGMA} rad. Times: median of {repeats} repeats "
          f"(study: {max(1, repeats - 2)}).\n")  # fmt: skip
    print(f"Load average at the end: {load[0]:.2f} {load[1]:.2f} {load[2]:.2f} (on a busy "
          "machine the wall-clock rates drop; CPU-time rates are steadier).\n")  # fmt: skip
    print("| case | runs | wall median (s) | wall min-max (s) | CPU median (s) | "
          "run-steps/s (wall) | run-steps/s (CPU) |")  # fmt: skip
    print("|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print("| " + " | ".join(r) + " |")
    print(f"\nSpeed-up over the per-run Python loop: B={big:,} {rates[big] / base_rate:.0f}x, "
          f"study {study_rate / base_rate:.0f}x, B=1 {rates[1] / base_rate:.1f}x. "
          f"(Baseline IAE agrees with the batched loop to {agree:.1e} rad s.)")  # fmt: skip
    print("Target >= 4 M run-steps/s at B=10,000: "
          + (f"{'met' if rates[big] >= 4e6 else 'NOT met'} ({rates[big] / 1e6:.2f} M).\n"
             if big == 10_000 else "not measured (--quick).\n"))  # fmt: skip
    print("Streaming mode memory (fresh process each; simulate_metrics, default batch_size "
          "4096):\n")
    print("| runs | RSS before the call (MiB) | peak RSS, VmHWM (MiB) | "
          "traced peak in the call (MiB) |")  # fmt: skip
    print("|---:|---:|---:|---:|")
    for n, before, peak, traced in mem:
        print(f"| {n:,} | {before:.0f} | {peak:.0f} | {traced:.1f} |")
    print(f"\nCommand: {sys.executable} benchmarks/bench_loop.py"
          + (" --quick" if quick else f" --repeats {repeats}"))  # fmt: skip


if __name__ == "__main__":
    main()

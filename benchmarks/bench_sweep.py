"""Benchmark of resumable sweeps (issue #5): throughput and memory, in-process vs 2 workers.

A sweep of N runs: 5 controllers (FLC, IT2FLC FoU 0.1/0.2/0.3, type-1 dead-zone-matched 0.2)
x 2 trajectories (curved, sinusoidal) x 2 noise levels (0.05, 0.1 rad) x N/20 seeds, each run
``--duration`` seconds at 100 Hz (default 2 s, so that the 100 000-run case takes well under a
minute per executor on a 2-core machine; ``--duration 10`` for the paper's runs), chunks of 2000
runs, through the real ``run_sweep`` (chunk CSV files fsync-ed and renamed, final assembly).

Every case runs in a fresh subprocess so that peak RSS (``ru_maxrss``) is its own:
the driver's, and the largest worker's as reported by the workers themselves. The same N
is run with both executors and the two ``results.csv`` files are compared byte for byte.
Memory is flat when the 100 000-run peak equals the 10 000-run peak.

Run from the repository root::

    .venv/bin/python benchmarks/bench_sweep.py                 # 10k and 100k runs, ~2 min
    .venv/bin/python benchmarks/bench_sweep.py --runs 20000    # one size only
    .venv/bin/python benchmarks/bench_sweep.py --dask          # also a 2-worker LocalCluster
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import platform
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# The loop is elementwise numpy (no BLAS); keep OpenBLAS from starting threads per process.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

CONFIG = """
[sweep]
seeds = {seeds}
noise_std = [0.05, 0.1]
trajectories = ["curved", "sinusoidal"]
chunk_size = 2000

[simulation]
duration = {duration}

[[controllers]]
kind = "flc"

[[controllers]]
kind = "it2"
fou = [0.1, 0.2, 0.3]

[[controllers]]
kind = "t1-matched"
fou = 0.2
"""
RUNS_PER_SEED = 5 * 2 * 2


def one_case(args: argparse.Namespace) -> None:
    """Child process: run one sweep, print its measurements as JSON."""
    from it2track.experiments.executors import DaskExecutor, make_executor, peak_rss_bytes
    from it2track.experiments.sweep import load_sweep_config, run_sweep

    work = Path(args.work)
    config = work / "sweep.toml"
    n_runs = args.runs[-1]  # --runs is repeatable; a child gets exactly one
    config.write_text(CONFIG.format(seeds=n_runs // RUNS_PER_SEED, duration=args.duration))
    plan = load_sweep_config(config)
    out = work / "out"
    cluster = None
    if args.executor == "dask":
        import distributed

        cluster = distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
        )
        executor = DaskExecutor(cluster.scheduler_address)
    else:
        executor = make_executor(workers=args.workers)
    t0 = time.perf_counter()
    with executor:
        summary = run_sweep(plan, out, executor=executor, progress=False)
    elapsed = time.perf_counter() - t0
    if cluster is not None:
        cluster.close()
    driver_rss = peak_rss_bytes()  # before hashing, which reads the file in 1 MiB blocks
    sha = hashlib.sha256()
    with open(out / "results.csv", "rb") as fh:
        while block := fh.read(1 << 20):
            sha.update(block)
    digest = sha.hexdigest()
    print(json.dumps({
        "runs": plan.n_runs, "chunks": summary.n_chunks, "seconds": elapsed,
        "runs_per_s": plan.n_runs / elapsed, "driver_rss": driver_rss,
        "worker_rss": summary.worker_peak_rss, "workers": len(summary.workers),
        "sha256": digest,
    }))  # fmt: skip


def run_case(executor: str, workers: int, runs: int, duration: float) -> dict[str, float]:
    with tempfile.TemporaryDirectory(prefix="bench-sweep-") as work:
        cmd = [sys.executable, __file__, "--child", "--executor", executor, "--workers",
               str(workers), "--runs", str(runs), "--duration", str(duration), "--work", work]
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if proc.returncode:
            raise SystemExit(f"case failed: {shlex.join(cmd)}\n{proc.stderr}")
        return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, action="append",
                        help="sweep size (repeatable; default 10000 and 100000)")
    parser.add_argument("--duration", type=float, default=2.0, help="seconds per run")
    parser.add_argument("--dask", action="store_true", help="also a 2-worker Dask LocalCluster")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--executor", default="local", help=argparse.SUPPRESS)
    parser.add_argument("--workers", type=int, default=0, help=argparse.SUPPRESS)
    parser.add_argument("--work", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        one_case(args)
        return
    sizes = args.runs or [10_000, 100_000]
    for n in sizes:
        if n % RUNS_PER_SEED:
            parser.error(f"--runs {n} must be a multiple of {RUNS_PER_SEED}")
    cases = [("in-process", "local", 0), ("2 local workers", "local", 2)]
    if args.dask:
        cases.append(("Dask LocalCluster, 2 workers", "dask", 0))
    command = shlex.join([Path(sys.executable).name, *sys.argv])
    print(f"# bench_sweep: {command}")
    print(f"# {platform.platform()}, {os.cpu_count()} CPUs, Python {platform.python_version()};"
          f" {args.duration:g} s per run at 100 Hz, chunks of 2000 runs")
    header = (f"| {'runs':>7} | {'executor':<29} | {'time s':>7} | {'runs/s':>7} | "
              f"{'driver peak RSS':>15} | {'worker peak RSS':>15} | results.csv |")
    print(header)
    print("|" + "|".join("-" * (len(c)) for c in header.split("|")[1:-1]) + "|")
    for n in sizes:
        digests = set()
        for name, executor, workers in cases:
            r = run_case(executor, workers, n, args.duration)
            digests.add(r["sha256"])
            same = "same" if len(digests) == 1 else "DIFFERENT"
            print(f"| {r['runs']:>7} | {name:<29} | {r['seconds']:>7.1f} | "
                  f"{r['runs_per_s']:>7.0f} | {r['driver_rss'] / 2**20:>11.0f} MiB | "
                  f"{r['worker_rss'] / 2**20:>11.0f} MiB | {same:<11} |", flush=True)


if __name__ == "__main__":
    main()

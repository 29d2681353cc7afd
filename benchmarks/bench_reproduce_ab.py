"""The default ``it2track reproduce`` of two installations, timed alternately (issue #17: the
new verdict machinery within 1.5x of the previous wall time).

Runs ``A reproduce --out TMP``, then ``B reproduce --out TMP``, ``--pairs`` times, alternating
so that both see the same machine; prints per run the wall time, the CPU time of the command
and its children (user + system, from ``resource.getrusage(RUSAGE_CHILDREN)``) and the 1-minute
load average before and after, then the medians and the ratios B / A (per pair and of the
medians). On a shared machine the load moves during a run: compare pairs run at similar load.

Run from the repository root, e.g. the main checkout's installation against this one::

    .venv/bin/python benchmarks/bench_reproduce_ab.py \\
        --a /work/main/.venv/bin/it2track --b .venv/bin/it2track --pairs 3
    .venv/bin/python benchmarks/bench_reproduce_ab.py --a ... --b ... -- --quick
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import tempfile
import time
from pathlib import Path


def _load() -> float:
    return os.getloadavg()[0]


def _run(exe: str, extra: list[str]) -> tuple[float, float, float, float]:
    """(wall s, CPU s, load before, load after) of one ``reproduce``."""
    with tempfile.TemporaryDirectory() as tmp:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        load0 = _load()
        start = time.perf_counter()
        subprocess.run([exe, "reproduce", "--out", str(Path(tmp) / "out"), "--no-progress",
                        *extra], check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        return wall, cpu, load0, _load()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a", required=True, help="the reference it2track executable")
    parser.add_argument("--b", required=True, help="the it2track executable measured")
    parser.add_argument("--pairs", type=int, default=3, help="alternating pairs (default 3)")
    parser.add_argument("extra", nargs="*", help="more reproduce options (after --)")
    args = parser.parse_args()
    runs: dict[str, list[tuple[float, float, float, float]]] = {"A": [], "B": []}
    for i in range(args.pairs):
        for name, exe in (("A", args.a), ("B", args.b)):
            wall, cpu, l0, l1 = _run(exe, args.extra)
            runs[name].append((wall, cpu, l0, l1))
            print(f"pair {i + 1} {name}: {wall:7.1f} s wall, {cpu:6.1f} s CPU, load "
                  f"{l0:.2f} -> {l1:.2f}", flush=True)
    for name in ("A", "B"):
        walls = [r[0] for r in runs[name]]
        cpus = [r[1] for r in runs[name]]
        print(f"{name}: median {statistics.median(walls):.1f} s wall ({min(walls):.1f}-"
              f"{max(walls):.1f}), median {statistics.median(cpus):.1f} s CPU")
    ratios = [b[0] / a[0] for a, b in zip(runs["A"], runs["B"], strict=True)]
    cpu_ratios = [b[1] / a[1] for a, b in zip(runs["A"], runs["B"], strict=True)]
    print("B / A per pair, wall: " + ", ".join(f"{r:.2f}" for r in ratios)
          + "; CPU: " + ", ".join(f"{r:.2f}" for r in cpu_ratios))
    med = (statistics.median(r[0] for r in runs["B"])
           / statistics.median(r[0] for r in runs["A"]))
    med_cpu = (statistics.median(r[1] for r in runs["B"])
               / statistics.median(r[1] for r in runs["A"]))
    print(f"B / A of the medians: {med:.2f} wall, {med_cpu:.2f} CPU")


if __name__ == "__main__":
    main()

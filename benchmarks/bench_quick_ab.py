"""``reproduce --quick`` from two source trees, timed alternately (issue #18: ``--quick`` within
5 s warm on the 2-core machine).

Runs ``python -m it2track reproduce --quick --no-physics --no-chip --no-progress`` with
``PYTHONPATH`` set to tree A, then to tree B, ``--pairs`` times, alternating so that both see the
same machine, with bytecode caches on (no ``PYTHONDONTWRITEBYTECODE``), as on a user's machine.
Per run it prints the wall time until the command exits, the wall time until the last of its
processes exits (the figure workers' fork server outlives the command; a pipe reading the
command's output waits for it), the CPU time of all of them (this process is their child
subreaper on Linux, so the fork server and the figure workers are reaped here and counted) and
the 1-minute load average before the run; then the medians. On a shared machine the load moves
during a run: compare pairs run at similar load.

Run from the repository root, e.g. the main checkout against this one::

    .venv/bin/python benchmarks/bench_quick_ab.py --a ../main/src --b src --pairs 7
"""

from __future__ import annotations

import argparse
import ctypes
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def _run(src: str) -> tuple[float, float, float, float]:
    """(wall until the command exits, wall until its last process exits, CPU s, load)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(Path(src).resolve())
    with tempfile.TemporaryDirectory() as tmp:
        load = os.getloadavg()[0]
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "it2track", "reproduce", "--out",
                        str(Path(tmp) / "out"), "--quick", "--no-physics", "--no-chip",
                        "--no-progress"], check=True, env=env, cwd=tmp,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        done = time.perf_counter()
        while True:  # the orphans (fork server, workers) are ours to reap
            try:
                os.wait()
            except ChildProcessError:
                break
        gone = time.perf_counter()
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return done - start, gone - start, cpu, load


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a", required=True, help="the reference source tree (its src/)")
    parser.add_argument("--b", required=True, help="the source tree measured (its src/)")
    parser.add_argument("--pairs", type=int, default=5, help="alternating pairs (default 5)")
    args = parser.parse_args()
    if sys.platform == "linux":  # PR_SET_CHILD_SUBREAPER
        ctypes.CDLL(None).prctl(36, 1, 0, 0, 0)
    runs: dict[str, list[tuple[float, float, float, float]]] = {"A": [], "B": []}
    for i in range(args.pairs):
        for name, src in (("A", args.a), ("B", args.b)):
            wall, gone, cpu, load = _run(src)
            runs[name].append((wall, gone, cpu, load))
            print(f"pair {i + 1} {name}: {wall:5.2f} s wall, last process gone at {gone:5.2f} s, "
                  f"{cpu:5.2f} s CPU, load {load:.2f}", flush=True)
    for name, rows in runs.items():
        med = [statistics.median(r[k] for r in rows) for k in range(4)]
        print(f"{name}: median {med[0]:.2f} s wall, last process gone at {med[1]:.2f} s, "
              f"{med[2]:.2f} s CPU, load {med[3]:.2f}")


if __name__ == "__main__":
    main()

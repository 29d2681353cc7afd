"""What a first run's kernel compile costs, function by function (issue #18).

Compiles every entry point of the compiled engine (:func:`it2track.tracking.kernel_cache.
compile_all`: the closed loop, the fuzzy batch and the scalar call) into a fresh, empty numba
cache in a subprocess, the way the background compile of a first run does, and prints:

1. the CPU seconds of the whole compile and of each entry point;
2. each function numba compiled on the way (numba's ``numba:compile`` events), with its
   wall seconds *including* the functions it calls (a callee is compiled inside its caller's
   type inference), and its own share (without its callees);
3. LLVM's share (numba's ``llvm_lock`` timer) of each entry point;
4. the numpy engine's rate while the kernels compile (``IT2TRACK_ENGINE=numpy``: the numpy
   fuzzy evaluation too), the paper's IT2FLC in batches of 256 and 2048 runs, run-steps per
   CPU second (median of 3): what ``it2track.fuzzy.kernels.NUMPY_RUN_STEPS_PER_S`` quotes,
   which decides whether a first run waits for the compiled loop;
5. the load average, since a busy machine stretches every figure.

The closed loop (``_loop``) is what a first study waits for: a background compile releases it
first, then compiles ``batch`` and ``scalar2`` (which reuse its ``eval_block``).

Run from the repository root::

    .venv/bin/python benchmarks/bench_compile.py
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import textwrap

_CHILD = textwrap.dedent("""
    import json, time
    from numba.core import event
    from it2track.tracking import kernel_cache

    calls = kernel_cache._entry_calls()
    entries, events = [], []
    with event.install_recorder("numba:compile") as rec:
        for dispatcher, args in calls:
            c0 = time.process_time()
            dispatcher(*args)
            cpu = time.process_time() - c0
            (sig,) = [s for s in dispatcher.signatures]
            timers = dispatcher.get_metadata(sig)["timers"]
            entries.append((dispatcher.py_func.__name__, cpu, timers["llvm_lock"]))
    stack = []
    for ts, ev in rec.buffer:
        name = ev.data["dispatcher"].py_func.__qualname__
        if ev.is_start:
            stack.append([name, ts, 0.0])
        else:
            name, start, children = stack.pop()
            total = ts - start
            if stack:
                stack[-1][2] += total
            events.append((name, total, total - children))
    print(json.dumps({"entries": entries, "events": events}))
""")

_NUMPY_RATE = textwrap.dedent("""
    import json, statistics, time
    import it2track
    from it2track.tracking import LoopConfig, run_grid, simulate_metrics, get_trajectory
    from it2track.tracking.controllers import FuzzyHeadingController
    c = [FuzzyHeadingController(fls=it2track.heading_fls(0.2))]
    rates = {}
    for n in (256, 2048):
        runs = run_grid(1, 1, noise_stds=[0.05], seeds=n)
        ts = []
        for _ in range(3):
            t = time.process_time()
            simulate_metrics(c, [get_trajectory("curved")], runs, LoopConfig())
            ts.append(time.process_time() - t)
        rates[n] = n * LoopConfig().n_steps / statistics.median(ts)
    print(json.dumps(rates))
""")


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def main() -> None:
    print(f"load average before: {_load()}  (cores: {os.cpu_count()})")
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        out = subprocess.run([sys.executable, "-c", _CHILD], env=env, check=True,
                             capture_output=True, text=True).stdout
    data = json.loads(out.splitlines()[-1])
    entries, events = data["entries"], data["events"]
    print(f"\n1. compile of every entry point into an empty cache: "
          f"{sum(e[1] for e in entries):.1f} s CPU")
    print(f"   {'entry point':<12} {'CPU s':>7} {'LLVM s':>7}")
    for name, cpu, llvm in entries:
        print(f"   {name:<12} {cpu:7.2f} {llvm:7.2f}")
    merged: dict[str, list[float]] = {}
    for name, total, own in events:
        row = merged.setdefault(name, [0, 0.0, 0.0])
        row[0] += 1
        row[1] += total
        row[2] += own
    print("\n2. every function numba compiled (wall s; 'own' leaves out its callees)")
    print(f"   {'function':<40} {'times':>5} {'total':>7} {'own':>7}")
    for name, (times, total, own) in sorted(merged.items(), key=lambda kv: -kv[1][2]):
        if own >= 0.05:
            print(f"   {name:<40} {times:5d} {total:7.2f} {own:7.2f}")
    env = {**os.environ, "IT2TRACK_ENGINE": "numpy"}
    rates = json.loads(subprocess.run([sys.executable, "-c", _NUMPY_RATE], env=env, check=True,
                                      capture_output=True, text=True).stdout.splitlines()[-1])
    print("\n4. the numpy engine (numpy fuzzy evaluation too), paper IT2FLC, curved path, "
          "10 s at 100 Hz:")
    for n, rate in rates.items():
        print(f"   batches of {n:>4} runs: {rate / 1e6:.2f} M run-steps per CPU second")
    print(f"\nload average after: {_load()}")


if __name__ == "__main__":
    main()

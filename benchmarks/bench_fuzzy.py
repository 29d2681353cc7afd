"""Throughput of the fuzzy core on the paper's controller (FoU 0.2), against PyIT2FLS.

Run from the repository root::

    .venv/bin/python benchmarks/bench_fuzzy.py
    IT2TRACK_ENGINE=numpy .venv/bin/python benchmarks/bench_fuzzy.py   # the numpy path

``fls(e, de)`` uses the compiled kernels (numba) where they apply, the numpy evaluation
otherwise or with ``IT2TRACK_ENGINE=numpy``; ``benchmarks/bench_engine.py`` compares both.

Measures, on one pinned CPU core and in one run:

- batched evaluation ``fls(e, de)`` with arrays of 1, 10^3 and 10^6 samples for every type
  reducer (km, ekm, eiasc, exhaustive, nie-tan, wu-mendel);
- the scalar fast path ``fls(0.3, -0.1)`` with Python floats;
- PyIT2FLS ``IT2TSK.evaluate`` per sample (the same controller built from DESIGN.md sec. 3) with
  its default EIASC and with its KM reducer, on a few hundred samples.

Every figure is the median of several repeats (``--repeats``); the ratio column divides our
samples/s at 10^6 by PyIT2FLS's default (EIASC) per-sample samples/s measured in the same run.
Throughput is measured in CPU time of this process (``--clock cpu``, the default: immune to
other processes preempting ours on a shared machine) or wall-clock time (``--clock wall``);
both are printed in the log, the table uses the chosen one.
Prints a markdown table for the README and checks the targets (exact reducers >= 10 M
samples/s at 10^6, a scalar call <= 20 us, >= 1000x PyIT2FLS).
"""

from __future__ import annotations

import os

# One core: no hidden BLAS/OpenMP threads (set before NumPy is imported).
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
os.environ.setdefault("MPLBACKEND", "Agg")  # PyIT2FLS imports matplotlib.pyplot

import argparse  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

import numpy as np  # noqa: E402

from it2track.fuzzy import EIASC, EKM, EXHAUSTIVE, KM, NIE_TAN, WU_MENDEL  # noqa: E402
from it2track.paper import heading_fls  # noqa: E402

FOU = 0.2
REDUCERS = (KM, EKM, EIASC, EXHAUSTIVE, NIE_TAN, WU_MENDEL)
BATCHES = (1, 1_000, 1_000_000)
TABLE2 = {("N", "N"): -12.0, ("N", "Z"): -8.0, ("N", "P"): -4.0,
          ("Z", "N"): -8.0, ("Z", "Z"): 0.0, ("Z", "P"): 8.0,
          ("P", "N"): 4.0, ("P", "Z"): 8.0, ("P", "P"): 12.0}


CLOCK = time.process_time


def rate(fn: Callable[[], object], samples_per_call: int, *, repeats: int,
         min_time: float) -> tuple[float, float, float]:
    """Median, min and max samples/s of ``fn`` over ``repeats`` timed runs of >= min_time s,
    on the clock ``CLOCK``; also logs the wall-clock median."""
    fn()  # warm-up (workspaces, caches)
    calls = 1
    while True:  # calibrate the number of calls per repeat
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        dt = time.perf_counter() - t0
        if dt >= min_time / 4 or calls >= 1 << 20:
            break
        calls *= 4
    calls = max(1, int(calls * min_time / max(dt, 1e-9)))
    rates, wall = [], []
    for _ in range(repeats):
        w0, t0 = time.perf_counter(), CLOCK()
        for _ in range(calls):
            fn()
        t1, w1 = CLOCK(), time.perf_counter()
        rates.append(calls * samples_per_call / max(t1 - t0, 1e-9))
        wall.append(calls * samples_per_call / (w1 - w0))
    rate.last_wall = statistics.median(wall)  # type: ignore[attr-defined]
    return statistics.median(rates), min(rates), max(rates)


def pyit2fls_controller(algorithm_name: str | None):
    import pyit2fls as P

    h = FOU / 2
    domain = np.linspace(-1, 1, 201)
    sets = {
        "N": P.IT2FS(domain, P.rtri_mf, [-0.2 + h, -1.0, 1.0], P.rtri_mf, [-0.2 - h, -1.0, 1.0]),
        "Z": P.IT2FS(domain, P.tri_mf, [-0.8 - h, 0.0, 0.8 + h, 1.0],
                     P.tri_mf, [-0.8 + h, 0.0, 0.8 - h, 1.0]),
        "P": P.IT2FS(domain, P.ltri_mf, [0.2 - h, 1.0, 1.0], P.ltri_mf, [0.2 + h, 1.0, 1.0]),
    }
    tsk = P.IT2TSK(P.product_t_norm, P.max_s_norm)
    tsk.add_input_variable("e")
    tsk.add_input_variable("de")
    tsk.add_output_variable("u")
    for (a, b), y in TABLE2.items():
        tsk.add_rule([("e", sets[a]), ("de", sets[b])], [("u", {"const": y, "e": 0.0, "de": 0.0})])
    if algorithm_name is not None:
        tsk.algorithm = getattr(P, algorithm_name)
    from importlib.metadata import version

    return tsk, version("pyit2fls")


def cpu_model() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def fmt_rate(r: float) -> str:
    if r >= 1e6:
        return f"{r / 1e6:.1f} M/s"
    if r >= 1e3:
        return f"{r / 1e3:.1f} k/s"
    return f"{r:.0f} /s"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5, help="timed repeats per figure")
    parser.add_argument("--min-time", type=float, default=0.2,
                        help="seconds per timed repeat (batched runs)")
    parser.add_argument("--pyit2fls-samples", type=int, default=300)
    parser.add_argument("--cpu", type=int, default=None,
                        help="CPU to pin to (default: the first one allowed)")
    parser.add_argument("--no-pin", action="store_true", help="do not pin to one CPU")
    parser.add_argument("--clock", choices=["cpu", "wall"], default="cpu",
                        help="time base of the table (default: CPU time of this process)")
    args = parser.parse_args(argv)
    global CLOCK
    CLOCK = time.process_time if args.clock == "cpu" else time.perf_counter

    pinned = "not pinned"
    if not args.no_pin and hasattr(os, "sched_setaffinity"):
        cpu = args.cpu if args.cpu is not None else min(os.sched_getaffinity(0))
        os.sched_setaffinity(0, {cpu})
        pinned = f"pinned to CPU {cpu}"
    t_start = time.perf_counter()
    rng = np.random.default_rng(2024)
    e_all = rng.uniform(-1, 1, max(BATCHES))
    de_all = rng.uniform(-1, 1, max(BATCHES))

    print(f"# it2track fuzzy benchmark: paper controller, FoU {FOU}, product t-norm")
    print(f"python {platform.python_version()}, numpy {np.__version__}, {cpu_model()}, "
          f"{pinned}, {args.clock} clock, median of {args.repeats} repeats, "
          f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs, engine "
          f"{os.environ.get('IT2TRACK_ENGINE', 'auto')}\n")

    ours: dict[str, dict[int, tuple[float, float, float]]] = {}
    for red in REDUCERS:
        fls = heading_fls(FOU, reducer=red)
        ours[red.name] = {}
        for n in BATCHES:
            e, de = e_all[:n].copy(), de_all[:n].copy()
            ours[red.name][n] = rate(lambda fls=fls, e=e, de=de: fls(e, de), n,
                                     repeats=args.repeats,
                                     min_time=args.min_time if n > 1 else 0.1)
            med, lo, hi = ours[red.name][n]
            print(f"  {red.name:10s} batch {n:>9,d}: {fmt_rate(med):>10s} "
                  f"(min {fmt_rate(lo)}, max {fmt_rate(hi)}; wall {fmt_rate(rate.last_wall)})",
                  flush=True)

    fls = heading_fls(FOU)
    assert type(fls(0.3, -0.1)) is float
    scalar = rate(lambda: fls(0.3, -0.1), 1, repeats=args.repeats, min_time=0.1)
    print(f"  scalar fast path fls(0.3, -0.1): {1e6 / scalar[0]:.2f} us/call "
          f"(wall {1e6 / rate.last_wall:.2f} us)", flush=True)

    theirs: dict[str, tuple[float, float, float]] = {}
    version = "?"
    m = args.pyit2fls_samples
    pts = list(zip(e_all[:m].tolist(), de_all[:m].tolist(), strict=True))
    # (IT2TSK cannot use PyIT2FLS's Nie-Tan: it returns a number where IT2TSK expects (l, r).)
    for label, alg in (("EIASC (default)", None), ("KM", "KM_algorithm")):
        try:
            tsk, version = pyit2fls_controller(alg)
        except ImportError:
            print("  pyit2fls not installed: skipping the comparison")
            break

        def run(tsk=tsk):
            for e, de in pts:
                tsk.evaluate({"e": e, "de": de})

        theirs[label] = rate(run, m, repeats=max(3, args.repeats // 2), min_time=0.0)
        print(f"  pyit2fls IT2TSK {label:15s}: {1e6 / theirs[label][0]:.0f} us/sample "
              f"(wall {1e6 / rate.last_wall:.0f} us)", flush=True)

    ref = theirs.get("EIASC (default)", (float("nan"),))[0]
    print("\n## Results (samples/s, median)\n")
    print(f"Paper controller (FoU {FOU}, 9 rules), one CPU core ({cpu_model()}), "
          f"{args.clock} time, numpy {np.__version__}, pyit2fls {version}.\n")
    print("| type reducer | exact | batch 1 (array) | batch 10³ | batch 10⁶ "
          "| × pyit2fls (10⁶ vs its per-sample EIASC) |")
    print("|---|---|---|---|---|---|")
    for red in REDUCERS:
        r = ours[red.name]
        ratio = r[BATCHES[-1]][0] / ref
        print(f"| {red.name} | {'yes' if red.exact else 'no (approx.)'} "
              f"| {fmt_rate(r[1][0])} ({1e6 / r[1][0]:.0f} µs) | {fmt_rate(r[1000][0])} "
              f"| **{fmt_rate(r[BATCHES[-1]][0])}** | {ratio:,.0f}× |")
    print(f"| scalar fast path `fls(0.3, -0.1)` (exhaustive) | yes "
          f"| {fmt_rate(scalar[0])} ({1e6 / scalar[0]:.1f} µs) | | | |")
    for label, (med, _, _) in theirs.items():
        print(f"| pyit2fls {version} `IT2TSK.evaluate`, {label}, per sample | yes "
              f"| {fmt_rate(med)} ({1e6 / med:.0f} µs) | | | {med / ref:.2f}× |")
    print("\nCommand: `.venv/bin/python benchmarks/bench_fuzzy.py` "
          f"(took {time.perf_counter() - t_start:.0f} s; load average at the end "
          f"{os.getloadavg()[0]:.2f})\n")

    exact_1e6 = {red.name: ours[red.name][BATCHES[-1]][0] for red in REDUCERS if red.exact}
    best = max(exact_1e6.values())
    checks = [
        (f"best exact reducer at 10⁶ >= 10 M samples/s (stretch 50 M): "
         f"{max(exact_1e6, key=exact_1e6.__getitem__)} {fmt_rate(best)}", best >= 10e6),
        (f"scalar call <= 20 µs: {1e6 / scalar[0]:.1f} µs", 1e6 / scalar[0] <= 20),
        (f">= 1000x pyit2fls per-sample throughput: {best / ref:,.0f}x", best / ref >= 1000),
    ]
    for name, r in exact_1e6.items():
        checks.append((f"  {name} at 10⁶: {fmt_rate(r)} ({'>=' if r >= 10e6 else '<'} 10 M/s)",
                       None))
    print("## Targets\n")
    for text, ok in checks:
        mark = "" if ok is None else ("PASS " if ok else "MISS ")
        print(f"- {mark}{text}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

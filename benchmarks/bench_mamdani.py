"""Batch throughput of IT2 Mamdani evaluation, against PyIT2FLS's ``IT2Mamdani`` per sample.

Run from the repository root::

    .venv/bin/python benchmarks/bench_mamdani.py

The system is PyIT2FLS's own documented IT2 Mamdani example (the ``IT2FLS`` class docstring of
pyit2fls 0.9: three Gaussian sets with uncertain standard deviation on ``[0, 1]``, two inputs,
three rules, min t-norm / max s-norm, centroid type reduction on 100 grid points), with one
output (``y1``), built in both libraries. Measured in one run, on one pinned core:

- it2track ``IT2Mamdani`` with arrays of 10^3 and 10^5 samples, for the exact reducers (KM,
  EKM, EIASC, exhaustive) and Nie-Tan, at resolution 100 (as PyIT2FLS) and 101 (MATLAB's);
- PyIT2FLS ``IT2Mamdani.evaluate`` per sample, with its KM and EIASC algorithms.

Figures are medians of ``--repeats`` repeats in CPU time of this process (``--clock cpu``,
immune to other processes on a shared machine) or wall-clock time; the ratio column divides
our samples/s at 10^5 by PyIT2FLS's per-sample samples/s with its default algorithm (EIASC),
measured in the same run (its KM time is printed too). The two implementations are checked to
agree (KM, EIASC: 1e-12) before timing.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
os.environ.setdefault("MPLBACKEND", "Agg")  # PyIT2FLS imports matplotlib.pyplot

import argparse  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import replace  # noqa: E402

import numpy as np  # noqa: E402

from it2track.fuzzy import (  # noqa: E402
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    Input,
    IT2Mamdani,
    IT2Set,
    Output,
    Rule,
    TypeReducer,
)

CLOCK = time.process_time
BATCHES = (1_000, 100_000)
REDUCERS: tuple[TypeReducer, ...] = (KM, EKM, EIASC, EXHAUSTIVE, NIE_TAN)


def ours(reducer: TypeReducer, resolution: int = 100) -> IT2Mamdani:
    def sets() -> list[IT2Set]:
        return [IT2Set.gaussian_uncertain_std(m, 0.1, 0.2, n)
                for m, n in ((0.0, "Small"), (0.5, "Medium"), (1.0, "Large"))]

    return IT2Mamdani(
        inputs=[Input("x1", (0, 1), sets()), Input("x2", (0, 1), sets())],
        outputs=[Output("y1", (0, 1), sets())],
        rules=[Rule(["Small", "Small"], "Small"), Rule(["Medium", "Medium"], "Medium"),
               Rule(["Large", "Large"], "Large")],
        reducer=reducer, resolution=resolution,
    )


def theirs(algorithm: str):  # type: ignore[no-untyped-def]
    import pyit2fls as P

    domain = np.linspace(0.0, 1.0, 100)
    small = P.IT2FS_Gaussian_UncertStd(domain, [0, 0.15, 0.1, 1.0])
    medium = P.IT2FS_Gaussian_UncertStd(domain, [0.5, 0.15, 0.1, 1.0])
    large = P.IT2FS_Gaussian_UncertStd(domain, [1.0, 0.15, 0.1, 1.0])
    fls = P.IT2Mamdani(P.min_t_norm, P.max_s_norm, algorithm=algorithm)
    fls.add_input_variable("x1")
    fls.add_input_variable("x2")
    fls.add_output_variable("y1")
    fls.add_rule([("x1", small), ("x2", small)], [("y1", small)])
    fls.add_rule([("x1", medium), ("x2", medium)], [("y1", medium)])
    fls.add_rule([("x1", large), ("x2", large)], [("y1", large)])
    return fls


def rate(fn: Callable[[], object], samples: int, *, repeats: int, min_time: float
         ) -> tuple[float, float]:
    """Median samples/s over ``repeats`` runs of >= ``min_time`` s (clock ``CLOCK``), and the
    wall-clock median."""
    fn()
    calls = 1
    while True:
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        dt = time.perf_counter() - t0
        if dt >= min_time / 4 or calls >= 1 << 16:
            break
        calls *= 4
    calls = max(1, int(calls * min_time / max(dt, 1e-9)))
    rates, wall = [], []
    for _ in range(repeats):
        w0, t0 = time.perf_counter(), CLOCK()
        for _ in range(calls):
            fn()
        t1, w1 = CLOCK(), time.perf_counter()
        rates.append(calls * samples / max(t1 - t0, 1e-9))
        wall.append(calls * samples / (w1 - w0))
    return statistics.median(rates), statistics.median(wall)


def fmt(r: float) -> str:
    return f"{r / 1e6:.2f} M/s" if r >= 1e6 else f"{r / 1e3:.1f} k/s" if r >= 1e3 else f"{r:.0f} /s"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--min-time", type=float, default=0.2)
    parser.add_argument("--pyit2fls-samples", type=int, default=100)
    parser.add_argument("--no-pin", action="store_true")
    parser.add_argument("--clock", choices=["cpu", "wall"], default="cpu")
    args = parser.parse_args(argv)
    global CLOCK
    CLOCK = time.process_time if args.clock == "cpu" else time.perf_counter
    pinned = "not pinned"
    if not args.no_pin and hasattr(os, "sched_setaffinity"):
        cpu = min(os.sched_getaffinity(0))
        os.sched_setaffinity(0, {cpu})
        pinned = f"pinned to CPU {cpu}"
    rng = np.random.default_rng(2024)
    x1_all, x2_all = rng.uniform(0, 1, (2, max(BATCHES)))
    print("# it2track IT2 Mamdani benchmark: PyIT2FLS's documented example (2 inputs, "
          "3 rules, centroid type reduction)")
    print(f"python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}, "
          f"{pinned}, {args.clock} clock, median of {args.repeats} repeats, "
          f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs\n")

    # Agreement first (the same computation on the same 100-point grid).
    m = args.pyit2fls_samples
    pts = list(zip(x1_all[:m].tolist(), x2_all[:m].tolist(), strict=True))
    per_sample: dict[str, float] = {}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            for alg, red in (("KM", KM), ("EIASC", EIASC)):
                fls = theirs(alg)
                yl, yr = ours(red).interval(x1_all[:m], x2_all[:m])
                gap = max(max(abs(fls.evaluate({"x1": a, "x2": b})[1]["y1"][0] - yl[i]),
                              abs(fls.evaluate({"x1": a, "x2": b})[1]["y1"][1] - yr[i]))
                          for i, (a, b) in enumerate(pts))
                assert gap <= 1e-12, f"{alg}: PyIT2FLS and it2track differ by {gap:.3g}"

                def run(fls=fls) -> None:
                    for a, b in pts:
                        fls.evaluate({"x1": a, "x2": b})

                per_sample[alg], wall = rate(run, m, repeats=max(3, args.repeats // 2),
                                             min_time=0.0)
                print(f"  pyit2fls IT2Mamdani {alg:6s}: {1e6 / per_sample[alg]:8.0f} us/sample "
                      f"(wall {1e6 / wall:.0f} us); agrees with it2track to {gap:.1e}",
                      flush=True)
    except ImportError:
        print("  pyit2fls not installed: no comparison")

    results: dict[tuple[str, int, int], float] = {}
    for red in REDUCERS:
        for resolution in (100, 101):
            fls = ours(red, resolution)
            for n in BATCHES:
                x1, x2 = x1_all[:n].copy(), x2_all[:n].copy()
                med, wall = rate(lambda fls=fls, x1=x1, x2=x2: fls(x1, x2), n,
                                 repeats=args.repeats, min_time=args.min_time)
                results[(red.name, resolution, n)] = med
                print(f"  it2track {red.name:10s} J={resolution} batch {n:>7,d}: "
                      f"{fmt(med):>10s} (wall {fmt(wall)})", flush=True)
    scalar = replace(ours(EXHAUSTIVE), reducer=EXHAUSTIVE)
    one, _ = rate(lambda: scalar(0.3, 0.6), 1, repeats=args.repeats, min_time=0.1)
    print(f"  it2track one sample scalar call: {1e6 / one:.0f} us")

    print("\n## Results (samples/s, median)\n")
    print(f"| type reducer | batch 10³ | batch 10⁵ | × pyit2fls (EIASC) per sample "
          f"({args.clock} time) |")
    print("|---|---|---|---|")
    ref = per_sample.get("EIASC", float("nan"))
    for red in REDUCERS:
        big = results[(red.name, 100, BATCHES[-1])]
        ratio = f"{big / ref:,.0f}×" if ref == ref else "—"
        print(f"| {red.name} | {fmt(results[(red.name, 100, BATCHES[0])])} | {fmt(big)} | "
              f"{ratio} |")
    for alg, r in per_sample.items():
        print(f"| pyit2fls IT2Mamdani ({alg}) | {1e6 / r:.0f} µs / sample | | 1× |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

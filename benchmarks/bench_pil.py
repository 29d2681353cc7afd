"""Benchmark of processor in the loop (issue #22): what a control period costs on the
simulated ATmega328P, and why the simulator is embedded as a library.

Measures, on this machine, in one run (medians over repeats, wall-clock and process CPU time;
the simulated MCUs run in this process, so CPU time counts them):

1. one controller call on the simulated MCU through libsimavr (:class:`AvrInTheLoop`): us per
   call for the paper's IT2FLC (exhaustive float, KM float, exhaustive q15) over a batch of
   inputs, the simulated cycles per call and the simulation speed (simulated MHz);
2. the exchange's own cost: a batch of one call per ctypes call against the whole batch in one,
   and the alternative the library replaces, a ``simavr`` process per step (a prebuilt
   one-call program, process start and ELF load included);
3. the closed loop per control period: one run of 10 s (1001 periods) with the controller on
   the MCU (latency none and measured) against the same C compiled for the host
   (:class:`CHeadingController`) in the same loop, and the ratio;
4. a batch of 8 runs with 1 and 2 simulated MCUs (threads).

Run it from the repository root (needs gcc, libsimavr-dev, gcc-avr, avr-libc, binutils-avr,
simavr)::

    .venv/bin/python benchmarks/bench_pil.py            # ~2 min on an idle machine
    .venv/bin/python benchmarks/bench_pil.py --quick    # smaller, for a smoke test
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

from it2track.codegen import CHeadingController, RealType, generate_c
from it2track.codegen.mcu import AVR_CLOCK_HZ, AVR_FLAGS, AVR_MCU, _env, cost_grid
from it2track.codegen.pil import PIL_TOOLS, AvrInTheLoop
from it2track.codegen.tools import require, run_tool
from it2track.fuzzy import Reducer
from it2track.paper import heading_fls
from it2track.tracking import LoopConfig, RunTable, get_trajectory, simulate_metrics
from it2track.tracking.pil import PilHeadingController


def timed(fn, repeats: int) -> tuple[float, float]:
    """Median wall and CPU seconds of ``fn()`` over ``repeats`` calls."""
    wall, cpu = [], []
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        cpu.append(time.process_time() - c0)
        wall.append(time.perf_counter() - w0)
    return statistics.median(wall), statistics.median(cpu)


def one_call_program(code, x, work: Path) -> Path:
    """The cost benchmark's program (``avr_bench.c.j2``) for one input, compiled once."""
    for name, text in code.files().items():
        (work / name).write_text(text)
    main = _env().get_template("avr_bench.c.j2").render(
        p=code.prefix, header_name=code.header_name, n_in=code.n_inputs, n_points=1,
        fixed=False, points=[[float(v).hex() + "f" for v in x]])
    (work / "one.c").write_text(main)
    run_tool(["avr-gcc", *AVR_FLAGS, "-o", "one.elf", "one.c", code.source_name, "-lm"],
             cwd=work)
    return work / "one.elf"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer inputs, periods, repeats")
    args = parser.parse_args()
    require((*PIL_TOOLS, "simavr"))
    quick = args.quick
    repeats = 3 if quick else 5
    build = Path(tempfile.mkdtemp(prefix="bench-pil-"))
    print(f"load average at start: {', '.join(f'{v:.2f}' for v in os.getloadavg())}")
    base = heading_fls(0.2)
    x = cost_grid(11 if quick else 21, n_random=0 if quick else 200, seed=1)

    print(f"\n1. one call on the simulated ATmega328P (libsimavr, {len(x)} inputs per batch)")
    print(f"{'controller':<24} {'us/call':>8} {'cycles':>8} {'sim MHz':>8}")
    for label, red, real in (("IT2 exhaustive, float", Reducer.EXHAUSTIVE, RealType.FLOAT),
                             ("IT2 KM, float", Reducer.KM, RealType.FLOAT),
                             ("IT2 exhaustive, q15", Reducer.EXHAUSTIVE, RealType.Q15)):
        code = generate_c(dataclasses.replace(base, reducer=red.value), real=real)
        with AvrInTheLoop(code, build_dir=build) as mcu:
            raw = mcu.step_raw(x if real is RealType.FLOAT else code.fixed.to_int(x))
            xin = x if real is RealType.FLOAT else code.fixed.to_int(x)
            start = mcu.cycle()
            wall, _ = timed(lambda m=mcu, xi=xin: m.step_raw(xi), repeats)
            simulated = (mcu.cycle() - start) / repeats  # measured calls + the exchange
        per_call = wall / len(x)
        print(f"{label:<24} {per_call * 1e6:>8.0f} {raw.cycles.mean():>8.0f} "
              f"{simulated / wall / 1e6:>8.1f}")

    print("\n2. the exchange (IT2 exhaustive, float)")
    code = generate_c(base, real=RealType.FLOAT)
    with AvrInTheLoop(code, build_dir=build) as mcu:
        n_single = 50 if quick else 200
        _, batch_cpu = timed(lambda: mcu.step_raw(x[:n_single]), repeats)
        single_wall, single_cpu = timed(
            lambda: [mcu.step_raw(x[i:i + 1]) for i in range(n_single)], repeats)
    per_batched, per_single = batch_cpu / n_single, single_cpu / n_single
    work = Path(tempfile.mkdtemp(prefix="one-", dir=build))
    elf = one_call_program(code, x[0], work)

    def spawn() -> None:
        subprocess.run(["simavr", "-m", AVR_MCU, "-f", str(AVR_CLOCK_HZ), str(elf)],
                       capture_output=True, check=True)

    proc_wall, _ = timed(spawn, repeats * 2)
    print("  (CPU time of this process; the process per step: wall-clock)")
    print(f"  one call per ctypes call:           {per_single * 1e6:8.0f} us per call")
    print(f"  a batch of {n_single} in one ctypes call:  {per_batched * 1e6:8.0f} us per call")
    print(f"  exchange overhead per call:         {(per_single - per_batched) * 1e6:8.1f} us")
    print(f"  a simavr process per step:          {proc_wall * 1e6:8.0f} us per call "
          f"({proc_wall / (single_wall / n_single):.0f}x the library's wall-clock)")

    duration = 2.0 if quick else 10.0
    cfg = LoopConfig(duration=duration)
    traj = [get_trajectory("curved")]
    print(f"\n3. the closed loop, one run of {duration:g} s ({cfg.n_steps + 1} periods), "
          "IT2 exhaustive, float, sigma = 0.05 rad")
    host = CHeadingController.from_system(base, real=RealType.FLOAT, build_dir=str(build))
    runs = RunTable(0, 0, 0.05, 0)
    simulate_metrics([host], traj, runs, cfg)  # build before timing
    host_wall, host_cpu = timed(lambda: simulate_metrics([host], traj, runs, cfg), repeats)
    periods = cfg.n_steps + 1
    print(f"  host C (CHeadingController):        {host_wall / periods * 1e6:8.0f} us per "
          f"period (CPU {host_cpu / periods * 1e6:.0f})")
    for latency in ("none", "measured"):
        pil = PilHeadingController.from_system(base, latency=latency, build_dir=str(build))
        simulate_metrics([pil], traj, runs, LoopConfig(duration=0.1))  # start the MCU
        wall, cpu = timed(lambda p=pil: simulate_metrics([p], traj, runs, cfg), repeats)
        print(f"  PIL, latency {latency:<9}             {wall / periods * 1e6:8.0f} us per "
              f"period (CPU {cpu / periods * 1e6:.0f}; {wall / host_wall:.1f}x host C)")

    n_runs = 8
    print(f"\n4. a batch of {n_runs} runs of {duration:g} s, latency measured")
    batch = RunTable(0, 0, 0.05, np.arange(n_runs))
    for threads in (1, 2):
        pil = PilHeadingController.from_system(base, latency="measured", threads=threads,
                                               build_dir=str(build))
        simulate_metrics([pil], traj, batch, LoopConfig(duration=0.1))
        wall, cpu = timed(lambda p=pil: simulate_metrics([p], traj, batch, cfg),
                          max(1, repeats // 2))
        print(f"  {threads} simulated MCU(s): {wall / (n_runs * periods) * 1e6:8.0f} us per "
              f"run-period (CPU {cpu / (n_runs * periods) * 1e6:.0f})")
    print(f"\nload average at end: {', '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()

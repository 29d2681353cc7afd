"""What one IT2FLC step costs on a microcontroller, per type reducer and arithmetic (issues 11, 22).

Run from the repository root (needs the Debian packages gcc-avr, avr-libc, simavr,
gcc-arm-none-eabi, libnewlib-arm-none-eabi; gcc for the host cross-check)::

    .venv/bin/python benchmarks/bench_mcu.py [--grid 61] [--random 2000] \
        [--figure docs/mcu_costs.png]

Generates float C and integer-only q15 fixed-point C for the paper's controller (FoU 0.2) with
each type reducer (and the type-1 FLC; the Wu-Mendel bounds have no q15 build), cross-compiles
it for the ATmega328P (``avr-gcc -mmcu=atmega328p -Os``), runs it on the cycle-accurate simavr
at 16 MHz and counts the cycles of every call with Timer1 (prescaler 1), over a grid of
``[-1, 1]^2`` plus random inputs; checks that the AVR's outputs equal the host's build of the
same C bit for bit; and reports flash (controller object and a minimal program with the
software float routines, if any), stack, the error against the Python double system beside its
derived bound, and the Cortex-M4F object size (Debian has no cycle-accurate Cortex-M model, so
no cycles for it). Cycle counts come from a simulator, so they do not depend on this machine or
its load.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

from it2track.codegen.costs import measure_costs


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--grid", type=int, default=61, help="grid points per input (default 61)")
    ap.add_argument("--random", type=int, default=2000, help="random inputs (default 2000)")
    ap.add_argument("--fou", type=float, default=0.2, help="FoU width (default 0.2)")
    ap.add_argument("--figure", default=None, help="also write the cost figure (PNG/SVG)")
    args = ap.parse_args(argv)
    if args.grid < 2 or args.random < 0:
        ap.error("--grid must be >= 2 and --random >= 0")
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="it2track-mcu-") as tmp:
        table = measure_costs(fou=args.fou, grid=args.grid, n_random=args.random,
                              build_dir=tmp)
    elapsed = time.perf_counter() - t0
    print(f"paper controller, FoU {args.fou:g}: {table.n_points} inputs per controller "
          f"({args.grid}x{args.grid} grid on [-1, 1]^2 + {args.random} random)")
    for tool, version in table.tools.items():
        print(f"  {tool}: {version}")
    print()
    print(table.as_text())
    print()
    print(table.as_markdown())
    print()
    same = all(r.equals_host for r in table.rows)
    print(f"AVR outputs equal the host build of the same C bit for bit: {same}")
    print(f"measured in {elapsed:.1f} s (load average {os.getloadavg()[0]:.2f})")
    if args.figure:
        from it2track.report.mcu import write_mcu_cost_figure

        print(f"wrote {write_mcu_cost_figure(table, args.figure)}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())

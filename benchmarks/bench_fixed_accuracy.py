"""How close the q15 fixed-point controller is to the double one (issue 22): the figures README
and docs/guide/deployment.md quote.

Run from the repository root (needs gcc)::

    .venv/bin/python benchmarks/bench_fixed_accuracy.py [--grid 513] [--random 200000]

For the paper's controller (FoU 0.1, 0.2, 0.3 with the exhaustive reducer, and the type-1 FLC)
compiled as q15 on the host: the derived error bound's largest value and the measured largest
error, (a) at every input of a ``grid x grid`` lattice of the Q15 square plus random lattice
points -- the inputs the C function can be given -- and (b) at random real inputs rounded to
Q15; then the closed loop (the paper's three paths, noise-free and noisy, 4 seeds): the largest
relative difference of each metric from the double controller's loop. Everything is computed
here; nothing is timed.
"""

from __future__ import annotations

import argparse
import sys
import tempfile

import numpy as np

import it2track
from it2track.codegen import RealType, generate_c
from it2track.codegen.controller import CHeadingController
from it2track.codegen.errorbound import fixed_error_bound
from it2track.codegen.host import HostLibrary, build_host_library
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    get_trajectory,
    run_grid,
    simulate_metrics,
)

METRICS = ("IAE", "ITAE", "ISE", "ITSE", "pos_rms", "effort")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--grid", type=int, default=513, help="lattice points per axis")
    ap.add_argument("--random", type=int, default=200_000, help="random inputs")
    args = ap.parse_args(argv)
    if args.grid < 2 or args.random < 1:
        ap.error("--grid must be >= 2 and --random >= 1")
    rng = np.random.default_rng(0)
    print(f"{'controller':<22} {'inputs':<8} {'bound max':>10} {'error max':>10} "
          f"{'u error max / output step':>26}")
    with tempfile.TemporaryDirectory(prefix="it2track-fixed-") as tmp:
        for fou in (0.0, 0.1, 0.2, 0.3):
            fls = it2track.heading_fls(fou)
            code = generate_c(fls, real=RealType.Q15)
            fmt = code.fixed
            assert fmt is not None
            lib = HostLibrary(code, build_host_library(code, tmp))
            axis = np.linspace(-32768, 32767, args.grid).round()
            lattice = np.concatenate([
                np.stack(np.meshgrid(axis, axis, indexing="ij"), -1).reshape(-1, 2),
                rng.integers(-32768, 32767, size=(args.random, 2), endpoint=True)])
            real = rng.uniform(-1.0, 1.0, size=(args.random, 2))
            for kind, x in (("lattice", fmt.inputs_seen(lattice)), ("real", real)):
                u, yl, yr, _ = lib.evaluate(x)
                bound = fixed_error_bound(fls, fmt, x)
                err = max(float(np.abs(u - fls(*x.T)).max()),
                          *(float(np.abs(a - b).max())
                            for a, b in zip((yl, yr), fls.interval(*x.T), strict=True)))
                worst = max(float(bound.u.max()), float(bound.yl.max()),
                            float(bound.yr.max()))
                step = 2.0**-fmt.out_frac
                print(f"{'FoU ' + format(fou, 'g') + (' (type-1)' if fou == 0 else ''):<22} "
                      f"{kind:<8} {worst:>10.2e} {err:>10.2e} "
                      f"{float(np.abs(u - fls(*x.T)).max()) / step:>26.3f}")
        print()
        fls = it2track.heading_fls(0.2)
        ctrls = [FuzzyHeadingController(fls=fls),
                 CHeadingController.from_system(fls, real=RealType.Q15, build_dir=tmp)]
        trajs = [get_trajectory(t) for t in ("straight", "curved", "sinusoidal")]
        runs = run_grid(2, 3, [0.0, 0.05], 4)
        metrics = simulate_metrics(ctrls, trajs, runs, LoopConfig())
        py, fx = runs.controller == 0, runs.controller == 1
        print("closed loop, FoU 0.2, 3 paths x (noise-free, sigma 0.05) x 4 seeds: largest "
              "difference of q15 from double (relative where the double metric is not 0)")
        for name in METRICS:
            a, b = metrics[name][fx], metrics[name][py]
            nz = b != 0
            rel = float((np.abs(a - b)[nz] / np.abs(b[nz])).max()) if nz.any() else 0.0
            zero = float(np.abs(a[~nz]).max()) if (~nz).any() else 0.0
            print(f"  {name:<8} relative {rel:.1e}  absolute {float(np.abs(a - b).max()):.1e}"
                  f"  ({int((~nz).sum())} runs where both are {zero:g})")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Do the settled verdicts replicate? Two studies with different base seeds, compared level by
level (issue #17's done-when; not a speed benchmark).

Runs the study twice -- base seeds 0 and 1 (``seed`` in ``[study]``), otherwise the same
config -- and compares their ``verdicts.csv`` rows: every level (claim x path, and all paths,
x sigma) that either run reports as settled (replication probability >= the target) must
have the same status in both. Prints the counts, every disagreement, each run's settled
share, and the wall time and load average. Exits 1 on any disagreement.

Run from the repository root::

    .venv/bin/python benchmarks/check_verdict_replication.py            # the default study
    .venv/bin/python benchmarks/check_verdict_replication.py --quick    # the smoke study
    .venv/bin/python benchmarks/check_verdict_replication.py --config my.toml --seeds 3 7
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import replace


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def main() -> int:
    from it2track.experiments.study import StudyConfig, load_study_config, quick_config, run_study
    from it2track.experiments.verdicts import compare_verdicts

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--config", help="study TOML file (default: the paper's defaults)")
    parser.add_argument("--quick", action="store_true", help="the smoke study (seconds)")
    parser.add_argument("--seeds", type=int, nargs=2, default=(0, 1), metavar=("A", "B"),
                        help="the two base seeds (default 0 1)")
    args = parser.parse_args()
    base = load_study_config(args.config) if args.config else StudyConfig()
    if args.quick:
        base = quick_config(base)
    runs = []
    for seed in args.seeds:
        cfg = replace(base, loop=replace(base.loop, seed=seed))
        started = time.perf_counter()
        print(f"base seed {seed}: running (load {_load()}) ...", flush=True)
        result = run_study(cfg)
        rows = result.verdict_rows
        noisy = [r for r in rows if r["sigma"] > 0.0]
        settled = sum(bool(r["settled"]) for r in noisy)
        print(f"base seed {seed}: {len(rows)} levels, {settled} of {len(noisy)} noisy levels "
              f"settled, {time.perf_counter() - started:.1f} s (load {_load()})")
        runs.append(rows)
    cmp = compare_verdicts(*runs)
    print(f"{cmp['levels']} noisy levels; {cmp['settled_either']} settled in either run; "
          f"{cmp['agree']} of them with the same status in both runs; "
          f"{len(cmp['disagree'])} disagree")
    for claim, path, sigma, sa, pa, sb, pb in cmp["disagree"]:
        print(f"  {claim} {path} sigma = {sigma:g}: {sa} (replication {pa:.3f}) vs {sb} "
              f"(replication {pb:.3f})")
    return 1 if cmp["disagree"] else 0


if __name__ == "__main__":
    sys.exit(main())

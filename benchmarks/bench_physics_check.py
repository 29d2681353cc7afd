"""What the physics check adds to ``it2track reproduce``: its wall time, runs and share.

Two ways:

- ``--manifest DIR`` (one or more): read the ``manifest.json`` of finished ``reproduce`` runs
  and print, per run, the physics check's stages (simulation; files and animation), its runs
  and wall seconds per run, the rest of the pipeline and the total, and whether rounds came
  from an interrupted run's cache (their time is then not the check's);
- otherwise run the check itself (:func:`it2track.experiments.physics.run_physics`) on the
  study's defaults for ``--surfaces`` (default: all three) with the default design, and print
  per surface the wall and process CPU seconds, runs and seconds per run, with the 1-minute
  load average before and after (the machine is shared: the load says how far to trust it).

Run from the repository root::

    .venv/bin/python benchmarks/bench_physics_check.py --manifest results
    .venv/bin/python benchmarks/bench_physics_check.py --surfaces icy   # minutes
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path


def _from_manifest(folder: Path) -> None:
    m = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
    stages = m.get("stage_s", {})
    phys = m.get("physics", {})
    sim = stages.get("physics check (MuJoCo)", 0.0)
    files = stages.get("physics check: files and animation", 0.0)
    total = float(m["elapsed_s"])
    print(f"{folder}: command {m.get('command', '?')!r}")
    if phys.get("status") != "run":
        print(f"  physics check not run: {phys.get('reason', '?')}; total {total:.1f} s")
        return
    runs = int(phys["runs"])
    print(f"  physics check: simulation {sim:.1f} s ({runs} runs, {sim / runs:.3f} s/run), "
          f"files and animation {files:.1f} s; {sim + files:.1f} s of {total:.1f} s total "
          f"({100 * (sim + files) / total:.0f} %); the rest {total - sim - files:.1f} s")
    print(f"  design {phys['design']}; surfaces {phys['check']['surfaces']}")
    if phys.get("rounds_from_cache"):
        print(f"  note: {phys['rounds_from_cache']} round(s) came from a cache: not all of "
              "the check's time is in this run")


def _run(surfaces: list[str]) -> None:
    from it2track.experiments.physics import PhysicsCheck, run_physics
    from it2track.experiments.study import StudyConfig

    config = StudyConfig()
    for s in surfaces:
        check = PhysicsCheck(surfaces=(s,))
        load = os.getloadavg()[0]
        w0, c0 = time.perf_counter(), time.process_time()
        result = run_physics(config, check)
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        print(f"{s}: {result.runs} runs, wall {wall:.1f} s ({wall / result.runs:.3f} s/run), "
              f"process CPU {cpu:.1f} s; load {load:.1f} -> {os.getloadavg()[0]:.1f}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--manifest", nargs="+", type=Path, help="reproduce output folders")
    ap.add_argument("--surfaces", nargs="+", default=["dry", "wet", "icy"])
    args = ap.parse_args(argv)
    if args.manifest:
        for folder in args.manifest:
            _from_manifest(folder)
    else:
        _run(args.surfaces)
    return 0


if __name__ == "__main__":
    sys.exit(main())

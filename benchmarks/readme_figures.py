"""Re-measure every time and count README quotes, and print them in a form README can quote.

Run from the repository root (a few minutes; ``--suite`` adds the whole test suite, ~15 min)::

    .venv/bin/python benchmarks/readme_figures.py [--repeats 3] [--suite] [--skip-cold]

Measures, each command in a fresh process (``python -m it2track ...``), wall clock from start
to exit, with the load average before and after each:

1. ``it2track simulate`` (the default run), first after installing and warm. "First" is a
   process whose numba cache (``NUMBA_CACHE_DIR``) is an empty folder, as after ``pip
   install``; the kernels then compile in a background process, whose own time (wall and CPU,
   from its status file) is printed too. "Warm" is the same command once that compile has
   finished: the median of ``--repeats`` runs.
2. ``it2track reproduce --out DIR`` (the default study): first (an empty cache again, each of
   ``--repeats`` runs in a cache of its own; the kernels compile in the background, the
   study waits for the closed loop's), then ``it2track compile`` in an empty cache and the
   first ``reproduce`` after it (README's install command), and warm (median of
   ``--repeats``); the ratios.
3. ``it2track reproduce --quick --out DIR``, warm: median of ``--repeats``.
4. The test suite: tests collected and the strict expected failures marked (``pytest
   --collect-only``, in this process: seconds); with ``--suite``, the README's test command
   run once, its passed / skipped / xfailed counts and its wall time.

Everything is printed as plain lines (``name: value``) and, last, as the README sentences
that quote them. Numbers on a shared machine vary with its load: quote them with the load
average printed beside them, and re-measure on a quiet machine before a release.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _load() -> float:
    return os.getloadavg()[0]


def _timed(args: list[str], *, env: dict[str, str] | None = None,
           cwd: Path | None = None) -> tuple[float, float, float, str]:
    """(wall seconds, load before, load after, stderr) of ``python -m it2track ARGS``."""
    before = _load()
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "it2track", *args], cwd=cwd,
                          env=_user_env(env), capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SystemExit(f"it2track {' '.join(args)} failed ({proc.returncode}):\n"
                         f"{proc.stderr[-3000:]}")
    return wall, before, _load(), proc.stderr


def _user_env(env: dict[str, str] | None) -> dict[str, str]:
    """This process's environment with ``env`` on top, as a user's shell has it: without
    ``PYTHONDONTWRITEBYTECODE``, which some sandboxes set. With it every run compiles
    it2track's modules from source again (0.3-0.5 s a run here); a user's first run writes
    their bytecode caches and later runs read them (pip writes them for a wheel)."""
    out = {**os.environ, **(env or {})}
    out.pop("PYTHONDONTWRITEBYTECODE", None)
    return out


def _lock(env: dict[str, str]) -> Path:
    code = "from it2track.tracking import kernel_cache as k; print(k.lock_path())"
    out = subprocess.run([sys.executable, "-c", code], env={**os.environ, **env},
                         capture_output=True, text=True, check=True).stdout.strip()
    return Path(out)


def _wait_for_compile(env: dict[str, str]) -> dict[str, float]:
    """Wait until the background compile of this cache is done; its status."""
    from it2track.fuzzy.kernels import locked

    lock = _lock(env)
    while locked(str(lock)):
        time.sleep(0.5)
    try:
        return json.loads(lock.with_suffix(".json").read_text())
    except (OSError, ValueError):
        return {}


def _median(values: list[float]) -> str:
    return (f"{statistics.median(values):.1f} s (median of {len(values)}: "
            + ", ".join(f"{v:.1f}" for v in values) + ")")


def _loads(pairs: list[tuple[float, float]]) -> str:
    return ", ".join(f"{a:.1f}→{b:.1f}" for a, b in pairs)


def measure_simulate(repeats: int, out: dict[str, object]) -> None:
    with tempfile.TemporaryDirectory() as cache:
        env = {"NUMBA_CACHE_DIR": cache}
        wall, a, b, err = _timed(["simulate"], env=env)
        said = "compiling the simulation kernels, once per install" in err
        out["simulate, first run (empty kernel cache)"] = (
            f"{wall:.1f} s (load {a:.1f}→{b:.1f}; stage line shown: {'yes' if said else 'NO'})")
        status = _wait_for_compile(env)
        if status:
            out["kernel compile (background, for simulate)"] = _compile_status(status)
        runs = [_timed(["simulate"], env=env) for _ in range(repeats)]
        out["simulate, warm"] = (_median([r[0] for r in runs])
                                 + f" (load {_loads([(r[1], r[2]) for r in runs])})")
        out["simulate, first / warm"] = f"{wall / statistics.median(r[0] for r in runs):.2f}"


def _compile_status(status: dict[str, float]) -> str:
    def f(key: str) -> str:
        return f"{status.get(key, float('nan')):.1f}"

    return (f"closed loop {f('loop_seconds')} s wall ({f('loop_cpu_seconds')} s CPU), all "
            f"{f('seconds')} s wall ({f('cpu_seconds')} s CPU)")


def measure_reproduce(repeats: int, out: dict[str, object], *, cold: bool,
                      extra: list[str] | None = None) -> None:
    extra = list(extra or [])
    label = "reproduce (default" + (f", {' '.join(extra)})" if extra else ")")
    with tempfile.TemporaryDirectory() as tmp:
        tmp_path = Path(tmp)
        firsts: list[tuple[float, float, float]] = []
        after: tuple[float, float, float, str] | None = None
        for k in range(repeats if cold else 0):
            # an empty cache, as after `pip install`, without `it2track compile`
            env = {"NUMBA_CACHE_DIR": str(tmp_path / f"numba{k}")}
            Path(env["NUMBA_CACHE_DIR"]).mkdir()
            firsts.append(_timed(["reproduce", *extra, "--out", str(tmp_path / f"cold{k}")],
                                 env=env)[:3])
            status = _wait_for_compile(env)
            out[f"kernel compile (background, during first reproduce {k + 1})"] = (
                _compile_status(status) if status else "no status")
        if cold:
            out[f"{label}, first run (empty kernel cache)"] = (
                _median([r[0] for r in firsts]) + f" (load {_loads([r[1:] for r in firsts])})")
            # README's install command: `it2track compile`, then the first reproduce
            env = {"NUMBA_CACHE_DIR": str(tmp_path / "numba-compiled")}
            Path(env["NUMBA_CACHE_DIR"]).mkdir()
            wall, a, b, _ = _timed(["compile"], env=env)
            out["it2track compile (empty kernel cache)"] = f"{wall:.1f} s (load {a:.1f}→{b:.1f})"
            after = _timed(["reproduce", *extra, "--out", str(tmp_path / "after")], env=env)
            out[f"{label}, first run after `it2track compile`"] = (
                f"{after[0]:.1f} s (load {after[1]:.1f}→{after[2]:.1f}; compile line shown: "
                f"{'YES' if 'compiling the simulation kernels' in after[3] else 'no'})")
        runs = []
        for k in range(repeats):
            runs.append(_timed(["reproduce", *extra, "--out", str(tmp_path / f"warm{k}")]))
        warm = statistics.median(r[0] for r in runs)
        out[f"{label}, warm"] = (_median([r[0] for r in runs])
                                 + f" (load {_loads([(r[1], r[2]) for r in runs])})")
        if firsts:
            first = statistics.median(r[0] for r in firsts)
            out[f"{label}, first / warm (medians)"] = f"{first / warm:.2f}"
        if after is not None:
            out[f"{label}, first after `it2track compile` / warm"] = f"{after[0] / warm:.2f}"
        quick = [_timed(["reproduce", "--quick", "--out", str(tmp_path / f"quick{k}")])
                 for k in range(max(repeats, 3))]
        out["reproduce --quick, warm"] = (_median([r[0] for r in quick])
                                          + f" (load {_loads([(r[1], r[2]) for r in quick])})")


class _Counter:
    """A pytest plugin counting the collected tests and the xfail-marked ones."""

    def __init__(self) -> None:
        self.collected = 0
        self.xfail = 0

    def pytest_collection_finish(self, session) -> None:
        self.collected = len(session.items)
        self.xfail = sum(1 for item in session.items if item.get_closest_marker("xfail"))


def count_tests(out: dict[str, object]) -> _Counter:
    import pytest

    counter = _Counter()
    cwd, env = os.getcwd(), dict(os.environ)
    os.chdir(ROOT)
    try:  # pytest's per-file counts are not README's figures: only the totals are printed
        with contextlib.redirect_stdout(io.StringIO()):
            code = pytest.main(["--collect-only", "-qq", "-p", "no:cacheprovider"],
                               plugins=[counter])
    finally:  # the tests' conftest sets variables the measured commands must not inherit
        os.chdir(cwd)
        os.environ.clear()
        os.environ.update(env)
    if code != 0:
        raise SystemExit(f"pytest --collect-only failed ({code})")
    out["tests collected"] = counter.collected
    out["tests marked xfail (strict)"] = counter.xfail
    return counter


def run_suite(out: dict[str, object]) -> None:
    before = _load()
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider"],
                          cwd=ROOT, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t0
    last = proc.stdout.strip().splitlines()[-1] if proc.stdout.strip() else ""
    counts = {k: int(v) for v, k in re.findall(r"(\d+) (passed|failed|skipped|xfailed|"
                                                r"xpassed|errors?)", last)}
    out["test suite"] = (f"{counts} in {wall / 60:.1f} min (load {before:.1f}→{_load():.1f}; "
                         f"exit {proc.returncode})")
    failed = [line for line in proc.stdout.splitlines() if line.startswith(("FAILED", "ERROR"))]
    if failed:  # which ones: the summary's lines, so a failure needs no second run to name
        out["tests that failed"] = "; ".join(failed)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="warm runs per command")
    parser.add_argument("--suite", action="store_true", help="also run the whole test suite")
    parser.add_argument("--skip-cold", action="store_true",
                        help="no first-run (empty cache) measurements")
    parser.add_argument("--reproduce-args", default="",
                        help="options added to the default reproduce, e.g. '--no-physics "
                        "--no-chip' (what a machine without MuJoCo and the AVR toolchain runs)")
    args = parser.parse_args()
    if shutil.which("git"):
        rev = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                             capture_output=True, text=True, check=False).stdout.strip()
    else:
        rev = "?"
    out: dict[str, object] = {}
    print(f"README figures, {time.strftime('%Y-%m-%d %H:%M')}, revision {rev}, "
          f"{os.cpu_count()} CPUs, load average {_load():.2f}", flush=True)
    counter = count_tests(out)
    if not args.skip_cold:
        measure_simulate(args.repeats, out)
    else:
        runs = [_timed(["simulate"]) for _ in range(args.repeats)]
        out["simulate, warm"] = _median([r[0] for r in runs])
    measure_reproduce(args.repeats, out, cold=not args.skip_cold,
                      extra=args.reproduce_args.split())
    if args.suite:
        run_suite(out)
    print()
    for key, value in out.items():
        print(f"{key}: {value}")
    print(f"load average at the end: {_load():.2f}")
    print("\nREADME (Tests): "
          f"{counter.collected} tests, {counter.xfail} of them strict expected failures")


if __name__ == "__main__":
    main()

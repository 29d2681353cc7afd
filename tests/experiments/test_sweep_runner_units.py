"""run_sweep and SweepSummary (sweep/runner.py) on a four-run sweep whose simulation is replaced
by a formula of the run (so each test takes milliseconds and every number is known): what a
sweep and a resume compute and report, the progress bar, what the executor is handed and what
its results become, a failing chunk, a results.csv not ours, the temporaries of a killed run.
The real simulation through the same runner: test_sweep_store.py."""

from __future__ import annotations

import hashlib
import math
import os
import socket
import sys
import types
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from it2track.experiments.executors import InProcessExecutor
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.experiments.sweep import (
    StoreError,
    SweepPlan,
    SweepSummary,
    TrajectoryRef,
    run_sweep,
    simulate_grid_chunk,
)
from it2track.experiments.sweep import chunks as sweep_chunks
from it2track.experiments.sweep import runner as sweep_runner
from it2track.plant import RobotParams
from it2track.tracking import METRIC_NAMES, LoopConfig

DEAD_PID = 4999999  # above Linux's largest pid_max (2**22): never a live process


def _plan(seeds: int = 2, chunk_size: int = 3) -> SweepPlan:
    """Two PD controllers (kp 20 and 10) x one trajectory x one noise level x ``seeds``:
    ``2 * seeds`` runs; with the defaults 4 runs in chunks of 3 and 1."""
    return SweepPlan(
        config=LoopConfig(duration=0.1),
        robots=(RobotParams(),),
        robot_columns={},
        controllers=(ControllerSpec(kind=ControllerKind.PD, kp=20.0, kd=0.5),
                     ControllerSpec(kind=ControllerKind.PD, kp=10.0)),
        trajectory_refs=(TrajectoryRef("straight"),),
        noise_std=(0.0,),
        seeds=tuple(range(seeds)),
        chunk_size=chunk_size,
    )


def _value(kp: float, seed: int, metric: int) -> float:
    return kp + 0.25 * seed + metric / 64


@pytest.fixture
def calls(monkeypatch: pytest.MonkeyPatch) -> list[list[tuple[float, int]]]:
    """Replace the simulation by :func:`_value` of each run; record the runs of every call."""
    seen: list[list[tuple[float, int]]] = []

    def fake(controllers: Any, trajectories: Any, runs: Any, config: Any,
             batch_size: int) -> dict[str, np.ndarray]:
        kps = [float(controllers[c].kp) for c in runs.controller]
        seeds = [int(s) for s in runs.seed]
        seen.append(list(zip(kps, seeds, strict=True)))
        return {name: np.array([_value(kp, s, m) for kp, s in zip(kps, seeds, strict=True)])
                for m, name in enumerate(METRIC_NAMES)}

    monkeypatch.setattr(sweep_chunks, "simulate_metrics", fake)
    return seen


def _expected_chunk(plan: SweepPlan, chunk_id: int) -> bytes:
    chunk = plan.chunks()[chunk_id]
    kps = [20.0, 10.0]
    n = len(plan.seeds)
    runs = [(kps[r // n], plan.seeds[r % n]) for r in range(chunk.start, chunk.stop)]
    metrics = {name: np.array([_value(kp, s, m) for kp, s in runs])
               for m, name in enumerate(METRIC_NAMES)}
    return (plan.header_csv() + plan.rows_csv(chunk, metrics)).encode("utf-8")


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


# -- SweepSummary ---------------------------------------------------------------------------


def _summary(runs_computed: int, seconds: float) -> SweepSummary:
    return SweepSummary(Path("out"), 4, 2, 2, 0, runs_computed, seconds, 0, 0, ())


def test_runs_per_second_is_runs_computed_over_seconds_nan_without_time() -> None:
    assert _summary(3, 0.5).runs_per_second == 6.0
    assert _summary(4, 2.0).runs_per_second == 2.0
    assert math.isnan(_summary(4, 0.0).runs_per_second)
    assert math.isnan(_summary(0, -1.0).runs_per_second)


# -- a sweep, then a resume -----------------------------------------------------------------


def test_a_sweep_writes_every_chunk_and_results_and_reports_what_it_did(
    tmp_path: Path, calls: list[list[tuple[float, int]]], monkeypatch: pytest.MonkeyPatch
) -> None:
    clock = iter([10.0, 12.5])
    monkeypatch.setattr(sweep_runner, "time", types.SimpleNamespace(
        perf_counter=lambda: next(clock)))
    monkeypatch.setattr(sweep_runner, "peak_rss_bytes", lambda: 123456)
    monkeypatch.setattr(sweep_chunks, "peak_rss_bytes", lambda: 7000)
    plan = _plan()
    out = tmp_path / "a" / "b" / "out"  # parents created
    summary = run_sweep(plan, str(out), progress=False)  # the serial executor by default
    assert summary == SweepSummary(
        out=out, n_runs=4, n_chunks=2, chunks_computed=2, chunks_skipped=0, runs_computed=4,
        seconds=2.5, driver_peak_rss=123456, worker_peak_rss=7000,
        workers=(f"{socket.gethostname()}:{os.getpid()}",),
    )
    assert calls == [[(20.0, 0), (20.0, 1), (10.0, 0)], [(10.0, 1)]]
    chunks = [_expected_chunk(plan, 0), _expected_chunk(plan, 1)]
    for i, data in enumerate(chunks):
        path = out / "chunks" / f"chunk-{i:06d}.csv"
        assert path.read_bytes() == data
        assert (out / "chunks" / f"chunk-{i:06d}.csv.sha256").read_text() == (
            f"{_sha(data)}  chunk-{i:06d}.csv\n")
    header = plan.header_csv().encode()
    results = header + b"".join(c[len(header):] for c in chunks)
    assert (out / "results.csv").read_bytes() == results
    assert (out / "results.csv.sha256").read_text() == f"{_sha(results)}  results.csv\n"
    last = (out / "results.csv").read_text().splitlines()[-1].split(",")
    assert last[0] == "3" and last[-len(METRIC_NAMES):] == [
        repr(10.25 + m / 64) for m in range(len(METRIC_NAMES))]
    assert sorted(p.name for p in out.iterdir()) == [
        ".lock", "chunks", "results.csv", "results.csv.sha256", "sweep.json"]


def test_a_resume_computes_only_the_missing_chunk_and_counts_its_runs(
    tmp_path: Path, calls: list[list[tuple[float, int]]]
) -> None:
    plan = _plan()
    out = tmp_path / "out"
    run_sweep(plan, out, progress=False)
    reference = (out / "results.csv").read_bytes()
    with pytest.raises(StoreError, match="already holds a sweep"):
        run_sweep(plan, out, progress=False)
    (out / "chunks" / "chunk-000000.csv").unlink()  # the chunk of three runs
    calls.clear()
    summary = run_sweep(plan, out, resume=True, progress=False)
    assert calls == [[(20.0, 0), (20.0, 1), (10.0, 0)]]
    assert (summary.n_runs, summary.n_chunks) == (4, 2)
    assert (summary.chunks_computed, summary.chunks_skipped, summary.runs_computed) == (1, 1, 3)
    assert (out / "results.csv").read_bytes() == reference
    # Nothing missing: nothing computed, results.csv assembled again, the same bytes.
    calls.clear()
    summary = run_sweep(plan, out, resume=True, progress=False)
    assert calls == []
    assert (summary.chunks_computed, summary.chunks_skipped, summary.runs_computed) == (0, 2, 0)
    assert summary.workers == () and summary.worker_peak_rss == 0
    assert (out / "results.csv").read_bytes() == reference


# -- the progress bar -----------------------------------------------------------------------


class _Bar:
    """Records what a tqdm bar is given."""

    def __init__(self, **kwargs: Any) -> None:
        # (the stream as tqdm resolves it: file=None is sys.stderr)
        self.file = kwargs.pop("file", None) or sys.stderr
        self.kwargs: dict[str, Any] = kwargs
        self.updates: list[int] = []
        self.closed = False

    def update(self, n: int) -> None:
        self.updates.append(n)

    def close(self) -> None:
        self.closed = True


@pytest.fixture
def bars(monkeypatch: pytest.MonkeyPatch) -> list[_Bar]:
    """The bars run_sweep makes, in order (tqdm replaced by :class:`_Bar`)."""
    made: list[_Bar] = []

    def make(**kwargs: Any) -> _Bar:
        made.append(_Bar(**kwargs))
        return made[-1]

    monkeypatch.setattr(sweep_runner, "tqdm", make)
    return made


def test_the_bar_counts_runs_from_those_already_done(
    tmp_path: Path, calls: list[list[tuple[float, int]]], bars: list[_Bar]
) -> None:
    plan, out = _plan(), tmp_path / "out"
    run_sweep(plan, out)
    (out / "chunks" / "chunk-000001.csv").unlink()  # the chunk of one run
    run_sweep(plan, out, resume=True, progress=False)
    first, second = bars
    common = {"total": 4, "unit": "run", "desc": "sweep", "dynamic_ncols": True}
    assert first.file is sys.stderr and second.file is sys.stderr
    assert first.kwargs == {**common, "initial": 0, "disable": False}
    assert (first.updates, first.closed) == ([3, 1], True)
    assert second.kwargs == {**common, "initial": 3, "disable": True}
    assert (second.updates, second.closed) == ([1], True)


def test_progress_shows_a_bar_of_runs_on_stderr_and_nothing_without_it(
    tmp_path: Path, calls: list[list[tuple[float, int]]], capsys: pytest.CaptureFixture[str]
) -> None:
    run_sweep(_plan(), tmp_path / "quiet", progress=False)
    assert capsys.readouterr() == ("", "")
    run_sweep(_plan(), tmp_path / "shown")
    shown = capsys.readouterr()
    assert shown.out == ""
    assert "sweep:   0%" in shown.err and "0/4 [" in shown.err, shown.err
    assert "sweep: 100%" in shown.err and "4/4 [" in shown.err and "run/s]" in shown.err


# -- the executor ---------------------------------------------------------------------------


class _Recording(InProcessExecutor):
    """Runs the tasks in order but yields them last first, as workers named in ``names`` with
    peak memory ``rss``; records what it was handed."""

    def __init__(self, names: list[str], rss: list[int], fail_at: int | None = None) -> None:
        self.names, self.rss, self.fail_at = names, rss, fail_at
        self.handed: list[Any] = []

    def imap_unordered(self, fn: Any, tasks: Any, *, max_pending: int | None = None) -> Any:
        self.handed.append((fn, max_pending))
        done = []
        for task in tasks:
            if task.chunk_id == self.fail_at:
                raise RuntimeError(f"chunk {task.chunk_id} failed")
            result = fn(task)
            done.append((task, replace(result, worker=self.names[task.chunk_id],
                                       peak_rss=self.rss[task.chunk_id])))
            if self.fail_at is not None:
                yield done.pop()
        yield from reversed(done)


def test_the_executor_gets_the_chunk_function_and_max_pending_and_any_order_is_fine(
    tmp_path: Path, calls: list[list[tuple[float, int]]]
) -> None:
    plan = _plan(seeds=3, chunk_size=1)  # 6 chunks of one run
    names = ["w5", "w3", "w0", "w3", "w1", "w2"]
    executor = _Recording(names, [5, 9, 2, 0, 9, 1])
    summary = run_sweep(plan, tmp_path / "out", executor=executor, max_pending=3,
                        progress=False)
    assert executor.handed == [(simulate_grid_chunk, 3)]
    assert summary.workers == ("w0", "w1", "w2", "w3", "w5")
    assert summary.worker_peak_rss == 9
    assert (summary.chunks_computed, summary.runs_computed) == (6, 6)
    for i in range(6):
        assert (tmp_path / "out" / "chunks" / f"chunk-{i:06d}.csv").read_bytes() == (
            _expected_chunk(plan, i))
    serial = run_sweep(plan, tmp_path / "serial", progress=False)
    assert (tmp_path / "out" / "results.csv").read_bytes() == (
        tmp_path / "serial" / "results.csv").read_bytes()
    assert serial.worker_peak_rss > 0
    quiet = _Recording(names, [0] * 6)
    assert run_sweep(plan, tmp_path / "zero", executor=quiet,
                     progress=False).worker_peak_rss == 0
    assert quiet.handed == [(simulate_grid_chunk, None)]


def test_a_failing_chunk_stops_the_sweep_keeping_the_chunks_done_and_resume_finishes(
    tmp_path: Path, calls: list[list[tuple[float, int]]], bars: list[_Bar]
) -> None:
    plan, out = _plan(seeds=3, chunk_size=2), tmp_path / "out"  # 3 chunks of two runs
    failing = _Recording(["w0", "w1", "w2"], [1, 1, 1], fail_at=2)
    with pytest.raises(RuntimeError, match=r"^chunk 2 failed$"):
        run_sweep(plan, out, executor=failing, progress=False)
    assert bars[0].closed and bars[0].updates == [2, 2]
    assert sorted(p.name for p in (out / "chunks").iterdir()) == [
        "chunk-000000.csv", "chunk-000000.csv.sha256", "chunk-000001.csv",
        "chunk-000001.csv.sha256"]
    assert not (out / "results.csv").exists()
    calls.clear()
    summary = run_sweep(plan, out, resume=True, progress=False)  # the lock was released
    assert calls == [[(10.0, 1), (10.0, 2)]]
    assert (summary.chunks_computed, summary.chunks_skipped, summary.runs_computed) == (1, 2, 2)
    run_sweep(plan, tmp_path / "clean", progress=False)
    assert (out / "results.csv").read_bytes() == (tmp_path / "clean" / "results.csv").read_bytes()


# -- a folder that is not empty -------------------------------------------------------------


def test_a_results_csv_not_ours_stops_the_sweep_before_anything_is_created(
    tmp_path: Path, calls: list[list[tuple[float, int]]]
) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "results.csv").write_text("the user's own\n")
    with pytest.raises(StoreError) as info:
        run_sweep(_plan(), out, progress=False)
    assert str(info.value) == (
        f"{out / 'results.csv'} exists and it2track cannot prove it wrote it (no SHA-256 it "
        "recorded when writing matches the file); move it away, choose another name, or pass "
        "--force to replace it"
    )
    assert [p.name for p in out.iterdir()] == ["results.csv"]
    assert calls == []
    summary = run_sweep(_plan(), out, force=True, progress=False)
    assert summary.chunks_computed == 2
    clean = tmp_path / "clean"
    run_sweep(_plan(), clean, progress=False)
    assert (out / "results.csv").read_bytes() == (clean / "results.csv").read_bytes()
    assert (out / "results.csv.sha256").read_bytes() == (clean / "results.csv.sha256").read_bytes()


def test_temporaries_of_a_killed_run_are_removed_and_nothing_else(
    tmp_path: Path, calls: list[list[tuple[float, int]]]
) -> None:
    out = tmp_path / "out"
    (out / "chunks").mkdir(parents=True)

    def temp(target: str) -> str:
        return f".{target}.it2track-{DEAD_PID}-0123456789ab.tmp"

    ours = [temp("sweep.json"), temp("results.csv"), temp("results.csv.sha256")]
    ours_chunks = [temp("chunk-000000.csv"), temp("chunk-000001.csv.sha256")]
    kept = [temp("notes.csv"), ".results.csv.tmp"]
    kept_chunks = [temp("chunk-000002.csv"), temp("chunk-000002.csv.sha256"), temp("x.csv")]
    for name in ours + kept:
        (out / name).write_text("stale")
    for name in ours_chunks + kept_chunks:
        (out / "chunks" / name).write_text("stale")
    run_sweep(_plan(), out, progress=False)  # chunks 0 and 1
    left = {p.name for p in out.iterdir()}
    assert left == {*kept, ".lock", "chunks", "results.csv", "results.csv.sha256", "sweep.json"}
    assert {p.name for p in (out / "chunks").iterdir()} == {
        *kept_chunks, "chunk-000000.csv", "chunk-000000.csv.sha256", "chunk-000001.csv",
        "chunk-000001.csv.sha256"}

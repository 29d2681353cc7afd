"""The sweep results store: exact results, resume, kill -9 / Ctrl-C and resume, config hash."""

from __future__ import annotations

import csv
import io
import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from it2track import heading_fls, save
from it2track.cli.sweep import sweep as sweep_command
from it2track.experiments.sweep import (
    StoreError,
    digest_path,
    load_sweep_config,
    read_results,
    run_sweep,
)
from it2track.experiments.sweep import chunks as sweep_chunks
from it2track.experiments.sweep import plan as sweep_plan
from it2track.experiments.sweep import store as sweep_store
from it2track.tracking import METRIC_NAMES, RunTable, simulate_metrics

SMALL = """
[sweep]
seed = 5
seeds = 3
noise_std = [0.0, 0.2]
trajectories = ["straight", "sinusoidal"]
chunk_size = 7

[simulation]
duration = 1.0

[robot]
half_track = [5.6, 0.4]

[[controllers]]
kind = "flc"

[[controllers]]
kind = "it2"
fou = [0.2, 0.6]

[[controllers]]
kind = "pd"
kp = 20.0
kd = 0.5
"""

# 2 controllers x 1 trajectory x 1 noise level x 200 seeds of 1 s = 400 runs in 40 chunks:
# long enough (seconds) to be killed mid-way, short enough for the test budget.
SLOW = """
[sweep]
seeds = 200
noise_std = 0.1
trajectories = "curved"
chunk_size = 10

[simulation]
duration = 1.0

[[controllers]]
kind = "flc"

[[controllers]]
kind = "it2"
fou = 0.3
"""


def write(tmp_path: Path, text: str, name: str = "sweep.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def test_results_equal_direct_simulation(tmp_path: Path) -> None:
    plan = load_sweep_config(write(tmp_path, SMALL))
    summary = run_sweep(plan, tmp_path / "out", progress=False)
    assert summary.n_runs == plan.n_runs == 2 * 4 * 2 * 2 * 3
    assert summary.chunks_computed == len(plan.chunks()) and summary.chunks_skipped == 0
    header, rows = read_results(tmp_path / "out" / "results.csv")
    assert header == plan.columns
    assert [int(r[0]) for r in rows] == list(range(plan.n_runs))
    col = {name: i for i, name in enumerate(header)}
    controllers = [spec.build() for spec in plan.controllers]
    for g in range(len(plan.robots)):
        mine = [r for r in rows if int(r[col["group"]]) == g]
        assert {float(r[col["half_track"]]) for r in mine} == {plan.robots[g].half_track}
        runs = RunTable(
            [int(r[col["controller"]]) for r in mine],
            [[ref.name for ref in plan.trajectory_refs].index(r[col["trajectory"]])
             for r in mine],
            [float(r[col["noise_std"]]) for r in mine],
            [int(r[col["seed"]]) for r in mine],
        )
        expected = simulate_metrics(
            controllers, plan.trajectories, runs, plan.group_config(g), batch_size=5
        )
        for name in METRIC_NAMES:
            got = np.array([float(r[col[name]]) for r in mine])
            # repr round-trips exactly: the store holds the engine's bits.
            np.testing.assert_array_equal(got, expected[name], err_msg=f"{name}, group {g}")
    labels = [r[col["label"]] for r in rows[:: 2 * 2 * 3]][:4]
    assert labels == ["FLC", "IT2FLC FoU 0.2", "IT2FLC FoU 0.6", "PD kp 20 kd 0.5"]


def test_store_is_standard_csv(tmp_path: Path) -> None:
    text = SMALL.replace('kind = "pd"', 'kind = "pd"\nlabel = \'PD, "tuned"\'')
    plan = load_sweep_config(write(tmp_path, text))
    run_sweep(plan, tmp_path / "out", progress=False)
    written = (tmp_path / "out" / "results.csv").read_text(encoding="utf-8")
    header, rows = read_results(tmp_path / "out" / "results.csv")
    assert 'PD, "tuned"' in {r[header.index("label")] for r in rows}
    assert rows[0][header.index("fou")] == ""  # fields a controller does not have stay empty
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    assert buf.getvalue() == written  # exactly what csv.writer writes


def test_chunk_size_does_not_change_results(tmp_path: Path) -> None:
    a = load_sweep_config(write(tmp_path, SMALL, "a.toml"))
    b = load_sweep_config(write(tmp_path, SMALL.replace("chunk_size = 7", "chunk_size = 1000"),
                                "b.toml"))
    assert a.config_hash() != b.config_hash()  # the layout is part of the identity
    run_sweep(a, tmp_path / "a", progress=False)
    run_sweep(b, tmp_path / "b", progress=False)
    assert len(list((tmp_path / "b" / "chunks").glob("chunk-*.csv"))) == 2  # one per plant set
    assert (tmp_path / "a" / "results.csv").read_bytes() == (
        tmp_path / "b" / "results.csv"
    ).read_bytes()


def test_resume_recomputes_only_missing_or_broken_chunks(tmp_path: Path) -> None:
    plan = load_sweep_config(write(tmp_path, SMALL))
    out = tmp_path / "out"
    run_sweep(plan, out, progress=False)
    reference = (out / "results.csv").read_bytes()
    chunks = sorted((out / "chunks").glob("chunk-*.csv"))
    chunks[1].unlink()
    chunks[4].unlink()
    text = chunks[2].read_text()
    chunks[2].write_text(text[: len(text) // 2])  # torn file (as if written without rename)
    # A killed writer's temporary (our naming, a pid that cannot exist on Linux) ...
    ours = out / "chunks" / f".{chunks[3].name}.it2track-4999999-0123456789ab.tmp"
    ours.write_text("partial")
    # ... and the user's own files that merely look like temporaries: they must survive.
    foreign = [out / "chunks" / f".{chunks[3].name}.999.tmp", out / ".notes.tmp",
               out / f".results.csv.it2track-{os.getpid()}-0123456789ab.tmp"]  # a live pid
    for f in foreign:
        f.write_text("the user's")
    (out / "results.csv").unlink()
    summary = run_sweep(plan, out, resume=True, progress=False)
    assert summary.chunks_computed == 3
    assert summary.chunks_skipped == len(chunks) - 3
    assert (out / "results.csv").read_bytes() == reference
    assert not ours.exists()
    assert all(f.read_text() == "the user's" for f in foreign)
    for f in foreign:
        f.unlink()
    assert not list(out.rglob("*.tmp"))
    # Resuming a finished sweep only re-assembles the same file.
    again = run_sweep(plan, out, resume=True, progress=False)
    assert again.chunks_computed == 0
    assert (out / "results.csv").read_bytes() == reference


def test_store_refuses_other_configs_and_second_writers(tmp_path: Path) -> None:
    plan = load_sweep_config(write(tmp_path, SMALL))
    out = tmp_path / "out"
    run_sweep(plan, out, progress=False)
    with pytest.raises(StoreError, match="already holds a sweep"):
        run_sweep(plan, out, progress=False)
    other = load_sweep_config(
        write(tmp_path, SMALL.replace("noise_std = [0.0, 0.2]", "noise_std = [0.0, 0.3]"),
              "other.toml")
    )
    with pytest.raises(StoreError, match=r"configuration changed .*differs in: noise_std"):
        run_sweep(other, out, resume=True, progress=False)
    # Chunk files without sweep.json belong to nobody.
    (out / "sweep.json").unlink()
    with pytest.raises(StoreError, match=r"no sweep\.json"):
        run_sweep(plan, out, resume=True, progress=False)

    fcntl = pytest.importorskip("fcntl")
    locked = tmp_path / "locked"
    locked.mkdir()
    fd = os.open(locked / ".lock", os.O_RDWR | os.O_CREAT)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(StoreError, match="another process"):
            run_sweep(plan, locked, progress=False)
    finally:
        os.close(fd)


def test_cli_sweep_run_refuse_resume(tmp_path: Path) -> None:
    config = write(tmp_path, SMALL)
    out = tmp_path / "out"
    runner = CliRunner()
    args = ["--config", str(config), "--out", str(out), "--no-progress"]
    first = runner.invoke(sweep_command, args)
    assert first.exit_code == 0, first.output
    assert "96 runs computed (14 chunks, 0 already done)" in first.output
    second = runner.invoke(sweep_command, args)
    assert second.exit_code == 1
    assert "already holds a sweep" in second.output
    third = runner.invoke(sweep_command, [*args, "--resume"])
    assert third.exit_code == 0, third.output
    assert "0 runs computed (0 chunks, 14 already done)" in third.output
    bad = write(tmp_path, SMALL.replace("seeds = 3", "seeds = []"), "bad.toml")
    fourth = runner.invoke(sweep_command, ["--config", str(bad), "--out", str(tmp_path / "x")])
    assert fourth.exit_code == 1
    assert "seeds=[] is an empty axis" in fourth.output and str(bad) in fourth.output


# -- identity: file contents and the it2track version, not paths ----------------------------

FILE_SWEEP = """
[sweep]
seeds = 2
noise_std = 0.1
trajectories = "sinusoidal"
chunk_size = 2

[simulation]
duration = 0.5

[[controllers]]
kind = "flc"

[[controllers]]
kind = "file"
path = "{path}"
"""


def test_file_controller_is_identified_by_its_content(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    save(heading_fls(0.3), tmp_path / "ctrl.t2fis")
    config = write(tmp_path, FILE_SWEEP.format(path="ctrl.t2fis"))
    out = tmp_path / "out"
    first = run_sweep(load_sweep_config(config), out, progress=False)
    reference = (out / "results.csv").read_bytes()
    header, _ = read_results(out / "results.csv")
    assert "path" not in header and "file_sha256" in header  # rows follow the content
    assert json.loads((out / "sweep.json").read_text())["controller_files"] == {
        "ctrl.t2fis": str(tmp_path / "ctrl.t2fis")
    }

    # The same file reached by other paths: an absolute one, a relative config path.
    other = tmp_path / "elsewhere"
    other.mkdir()
    absolute = write(other, FILE_SWEEP.format(path=tmp_path / "ctrl.t2fis"))
    monkeypatch.chdir(tmp_path)
    for cfg in (absolute, Path("sweep.toml")):
        (out / "results.csv").unlink()
        chunks = sorted((out / "chunks").glob("chunk-*.csv"))
        chunks[-1].unlink()
        summary = run_sweep(load_sweep_config(cfg), out, resume=True, progress=False)
        assert (summary.chunks_computed, summary.chunks_skipped) == (1, first.n_chunks - 1)
        assert (out / "results.csv").read_bytes() == reference

    # An edited controller file is another controller: refused, naming the file.
    save(heading_fls(0.5), tmp_path / "ctrl.t2fis")
    with pytest.raises(StoreError) as info:
        run_sweep(load_sweep_config(config), out, resume=True, progress=False)
    message = str(info.value)
    assert f"controller file {str(tmp_path / 'ctrl.t2fis')!r}" in message, message
    assert "has changed" in message and "differs in: controllers" in message, message


def test_file_edited_while_the_sweep_runs_is_refused(tmp_path: Path) -> None:
    save(heading_fls(0.3), tmp_path / "ctrl.t2fis")
    plan = load_sweep_config(write(tmp_path, FILE_SWEEP.format(path="ctrl.t2fis")))
    save(heading_fls(0.5), tmp_path / "ctrl.t2fis")  # after planning, before the runs
    with pytest.raises(ValueError, match=r"ctrl\.t2fis' changed since the sweep was planned"):
        run_sweep(plan, tmp_path / "out", progress=False)
    # Only chunk 0 (the FLC's runs) was written; the file controller's chunk was refused.
    assert [p.name for p in (tmp_path / "out" / "chunks").glob("chunk-*.csv")] == [
        "chunk-000000.csv"
    ]


def test_store_of_another_it2track_version_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    plan = load_sweep_config(write(tmp_path, FILE_SWEEP.replace(
        'kind = "file"\npath = "{path}"', 'kind = "it2"\nfou = 0.2'
    )))  # fmt: skip
    out = tmp_path / "out"
    run_sweep(plan, out, progress=False)
    for module in (sweep_plan, sweep_store):  # the plan hashes it, the store checks it
        monkeypatch.setattr(module, "__version__", "99.0")
    assert plan.normalised()["it2track_version"] == "99.0"  # part of the hash, too
    with pytest.raises(StoreError, match=r"started by it2track 0\.1\.0, this is it2track 99"):
        run_sweep(plan, out, resume=True, progress=False)


def test_cli_sweep_reports_a_failing_run_without_traceback(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def broken(*args: object, **kwargs: object) -> None:
        raise ValueError("trajectory too short for the loop")

    monkeypatch.setattr(sweep_chunks, "simulate_metrics", broken)
    config = write(tmp_path, SMALL)
    out = tmp_path / "out"
    result = CliRunner().invoke(sweep_command, ["--config", str(config), "--out", str(out),
                                                "--no-progress"])  # fmt: skip
    assert result.exit_code == 1 and isinstance(result.exception, SystemExit), result.output
    assert "the sweep stopped: ValueError: trajectory too short for the loop" in result.output
    assert "rerun with --resume" in result.output


# -- killing a real process -------------------------------------------------------------------


@pytest.fixture(scope="module")
def slow_reference(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, bytes]:
    base = tmp_path_factory.mktemp("slow")
    config = write(base, SLOW)
    run_sweep(load_sweep_config(config), base / "reference", progress=False)
    return config, (base / "reference" / "results.csv").read_bytes()


# Imported by the sweep subprocess (and its spawned workers): chunk GATE and later ones wait
# (after writing a marker) instead of computing, so that the signal always reaches a sweep with
# exactly the chunks before GATE saved and the rest still to do -- never a finished one.
GATE_MODULE = """
import os
import time
from pathlib import Path

from it2track.experiments.sweep import runner as _sweep

_real = _sweep.simulate_grid_chunk


def gated(chunk):
    if chunk.chunk_id >= int(os.environ["SWEEP_GATE"]):
        Path(os.environ["SWEEP_GATE_MARKER"]).touch()
        time.sleep(120)
    return _real(chunk)


_sweep.simulate_grid_chunk = gated
"""


def _complete_chunks(out: Path) -> list[str]:
    """Chunk files whose checksum file exists too (what a resume will keep)."""
    return sorted(
        p.name for p in out.glob("chunks/chunk-*.csv") if digest_path(p).exists()
    )


def _start_and_wait_for_chunks(
    config: Path, out: Path, n: int, workers: int
) -> subprocess.Popen[bytes]:
    """Start a sweep whose chunks >= n block, and wait until it is blocked with n saved."""
    gate_dir = out.parent / "gate"
    gate_dir.mkdir()
    (gate_dir / "sweepgate.py").write_text(GATE_MODULE)
    marker = gate_dir / "reached"
    env = {**os.environ, "SWEEP_GATE": str(n), "SWEEP_GATE_MARKER": str(marker),
           "PYTHONPATH": os.pathsep.join([str(gate_dir), os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.Popen(
        [sys.executable, "-c", "import sweepgate; from it2track.cli.main import main; main()",
         "sweep", "--config", str(config), "--out", str(out), "--no-progress",
         "--workers", str(workers)],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
    )  # fmt: skip
    deadline = time.monotonic() + 60
    while not marker.exists() or len(_complete_chunks(out)) < n:
        if proc.poll() is not None:
            _, err = proc.communicate()
            pytest.fail(f"sweep exited early ({proc.returncode}): {err.decode()}")
        if time.monotonic() > deadline:
            proc.kill()
            pytest.fail("the sweep did not reach its gate within 60 s")
        time.sleep(0.005)
    return proc


def _children(pid: int) -> list[int]:
    path = Path(f"/proc/{pid}/task/{pid}/children")
    return [int(p) for p in path.read_text().split()] if path.exists() else []


def _alive(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"  # a zombie has exited


@pytest.mark.parametrize(
    ("sig", "workers"),
    [(signal.SIGKILL, 0), (signal.SIGINT, 0), (signal.SIGKILL, 2)],
    ids=["SIGKILL", "SIGINT", "SIGKILL-2-workers"],
)
def test_killed_sweep_resumes_to_identical_results(
    tmp_path: Path, slow_reference: tuple[Path, bytes], sig: signal.Signals, workers: int
) -> None:
    config, reference = slow_reference
    plan = load_sweep_config(config)
    n_chunks = len(plan.chunks())
    out = tmp_path / "out"
    proc = _start_and_wait_for_chunks(config, out, 3, workers)
    children = _children(proc.pid)
    if workers and sys.platform == "linux":
        assert len(children) >= workers  # the workers (and multiprocessing's resource tracker)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    if sig is signal.SIGKILL:
        assert proc.returncode == -signal.SIGKILL
    else:
        assert proc.returncode == 130, err.decode()
        assert "rerun with --resume" in err.decode()
    saved = _complete_chunks(out)
    assert len(saved) == 3 < n_chunks, "the sweep was not interrupted at its gate"
    assert not (out / "results.csv").exists()
    if workers:
        # Worker processes notice their driver's death and exit (no orphans left computing).
        deadline = time.monotonic() + 10
        while any(_alive(c) for c in children) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not [c for c in children if _alive(c)], "orphaned worker processes"

    result = CliRunner().invoke(
        sweep_command, ["--config", str(config), "--out", str(out), "--resume", "--no-progress"]
    )
    assert result.exit_code == 0, result.output
    assert f"{n_chunks - len(saved)} chunks, {len(saved)} already done" in result.output
    assert (out / "results.csv").read_bytes() == reference  # no duplicate, no missing row
    assert sorted(p.name for p in (out / "chunks").iterdir()) == sorted(
        [f"chunk-{i:06d}.csv" for i in range(n_chunks)]
        + [f"chunk-{i:06d}.csv.sha256" for i in range(n_chunks)]
    )

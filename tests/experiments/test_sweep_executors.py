"""Executors: local processes and a Dask cluster give the in-process results, byte for byte."""

from __future__ import annotations

import os
import sys
import textwrap
from pathlib import Path

import pytest

from it2track.experiments.executors import (
    DaskExecutor,
    ExecutorError,
    InProcessExecutor,
    ProcessExecutor,
    make_executor,
)
from it2track.experiments.sweep import load_sweep_config, run_sweep

CONFIG = """
[sweep]
seed = 11
seeds = 4
noise_std = [0.05, 0.2]
trajectories = ["curved", "sinusoidal"]
chunk_size = 9

[simulation]
duration = 1.0

[robot.motor]
resistance = [5.0, 4.0]

[[controllers]]
kind = "flc"

[[controllers]]
kind = "it2"
fou = [0.2, 0.5]
"""


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, bytes]:
    base = tmp_path_factory.mktemp("executors")
    config = base / "sweep.toml"
    config.write_text(textwrap.dedent(CONFIG), encoding="utf-8")
    run_sweep(load_sweep_config(config), base / "in-process", progress=False)
    return config, (base / "in-process" / "results.csv").read_bytes()


def _chunks(out: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted((out / "chunks").iterdir())}


def test_two_local_workers_equal_in_process(
    tmp_path: Path, reference: tuple[Path, bytes]
) -> None:
    config, expected = reference
    plan = load_sweep_config(config)
    with ProcessExecutor(2) as ex:
        summary = run_sweep(plan, tmp_path / "out", executor=ex, progress=False)
    assert summary.chunks_computed == len(plan.chunks())
    assert all(w.split(":")[-1] != str(os.getpid()) for w in summary.workers)  # not us
    assert (tmp_path / "out" / "results.csv").read_bytes() == expected
    assert _chunks(tmp_path / "out") == _chunks(config.parent / "in-process")


def test_dask_local_cluster_equals_in_process(
    tmp_path: Path, reference: tuple[Path, bytes]
) -> None:
    distributed = pytest.importorskip("distributed")
    config, expected = reference
    plan = load_sweep_config(config)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
    ) as cluster:
        with DaskExecutor(cluster.scheduler_address) as ex:
            assert ex.n_workers == 2
            summary = run_sweep(plan, tmp_path / "out", executor=ex, progress=False)
    assert summary.chunks_computed == len(plan.chunks())
    assert (tmp_path / "out" / "results.csv").read_bytes() == expected


def test_make_executor_maps_options() -> None:
    assert isinstance(make_executor(), InProcessExecutor)
    assert isinstance(make_executor(workers=0), InProcessExecutor)
    ex = make_executor(workers=3)
    assert isinstance(ex, ProcessExecutor) and ex.n_workers == 3
    ex.close()
    with pytest.raises(ExecutorError, match="not both"):
        make_executor(workers=2, scheduler="tcp://127.0.0.1:8786")
    with pytest.raises(ExecutorError, match="workers=-1"):
        make_executor(workers=-1)
    with pytest.raises(ExecutorError, match="context='fork'"):
        ProcessExecutor(2, context="fork")


def test_dask_missing_is_a_clear_error(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)  # import now raises ImportError
    with pytest.raises(ExecutorError, match=r"pip install 'it2track\[dask\]'"):
        DaskExecutor("tcp://127.0.0.1:8786")


def _square(x: int) -> int:
    if x == 3:
        raise KeyError("three")
    return x * x


def test_imap_unordered_contract() -> None:
    ex = InProcessExecutor()
    assert list(ex.imap_unordered(_square, [1, 2])) == [(1, 1), (2, 4)]
    with pytest.raises(KeyError, match="three"):
        list(ex.imap_unordered(_square, [1, 3]))
    with pytest.raises(ValueError, match="max_pending"):
        list(ex.imap_unordered(_square, [1], max_pending=0))


def test_local_workers_share_the_cores_between_their_kernel_threads(monkeypatch) -> None:
    # Each worker's compiled kernels would otherwise start one thread per CPU: N workers on N
    # CPUs ran N * N threads, and --workers 2 was slower than in-process (bench_sweep).
    import operator

    from it2track.fuzzy import kernels

    monkeypatch.delenv("NUMBA_NUM_THREADS", raising=False)
    cpus = len(os.sched_getaffinity(0))
    with ProcessExecutor(2) as ex:
        got = [r for _, r in ex.imap_unordered(operator.call, [kernels.threads] * 4)]
    assert got == [max(1, cpus // 2)] * 4
    # A user's own setting wins (a value no default would give).
    monkeypatch.setenv("NUMBA_NUM_THREADS", "7")
    with ProcessExecutor(1) as ex:
        got = [r for _, r in ex.imap_unordered(os.getenv, ["NUMBA_NUM_THREADS"])]
    assert got == ["7"]


def test_worker_threads_are_set_also_when_numba_was_imported_first():
    # A worker whose __main__ imported numba already has read NUMBA_NUM_THREADS: the
    # initialiser must then set the thread count itself.
    import subprocess

    code = ("import os, numba; os.environ.pop('NUMBA_NUM_THREADS', None); "
            "from it2track.experiments.executors import _init_worker; "
            "_init_worker(os.getpid(), 1); print(numba.get_num_threads())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env={k: v for k, v in os.environ.items()
                                          if k != "NUMBA_NUM_THREADS"})
    assert out.stdout.strip() == "1"

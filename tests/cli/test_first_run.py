"""The first run after installing: the kernels compile once, said and shown, in a background
process while the numpy engine computes (same numbers); the entry points compile once each.

Most tests drive the machinery with a lock this test holds or a stand-in compile; one slow test
runs ``it2track simulate`` in a fresh process with an empty numba cache, end to end.
"""

from __future__ import annotations

import fcntl
import io
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import it2track
from it2track.cli import kernels as cli_kernels
from it2track.fuzzy import kernels
from it2track.tracking import LoopConfig, RunTable, compiled, kernel_cache, simulate_metrics
from it2track.tracking.controllers import FuzzyHeadingController, PDHeadingController
from it2track.tracking.trajectories import get_trajectory

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def held_lock(tmp_path):
    """A lock file held (exclusively) by this test, as a background compile holds it."""
    path = tmp_path / "kernels.lock"
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
    fcntl.flock(fd, fcntl.LOCK_EX)
    yield path, fd
    os.close(fd)


def test_a_held_lock_is_seen_and_a_released_one_is_not(held_lock, tmp_path):
    path, fd = held_lock
    assert kernels.locked(str(path)) and kernel_cache.compiling(path)
    fcntl.flock(fd, fcntl.LOCK_UN)
    assert not kernels.locked(str(path)) and not kernel_cache.compiling(path)
    assert not kernels.locked(str(tmp_path / "absent.lock"))
    link = tmp_path / "link.lock"
    link.symlink_to(path)
    fcntl.flock(fd, fcntl.LOCK_EX)
    assert not kernels.locked(str(link))  # a planted link is never followed


def test_while_the_lock_is_held_the_numpy_engine_answers(held_lock, monkeypatch):
    pytest.importorskip("numba")
    path, fd = held_lock
    monkeypatch.delenv(kernels.ENGINE_ENV, raising=False)
    monkeypatch.setattr(kernels, "_jit", None)  # as in a fresh command: nothing loaded yet
    x = np.linspace(-1, 1, 7)
    with kernel_cache.deferring(path):
        assert os.environ[kernels.LOCK_ENV] == str(path)  # for the workers it starts
        assert kernels.load_jit() is None and compiled.load() is None
        fls = it2track.heading_fls(0.2)
        deferred = fls(x, x[::-1])
        assert "_kernel_pack" not in fls.__dict__  # asked again at the next call
        fcntl.flock(fd, fcntl.LOCK_UN)  # the compile ends
        assert kernels.load_jit() is not None and compiled.load() is not None
        again = fls(x, x[::-1])
        assert fls.__dict__["_kernel_pack"] is not None
    assert kernels.LOCK_ENV not in os.environ and kernels._defer is None
    assert deferred.tobytes() == again.tobytes()


def test_cached_is_true_once_compiled_and_real_runs_add_no_specialisation():
    """After compile_all, the probe finds every entry point; runs of every kind (fuzzy and PD
    controllers, traces, batches, scalar calls, type-1 and other reducers) use exactly the
    signatures the probe checks, so a warm cache never compiles again."""
    pytest.importorskip("numba")
    code = """
import json, numpy as np, it2track
from it2track.fuzzy import Reducer, _jit as fj
from it2track.tracking import _jit as tj, kernel_cache as kc, LoopConfig, RunTable, run_grid
from it2track.tracking import simulate, simulate_metrics, get_trajectory
from it2track.tracking.controllers import FuzzyHeadingController, PDHeadingController
kc.compile_all()
probe = kc.cached()
ctrls = [FuzzyHeadingController(fls=it2track.heading_fls(0.2)),
         FuzzyHeadingController(fls=it2track.heading_fls(0.0)), PDHeadingController(kp=6, kd=0.2),
         FuzzyHeadingController(fls=it2track.heading_fls(0.1, reducer=Reducer.KM.value))]
paths = [get_trajectory(n) for n in ("straight", "curved")]
simulate_metrics(ctrls, paths, run_grid(4, 2, noise_stds=[0.0, 0.05], seeds=3),
                 LoopConfig(duration=0.2))
simulate(ctrls, paths, RunTable(1, 1, 0.1, 2), LoopConfig(duration=0.2))
for w in (0.0, 0.2):
    for r in Reducer:
        f = it2track.heading_fls(w, reducer=r.value)
        f(np.zeros(20000), np.zeros(20000)); f.interval(np.zeros(3), np.ones(3)); f(0.3, -0.1)
sigs = {n: [str(s) for s in d.overloads] for n, d in
        (("loop", tj.loop), ("batch", fj.batch), ("scalar2", fj.scalar2))}
print(json.dumps({"probe": probe, "sigs": sigs}))
"""
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=1800, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = json.loads(proc.stdout.splitlines()[-1])
    assert out["probe"] is True
    for name, sigs in out["sigs"].items():
        assert len(sigs) == 1, (name, sigs)


class _FakeBackground:
    """A background compile that ends after ``seconds`` (for the stage's display)."""

    def __init__(self, seconds, *, ok=True):
        self.process = object()
        self.lock = Path("/nonexistent")
        self.started = time.monotonic()
        self.estimate_s = 12.0
        self.end = self.started + seconds
        self.ok = ok

    def running(self):
        return time.monotonic() < self.end

    def outcome(self):
        return None if self.running() else (self.ok, 3.0)


def _bar():
    from tqdm import tqdm

    return tqdm(total=100, file=io.StringIO(), desc="simulating", mininterval=0)


def test_the_stage_says_it_compiles_once_and_when_the_compiled_engine_takes_over(
        monkeypatch, capsys):
    monkeypatch.setattr(kernel_cache, "cached", lambda: False)
    monkeypatch.setattr(kernel_cache, "start", lambda: _FakeBackground(1.2))
    bar = _bar()
    with cli_kernels.kernel_stage(progress=True) as stage:
        assert stage.status == "background"
        stage.watch(bar)
        assert "ETA once the kernels are compiled" in bar.bar_format
        bar.update(10)
        deadline = time.monotonic() + 30
        while stage.status == "background" and time.monotonic() < deadline:
            time.sleep(0.1)
        assert stage.status == "cached"
        assert bar.bar_format is None  # the default format, with its ETA, is back
    err = capsys.readouterr().err
    assert "compiling the simulation kernels, once per install — about 12 s, in the " \
           "background; the numpy engine computes meanwhile (same numbers)" in err
    assert "compiled the simulation kernels in 3 s: the compiled engine takes over" in err
    assert "keep compiling" not in err


def test_a_command_that_ends_first_leaves_the_compile_running_and_says_so(monkeypatch,
                                                                         capsys):
    monkeypatch.setattr(kernel_cache, "cached", lambda: False)
    monkeypatch.setattr(kernel_cache, "start", lambda: _FakeBackground(3600.0))
    with cli_kernels.kernel_stage(progress=True):
        pass
    err = capsys.readouterr().err
    assert "the kernels keep compiling in the background (about 12 s more" in err


def test_without_a_background_process_the_kernels_compile_first_with_a_bar(monkeypatch,
                                                                          capsys):
    calls = []
    monkeypatch.setattr(kernel_cache, "cached", lambda: False)
    monkeypatch.setattr(kernel_cache, "start", lambda: None)
    monkeypatch.setattr(kernel_cache, "estimate_seconds", lambda lock=None: 7.0)
    monkeypatch.setattr(kernel_cache, "compile_all",
                        lambda: calls.append(time.sleep(1.2)) or 1.2)
    with cli_kernels.kernel_stage(progress=True) as stage:
        assert calls and stage.status == "inline"
    err = capsys.readouterr().err
    assert "compiling the simulation kernels, once per install — about 7 s" in err
    assert "compiling kernels:" in err  # the bar ran while it compiled
    assert "compiled the simulation kernels in 1 s" in err


def test_a_warm_cache_says_nothing(monkeypatch, capsys):
    monkeypatch.setattr(kernel_cache, "cached", lambda: True)
    monkeypatch.setattr(kernel_cache, "start", lambda: pytest.fail("nothing to compile"))
    with cli_kernels.kernel_stage(progress=True) as stage:
        stage.watch(bar := _bar())
        assert bar.bar_format is None
    assert capsys.readouterr().err == ""


def test_the_estimate_is_the_last_cpu_time_stretched_by_the_load(tmp_path, monkeypatch):
    lock = tmp_path / "k.lock"
    monkeypatch.setattr(os, "getloadavg", lambda: (3.0, 0.0, 0.0))
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    assert kernel_cache.estimate_seconds(lock) == kernel_cache.DEFAULT_CPU_SECONDS * 2.0
    lock.with_suffix(".json").write_text(json.dumps({"ok": True, "seconds": 99.0,
                                                     "cpu_seconds": 10.0}))
    assert kernel_cache.estimate_seconds(lock) == 20.0
    monkeypatch.setattr(os, "getloadavg", lambda: (0.5, 0.0, 0.0))
    assert kernel_cache.estimate_seconds(lock) == 10.0  # never below the CPU time
    lock.with_suffix(".json").write_text(json.dumps({"ok": False, "cpu_seconds": 10.0}))
    assert kernel_cache.estimate_seconds(lock) == kernel_cache.DEFAULT_CPU_SECONDS


def test_the_lock_folder_must_be_this_users_own(tmp_path, monkeypatch):
    monkeypatch.setattr(kernel_cache.tempfile, "gettempdir", lambda: str(tmp_path))
    own = kernel_cache.lock_path()
    assert own is not None and own.parent == tmp_path / f"it2track-{os.getuid()}"
    assert (own.parent.stat().st_mode & 0o777) == 0o700
    os.chmod(own.parent, 0o777)  # writable by others: not trusted
    assert kernel_cache.lock_path() is None
    os.chmod(own.parent, 0o700)
    os.rmdir(own.parent)
    (tmp_path / "elsewhere").mkdir()
    own.parent.symlink_to(tmp_path / "elsewhere")  # a planted link
    assert kernel_cache.lock_path() is None


def test_simulate_gives_the_same_numbers_deferred_or_compiled(held_lock, monkeypatch):
    pytest.importorskip("numba")
    path, fd = held_lock
    monkeypatch.setattr(kernels, "_jit", None)
    args = ([FuzzyHeadingController(fls=it2track.heading_fls(0.2)),
             PDHeadingController(kp=6.0, kd=0.2)], [get_trajectory("curved")],
            RunTable([0, 1], [0, 0], [0.05, 0.05], [3, 3]), LoopConfig(duration=0.5))
    with kernel_cache.deferring(path):
        deferred = simulate_metrics(*args)
    fcntl.flock(fd, fcntl.LOCK_UN)
    fast = simulate_metrics(*args)
    for name, value in fast.items():
        assert value.tobytes() == deferred[name].tobytes(), name


@pytest.mark.slow
def test_first_simulate_in_an_empty_cache_end_to_end(tmp_path):
    """A fresh numba cache: the first ``simulate`` says it compiles, answers at once with the
    numpy engine's numbers, and leaves one background process that fills the cache; the
    next run says nothing and uses it."""
    pytest.importorskip("numba")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"),
           "IT2TRACK_BACKGROUND_COMPILE": "1", "TMPDIR": str(tmp_path)}
    env.pop(kernels.LOCK_ENV, None)
    cmd = [sys.executable, "-m", "it2track", "simulate", "--duration", "2", "--json"]

    def run(**extra):
        return subprocess.run(cmd, env={**env, **extra}, capture_output=True, text=True,
                              timeout=900, check=False)

    first = run()
    assert first.returncode == 0, first.stderr
    assert "compiling the simulation kernels, once per install — about" in first.stderr
    reference = run(IT2TRACK_ENGINE="numpy")
    assert json.loads(first.stdout) == json.loads(reference.stdout)
    lock = next((tmp_path / f"it2track-{os.getuid()}").glob("kernels-*.lock"))
    deadline = time.monotonic() + 1800
    while kernels.locked(str(lock)) and time.monotonic() < deadline:
        time.sleep(1.0)
    assert not kernels.locked(str(lock)), "the background compile never finished"
    status = json.loads(lock.with_suffix(".json").read_text())
    assert status["ok"] is True and status["cpu_seconds"] > 0
    second = run()
    assert second.returncode == 0, second.stderr
    assert "compiling" not in second.stderr
    assert json.loads(second.stdout) == json.loads(first.stdout)

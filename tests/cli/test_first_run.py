"""The first run after installing: the kernels compile once, said and shown, in a background
process while the numpy engine computes (same numbers); the entry points compile once each.

Most tests drive the machinery with a lock this test holds or a stand-in compile; one slow test
runs ``it2track simulate`` in a fresh process with an empty numba cache, end to end.
"""

from __future__ import annotations

import fcntl
import io
import json
import math
import os
import subprocess
import sys
import threading
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
    """The fuzzy kernels' lock file held (exclusively) by this test, as a background compile
    holds it (the closed loop's lock beside it is not held)."""
    path = tmp_path / "kernels.lock"
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
    fcntl.flock(fd, fcntl.LOCK_EX)
    yield path, fd
    os.close(fd)


@pytest.fixture
def held_locks(held_lock):
    """Both locks of a background compile held by this test: the fuzzy kernels' and the closed
    loop's (``kernels.loop.lock`` beside it)."""
    path, fd = held_lock
    loop = kernel_cache.loop_lock_path(path)
    assert loop == path.parent / "kernels.loop.lock"
    loop_fd = os.open(loop, os.O_RDWR | os.O_CREAT, 0o600)
    fcntl.flock(loop_fd, fcntl.LOCK_EX)
    yield path, fd, loop_fd
    os.close(loop_fd)


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


def test_while_the_lock_is_held_the_numpy_engine_answers(held_locks, monkeypatch):
    pytest.importorskip("numba")
    path, fd, loop_fd = held_locks
    monkeypatch.delenv(kernels.ENGINE_ENV, raising=False)
    monkeypatch.delenv(kernels.WAIT_ENV, raising=False)
    monkeypatch.setattr(kernels, "_jit", None)  # as in a fresh command: nothing loaded yet
    x = np.linspace(-1, 1, 7)
    with kernel_cache.deferring(path):
        assert os.environ[kernels.LOCK_ENV] == str(path)  # for the workers it starts
        assert kernels.WAIT_ENV not in os.environ
        assert kernels.load_jit() is None and compiled.load() is None
        fls = it2track.heading_fls(0.2)
        deferred = fls(x, x[::-1])
        assert "_kernel_pack" not in fls.__dict__  # asked again at the next call
        fcntl.flock(loop_fd, fcntl.LOCK_UN)  # the closed loop is compiled, the rest is not
        assert compiled.load() is not None and kernels.load_jit() is None
        assert kernels.deferred("fuzzy") and not kernels.deferred("loop")
        fcntl.flock(fd, fcntl.LOCK_UN)  # the compile ends
        assert kernels.load_jit() is not None and compiled.load() is not None
        again = fls(x, x[::-1])
        assert fls.__dict__["_kernel_pack"] is not None
    assert kernels.LOCK_ENV not in os.environ and kernels._defer is None
    assert deferred.tobytes() == again.tobytes()


def test_a_long_job_waits_for_the_closed_loop_instead_of_the_numpy_engine(held_locks,
                                                                        monkeypatch):
    """``wait``: the first call of the compiled loop blocks until the loop's lock is released
    (not the fuzzy kernels' lock, still held: those stay on numpy), then gets the module."""
    pytest.importorskip("numba")
    path, _fd, loop_fd = held_locks
    monkeypatch.delenv(kernels.ENGINE_ENV, raising=False)
    monkeypatch.setattr(kernels, "_jit", None)
    released = []

    def release():
        time.sleep(0.5)
        released.append(time.monotonic())
        fcntl.flock(loop_fd, fcntl.LOCK_UN)

    with kernel_cache.deferring(path, wait=True):
        assert os.environ[kernels.WAIT_ENV] == "1"  # the workers wait too
        assert kernels.load_jit() is None  # the fuzzy kernels still compile: numpy
        thread = threading.Thread(target=release)
        thread.start()
        module = compiled.load()
        returned = time.monotonic()
        thread.join()
        assert module is not None and released and returned >= released[0]
        assert kernels.deferred("fuzzy")
    assert kernels.WAIT_ENV not in os.environ and kernels.LOCK_ENV not in os.environ


def test_a_compile_that_never_ends_is_waited_for_a_bounded_time(held_locks, monkeypatch):
    path, _fd, loop_fd = held_locks
    loop = str(kernel_cache.loop_lock_path(path))
    t0 = time.monotonic()
    assert kernels.wait_unlocked(loop, limit_s=0.3) is False
    assert time.monotonic() - t0 >= 0.3
    monkeypatch.setattr(kernels, "WAIT_LIMIT_S", 0.2)
    gate = kernels.gate(str(path), wait=True)
    t0 = time.monotonic()
    assert gate("loop") is True  # gives up waiting: the numpy engine computes
    assert time.monotonic() - t0 >= 0.2
    # a call of at most SHORT_CALL_S on numpy (0.5 s x 0.6 M run-steps/s) does not wait
    assert kernels.SHORT_CALL_S * kernels.NUMPY_RUN_STEPS_PER_S == 3e5
    gate = kernels.gate(str(path), wait=True)
    t0 = time.monotonic()
    assert gate("loop", 3e5) is True
    assert time.monotonic() - t0 < 0.15
    gate = kernels.gate(str(path), wait=True)
    t0 = time.monotonic()
    assert gate("loop", 3e5 + 1.0) is True
    assert time.monotonic() - t0 >= 0.2
    t0 = time.monotonic()
    assert gate("loop") is True  # it gave up once: not again at every call
    assert time.monotonic() - t0 < 0.15
    assert kernels.gate(str(path))("loop", math.inf) is True  # not waiting: at once
    fcntl.flock(loop_fd, fcntl.LOCK_UN)
    assert gate("loop") is False and kernels.wait_unlocked(loop, limit_s=0.0) is True
    assert kernels.wait_unlocked(str(path.parent / "absent.lock"), limit_s=0.0) is True


def test_the_background_process_releases_the_loop_first(tmp_path, monkeypatch):
    """The compile process: the closed loop (first entry point) is compiled and recorded, its
    lock released, and only then the fuzzy kernels are compiled; the main lock is held to
    the end and the status file records both times."""
    lock = tmp_path / "k.lock"
    loop = kernel_cache.loop_lock_path(lock)
    fds = []
    for p in (lock, loop):
        fds.append(os.open(p, os.O_RDWR | os.O_CREAT, 0o600))
        fcntl.flock(fds[-1], fcntl.LOCK_EX)
    seen = []

    def loop_entry():
        seen.append(("loop", kernels.locked(str(lock)), kernels.locked(str(loop))))

    def fuzzy_entry():
        status = json.loads(lock.with_suffix(".json").read_text())
        seen.append(("fuzzy", kernels.locked(str(lock)), kernels.locked(str(loop)),
                     sorted(status)))

    monkeypatch.setattr(kernel_cache, "lock_path", lambda: lock)
    monkeypatch.setattr(kernel_cache, "_entry_calls",
                        lambda: [(loop_entry, ()), (fuzzy_entry, ())])
    monkeypatch.setattr(os, "nice", lambda n: seen.append(("nice", n)))
    assert kernel_cache._main(["--lock-fd", str(fds[0]), "--loop-lock-fd", str(fds[1])]) == 0
    assert seen == [("loop", True, True), ("nice", 10),
                    ("fuzzy", True, False, ["loop_cpu_seconds", "loop_seconds", "ok"])]
    assert not kernels.locked(str(lock))  # released at the end
    status = json.loads(lock.with_suffix(".json").read_text())
    assert status["ok"] is True
    assert status["seconds"] >= status["loop_seconds"] >= 0.0
    assert status["cpu_seconds"] >= status["loop_cpu_seconds"] > 0.0


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
    assert ("compiled the closed-loop kernel in 3 s: the compiled engine takes over (the fuzzy "
            "kernels follow in the background)") in err
    assert "keep compiling" not in err


@pytest.mark.parametrize(("run_steps", "waits", "said"), [
    (None, False, "the numpy engine computes meanwhile (same numbers)"),
    # the fake compile's estimate is 12 s: 7.2e6 run-steps at 0.6e6/s on numpy
    (7.2e6, False, "the numpy engine computes meanwhile (same numbers)"),
    (7.2e6 + 1.0, True, "this job waits for them (on the numpy engine it would take about "
                        "12 s)"),
    (6e5 * 90.0, True, "would take about 2 min)"),
    (6e5 * 89.0, True, "would take about 89 s)"),
    (6e5 * 3599.0, True, "would take about 60 min)"),
    (6e5 * 3600.0, True, "would take hours)"),
    (math.inf, True, "this job waits for them (on the numpy engine it would take hours)"),
])
def test_a_job_longer_on_numpy_than_the_compile_waits_for_it(monkeypatch, capsys, run_steps,
                                                             waits, said):
    assert kernels.NUMPY_RUN_STEPS_PER_S == 6e5
    monkeypatch.setattr(kernel_cache, "cached", lambda: False)
    monkeypatch.setattr(kernel_cache, "start", lambda: _FakeBackground(0.2))
    modes = []
    real = kernel_cache.deferring
    monkeypatch.setattr(kernel_cache, "deferring",
                        lambda lock, wait=False: modes.append(wait) or real(lock, wait=wait))
    with cli_kernels.kernel_stage(progress=True, run_steps=run_steps):
        assert (os.environ.get(kernels.WAIT_ENV) == "1") is waits
    assert modes == [waits]
    assert said in capsys.readouterr().err


def test_a_compile_started_early_is_the_one_the_stage_follows(monkeypatch, capsys):
    starts = []
    monkeypatch.setattr(kernel_cache, "cached", lambda: False)
    monkeypatch.setattr(kernel_cache, "start",
                        lambda: starts.append(1) or _FakeBackground(0.2))
    early = cli_kernels.start_kernels()
    assert not early.cached and starts == [1]
    with cli_kernels.kernel_stage(progress=True, started=early) as stage:
        assert stage.background is early.background
    assert starts == [1]  # not a second one
    assert "(by another it2track command)" not in capsys.readouterr().err
    monkeypatch.setattr(kernel_cache, "cached", lambda: True)
    assert cli_kernels.start_kernels().cached and starts == [1]


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
    # the closed loop's CPU time (what a command waits for), not the whole compile's
    lock.with_suffix(".json").write_text(json.dumps({
        "ok": True, "seconds": 99.0, "cpu_seconds": 14.0, "loop_seconds": 50.0,
        "loop_cpu_seconds": 10.0}))
    assert kernel_cache.estimate_seconds(lock) == 20.0
    monkeypatch.setattr(os, "getloadavg", lambda: (0.5, 0.0, 0.0))
    assert kernel_cache.estimate_seconds(lock) == 10.0  # never below the CPU time
    lock.with_suffix(".json").write_text(json.dumps({"ok": False, "loop_cpu_seconds": 10.0}))
    assert kernel_cache.estimate_seconds(lock) == kernel_cache.DEFAULT_CPU_SECONDS
    # a status of the version before (the whole compile's time only): the default
    lock.with_suffix(".json").write_text(json.dumps({"ok": True, "cpu_seconds": 10.0}))
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
    locks = sorted((tmp_path / f"it2track-{os.getuid()}").glob("kernels-*.lock"))
    assert [p.name.endswith(".loop.lock") for p in locks] == [False, True]
    lock = locks[0]
    assert kernel_cache.loop_lock_path(lock) == locks[1]
    deadline = time.monotonic() + 1800
    while kernels.locked(str(lock)) and time.monotonic() < deadline:
        time.sleep(1.0)
    assert not kernels.locked(str(lock)), "the background compile never finished"
    assert not kernels.locked(str(locks[1]))
    status = json.loads(lock.with_suffix(".json").read_text())
    assert status["ok"] is True
    assert status["cpu_seconds"] > status["loop_cpu_seconds"] > 0
    second = run()
    assert second.returncode == 0, second.stderr
    assert "compiling" not in second.stderr
    again = subprocess.run([sys.executable, "-m", "it2track", "compile"], env=env,
                           capture_output=True, text=True, timeout=900, check=False)
    assert again.returncode == 0, again.stderr
    assert "already compiled" in again.stderr
    assert json.loads(second.stdout) == json.loads(first.stdout)


class _FakeCompile(_FakeBackground):
    """A background compile whose closed loop ends after ``loop_s`` and the rest after
    ``all_s``."""

    def __init__(self, loop_s, all_s, *, ok=True):
        super().__init__(loop_s, ok=ok)
        self.all_end = self.started + all_s

    def finished(self):
        return time.monotonic() >= self.all_end


def _run_compile(monkeypatch, *, cached_states, background):
    from click.testing import CliRunner

    from it2track.cli.main import main

    states = iter(cached_states)
    monkeypatch.setattr(kernel_cache, "cached", lambda: next(states))
    monkeypatch.setattr(kernel_cache, "start", lambda: background)
    monkeypatch.setattr(kernel_cache, "estimate_seconds", lambda lock=None: 7.0)
    return CliRunner().invoke(main, ["compile"])


def test_compile_waits_for_the_whole_compile_and_says_what_it_did(monkeypatch):
    fake = _FakeCompile(0.3, 1.0)
    result = _run_compile(monkeypatch, cached_states=[False, True], background=fake)
    assert result.exit_code == 0, result.output
    assert time.monotonic() >= fake.all_end  # waited for the fuzzy kernels too
    out = result.output
    assert ("compiling the simulation kernels, once per install — about 12 s for the closed "
            "loop, a few more for the fuzzy kernels") in out
    assert "compiled the closed-loop kernel in 3 s; now the fuzzy kernels" in out
    assert "the simulation kernels are compiled (1 s); every command loads them" in out


def test_compile_follows_a_compile_another_command_started(monkeypatch):
    fake = _FakeCompile(0.1, 0.2)
    fake.process = None
    result = _run_compile(monkeypatch, cached_states=[False, True], background=fake)
    assert result.exit_code == 0, result.output
    assert "once per install (started by another it2track command) — about" in result.output


def test_compile_says_when_there_is_nothing_to_do(monkeypatch):
    result = _run_compile(monkeypatch, cached_states=[True], background=None)
    assert result.exit_code == 0
    assert result.output == ("the simulation kernels are already compiled (numba's cache "
                             "holds them)\n")
    result = _run_compile(monkeypatch, cached_states=[None], background=None)
    assert result.exit_code == 0
    assert result.output.startswith("nothing to compile: the numpy engine computes")


def test_compile_fails_loudly_when_the_cache_stays_empty(monkeypatch):
    calls = []
    monkeypatch.setattr(kernel_cache, "compile_all", lambda: calls.append(1) or 0.1)
    fake = _FakeCompile(0.1, 0.2, ok=False)
    result = _run_compile(monkeypatch, cached_states=[False, False], background=fake)
    assert result.exit_code == 1
    assert calls == [1]  # the failed compile is run here, to show its error
    assert "the kernels are still not in numba's cache" in result.output
    assert "NUMBA_CACHE_DIR" in result.output


def test_compile_names_the_error_of_a_failed_compile(monkeypatch):
    def fail():
        raise RuntimeError("LLVM ERROR: out of memory")

    monkeypatch.setattr(kernel_cache, "compile_all", fail)
    result = _run_compile(monkeypatch, cached_states=[False, False],
                          background=_FakeCompile(0.1, 0.2, ok=False))
    assert result.exit_code == 1
    assert ("the simulation kernels failed to compile: RuntimeError: LLVM ERROR: out of "
            "memory") in result.output


def test_compile_without_a_background_process_compiles_here(monkeypatch):
    calls = []
    monkeypatch.setattr(kernel_cache, "compile_all", lambda: calls.append(1) or 0.4)
    result = _run_compile(monkeypatch, cached_states=[False, True], background=None)
    assert result.exit_code == 0, result.output
    assert calls == [1]
    assert "compiling the simulation kernels, once per install — about 7 s" in result.output
    assert "compiled the simulation kernels in 0 s" in result.output


def test_start_hands_both_locks_to_one_process(tmp_path, monkeypatch):
    monkeypatch.setattr(kernel_cache.tempfile, "gettempdir", lambda: str(tmp_path))
    monkeypatch.delenv(kernel_cache.BACKGROUND_ENV, raising=False)
    monkeypatch.setenv(kernels.LOCK_ENV, "inherited")
    monkeypatch.setenv(kernels.WAIT_ENV, "1")
    seen = {}

    class FakePopen:
        def __init__(self, args, **kw):
            lock = kernel_cache.lock_path()
            seen.update(args=args, pass_fds=kw["pass_fds"], env=kw["env"],
                        held=(kernels.locked(str(lock)),
                              kernels.locked(str(kernel_cache.loop_lock_path(lock)))))

    monkeypatch.setattr(kernel_cache.subprocess, "Popen", FakePopen)
    bg = kernel_cache.start()
    assert isinstance(bg.process, FakePopen)
    fd, loop_fd = seen["pass_fds"]
    assert seen["args"][-4:] == ["--lock-fd", str(fd), "--loop-lock-fd", str(loop_fd)]
    assert seen["held"] == (True, True)  # both taken before the process starts
    assert kernels.LOCK_ENV not in seen["env"] and kernels.WAIT_ENV not in seen["env"]
    assert not kernels.locked(str(bg.lock))  # this process's copies are closed


def test_start_finds_a_compile_running_or_refuses_a_planted_link(tmp_path, monkeypatch):
    monkeypatch.setattr(kernel_cache.tempfile, "gettempdir", lambda: str(tmp_path))
    monkeypatch.delenv(kernel_cache.BACKGROUND_ENV, raising=False)
    monkeypatch.setattr(kernel_cache.subprocess, "Popen",
                        lambda *a, **k: pytest.fail("no second compile"))
    lock = kernel_cache.lock_path()
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        os.pwrite(fd, repr(time.time() - 5.0).encode(), 0)
        other = kernel_cache.start()
        assert other is not None and other.process is None and other.lock == lock
        assert 4.0 <= time.monotonic() - other.started < 60.0  # it started 5 s ago
    finally:
        os.close(fd)
    kernel_cache.loop_lock_path(lock).symlink_to(tmp_path / "elsewhere")
    assert kernel_cache.start() is None  # a link in the way: compile inline
    assert not (tmp_path / "elsewhere").exists()


def test_a_short_call_of_a_waiting_job_runs_on_numpy_at_once(held_locks, monkeypatch):
    """simulate passes its size: 2 runs x 50 steps (100 run-steps) is a short call, run on
    numpy at once while a long job waits; made "long" (SHORT_CALL_S below it) it waits."""
    pytest.importorskip("numba")
    path, _fd, _loop_fd = held_locks
    monkeypatch.delenv(kernels.ENGINE_ENV, raising=False)
    monkeypatch.setattr(kernels, "WAIT_LIMIT_S", 1.5)
    args = ([PDHeadingController(kp=6.0, kd=0.2)], [get_trajectory("curved")],
            RunTable([0, 0], [0, 0], [0.05, 0.05], [3, 4]), LoopConfig(duration=0.5))
    reference = simulate_metrics(*args)  # (warm: imports and the compiled engine)
    with kernel_cache.deferring(path, wait=True):
        t0 = time.monotonic()
        short = simulate_metrics(*args)
        short_s = time.monotonic() - t0
        monkeypatch.setattr(kernels, "SHORT_CALL_S", 99.0 / kernels.NUMPY_RUN_STEPS_PER_S)
        t0 = time.monotonic()
        simulate_metrics(*args)
        long_s = time.monotonic() - t0
    assert short_s < 1.5 <= long_s
    for name, value in reference.items():
        assert value.tobytes() == short[name].tobytes(), name


def test_the_gate_travels_to_figure_workers_started_before_it(held_lock, monkeypatch):
    """Figure workers fork from a server started before the compile: each job carries the
    command's gate, so a figure that evaluates a fuzzy system (the dead-zone slice) uses the
    numpy engine while the compile runs instead of compiling the kernels for itself."""
    from it2track.report import plan, render

    path, fd = held_lock
    monkeypatch.setattr(kernels, "_defer", None)
    monkeypatch.delenv(kernels.LOCK_ENV, raising=False)
    assert kernels.current_gate() is None
    with kernel_cache.deferring(path, wait=True):
        state = kernels.current_gate()
        assert state == (str(path), True)
        submitted = []

        class Pool:
            def submit(self, fn, *args, **kw):
                submitted.append((fn, args, kw))

        monkeypatch.setattr(plan, "figure_plan", lambda result, summary: ["dead_zone"])
        renderer = render.FigureRenderer(Path("/nonexistent"), workers=0)
        renderer._pool = Pool()
        assert renderer.submit(object(), []) == ["dead_zone"]
        assert submitted[0][0] is render._timed_write
        assert submitted[0][2] == {"kernel_gate": (str(path), True)}
    assert kernels.current_gate() is None
    kernels.follow_gate(state)  # in the worker
    try:
        assert kernels.deferred("fuzzy")
        fcntl.flock(fd, fcntl.LOCK_UN)
        assert not kernels.deferred("fuzzy")
    finally:
        kernels.follow_gate(None)
    assert kernels._defer is None

"""The compiled kernels' first run: fill numba's on-disk cache in a background process while the
numpy engine computes.

numba compiles the kernels (:mod:`it2track.fuzzy._jit`, :mod:`it2track.tracking._jit`) the
first time they are called and caches them on disk (``cache=True``: ``__pycache__`` beside the
sources, or ``NUMBA_CACHE_DIR``), so only the first run after installing (or after editing a
kernel) compiles: half a minute or more of one core. A process that compiles them inline
computes nothing meanwhile, and every process of a run (figure workers, sweep workers) compiles
the same kernels again. Here instead:

* :func:`cached` tells, without compiling, whether the cache holds every entry point (the
  closed loop, the fuzzy batch and the scalar call, with the argument types the engines pass),
  and loads them if it does;
* :func:`start` launches one background process (``python -m it2track.tracking.kernel_cache``)
  that compiles them into the cache: the closed loop first, holding an exclusive lock on
  :func:`loop_lock_path` until it is cached, then the fuzzy batch and scalar kernels (at a
  lower priority: the commands compute meanwhile), holding :func:`lock_path` until the end (a
  second command finds the lock and starts none);
* :func:`deferring` makes this process (and the worker processes it starts, through the
  environment variables :data:`LOCK_ENV` and :data:`WAIT_ENV`) use the numpy engine for each
  part while its lock is held -- or, for a long job (``wait``), wait for the closed loop
  instead: the numpy engine is several times slower, and on a small machine it would take its
  core from the compile. The compiled engine takes over, loading from the cache, at the first
  call after a lock is released.

The numpy engine and the compiled one give the same bits, so which one computed a run never
shows in its numbers. Only the command line defers (it opts in per command); a library call or
a test in a cold cache compiles inline, as before. Nothing of this runs on Windows (no
``fcntl``): there the kernels compile inline.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import stat
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..fuzzy.kernels import LOCK_ENV, NUMPY_RUN_STEPS_PER_S, WAIT_ENV
from ..fuzzy.kernels import gate as kernels_gate
from ..fuzzy.kernels import locked as kernels_locked
from ..fuzzy.kernels import loop_lock as kernels_loop_lock

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX
    fcntl = None  # type: ignore[assignment]

__all__ = ["BACKGROUND_ENV", "LOCK_ENV", "WAIT_ENV", "Background", "cached", "compile_all",
           "compiling", "deferring", "lock_path", "loop_lock_path", "numpy_seconds", "start"]

# LOCK_ENV: set (to the lock file) in the worker processes a deferring command starts: they
# use the numpy engine while a background compile holds that lock.
#: ``0`` turns the background compile off (the kernels then compile inline when first called).
BACKGROUND_ENV = "IT2TRACK_BACKGROUND_COMPILE"
#: CPU seconds the closed loop's compile takes when nothing better is known: one core of the
#: 2-core reference machine, measured by ``benchmarks/bench_compile.py`` (``_loop``, quiet;
#: the load average stretches the estimate); each compile then records its own CPU time on
#: this machine, which later estimates use.
DEFAULT_CPU_SECONDS = 16.0


def lock_path() -> Path | None:
    """The lock a background compile holds: one per installed package, numba cache and
    interpreter, in a folder of this user's own under the temporary directory (beside it,
    ``.json``: how the last compile went). ``None`` if that folder is not this user's own
    (then nothing runs in the background)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        numba_version = version("numba")
    except PackageNotFoundError:
        numba_version = "-"
    src = Path(__file__).resolve().parent.parent
    key = "|".join([str(src), os.environ.get("NUMBA_CACHE_DIR", ""), sys.version,
                    numba_version])
    digest = hashlib.sha256(key.encode()).hexdigest()[:16]
    folder = Path(tempfile.gettempdir()) / f"it2track-{os.getuid()}"
    try:
        folder.mkdir(mode=0o700, exist_ok=True)
        st = folder.lstat()
    except OSError:
        return None
    if not stat.S_ISDIR(st.st_mode) or st.st_uid != os.getuid() or st.st_mode & 0o022:
        return None  # a link, or someone else's folder: not ours to write in
    return folder / f"kernels-{digest}.lock"


def loop_lock_path(lock: Path) -> Path:
    """The closed loop's lock beside ``lock`` (:func:`lock_path`)."""
    return Path(kernels_loop_lock(str(lock)))


def numpy_seconds(run_steps: float) -> float:
    """About how long the numpy engine takes for ``run_steps`` (runs x steps) on one core."""
    return run_steps / NUMPY_RUN_STEPS_PER_S


def compiling(path: Path | str | None = None) -> bool:
    """Whether a background compile holds the lock ``path`` (default: :func:`lock_path`)."""
    path = path or lock_path()
    return path is not None and kernels_locked(str(path))


def _sample_system() -> Any:
    """A small two-input IT2 Sugeno system of the kind the kernels serve (its values do not
    matter: the entry points are compiled for argument types, not values)."""
    from ..fuzzy import Input, IT2Set, IT2Sugeno, Rule, Triangle

    sets = [IT2Set(Triangle(-1.0, -1.0, 1.0), Triangle(-1.0, -1.0, 0.5), "N"),
            IT2Set(Triangle(-1.0, 1.0, 1.0), Triangle(-0.5, 1.0, 1.0), "P")]
    inputs = (Input("e", (-1.0, 1.0), sets), Input("de", (-1.0, 1.0), sets))
    rules = (Rule(["N", "N"], -1.0), Rule(["N", "P"], 0.0), Rule(["P", "N"], 0.0),
             Rule(["P", "P"], 1.0))
    return IT2Sugeno(inputs=inputs, rules=rules)


class _Recorder:
    """Stands in for the compiled loop module: records the loop's arguments, computes
    nothing."""

    def __init__(self, module: Any) -> None:
        self.LANES, self.N_METRICS, self.N_FIELDS = module.LANES, module.N_METRICS, \
            module.N_FIELDS
        self.args: tuple[Any, ...] | None = None

    def loop(self, *args: Any) -> None:
        if self.args is None:
            self.args = args


def _entry_calls() -> list[tuple[Any, tuple[Any, ...]]]:
    """Each compiled entry point with arguments of the types the engines pass it: the closed
    loop first (a background compile releases its lock once that one is cached)."""
    import numpy as np

    from ..fuzzy import _jit as fuzzy_jit
    from ..fuzzy import kernels
    from . import _jit as loop_jit
    from . import compiled
    from .controllers import FuzzyHeadingController
    from .simulate import LoopConfig, RunTable, _Engine
    from .trajectories import straight

    system = _sample_system()
    packed = kernels.pack(system)
    recorder = _Recorder(loop_jit)
    engine = _Engine([straight()], LoopConfig(duration=0.02))
    compiled.run(recorder, engine, [FuzzyHeadingController(fls=system)],
                 RunTable(0, 0, 0.05, 0), record=False)
    assert recorder.args is not None
    x = np.zeros((2, 3))
    out = np.empty(3)
    return [
        (loop_jit.loop, recorder.args),
        (fuzzy_jit.batch, (packed, x, out, out, np.empty(3, dtype=np.int8), True, 0, 3)),
        (fuzzy_jit.scalar2, (packed, 0.25, -0.5)),
    ]


def _load_cached(dispatcher: Any, args: tuple[Any, ...]) -> bool:
    """Load ``dispatcher``'s code for ``args`` from numba's disk cache (what its first call
    would do); False if the cache does not hold it. Never compiles."""
    import inspect

    from numba.core import types
    from numba.core.compiler_lock import global_compiler_lock

    sig = tuple(dispatcher.typeof_pyval(a) for a in args)
    # Parameters left out take their default, which numba types as Omitted(default) (as the
    # engines' calls leave ``ext`` out).
    params = list(inspect.signature(dispatcher.py_func).parameters.values())[len(args):]
    sig += tuple(types.Omitted(p.default) for p in params if p.default is not p.empty)
    if sig in dispatcher.overloads:
        return True
    with global_compiler_lock:
        cres = dispatcher._cache.load_overload(sig, dispatcher.targetctx)
        if cres is None:
            return False
        dispatcher.add_overload(cres)
    return True


def cached() -> bool | None:
    """Whether numba's cache holds every kernel entry point for this machine (they are then
    loaded, as their first call would). ``None`` if numba is not used (missing, or
    ``IT2TRACK_ENGINE=numpy``) or its cache cannot be inspected (then the kernels compile
    when first called, as without this module)."""
    from ..fuzzy import kernels

    try:
        if kernels.engine() == "numpy":
            return None
        import numba  # noqa: F401
    except (ImportError, ValueError):
        return None
    try:
        from ..fuzzy import _jit as fuzzy_jit
        from . import _jit as loop_jit

        # No index file: nothing cached (the usual first run), told without starting numba's
        # compiler (a second or more of a cold process, for nothing).
        for dispatcher in (loop_jit.loop, fuzzy_jit.batch, fuzzy_jit.scalar2):
            if not os.path.exists(dispatcher._cache._cache_file._index_path):
                return False
        return all(_load_cached(d, a) for d, a in _entry_calls())
    except Exception:  # numba's internals moved: the first calls will compile, as before
        return None


def compile_all() -> float:
    """Compile every entry point into numba's cache (in this process); returns the seconds."""
    started = time.perf_counter()
    for dispatcher, args in _entry_calls():
        dispatcher(*args)
    return time.perf_counter() - started


def _status_path(lock: Path) -> Path:
    return lock.with_suffix(".json")


def estimate_seconds(lock: Path | None = None) -> float:
    """How long the closed loop's compile takes here, in wall seconds: its CPU time (the last
    compile's on this machine, recorded beside ``lock``, default :func:`lock_path`; else
    :data:`DEFAULT_CPU_SECONDS`) stretched by the load (a compile is one busy thread: on ``n``
    CPUs with load ``a``, it gets about ``n / (a + 1)`` of one)."""
    cpu = DEFAULT_CPU_SECONDS
    lock = lock or lock_path()
    if lock is not None:
        try:
            status = json.loads(_status_path(lock).read_text())
            seconds = float(status["loop_cpu_seconds"])
            if status.get("ok") and 0.0 < seconds < 3600.0:
                cpu = seconds
        except (OSError, ValueError, KeyError, TypeError):
            pass
    try:
        load = os.getloadavg()[0]
    except OSError:
        load = 0.0
    return cpu * max(1.0, (load + 1.0) / (os.cpu_count() or 1))


@dataclass
class Background:
    """A background compile: its process (``None`` if another command started it), lock
    (:func:`lock_path`; the closed loop's is :func:`loop_lock_path` beside it), start time
    and the expected duration of the closed loop's compile."""

    process: subprocess.Popen[bytes] | None
    lock: Path
    started: float
    estimate_s: float

    def running(self) -> bool:
        """Whether the closed loop still compiles (it holds the loop's lock)."""
        return compiling(loop_lock_path(self.lock))

    def finished(self) -> bool:
        """Whether the whole compile ended (the fuzzy kernels' lock is free too)."""
        return not self.running() and not compiling(self.lock)

    def outcome(self) -> tuple[bool, float] | None:
        """``(ok, seconds)`` of the closed loop's compile, from the status file (None if
        unknown or still running)."""
        if self.running():
            return None
        try:
            status = json.loads(_status_path(self.lock).read_text())
            return bool(status["ok"]), float(status["loop_seconds"])
        except (OSError, ValueError, KeyError, TypeError):
            return None


def _flock(path: Path) -> int | None:
    """An open descriptor of ``path`` holding its exclusive lock, or None if another process
    holds it. Raises OSError if it cannot be opened or locked."""
    fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        return None
    except OSError:
        os.close(fd)
        raise
    return fd


def start() -> Background | None:
    """Start the background compile unless one is running (then return that one) or the
    background compile is off (:data:`BACKGROUND_ENV` ``=0``, no ``fcntl``: ``None``).

    The locks are taken here, before the process starts, and handed to it: the caller
    defers to the numpy engine (or waits) from the first call on, and a second command sees
    them at once.
    """
    if fcntl is None or os.environ.get(BACKGROUND_ENV, "1").strip() == "0":
        return None
    lock = lock_path()
    if lock is None:
        return None
    estimate = estimate_seconds(lock)
    try:
        fd = _flock(lock)
    except OSError:  # no lock to be had here: the kernels compile inline
        return None
    if fd is None:  # another command is compiling them, since the time it wrote
        try:
            rfd = os.open(lock, os.O_RDONLY | os.O_NOFOLLOW)
        except OSError:
            return None
        try:
            since = time.time() - float(os.pread(rfd, 64, 0).decode() or "nan")
        except (OSError, ValueError):
            since = 0.0
        finally:
            os.close(rfd)
        since = since if 0.0 <= since < 3600.0 else 0.0
        return Background(None, lock, time.monotonic() - since, estimate)
    loop_fd = None
    try:
        # (the compile that held the main lock released this one first: it is free)
        with contextlib.suppress(OSError):
            loop_fd = _flock(loop_lock_path(lock))
        if loop_fd is None:
            return None
        with contextlib.suppress(OSError):  # when it started, for the other commands
            os.ftruncate(fd, 0)
            os.pwrite(fd, repr(time.time()).encode(), 0)
        env = {k: v for k, v in os.environ.items() if k not in (LOCK_ENV, WAIT_ENV)}
        try:
            proc = subprocess.Popen(
                [sys.executable, "-m", "it2track.tracking.kernel_cache", "--lock-fd",
                 str(fd), "--loop-lock-fd", str(loop_fd)],
                pass_fds=(fd, loop_fd), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL, env=env, start_new_session=True)
        except OSError:
            return None
    finally:
        os.close(fd)  # the child's copies keep the locks until it releases them
        if loop_fd is not None:
            os.close(loop_fd)
    return Background(proc, lock, time.monotonic(), estimate)


@contextlib.contextmanager
def deferring(lock: Path, *, wait: bool = False) -> Iterator[None]:
    """Within: this process, and the worker processes started meanwhile, use the numpy
    engine for each part of the kernels while a background compile holds its lock (``lock``
    and :func:`loop_lock_path`); ``wait``: wait for the closed loop instead (a long job)."""
    from ..fuzzy import kernels

    saved_env = {name: os.environ.get(name) for name in (LOCK_ENV, WAIT_ENV)}
    saved_gate = kernels._defer
    os.environ[LOCK_ENV] = str(lock)
    if wait:
        os.environ[WAIT_ENV] = "1"
    else:
        os.environ.pop(WAIT_ENV, None)
    kernels._defer = kernels_gate(str(lock), wait=wait)
    try:
        yield
    finally:
        kernels._defer = saved_gate
        for name, value in saved_env.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value


def _write_status(lock: Path | None, status: dict[str, Any]) -> None:
    if lock is None:
        return
    with contextlib.suppress(OSError):
        tmp_fd, tmp = tempfile.mkstemp(dir=lock.parent, suffix=".tmp")
        with os.fdopen(tmp_fd, "w") as fh:
            fh.write(json.dumps(status))
        os.replace(tmp, _status_path(lock))


def _main(argv: list[str]) -> int:
    """The background process: compile the closed loop, record it beside the lock, release
    the loop's lock; compile the fuzzy kernels at a lower priority, record the outcome, exit
    (which releases the main lock)."""

    def fd_of(flag: str) -> int | None:
        return int(argv[argv.index(flag) + 1]) if flag in argv else None

    fd, loop_fd = fd_of("--lock-fd"), fd_of("--loop-lock-fd")
    lock = lock_path()
    started = time.perf_counter()
    ok = True
    status: dict[str, Any] = {}
    try:
        calls = _entry_calls()
    except Exception:  # the commands then compile inline, as without this module
        ok, calls = False, []
    for n, (dispatcher, args) in enumerate(calls):
        try:
            dispatcher(*args)
        except Exception:  # the commands then compile inline, as without this module
            ok = False
        if n == 0:  # the closed loop (the first entry point): the commands may use it now
            status = {"ok": ok, "loop_seconds": round(time.perf_counter() - started, 3),
                      "loop_cpu_seconds": round(time.process_time(), 3)}
            _write_status(lock, status)
            if loop_fd is not None:
                os.close(loop_fd)
            with contextlib.suppress(OSError):
                os.nice(10)  # the rest yields to the commands now computing
    status.update(ok=ok, seconds=round(time.perf_counter() - started, 3),
                  cpu_seconds=round(time.process_time(), 3))
    _write_status(lock, status)
    if fd is not None:
        os.close(fd)
    return 0 if ok else 1


if __name__ == "__main__":  # pragma: no cover - run as the background process
    sys.exit(_main(sys.argv[1:]))

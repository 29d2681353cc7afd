"""Compiled evaluation of Sugeno systems, used by :mod:`.sugeno` when it applies.

:class:`~.sugeno.IT2Sugeno` and :class:`~.sugeno.T1Sugeno` ask this module first
(:func:`output`, :func:`interval`); it answers with numba-compiled kernels (``._jit``) when
numba is installed, not disabled, and the system uses only what the kernels implement, and
returns ``None`` otherwise, so the numpy evaluation runs. The numpy evaluation stays the
reference: the kernels give the same bits (tests compare them), and wherever the reference
would raise (NaN input, zero firing without ``on_zero_firing``, no convergence) the kernel
hands the call back to it, so errors and messages are the reference's.

What the kernels implement (an allow-list; anything else goes to numpy): exactly the classes
``IT2Sugeno`` and ``T1Sugeno`` (not subclasses; ``T1Sugeno`` with either weighted
defuzzifier), membership rows of every :class:`~.kinds.MFKind` but ``OTHER`` (the
triangles, trapezoids and Gaussians of :mod:`.membership`, every class of :mod:`.curves` and
:mod:`.shapes` but ``Discrete``, and MATLAB's scaled and lagged lower MFs), tables with no
rule-language ``features``, every t-norm, the six built-in reducers (matched by their kernels,
so a custom :class:`~.reducers.TypeReducer` goes to numpy) with their ``max_iter``, and both
zero-firing policies. The new shapes, t-norms and ``wtsum`` are compiled only for the systems
that use them (:func:`extended`).

Engine choice: the environment variable ``IT2TRACK_ENGINE`` is ``auto`` (default: compiled
where supported and numba is importable), ``numpy`` (never compile; numba is not even
imported) or ``compiled`` (like ``auto``, but a missing numba is an error). It is read when a
system is first evaluated. numba is an optional accelerator here: :mod:`it2track.fuzzy` imports
numpy only and imports numba lazily, on the first evaluation that can use it.

Threads: large batches are split into contiguous ranges evaluated at once by a small thread
pool (the kernels are serial and release the GIL); :func:`threads` says how many, from
``numba.get_num_threads()`` (so ``numba.set_num_threads`` and ``NUMBA_NUM_THREADS`` apply).
numba's own parallel backend is not used: it would double the compile time and is not
re-entrant from several Python threads. Results never depend on the number of threads: each
point is computed alone.
"""

from __future__ import annotations

import math
import os
import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import reducers as _r
from .kinds import MFKind
from .norms import WeightedDefuzzifier
from .rules import TNorm

__all__ = ["ENGINE_ENV", "engine", "extended", "interval", "output", "pack", "supported"]

FloatArray = NDArray[np.float64]

#: Environment variable choosing the evaluation engine (``auto``, ``numpy``, ``compiled``).
ENGINE_ENV = "IT2TRACK_ENGINE"
_ENGINES = ("auto", "numpy", "compiled")
#: Membership kinds the kernels implement (codes in ``_jit._memberships``).
_KINDS = frozenset(MFKind) - {MFKind.OTHER}
#: ... of which these need no extended specialisation (see :func:`extended`).
_BASIC_KINDS = frozenset({MFKind.TRAPEZOID, MFKind.GAUSSIAN, MFKind.UM_GAUSSIAN_UPPER,
                          MFKind.UM_GAUSSIAN_LOWER})
#: t-norm codes of the kernels (``_jit.PRODUCT`` ...).
_TNORMS = {TNorm.PRODUCT: 0, TNorm.MINIMUM: 1, TNorm.BOUNDED_DIFFERENCE: 2,
           TNorm.DRASTIC_PRODUCT: 3, TNorm.EINSTEIN_PRODUCT: 4, TNorm.HAMACHER_PRODUCT: 5,
           TNorm.NILPOTENT_MINIMUM: 6}  # fmt: skip
#: Rule-language features (``SystemTables.features``) the kernels implement.
_FEATURES: frozenset[str] = frozenset()
#: Built-in reducers by their kernels -> code in ``_jit``.
_REDUCERS: dict[Any, int] = {
    _r._exhaustive_left: 0, _r._km_left: 1, _r._ekm_left: 2, _r._eiasc_left: 3,
    _r._nie_tan: 4, _r._wu_mendel: 5,
}  # fmt: skip
_T1, _T1_SUM = 6, 7
_PARALLEL_MIN = 8192  # fewer points than this: the serial kernel (no thread start-up)
_jit: Any = None
#: Environment variable naming the lock of a background compile (it2track.tracking.kernel_cache):
#: while another process holds it, this one uses the numpy engine (same bits) for the fuzzy
#: kernels; the closed loop's own lock (:func:`loop_lock`, released first) is beside it.
LOCK_ENV = "IT2TRACK_KERNEL_LOCK"
#: ``1``: while the closed loop compiles, wait for it instead of running the numpy engine (a
#: command whose job is long sets it, for itself and the worker processes it starts).
WAIT_ENV = "IT2TRACK_KERNEL_WAIT"


def locked(path: str) -> bool:
    """Whether another process holds the lock file ``path`` (a background compile runs)."""
    try:
        import fcntl

        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW)
    except (ImportError, OSError):
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    finally:
        os.close(fd)  # (closing releases the shared lock taken above)
    return False


def loop_lock(path: str) -> str:
    """The closed loop's lock beside the fuzzy kernels' lock ``path`` (``k.lock`` ->
    ``k.loop.lock``): a background compile releases it as soon as the loop is cached."""
    root, ext = os.path.splitext(path)
    return f"{root}.loop{ext}"


#: Seconds a job waits for the closed loop's compile at most (then it goes on with numpy).
WAIT_LIMIT_S = 600.0


def wait_unlocked(path: str, limit_s: float | None = None) -> bool:
    """Wait until no process holds the lock file ``path``, at most ``limit_s`` seconds
    (default :data:`WAIT_LIMIT_S`); whether it is free (at once if there is no such file)."""
    deadline = time.monotonic() + (WAIT_LIMIT_S if limit_s is None else limit_s)
    while locked(path):
        if time.monotonic() >= deadline:
            return False
        time.sleep(0.05)
    return True


#: Run-steps a second of the numpy engine on one core while the kernels compile (the numpy
#: fuzzy evaluation too), rounded down: the paper's IT2FLC in batches of 256 runs, 0.77 M per
#: CPU second on the reference machine, 3.35 M in batches of 2048 (``benchmarks/
#: bench_compile.py`` section 4 prints both). Decides what waits for the compiled loop
#: (``--quick``, 0.8 M run-steps, does not; the default study, 140 M, does, whichever rate
#: applies).
NUMPY_RUN_STEPS_PER_S = 0.6e6
#: A call this short on the numpy engine (seconds) runs there even while a long job waits
#: for the compiled loop (a study's traces for its figures, while the compile goes on).
SHORT_CALL_S = 0.5


def gate(path: str, *, wait: bool = False) -> Callable[[str, float], bool]:
    """The :data:`_defer` of a background compile holding ``path`` (the fuzzy kernels) and
    :func:`loop_lock` (the closed loop): ``gate("fuzzy", n)``/``gate("loop", n)`` is True
    while that part compiles. ``wait``: ``gate("loop", n)`` waits until the loop is compiled
    instead (at most :data:`WAIT_LIMIT_S`, against a compile that hangs), unless the call's
    ``n`` run-steps take at most :data:`SHORT_CALL_S` on the numpy engine."""
    loop = loop_lock(path)
    gave_up: list[bool] = []  # (a wait that timed out is not repeated at every call)

    def deferring(part: str, run_steps: float = math.inf) -> bool:
        if part == "loop":
            short = run_steps <= SHORT_CALL_S * NUMPY_RUN_STEPS_PER_S
            if wait and not short and not gave_up:
                if wait_unlocked(loop):
                    return False
                gave_up.append(True)
                return True
            return locked(loop)
        return locked(path)

    return deferring


#: While ``_defer(part)`` is True the compiled ``part`` (``"fuzzy"``: the batch and scalar
#: kernels; ``"loop"``: the closed loop) is not used: :func:`load_jit` (fuzzy) and
#: :func:`it2track.tracking.compiled.load` (loop) answer None and the numpy engine computes.
_defer: Callable[[str, float], bool] | None = (
    gate(os.environ[LOCK_ENV], wait=os.environ.get(WAIT_ENV) == "1")
    if os.environ.get(LOCK_ENV) else None)


def current_gate() -> tuple[str, bool] | None:
    """This process's background-compile gate (the lock and whether it waits; None: none), for
    a worker process started before the compile began (:func:`follow_gate`)."""
    lock = os.environ.get(LOCK_ENV)
    return (lock, os.environ.get(WAIT_ENV) == "1") if lock else None


def follow_gate(state: tuple[str, bool] | None) -> None:
    """Make this process follow the gate ``state`` of :func:`current_gate` (a figure worker:
    its fork server started before the command's compile, so its environment has none)."""
    global _defer
    _defer = None if state is None else gate(state[0], wait=state[1])


def deferred(part: str, run_steps: float = math.inf) -> bool:
    """Whether the compiled ``part`` (``"fuzzy"`` or ``"loop"``) is left to the numpy engine
    for now, for a call of ``run_steps`` (a background compile holds its lock; see
    :data:`_defer` and :func:`gate`)."""
    return _defer is not None and _defer(part, run_steps)


def engine() -> str:
    """The engine ``IT2TRACK_ENGINE`` asks for (``"auto"`` when unset).

    Raises
    ------
    ValueError
        If the variable holds anything but ``auto``, ``numpy`` or ``compiled``.
    """
    value = os.environ.get(ENGINE_ENV, "auto").strip().lower() or "auto"
    if value not in _ENGINES:
        raise ValueError(f"environment variable {ENGINE_ENV}={value!r} must be one of {_ENGINES}")
    return value


def load_jit() -> Any:
    """The compiled module (imports numba), or ``None`` if numba is missing or disabled, or
    its kernels are being compiled in the background (:func:`deferred`)."""
    global _jit
    if _jit is None:
        if engine() == "numpy" or deferred("fuzzy"):
            return None
        _jit = import_jit()
    return _jit


def import_jit() -> Any:
    """The compiled module whatever the background compile does (imports numba; compiles
    nothing), or ``None`` if numba is missing or ``IT2TRACK_ENGINE=numpy``."""
    choice = engine()
    if choice == "numpy":
        return None
    try:
        from . import _jit as module
    except ImportError:
        if choice == "compiled":
            raise ImportError(f"{ENGINE_ENV}=compiled but numba cannot be imported") from None
        return None
    return module


def _compiled_as(system: Any) -> str | None:
    """``"it2"`` or ``"t1"`` if ``system`` is exactly an ``IT2Sugeno`` or a ``T1Sugeno``, else
    None. Each of the two classes names itself in its own ``_compiled_as``; this reads the
    class's own namespace, so a subclass (which may change the behaviour) gets None, and this
    module needs no import of :mod:`.sugeno` (which imports it, through :mod:`.system`)."""
    kind: str | None = vars(type(system)).get("_compiled_as")
    return kind


def supported(system: Any) -> str | None:
    """``None`` if the kernels implement ``system``, else why not (for messages and tests)."""
    kind = _compiled_as(system)
    if kind is None:
        return f"{type(system).__name__} is not IT2Sugeno or T1Sugeno"
    t = system.tables
    if getattr(system, "aggregation", None) is not None:
        return "a T1Sugeno aggregation (rules grouped by consequent) is not compiled"
    extra = set().union(*(o.features for o in t.outputs)) - _FEATURES  # every output's
    if extra:
        return f"rule features {sorted(extra)} are not compiled"
    kinds = {MFKind(int(k)) for k in t.mf_kind}
    if not kinds <= _KINDS:
        return f"membership kinds {sorted(k.name for k in kinds - _KINDS)} are not compiled"
    for k in np.flatnonzero(t.mf_kind == MFKind.SCALED_LAGGED):
        if not 0 <= t.mf_params[k, 0] < k:  # (the tables put the upper row first)
            return f"scaled-lagged row {k} reads row {t.mf_params[k, 0]:g}, not an earlier one"
    if system.tnorm not in _TNORMS:
        return f"t-norm {system.tnorm!r} is not compiled"
    if kind == "it2":
        red = system.reducer
        kernel = red._approx if red._approx is not None else red._left
        if kernel not in _REDUCERS:
            return f"reducer {red.name!r} is not a built-in one"
    return None


def extended(system: Any) -> bool:
    """True if ``system`` (one :func:`supported` accepts) needs the kernels' extended
    specialisation: a membership kind of :mod:`.curves`/:mod:`.shapes` (or MATLAB's lagged
    lower MF), a t-norm other than product/minimum, or ``wtsum``.

    The kernels are compiled twice over, lazily: without these (``ext`` left out: numba
    prunes their branches, so a system like the paper's compiles exactly the code it did
    before they existed) and, the first time a system needs them, with them.
    """
    t = system.tables
    return bool(
        not {MFKind(int(k)) for k in t.mf_kind} <= _BASIC_KINDS
        or _TNORMS[system.tnorm] > 1
        or (_compiled_as(system) == "t1" and system.defuzzifier is not WeightedDefuzzifier.AVERAGE)
    )


def pack(system: Any) -> FloatArray:
    """The system as one flat float64 array (layout: the constants at the top of ``_jit``).

    Header (25 values), then the arrays the header's offsets point to: universes, membership
    kinds, parameters (5 per row) and inputs, the rules' upper and lower rows
    (``(R, n_inputs)``, rules sorted by ``y_lo``), the sorted consequents, the order of
    ``y_hi``, and the Wu-Mendel and Nie-Tan constants. Integers are stored exactly (< 2^53).
    """
    t = system.tables
    r = t.n_rules
    y_lo, y_hi, ohi = t.y_lo_s, t.y_hi_s, t.order_hi_s
    y_hs = y_hi[ohi]
    if _compiled_as(system) == "it2":
        red = system.reducer
        kernel = red._approx if red._approx is not None else red._left
        code = _REDUCERS[kernel]
        max_iter = red._cap(r)
    else:
        code = _T1 if system.defuzzifier is WeightedDefuzzifier.AVERAGE else _T1_SUM
        max_iter = 1
    eps = np.finfo(np.float64).eps
    tol_l = (8.0 + 2.0 * r) * eps * max(1.0, float(np.abs(y_lo).max()))
    tol_r = (8.0 + 2.0 * r) * eps * max(1.0, float(np.abs(y_hs).max()))
    parts = [
        t.lo, t.hi, t.mf_kind.astype(np.float64), t.mf_params.reshape(-1),
        t.mf_input.astype(np.float64), t.upper_rows_s.reshape(-1).astype(np.float64),
        t.lower_rows_s.reshape(-1).astype(np.float64), y_lo, y_hs, ohi.astype(np.float64),
        np.concatenate([y_lo - y_lo.min(), y_lo.max() - y_lo, y_hi - y_hi.min(),
                        y_hi.max() - y_hi]),
        0.5 * (y_lo + y_hi), y_hi,
    ]  # fmt: skip
    header = [
        t.n_inputs, t.n_rows, r, code, _TNORMS[system.tnorm], max_iter,
        system.on_zero_firing is not None,
        0.0 if system.on_zero_firing is None else system.on_zero_firing,
        tol_l, tol_r, round(r / 2.4), round(r / 1.7),
    ]  # fmt: skip
    offsets = []
    pos = 25
    for p in parts:
        offsets.append(pos)
        pos += p.size
    out = np.concatenate([np.array(header + offsets, dtype=np.float64), *parts])
    out.setflags(write=False)
    return out


def _entry(system: Any) -> FloatArray | None:
    """The packed system if the kernels serve it (cached on the system), else None."""
    try:
        packed: FloatArray | None = system.__dict__["_kernel_pack"]
        return packed
    except KeyError:
        pass
    packed = None
    ext = False
    if engine() != "numpy" and supported(system) is None:
        if load_jit() is not None:
            packed = pack(system)
            ext = extended(system)
        elif _defer is not None:
            return None  # deferred to the numpy engine for now: ask again at the next call
    # immutable system: derived caches (set before the pack, which output() looks up first)
    object.__setattr__(system, "_kernel_ext", ext)
    object.__setattr__(system, "_kernel_pack", packed)
    return packed


def _float(x: object) -> float | None:
    """``x`` as a float if it is a Python/NumPy real scalar (what the scalar path takes)."""
    if type(x) is float or type(x) is int or isinstance(x, np.floating):
        return float(x)
    return None


def output(system: Any, xs: tuple[Any, ...]) -> float | None:
    """``system(*xs)`` for two scalar inputs by the compiled kernel, or None (numpy answers).

    Kept lean (a real-time loop calls it every period): the packed system is looked up once
    per system, and only two type checks stand between the call and the kernel.
    """
    try:
        packed = system.__dict__["_kernel_pack"]
    except KeyError:
        packed = _entry(system)
    if packed is None or len(xs) != 2:
        return None
    a, b = xs
    if type(a) is not float:
        a = _float(a)
        if a is None:
            return None
    if type(b) is not float:
        b = _float(b)
        if b is None:
            return None
    if system.__dict__["_kernel_ext"]:
        u: float = _jit.scalar2(packed, a, b, True)
    else:
        u = _jit.scalar2(packed, a, b)  # (ext left out: the basic specialisation)
    return u if u == u else None  # NaN: the reference raises


def interval(
    system: Any, x: FloatArray, *, crisp: bool
) -> tuple[FloatArray, FloatArray | None] | None:
    """Evaluate clipped inputs ``x`` (n_inputs, N) by the compiled kernel, or None.

    ``crisp``: return ``(u, None)`` with ``u = (yl + yr) / 2``; else ``(yl, yr)``. None when
    the kernels do not serve the system or the reference must raise somewhere.
    """
    packed = _entry(system)
    if packed is None:
        return None
    n = x.shape[1]
    x = np.ascontiguousarray(x, dtype=np.float64)
    out_a = np.empty(n)
    out_b = out_a if crisp else np.empty(n)
    status = np.empty(n, dtype=np.int8)
    bounds = _split(n, threads() if n >= _PARALLEL_MIN else 1, _jit.BLOCK)
    ext = (True,) if system.__dict__["_kernel_ext"] else ()  # (left out: basic, see extended)
    run_threads([(_jit.batch, (packed, x, out_a, out_b, status, crisp, a, b, *ext))
                 for a, b in bounds])  # fmt: skip
    if status.any():
        return None
    return out_a, (None if crisp else out_b)


def threads() -> int:
    """Threads the compiled kernels use: ``numba.get_num_threads()`` (``numba.set_num_threads``
    changes it; ``NUMBA_NUM_THREADS`` sets the default, the number of CPUs)."""
    import numba

    return int(numba.get_num_threads())


def _split(n: int, parts: int, align: int) -> list[tuple[int, int]]:
    """``parts`` contiguous ranges covering ``0 .. n`` (boundaries multiples of ``align``)."""
    if n == 0:
        return [(0, 0)]
    size = -(-n // max(1, parts))
    size = -(-size // align) * align
    return [(a, min(n, a + size)) for a in range(0, n, size)]


_POOL: tuple[int, ThreadPoolExecutor] | None = None
_POOL_LOCK = threading.Lock()


def run_threads(calls: list[tuple[Callable[..., object], tuple[object, ...]]]) -> None:
    """Run ``fn(*args)`` for every pair, the first in this thread and the others on a thread
    pool (the compiled kernels release the GIL), and wait for all; re-raises the first error.

    The kernels write disjoint parts of their outputs, so results do not depend on the number
    of threads or their timing. The pool is per process (recreated after a fork).
    """
    global _POOL
    if len(calls) <= 1:
        for fn, args in calls:
            fn(*args)
        return
    with _POOL_LOCK:
        if _POOL is None or _POOL[0] != os.getpid():
            _POOL = (os.getpid(), ThreadPoolExecutor(max_workers=os.cpu_count() or 2,
                                                     thread_name_prefix="it2track-kernel"))
        pool = _POOL[1]
    futures = [pool.submit(fn, *args) for fn, args in calls[1:]]
    fn, args = calls[0]
    fn(*args)
    for f in futures:
        f.result()

"""Executors: where independent, self-contained tasks run (this process, local processes, Dask).

An executor maps a module-level function over an iterable of small, picklable task
descriptions and yields ``(task, result)`` pairs as the tasks finish (in any order)::

    with make_executor(workers=2) as ex:
        for task, result in ex.imap_unordered(simulate_chunk, tasks):
            ...                                   # the caller writes results, in its process

Three strategies, chosen by the caller (the CLI maps ``--workers``/``--scheduler`` to them):

- :class:`InProcessExecutor` (default): runs each task in the calling process, in order.
- :class:`ProcessExecutor`: ``concurrent.futures.ProcessPoolExecutor`` with a ``spawn`` (or
  ``forkserver``) context, so workers never inherit the caller's threads or locks. Workers
  ignore SIGINT: a Ctrl-C reaches the caller only, which cancels what has not started (and
  waits for the running tasks). Workers exit by themselves within a second if the caller dies
  (``kill -9``).
- :class:`DaskExecutor`: a ``dask.distributed`` cluster named by its scheduler address
  (``tcp://host:port``). Dask is imported only here, lazily; without it the executor raises
  :class:`ExecutorError` telling how to install it. Workers need ``it2track`` installed.

At most ``max_pending`` tasks are in flight at a time (default: twice the worker count), so the
memory of the caller stays flat however many tasks the iterable holds. Tasks should describe
work (specs and index ranges), not carry big arrays; results are whatever the function returns.
Determinism is the function's business: executors never change what a task computes.
"""

from __future__ import annotations

import abc
import math
import multiprocessing
import os
import queue
import re
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass
from typing import Any, TypeVar

__all__ = [
    "DaskExecutor",
    "DaskSecurity",
    "Executor",
    "ExecutorError",
    "InProcessExecutor",
    "ProcessExecutor",
    "check_scheduler_address",
    "make_executor",
    "peak_rss_bytes",
]

T = TypeVar("T")
R = TypeVar("R")


class ExecutorError(RuntimeError):
    """An executor cannot be created (bad worker count, Dask missing, scheduler unreachable)."""


class Executor(abc.ABC):
    """Maps a function over tasks; see the module docstring. Use as a context manager."""

    #: Number of tasks that can run at the same time.
    n_workers: int = 1

    @abc.abstractmethod
    def imap_unordered(
        self,
        fn: Callable[[T], R],
        tasks: Iterable[T],
        *,
        max_pending: int | None = None,
    ) -> Iterator[tuple[T, R]]:
        """Yield ``(task, fn(task))`` for every task, as they finish.

        ``tasks`` is consumed lazily: at most ``max_pending`` (default ``2 * n_workers``)
        tasks are submitted and not yet yielded. An exception raised by ``fn`` propagates
        to the caller when its task is reached; tasks not yet started are cancelled.
        """

    def close(self) -> None:  # noqa: B027 - optional hook, nothing to release by default
        """Release workers and connections (idempotent)."""

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _pending_limit(self, max_pending: int | None) -> int:
        limit = 2 * self.n_workers if max_pending is None else max_pending
        if isinstance(limit, bool) or not isinstance(limit, int) or limit < 1:
            raise ValueError(f"max_pending={max_pending!r} must be a positive integer")
        return limit


class InProcessExecutor(Executor):
    """Run every task in the calling process, one after the other, in order."""

    n_workers = 1

    def imap_unordered(
        self,
        fn: Callable[[T], R],
        tasks: Iterable[T],
        *,
        max_pending: int | None = None,
    ) -> Iterator[tuple[T, R]]:
        self._pending_limit(max_pending)
        for task in tasks:
            yield task, fn(task)

    def __repr__(self) -> str:
        return "InProcessExecutor()"


def _watch_parent(parent: int, period: float) -> None:
    while True:
        time.sleep(period)
        if os.getppid() != parent:  # re-parented: the driver died (e.g. kill -9)
            os._exit(1)


def _usable_cpus() -> int:
    """CPUs this process may run on (its affinity mask, as numba's default thread count)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def _init_worker(parent: int, kernel_threads: int) -> None:
    """Worker initialiser: leave Ctrl-C to the parent (which cancels the pool), and exit when
    the parent dies -- a pool worker would otherwise wait forever for its next task.

    The workers share the CPUs: each one's compiled kernels get ``kernel_threads`` threads
    (``NUMBA_NUM_THREADS``, read when numba is first imported, which a fresh spawned worker
    has not done yet), unless the user has set ``NUMBA_NUM_THREADS``. Results do not depend on
    the number of threads."""
    if "NUMBA_NUM_THREADS" not in os.environ:
        if "numba" not in sys.modules:
            os.environ["NUMBA_NUM_THREADS"] = str(kernel_threads)
        else:  # imported already (e.g. by a script preloaded as __main__)
            import numba

            numba.set_num_threads(min(kernel_threads, numba.get_num_threads()))
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(
        target=_watch_parent, args=(parent, 0.5), name="it2track-parent-watch", daemon=True
    ).start()


class ProcessExecutor(Executor):
    """Local worker processes (``concurrent.futures.ProcessPoolExecutor``).

    Parameters
    ----------
    workers : int
        Number of worker processes (>= 1).
    context : {"spawn", "forkserver"}
        Start method. ``spawn`` (default) works everywhere; ``forkserver`` starts workers
        faster on POSIX. ``fork`` is refused: it copies the parent's threads and locks.
    """

    def __init__(self, workers: int, *, context: str = "spawn") -> None:
        if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
            raise ExecutorError(f"workers={workers!r} must be an integer >= 1")
        if context not in ("spawn", "forkserver"):
            raise ExecutorError(f"context={context!r} must be 'spawn' or 'forkserver'")
        self.n_workers = workers
        self.context = context
        self._pool: ProcessPoolExecutor | None = None

    def _get_pool(self) -> ProcessPoolExecutor:
        if self._pool is None:
            self._pool = ProcessPoolExecutor(
                max_workers=self.n_workers,
                mp_context=multiprocessing.get_context(self.context),
                initializer=_init_worker,
                initargs=(os.getpid(), max(1, _usable_cpus() // self.n_workers)),
            )
        return self._pool

    def imap_unordered(
        self,
        fn: Callable[[T], R],
        tasks: Iterable[T],
        *,
        max_pending: int | None = None,
    ) -> Iterator[tuple[T, R]]:
        limit = self._pending_limit(max_pending)
        pool = self._get_pool()
        pending: dict[Future[R], T] = {}
        it = iter(tasks)
        exhausted = False
        try:
            while True:
                while not exhausted and len(pending) < limit:
                    try:
                        task = next(it)
                    except StopIteration:
                        exhausted = True
                        break
                    pending[pool.submit(fn, task)] = task
                if not pending:
                    return
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for fut in done:
                    task = pending.pop(fut)
                    yield task, fut.result()
        finally:
            for fut in pending:
                fut.cancel()

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def __repr__(self) -> str:
        return f"ProcessExecutor({self.n_workers}, context={self.context!r})"


def _import_distributed() -> Any:
    try:
        import distributed
    except ImportError as exc:
        raise ExecutorError(
            "the Dask executor needs dask.distributed, which is not installed: "
            "pip install 'it2track[dask]'"
        ) from exc
    return distributed


#: Scheduler address: ``[scheme://]host:port`` (IPv6 hosts in brackets).
_ADDRESS_RE = re.compile(
    r"^(?:(?P<scheme>[A-Za-z][A-Za-z0-9+.-]*)://)?"
    r"(?P<host>\[[0-9A-Fa-f:.]+\]|[^\s:/\[\]@]+):(?P<port>[0-9]{1,5})/?$"
)
_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx")


def check_scheduler_address(address: object) -> str:
    """``address`` if it looks like a Dask scheduler address, else :class:`ExecutorError`.

    Accepted: ``scheme://host:port`` with scheme tcp, tls, ws, wss or ucx, or ``host:port``
    (TCP); port 1-65535; and ``inproc://...`` (a scheduler in this process). Checked before
    Dask is asked to connect: a malformed address would otherwise raise inside
    ``distributed.Client`` and stall its destructor for a minute.
    """
    if not isinstance(address, str) or not address:
        raise ExecutorError(
            f"scheduler={address!r} must be an address like tcp://HOST:PORT (e.g. "
            "tcp://10.0.0.5:8786)"
        )
    if address.startswith("inproc://") and len(address) > len("inproc://"):
        return address  # a scheduler in this process (tests, notebooks)
    m = _ADDRESS_RE.match(address)
    if m is None:
        raise ExecutorError(
            f"scheduler address {address!r} is not of the form tcp://HOST:PORT (e.g. "
            "tcp://10.0.0.5:8786 or tls://host:8786); the port is required"
        )
    scheme = (m["scheme"] or "tcp").lower()
    if scheme not in _SCHEMES:
        raise ExecutorError(
            f"scheduler address {address!r}: unknown protocol {scheme!r}; use one of "
            f"{', '.join(_SCHEMES)}"
        )
    port = int(m["port"])
    if not 1 <= port <= 65535:
        raise ExecutorError(f"scheduler address {address!r}: port {port} is not in 1-65535")
    return address


@dataclass(frozen=True, kw_only=True)
class DaskSecurity:
    """TLS settings for the connection to a Dask scheduler (``distributed.Security``).

    Parameters
    ----------
    ca_file : str
        CA certificate(s) that signed the scheduler's certificate (PEM).
    cert : str
        This client's certificate (PEM); may also hold the key.
    key : str
        This client's private key (PEM), if not in ``cert``.

    With any of these given, the scheduler address must use ``tls://`` and encryption is
    required. Without them, Dask's own configuration applies (``distributed.comm.tls.*`` in
    ``~/.config/dask/*.yaml`` or ``DASK_DISTRIBUTED__COMM__TLS__CA_FILE`` etc.).
    """

    ca_file: str = ""
    cert: str = ""
    key: str = ""

    def __post_init__(self) -> None:
        for key in ("ca_file", "cert", "key"):
            value = getattr(self, key)
            if not isinstance(value, str):
                raise ExecutorError(f"TLS {key}={value!r} must be a file path")
            if value and not os.path.isfile(value):
                raise ExecutorError(f"TLS {key} file {value!r} does not exist or is not a file")
        if self.key and not self.cert:
            raise ExecutorError("a TLS key needs its certificate (--tls-cert)")

    @property
    def given(self) -> bool:
        return bool(self.ca_file or self.cert or self.key)

    def to_distributed(self, distributed: Any) -> Any:
        return distributed.Security(
            tls_ca_file=self.ca_file or None,
            tls_client_cert=self.cert or None,
            tls_client_key=self.key or None,
            require_encryption=True,
        )


class DaskExecutor(Executor):
    """Tasks on a ``dask.distributed`` cluster.

    Trust model: Dask's scheduler does not authenticate clients or workers unless TLS is
    configured, and results come back from workers as pickles that the driver unpickles -- a
    machine that can reach the scheduler can run code on the driver. Use a cluster on a network
    you trust, or TLS with certificates (``security``), never a scheduler open to others.

    Parameters
    ----------
    scheduler : str
        Scheduler address, e.g. ``"tcp://10.0.0.5:8786"`` (``tls://`` with TLS).
    timeout : float
        Seconds to wait for the connection.
    worker_timeout : float
        Seconds to wait for at least one worker (when the scheduler has none, at start or
        because every worker left during the run) before giving up with :class:`ExecutorError`.
    security : DaskSecurity, optional
        TLS certificates; default: Dask's configuration.

    Raises
    ------
    ExecutorError
        If the address is malformed, dask.distributed is not installed, the scheduler cannot
        be reached, or no worker connects within ``worker_timeout``.
    """

    #: Seconds between checks for lost workers while waiting for results.
    poll_interval: float = 1.0

    def __init__(
        self,
        scheduler: str,
        *,
        timeout: float = 30.0,
        worker_timeout: float = 60.0,
        security: DaskSecurity | None = None,
    ) -> None:
        check_scheduler_address(scheduler)
        for name, value in (("timeout", timeout), ("worker_timeout", worker_timeout)):
            if (isinstance(value, bool) or not isinstance(value, int | float)
                    or not math.isfinite(value) or value <= 0):
                raise ExecutorError(f"{name}={value!r} must be a number of seconds > 0")
        tls = scheduler.lower().startswith("tls://")
        if security is not None and security.given and not tls:
            raise ExecutorError(
                f"TLS certificates were given but the scheduler address {scheduler!r} is not "
                "tls://HOST:PORT"
            )
        distributed = _import_distributed()
        self.scheduler = scheduler
        self.worker_timeout = float(worker_timeout)
        kwargs: dict[str, Any] = {}
        if security is not None and security.given:
            kwargs["security"] = security.to_distributed(distributed)
        try:
            self._client = distributed.Client(
                scheduler, timeout=timeout, set_as_default=False, **kwargs
            )
        except (OSError, ValueError, TypeError) as exc:  # includes timeouts and refusals
            raise ExecutorError(f"cannot connect to Dask scheduler {scheduler!r}: {exc}") from exc
        try:
            if not self._client.nthreads():
                print(
                    f"waiting up to {self.worker_timeout:g} s for a Dask worker to connect to "
                    f"{scheduler} ...",
                    file=sys.stderr,
                    flush=True,
                )
                self._client.wait_for_workers(1, timeout=self.worker_timeout)
        except (OSError, TimeoutError) as exc:
            self.close()
            raise ExecutorError(
                f"no Dask worker is connected to {scheduler} (waited {self.worker_timeout:g} s): "
                f"start workers with `dask worker {scheduler}` or raise --worker-timeout"
            ) from exc
        threads = sum(self._client.nthreads().values())
        self.n_workers = max(1, threads)

    def imap_unordered(
        self,
        fn: Callable[[T], R],
        tasks: Iterable[T],
        *,
        max_pending: int | None = None,
    ) -> Iterator[tuple[T, R]]:
        limit = self._pending_limit(max_pending)
        client = self._client
        if client is None:
            raise ExecutorError("the Dask executor is closed")
        it = iter(tasks)
        owner: dict[str, T] = {}
        pending: dict[str, Any] = {}
        ready: queue.SimpleQueue[Any] = queue.SimpleQueue()

        def submit() -> bool:
            try:
                task = next(it)
            except StopIteration:
                return False
            fut = client.submit(fn, task, pure=False)
            owner[fut.key] = task
            pending[fut.key] = fut
            fut.add_done_callback(ready.put)  # called from Dask's thread when it finishes
            return True

        while len(pending) < limit and submit():
            pass
        idle_since: float | None = None
        try:
            while pending:
                try:
                    fut = ready.get(timeout=self.poll_interval)
                except queue.Empty:
                    # Nothing finished for a while: are there still workers to do the work?
                    if client.nthreads():
                        idle_since = None
                    elif idle_since is None:
                        idle_since = time.monotonic()
                    elif time.monotonic() - idle_since > self.worker_timeout:
                        raise ExecutorError(
                            f"every Dask worker left {self.scheduler} and none came back within "
                            f"{self.worker_timeout:g} s; {len(pending)} task(s) were waiting"
                        ) from None
                    continue
                if fut.key not in pending:
                    continue
                idle_since = None
                result = fut.result()
                task = owner.pop(fut.key)
                del pending[fut.key]
                fut.release()
                while len(pending) < limit and submit():
                    pass
                yield task, result
        finally:
            if pending:
                client.cancel(list(pending.values()))

    def close(self) -> None:
        client = getattr(self, "_client", None)
        if client is not None:
            client.close()
            self._client = None

    def __repr__(self) -> str:
        return f"DaskExecutor({self.scheduler!r})"


def make_executor(
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    context: str = "spawn",
    security: DaskSecurity | None = None,
    worker_timeout: float = 60.0,
) -> Executor:
    """The executor for the CLI options ``--workers N`` / ``--scheduler ADDRESS``.

    No option (or ``workers=0``) gives :class:`InProcessExecutor`; ``workers >= 1`` a
    :class:`ProcessExecutor` with that many processes; a ``scheduler`` a :class:`DaskExecutor`.

    Raises
    ------
    ExecutorError
        If both are given, ``workers`` is negative, or the Dask executor cannot start.
    """
    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, int) or workers < 0
    ):
        raise ExecutorError(f"workers={workers!r} must be an integer >= 0")
    if scheduler is not None:
        if workers:
            raise ExecutorError("give either workers or a Dask scheduler, not both")
        return DaskExecutor(scheduler, security=security, worker_timeout=worker_timeout)
    if security is not None and security.given:
        raise ExecutorError("TLS certificates apply only to a Dask scheduler (--scheduler)")
    if not workers:
        return InProcessExecutor()
    return ProcessExecutor(workers, context=context)


def peak_rss_bytes() -> int:
    """Peak resident set size of the calling process so far, in bytes (0 if unknown).

    From ``resource.getrusage`` (kB on Linux, bytes on macOS); 0 where ``resource`` is missing.
    """
    try:
        import resource
    except ImportError:  # pragma: no cover - Windows
        return 0
    peak = int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
    return peak if sys.platform == "darwin" else peak * 1024

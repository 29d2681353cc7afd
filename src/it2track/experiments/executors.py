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
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from typing import Any, TypeVar

__all__ = [
    "DaskExecutor",
    "Executor",
    "ExecutorError",
    "InProcessExecutor",
    "ProcessExecutor",
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


def _init_worker(parent: int) -> None:
    """Worker initialiser: leave Ctrl-C to the parent (which cancels the pool), and exit when
    the parent dies -- a pool worker would otherwise wait forever for its next task."""
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
                initargs=(os.getpid(),),
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


class DaskExecutor(Executor):
    """Tasks on a ``dask.distributed`` cluster.

    Parameters
    ----------
    scheduler : str
        Scheduler address, e.g. ``"tcp://10.0.0.5:8786"``.
    timeout : float
        Seconds to wait for the connection.

    Raises
    ------
    ExecutorError
        If dask.distributed is not installed or the scheduler cannot be reached.
    """

    def __init__(self, scheduler: str, *, timeout: float = 30.0) -> None:
        if not isinstance(scheduler, str) or not scheduler:
            raise ExecutorError(f"scheduler={scheduler!r} must be an address like tcp://host:port")
        distributed = _import_distributed()
        self.scheduler = scheduler
        try:
            self._client = distributed.Client(scheduler, timeout=timeout, set_as_default=False)
        except OSError as exc:  # includes TimeoutError and connection refusals
            raise ExecutorError(f"cannot connect to Dask scheduler {scheduler!r}: {exc}") from exc
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
        distributed = _import_distributed()
        client = self._client
        it = iter(tasks)
        owner: dict[str, T] = {}

        def submit() -> Any | None:
            try:
                task = next(it)
            except StopIteration:
                return None
            fut = client.submit(fn, task, pure=False)
            owner[fut.key] = task
            return fut

        first = [f for f in (submit() for _ in range(limit)) if f is not None]
        if not first:
            return
        pending = {f.key: f for f in first}
        queue = distributed.as_completed(first, loop=client.loop)
        try:
            for fut in queue:
                result = fut.result()
                task = owner.pop(fut.key)
                del pending[fut.key]
                fut.release()
                nxt = submit()
                if nxt is not None:
                    pending[nxt.key] = nxt
                    queue.add(nxt)
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
    *, workers: int | None = None, scheduler: str | None = None, context: str = "spawn"
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
        return DaskExecutor(scheduler)
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

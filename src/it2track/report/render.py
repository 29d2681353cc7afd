"""Write the study's figures on worker processes while this process does other work.

Drawing the figures costs about as much CPU time as the default study's simulations, on one
core. :class:`FigureRenderer` hands each figure to a pool of worker processes as soon as its
data exist (the time series and control surfaces before the Monte Carlo ends, the statistics
figures after it), so that figures, simulation and the text outputs share the machine's cores.
The files do not depend on where they were drawn (see
:func:`it2track.report.figures.write_figure`).

The workers start by ``forkserver`` where the platform has it, with the figure modules
preloaded once in the server (``spawn`` elsewhere): they never inherit this process's threads,
locks or matplotlib state.
"""

from __future__ import annotations

import multiprocessing
import multiprocessing.forkserver as forkserver
import os
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Executor, Future, ProcessPoolExecutor, wait
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # (not imported here: start_figure_server runs before the study's imports)
    from ..experiments.study import StudyResult

__all__ = ["FigureError", "FigureRenderer", "default_figure_workers", "start_figure_server"]

#: Module the figure workers import before their first job: the figures, warmed up.
_PRELOAD = "it2track.report._figure_preload"
#: The fork server's own first preload: it ends at once when its last client has gone.
_SERVER = "it2track.report._fork_server"


class FigureError(RuntimeError):
    """A figure could not be drawn or written; the message names the figure."""


def default_figure_workers() -> int:
    """Worker processes for the figures: the cores this process may use, at most 4 (there are
    about ten figures of very different cost); 0 (draw here) on a single core."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        cores = os.cpu_count() or 1
    return 0 if cores < 2 else min(cores, 4)


def _timed_write(key: str, result: StudyResult, summary: Sequence[Mapping[str, Any]],
                 out_dir: Path, svg: bool, draft: bool = False,
                 kernel_gate: tuple[str, bool] | None = None) -> tuple[Path, float]:
    """Worker job: write one figure; returns its PNG and the CPU seconds it took.
    ``kernel_gate``: the command's background compile at submission (a figure that evaluates
    a fuzzy system uses the numpy engine while it runs, instead of compiling for itself)."""
    from ..fuzzy import kernels
    from .figures import write_figure

    kernels.follow_gate(kernel_gate)
    started = time.process_time()
    png = write_figure(key, result, summary, out_dir, svg=svg, draft=draft)
    return png, time.process_time() - started


if TYPE_CHECKING:
    #: A figure job's arguments: key, result, summary, folder, svg, draft.
    _Args = tuple[str, StudyResult, Sequence[Mapping[str, Any]], Path, bool, bool]


def _gate() -> tuple[str, bool] | None:
    from ..fuzzy import kernels

    return kernels.current_gate()


def _init_worker() -> None:
    """Figure worker start: the numpy engine for the fuzzy evaluations a figure makes (the dead
    zone's slices, 2001 points per controller), unless ``IT2TRACK_ENGINE`` says otherwise. The
    same bits as the compiled kernels, without importing numba and loading them (about 0.5 s
    of CPU in the worker that draws the dead zone, at the end of a run)."""
    from ..fuzzy.kernels import ENGINE_ENV

    os.environ.setdefault(ENGINE_ENV, "numpy")


def _warm_up() -> None:
    """Worker job: import the figure modules (and matplotlib) before the first figure."""
    import importlib

    importlib.import_module(_PRELOAD)


def start_figure_server() -> bool:
    """Start the figure workers' fork server now; a :class:`FigureRenderer` made later forks
    its workers from it. Returns whether a server was started (only with ``forkserver``).

    The server imports matplotlib and the figures and draws its warm-up figure (about 1.5 s)
    in its own process while this one goes on: called as a command starts, before its own
    imports and its checks, the workers are ready when the first figure's data exist instead
    of a second after. The server ends with this process.
    """
    if "forkserver" not in multiprocessing.get_all_start_methods():  # pragma: no cover
        return False
    _context()  # names the preload
    forkserver.ensure_running()
    return True


def _context() -> Any:
    if "forkserver" in multiprocessing.get_all_start_methods():
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload([_SERVER, _PRELOAD])
        return ctx
    return multiprocessing.get_context("spawn")  # pragma: no cover - no forkserver here


class FigureRenderer:
    """Figures written into ``out_dir`` by worker processes, as their data become available.

    Parameters
    ----------
    out_dir : Path
        Folder for ``<key>.png`` (and ``<key>.svg``).
    workers : int
        Worker processes; 0 draws every figure in this process, at :meth:`submit`.
    svg : bool, default True
        Also write SVG files.
    on_done : callable, optional
        Called in this process as ``on_done(key, cpu_seconds)`` when a figure is written
        (from :meth:`submit` without workers, from :meth:`results` with them).
    draft : bool, default False
        Draft PNGs, for a smoke run (see :func:`~it2track.report.figures.write_figure`).

    Examples
    --------
    >>> with FigureRenderer(out, workers=2) as renderer:  # doctest: +SKIP
    ...     renderer.submit(early_result, [])     # traces and surfaces only
    ...     result = run_study(config)
    ...     renderer.submit(result, summarise(result.rows))
    ...     figures = renderer.results(result)
    """

    def __init__(self, out_dir: Path, *, workers: int, svg: bool = True,
                 on_done: Callable[[str, float], object] | None = None,
                 draft: bool = False) -> None:
        if workers < 0:
            raise ValueError(f"workers={workers} must be >= 0")
        self.out_dir = Path(out_dir)
        self.svg = svg
        self.draft = draft
        self.on_done = on_done
        self.workers = workers
        self._pool: Executor | None = None
        self._starter: threading.Thread | None = None
        self._start_error: BaseException | None = None
        self._lock = threading.Lock()
        self._starting = False
        self._deferred: list[tuple[str, _Args, tuple[str, bool] | None]] = []
        self._futures: dict[str, Future[tuple[Path, float]]] = {}
        self._done: dict[str, Path] = {}
        self._reported: set[str] = set()

    def __enter__(self) -> FigureRenderer:
        if self.workers:
            self._pool = ProcessPoolExecutor(self.workers, mp_context=_context(),
                                             initializer=_init_worker)
            # Start the workers now, while the study runs, from a thread: the first start
            # waits for the fork server to import matplotlib and the figures (seconds).
            # Figures submitted meanwhile are handed over by that thread once it is done.
            self._starting = True
            self._starter = threading.Thread(target=self._start_workers, daemon=True,
                                             name="figure-workers")
            self._starter.start()
        return self

    def _start_workers(self) -> None:
        pool = self._pool
        assert pool is not None
        try:
            for _ in range(self.workers):
                pool.submit(_warm_up)
        except Exception as exc:  # reported by results()
            self._start_error = exc
        with self._lock:
            self._starting = False
            if self._start_error is None:
                for key, args, gate in self._deferred:
                    self._futures[key] = pool.submit(_timed_write, *args, kernel_gate=gate)
                self._deferred.clear()

    def _join_starter(self) -> None:
        if self._starter is not None:
            self._starter.join()
            self._starter = None

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close(cancel=exc_type is not None)

    def close(self, *, cancel: bool = False) -> None:
        """Stop the workers (after the figures submitted, unless ``cancel``)."""
        self._join_starter()
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=cancel)
            self._pool = None

    @property
    def submitted(self) -> list[str]:
        """Keys of the figures submitted so far, in submission order."""
        with self._lock:
            waiting = [k for k, _, _ in self._deferred]
            return [*self._done, *(k for k in self._futures if k not in self._done), *waiting]

    def submit(self, result: StudyResult, summary: Sequence[Mapping[str, Any]]) -> list[str]:
        """Submit every figure whose data ``result`` and ``summary`` hold and that was not
        submitted before (see :func:`~it2track.report.figures.figure_plan`).

        Returns
        -------
        list of str
            The keys submitted by this call.
        """
        from .plan import figure_plan

        keys = [k for k in figure_plan(result, summary) if k not in self.submitted]
        for key in keys:
            args: _Args = (key, result, summary, self.out_dir, self.svg, self.draft)
            if self._pool is None:
                png, seconds = self._write_here(*args)
                self._done[key] = png
                self._report(key, seconds)
                continue
            with self._lock:
                if self._starting:  # never block on the workers' start-up
                    self._deferred.append((key, args, _gate()))
                else:
                    self._futures[key] = self._pool.submit(_timed_write, *args, kernel_gate=_gate())
        return keys

    def _write_here(self, key: str, result: StudyResult, summary: Sequence[Mapping[str, Any]],
                    out_dir: Path, svg: bool, draft: bool) -> tuple[Path, float]:
        try:
            return _timed_write(key, result, summary, out_dir, svg, draft)
        except Exception as exc:
            raise FigureError(f"figure {key!r} failed: {type(exc).__name__}: {exc}") from exc

    def _report(self, key: str, seconds: float) -> None:
        if key not in self._reported:
            self._reported.add(key)
            if self.on_done is not None:
                self.on_done(key, seconds)

    def poll(self) -> None:
        """Report the figures finished since the last call (without waiting)."""
        with self._lock:
            futures = list(self._futures.items())
        for key, future in futures:
            if future.done() and key not in self._done:
                self._collect(key, future)

    def _collect(self, key: str, future: Future[tuple[Path, float]]) -> None:
        try:
            png, seconds = future.result()
        except Exception as exc:
            raise FigureError(f"figure {key!r} failed: {type(exc).__name__}: {exc}") from exc
        self._done[key] = png
        self._report(key, seconds)

    def results(self, result: StudyResult) -> dict[str, Path]:
        """Wait for every submitted figure.

        Parameters
        ----------
        result : StudyResult
            The whole result: its :func:`~it2track.report.figures.figure_keys` give the order.

        Returns
        -------
        dict of str -> Path
            Figure key -> PNG file, in report order.

        Raises
        ------
        FigureError
            A figure failed (the first one, in submission order).
        """
        from .plan import figure_keys

        self._join_starter()  # hands over the figures submitted while the workers started
        if self._start_error is not None:
            raise FigureError(f"the figure workers did not start: {self._start_error}")
        pending = {f: k for k, f in self._futures.items() if k not in self._done}
        while pending:
            finished, _ = wait(pending, return_when="FIRST_COMPLETED")
            for future in sorted(finished, key=lambda f: list(self._futures).index(pending[f])):
                self._collect(pending.pop(future), future)
        order = {k: i for i, k in enumerate(figure_keys(result))}
        return dict(sorted(self._done.items(), key=lambda kv: order.get(kv[0], len(order))))

"""The first run of a simulating command: say that the kernels compile, once, and show it.

:func:`kernel_stage` wraps the work of ``simulate``, ``reproduce``, ``sweep`` and ``optimize``.
When numba's cache already holds the kernels it loads them and says nothing. Otherwise it
prints one stage line (``compiling the simulation kernels, once per install — about N s``),
starts the compile in a background process (:mod:`it2track.tracking.kernel_cache`), shows a
bar of its progress while the command computes on the numpy engine (same bits) -- or, for a
job the numpy engine would take longer over than the compile (``run_steps``), waits for the
closed loop -- and says when the compiled engine takes over. A progress bar of the command handed to
:meth:`KernelStage.watch` shows no ETA while the kernels compile (its rate would be the numpy
engine's) and starts its rate afresh when they are ready. Without a background process
(``IT2TRACK_BACKGROUND_COMPILE=0``, or no ``fcntl``) the kernels compile right here, with the
same line and bar, before the work starts.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import click

__all__ = ["KernelStage", "KernelStart", "compile_kernels", "kernel_stage", "start_kernels"]

#: The simulating bar's format while the kernels compile: no rate and no ETA.
_COMPILING_FORMAT = ("{desc}: {percentage:3.0f}%|{bar}| {n_fmt}/{total_fmt} [{elapsed}, "
                     "ETA once the kernels are compiled]")


class KernelStage:
    """What :func:`kernel_stage` found: ``status`` is ``"cached"`` (loaded, or numba not
    used), ``"background"`` (compiling in another process; the numpy engine computes, or a
    long job waits, meanwhile) or
    ``"inline"`` (compiled here, before the work)."""

    #: What :meth:`_finish` says when the followed compile ends ({s}: its seconds).
    done_text = ("compiled the closed-loop kernel in {s} s: the compiled engine takes over (the "
                 "fuzzy kernels follow in the background)")

    def __init__(self, status: str, *, progress: bool, background: Any = None) -> None:
        self.status = status
        self.progress = progress
        self.background = background
        if isinstance(background, _Inline):
            self.done_text = "compiled the simulation kernels in {s} s"
        self._bars: list[Any] = []
        self._done = threading.Event()
        self._thread: threading.Thread | None = None
        self._bar: Any = None

    # -- the bar of the compile, updated by a thread ------------------------------------------
    def _start_display(self) -> None:
        from tqdm import tqdm

        bg = self.background
        if self.progress:
            self._bar = tqdm(total=round(bg.estimate_s), unit="s", file=sys.stderr,
                             desc="compiling kernels", leave=False,
                             bar_format="{desc}: {percentage:3.0f}%|{bar}| {n}/{total} s "
                                        "(estimated)")
        self._thread = threading.Thread(target=self._follow, name="it2track-kernel-stage",
                                        daemon=True)
        self._thread.start()

    def _follow(self) -> None:
        bg = self.background
        while not self._done.wait(0.5):
            if not bg.running():
                self._finish()
                return
            if self._bar is not None:
                elapsed = time.monotonic() - bg.started
                self._bar.n = min(int(elapsed), max(0, self._bar.total - 1))
                self._bar.refresh()

    def _finish(self) -> None:
        """The compile ended: close its bar, say so, give the watched bars their ETA back."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None
        outcome = self.background.outcome()
        if self.progress:
            if outcome is not None and outcome[0]:
                click.echo(self.done_text.format(s=f"{outcome[1]:.0f}"), err=True)
            else:
                click.echo("the background compile of the kernels did not finish; the "
                           "compiled engine compiles them when first needed", err=True)
        for bar in self._bars:
            _restart_rate(bar)
        self._bars.clear()
        self.status = "cached"

    def watch(self, bar: Any) -> None:
        """Hide ``bar``'s ETA while the kernels compile; restart its rate when they are
        ready (so its ETA never counts the compile)."""
        if self.status != "background" or bar is None or getattr(bar, "disable", False):
            return
        bar.__dict__["_it2track_format"] = bar.bar_format
        bar.bar_format = _COMPILING_FORMAT
        self._bars.append(bar)

    def close(self) -> None:
        """Stop following the compile (it goes on in its process if not finished)."""
        self._done.set()
        if self._thread is not None:
            self._thread.join()
        if self.status == "background" and not self.background.running():
            self._finish()
        if self.status == "background":
            if self._bar is not None:
                self._bar.close()
            if self.progress:
                left = max(0.0, self.background.estimate_s
                           - (time.monotonic() - self.background.started))
                click.echo(f"the kernels keep compiling in the background (about {left:.0f} s "
                           "more, once per install); later runs use them", err=True)
        elif (self.progress and self.background is not None
              and not getattr(self.background, "finished", lambda: True)()):
            click.echo("the fuzzy kernels keep compiling in the background (a few seconds, "
                       "once per install); later runs use them", err=True)


def _restart_rate(bar: Any) -> None:
    """Give ``bar`` back its format and forget the rate it measured (the numpy engine's)."""
    bar.bar_format = bar.__dict__.pop("_it2track_format", None)
    try:
        from tqdm.std import EMA

        bar._ema_dn, bar._ema_dt, bar._ema_miniters = (EMA(bar.smoothing) for _ in range(3))
    except (ImportError, AttributeError):  # another tqdm: its ETA adapts by itself
        pass
    bar.refresh()


class KernelStart:
    """What :func:`start_kernels` found and did: ``cached`` (numba's cache holds the kernels,
    or numba is not used), else the ``background`` compile it started (None: none could be,
    the kernels then compile inline) and the ``estimate`` of its duration, seconds."""

    def __init__(self, cached: bool, background: Any = None, estimate: float = 0.0) -> None:
        self.cached = cached
        self.background = background
        self.estimate = estimate


def start_kernels() -> KernelStart:
    """Look at numba's cache and, if it lacks the kernels, start their background compile now.

    A command calls this as soon as its inputs are checked (a first run's compile then
    overlaps the command's own preparation) and hands the result to :func:`kernel_stage`,
    which says and shows it.
    """
    from ..tracking import kernel_cache

    if kernel_cache.cached() is not False:
        return KernelStart(True)
    estimate = kernel_cache.estimate_seconds()
    return KernelStart(False, kernel_cache.start(), estimate)


@contextmanager
def kernel_stage(*, progress: bool, run_steps: float | None = None,
                 started: KernelStart | None = None) -> Iterator[KernelStage]:
    """Make sure the simulation kernels are compiled, once per install, without a silent wait.

    Parameters
    ----------
    progress : bool
        Print the stage line and the bar (on stderr); ``False``: silently.
    run_steps : float, optional
        The job's size (runs x steps; ``math.inf``: open-ended), if known. When the numpy
        engine would take longer over it than the closed loop's compile
        (:func:`~it2track.tracking.kernel_cache.numpy_seconds`), the job waits for the compiled
        loop instead of starting on the numpy engine, which would also slow the compile down.
    started : KernelStart, optional
        What :func:`start_kernels`, called earlier by the command, found and started
        (default: look now).

    Yields
    ------
    KernelStage
        Hand the command's progress bar to :meth:`KernelStage.watch`.
    """
    from ..tracking import kernel_cache

    started = started or start_kernels()
    if started.cached:
        yield KernelStage("cached", progress=progress)
        return
    estimate, background = started.estimate, started.background
    if background is None:  # compile here, now, with the same line and a bar
        if progress:
            click.echo(f"compiling the simulation kernels, once per install — about "
                       f"{estimate:.0f} s", err=True)
        stage = KernelStage("background", progress=progress,
                            background=_Inline(kernel_cache, estimate))
        stage._start_display()
        try:
            stage.background.run()
        finally:
            stage.close()
        yield KernelStage("inline", progress=progress)
        return
    wait = run_steps is not None and (
        kernel_cache.numpy_seconds(run_steps) > background.estimate_s)
    if progress:
        who = "" if background.process is not None else " (by another it2track command)"
        then = (f"this job waits for them (on the numpy engine it would take "
                f"{_duration(kernel_cache.numpy_seconds(run_steps))})" if wait and run_steps
                else "the numpy engine computes meanwhile (same numbers)")
        click.echo(f"compiling the simulation kernels, once per install — about "
                   f"{background.estimate_s:.0f} s, in the background{who}; {then}", err=True)
    stage = KernelStage("background", progress=progress, background=background)
    with kernel_cache.deferring(background.lock, wait=wait):
        stage._start_display()
        try:
            yield stage
        finally:
            stage.close()


def _duration(seconds: float) -> str:
    """``seconds`` for a message: ``"about 5 min"``, ``"about 40 s"``, ``"hours"``."""
    if seconds >= 3600.0:
        return "hours"
    return f"about {seconds / 60.0:.0f} min" if seconds >= 90.0 else f"about {seconds:.0f} s"


class _Inline:
    """The compile done in this process, with the interface of ``kernel_cache.Background``
    that :class:`KernelStage` follows."""

    def __init__(self, kernel_cache: Any, estimate_s: float) -> None:
        self._kc = kernel_cache
        self.estimate_s = estimate_s
        self.started = time.monotonic()
        self._result: tuple[bool, float] | None = None

    def run(self) -> None:
        self.started = time.monotonic()
        try:
            seconds = self._kc.compile_all()
            self._result = (True, seconds)
        except Exception:  # the first call compiles them again, and raises what it raises
            self._result = (False, time.monotonic() - self.started)

    def running(self) -> bool:
        return self._result is None

    def outcome(self) -> tuple[bool, float] | None:
        return self._result


@click.command("compile")
def compile_kernels() -> None:
    """Compile the simulation kernels into numba's cache now, once per install.

    Otherwise the first simulating command after installing compiles them (in the
    background, about 20 s of one core, which a first study partly waits for); after this
    one every command starts with them. Waits for a compile another command started
    rather than doing it twice. Nothing to do when the cache holds them, or when numba is
    not used (not installed, or IT2TRACK_ENGINE=numpy).
    """
    from ..tracking import kernel_cache

    state = kernel_cache.cached()
    if state is None:
        click.echo("nothing to compile: the numpy engine computes (numba is not installed, or "
                   "IT2TRACK_ENGINE=numpy)", err=True)
        return
    if state:
        click.echo("the simulation kernels are already compiled (numba's cache holds them)",
                   err=True)
        return
    t0 = time.monotonic()
    estimate = kernel_cache.estimate_seconds()
    background = kernel_cache.start()
    if background is None:  # no background process here: compile in this one
        with kernel_stage(progress=True, started=KernelStart(False, None, estimate)):
            pass
    else:
        who = "" if background.process is not None else " (started by another it2track command)"
        click.echo(f"compiling the simulation kernels, once per install{who} — about "
                   f"{background.estimate_s:.0f} s for the closed loop, a few more for the "
                   "fuzzy kernels", err=True)
        stage = KernelStage("background", progress=True, background=background)
        stage.done_text = "compiled the closed-loop kernel in {s} s; now the fuzzy kernels"
        stage._start_display()
        try:
            while not background.finished():
                time.sleep(0.2)
        finally:
            stage.close()
        outcome = background.outcome()
        if outcome is not None and not outcome[0]:
            try:  # again here, for its error
                kernel_cache.compile_all()
            except Exception as exc:
                raise click.ClickException(f"the simulation kernels failed to compile: "
                                           f"{type(exc).__name__}: {exc}") from exc
    if kernel_cache.cached() is not True:
        raise click.ClickException("the kernels are still not in numba's cache: numba could "
                                   "not write it (set NUMBA_CACHE_DIR to a writable folder) or "
                                   "the compile failed (run `it2track simulate` to see its "
                                   "error)")
    click.echo(f"the simulation kernels are compiled ({time.monotonic() - t0:.0f} s); every "
               "command loads them from numba's cache from now on", err=True)

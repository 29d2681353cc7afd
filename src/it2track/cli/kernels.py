"""The first run of a simulating command: say that the kernels compile, once, and show it.

:func:`kernel_stage` wraps the work of ``simulate``, ``reproduce``, ``sweep`` and ``optimize``.
When numba's cache already holds the kernels it loads them and says nothing. Otherwise it
prints one stage line (``compiling the simulation kernels, once per install — about N s``),
starts the compile in a background process (:mod:`it2track.tracking.kernel_cache`), shows a
bar of its progress while the command computes on the numpy engine (same bits), and says when
the compiled engine takes over. A progress bar of the command handed to
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

__all__ = ["KernelStage", "kernel_stage"]

#: The simulating bar's format while the kernels compile: no rate and no ETA.
_COMPILING_FORMAT = ("{desc}: {percentage:3.0f}%|{bar}| {n_fmt}/{total_fmt} [{elapsed}, "
                     "ETA once the kernels are compiled]")


class KernelStage:
    """What :func:`kernel_stage` found: ``status`` is ``"cached"`` (loaded, or numba not
    used), ``"background"`` (compiling in another process, numpy engine meanwhile) or
    ``"inline"`` (compiled here, before the work)."""

    def __init__(self, status: str, *, progress: bool, background: Any = None) -> None:
        self.status = status
        self.progress = progress
        self.background = background
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
                click.echo(f"compiled the simulation kernels in {outcome[1]:.0f} s: the "
                           "compiled engine takes over", err=True)
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


def _restart_rate(bar: Any) -> None:
    """Give ``bar`` back its format and forget the rate it measured (the numpy engine's)."""
    bar.bar_format = bar.__dict__.pop("_it2track_format", None)
    try:
        from tqdm.std import EMA

        bar._ema_dn, bar._ema_dt, bar._ema_miniters = (EMA(bar.smoothing) for _ in range(3))
    except (ImportError, AttributeError):  # another tqdm: its ETA adapts by itself
        pass
    bar.refresh()


@contextmanager
def kernel_stage(*, progress: bool) -> Iterator[KernelStage]:
    """Make sure the simulation kernels are compiled, once per install, without a silent wait.

    Parameters
    ----------
    progress : bool
        Print the stage line and the bar (on stderr); ``False``: silently.

    Yields
    ------
    KernelStage
        Hand the command's progress bar to :meth:`KernelStage.watch`.
    """
    from ..tracking import kernel_cache

    if kernel_cache.cached() is not False:
        yield KernelStage("cached", progress=progress)
        return
    estimate = kernel_cache.estimate_seconds()
    background = kernel_cache.start()
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
    if progress:
        who = "" if background.process is not None else " (by another it2track command)"
        click.echo(f"compiling the simulation kernels, once per install — about "
                   f"{background.estimate_s:.0f} s, in the background{who}; the numpy engine "
                   "computes meanwhile (same numbers)", err=True)
    stage = KernelStage("background", progress=progress, background=background)
    with kernel_cache.deferring(background.lock):
        stage._start_display()
        try:
            yield stage
        finally:
            stage.close()


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

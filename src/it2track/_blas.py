"""Tiny dense linear algebra without OpenBLAS's helper threads.

OpenBLAS hands part of even a 5x5 LAPACK solve to its helper threads (its row interchanges,
``laswp``, have no size threshold), and ``scipy.linalg.expm`` solves one per call. On a
machine whose cores are all busy -- ``it2track reproduce`` runs its figure workers beside the
simulation -- every such hand-over waits for a time slice: a robot plant's ~30 exponentials of
5x5 matrices took 0.3-0.5 s there instead of 2 ms. :func:`single_threaded_blas` runs a block
with OpenBLAS on the calling thread alone. The numbers are the same bits (the helper threads
only split the columns a row interchange moves); only the waiting goes.

OpenBLAS is found among the shared libraries loaded in this process (Linux ``/proc/self/maps``:
numpy's and scipy's wheels each bundle one); elsewhere, or with another BLAS, the block runs
unchanged. Standard library only.
"""

from __future__ import annotations

import ctypes
import functools
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, cast

__all__ = ["blas_thread_counts", "single_threaded_blas"]

#: OpenBLAS's "set the thread count, return the previous one" (0.3.27 and later), under the
#: names of the plain library and of the scipy-openblas wheels (32- and 64-bit integers).
_SETTERS = ("openblas_set_num_threads_local", "scipy_openblas_set_num_threads_local",
            "scipy_openblas_set_num_threads_local64_")
_GETTERS = ("openblas_get_num_threads", "scipy_openblas_get_num_threads",
            "scipy_openblas_get_num_threads64_")
_lock = threading.RLock()


def _openblas_paths(maps: str) -> list[str]:
    """Paths of the OpenBLAS libraries in the text of ``/proc/PID/maps``, each once."""
    paths: list[str] = []
    for line in maps.splitlines():
        parts = line.split(maxsplit=5)  # address perms offset device inode path
        path = parts[5] if len(parts) == 6 else ""
        if "openblas" in Path(path).name.lower() and path not in paths:
            paths.append(path)
    return paths


def _function(lib: ctypes.CDLL, names: tuple[str, ...], *args: Any) -> Callable[..., int] | None:
    """The first of ``names`` that ``lib`` exports, taking ``args`` (ctypes types), or None."""
    for name in names:
        fn = getattr(lib, name, None)
        if fn is not None:
            fn.restype = ctypes.c_int
            fn.argtypes = list(args)
            return cast(Callable[..., int], fn)
    return None


@functools.cache
def _libraries() -> tuple[tuple[Callable[[int], int], Callable[[], int]], ...]:
    """(setter, getter) of each OpenBLAS loaded at the first call (numpy's and scipy.linalg's
    are, once ``scipy.linalg`` is imported: import it before calling)."""
    try:
        maps = Path("/proc/self/maps").read_text(encoding="utf-8", errors="replace")
    except OSError:  # not Linux
        return ()
    found = []
    for path in _openblas_paths(maps):
        try:
            lib = ctypes.CDLL(path)  # already loaded: the same handle, nothing runs
        except OSError:
            continue
        setter, getter = _function(lib, _SETTERS, ctypes.c_int), _function(lib, _GETTERS)
        if setter is not None and getter is not None:
            found.append((setter, getter))
    return tuple(found)


def blas_thread_counts() -> list[int]:
    """The thread count of each OpenBLAS found (empty if none)."""
    return [getter() for _, getter in _libraries()]


@contextmanager
def single_threaded_blas() -> Iterator[None]:
    """Run the block with every OpenBLAS of this process on one thread; the previous counts
    come back after it. For small matrices only (a large product would lose its threads).
    The count is the library's, not the thread's: blocks of several threads take turns."""
    with _lock:
        libs = _libraries()
        previous = [setter(1) for setter, _ in libs]
        try:
            yield
        finally:
            for (setter, _), count in zip(libs, previous, strict=True):
                setter(count)

"""Compile generated C with the host's C compiler into a shared library and call it (ctypes).

The library holds the controller and a batch shim, ``<prefix>_batch(n, x, u, yl, yr,
status)``, which calls ``<prefix>_eval`` once per row of ``x``: one ctypes call evaluates a
whole batch. Builds are cached by the SHA-256 of the sources and flags.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import secrets
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .generate import CCode, RealType
from .tools import require, run_tool

__all__ = ["HOST_FLAGS", "HostLibrary", "build_host_library"]

#: Flags of the host build: strict C99, warnings as errors, and IEEE evaluation in the declared
#: type (no FMA contraction, no excess precision), so a float build rounds like the AVR's.
HOST_FLAGS: tuple[str, ...] = (
    "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O2",
    "-ffp-contract=off", "-fexcess-precision=standard",
)

_SHIM = """\
#include "{header}"

int {p}_batch(long n, const {p}_real *x, {p}_real *u, {p}_real *yl, {p}_real *yr, int *status);

int {p}_batch(long n, const {p}_real *x, {p}_real *u, {p}_real *yl, {p}_real *yr, int *status)
{{
    long j;
    int bad = 0;
    for (j = 0; j < n; ++j) {{
        status[j] = {p}_eval(x + j * {P}_N_IN, u + j, yl + j, yr + j);
        bad += status[j] != {P}_OK;
    }}
    return bad;
}}
"""


def build_host_library(code: CCode, build_dir: str | os.PathLike[str],
                       *, flags: tuple[str, ...] = HOST_FLAGS) -> Path:
    """Compile ``code`` (plus the batch shim) into a shared library under ``build_dir``.

    A library built before from the same sources and flags is reused.

    Raises
    ------
    ToolMissingError
        Without ``gcc`` (Debian package ``gcc``).
    BuildError
        If the compiler fails (the generated code must compile warning-free).
    """
    require(["gcc"])
    shim = _SHIM.format(header=code.header_name, p=code.prefix, P=code.prefix.upper())
    key = hashlib.sha256((code.digest() + shim + " ".join(flags)).encode()).hexdigest()[:20]
    root = Path(build_dir) / f"host-{code.prefix}-{key}"
    lib = root / f"lib{code.prefix}.so"
    if lib.exists():
        return lib
    tmp = Path(build_dir) / f".host-{key}-{secrets.token_hex(4)}"
    tmp.mkdir(parents=True)
    for name, text in code.files().items():
        (tmp / name).write_text(text)
    (tmp / "shim.c").write_text(shim)
    run_tool(["gcc", *flags, "-fPIC", "-shared", "-o", str(tmp / lib.name),
              str(tmp / code.source_name), str(tmp / "shim.c"), "-lm"], cwd=tmp)
    try:
        os.replace(tmp, root)
    except OSError:  # another process built the same library meanwhile
        if not lib.exists():
            raise
    return lib


@dataclass(frozen=True, eq=False)
class HostLibrary:
    """A compiled controller loaded with ctypes.

    Parameters
    ----------
    code : CCode
        The generated code (its prefix and real type select the symbols and dtype).
    path : Path
        The shared library from :func:`build_host_library`.
    """

    code: CCode
    path: Path
    _fn: Any = field(init=False, repr=False)

    def __post_init__(self) -> None:
        lib = ctypes.CDLL(str(self.path))
        fn = getattr(lib, f"{self.code.prefix}_batch")
        real = np.ctypeslib.ndpointer(self.dtype, flags="C_CONTIGUOUS")
        fn.argtypes = [ctypes.c_long, real, real, real, real,
                       np.ctypeslib.ndpointer(np.intc, flags="C_CONTIGUOUS")]
        fn.restype = ctypes.c_int
        object.__setattr__(self, "_fn", fn)

    @property
    def dtype(self) -> type[np.generic]:
        """The numpy type of ``<prefix>_real`` (float32, float64, or the fixed-point integer)."""
        if self.code.fixed is not None:
            return self.code.fixed.dtype
        return np.float32 if self.code.real is RealType.FLOAT else np.float64

    def evaluate_raw(self, x: ArrayLike) -> tuple[NDArray[Any], NDArray[Any], NDArray[Any],
                                                  NDArray[np.intc]]:
        """Evaluate a batch in the library's own type: ``x`` must already be of
        :attr:`dtype` (for a fixed-point build the integers of its Q formats), and ``u, yl,
        yr`` come back in it, exactly as the C returned them."""
        arr = np.ascontiguousarray(x)
        if arr.dtype != np.dtype(self.dtype):
            raise ValueError(f"x must be of dtype {np.dtype(self.dtype).name}, got "
                             f"{arr.dtype.name}")
        if arr.ndim != 2 or arr.shape[1] != self.code.n_inputs:
            raise ValueError(f"x must have shape (N, {self.code.n_inputs}), got {arr.shape}")
        n = arr.shape[0]
        u = np.empty(n, dtype=self.dtype)
        yl = np.empty(n, dtype=self.dtype)
        yr = np.empty(n, dtype=self.dtype)
        status = np.empty(n, dtype=np.intc)
        if n:
            self._fn(n, arr, u, yl, yr, status)
        return u, yl, yr, status

    def evaluate(self, x: ArrayLike) -> tuple[NDArray[Any], NDArray[Any], NDArray[Any],
                                              NDArray[np.intc]]:
        """Evaluate a batch.

        Parameters
        ----------
        x : array_like, shape (N, n_inputs)
            Real inputs: converted to the library's real type (float32 or float64) first, or,
            for a fixed-point build, to its integers (:meth:`FixedFormat.to_int
            <it2track.codegen.fixedpoint.FixedFormat.to_int>`).

        Returns
        -------
        u, yl, yr : ndarray, shape (N,)
            In the library's real type; for a fixed-point build, the integers converted to
            float64 values.
        status : ndarray of intc, shape (N,)
            The status of each call (0 = OK).
        """
        fmt = self.code.fixed
        if fmt is not None:
            u, yl, yr, status = self.evaluate_raw(fmt.to_int(x))
            return fmt.to_real(u), fmt.to_real(yl), fmt.to_real(yr), status
        arr = np.asarray(x, dtype=self.dtype)
        if arr.ndim != 2 or arr.shape[1] != self.code.n_inputs:
            raise ValueError(f"x must have shape (N, {self.code.n_inputs}), got {arr.shape}")
        return self.evaluate_raw(arr)

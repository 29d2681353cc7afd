"""Software in the loop: a heading controller whose fuzzy system is the generated C.

:class:`CHeadingController` is a plain :class:`~it2track.tracking.HeadingController`: the
closed loop (:func:`~it2track.tracking.simulate`, :func:`~it2track.tracking.simulate_metrics`)
calls its :meth:`~CHeadingController.output` with a batch of runs, and it evaluates them with
one ctypes call into the compiled controller (built with the host's C compiler on first use, in
each process, and cached on disk by content).
"""

from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..fuzzy import (
    ConvergenceError,
    IT2Mamdani,
    IT2Sugeno,
    T1Mamdani,
    T1Sugeno,
    ZeroFiringError,
)
from ..tracking import HeadingController
from .generate import CCode, RealType, generate_c
from .host import HostLibrary, build_host_library

__all__ = ["CHeadingController", "default_build_dir", "raise_for_status"]

FloatArray = NDArray[np.float64]

_LIBS: dict[tuple[str, str], HostLibrary] = {}


def default_build_dir() -> Path:
    """Per-user cache of host builds: ``$IT2TRACK_BUILD_DIR`` or a folder in the temp dir."""
    env = os.environ.get("IT2TRACK_BUILD_DIR")
    if env:
        return Path(env)
    uid = os.getuid() if hasattr(os, "getuid") else 0
    return Path(tempfile.gettempdir()) / f"it2track-c-builds-{uid}"


@dataclass(frozen=True, kw_only=True, eq=False)
class CHeadingController(HeadingController):
    """Heading controller ``u = C(clip(ke e), clip(kde de))`` evaluated by compiled C.

    Parameters
    ----------
    code : CCode
        Generated code for a two-input system (error, change of error), e.g. from
        :meth:`from_system`.
    ke, kde : float
        Input gains, applied in double precision before the call (as
        :class:`~it2track.tracking.FuzzyHeadingController` does).
    name : str
        Label used in results (default ``"C <prefix> (<real>)"``).
    build_dir : str or None
        Where host builds are cached (default :func:`default_build_dir`).

    Raises
    ------
    ZeroFiringError, ConvergenceError, ValueError
        From :meth:`output`, where the C returns the matching error status (as the Python
        system would raise).
    """

    code: CCode
    ke: float = 1.0
    kde: float = 1.0
    name: str = ""
    build_dir: str | None = None
    _lib: Any = field(init=False, repr=False, default=None)

    def __post_init__(self) -> None:
        if not isinstance(self.code, CCode):
            raise ValueError(f"code={self.code!r} must be a CCode (see generate_c)")
        if self.code.n_inputs != 2:
            raise ValueError(f"a heading controller needs 2 inputs (e, de); the code has "
                             f"{self.code.n_inputs}")
        for key, value in (("ke", self.ke), ("kde", self.kde)):
            if isinstance(value, bool) or not isinstance(value, int | float) \
                    or not math.isfinite(value):
                raise ValueError(f"CHeadingController: {key}={value!r} must be a finite number")
        if not self.name:
            object.__setattr__(self, "name", f"C {self.code.prefix} ({self.code.real.value})")

    @classmethod
    def from_system(cls, fls: IT2Sugeno | T1Sugeno | IT2Mamdani | T1Mamdani, *,
                    real: RealType = RealType.DOUBLE,
                    ke: float = 1.0, kde: float = 1.0, name: str = "",
                    build_dir: str | None = None) -> CHeadingController:
        """Generate C for ``fls`` (see :func:`~it2track.codegen.generate_c`) and wrap it."""
        return cls(code=generate_c(fls, real=real), ke=ke, kde=kde, name=name,
                   build_dir=build_dir)

    def library(self) -> HostLibrary:
        """The compiled controller (built on first use in this process)."""
        lib = self._lib
        if lib is None:
            where = Path(self.build_dir) if self.build_dir else default_build_dir()
            key = (self.code.digest(), os.fspath(where))
            lib = _LIBS.get(key)
            if lib is None:
                where.mkdir(parents=True, exist_ok=True)
                lib = HostLibrary(self.code, build_host_library(self.code, where))
                _LIBS[key] = lib
            object.__setattr__(self, "_lib", lib)
        return lib

    def __getstate__(self) -> dict[str, Any]:
        state = dict(self.__dict__)
        state["_lib"] = None  # a ctypes handle does not cross processes; rebuilt on demand
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)

    def output(self, e: FloatArray, de: FloatArray, state: FloatArray) -> FloatArray:
        x = np.empty((e.shape[0], 2))
        np.multiply(e, self.ke, out=x[:, 0]) if self.ke != 1.0 else np.copyto(x[:, 0], e)
        np.multiply(de, self.kde, out=x[:, 1]) if self.kde != 1.0 else np.copyto(x[:, 1], de)
        u, _, _, status = self.library().evaluate(x)
        raise_for_status(self.name, x, status)
        return u.astype(np.float64)


def raise_for_status(name: str, x: NDArray[Any], status: NDArray[Any]) -> None:
    """Raise what the Python system would for the first error status of a batch of calls.

    Parameters
    ----------
    name : str
        The controller's name, for the message.
    x : ndarray, shape (N, 2)
        The inputs ``(e, de)`` of the calls.
    status : ndarray of int, shape (N,)
        The statuses the C returned (0 = OK).

    Raises
    ------
    ValueError
        Status 1 (a NaN or inf input).
    ConvergenceError
        Status 3 (the iterative type reducer did not converge).
    ZeroFiringError
        Status 2 or 4 (no rule fires; zero lower firing).
    """
    if not status.any():
        return
    j = int(np.flatnonzero(status)[0])
    point = f"(e={x[j, 0]:.6g}, de={x[j, 1]:.6g})"
    code = int(status[j])
    if code == 1:
        raise ValueError(f"{name}: input {point} is NaN or inf")
    if code == 3:
        raise ConvergenceError(f"{name}: the type reducer did not converge at {point}")
    raise ZeroFiringError(f"{name}: no output at {point} (status {code}: "
                          f"{'no rule fires' if code == 2 else 'zero lower firing'})")

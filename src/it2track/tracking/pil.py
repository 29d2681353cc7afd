"""Processor in the loop: a heading controller whose every step runs on a simulated ATmega328P.

:class:`PilHeadingController` is a :class:`~it2track.tracking.HeadingController` like any
other: the closed loop (:func:`~it2track.tracking.simulate`,
:func:`~it2track.tracking.simulate_metrics`) calls it once per control period with a batch of
runs, and it evaluates them with the generated C (:func:`~it2track.codegen.generate_c`)
executing on the cycle-accurate simulated MCU (16 MHz, :class:`~it2track.codegen.pil.AvrInTheLoop`,
embedded through libsimavr). The inputs reach the MCU as the controller sees them: ``ke e`` and
``kde de`` computed in double on the host (the sensor side), then rounded to float32 (or
converted to the q15 build's integers); the C clips them to its universes.

Every call's CPU cycles come back with the output. The **latency model** decides when the
output reaches the motors:

``none``
    at ``t_k``, as every host loop assumes (computation takes no time);
``measured``
    after the call's measured cycles at 16 MHz: for that first part of the period the motors
    keep the previous period's voltages (0 V before the first output), the robot is advanced
    exactly over both parts (:class:`~it2track.plant.switched.SwitchedDrive`);
``period``
    at ``t_(k+1)``: one full period late, the usual discrete-time model of a controller that
    computes during the period and writes its output at the next tick.

Under ``measured`` and ``period`` a call longer than the control period is an overrun and an
error. The trace records ``cycles`` (per step) and ``latency`` (the delay applied, s).
"""

from __future__ import annotations

import enum
import math
import os
import threading
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..codegen import CCode, RealType, generate_c
from ..codegen.controller import default_build_dir, raise_for_status
from ..codegen.mcu import AVR_CLOCK_HZ
from ..codegen.pil import AvrInTheLoop
from ..fuzzy import IT2Sugeno, T1Sugeno
from .controllers import HeadingController

__all__ = ["Latency", "PilHeadingController"]

FloatArray = NDArray[np.float64]


class Latency(enum.Enum):
    """When a processor-in-the-loop output reaches the motors (see the module docstring)."""

    NONE = "none"
    MEASURED = "measured"
    PERIOD = "period"


@dataclass(frozen=True, kw_only=True, eq=False)
class PilHeadingController(HeadingController):
    """Heading controller ``u = C(clip(ke e), clip(kde de))`` executed on the simulated
    ATmega328P, one call per run and period.

    Parameters
    ----------
    code : CCode
        Generated code for a two-input system (error, change of error), e.g. from
        :meth:`from_system`. A DOUBLE build computes in float on the AVR (avr-gcc's double is
        32-bit).
    ke, kde : float
        Input gains, applied in double precision before the call.
    latency : Latency or str
        ``"none"``, ``"measured"`` or ``"period"`` (default ``"none"``).
    threads : int
        Simulated MCUs stepping the parts of a batch in parallel (>= 1; results do not depend
        on it).
    name : str
        Label used in results (default ``"PIL <prefix> (<real>, latency <model>)"``).
    build_dir : str or None
        Where the firmware and the libsimavr shim are built and cached (default
        :func:`~it2track.codegen.controller.default_build_dir`).

    Raises
    ------
    ValueError
        For a bad parameter (naming it); from :meth:`output`, for an overrun (a call longer
        than the control period under ``measured`` or ``period``) or a NaN input.
    ZeroFiringError, ConvergenceError
        From :meth:`output`, where the C returns the matching error status.
    ToolMissingError
        On the first :meth:`output` without gcc, libsimavr-dev, gcc-avr, avr-libc or
        binutils-avr.
    """

    code: CCode
    ke: float = 1.0
    kde: float = 1.0
    latency: Latency = Latency.NONE
    threads: int = 1
    name: str = ""
    build_dir: str | None = None
    _mcu: Any = field(init=False, repr=False, default=None)
    _lock: Any = field(init=False, repr=False, default=None)

    trace_series = ("cycles", "latency")

    def __post_init__(self) -> None:
        if not isinstance(self.code, CCode):
            raise ValueError(f"code={self.code!r} must be a CCode (see generate_c)")
        if self.code.n_inputs != 2:
            raise ValueError(f"a heading controller needs 2 inputs (e, de); the code has "
                             f"{self.code.n_inputs}")
        for key, value in (("ke", self.ke), ("kde", self.kde)):
            if isinstance(value, bool) or not isinstance(value, int | float) \
                    or not math.isfinite(value):
                raise ValueError(f"PilHeadingController: {key}={value!r} must be a finite "
                                 "number")
        latency = self.latency
        if not isinstance(latency, Latency):
            try:
                latency = Latency(latency)
            except ValueError:
                raise ValueError(f"PilHeadingController: latency={self.latency!r} must be one "
                                 f"of {[m.value for m in Latency]}") from None
            object.__setattr__(self, "latency", latency)
        t = self.threads
        if isinstance(t, bool) or not isinstance(t, int) or t < 1:
            raise ValueError(f"PilHeadingController: threads={t!r} must be a positive integer")
        if not self.name:
            object.__setattr__(self, "name", f"PIL {self.code.prefix} ({self.code.real.value}, "
                                             f"latency {latency.value})")
        object.__setattr__(self, "_lock", threading.Lock())

    @classmethod
    def from_system(cls, fls: IT2Sugeno | T1Sugeno, *, real: RealType = RealType.FLOAT,
                    ke: float = 1.0, kde: float = 1.0, latency: Latency | str = Latency.NONE,
                    threads: int = 1, name: str = "",
                    build_dir: str | None = None) -> PilHeadingController:
        """Generate C for ``fls`` (:func:`~it2track.codegen.generate_c`, default float) and
        run it in the loop.

        Parameters
        ----------
        fls : IT2Sugeno or T1Sugeno
            A two-input Sugeno system.
        real : RealType
            Arithmetic of the generated code.
        ke, kde, latency, threads, name, build_dir
            As for the class.

        Returns
        -------
        PilHeadingController
        """
        return cls(code=generate_c(fls, real=real), ke=ke, kde=kde,
                   latency=latency,  # type: ignore[arg-type]  # converted on construction
                   threads=threads, name=name, build_dir=build_dir)

    @property
    def delays_output(self) -> bool:  # type: ignore[override]
        """True unless the latency model is ``none``."""
        return self.latency is not Latency.NONE

    def mcu(self) -> AvrInTheLoop:
        """The simulated MCUs (built and started on first use in this process)."""
        with self._lock:
            if self._mcu is None:
                where = self.build_dir or os.fspath(default_build_dir())
                object.__setattr__(self, "_mcu", AvrInTheLoop(self.code, threads=self.threads,
                                                              build_dir=where))
            return self._mcu

    def __getstate__(self) -> dict[str, Any]:
        state = dict(self.__dict__)
        state["_mcu"] = None  # simulated MCUs do not cross processes; restarted on demand
        state["_lock"] = None
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        object.__setattr__(self, "_lock", threading.Lock())

    def initial_state(self, n: int, ts: float) -> FloatArray:
        # Rows: delay of the last output (s), its cycles, the period ts (constant).
        state = np.zeros((3, n))
        state[2] = ts
        return state

    def output(self, e: FloatArray, de: FloatArray, state: FloatArray) -> FloatArray:
        x = np.empty((e.shape[0], 2))
        np.multiply(e, self.ke, out=x[:, 0]) if self.ke != 1.0 else np.copyto(x[:, 0], e)
        np.multiply(de, self.kde, out=x[:, 1]) if self.kde != 1.0 else np.copyto(x[:, 1], de)
        if not np.isfinite(x).all():
            raise_for_status(self.name, x, np.asarray(~np.isfinite(x).all(axis=1), dtype=np.intc))
        u, raw = self.mcu().step(x)
        raise_for_status(self.name, x, raw.status)
        cycles = raw.cycles.astype(np.float64)
        state[1] = cycles
        if self.latency is Latency.NONE:
            state[0] = 0.0
            return u
        seconds = cycles / AVR_CLOCK_HZ
        over = seconds > state[2]
        if over.any():
            j = int(np.flatnonzero(over)[0])
            raise ValueError(
                f"{self.name}: a call took {int(cycles[j])} cycles = {1e3 * seconds[j]:.3f} ms "
                f"at {AVR_CLOCK_HZ / 1e6:g} MHz, longer than the control period "
                f"ts = {1e3 * state[2, j]:g} ms (an overrun: lengthen ts or use a faster "
                "reducer)")
        if self.latency is Latency.MEASURED:
            state[0] = seconds
        else:
            state[0] = state[2]
        return u

    def output_delay(self, state: FloatArray) -> FloatArray:
        return state[0]

    def step_series(self, state: FloatArray) -> dict[str, FloatArray]:
        return {"cycles": state[1], "latency": state[0]}

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

For Monte Carlo studies too large for the simulated MCU, :class:`TabledLatencyController` runs
the same C compiled for the host (whose float32 and q15 results equal the AVR's bit for bit)
with a latency function of the inputs, a :class:`LatencyTable` of cycles the simulated MCU
measured on a grid.
"""

from __future__ import annotations

import enum
import math
import os
import threading
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..codegen import CCode, CHeadingController, RealType, generate_c
from ..codegen.controller import default_build_dir, raise_for_status
from ..codegen.mcu import AVR_CLOCK_HZ
from ..codegen.pil import AvrInTheLoop
from ..fuzzy import IT2Sugeno, T1Sugeno
from .controllers import HeadingController

__all__ = ["Latency", "LatencyTable", "PilHeadingController", "TabledLatencyController"]

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


@dataclass(frozen=True, kw_only=True, eq=False)
class LatencyTable:
    """A latency function of the inputs: the CPU cycles of one controller call, measured on
    the simulated MCU on a grid of its input box and looked up at the nearest grid point.

    The cycles of a call depend on its inputs (data-dependent software-float timings, the
    reducers' input-dependent work), so a run's latency varies from step to step. Measuring
    every step on the simulated MCU is processor in the loop itself (:class:`PilHeadingController`);
    this table lets the host-compiled C carry a large Monte Carlo with a latency close to the
    chip's (:class:`TabledLatencyController`).

    Parameters
    ----------
    lo, hi : tuple of float
        Per input, the grid's first and last point (the universe); ``lo < hi``.
    cycles : ndarray of int, shape (n_0, n_1, ...)
        Cycles at the grid points ``lo_i + (hi_i - lo_i) j / (n_i - 1)``; each ``n_i >= 2``.

    Raises
    ------
    ValueError
        If the shapes disagree, a bound is not finite or ``lo >= hi``, or a count is negative.
    """

    lo: tuple[float, ...]
    hi: tuple[float, ...]
    cycles: NDArray[np.int64]

    def __post_init__(self) -> None:
        cycles = np.asarray(self.cycles)
        if cycles.dtype.kind not in "iu":
            raise ValueError(f"LatencyTable: cycles must be integers, got {cycles.dtype}")
        cycles = cycles.astype(np.int64)
        lo = tuple(float(v) for v in self.lo)
        hi = tuple(float(v) for v in self.hi)
        if not (len(lo) == len(hi) == cycles.ndim) or any(n < 2 for n in cycles.shape):
            raise ValueError(f"LatencyTable: lo, hi ({len(lo)}, {len(hi)} values) and the "
                             f"cycles' shape {cycles.shape} must agree, >= 2 points per input")
        if not all(math.isfinite(a) and math.isfinite(b) and a < b for a, b in zip(lo, hi,
                                                                                  strict=True)):
            raise ValueError(f"LatencyTable: lo={lo} and hi={hi} must be finite with lo < hi")
        if (cycles < 0).any():
            raise ValueError("LatencyTable: cycles must be >= 0")
        cycles.setflags(write=False)
        object.__setattr__(self, "lo", lo)
        object.__setattr__(self, "hi", hi)
        object.__setattr__(self, "cycles", cycles)

    @classmethod
    def measure(cls, code: CCode, universes: Sequence[tuple[float, float]], *,
                points: int = 129, threads: int = 1,
                build_dir: str | None = None) -> LatencyTable:
        """Measure ``code``'s cycles on a ``points``-per-input grid of ``universes`` on the
        simulated MCU (:class:`~it2track.codegen.pil.AvrInTheLoop`).

        Parameters
        ----------
        code : CCode
            Generated code.
        universes : sequence of (float, float)
            Per input, the box to tabulate (the inputs are clipped to it before the lookup).
        points : int
            Grid points per input (>= 2).
        threads : int
            Simulated MCUs measuring in parallel.
        build_dir : str or None
            Build cache (default :func:`~it2track.codegen.controller.default_build_dir`).

        Returns
        -------
        LatencyTable
        """
        if isinstance(points, bool) or not isinstance(points, int) or points < 2:
            raise ValueError(f"LatencyTable.measure: points={points!r} must be an integer >= 2")
        if len(universes) != code.n_inputs:
            raise ValueError(f"LatencyTable.measure: {len(universes)} universes for a "
                             f"{code.n_inputs}-input controller")
        axes = [np.linspace(float(a), float(b), points) for a, b in universes]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))
        where = build_dir or os.fspath(default_build_dir())
        with AvrInTheLoop(code, threads=threads, build_dir=where) as mcu:
            _, raw = mcu.step(grid)
        return cls(lo=tuple(a for a, _ in universes), hi=tuple(b for _, b in universes),
                   cycles=raw.cycles.reshape((points,) * len(axes)))

    def lookup(self, x: NDArray[np.float64]) -> NDArray[np.int64]:
        """Cycles at the grid point nearest to each row of ``x`` (clipped to the box).

        Parameters
        ----------
        x : ndarray, shape (N, n_inputs)
            Inputs in the controller's units.

        Returns
        -------
        ndarray of int64, shape (N,)
        """
        index = []
        for i, (a, b) in enumerate(zip(self.lo, self.hi, strict=True)):
            n = self.cycles.shape[i]
            pos = (np.clip(x[:, i], a, b) - a) * ((n - 1) / (b - a))
            index.append(np.clip(np.rint(pos), 0, n - 1).astype(np.intp))
        return self.cycles[tuple(index)]


@dataclass(frozen=True, kw_only=True, eq=False)
class TabledLatencyController(HeadingController):
    """The controller as the chip runs it, computed on the host: the host-compiled C (its
    float32 and q15 results equal the AVR's bit for bit) with the latency of a
    :class:`LatencyTable` at each step's inputs, applied as the ``measured`` model does.

    Parameters
    ----------
    host : CHeadingController
        The compiled controller (its gains apply to the lookup too).
    table : LatencyTable
        Cycles as a function of the inputs ``(ke e, kde de)``.
    name : str
        Label used in results (default: the host controller's name plus ``" + latency"``).

    Raises
    ------
    ValueError
        For a bad parameter; from :meth:`output`, if a tabulated call is longer than the
        control period (an overrun).
    """

    host: CHeadingController
    table: LatencyTable
    name: str = ""

    delays_output = True
    trace_series = ("cycles", "latency")

    def __post_init__(self) -> None:
        if not isinstance(self.host, CHeadingController):
            raise ValueError(f"TabledLatencyController: host={self.host!r} must be a "
                             "CHeadingController")
        if not isinstance(self.table, LatencyTable) or self.table.cycles.ndim != 2:
            raise ValueError("TabledLatencyController: table must be a two-input LatencyTable")
        if not self.name:
            object.__setattr__(self, "name", f"{self.host.name} + latency")

    def initial_state(self, n: int, ts: float) -> FloatArray:
        state = np.zeros((3, n))  # rows as PilHeadingController's: delay, cycles, ts
        state[2] = ts
        return state

    def output(self, e: FloatArray, de: FloatArray, state: FloatArray) -> FloatArray:
        u = self.host.output(e, de, state[:0])
        x = np.stack([e * self.host.ke, de * self.host.kde], axis=1)
        cycles = self.table.lookup(x).astype(np.float64)
        seconds = cycles / AVR_CLOCK_HZ
        over = seconds > state[2]
        if over.any():
            j = int(np.flatnonzero(over)[0])
            raise ValueError(f"{self.name}: a call takes {int(cycles[j])} cycles, longer than "
                             f"the control period ts = {1e3 * state[2, j]:g} ms (an overrun)")
        state[0] = seconds
        state[1] = cycles
        return u

    def output_delay(self, state: FloatArray) -> FloatArray:
        return state[0]

    def step_series(self, state: FloatArray) -> dict[str, FloatArray]:
        return {"cycles": state[1], "latency": state[0]}

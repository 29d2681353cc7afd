"""Processor in the loop: generated C running on a simulated ATmega328P, one call per step.

simavr is also a library (``libsimavr``, Debian ``libsimavr-dev``). :class:`AvrInTheLoop`
drives it in-process, without a simulator process per step (DESIGN.md sec. 11):

- the controller is cross-compiled once into a small firmware (``pil_firmware.c.j2``) that
  keeps an exchange block ``pil_io`` in SRAM (its address from ``avr-nm``), calls
  ``<prefix>_eval`` on the inputs found there, measures the call's CPU cycles with Timer1
  exactly as the cost benchmark does (:func:`~it2track.codegen.mcu.run_on_avr`: prescaler 1,
  compiler barriers, the empty measurement subtracted) and signals with a write to ``GPIOR0``;
- a C shim (``simavr_pil.c``), compiled with the host's ``gcc`` against ``libsimavr`` on first
  use and cached by content, loads the ELF once per simulated MCU; per call it writes the input
  bytes into the MCU's SRAM, runs the MCU until the signal and copies the outputs back. One
  ctypes call steps a whole batch; ctypes releases the GIL during it, so several MCUs (one per
  thread) step the parts of a batch in parallel.

The MCU runs only while it computes: the host plays the control period's timer. The generated
controller keeps no state between calls (no static data), so one MCU serves many runs in
turn, and a run's outputs and cycles depend on its own inputs only, whatever the batch or the
number of threads.

Inputs go in as the controller sees them: float32 for a float (or double: avr-gcc's double is
32-bit) build, the Q-format integers of :class:`~it2track.codegen.fixedpoint.FixedFormat` for a
q15 build.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import re
import secrets
import subprocess
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .generate import CCode
from .mcu import AVR_CLOCK_HZ, AVR_FLAGS, AVR_MCU, _env
from .tools import PIL_TOOLS, BuildError, require, run_tool

__all__ = ["PIL_TOOLS", "AvrInTheLoop", "PilFirmware", "PilStep", "build_pil_firmware",
           "build_pil_shim"]

#: The cycles one call may take before the shim gives up (4 s of the 16 MHz clock: a call that
#: long has hung; the slowest reducer takes ~30,000).
MAX_CALL_CYCLES = 64_000_000
_SHIM_SOURCE = Path(__file__).with_name("simavr_pil.c")
_SHIM_FLAGS = ("-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-fPIC", "-shared")
_ERRORS = {
    1: "simavr could not read the firmware ELF",
    2: "simavr could not create the MCU",
    3: "the firmware stopped (it slept with interrupts off or crashed)",
    4: f"the firmware did not signal within {MAX_CALL_CYCLES} cycles",
    5: "the firmware's exchange block or signal register is out of range",
}
_OPEN_LOCK = threading.Lock()  # libelf and simavr's MCU constructors share global state
_SHIMS: dict[str, Any] = {}


def _simavr_flags() -> tuple[list[str], list[str]]:
    """Compile and link flags for libsimavr: pkg-config's, else the Debian layout's (its .pc
    names libelf as a private requirement without Debian shipping libelf.pc)."""
    try:
        proc = subprocess.run(["pkg-config", "--cflags", "--libs", "simavr"],
                              capture_output=True, text=True, timeout=30, check=False)
    except (OSError, subprocess.TimeoutExpired):
        proc = None
    if proc is not None and proc.returncode == 0 and "-lsimavr" in proc.stdout:
        flags = proc.stdout.split()
        return [f for f in flags if not f.startswith("-l")], [f for f in flags
                                                               if f.startswith("-l")]
    return ["-I/usr/include/simavr"], ["-lsimavr"]


def build_pil_shim(build_dir: str | os.PathLike[str]) -> Path:
    """Compile the libsimavr shim (``simavr_pil.c``) into a shared library under
    ``build_dir`` (reused when built before from the same source and flags).

    Parameters
    ----------
    build_dir : path
        Cache folder (created if missing).

    Returns
    -------
    Path
        The shared library.

    Raises
    ------
    ToolMissingError
        Without ``gcc`` or ``libsimavr-dev``.
    BuildError
        If the compiler fails.
    """
    require(("gcc", "libsimavr"))
    source = _SHIM_SOURCE.read_text()
    cflags, libs = _simavr_flags()
    flags = [*_SHIM_FLAGS, *cflags]
    key = hashlib.sha256((source + " ".join(flags + libs)).encode()).hexdigest()[:20]
    root = Path(build_dir) / f"pil-shim-{key}"
    lib = root / "libit2pil.so"
    if lib.exists():
        return lib
    tmp = Path(build_dir) / f".pil-shim-{key}-{secrets.token_hex(4)}"
    tmp.mkdir(parents=True)
    (tmp / "simavr_pil.c").write_text(source)
    run_tool(["gcc", *flags, "-o", str(tmp / lib.name), "simavr_pil.c", *libs], cwd=tmp)
    try:
        os.replace(tmp, root)
    except OSError:  # another process built it meanwhile
        if not lib.exists():
            raise
    return lib


def _load_shim(path: Path) -> Any:
    key = os.fspath(path)
    shim = _SHIMS.get(key)
    if shim is None:
        shim = ctypes.CDLL(key)
        u8p = ctypes.POINTER(ctypes.c_uint8)
        shim.pil_open.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint32,
                                  ctypes.c_uint16, ctypes.c_uint16, ctypes.c_uint64,
                                  ctypes.POINTER(ctypes.c_void_p)]
        shim.pil_open.restype = ctypes.c_int
        shim.pil_step.argtypes = [ctypes.c_void_p, ctypes.c_long, u8p, ctypes.c_long,
                                  ctypes.c_long, u8p, ctypes.c_long, ctypes.c_long,
                                  ctypes.c_uint64]
        shim.pil_step.restype = ctypes.c_int
        shim.pil_close.argtypes = [ctypes.c_void_p]
        shim.pil_close.restype = None
        shim.pil_cycle.argtypes = [ctypes.c_void_p]
        shim.pil_cycle.restype = ctypes.c_uint64
        _SHIMS[key] = shim
    return shim


@dataclass(frozen=True, kw_only=True)
class PilFirmware:
    """A controller's PIL firmware (see :func:`build_pil_firmware`).

    Attributes
    ----------
    elf : Path
        The AVR executable.
    block : int
        SRAM address of the exchange block ``pil_io``.
    real_dtype : numpy.dtype
        The controller's ``<prefix>_real`` on the AVR, little-endian (float32 or int16).
    n_inputs : int
    """

    elf: Path
    block: int
    real_dtype: np.dtype[Any]
    n_inputs: int

    @property
    def out_dtype(self) -> np.dtype[Any]:
        """The block's outputs as they lie in SRAM (packed)."""
        r = self.real_dtype
        return np.dtype([("u", r), ("yl", r), ("yr", r), ("cycles", "<u4"), ("status", "u1")])

    @property
    def in_bytes(self) -> int:
        return self.n_inputs * self.real_dtype.itemsize


_GPIOR0 = 0x3E  # data-space address of GPIOR0 on the ATmega328P


def build_pil_firmware(code: CCode, build_dir: str | os.PathLike[str]) -> PilFirmware:
    """Cross-compile ``code`` into the PIL firmware (``avr-gcc -mmcu=atmega328p -Os``, the
    cost benchmark's flags) under ``build_dir``, reused when built before from the same code.

    Parameters
    ----------
    code : CCode
        Generated code (a DOUBLE build computes in float on the AVR, as avr-gcc's double is
        32-bit).
    build_dir : path
        Cache folder (created if missing).

    Returns
    -------
    PilFirmware

    Raises
    ------
    ToolMissingError
        Without avr-gcc, avr-libc or avr-nm.
    BuildError
        If compiling fails or the exchange block is not found.
    """
    require(("avr-gcc", "avr-libc", "avr-nm"))
    fmt = code.fixed
    main = _env().get_template("pil_firmware.c.j2").render(
        p=code.prefix, header_name=code.header_name, n_in=code.n_inputs)
    key = hashlib.sha256((code.digest() + main + " ".join(AVR_FLAGS)).encode()).hexdigest()[:20]
    root = Path(build_dir) / f"pil-{code.prefix}-{key}"
    elf = root / "pil.elf"
    if not elf.exists():
        tmp = Path(build_dir) / f".pil-{key}-{secrets.token_hex(4)}"
        tmp.mkdir(parents=True)
        for name, text in code.files().items():
            (tmp / name).write_text(text)
        (tmp / "pil.c").write_text(main)
        run_tool(["avr-gcc", *AVR_FLAGS, "-o", "pil.elf", "pil.c", code.source_name, "-lm"],
                 cwd=tmp)
        try:
            os.replace(tmp, root)
        except OSError:
            if not elf.exists():
                raise
    nm = run_tool(["avr-nm", str(elf)]).stdout
    found = re.search(r"^([0-9a-fA-F]+) [bBdD] pil_io$", nm, re.MULTILINE)
    if found is None:
        raise BuildError(f"{elf}: no symbol pil_io in avr-nm's output")
    block = int(found.group(1), 16) & 0xFFFF  # data addresses carry the 0x800000 offset
    real = np.dtype(fmt.dtype).newbyteorder("<") if fmt is not None else np.dtype("<f4")
    return PilFirmware(elf=elf, block=block, real_dtype=real, n_inputs=code.n_inputs)


@dataclass(frozen=True, kw_only=True)
class PilStep:
    """One call per input row on the simulated MCU (see :meth:`AvrInTheLoop.step_raw`).

    Attributes
    ----------
    u, yl, yr : ndarray, shape (N,)
        As the AVR returned them (float32, or the fixed-point integers).
    status : ndarray of uint8, shape (N,)
    cycles : ndarray of int64, shape (N,)
        CPU cycles of each ``<prefix>_eval`` call (Timer1, the empty measurement subtracted).
    """

    u: NDArray[Any]
    yl: NDArray[Any]
    yr: NDArray[Any]
    status: NDArray[np.uint8]
    cycles: NDArray[np.int64]


class AvrInTheLoop:
    """Generated C running on simulated ATmega328Ps (16 MHz), called once per input row.

    Parameters
    ----------
    code : CCode
        Generated code for the controller.
    threads : int
        Simulated MCUs, each stepped on its own thread (>= 1). A batch is split into this many
        contiguous parts; the results do not depend on it.
    build_dir : path
        Where the shim and the firmware are built and cached.

    Raises
    ------
    ToolMissingError
        Without gcc, libsimavr-dev, avr-gcc, avr-libc or binutils-avr.
    BuildError
        If a build fails or simavr cannot start the firmware.
    ValueError
        For ``threads`` not a positive integer.

    Notes
    -----
    Use as a context manager, or call :meth:`close` (the MCUs are also released when the
    object is garbage-collected).
    """

    def __init__(self, code: CCode, *, threads: int = 1,
                 build_dir: str | os.PathLike[str]) -> None:
        if isinstance(threads, bool) or not isinstance(threads, int) or threads < 1:
            raise ValueError(f"threads={threads!r} must be a positive integer")
        require(PIL_TOOLS)
        Path(build_dir).mkdir(parents=True, exist_ok=True)
        self.code = code
        self.firmware = build_pil_firmware(code, build_dir)
        self._shim = _load_shim(build_pil_shim(build_dir))
        self._mcus: list[int] = []
        self._pool: ThreadPoolExecutor | None = None
        try:
            for _ in range(threads):
                self._mcus.append(self._open())
        except BaseException:
            self.close()
            raise
        if threads > 1:
            self._pool = ThreadPoolExecutor(max_workers=threads,
                                            thread_name_prefix="it2track-pil")

    def _open(self) -> int:
        handle = ctypes.c_void_p()
        with _OPEN_LOCK:
            status = self._shim.pil_open(os.fsencode(self.firmware.elf), AVR_MCU.encode(),
                                         AVR_CLOCK_HZ, _GPIOR0, self.firmware.block,
                                         MAX_CALL_CYCLES, ctypes.byref(handle))
        if status != 0 or not handle.value:
            raise BuildError(f"{self.firmware.elf}: {_ERRORS.get(status, f'error {status}')}")
        return int(handle.value)

    @property
    def threads(self) -> int:
        """The number of simulated MCUs."""
        return len(self._mcus)

    def close(self) -> None:
        """Release the simulated MCUs (idempotent)."""
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None
        mcus, self._mcus = self._mcus, []
        for handle in mcus:
            self._shim.pil_close(handle)

    def __enter__(self) -> AvrInTheLoop:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:
        if getattr(self, "_mcus", None):
            self.close()

    def _run(self, handle: int, x: NDArray[Any], out: NDArray[Any]) -> int:
        fw = self.firmware
        n = x.shape[0]
        if n == 0:
            return 0
        u8p = ctypes.POINTER(ctypes.c_uint8)
        status: int = self._shim.pil_step(
            handle, n, x.ctypes.data_as(u8p), fw.in_bytes, 0, out.ctypes.data_as(u8p),
            fw.out_dtype.itemsize, fw.in_bytes, MAX_CALL_CYCLES)
        return status

    def step_raw(self, x: ArrayLike) -> PilStep:
        """Call the controller on the MCU once per row of ``x``, given in its own type.

        Parameters
        ----------
        x : array_like, shape (N, n_inputs)
            float32 for a float build, the Q-format integers (int16) for a q15 build: written
            to SRAM as they are.

        Returns
        -------
        PilStep

        Raises
        ------
        ValueError
            If ``x`` has the wrong shape or type.
        BuildError
            If the firmware stops or hangs.
        """
        fw = self.firmware
        arr = np.asarray(x)
        if arr.dtype != fw.real_dtype.newbyteorder("="):
            raise ValueError(f"x must be of dtype {fw.real_dtype.name}, got {arr.dtype.name}")
        if arr.ndim != 2 or arr.shape[1] != fw.n_inputs:
            raise ValueError(f"x must have shape (N, {fw.n_inputs}), got {arr.shape}")
        if not self._mcus:
            raise ValueError("the simulated MCUs have been closed")
        arr = np.ascontiguousarray(arr, dtype=fw.real_dtype)
        n = arr.shape[0]
        out = np.zeros(n, dtype=fw.out_dtype)
        parts = np.array_split(np.arange(n), len(self._mcus)) if n else []
        if self._pool is None or n < 2 * len(self._mcus):
            codes = [self._run(self._mcus[0], arr, out)]
        else:
            jobs = [self._pool.submit(self._run, h, arr[p[0]:p[-1] + 1], out[p[0]:p[-1] + 1])
                    for h, p in zip(self._mcus, parts, strict=True) if p.size]
            codes = [job.result() for job in jobs]
        bad = next((c for c in codes if c != 0), 0)
        if bad:
            raise BuildError(f"{fw.elf}: {_ERRORS.get(bad, f'error {bad}')}")
        native = fw.real_dtype.newbyteorder("=")
        return PilStep(u=out["u"].astype(native), yl=out["yl"].astype(native),
                       yr=out["yr"].astype(native), status=out["status"].copy(),
                       cycles=out["cycles"].astype(np.int64))

    def step(self, x: ArrayLike) -> tuple[NDArray[np.float64], PilStep]:
        """Call the controller on real inputs.

        Parameters
        ----------
        x : array_like, shape (N, n_inputs)
            Real inputs: rounded to float32, or converted to the fixed-point integers
            (:meth:`~it2track.codegen.fixedpoint.FixedFormat.to_int`).

        Returns
        -------
        u : ndarray of float64, shape (N,)
            The output as a real value.
        raw : PilStep
            Everything the MCU returned.
        """
        fmt = self.code.fixed
        arr = np.asarray(x, dtype=np.float64)
        if arr.ndim != 2 or arr.shape[1] != self.firmware.n_inputs:
            raise ValueError(f"x must have shape (N, {self.firmware.n_inputs}), got "
                             f"{arr.shape}")
        raw = self.step_raw(fmt.to_int(arr) if fmt is not None else arr.astype(np.float32))
        u = fmt.to_real(raw.u) if fmt is not None else raw.u.astype(np.float64)
        return np.asarray(u, dtype=np.float64), raw

    def cycle(self) -> int:
        """The first MCU's cycle counter (simulated cycles since reset, every call's
        measurement and exchange included)."""
        if not self._mcus:
            raise ValueError("the simulated MCUs have been closed")
        return int(self._shim.pil_cycle(self._mcus[0]))

"""What a controller step costs on a microcontroller: cycles on the simulated ATmega328P, bytes.

One implementation for the tests, the benchmark (``benchmarks/bench_mcu.py``), README and the
report:

- :func:`run_on_avr` cross-compiles generated C with ``avr-gcc -mmcu=atmega328p -Os`` (float
  arithmetic: avr-gcc's ``double`` is 32-bit too), runs it on the cycle-accurate ``simavr`` at
  16 MHz and returns, per input, the status, the outputs (bit-exact) and the CPU cycles of the
  call, counted by Timer1 at prescaler 1 between compiler barriers (DESIGN.md sec. 9).
  ``simavr`` executes instruction by instruction with each instruction's documented cycle
  count, so the counts are deterministic: the same program and inputs give the same cycles on
  every machine.
- :func:`avr_sizes` / :func:`arm_sizes`: flash and RAM of the controller object (``avr-size``,
  ``arm-none-eabi-size``; Cortex-M4F with ``-mcpu=cortex-m4 -mthumb -mfloat-abi=hard
  -mfpu=fpv4-sp-d16``), the stack frames (``-fstack-usage``) and the flash of a minimal AVR
  program around one call (with the start-up code and the software float routines it pulls in).
- :func:`~it2track.codegen.costs.measure_costs` (in :mod:`.costs`): all of it per type reducer
  and arithmetic for the paper's controller, as a :class:`~it2track.codegen.costs.CostTable`.

Tools missing raise :class:`~it2track.codegen.tools.ToolMissingError` naming the Debian
packages (``gcc-avr``, ``avr-libc``, ``simavr``, ``gcc-arm-none-eabi``,
``libnewlib-arm-none-eabi``).
"""

from __future__ import annotations

import os
import re
import secrets
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import jinja2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from .generate import CCode
from .tools import ARM_TOOLS, AVR_TOOLS, BuildError, require, run_tool

__all__ = [
    "ARM_FLAGS",
    "ARM_TOOLS",
    "AVR_CLOCK_HZ",
    "AVR_FLAGS",
    "AVR_TOOLS",
    "CONTROL_PERIOD_S",
    "AvrRun",
    "CodeSize",
    "arm_sizes",
    "avr_sizes",
    "cost_grid",
    "run_on_avr",
]

#: The ATmega328P of an Arduino Uno.
AVR_MCU = "atmega328p"
AVR_CLOCK_HZ = 16_000_000
#: The paper's control period (10 ms).
CONTROL_PERIOD_S = 0.01
AVR_FLAGS: tuple[str, ...] = (
    f"-mmcu={AVR_MCU}", "-Os", "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic",
)
#: ``-Wdouble-promotion``: a float build must not compute anything in double (the M4F's FPU is
#: single precision; double would be software).
ARM_FLAGS: tuple[str, ...] = (
    "-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard", "-mfpu=fpv4-sp-d16", "-Os", "-std=c99",
    "-Wall", "-Wextra", "-Werror", "-pedantic", "-Wdouble-promotion",
)
#: Inputs per simavr run (the input table lives in flash: 8 bytes per two-input point).
CHUNK = 1000

_LINE = re.compile(r"R ([0-9a-f]{4}) ([0-9a-f]) ([0-9a-f]{8}) ([0-9a-f]{8}) ([0-9a-f]{8}) "
                   r"([0-9a-f]{8})")
_ANSI = re.compile(r"\x1b\[[0-9;]*m")

FloatArray = NDArray[np.float64]


def _env() -> jinja2.Environment:
    return jinja2.Environment(
        loader=jinja2.PackageLoader("it2track.codegen", "templates"),
        undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True,
        keep_trailing_newline=True, autoescape=False)


def _workdir(build_dir: str | os.PathLike[str] | None, tag: str) -> Path:
    root = Path(build_dir) if build_dir is not None else Path(tempfile.gettempdir())
    root.mkdir(parents=True, exist_ok=True)
    path = root / f"{tag}-{secrets.token_hex(4)}"
    path.mkdir()
    return path


def _write_code(code: CCode, where: Path) -> None:
    for name, text in code.files().items():
        (where / name).write_text(text)


@dataclass(frozen=True, kw_only=True)
class AvrRun:
    """Results of :func:`run_on_avr`, one entry per input point.

    Attributes
    ----------
    x : ndarray, shape (N, n_inputs)
        The inputs as the AVR saw them: float32, or for a fixed-point build its integers.
    status : ndarray of int, shape (N,)
    cycles : ndarray of int, shape (N,)
        CPU cycles of one ``<prefix>_eval`` call (the empty measurement subtracted).
    u, yl, yr : ndarray, shape (N,)
        The outputs as the AVR returned them: float32, or the fixed-point integers (convert
        with :meth:`~it2track.codegen.fixedpoint.FixedFormat.to_real`).
    """

    x: NDArray[Any]
    status: NDArray[np.int64]
    cycles: NDArray[np.int64]
    u: NDArray[Any]
    yl: NDArray[Any]
    yr: NDArray[Any]


def run_on_avr(code: CCode, x: ArrayLike, *, build_dir: str | os.PathLike[str] | None = None,
               timeout: float = 600.0) -> AvrRun:
    """Run ``code`` on the simulated ATmega328P (16 MHz) for every row of ``x``.

    Parameters
    ----------
    code : CCode
        Generated code; a DOUBLE build computes in float on the AVR as well.
    x : array_like, shape (N, n_inputs)
        Real inputs; rounded to float32, or for a fixed-point build converted to its integers
        (:meth:`~it2track.codegen.fixedpoint.FixedFormat.to_int`).
    build_dir : path, optional
        Where to build (a fresh sub-folder per call; default: the temp dir).
    timeout : float
        Seconds allowed per simavr run.

    Raises
    ------
    ToolMissingError
        Without avr-gcc, avr-libc or simavr.
    BuildError
        If compiling fails or simavr's output is incomplete.
    """
    require(AVR_TOOLS)
    fmt = code.fixed
    arr = np.asarray(x, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != code.n_inputs:
        raise ValueError(f"x must have shape (N, {code.n_inputs}), got {arr.shape}")
    if len(arr) > 65535:
        raise ValueError(f"at most 65535 points per run, got {len(arr)}")
    if not np.all(np.isfinite(arr)):
        raise ValueError("x must be finite (it is printed as C constants)")
    pts: NDArray[Any] = np.ascontiguousarray(
        fmt.to_int(arr) if fmt is not None else arr.astype(np.float32))

    def literal(v: Any) -> str:
        return str(int(v)) if fmt is not None else float(v).hex() + "f"

    work = _workdir(build_dir, f"avr-{code.prefix}")
    _write_code(code, work)
    outs = []
    for start in range(0, len(pts), CHUNK):
        chunk = pts[start:start + CHUNK]
        main = _env().get_template("avr_bench.c.j2").render(
            p=code.prefix, header_name=code.header_name, n_in=code.n_inputs,
            n_points=len(chunk), fixed=fmt is not None,
            points=[[literal(v) for v in row] for row in chunk])
        (work / "bench.c").write_text(main)
        elf = work / "bench.elf"
        run_tool(["avr-gcc", *AVR_FLAGS, "-o", str(elf), "bench.c", code.source_name, "-lm"],
                 cwd=work)
        try:
            proc = subprocess.run(["simavr", "-m", AVR_MCU, "-f", str(AVR_CLOCK_HZ), str(elf)],
                                  capture_output=True, text=True, timeout=timeout, check=False)
        except subprocess.TimeoutExpired as exc:
            raise BuildError(f"simavr did not finish within {timeout:g} s") from exc
        text = _ANSI.sub("", proc.stdout + proc.stderr)
        rows = _LINE.findall(text)
        if len(rows) != len(chunk) or not re.search(r"^E\.?$", text, re.MULTILINE):
            raise BuildError(f"simavr printed {len(rows)} of {len(chunk)} results "
                             f"(exit {proc.returncode}):\n{text[-2000:]}")
        outs.append(np.array([[int(v, 16) for v in row] for row in rows], dtype=np.int64))
    table = np.concatenate(outs) if outs else np.zeros((0, 6), dtype=np.int64)
    if not np.array_equal(table[:, 0], np.arange(len(table)) % CHUNK):
        raise BuildError("simavr results out of order")

    def as_float(col: NDArray[np.int64]) -> NDArray[Any]:
        if fmt is not None:
            return col.astype(np.uint16).view(np.int16)
        return col.astype(np.uint32).view(np.float32)

    return AvrRun(x=pts, status=table[:, 1], cycles=table[:, 2], u=as_float(table[:, 3]),
                  yl=as_float(table[:, 4]), yr=as_float(table[:, 5]))


@dataclass(frozen=True, kw_only=True)
class CodeSize:
    """Bytes of a compiled controller.

    Attributes
    ----------
    text, data, bss : int
        Sections of the controller object (code and the ``const`` tables, which are in flash on
        the AVR; initialised and zeroed RAM).
    stack : int
        Sum of the stack frames of the controller's functions (``-fstack-usage``), an upper
        bound on its stack depth not counting the compiler's arithmetic helpers.
    program_flash : int or None
        Flash of a minimal AVR program that calls the controller once (start-up code and the
        software float routines included); None for the Cortex-M4 (object only).
    """

    text: int
    data: int
    bss: int
    stack: int
    program_flash: int | None = None

    @property
    def flash(self) -> int:
        """Flash bytes of the controller object (``text + data``)."""
        return self.text + self.data

    @property
    def ram(self) -> int:
        """Static RAM of the controller object (``data + bss``): 0, it keeps no state."""
        return self.data + self.bss


def _size(tool: str, path: Path) -> tuple[int, int, int]:
    out = run_tool([tool, str(path)]).stdout.splitlines()
    text, data, bss = (int(v) for v in out[1].split()[:3])
    return text, data, bss


def _stack(work: Path) -> int:
    total = 0
    for su in work.glob("*.su"):
        for line in su.read_text().splitlines():
            parts = line.split("\t")
            if len(parts) >= 2 and parts[1].strip().isdigit():
                total += int(parts[1])
    return total


_MINIMAL = """\
#include "{header}"
volatile {p}_real v_in[{P}_N_IN];
volatile {p}_real v_out;
int main(void)
{{
    {p}_real in[{P}_N_IN], u, yl, yr;
    int i;
    for (i = 0; i < {P}_N_IN; ++i) {{
        in[i] = v_in[i];
    }}
    if ({p}_eval(in, &u, &yl, &yr) == {P}_OK) {{
        v_out = u + yl + yr;
    }}
    for (;;) {{
    }}
    return 0;
}}
"""


def avr_sizes(code: CCode, *, build_dir: str | os.PathLike[str] | None = None) -> CodeSize:
    """Sizes on the ATmega328P (``avr-gcc -mmcu=atmega328p -Os``)."""
    require(("avr-gcc", "avr-size", "avr-libc"))
    work = _workdir(build_dir, f"avr-size-{code.prefix}")
    _write_code(code, work)
    run_tool(["avr-gcc", *AVR_FLAGS, "-fstack-usage", "-c", code.source_name], cwd=work)
    obj = work / (Path(code.source_name).stem + ".o")
    text, data, bss = _size("avr-size", obj)
    stack = _stack(work)
    (work / "minimal.c").write_text(_MINIMAL.format(header=code.header_name, p=code.prefix,
                                                    P=code.prefix.upper()))
    run_tool(["avr-gcc", *AVR_FLAGS, "-o", "minimal.elf", "minimal.c", code.source_name, "-lm"],
             cwd=work)
    ptext, pdata, _ = _size("avr-size", work / "minimal.elf")
    return CodeSize(text=text, data=data, bss=bss, stack=stack, program_flash=ptext + pdata)


def arm_sizes(code: CCode, *, build_dir: str | os.PathLike[str] | None = None) -> CodeSize:
    """Object sizes on the Cortex-M4F (``arm-none-eabi-gcc`` with :data:`ARM_FLAGS`)."""
    require(ARM_TOOLS)
    work = _workdir(build_dir, f"arm-size-{code.prefix}")
    _write_code(code, work)
    run_tool(["arm-none-eabi-gcc", *ARM_FLAGS, "-fstack-usage", "-c", code.source_name],
             cwd=work)
    text, data, bss = _size("arm-none-eabi-size", work / (Path(code.source_name).stem + ".o"))
    return CodeSize(text=text, data=data, bss=bss, stack=_stack(work))


def cost_grid(n: int, *, lo: float = -1.0, hi: float = 1.0, n_random: int = 0,
              seed: int = 0) -> NDArray[np.float32]:
    """Two-input measurement points: an ``n x n`` grid on ``[lo, hi]^2`` plus uniform random
    points (float32, shape ``(n*n + n_random, 2)``)."""
    if n < 2:
        raise ValueError(f"n={n!r} must be >= 2")
    axis = np.linspace(lo, hi, n)
    g = np.stack(np.meshgrid(axis, axis, indexing="ij"), axis=-1).reshape(-1, 2)
    r = np.random.default_rng(seed).uniform(lo, hi, size=(n_random, 2))
    return np.concatenate([g, r]).astype(np.float32)

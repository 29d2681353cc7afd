"""The cost table: what one step of the paper's controller costs on microcontrollers, per type
reducer and arithmetic (float and q15 fixed point).

:func:`measure_costs` generates the C, runs it on the simulated ATmega328P
(:func:`~it2track.codegen.mcu.run_on_avr`), checks its outputs against the host build of the
same code bit for bit, measures its sizes (:func:`~it2track.codegen.mcu.avr_sizes`,
:func:`~it2track.codegen.mcu.arm_sizes`) and its error against the Python (double) system
beside the derived bound (:mod:`.errorbound`). One implementation for the tests, the benchmark
(``benchmarks/bench_mcu.py``), README and the report.

The Cortex-M4F column is the object's size only: Debian has no cycle-accurate Cortex-M model
(``qemu-system-arm`` and ``unicorn`` emulate instructions without their timing), so no cycle
count is given for it.
"""

from __future__ import annotations

import dataclasses
import os
import subprocess
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..fuzzy import IT2Sugeno, Reducer, T1Sugeno
from .errorbound import fixed_error_bound, float_error_bound
from .generate import RealType, generate_c
from .mcu import (
    ARM_TOOLS,
    AVR_CLOCK_HZ,
    AVR_TOOLS,
    CONTROL_PERIOD_S,
    arm_sizes,
    avr_sizes,
    cost_grid,
    run_on_avr,
)
from .tools import BuildError, require

__all__ = ["ARITHMETICS", "CostRow", "CostTable", "measure_costs"]

#: The arithmetics the table compares (the float build as avr-gcc compiles it, and q15).
ARITHMETICS: tuple[RealType, ...] = (RealType.FLOAT, RealType.Q15)


@dataclass(frozen=True, kw_only=True)
class CostRow:
    """One controller's cost (see :class:`CostTable`).

    ``flash``, ``ram`` and ``stack`` are the AVR controller object's
    (:class:`~it2track.codegen.mcu.CodeSize` ``flash``, ``ram``, ``stack``);
    ``program_flash`` the minimal AVR program's; ``arm_text`` the Cortex-M4F object's flash
    (None when not measured). ``error`` is the largest ``|u - u_double|`` over the measured
    inputs (real values; a q15 build receives them rounded to its integers) and ``bound`` the
    largest derived bound there (:mod:`.errorbound`); ``equals_host`` whether the AVR's outputs
    equal the host build of the same C bit for bit.
    """

    label: str
    reducer: str
    arithmetic: str
    exact: bool
    cycles_max: int
    cycles_mean: float
    flash: int
    program_flash: int
    ram: int
    stack: int
    error: float
    bound: float
    equals_host: bool
    arm_text: int | None

    @property
    def us_max(self) -> float:
        """Worst step in microseconds at 16 MHz."""
        return self.cycles_max / AVR_CLOCK_HZ * 1e6

    @property
    def us_mean(self) -> float:
        return self.cycles_mean / AVR_CLOCK_HZ * 1e6

    @property
    def period_share(self) -> float:
        """Worst step as a fraction of the paper's 10 ms control period."""
        return self.us_max * 1e-6 / CONTROL_PERIOD_S


@dataclass(frozen=True, kw_only=True)
class CostTable:
    """What the controller costs on the microcontrollers, one row per controller and
    arithmetic.

    Attributes
    ----------
    rows : tuple of CostRow
    n_points : int
        Inputs measured per controller (the grid plus random points).
    fou : float
        FoU width of the paper's controller measured.
    tools : dict of str -> str
        Versions of the compilers and simulator used.
    """

    rows: tuple[CostRow, ...]
    n_points: int
    fou: float
    tools: dict[str, str]

    def as_text(self) -> str:
        """The table as aligned plain text (what ``benchmarks/bench_mcu.py`` prints)."""
        head = (f"{'controller':<28} {'arith':>5} {'cycles max':>10} {'mean':>8} {'us max':>8} "
                f"{'% of 10ms':>9} {'AVR flash':>9} {'program':>8} {'stack':>5} "
                f"{'error':>8} {'bound':>8} {'M4 text':>7}")
        lines = [head, "-" * len(head)]
        for r in self.rows:
            lines.append(
                f"{r.label:<28} {r.arithmetic:>5} {r.cycles_max:>10d} {r.cycles_mean:>8.0f} "
                f"{r.us_max:>8.0f} {100 * r.period_share:>8.1f}% {r.flash:>9d} "
                f"{r.program_flash:>8d} {r.stack:>5d} {r.error:>8.1e} {r.bound:>8.1e} "
                f"{'-' if r.arm_text is None else r.arm_text:>7}")
        return "\n".join(lines)

    def as_markdown(self) -> str:
        """The table in Markdown (README)."""
        lines = ["| controller | arithmetic | AVR cycles, worst | mean | µs worst @16 MHz | "
                 "% of 10 ms | AVR flash (object / program) | stack | error vs double "
                 "(measured / bound) | Cortex-M4F text |",
                 "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for r in self.rows:
            lines.append(
                f"| {r.label} | {r.arithmetic} | {r.cycles_max:,} | {r.cycles_mean:,.0f} | "
                f"{r.us_max:,.0f} | {100 * r.period_share:.1f} % | {r.flash:,} / "
                f"{r.program_flash:,} B | {r.stack} B | {r.error:.1e} / {r.bound:.1e} | "
                f"{'-' if r.arm_text is None else f'{r.arm_text:,} B'} |")
        return "\n".join(lines)


def _version(tool: str) -> str:
    try:
        proc = subprocess.run([tool, "--version"], capture_output=True, text=True, timeout=30,
                              check=False)
    except (OSError, subprocess.TimeoutExpired):
        return "?"
    first = (proc.stdout or proc.stderr).strip().splitlines()
    return first[0] if first else "?"


def _simavr_version() -> str:
    try:
        out = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "simavr"],
                             capture_output=True, text=True, timeout=30, check=False)
        return f"simavr {out.stdout.strip()}" if out.returncode == 0 else "simavr"
    except (OSError, subprocess.TimeoutExpired):
        return "simavr"


def measure_costs(
    *,
    fou: float = 0.2,
    reducers: Sequence[Reducer] | None = None,
    arithmetics: Sequence[RealType] = ARITHMETICS,
    grid: int = 21,
    n_random: int = 0,
    include_type1: bool = True,
    arm: bool = True,
    build_dir: str | os.PathLike[str] | None = None,
) -> CostTable:
    """Measure the paper's controller (FoU ``fou``) per type reducer and arithmetic on the
    simulated AVR.

    For each reducer and arithmetic (a reducer a fixed-point build does not carry, the
    Wu-Mendel bounds, has no q15 row): AVR cycles per step (worst and mean over a
    ``grid x grid`` grid of ``[-1, 1]^2`` plus ``n_random`` random points), flash and stack,
    the largest ``|u|`` difference of the AVR result from the Python (double) system beside the
    derived bound, whether the AVR's outputs equal the host's build of the same C bit for bit
    (when ``gcc`` is present), and the Cortex-M4F code size (``arm``). ``include_type1`` adds
    the type-1 FLC (FoU 0).

    Returns
    -------
    CostTable

    Raises
    ------
    ToolMissingError
        If avr-gcc, avr-libc or simavr (or, with ``arm``, the ARM toolchain) is missing.
    ValueError
        For an arithmetic other than float and q15.
    """
    from ..paper import heading_fls

    for real in arithmetics:
        if real not in ARITHMETICS:
            raise ValueError(f"arithmetics: {real!r} is not one of "
                             f"{', '.join(r.value for r in ARITHMETICS)}")
    require(AVR_TOOLS)
    if arm:
        require(ARM_TOOLS)
    reds = list(Reducer) if reducers is None else list(reducers)
    x = cost_grid(grid, n_random=n_random)
    x64 = x.astype(np.float64)
    systems: list[tuple[str, IT2Sugeno | T1Sugeno]] = []
    if include_type1:
        systems.append(("type-1 FLC (FoU 0)", heading_fls(0.0)))
    base = heading_fls(fou)
    assert isinstance(base, IT2Sugeno)
    for red in reds:
        label = f"IT2 {red.value.name}" + ("" if red.value.exact else " (approx.)")
        systems.append((label, dataclasses.replace(base, reducer=red.value)))
    host_ok = True
    try:
        require(("gcc",))
    except Exception:
        host_ok = False
    rows = []
    for label, fls in systems:
        for real in arithmetics:
            if real.fixed and isinstance(fls, IT2Sugeno) and fls.reducer.name == "wu-mendel":
                continue
            rows.append(_measure(label, fls, real, x64, host_ok, arm, build_dir))
    tools = {"avr-gcc": _version("avr-gcc"), "simavr": _simavr_version()}
    if arm:
        tools["arm-none-eabi-gcc"] = _version("arm-none-eabi-gcc")
    return CostTable(rows=tuple(rows), n_points=len(x), fou=fou, tools=tools)


def _measure(label: str, fls: IT2Sugeno | T1Sugeno, real: RealType, x64: np.ndarray,
             host_ok: bool, arm: bool, build_dir: str | os.PathLike[str] | None) -> CostRow:
    code = generate_c(fls, real=real)
    run = run_on_avr(code, x64, build_dir=build_dir)
    if np.any(run.status != 0):
        raise BuildError(f"{label} ({real.value}): the AVR returned error statuses "
                         f"{sorted(set(run.status.tolist()))}")
    ref = np.asarray(fls(x64[:, 0], x64[:, 1]), dtype=np.float64)
    fmt = code.fixed
    if fmt is not None:
        u = fmt.to_real(run.u)
        bound = float(fixed_error_bound(fls, fmt, x64).u.max())
    else:
        u = run.u.astype(np.float64)
        bound = float(float_error_bound(fls, run.x.astype(np.float64))[2].max())
    err = float(np.max(np.abs(u - ref)))
    same = False
    if host_ok:
        from .host import HostLibrary, build_host_library

        where = Path(build_dir) if build_dir is not None else Path(tempfile.gettempdir())
        lib = HostLibrary(code, build_host_library(code, where))
        hu, hyl, hyr, _ = lib.evaluate_raw(run.x)
        same = all(a.tobytes() == b.tobytes()
                   for a, b in zip((hu, hyl, hyr), (run.u, run.yl, run.yr), strict=True))
    size = avr_sizes(code, build_dir=build_dir)
    arm_text = arm_sizes(code, build_dir=build_dir).flash if arm else None
    red_name = code.reducer
    return CostRow(
        label=label + (f", {real.value}" if real.fixed else ""), reducer=red_name,
        arithmetic=real.value, exact=red_name not in ("nie-tan", "wu-mendel"),
        cycles_max=int(run.cycles.max()), cycles_mean=float(run.cycles.mean()),
        flash=size.flash, program_flash=int(size.program_flash or 0), ram=size.ram,
        stack=size.stack, error=err, bound=bound, equals_host=same, arm_text=arm_text)

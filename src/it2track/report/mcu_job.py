"""The study controller's cost on microcontrollers, measured in the background for the report.

``it2track reproduce`` starts a :class:`McuJob` before its simulations: a child Python process
(``python -m it2track.report.mcu_job``) runs :func:`it2track.codegen.costs.measure_costs` for the
paper's controller with the study's main FoU (every type reducer and the type-1 FLC: cycles on
the simulated ATmega328P, AVR flash, RAM and stack, Cortex-M4F code size) and draws the cost
figure (:mod:`it2track.report.mcu`). Nearly all of its work is done by the cross-compilers and
simavr, which are separate processes anyway; the child keeps matplotlib out of the main process
(whose figures are drawn by workers too) and shares nothing with the simulations, so the
study's numbers cannot depend on it. The result comes back as JSON (floats round-trip exactly).

The child runs in its own session (process group) with ``python -P`` (the current folder cannot
shadow the installed packages) and ``IT2TRACK_ENGINE=numpy`` (it never compiles numba kernels,
which would compete with the study for the cores). It draws the figure into the job's temporary
folder; the parent copies it into the output only once the measurement is known to have
succeeded. :meth:`McuJob.cancel` stops the whole group, compilers and simavr included.

When the toolchain is missing the job does not start; :class:`McuCosts` then names the Debian
packages to install. The outcome is one :class:`McuCosts`, whatever happened.
"""

from __future__ import annotations

import argparse
import dataclasses
import enum
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..atomicfile import atomic_write_bytes, atomic_write_text
from ..codegen.costs import CostRow, CostTable
from ..codegen.tools import MCU_TOOLS, missing_tools
from ..fuzzy.kernels import ENGINE_ENV

__all__ = [
    "FIGURE_NAME",
    "TABLE_NAME",
    "McuCosts",
    "McuJob",
    "McuStatus",
    "cost_rows",
    "install_command",
    "remeasure_commands",
    "table_from_json",
    "table_to_json",
    "write_cost_csv",
]

#: The figure's file name (PNG; SVG beside it on request) and the table's, in the output folder.
FIGURE_NAME = "mcu_costs.png"
TABLE_NAME = "mcu_costs.csv"


def remeasure_commands(fou: float) -> tuple[str, str]:
    """The commands that re-measure the costs of the controller with FoU ``fou`` outside the
    study (on the benchmark's 61 x 61 grid plus 2,000 random inputs) and write the C measured
    (the study's reducer, exhaustive).

    ``fou`` is written with ``repr`` (the exact float, not 6 significant digits); the figure goes
    to the current folder (not ``docs/``, whose figure the repository's README shows)."""
    exact = repr(float(fou))
    return (f"python benchmarks/bench_mcu.py --fou {exact} --figure {FIGURE_NAME}",
            f"it2track export c --paper {exact} --real float --reducer exhaustive --out ctrl/")


class McuStatus(enum.Enum):
    """What became of the measurement."""

    MEASURED = "measured"
    SKIPPED = "skipped"
    TOOLS_MISSING = "tools missing"
    FAILED = "failed"


@dataclass(frozen=True, kw_only=True)
class McuCosts:
    """The outcome of the microcontroller measurement.

    Attributes
    ----------
    status : McuStatus
    fou : float
        FoU width of the paper's controller measured.
    grid : int
        Inputs per axis of the measurement grid on ``[-1, 1]^2`` (``grid**2`` inputs).
    table : CostTable or None
        The measured costs (``MEASURED`` only).
    figure : Path or None
        The cost figure's PNG (``MEASURED`` only).
    missing : tuple of str
        Debian packages to install (``TOOLS_MISSING``).
    reason : str
        Why it was skipped or how it failed.
    seconds : float
        Wall time of the measurement and the figure, s (0 when nothing ran).
    """

    status: McuStatus
    fou: float
    grid: int
    table: CostTable | None = None
    figure: Path | None = None
    missing: tuple[str, ...] = ()
    reason: str = ""
    seconds: float = 0.0

    def __post_init__(self) -> None:
        if (self.table is not None) != (self.status is McuStatus.MEASURED):
            raise ValueError(f"McuCosts table: given for status {self.status.value!r}; a "
                             "table goes with 'measured' only")
        if bool(self.missing) != (self.status is McuStatus.TOOLS_MISSING):
            raise ValueError(f"McuCosts missing={self.missing!r}: packages go with "
                             "'tools missing' only")

    def provenance(self) -> dict[str, Any]:
        """What ``manifest.json`` records of the measurement."""
        out: dict[str, Any] = {"status": self.status.value, "fou": self.fou, "grid": self.grid}
        if self.table is not None:
            out["inputs"] = self.table.n_points
            out["tools"] = dict(self.table.tools)
            out["seconds"] = round(self.seconds, 3)
        if self.missing:
            out["missing_packages"] = list(self.missing)
        if self.reason:
            out["reason"] = self.reason
        return out


def install_command(packages: Sequence[str]) -> str:
    """The ``apt-get`` command that installs ``packages``."""
    return "apt-get install " + " ".join(packages)


def table_to_json(table: CostTable) -> dict[str, Any]:
    """``table`` as JSON-ready data (see :func:`table_from_json`)."""
    return dataclasses.asdict(table)


def table_from_json(data: Mapping[str, Any]) -> CostTable:
    """The :class:`CostTable` that :func:`table_to_json` wrote."""
    return CostTable(rows=tuple(CostRow(**r) for r in data["rows"]),
                     n_points=int(data["n_points"]), fou=float(data["fou"]),
                     tools={str(k): str(v) for k, v in data["tools"].items()})


def cost_rows(table: CostTable) -> list[dict[str, Any]]:
    """One dict per controller of ``table``: the columns of ``mcu_costs.csv`` (the Cortex-M4F
    size empty when it was not measured)."""
    return [{
        "controller": r.label, "reducer": r.reducer, "arithmetic": r.arithmetic,
        "exact": r.exact,
        "avr_cycles_worst": r.cycles_max, "avr_cycles_mean": r.cycles_mean,
        "avr_us_worst": r.us_max, "avr_us_mean": r.us_mean,
        "period_share_worst": r.period_share,
        "avr_flash_bytes": r.flash, "avr_program_flash_bytes": r.program_flash,
        "avr_ram_bytes": r.ram, "avr_stack_bytes": r.stack,
        "m4f_text_bytes": "" if r.arm_text is None else r.arm_text,
        "error_vs_double": r.error, "error_bound": r.bound, "equals_host": r.equals_host,
        "inputs": table.n_points,
    } for r in table.rows]


def write_cost_csv(path: Path, table: CostTable) -> Path:
    """Write :func:`cost_rows` of ``table`` to ``path`` (atomically; floats with ``repr``)."""
    from .outputs import write_rows_csv

    return write_rows_csv(path, cost_rows(table))


class McuJob:
    """The measurement, running in a child process (or an outcome known without one).

    Use :meth:`start` or :meth:`skipped`; :meth:`result` waits for the outcome, :meth:`cancel`
    stops the child and its own children (also on leaving a ``with`` block).
    """

    def __init__(self, *, fou: float, grid: int, outcome: McuCosts | None = None,
                 proc: subprocess.Popen[bytes] | None = None, work: Path | None = None,
                 cleanup: tempfile.TemporaryDirectory[str] | None = None,
                 out_dir: Path | None = None, svg: bool = False) -> None:
        self.fou = fou
        self.grid = grid
        self._outcome = outcome
        self._proc = proc
        self._work = work
        self._cleanup = cleanup
        self._out_dir = out_dir
        self._svg = svg

    @classmethod
    def skipped(cls, reason: str, *, fou: float, grid: int) -> McuJob:
        """A job that measures nothing; its result says ``reason``."""
        return cls(fou=fou, grid=grid, outcome=McuCosts(status=McuStatus.SKIPPED, fou=fou,
                                                        grid=grid, reason=reason))

    @classmethod
    def start(cls, *, out_dir: Path, fou: float, grid: int, svg: bool) -> McuJob:
        """Start measuring in a child process; the figure goes to ``out_dir``.

        Parameters
        ----------
        out_dir : Path
            Folder of the figure (:data:`FIGURE_NAME`, and its SVG if ``svg``); nothing is
            written there unless the measurement succeeds.
        fou : float
            FoU width of the paper's controller (> 0).
        grid : int
            Inputs per axis (>= 2).
        svg : bool
            Also write the figure as SVG.

        Returns
        -------
        McuJob
            Already finished (``TOOLS_MISSING``) when a tool is missing.
        """
        if grid < 2 or not fou > 0:
            raise ValueError(f"grid={grid!r} must be >= 2 and fou={fou!r} > 0")
        missing = missing_tools(MCU_TOOLS)
        if missing:
            return cls(fou=fou, grid=grid, outcome=McuCosts(
                status=McuStatus.TOOLS_MISSING, fou=fou, grid=grid, missing=tuple(missing)))
        cleanup = tempfile.TemporaryDirectory(prefix="it2track-mcu-", ignore_cleanup_errors=True)
        work = Path(cleanup.name)
        (work / "figure").mkdir()
        argv = _child_argv()
        cmd = [*argv, "--fou", repr(fou), "--grid", str(grid),
               "--figure-dir", str(work / "figure"), "--result", str(work / "result.json"),
               "--build-dir", str(work / "build")]
        if svg:
            cmd.append("--svg")
        try:
            with (work / "stderr.txt").open("wb") as err:
                # Its own session: cancel() signals the child's whole process group.
                proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=err, stderr=err,
                                        env=_child_env(), start_new_session=True)
        except OSError as exc:
            cleanup.cleanup()
            return cls(fou=fou, grid=grid, outcome=McuCosts(
                status=McuStatus.FAILED, fou=fou, grid=grid,
                reason=f"could not start {argv[0]}: {exc}"))
        return cls(fou=fou, grid=grid, proc=proc, work=work, cleanup=cleanup,
                   out_dir=Path(out_dir), svg=svg)

    def result(self) -> McuCosts:
        """Wait for the child and return the outcome (``FAILED`` with its message if it
        failed)."""
        if self._outcome is not None:
            return self._outcome
        assert self._proc is not None and self._work is not None
        code = self._proc.wait()
        self._proc = None  # finished and reaped: nothing left to stop
        try:
            data = json.loads((self._work / "result.json").read_text(encoding="utf-8"))
        except (OSError, ValueError):
            err = (self._work / "stderr.txt").read_text(encoding="utf-8", errors="replace")
            tail = " ".join(err.split()[-60:]) or "no output"
            data = {"status": "failed", "reason": f"the measuring process exited with {code}: "
                                                  f"{tail}"}
        outcome = _outcome_from(data, fou=self.fou, grid=self.grid)
        if outcome.status is McuStatus.MEASURED:
            try:
                outcome = dataclasses.replace(outcome, figure=self._publish_figure())
            except OSError as exc:
                outcome = McuCosts(status=McuStatus.FAILED, fou=self.fou, grid=self.grid,
                                   reason=f"the cost figure could not be copied: {exc}")
        self._outcome = outcome
        self._close()
        return self._outcome

    def _publish_figure(self) -> Path:
        """Copy the child's figure (PNG, and SVG if asked) into the output folder, each file
        atomically (the job's temporary folder may be on another file system); if one fails,
        remove the ones copied and raise."""
        assert self._work is not None and self._out_dir is not None
        names = [FIGURE_NAME, *([str(Path(FIGURE_NAME).with_suffix(".svg"))] if self._svg
                                else [])]
        copied: list[Path] = []
        try:
            for name in names:
                data = (self._work / "figure" / name).read_bytes()
                copied.append(atomic_write_bytes(self._out_dir / name, data))
        except OSError:
            for path in copied:
                path.unlink(missing_ok=True)
            raise
        return self._out_dir / FIGURE_NAME

    def cancel(self) -> None:
        """Stop the child and everything it started (compilers, simavr) if it still runs: its
        outcome is then never read and nothing reaches the output folder."""
        proc, self._proc = self._proc, None
        try:
            if proc is not None:
                _stop_group(proc)
        finally:
            self._close()

    def _close(self) -> None:
        if self._cleanup is not None:
            self._cleanup.cleanup()
            self._cleanup = None

    def __enter__(self) -> McuJob:
        return self

    def __exit__(self, *exc: object) -> None:
        self.cancel()


def _child_argv() -> list[str]:
    """The child's interpreter and module. ``-P``: the current folder is not put on
    ``sys.path``, so a local ``it2track/`` or ``numpy.py`` cannot shadow the installed
    packages. (A hook the tests replace.)"""
    return [sys.executable, "-P", "-m", __name__]


def _child_env() -> dict[str, str]:
    """The child's environment: this one, with the numpy engine (the costs do not depend on the
    engine, and the child then never spends CPU compiling numba kernels)."""
    return {**os.environ, ENGINE_ENV: "numpy"}


def _stop_group(proc: subprocess.Popen[bytes]) -> None:
    """SIGTERM to ``proc``'s process group (it leads its own session), SIGKILL if ``proc`` has
    not ended after a short wait."""
    try:
        os.killpg(proc.pid, signal.SIGTERM)  # proc is not reaped yet: its group id is its own
    except ProcessLookupError:
        pass
    try:
        proc.wait(timeout=5)
    except subprocess.TimeoutExpired:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        proc.wait()


def _outcome_from(data: Mapping[str, Any], *, fou: float, grid: int) -> McuCosts:
    if data.get("status") == McuStatus.MEASURED.value:
        return McuCosts(status=McuStatus.MEASURED, fou=fou, grid=grid,
                        table=table_from_json(data["table"]), seconds=float(data["seconds"]))
    return McuCosts(status=McuStatus.FAILED, fou=fou, grid=grid,
                    reason=str(data.get("reason", "unknown failure")))


def main(argv: Sequence[str] | None = None) -> int:
    """The child process: measure, draw into ``--figure-dir``, write the outcome as JSON to
    ``--result`` (last: without it the parent counts the measurement as failed)."""
    ap = argparse.ArgumentParser(prog="python -m it2track.report.mcu_job",
                                 description="Measure the MCU costs for it2track reproduce.")
    ap.add_argument("--fou", type=float, required=True)
    ap.add_argument("--grid", type=int, required=True)
    ap.add_argument("--figure-dir", type=Path, required=True)
    ap.add_argument("--result", type=Path, required=True)
    ap.add_argument("--build-dir", type=Path, required=True)
    ap.add_argument("--svg", action="store_true")
    args = ap.parse_args(argv)
    from ..codegen.costs import measure_costs
    from ..codegen.tools import BuildError, ToolMissingError

    started = time.perf_counter()
    try:
        table = measure_costs(fou=args.fou, grid=args.grid, build_dir=args.build_dir)
    except (BuildError, ToolMissingError, OSError, ValueError) as exc:
        data: dict[str, Any] = {"status": McuStatus.FAILED.value,
                                "reason": f"{type(exc).__name__}: {exc}"}
    else:
        from .mcu import write_mcu_cost_figure

        png = write_mcu_cost_figure(table, args.figure_dir / FIGURE_NAME)
        if args.svg:
            write_mcu_cost_figure(table, png.with_suffix(".svg"))
        data = {"status": McuStatus.MEASURED.value, "table": table_to_json(table),
                "seconds": time.perf_counter() - started}
    atomic_write_text(args.result, json.dumps(data, allow_nan=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())

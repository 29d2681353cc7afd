"""External tools (compilers, simulator): where they are, and which Debian package has them."""

from __future__ import annotations

import ctypes.util
import shutil
import subprocess
from collections.abc import Sequence
from pathlib import Path

__all__ = ["ARM_TOOLS", "AVR_TOOLS", "MCU_PACKAGES", "MCU_TOOLS", "PIL_TOOLS", "TOOL_PACKAGES",
           "BuildError", "ToolMissingError", "missing_tools", "require", "run_tool"]

#: Tool -> the Debian package that installs it.
TOOL_PACKAGES: dict[str, str] = {
    "gcc": "gcc",
    "avr-gcc": "gcc-avr",
    "avr-g++": "gcc-avr",
    "avr-size": "binutils-avr",
    "avr-nm": "binutils-avr",
    "avr-libc": "avr-libc",
    "simavr": "simavr",
    "libsimavr": "libsimavr-dev",
    "arm-none-eabi-gcc": "gcc-arm-none-eabi",
    "arm-none-eabi-size": "binutils-arm-none-eabi",
    "newlib": "libnewlib-arm-none-eabi",
}
#: What the microcontroller measurement (:func:`it2track.codegen.costs.measure_costs`) needs:
#: the AVR build and simulation, and the Cortex-M4F build.
AVR_TOOLS = ("avr-gcc", "avr-size", "avr-libc", "simavr")
ARM_TOOLS = ("arm-none-eabi-gcc", "arm-none-eabi-size", "newlib")
MCU_TOOLS = (*AVR_TOOLS, *ARM_TOOLS)
#: What processor-in-the-loop (:mod:`it2track.codegen.pil`) needs: the AVR build, ``avr-nm``
#: for the firmware's symbols, and the simulator as a library with the host compiler for the
#: shim that drives it.
PIL_TOOLS = ("avr-gcc", "avr-nm", "avr-libc", "gcc", "libsimavr")
#: The Debian packages of :data:`MCU_TOOLS`, in order: the one list the CLI help, the report,
#: the README and the docs name (``.ci/run`` installs the same).
MCU_PACKAGES: tuple[str, ...] = tuple(dict.fromkeys(TOOL_PACKAGES[t] for t in MCU_TOOLS))


class ToolMissingError(RuntimeError):
    """A tool the operation needs is not installed; the message names its Debian package."""


class BuildError(RuntimeError):
    """A compiler or the simulator failed; the message holds the command and its output."""


def _avr_libc_present() -> bool:
    return Path("/usr/lib/avr/include/avr/io.h").exists() or Path(
        "/usr/avr/include/avr/io.h").exists()


def _newlib_present() -> bool:
    return any(Path(p).exists() for p in ("/usr/lib/arm-none-eabi/newlib",
                                          "/usr/lib/arm-none-eabi/include/stdlib.h"))


def _libsimavr_present() -> bool:
    header = Path("/usr/include/simavr/sim_avr.h").exists() or Path(
        "/usr/local/include/simavr/sim_avr.h").exists()
    return header and ctypes.util.find_library("simavr") is not None


def missing_tools(tools: Sequence[str]) -> list[str]:
    """Debian packages to install for ``tools`` (empty if all are present), deduplicated."""
    missing: list[str] = []
    for tool in tools:
        if tool == "avr-libc":
            ok = _avr_libc_present()
        elif tool == "newlib":
            ok = _newlib_present()
        elif tool == "libsimavr":
            ok = _libsimavr_present()
        else:
            ok = shutil.which(tool) is not None
        if not ok and TOOL_PACKAGES[tool] not in missing:
            missing.append(TOOL_PACKAGES[tool])
    return missing


def require(tools: Sequence[str]) -> None:
    """Raise :class:`ToolMissingError` naming the Debian packages of any missing tool."""
    missing = missing_tools(tools)
    if missing:
        raise ToolMissingError(
            f"needs {', '.join(tools)}; install the Debian package(s) {', '.join(missing)} "
            f"(apt-get install {' '.join(missing)})"
        )


def run_tool(cmd: Sequence[str], *, cwd: Path | None = None, timeout: float = 300.0
             ) -> subprocess.CompletedProcess[str]:
    """Run ``cmd``; raise :class:`BuildError` with its output if it fails."""
    try:
        proc = subprocess.run(list(cmd), cwd=cwd, capture_output=True, text=True,
                              timeout=timeout, check=False)
    except subprocess.TimeoutExpired as exc:
        raise BuildError(f"{' '.join(cmd)} timed out after {timeout:g} s") from exc
    if proc.returncode != 0:
        raise BuildError(
            f"{' '.join(cmd)} failed (exit {proc.returncode}):\n{proc.stdout}{proc.stderr}"
        )
    return proc

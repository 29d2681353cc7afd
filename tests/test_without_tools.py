"""The tests that need a toolchain, the simulator or a browser pass or skip, never fail, on a
machine without them: they run here in a subprocess whose ``PATH`` hides ``avr-*``,
``arm-none-eabi-*``, ``simavr*`` and ``chromium*`` (every other program stays reachable), and
every skip names what to install.

Only the files and tests that use those tools run (the microcontroller measurement, the
generated C on the AVR and the Cortex-M4F, the report's microcontroller section, the Arduino
sketch and the browser checks), so the run stays short.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from it2track.codegen.tools import TOOL_PACKAGES

ROOT = Path(__file__).resolve().parents[1]
HIDDEN = re.compile(r"^(avr-|arm-none-eabi-|simavr|chromium)")
TOOL_TESTS = [
    "tests/codegen/test_codegen_mcu.py",
    "tests/codegen/test_codegen_examples.py",
    "tests/cli/test_reproduce_mcu.py",
    "tests/report/test_mcu_section.py",
    "tests/report/test_mcu_figure.py",
    "tests/report/test_html_render.py::test_renders_in_headless_chromium",
    "tests/report/test_html_render.py::test_figures_decode_in_chromium",
    "tests/report/test_report_study_sections.py::"
    "test_the_whole_study_page_renders_in_headless_chromium",
]


def hiding_path(folder: Path) -> str:
    """A ``PATH`` of one folder of links to every program on this ``PATH`` but the hidden
    ones (the first of each name, as the shell would find it)."""
    folder.mkdir()
    for entry in os.environ.get("PATH", "").split(os.pathsep):
        if not entry or not os.path.isdir(entry):
            continue
        for item in os.scandir(entry):
            link = folder / item.name
            if HIDDEN.match(item.name) or os.path.lexists(link):
                continue
            if item.is_file() and os.access(item.path, os.X_OK):
                link.symlink_to(item.path)
    return str(folder)


def test_the_hiding_path_hides_only_the_tools(tmp_path):
    path = hiding_path(tmp_path / "bin")
    names = set(os.listdir(path))
    assert not any(HIDDEN.match(n) for n in names)
    for tool in ("sh", "gcc", "git", "avr-gcc", "simavr", "chromium", "arm-none-eabi-gcc"):
        if shutil.which(tool) and not HIDDEN.match(tool):
            assert tool in names, tool  # everything else stays reachable
    assert HIDDEN.match("avr-gcc") and HIDDEN.match("chromium-browser")
    assert not HIDDEN.match("gcc") and not HIDDEN.match("python3")


@pytest.mark.slow
def test_tool_tests_pass_or_skip_without_the_tools(tmp_path):
    env = {**os.environ, "PATH": hiding_path(tmp_path / "bin")}
    cmd = [sys.executable, "-m", "pytest", "-q", "-rs", "-p", "no:cacheprovider",
           "--basetemp", str(tmp_path / "base"), *TOOL_TESTS]
    proc = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=1800, check=False)
    out = proc.stdout
    summary = out.strip().splitlines()[-1] if out.strip() else ""
    assert proc.returncode == 0, f"exit {proc.returncode}:\n{out[-6000:]}\n{proc.stderr[-2000:]}"
    assert "failed" not in summary and "error" not in summary, summary
    assert re.search(r"\d+ passed", summary) and re.search(r"\d+ skipped", summary), summary
    reasons = [line for line in out.splitlines() if line.startswith("SKIPPED")]
    assert reasons
    packages = set(TOOL_PACKAGES.values()) | {"chromium"}
    for line in reasons:  # every skip says which Debian package brings the tool back
        assert any(p in line for p in packages), line
        assert "Debian package" in line or "apt-get install" in line, line

"""`it2track reproduce` measures the microcontroller costs in the background: the report's
section carries the cycles a direct measure_costs call gives (simavr is deterministic), a
missing toolchain is named with its Debian packages, --no-mcu and --quick skip, a failed
measurement publishes nothing of its own, and none of it changes a simulated number."""

from __future__ import annotations

import csv
import json
import re
import sys
from dataclasses import replace
from pathlib import Path

import pytest
from click.testing import CliRunner

from it2track.cli.main import main
from it2track.codegen.tools import MCU_PACKAGES, MCU_TOOLS, missing_tools
from it2track.experiments.study import StudyConfig

GRID = 2  # the smallest grid: 4 inputs per controller
ROOT = Path(__file__).resolve().parents[2]

#: A measuring child that draws its figure and then crashes (stands in for
#: ``python -m it2track.report.mcu_job``).
DRAW_THEN_CRASH = """
import sys
from pathlib import Path

args = sys.argv[1:]
figures = Path(args[args.index("--figure-dir") + 1])
for name in ("mcu_costs.png", "mcu_costs.svg"):
    (figures / name).write_bytes(b"drawn before the failure")
sys.exit(3)
"""


def _tiny_study() -> StudyConfig:
    from it2track.tracking import LoopConfig

    return replace(StudyConfig(), loop=LoopConfig(duration=0.5), seeds=2, sweep_seeds=2,
                   noise_levels=(0.0, 0.05), fou_sweep=(0.0, 0.2), pd=None, tuning=None,
                   robustness=None)


def _run(out: Path, *args: str) -> tuple[Path, dict, str]:
    # --no-chip: the verdicts on the chip need part of the same toolchain (tests/cli/
    # test_reproduce_chip.py); here only the cost measurement varies between the runs.
    result = CliRunner().invoke(main, ["reproduce", "--no-progress", "--no-chip", *args,
                                       "--out", str(out)], prog_name="it2track")
    assert result.exit_code == 0, result.output
    manifest = json.loads((out / "manifest.json").read_text())
    page = (out / "report.html").read_text()
    return out, manifest, page[page.index('<h2 id="mcu">'):page.index('<h2 id="summary">')]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The tiny study four ways: measured, --no-mcu, with a measuring child that draws its
    figure and then crashes, and with the cross tools hidden."""
    import shutil

    import it2track.cli.reproduce as cli
    from it2track.codegen import tools
    from it2track.report import mcu_job

    root = tmp_path_factory.mktemp("mcu")
    out = {}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(cli, "_default_study_config", _tiny_study)
        if not missing_tools(MCU_TOOLS):
            out["measured"] = _run(root / "measured", "--mcu-grid", str(GRID))
        out["off"] = _run(root / "off", "--no-mcu")
        with pytest.MonkeyPatch.context() as child:
            script = root / "draw_then_crash.py"
            script.write_text(DRAW_THEN_CRASH)
            child.setattr(mcu_job, "missing_tools", lambda tools: [])
            child.setattr(mcu_job, "_child_argv", lambda: [sys.executable, str(script)])
            out["failed"] = _run(root / "failed", "--mcu-grid", str(GRID))
        # A hermetic toolbox, whatever this machine has: these three and newlib are missing,
        # the other microcontroller tools present (never run: the job stops at the check).
        real = shutil.which
        hidden = {"avr-gcc", "simavr", "arm-none-eabi-gcc"}

        def which(name, *a, **k):
            if name in hidden:
                return None
            return f"/usr/bin/{name}" if name in tools.TOOL_PACKAGES else real(name, *a, **k)

        mp.setattr(shutil, "which", which)
        mp.setattr(tools, "_avr_libc_present", lambda: True)
        mp.setattr(tools, "_newlib_present", lambda: False)
        out["toolless"] = _run(root / "toolless")
    return out


def _needs_tools(runs):
    if "measured" not in runs:
        packages = missing_tools(MCU_TOOLS)
        pytest.skip(f"needs the Debian packages {', '.join(packages)}")
    return runs["measured"]


def test_report_carries_the_cycles_of_a_direct_measurement(runs, tmp_path):
    from it2track.codegen.costs import measure_costs

    out, manifest, section = _needs_tools(runs)
    direct = measure_costs(fou=StudyConfig().main_fou, grid=GRID, build_dir=tmp_path)
    with (out / "mcu_costs.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [r["controller"] for r in rows] == [r.label for r in direct.rows]
    for row, ref in zip(rows, direct.rows, strict=True):
        for key, want in (("avr_cycles_worst", ref.cycles_max),
                          ("avr_cycles_mean", ref.cycles_mean), ("avr_flash_bytes", ref.flash),
                          ("avr_ram_bytes", ref.ram), ("avr_stack_bytes", ref.stack),
                          ("m4f_text_bytes", ref.arm_text)):
            assert row[key] == repr(want) if isinstance(want, float) else str(want), (
                ref.label, key)
        # the page shows the same worst and mean cycles
        shown = re.search(re.escape(ref.label) + r"(?: ●)?</td><td class=\"num\">([\d,]+)</td>"
                          r"<td class=\"num\">([\d,]+)</td>", section)
        assert shown, ref.label
        assert shown.groups() == (f"{ref.cycles_max:,}", f"{ref.cycles_mean:,.0f}")
    assert f"{GRID} × {GRID} grid" in section and '<figure id="fig-mcu_costs">' in section
    assert "avr-gcc" in section and "simavr" in section
    assert {"mcu_costs.csv", "mcu_costs.png", "mcu_costs.svg"} <= set(manifest["files"])
    assert manifest["mcu"]["status"] == "measured" and manifest["mcu"]["grid"] == GRID
    assert manifest["command"].endswith(f"--mcu-grid {GRID} --no-chip --no-progress")
    assert "microcontroller costs" in manifest["stage_s"]


def test_missing_tools_are_named_and_the_rest_is_unaffected(runs):
    out, manifest, section = runs["toolless"]
    packages = "gcc-avr simavr gcc-arm-none-eabi libnewlib-arm-none-eabi"
    assert f"apt-get install {packages}" in section
    assert manifest["mcu"]["missing_packages"] == packages.split()
    assert not any(p.name.startswith("mcu_costs") for p in out.iterdir())
    assert "<table" not in section
    # the simulated numbers are those of a run without the measurement
    off = runs["off"][0]
    for name in ("metrics.csv", "summary.csv", "claims.md"):
        assert (out / name).read_bytes() == (off / name).read_bytes(), name


def test_the_measurement_does_not_change_the_simulated_numbers(runs):
    out = _needs_tools(runs)[0]
    off = runs["off"][0]
    for name in ("metrics.csv", "summary.csv", "claims.md"):
        assert (out / name).read_bytes() == (off / name).read_bytes(), name


def test_a_failed_measurement_publishes_none_of_its_files(runs):
    out, manifest, section = runs["failed"]
    assert not any(p.name.startswith("mcu_costs") for p in out.iterdir())
    assert not any(f.startswith("mcu_costs") for f in manifest["files"])
    assert manifest["mcu"]["status"] == "failed" and "exited with 3" in manifest["mcu"]["reason"]
    assert "The measurement failed" in section and "<figure" not in section
    off = runs["off"][0]
    for name in ("metrics.csv", "summary.csv", "claims.md"):
        assert (out / name).read_bytes() == (off / name).read_bytes(), name


def test_a_failing_cancel_still_removes_the_staging_folder(monkeypatch, tmp_path):
    """The job's cancel() raising (in reproduce's ``finally``) must not keep the half-written
    run's staging folder."""
    from it2track.report.mcu_job import McuJob

    def fail_start(*a, **k):
        raise OSError("start failed")

    def fail_cancel(self):
        raise RuntimeError("cancel failed")

    monkeypatch.setattr(McuJob, "start", fail_start)
    monkeypatch.setattr(McuJob, "cancel", fail_cancel)
    out = tmp_path / "o"
    result = CliRunner().invoke(main, ["reproduce", "--no-progress", "--out", str(out)])
    assert result.exit_code != 0 and isinstance(result.exception, RuntimeError)
    assert list(out.iterdir()) == [], list(out.rglob("*"))


def test_the_toolchain_packages_are_named_alike_everywhere():
    """The CLI help, the README and the study guide name MCU_PACKAGES (what the report and the
    missing-tools detection use), and .ci/run installs each of them."""
    from it2track.cli.reproduce import reproduce

    listed = ", ".join(MCU_PACKAGES)
    assert MCU_PACKAGES == ("gcc-avr", "binutils-avr", "avr-libc", "simavr",
                            "gcc-arm-none-eabi", "binutils-arm-none-eabi",
                            "libnewlib-arm-none-eabi")
    (option,) = [p for p in reproduce.params if p.name == "mcu"]
    assert listed in " ".join((option.help or "").split())
    for doc in ("README.md", "docs/guide/study.md"):
        assert listed in " ".join((ROOT / doc).read_text().split()), doc
    ci = (ROOT / ".ci" / "run").read_text()
    for package in MCU_PACKAGES:
        assert re.search(rf"[(\s]{re.escape(package)}[)\s]", ci), package


def test_no_mcu_skips_and_is_recorded(runs):
    out, manifest, section = runs["off"]
    assert "Not measured (skipped with --no-mcu)" in section
    assert manifest["mcu"] == {"status": "skipped", "fou": 0.2, "grid": 21,
                               "reason": "skipped with --no-mcu"}
    assert manifest["command"].endswith("--no-mcu --no-chip --no-progress")
    assert not any(p.name.startswith("mcu_costs") for p in out.iterdir())


@pytest.mark.parametrize("args, needle", [
    (["--no-mcu", "--mcu-grid", "5"], "--no-mcu turns it off"),
    (["--quick", "--mcu-grid", "5"], "--quick turns it off"),
    (["--mcu-grid", "1"], "1 is not in the range 2<=x<=61"),
    (["--mcu-grid", "62"], "62 is not in the range 2<=x<=61"),
])
def test_mcu_grid_without_a_measurement_is_refused_before_any_work(tmp_path, args, needle):
    out = tmp_path / "o"
    result = CliRunner().invoke(main, ["reproduce", "--no-progress", *args, "--out", str(out)])
    assert result.exit_code != 0
    assert "--mcu-grid" in result.output and needle in result.output, result.output
    assert not out.exists()

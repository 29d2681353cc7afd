"""The report's microcontroller section: rendered from a hand-made CostTable (no toolchain
needed) with the table's numbers, the skipped / toolless / failed outcomes saying why and what to
install, and the background job's outcomes (JSON round trip, a crashed child, missing tools,
a child that drew its figure and then failed, cancelling a child with its own children).

The job's child is replaced by :data:`FAKE_CHILD` (through ``mcu_job._child_argv``) where the
test needs it to do something the real measurement does not do on demand."""

from __future__ import annotations

import csv
import html
import json
import os
import re
import shlex
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from it2track.codegen.costs import CostRow, CostTable
from it2track.codegen.tools import MCU_PACKAGES
from it2track.report import mcu_job
from it2track.report.html.mcu import mcu_section
from it2track.report.mcu_job import (
    McuCosts,
    McuJob,
    McuStatus,
    remeasure_commands,
    table_from_json,
    table_to_json,
    write_cost_csv,
)

#: A stand-in for ``python -m it2track.report.mcu_job``: argv[1] says what it does.
FAKE_CHILD = """
import argparse, json, os, subprocess, sys, time
from pathlib import Path

mode, extra = sys.argv[1], sys.argv[2]
ap = argparse.ArgumentParser()
ap.add_argument("--figure-dir", type=Path, required=True)
ap.add_argument("--result", type=Path, required=True)
ap.add_argument("--svg", action="store_true")
args, _ = ap.parse_known_args(sys.argv[3:])
if mode in ("draw-then-crash", "draw-then-fail", "measured"):
    (args.figure_dir / "mcu_costs.png").write_bytes(b"png bytes")
    if args.svg:
        (args.figure_dir / "mcu_costs.svg").write_bytes(b"svg bytes")
if mode == "draw-then-crash":
    sys.exit(3)
if mode == "draw-then-fail":
    args.result.write_text(json.dumps({"status": "failed", "reason": "BuildError: late"}))
if mode == "measured":
    args.result.write_text(Path(extra).read_text())
if mode == "hang":  # a grandchild (as avr-gcc or simavr would be), then wait
    sleeper = subprocess.Popen(["sleep", "600"])
    Path(extra + ".tmp").write_text(str(sleeper.pid))
    os.replace(extra + ".tmp", extra)
    time.sleep(600)
"""

TOOLS = {"avr-gcc": "avr-gcc (GCC) 5.4.0", "simavr": "simavr 1.6+dfsg-3",
         "arm-none-eabi-gcc": "arm-none-eabi-gcc 12.2.1"}


def _table() -> CostTable:
    # cycles, flash, program, ram, stack, M4F text: distinct numbers so that a column mix-up
    # shows
    spec = [("type-1 FLC (FoU 0)", "type-1", True, 6075, 4556.4, 1654, 2776, 0, 155, 808),
            ("IT2 exhaustive", "exhaustive", True, 15655, 12577.0, 3040, 4162, 2, 347, 1472),
            ("IT2 exhaustive, q15", "exhaustive", True, 6049, 5248.0, 8688, 8940, 1, 235, 2216),
            ("IT2 km", "km", True, 27607, 18943.0, 3558, 4762, 0, 335, 1760),
            ("IT2 nie-tan (approx.)", "nie-tan", False, 9352, 7700.0, 2002, 3124, 0, 223, None)]
    rows = tuple(CostRow(label=label, reducer=red, arithmetic="q15" if "q15" in label else "float",
                         exact=exact, cycles_max=cmax, cycles_mean=cmean, flash=flash,
                         program_flash=prog, ram=ram, stack=stack,
                         error=2.6e-4 if "q15" in label else 2e-6,
                         bound=2.9e-4 if "q15" in label else 1.2e-4, equals_host=True,
                         arm_text=arm)
                 for label, red, exact, cmax, cmean, flash, prog, ram, stack, arm in spec)
    return CostTable(rows=rows, n_points=441, fou=0.2, tools=TOOLS)


def _cells(section: str) -> dict[str, list[str]]:
    """Controller -> its cells (the marker stripped), from the section's cost table."""
    body = section[section.index('<table class="mcu">'):]
    body = body[:body.index("</table>")]
    out = {}
    for row in re.findall(r"<tr><td>(.*?)</tr>", body):
        cells = [html.unescape(c) for c in re.findall(r"(?:^|<td[^>]*>)([^<]*)</td>", row)]
        out[cells[0].removesuffix(" ●")] = [cells[0], *cells[1:]]
    return out


def test_measured_section_shows_the_tables_numbers():
    costs = McuCosts(status=McuStatus.MEASURED, fou=0.2, grid=21, table=_table(), seconds=3.2)
    ref = {"key": "mcu_costs", "number": 7, "src": "data:image/png;base64,AAAA",
           "name": "mcu_costs.png"}
    text = str(mcu_section(costs, ref))
    cells = _cells(text)
    assert list(cells) == ["type-1 FLC (FoU 0)", "IT2 exhaustive", "IT2 exhaustive, q15",
                           "IT2 km", "IT2 nie-tan (approx.)"]
    # controller, cycles worst, mean, us worst, us mean, % of 10 ms, flash, program, RAM,
    # stack, M4F, error, bound
    assert cells["IT2 exhaustive"] == ["IT2 exhaustive ●", "15,655", "12,577", "978", "786",
                                       "9.8 %", "3,040", "4,162", "2", "347", "1,472",
                                       "2.0e-06", "1.2e-04"]
    # the fixed-point build is not what the study simulates: no marker
    assert cells["IT2 exhaustive, q15"] == ["IT2 exhaustive, q15", "6,049", "5,248", "378",
                                            "328", "3.8 %", "8,688", "8,940", "1", "235",
                                            "2,216", "2.6e-04", "2.9e-04"]
    assert cells["type-1 FLC (FoU 0)"][1:6] == ["6,075", "4,556", "380", "285", "3.8 %"]
    assert cells["IT2 km"][0] == "IT2 km" and cells["IT2 km"][3] == "1,725"  # 27607 / 16
    assert cells["IT2 nie-tan (approx.)"][-3] == "—"  # no Cortex-M4F size
    # the figure with its number, the toolchain versions, the commands that re-measure
    assert '<figure id="fig-mcu_costs">' in text and "Figure 7." in text
    assert 'src="data:image/png;base64,AAAA"' in text
    for version in TOOLS.values():
        assert html.escape(version) in text
    for command in remeasure_commands(0.2):
        assert html.escape(command) in text
    assert "21 × 21 grid" in text and "441 inputs" in text and "bit for bit" in text
    assert "mcu_costs.csv" in text


def test_remeasure_commands_name_the_studys_fou_and_run(tmp_path):
    bench, export = remeasure_commands(0.3)
    assert "--fou 0.3" in bench and "--paper 0.3" in export
    # the figure goes to the current folder, never over the README's docs/mcu_costs.png
    assert shlex.split(bench)[-2:] == ["--figure", "mcu_costs.png"] and "docs/" not in bench
    for fou in (0.123456789, 1 / 3, 1e-7):
        bench, export = remeasure_commands(fou)
        assert float(shlex.split(bench)[shlex.split(bench).index("--fou") + 1]) == fou
        assert float(shlex.split(export)[shlex.split(export).index("--paper") + 1]) == fou
    from it2track.cli.main import main

    args = shlex.split(export)[1:]
    args[args.index("--out") + 1] = str(tmp_path / "ctrl")
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert "exhaustive" in (tmp_path / "ctrl" / "it2.c").read_text()


@pytest.mark.parametrize("status, needles", [
    (McuStatus.TOOLS_MISSING, ["gcc-avr, simavr", "apt-get install gcc-avr simavr"]),
    (McuStatus.SKIPPED, ["Not measured (skipped with --quick)", "gcc-avr, binutils-avr, "
                         "avr-libc, simavr, gcc-arm-none-eabi, binutils-arm-none-eabi, "
                         "libnewlib-arm-none-eabi", ", ".join(MCU_PACKAGES)]),
    (McuStatus.FAILED, ["The measurement failed", "BuildError: avr-gcc &lt;failed&gt;"]),
])
def test_unmeasured_sections_say_why_and_how(status, needles):
    reason = {McuStatus.SKIPPED: "skipped with --quick",
              McuStatus.FAILED: "BuildError: avr-gcc <failed>"}.get(status, "")
    missing = ("gcc-avr", "simavr") if status is McuStatus.TOOLS_MISSING else ()
    text = str(mcu_section(McuCosts(status=status, fou=0.2, grid=21, missing=missing,
                                    reason=reason)))
    for needle in needles:
        assert needle in text, (status, needle)
    assert "<table" not in text and "<figure" not in text
    assert html.escape(remeasure_commands(0.2)[0]) in text


def test_outcome_is_consistent():
    with pytest.raises(ValueError, match="table"):
        McuCosts(status=McuStatus.SKIPPED, fou=0.2, grid=21, table=_table())
    with pytest.raises(ValueError, match="table"):
        McuCosts(status=McuStatus.MEASURED, fou=0.2, grid=21)
    with pytest.raises(ValueError, match="missing"):
        McuCosts(status=McuStatus.FAILED, fou=0.2, grid=21, missing=("simavr",))
    prov = McuCosts(status=McuStatus.TOOLS_MISSING, fou=0.2, grid=5,
                    missing=("simavr",)).provenance()
    assert prov == {"status": "tools missing", "fou": 0.2, "grid": 5,
                    "missing_packages": ["simavr"]}


def test_table_round_trips_through_json_and_csv(tmp_path):
    import json

    table = _table()
    assert table_from_json(json.loads(json.dumps(table_to_json(table)))) == table
    path = write_cost_csv(tmp_path / "mcu_costs.csv", table)
    with path.open() as fh:
        rows = list(csv.DictReader(fh))
    assert [r["controller"] for r in rows] == [r.label for r in table.rows]
    ex = rows[1]
    assert (ex["avr_cycles_worst"], ex["avr_ram_bytes"], ex["avr_stack_bytes"],
            ex["m4f_text_bytes"]) == ("15655", "2", "347", "1472")
    assert float(ex["avr_us_worst"]) == table.rows[1].us_max == pytest.approx(15655 / 16)
    assert float(ex["period_share_worst"]) == pytest.approx(15655 / 16e6 / 0.01)
    assert rows[4]["m4f_text_bytes"] == "" and ex["inputs"] == "441"
    q = rows[2]
    assert (q["arithmetic"], q["error_vs_double"], q["error_bound"], q["equals_host"]) == (
        "q15", "0.00026", "0.00029", "True")
    assert ex["arithmetic"] == "float" and float(ex["error_bound"]) == 1.2e-4


def test_missing_tools_finish_the_job_without_a_process(monkeypatch, tmp_path):
    import shutil

    from it2track.codegen import tools

    real = shutil.which
    hidden = {"avr-gcc", "simavr", "arm-none-eabi-gcc"}
    monkeypatch.setattr(shutil, "which",
                        lambda name, *a, **k: None if name in hidden else real(name, *a, **k))
    monkeypatch.setattr(tools, "_newlib_present", lambda: False)
    job = McuJob.start(out_dir=tmp_path, fou=0.2, grid=3, svg=False)
    costs = job.result()
    assert costs.status is McuStatus.TOOLS_MISSING
    assert costs.missing == ("gcc-avr", "simavr", "gcc-arm-none-eabi",
                             "libnewlib-arm-none-eabi")
    assert list(tmp_path.iterdir()) == []


def test_a_crashed_child_is_a_failure_with_its_exit_status(monkeypatch, tmp_path):
    monkeypatch.setattr(mcu_job, "missing_tools", lambda tools: [])
    monkeypatch.setattr(sys, "executable", "/bin/false")
    with McuJob.start(out_dir=tmp_path, fou=0.2, grid=3, svg=False) as job:
        costs = job.result()
    assert costs.status is McuStatus.FAILED
    assert "exited with 1" in costs.reason


def _fake(monkeypatch, tmp_path: Path, mode: str, extra: str = "-") -> None:
    script = tmp_path / "fake_child.py"
    script.write_text(FAKE_CHILD)
    monkeypatch.setattr(mcu_job, "missing_tools", lambda tools: [])
    monkeypatch.setattr(mcu_job, "_child_argv", lambda: [sys.executable, str(script), mode,
                                                         extra])


@pytest.mark.parametrize("mode, needle", [("draw-then-crash", "exited with 3"),
                                          ("draw-then-fail", "BuildError: late")])
def test_a_figure_drawn_before_a_failure_is_not_published(monkeypatch, tmp_path, mode, needle):
    _fake(monkeypatch, tmp_path, mode)
    out = tmp_path / "staging"
    out.mkdir()
    with McuJob.start(out_dir=out, fou=0.2, grid=3, svg=True) as job:
        costs = job.result()
    assert costs.status is McuStatus.FAILED and needle in costs.reason
    assert costs.figure is None
    assert list(out.iterdir()) == []


def test_a_measured_figure_is_copied_into_the_output(monkeypatch, tmp_path):
    result = tmp_path / "result.json"
    result.write_text(json.dumps({"status": "measured", "table": table_to_json(_table()),
                                  "seconds": 1.5}))
    _fake(monkeypatch, tmp_path, "measured", str(result))
    out = tmp_path / "staging"
    out.mkdir()
    with McuJob.start(out_dir=out, fou=0.2, grid=21, svg=True) as job:
        work = job._work
        costs = job.result()
    assert costs.status is McuStatus.MEASURED and costs.table == _table()
    assert costs.figure == out / "mcu_costs.png"
    assert sorted(p.name for p in out.iterdir()) == ["mcu_costs.png", "mcu_costs.svg"]
    assert (out / "mcu_costs.png").read_bytes() == b"png bytes"
    assert (out / "mcu_costs.svg").read_bytes() == b"svg bytes"
    assert work is not None and not work.exists()  # the job's temporary folder is gone


def test_a_measurement_without_its_svg_is_a_failure_that_publishes_nothing(monkeypatch,
                                                                           tmp_path):
    result = tmp_path / "result.json"
    result.write_text(json.dumps({"status": "measured", "table": table_to_json(_table()),
                                  "seconds": 1.5}))
    _fake(monkeypatch, tmp_path, "measured", str(result))
    out = tmp_path / "staging"
    out.mkdir()
    job = McuJob.start(out_dir=out, fou=0.2, grid=21, svg=False)
    job._svg = True  # the child was not asked for the SVG the parent now expects
    costs = job.result()
    assert costs.status is McuStatus.FAILED and "mcu_costs.svg" in costs.reason
    assert list(out.iterdir()) == []


def _alive(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc")
def test_cancel_stops_the_childs_own_children(monkeypatch, tmp_path):
    pidfile = tmp_path / "grandchild.pid"
    _fake(monkeypatch, tmp_path, "hang", str(pidfile))
    job = McuJob.start(out_dir=tmp_path, fou=0.2, grid=3, svg=False)
    pid = None
    try:
        deadline = time.monotonic() + 60
        while not pidfile.exists():
            assert time.monotonic() < deadline, "the fake child did not start its grandchild"
            time.sleep(0.05)
        pid = int(pidfile.read_text())
        work = job._work
        job.cancel()
        assert work is not None and not work.exists()
        deadline = time.monotonic() + 30  # a liveness bound, not a timing assertion
        while _alive(pid):
            assert time.monotonic() < deadline, "the grandchild outlived cancel()"
            time.sleep(0.05)
    finally:
        job.cancel()
        if pid is not None and _alive(pid):
            os.kill(pid, 9)


def test_the_child_imports_the_installed_package_with_the_numpy_engine(monkeypatch, tmp_path):
    """A local ``it2track/`` or ``numpy.py`` in the current folder must not shadow the installed
    packages in the child (``python -P``); the child runs the numpy engine."""
    (tmp_path / "it2track").mkdir()
    (tmp_path / "it2track" / "__init__.py").write_text(
        "open('shadowed-it2track', 'w').close()\nraise SystemExit('local it2track imported')\n")
    (tmp_path / "numpy.py").write_text(
        "open('shadowed-numpy', 'w').close()\nraise SystemExit('local numpy imported')\n")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(mcu_job, "missing_tools", lambda tools: [])
    # No compilers on PATH: the real child fails fast, in measure_costs, with its own message.
    monkeypatch.setenv("PATH", str(tmp_path / "no-bin"))
    out = tmp_path / "staging"
    out.mkdir()
    with McuJob.start(out_dir=out, fou=0.2, grid=3, svg=False) as job:
        costs = job.result()
    assert costs.status is McuStatus.FAILED
    assert costs.reason.startswith("ToolMissingError"), costs.reason
    assert not (tmp_path / "shadowed-it2track").exists()
    assert not (tmp_path / "shadowed-numpy").exists()
    env = mcu_job._child_env()
    assert env["IT2TRACK_ENGINE"] == "numpy" and env["PATH"] == os.environ["PATH"]
    assert mcu_job._child_argv()[1:] == ["-P", "-m", "it2track.report.mcu_job"]

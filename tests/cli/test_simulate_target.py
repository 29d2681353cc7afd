"""``it2track simulate --target atmega328p``: the controller on the simulated MCU from the CLI.

The options are checked before anything runs; the metrics equal the library's PIL loop; the
trace carries the per-step cycles; a missing toolchain is named by its Debian package."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
from click.testing import CliRunner

import it2track
from it2track.cli.main import main
from it2track.codegen.tools import PIL_TOOLS, missing_tools
from it2track.fuzzy import Reducer
from it2track.tracking import LoopConfig, RunTable, get_trajectory, simulate
from it2track.tracking.pil import PilHeadingController


def _skip_without_pil() -> None:
    missing = missing_tools(PIL_TOOLS)
    if missing:
        pytest.skip(f"needs {', '.join(PIL_TOOLS)}: install the Debian package(s) "
                    f"{', '.join(missing)}")


def _run(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["simulate", *args])
    return result.exit_code, result.output


@pytest.mark.parametrize("args, message", [
    (["--latency", "measured"], "--latency applies to --target atmega328p only"),
    (["--real", "q15"], "--real applies to --target atmega328p only"),
    (["--target", "atmega328p", "--controller", "pd"],
     "--controller pd has none"),
    (["--target", "avr"], "Invalid value for '--target'"),
    (["--target", "atmega328p", "--latency", "late"], "Invalid value for '--latency'"),
])
def test_bad_target_options_are_refused(args, message):
    code, out = _run(*args)
    assert code != 0 and message in out, out
    assert "Traceback" not in out


def test_a_missing_simulator_library_is_named(monkeypatch):
    import it2track.codegen.tools as tools

    monkeypatch.setattr(tools, "_libsimavr_present", lambda: False)
    code, out = _run("--target", "atmega328p", "--duration", "0.1")
    assert code == 1 and "libsimavr-dev" in out and "Traceback" not in out


def test_metrics_equal_the_library_pil_loop(tmp_path, monkeypatch):
    _skip_without_pil()
    monkeypatch.setenv("IT2TRACK_BUILD_DIR", str(tmp_path / "builds"))
    trace_file = tmp_path / "trace.csv"
    code, out = _run("--target", "atmega328p", "--reducer", "km", "--trajectory", "curved",
                     "--duration", "0.5", "--noise-std", "0.1", "--seed", "3", "--json",
                     "--trace", str(trace_file))
    assert code == 0, out
    got = json.loads(out)
    fls = it2track.heading_fls(0.2, reducer=Reducer.KM.value)
    pil = PilHeadingController.from_system(fls, latency="measured",
                                           build_dir=str(tmp_path / "builds"))
    ref = simulate([pil], [get_trajectory("curved")], RunTable(0, 0, 0.1, 3),
                   LoopConfig(duration=0.5))
    for name, value in ref.metrics.items():
        assert got[name] == float(value[0]), name
    cycles = ref["cycles"][0]
    assert got["mcu_cycles_max"] == cycles.max()
    assert got["mcu_cycles_mean"] == cycles.mean()
    assert got["mcu_latency_max_ms"] == cycles.max() / 16e3
    with open(trace_file, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["cycles"]) for r in rows] == cycles.tolist()
    assert np.array_equal([float(r["latency"]) for r in rows], cycles / 16e6)


def test_text_output_names_the_chip_and_the_arithmetic(tmp_path, monkeypatch):
    _skip_without_pil()
    monkeypatch.setenv("IT2TRACK_BUILD_DIR", str(tmp_path / "builds"))
    code, out = _run("--target", "atmega328p", "--real", "q15", "--latency", "period",
                     "--controller", "flc", "--duration", "0.2")
    assert code == 0, out
    assert out.startswith("FLC on the ATmega328P (q15) on straight")
    assert "mcu_cycles_max" in out

"""``it2track simulate`` prints every metric with its unit, and the units are the documented
ones."""

from __future__ import annotations

import json
import re

import pytest
from click.testing import CliRunner

from it2track.cli.main import main
from it2track.tracking import metrics
from it2track.tracking.metrics import METRIC_NAMES, METRIC_UNITS


def _documented_units() -> dict[str, str]:
    """The unit column of the table in the metrics module's docstring."""
    doc = metrics.__doc__ or ""
    table = {}
    for line in doc.splitlines():
        m = re.fullmatch(r"(\S+)\s{2,}.*?\s{2,}(\S.*?)\s*", line)
        if m and m.group(1) in METRIC_NAMES:
            table[m.group(1)] = m.group(2)
    return table


def test_every_metric_has_its_documented_unit():
    documented = _documented_units()
    assert set(documented) == {"IAE", "ITAE", "ISE", "ITSE", "pos_rms", "pos_max", "pos_final",
                               "effort", "u_tv", "sat_time"}
    assert list(METRIC_UNITS) == list(METRIC_NAMES)
    for name in METRIC_NAMES:
        base = name.removesuffix("_meas")  # the table documents the *_meas four once
        assert METRIC_UNITS[name] == documented[base], name


@pytest.mark.parametrize("controller", ["it2", "pd"])
def test_simulate_prints_each_metric_with_its_unit(controller):
    args = ["simulate", "--duration", "0.5", "--controller", controller]
    text = CliRunner().invoke(main, args)
    as_json = CliRunner().invoke(main, [*args, "--json"])
    assert text.exit_code == 0 and as_json.exit_code == 0, text.output + as_json.output
    # stdout only: a first run's stage line ("compiling the simulation kernels...") goes to
    # stderr, which CliRunner's .output interleaves
    values = json.loads(as_json.stdout)
    lines = text.stdout.splitlines()[1:]
    assert len(lines) == len(METRIC_NAMES)
    for line, name in zip(lines, METRIC_NAMES, strict=True):
        key, value, unit = re.fullmatch(r"  (\S+) +(\S+)  (.+)", line).groups()
        assert key == name and unit == METRIC_UNITS[name], line
        assert float(value) == float(f"{values[name]:.6g}"), line
    assert "IAE" in text.output and re.search(r"\n  IAE +\S+  rad s\n", text.output)
    assert re.search(r"\n  effort +\S+  V\^2 s\n", text.output)

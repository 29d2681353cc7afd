"""`it2track reproduce` and the verdicts on the chip: chip_verdicts.csv, the claims.md section
and the page's section come from the same rows; --no-chip leaves no trace of it; a missing
toolchain and --quick say why it did not run."""

from __future__ import annotations

import csv
import json
from dataclasses import replace
from pathlib import Path

import pytest
from click.testing import CliRunner

from it2track.cli.main import main
from it2track.codegen.tools import PIL_TOOLS, missing_tools
from it2track.experiments.sequential import SequentialDesign
from it2track.experiments.study import StudyConfig


def _tiny_study() -> StudyConfig:
    from it2track.tracking import LoopConfig

    return replace(StudyConfig(), loop=LoopConfig(duration=0.5), seeds=2, sweep_seeds=4,
                   noise_levels=(0.0, 0.05), fou_sweep=(0.0, 0.2), pd=None, tuning=None,
                   robustness=None, trajectories=("curved",),
                   verdicts=SequentialDesign(first=4, batch=2, cap=4, resamples=200))


def _run(out: Path, *args: str) -> tuple[str, dict, str, str]:
    result = CliRunner().invoke(main, ["reproduce", "--no-progress", "--no-mcu", "--no-svg",
                                       *args, "--out", str(out)], prog_name="it2track")
    assert result.exit_code == 0, result.output
    manifest = json.loads((out / "manifest.json").read_text())
    return (result.output, manifest, (out / "claims.md").read_text(),
            (out / "report.html").read_text())


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    import it2track.cli.reproduce as cli

    root = tmp_path_factory.mktemp("onmcu")
    out = {}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(cli, "_default_study_config", _tiny_study)
        mp.setenv("IT2TRACK_BUILD_DIR", str(root / "builds"))
        if not missing_tools(PIL_TOOLS):
            out["chip"] = (root / "chip", *_run(root / "chip", "--chip"))
        out["off"] = (root / "off", *_run(root / "off", "--no-chip"))
    return out


def test_the_csv_the_claims_and_the_page_carry_the_same_rows(runs):
    if "chip" not in runs:
        pytest.skip(f"needs {', '.join(PIL_TOOLS)}: install the Debian package(s) "
                    f"{', '.join(missing_tools(PIL_TOOLS))}")
    out, terminal, manifest, claims, page = runs["chip"]
    with open(out / "chip_verdicts.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    # 3 reducers x 3 claims x (all + the path) x 2 levels
    assert len(rows) == 3 * 3 * 2 * 2
    assert {r["reducer"] for r in rows} == {"exhaustive", "eiasc", "km"}
    with open(out / "verdicts.csv", newline="") as fh:
        verdicts = {(r["claim"], r["path"], r["sigma"]): r for r in csv.DictReader(fh)}
    for r in rows:
        host = verdicts[(r["claim"], r["path"], r["sigma"])]
        assert r["host_status"] == host["status"]
        assert r["survives"] == str(r["status"] == host["status"] and r["settled"] == "True")
    for r in rows:
        if r["path"] == "all" and r["sigma"] == "0.05" and r["host_settled"] == "True":
            kept = r["survives"] == "True"
            changed = not kept and r["settled"] == "True"
            line = (f"chip {r['reducer']} {r['claim']}: {int(kept)} of 1 settled study levels "
                    f"keep their status ({int(changed)} changed, "
                    f"{int(r['settled'] != 'True')} unsettled on the chip)")
            assert line in terminal, line
    assert "## The verdicts on the chip" in claims and "match: every output equals" in claims
    assert '<h2 id="chip">' in page and "bit for bit" in page
    assert manifest["chip"]["replay_matches"] is True
    assert manifest["chip"]["config"] == {"first": 2, "batch": 1, "cap": 2, "points": 65,
                                          "replay": 1}
    assert "chip_verdicts.csv" in manifest["files"]


def test_no_chip_leaves_no_output(runs):
    out, terminal, manifest, claims, page = runs["off"]
    assert not (out / "chip_verdicts.csv").exists()
    assert "on the chip" not in claims and "on the chip" not in page
    assert 'id="chip"' not in page and "chip_verdicts" not in page + claims
    assert not [line for line in terminal.splitlines() if line.strip().startswith("chip")]
    assert manifest["chip"] is None
    assert manifest["command"].endswith("--no-chip --no-progress")


def test_a_missing_toolchain_is_named(monkeypatch, capsys):
    from it2track.cli.reproduce_chip import _chip, _chip_lines, _chip_provenance
    from it2track.codegen import tools
    from it2track.report.chip import chip_markdown
    from it2track.report.html.chip import chip_section

    monkeypatch.setattr(tools, "missing_tools", lambda names: ["libsimavr-dev"])
    got = _chip(_tiny_study(), None, None, quick=False)
    why = "the toolchain is missing: install the Debian package(s) libsimavr-dev"
    assert got.result is None and got.reason == why
    assert why in capsys.readouterr().err
    assert why in chip_markdown(got) and why in str(chip_section(got))
    assert _chip_lines(got) == [f"chip: not judged ({why})"]
    assert _chip_provenance(got) == {"skipped": why}


def test_quick_skips_unless_asked():
    from it2track.cli.reproduce_chip import QUICK_CHIP, _chip

    got = _chip(_tiny_study(), None, None, quick=True)
    assert got.result is None and "skipped with --quick" in got.reason
    assert _chip(_tiny_study(), None, False, quick=True) is None
    assert QUICK_CHIP["cap"] == QUICK_CHIP["first"]  # no extension round in a smoke run


def test_the_help_names_every_package_the_chip_needs():
    from it2track.cli.reproduce import reproduce
    from it2track.codegen.tools import TOOL_PACKAGES

    (option,) = [p for p in reproduce.params if p.name == "chip"]
    text = " ".join((option.help or "").split())
    for tool in PIL_TOOLS:
        assert TOOL_PACKAGES[tool] in text, tool

"""`it2track reproduce --quick` end to end: every output exists, parses and is reproducible."""

import csv
import json
from html.parser import HTMLParser

import numpy as np
import pytest
from click.testing import CliRunner

from it2track.cli.main import main
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.experiments.study import StudyConfig
from it2track.tracking import METRIC_NAMES, RunTable, get_trajectory, simulate

EXPECTED = ("metrics.csv", "summary.csv", "verdicts.csv", "claims.md", "report.html",
            "manifest.json", "robustness.csv", "sensitivity.csv")
SMOKE = "smoke run — not evidence"


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("quick")
    result = CliRunner().invoke(main, ["reproduce", "--quick", "--no-progress", "--out",
                                       str(out)])
    assert result.exit_code == 0, result.output
    return out, result.output


def test_every_output_exists_and_parses(quick_run):
    out, stdout = quick_run
    for name in EXPECTED:
        assert (out / name).is_file(), name
    assert not [p for p in out.iterdir() if p.name.startswith(".reproduce-")], "staging left"
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["config"]["study"]["seeds"] == 6
    assert set(EXPECTED) <= set(manifest["files"])
    assert manifest["versions"]["numpy"] == np.__version__
    for name in manifest["files"]:
        assert (out / name).is_file(), f"manifest lists missing {name}"
    pngs = sorted(out.glob("*.png"))
    assert pngs and not list(out.glob("*.svg")), "--quick writes PNG figures only"
    with (out / "metrics.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert set(METRIC_NAMES) <= set(rows[0])
    assert {r["experiment"] for r in rows} == {"paper", "noise", "fou"}
    with (out / "summary.csv").open() as fh:
        summary = list(csv.DictReader(fh))
    assert {"mean", "ci_low", "ci_high", "win_rate"} <= set(summary[0])
    claims = (out / "claims.md").read_text()
    for cid in ("C1", "C2", "C3", "D1", "D2", "D3"):
        assert f"| {cid} |" in claims
        assert f"{cid}:" in stdout
    for section in ("## Verdicts per trajectory", "## Robustness to the paper's open modelling",
                    "### Global sensitivity", "## Tuned against tuned",
                    "## How likely were the paper's single-run figures?", "docs/model.md",
                    "Holm-Bonferroni"):
        assert section in claims, section
    with (out / "robustness.csv").open() as fh:
        rob = list(csv.DictReader(fh))
    assert {"claim", "choice", "value", "sigma", "trajectory", "verdict", "n", "estimate",
            "ci_low", "ci_high", "p_holm", "outcome"} <= set(rob[0])
    assert {r["choice"] for r in rob} >= {"baseline", "half_track", "noise_reading"}
    zero = [r for r in summary if r["noise_std"] == "0.0"]
    assert zero and all(r["n"] == "1" and r["ci_low"] == "" for r in zero)
    HTMLParser().feed((out / "report.html").read_text())


def test_quick_is_marked_as_a_smoke_run_wherever_a_verdict_appears(quick_run):
    out, stdout = quick_run
    lines = stdout.splitlines()
    verdicts = [ln for ln in lines if ln.strip()[:3] in {f"{c}:" for c in
                                                          ("C1", "C2", "C3", "D1", "D2", "D3")}]
    assert len(verdicts) == 6 and all(ln.endswith(f"({SMOKE})") for ln in verdicts)
    assert any(ln.strip().startswith(SMOKE) for ln in lines)  # said before the verdicts too
    claims = (out / "claims.md").read_text()
    assert claims.startswith(f"# Claims of the paper, tested ({SMOKE})")
    table = [ln for ln in claims.splitlines() if ln.startswith("| C") or ln.startswith("| D")]
    assert table and all(SMOKE in ln for ln in table[:6])
    for section in claims.split("\n## ")[1:]:
        if section.startswith(("C1:", "C2:", "D1:")):  # every claim's own verdict line
            assert f"({SMOKE})**" in section, section[:40]
    page = (out / "report.html").read_text()
    assert 'id="smoke"' in page and "Verdicts at a glance (smoke run — not evidence)" in page
    assert page.count(SMOKE) >= 12  # the banner, the subtitle, every verdict cell


def test_verdicts_csv_has_a_row_per_claim_path_and_level(quick_run):
    out, _ = quick_run
    with (out / "verdicts.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    keys = {(r["claim"], r["path"], float(r["sigma"])) for r in rows}
    levels = (0.0, 0.05, 0.2)
    paths = ("all", "straight", "curved", "sinusoidal")
    for claim in ("C1", "C2", "D1", "D2", "D3"):
        assert {(claim, p, s) for p in paths for s in levels} <= keys, claim
    assert {("C3", "all", s) for s in levels} <= keys
    for r in rows:
        rep = float(r["replication"])
        assert 0.0 <= rep <= 1.0
        assert (r["settled"] == "True") == (rep >= 0.95)
        if float(r["sigma"]) == 0.0:
            assert r["status"] == "deterministic" and r["n"] == "1" and rep == 1.0
        else:
            assert 4 <= int(r["n"]) <= 8  # --quick's first round and cap


def test_metrics_agree_with_a_direct_closed_loop_call(quick_run):
    out, _ = quick_run
    with (out / "metrics.csv").open() as fh:
        rows = [r for r in csv.DictReader(fh)
                if r["experiment"] == "paper" and r["controller"] == "IT2FLC FoU 0.2"
                and r["trajectory"] == "sinusoidal" and r["seed"] == "3"]
    assert len(rows) == 1
    row = rows[0]
    from it2track.cli.reproduce import _quick

    cfg = _quick(StudyConfig())
    controller = ControllerSpec(kind=ControllerKind.IT2, fou=0.2).build()
    trace = simulate([controller], [get_trajectory("sinusoidal")],
                     RunTable(0, 0, float(row["noise_std"]), 3), cfg.loop)
    for name in METRIC_NAMES:
        assert float(row[name]) == trace.metrics[name][0], name


def test_rerun_reproduces_metrics_byte_for_byte(quick_run, tmp_path):
    out, _ = quick_run
    result = CliRunner().invoke(main, ["reproduce", "--quick", "--no-progress", "--out",
                                       str(tmp_path)])
    assert result.exit_code == 0, result.output
    for name in ("metrics.csv", "summary.csv", "claims.md"):
        assert (tmp_path / name).read_bytes() == (out / name).read_bytes(), name


def test_bad_config_is_reported_without_output(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[study]\nseeds = -1\n")
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["reproduce", "--config", str(bad), "--out", str(out)])
    assert result.exit_code != 0
    assert "seeds" in result.output and str(bad) in result.output
    assert not out.exists() or not any(out.iterdir())


def test_publish_replaces_a_previous_run_without_leftovers(tmp_path):
    import hashlib

    from it2track.cli.outdir import _publish

    def sha(text):
        return hashlib.sha256(text.encode()).hexdigest()

    out = tmp_path / "out"
    out.mkdir()
    (out / "old_figure.png").write_text("old")  # the previous run's, unchanged: removed
    (out / "users_notes.txt").write_text("keep me")  # not ours: never touched
    (out / "metrics.csv").write_text("old")
    (out / "manifest.json").write_text(json.dumps({
        "files": ["old_figure.png", "metrics.csv", "manifest.json"],
        "sha256": {"old_figure.png": sha("old"), "metrics.csv": sha("old")}}))
    staging = tmp_path / "staging"
    staging.mkdir()
    (staging / "metrics.csv").write_text("new")
    (staging / "manifest.json").write_text(json.dumps({"files": ["metrics.csv",
                                                                 "manifest.json"]}))
    _publish(staging, out)
    assert sorted(p.name for p in out.iterdir()) == ["manifest.json", "metrics.csv",
                                                     "users_notes.txt"]
    assert (out / "metrics.csv").read_text() == "new"
    assert json.loads((out / "manifest.json").read_text())["sha256"] == {"metrics.csv": sha("new")}


def test_manifest_command_comes_from_the_parsed_options(quick_run):
    out, _ = quick_run
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["command"].startswith("main reproduce") or manifest["command"].startswith(
        "it2track reproduce")
    assert "--quick" in manifest["command"] and f"--out {out}" in manifest["command"]


def test_quick_skips_the_microcontroller_measurement(quick_run):
    out, _ = quick_run
    page = (out / "report.html").read_text()
    assert '<a href="#mcu">' in page and "Not measured (skipped with --quick)" in page
    assert json.loads((out / "manifest.json").read_text())["mcu"]["status"] == "skipped"
    assert not any(p.name.startswith("mcu_costs") for p in out.iterdir())


def test_simulate_rejects_a_zero_noise_rate():
    result = CliRunner().invoke(main, ["simulate", "--noise-rate", "0"])
    assert result.exit_code != 0 and "--noise-rate" in result.output


def test_fis_eval_takes_negative_values(tmp_path):
    import it2track

    path = tmp_path / "h.toml"
    it2track.save(it2track.heading_fls(0.2), path)
    result = CliRunner().invoke(main, ["fis", "eval", str(path), "0.3", "-0.1"])
    assert result.exit_code == 0, result.output
    u = float(result.output.split("=")[1].split()[0])
    assert u == pytest.approx(it2track.heading_fls(0.2)(0.3, -0.1), rel=1e-9)


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--controller", "pd", "--fou", "0.3"], "--fou does not apply to --controller pd"),
        (["--controller", "flc", "--kp", "3"], "--kp does not apply"),
        (["--controller", "t1-matched", "--reducer", "km"], "--reducer does not apply"),
        (["--noise-power", "0.1", "--noise-std", "0.2"], "not both"),
    ],
)
def test_simulate_rejects_options_it_would_ignore(args, needle):
    result = CliRunner().invoke(main, ["simulate", "--duration", "0.1", *args])
    assert result.exit_code != 0 and needle in result.output, result.output


def test_reproduce_rejects_workers_and_scheduler_together(tmp_path):
    result = CliRunner().invoke(main, ["reproduce", "--quick", "--workers", "2", "--scheduler",
                                       "tcp://127.0.0.1:1", "--out", str(tmp_path / "o")])
    assert result.exit_code != 0 and "not both" in result.output, result.output
    assert not (tmp_path / "o").exists()


def test_publish_never_removes_directories(tmp_path):
    from click import ClickException

    from it2track.cli.outdir import _publish

    out = tmp_path / "out"
    (out / "metrics.csv").mkdir(parents=True)  # a folder where a result goes
    (out / "metrics.csv" / "inside.txt").write_text("the user's")
    (out / "old_dir").mkdir()
    (out / "manifest.json").write_text(json.dumps({"files": ["old_dir", "manifest.json"]}))
    staging = tmp_path / "staging"
    staging.mkdir()
    (staging / "metrics.csv").write_text("new")
    (staging / "manifest.json").write_text(json.dumps({"files": ["metrics.csv"]}))
    with pytest.raises(ClickException, match=r"metrics\.csv exists and is not a regular file"):
        _publish(staging, out)
    assert (out / "metrics.csv" / "inside.txt").read_text() == "the user's"
    assert (out / "old_dir").is_dir() and (out / "manifest.json").is_file()


def test_reproduce_with_a_local_worker_writes_the_same_numbers(quick_run, tmp_path):
    out, _ = quick_run
    result = CliRunner().invoke(main, ["reproduce", "--quick", "--no-progress", "--workers", "1",
                                       "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    for name in ("metrics.csv", "summary.csv", "verdicts.csv", "claims.md"):
        assert (tmp_path / name).read_bytes() == (out / name).read_bytes(), name
    manifest = json.loads((tmp_path / "manifest.json").read_text())
    from it2track.cli.reproduce import _quick
    from it2track.experiments.study import study_run_count

    # The plan's runs, plus the sequential design's: every noise-sweep row beyond the first
    # round's seeds is a run of its own.
    quick = _quick(StudyConfig())
    with (tmp_path / "metrics.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    extra = sum(r["experiment"] == "noise" and int(r["seed"]) >= quick.sweep_seeds
                for r in rows)
    assert extra > 0
    assert manifest["simulations"] == study_run_count(quick) + extra
    assert manifest["rows"] == len(rows)


def _tiny_study():
    from dataclasses import replace

    from it2track.tracking import LoopConfig

    cfg = StudyConfig()
    return replace(cfg, loop=LoopConfig(duration=0.5), seeds=2, sweep_seeds=2,
                   noise_levels=(0.0, 0.05), fou_sweep=(0.0, 0.2), pd=None, tuning=None,
                   robustness=None)


def test_default_command_line_is_recorded_exactly_and_reruns_byte_for_byte(
        tmp_path, monkeypatch):
    # The default command line (no --quick), with the study made tiny through the hook that
    # supplies the default config: every option is parsed exactly as in a real default run.
    import shlex

    import it2track.cli.reproduce as cli

    monkeypatch.setattr(cli, "_default_study_config", _tiny_study)
    first = tmp_path / "first"
    result = CliRunner().invoke(main, ["reproduce", "--out", str(first)], prog_name="it2track")
    assert result.exit_code == 0, result.output
    command = json.loads((first / "manifest.json").read_text())["command"]
    assert command == f"it2track reproduce --out {shlex.quote(str(first))}"
    # Rerun the recorded command (into another folder): the same metrics, byte for byte.
    second = tmp_path / "second dir"
    args = shlex.split(command)[1:]
    args[args.index("--out") + 1] = str(second)
    result = CliRunner().invoke(main, args, prog_name="it2track")
    assert result.exit_code == 0, result.output
    assert (second / "metrics.csv").read_bytes() == (first / "metrics.csv").read_bytes()
    recorded = json.loads((second / "manifest.json").read_text())["command"]
    assert recorded == f"it2track reproduce --out {shlex.quote(str(second))}"


def test_recorded_command_keeps_given_options_in_declaration_order(tmp_path, monkeypatch):
    import it2track.cli.reproduce as cli

    monkeypatch.setattr(cli, "_default_study_config", _tiny_study)
    out = tmp_path / "o"
    # --workers 0 is the default value but was given: it is part of the command as given.
    result = CliRunner().invoke(main, ["reproduce", "--no-progress", "--seeds", "3", "--workers",
                                       "0", "--out", str(out)], prog_name="it2track")
    assert result.exit_code == 0, result.output
    command = json.loads((out / "manifest.json").read_text())["command"]
    assert command == f"it2track reproduce --out {out} --seeds 3 --workers 0 --no-progress"


@pytest.mark.parametrize("name", ["robustness.csv", "sensitivity.csv"])
def test_a_folder_in_the_way_of_any_result_is_refused_before_simulating(tmp_path, monkeypatch,
                                                                        name):
    # Not only the five fixed names: every file this run will write is checked up front,
    # instead of failing at publish time after the whole run.
    import it2track.experiments.study as study

    def no_run(*args, **kwargs):  # pragma: no cover - reached only with the bug
        raise AssertionError("the study ran")

    monkeypatch.setattr(study, "run_study", no_run)
    (tmp_path / name).mkdir()
    result = CliRunner().invoke(main, ["reproduce", "--quick", "--no-progress", "--out",
                                       str(tmp_path)])
    assert result.exit_code != 0
    assert f"{tmp_path / name} exists and is not a regular file" in result.output, result.output
    assert "nothing was simulated" in result.output

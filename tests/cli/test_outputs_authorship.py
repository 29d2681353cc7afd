"""The rule of authorship on the command line: ``simulate --trace``, ``fis convert``,
``surface --out`` and ``optimize --out`` replace a file only if it2track can prove it wrote it
(its SHA-256 recorded beside it or in the run's sealed manifest), or with ``--force``; the
refusal comes before any work, names the option and the file, and writes nothing."""

from __future__ import annotations

import json
import os
import textwrap
from pathlib import Path

import pytest
from click.testing import CliRunner

import it2track
from it2track.authorship import SEAL_KEY, read_sealed_json, sha256_file
from it2track.cli.main import main
from it2track.io import dumps

REFUSED = "exists and it2track cannot prove it wrote it"


def run(*args: object):
    return CliRunner().invoke(main, [str(a) for a in args])


def flat(text: str) -> str:
    return " ".join(text.split())


def unwritable_folder(tmp_path: Path) -> Path:
    """A folder this process cannot create files in (read-only mode, or a kernel folder when
    running as root, where modes do not apply)."""
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    candidates = [folder, Path("/sys/kernel")]
    for c in candidates:
        try:
            fd = os.open(c / ".it2track-probe", os.O_WRONLY | os.O_CREAT | os.O_EXCL)
        except OSError:
            return c
        os.close(fd)
        os.unlink(c / ".it2track-probe")
    pytest.skip("no folder here refuses writes to this user (root without /sys)")


def test_simulate_trace_replaces_only_its_own_file(tmp_path: Path) -> None:
    trace = tmp_path / "run.csv"
    sim = ("simulate", "--duration", "0.1", "--trace", trace)
    first = run(*sim)
    assert first.exit_code == 0, first.output
    data = trace.read_bytes()
    assert data.startswith(b"t,x,y,") and len(data.splitlines()) == 12  # header + 11 instants
    assert (tmp_path / "run.csv.sha256").read_text() == f"{sha256_file(trace)}  run.csv\n"
    again = run(*sim, "--seed", "3")  # its own file, unchanged: replaced
    assert again.exit_code == 0, again.output
    assert trace.read_bytes() != data
    trace.write_bytes(trace.read_bytes() + b"# my note\n")
    edited = trace.read_bytes()
    refused = run(*sim)
    assert refused.exit_code == 1 and "Traceback" not in refused.output
    assert f"--trace {trace}: {trace} {REFUSED}" in flat(refused.output)
    assert "--force" in refused.output and trace.read_bytes() == edited
    forced = run(*sim, "--force")
    assert forced.exit_code == 0 and trace.read_bytes() != edited


def test_simulate_never_replaces_a_users_file(tmp_path: Path) -> None:
    trace = tmp_path / "mine.csv"
    trace.write_text("the user's")
    result = run("simulate", "--duration", "0.1", "--trace", trace)
    assert result.exit_code == 1 and REFUSED in flat(result.output)
    assert trace.read_text() == "the user's" and not (tmp_path / "mine.csv.sha256").exists()
    result = run("simulate", "--duration", "0.1", "--force")
    assert result.exit_code == 1 and "--force applies only with --trace" in result.output


def test_fis_convert_replaces_only_its_own_file(tmp_path: Path) -> None:
    source = tmp_path / "h.toml"
    it2track.save(it2track.heading_fls(0.2), source)
    target = tmp_path / "h.fis"
    assert run("fis", "convert", source, target).exit_code == 0
    assert target.read_text() == dumps(it2track.load(source), "fis")
    assert run("fis", "convert", source, target).exit_code == 0  # ours: replaced
    target.write_text(target.read_text().replace("Name=", "Name= ", 1))
    edited = target.read_text()
    result = run("fis", "convert", source, target)
    assert result.exit_code == 1 and f"TARGET {target}: {target} {REFUSED}" in flat(
        result.output)
    assert target.read_text() == edited
    assert run("fis", "convert", source, target, "--force").exit_code == 0
    assert target.read_text() != edited


def test_fis_convert_into_an_unwritable_folder_names_the_target(tmp_path: Path) -> None:
    source = tmp_path / "h.toml"
    it2track.save(it2track.heading_fls(0.2), source)
    folder = unwritable_folder(tmp_path)
    target = folder / "x.fis"
    result = run("fis", "convert", source, target)
    message = flat(result.output)
    assert result.exit_code == 1 and "Traceback" not in result.output
    assert f"TARGET {target}" in message and ".it2track-" not in message, message
    assert not target.exists()


def test_surface_replaces_only_its_own_file(tmp_path: Path) -> None:
    source = tmp_path / "h.toml"
    it2track.save(it2track.heading_fls(0.2), source)
    image = tmp_path / "s.png"
    cmd = ("surface", source, "--points", "5", "--out", image)
    assert run(*cmd).exit_code == 0
    assert image.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "s.png.sha256").read_text() == f"{sha256_file(image)}  s.png\n"
    assert run(*cmd, "--style", "contour").exit_code == 0
    image.write_bytes(b"the user's picture")
    result = run(*cmd)
    assert result.exit_code == 1 and f"--out {image}: {image} {REFUSED}" in flat(result.output)
    assert image.read_bytes() == b"the user's picture"
    assert run(*cmd, "--force").exit_code == 0
    assert image.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_surface_into_an_unwritable_folder_names_the_target(tmp_path: Path) -> None:
    source = tmp_path / "h.toml"
    it2track.save(it2track.heading_fls(0.2), source)
    image = unwritable_folder(tmp_path) / "x.png"
    result = run("surface", source, "--points", "5", "--out", image)
    message = flat(result.output)
    assert result.exit_code == 1 and f"--out {image}" in message and ".it2track-" not in message
    assert not image.exists()


@pytest.mark.parametrize(("fix", "needle"), [
    ("e=nan", "'e=nan': the value 'nan' of e must be a finite number"),
    ("e=-inf", "'e=-inf': the value '-inf' of e must be a finite number"),
    ("e=abc", "'e=abc': the value 'abc' of e is not a number"),
    ("e", "'e': expected NAME=VALUE"),
    ("=1", "'=1': expected NAME=VALUE"),
])
def test_surface_fix_names_the_value(tmp_path: Path, fix: str, needle: str) -> None:
    source = tmp_path / "h.toml"
    it2track.save(it2track.heading_fls(0.2), source)
    result = run("surface", source, "--out", tmp_path / "s.png", "--fix", fix)
    assert result.exit_code == 2 and "--fix" in result.output
    assert needle in flat(result.output), result.output
    assert not (tmp_path / "s.png").exists()


OPTIMIZE = """
[optimize]
objective = "ISE"
train_seeds = 2
holdout_seeds = { start = 100, count = 2 }
noise_std = 0.05
trajectories = ["straight"]

[optimize.symmetric]
grid = 3
maxiter = 2

[optimize.asymmetric]
enabled = false

[simulation]
duration = 0.5
"""


def test_optimize_replaces_only_what_its_sealed_manifest_lists(tmp_path: Path,
                                                              monkeypatch) -> None:
    config = tmp_path / "opt.toml"
    config.write_text(textwrap.dedent(OPTIMIZE))
    out = tmp_path / "out"
    cmd = ("optimize", "--config", config, "--out", out, "--no-progress")
    first = run(*cmd)
    assert first.exit_code == 0, first.output
    manifest = read_sealed_json(out / "optimize.json")
    assert manifest is not None and SEAL_KEY in manifest
    assert manifest["sha256"] == {"optimize.md": sha256_file(out / "optimize.md"),
                                  "convergence.png": sha256_file(out / "convergence.png")}
    assert run(*cmd).exit_code == 0  # all ours: replaced

    import it2track.experiments.optimize as optimize

    def no_run(*args: object, **kwargs: object) -> None:  # pragma: no cover - only with a bug
        raise AssertionError("the optimisation ran")

    monkeypatch.setattr(optimize, "run_optimization", no_run)
    for name, edit in (("optimize.md", b"my notes"), ("convergence.png", b"my figure"),
                       ("optimize.json", None)):
        case = tmp_path / name
        case.mkdir()
        for f in ("optimize.md", "convergence.png", "optimize.json"):
            (case / f).write_bytes((out / f).read_bytes())
        if edit is None:
            data = json.loads((case / name).read_text())
            data["objective"] = "IAE"  # edited by hand: the seal no longer matches
            (case / name).write_text(json.dumps(data))
        else:
            (case / name).write_bytes(edit)
        before = {f: (case / f).read_bytes() for f in os.listdir(case)}
        result = run("optimize", "--config", config, "--out", case, "--no-progress")
        assert result.exit_code == 1, result.output
        assert f"--out {case}: {case / name} {REFUSED}" in flat(result.output)
        assert {f: (case / f).read_bytes() for f in os.listdir(case)} == before

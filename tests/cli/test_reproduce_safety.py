"""`reproduce` never deletes or clobbers what it cannot prove it wrote; it cleans up after
itself, also after a kill, and refuses an unusable --out before simulating anything."""

from __future__ import annotations

import hashlib
import json
import os
import signal
import socket
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from click import ClickException
from click.testing import CliRunner

from it2track.authorship import SEAL_KEY, seal_json
from it2track.cli import outdir as cli_main
from it2track.cli.main import main
from it2track.cli.outdir import _discard_staging, _make_staging, _publish

DEAD_PID = 4999999  # above Linux's largest pid_max (2**22): never a live process


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _staging(tmp_path: Path, files: dict[str, str]) -> Path:
    staging = tmp_path / "staging"
    staging.mkdir()
    for name, text in files.items():
        (staging / name).write_text(text)
    (staging / "manifest.json").write_text(json.dumps({"files": [*files, "manifest.json"]}))
    return staging


def test_a_foreign_manifest_deletes_nothing(tmp_path: Path) -> None:
    """Even sealed (anyone can compute a seal), a manifest naming folders, paths outside --out
    and files whose bytes are not the listed ones makes nothing disappear."""
    out = tmp_path / "out"
    (out / "folder").mkdir(parents=True)
    (out / "folder" / "data.txt").write_text("the user's data")
    (out / "notes.txt").write_text("the user's notes")
    (out / "edited.png").write_text("edited by the user")
    (tmp_path / "outside.txt").write_text("outside --out")
    (out / "manifest.json").write_text(json.dumps(seal_json({
        "files": ["notes.txt", "folder", "edited.png", "../outside.txt", "/etc/hostname",
                  ".", "..", "", 7, "manifest.json"],
        "sha256": {"folder": "0" * 64, "edited.png": _sha(b"what we wrote"),
                   "../outside.txt": _sha(b"outside --out")},
    })))
    _publish(_staging(tmp_path, {"metrics.csv": "new"}), out)
    assert (out / "folder" / "data.txt").read_text() == "the user's data"
    assert (out / "notes.txt").read_text() == "the user's notes"
    assert (out / "edited.png").read_text() == "edited by the user"
    assert (tmp_path / "outside.txt").read_text() == "outside --out"
    assert (out / "metrics.csv").read_text() == "new"


def test_a_manifest_that_is_not_ours_is_refused_and_with_force_deletes_nothing(
    tmp_path: Path,
) -> None:
    """A manifest.json without a valid seal (the user's own, one edited by hand, one of an
    older it2track, not JSON) is a file this program cannot prove it wrote: the publish
    stops, naming it; with --force it is replaced, and still nothing it lists is deleted."""
    listed = {"files": ["notes.txt"], "sha256": {"notes.txt": _sha(b"keep")}}
    edited = seal_json(listed)
    edited["files"] = ["notes.txt", "claims.md"]
    contents = ("not json", "[1, 2]", json.dumps({"files": "notes.txt"}), json.dumps(listed),
                json.dumps(edited), json.dumps({**listed, SEAL_KEY: "0" * 64}))
    for k, content in enumerate(contents):
        case = tmp_path / f"case{k}"
        out = case / "out"
        out.mkdir(parents=True)
        (out / "notes.txt").write_text("keep")
        (out / "manifest.json").write_text(content)
        staged = _staging(case, {"claims.md": "x"})
        with pytest.raises(ClickException, match=r"manifest\.json exists and it2track cannot "
                           r"prove it wrote it.*--force"):
            _publish(staged, out)
        assert (out / "manifest.json").read_text() == content
        assert not (out / "claims.md").exists()
        _publish(staged, out, force=True)
        assert (out / "notes.txt").read_text() == "keep"
        assert json.loads((out / "manifest.json").read_text())["sha256"]["claims.md"]


def test_a_users_file_of_a_result_name_is_refused_before_any_work(tmp_path: Path) -> None:
    """The issue's cases: the user's own claims.md, or own manifest.json, in --out (no previous
    run): refused by _make_staging -- before any simulation -- naming the file; a file the
    previous run wrote and nobody changed is replaced; an edited one is refused."""
    for name in ("claims.md", "manifest.json", "fou_comparison.png"):
        out = tmp_path / name / "out"
        out.mkdir(parents=True)
        (out / name).write_text("the user's")
        with pytest.raises(ClickException, match=rf"--out {out}: {out / name} exists and "
                           "it2track cannot prove it wrote it"):
            _make_staging(str(out), ["fou_comparison.png"])
        assert sorted(p.name for p in out.iterdir()) == [name]  # no staging folder either
        _discard_staging(_make_staging(str(out), ["fou_comparison.png"], force=True))
    out = tmp_path / "ours"
    out.mkdir()
    _publish(_staging(tmp_path, {"claims.md": "ours", "metrics.csv": "ours"}), out)
    _discard_staging(_make_staging(str(out)))  # all proven by the sealed manifest
    (out / "claims.md").write_text("ours, edited")
    with pytest.raises(ClickException, match=r"claims\.md exists and it2track cannot prove"):
        _make_staging(str(out))


def test_two_runs_in_a_row_remove_only_the_first_runs_unchanged_files(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    first = tmp_path / "first"
    first.mkdir()
    for name in ("a.png", "b.png", "metrics.csv"):
        (first / name).write_text(f"first {name}")
    (first / "manifest.json").write_text(json.dumps({"files": ["a.png", "b.png",
                                                              "metrics.csv", "manifest.json"]}))
    _publish(first, out)
    (out / "b.png").write_text("the user annotated this figure")
    second = tmp_path / "second"
    second.mkdir()
    (second / "metrics.csv").write_text("second")
    (second / "manifest.json").write_text(json.dumps({"files": ["metrics.csv",
                                                               "manifest.json"]}))
    _publish(second, out)
    assert not (out / "a.png").exists()  # ours, unchanged, no longer produced: removed
    assert (out / "b.png").read_text() == "the user annotated this figure"  # changed: kept
    assert (out / "metrics.csv").read_text() == "second"


def test_symlinks_and_devices_in_the_way_stop_the_publish(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    (out / "metrics.csv").symlink_to(victim)
    with pytest.raises(ClickException, match="not a regular file"):
        _publish(_staging(tmp_path, {"metrics.csv": "new"}), out)
    assert victim.read_text() == "precious" and (out / "metrics.csv").is_symlink()


def _plant_staging(out: Path, name: str, owner: dict | None, extra: bool = False) -> Path:
    root = out / name
    (root / "files").mkdir(parents=True)
    (root / "files" / ".metrics.csv.it2track-1-0123456789ab.tmp").write_text("half")
    (root / "files" / "claims.md").write_text("done")
    if owner is not None:
        (root / "owner.json").write_text(json.dumps(owner))
    if extra:
        (root / "files" / "sub").mkdir()
    return root


def test_only_stale_staging_folders_that_are_provably_ours_are_removed(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    me = {"program": "it2track reproduce", "host": socket.gethostname()}
    stale = _plant_staging(out, ".reproduce-stale", {**me, "pid": DEAD_PID, "start": 1})
    live = _plant_staging(out, ".reproduce-live",
                          {**me, "pid": os.getpid(), "start": cli_main._process_start(os.getpid())})
    reused = _plant_staging(out, ".reproduce-reused", {**me, "pid": os.getpid(), "start": -5})
    other_host = _plant_staging(out, ".reproduce-remote",
                                {**me, "host": "another-machine", "pid": DEAD_PID})
    no_owner = _plant_staging(out, ".reproduce-old", None)  # an older version's, or a user's
    odd = _plant_staging(out, ".reproduce-odd", {**me, "pid": DEAD_PID}, extra=True)
    not_ours = _plant_staging(out, ".reproduce-mine", {"program": "something else",
                                                       "pid": DEAD_PID})
    link_target = tmp_path / "elsewhere"
    link_target.mkdir()
    (link_target / "keep.txt").write_text("keep")
    (out / ".reproduce-link").symlink_to(link_target)
    staging = _make_staging(str(out))
    try:
        assert staging.is_dir() and staging.name == "files"
        assert not stale.exists() and not reused.exists()  # dead owner / pid reused
        for kept in (live, other_host, no_owner, odd, not_ours):
            assert (kept / "files" / "claims.md").read_text() == "done", kept.name
        assert (link_target / "keep.txt").read_text() == "keep"
    finally:
        _discard_staging(staging)
    assert not staging.parent.exists()


HOLDER = """
import sys, time
from it2track.cli.outdir import _discard_staging, _make_staging
staging = _make_staging(sys.argv[1])
try:
    (staging / "half.csv").write_text("half written")
    print(staging, flush=True)
    time.sleep(60)
finally:
    _discard_staging(staging)
"""


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM], ids=["SIGKILL", "SIGTERM"])
def test_a_killed_run_leaves_no_staging_folder_for_good(tmp_path: Path, sig: int) -> None:
    out = tmp_path / "out"
    script = tmp_path / "holder.py"
    script.write_text(textwrap.dedent(HOLDER))
    proc = subprocess.Popen([sys.executable, str(script), str(out)], stdout=subprocess.PIPE,
                            text=True)
    try:
        line = proc.stdout.readline() if proc.stdout else ""
        staging = Path(line.strip())
        assert staging.is_dir(), line
        proc.send_signal(sig)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:  # pragma: no cover
            proc.kill()
            proc.wait()
        if proc.stdout:
            proc.stdout.close()
    if sig == signal.SIGTERM:  # unwinds: the run removes its own folder
        assert proc.returncode == 128 + signal.SIGTERM
        assert not staging.parent.exists()
    else:  # killed outright: the next run removes it
        assert staging.parent.exists()
        deadline = time.monotonic() + 10
        while cli_main._process_start(proc.pid) is not None and time.monotonic() < deadline:
            time.sleep(0.01)  # pragma: no cover - the zombie is reaped by wait()
        new = _make_staging(str(out))
        try:
            assert not staging.parent.exists()
        finally:
            _discard_staging(new)
    assert [p.name for p in out.iterdir()] == []


def test_an_unusable_out_is_refused_before_any_simulation(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import it2track.experiments.study as study

    def no_simulation(*args: object, **kwargs: object) -> None:  # pragma: no cover
        raise AssertionError("simulated although --out is unusable")

    monkeypatch.setattr(study, "run_study", no_simulation)
    a_file = tmp_path / "file.txt"
    a_file.write_text("x")
    runner = CliRunner()
    result = runner.invoke(main, ["reproduce", "--quick", "--out", str(a_file / "sub")])
    assert result.exit_code == 1 and "cannot create the output folder" in result.output
    assert str(a_file / "sub") in result.output and "Traceback" not in result.output
    result = runner.invoke(main, ["reproduce", "--quick", "--out", ""])
    assert result.exit_code != 0 and "--out" in result.output
    (tmp_path / "o" / "report.html").mkdir(parents=True)
    result = runner.invoke(main, ["reproduce", "--quick", "--out", str(tmp_path / "o")])
    assert result.exit_code == 1
    assert "report.html exists and is a directory, not a regular file" in result.output

    def read_only(*args: object, **kwargs: object) -> str:
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(cli_main.tempfile, "mkdtemp", read_only)
    result = runner.invoke(main, ["reproduce", "--quick", "--out", str(tmp_path / "ro")])
    assert result.exit_code == 1, result.output
    assert "cannot write into the output folder" in result.output
    assert "Permission denied" in result.output and "nothing was simulated" in result.output

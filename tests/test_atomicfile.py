"""it2track.atomicfile: durable, all-or-nothing writes that never clobber what is not ours."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from it2track import atomicfile
from it2track.atomicfile import (
    NotRegularFileError,
    atomic_write_bytes,
    atomic_write_text,
    check_replaceable,
    remove_stale_temporaries,
)

DEAD_PID = 4999999  # above Linux's largest pid_max (2**22): never a live process


def test_data_are_fsynced_before_the_rename_and_the_directory_after(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "out.bin"
    data = b"x" * 100_000
    events: list[tuple[str, str, bytes | None]] = []
    real_fsync, real_replace = os.fsync, os.replace

    def fsync(fd: int) -> None:
        path = os.readlink(f"/proc/self/fd/{fd}")
        content = Path(path).read_bytes() if os.path.isfile(path) else None
        events.append(("fsync", path, content))  # what is on disk when fsync is asked
        real_fsync(fd)

    def replace(src: str, dst: str) -> None:
        events.append(("replace", os.fspath(src), None))
        real_replace(src, dst)

    monkeypatch.setattr(atomicfile.os, "fsync", fsync)
    monkeypatch.setattr(atomicfile.os, "replace", replace)
    atomic_write_bytes(target, data)
    kinds = [e[0] for e in events]
    assert "replace" in kinds, "the file was not renamed into place"
    r = kinds.index("replace")
    tmp = events[r][1]
    assert Path(tmp).parent == tmp_path and Path(tmp).name != target.name
    synced = [e for e in events[:r] if e[0] == "fsync" and e[1] == tmp]
    assert synced, "no fsync of the temporary file before the rename"
    assert synced[-1][2] == data, "fsync before the data were flushed"
    assert ("fsync", str(tmp_path), None) in events[r + 1 :], "directory not fsynced"
    assert target.read_bytes() == data


def test_the_target_keeps_its_old_content_until_the_write_completes(tmp_path: Path) -> None:
    target = tmp_path / "t.txt"
    target.write_text("old")
    with atomicfile.atomic_open(target, "w") as fh:
        fh.write("new content")
        fh.flush()
        assert target.read_text() == "old"  # not written in place
        (tmp,) = [p for p in tmp_path.iterdir() if p.name != "t.txt"]
        assert tmp.name.startswith(".t.txt.it2track-") and tmp.name.endswith(".tmp")
    assert target.read_text() == "new content"
    assert [p.name for p in tmp_path.iterdir()] == ["t.txt"]


WRITER = """
import sys, time
from pathlib import Path
from it2track.atomicfile import atomic_open
target, marker = Path(sys.argv[1]), Path(sys.argv[2])
with atomic_open(target, "wb") as fh:
    fh.write(b"N" * 1_000_000)
    fh.flush()
    marker.write_text("half written")
    time.sleep(60)
    fh.write(b"N" * 1_000_000)
"""


def test_a_writer_killed_mid_write_leaves_the_old_file_intact(tmp_path: Path) -> None:
    target = tmp_path / "data.bin"
    target.write_bytes(b"OLD" * 1000)
    marker = tmp_path / "marker"
    script = tmp_path / "writer.py"
    script.write_text(textwrap.dedent(WRITER))
    proc = subprocess.Popen([sys.executable, str(script), str(target), str(marker)])
    try:
        deadline = time.monotonic() + 60
        while not marker.exists():
            assert proc.poll() is None, "the writer exited early"
            assert time.monotonic() < deadline, "the writer never reached mid-write"
            time.sleep(0.01)
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:  # pragma: no cover
            proc.kill()
    assert target.read_bytes() == b"OLD" * 1000
    leftovers = [p for p in tmp_path.iterdir() if p.name.startswith(".data.bin.it2track-")]
    assert len(leftovers) == 1 and leftovers[0].stat().st_size == 1_000_000
    # The dead writer's temporary is recognisably ours: cleanup removes it, and only it.
    assert remove_stale_temporaries(tmp_path) == leftovers
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data.bin", "marker", "writer.py"]


def test_a_planted_symlink_at_the_temporary_name_is_never_followed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    target = tmp_path / "out.txt"
    monkeypatch.setattr(atomicfile.secrets, "token_hex", lambda n: "0" * (2 * n))
    planted = tmp_path / f".out.txt.it2track-{os.getpid()}-000000000000.tmp"
    planted.symlink_to(victim)
    with pytest.raises(FileExistsError):
        atomic_write_text(target, "attacker-controlled write")
    assert victim.read_text() == "precious"
    assert planted.is_symlink() and not target.exists()


def test_the_convergence_plot_never_follows_a_planted_symlink(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("matplotlib")
    from it2track.report.optimize_plot import plot_convergence

    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    out = tmp_path / "convergence.png"
    # The name the old code wrote to (predictable: pid only) and the new one made predictable.
    (tmp_path / f".convergence.png.{os.getpid()}.tmp").symlink_to(victim)
    monkeypatch.setattr(atomicfile.secrets, "token_hex", lambda n: "0" * (2 * n))
    planted = tmp_path / f".convergence.png.it2track-{os.getpid()}-000000000000.tmp"
    planted.symlink_to(victim)
    history = [{"phase": "symmetric-grid", "objective": 1.0}]
    with pytest.raises(FileExistsError):
        plot_convergence(history, out)
    assert victim.read_text() == "precious" and not out.exists()
    planted.unlink()
    plot_convergence(history, out)  # with the name free, it writes normally
    assert out.read_bytes().startswith(b"\x89PNG") and victim.read_text() == "precious"


@pytest.mark.parametrize("kind", ["directory", "fifo", "symlink", "dangling-symlink"])
def test_what_is_not_a_regular_file_is_never_replaced(tmp_path: Path, kind: str) -> None:
    target = tmp_path / "target"
    other = tmp_path / "other.txt"
    other.write_text("keep")
    if kind == "directory":
        target.mkdir()
    elif kind == "fifo":
        os.mkfifo(target)
    elif kind == "symlink":
        target.symlink_to(other)
    else:
        target.symlink_to(tmp_path / "nowhere")
    before = os.lstat(target)
    with pytest.raises(NotRegularFileError, match="not a regular file") as info:
        atomic_write_text(target, "data")
    assert info.value.filename == str(target)
    after = os.lstat(target)
    assert (after.st_ino, after.st_mode) == (before.st_ino, before.st_mode)
    assert other.read_text() == "keep" and not (tmp_path / "nowhere").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["other.txt", "target"]


def test_device_nodes_are_refused_before_anything_is_written() -> None:
    for device in ("/dev/full", "/dev/null"):
        if os.path.exists(device):
            with pytest.raises(NotRegularFileError, match="character device"):
                check_replaceable(device)
    with pytest.raises(ValueError, match="empty"):
        check_replaceable("")


def test_stale_temporary_cleanup_touches_only_ours_of_dead_writers(tmp_path: Path) -> None:
    names = {
        "dead": f".a.csv.it2track-{DEAD_PID}-0123456789ab.tmp",
        "live": f".a.csv.it2track-{os.getpid()}-0123456789ab.tmp",
        "other-target": f".b.csv.it2track-{DEAD_PID}-0123456789ab.tmp",
        "user": ".a.csv.tmp",
        "user2": ".notes.1234.tmp",
    }
    for name in names.values():
        (tmp_path / name).write_text("x")
    link = tmp_path / f".c.csv.it2track-{DEAD_PID}-0123456789ab.tmp"
    link.symlink_to(tmp_path / names["user"])
    removed = remove_stale_temporaries(tmp_path, {"a.csv", "c.csv"})
    assert removed == [tmp_path / names["dead"]]
    assert link.is_symlink()
    assert remove_stale_temporaries(tmp_path) == [tmp_path / names["other-target"]]
    left = {p.name for p in tmp_path.iterdir()}
    assert left == {names["live"], names["user"], names["user2"], link.name}

"""it2track.atomicfile: durable, all-or-nothing writes that never clobber what is not ours."""

from __future__ import annotations

import errno
import os
import signal
import socket
import stat
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from it2track import atomicfile
from it2track.atomicfile import (
    _TEMP_RE,
    NotRegularFileError,
    _kind,
    _pid_alive,
    atomic_write_bytes,
    atomic_write_text,
    check_can_create_in,
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


@pytest.mark.parametrize(("mode", "words"), [
    (stat.S_IFDIR, "a directory"), (stat.S_IFLNK, "a symbolic link"),
    (stat.S_IFCHR, "a character device"), (stat.S_IFBLK, "a block device"),
    (stat.S_IFIFO, "a FIFO (named pipe)"), (stat.S_IFSOCK, "a socket"),
    (0, "not a regular file"),
])
def test_every_kind_of_file_is_named_in_words(mode: int, words: str) -> None:
    assert _kind(mode | 0o644) == words


def test_the_refusal_names_the_kind_and_is_a_file_exists_error(tmp_path: Path) -> None:
    sock = socket.socket(socket.AF_UNIX)
    try:
        sock.bind(str(tmp_path / "s"))
        with pytest.raises(NotRegularFileError) as info:
            check_replaceable(tmp_path / "s")
    finally:
        sock.close()
    assert info.value.errno == errno.EEXIST and info.value.filename == str(tmp_path / "s")
    assert info.value.strerror == ("exists and is a socket, not a regular file; refusing to "
                                   "replace it")
    with pytest.raises(ValueError) as empty:
        check_replaceable("")
    assert str(empty.value) == "the output path is empty; give a file name"


def test_text_is_written_as_utf8_with_newline_line_ends(tmp_path: Path) -> None:
    target = tmp_path / "t.txt"
    assert atomic_write_text(target, "é\nx\r\n") == target
    assert target.read_bytes() == b"\xc3\xa9\nx\r\n"
    assert atomic_write_text(str(target), "") == target and target.read_bytes() == b""


def test_text_is_utf8_whatever_the_locale(tmp_path: Path) -> None:
    """In the C locale (no coercion, no UTF-8 mode) open()'s default encoding is ASCII: the
    encoding must be given, not inherited. (Also called in this process, so that a mutation
    tool that selects the tests calling a function selects this one for atomic_write_text.)"""
    atomic_write_text(tmp_path / "here.txt", "é")
    target = tmp_path / "é.txt"
    env = {**os.environ, "LC_ALL": "C", "LANG": "C", "PYTHONCOERCECLOCALE": "0",
           "PYTHONUTF8": "0", "PYTHONPATH": os.pathsep.join(sys.path)}
    code = ("import sys; from it2track.atomicfile import atomic_write_text; "
            "atomic_write_text(sys.argv[1], '\\u00e9')")
    proc = subprocess.run([sys.executable, "-c", code, str(target)], env=env,
                          capture_output=True, text=True, check=False)
    assert proc.returncode == 0, proc.stderr
    assert target.read_bytes() == b"\xc3\xa9"


def test_a_live_process_is_alive_and_left_alone() -> None:
    sleeper = ("import signal, time\n"
               "for s in (signal.SIGHUP, signal.SIGINT, signal.SIGTERM, signal.SIGUSR1):\n"
               "    signal.signal(s, signal.SIG_DFL)\n"
               "print('ready', flush=True)\n"
               "time.sleep(60)\n")
    child = subprocess.Popen([sys.executable, "-c", sleeper], stdout=subprocess.PIPE)
    try:
        assert child.stdout is not None and child.stdout.readline() == b"ready\n"
        assert _pid_alive(child.pid) and _pid_alive(os.getpid())
        time.sleep(0.2)
        assert child.poll() is None  # probed with signal 0, not sent a real signal
    finally:
        child.kill()
        child.wait()
        assert child.stdout is not None
        child.stdout.close()
    assert not _pid_alive(DEAD_PID)


def test_pid_alive_when_the_probe_is_refused_or_fails(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(pid: int, sig: int) -> None:
        raise PermissionError(errno.EPERM, "not yours")

    def fail(pid: int, sig: int) -> None:
        raise OSError(errno.EINVAL, "bad pid")

    monkeypatch.setattr(os, "kill", refuse)
    assert _pid_alive(DEAD_PID) is True  # exists, someone else's
    monkeypatch.setattr(os, "kill", fail)
    assert _pid_alive(DEAD_PID) is False


def test_cleanup_goes_on_past_entries_it_keeps(tmp_path: Path,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    """Whatever order the folder lists them in: a kept entry (a user's file, a link, a live
    writer's temporary) never stops the cleanup of the dead writers' ones after it."""
    live = tmp_path / f".a.csv.it2track-{os.getpid()}-0123456789ab.tmp"
    link = tmp_path / f".a.csv.it2track-{DEAD_PID}-00000000000a.tmp"
    dead = tmp_path / f".a.csv.it2track-{DEAD_PID}-00000000000b.tmp"
    user = tmp_path / ".a.csv.tmp"
    for path in (live, dead, user):
        path.write_text("x")
    link.symlink_to(user)
    real = os.scandir
    order = [user.name, link.name, live.name, dead.name]

    def ordered(path: os.PathLike[str]) -> list[os.DirEntry[str]]:
        return sorted(real(path), key=lambda e: order.index(e.name))

    monkeypatch.setattr(os, "scandir", ordered)
    assert remove_stale_temporaries(tmp_path) == [dead]
    assert live.exists() and user.exists() and link.is_symlink()


def test_cleanup_of_a_temporary_removed_meanwhile_is_no_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    dead = tmp_path / f".a.csv.it2track-{DEAD_PID}-0123456789ab.tmp"
    dead.write_text("x")

    def gone(path: object) -> None:
        raise FileNotFoundError(errno.ENOENT, "removed by another cleanup", str(path))

    monkeypatch.setattr(os, "unlink", gone)
    assert remove_stale_temporaries(tmp_path) == []


def test_check_can_create_in(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    opened: list[tuple[str, int, int]] = []
    real_open = os.open

    def spy(path: str, flags: int, mode: int = 0o777) -> int:
        opened.append((os.fspath(path), flags, mode))
        return real_open(path, flags, mode)

    monkeypatch.setattr(os, "open", spy)
    check_can_create_in(tmp_path)
    monkeypatch.undo()
    assert list(tmp_path.iterdir()) == []  # the probe is gone
    ((probe, flags, mode),) = opened
    assert Path(probe).parent == tmp_path and mode == 0o600
    m = _TEMP_RE.match(Path(probe).name)
    assert m is not None and m["target"] == "probe" and int(m["pid"]) == os.getpid()
    want = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC
    assert flags == want
    missing = tmp_path / "missing"
    with pytest.raises(OSError) as info:
        check_can_create_in(missing)
    assert info.value.errno == errno.ENOENT and info.value.filename == str(missing)
    assert info.value.strerror == os.strerror(errno.ENOENT)

"""it2track.cli.outdir, function by function: the messages to the letter, the proofs the
publish trusts, the staging folder's owner record, and every entry a cleanup or a publish
must keep whatever order the folder lists it in (the mutation tests of docs/guide/mutation.md
ask each of these)."""

from __future__ import annotations

import errno
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from click import ClickException

from it2track import atomicfile, authorship
from it2track.authorship import seal_json, sha256_bytes
from it2track.cli import outdir
from it2track.cli.outdir import (
    _discard_staging,
    _make_staging,
    _owner_alive,
    _process_start,
    _publish,
    _remove_stale_staging,
    _terminate_cleanly,
    check_output_file,
    check_outputs,
    write_output_file,
)

DEAD_PID = 4999999  # above Linux's largest pid_max (2**22): never a live process
#: A child that dies of any of the signals 1-15 (whatever its parent ignores) once ready.
SLEEPER = ("import signal, time\n"
           "for s in range(1, 16):\n"
           "    if s not in (signal.SIGKILL, signal.SIGSTOP):\n"
           "        signal.signal(s, signal.SIG_DFL)\n"
           "print('ready', flush=True)\n"
           "time.sleep(60)\n")
ME = {"program": "it2track reproduce", "host": socket.gethostname()}


def fail_message(call, *args, **kwargs) -> str:
    with pytest.raises(ClickException) as info:
        call(*args, **kwargs)
    return info.value.message


def never(path: Path) -> bool:
    return False


def ordered_scandir(monkeypatch: pytest.MonkeyPatch, order: list[str]) -> None:
    """os.scandir listing the names in ``order`` (the others after them)."""
    real = os.scandir

    def scandir(path: os.PathLike[str]) -> list[os.DirEntry[str]]:
        entries = list(real(path))
        rank = {n: i for i, n in enumerate(order)}
        return sorted(entries, key=lambda e: rank.get(e.name, len(order)))

    monkeypatch.setattr(os, "scandir", scandir)


# -- check_outputs, check_output_file, write_output_file ----------------------------------------


def test_check_outputs_message_and_defaults(tmp_path: Path) -> None:
    target = tmp_path / "t.csv"
    (tmp_path / "t.csv.sha256").write_text("notes\n")
    check_outputs([target], option="--trace t.csv", force=False, proof=never)  # no sidecars
    message = fail_message(check_outputs, [target], option="--trace t.csv", force=False,
                           proof=never, sidecars=True)
    assert message == (f"--trace t.csv: {tmp_path / 't.csv.sha256'} exists and is not a "
                       "checksum file it2track wrote for t.csv; move it away, choose another "
                       "name, or pass --force to replace it; nothing was done")
    target.write_text("mine")
    message = fail_message(check_outputs, [target], option="--out o", force=False,
                           proof=never, outcome="nothing was simulated")
    assert message.startswith(f"--out o: {target} exists and it2track cannot prove")
    assert message.endswith("; nothing was simulated")


def test_check_output_file_messages(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    assert fail_message(check_output_file, "", "--trace", force=False) == (
        "--trace '' is empty: give a file name")
    missing = tmp_path / "no" / "x.csv"
    assert fail_message(check_output_file, str(missing), "--trace", force=False) == (
        f"--trace {missing}: the folder {missing.parent} does not exist")
    (tmp_path / "x.csv.sha256").write_text("notes\n")
    message = fail_message(check_output_file, str(tmp_path / "x.csv"), "--trace", force=False)
    assert "x.csv.sha256 exists and is not a checksum file" in message
    (tmp_path / "x.csv.sha256").unlink()
    assert check_output_file(str(tmp_path / "x.csv"), "--trace", force=False) == (
        tmp_path / "x.csv")
    mine = tmp_path / "mine.csv"
    mine.write_text("the user's")
    assert fail_message(check_output_file, str(mine), "--trace", force=False) == (
        f"--trace {mine}: {mine} exists and it2track cannot prove it wrote it (no SHA-256 it "
        "recorded when writing matches the file); move it away, choose another name, or pass "
        "--force to replace it; nothing was done")
    assert check_output_file(str(mine), "--trace", force=True) == mine
    write_output_file(mine, b"ours", "--trace")
    assert check_output_file(str(mine), "--trace", force=False) == mine  # proven beside it

    def refuse(directory: object) -> None:
        raise OSError(errno.EACCES, "Permission denied", str(directory))

    monkeypatch.setattr(atomicfile, "check_can_create_in", refuse)
    assert fail_message(check_output_file, str(tmp_path / "y.csv"), "--trace",
                        force=False) == (f"--trace {tmp_path / 'y.csv'}: cannot write into the "
                                         f"folder {tmp_path}: Permission denied; choose another "
                                         "place")

    def bare(directory: object) -> None:
        raise OSError

    monkeypatch.setattr(atomicfile, "check_can_create_in", bare)
    assert fail_message(check_output_file, str(tmp_path / "y.csv"), "--trace",
                        force=False).endswith(": OSError; choose another place")


def test_write_output_file_names_the_option_and_target(tmp_path: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "t.csv"
    data = b"t\n0\n"
    write_output_file(target, data, "--trace")
    assert target.read_bytes() == data
    assert (tmp_path / "t.csv.sha256").read_text() == f"{sha256_bytes(data)}  t.csv\n"

    def full(path: object, data: bytes) -> None:
        raise OSError(errno.ENOSPC, "No space left on device", ".t.csv.it2track-1-x.tmp")

    monkeypatch.setattr(authorship, "write_with_sidecar", full)
    assert fail_message(write_output_file, target, b"x", "--trace") == (
        f"cannot write --trace {target}: No space left on device")

    def bare(path: object, data: bytes) -> None:
        raise OSError

    monkeypatch.setattr(authorship, "write_with_sidecar", bare)
    assert fail_message(write_output_file, target, b"x", "--trace") == (
        f"cannot write --trace {target}: OSError")


# -- the owner of a staging folder ------------------------------------------------------------


def test_process_start_reads_the_start_time_even_of_an_odd_name(tmp_path: Path) -> None:
    """/proc/PID/stat holds the command name in parentheses, and a name may itself hold
    ') ' and spaces: the start time (field 22) is counted from the last ')'. Checked against
    the clock: boot time + start ticks / CLK_TCK is when the child started."""
    odd = tmp_path / "a) b c ("
    odd.symlink_to(os.path.realpath(sys.executable))
    before = time.time()
    child = subprocess.Popen([str(odd), "-c", "import time; time.sleep(30)"])
    try:
        time.sleep(0.05)
        ticks = _process_start(child.pid)
        name = Path(f"/proc/{child.pid}/stat").read_text()
    finally:
        child.kill()
        child.wait()
    assert "a) b c (" in name  # the kernel kept the odd name
    btime = next(int(line.split()[1]) for line in Path("/proc/stat").read_text().splitlines()
                 if line.startswith("btime "))
    started = btime + ticks / os.sysconf("SC_CLK_TCK")
    assert before - 2.0 <= started <= time.time() + 2.0
    assert _process_start(DEAD_PID) is None


def test_owner_alive(monkeypatch: pytest.MonkeyPatch) -> None:
    for pid in (True, "12", None, 1.5, 0, -5):  # cannot tell: never ours to remove
        assert _owner_alive({**ME, "pid": pid}) is True, pid
    assert _owner_alive({**ME, "host": "elsewhere", "pid": DEAD_PID}) is True
    assert _owner_alive({**ME, "pid": DEAD_PID}) is False
    me = os.getpid()
    assert _owner_alive({**ME, "pid": me}) is True  # no start time recorded
    assert _owner_alive({**ME, "pid": me, "start": _process_start(me)}) is True
    assert _owner_alive({**ME, "pid": me, "start": -1}) is False  # the pid was reused

    def refuse(pid: int, sig: int) -> None:
        raise PermissionError(errno.EPERM, "not yours")

    monkeypatch.setattr(os, "kill", refuse)
    assert _owner_alive({**ME, "pid": DEAD_PID}) is True

    def exists(pid: int, sig: int) -> None:
        pass

    monkeypatch.setattr(os, "kill", exists)  # pid 1 is a process like any other:
    assert _owner_alive({**ME, "pid": 1, "start": -1}) is False  # its start time decides


def test_owner_alive_probes_with_signal_0() -> None:
    child = subprocess.Popen([sys.executable, "-c", SLEEPER], stdout=subprocess.PIPE)
    try:
        assert child.stdout is not None and child.stdout.readline() == b"ready\n"
        assert _owner_alive({**ME, "pid": child.pid}) is True
        time.sleep(0.2)
        assert child.poll() is None  # not sent a real signal
    finally:
        child.kill()
        child.wait()
        assert child.stdout is not None
        child.stdout.close()


# -- cleaning up after killed runs --------------------------------------------------------------


def plant(out: Path, name: str, owner: object, *, files: dict[str, str] | None = None,
          owner_text: str | None = None) -> Path:
    root = out / name
    root.mkdir(parents=True)
    if owner_text is not None:
        (root / "owner.json").write_text(owner_text)
    elif owner is not None:
        (root / "owner.json").write_text(json.dumps(owner))
    if files is not None:
        (root / "files").mkdir()
        for n, text in files.items():
            (root / "files" / n).write_text(text)
    return root


def test_stale_staging_cleanup_goes_on_past_what_it_keeps(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    out.mkdir()
    dead = {**ME, "pid": DEAD_PID}
    elsewhere = tmp_path / "elsewhere"
    plant(tmp_path, "elsewhere", dead, files={"a.csv": "x"})
    (out / ".reproduce-link").symlink_to(elsewhere)
    kept = {
        "not-json": plant(out, ".reproduce-a", None, owner_text="{"),
        "a-list": plant(out, ".reproduce-b", None, owner_text="[1]"),
        "not-ours": plant(out, ".reproduce-c", {**dead, "program": "other"}, files={}),
        "alive": plant(out, ".reproduce-d", {**ME, "pid": os.getpid()}, files={}),
        "more": plant(out, ".reproduce-e", dead, files={"a.csv": "x"}),
        "files-is-a-file": plant(out, ".reproduce-f", dead),
        "files-is-a-link": plant(out, ".reproduce-g", dead),
        "link-inside": plant(out, ".reproduce-h", dead, files={}),
        "owner-is-a-link": plant(out, ".reproduce-i", None),
    }
    (kept["more"] / "extra.txt").write_text("the user's")
    (kept["files-is-a-file"] / "files").write_text("a file")
    (kept["files-is-a-link"] / "files").symlink_to(elsewhere / "files")
    (kept["link-inside"] / "files" / "x.csv").symlink_to(elsewhere / "files" / "a.csv")
    (kept["owner-is-a-link"] / "owner.json").symlink_to(elsewhere / "owner.json")
    removed = [plant(out, ".reproduce-y", dead, files={"claims.md": "done"}),
               plant(out, ".reproduce-z", dead)]  # owner.json alone, no files/
    ordered_scandir(monkeypatch, [".reproduce-link", *sorted(p.name for p in kept.values()),
                                  ".reproduce-y", ".reproduce-z"])
    _remove_stale_staging(out)
    for why, root in kept.items():
        assert root.exists(), why
    assert (elsewhere / "files" / "a.csv").read_text() == "x"
    assert not any(r.exists() for r in removed)
    err = capsys.readouterr()
    assert f"note: left {kept['more']} alone (holds more than a run's files)\n" in err.err
    assert "note:" not in err.out


def test_a_staging_folder_that_cannot_be_removed_is_named(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    root = plant(tmp_path, ".reproduce-x", {**ME, "pid": DEAD_PID}, files={})

    def busy(path: object) -> None:
        raise OSError(errno.EBUSY, "Device or resource busy", str(path))

    monkeypatch.setattr(os, "rmdir", busy)
    _remove_stale_staging(tmp_path)
    err = capsys.readouterr()
    assert err.err == f"note: could not remove the stale {root}: Device or resource busy\n"
    assert err.out == ""


# -- the staging folder -------------------------------------------------------------------------


def test_make_staging_records_its_owner(tmp_path: Path) -> None:
    out = tmp_path / "a" / "b" / "out"  # created with its parents
    before = time.time()
    staging = _make_staging(str(out))
    try:
        root = staging.parent
        assert staging.name == "files" and staging.is_dir() and list(staging.iterdir()) == []
        assert root.parent == out and root.name.startswith(".reproduce-")
        text = (root / "owner.json").read_text()
        assert text.endswith("}\n") and text.count("\n") == 1
        owner = json.loads(text)
        assert set(owner) == {"program", "host", "pid", "start", "created"}
        assert owner["program"] == "it2track reproduce"
        assert owner["host"] == socket.gethostname() and owner["pid"] == os.getpid()
        assert owner["start"] == _process_start(os.getpid()) is not None
        assert before <= owner["created"] <= time.time()
        assert sorted(p.name for p in root.iterdir()) == ["files", "owner.json"]
    finally:
        _discard_staging(staging)
    assert not root.exists() and out.is_dir()


def test_make_staging_messages(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    assert fail_message(_make_staging, "") == "--out '' is empty: give an output folder"
    a_file = tmp_path / "file"
    a_file.write_text("x")
    assert fail_message(_make_staging, str(a_file / "sub")) == (
        f"cannot create the output folder --out {a_file / 'sub'}: Not a directory; nothing "
        "was simulated")
    (tmp_path / "o").mkdir()
    (tmp_path / "o" / "claims.md").write_text("mine")
    assert fail_message(_make_staging, str(tmp_path / "o")).endswith(
        "--force to replace it; nothing was simulated")

    def refuse(*args: object, **kwargs: object) -> str:
        raise OSError(errno.EACCES, "Permission denied")

    monkeypatch.setattr(outdir.tempfile, "mkdtemp", refuse)
    assert fail_message(_make_staging, str(tmp_path / "p")) == (
        f"cannot write into the output folder --out {tmp_path / 'p'}: Permission denied; "
        "nothing was simulated")


def test_a_failed_owner_record_removes_the_staging_root(tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[tuple[object, dict[str, object]]] = []
    real_rmtree = shutil.rmtree

    def rmtree(path: object, **kwargs: object) -> None:
        calls.append((path, kwargs))
        real_rmtree(path, **kwargs)  # type: ignore[arg-type]

    def full(path: object, text: str) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(shutil, "rmtree", rmtree)
    monkeypatch.setattr(atomicfile, "atomic_write_text", full)
    out = tmp_path / "out"
    assert fail_message(_make_staging, str(out)) == (
        f"cannot write into the output folder --out {out}: No space left on device; nothing "
        "was simulated")
    assert list(out.iterdir()) == []
    ((path, kwargs),) = calls
    assert Path(str(path)).parent == out and kwargs == {"ignore_errors": True}


def test_discard_staging_never_raises_over_the_error_being_reported(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    staging = _make_staging(str(tmp_path))
    calls: list[tuple[object, dict[str, object]]] = []
    real_rmtree = shutil.rmtree

    def rmtree(path: object, **kwargs: object) -> None:
        calls.append((path, kwargs))
        real_rmtree(path, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(shutil, "rmtree", rmtree)
    _discard_staging(staging)
    assert calls == [(staging.parent, {"ignore_errors": True})]


@pytest.fixture
def default_sigterm() -> object:
    """SIGTERM at its default for the test (whatever the test runner set), restored after."""
    old = signal.signal(signal.SIGTERM, signal.SIG_DFL)
    yield
    signal.signal(signal.SIGTERM, old)


def test_sigterm_unwinds_like_ctrl_c_and_is_restored(tmp_path: Path,
                                                     default_sigterm: None) -> None:
    staging = _make_staging(str(tmp_path))
    handler = signal.getsignal(signal.SIGTERM)
    try:
        assert callable(handler)
        with pytest.raises(SystemExit) as info:
            handler(signal.SIGTERM, None)  # type: ignore[operator]
        assert info.value.code == 128 + signal.SIGTERM == 143
    finally:
        _discard_staging(staging)
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL


def test_a_handler_of_the_callers_is_left_in_place() -> None:
    def mine(signum: int, frame: object) -> None:  # pragma: no cover - never delivered
        pass

    old = signal.signal(signal.SIGTERM, mine)
    try:
        _terminate_cleanly()
        assert signal.getsignal(signal.SIGTERM) is mine
    finally:
        signal.signal(signal.SIGTERM, old)


def test_terminate_cleanly_outside_the_main_thread_does_nothing(default_sigterm: None) -> None:
    errors: list[BaseException] = []

    def run() -> None:
        try:
            _terminate_cleanly()
        except BaseException as exc:  # pragma: no cover - reached only with the bug
            errors.append(exc)

    thread = threading.Thread(target=run)
    thread.start()
    thread.join()
    assert errors == [] and signal.getsignal(signal.SIGTERM) is signal.SIG_DFL


# -- publishing ---------------------------------------------------------------------------------


def staged(tmp_path: Path, files: dict[str, str], name: str = "staging") -> Path:
    staging = tmp_path / name
    staging.mkdir()
    for n, text in files.items():
        (staging / n).write_text(text)
    (staging / "manifest.json").write_text(json.dumps({"files": [*files, "manifest.json"]}))
    return staging


def sealed_manifest(out: Path, files: object, digests: object) -> None:
    (out / "manifest.json").write_text(json.dumps(seal_json({"files": files,
                                                             "sha256": digests})))


def sha(text: str) -> str:
    return sha256_bytes(text.encode())


def test_publish_refusal_message(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "claims.md").write_text("mine")
    message = fail_message(_publish, staged(tmp_path, {"claims.md": "new"}), out)
    assert message.startswith(f"--out {out}: {out / 'claims.md'} exists and it2track cannot")
    assert message.endswith("; nothing was published")
    assert (out / "claims.md").read_text() == "mine"


def test_publish_removes_only_plain_names_it_can_prove(tmp_path: Path) -> None:
    """Listed with a matching digest but not a plain name of --out (a path, a backslash, a
    hidden file): kept; a plain stale file after them: removed, whatever the order."""
    out = tmp_path / "out"
    (out / "sub").mkdir(parents=True)
    names = {"sub/x.png": "s", "a\\b.png": "b", ".hidden.png": "h", "old.png": "o",
             "metrics.csv": "m"}
    for n, text in names.items():
        (out / n).write_text(text)
    listed = ["gone.png", "sub/x.png", "a\\b.png", ".hidden.png", "metrics.csv", "old.png"]
    sealed_manifest(out, listed, {n: sha(t) for n, t in names.items()})
    _publish(staged(tmp_path, {"metrics.csv": "new"}), out)
    assert sorted(str(p.relative_to(out)) for p in out.rglob("*")) == [
        ".hidden.png", "a\\b.png", "manifest.json", "metrics.csv", "sub", "sub/x.png"]


def test_publish_never_iterates_a_listing_that_is_not_a_list(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    for n in ("a", "b"):
        (out / n).write_text(n)
    sealed_manifest(out, "ab", {"a": sha("a"), "b": sha("b")})
    _publish(staged(tmp_path, {"c.csv": "c"}), out)
    assert (out / "a").exists() and (out / "b").exists()


def test_publish_with_digests_that_are_not_a_table_keeps_everything(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "old.png").write_text("o")
    sealed_manifest(out, ["old.png"], ["old.png"])
    _publish(staged(tmp_path, {"c.csv": "c"}), out)
    assert (out / "old.png").read_text() == "o"


def test_publish_with_force_notes_only_files_it_keeps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    out.mkdir()
    for n in ("claims.md", "a.png", "b.png"):
        (out / n).write_text("edited by the user")
    sealed_manifest(out, ["claims.md", "a.png", "b.png"],
                    {"claims.md": sha("ours"), "a.png": sha("ours"), "b.png": sha("ours")})
    _publish(staged(tmp_path, {"claims.md": "new"}), out, force=True)
    assert (out / "claims.md").read_text() == "new"
    err = capsys.readouterr()
    assert err.err == (f"note: kept 2 file(s) in {out} that the previous manifest lists but "
                       "that this run cannot prove it wrote (changed since, or no checksum): "
                       "a.png, b.png\n")
    assert err.out == ""


def test_publish_keeps_a_file_it_cannot_read(tmp_path: Path,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "old.png").write_text("o")
    sealed_manifest(out, ["old.png"], {"old.png": sha("o")})
    real = authorship.sha256_file

    def unreadable(path: os.PathLike[str]) -> str:
        if Path(path).name == "old.png":
            raise PermissionError(errno.EACCES, "Permission denied", str(path))
        return real(path)

    monkeypatch.setattr(authorship, "sha256_file", unreadable)
    _publish(staged(tmp_path, {"c.csv": "c"}), out)
    assert (out / "old.png").read_text() == "o"


def test_publish_tolerates_a_stale_file_removed_meanwhile(tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "old.png").write_text("o")
    sealed_manifest(out, ["old.png"], {"old.png": sha("o")})
    real = authorship.sha256_file

    def hash_then_vanish(path: os.PathLike[str]) -> str:
        digest = real(path)
        if Path(path).name == "old.png":
            os.unlink(path)  # another cleanup got there first
        return digest

    monkeypatch.setattr(authorship, "sha256_file", hash_then_vanish)
    _publish(staged(tmp_path, {"c.csv": "c"}), out)
    assert sorted(p.name for p in out.iterdir()) == ["c.csv", "manifest.json"]


def test_an_interrupted_publish_leaves_no_manifest(tmp_path: Path,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    """The old manifest goes first: a publish that fails half-way leaves none, never one that
    describes a mix of two runs."""
    out = tmp_path / "out"
    out.mkdir()
    _publish(staged(tmp_path, {"a.csv": "1", "b.csv": "1"}, "first"), out)
    assert (out / "manifest.json").exists()
    real = Path.replace

    def fail_on_b(self: Path, target: os.PathLike[str]) -> Path:
        if self.name == "b.csv":
            raise OSError(errno.EIO, "Input/output error")
        return real(self, target)

    monkeypatch.setattr(Path, "replace", fail_on_b)
    with pytest.raises(OSError):
        _publish(staged(tmp_path, {"a.csv": "2", "b.csv": "2"}, "second"), out)
    assert not (out / "manifest.json").exists()
    assert (out / "a.csv").read_text() == "2" and (out / "b.csv").read_text() == "1"

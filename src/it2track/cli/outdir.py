"""Where the commands write: the rule of authorship for every output (a file is replaced only
if it2track can prove it wrote it, or with ``--force``; see :mod:`it2track.authorship`) as
command-line errors naming the option and the file, and the output folder of ``it2track
reproduce`` (a staging folder per run, published into ``--out`` without ever losing a file of
the user's).
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any, NoReturn

import click

__all__ = [
    "_discard_staging",
    "_drop_cache",
    "_make_staging",
    "_publish",
    "check_output_file",
    "check_outputs",
    "write_output_file",
]


def _fail(message: str) -> NoReturn:
    raise click.ClickException(message)


def check_outputs(
    paths: Iterable[str | os.PathLike[str]],
    *,
    option: str,
    force: bool,
    proof: Callable[[Path], bool],
    sidecars: bool = False,
    outcome: str = "nothing was done",
) -> None:
    """:func:`it2track.authorship.check_may_replace` as a command-line error: ``option`` (the
    option and value the user gave, e.g. ``"--out results"``), the file and why, and
    ``outcome``."""
    from ..atomicfile import NotRegularFileError
    from ..authorship import UnprovenFileError, check_may_replace

    try:
        check_may_replace(paths, proof=proof, force=force, sidecars=sidecars)
    except (NotRegularFileError, UnprovenFileError) as exc:
        _fail(f"{option}: {exc.filename} {exc.strerror}; {outcome}")


def check_output_file(path: str, option: str, *, force: bool) -> Path:
    """An output file named by ``option`` (``--trace``, ``--out``, a TARGET argument), checked
    before any work: not empty, in an existing folder that can be written, absent or a regular
    file that it2track wrote (its ``NAME.sha256`` matches) unless ``force`` -- never a
    directory, link, device or FIFO. Written later by :func:`write_output_file`."""
    from ..atomicfile import check_can_create_in
    from ..authorship import proven_by_sidecar

    if not path:
        _fail(f"{option} '' is empty: give a file name")
    target = Path(path)
    parent = target.parent
    if not parent.is_dir():
        _fail(f"{option} {path}: the folder {parent} does not exist")
    check_outputs([target], option=f"{option} {path}", force=force, proof=proven_by_sidecar,
                  sidecars=True)
    try:
        check_can_create_in(parent)
    except OSError as exc:
        _fail(f"{option} {path}: cannot write into the folder {parent}: "
              f"{exc.strerror or type(exc).__name__}; choose another place")
    return target


def write_output_file(path: str | os.PathLike[str], data: bytes, option: str) -> None:
    """Write an output checked by :func:`check_output_file`, with its ``NAME.sha256`` (the
    proof the next run needs); an error names ``option`` and the file, never a temporary."""
    from ..authorship import write_with_sidecar

    try:
        write_with_sidecar(path, data)
    except OSError as exc:
        _fail(f"cannot write {option} {os.fspath(path)}: "
              f"{exc.strerror or exc.__class__.__name__}")


#: Results every run writes (the others vary with the config; ``_make_staging`` takes them):
#: checked before any work starts.
_FIXED_OUTPUTS = ("metrics.csv", "summary.csv", "verdicts.csv", "claims.md", "report.html",
                  "manifest.json")
_STAGING_PREFIX = ".reproduce-"
_OWNER_FILE = "owner.json"
_OWNER_PROGRAM = "it2track reproduce"


def _process_start(pid: int) -> int | None:
    """Start time of process ``pid`` (clock ticks since boot, Linux ``/proc``), else None."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    try:
        return int(text.rsplit(")", 1)[1].split()[19])
    except (IndexError, ValueError):  # pragma: no cover - unexpected /proc format
        return None


def _owner_alive(owner: dict[str, Any]) -> bool:
    """Is the process that created a staging folder (``owner.json``) still running?"""
    import os
    import socket

    if owner.get("host") != socket.gethostname():
        return True  # another machine (shared filesystem): cannot tell, so never ours to remove
    pid = owner.get("pid")
    if isinstance(pid, bool) or not isinstance(pid, int) or pid <= 0:
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    start = owner.get("start")
    return start is None or _process_start(pid) in (None, start)  # a reused pid is not it


def _remove_stale_staging(out: Path) -> None:
    """Remove staging folders that killed runs of ``reproduce`` left in ``out``.

    A folder is removed only if it is provably ours and stale: a real directory named
    ``.reproduce-*`` holding our ``owner.json`` (program, host, pid, process start time) whose
    process is gone, and nothing but that file and a ``files/`` folder of regular files. Any
    other ``.reproduce-*`` entry (a user's, an older version's, a live run's) is left alone.
    """
    import os
    import stat

    try:
        entries = [e for e in os.scandir(out) if e.name.startswith(_STAGING_PREFIX)]
    except OSError:
        return
    for entry in entries:
        if not entry.is_dir(follow_symlinks=False):
            continue
        root = Path(entry.path)
        try:
            st = os.lstat(root / _OWNER_FILE)
            if not stat.S_ISREG(st.st_mode):
                continue
            owner = json.loads((root / _OWNER_FILE).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if not isinstance(owner, dict) or owner.get("program") != _OWNER_PROGRAM:
            continue
        if _owner_alive(owner):
            continue
        files = root / "files"
        try:
            names = set(os.listdir(root))
            inner = list(os.scandir(files)) if "files" in names else []
        except OSError:
            continue
        # (files/ was listed just above: a regular file there raised and is left alone)
        if names - {_OWNER_FILE, "files"} or not all(
            e.is_file(follow_symlinks=False) for e in inner
        ) or files.is_symlink():
            click.echo(f"note: left {root} alone (holds more than a run's files)", err=True)
            continue
        try:
            for e in inner:
                os.unlink(e.path)
            if "files" in names:
                os.rmdir(files)
            os.unlink(root / _OWNER_FILE)
            os.rmdir(root)
        except OSError as exc:
            click.echo(f"note: could not remove the stale {root}: {exc.strerror}", err=True)


def _previous_run(out: Path) -> Callable[[Path], bool]:
    """Proof of authorship for the files in ``out``: listed with their SHA-256 in the sealed
    ``manifest.json`` of a previous run (:func:`it2track.authorship.read_sealed_json`), the
    manifest itself by its seal."""
    from ..authorship import proven_by_digests, read_sealed_json

    old = read_sealed_json(out / "manifest.json")
    listed = proven_by_digests(old.get("sha256") if old is not None else None)

    def proof(path: Path) -> bool:
        if path.name == "manifest.json":
            return old is not None
        return listed(path)

    return proof


def _make_staging(out_dir: str, also: Iterable[str] = (), *, force: bool = False) -> Path:
    """Create ``out_dir`` and a fresh staging folder in it; returns the folder results go to.

    Checked before any simulation: an empty ``--out``, a folder that cannot be created or
    written (read-only, a file in the way), and every file this run may write (the fixed names
    and ``also``): absent, or a regular file the previous run's sealed ``manifest.json`` proves
    it2track wrote (or any regular file with ``force``); never a folder, link or device. Stale
    staging folders of killed runs are removed (see :func:`_remove_stale_staging`). The
    staging root holds ``owner.json`` (this process's identity, the proof a later run needs
    to remove it) and ``files/``, which is returned.
    """
    import os
    import socket

    if not out_dir:
        _fail("--out '' is empty: give an output folder")
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        _fail(f"cannot create the output folder --out {out_dir}: "
              f"{exc.strerror or exc}; nothing was simulated")
    check_outputs([out / name for name in dict.fromkeys((*_FIXED_OUTPUTS, *also))],
                  option=f"--out {out_dir}", force=force, proof=_previous_run(out),
                  outcome="nothing was simulated")
    _remove_stale_staging(out)
    try:
        root = Path(tempfile.mkdtemp(prefix=_STAGING_PREFIX, dir=out))
    except OSError as exc:
        _fail(f"cannot write into the output folder --out {out_dir}: "
              f"{exc.strerror or exc}; nothing was simulated")
    try:
        owner = {"program": _OWNER_PROGRAM, "host": socket.gethostname(), "pid": os.getpid(),
                 "start": _process_start(os.getpid()), "created": time.time()}
        from ..atomicfile import atomic_write_text

        atomic_write_text(root / _OWNER_FILE, json.dumps(owner) + "\n")
        (root / "files").mkdir()
    except OSError as exc:
        shutil.rmtree(root, ignore_errors=True)
        _fail(f"cannot write into the output folder --out {out_dir}: "
              f"{exc.strerror or exc}; nothing was simulated")
    _terminate_cleanly()
    return root / "files"


def _terminate_cleanly() -> None:
    """Let SIGTERM unwind like Ctrl-C (``finally`` blocks run, the staging folder goes)."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return

    def handler(signum: int, frame: Any) -> None:
        raise SystemExit(128 + signum)

    if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
        signal.signal(signal.SIGTERM, handler)
        _RESTORE_SIGTERM.append(signal.SIG_DFL)


_RESTORE_SIGTERM: list[Any] = []


def _discard_staging(staging: Path) -> None:
    """Remove this run's own staging folder (the parent of ``staging``)."""
    import signal

    shutil.rmtree(staging.parent, ignore_errors=True)
    while _RESTORE_SIGTERM:
        signal.signal(signal.SIGTERM, _RESTORE_SIGTERM.pop())


def _publish(staging: Path, out: Path, *, force: bool = False) -> None:
    """Move a finished run from ``staging`` into ``out``, never losing a file of the user's.

    Only two kinds of file in ``out`` are ever replaced or removed:

    - files of the names this run writes that the previous run's sealed ``manifest.json``
      proves it2track wrote (their SHA-256 matches; the manifest itself by its seal), or any
      regular file of those names with ``force`` -- checked again here, as before the run: a
      file that appeared or changed meanwhile stops the publish before anything moves;
    - files that manifest lists *with their SHA-256* and that still have exactly those bytes
      but that this run does not write (e.g. figures of a trajectory no longer studied).
      Anything else -- a name without a digest or with another one (a file edited since), a
      manifest this program did not write or that was edited, a folder, a link, a path
      outside ``out`` -- is kept (and named on stderr).

    The new manifest records the SHA-256 of every file of this run, as that proof for the
    next run, and is sealed (:func:`it2track.authorship.seal_json`). The old manifest goes
    before anything else moves and the new one comes last: an interrupted publish leaves no
    manifest rather than one that describes a mix of runs.
    """
    import os
    import stat

    from ..authorship import read_sealed_json, seal_json, sha256_file
    from ..report import outputs

    new = sorted(p.name for p in staging.iterdir())
    check_outputs([out / name for name in new], option=f"--out {out}", force=force,
                  proof=_previous_run(out), outcome="nothing was published")
    staged_manifest = staging / "manifest.json"
    manifest = json.loads(staged_manifest.read_text(encoding="utf-8"))
    manifest["sha256"] = {n: sha256_file(staging / n) for n in new if n != "manifest.json"}
    outputs.write_json(staged_manifest, seal_json(manifest))

    old_path = out / "manifest.json"
    stale: dict[str, str] = {}
    old = read_sealed_json(old_path) or {}
    listed = old.get("files", [])
    digests = old.get("sha256", {})
    if not isinstance(digests, dict):
        digests = {}
    kept: list[str] = []
    for name in listed if isinstance(listed, list) else []:
        if not isinstance(name, str) or name in new or name == "manifest.json":
            continue
        target = out / name
        plain = (name not in ("", ".", "..") and "/" not in name and "\\" not in name
                 and not name.startswith("."))
        if not plain or not os.path.lexists(target):
            continue
        digest = digests.get(name)
        try:
            ours = (isinstance(digest, str) and stat.S_ISREG(os.lstat(target).st_mode)
                    and sha256_file(target) == digest)
        except OSError:
            ours = False
        if ours:
            stale[name] = str(digest)
        else:
            kept.append(name)
    if old_path.is_file() and not old_path.is_symlink():
        old_path.unlink()
    for name in sorted(stale):
        (out / name).unlink(missing_ok=True)
    for name in new:
        if name != "manifest.json":
            (staging / name).replace(out / name)
    staged_manifest.replace(old_path)
    if kept:
        click.echo(
            f"note: kept {len(kept)} file(s) in {out} that the previous manifest lists but that "
            f"this run cannot prove it wrote (changed since, or no checksum): "
            f"{', '.join(sorted(kept))}",
            err=True,
        )


def _drop_cache(folder: Path) -> None:
    """Remove the physics check's cache (``reproduce``'s ``OUT/.physics-cache``) after a
    published run: only its own files, then the folder if that left it empty."""
    from ..experiments.physics import RowCache

    if not folder.is_dir() or folder.is_symlink():
        return
    for p in RowCache(folder).files():
        if p.is_file() and not p.is_symlink():
            p.unlink()
    try:
        folder.rmdir()
    except OSError:
        pass  # something else is in it: not ours to remove

"""The results store of a sweep: its files, how they are written and resumed, and why one CSV
per chunk.

Layout (directory ``DIR``)::

    DIR/sweep.json                       normalised configuration, its SHA-256, layout, columns
    DIR/chunks/chunk-000042.csv          one CSV per finished chunk (header + its rows)
    DIR/chunks/chunk-000042.csv.sha256   its SHA-256 (``sha256sum -c`` format)
    DIR/results.csv                      all rows in run order, assembled when every chunk is done
    DIR/results.csv.sha256               its SHA-256: the proof that lets a resume replace it
    DIR/.lock                            advisory lock held while a process works on DIR

Every file is written to a temporary name (:mod:`it2track.atomicfile`), flushed, ``fsync``-ed
and renamed (then the directory is ``fsync``-ed), so a chunk file exists only if it is complete:
killing the process at any moment loses at most the chunks being computed. ``resume`` checks the
configuration hash and skips the chunks on disk whose bytes still hash to their stored SHA-256
and whose rows are the runs of the chunk's place in the plan (an edited, torn, unverifiable or
misplaced chunk is computed again); ``results.csv`` is replaced only if it still matches its
``.sha256`` (never a file of the user's, unless ``force``); temporaries are removed only if they
carry this package's temporary naming and their writer is dead, never a user's ``.*.tmp``. The
hash covers everything that determines the numbers and the chunk
layout -- including the it2track version and the bytes (not the paths) of controller and
trajectory files -- so a store is never extended with results of another configuration, an
edited file or another version of it2track. Floats are written with ``repr``, which
round-trips exactly, so ``results.csv`` is byte-identical however the sweep was interrupted,
chunked or distributed.

Why one CSV per chunk: appending to one file cannot be made atomic (a kill mid-append leaves a
torn row that a resume must detect and cut), while a rename is atomic on POSIX filesystems; a
chunk's file is its own completion marker, so no index file can disagree with the data; CSV needs
no extra dependency and opens anywhere; out-of-order completion (workers, Dask) needs no
coordination; and the final assembly is a plain concatenation in chunk order.
"""

from __future__ import annotations

import contextlib
import csv
import hashlib
import json
import os
import stat
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from ... import __version__
from ...atomicfile import NotRegularFileError, atomic_open, atomic_write_bytes
from ...authorship import (
    UnprovenFileError,
    check_may_replace,
    proven_by_sidecar,
    sidecar_line,
    sidecar_path,
)
from .plan import STORE_FORMAT, SweepPlan, _hash_json

__all__ = ["StoreError", "chunk_path", "digest_path", "read_results"]


class StoreError(RuntimeError):
    """A results directory cannot be used: another sweep, a changed config, a held lock."""


@contextlib.contextmanager
def _locked(out: Path) -> Iterator[None]:
    """Hold an exclusive advisory lock on ``out/.lock`` (POSIX; released if we die)."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows: no locking
        yield
        return
    flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(out / ".lock", flags, 0o644)
    except OSError as exc:
        raise StoreError(f"{out / '.lock'}: cannot open the sweep's lock file: {exc}") from None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            raise StoreError(f"{out}: another process is working on this sweep") from None
        yield
    finally:
        os.close(fd)


def chunk_path(out: Path, chunk_id: int) -> Path:
    return out / "chunks" / f"chunk-{chunk_id:06d}.csv"


def digest_path(chunk_file: Path) -> Path:
    """The checksum file of a chunk: ``chunk-000042.csv.sha256`` (``sha256sum -c`` format)."""
    return chunk_file.with_name(chunk_file.name + ".sha256")


def _digest_line(chunk_file: Path, digest: str) -> bytes:
    return f"{digest}  {chunk_file.name}\n".encode("ascii")


def _write_chunk(path: Path, data: bytes) -> None:
    """The chunk file, then its checksum file (each atomically): a chunk counts as done only
    when both exist and agree, so a kill between the two only costs a recomputation."""
    atomic_write_bytes(path, data)
    atomic_write_bytes(digest_path(path), _digest_line(path, hashlib.sha256(data).hexdigest()))


def _read_regular(path: Path) -> bytes | None:
    """The bytes of a regular file (never following a symbolic link), or None."""
    try:
        st = os.lstat(path)
        if not stat.S_ISREG(st.st_mode):
            return None
        return path.read_bytes()
    except OSError:
        return None


def _chunk_digest(path: Path, header: str, keys: Sequence[str]) -> str | None:
    """The SHA-256 of ``path`` if it is a complete, unaltered chunk of its place in the plan,
    else None.

    Complete: our header and one row per run; unaltered: its bytes hash to the digest stored
    in its ``.sha256`` file when it was written; in its place: row ``i`` starts with
    ``keys[i]``, the run id and the identifying columns the plan gives that run (a copy of
    another chunk, even with a matching checksum file, is not this chunk). A missing, torn,
    edited or misplaced chunk (or checksum file) gives None: the chunk is computed again.
    """
    data = _read_regular(path)
    stored = _read_regular(digest_path(path))
    if data is None or stored is None:
        return None
    digest = hashlib.sha256(data).hexdigest()
    if stored != _digest_line(path, digest):
        return None
    head = header.encode("utf-8")
    if not (data.startswith(head) and data.endswith(b"\n")):
        return None
    rows = data[len(head):-1].split(b"\n")
    if len(rows) != len(keys) or not all(
        row.startswith(key.encode("utf-8") + b",") for row, key in zip(rows, keys, strict=True)
    ):
        return None
    return digest


def _describe_change(old: Mapping[str, Any], new: Mapping[str, Any]) -> str:
    keys = sorted(k for k in set(old) | set(new) if old.get(k) != new.get(k))
    return ", ".join(keys) or "(store format)"


def _changed_files(meta: Mapping[str, Any], plan: SweepPlan) -> list[str]:
    """Sentences naming the controller and trajectory files whose content changed."""
    old = meta.get("config", {})

    def digests(section: str, key: str, digest_key: str) -> dict[str, str]:
        entries = old.get(section, [])
        return {
            str(e[key]): str(e[digest_key])
            for e in entries if isinstance(e, Mapping) and key in e and digest_key in e
        }  # fmt: skip

    controllers = digests("controllers", "label", "file_sha256")
    trajectories = digests("trajectories", "name", "sha256")
    out: list[str] = []
    for c in plan.controllers:
        before = controllers.get(c.label)
        if c.path and before is not None and before != c.sha256:
            out.append(
                f"controller file {c.path!r} ([[controllers]] {c.label!r}) has changed: sha256 "
                f"{before[:12]} when the sweep started, now {c.sha256[:12]}"
            )
    for r in plan.trajectory_refs:
        before = trajectories.get(r.name)
        if r.path and before is not None and before != r.sha256:
            out.append(
                f"trajectory file {r.path!r} has changed: sha256 {before[:12]} when the sweep "
                f"started, now {r.sha256[:12]}"
            )
    return out


def _check_results(out: Path, *, force: bool) -> None:
    """``results.csv`` may be (re)written: absent, or a regular file whose ``.sha256`` beside it
    (written with it) still matches, or ``force`` -- never a file of the user's."""
    try:
        check_may_replace([out / "results.csv"], proof=proven_by_sidecar, force=force,
                          sidecars=True)
    except (NotRegularFileError, UnprovenFileError) as exc:
        raise StoreError(f"{exc.filename} {exc.strerror}") from None


def _prepare_store(plan: SweepPlan, out: Path, *, resume: bool, force: bool) -> None:
    _check_results(out, force=force)
    meta_path = out / "sweep.json"
    normalised = plan.normalised()
    digest = _hash_json(normalised)
    if meta_path.exists():
        if not resume:
            raise StoreError(
                f"{out} already holds a sweep; pass resume (--resume) to continue it, "
                "or choose another directory"
            )
        try:
            meta = json.loads(meta_path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise StoreError(f"{meta_path}: unreadable sweep metadata: {exc}") from None
        if meta.get("format") != STORE_FORMAT:
            raise StoreError(f"{meta_path}: format {meta.get('format')!r} is not {STORE_FORMAT}")
        version = meta.get("it2track_version")
        if version != __version__:
            raise StoreError(
                f"{out}: the sweep was started by it2track {version}, this is it2track "
                f"{__version__}; results of two versions must not be mixed in one store: "
                f"finish it with it2track {version} or use another directory"
            )
        if meta.get("hash") != digest:
            changed = _describe_change(meta.get("config", {}), normalised)
            details = "".join(f"; {s}" for s in _changed_files(meta, plan))
            raise StoreError(
                f"{out}: the configuration changed since the sweep started (stored hash "
                f"{str(meta.get('hash'))[:12]}, now {digest[:12]}; differs in: {changed})"
                f"{details}; resume with the original config and files or use another "
                "directory"
            )
        return
    leftovers = sorted(p.name for p in (out / "chunks").glob("chunk-*.csv"))
    if leftovers:
        raise StoreError(
            f"{out}: chunks/ holds {len(leftovers)} chunk file(s) (e.g. {leftovers[0]}) but no "
            "sweep.json; they belong to an unknown sweep: remove them or use another directory"
        )
    meta = {
        "format": STORE_FORMAT,
        "hash": digest,
        "config": normalised,
        "n_runs": plan.n_runs,
        "n_chunks": len(plan.chunks()),
        "columns": plan.columns,
        "run_order": ["group", "controller", "trajectory", "noise_std", "seed"],
        "source": plan.source,
        "trajectory_files": {r.name: r.path for r in plan.trajectory_refs if r.path},
        "controller_files": {c.label: c.path for c in plan.controllers if c.path},
        "it2track_version": __version__,
    }
    text = json.dumps(meta, indent=1, allow_nan=False) + "\n"
    atomic_write_bytes(meta_path, text.encode("utf-8"))


def _assemble(plan: SweepPlan, out: Path, header: str, digests: Mapping[int, str], *,
              force: bool) -> None:
    """``results.csv``: the header, then every chunk's rows in run order (streamed), and its
    SHA-256 in ``results.csv.sha256`` (the proof a later resume needs to replace it).

    Each chunk is hashed while it is copied and must still have the digest it had when it was
    verified or written (``digests``): a chunk changed meanwhile stops the assembly. The rule
    of :func:`_check_results` is checked again first (a file may have appeared meanwhile).
    """
    _check_results(out, force=force)
    target = out / "results.csv"
    whole = hashlib.sha256()
    with atomic_open(target, "wb") as dst:
        dst.write(header.encode("utf-8"))
        whole.update(header.encode("utf-8"))
        for chunk in plan.chunks():
            path = chunk_path(out, chunk.id)
            h = hashlib.sha256()
            with open(path, "rb") as src:
                first = src.readline()  # the chunk's header
                h.update(first)
                while block := src.read(1 << 20):
                    h.update(block)
                    whole.update(block)
                    dst.write(block)
            if h.hexdigest() != digests[chunk.id]:
                raise StoreError(
                    f"{path} changed while the sweep was assembling results.csv (sha256 "
                    f"{digests[chunk.id][:12]} expected, {h.hexdigest()[:12]} found); "
                    "rerun with --resume to recompute it"
                )
        # The proof first, then the rename (when the block ends): a crash between the two
        # leaves a results.csv that does not match it, never a proof of bytes not ours.
        atomic_write_bytes(sidecar_path(target), sidecar_line(target, whole.hexdigest()))


def read_results(path: str | Path) -> tuple[list[str], list[list[str]]]:
    """Header and rows of a results or chunk CSV file (strings; ``float(cell)`` is exact)."""
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    return rows[0], rows[1:]

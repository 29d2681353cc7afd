"""A resumed sweep trusts a chunk only if its bytes still hash to the SHA-256 stored with it."""

from __future__ import annotations

import hashlib
import textwrap
from pathlib import Path

from it2track.experiments.sweep import digest_path, load_sweep_config, run_sweep

CONFIG = """
[sweep]
seeds = 4
noise_std = [0.0, 0.1]
trajectories = "sinusoidal"
chunk_size = 3

[simulation]
duration = 0.5

[[controllers]]
kind = "flc"

[[controllers]]
kind = "it2"
fou = 0.2
"""


def _run(tmp_path: Path):
    cfg = tmp_path / "sweep.toml"
    cfg.write_text(textwrap.dedent(CONFIG), encoding="utf-8")
    plan = load_sweep_config(cfg)
    out = tmp_path / "out"
    run_sweep(plan, out, progress=False)
    return plan, out


def test_every_chunk_has_a_matching_checksum_file(tmp_path: Path) -> None:
    plan, out = _run(tmp_path)
    chunks = sorted((out / "chunks").glob("chunk-*.csv"))
    assert len(chunks) == len(plan.chunks())
    for chunk in chunks:
        digest = hashlib.sha256(chunk.read_bytes()).hexdigest()
        assert digest_path(chunk).read_text() == f"{digest}  {chunk.name}\n"


def test_resume_recomputes_an_edited_cell_a_lost_checksum_and_a_forged_one(
    tmp_path: Path,
) -> None:
    plan, out = _run(tmp_path)
    reference = (out / "results.csv").read_bytes()
    chunks = sorted((out / "chunks").glob("chunk-*.csv"))
    # 1. one metric cell edited: same header, same number of lines (what the old check saw)
    lines = chunks[0].read_text().splitlines(keepends=True)
    cells = lines[1].rstrip("\n").split(",")
    cells[-1] = "0.125"
    lines[1] = ",".join(cells) + "\n"
    chunks[0].write_text("".join(lines))
    # 2. a chunk whose checksum file is gone (killed between the two writes)
    digest_path(chunks[1]).unlink()
    # 3. an edited chunk with its checksum file "fixed" by hand in the wrong format
    text = chunks[2].read_text().replace(",", ", ", 1)
    chunks[2].write_text(text)
    digest_path(chunks[2]).write_text(hashlib.sha256(text.encode()).hexdigest() + "\n")
    (out / "results.csv").unlink()
    summary = run_sweep(plan, out, resume=True, progress=False)
    assert summary.chunks_computed == 3
    assert (out / "results.csv").read_bytes() == reference
    again = run_sweep(plan, out, resume=True, progress=False)
    assert again.chunks_computed == 0
    assert (out / "results.csv").read_bytes() == reference


def test_a_chunk_replaced_by_a_symlink_is_not_trusted(tmp_path: Path) -> None:
    plan, out = _run(tmp_path)
    reference = (out / "results.csv").read_bytes()
    chunk = sorted((out / "chunks").glob("chunk-*.csv"))[0]
    copy = tmp_path / "elsewhere.csv"
    copy.write_bytes(chunk.read_bytes())
    chunk.unlink()
    chunk.symlink_to(copy)
    try:
        run_sweep(plan, out, resume=True, progress=False)
    except OSError as exc:  # the symlink is never replaced nor followed for writing
        assert "not a regular file" in str(exc)
    else:  # pragma: no cover - the write must refuse
        raise AssertionError("a chunk symlink was replaced")
    assert chunk.is_symlink() and copy.read_bytes() != b""
    assert (out / "results.csv").read_bytes() == reference


def _forge(chunk: Path, data: bytes) -> None:
    """Replace ``chunk`` by ``data`` with a checksum file that matches (what ``sha256sum``
    would write): the hash alone can no longer tell."""
    chunk.write_bytes(data)
    digest_path(chunk).write_text(f"{hashlib.sha256(data).hexdigest()}  {chunk.name}\n")


def test_resume_recomputes_a_chunk_replaced_by_a_copy_of_another_with_its_checksum(
    tmp_path: Path,
) -> None:
    """The issue's tampering: chunk 1 replaced by a copy of chunk 0 with a matching .sha256.
    results.csv held run 0 twice and no run 1; the run ids are now checked against the
    chunk's place in the plan, and the chunk is computed again."""
    plan, out = _run(tmp_path)
    reference = (out / "results.csv").read_bytes()
    chunks = sorted((out / "chunks").glob("chunk-*.csv"))
    assert plan.chunks()[0].size == plan.chunks()[1].size == 3  # same size: only ids differ
    _forge(chunks[1], chunks[0].read_bytes())
    summary = run_sweep(plan, out, resume=True, progress=False)
    assert summary.chunks_computed == 1 and summary.chunks_skipped == len(chunks) - 1
    assert (out / "results.csv").read_bytes() == reference
    runs = [line.split(",", 1)[0] for line in reference.decode().splitlines()[1:]]
    assert runs == [str(r) for r in range(plan.n_runs)]


def test_resume_checks_every_identifying_column_not_only_the_run_id(tmp_path: Path) -> None:
    """Chunk 0's rows renumbered as runs 3-5 (ids right, seeds and noise levels those of runs
    0-2), and a chunk whose last row is dropped: both computed again."""
    plan, out = _run(tmp_path)
    reference = (out / "results.csv").read_bytes()
    chunks = sorted((out / "chunks").glob("chunk-*.csv"))
    header, *rows = chunks[0].read_text().splitlines(keepends=True)
    renumbered = [f"{3 + i},{row.split(',', 1)[1]}" for i, row in enumerate(rows)]
    _forge(chunks[1], (header + "".join(renumbered)).encode())
    header2, *rows2 = chunks[2].read_text().splitlines(keepends=True)
    _forge(chunks[2], (header2 + "".join(rows2[:-1])).encode())
    assert plan.row_keys(plan.chunks()[1])[0].startswith("3,")
    summary = run_sweep(plan, out, resume=True, progress=False)
    assert summary.chunks_computed == 2
    assert (out / "results.csv").read_bytes() == reference


def test_results_csv_is_replaced_only_with_its_proof(tmp_path: Path) -> None:
    """results.csv carries its SHA-256 beside it; a resume replaces it while that matches,
    refuses an edited one (naming it) before any work, and replaces it with force."""
    import pytest

    from it2track.experiments.sweep import StoreError

    plan, out = _run(tmp_path)
    results = out / "results.csv"
    reference = results.read_bytes()
    proof = (out / "results.csv.sha256").read_text()
    assert proof == f"{hashlib.sha256(reference).hexdigest()}  results.csv\n"
    assert run_sweep(plan, out, resume=True, progress=False).chunks_computed == 0
    results.write_bytes(reference + b"my extra row\n")
    (out / "chunks" / "chunk-000000.csv").unlink()  # would be recomputed: must not be
    with pytest.raises(StoreError, match=r"results\.csv exists and it2track cannot prove"):
        run_sweep(plan, out, resume=True, progress=False)
    assert results.read_bytes() == reference + b"my extra row\n"
    assert not (out / "chunks" / "chunk-000000.csv").exists()  # no work was done
    summary = run_sweep(plan, out, resume=True, progress=False, force=True)
    assert summary.chunks_computed == 1 and results.read_bytes() == reference


def test_a_new_sweep_never_replaces_a_users_results_csv(tmp_path: Path) -> None:
    import pytest

    from it2track.experiments.sweep import StoreError

    cfg = tmp_path / "sweep.toml"
    cfg.write_text(textwrap.dedent(CONFIG), encoding="utf-8")
    plan = load_sweep_config(cfg)
    out = tmp_path / "out"
    out.mkdir()
    (out / "results.csv").write_text("the user's\n")
    with pytest.raises(StoreError, match=r"results\.csv exists and it2track cannot prove"):
        run_sweep(plan, out, progress=False)
    assert sorted(p.name for p in out.iterdir()) == ["results.csv"]  # nothing created
    (out / "results.csv").unlink()
    (out / "results.csv.sha256").write_text("the user's notes\n")
    with pytest.raises(StoreError, match=r"results\.csv\.sha256 exists and is not a checksum"):
        run_sweep(plan, out, progress=False)
    assert (out / "results.csv.sha256").read_text() == "the user's notes\n"

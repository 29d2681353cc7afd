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

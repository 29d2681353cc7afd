"""What a resume refuses, to the letter: a changed configuration names the keys and the files
whose bytes changed (and only those), a tampered sweep.json is still read safely; and
read_results returns the cells exactly (store.py)."""

from __future__ import annotations

import hashlib
import json
import textwrap
from pathlib import Path

import pytest

from it2track import heading_fls, save
from it2track.experiments.sweep import StoreError, load_sweep_config, read_results, run_sweep

CONFIG = """
[sweep]
seeds = 1
noise_std = 0.1
trajectories = ["straight", "wp.csv"]

[simulation]
duration = 0.5

[[controllers]]
kind = "flc"

[[controllers]]
kind = "file"
path = "ctrl.t2fis"
"""
PATH = "t,x,y\n0,0,0\n1,1,0\n2,2,0.5\n3,3,0\n"


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _start(tmp_path: Path) -> tuple[Path, Path]:
    save(heading_fls(0.3), tmp_path / "ctrl.t2fis")
    (tmp_path / "wp.csv").write_text(PATH)
    cfg = tmp_path / "sweep.toml"
    cfg.write_text(textwrap.dedent(CONFIG), encoding="utf-8")
    out = tmp_path / "out"
    run_sweep(load_sweep_config(cfg), out, progress=False)
    return cfg, out


def _refusal(cfg: Path, out: Path) -> str:
    with pytest.raises(StoreError) as info:
        run_sweep(load_sweep_config(cfg), out, resume=True, progress=False)
    return str(info.value)


def test_a_resume_names_every_changed_file_with_both_digests(tmp_path: Path) -> None:
    cfg, out = _start(tmp_path)
    ctrl, wp = tmp_path / "ctrl.t2fis", tmp_path / "wp.csv"
    before = (_sha(ctrl), _sha(wp))
    stored = json.loads((out / "sweep.json").read_text())["hash"]
    save(heading_fls(0.5), ctrl)
    wp.write_text(PATH.replace("0.5", "0.7"))
    now = load_sweep_config(cfg).config_hash()
    assert _refusal(cfg, out) == (
        f"{out}: the configuration changed since the sweep started (stored hash "
        f"{stored[:12]}, now {now[:12]}; differs in: controllers, trajectories); "
        f"controller file {str(ctrl)!r} ([[controllers]] 'ctrl.t2fis') has changed: sha256 "
        f"{before[0][:12]} when the sweep started, now {_sha(ctrl)[:12]}; "
        f"trajectory file {str(wp)!r} has changed: sha256 {before[1][:12]} when the sweep "
        f"started, now {_sha(wp)[:12]}; resume with the original config and files or use "
        "another directory")


def test_an_unchanged_file_is_not_named(tmp_path: Path) -> None:
    cfg, out = _start(tmp_path)
    wp = tmp_path / "wp.csv"
    old = _sha(wp)
    wp.write_text(PATH.replace("0.5", "0.7"))
    message = _refusal(cfg, out)
    assert "differs in: trajectories); trajectory file" in message
    assert f"sha256 {old[:12]} when the sweep started, now {_sha(wp)[:12]}; resume" in message
    assert "controller file" not in message


def test_a_changed_controller_file_alone_is_named(tmp_path: Path) -> None:
    cfg, out = _start(tmp_path)
    save(heading_fls(0.5), tmp_path / "ctrl.t2fis")
    message = _refusal(cfg, out)
    assert "differs in: controllers); controller file" in message
    assert "trajectory file" not in message


def test_a_hash_that_differs_with_the_same_settings_is_the_store_format(tmp_path: Path) -> None:
    cfg, out = _start(tmp_path)
    meta = json.loads((out / "sweep.json").read_text())
    meta["hash"] = "0" * 64
    (out / "sweep.json").write_text(json.dumps(meta))
    now = load_sweep_config(cfg).config_hash()
    assert _refusal(cfg, out) == (
        f"{out}: the configuration changed since the sweep started (stored hash 000000000000, "
        f"now {now[:12]}; differs in: (store format)); resume with the original config and "
        "files or use another directory")


def test_a_tampered_sweep_json_is_read_without_guessing(tmp_path: Path) -> None:
    # entries that are not tables, or lack the name or the digest, name no file; a key only
    # one side has is a difference
    cfg, out = _start(tmp_path)
    meta = json.loads((out / "sweep.json").read_text())
    ctrl = meta["config"]["controllers"]
    # (a digest for a built-in controller or trajectory: they have no file to name)
    meta["config"]["controllers"] = ["junk", {"label": "ctrl.t2fis"}, ctrl[0],
                                     {"file_sha256": "ab" * 32},
                                     {"label": "FLC", "file_sha256": "ab" * 32}]
    meta["config"]["trajectories"] = [7, {"name": "wp"}, {"sha256": "cd" * 32},
                                      {"name": "straight", "sha256": "cd" * 32}]
    meta["config"]["extra"] = 1
    meta["hash"] = "0" * 64
    (out / "sweep.json").write_text(json.dumps(meta))
    message = _refusal(cfg, out)
    assert "differs in: controllers, extra, trajectories); resume with" in message
    assert "file" not in message.split("differs in")[1].split("; resume")[0]
    # no sections at all, then no configuration at all: every key differs, no file named
    del meta["config"]["controllers"], meta["config"]["trajectories"]
    (out / "sweep.json").write_text(json.dumps(meta))
    assert "differs in: controllers, extra, trajectories); resume with" in _refusal(cfg, out)
    del meta["config"]
    (out / "sweep.json").write_text(json.dumps(meta))
    keys = ", ".join(sorted(load_sweep_config(cfg).normalised()))
    assert f"differs in: {keys}); resume with" in _refusal(cfg, out)


def test_read_results_keeps_every_cell_as_written(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "r.csv"
    # a quoted cell holding a line break and a non-ASCII label: read back exactly
    path.write_bytes('run,label\r\n0,"a\r\nb"\r\n1,θ\r\n'.encode())
    assert read_results(path) == (["run", "label"], [["0", "a\r\nb"], ["1", "θ"]])
    # UTF-8 whatever the platform's default encoding (here made Latin-1 for files opened
    # without one)
    from it2track.experiments.sweep import store

    def latin1_default(file, mode="r", *args, **kwargs):
        if kwargs.get("encoding") is None and "b" not in mode:
            kwargs["encoding"] = "latin-1"
        return open(file, mode, *args, **kwargs)

    monkeypatch.setattr(store, "open", latin1_default, raising=False)
    assert read_results(path)[1][1] == ["1", "θ"]


def test_a_second_sweep_into_the_same_folder_is_refused_to_the_letter(tmp_path: Path) -> None:
    cfg, out = _start(tmp_path)
    with pytest.raises(StoreError) as info:
        run_sweep(load_sweep_config(cfg), out, progress=False)
    assert str(info.value) == (f"{out} already holds a sweep; pass resume (--resume) to "
                               "continue it, or choose another directory")


def test_unreadable_or_foreign_metadata_is_refused_naming_it(tmp_path: Path) -> None:
    cfg, out = _start(tmp_path)
    meta_path = out / "sweep.json"
    meta = json.loads(meta_path.read_text())
    meta_path.write_text("{")
    with pytest.raises(ValueError) as parse:
        json.loads("{")
    assert _refusal(cfg, out) == f"{meta_path}: unreadable sweep metadata: {parse.value}"
    meta["format"] = "it2track-sweep/1"
    meta_path.write_text(json.dumps(meta))
    assert _refusal(cfg, out) == f"{meta_path}: format 'it2track-sweep/1' is not it2track-sweep/2"
    del meta["format"]
    meta_path.write_text(json.dumps(meta))
    assert _refusal(cfg, out) == f"{meta_path}: format None is not it2track-sweep/2"


def test_sweep_json_is_read_as_utf8_whatever_the_platforms_default(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a sweep.json holding a raw non-ASCII label (written by hand, not by json's ASCII
    # escapes) and a changed noise level: only the noise level differs
    cfg, out = _start(tmp_path)
    cfg.write_text(textwrap.dedent(CONFIG).replace('kind = "flc"', 'kind = "flc"\nlabel = "θ"'),
                   encoding="utf-8")
    plan = load_sweep_config(cfg)
    meta = json.loads((out / "sweep.json").read_text())
    meta["config"] = {**plan.normalised(), "noise_std": [0.2]}
    meta["hash"] = "0" * 64
    (out / "sweep.json").write_text(json.dumps(meta, ensure_ascii=False), encoding="utf-8")
    read_text = Path.read_text

    def latin1_default(self, encoding=None, errors=None, **kw):
        return read_text(self, encoding=encoding or "latin-1", errors=errors, **kw)

    monkeypatch.setattr(Path, "read_text", latin1_default)
    assert "differs in: noise_std);" in _refusal(cfg, out)


def test_a_chunk_changed_during_assembly_stops_it_naming_both_digests(tmp_path: Path) -> None:
    from it2track.experiments.sweep.store import _assemble, chunk_path

    cfg, out = _start(tmp_path)
    plan = load_sweep_config(cfg)
    digests = {c.id: _sha(chunk_path(out, c.id)) for c in plan.chunks()}
    last = plan.chunks()[-1].id
    actual, digests[last] = digests[last], "f" * 64
    with pytest.raises(StoreError) as info:
        _assemble(plan, out, plan.header_csv(), digests, force=False)
    assert str(info.value) == (
        f"{chunk_path(out, last)} changed while the sweep was assembling results.csv (sha256 "
        f"ffffffffffff expected, {actual[:12]} found); rerun with --resume to recompute it")


def test_sweep_json_records_the_plan(tmp_path: Path) -> None:
    from it2track import __version__

    cfg, out = _start(tmp_path)
    plan = load_sweep_config(cfg)
    text = (out / "sweep.json").read_text()
    assert text == json.dumps(json.loads(text), indent=1) + "\n"  # one space per level
    assert json.loads(text) == {
        "format": "it2track-sweep/2", "hash": plan.config_hash(), "config": plan.normalised(),
        "n_runs": 4, "n_chunks": 1, "columns": plan.columns,
        "run_order": ["group", "controller", "trajectory", "noise_std", "seed"],
        "source": str(cfg), "trajectory_files": {"wp": str(tmp_path / "wp.csv")},
        "controller_files": {"ctrl.t2fis": str(tmp_path / "ctrl.t2fis")},
        "it2track_version": __version__}


def test_chunks_without_sweep_json_are_refused_naming_the_first(tmp_path: Path) -> None:
    cfg, out = _start(tmp_path)
    chunk = out / "chunks" / "chunk-000000.csv"
    (out / "chunks" / "chunk-000007.csv").write_bytes(chunk.read_bytes())
    (out / "sweep.json").unlink()
    with pytest.raises(StoreError) as info:
        run_sweep(load_sweep_config(cfg), out, resume=True, progress=False)
    assert str(info.value) == (
        f"{out}: chunks/ holds 2 chunk file(s) (e.g. chunk-000000.csv) but no sweep.json; "
        "they belong to an unknown sweep: remove them or use another directory")


def test_a_plan_with_a_nan_is_refused_before_sweep_json_is_written(tmp_path: Path) -> None:
    # (a TOML file cannot give one -- every float is checked finite -- but SweepPlan built in
    # Python can, in a plant column: sweep.json stays strict JSON and nothing is written)
    import math
    from dataclasses import replace

    cfg, _ = _start(tmp_path)
    plan = load_sweep_config(cfg)
    plan = replace(plan, robot_columns={"half_track": (math.nan,) * len(plan.robots)})
    out = tmp_path / "nan"
    with pytest.raises(ValueError, match="Out of range float values are not JSON compliant"):
        run_sweep(plan, out, progress=False)
    assert sorted(p.name for p in out.iterdir()) == [".lock", "chunks"]


def test_a_chunks_checksum_file_is_named_after_it(tmp_path: Path) -> None:
    from it2track.experiments.sweep import digest_path

    assert digest_path(Path("d/chunk-000042.csv")) == Path("d/chunk-000042.csv.sha256")
    _, out = _start(tmp_path)
    assert sorted(p.name for p in (out / "chunks").iterdir()) == [
        "chunk-000000.csv", "chunk-000000.csv.sha256"]

"""``load``/``save``: dispatch by suffix, atomic writes, encodings."""

from __future__ import annotations

import dataclasses
import os
import stat

import pytest

from it2track import atomicfile as _atomic
from it2track import heading_fls
from it2track.io import (
    FisFormatError,
    UnsupportedFeatureError,
    format_of,
    load,
    save,
)


def test_format_by_suffix() -> None:
    assert format_of("a.toml") == "toml"
    assert format_of("a.T2FIS") == "t2fis"
    assert format_of("dir.v2/a.fis") == "fis"
    with pytest.raises(ValueError, match=r"unknown fuzzy-system file suffix '\.json'"):
        format_of("a.json")


def test_save_and_load_each_suffix(tmp_path) -> None:
    fls = heading_fls(0.2)
    for suffix in (".toml", ".t2fis", ".fis"):
        path = tmp_path / f"c{suffix}"
        save(fls, path)
        assert float(load(path)(0.5, 0.0)) == 4.0
        assert float(load(str(path))(0.5, 0.0)) == 4.0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.fis", "c.t2fis", "c.toml"]


def test_saved_file_has_ordinary_permissions(tmp_path) -> None:
    path = tmp_path / "c.toml"
    save(heading_fls(0.2), path)
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask


def test_unsupported_content_writes_nothing(tmp_path) -> None:
    path = tmp_path / "c.t2fis"
    with pytest.raises(UnsupportedFeatureError):
        save(dataclasses.replace(heading_fls(0.2), on_zero_firing=0.0), path)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(ValueError, match="suffix"):
        save(heading_fls(0.2), tmp_path / "c.txt")
    assert list(tmp_path.iterdir()) == []


def test_failed_replace_keeps_the_old_file_and_leaves_no_temporary(tmp_path, monkeypatch) -> None:
    path = tmp_path / "c.toml"
    save(heading_fls(0.1), path)
    before = path.read_bytes()

    def broken(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(_atomic.os, "replace", broken)
    with pytest.raises(OSError, match="disk full"):
        save(heading_fls(0.3), path)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["c.toml"]


def test_error_inside_atomic_open_removes_the_temporary(tmp_path) -> None:
    path = tmp_path / "x.bin"
    with pytest.raises(RuntimeError), _atomic.atomic_open(path, "wb") as fh:
        fh.write(b"half")
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(ValueError, match="mode"):
        with _atomic.atomic_open(path, "a"):
            pass  # pragma: no cover


def test_load_errors(tmp_path) -> None:
    with pytest.raises(FileNotFoundError):
        load(tmp_path / "missing.toml")
    with pytest.raises(ValueError, match="suffix"):
        load(tmp_path / "missing.xml")
    bad = tmp_path / "bad.toml"
    bad.write_bytes(b'format = "it2track-fuzzy-system"\nname = "\xff"\n')
    with pytest.raises(FisFormatError) as info:
        load(bad)
    assert info.value.line == 2 and "not valid UTF-8" in info.value.message


def test_latin1_and_bom_matlab_files(tmp_path) -> None:
    from pathlib import Path

    text = (Path(__file__).parent / "data" / "tipper.fis").read_text()
    latin = tmp_path / "latin.fis"
    latin.write_bytes(text.replace("'tipper'", "'caf\xe9'").encode("latin-1"))
    assert load(latin).name == "caf\xe9"
    bom = tmp_path / "bom.fis"
    bom.write_bytes(b"\xef\xbb\xbf" + text.encode())
    assert load(bom).name == "tipper"

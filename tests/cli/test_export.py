"""``it2track export c``: generated files, every bad option refused before anything is written,
and no foreign file ever replaced."""

from __future__ import annotations

import os
import subprocess

import pytest
from click.testing import CliRunner

import it2track
from it2track.cli.main import main
from it2track.codegen.tools import missing_tools
from it2track.fuzzy import Gaussian, Input, IT2Set, IT2Sugeno, Rule
from it2track.io import save

STRICT = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O2"]


def run(*args):
    return CliRunner().invoke(main, ["export", "c", *map(str, args)])


def test_paper_export_writes_header_and_source_that_compile(tmp_path):
    out = tmp_path / "ctrl"
    res = run("--paper", 0.2, "--out", out)
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in out.iterdir()) == ["it2.c", "it2.h"]
    src = (out / "it2.c").read_text()
    assert "it2_eval" in src and "malloc" not in src and "#include <math.h>" not in src
    if missing_tools(["gcc"]):
        pytest.skip("compiling needs the Debian package gcc")
    subprocess.run(["gcc", *STRICT, "-c", "it2.c"], cwd=out, check=True)


def test_options_select_real_reducer_and_prefix(tmp_path):
    res = run("--paper", 0.3, "--out", tmp_path, "--real", "float", "--reducer", "eiasc",
              "--prefix", "left_ctrl")
    assert res.exit_code == 0, res.output
    head = (tmp_path / "left_ctrl.h").read_text()
    src = (tmp_path / "left_ctrl.c").read_text()
    assert "typedef float left_ctrl_real;" in head
    assert "int left_ctrl_eval(" in head and "LEFT_CTRL_OK 0" in head
    assert "EIASC" in src and "0.35f" not in src  # float literals are exact float32 values


def test_q15_export_names_its_scaling_and_compiles(tmp_path):
    res = run("--paper", 0.2, "--out", tmp_path, "--real", "q15", "--reducer", "exhaustive")
    assert res.exit_code == 0, res.output
    assert "fixed point: in[0] Q15, in[1] Q15; u, yl, yr Q11" in res.output
    head = (tmp_path / "it2.h").read_text()
    assert "typedef int16_t it2_real;" in head and "#define IT2_OUT_FRAC 11" in head
    src = (tmp_path / "it2.c").read_text()
    assert "float" not in src and "double" not in src
    if missing_tools(["gcc"]):
        pytest.skip("compiling needs the Debian package gcc")
    subprocess.run(["gcc", *STRICT, "-c", "it2.c"], cwd=tmp_path, check=True)


def test_q15_refuses_what_fixed_point_does_not_carry(tmp_path):
    res = run("--paper", 0.2, "--out", tmp_path, "--real", "q15", "--reducer", "wu-mendel")
    assert res.exit_code == 2 and "Wu-Mendel" in res.output and "Traceback" not in res.output
    assert list(tmp_path.iterdir()) == []


def test_system_file_exports_with_its_own_reducer(tmp_path):
    path = tmp_path / "c.toml"
    save(it2track.heading_fls(0.1, reducer=it2track.fuzzy.EKM), path)
    res = run(path, "--out", tmp_path / "o")
    assert res.exit_code == 0, res.output
    assert "reducer ekm" in res.output


def _lagged(tmp_path):
    a = IT2Set.from_scale_lag(Gaussian(-1, 0.5), scale=0.8, lag=0.2, name="A")
    b = IT2Set.from_scale_lag(Gaussian(1, 0.5), scale=0.8, lag=0.2, name="B")
    fls = IT2Sugeno(inputs=[Input("x", (-2, 2), [a, b])],
                    rules=[Rule(["A"], -1.0), Rule(["B"], 1.0)], name="lagged")
    path = tmp_path / "lagged.toml"
    save(fls, path)
    return path


@pytest.mark.parametrize("args, hint, words", [
    (["--paper", "0.2", "--paper", "nan"], "--paper", "finite"),
    (["--paper", "-0.1"], "--paper", ">= 0"),
    (["--paper", "1.7"], "--paper", "1.6"),
    (["--paper", "0.2", "--prefix", "Bad-Name"], "--prefix", "identifier"),
    (["--paper", "0.2", "--prefix", "int"], "--prefix", "keyword"),
    (["--paper", "0", "--reducer", "km"], "--reducer", "type-1"),
    (["--paper", "0.2", "--real", "half"], "--real", "half"),
    (["--paper", "0.2", "--reducer", "fast"], "--reducer", "fast"),
])
def test_bad_options_are_refused_naming_the_option(tmp_path, args, hint, words):
    out = tmp_path / "out"
    res = run(*args, "--out", out)
    assert res.exit_code == 2, res.output
    assert hint in res.output and words in res.output
    assert not out.exists()


def test_system_and_paper_are_exclusive(tmp_path):
    res = run(tmp_path / "x.toml", "--paper", "0.2", "--out", tmp_path / "o")
    assert res.exit_code == 2 and "exactly one" in res.output
    res = run("--out", tmp_path / "o")
    assert res.exit_code == 2 and "exactly one" in res.output


def test_bad_system_files_are_refused(tmp_path):
    out = tmp_path / "o"
    for path, words in [(tmp_path / "missing.toml", "no such file"),
                        (tmp_path / "c.txt", "suffix"),
                        (tmp_path, "suffix")]:
        res = run(path, "--out", out)
        assert res.exit_code == 2 and words in res.output, res.output
    fifo = tmp_path / "pipe.t2fis"
    os.mkfifo(fifo)
    res = run(fifo, "--out", out)
    assert res.exit_code == 2 and "not a regular file" in res.output
    bad = tmp_path / "bad.toml"
    bad.write_text("format = 3\n")
    res = run(bad, "--out", out)
    assert res.exit_code == 2 and "bad.toml" in res.output
    assert not out.exists()


def test_unsupported_system_is_refused_before_anything_is_written(tmp_path):
    out = tmp_path / "o"
    res = run(_lagged(tmp_path), "--out", out)
    assert res.exit_code == 2
    assert "cannot generate C" in res.output and "scale" in res.output.lower()
    assert not out.exists()


def test_out_directory_checks(tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("x")
    res = run("--paper", 0.2, "--out", afile)
    assert res.exit_code == 2 and "not a directory" in res.output
    res = run("--paper", 0.2, "--out", tmp_path / "no" / "such")
    assert res.exit_code == 2 and "does not exist" in res.output
    res = run("--paper", 0.2, "--out", "")
    assert res.exit_code == 2 and "--out" in res.output


def test_never_replaces_a_foreign_file_without_force(tmp_path):
    (tmp_path / "it2.c").write_text("/* mine */\n")
    res = run("--paper", 0.2, "--out", tmp_path)
    assert res.exit_code == 2 and "not written by it2track" in res.output
    assert (tmp_path / "it2.c").read_text() == "/* mine */\n"
    assert not (tmp_path / "it2.h").exists()  # nothing written, not even the other file
    res = run("--paper", 0.2, "--out", tmp_path, "--force")
    assert res.exit_code == 0, res.output
    assert (tmp_path / "it2.c").read_text().startswith("/* Generated by it2track")


def test_replaces_its_own_files(tmp_path):
    assert run("--paper", 0.2, "--out", tmp_path).exit_code == 0
    res = run("--paper", 0.3, "--out", tmp_path)
    assert res.exit_code == 0, res.output
    assert "-0.95" in (tmp_path / "it2.c").read_text()  # Z's upper foot -0.8 - 0.3/2


def test_force_never_replaces_what_is_not_a_regular_file(tmp_path):
    target = tmp_path / "elsewhere.c"
    target.write_text("/* keep */\n")
    os.symlink(target, tmp_path / "it2.c")
    res = run("--paper", 0.2, "--out", tmp_path, "--force")
    assert res.exit_code == 2 and "not a regular file" in res.output
    assert target.read_text() == "/* keep */\n" and (tmp_path / "it2.c").is_symlink()
    (tmp_path / "it2.c").unlink()
    (tmp_path / "it2.h").mkdir()
    res = run("--paper", 0.2, "--out", tmp_path, "--force")
    assert res.exit_code == 2 and "not a regular file" in res.output
    assert not (tmp_path / "it2.c").exists()

"""The example configs ship inside the package: ``it2track config show`` prints or writes them,
every ``--config`` option takes a packaged name as well as a file, and each packaged config is
valid for the command it is meant for."""

from __future__ import annotations

import os
from pathlib import Path

import click
import pytest
from click.testing import CliRunner

from it2track import configs
from it2track.cli.config import ConfigFile
from it2track.cli.main import main

NAMES = ("optimize", "paper", "sweep", "sweep_dc_motor")


def test_the_packaged_names_and_files():
    assert configs.names() == NAMES
    for name in NAMES:
        p = configs.path(name)
        assert p.is_file() and p.suffix == ".toml" and p.stem == name
        assert p.parent.name == "configs" and p.parent.parent.name == "it2track"
        assert configs.text(name) == p.read_text(encoding="utf-8")
    with pytest.raises(ValueError, match="'papr' is not a packaged config; the names are "
                                         "optimize, paper, sweep, sweep_dc_motor"):
        configs.path("papr")


def test_each_packaged_config_loads_with_its_reader():
    from it2track.experiments.optimize import load_optimize_config
    from it2track.experiments.study import StudyConfig, load_study_config
    from it2track.experiments.sweep import load_sweep_config

    assert load_study_config(configs.path("paper")) == StudyConfig()
    # the sweep's own comment: 2 plant sets x 9 controllers x 3 paths x 4 levels x 50 seeds
    assert load_sweep_config(configs.path("sweep")).n_runs == 2 * 9 * 3 * 4 * 50
    opt = load_optimize_config(configs.path("optimize"))
    assert opt.compare == (0.1, 0.2, 0.3)


@pytest.mark.parametrize("name", NAMES)
def test_show_prints_the_packaged_text(name):
    result = CliRunner().invoke(main, ["config", "show", name])
    assert result.exit_code == 0, result.output
    assert result.output == configs.text(name)


def test_show_out_writes_a_copy_and_never_replaces_a_file(tmp_path):
    out = tmp_path / "mine.toml"
    ok = CliRunner().invoke(main, ["config", "show", "sweep", "--out", str(out)])
    assert ok.exit_code == 0, ok.output
    assert out.read_bytes() == configs.path("sweep").read_bytes()
    assert f"--config {out}" in ok.output
    out.write_text("# my edits\n")
    again = CliRunner().invoke(main, ["config", "show", "sweep", "--out", str(out)])
    assert again.exit_code == 2 and "exists" in again.output and "--force" in again.output
    assert out.read_text() == "# my edits\n"
    forced = CliRunner().invoke(main, ["config", "show", "paper", "--out", str(out), "--force"])
    assert forced.exit_code == 0 and out.read_text() == configs.text("paper")


@pytest.mark.parametrize("case", ["folder", "symlink", "no-parent", "empty"])
def test_show_out_refuses_what_is_not_a_new_file(tmp_path, case):
    target = {"folder": tmp_path, "symlink": tmp_path / "link.toml",
              "no-parent": tmp_path / "nowhere" / "x.toml", "empty": ""}[case]
    if case == "symlink":
        (tmp_path / "real.toml").write_text("keep")
        os.symlink(tmp_path / "real.toml", target)
    before = sorted(p.name for p in tmp_path.iterdir())
    result = CliRunner().invoke(main, ["config", "show", "paper", "--out", str(target),
                                       "--force"])
    assert result.exit_code == 2 and "--out" in result.output, result.output
    assert "Traceback" not in result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    if case == "symlink":
        assert (tmp_path / "real.toml").read_text() == "keep"


def test_show_refuses_an_unknown_name():
    result = CliRunner().invoke(main, ["config", "show", "papers"])
    assert result.exit_code == 2
    assert "'papers' is not a packaged config; the names are optimize, paper, sweep" in (
        result.output)


def test_a_config_value_is_a_file_first_then_a_packaged_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    conv = ConfigFile()
    assert Path(conv.convert("paper", None, None)) == configs.path("paper")
    Path("paper").write_text("[study]\n")  # a file of that name in the current folder wins
    assert conv.convert("paper", None, None) == "paper"
    assert conv.convert(str(tmp_path / "paper"), None, None) == str(tmp_path / "paper")
    with pytest.raises(click.BadParameter, match="'nope': no such file, and not a packaged "
                                                 "config"):
        conv.convert("nope", None, None)
    with pytest.raises(click.BadParameter, match="is a folder"):
        conv.convert(str(tmp_path), None, None)
    with pytest.raises(click.BadParameter, match="empty"):
        conv.convert("", None, None)


def _config_options(command: click.Command, path: str = "it2track"):
    for param in command.params:
        if "--config" in getattr(param, "opts", ()):
            yield path, param
    for name, sub in getattr(command, "commands", {}).items():
        yield from _config_options(sub, f"{path} {name}")


def test_every_config_option_takes_a_packaged_name():
    found = dict(_config_options(main))
    assert set(found) == {"it2track reproduce", "it2track sweep", "it2track optimize"}
    for where, param in found.items():
        assert isinstance(param.type, ConfigFile), where


@pytest.mark.parametrize(("command", "name"), [("sweep", "sweep"), ("optimize", "optimize")])
def test_sweep_and_optimize_read_a_packaged_config_by_name(command, name, tmp_path,
                                                           monkeypatch):
    from it2track.experiments.specs import ConfigError

    read = []

    def stop(path):
        read.append(Path(path))
        raise ConfigError("stop here")  # the command reports it as a config error

    loader = "load_sweep_config" if command == "sweep" else "load_optimize_config"
    module = ("it2track.experiments.sweep" if command == "sweep"
              else "it2track.experiments.optimize")
    monkeypatch.setattr(f"{module}.{loader}", stop)
    result = CliRunner().invoke(main, [command, "--config", name, "--out",
                                       str(tmp_path / "o")])
    assert read == [configs.path(name)], result.output
    assert "stop here" in result.output and "Traceback" not in result.output

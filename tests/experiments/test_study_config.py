"""The study's TOML configuration: defaults, strictness, error messages."""

from dataclasses import replace
from pathlib import Path

import pytest

from it2track.experiments.specs import ConfigError, ControllerKind, ControllerSpec
from it2track.experiments.study import StudyConfig, experiment_sizes, load_study_config

ROOT = Path(__file__).resolve().parents[2]


def test_paper_toml_equals_the_defaults():
    # configs/paper.toml documents the defaults; the two must not drift apart.
    assert load_study_config(ROOT / "configs" / "paper.toml") == StudyConfig()


def write(tmp_path, text):
    p = tmp_path / "study.toml"
    p.write_text(text)
    return p


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("[study]\nseedz = 3\n", "unknown key(s) ['seedz']"),
        ("[simulation]\nts = 'fast'\n", "ts='fast' must be a number"),
        ("[study]\nseeds = 0\n", "seeds=0"),
        ("[study]\nfous = [0.1, -0.2]\n", "fous"),
        ("[study]\nmain_fou = 0.25\n", "main_fou"),
        ("[robot.motor]\nresistance = -5.0\n", "resistance"),
        ("[robot]\nwheelradius = 0.1\n", "wheelradius"),
        ("[simulation]\nduration = 1.005\n", "whole number of periods"),
        ("[study]\ntrajectories = ['spiral']\n", "unknown trajectory 'spiral'"),
        ("[[controllers]]\nkind = 'fuzzy'\n", "kind='fuzzy'"),
        ("[[controllers]]\nkind = 'it2'\nfou = 0.2\nke = 'x'\n", "ke='x'"),
        ("[study\n", "invalid TOML"),
        ("[banana]\n", "unknown key(s) ['banana']"),
    ],
)
def test_bad_config_names_file_key_and_value(tmp_path, text, needle):
    path = write(tmp_path, text)
    with pytest.raises(ConfigError) as info:
        load_study_config(path)
    message = str(info.value)
    assert str(path) in message, message
    assert needle in message, message


def test_config_values_are_applied(tmp_path):
    path = write(
        tmp_path,
        "[simulation]\nduration = 2.0\n[robot]\nhalf_track = 0.3\n[study]\nseeds = 5\n"
        "fous = [0.3]\nmain_fou = 0.3\npd_baseline = false\n"
        "[[controllers]]\nkind = 'it2'\nfou = 0.5\nke = 2.0\n",
    )
    cfg = load_study_config(path)
    assert cfg.loop.duration == 2.0
    assert cfg.loop.robot.half_track == 0.3
    assert cfg.seeds == 5 and cfg.fous == (0.3,) and cfg.pd is None
    assert cfg.extra_controllers == (ControllerSpec(kind=ControllerKind.IT2, fou=0.5, ke=2.0),)
    # the extra controller joins every experiment's line-up except the FoU sweep
    labels = [s.label for s in cfg.paper_controllers(None)]
    assert "IT2FLC FoU 0.5 Ke 2 Kde 1" in labels


def test_file_controller_path_is_relative_to_the_config(tmp_path):
    path = write(tmp_path, "[[controllers]]\nkind = 'file'\npath = 'mine.t2fis'\n")
    cfg = load_study_config(path)
    assert cfg.extra_controllers[0].path == str(tmp_path / "mine.t2fis")


def test_experiment_sizes_count_runs():
    cfg = replace(StudyConfig(), seeds=2, sweep_seeds=3, pd=None)
    sizes = experiment_sizes(cfg)
    # paper: FLC + 3 IT2 + 3 matched = 7 controllers x 3 trajectories x 2 seeds
    assert sizes["paper"] == 7 * 3 * 2
    # noise: FLC + 3 IT2 + 1 matched = 5 x 3 trajectories x 7 levels x 3 seeds
    assert sizes["noise"] == 5 * 3 * 7 * 3
    # fou: w = 0 (FLC) + 20 widths x (IT2 + matched) = 41 x 3 x 3
    assert sizes["fou"] == 41 * 3 * 3
    assert sizes["pd_tuning"] == 0

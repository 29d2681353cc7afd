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
        "fous = [0.3]\nmain_fou = 0.3\npd_baseline = false\nrobustness = false\n"
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
    import it2track

    it2track.save(it2track.heading_fls(0.25), tmp_path / "mine.t2fis")
    path = write(tmp_path, "[[controllers]]\nkind = 'file'\npath = 'mine.t2fis'\n")
    cfg = load_study_config(path)
    assert cfg.extra_controllers[0].path == str(tmp_path / "mine.t2fis")


def test_experiment_sizes_count_runs():
    cfg = replace(StudyConfig(), seeds=2, sweep_seeds=3, pd=None, tuning=None)
    sizes = experiment_sizes(cfg)
    # paper: FLC + 3 IT2 + 3 slope-matched + 3 dead-zone-matched = 10 controllers x 3
    # trajectories x 2 seeds
    assert sizes["paper"] == 10 * 3 * 2
    # noise: FLC + 3 IT2 + 2 matched + the surface copy = 7 x 3 trajectories x (6 noisy
    # levels x 3 seeds + one noise-free run) in the first round; at most the cap (400) seeds
    assert sizes["noise"] == 7 * 3 * (6 * 3 + 1)
    assert sizes["noise_cap"] == 7 * 3 * (6 * 400 + 1)
    # fou: w = 0 (FLC) + 20 widths x (IT2 + matched) = 41 x 3 x 3
    assert sizes["fou"] == 41 * 3 * 3
    assert sizes["pd_tuning"] == sizes["fuzzy_tuning"] == 0
    tuned = replace(StudyConfig(), seeds=2, sweep_seeds=3)
    sizes = experiment_sizes(tuned)
    # PD grid 15 x 11 plus the 4 paper fuzzy controllers (effort limit), 16 seeds, 3 paths;
    # each of the 4 tuned fuzzy controllers: 165 candidates on the same runs
    assert sizes["pd_tuning"] == (15 * 11 + 4) * 3 * 16
    assert sizes["fuzzy_tuning"] == 4 * 165 * 3 * 16
    assert sizes["paper"] == (10 + 1 + 4) * 3 * 2  # + the PD and the 4 tuned controllers


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("[study]\nnoise_levels = [0.05, 0.05]\n", "noise_levels"),
        ("[study]\ntrajectories = ['straight', 'straight']\n", "twice"),
        ("[[controllers]]\nkind = 'it2'\nfou = 0.2\n", "used by the study's own controllers"),
        ("[[controllers]]\nkind = 'pd'\nkp = 10.0\ntf = -0.1\n", "tf=-0.1"),
        ("[[controllers]]\nkind = 'file'\npath = 'missing.t2fis'\n", "missing.t2fis"),
        ("[[controllers]]\nkind = 'file'\npath = 'bad.t2fis'\n", "bad.t2fis"),
    ],
)
def test_bad_lineups_fail_at_load_time(tmp_path, text, needle):
    (tmp_path / "bad.t2fis").write_text("[System]\nName='x'\nType='sugeno'\n")
    path = write(tmp_path, text)
    with pytest.raises(ConfigError) as info:
        load_study_config(path)
    assert needle in str(info.value), str(info.value)


def test_waypoint_files_resolve_against_the_config_folder(tmp_path, monkeypatch):
    (tmp_path / "path.csv").write_text("t,x,y\n0,0,0\n1,1,0\n2,2,1\n3,3,1\n")
    path = write(tmp_path, "[study]\ntrajectories = ['path.csv', 'straight']\n")
    monkeypatch.chdir("/")
    cfg = load_study_config(path)
    assert cfg.trajectories == (str(tmp_path / "path.csv"), "straight")


def test_non_default_reducers_get_their_own_label():
    from it2track.experiments.specs import ControllerKind, ControllerSpec

    a = ControllerSpec(kind=ControllerKind.IT2, fou=0.2, reducer="KM")
    b = ControllerSpec(kind=ControllerKind.IT2, fou=0.2, reducer="km")
    assert a == b and a.label == "IT2FLC FoU 0.2 km"
    assert ControllerSpec(kind=ControllerKind.IT2, fou=0.2).label == "IT2FLC FoU 0.2"


def test_pd_tuning_matches_the_fuzzy_controllers_effort():
    # The tuned PD may not work harder than the most active paper fuzzy controller on the same
    # tuning runs, and is the lowest-ISE grid point that obeys that.
    from it2track.experiments.study import PDTuning, tune_pd
    from it2track.tracking import LoopConfig, get_trajectory, run_grid, simulate_metrics

    cfg = replace(StudyConfig(), loop=LoopConfig(duration=2.0), fous=(0.1, 0.3), main_fou=0.3,
                  pd=PDTuning(seeds=2, kp_grid=(2.0, 6.0, 20.0, 80.0), kd_grid=(0.0, 0.5)),
                  tuning=None, robustness=None)
    spec, rec = tune_pd(cfg)
    assert rec["effort_limit_rule"].startswith("largest mean effort")
    # The limit, computed independently: the paper's fuzzy controllers on the tuning runs
    # (seeds 1_000_000 + i at the study's sigma), the MOST active one's mean effort.
    fuzzy = [ControllerSpec(kind=ControllerKind.FLC).build()] + [
        ControllerSpec(kind=ControllerKind.IT2, fou=w).build() for w in (0.1, 0.3)]
    runs = run_grid(3, 3, [cfg.noise_std], [1_000_000, 1_000_001])
    m = simulate_metrics(fuzzy, [get_trajectory(t) for t in cfg.trajectories], runs, cfg.loop)
    means = m["effort"].reshape(3, -1).mean(axis=1)
    assert means.min() < means.max(), "the controllers' efforts must differ"
    assert rec["effort_limit"] == pytest.approx(means.max(), rel=1e-12)
    assert rec["effort"] <= rec["effort_limit"]
    feasible = [g for g in rec["grid"] if g[3] <= rec["effort_limit"]]
    assert (spec.kp, spec.kd) == tuple(min(feasible, key=lambda g: g[2])[:2])
    assert any(g[3] > rec["effort_limit"] for g in rec["grid"]), "limit binds nowhere"


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("[pd]\neffort_limit = 5.0\n", "match_effort = false"),
        ("[pd]\nmatch_effort = false\neffort_limit = -1.0\n", "effort_limit=-1.0"),
        ("[pd]\nseeds = 0\n", "seeds=0"),
        ("[pd]\nkp_grid = []\n", "kp_grid"),
        ("[pd]\nkd = 0.2\n", "without kp"),
    ],
)
def test_bad_pd_tuning_names_the_section(tmp_path, text, needle):
    path = write(tmp_path, text)
    with pytest.raises(ConfigError) as info:
        load_study_config(path)
    assert "[pd]" in str(info.value) and needle in str(info.value), str(info.value)


@pytest.mark.parametrize("text", [
    "[study]\npd_baseline = false\ntuning = true\n",
    "[pd]\nkp = 5.0\n[tuning]\nke_grid = [1.0]\n",
])
def test_an_explicit_fuzzy_tuning_needs_the_pd_tuning(tmp_path, text):
    path = write(tmp_path, text)
    with pytest.raises(ConfigError, match="tuning needs the PD tuning"):
        load_study_config(path)


def test_without_a_pd_tuning_the_fuzzy_controllers_stay_untuned(tmp_path):
    assert load_study_config(write(tmp_path, "[study]\npd_baseline = false\n")).tuning is None
    assert replace(StudyConfig(), pd=None).tuning is None
    cfg = replace(StudyConfig(), pd=None)
    assert "tuning" not in {c.name for c in cfg.robustness.choices}


def test_quick_keeps_the_users_pd_settings():
    from it2track.cli.reproduce import _quick
    from it2track.experiments.study import PDTuning

    cfg = replace(StudyConfig(), pd=PDTuning(match_effort=False, effort_limit=30.0, tf=0.05))
    quick = _quick(cfg).pd
    assert (quick.match_effort, quick.effort_limit, quick.tf) == (False, 30.0, 0.05)
    assert quick.seeds == 2
    given = replace(StudyConfig(), pd=PDTuning(kp=5.0, kd=0.1), tuning=None)
    assert _quick(given).pd == given.pd

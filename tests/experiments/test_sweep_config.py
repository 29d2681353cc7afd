"""Sweep configuration files: axes, run order, chunk layout and errors that name file/key/value."""

from __future__ import annotations

import itertools
import textwrap
from pathlib import Path

import pytest
from click.testing import CliRunner

from it2track import __version__
from it2track.cli.sweep import sweep as sweep_command
from it2track.experiments.specs import ConfigError
from it2track.experiments.sweep import expand_axes, load_sweep_config

BASE = """
[sweep]
seed = 3
seeds = 3
noise_std = [0.0, 0.1]
trajectories = ["straight", "curved"]
chunk_size = 5

[simulation]
duration = 1.0

[robot]
half_track = [5.6, 0.3]

[[controllers]]
kind = "flc"

[[controllers]]
kind = "it2"
fou = [0.1, 0.3]
"""


def write(tmp_path: Path, text: str, name: str = "sweep.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def test_axes_run_order_and_chunks(tmp_path: Path) -> None:
    plan = load_sweep_config(write(tmp_path, BASE))
    assert [c.label for c in plan.controllers] == ["FLC", "IT2FLC FoU 0.1", "IT2FLC FoU 0.3"]
    assert [r.half_track for r in plan.robots] == [5.6, 0.3]
    assert plan.robot_columns == {"half_track": (5.6, 0.3)}
    assert plan.config.seed == 3 and plan.config.duration == 1.0
    assert plan.seeds == (0, 1, 2) and plan.noise_std == (0.0, 0.1)
    assert plan.runs_per_group == 3 * 2 * 2 * 3
    assert plan.n_runs == 2 * 36
    chunks = plan.chunks()
    assert [c.id for c in chunks] == list(range(len(chunks)))
    # Chunks tile each group and never straddle two plant parameter sets.
    for g in range(2):
        mine = [c for c in chunks if c.group == g]
        assert mine[0].start == 0 and mine[-1].stop == plan.runs_per_group
        assert all(a.stop == b.start for a, b in itertools.pairwise(mine))
        assert all(0 < c.size <= 5 for c in mine)
    # A task decodes its index range in run order (seed fastest, then noise, trajectory, ctrl).
    task = plan.task(chunks[2])  # runs 10..14 of group 0
    runs = task.runs()
    assert task.controller_offset == 0 and len(task.controllers) == 2
    assert runs.seed.tolist() == [1, 2, 0, 1, 2]
    assert runs.noise_std.tolist() == [0.1, 0.1, 0.0, 0.0, 0.0]
    assert runs.trajectory.tolist() == [1, 1, 0, 0, 0]
    assert runs.controller.tolist() == [0, 0, 1, 1, 1]
    assert task.config.robot.half_track == 5.6
    assert plan.task(chunks[-1]).config.robot.half_track == 0.3


def test_hash_follows_results_not_batch_size(tmp_path: Path) -> None:
    a = load_sweep_config(write(tmp_path, BASE, "a.toml"))
    b = load_sweep_config(write(tmp_path, BASE.replace("chunk_size = 5", "chunk_size = 5\n"
                                                       "batch_size = 7"), "b.toml"))
    c = load_sweep_config(write(tmp_path, BASE.replace("seed = 3", "seed = 4"), "c.toml"))
    assert a.config_hash() == b.config_hash()
    assert a.config_hash() != c.config_hash()


def test_expand_axes_order() -> None:
    out = expand_axes({"kind": "it2", "fou": [0.1, 0.2], "ke": [1, 2]}, "x")
    assert [(d["fou"], d["ke"]) for d in out] == [(0.1, 1), (0.1, 2), (0.2, 1), (0.2, 2)]
    assert expand_axes({"kind": "flc"}, "x") == [{"kind": "flc"}]


def test_seed_forms(tmp_path: Path) -> None:
    plan = load_sweep_config(write(tmp_path, BASE.replace("seeds = 3", "seeds = [7, 2]")))
    assert plan.seeds == (7, 2)
    plan = load_sweep_config(
        write(tmp_path, BASE.replace("seeds = 3", "seeds = {start = 100, count = 2}"))
    )
    assert plan.seeds == (100, 101)


def test_waypoint_csv_trajectory_relative_to_config(tmp_path: Path) -> None:
    (tmp_path / "wp.csv").write_text("t,x,y\n0,0,0\n1,1,0\n2,2,0.5\n3,3,0\n")
    plan = load_sweep_config(
        write(tmp_path, BASE.replace('["straight", "curved"]', '["straight", "wp.csv"]'))
    )
    assert [r.name for r in plan.trajectory_refs] == ["straight", "wp"]
    before = plan.config_hash()
    (tmp_path / "wp.csv").write_text("t,x,y\n0,0,0\n1,1,0\n2,2,0.7\n3,3,0\n")
    plan2 = load_sweep_config(tmp_path / "sweep.toml")
    assert plan2.config_hash() != before  # the hash follows the file's content


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        # unknown keys, in every section
        ("[simulation]", "colour = 1\n[simulation]", "unknown key(s) ['colour']"),
        ("chunk_size = 5", "chunk_size = 5\nchunks = 2", "[sweep]: unknown key(s) ['chunks']"),
        ("duration = 1.0", "duration = 1.0\nstep = 2", "[simulation]: unknown key(s) ['step']"),
        ("half_track = [5.6, 0.3]", "half_track = [5.6, 0.3]\ntrack = 1.0",
         "[robot]: unknown key(s) ['track']"),
        ("half_track = [5.6, 0.3]", "half_track = 1.0\n[robot.motor]\nresistence = [1.0, 2.0]",
         "[robot.motor]: unknown key(s) ['resistence']"),
        ('kind = "flc"', 'kind = "flc"\ngain = 2.0', "[controllers][0]: unknown key(s) ['gain']"),
        # bad values
        ("noise_std = [0.0, 0.1]", "noise_std = [0.0, -0.1]", "noise_std value -0.1 must be >= 0"),
        ("noise_std = [0.0, 0.1]", 'noise_std = ["a"]', "noise_std[0]='a' must be a number"),
        ("seeds = 3", "seeds = 0", "seeds=0 must be a seed count >= 1"),
        ("seeds = 3", "seeds = [1, -2]", "seed indices must be >= 0"),
        ("seeds = 3", "seeds = [1, 1]", "seed indices must not repeat"),
        ("chunk_size = 5", "chunk_size = 0", "chunk_size=0 must be an integer >= 1"),
        ("chunk_size = 5", "chunk_size = 2.5", "chunk_size=2.5 must be an integer"),
        ("seed = 3", "seed = -1", "seed=-1 must be an integer >= 0"),
        ('["straight", "curved"]', '["straight", "zigzag"]', "unknown trajectory 'zigzag'"),
        ('["straight", "curved"]', '["straight", "missing.csv"]', "cannot read"),
        ('["straight", "curved"]', '["straight", "straight"]', "must not repeat"),
        ("fou = [0.1, 0.3]", "fou = [0.1, 1.7]", "fou=1.7 must satisfy 0 <= fou < 1.6"),
        ('kind = "flc"', 'kind = "fuzzy"', "kind='fuzzy' must be one of"),
        ("fou = [0.1, 0.3]", 'fou = [0.1, "wide"]', "fou='wide' must be a number"),
        ("half_track = [5.6, 0.3]", "half_track = [5.6, -1.0]",
         "half_track must be finite and > 0, got -1.0"),
        ("duration = 1.0", "duration = 1.005", "whole number of periods"),
        # empty axes
        ("noise_std = [0.0, 0.1]", "noise_std = []", "noise_std=[] is an empty axis"),
        ("seeds = 3", "seeds = []", "seeds=[] is an empty axis"),
        ('["straight", "curved"]', "[]", "trajectories=[] is an empty axis"),
        ("fou = [0.1, 0.3]", "fou = []", "[controllers][1]: fou=[] is an empty axis"),
        ("half_track = [5.6, 0.3]", "half_track = []", "[robot]: half_track=[] is an empty axis"),
        # controllers
        ("fou = [0.1, 0.3]", 'fou = [0.1, 0.3]\nlabel = "mine"', "cannot name 2 controllers"),
        ('kind = "flc"', 'kind = "it2"\nfou = 0.1', "repeats one of"),
    ],
)
def test_config_errors_name_file_key_value(
    tmp_path: Path, old: str, new: str, expected: str
) -> None:
    assert old in BASE
    path = write(tmp_path, BASE.replace(old, new, 1))
    with pytest.raises(ConfigError) as info:
        load_sweep_config(path)
    message = str(info.value)
    assert str(path) in message, message
    assert expected in message, message


def test_missing_sections(tmp_path: Path) -> None:
    no_ctrl = BASE[: BASE.index("[[controllers]]")]
    with pytest.raises(ConfigError, match=r"missing \[\[controllers\]\]"):
        load_sweep_config(write(tmp_path, no_ctrl))
    with pytest.raises(ConfigError, match="missing key 'noise_std'"):
        load_sweep_config(write(tmp_path, BASE.replace("noise_std = [0.0, 0.1]", "")))
    with pytest.raises(ConfigError, match="invalid TOML"):
        load_sweep_config(write(tmp_path, "[sweep\n"))


def test_loop_config_is_serialised_by_its_own_to_dict(tmp_path: Path) -> None:
    plan = load_sweep_config(write(tmp_path, BASE))
    data = plan.normalised()
    expected = plan.config.to_dict()
    del expected["robot"]  # the plant varies by group
    assert data["simulation"] == expected
    assert data["it2track_version"] == __version__


@pytest.mark.parametrize(
    ("entry", "file_text", "expected"),
    [
        ('kind = "file"\npath = "ctrl.t2fis"', "not a fuzzy system\n",
         "ctrl.t2fis:1: text before the first section"),
        ('kind = "file"\npath = "missing.t2fis"', None,
         "cannot read '{dir}/missing.t2fis': No such file or directory"),
        ('kind = "file"\npath = "ctrl.xyz"', "", "unknown fuzzy-system file suffix '.xyz'"),
        ('kind = "pd"\nkp = 20.0\ntf = -0.1', None, "tf=-0.1 must be >= 0"),
    ],
    ids=["malformed-t2fis", "missing-file", "bad-suffix", "pd-negative-tf"],
)
def test_controllers_are_built_while_parsing(
    tmp_path: Path, entry: str, file_text: str | None, expected: str
) -> None:
    """A controller that cannot be built is a ConfigError naming the file and the entry,
    raised before anything is written (not a traceback in the middle of the sweep)."""
    if file_text is not None:
        name = "ctrl.t2fis" if "ctrl.t2fis" in entry else "ctrl.xyz"
        (tmp_path / name).write_text(file_text, encoding="utf-8")
    path = write(tmp_path, BASE + f"\n[[controllers]]\n{entry}\n")
    with pytest.raises(ConfigError) as info:
        load_sweep_config(path)
    message = str(info.value)
    assert f"{path} [controllers][2]: controller " in message, message
    assert expected.format(dir=tmp_path) in message, message

    out = tmp_path / "out"
    result = CliRunner().invoke(sweep_command, ["--config", str(path), "--out", str(out)])
    assert result.exit_code == 1 and isinstance(result.exception, SystemExit), result.output
    assert expected.format(dir=tmp_path) in result.output
    assert not out.exists()  # nothing written: the corrected config can start the sweep

"""The sweep file's parsers one at a time (sweep/config.py), on tiny inputs: every check at its
boundary, every message to the letter (file, section, key and value), the order of the axes and
what each default is. Fast (no simulation): the mutation run of ``sweep.config`` uses these."""

from __future__ import annotations

import hashlib
import json
import math
import textwrap
from pathlib import Path

import pytest

from it2track import _limits
from it2track.experiments.specs import ConfigError, ControllerSpec, Table
from it2track.experiments.sweep import SweepPlan, load_sweep_config
from it2track.experiments.sweep.config import (
    _parse_controllers,
    _parse_robots,
    _positive_int,
    _unique_trajectory_names,
    check_targets,
    expand_axes,
    parse_noise_levels,
    parse_seeds,
    parse_trajectories,
)
from it2track.experiments.sweep.refs import ControllerRef, TrajectoryRef
from it2track.plant import MotorParams, RobotParams
from it2track.tracking import LoopConfig, StepReference, get_trajectory

W = "f.toml [sweep]"
BIG = 2**63  # one past the largest seed index


def sweep_table(**data) -> Table:
    return Table(data, "f.toml", section="sweep")


def error(call, *args, **kwargs) -> str:
    """The message of the ConfigError ``call`` raises (exactly that class, no chained cause)."""
    with pytest.raises(ConfigError) as info:
        call(*args, **kwargs)
    assert type(info.value) is ConfigError
    assert info.value.__cause__ is None  # (``from None``: no other error in the traceback)
    assert info.value.__context__ is None or info.value.__suppress_context__
    return str(info.value)


def limit_memory(monkeypatch: pytest.MonkeyPatch, available: int) -> None:
    monkeypatch.setattr(_limits, "available_memory", lambda: available)


# -- expand_axes -----------------------------------------------------------------------------


def test_expand_axes_crosses_lists_first_key_slowest_and_keeps_key_order() -> None:
    out = expand_axes({"ke": [1, 2], "kind": "it2", "fou": [0.1, 0.2, 0.3]}, "x")
    assert out == [{"ke": k, "kind": "it2", "fou": f} for k in (1, 2) for f in (0.1, 0.2, 0.3)]
    assert all(list(d) == ["ke", "kind", "fou"] for d in out)


def test_expand_axes_without_lists_is_one_copy_and_leaves_tables_alone() -> None:
    data = {"kind": "flc", "motor": {"resistance": [1.0, 2.0]}}
    out = expand_axes(data, "x")
    assert out == [data] and out[0] is not data
    assert expand_axes({}, "x") == [{}]
    assert expand_axes({"a": [5]}, "x") == [{"a": 5}]


def test_expand_axes_refuses_an_empty_axis_naming_the_first() -> None:
    assert error(expand_axes, {"kind": "it2", "ke": [1], "fou": [], "kde": []}, "w.toml [c]") == (
        "w.toml [c]: fou=[] is an empty axis (give at least one value)")


# -- parse_seeds -----------------------------------------------------------------------------


def test_seed_count_list_and_table_forms() -> None:
    assert parse_seeds(sweep_table(seeds=3), "seeds") == (0, 1, 2)
    assert parse_seeds(sweep_table(seeds=1), "seeds") == (0,)
    assert parse_seeds(sweep_table(seeds=[7, 0, 2]), "seeds") == (7, 0, 2)
    assert parse_seeds(sweep_table(seeds=[BIG - 1]), "seeds") == (BIG - 1,)
    assert parse_seeds(sweep_table(seeds={"start": 5, "count": 3}), "seeds") == (5, 6, 7)
    assert parse_seeds(sweep_table(seeds={"count": 2}), "seeds") == (0, 1)
    assert parse_seeds(sweep_table(seeds={"start": 0, "count": 1}), "seeds") == (0,)
    assert parse_seeds(sweep_table(s={"start": BIG - 1, "count": 1}), "s") == (BIG - 1,)
    for value in (3, [1], {"count": 1}):
        t = sweep_table(seeds=value)
        assert isinstance(parse_seeds(t, "seeds"), tuple)
        t.done()  # the key counts as used


def test_seed_default_and_missing_key() -> None:
    t = sweep_table()
    assert parse_seeds(t, "seeds", [4, 9]) == (4, 9)
    assert isinstance(parse_seeds(t, "seeds", [4, 9]), tuple)
    assert parse_seeds(t, "seeds", ()) == ()
    assert error(parse_seeds, t, "seeds") == "f.toml [sweep]: missing key 'seeds'"


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (0, f"{W}: seeds=0 must be a seed count >= 1, a list or a table"),
        (-4, f"{W}: seeds=-4 must be a seed count >= 1, a list or a table"),
        (True, f"{W}: seeds=True must be an integer"),
        (2.0, f"{W}: seeds=2.0 must be an integer"),
        (BIG + 1, f"{W}: seeds={BIG + 1}: seed indices must lie in [0, 2**63 - 1]"),
        ([], f"{W}: seeds=[] is an empty axis (give at least one seed index)"),
        ([1, -2, -3], f"{W}: seeds=[1, -2, -3]: seed indices must be >= 0 (got -2)"),
        ([1, "a"], f"{W}: seeds[1]='a' must be an integer"),
        ([3, BIG, BIG + 1],
         f"{W}: seeds: seed index {BIG} is larger than 2**63 - 1, the largest allowed"),
        ([1, 2, 1], f"{W}: seeds=[1, 2, 1]: seed indices must not repeat"),
        ({"start": -1, "count": 2},
         f"{W}: seeds={{'start': -1, 'count': 2}} needs start >= 0 and count >= 1"),
        ({"start": 0, "count": 0},
         f"{W}: seeds={{'start': 0, 'count': 0}} needs start >= 0 and count >= 1"),
        ({"start": BIG - 1, "count": 2},
         f"{W}: seeds={{'start': {BIG - 1}, 'count': 2}}: seed indices must lie in "
         f"[0, 2**63 - 1] (the last would be {BIG})"),
        ({"start": 1}, "f.toml [sweep.seeds]: missing key 'count'"),
        ({"count": 2, "stop": 4}, "f.toml [sweep.seeds]: unknown key(s) ['stop']"),
        ({"start": 1.5, "count": 2}, "f.toml [sweep.seeds]: start=1.5 must be an integer"),
    ],
)
def test_bad_seeds_are_refused_naming_the_value(value, message: str) -> None:
    assert error(parse_seeds, sweep_table(seeds=value), "seeds") == message


def test_a_seed_count_that_cannot_fit_in_memory_is_refused(monkeypatch) -> None:
    # 2**63 seeds pass the index check (the last is 2**63 - 1) and fail the memory check
    message = error(parse_seeds, sweep_table(seeds=BIG), "seeds")
    assert message.startswith(f"{W}: seeds: {BIG} seed indices needs an estimated ")
    assert message.endswith("; give fewer seeds")
    limit_memory(monkeypatch, 500)  # 100 bytes a seed index
    assert parse_seeds(sweep_table(seeds=5), "seeds") == (0, 1, 2, 3, 4)
    assert parse_seeds(sweep_table(seeds={"start": 9, "count": 5}), "seeds") == tuple(
        range(9, 14))
    limit_memory(monkeypatch, 499)
    for value in (5, {"start": 9, "count": 5}):
        assert error(parse_seeds, sweep_table(seeds=value), "seeds") == (
            f"{W}: seeds: 5 seed indices needs an estimated 500 B of memory, more than the "
            "499 B available; give fewer seeds")
    assert parse_seeds(sweep_table(seeds=list(range(5))), "seeds") == (0, 1, 2, 3, 4)


# -- parse_noise_levels ----------------------------------------------------------------------


def test_noise_levels_a_number_or_a_list() -> None:
    assert parse_noise_levels(sweep_table(noise_std=0.1), "noise_std") == (0.1,)
    levels = parse_noise_levels(sweep_table(noise_std=[0, 0.5, 1e6]), "noise_std")
    assert levels == (0.0, 0.5, 1e6) and isinstance(levels, tuple)
    assert [type(v) for v in levels] == [float, float, float]
    assert parse_noise_levels(sweep_table(noise_std=[-0.0]), "noise_std") == (0.0,)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ([], f"{W}: noise_std=[] is an empty axis (give at least one value)"),
        ([0.1, -1.0, -2.0], f"{W}: noise_std value -1.0 must be >= 0"),
        (-5e-324, f"{W}: noise_std value -5e-324 must be >= 0"),
        ([0.0, math.nextafter(1e6, 2e6), 3e6],
         f"{W}: noise_std value 1000000.0000000001 exceeds 1e+06 rad, the largest heading-noise "
         "standard deviation allowed (beyond it theta + noise loses all precision, and far "
         "beyond it overflows)"),
        ([0.1, 0.2, 0.1], f"{W}: noise_std=[0.1, 0.2, 0.1]: values must not repeat"),
        ([0.0, -0.0], f"{W}: noise_std=[0.0, -0.0]: values must not repeat"),
        (math.nan, f"{W}: noise_std=nan must be finite"),
        ([0.1, "a"], f"{W}: noise_std[1]='a' must be a number"),
        ("a", f"{W}: noise_std='a' must be a number"),
    ],
)
def test_bad_noise_levels_are_refused_naming_the_value(value, message: str) -> None:
    assert error(parse_noise_levels, sweep_table(noise_std=value), "noise_std") == message


def test_noise_levels_are_required() -> None:
    assert error(parse_noise_levels, sweep_table(), "noise_std") == (
        f"{W}: missing key 'noise_std'")


# -- parse_trajectories ----------------------------------------------------------------------


def _csv(path: Path, last_y: float = 0.5) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(f"t,x,y\n0,0,0\n1,1,0\n2,2,{last_y}\n3,3,0\n", encoding="utf-8")
    return path


def test_built_in_trajectories_by_name() -> None:
    t = sweep_table(trajectories="curved")
    refs, loaded = parse_trajectories(t, "trajectories", None)
    assert refs == (TrajectoryRef("curved"),) and loaded == (get_trajectory("curved"),)
    t.done()
    refs, loaded = parse_trajectories(
        sweep_table(trajectories=["straight", "sinusoidal"]), "trajectories", None)
    assert refs == (TrajectoryRef("straight"), TrajectoryRef("sinusoidal"))
    assert [x.name for x in loaded] == ["straight", "sinusoidal"]


def test_csv_trajectories_relative_to_the_config(tmp_path: Path, monkeypatch) -> None:
    wp = _csv(tmp_path / "cfg" / "wp.csv")
    refs, loaded = parse_trajectories(
        sweep_table(trajectories=["wp.csv", "straight"]), "trajectories", tmp_path / "cfg")
    assert refs == (TrajectoryRef("wp", str(wp), hashlib.sha256(wp.read_bytes()).hexdigest()),
                    TrajectoryRef("straight"))
    assert loaded[0] == get_trajectory(str(wp))
    # an absolute path is not moved under the config's folder, an upper-case suffix is a file
    upper = _csv(tmp_path / "UP.CSV")
    refs, _ = parse_trajectories(
        sweep_table(trajectories=[str(wp), str(upper)]), "trajectories", tmp_path / "elsewhere")
    assert [(r.name, r.path) for r in refs] == [("wp", str(wp)), ("UP", str(upper))]
    # without a base folder a relative path is taken as given (from the working directory)
    monkeypatch.chdir(tmp_path / "cfg")
    refs, _ = parse_trajectories(sweep_table(trajectories="wp.csv"), "trajectories", None)
    assert refs[0].path == "wp.csv" and refs[0].sha256 == parse_trajectories(
        sweep_table(trajectories=str(wp)), "trajectories", None)[0][0].sha256


def test_trajectory_errors_name_the_key_and_value(tmp_path: Path) -> None:
    def message(value, base: Path | None = tmp_path) -> str:
        return error(parse_trajectories, sweep_table(trajectories=value), "trajectories", base)

    assert message(["straight", "zigzag"]) == (
        f"{W}: trajectories: unknown trajectory 'zigzag'; use one of ['curved', 'sinusoidal', "
        "'straight'] or a .csv waypoint file")
    assert message("missing.csv") == (
        f"{W}: trajectories: cannot read '{tmp_path}/missing.csv': No such file or directory")
    (tmp_path / "dir.csv").mkdir()
    assert message("dir.csv") == (
        f"{W}: trajectories: {tmp_path}/dir.csv: is a directory, not a regular file; give a "
        "regular input file")
    assert message([]) == f"{W}: trajectories=[] is an empty axis (give at least one trajectory)"
    assert message(["straight", 3]) == f"{W}: trajectories[1]=3 must be a string"
    assert message(3) == f"{W}: trajectories=3 must be a string"
    mix = (f"{W}: trajectories mixes trajectory names and reference tables; a robot follows "
           "trajectories, a single-input plant reference signals")
    assert message(["straight", {"kind": "step"}]) == mix
    assert message([{"kind": "step"}, "straight"]) == mix
    assert message(["straight", "straight"]) == (
        f"{W}: trajectories: 'straight' is listed twice (trajectories must not repeat)")
    with pytest.raises(ConfigError, match="missing key 'trajectories'"):
        parse_trajectories(sweep_table(), "trajectories", None)


def test_a_malformed_csv_is_a_config_error_naming_the_key(tmp_path: Path) -> None:
    (tmp_path / "bad.csv").write_text("t,x,y\n0,0,0\n", encoding="utf-8")
    with pytest.raises(ValueError) as direct:
        get_trajectory(str(tmp_path / "bad.csv"))
    message = error(parse_trajectories, sweep_table(trajectories="bad.csv"), "trajectories",
                    tmp_path)
    assert message == f"{W}: trajectories: {direct.value}"


def test_the_same_file_twice_is_refused_however_spelled(tmp_path: Path) -> None:
    _csv(tmp_path / "wp.csv")
    (tmp_path / "sub").mkdir()
    assert error(parse_trajectories, sweep_table(trajectories=["wp.csv", "sub/../wp.csv"]),
                 "trajectories", tmp_path) == (
        f"{W}: trajectories: '{tmp_path}/sub/../wp.csv' is listed twice (trajectories must "
        "not repeat)")


def test_csv_files_of_one_name_are_told_apart_by_their_folders(tmp_path: Path) -> None:
    for folder in ("a", "b", "x/c", "y/c"):
        _csv(tmp_path / folder / "path.csv", last_y=len(folder))
    _csv(tmp_path / "d" / "straight.csv")
    refs, loaded = parse_trajectories(
        sweep_table(trajectories=["a/path.csv", "b/path.csv", "straight", "d/straight.csv"]),
        "trajectories", tmp_path)
    assert [r.name for r in refs] == ["a-path", "b-path", "straight", "d-straight"]
    assert [x.name for x in loaded] == ["a-path", "b-path", "straight", "d-straight"]
    refs, _ = parse_trajectories(
        sweep_table(trajectories=["x/c/path.csv", "y/c/path.csv", "a/path.csv"]),
        "trajectories", tmp_path)
    assert [r.name for r in refs] == ["x-c-path", "y-c-path", "a-path"]


def test_a_file_at_the_root_is_named_root() -> None:
    # (the names come from the paths alone: the files need not exist)
    refs = [TrajectoryRef("p", "/p.csv", "1" * 64), TrajectoryRef("p", "/X/p.csv", "2" * 64)]
    assert _unique_trajectory_names(refs, "w") == [
        TrajectoryRef("root-p", "/p.csv", "1" * 64), TrajectoryRef("X-p", "/X/p.csv", "2" * 64)]
    assert _unique_trajectory_names(refs[:1], "w") == refs[:1]


def test_names_take_up_to_63_folders() -> None:
    """(A clash first resolved by the 63rd folder used to be refused all the same.)"""
    def refs(depth: int) -> list[TrajectoryRef]:
        # files that differ only in the folder `depth` levels above them
        return [TrajectoryRef("p", f"/{top}/" + "a/" * (depth - 1) + "p.csv", "1" * 64)
                for top in ("x", "y")]

    named = _unique_trajectory_names(refs(63), "w")
    assert [r.name for r in named] == ["-".join([top, *["a"] * 62, "p"]) for top in "xy"]
    names = ["-".join([*["a"] * 63, "p"])] * 2
    assert error(_unique_trajectory_names, refs(64), "f.toml [sweep]: trajectories") == (
        f"f.toml [sweep]: trajectories: cannot give the trajectories distinct names: {names}")


def test_one_stem_in_one_folder_cannot_be_told_apart(tmp_path: Path) -> None:
    _csv(tmp_path / "p.csv")
    _csv(tmp_path / "p.CSV")
    name = "-".join(["root", *tmp_path.parts[1:], "p"])
    assert error(parse_trajectories, sweep_table(trajectories=["p.csv", "p.CSV"]),
                 "trajectories", tmp_path) == (
        f"{W}: trajectories: cannot give the trajectories distinct names: {[name, name]}")


STEPS = [{"kind": "step", "amplitude": 2.0, "at": 0.5, "name": "up"},
         {"kind": "step", "name": "unit"}]


def test_reference_tables_become_step_references() -> None:
    t = sweep_table(trajectories=STEPS)
    refs, loaded = parse_trajectories(t, "trajectories", None)
    up = StepReference(amplitude=2.0, at=0.5, name="up")
    unit = StepReference(name="unit")
    assert refs == (TrajectoryRef("up", reference=up), TrajectoryRef("unit", reference=unit))
    assert loaded == (up, unit)
    t.done()  # the key counts as used


@pytest.mark.parametrize(
    ("tables", "message"),
    [
        ([STEPS[0], {"kind": "ramp"}],
         f"{W}: trajectories[1]: kind='ramp' must be 'step' (the built-in reference; others are "
         "given from Python as FunctionReference)"),
        ([STEPS[0], {**STEPS[1], "name": "up"}],
         f"{W}: trajectories[1]: name='up' repeats; every reference needs a distinct name"),
        ([{"kind": "step", "amplitude": "big"}],
         f"{W}: trajectories[0]: StepReference: amplitude='big' must be a finite number"),
    ],
)
def test_bad_reference_tables_are_refused(tables, message: str) -> None:
    assert error(parse_trajectories, sweep_table(trajectories=tables), "trajectories",
                 None) == message


# -- check_targets, _positive_int ------------------------------------------------------------

NO_PLANT = ("tracking a reference signal needs a single-input plant: LoopConfig.plant is None "
            "(the paper's robot, which tracks trajectories); set LoopConfig.plant, e.g. "
            "it2track.plant.linear.LinearSpec or it2track.plant.control.from_control(sys)")


def test_the_plant_must_fit_the_targets() -> None:
    check_targets(LoopConfig(), (get_trajectory("straight"),), "w")
    assert error(check_targets, LoopConfig(), (StepReference(),), "f.toml [sweep]") == (
        f"{W}: {NO_PLANT}")


def test_positive_int() -> None:
    t = sweep_table(chunk_size=1, batch_size=3)
    assert _positive_int(t, "chunk_size", 9) == 1
    assert _positive_int(t, "batch_size", 9) == 3
    assert _positive_int(t, "absent", 9) == 9
    t.done()
    for value in (0, -2):
        assert error(_positive_int, sweep_table(chunk_size=value), "chunk_size", 9) == (
            f"{W}: chunk_size={value} must be an integer >= 1")
    assert error(_positive_int, sweep_table(n=2.0), "n", 9) == f"{W}: n=2.0 must be an integer"


# -- controllers and robots ------------------------------------------------------------------


def test_controller_entries_are_expanded_labelled_and_built(tmp_path: Path) -> None:
    refs = _parse_controllers(
        [{"kind": "flc"}, {"kind": "it2", "fou": [0.1, 0.2], "ke": 2.0},
         {"kind": "pd", "kp": 3.0, "label": "mine"}], "f.toml", tmp_path)
    assert refs == (
        ControllerRef(ControllerSpec.from_table({"kind": "flc"}, where="w")),
        ControllerRef(ControllerSpec.from_table({"kind": "it2", "fou": 0.1, "ke": 2.0},
                                                where="w")),
        ControllerRef(ControllerSpec.from_table({"kind": "it2", "fou": 0.2, "ke": 2.0},
                                                where="w")),
        ControllerRef(ControllerSpec.from_table({"kind": "pd", "kp": 3.0, "label": "mine"},
                                                where="w")),
    )
    assert [r.label for r in refs] == [
        "FLC", "IT2FLC FoU 0.1 Ke 2 Kde 1", "IT2FLC FoU 0.2 Ke 2 Kde 1", "mine"]


def _fis(path: Path) -> Path:
    from it2track.io import save
    from it2track.paper import heading_fls

    path.parent.mkdir(parents=True, exist_ok=True)
    save(heading_fls(0.2), path)
    return path


def test_controller_files_relative_to_the_config(tmp_path: Path, monkeypatch) -> None:
    fis = _fis(tmp_path / "cfg" / "c.t2fis")
    other = _fis(tmp_path / "other.t2fis")
    refs = _parse_controllers(
        [{"kind": "file", "path": "c.t2fis"}, {"kind": "file", "path": str(other)}],
        "f.toml", tmp_path / "cfg")
    assert [r.spec.path for r in refs] == [str(fis), str(other)]
    assert [r.path for r in refs] == [str(fis), str(other)]
    assert all(len(r.sha256) == 64 for r in refs)
    monkeypatch.chdir(tmp_path / "cfg")
    (ref,) = _parse_controllers([{"kind": "file", "path": "c.t2fis"}], "f.toml", None)
    assert ref.spec.path == "c.t2fis" and ref.sha256 == refs[0].sha256


@pytest.mark.parametrize(
    ("entries", "message"),
    [
        ([], "f.toml: [[controllers]] must list at least one controller table"),
        ({"kind": "flc"}, "f.toml: [[controllers]] must list at least one controller table"),
        ([{"kind": "flc"}, 3], "f.toml [controllers][1]: expected a table, got 3"),
        ([{"kind": "it2", "fou": [0.1, 0.2], "label": "mine"}],
         "f.toml [controllers][0]: label='mine' cannot name 2 controllers; drop it (labels are "
         "derived from the values) or split the entry"),
        ([{"kind": "flc"}, {"kind": "it2", "fou": 0.1}, {"kind": "it2", "fou": [0.3, 0.1]}],
         "f.toml [controllers][2]: controller 'IT2FLC FoU 0.1' repeats one of f.toml "
         "[controllers][1]; every controller of a sweep needs a distinct label"),
        ([{"kind": "flc"}, {"kind": "fuzzy"}],
         "f.toml [controllers][1]: kind='fuzzy' must be one of flc, it2, t1-matched, "
         "t1-slope-matched, t1-surface, pd, file"),
    ],
)
def test_bad_controller_entries_are_refused(entries, message: str) -> None:
    assert error(_parse_controllers, entries, "f.toml", None) == message


def test_an_unreadable_controller_file_is_named(tmp_path: Path) -> None:
    assert error(_parse_controllers, [{"kind": "file", "path": "gone.t2fis"}], "f.toml",
                 tmp_path) == (
        f"f.toml [controllers][0]: controller 'gone.t2fis': cannot read '{tmp_path}/gone.t2fis'"
        ": No such file or directory")


def robot_table(**data) -> Table:
    return Table(data, "f.toml", section="robot")


def test_robot_axes_cross_top_level_then_motor_keys() -> None:
    robots, columns = _parse_robots(robot_table(
        half_track=[0.2, 0.3], wheel_radius=0.05, motor={"resistance": [4, 6.0], "inertia": 1e-4}))
    base = RobotParams()
    assert robots == tuple(
        RobotParams(half_track=h, wheel_radius=0.05,
                    motor=MotorParams(**{**vars(base.motor), "resistance": r, "inertia": 1e-4}))
        for h in (0.2, 0.3) for r in (4.0, 6.0))
    assert columns == {"half_track": (0.2, 0.2, 0.3, 0.3),
                       "motor.resistance": (4.0, 6.0, 4.0, 6.0)}
    assert json.dumps(columns) == (
        '{"half_track": [0.2, 0.2, 0.3, 0.3], "motor.resistance": [4.0, 6.0, 4.0, 6.0]}')


def test_robot_defaults_and_fixed_values() -> None:
    assert _parse_robots(robot_table()) == ((RobotParams(),), {})
    robots, columns = _parse_robots(robot_table(half_track=0.4, motor={"resistance": 3.0}))
    assert columns == {}
    assert robots == (RobotParams(half_track=0.4, motor=MotorParams(
        **{**vars(RobotParams().motor), "resistance": 3.0})),)
    assert _parse_robots(robot_table(motor={})) == ((RobotParams(),), {})


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"motor": 3}, "f.toml [robot]: motor=3 must be a table [robot.motor]"),
        ({"half_track": []}, "f.toml [robot]: half_track=[] is an empty axis (give at least one "
                             "value)"),
        ({"motor": {"resistance": []}}, "f.toml [robot]: motor.resistance=[] is an empty axis "
                                        "(give at least one value)"),
        ({"track": 1.0}, "f.toml [robot]: unknown key(s) ['track']"),
        ({"motor": {"resistence": [1.0, 2.0]}},
         "f.toml [robot.motor]: unknown key(s) ['resistence']"),
    ],
)
def test_bad_robot_tables_are_refused(data, message: str) -> None:
    assert error(_parse_robots, robot_table(**data)) == message


# -- load_sweep_config -----------------------------------------------------------------------

SMALL = """
[sweep]
seeds = 2
noise_std = 0.1
trajectories = "straight"

[simulation]
duration = 0.5

[[controllers]]
kind = "flc"
"""


def write(tmp_path: Path, text: str, name: str = "s.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def test_a_small_file_gives_exactly_this_plan(tmp_path: Path) -> None:
    path = write(tmp_path, SMALL)
    plan = load_sweep_config(path)
    flc = ControllerRef(ControllerSpec.from_table({"kind": "flc"}, where="w"))
    assert plan == SweepPlan(
        config=LoopConfig(duration=0.5, seed=0), robots=(RobotParams(),), robot_columns={},
        controllers=(flc,), trajectory_refs=(TrajectoryRef("straight"),), noise_std=(0.1,),
        seeds=(0, 1), chunk_size=2000, batch_size=4096, source=str(path))
    assert plan.trajectories == (get_trajectory("straight"),)
    assert load_sweep_config(str(path)) == plan


def test_every_section_is_read(tmp_path: Path) -> None:
    _csv(tmp_path / "wp.csv")
    _fis(tmp_path / "c.t2fis")
    path = write(tmp_path, """
    [sweep]
    seed = 0
    seeds = [4, 1]
    noise_std = [0.0, 0.2]
    trajectories = ["wp.csv"]
    chunk_size = 1
    batch_size = 1

    [simulation]
    duration = 0.5
    ts = 0.05

    [robot]
    half_track = [0.2, 0.3]

    [[controllers]]
    kind = "file"
    path = "c.t2fis"
    """)
    plan = load_sweep_config(path)
    assert plan.config == LoopConfig(duration=0.5, ts=0.05, seed=0)
    assert plan.seeds == (4, 1) and plan.noise_std == (0.0, 0.2)
    assert (plan.chunk_size, plan.batch_size) == (1, 1)
    assert [r.half_track for r in plan.robots] == [0.2, 0.3]
    assert plan.robot_columns == {"half_track": (0.2, 0.3)}
    assert plan.trajectory_refs[0].path == str(tmp_path / "wp.csv")
    assert plan.controllers[0].spec.path == str(tmp_path / "c.t2fis")
    assert plan.source == str(path)


def test_a_single_input_plant_takes_reference_tables(tmp_path: Path) -> None:
    text = SMALL.replace('trajectories = "straight"',
                         'trajectories = [{ kind = "step", name = "s" }]') + """
    [plant]
    kind = "lti"
    num = [1.0]
    den = [1.0, 1.0]
    """
    plan = load_sweep_config(write(tmp_path, text))
    assert plan.trajectories == (StepReference(name="s"),)
    assert plan.config.plant is not None and plan.config.plant.output_names
    path = write(tmp_path, SMALL.replace('trajectories = "straight"',
                                         'trajectories = [{ kind = "step", name = "s" }]'))
    assert error(load_sweep_config, path) == f"{path} [sweep]: {NO_PLANT}"


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("seeds = 2", "seed = -1\nseeds = 2", "{path} [sweep]: seed=-1 must be an integer >= 0"),
        ("seeds = 2", "seed = 1.0\nseeds = 2", "{path} [sweep]: seed=1.0 must be an integer"),
        ("seeds = 2", "seeds = 0", "{path} [sweep]: seeds=0 must be a seed count >= 1, a list "
                                   "or a table"),
        ("seeds = 2", "", "{path} [sweep]: missing key 'seeds'"),
        ("noise_std = 0.1", "noise_std = -0.1", "{path} [sweep]: noise_std value -0.1 must be "
                                                ">= 0"),
        ('trajectories = "straight"', 'trajectories = "x"',
         "{path} [sweep]: trajectories: unknown trajectory 'x'; use one of ['curved', "
         "'sinusoidal', 'straight'] or a .csv waypoint file"),
        ("seeds = 2", "seeds = 2\nchunk_size = 0",
         "{path} [sweep]: chunk_size=0 must be an integer >= 1"),
        ("seeds = 2", "seeds = 2\nbatch_size = 0",
         "{path} [sweep]: batch_size=0 must be an integer >= 1"),
        ("seeds = 2", "seeds = 2\nchunks = 3", "{path} [sweep]: unknown key(s) ['chunks']"),
        ("[simulation]", "[robot]\nmotor = 1\n[simulation]",
         "{path} [robot]: motor=1 must be a table [robot.motor]"),
        ("[simulation]", "[robot]\nhalf_track = -1.0\n[simulation]",
         "{path} [robot]: half_track must be finite and > 0, got -1.0"),
        ("duration = 0.5", "duration = 0.5\nstep = 1", "{path} [simulation]: unknown key(s) "
                                                       "['step']"),
        ("[simulation]", "[plant]\nkind = \"pid\"\n[simulation]",
         "{path} [plant]: kind='pid' must be one of ['kinematic', 'lti', 'mujoco']"),
        ('kind = "flc"', 'kind = "flc"\ngain = 1', "{path} [controllers][0]: unknown key(s) "
                                                   "['gain']"),
        ("[[controllers]]", "[extra]\n[[controllers]]", "{path}: unknown key(s) ['extra']"),
        ('[[controllers]]\nkind = "flc"', "", "{path}: missing [[controllers]] (at least one "
                                             "controller table)"),
        ('[[controllers]]\nkind = "flc"', "",
         "{path}: [[controllers]] must list at least one controller table"),
    ],
)
def test_load_errors_name_the_file_section_and_key(tmp_path: Path, old, new, message) -> None:
    assert old in SMALL
    text = SMALL.replace(old, new)
    path = write(tmp_path, "controllers = 1\n" + text if "must list" in message else text)
    assert error(load_sweep_config, path) == message.format(path=path)


def test_a_missing_or_malformed_file_is_named(tmp_path: Path) -> None:
    path = tmp_path / "none.toml"
    assert error(load_sweep_config, path) == f"{path}: cannot read: No such file or directory"
    bad = write(tmp_path, "[sweep\n")
    assert error(load_sweep_config, bad).startswith(f"{bad}: invalid TOML: ")


def test_a_plan_that_cannot_fit_in_memory_is_refused_naming_the_file(
    tmp_path: Path, monkeypatch
) -> None:
    path = write(tmp_path, SMALL)
    # one run of the loop needs 7.8 KiB (it fits), the plan one chunk of two runs on top
    limit_memory(monkeypatch, 10_000)
    message = error(load_sweep_config, path)
    assert message.startswith(
        f"{path}: the sweep of 2 runs in 1 chunks of up to 2 runs (chunk_size=2000, "
        "batch_size=4096) needs an estimated ")
    assert message.endswith(" of memory, more than the 9.77 KiB available; use fewer runs, or a "
                            "chunk_size/batch_size that fits")
    monkeypatch.undo()
    assert load_sweep_config(path).n_runs == 2


def test_a_controller_file_that_cannot_be_built_is_named(tmp_path: Path) -> None:
    (tmp_path / "c.t2fis").write_text("not a fuzzy system\n", encoding="utf-8")
    assert error(_parse_controllers, [{"kind": "flc"}, {"kind": "file", "path": "c.t2fis"}],
                 "f.toml", tmp_path) == (
        f"f.toml [controllers][1]: controller 'c.t2fis': {tmp_path}/c.t2fis:1: text before the "
        "first section (expected [System])")
    assert error(_parse_controllers, [{"kind": "pd", "kp": 2.0, "tf": -0.1}], "f.toml",
                 None) == "f.toml [controllers][0]: controller tf=-0.1 must be >= 0"


def test_each_trajectory_is_loaded_once(tmp_path: Path, monkeypatch) -> None:
    """The plan keeps the trajectories parsed with their digests (a file is not read again)."""
    from it2track.experiments.sweep import refs as refs_module

    wp = _csv(tmp_path / "wp.csv")
    calls: list[str] = []
    real = refs_module.get_trajectory
    monkeypatch.setattr(refs_module, "get_trajectory",
                        lambda name: calls.append(name) or real(name))
    plan = load_sweep_config(write(tmp_path, SMALL.replace(
        'trajectories = "straight"', 'trajectories = ["wp.csv", "straight"]')))
    assert calls == [str(wp), "straight"]
    assert [t.name for t in plan.trajectories] == ["wp", "straight"]

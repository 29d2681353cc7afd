"""What a resume trusts (issue 19): a stored chunk counts as done only if its bytes hash to
its checksum line, it has exactly one row per run of its place in the plan, and row ``i``
starts with run ``i``'s id and identifying cells (plan.row_keys, store._chunk_digest)."""

from __future__ import annotations

import csv
import hashlib
import io
import itertools
from pathlib import Path

import numpy as np
import pytest

from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.experiments.sweep.plan import SweepPlan
from it2track.experiments.sweep.refs import TrajectoryRef
from it2track.experiments.sweep.store import _chunk_digest, chunk_path, digest_path
from it2track.plant import RobotParams
from it2track.tracking import METRIC_NAMES, LoopConfig

LABEL = 'wide, "it2"'  # a label csv must quote
PLAN = SweepPlan(
    config=LoopConfig(duration=0.5),
    robots=(RobotParams(), RobotParams(half_track=0.4)),
    robot_columns={"half_track": (5.6, 0.4)},
    controllers=(ControllerSpec(kind=ControllerKind.FLC),
                 ControllerSpec(kind=ControllerKind.IT2, fou=0.2, label=LABEL)),
    trajectory_refs=(TrajectoryRef("straight"), TrajectoryRef("curved")),
    noise_std=(0.0, 0.1),
    seeds=(1, 10),  # "1" is a prefix of "10"
    chunk_size=5,
)
HEADER = PLAN.header_csv()


def _csv(cells) -> str:
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow(cells)
    return buf.getvalue()[:-1]


def test_row_keys_are_each_runs_identifying_cells_in_run_order():
    # independently: every run of every group in run order (seed fastest), as csv.writer
    # writes the cells, against the keys of the chunks laid end to end
    ctrl = [["FLC", "flc", "", "1.0", "1.0", "", "product"],
            [LABEL, "it2", "0.2", "1.0", "1.0", "exhaustive", "product"]]
    expect = []
    for run, (g, c, t, n, s) in enumerate(itertools.product(
            range(2), range(2), ("straight", "curved"), ("0.0", "0.1"), ("1", "10"))):
        expect.append(_csv([str(run), str(g), ("5.6", "0.4")[g], str(c % 2), *ctrl[c],
                            t, n, s]))
    got = [k for chunk in PLAN.chunks() for k in PLAN.row_keys(chunk)]
    assert got == expect
    assert PLAN.header_csv() == ",".join(
        ["run", "group", "half_track", "controller", "label", "kind", "fou", "ke", "kde",
         "reducer", "tnorm", "trajectory", "noise_std", "seed", *METRIC_NAMES]) + "\n"
    assert [(c.group, c.start, c.stop) for c in PLAN.chunks()] == [
        (0, 0, 5), (0, 5, 10), (0, 10, 15), (0, 15, 16),
        (1, 0, 5), (1, 5, 10), (1, 10, 15), (1, 15, 16)]
    assert PLAN.row_keys(PLAN.chunks()[-1]) == [
        '31,1,0.4,1,"wide, ""it2""",it2,0.2,1.0,1.0,exhaustive,product,curved,0.1,10']


def _rows(chunk_id: int, keys=None) -> bytes:
    chunk = PLAN.chunks()[chunk_id]
    keys = PLAN.row_keys(chunk) if keys is None else keys
    metrics = {m: np.arange(len(keys), dtype=float) + 0.5 for m in METRIC_NAMES}
    if keys == PLAN.row_keys(chunk):
        return (HEADER + PLAN.rows_csv(chunk, metrics)).encode()
    tail = ",".join(["0.5"] * len(METRIC_NAMES))
    return (HEADER + "".join(f"{k},{tail}\n" for k in keys)).encode()


def _store(tmp_path: Path, chunk_id: int, data: bytes) -> Path:
    path = chunk_path(tmp_path, chunk_id)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data)
    digest = hashlib.sha256(data).hexdigest()
    digest_path(path).write_text(f"{digest}  {path.name}\n")
    return path


def _check(path: Path, chunk_id: int):
    return _chunk_digest(path, HEADER, PLAN.row_keys(PLAN.chunks()[chunk_id]))


def test_a_complete_chunk_in_its_place_is_trusted(tmp_path):
    data = _rows(1)
    path = _store(tmp_path, 1, data)
    assert _check(path, 1) == hashlib.sha256(data).hexdigest()
    # a one-run chunk too (the last of a group)
    assert _check(_store(tmp_path, 3, _rows(3)), 3) is not None


@pytest.mark.parametrize("chunk_id", [0, 2, 4, 5])
def test_a_chunk_stored_in_another_place_is_not(tmp_path, chunk_id):
    # chunk 1's place holding the rows of another chunk of the same size, its checksum
    # matching: the run ids (and for chunk 5, the group and plant) are not chunk 1's
    path = _store(tmp_path, 1, _rows(chunk_id))
    assert _check(path, 1) is None


def test_the_row_count_must_be_the_chunks(tmp_path):
    keys = PLAN.row_keys(PLAN.chunks()[1])
    assert _check(_store(tmp_path, 1, _rows(1, keys[:-1])), 1) is None  # one row short
    assert _check(_store(tmp_path, 1, _rows(1, [*keys, keys[-1]])), 1) is None  # one more
    assert _check(_store(tmp_path, 1, _rows(1, keys)), 1) is not None


def test_every_identifying_cell_is_compared_whole(tmp_path):
    keys = PLAN.row_keys(PLAN.chunks()[0])
    assert keys[0].endswith(",0.0,1")
    # run 0 is seed 1; a row claiming seed 10 starts with the same characters
    wrong = [keys[0][:-1] + "10", *keys[1:]]
    assert _check(_store(tmp_path, 0, _rows(0, wrong)), 0) is None
    # the last row's noise level edited, its id right
    edited = [*keys[:-1], keys[-1].replace(",0.0,", ",0.1,")]
    assert _check(_store(tmp_path, 0, _rows(0, edited)), 0) is None


def test_a_torn_or_foreign_chunk_is_not_trusted(tmp_path):
    good = _rows(0)
    assert _check(_store(tmp_path, 0, good[:-1]), 0) is None  # no final line end
    assert _check(_store(tmp_path, 0, good.replace(b"run,", b"id,", 1)), 0) is None
    assert _check(_store(tmp_path, 0, good[len(HEADER):]), 0) is None  # no header
    assert _check(_store(tmp_path, 0, good + b"\n"), 0) is None  # an empty last row
    assert _check(_store(tmp_path, 0, good), 0) is not None


def test_the_checksum_line_must_be_exactly_sha256sums(tmp_path):
    data = _rows(0)
    path = _store(tmp_path, 0, data)
    digest = hashlib.sha256(data).hexdigest()
    for line in (f"{digest.upper()}  {path.name}\n", f"{digest} {path.name}\n",
                 f"{digest}  {path.name}", f"{digest}  chunk-000001.csv\n", f"{digest}\n"):
        digest_path(path).write_text(line)
        assert _check(path, 0) is None, line
    digest_path(path).unlink()
    assert _check(path, 0) is None
    digest_path(path).mkdir()  # not a regular file
    assert _check(path, 0) is None


def test_a_missing_chunk_or_a_directory_is_not_trusted(tmp_path):
    path = chunk_path(tmp_path, 0)
    assert _check(path, 0) is None
    path.mkdir(parents=True)
    digest_path(path).write_text(f"{hashlib.sha256(b'').hexdigest()}  {path.name}\n")
    assert _check(path, 0) is None


# -- the plan: its checks, layout, identity and row text ---------------------------------------

def _plan(**kw) -> SweepPlan:
    values = dict(config=LoopConfig(duration=0.5), robots=(RobotParams(),), robot_columns={},
                  controllers=(ControllerSpec(kind=ControllerKind.FLC),),
                  trajectory_refs=(TrajectoryRef("straight"),), noise_std=(0.1,), seeds=(0,))
    return SweepPlan(**{**values, **kw})


@pytest.mark.parametrize("name", ["robots", "controllers", "trajectory_refs", "noise_std",
                                  "seeds"])
def test_every_axis_must_have_a_value(name):
    with pytest.raises(ValueError) as info:
        _plan(**{name: ()})
    assert str(info.value) == f"SweepPlan.{name} must not be empty"


def test_a_plant_column_needs_one_value_per_robot():
    with pytest.raises(ValueError) as info:
        _plan(robot_columns={"half_track": (5.6, 0.4)})
    assert str(info.value) == "SweepPlan.robot_columns['half_track'] needs one value per robot"


@pytest.mark.parametrize("key", ["chunk_size", "batch_size"])
@pytest.mark.parametrize("value", [0, True, 2.0, -1])
def test_chunk_and_batch_sizes_are_integers_of_at_least_one(key, value):
    with pytest.raises(ValueError) as info:
        _plan(**{key: value})
    assert str(info.value) == f"SweepPlan.{key}={value!r} must be an integer >= 1"
    assert getattr(_plan(**{key: 1}), key) == 1


def test_the_chunk_layout_at_the_chunk_size_boundaries():
    # 16 runs per group
    assert [(c.start, c.stop) for c in PLAN.chunks() if c.group == 0] == [
        (0, 5), (5, 10), (10, 15), (15, 16)]
    from dataclasses import replace

    for size, bounds in ((16, [(0, 16)]), (15, [(0, 15), (15, 16)]), (17, [(0, 16)]),
                         (1, [(i, i + 1) for i in range(16)])):
        plan = replace(PLAN, chunk_size=size)
        assert [(c.start, c.stop) for c in plan.chunks() if c.group == 1] == bounds
        assert [c.id for c in plan.chunks()] == list(range(2 * len(bounds)))
    assert (PLAN.runs_per_group, PLAN.n_runs) == (16, 32)
    assert [c.size for c in PLAN.chunks()] == [5, 5, 5, 1] * 2


def test_a_task_is_the_chunks_runs_under_its_groups_plant():
    chunk = PLAN.chunks()[5]  # group 1, runs 5..9: controller 0 then 1
    task = PLAN.task(chunk)
    assert (task.chunk_id, task.start, task.stop, task.batch_size) == (5, 5, 10,
                                                                       PLAN.batch_size)
    assert task.config.robot.half_track == 0.4 and task.config.duration == 0.5
    assert task.controller_offset == 0 and len(task.controllers) == 2
    assert task.runs().seed.tolist() == [10, 1, 10, 1, 10]
    assert PLAN.task(PLAN.chunks()[2]).controller_offset == 1


def test_plain_specs_are_wrapped_and_trajectories_loaded():
    from it2track.experiments.sweep.refs import ControllerRef

    plan = _plan(trajectory_refs=(TrajectoryRef("straight"), TrajectoryRef("curved")))
    assert [type(c) for c in plan.controllers] == [ControllerRef]
    assert plan.controllers[0].spec == ControllerSpec(kind=ControllerKind.FLC)
    assert [t.name for t in plan.trajectories] == ["straight", "curved"]
    ref = ControllerRef.from_spec(ControllerSpec(kind=ControllerKind.FLC))
    assert _plan(controllers=(ref,)).controllers[0] is ref  # a ref is kept as it is
    given = plan.trajectories
    assert _plan(trajectories=given).trajectories is given  # loaded targets are kept


def test_a_plan_holding_a_nan_has_no_hash():
    import math

    # (a NaN noise level is refused when the plan is made, test_sweep_plan_axes.py; a plant
    # column is not checked, it only labels the rows)
    with pytest.raises(ValueError, match="Out of range float values are not JSON compliant"):
        _plan(robot_columns={"half_track": (math.nan,)}).config_hash()


def test_the_identity_is_everything_that_changes_a_number():
    import json

    from it2track import __version__

    n = PLAN.normalised()
    assert sorted(n) == ["chunk_size", "controllers", "format", "it2track_version",
                         "noise_std", "robot_columns", "robots", "seeds", "simulation",
                         "trajectories"]
    assert (n["format"], n["it2track_version"], n["chunk_size"]) == ("it2track-sweep/2",
                                                                     __version__, 5)
    assert n["robot_columns"] == {"half_track": [5.6, 0.4]}
    assert [r["half_track"] for r in n["robots"]] == [5.6, 0.4]
    assert "robot" not in n["simulation"] and n["simulation"]["duration"] == 0.5
    assert n["trajectories"] == [{"name": "straight", "source": "builtin"},
                                 {"name": "curved", "source": "builtin"}]
    assert (n["noise_std"], n["seeds"]) == ([0.0, 0.1], [1, 10])
    assert n["controllers"][1]["label"] == LABEL
    text = json.dumps(n, sort_keys=True, separators=(",", ":"), allow_nan=False)
    assert PLAN.config_hash() == hashlib.sha256(text.encode()).hexdigest()
    from dataclasses import replace

    assert replace(PLAN, batch_size=7).config_hash() == PLAN.config_hash()
    assert replace(PLAN, chunk_size=7).config_hash() != PLAN.config_hash()


def test_rows_are_the_keys_then_the_metrics_by_repr():
    chunk = PLAN.chunks()[3]  # one run
    metrics = {m: np.array([0.1 + 0.2 + i]) for i, m in enumerate(METRIC_NAMES)}
    text = PLAN.rows_csv(chunk, metrics)
    assert text == PLAN.row_keys(chunk)[0] + "," + ",".join(
        repr(0.1 + 0.2 + i) for i in range(len(METRIC_NAMES))) + "\n"
    (cells,) = csv.reader(io.StringIO(text))
    assert cells[4] == LABEL and cells[14] == "0.30000000000000004"  # IAE
    two = PLAN.chunks()[0]
    rows = PLAN.rows_csv(two, {m: np.arange(5.0) for m in METRIC_NAMES}).splitlines()
    assert [r.split(",")[0] for r in rows] == ["0", "1", "2", "3", "4"]
    assert rows[4].endswith("," + ",".join(["4.0"] * len(METRIC_NAMES)))


def test_rows_refuse_missing_or_mis_sized_metrics():
    chunk = PLAN.chunks()[1]
    metrics = {m: np.zeros(5) for m in METRIC_NAMES if m not in ("ISE", "effort")}
    with pytest.raises(ValueError) as info:
        PLAN.rows_csv(chunk, metrics)
    assert str(info.value) == "chunk 1: metrics ['ISE', 'effort'] missing from the result"
    for bad in (np.zeros(4), np.zeros(6), np.zeros((5, 1))):
        metrics = {m: np.zeros(5) for m in METRIC_NAMES} | {"ITSE": bad}
        with pytest.raises(ValueError) as info:
            PLAN.rows_csv(chunk, metrics)
        assert str(info.value) == "chunk 1: expected 5 values per metric"


def test_cells_are_written_as_csv_writer_writes_them():
    from it2track.experiments.sweep.plan import _csv_cell, _fmt

    for text in ("plain", "a,b", 'say "hi"', "two\nlines", " lead", "θ"):
        assert _csv_cell(text) == _csv([text])
    assert _csv_cell("") == ""
    assert (_fmt(True), _fmt(False), _fmt(0.1), _fmt(3), _fmt("x")) == (
        "true", "false", "0.1", "3", "x")
    assert _fmt(1e-20) == "1e-20" and _fmt(2.0) == "2.0"


@pytest.mark.parametrize(("chunk_size", "batch_size", "chunk"), [(5, 3, 5), (20, 30, 16)])
def test_the_plan_must_fit_in_memory(monkeypatch, chunk_size, batch_size, chunk):
    # the docstring's estimate: ~200 bytes per chunk of the layout, ~2 kB per run of the
    # chunk in flight, one simulation batch (at most a chunk) of the loop
    from dataclasses import replace

    from it2track import _limits
    from it2track._limits import ResourceLimitError, format_bytes, loop_bytes

    cfg = PLAN.config
    n_chunks = 2 * -(-16 // chunk_size)
    need = 200 * n_chunks + 2048 * chunk + loop_bytes(
        n_steps=cfg.n_steps, runs=min(batch_size, chunk), trajectories=2,
        noise_samples=int(cfg.duration * cfg.noise_rate) + 1)
    monkeypatch.setattr(_limits, "available_memory", lambda: need)
    replace(PLAN, chunk_size=chunk_size, batch_size=batch_size)  # fits exactly
    monkeypatch.setattr(_limits, "available_memory", lambda: need - 1)
    with pytest.raises(ResourceLimitError) as info:
        replace(PLAN, chunk_size=chunk_size, batch_size=batch_size)
    assert str(info.value) == (
        f"the sweep of 32 runs in {n_chunks} chunks of up to {chunk} runs "
        f"(chunk_size={chunk_size}, batch_size={batch_size}) needs an estimated "
        f"{format_bytes(need)} of memory, more than the {format_bytes(need - 1)} available; "
        "use fewer runs, or a chunk_size/batch_size that fits")


def test_integer_metrics_are_written_as_floats_and_tasks_keep_the_batch_size():
    from dataclasses import replace

    chunk = PLAN.chunks()[3]
    text = PLAN.rows_csv(chunk, {m: np.array([4]) for m in METRIC_NAMES})
    assert text.endswith(",4.0" * len(METRIC_NAMES) + "\n")
    assert replace(PLAN, batch_size=3).task(chunk).batch_size == 3


def test_a_plant_set_the_loop_cannot_take_is_named_by_its_group():
    from dataclasses import replace

    stiff = replace(RobotParams(), motor=replace(RobotParams().motor, inductance=1e-12))
    with pytest.raises(ValueError) as info:
        _plan(robots=(RobotParams(), stiff), robot_columns={"motor.inductance": (0.0, 1e-12)})
    assert str(info.value).startswith(
        "plant set 1 ([robot] values of run group 1): motor resistance=")

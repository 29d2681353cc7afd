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

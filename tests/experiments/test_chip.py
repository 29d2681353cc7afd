"""The verdicts on the chip (issue 22 point 2): the rows derive from the simulated runs, the
type-1 runs are shared by the reducers while the IT2FLCs follow theirs, the latency costs are
the measured tables', and the replay on simavr matches the host C bit for bit (and says so when
it does not)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from it2track.codegen.tools import PIL_TOOLS, missing_tools
from it2track.experiments import chip as chipmod
from it2track.experiments.chip import CHIP_COLUMNS, ChipConfig, run_chip, survival
from it2track.experiments.sequential import SequentialDesign
from it2track.experiments.study import StudyConfig
from it2track.tracking import LoopConfig

REDUCERS = ("exhaustive", "km")


def _skip_without_pil() -> None:
    missing = missing_tools(PIL_TOOLS)
    if missing:
        pytest.skip(f"needs {', '.join(PIL_TOOLS)}: install the Debian package(s) "
                    f"{', '.join(missing)}")


def _tiny() -> StudyConfig:
    return replace(StudyConfig(), loop=LoopConfig(duration=0.5), seeds=2, sweep_seeds=4,
                   noise_levels=(0.0, 0.1), fous=(0.1, 0.2), fou_sweep=(0.0, 0.2),
                   trajectories=("curved",), pd=None, tuning=None, robustness=None,
                   verdicts=SequentialDesign(first=4, batch=2, cap=6, resamples=200))


#: The study's status of C1's levels handed to the experiment (C2 and D1 get none).
HOST = [{"claim": "C1", "path": p, "sigma": s, "status": "holds", "settled": True}
        for p in ("all", "curved") for s in (0.0, 0.1)]


@pytest.fixture(scope="module")
def build_dir(tmp_path_factory):
    return str(tmp_path_factory.mktemp("chip-builds"))


@pytest.fixture(scope="module")
def result(build_dir):
    _skip_without_pil()
    return run_chip(_tiny(), ChipConfig(first=4, batch=2, cap=6, points=5, replay=1),
                    host_rows=HOST, reducers=REDUCERS, build_dir=build_dir)


def _cells(rows, path, sigma, label):
    sel = (rows["trajectory"] == path) & (rows["noise_std"] == sigma) & (
        rows["controller"] == label)
    return dict(zip(rows["seed"][sel].tolist(), np.flatnonzero(sel).tolist(), strict=True))


def test_every_estimate_is_the_paired_mean_of_its_runs(result):
    """Recompute each decisive cell from the runs: the mean paired difference a - b over the
    seeds both controllers have, and n."""
    checked = 0
    for row in result.rows:
        if row["estimate"] == "" or row["path"] == "all":
            continue
        where, comparison = row["decisive"].split(": ")
        path, metric = where.split(" ")
        a, b = comparison.split(" - ")
        rows = result.metrics[row["reducer"]]
        ia = _cells(rows, path, row["sigma"], a)
        ib = _cells(rows, path, row["sigma"], b)
        seeds = sorted(set(ia) & set(ib))
        diff = np.array([rows[metric][ia[s]] - rows[metric][ib[s]] for s in seeds])
        assert row["estimate"] == pytest.approx(diff.mean(), rel=1e-12, abs=0.0), row
        assert row["n"] == len(seeds) >= 4
        checked += 1
    assert checked >= len(REDUCERS) * 3  # C1, C2, D1 on the path at the noisy level


def test_rows_have_the_columns_and_compare_with_the_study(result):
    assert all(tuple(r) == CHIP_COLUMNS for r in result.rows)
    assert {r["reducer"] for r in result.rows} == set(REDUCERS)
    assert {r["claim"] for r in result.rows} == {"C1", "C2", "D1"}
    for r in result.rows:
        if r["claim"] == "C1":
            assert r["host_status"] == "holds"
            assert r["survives"] is (r["status"] == "holds" and r["settled"] is True)
        else:
            assert r["host_status"] == r["survives"] == ""
    for s in survival(result.rows):
        judged = s["host_settled"]
        assert judged == (1 if s["claim"] == "C1" else 0)  # the noisy level over all paths
        assert s["kept"] + len(s["changed"]) + len(s["open"]) == judged


def test_type1_runs_are_shared_and_the_it2flcs_follow_their_reducer(result):
    ex, km = result.metrics["exhaustive"], result.metrics["km"]
    for label in ("FLC", "T1 slope-matched 0.2"):
        a, b = _cells(ex, "curved", 0.1, label), _cells(km, "curved", 0.1, label)
        seeds = sorted(set(a) & set(b))
        assert len(seeds) >= 4
        assert [ex["ISE"][a[s]] for s in seeds] == [km["ISE"][b[s]] for s in seeds]
    a, b = _cells(ex, "curved", 0.1, "IT2FLC FoU 0.2"), _cells(km, "curved", 0.1,
                                                               "IT2FLC FoU 0.2")
    # KM takes about twice the exhaustive reducer's cycles: another latency, other runs
    assert all(ex["ISE"][a[s]] != km["ISE"][b[s]] for s in sorted(set(a) & set(b)))


def test_latency_costs_are_the_measured_tables(result):
    from it2track.codegen import RealType, generate_c
    from it2track.tracking.pil import LatencyTable

    cfg = _tiny()
    for cost in result.costs:
        spec = chipmod._main_spec(cfg, cost["reducer"])
        code = generate_c(spec.build().fls, real=RealType.FLOAT)
        table = LatencyTable.measure(code, [(-1.0, 1.0), (-1.0, 1.0)], points=5)
        assert cost["cycles_max"] == int(table.cycles.max())
        assert cost["cycles_mean"] == float(table.cycles.mean())
        assert cost["period_share_max"] == table.cycles.max() / 16e6 / 0.01
    ex, km = (next(c for c in result.costs if c["reducer"] == r) for r in REDUCERS)
    assert km["cycles_max"] > ex["cycles_max"]


def test_the_replay_matches_the_mcu_step_for_step(result):
    assert result.matches
    for r in result.replay:
        assert r["outputs_equal"] and r["steps"] == 51  # 0.5 s at 100 Hz, both ends
        assert r["sigma"] == 0.1 and r["trajectory"] == "curved" and r["seed"] == 0
        assert 0 < r["mcu_cycles_mean"] <= r["mcu_cycles_max"]
    assert [r["reducer"] for r in result.replay] == list(REDUCERS)


def test_a_replay_that_differs_is_reported(build_dir, monkeypatch):
    """An MCU output one float32 step away from the host's is no match."""
    _skip_without_pil()
    from it2track.codegen.pil import AvrInTheLoop

    step = AvrInTheLoop.step

    def off_by_one_ulp(self, x):
        u, raw = step(self, x)
        u = u.copy()
        u[len(u) // 2] = float(np.nextafter(np.float32(u[len(u) // 2]), np.float32(np.inf)))
        return u, raw

    monkeypatch.setattr(AvrInTheLoop, "step", off_by_one_ulp)
    cfg = _tiny()
    got = chipmod._replay(cfg, ChipConfig(points=5, replay=1), ("exhaustive",),
                          chipmod._Builder(5, build_dir), build_dir)
    assert [r["outputs_equal"] for r in got] == [False]


def test_chip_config_is_checked_and_halves_the_study():
    assert ChipConfig.for_study(StudyConfig()) == ChipConfig(first=50, batch=50, cap=100)
    tiny = ChipConfig.for_study(_tiny())
    assert (tiny.first, tiny.batch, tiny.cap) == (2, 1, 2)
    for kwargs, needle in (({"first": 1}, "chip first=1 must be an integer >= 2"),
                           ({"points": 1}, "chip points=1"), ({"replay": -1}, "chip replay=-1"),
                           ({"batch": 0}, "chip batch=0"), ({"first": 5, "cap": 4}, "cap=4"),
                           ({"first": True}, "chip first=True")):
        with pytest.raises(ValueError, match=needle):
            ChipConfig(**kwargs)
    design = ChipConfig(first=3, batch=2, cap=5).design(SequentialDesign(resamples=300,
                                                                         target=0.9))
    assert (design.first, design.batch, design.cap, design.resamples, design.target) == (
        3, 2, 5, 300, 0.9)

"""The physics check (experiments/physics.py): the claims re-judged on the MuJoCo robot with
the study's sequential design; verdicts recomputed from the rows, the cache that lets an
interrupted check resume, the check's validation and the survival table."""

from __future__ import annotations

import math
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats

from it2track.experiments.physics import (
    PhysicsCheck,
    RowCache,
    claim_controllers,
    physics_config,
    physics_traces,
    run_physics,
    survival,
)
from it2track.experiments.sequential import SequentialDesign
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.experiments.study import StudyConfig
from it2track.tracking import LoopConfig

SIGMA = 0.05


def _tiny() -> StudyConfig:
    return replace(StudyConfig(), loop=LoopConfig(duration=0.5), trajectories=("straight",
                   "curved"), noise_levels=(0.0, SIGMA), sweep_seeds=2, pd=None, tuning=None,
                   robustness=None, verdicts=SequentialDesign(first=2, resamples=200))


CHECK = PhysicsCheck(surfaces=("dry", "icy"), first=2, batch=1, cap=3)


@pytest.fixture(scope="module")
def checked(tmp_path_factory):
    pytest.importorskip(
        "mujoco", reason="needs the mujoco PyPI package: pip install 'it2track[mujoco]'")
    folder = tmp_path_factory.mktemp("physics") / "cache"
    cache = RowCache(folder)
    return run_physics(_tiny(), CHECK, cache=cache), cache


def _interval(diff: np.ndarray) -> tuple[float, float, float]:
    n = diff.size
    mean = float(diff.mean())
    half = stats.t.ppf(0.975, n - 1) * diff.std(ddof=1) / math.sqrt(n)
    return mean, mean - half, mean + half


def test_verdict_rows_are_computed_from_the_metrics(checked):
    result, _ = checked
    rows = result.rows()
    assert set(rows["surface"]) == {"dry", "icy"}
    verdicts = result.verdict_rows()
    # every claim x (all, each path) x both levels x both surfaces (C3: all paths only)
    assert len(verdicts) == 2 * 2 * (5 * 3 + 1)
    checked_cells = 0
    for v in verdicts:
        if v["sigma"] != SIGMA or v["path"] == "all" or v["claim"] not in ("C1", "C2", "D1"):
            continue
        path, rest = v["decisive"].split(" ", 1)
        metric, pair = rest.split(": ")
        a, b = pair.split(" - ")
        sel = ((rows["surface"] == v["surface"]) & (rows["trajectory"] == path)
               & (rows["noise_std"] == SIGMA))
        ra = {int(s): x for s, x, c in zip(rows["seed"][sel], rows[metric][sel],
                                            rows["controller"][sel], strict=True) if c == a}
        rb = {int(s): x for s, x, c in zip(rows["seed"][sel], rows[metric][sel],
                                            rows["controller"][sel], strict=True) if c == b}
        seeds = sorted(set(ra) & set(rb))
        diff = np.array([ra[s] - rb[s] for s in seeds])
        mean, low, high = _interval(diff)
        assert v["estimate"] == pytest.approx(mean, rel=1e-9, abs=1e-15)
        assert v["ci_low"] == pytest.approx(low, rel=1e-9, abs=1e-15)
        assert v["ci_high"] == pytest.approx(high, rel=1e-9, abs=1e-15)
        assert 2 <= v["n"] <= CHECK.cap and v["n"] <= len(seeds)
        assert 0.0 <= v["replication"] <= 1.0
        assert v["settled"] == (v["replication"] >= 0.95)
        checked_cells += 1
    assert checked_cells == 2 * 3 * 2  # C1, C2, D1 on both paths, both surfaces


def test_the_rows_are_the_physical_robot_on_each_surface(checked):
    """Same controller, path, sigma and seed: the kinematic robot, dry and icy ground differ
    (wheel slip on ice), and every surface ran the claims' controllers only (no PD)."""
    from it2track.tracking import RunTable, get_trajectory, simulate_metrics

    result, _ = checked
    rows = result.rows()
    assert set(rows["controller"]) == set(result.controllers)
    assert "PD" not in " ".join(result.controllers)
    pick = ((rows["controller"] == "FLC") & (rows["trajectory"] == "curved")
            & (rows["noise_std"] == SIGMA) & (rows["seed"] == 0))
    by_surface = {s: float(x) for s, x in zip(rows["surface"][pick], rows["IAE"][pick],
                                                       strict=True)}
    config = _tiny()
    flc = ControllerSpec(kind=ControllerKind.FLC).build()
    kin = simulate_metrics([flc], [get_trajectory("curved")],
                           RunTable(np.array([0]), np.array([0]), np.array([SIGMA]),
                                    np.array([0])), config.loop)["IAE"][0]
    dry = simulate_metrics([flc], [get_trajectory("curved")],
                           RunTable(np.array([0]), np.array([0]), np.array([SIGMA]),
                                    np.array([0])),
                           physics_config(config, CHECK, "dry").loop)["IAE"][0]
    assert by_surface["dry"] == dry  # bit for bit the MuJoCo robot's run
    assert len({by_surface["dry"], by_surface["icy"], float(kin)}) == 3


def test_a_rerun_reads_every_round_back_from_the_cache(checked, tmp_path):
    result, cache = checked
    first_misses = cache.misses
    assert first_misses >= 2 * 2  # at least the first round and one extension per surface
    again = RowCache(cache.folder)
    rerun = run_physics(_tiny(), CHECK, cache=again)
    assert (again.hits, again.misses) == (first_misses, 0)
    assert rerun.verdict_rows() == result.verdict_rows()
    a, b = rerun.rows(), result.rows()
    assert all(np.array_equal(a[k], b[k]) for k in a)
    # a torn file is simulated again, not read
    victim = again.files()[0]
    victim.write_bytes(victim.read_bytes()[:100])
    third = RowCache(cache.folder)
    assert run_physics(_tiny(), CHECK, cache=third).verdict_rows() == result.verdict_rows()
    assert third.misses == 1
    # another configuration never reads these files
    other = RowCache(cache.folder)
    run_physics(_tiny(), replace(CHECK, surfaces=("wet",), cap=2), cache=other)
    assert other.hits == 0


def test_check_validation_names_the_field():
    for kwargs, field in (({"surfaces": ("dry", "mud")}, "surfaces"),
                          ({"surfaces": ("dry", "dry")}, "surfaces"),
                          ({"surfaces": ()}, "surfaces"), ({"surfaces": "dry"}, "surfaces"),
                          ({"first": 1}, "first"), ({"first": 7, "cap": 6}, "first"),
                          ({"cap": 201, "first": 2}, "cap"), ({"batch": 0}, "batch"),
                          ({"cap": True}, "cap"), ({"first": 2.0}, "first")):
        with pytest.raises(ValueError, match=rf"PhysicsCheck\.{field}"):
            PhysicsCheck(**kwargs)
    edge = PhysicsCheck(first=200, cap=200, batch=1)  # the boundaries themselves are allowed
    design = edge.design(SequentialDesign(target=0.9, resamples=300, seed=5))
    assert (design.first, design.batch, design.cap) == (200, 1, 200)
    assert (design.target, design.resamples, design.seed) == (0.9, 300, 5)  # the study's


def test_claim_controllers_leave_out_the_pd_and_extras():
    config = replace(_tiny(), extra_controllers=(ControllerSpec(kind=ControllerKind.PD,
                                                                kp=3.0, kd=0.1),))
    labels = [s.label for s in claim_controllers(config)]
    assert labels == ["FLC", "IT2FLC FoU 0.1", "IT2FLC FoU 0.2", "IT2FLC FoU 0.3",
                      "T1 slope-matched 0.2", "T1 dead-zone-matched 0.2",
                      "T1 surface copy 0.2"]


def _level(claim, sigma, status, settled, rep=0.99, n=4, path="all"):
    return {"claim": claim, "path": path, "sigma": sigma, "status": status,
            "settled": settled, "replication": rep, "n": n}


def test_survival_marks_only_levels_settled_alike_on_both_robots():
    kin = [_level("C1", 0.0, "deterministic", True), _level("C1", 0.1, "holds", True),
           _level("C1", 0.2, "holds", False, 0.5), _level("C2", 0.1, "holds", True),
           _level("C1", 0.1, "contradicted", True, path="straight")]
    dry = [_level("C1", 0.0, "deterministic", True), _level("C1", 0.1, "holds", True, 0.95),
           _level("C1", 0.2, "holds", True), _level("C2", 0.1, "contradicted", True)]
    icy = [_level("C1", 0.1, "holds", False, 0.94), _level("C1", 0.2, "holds", True),
           _level("C2", 0.1, "holds", True, n=6)]
    fake = SimpleNamespace(surfaces=[SimpleNamespace(surface="dry", verdict_rows=dry),
                                     SimpleNamespace(surface="icy", verdict_rows=icy)])
    out = {(r["claim"], r["sigma"]): r for r in survival(kin, fake)}
    assert set(out) == {("C1", 0.1), ("C1", 0.2), ("C2", 0.1)}  # noisy levels only
    assert out[("C1", 0.1)]["dry_same"] and not out[("C1", 0.1)]["icy_same"]  # icy unsettled
    assert not out[("C1", 0.2)]["dry_same"]  # unsettled on the kinematic robot
    assert not out[("C2", 0.1)]["dry_same"] and out[("C2", 0.1)]["icy_same"]
    assert out[("C2", 0.1)]["icy_n"] == 6 and out[("C1", 0.1)]["dry_replication"] == 0.95
    assert out[("C1", 0.1)]["kinematic"] == "holds"  # the all-paths row, not straight's


def test_traces_for_the_animation():
    pytest.importorskip(
        "mujoco", reason="needs the mujoco PyPI package: pip install 'it2track[mujoco]'")
    config = replace(_tiny(), loop=LoopConfig(duration=0.2))
    panels = physics_traces(config, CHECK)
    assert [p[0] for p in panels] == ["kinematic robot, curved", "MuJoCo, dry (μ 0.8)",
                                      "MuJoCo, icy (μ 0.1)"]
    assert all(p[2] == ("FLC", "IT2FLC FoU 0.2") for p in panels)
    assert not np.array_equal(panels[0][1]["x"], panels[2][1]["x"])
    with pytest.raises(ValueError, match="path='zigzag' is not one of"):
        physics_traces(config, CHECK, path="zigzag")

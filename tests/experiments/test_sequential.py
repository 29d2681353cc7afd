"""The sequential seed design: extends exactly the units behind unsettled levels, keeps every
controller of a unit on the same seeds, stops at the cap, and its settled verdicts replicate."""

import numpy as np
import pytest

from it2track.experiments.claimcells import claim_definitions
from it2track.experiments.sequential import SeedBatch, SequentialDesign, concat_rows, settle
from it2track.experiments.verdicts import VERDICT_COLUMNS, verdict_rows
from it2track.tracking import METRIC_NAMES

TRAJ = ("straight", "curved")
FOUS = (0.1, 0.2, 0.3)
CTRL = ("FLC", "IT2FLC FoU 0.1", "IT2FLC FoU 0.2", "IT2FLC FoU 0.3", "PD")
LEVELS = (0.0, 0.05, 0.1)


def level(c, s, p):
    """C1 clear at 0.1 on both paths; at 0.05 a tiny effect on the curved path only (needs
    many seeds, may never settle); C2 clear at 0.1, absent at 0.05."""
    if c == "PD":
        return 0.02
    w = 0.0 if c == "FLC" else float(c.split()[-1])
    if s == 0.1:
        return 0.01 * (1.0 - 0.5 * w)
    if s == 0.05:
        return 0.01 * (1.0 - (0.012 if (w == 0.2 and p == "curved") else 0.0))
    return 0.01 * (1.0 - w)


class Sim:
    """Metrics of (controller, path, sigma, seed) from a per-seed stream (the same seed gives
    the same run whenever it is simulated), recording every batch asked for."""

    def __init__(self, base=0):
        self.base = base
        self.calls = []

    def __call__(self, batches):
        self.calls.append(list(batches))
        cols = {k: [] for k in ("experiment", "trajectory", "controller", "kind", "fou",
                                "noise_std", "seed", *METRIC_NAMES)}
        for b in batches:
            for c, p, s in b.cells:
                for k in b.seeds.tolist() if s > 0 else [0]:
                    rng = np.random.default_rng([self.base, k, TRAJ.index(p), int(s * 1000)])
                    shared = rng.normal(0.0, 0.3)
                    own = np.random.default_rng([self.base, k, TRAJ.index(p), int(s * 1000),
                                                 CTRL.index(c)]).normal(0.0, 0.01)
                    jitter = 1.0 if s == 0 else 1.0 + shared + own
                    cols["experiment"].append("noise")
                    cols["trajectory"].append(p)
                    cols["controller"].append(c)
                    cols["kind"].append("x")
                    cols["fou"].append(0.0)
                    cols["noise_std"].append(s)
                    cols["seed"].append(k)
                    for i, m in enumerate(METRIC_NAMES):
                        cols[m].append(level(c, s, p) * (1 + 0.2 * i) * jitter)
        return {k: np.asarray(v, dtype=object if k in ("experiment", "trajectory",
                                                       "controller", "kind") else None)
                for k, v in cols.items()}


CLAIMS = [d for d in claim_definitions(fous=FOUS, main_fou=0.2, trajectories=TRAJ)
          if d.id in ("C1", "C2")]


def run(design, base=0):
    sim = Sim(base)
    out = settle(sim, claims=CLAIMS, controllers=CTRL, trajectories=TRAJ, levels=LEVELS,
                 design=design, fous=FOUS, main_fou=0.2)
    return sim, out


def test_extends_only_the_cells_behind_unsettled_levels_to_the_cap_in_batches():
    design = SequentialDesign(first=20, batch=20, cap=60, resamples=300)
    sim, out = run(design)
    # Round 0: every cell at 20 seeds (one run at sigma 0), every controller.
    first = sim.calls[0]
    assert {(b.start, b.stop) for b in first if b.cells[0][2] > 0} == {(0, 20)}
    assert {(b.start, b.stop) for b in first if b.cells[0][2] == 0} == {(0, 1)}
    assert {c for b in first for c, _, _ in b.cells} == set(CTRL)
    # Sigma 0.1 settles at once (clear effects); C1 at 0.05 on the curved path (a tiny
    # effect) is extended in batches of 20 to the cap of 60, for C1's controllers there.
    for c in CTRL:
        assert out.n[(c, "straight", 0.1)] == out.n[(c, "curved", 0.1)] == 20
    assert out.n[("IT2FLC FoU 0.2", "curved", 0.05)] == out.n[("FLC", "curved", 0.05)] == 60
    assert out.n[("PD", "curved", 0.05)] == 20  # compared by no claim: never extended
    assert [r["round"] for r in out.rounds] == [1, 2]
    for r in out.rounds:
        for _p, s, a, b, ctrls in r["units"]:
            assert s == 0.05 and b - a == 20 and "PD" not in ctrls
    for batches in sim.calls[1:]:
        for b in batches:  # one seed range per batch, shared by its controllers
            assert b.stop - b.start == 20
    c1 = next(c for c in out.claims if c.id == "C1")
    assert c1.level_status[0.1] == "holds" and c1.replication[("all", 0.1)] >= 0.95
    assert c1.settled("all", 0.1)
    # Every level got a probability; the unsettled ones are named in the verdict's detail.
    for c in out.claims:
        for s in c.unsettled_at:
            assert c.replication[("all", s)] < 0.95
            assert "unsettled at" in c.detail or c.verdict == "unsettled"


def test_a_cap_equal_to_the_first_round_never_extends():
    sim, out = run(SequentialDesign(first=20, batch=20, cap=20, resamples=200))
    assert len(sim.calls) == 1 and out.rounds == []
    assert set(out.n.values()) == {1, 20}


def test_a_pair_is_judged_on_the_seeds_both_have():
    # C1's pair on the curved path at 0.05 has 60 seeds, C2's IT2FLC 0.1 only as many as C2
    # asked for: every cell's n is the pair's common count.
    design = SequentialDesign(first=20, batch=20, cap=60, resamples=300)
    _, out = run(design)
    for claim in out.claims:
        d = next(x for x in CLAIMS if x.id == claim.id)
        for e in claim.evidence:
            if e["sigma"] == 0.0:
                continue
            a, b = e["comparison"].split(" - ")
            key = (e["trajectory"], e["sigma"])
            assert e["n"] == min(out.n[(a, *key)], out.n[(b, *key)]), (d.id, e)


def test_verdict_rows_cover_every_level_and_path_with_its_n():
    design = SequentialDesign(first=20, batch=20, cap=60, resamples=300)
    _, out = run(design)
    rows = verdict_rows(CLAIMS, out.claims)
    assert all(list(r) == list(VERDICT_COLUMNS) for r in rows)
    keys = {(r["claim"], r["path"], r["sigma"]) for r in rows}
    assert keys == {(c, p, s) for c in ("C1", "C2") for p in ("all", *TRAJ) for s in LEVELS}
    for r in rows:
        if r["sigma"] == 0.0:
            assert r["status"] == "deterministic" and r["n"] == 1 and r["replication"] == 1.0
            assert r["decisive"].endswith("cells as claimed")
            continue
        claim = next(c for c in out.claims if c.id == r["claim"])
        assert r["replication"] == claim.replication[(r["path"], r["sigma"])]
        assert r["settled"] == (r["replication"] >= 0.95)
        claim = next(d for d in CLAIMS if d.id == r["claim"])
        paths = TRAJ if r["path"] == "all" else (r["path"],)
        expect_n = min(out.n[(c, p, r["sigma"])] for c in claim.controllers for p in paths)
        assert r["n"] == expect_n
        cells = 4 * (1 if r["claim"] == "C1" else 2) * (len(TRAJ) if r["path"] == "all" else 1)
        assert r["cells"] == cells
        if r["status"] == "holds":
            assert r["supporting"] == cells and r["ci_high"] < 0.0
        if r["status"] == "contradicted":
            assert r["contradicting"] >= 1 and r["p_holm"] <= 0.025


def _status(claim, key):
    path, sigma = key
    return (claim.level_status[sigma] if path == "all"
            else claim.per_trajectory[path]["status"][sigma])


def test_settled_levels_agree_between_independent_seed_sets():
    design = SequentialDesign(first=20, batch=20, cap=60, resamples=300)
    _, a = run(design, base=0)
    _, b = run(design, base=1)
    compared = 0
    for ca, cb in zip(a.claims, b.claims, strict=True):
        for key in ca.replication:
            if key[1] == 0.0:
                continue
            if ca.settled(*key) or cb.settled(*key):
                assert _status(ca, key) == _status(cb, key), (ca.id, key)
                compared += 1
    assert compared >= 6


def test_first_round_rows_are_checked_and_reused():
    design = SequentialDesign(first=20, batch=20, cap=20, resamples=200)
    sim = Sim()
    rows = sim([SeedBatch(tuple((c, p, s) for c in CTRL), 0, 20 if s else 1)
                for p in TRAJ for s in LEVELS])
    again = Sim()
    out = settle(again, claims=CLAIMS, controllers=CTRL, trajectories=TRAJ, levels=LEVELS,
                 design=design, rows=rows)
    assert again.calls == [] and len(out.rows["seed"]) == len(rows["seed"])
    short = {k: v[(rows["seed"] < 19) | (rows["controller"] != "PD")] for k, v in rows.items()}
    with pytest.raises(ValueError, match=r"'PD' on 'straight' at sigma 0\.05 have 19 "
                                         r"realisations, not 20"):
        settle(again, claims=CLAIMS, controllers=CTRL, trajectories=TRAJ, levels=LEVELS,
               design=design, rows=short)


@pytest.mark.parametrize(("kw", "match"), [
    ({"first": 1}, "first=1"), ({"batch": 0}, "batch=0"), ({"cap": 50}, "cap=50"),
    ({"resamples": 99}, "resamples=99"), ({"resamples": 20_001}, r"in \[100, 20000\]"),
    ({"target": 0.0}, "replication=0.0"),
    ({"target": 1.5}, "replication=1.5"), ({"target": float("nan")}, "replication=nan"),
    ({"seed": -1}, "seed=-1"), ({"first": True}, "first=True"), ({"cap": 100.0}, "cap=100.0"),
])
def test_design_refuses_bad_values(kw, match):
    with pytest.raises(ValueError, match=match):
        SequentialDesign(**kw)
    assert SequentialDesign(target=1.0).target == 1.0
    assert SequentialDesign(first=2, cap=2).cap == 2
    assert SequentialDesign(resamples=20_000).resamples == 20_000


def test_concat_rows_needs_the_same_columns():
    a = {"seed": np.array([0]), "x": np.array([1.0])}
    b = {"seed": np.array([1]), "x": np.array([2.0])}
    assert concat_rows([a, b])["x"].tolist() == [1.0, 2.0]
    with pytest.raises(ValueError, match="other columns"):
        concat_rows([a, {"seed": np.array([1]), "y": np.array([2.0])}])
    with pytest.raises(ValueError, match="no rows"):
        concat_rows([{"seed": np.array([], dtype=int)}])

"""The physics check's summary in claims.md and on the page (report/physics.py): per claim,
the levels settled on the kinematic robot kept, settled otherwise or unsettled per surface."""

from __future__ import annotations

from it2track.report.physics import (
    PhysicsOutcome,
    counts_markdown,
    physics_markdown,
    survivor_counts,
    survivors_text,
)


def _row(claim, sigma, kin, kin_settled, **surfaces):
    row = {"claim": claim, "sigma": sigma, "kinematic": kin, "kinematic_settled": kin_settled}
    for s, (status, settled) in surfaces.items():
        row.update({s: status, f"{s}_replication": 0.97 if settled else 0.5, f"{s}_n": 4,
                    f"{s}_settled": settled,
                    f"{s}_same": kin_settled and settled and status == kin})
    return row


ROWS = [
    _row("C1", 0.05, "holds", True, dry=("holds", True), icy=("contradicted", True)),
    _row("C1", 0.1, "holds", True, dry=("holds", True), icy=("holds", False)),
    _row("C1", 0.2, "holds", False, dry=("contradicted", True), icy=("holds", True)),
    _row("D3", 0.05, "holds", True, dry=("holds", False), icy=("holds", True)),
]


def test_counts_cover_only_levels_settled_on_the_kinematic_robot():
    counts = {c["claim"]: c for c in survivor_counts(ROWS, ["dry", "icy"])}
    assert counts["C1"]["levels"] == 2  # sigma 0.2 is unsettled on the kinematic robot
    assert counts["C1"]["dry"] == {"same": 2, "different": 0, "unsettled": 0}
    assert counts["C1"]["icy"] == {"same": 0, "different": 1, "unsettled": 1}
    assert counts["D3"]["dry"] == {"same": 0, "different": 0, "unsettled": 1}
    text = survivors_text(ROWS, ["dry", "icy"])
    assert ("**dry**: every level as on the kinematic robot: C1; some level settled "
            "otherwise: none.") in text
    assert ("**icy**: every level as on the kinematic robot: D3; some level settled "
            "otherwise: C1.") in text
    table = counts_markdown(ROWS, ["dry", "icy"])
    assert table[2] == "| C1 | 2 | 2 / 0 / 0 | 0 / 1 / 1 |"


def test_a_skipped_check_says_why_and_how_to_run_it():
    text = physics_markdown(PhysicsOutcome.skipped("skipped with --no-physics"))
    assert "Skipped (skipped with --no-physics)" in text
    assert "`pip install 'it2track[mujoco]'`" in text
    assert PhysicsOutcome.skipped("x").provenance() == {"status": "skipped", "reason": "x"}

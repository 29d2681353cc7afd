"""Settled verdicts replicate: two studies with different base seeds agree on every level
either reports as settled (a reduced config; benchmarks/check_verdict_replication.py runs the
default one)."""

from dataclasses import replace

import pytest

from it2track.experiments.sequential import SequentialDesign
from it2track.experiments.study import StudyConfig, run_study
from it2track.experiments.verdicts import compare_verdicts
from it2track.tracking import LoopConfig


def _row(claim, path, sigma, status, rep, settled):
    return {"claim": claim, "path": path, "sigma": sigma, "status": status,
            "replication": rep, "settled": settled}


def test_compare_verdicts_counts_only_levels_settled_in_either_run():
    a = [_row("C1", "all", 0.0, "deterministic", 1.0, True),
         _row("C1", "all", 0.1, "holds", 0.99, True),
         _row("C1", "all", 0.2, "holds", 0.5, False),
         _row("C1", "all", 0.3, "not shown", 0.95, True),
         _row("C2", "all", 0.1, "holds", 0.9, False)]
    b = [_row("C1", "all", 0.0, "deterministic", 1.0, True),
         _row("C1", "all", 0.1, "holds", 0.97, True),
         _row("C1", "all", 0.2, "contradicted", 0.6, False),  # unsettled in both: not compared
         _row("C1", "all", 0.3, "contradicted", 0.7, False),  # settled in a only: compared
         _row("C2", "all", 0.1, "not shown", 0.96, "True")]  # settled in b (CSV text)
    out = compare_verdicts(a, b)
    assert (out["levels"], out["settled_either"], out["agree"]) == (4, 3, 1)
    assert out["disagree"] == [("C1", "all", 0.3, "not shown", 0.95, "contradicted", 0.7),
                               ("C2", "all", 0.1, "holds", 0.9, "not shown", 0.96)]
    with pytest.raises(ValueError, match="different levels"):
        compare_verdicts(a, b[:-1])


def test_two_base_seeds_agree_on_every_settled_level():
    # 3 s runs, two noisy levels, 50 realisations per round up to 200 (the default: 100 up to
    # 400). At 20 up to 60 a few levels settled on a sample too small to show a rare bad seed.
    base = replace(StudyConfig(), loop=LoopConfig(duration=3.0), noise_levels=(0.0, 0.05, 0.2),
                   sweep_seeds=50, seeds=4, fou_sweep=(0.0, 0.2), pd=None, tuning=None,
                   robustness=None,
                   verdicts=SequentialDesign(first=50, batch=50, cap=200, resamples=500))
    runs = [run_study(replace(base, loop=replace(base.loop, seed=s))).verdict_rows
            for s in (0, 1)]
    out = compare_verdicts(*runs)
    assert out["disagree"] == []
    assert out["settled_either"] >= 30  # the check is not vacuous (42 noisy levels)
    # The runs really are independent: some replication probabilities differ.
    reps = [{(r["claim"], r["path"], r["sigma"]): r["replication"] for r in rows}
            for rows in runs]
    assert sum(reps[0][k] != reps[1][k] for k in reps[0]) > 5

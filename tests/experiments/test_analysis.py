"""Summary statistics and claim verdicts, on synthetic metrics where the truth is known."""

import numpy as np
import pytest
from scipy import stats

from it2track.experiments.analysis import evaluate_claims, summarise, verdict_text
from it2track.experiments.stats import mean_interval, paired_comparison
from it2track.tracking import METRIC_NAMES

TRAJ = ("straight", "curved", "sinusoidal")
FOUS = (0.1, 0.2, 0.3)


def synthetic_rows(level_fn, levels=(0.0, 0.1, 0.3), n_seeds=40, seed=1):
    """Metrics table where controller c at sigma has metric = level_fn(c, sigma) * (1 + noise),
    the noise shared by all controllers for one seed (common random numbers)."""
    rng = np.random.default_rng(seed)
    controllers = ["FLC", *(f"IT2FLC FoU {w:g}" for w in FOUS), "T1 dead-zone-matched 0.2"]
    cols = {k: [] for k in ("experiment", "trajectory", "controller", "kind", "fou",
                            "noise_std", "seed", *METRIC_NAMES)}
    shared = rng.normal(0.0, 0.05, size=(len(TRAJ), len(levels), n_seeds))
    for ci, c in enumerate(controllers):
        for ti, t in enumerate(TRAJ):
            for li, s in enumerate(levels):
                for k in range(n_seeds):
                    cols["experiment"].append("noise")
                    cols["trajectory"].append(t)
                    cols["controller"].append(c)
                    cols["kind"].append("x")
                    cols["fou"].append(0.0)
                    cols["noise_std"].append(s)
                    cols["seed"].append(k)
                    base = level_fn(c, s) * (1.0 + shared[ti, li, k]
                                             + 0.001 * rng.normal() * (ci + 1))
                    for m in METRIC_NAMES:
                        cols[m].append(base)
    return {k: np.asarray(v, dtype=object if k in ("experiment", "trajectory", "controller",
                                                   "kind") else None)
            for k, v in cols.items()}


def claims(rows):
    out = evaluate_claims(rows, fous=FOUS, main_fou=0.2, trajectories=TRAJ)
    return {c.id: c for c in out}


def test_claims_hold_when_the_data_say_so():
    # Errors fall with the FoU at every level, straight ISE min ~0.003, IT2 beats matched T1.
    value = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.008, "IT2FLC FoU 0.2": 0.005,
             "IT2FLC FoU 0.3": 0.003, "T1 dead-zone-matched 0.2": 0.007}
    result = claims(synthetic_rows(lambda c, s: value[c]))
    assert result["C1"].verdict == "holds"
    assert result["C2"].verdict == "holds"
    assert result["C3"].verdict == "holds"
    assert result["D1"].verdict == "holds"


def test_c2_does_not_hold_when_errors_grow_with_the_fou():
    value = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.003, "IT2FLC FoU 0.2": 0.005,
             "IT2FLC FoU 0.3": 0.008, "T1 dead-zone-matched 0.2": 0.004}
    result = claims(synthetic_rows(lambda c, s: value[c]))
    assert result["C2"].verdict == "does not hold"
    assert result["C1"].verdict == "holds"
    assert result["D1"].verdict == "does not hold"  # matched T1 is better than the IT2FLC
    failing = [e for e in result["C2"].evidence if not e["passes"]]
    assert failing and all("FoU" in e["comparison"] for e in failing)


def test_verdict_depends_on_noise_level():
    # IT2 beats the FLC only when sigma > 0; C3 holds only where the best ISE is ~0.003.
    def value(c, s):
        if c == "FLC":
            return 0.02
        if c.startswith("IT2"):
            return 0.02 if s == 0.0 else 0.003 * (1 + s)
        return 0.03

    result = claims(synthetic_rows(value))
    assert result["C1"].verdict == "holds only for sigma in [0.1, 0.3] rad"
    assert result["C1"].holds_at == (0.1, 0.3)
    assert result["C3"].verdict == "holds only for sigma in [0.1, 0.3] rad"


def test_c3_does_not_hold_for_large_errors():
    result = claims(synthetic_rows(lambda c, s: 0.5))
    assert result["C3"].verdict == "does not hold"
    assert result["C2"].verdict == "does not hold"  # equal errors: no significant decrease


def test_verdict_text_forms():
    assert verdict_text([0.0, 0.1], [0.0, 0.1]) == "holds"
    assert verdict_text([0.0, 0.1, 0.2], [0.1]) == "holds only for sigma = 0.1 rad"
    assert verdict_text([0.0, 0.1, 0.2], [0.0, 0.2]) == "holds only for sigma in {0, 0.2} rad"


def test_mean_interval_matches_student_t():
    x = np.array([1.0, 2.5, 2.0, 4.5, 5.0])
    iv = mean_interval(x)
    half = stats.t.ppf(0.975, 4) * x.std(ddof=1) / np.sqrt(5)
    assert iv.mean == pytest.approx(3.0)
    assert (iv.low, iv.high) == pytest.approx((3.0 - half, 3.0 + half))
    assert mean_interval([2.0]).low == mean_interval([2.0]).high == 2.0
    with pytest.raises(ValueError, match="NaN"):
        mean_interval([1.0, np.nan])


def test_paired_comparison_uses_per_seed_differences():
    rng = np.random.default_rng(0)
    common = rng.normal(10.0, 3.0, 50)  # large shared noise
    a, b = common - 0.1, common  # a is always 0.1 better
    cmp = paired_comparison(a, b)
    assert cmp.win_rate == 1.0
    assert cmp.diff.mean == pytest.approx(-0.1)
    assert cmp.diff.high < 0  # significant although the marginal intervals overlap
    assert mean_interval(a).high > mean_interval(b).low


def test_summary_rows_pair_with_the_flc():
    value = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.008, "IT2FLC FoU 0.2": 0.005,
             "IT2FLC FoU 0.3": 0.003, "T1 dead-zone-matched 0.2": 0.007}
    rows = synthetic_rows(lambda c, s: value[c], levels=(0.1,), n_seeds=10)
    summary = summarise(rows)
    ise = [r for r in summary if r["metric"] == "ISE" and r["trajectory"] == "straight"]
    by_ctrl = {r["controller"]: r for r in ise}
    assert by_ctrl["FLC"]["diff_mean"] == ""
    assert by_ctrl["IT2FLC FoU 0.3"]["win_rate"] == 1.0
    assert by_ctrl["IT2FLC FoU 0.3"]["diff_mean"] < 0
    assert by_ctrl["IT2FLC FoU 0.3"]["n"] == 10

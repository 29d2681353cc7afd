"""Summary statistics and claim verdicts, on synthetic metrics where the truth is known."""

import numpy as np
import pytest
from scipy import stats

from it2track.experiments.analysis import evaluate_claims, summarise, verdict_text
from it2track.experiments.stats import mean_interval, paired_comparison
from it2track.tracking import METRIC_NAMES

TRAJ = ("straight", "curved", "sinusoidal")
FOUS = (0.1, 0.2, 0.3)


METRIC_SCALE = {m: 1.0 + 0.37 * i for i, m in enumerate(METRIC_NAMES)}


def synthetic_rows(level_fn, levels=(0.0, 0.1, 0.3), n_seeds=40, seed=1, metric_fn=None):
    """Metrics table where controller c at sigma has metric m = level_fn(c, sigma) * scale(m)
    * (1 + noise), the noise shared by all controllers for one seed (common random numbers).
    Each metric gets its own scale (``metric_fn(c, s, m)`` overrides it) and the rows are
    shuffled, so mixing metrics up or pairing rows by position instead of by seed fails."""
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
                    jitter = 1.0 + shared[ti, li, k] + 0.001 * rng.normal() * (ci + 1)
                    for m in METRIC_NAMES:
                        scale = metric_fn(c, s, m) if metric_fn else METRIC_SCALE[m]
                        cols[m].append(level_fn(c, s) * scale * jitter)
    order = rng.permutation(len(cols["seed"]))
    return {k: np.asarray(v, dtype=object if k in ("experiment", "trajectory", "controller",
                                                   "kind") else None)[order]
            for k, v in cols.items()}


def claims(rows):
    out = evaluate_claims(rows, fous=FOUS, main_fou=0.2, trajectories=TRAJ)
    return {c.id: c for c in out}


def test_claims_hold_when_the_data_say_so():
    # Errors fall with the FoU at every level, straight ISE min ~0.003, IT2 beats matched T1.
    value = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.008, "IT2FLC FoU 0.2": 0.005,
             "IT2FLC FoU 0.3": 0.003, "T1 dead-zone-matched 0.2": 0.007}
    # ISE itself is value * 1.0 so that C3 sees the numbers above.
    result = claims(synthetic_rows(lambda c, s: value[c],
                                   metric_fn=lambda c, s, m: 1.0 if m == "ISE" else 2.0))
    assert result["C1"].verdict == "holds"
    assert result["C2"].verdict == "holds"
    assert result["C3"].verdict == "holds"
    assert result["D1"].verdict == "holds"


def test_c2_does_not_hold_when_errors_grow_with_the_fou():
    value = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.003, "IT2FLC FoU 0.2": 0.005,
             "IT2FLC FoU 0.3": 0.008, "T1 dead-zone-matched 0.2": 0.004}
    result = claims(synthetic_rows(lambda c, s: value[c]))
    assert result["C2"].verdict == "does not hold"
    assert result["C2"].contradicted_at == (0.0, 0.1, 0.3)
    assert result["C1"].verdict == "holds"
    assert result["D1"].verdict == "does not hold"  # matched T1 is better than the IT2FLC
    failing = [e for e in result["C2"].evidence if e["outcome"] != "supports"]
    assert failing and all(e["outcome"] == "contradicts" for e in failing)


def test_one_metric_can_break_a_claim():
    # IT2 beats the FLC on every metric but ITAE on the curved path, where it is worse: C1
    # must not hold, and the evidence must name exactly that cell.
    value = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.008, "IT2FLC FoU 0.2": 0.005,
             "IT2FLC FoU 0.3": 0.003, "T1 dead-zone-matched 0.2": 0.007}

    def metric_fn(c, s, m):
        return 5.0 if (c == "IT2FLC FoU 0.2" and m == "ITAE") else 1.0

    rows = synthetic_rows(lambda c, s: value[c], metric_fn=metric_fn)
    result = claims(rows)
    assert result["C1"].verdict == "does not hold"
    bad = {(e["trajectory"], e["metric"]) for e in result["C1"].evidence
           if e["outcome"] == "contradicts"}
    assert bad == {(t, "ITAE") for t in TRAJ}


def test_ties_are_inconclusive_not_contradictions():
    # Identical errors (e.g. two controllers that never leave their dead zones): the claim is
    # "not shown" there, not refuted, and the win rate is 0.5.
    value = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.01, "IT2FLC FoU 0.2": 0.01,
             "IT2FLC FoU 0.3": 0.01, "T1 dead-zone-matched 0.2": 0.01}
    rows = synthetic_rows(lambda c, s: value[c], n_seeds=10)
    for k in METRIC_NAMES:  # make the controllers exactly equal per seed
        flc = {(t, s, z): v for t, s, z, v, c in zip(rows["trajectory"], rows["noise_std"],
                                                      rows["seed"], rows[k], rows["controller"],
                                                      strict=True) if c == "FLC"}
        rows[k] = np.array([flc[(t, s, z)] for t, s, z in zip(
            rows["trajectory"], rows["noise_std"], rows["seed"], strict=True)])
    result = claims(rows)
    assert result["C1"].verdict == "not shown"
    assert result["C1"].contradicted_at == ()
    assert all(e["outcome"] == "inconclusive" for e in result["C1"].evidence)
    assert all(e["win_rate"] == 0.5 for e in result["C1"].evidence)


def test_verdict_depends_on_noise_level():
    # IT2 beats the FLC only when sigma > 0; C3 holds only where the best ISE is ~0.003.
    def value(c, s):
        if c == "FLC":
            return 0.02
        if c.startswith("IT2"):
            return 0.02 if s == 0.0 else 0.003 * (1 + s)
        return 0.03

    result = claims(synthetic_rows(value, metric_fn=lambda c, s, m: 1.0))
    assert result["C1"].verdict == "holds only for sigma in [0.1, 0.3] rad"
    assert result["C1"].holds_at == (0.1, 0.3)
    assert result["C1"].detail == "not shown at sigma = 0 rad"  # exact ties at sigma = 0
    assert result["C3"].verdict == "holds only for sigma in [0.1, 0.3] rad"
    assert result["C3"].detail == "contradicted at sigma = 0 rad"  # ISE 0.02: above the band


def test_c3_does_not_hold_for_large_errors():
    result = claims(synthetic_rows(lambda c, s: 0.5))
    assert result["C3"].verdict == "does not hold"
    assert {e["position"] for e in result["C3"].evidence} == {"above the band"}
    # equal errors up to a tiny controller-specific jitter: no significant decrease anywhere
    assert result["C2"].holds_at == ()


def test_a_single_realisation_shows_nothing():
    value = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.008, "IT2FLC FoU 0.2": 0.005,
             "IT2FLC FoU 0.3": 0.003, "T1 dead-zone-matched 0.2": 0.007}
    result = claims(synthetic_rows(lambda c, s: value[c], n_seeds=1))
    for claim in result.values():
        assert claim.verdict == "not shown", claim.id
        assert {e["outcome"] for e in claim.evidence} == {"inconclusive"}


def test_verdict_text_forms():
    assert verdict_text([0.0, 0.1], [0.0, 0.1]) == "holds"
    assert verdict_text([0.0, 0.1], [], [0.1]) == "does not hold"
    assert verdict_text([0.0, 0.1], [], []) == "not shown"
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
    assert cmp.win_rate == 1.0 and cmp.ties == 0.0
    tie = paired_comparison([1.0, 2.0, 3.0, 4.0], [1.0, 2.0, 5.0, 0.0])
    assert tie.ties == 0.5 and tie.win_rate == 0.5  # one win, one loss, two ties
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

"""Summary statistics and claim verdicts, on synthetic metrics where the truth is known."""

import math

import numpy as np
import pytest
from scipy import stats

from it2track.experiments.analysis import (
    ALPHA,
    MEASURED_INTEGRALS,
    c3_sigma_range,
    evaluate_claims,
    ordering_probability,
    summarise,
    verdict_text,
)
from it2track.experiments.stats import (
    binomial_interval,
    holm_adjust,
    mean_interval,
    paired_comparison,
    t_tail,
)
from it2track.tracking import METRIC_NAMES

TRAJ = ("straight", "curved", "sinusoidal")
FOUS = (0.1, 0.2, 0.3)


METRIC_SCALE = {m: 1.0 + 0.37 * i for i, m in enumerate(METRIC_NAMES)}


CONTROLLERS = ("FLC", *(f"IT2FLC FoU {w:g}" for w in FOUS), "T1 slope-matched 0.2",
               "T1 dead-zone-matched 0.2")


def synthetic_rows(level_fn, levels=(0.0, 0.1, 0.3), n_seeds=40, seed=1, metric_fn=None):
    """Metrics table where controller c at sigma has metric m = level_fn(c, sigma) * scale(m)
    * (1 + noise), the noise shared by all controllers for one seed (common random numbers)
    and absent at sigma = 0 (a noise-free run is the same for every seed).
    Each metric gets its own scale (``metric_fn(c, s, m)`` overrides it) and the rows are
    shuffled, so mixing metrics up or pairing rows by position instead of by seed fails."""
    rng = np.random.default_rng(seed)
    cols = {k: [] for k in ("experiment", "trajectory", "controller", "kind", "fou",
                            "noise_std", "seed", *METRIC_NAMES)}
    shared = rng.normal(0.0, 0.05, size=(len(TRAJ), len(levels), n_seeds))
    own = rng.normal(0.0, 0.001, size=(len(CONTROLLERS), len(TRAJ), len(levels), n_seeds))
    for ci, c in enumerate(CONTROLLERS):
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
                    jitter = 1.0 if s == 0.0 else (1.0 + shared[ti, li, k]
                                                   + own[ci, ti, li, k] * (ci + 1))
                    for m in METRIC_NAMES:
                        scale = metric_fn(c, s, m) if metric_fn else METRIC_SCALE[m]
                        cols[m].append(level_fn(c, s) * scale * jitter)
    order = rng.permutation(len(cols["seed"]))
    return {k: np.asarray(v, dtype=object if k in ("experiment", "trajectory", "controller",
                                                   "kind") else None)[order]
            for k, v in cols.items()}


def claims(rows, **kw):
    out = evaluate_claims(rows, fous=FOUS, main_fou=0.2, trajectories=TRAJ, **kw)
    return {c.id: c for c in out}


GOOD = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.008, "IT2FLC FoU 0.2": 0.005, "IT2FLC FoU 0.3": 0.003,
        "T1 slope-matched 0.2": 0.006, "T1 dead-zone-matched 0.2": 0.007}


def test_claims_hold_when_the_data_say_so():
    # Errors fall with the FoU at every level, straight ISE min ~0.003, IT2 beats both T1s.
    # ISE itself is value * 1.0 so that C3 sees the numbers above.
    result = claims(synthetic_rows(lambda c, s: GOOD[c],
                                   metric_fn=lambda c, s, m: 1.0 if m == "ISE" else 2.0))
    for cid in ("C1", "C2", "C3", "D1", "D2"):
        assert result[cid].verdict == "holds", cid
        assert result[cid].levels == (0.1, 0.3), cid  # the noisy levels
        assert result[cid].deterministic_at == (0.0,), cid
        assert result[cid].level_status == {0.0: "deterministic", 0.1: "holds", 0.3: "holds"}
    assert result["C1"].detail == ("deterministic at σ = 0 rad (one noise-free run): as "
                                   "claimed in every cell")
    assert set(result["C1"].per_trajectory) == set(TRAJ)
    assert all(v["verdict"] == "holds" for v in result["C1"].per_trajectory.values())


def test_noise_free_cells_are_one_deterministic_run():
    result = claims(synthetic_rows(lambda c, s: GOOD[c]))
    det = [e for e in result["C1"].evidence if e["sigma"] == 0.0]
    assert len(det) == len(TRAJ) * 4
    assert all(e["outcome"] == "deterministic" and e["n"] == 1 and e["ci_low"] == ""
               and e["exact"] == "as claimed" for e in det)
    noisy = [e for e in result["C1"].evidence if e["sigma"] > 0.0]
    assert all(e["n"] == 40 and e["exact"] == "" for e in noisy)


def test_deterministic_detail_counts_opposite_and_tied_cells():
    # Noise-free: the IT2FLC is worse on the curved path, tied on the straight line.
    def value(c, s):
        if s == 0.0 and c == "IT2FLC FoU 0.2":
            return 0.0  # placeholder, replaced per trajectory below
        return GOOD[c]

    rows = synthetic_rows(value)
    it2_0 = (rows["controller"] == "IT2FLC FoU 0.2") & (rows["noise_std"] == 0.0)
    flc_0 = (rows["controller"] == "FLC") & (rows["noise_std"] == 0.0)
    for m in METRIC_NAMES:
        for traj, factor in (("straight", 1.0), ("curved", 2.0), ("sinusoidal", 0.5)):
            sel = it2_0 & (rows["trajectory"] == traj)
            ref = rows[m][flc_0 & (rows["trajectory"] == traj)][0]
            rows[m][sel] = ref * factor
    c1 = claims(rows)["C1"]
    assert c1.deterministic == ("deterministic at σ = 0 rad (one noise-free run): as "
                                "claimed in 4 of 12 cells, opposite in 4, tied in 4")
    assert c1.verdict == "holds"  # the noisy levels decide the verdict
    assert c1.per_trajectory["curved"]["deterministic"].endswith(
        "as claimed in 0 of 4 cells, opposite in 4")


def test_summary_reports_noise_free_cells_as_n_1_without_interval():
    rows = synthetic_rows(lambda c, s: GOOD[c], levels=(0.0, 0.1), n_seeds=10)
    summary = summarise(rows)
    zero = [r for r in summary if r["noise_std"] == 0.0]
    assert zero and all(r["n"] == 1 and r["ci_low"] == "" and r["ci_high"] == "" for r in zero)
    it2 = [r for r in zero if r["controller"] == "IT2FLC FoU 0.3"]
    assert all(r["win_rate"] == 1.0 and r["diff_low"] == "" and r["diff_mean"] < 0 for r in it2)
    noisy = [r for r in summary if r["noise_std"] == 0.1]
    assert all(r["n"] == 10 and r["ci_low"] < r["mean"] < r["ci_high"] for r in noisy)


def test_c2_does_not_hold_when_errors_grow_with_the_fou():
    value = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.003, "IT2FLC FoU 0.2": 0.005,
             "IT2FLC FoU 0.3": 0.008, "T1 slope-matched 0.2": 0.004,
             "T1 dead-zone-matched 0.2": 0.004}
    result = claims(synthetic_rows(lambda c, s: value[c]))
    assert result["C2"].verdict == "does not hold"
    assert result["C2"].contradicted_at == (0.1, 0.3)
    assert result["C1"].verdict == "holds"
    assert result["D1"].verdict == "does not hold"  # both T1s are better than the IT2FLC
    assert result["D2"].verdict == "does not hold"
    failing = [e for e in result["C2"].evidence
               if e["outcome"] not in ("supports", "deterministic")]
    assert failing and all(e["outcome"] == "contradicts" for e in failing)
    assert all(e["p_holm"] <= ALPHA for e in failing)


def test_one_metric_can_break_a_claim():
    # IT2 beats the FLC on every metric but ITAE, where it is worse: C1 must not hold, and the
    # evidence must name exactly those cells.
    def metric_fn(c, s, m):
        return 5.0 if (c == "IT2FLC FoU 0.2" and m == "ITAE") else 1.0

    rows = synthetic_rows(lambda c, s: GOOD[c], metric_fn=metric_fn)
    result = claims(rows)
    assert result["C1"].verdict == "does not hold"
    bad = {(e["trajectory"], e["metric"]) for e in result["C1"].evidence
           if e["outcome"] == "contradicts"}
    assert bad == {(t, "ITAE") for t in TRAJ}


def test_measured_heading_metrics_are_judged_when_asked():
    # Better on the true heading integrals, worse on the measured ones.
    def metric_fn(c, s, m):
        return 3.0 if (c == "IT2FLC FoU 0.2" and m.endswith("_meas")) else 1.0

    rows = synthetic_rows(lambda c, s: GOOD[c], metric_fn=metric_fn)
    assert claims(rows)["C1"].verdict == "holds"
    measured = claims(rows, metrics=MEASURED_INTEGRALS)["C1"]
    assert measured.verdict == "does not hold"
    assert {e["metric"] for e in measured.evidence} == set(MEASURED_INTEGRALS)


def test_per_trajectory_verdicts_show_where_a_claim_holds():
    # The IT2FLC wins on the curved and sinusoidal paths but loses on the straight line.
    rows = synthetic_rows(lambda c, s: GOOD[c])
    for m in METRIC_NAMES:
        sel = (rows["controller"] == "IT2FLC FoU 0.2") & (rows["trajectory"] == "straight")
        rows[m][sel] *= 3.0
    c1 = claims(rows)["C1"]
    assert c1.verdict == "does not hold"
    assert c1.per_trajectory["straight"]["verdict"] == "does not hold"
    assert c1.per_trajectory["curved"]["verdict"] == "holds"
    assert c1.per_trajectory["sinusoidal"]["verdict"] == "holds"


def test_ties_are_inconclusive_not_contradictions():
    # Identical errors (e.g. two controllers that never leave their dead zones): the claim is
    # "not shown" there, not refuted, and the win rate is 0.5.
    value = dict.fromkeys(CONTROLLERS, 0.01)
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
    assert {e["outcome"] for e in result["C1"].evidence if e["sigma"] > 0} == {"inconclusive"}
    assert all(e["win_rate"] == 0.5 for e in result["C1"].evidence)
    assert "tied in 12" in result["C1"].detail


def test_verdict_depends_on_noise_level():
    # IT2 beats the FLC only at the larger sigma; C3 holds only where the best ISE is ~0.003.
    def value(c, s):
        if c == "FLC":
            return 0.02
        if c.startswith("IT2"):
            return 0.02 if s <= 0.05 else 0.003 * (1 + s)
        return 0.03

    rows = synthetic_rows(value, levels=(0.0, 0.05, 0.1, 0.3),
                          metric_fn=lambda c, s, m: 1.0)
    result = claims(rows)
    assert result["C1"].verdict == "holds only for σ ∈ {0.1, 0.3} rad"
    assert result["C1"].holds_at == (0.1, 0.3)
    assert result["C1"].detail.startswith("not shown at σ = 0.05 rad")
    assert result["C3"].verdict == "holds only for σ ∈ {0.1, 0.3} rad"
    assert result["C3"].detail.startswith("contradicted at σ = 0.05 rad")  # 0.02: above


def test_c3_contradicts_above_the_band():
    result = claims(synthetic_rows(lambda c, s: 0.5))
    assert result["C3"].verdict == "does not hold"
    noisy = [e for e in result["C3"].evidence if e["sigma"] > 0]
    assert {e["position"] for e in noisy} == {"above the band"}
    assert {e["outcome"] for e in noisy} == {"contradicts"}
    # equal errors up to a tiny controller-specific jitter: no significant decrease anywhere
    assert result["C2"].holds_at == ()


def test_c3_contradicts_below_the_band():
    # The other side of the symmetric band: an ISE far below 0.00095 contradicts "of order
    # 0.003" just as one far above it does.
    result = claims(synthetic_rows(lambda c, s: 1e-5, metric_fn=lambda c, s, m: 1.0))
    noisy = [e for e in result["C3"].evidence if e["sigma"] > 0]
    assert {e["position"] for e in noisy} == {"below the band"}
    assert {e["outcome"] for e in noisy} == {"contradicts"}
    assert result["C3"].verdict == "does not hold"
    det = [e for e in result["C3"].evidence if e["sigma"] == 0]
    assert det[0]["outcome"] == "deterministic" and det[0]["exact"] == "opposite"


@pytest.mark.parametrize("mean", [0.003 / np.sqrt(10), 0.003 * np.sqrt(10)])
def test_c3_is_inconclusive_when_the_interval_straddles_a_band_edge(mean):
    # Mean exactly on an edge: the interval reaches both inside and outside the band. The old
    # asymmetric rule ("supports when the mean is in the band") called the upper edge support.
    rows = synthetic_rows(lambda c, s: mean if c == "IT2FLC FoU 0.3" else 10 * mean,
                          levels=(0.1,), metric_fn=lambda c, s, m: 1.0)
    c3 = claims(rows)["C3"]
    assert [e["outcome"] for e in c3.evidence] == ["inconclusive"]
    assert c3.verdict == "not shown"


def _exact_t_rows(t_stats, n=10):
    """C1 cells with prescribed one-sided t statistics of IT2 - FLC (one level, one trajectory
    per statistic's position, metrics in order): per-seed differences ``t * sd / sqrt(n) + sd
    z`` with z standardised exactly (mean 0, sd 1)."""
    z = np.linspace(-1.0, 1.0, n)
    z = (z - z.mean()) / z.std(ddof=1)
    cols = {k: [] for k in ("experiment", "trajectory", "controller", "kind", "fou",
                            "noise_std", "seed", *METRIC_NAMES)}
    cells = [(t, m) for t in TRAJ for m in ("IAE", "ITAE", "ISE", "ITSE")]
    assert len(t_stats) == len(cells)
    for c in ("FLC", *(f"IT2FLC FoU {w:g}" for w in FOUS)):
        for traj in TRAJ:
            for k in range(n):
                cols["experiment"].append("noise")
                cols["trajectory"].append(traj)
                cols["controller"].append(c)
                cols["kind"].append("x")
                cols["fou"].append(0.0)
                cols["noise_std"].append(0.1)
                cols["seed"].append(k)
                for m in METRIC_NAMES:
                    base = 1.0
                    if c == "IT2FLC FoU 0.2" and m in ("IAE", "ITAE", "ISE", "ITSE"):
                        t = t_stats[cells.index((traj, m))]
                        base += 0.01 * (t / np.sqrt(n) + z[k])
                    cols[m].append(base)
    return {k: np.asarray(v, dtype=object if k in ("experiment", "trajectory", "controller",
                                                   "kind") else None) for k, v in cols.items()}


def test_holm_turns_a_borderline_contradiction_into_inconclusive():
    # One of the 12 cells has one-sided p = 0.005 (its 95 % interval lies above 0, which the
    # old rule called a contradiction); Holm over 12 cells gives 0.06 > 0.025: inconclusive.
    # The other cells support the claim.
    t_border = stats.t.isf(0.005, 9)
    c1 = claims(_exact_t_rows([t_border] + [-8.0] * 11))["C1"]
    cell = c1.evidence[0]
    assert cell["ci_low"] > 0.0  # the naive per-cell rule would contradict
    assert cell["p_holm"] == pytest.approx(12 * 0.005)
    assert cell["outcome"] == "inconclusive"
    assert c1.verdict == "not shown"
    # A stronger cell survives the correction: p = 0.001 -> 0.012 <= 0.025.
    c1 = claims(_exact_t_rows([stats.t.isf(0.001, 9)] + [-8.0] * 11))["C1"]
    assert c1.evidence[0]["outcome"] == "contradicts"
    assert c1.evidence[0]["p_holm"] == pytest.approx(0.012)
    assert c1.verdict == "does not hold"


def test_a_single_realisation_shows_nothing():
    result = claims(synthetic_rows(lambda c, s: GOOD[c], n_seeds=1, levels=(0.1, 0.3)))
    assert result["D3"].verdict.startswith("not evaluated: the study has no 'T1 surface copy")
    for claim in result.values():
        if claim.id == "D3":
            continue
        assert claim.verdict == "not shown", claim.id
        assert {e["outcome"] for e in claim.evidence} == {"inconclusive"}


def test_ordering_probability_counts_realisations_with_the_strict_order():
    rows = synthetic_rows(lambda c, s: GOOD[c], levels=(0.0, 0.1), n_seeds=30)
    # Break the order for seeds 0-4 on the curved path only (FoU 0.3 worse than FoU 0.2).
    sel = ((rows["controller"] == "IT2FLC FoU 0.3") & (rows["trajectory"] == "curved")
           & (rows["seed"] < 5) & (rows["noise_std"] == 0.1))
    rows["ITSE"][sel] = 1.0
    out = {(r["sigma"], r["trajectory"]): r for r in ordering_probability(
        rows, fous=FOUS, trajectories=TRAJ)}
    assert out[(0.1, "all")]["k"] == 25 and out[(0.1, "all")]["n"] == 30
    assert out[(0.1, "curved")]["k"] == 25 and out[(0.1, "straight")]["k"] == 30
    assert (out[(0.1, "all")]["ci_low"], out[(0.1, "all")]["ci_high"]) == pytest.approx(
        binomial_interval(25, 30))
    assert out[(0.0, "all")] == {"sigma": 0.0, "trajectory": "all", "n": 1, "k": 1, "p": 1.0,
                                 "ci_low": "", "ci_high": "", "deterministic": True}


def test_clopper_pearson_matches_closed_forms_and_scipy():
    # k = 0 and k = n have closed forms; elsewhere compare with scipy's exact binomial test.
    assert binomial_interval(0, 20) == pytest.approx((0.0, 1 - 0.025 ** (1 / 20)))
    assert binomial_interval(20, 20) == pytest.approx((0.025 ** (1 / 20), 1.0))
    ref = stats.binomtest(7, 40).proportion_ci(0.95, method="exact")
    assert binomial_interval(7, 40) == pytest.approx((ref.low, ref.high))
    with pytest.raises(ValueError, match="k=5, n=4"):
        binomial_interval(5, 4)


def test_holm_and_t_tail_against_references():
    # Holm by hand: sorted p (0.01, 0.03, 0.04) times (3, 2, 1), running max.
    assert holm_adjust([0.04, 0.01, 0.03]).tolist() == pytest.approx([0.06, 0.03, 0.06])
    assert holm_adjust([]).size == 0
    x = np.array([0.3, -0.1, 0.5, 0.2, 0.4])
    assert t_tail(x, 0.0) == pytest.approx(stats.ttest_1samp(x, 0.0,
                                                             alternative="greater").pvalue)
    assert t_tail(x, 0.5, side="less") == pytest.approx(
        stats.ttest_1samp(x, 0.5, alternative="less").pvalue)
    assert t_tail([1.0], 0.0) == 1.0
    assert t_tail([2.0, 2.0], 1.0) == 0.0 and t_tail([2.0, 2.0], 3.0) == 1.0


def test_c3_sigma_range_interpolates_a_power_law_exactly():
    # Best ISE = 0.03 sigma: in the band [0.00095, 0.0095] for sigma in [0.0316, 0.316].
    levels = (0.0, 0.02, 0.05, 0.1, 0.2, 0.5)
    rows = synthetic_rows(lambda c, s: 0.03 * s if c == "IT2FLC FoU 0.3" else 1.0,
                          levels=levels, metric_fn=lambda c, s, m: 1.0, n_seeds=60)
    c3 = claims(rows)["C3"]
    rng = c3_sigma_range(c3)
    assert rng["levels_in_band"] == [0.05, 0.1, 0.2]
    assert rng["enters"]["sigma"] == pytest.approx(0.1 / np.sqrt(10), rel=0.05)
    assert rng["leaves"]["sigma"] == pytest.approx(1 / np.sqrt(10), rel=0.05)
    a, b = rng["enters"]["range"]
    assert a < rng["enters"]["sigma"] < b


def test_verdict_text_forms():
    assert verdict_text([0.05, 0.1], [0.05, 0.1]) == "holds"
    assert verdict_text([0.0, 0.1], [], [0.1]) == "does not hold"
    assert verdict_text([0.0, 0.1], [], []) == "not shown"
    assert verdict_text([0.0, 0.1, 0.2], [0.1]) == "holds only for σ = 0.1 rad"
    assert verdict_text([0.0, 0.1, 0.2], [0.0, 0.2]) == "holds only for σ ∈ {0, 0.2} rad"


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
    rows = synthetic_rows(lambda c, s: GOOD[c], levels=(0.1,), n_seeds=10)
    summary = summarise(rows)
    ise = [r for r in summary if r["metric"] == "ISE" and r["trajectory"] == "straight"]
    by_ctrl = {r["controller"]: r for r in ise}
    assert by_ctrl["FLC"]["diff_mean"] == ""
    assert by_ctrl["IT2FLC FoU 0.3"]["win_rate"] == 1.0
    assert by_ctrl["IT2FLC FoU 0.3"]["diff_mean"] < 0
    assert by_ctrl["IT2FLC FoU 0.3"]["n"] == 10


def test_c3_sigma_range_starts_from_an_exactly_zero_ise():
    # Below sigma = 0.05 the best controller never leaves its dead zone (ISE exactly 0): the
    # crossing into the band is interpolated linearly from 0 (a logarithm would fail).
    ise = {0.02: 0.0, 0.05: 0.002, 0.1: 0.02}
    rows = synthetic_rows(lambda c, s: ise[s] if c == "IT2FLC FoU 0.3" else 1.0,
                          levels=(0.02, 0.05, 0.1), metric_fn=lambda c, s, m: 1.0, n_seeds=60)
    rng = c3_sigma_range(claims(rows)["C3"])
    lo = 0.003 / np.sqrt(10)
    assert rng["enters"]["sigma"] == pytest.approx(0.02 + lo / 0.002 * 0.03, rel=0.05)
    assert rng["levels_in_band"] == [0.05]


def test_intervals_and_tails_equal_scipy_stats_bit_for_bit():
    # stats.py calls scipy.special directly; the numbers (hence every verdict and every row of
    # summary.csv) must be exactly those of scipy.stats' t and beta distributions.
    rng = np.random.default_rng(7)
    for n in (2, 3, 5, 40, 200):
        for _ in range(20):
            x = rng.normal(rng.normal(), rng.uniform(0.1, 3.0), n)
            sem = float(np.std(x, ddof=1)) / math.sqrt(n)
            iv = mean_interval(x, 0.9)
            assert iv.high == float(np.mean(x)) + float(stats.t.ppf(0.95, n - 1)) * sem
            t = (float(np.mean(x)) - 0.3) / sem
            assert t_tail(x, 0.3) == float(stats.t.sf(t, n - 1))
    a = 1.0 - 0.95
    for k, n in ((1, 40), (7, 40), (39, 40), (3, 5)):
        assert binomial_interval(k, n) == (float(stats.beta.ppf(a / 2, k, n - k + 1)),
                                           float(stats.beta.ppf(1 - a / 2, k + 1, n - k)))


def test_a_missing_baseline_is_reported_and_the_later_claims_still_judged():
    # Without the slope-matched FLC, D1 is "not evaluated" with its own statement and
    # criterion, over the study's levels, holding nowhere -- and D2, D3 after it are still
    # judged (a missing claim skips itself, not the rest).
    from it2track.experiments.claimcells import claim_definitions

    rows = synthetic_rows(lambda c, s: GOOD[c])
    keep = rows["controller"] != "T1 slope-matched 0.2"
    rows = {k: v[keep] for k, v in rows.items()}
    out = evaluate_claims(rows, fous=FOUS, main_fou=0.2, trajectories=TRAJ)
    assert [c.id for c in out] == ["C1", "C2", "C3", "D1", "D2", "D3"]
    d1 = out[3]
    defs = claim_definitions(fous=FOUS, main_fou=0.2, trajectories=TRAJ)
    assert (d1.statement, d1.criterion) == (defs[3].statement, defs[3].criterion)
    assert d1.verdict == "not evaluated: the study has no 'T1 slope-matched 0.2' baseline"
    assert d1.levels == (0.0, 0.1, 0.3) and d1.holds_at == () and d1.evidence == []
    assert out[4].verdict == "holds" and out[4].holds_at == (0.1, 0.3)


def test_no_rows_of_the_experiment_is_an_error_naming_it():
    rows = synthetic_rows(lambda c, s: GOOD[c], levels=(0.1,), n_seeds=2)
    with pytest.raises(ValueError) as info:
        evaluate_claims(rows, fous=FOUS, main_fou=0.2, trajectories=TRAJ,
                        experiment="robustness")
    assert str(info.value) == "no rows of experiment 'robustness' to evaluate the claims on"

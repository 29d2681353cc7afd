"""Replication probabilities: the bootstrap re-judges claims exactly as the data are judged,
approaches the non-central-t closed form, and settles a level at exactly the target."""

import numpy as np
import pytest
from scipy import stats

from it2track.experiments.analysis import evaluate_claims
from it2track.experiments.claimcells import (
    BELOW,
    CellData,
    ClaimDef,
    claim_cells,
    claim_definitions,
)
from it2track.experiments.judgement import judge_claim, with_replication
from it2track.experiments.replication import (
    STATUS_CODES,
    judge_replicates,
    observed_levels,
    replicate_claims,
    replication_probabilities,
    uniform_resampler,
)
from it2track.tracking import METRIC_NAMES

TRAJ = ("straight", "curved", "sinusoidal")
FOUS = (0.1, 0.2, 0.3)
LABELS = ("FLC", "IT2FLC FoU 0.1", "IT2FLC FoU 0.2", "IT2FLC FoU 0.3", "T1 slope-matched 0.2",
          "T1 dead-zone-matched 0.2", "T1 surface copy 0.2")


def rows_from(level_fn, *, levels=(0.0, 0.05, 0.1), n=30, seed=3, own=0.02):
    """Metrics where controller c at sigma on path p has metric m = level_fn(c, s, p) times a
    per-(seed, path, level) factor shared by every controller (common random numbers) and its
    own small noise."""
    rng = np.random.default_rng(seed)
    cols = {k: [] for k in ("experiment", "trajectory", "controller", "kind", "fou",
                            "noise_std", "seed", *METRIC_NAMES)}
    shared = rng.normal(0.0, 0.2, size=(len(TRAJ), len(levels), n))
    for c in LABELS:
        mine = rng.normal(0.0, own, size=(len(TRAJ), len(levels), n, len(METRIC_NAMES)))
        for ti, t in enumerate(TRAJ):
            for li, s in enumerate(levels):
                for k in range(n if s > 0 else 1):
                    cols["experiment"].append("noise")
                    cols["trajectory"].append(t)
                    cols["controller"].append(c)
                    cols["kind"].append("x")
                    cols["fou"].append(0.0)
                    cols["noise_std"].append(s)
                    cols["seed"].append(k)
                    for mi, m in enumerate(METRIC_NAMES):
                        jitter = 1.0 if s == 0 else 1.0 + shared[ti, li, k] + mine[ti, li, k, mi]
                        cols[m].append(level_fn(c, s, t) * (1.0 + 0.3 * mi) * jitter)
    return {k: np.asarray(v, dtype=object if k in ("experiment", "trajectory", "controller",
                                                   "kind") else None)
            for k, v in cols.items()}


def _mixed(c, s, t):
    """Claims in every state: C1 holding at 0.1 only, C2 borderline, D2 contradicted, C3 in
    the band at 0.05 only, D3 a near-copy."""
    base = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.0098, "IT2FLC FoU 0.2": 0.0097,
            "IT2FLC FoU 0.3": 0.0096, "T1 slope-matched 0.2": 0.0097,
            "T1 dead-zone-matched 0.2": 0.0085, "T1 surface copy 0.2": 0.0097}[c]
    if c == "IT2FLC FoU 0.2" and s == 0.1:
        base = 0.008
    if s == 0.1 and c.startswith("IT2"):
        base *= 3.0 if c != "IT2FLC FoU 0.2" else 1.0
    return base * (1.0 if t != "curved" else 1.3) * (1.0 + 10 * s)


def _judged(rows):
    defs = claim_definitions(fous=FOUS, main_fou=0.2, trajectories=TRAJ)
    results = evaluate_claims(rows, fous=FOUS, main_fou=0.2, trajectories=TRAJ, claims=defs)
    levels = tuple(sorted({float(s) for s in rows["noise_std"]}))
    cells = {d.id: claim_cells(rows, d, experiment="noise", levels=levels) for d in defs}
    return defs, results, cells


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_the_vector_judge_equals_the_claim_judgement_on_the_data(seed):
    # Differential: the bootstrap's judge, fed the data themselves, must give every status
    # evaluate_claims gives (Holm over the whole family, per path and over all paths).
    rows = rows_from(_mixed, seed=seed, n=12 + 9 * seed)
    defs, results, cells = _judged(rows)
    seen = set()
    for d, r in zip(defs, results, strict=True):
        observed = observed_levels(d, r)
        noisy = [k for k, st in observed.items() if st != "deterministic"]
        codes = judge_replicates(cells[d.id], noisy, None)
        assert codes.shape == (1, len(noisy))
        for k, code in zip(noisy, codes[0], strict=True):
            assert code == STATUS_CODES[observed[k]], (d.id, k)
            seen.add(observed[k])
    assert seen == {"holds", "contradicted", "not shown"}  # the data exercise every status


def _exact_normal(n, t, seed=0):
    """n values whose sample mean / (sd / sqrt n) is exactly t (sd 1)."""
    z = np.random.default_rng(seed).normal(size=n)
    z = (z - z.mean()) / z.std(ddof=1)
    return z + t / np.sqrt(n)


def _one_cell(d, sigma=0.1):
    return CellData(sigma=sigma, trajectory="straight", metric="ISE", comparison="a - b",
                    kind=BELOW, values=np.stack([d, np.zeros_like(d)]), labels=("a", "b"))


ONE = ClaimDef(id="X", statement="", criterion="", kind=BELOW, pairs=(("a", "b"),),
               trajectories=("straight",), metrics=("ISE",))


@pytest.mark.parametrize("t_obs", [-1.2, -2.4, -3.0, -3.6, -4.6, -5.5])
def test_one_cell_replication_approaches_its_closed_forms(t_obs):
    n, b = 400, 6000
    cell = _one_cell(_exact_normal(n, t_obs))
    result = judge_claim(ONE, [cell], (0.1,))
    q = stats.t.ppf(0.975, n - 1)
    holds = t_obs < -q
    assert result.level_status[0.1] == ("holds" if holds else "not shown")
    # Plug-in bootstrap: the replicate t is non-central t around the observed one.
    plug = replication_probabilities(ONE, [cell], result,
                                     uniform_resampler(b, 7, predictive=False))
    p_holds = stats.nct.cdf(-q, n - 1, t_obs)
    assert plug[("all", 0.1)] == pytest.approx(p_holds if holds else 1.0 - p_holds, abs=0.03)
    # Predictive (double) bootstrap: the replicate t spreads by twice the variance,
    # P(holds again) = Phi((-q - t) / sqrt 2) (the normal limit; n = 400).
    pred = replication_probabilities(ONE, [cell], result, uniform_resampler(b, 7))
    p_holds = stats.norm.cdf((-q - t_obs) / np.sqrt(2.0))
    assert pred[("all", 0.1)] == pytest.approx(p_holds if holds else 1.0 - p_holds, abs=0.03)
    assert pred[("straight", 0.1)] == pred[("all", 0.1)]
    # The predictive estimate is the more cautious one away from the threshold.
    if abs(t_obs + q) > 0.5:
        assert pred[("all", 0.1)] < plug[("all", 0.1)]


class _Rows:
    """A resampler returning fixed positions (the first rows are the identity)."""

    def __init__(self, good, bad):
        self.good, self.bad = good, bad

    def __call__(self, n):
        ident = np.tile(np.arange(n), (self.good, 1))
        worst = np.full((self.bad, n), n - 1)  # every draw the last value: a positive one
        return np.concatenate([ident, worst])


@pytest.mark.parametrize(("good", "bad", "settled"), [(19, 1, True), (18, 2, False)])
def test_a_level_is_settled_at_exactly_the_target(good, bad, settled):
    d = np.array([-3.0, -2.0, -2.5, -3.5, -2.2, -2.8, -3.1, 0.5])
    cell = _one_cell(d)
    result = judge_claim(ONE, [cell], (0.1,))
    assert result.level_status[0.1] == "holds"
    probs = replication_probabilities(ONE, [cell], result, _Rows(good, bad))
    assert probs[("all", 0.1)] == good / (good + bad)
    judged = with_replication(result, probs, 0.95)
    assert judged.settled("all", 0.1) is settled
    assert judged.verdict == ("holds" if settled else "unsettled")
    assert judged.unsettled_at == (() if settled else (0.1,))


def test_holm_family_spans_levels_and_excludes_noise_free_and_single_runs():
    # Two noisy levels whose contradiction p-values are each below 0.025 alone but not both
    # after Holm over the family of two: the judged statuses and the vector judge agree, and
    # the noise-free and single-realisation cells do not enlarge the family (m = 2).
    t_each = stats.t.ppf(1 - 0.015, 29)  # one-sided p = 0.015 per cell
    c1 = _one_cell(_exact_normal(30, t_each, 1), 0.05)
    c2 = _one_cell(_exact_normal(30, t_each, 2), 0.1)
    det = _one_cell(np.array([1.0]), 0.0)
    single = _one_cell(np.array([2.0]), 0.2)
    cells = [det, c1, c2, single]
    result = judge_claim(ONE, cells, (0.0, 0.05, 0.1, 0.2))
    assert "over all 2 noisy cells" in result.correction
    # Holm: 2 * 0.015 = 0.03 > 0.025, so neither contradicts.
    assert result.level_status == {0.0: "deterministic", 0.05: "not shown", 0.1: "not shown",
                                   0.2: "not shown"}
    codes = judge_replicates(cells, [("all", 0.05), ("all", 0.1), ("all", 0.2)], None)
    assert codes.tolist() == [[STATUS_CODES["not shown"]] * 3]
    # With only one of them in the family, it is contradicted (0.015 <= 0.025).
    alone = judge_claim(ONE, [det, c1, single], (0.0, 0.05, 0.2))
    assert alone.level_status[0.05] == "contradicted"
    assert judge_replicates([det, c1, single], [("all", 0.05)], None).tolist() == [
        [STATUS_CODES["contradicted"]]]


def test_an_empty_family_replicates_without_error():
    det = _one_cell(np.array([-1.0]), 0.0)
    result = judge_claim(ONE, [det], (0.0,))
    probs = replication_probabilities(ONE, [det], result, uniform_resampler(50, 0))
    assert probs == {("all", 0.0): 1.0, ("straight", 0.0): 1.0}
    single = _one_cell(np.array([-1.0]), 0.1)
    codes = judge_replicates([single], [("all", 0.1)], uniform_resampler(5, 0))
    assert codes.tolist() == [[STATUS_CODES["not shown"]]] * 5


def test_the_predictive_resample_is_a_resample_of_a_resample():
    one = uniform_resampler(5, 3, predictive=False)(12)
    two = uniform_resampler(5, 3)(12)
    # Every replicate position is drawn from the first stage's positions of its row.
    for a, b in zip(one, two, strict=True):
        assert set(b.tolist()) <= set(a.tolist())
    # A replicate's mean spreads about twice as much as a plug-in resample's.
    x = np.random.default_rng(0).normal(size=200)
    plug = x[uniform_resampler(4000, 1, predictive=False)(200)].mean(axis=1).var()
    pred = x[uniform_resampler(4000, 1)(200)].mean(axis=1).var()
    assert pred / plug == pytest.approx(2.0, rel=0.1)


def test_uniform_resampler_is_seeded_prefix_stable_and_checked():
    r = uniform_resampler(7, 4)
    a = r(10)
    assert a.shape == (7, 10) and a.min() >= 0 and a.max() <= 9
    big = uniform_resampler(7, 4)(200)
    again = uniform_resampler(7, 4)
    again(200)
    np.testing.assert_array_equal(again(10), a)  # the same draws after a larger request
    assert not np.array_equal(uniform_resampler(7, 5)(10), a)
    assert big.max() > 100
    for bad in (0, -1, True, 1.5):
        with pytest.raises(ValueError, match="resamples"):
            uniform_resampler(bad, 0)
    with pytest.raises(ValueError, match="seed"):
        uniform_resampler(5, -1)


def test_replicate_claims_restates_verdicts_over_settled_levels():
    rows = rows_from(_mixed, n=40)
    defs, results, _ = _judged(rows)
    out = replicate_claims(rows, defs, results, experiment="noise", resamples=400, seed=0,
                           target=0.95)
    for d, before, after in zip(defs, results, out, strict=True):
        assert after.level_status == before.level_status
        assert set(after.replication) == set(observed_levels(d, before))
        for (_path, s), p in after.replication.items():
            assert 0.0 <= p <= 1.0
            if s == 0.0:
                assert p == 1.0
        unsettled = {s for s in after.levels if after.replication[("all", s)] < 0.95}
        assert set(after.unsettled_at) == unsettled
        assert set(after.holds_at) == {s for s in before.holds_at if s not in unsettled}
    with pytest.raises(ValueError, match="target"):
        replicate_claims(rows, defs, results, experiment="noise", resamples=10, seed=0,
                         target=0.0)

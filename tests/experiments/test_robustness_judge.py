"""judge_variants on synthetic metrics rows whose statuses are known by construction: the
change categories, the baseline's spread over its batches, the ranking and the rows of
robustness.csv (robustness.py), without simulating."""

from __future__ import annotations

import numpy as np
import pytest

from it2track.experiments.analysis import evaluate_claims
from it2track.experiments.choices import DEFAULT_CHOICES, Variant
from it2track.experiments.claimcells import claim_definitions
from it2track.experiments.replication import replicate_claims
from it2track.experiments.robustness import RobustnessConfig, judge_variants
from it2track.tracking import METRIC_NAMES, LoopConfig

TRAJ = ("straight", "curved")
FOUS = (0.1, 0.2, 0.3)
#: Errors fall with the FoU; the straight ISE minimum 0.003 lies in C3's band.
GOOD = {"FLC": 0.01, "IT2FLC FoU 0.1": 0.008, "IT2FLC FoU 0.2": 0.005, "IT2FLC FoU 0.3": 0.003}


def rows(main, *, levels=(0.0, 0.1, 0.2), n=10, seed=0, noisy=0.001, measured=None,
         extra=None):
    """Metrics of the robustness experiment: every controller at its GOOD value, except the
    IT2FLC FoU 0.2 at ``main(trajectory, sigma)``; a shared relative noise per seed (common
    random numbers) and ``noisy`` own noise per controller, none at sigma = 0. With
    ``measured``, the *_meas metrics of the IT2FLC FoU 0.2 are ``measured`` instead;
    ``extra``: more controllers, or other values, each a number or a function of
    (trajectory, sigma)."""
    rng = np.random.default_rng(seed)
    values = {**GOOD, **(extra or {})}
    cols = {k: [] for k in ("experiment", "trajectory", "controller", "noise_std", "seed",
                            *METRIC_NAMES)}
    for t in TRAJ:
        for s in levels:
            shared = rng.normal(0.0, 0.05, n)
            for c in values:
                own = rng.normal(0.0, noisy, n)
                for k in range(n):
                    cols["experiment"].append("robustness")
                    cols["trajectory"].append(t)
                    cols["controller"].append(c)
                    cols["noise_std"].append(s)
                    cols["seed"].append(k)
                    jitter = 1.0 if s == 0.0 else 1.0 + shared[k] + own[k]
                    true = (main(t, s) if c == "IT2FLC FoU 0.2" else
                            values[c](t, s) if callable(values[c]) else values[c])
                    meas = measured if measured is not None and c == "IT2FLC FoU 0.2" else true
                    for m in METRIC_NAMES:
                        cols[m].append((meas if m.endswith("_meas") else true) * jitter)
    return {k: np.asarray(v, dtype=object if k in ("experiment", "trajectory", "controller")
                          else None) for k, v in cols.items()}


def good(t, s):
    return GOOD["IT2FLC FoU 0.2"]


def worse(t, s):
    return 0.02


def tied(t, s):
    return GOOD["FLC"]


CHOICES = tuple(c for c in DEFAULT_CHOICES if c.name in (
    "half_track", "control_period", "noise_reading", "heading_integrals", "output_gain"))
CONFIG = RobustnessConfig(choices=CHOICES, factorial=(), factorial_levels=(),
                          sensitivity=None, seeds=10, baseline_batches=3)


def variant(choice, value, *, levels=(0.0, 0.1, 0.2), heading="true"):
    return Variant(choice=choice, value=value, settings=(), loop=LoopConfig(),
                   noise_levels=levels, heading=heading, label=f"{choice} {value}")


VARIANTS = [
    variant("baseline", "paper"),
    variant("half_track", "worse"),  # C1 contradicted at both noisy levels: flipped
    variant("output_gain", "tied"),  # C1 not shown: changed at 0.1, in the spread at 0.2
    variant("control_period", "borderline"),  # C1 at 0.1 holds, unsettled
    variant("heading_integrals", "measured", heading="measured"),  # true worse, measured good
    variant("noise_reading", "3.16", levels=(0.3,)),  # compared at the reference 0.1
    variant("half_track x output_gain", "worse x tied"),  # factorial: flipped
]
ROWS = [
    rows(good, measured=0.02),  # judged on the true heading: the measured one is worse
    rows(worse, seed=1),
    rows(tied, seed=2, noisy=0.02),
    rows(lambda t, s: 0.01 * (1 - 0.004) if s == 0.1 else good(t, s), seed=5, noisy=0.01),
    rows(worse, seed=3, measured=GOOD["IT2FLC FoU 0.2"]),
    rows(good, levels=(0.3,), seed=4),
    rows(worse, seed=6),
]
#: Batch 1 ties at 0.2 (C1 not shown there); batch 2 is good throughout.
BATCHES = [rows(lambda t, s: GOOD["FLC"] if s == 0.2 else good(t, s), seed=7, noisy=0.02),
           rows(good, seed=8)]


@pytest.fixture  # (per test: mutmut picks the tests of a function by the calls each makes)
def result():
    return judge_variants(VARIANTS, ROWS, config=CONFIG, fous=FOUS, main_fou=0.2,
                          trajectories=TRAJ, reference_sigma=0.1, baseline_batches=BATCHES,
                          resamples=200, seed=3)


def verdict(result, claim, choice):
    return next(v for v in result.verdicts if v["claim"] == claim and v["choice"] == choice)


def test_the_first_variant_must_be_the_baseline():
    for variants in ([], VARIANTS[1:2]):
        with pytest.raises(ValueError) as info:
            judge_variants(variants, ROWS[1:2], config=CONFIG, fous=FOUS, main_fou=0.2,
                           trajectories=TRAJ, reference_sigma=0.1)
        assert str(info.value) == "judge_variants: the first variant must be the baseline"


def test_each_level_is_called_against_the_baselines_spread(result):
    # C1 level by level (sigma 0, 0.1, 0.2): the spread at 0.2 is "holds 2, not shown 1"
    # (batch 1 ties there); the noise-free level is deterministic everywhere.
    expect = {
        "baseline": ("deterministic;holds;holds", "yes;yes;yes",
                     "unchanged;unchanged;unchanged", "baseline", "baseline"),
        "half_track": ("deterministic;contradicted;contradicted", "yes;yes;yes",
                       "unchanged;flipped;flipped", "flipped", "one-at-a-time"),
        "output_gain": ("deterministic;not shown;not shown", "yes;yes;no",
                        "unchanged;changed;unsettled", "changed", "one-at-a-time"),
        "control_period": ("deterministic;holds;holds", "yes;no;yes",
                           "unchanged;unsettled;unchanged", "unsettled", "one-at-a-time"),
        # judged on the measured heading's integrals (the true ones are worse)
        "heading_integrals": ("deterministic;holds;holds", "yes;yes;yes",
                              "unchanged;unchanged;unchanged", "unchanged", "one-at-a-time"),
        "half_track x output_gain": ("deterministic;contradicted;contradicted", "yes;yes;yes",
                                     "unchanged;flipped;flipped", "flipped", "factorial"),
    }
    for choice, (status, settled, levels, change, part) in expect.items():
        v = verdict(result, "C1", choice)
        assert (v["status"], v["settled"], v["level_change"], v["change"], v["part"]) == (
            status, settled, levels, change, part), choice
        assert v["noise_levels"] == "0, 0.1, 0.2"
        assert v["baseline_spread"] == "deterministic 3;holds 3;holds 2, not shown 1"
    tied = verdict(result, "C1", "output_gain")
    assert (tied["value"], tied["label"], tied["verdict"]) == ("tied", "output_gain tied",
                                                                "not shown")
    assert tied["per_trajectory"] == "straight: unsettled;curved: unsettled"
    c1 = next(c for c in result.claims[2] if c.id == "C1")
    assert tied["replication"] == ";".join(f"{c1.replication[('all', s)]:.3f}"
                                            for s in (0.0, 0.1, 0.2))
    assert tied["replication"].startswith("1.000;0.9")
    assert verdict(result, "C1", "half_track")["per_trajectory"] == (
        "straight: does not hold;curved: does not hold")
    # a variant judged at another level (a noise reading) is compared at the reference 0.1
    reading = verdict(result, "C1", "noise_reading")
    assert (reading["noise_levels"], reading["status"], reading["baseline_spread"],
            reading["level_change"]) == ("0.3", "holds", "holds 3", "unchanged")


def test_claims_not_evaluated_are_left_out(result):
    # no T1 baselines in the rows: D1, D2, D3 are "not evaluated" and have no rows
    assert [c.id for c in result.claims[0]] == ["C1", "C2", "C3", "D1", "D2", "D3"]
    assert {v["claim"] for v in result.verdicts} == {"C1", "C2", "C3"}
    assert {c["claim"] for c in result.cells} == {"C1", "C2", "C3"}
    assert set(result.flips) == {"C1", "C2", "C3"}
    assert len(result.verdicts) == 3 * len(VARIANTS)
    assert len(result.cells) == sum(len(c.evidence) for claims in result.claims
                                    for c in claims)


def test_flips_list_every_non_baseline_variant_under_its_change(result):
    assert result.flips["C1"] == {
        "unchanged": ["heading_integrals measured", "noise_reading 3.16"],
        "changed": ["output_gain tied"],
        "flipped": ["half_track worse", "half_track x output_gain worse x tied"],
        "unsettled": ["control_period borderline"]}
    assert result.flips["C3"]["unchanged"] == [v.label for v in VARIANTS[1:]]


def test_choices_are_ranked_by_what_their_one_at_a_time_variants_move(result):
    # half_track: C1 flips at 0.1 and 0.2, C2 at 0.1; output_gain: C1 changes at 0.1,
    # C2 flips at 0.1; control_period: C2 flips at 0.1. The factorial cell does not count;
    # ties keep the order of the choices.
    assert result.ranking == [
        {"choice": "half_track", "flipped": 3, "changed": 0, "score": 6},
        {"choice": "output_gain", "flipped": 1, "changed": 1, "score": 3},
        {"choice": "control_period", "flipped": 1, "changed": 0, "score": 2},
        {"choice": "noise_reading", "flipped": 0, "changed": 0, "score": 0},
        {"choice": "heading_integrals", "flipped": 0, "changed": 0, "score": 0}]


def _replication(rows, resamples):
    defs = claim_definitions(fous=FOUS, main_fou=0.2, trajectories=TRAJ,
                             available=sorted(set(rows["controller"])))
    results = evaluate_claims(rows, fous=FOUS, main_fou=0.2, trajectories=TRAJ,
                              experiment="robustness", claims=defs)
    out = replicate_claims(rows, defs, results, experiment="robustness", resamples=resamples,
                           seed=3, target=0.95)
    return {c.id: c for c in out}


def test_the_spread_table_of_the_baselines_batches(result):
    c1 = [r for r in result.spread if r["claim"] == "C1"]
    # the noise-free level has no spread row
    assert [r["sigma"] for r in result.spread] == [0.1, 0.2] * 3
    assert c1[0] == {"claim": "C1", "sigma": 0.1, "batches": 3, "spread": "holds 3",
                     "statuses": ["holds"] * 3, "agreement": 1.0, "replication_mean": 1.0}
    row = c1[1]
    assert (row["batches"], row["spread"], row["statuses"]) == (
        3, "holds 2, not shown 1", ["holds", "not shown", "holds"])
    assert row["agreement"] == 1 / 3  # 1 of the 3 pairs agree
    # batch 0 with the variants' 200 resamples, the others with max(100, 200 // 5)
    reps = [_replication(ROWS[0], 200), *(_replication(b, 100) for b in BATCHES)]
    expect = [r["C1"].replication[("all", 0.2)] for r in reps]
    assert row["replication_mean"] == float(np.mean(expect))
    assert expect[1] < 1.0  # (the tied batch's resamples matter)
    assert (result.target, result.seeds_per_batch, result.config) == (0.95, 10, CONFIG)
    assert result.variants == VARIANTS and len(result.claims) == len(VARIANTS)


def test_cells_carry_the_trajectory_and_level_status(result):
    def cells(claim, choice, sigma):
        return [c for c in result.cells if c["claim"] == claim and c["choice"] == choice
                and c["sigma"] == sigma]

    det = cells("C1", "baseline", 0.0)
    assert len(det) == 2 * 4  # trajectories x metrics
    assert {(c["verdict"], c["level_verdict"], c["outcome"], c["change"]) for c in det} == {
        ("deterministic", "deterministic", "deterministic", "unchanged")}
    worse = cells("C1", "half_track", 0.1)
    assert {(c["verdict"], c["level_verdict"], c["change"], c["settled"], c["replication"],
             c["baseline_spread"]) for c in worse} == {
        ("contradicted", "contradicted", "flipped", True, 1.0, "holds 3")}
    assert [c["metric"] for c in worse] == ["IAE", "ITAE", "ISE", "ITSE"] * 2
    assert [c["trajectory"] for c in worse] == ["straight"] * 4 + ["curved"] * 4
    c = worse[0]
    assert (c["value"], c["label"], c["comparison"], c["n"]) == (
        "worse", "half_track worse", "IT2FLC FoU 0.2 - FLC", 10)
    c1 = next(x for x in result.claims[1] if x.id == "C1")
    e = next(x for x in c1.evidence if x["sigma"] == 0.1)
    assert (c["estimate"], c["ci_low"], c["ci_high"], c["p_holm"], c["outcome"]) == (
        e["diff_mean"], e["ci_low"], e["ci_high"], e["p_holm"], e["outcome"])
    tied = cells("C1", "output_gain", 0.1)
    assert {(x["verdict"], x["change"], x["settled"]) for x in tied} == {
        ("not shown", "changed", True)}
    measured = cells("C1", "heading_integrals", 0.1)
    assert [x["metric"] for x in measured[:4]] == ["IAE_meas", "ITAE_meas", "ISE_meas",
                                                   "ITSE_meas"]
    assert {x["verdict"] for x in measured} == {"holds"}
    band = cells("C3", "baseline", 0.1)
    assert len(band) == 1
    b = band[0]
    c3 = next(x for x in result.claims[0] if x.id == "C3")
    e3 = next(x for x in c3.evidence if x["sigma"] == 0.1)
    assert (b["trajectory"], b["metric"], b["comparison"], b["estimate"], b["n"],
            b["verdict"]) == ("straight", "ISE", "smallest mean (IT2FLC FoU 0.3) vs band",
                              e3["mean ISE"], 10, "holds")
    assert b["estimate"] == pytest.approx(0.003, rel=0.05)


def test_the_target_settles_levels():
    loose = judge_variants(VARIANTS[:4], ROWS[:4], config=CONFIG, fous=FOUS, main_fou=0.2,
                           trajectories=TRAJ, reference_sigma=0.1, baseline_batches=BATCHES,
                           resamples=200, seed=3, target=0.5)
    v = verdict(loose, "C1", "control_period")
    assert (v["settled"], v["level_change"], v["change"]) == (
        "yes;yes;yes", "unchanged;unchanged;unchanged", "unchanged")
    assert loose.target == 0.5


def _judge(variants, data, **kw):
    kw = {"config": CONFIG, "fous": FOUS, "main_fou": 0.2, "trajectories": TRAJ,
          "reference_sigma": 0.1, "resamples": 200, "seed": 3, **kw}
    return judge_variants(variants, data, **kw)


def test_every_variant_needs_its_rows():
    for n_rows in (2, 4):  # fewer rows than variants, or more
        with pytest.raises(ValueError):
            _judge(VARIANTS[:3], ROWS[:n_rows])


def test_an_empty_spread_is_refused():
    from it2track.experiments.robustness import level_change

    with pytest.raises(ValueError) as info:
        level_change("holds", True, [])
    assert str(info.value) == "level_change: the baseline spread is empty"


def test_the_baseline_alone():
    alone = _judge(VARIANTS[:1], ROWS[:1])
    assert alone.flips == {c: {"unchanged": [], "changed": [], "flipped": [], "unsettled": []}
                           for c in ("C1", "C2", "C3")}
    assert alone.ranking == []
    # one batch: no pair to disagree
    assert [(r["claim"], r["sigma"], r["batches"], r["agreement"]) for r in alone.spread] == [
        (c, s, 1, 1.0) for c in ("C1", "C2", "C3") for s in (0.1, 0.2)]
    assert [v["change"] for v in alone.verdicts] == ["baseline"] * 3


def test_a_claim_a_variant_cannot_judge_skips_only_itself():
    # the baseline has the dead-zone-matched FLC (D2), the variant it and no slope-matched
    # one: D1 is not evaluated for either, D2 after it still is
    dz = {"T1 dead-zone-matched 0.2": 0.007}
    out = _judge(VARIANTS[:2], [rows(good, extra=dz), rows(worse, seed=1, extra=dz)])
    assert [(v["claim"], v["choice"]) for v in out.verdicts] == [
        (c, v) for v in ("baseline", "half_track") for c in ("C1", "C2", "C3", "D2")]
    assert set(out.flips) == {"C1", "C2", "C3", "D2"}
    assert out.flips["D2"]["flipped"] == ["half_track worse"]


def test_the_baselines_batches_are_judged_on_its_heading():
    # a study that judges the measured heading: its batches too (their true heading is worse)
    base = variant("baseline", "paper", heading="measured")
    batch = rows(worse, seed=8, measured=GOOD["IT2FLC FoU 0.2"])
    out = _judge([base, VARIANTS[1]], [rows(worse, measured=GOOD["IT2FLC FoU 0.2"]),
                                       ROWS[1]], baseline_batches=[batch])
    assert {r["spread"] for r in out.spread if r["claim"] == "C1"} == {"holds 2"}


def test_the_other_batches_take_a_fifth_of_the_resamples_when_more_than_100():
    out = _judge(VARIANTS[:1], ROWS[:1], baseline_batches=BATCHES[:1], resamples=600)
    row = next(r for r in out.spread if r["claim"] == "C1" and r["sigma"] == 0.2)
    expect = [_replication(ROWS[0], 600), _replication(BATCHES[0], 120)]
    assert row["replication_mean"] == float(np.mean([r["C1"].replication[("all", 0.2)]
                                                      for r in expect]))


def test_the_bootstrap_defaults():
    few = [VARIANTS[0], VARIANTS[3]]
    data = [ROWS[0], ROWS[3]]
    kw = {"config": CONFIG, "fous": FOUS, "main_fou": 0.2, "trajectories": TRAJ,
          "reference_sigma": 0.1}
    default = judge_variants(few, data, **kw)
    explicit = judge_variants(few, data, resamples=1000, seed=0, target=0.95, **kw)
    assert default.verdicts == explicit.verdicts and default.target == 0.95
    other = judge_variants(few, data, resamples=1000, seed=1, **kw)
    fewer = judge_variants(few, data, resamples=999, seed=0, **kw)
    rep = verdict(default, "C1", "control_period")["replication"]
    assert rep != verdict(other, "C1", "control_period")["replication"]
    assert rep != verdict(fewer, "C1", "control_period")["replication"]


def test_each_cell_carries_its_own_trajectorys_status():
    # worse on the curved path only: C1 contradicted there, holding on the straight one
    split = rows(lambda t, s: good(t, s) if t == "straight" else worse(t, s), seed=1)
    out = _judge(VARIANTS[:2], [ROWS[0], split])
    cells = [c for c in out.cells if c["claim"] == "C1" and c["choice"] == "half_track"
             and c["sigma"] == 0.1]
    assert {(c["trajectory"], c["verdict"], c["level_verdict"]) for c in cells} == {
        ("straight", "holds", "contradicted"), ("curved", "contradicted", "contradicted")}


def test_a_flip_weighs_twice_a_change():
    # baseline: the FLC ties the IT2FLC (C1 not shown). control_period restores the FLC:
    # C1 holds at both levels, 2 changes (score 2); output_gain, later in the choices'
    # order, makes FoU 0.3 worse at 0.1 only: C2 flips there (score 2 x 1). A tie: the
    # choices' order decides.
    tie = {"FLC": GOOD["IT2FLC FoU 0.2"]}
    wide = {**tie, "IT2FLC FoU 0.3": lambda t, s: 0.02 if s == 0.1 else 0.003}
    out = _judge([VARIANTS[0], variant("control_period", "x"), variant("output_gain", "y")],
                 [rows(good, extra=tie), rows(good, seed=1), rows(good, seed=2, extra=wide)])
    assert out.ranking == [
        {"choice": "control_period", "flipped": 0, "changed": 2, "score": 2},
        {"choice": "output_gain", "flipped": 1, "changed": 0, "score": 2}]

"""The robustness experiment's configuration: checks at their boundaries, messages to the
letter, the ``[robustness]`` table and the variants it implies (robustness_config.py)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from it2track.experiments.choices import DEFAULT_CHOICES, Choice
from it2track.experiments.robustness_config import (
    RobustnessConfig,
    check_defaults,
    check_factor_levels,
    rebase,
    robustness_config_from_table,
    robustness_variants,
)
from it2track.experiments.sensitivity import SensitivityConfig, SensitivityFactor
from it2track.experiments.specs import ConfigError, Table
from it2track.tracking import LoopConfig

BY_NAME = {c.name: c for c in DEFAULT_CHOICES}
HALF, PERIOD, GAIN, TIMING = (BY_NAME[n] for n in ("half_track", "control_period",
                                                    "output_gain", "heading_timing"))


def _error(**kw) -> str:
    with pytest.raises(ValueError) as info:
        RobustnessConfig(**kw)
    return str(info.value)


# -- RobustnessConfig ------------------------------------------------------------------------


@pytest.mark.parametrize("levels", [(), (0.0,), (0.1, -0.1), (math.nan,), (math.inf,),
                                    (0.1, math.nan)])
def test_noise_levels_must_be_finite_and_positive(levels):
    assert _error(noise_levels=levels) == (
        f"robustness noise_levels={list(levels)!r} must be noise levels > 0")


def test_the_smallest_positive_noise_level_is_accepted():
    assert RobustnessConfig(noise_levels=(5e-324,)).noise_levels == (5e-324,)


def test_a_noise_level_listed_twice_is_refused():
    assert _error(noise_levels=(0.1, 0.2, 0.1)) == (
        "robustness noise_levels=[0.1, 0.2, 0.1] lists a level twice")


@pytest.mark.parametrize("seeds", [1, 0, True, 2.0])
def test_seeds_must_be_an_integer_of_at_least_two(seeds):
    assert _error(seeds=seeds) == (f"robustness seeds={seeds!r} must be an integer >= 2 (a "
                                   "single realisation shows nothing)")


def test_two_seeds_and_two_baseline_batches_are_enough():
    rob = RobustnessConfig(seeds=2, baseline_batches=2)
    assert (rob.seeds, rob.baseline_batches) == (2, 2)


def test_the_factorial_names_choices():
    msg = _error(choices=(HALF, TIMING), factorial=("half_track", "nope"), factorial_levels=())
    assert msg == ("robustness factorial names 'nope', not a choice; choices: "
                   "['half_track', 'heading_timing']")


@pytest.mark.parametrize("factorial", [("half_track",), ("half_track", "half_track"),
                                       ("half_track", "heading_timing", "half_track")])
def test_the_factorial_crosses_none_or_two_distinct_choices(factorial):
    msg = _error(choices=(HALF, TIMING), factorial=factorial, factorial_levels=())
    assert msg == (f"robustness factorial={list(factorial)!r} needs none or at least two "
                   "distinct choices")


def test_no_factorial_and_a_factorial_of_two_are_accepted():
    assert RobustnessConfig(factorial=(), factorial_levels=()).factorial == ()
    two = RobustnessConfig(choices=(HALF, TIMING), factorial=("half_track", "heading_timing"),
                           factorial_levels=())
    assert two.factorial == ("half_track", "heading_timing")


@pytest.mark.parametrize("batches", [1, 0, True, 2.0])
def test_baseline_batches_must_be_an_integer_of_at_least_two(batches):
    assert _error(baseline_batches=batches) == (
        f"robustness baseline_batches={batches!r} must be an integer >= 2 (a spread needs "
        "two independent batches)")


def test_factorial_levels_name_a_choice_once_with_tuples_of_values():
    twice = (("half_track", ((0.28,),)), ("half_track", ((0.056,),)))
    assert _error(factorial_levels=twice) == (
        "robustness factorial_levels names 'half_track' twice")
    for alts in ((), ([0.28],), ((0.28,), 0.056)):
        assert _error(factorial_levels=(("half_track", alts),)) == (
            "robustness factorial_levels 'half_track': needs a non-empty tuple of "
            "alternatives (each a tuple of path values)")


def test_factorial_values_are_the_default_then_the_listed_alternatives():
    rob = RobustnessConfig()
    assert rob.factorial_values(HALF) == ((5.6,), (0.28,))
    assert rob.factorial_values(PERIOD) == ((0.01, 100.0), (0.001, 1000.0))
    # not listed: every alternative, in the choice's order
    assert rob.factorial_values(GAIN) == ((1.0,), (0.5,), (2.0,))
    # listed out of order: the choice's order still
    both = RobustnessConfig(factorial_levels=(("half_track", ((0.056,), (0.28,))),))
    assert both.factorial_values(HALF) == ((5.6,), (0.28,), (0.056,))


def test_to_dict_is_every_setting_as_plain_data():
    sens = SensitivityConfig(factors=(SensitivityFactor(
        name="ke", path="controllers.ke", levels=(0.5, 2.0)),), trajectories=2, seeds=3, seed=4)
    rob = RobustnessConfig(choices=(HALF, PERIOD), noise_levels=(0.1, 0.2), seeds=3,
                           factorial=("half_track", "control_period"),
                           factorial_levels=(("control_period", ((0.005, 100.0),
                                                                 (0.001, 1000.0))),),
                           baseline_batches=5, sensitivity=sens)
    assert rob.to_dict() == {
        "noise_levels": [0.1, 0.2], "seeds": 3, "factorial": ["half_track", "control_period"],
        "factorial_levels": {"control_period": [[0.005, 100.0], [0.001, 1000.0]]},
        "baseline_batches": 5,
        "sensitivity": {"trajectories": 2, "seeds": 3, "seed": 4,
                        "factors": [{"name": "ke", "path": "controllers.ke",
                                     "levels": [0.5, 2.0]}]},
        "choices": [HALF.to_dict(), PERIOD.to_dict()]}
    assert replace(rob, sensitivity=None).to_dict()["sensitivity"] is None


# -- [robustness] ------------------------------------------------------------------------------


def _table(data, choices=DEFAULT_CHOICES):
    return robustness_config_from_table(Table(data, "s.toml", section="robustness"), choices)


def test_an_empty_table_is_the_default_configuration():
    assert _table({}) == RobustnessConfig()


def test_every_key_of_the_table_is_read():
    rob = _table({"noise_levels": [0.1, 0.3], "seeds": 5, "baseline_batches": 3,
                  "factorial": ["half_track", "output_gain"],
                  "factorial_levels": {"output_gain": [2.0]},
                  "sensitivity": {"trajectories": 3, "seeds": 4, "seed": 7,
                                  "factors": [{"name": "ke", "path": "controllers.ke",
                                               "levels": [0.5, 2.0]}]}})
    assert rob == RobustnessConfig(
        noise_levels=(0.1, 0.3), seeds=5, baseline_batches=3,
        factorial=("half_track", "output_gain"), factorial_levels=(("output_gain", ((2.0,),)),),
        sensitivity=SensitivityConfig(factors=(SensitivityFactor(
            name="ke", path="controllers.ke", levels=(0.5, 2.0)),), trajectories=3, seeds=4,
            seed=7))


def test_a_given_factorial_drops_the_default_levels():
    rob = _table({"factorial": ["half_track", "control_period"]})
    assert rob.factorial_levels == ()
    assert rob.factorial_values(HALF) == ((5.6,), (0.28,), (0.056,))


def test_without_the_default_crossing_the_factorial_is_off():
    # the user's choices lack output_gain: no default factorial, no default levels
    rob = _table({}, choices=(HALF, PERIOD))
    assert (rob.factorial, rob.factorial_levels) == ((), ())


def test_the_default_levels_are_kept_only_where_they_are_alternatives():
    half = replace(HALF, alternatives=((0.056,),))  # 0.28 no longer an alternative
    rob = _table({}, choices=(half, PERIOD, GAIN))
    assert rob.factorial == ("half_track", "control_period", "output_gain")
    assert rob.factorial_levels == (("control_period", ((0.001, 1000.0),)),)


def test_sensitivity_analysis_false_drops_the_screening():
    assert _table({"sensitivity_analysis": False}).sensitivity is None
    assert _table({"sensitivity_analysis": True}).sensitivity == SensitivityConfig()
    with pytest.raises(ConfigError) as info:
        _table({"sensitivity_analysis": False, "sensitivity": {"seeds": 3}})
    assert str(info.value) == "s.toml [robustness.sensitivity]: unknown key(s) ['seeds']"


@pytest.mark.parametrize(("data", "message"), [
    ({"factorial_levels": {"tuning": [True]}},
     "s.toml [robustness.factorial_levels]: 'tuning' is not crossed in the factorial "
     "['half_track', 'control_period', 'output_gain']"),
    ({"factorial_levels": {"half_track": []}},
     "s.toml [robustness.factorial_levels]: half_track = [] needs at least one alternative"),
    ({"factorial_levels": {"half_track": [0.28, 0.3]}},
     "s.toml [robustness.factorial_levels]: half_track[1] = [0.3] is not one of the choice's "
     "alternatives ['[0.28]', '[0.056]']"),
    ({"factorial_levels": {"control_period": [0.001]}},
     "s.toml [robustness.factorial_levels]: control_period[0]=0.001 must be a list of 2 "
     "values, one per path ['simulation.ts', 'simulation.noise_rate']"),
    ({"sensitivity": {"factors": [{"name": "x", "path": "metrics.heading",
                                   "levels": [0.0, 1.0]}]}},
     "s.toml [robustness.sensitivity].factors #1: factor 'x': 'metrics.heading' is not "
     "continuous"),
    ({"sensitivity": {"factors": [{"name": "x", "path": "controllers.ke",
                                   "levels": [1.0, 2.0], "unit": 1}]}},
     "s.toml [robustness.sensitivity].factors #1: unknown key(s) ['unit']"),
    ({"sensitivity": {"trajectories": 1}},
     "s.toml [robustness.sensitivity]: sensitivity trajectories=1 must be an integer >= 2"),
    ({"seeds": 1}, "s.toml [robustness]: robustness seeds=1 must be an integer >= 2 (a single "
     "realisation shows nothing)"),
    ({"colour": 1}, "s.toml [robustness]: unknown key(s) ['colour']"),
    ({"factorial_levels": {"half_track": [0.28], "x": 1}},
     "s.toml [robustness.factorial_levels]: 'x' is not crossed in the factorial "
     "['half_track', 'control_period', 'output_gain']"),
])
def test_bad_tables_name_the_section_key_and_value(data, message):
    with pytest.raises(ConfigError) as info:
        _table(data)
    assert str(info.value) == message


def test_a_factorial_levels_name_must_also_be_a_choice():
    # crossed by name but not a choice: refused by the table reader, naming the factorial
    # (RobustnessConfig would refuse the factorial itself later)
    with pytest.raises(ConfigError) as info:
        _table({"factorial": ["half_track", "ghost"], "factorial_levels": {"ghost": [1.0]}},
               choices=(HALF, PERIOD))
    assert str(info.value) == ("s.toml [robustness.factorial_levels]: 'ghost' is not crossed "
                               "in the factorial ['half_track', 'ghost']")


# -- defaults, rebasing, screening levels ------------------------------------------------------


def test_check_defaults_names_the_choice_path_and_both_values():
    robot = replace(LoopConfig().robot, half_track=0.3)
    loop = LoopConfig(robot=robot)
    check_defaults((PERIOD, GAIN), loop, "x.toml")  # both at the loop's own settings
    with pytest.raises(ConfigError) as info:
        check_defaults((PERIOD, HALF), loop, "x.toml")
    assert str(info.value) == ("x.toml [[choices]] 'half_track': default robot.half_track = "
                               "5.6 but the study runs 0.3; the default must be the study's "
                               "own setting")
    slow = LoopConfig(noise_rate=200.0)
    with pytest.raises(ConfigError, match=r"'control_period': default simulation.noise_rate "
                                          r"= 100 but the study runs 200"):
        check_defaults((PERIOD,), slow, "x.toml")


def test_rebase_moves_the_former_default_among_the_alternatives():
    robot = replace(LoopConfig().robot, half_track=0.28)
    out = rebase((HALF, GAIN), LoopConfig(robot=robot))
    assert out[0] == replace(HALF, default=(0.28,), alternatives=((5.6,), (0.056,)))
    assert out[1] is GAIN  # already the loop's own
    other = rebase((HALF,), LoopConfig(robot=replace(robot, half_track=0.5)))
    assert other[0].default == (0.5,)
    assert other[0].alternatives == ((5.6,), (0.28,), (0.056,))


def test_check_factor_levels_tries_every_combination_of_loop_levels():
    ok = SensitivityConfig(factors=(
        SensitivityFactor(name="half_track", path="robot.half_track", levels=(0.056, 5.6)),
        SensitivityFactor(name="ke", path="controllers.ke", levels=(0.5, 2.0))))
    check_factor_levels(ok, LoopConfig())
    # 2.5 s of a 2 s run: the window's start is past the end at that level only
    bad = SensitivityConfig(factors=(
        SensitivityFactor(name="half_track", path="robot.half_track", levels=(0.056, 5.6)),
        SensitivityFactor(name="metric_start", path="simulation.metric_start",
                          levels=(0.0, 2.5))))
    with pytest.raises(ValueError) as info:
        check_factor_levels(bad, LoopConfig(duration=2.0))
    assert "choice sensitivity = half_track=0.056, metric_start=2.5" in str(info.value)


# -- variants ----------------------------------------------------------------------------------


def test_variants_of_a_two_by_three_factorial():
    rob = RobustnessConfig(choices=(HALF, GAIN), noise_levels=(0.1,),
                           factorial=("half_track", "output_gain"),
                           factorial_levels=(("half_track", ((0.28,),)),), sensitivity=None)
    variants = robustness_variants(rob, LoopConfig())
    assert [(v.choice, v.value) for v in variants] == [
        ("baseline", "paper"), ("half_track", "0.28"), ("half_track", "0.056"),
        ("output_gain", "0.5"), ("output_gain", "2"),
        ("half_track x output_gain", "0.28 x 0.5"), ("half_track x output_gain", "0.28 x 2")]
    assert all(v.noise_levels == (0.1,) for v in variants)
    assert variants[1].label == "l = 0.28 m"
    assert variants[5].label == "l = 0.28 m, output gain 0.5"
    assert (variants[6].loop.robot.half_track, variants[6].output_gain) == (0.28, 2.0)
    assert variants[0].loop == LoopConfig() and variants[0].output_gain == 1.0


def test_no_factorial_gives_only_the_baseline_and_one_at_a_time():
    rob = RobustnessConfig(choices=(HALF,), factorial=(), factorial_levels=(),
                           sensitivity=None)
    assert [v.value for v in robustness_variants(rob, LoopConfig())] == ["paper", "0.28",
                                                                        "0.056"]


def test_a_choice_of_two_paths_takes_both_in_the_factorial():
    period = Choice(name="p", sets=("simulation.ts", "simulation.noise_rate"),
                    default=(0.01, 100.0), alternatives=((0.005, 200.0),))
    rob = RobustnessConfig(choices=(HALF, period), factorial=("half_track", "p"),
                           factorial_levels=(), sensitivity=None)
    last = robustness_variants(rob, LoopConfig())[-1]
    assert last.choice == "half_track x p"
    assert (last.loop.robot.half_track, last.loop.ts, last.loop.noise_rate) == (0.056, 0.005,
                                                                                200.0)


def test_a_factorial_label_names_each_moved_choice_in_its_own_words():
    # the period keeps the noise rate at its default: the choice still says "noise at
    # 100 Hz" (the loop's own description would drop it); a choice at its default is not
    # named
    rob = RobustnessConfig(choices=(HALF, PERIOD, GAIN), sensitivity=None,
                           factorial=("half_track", "control_period", "output_gain"),
                           factorial_levels=(("half_track", ((0.28,),)),
                                             ("control_period", ((0.001, 100.0),)),
                                             ("output_gain", ((2.0,),))))
    fact = [v for v in robustness_variants(rob, LoopConfig()) if " x " in v.choice]
    assert [(v.value, v.label) for v in fact] == [
        ("5.6 x ts=0.001 noise_rate=100 x 2", "Ts = 1 ms, noise at 100 Hz, output gain 2"),
        ("0.28 x ts=0.01 noise_rate=100 x 2", "l = 0.28 m, output gain 2"),
        ("0.28 x ts=0.001 noise_rate=100 x 1", "l = 0.28 m, Ts = 1 ms, noise at 100 Hz"),
        ("0.28 x ts=0.001 noise_rate=100 x 2",
         "l = 0.28 m, Ts = 1 ms, noise at 100 Hz, output gain 2")]


def test_the_morris_design_is_drawn_once_per_configuration_and_handed_out_as_copies() -> None:
    """The study sizes its progress bar with the design, then runs it: one SALib draw, the
    same numbers both times, and a caller's edit of its copy never reaches the next caller."""
    from it2track.experiments import sensitivity

    sens = SensitivityConfig()
    sensitivity._morris_design.cache_clear()
    x1, points1 = sensitivity.morris_design(sens)
    x2, points2 = sensitivity.morris_design(sens)
    assert sensitivity._morris_design.cache_info().misses == 1
    assert np.array_equal(x1, x2) and points1 == points2
    x1[0, 0] = -1.0
    points1[0].clear()
    x3, points3 = sensitivity.morris_design(sens)
    assert np.array_equal(x3, x2) and points3 == points2
    assert x2.shape == (sens.trajectories * (len(sens.factors) + 1), len(sens.factors))

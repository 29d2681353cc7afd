"""experiments/choices.py at its boundaries: every parser's accepted and refused values (zero,
the smallest positive number, NaN/inf, bools, wrong lengths), every message to the letter, the
labels and plain forms a table and a JSON record show, and what a variant records as changed.

Written from the cases a mutation test of the module found unpinned (docs/guide/mutation.md);
all pure Python, no simulation.
"""

import math
import re

import pytest

from it2track.experiments.choices import (
    DEFAULT_CHOICES,
    PATHS,
    Choice,
    apply_settings,
    baseline_value,
    choices_from_list,
    format_value,
)
from it2track.experiments.specs import ConfigError
from it2track.tracking import LoopConfig

TINY = 5e-324  # the smallest positive float


def exactly(message):
    return f"^{re.escape(message)}$"


@pytest.mark.parametrize("path", ["robot.half_track", "simulation.ts", "simulation.noise_rate",
                                  "controllers.ke"])
@pytest.mark.parametrize("value", [0, 0.0, -0.0, -1.0, -TINY, math.nan, math.inf, -math.inf,
                                   True, False, "1", None, [1.0]])
def test_positive_numbers_refuse_zero_negatives_non_finite_and_non_numbers(path, value):
    with pytest.raises(ConfigError, match=exactly(f"w={value!r} must be a finite number > 0")):
        PATHS[path](value, "w")


@pytest.mark.parametrize("path", ["simulation.metric_start", "controllers.kde"])
@pytest.mark.parametrize("value", [-TINY, -1.0, math.nan, math.inf, True, "0"])
def test_non_negative_numbers_refuse_negatives_and_non_numbers(path, value):
    with pytest.raises(ConfigError, match=exactly(f"w={value!r} must be a finite number >= 0")):
        PATHS[path](value, "w")


def test_numbers_accept_their_boundaries_as_floats():
    for value, want in ((TINY, TINY), (0.5, 0.5), (1, 1.0), (1e300, 1e300)):
        got = PATHS["robot.half_track"](value, "w")
        assert got == want and type(got) is float
    for value in (0, 0.0, TINY):
        got = PATHS["simulation.metric_start"](value, "w")
        assert got == value and type(got) is float


def test_words_accept_only_their_words():
    heading = PATHS["metrics.heading"]
    assert heading("true", "w") == "true" and heading("measured", "w") == "measured"
    for bad in ("True", "other", "", True, 1, None):
        with pytest.raises(ConfigError, match=exactly(
                f"w={bad!r} must be one of ['true', 'measured']")):
            heading(bad, "w")
    timing = PATHS["simulation.desired_heading_pose"]
    assert timing("previous", "w") == "previous"
    with pytest.raises(ConfigError, match=exactly(
            "w='next' must be one of ['current', 'previous']")):
        timing("next", "w")


def test_a_pose_is_three_finite_numbers_or_on_path():
    pose = PATHS["simulation.start_pose"]
    assert pose("on_path", "w") == "on_path"
    got = pose([1, -2, 0.5], "w")
    assert got == (1.0, -2.0, 0.5) and all(type(v) is float for v in got)
    assert pose((0.0, 0.0, 0.0), "w") == (0.0, 0.0, 0.0)
    for bad in ([1.0, 2.0], [1.0, 2.0, 3.0, 4.0], [], [1.0, 2.0, math.nan],
                [1.0, math.inf, 0.0], [1.0, 2.0, True], [1.0, "2", 3.0], "abc", "onpath", 3.0,
                None):
        with pytest.raises(ConfigError, match=exactly(
                f"w={bad!r} must be [x, y, theta] or 'on_path'")):
            pose(bad, "w")


def test_a_noise_sigma_is_sweep_or_a_level_at_least_zero():
    sigma = PATHS["noise.sigma"]
    assert sigma("sweep", "w") == "sweep"
    assert sigma(0, "w") == 0.0 and sigma(0.2, "w") == 0.2
    for bad in (-TINY, math.nan, "sweeps", True):
        with pytest.raises(ConfigError, match=exactly(
                f"w={bad!r} must be 'sweep' or a noise level >= 0, rad")):
            sigma(bad, "w")


def test_a_flag_is_a_bool():
    flag = PATHS["controllers.tuned"]
    assert flag(True, "w") is True and flag(False, "w") is False
    for bad in (1, 0, "true", None):
        with pytest.raises(ConfigError, match=exactly(f"w={bad!r} must be true or false")):
            flag(bad, "w")


@pytest.mark.parametrize(("value", "text"), [
    (True, "true"), (False, "false"), (0.056, "0.056"), (1e-5, "1e-05"), (1000.0, "1000"),
    ((0.0, 0.0, 0.0), "[0, 0, 0]"), ([1.5, True], "[1.5, true]"), ("on_path", "on_path"),
    (3, "3"), ((), "[]")])
def test_format_value(value, text):
    assert format_value(value) == text


def choice(**kw):
    args = {"name": "c", "sets": ("robot.half_track",), "default": (5.6,),
            "alternatives": ((0.28,),)}
    return Choice(**{**args, **kw})


@pytest.mark.parametrize(("kw", "message"), [
    ({"name": ""}, "choice name='' must be letters, digits and _"),
    ({"name": "a-b"}, "choice name='a-b' must be letters, digits and _"),
    ({"name": "a b"}, "choice name='a b' must be letters, digits and _"),
    ({"name": "_"}, "choice name='_' must be letters, digits and _"),
    ({"name": "__"}, "choice name='__' must be letters, digits and _"),
    ({"sets": (), "default": (), "alternatives": ((),)},
     "choice 'c': sets=[] must be distinct paths"),
    ({"sets": ("robot.half_track", "robot.half_track"), "default": (5.6, 5.6),
      "alternatives": ((1.0, 1.0),)},
     "choice 'c': sets=['robot.half_track', 'robot.half_track'] must be distinct paths"),
    ({"sets": ("robot.mass",)},
     f"choice 'c': sets 'robot.mass' is not a known path; known: {sorted(PATHS)}"),
    ({"alternatives": ()}, "choice 'c': needs at least one alternative"),
    ({"alternatives": ((0.28, 1.0),)},
     "choice 'c': value [0.28, 1.0] needs one entry per path ['robot.half_track']"),
    ({"default": ()}, "choice 'c': value [] needs one entry per path ['robot.half_track']"),
    ({"alternatives": ((0.0,),)},
     "choice 'c': robot.half_track=0.0 must be a finite number > 0"),
    ({"alternatives": ((5.6,),)}, "choice 'c': the default and the alternatives must all differ"),
    ({"alternatives": ((0.28,), (0.28,))},
     "choice 'c': the default and the alternatives must all differ"),
])
def test_a_choice_refuses_with_the_reason(kw, message):
    with pytest.raises(ValueError, match=exactly(message)):
        choice(**kw)


def test_a_choice_name_may_use_digits_and_underscores():
    assert choice(name="a_1").name == "a_1"
    assert choice(name="Ab9").name == "Ab9"


def test_settings_and_label_refuse_a_value_of_the_wrong_length():
    two = next(c for c in DEFAULT_CHOICES if c.name == "control_period")
    assert two.settings((0.005, 200.0)) == {"simulation.ts": 0.005,
                                            "simulation.noise_rate": 200.0}
    assert two.label((0.005, 200.0)) == "ts=0.005 noise_rate=200"
    for bad in ((0.005,), (0.005, 200.0, 1.0)):
        with pytest.raises(ValueError):
            two.settings(bad)
        with pytest.raises(ValueError):
            two.label(bad)
    one = choice()
    assert one.label((0.28,)) == "0.28" and one.settings((0.28,)) == {"robot.half_track": 0.28}


def test_to_dict_gives_plain_values_one_path_bare_several_as_lists():
    pose = next(c for c in DEFAULT_CHOICES if c.name == "start_pose")
    assert pose.to_dict() == {
        "name": "start_pose", "sets": ["simulation.start_pose"], "default": [0.0, 0.0, 0.0],
        "alternatives": ["on_path"], "description": pose.description, "doc": "start-pose"}
    period = next(c for c in DEFAULT_CHOICES if c.name == "control_period")
    d = period.to_dict()
    assert (d["sets"], d["default"], d["alternatives"][3]) == (
        ["simulation.ts", "simulation.noise_rate"], [0.01, 100.0], [0.001, 1000.0])
    assert choice(description="why", doc="here").to_dict() == {
        "name": "c", "sets": ["robot.half_track"], "default": 5.6, "alternatives": [0.28],
        "description": "why", "doc": "here"}


def test_default_choices_are_tuples_of_tuples():
    for c in DEFAULT_CHOICES:
        assert type(c.sets) is tuple and type(c.default) is tuple
        assert type(c.alternatives) is tuple and all(type(a) is tuple for a in c.alternatives)
        assert c.description and c.doc
    assert [c.name for c in DEFAULT_CHOICES][:2] == ["half_track", "control_period"]


ENTRY = {"name": "w", "sets": "simulation.metric_start", "default": 0.0, "alternatives": [2.0]}


def test_tables_map_onto_choices_with_optional_description_and_doc():
    (c,) = choices_from_list([ENTRY], "f.toml")
    assert c == Choice(name="w", sets=("simulation.metric_start",), default=(0.0,),
                       alternatives=((2.0,),), description="", doc="")
    (c,) = choices_from_list([{**ENTRY, "description": "d", "doc": "a"}], "f.toml")
    assert (c.description, c.doc) == ("d", "a")
    two = {"name": "p", "sets": ["simulation.ts", "simulation.noise_rate"],
           "default": [0.01, 100.0], "alternatives": [[0.005, 200.0]]}
    (c,) = choices_from_list([two], "f.toml")
    assert c.default == (0.01, 100.0) and c.alternatives == ((0.005, 200.0),)


@pytest.mark.parametrize(("entries", "message"), [
    ({"name": "w"}, "f.toml [[choices]]: must be an array of tables, got {'name': 'w'}"),
    ([ENTRY, {**ENTRY, "sets": "robot.mass"}],
     f"f.toml [[choices]] #2 'w': sets='robot.mass' is not a known path; known: "
     f"{sorted(PATHS)}"),
    ([{**ENTRY, "default": -1.0}],
     "f.toml [[choices]] #1 'w': default (simulation.metric_start)=-1.0 must be a finite "
     "number >= 0"),
    ([{**ENTRY, "alternatives": [2.0, -3.0]}],
     "f.toml [[choices]] #1 'w': alternatives[1] (simulation.metric_start)=-3.0 must be a "
     "finite number >= 0"),
    ([{"name": "p", "sets": ["simulation.ts", "simulation.noise_rate"], "default": 0.01,
       "alternatives": [[0.005, 200.0]]}],
     "f.toml [[choices]] #1 'p': default=0.01 must be a list of 2 values, one per path "
     "['simulation.ts', 'simulation.noise_rate']"),
    ([{"name": "p", "sets": ["simulation.ts", "simulation.noise_rate"],
       "default": [0.01, 100.0], "alternatives": [[0.005]]}],
     "f.toml [[choices]] #1 'p': alternatives[0]=[0.005] must be a list of 2 values, one per "
     "path ['simulation.ts', 'simulation.noise_rate']"),
    ([{"name": "p", "sets": ["simulation.ts", "simulation.noise_rate"],
       "default": [0.01, 100.0], "alternatives": [[0.005, -1.0]]}],
     "f.toml [[choices]] #1 'p': alternatives[0] (simulation.noise_rate)=-1.0 must be a "
     "finite number > 0"),
    ([{**ENTRY, "alternatives": [0.0]}],
     "f.toml [[choices]] #1 'w': choice 'w': the default and the alternatives must all "
     "differ"),
    ([{**ENTRY, "name": "a"}, {**ENTRY, "name": "b"}, {**ENTRY, "name": "b"}],
     "f.toml [[choices]]: name 'b' is used twice"),
])
def test_tables_are_refused_naming_file_entry_key_and_value(entries, message):
    with pytest.raises(ConfigError, match=exactly(message)):
        choices_from_list(entries, "f.toml")


def test_a_bad_key_names_the_entry_by_its_number():
    with pytest.raises(ConfigError, match=r"^f\.toml \[\[choices\]\] #2 'v'"):
        choices_from_list([ENTRY, {**ENTRY, "name": "v", "colour": 1}], "f.toml")
    with pytest.raises(ConfigError, match=r"^f\.toml \[\[choices\]\] #1\b"):
        choices_from_list([{"sets": "robot.half_track"}], "f.toml")


def test_the_baseline_is_the_studys_own_setting_and_unit_untuned_gains():
    loop = LoopConfig()
    want = {"robot.half_track": 5.6, "simulation.ts": 0.01, "simulation.noise_rate": 100.0,
            "simulation.start_pose": (0.0, 0.0, 0.0), "simulation.desired_heading_pose":
            "current", "simulation.metric_start": 0.0, "noise.sigma": "sweep",
            "metrics.heading": "true", "controllers.ke": 1.0, "controllers.kde": 1.0,
            "controllers.output_gain": 1.0, "controllers.tuned": False}
    assert {p: baseline_value(p, loop) for p in PATHS} == want
    for c in DEFAULT_CHOICES:  # every default choice starts from the study's own setting
        assert c.settings(c.default) == {p: want[p] for p in c.sets}


def test_a_variant_records_only_the_paths_moved_off_the_baseline():
    loop = LoopConfig()
    v = apply_settings(loop, (0.1, 0.2), {"controllers.ke": 1.0, "controllers.kde": 2.0,
                                          "controllers.tuned": True, "noise.sigma": "sweep"},
                       choice="g", value="x")
    assert v.settings == (("controllers.kde", 2.0), ("controllers.tuned", True))
    assert (v.ke, v.kde, v.tuned, v.noise_levels, v.loop) == (1.0, 2.0, True, (0.1, 0.2), loop)
    v = apply_settings(loop, (0.1, 0.2), {"noise.sigma": 0.3, "robot.half_track": 0.28},
                       choice="s", value="y")
    assert v.noise_levels == (0.3,) and v.loop.robot.half_track == 0.28
    assert v.settings == (("noise.sigma", 0.3), ("robot.half_track", 0.28))
    assert apply_settings(loop, (0.1,), {}, choice="baseline", value="paper").settings == ()


def test_an_unknown_path_is_refused_by_name():
    with pytest.raises(ValueError, match=exactly("unknown path 'robot2.mass'")):
        apply_settings(LoopConfig(), (0.1,), {"robot2.mass": 1.0}, choice="c", value="v")

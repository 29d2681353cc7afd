"""Point: jFuzzyLogic's input singleton (``MembershipFunctionSingleton.membership``:
``in == value ? valueY : 0``), read from FCL, carried by TOML, refused by the other writers."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from it2track.codegen import check_supported
from it2track.fuzzy import (
    Input,
    IT2Set,
    IT2Sugeno,
    MFKind,
    Point,
    Rule,
    T1Sugeno,
    Triangle,
    kernels,
)
from it2track.io import FisFormatError, UnsupportedFeatureError, dumps, loads
from it2track.io.fcl import loads as fcl_loads
from it2track.io.fcl import loads_terms

V = 0.3  # not a dyadic number: its neighbours are the next floats, not V +- a round step


def test_h_exactly_at_the_value_and_zero_at_the_next_float_either_side() -> None:
    below, above = np.nextafter(V, -math.inf), np.nextafter(V, math.inf)
    x = np.array([V, below, above, 0.1 + 0.2, -V, 0.0, math.inf, -math.inf])
    assert 0.1 + 0.2 != V  # 0.30000000000000004: a rounding of V is not V
    assert Point(V)(x).tolist() == [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    assert Point(V, h=0.25)(x).tolist() == [0.25, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    # the smallest steps: around 0 the next floats are subnormal; -0.0 == 0.0
    tiny = np.nextafter(0.0, 1.0)
    assert Point(0.0)(np.array([0.0, -0.0, tiny, -tiny])).tolist() == [1.0, 1.0, 0.0, 0.0]
    y = Point(V)(V)
    assert type(y) is np.float64 and y == 1.0  # a scalar for a scalar, as every term


def test_nan_is_zero_as_javas_comparison_and_rectangle_give() -> None:
    assert Point(V)(np.array([math.nan, V])).tolist() == [0.0, 1.0]
    assert Point(V)(math.nan) == 0.0


@pytest.mark.parametrize(("args", "message"), [
    ((math.nan,), "Point(value=nan, h=1.0): parameter value=nan must be a finite number"),
    ((math.inf,), "Point(value=inf, h=1.0): parameter value=inf must be a finite number"),
    (("5",), "Point(value='5', h=1.0): parameter value='5' must be a finite number"),
    ((5.0, 0.0), "Point(value=5.0, h=0.0): height h=0.0 must satisfy 0 < h <= 1"),
    ((5.0, 1.5), "Point(value=5.0, h=1.5): height h=1.5 must satisfy 0 < h <= 1"),
    ((5.0, math.nan), "Point(value=5.0, h=nan): parameter h=nan must be a finite number"),
])
def test_bad_parameters_are_refused_naming_them(args, message) -> None:
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        Point(*args)


def test_its_compiled_row_is_a_rectangle_of_zero_width_with_the_same_bits() -> None:
    assert Point(V, 0.5).kernel_row() == (MFKind.RECTANGLE, (V, V, 0.5, 0.0, 0.0))
    fls = T1Sugeno(inputs=[Input("x", (-1.0, 1.0), [("p", Point(V)),
                                                     ("t", Triangle(-1.0, 0.0, 1.0))])],
                   rules=[Rule(["p"], 4.0), Rule(["t"], 2.0)])
    x = np.array([V, np.nextafter(V, 1.0), np.nextafter(V, -1.0), 0.0, -0.5, math.nan])
    with np.errstate(invalid="ignore"):
        ours = [float(fls(v)) for v in x[:-1]]
    # at V: (4 * 1 + 2 * 0.7) / 1.7; beside V the triangle alone
    assert ours[0] == (4.0 + 2.0 * (1.0 - V)) / (2.0 - V)
    assert ours[1:] == [2.0, 2.0, 2.0, 2.0]
    if kernels._entry(fls) is not None:  # numba installed: the kernel gives the same bits
        x64 = x[:-1].reshape(1, -1)
        yl, _ = fls._interval_blocks(fls._prepare((x64[0],))[0])
        assert np.array_equal(np.asarray(fls(x64[0])), yl.ravel())


def test_in_an_interval_set_the_lower_point_is_lower() -> None:
    s = IT2Set(Point(V), Point(V, 0.5), "p")
    fls = IT2Sugeno(inputs=[Input("x", (-1.0, 1.0), [s, IT2Set.type1(Triangle(-1, 0, 1), "t")])],
                    rules=[Rule(["p"], 1.0), Rule(["t"], 0.0)])
    lower, upper = s(np.array([V, 0.0]))
    assert lower.tolist() == [0.5, 0.0] and upper.tolist() == [1.0, 0.0]
    # the point's firing [0.5, 1] against the triangle's 0.7 (1 - V): the ends at 0.5 and 1
    assert fls.interval(V) == (0.5 / (0.5 + 0.7), 1.0 / (1.0 + 0.7))
    assert fls.interval(np.nextafter(V, 1.0)) == (0.0, 0.0)


def system(mf) -> T1Sugeno:
    return T1Sugeno(inputs=[Input("x", (-1.0, 1.0), [("p", mf), ("t", Triangle(-1, 0, 1))])],
                    rules=[Rule(["p"], 1.0), Rule(["t"], 2.0)])


def test_toml_carries_it_bit_exactly() -> None:
    fls = system(Point(V, 0.75))
    text = dumps(fls, "toml")
    assert 'mf = { type = "point", value = 0.3, h = 0.75 }' in text
    again = loads(text, "toml")
    assert again == fls and dumps(again, "toml") == text
    with pytest.raises(Exception, match=re.escape("h=1.5 must satisfy 0 < h <= 1")):
        loads(text.replace("h = 0.75", "h = 1.5"), "toml")


@pytest.mark.parametrize(("fmt", "message"), [
    ("fis", "input 'x' set 'p' upper MF is a Point, which has no MATLAB MF type"),
    ("t2fis", "input 'x' set 'p' upper MF is a Point, which has no MATLAB MF type"),
    ("fll", "input 'x' set 'p' is a Point, which fuzzylite has no term for; save as .toml"),
    ("fml", "input 'x' term 'p' is a Point, which IEEE 1855 has no shape for"),
])
def test_the_formats_without_the_term_refuse_it_naming_it(fmt, message) -> None:
    with pytest.raises(UnsupportedFeatureError, match=re.escape(message)):
        dumps(system(Point(V)), fmt)


def test_c_generation_refuses_it_naming_the_term() -> None:
    with pytest.raises(UnsupportedFeatureError,
                       match=re.escape("input 'x': membership function "
                                       "Point(value=0.3, h=1.0) has no C implementation")):
        check_supported(system(Point(V)))


FCL = """FUNCTION_BLOCK f
VAR_INPUT x : REAL; END_VAR
VAR_OUTPUT y : REAL; END_VAR
FUZZIFY x
    TERM two := 2;
    TERM low := TRIAN 0 1 4;
END_FUZZIFY
DEFUZZIFY y
    TERM a := 10;
    TERM b := 20;
    METHOD : COGS;
END_DEFUZZIFY
RULEBLOCK r
    RULE 1 : IF x IS two THEN y IS a;
    RULE 2 : IF x IS low THEN y IS b;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


def test_fcl_reads_an_input_singleton_as_a_point_and_output_singletons_as_values() -> None:
    fls = fcl_loads(FCL)
    (x,) = fls.inputs
    assert x.sets[x.set_index("two")].upper == Point(2.0)
    assert x.universe == (0.0, 4.0)  # the point's and the triangle's span
    # at 2: 10 * 1 + 20 * (2 / 3), over 1 + 2 / 3; beside it the triangle alone: 20
    assert fls(2.0) == (10.0 + 20.0 * (2.0 / 3.0)) / (1.0 + 2.0 / 3.0)
    assert fls(np.nextafter(2.0, 3.0)) == 20.0
    terms = loads_terms(FCL.replace("TERM low := TRIAN 0 1 4;", "TERM neg := -1.5;"))
    assert [s.upper for s in terms["x"].sets] == [Point(2.0), Point(-1.5)]
    assert terms["x"].universe == (-1.5, 2.0)
    lone = loads_terms(FCL.replace("    TERM low := TRIAN 0 1 4;\n", ""))
    assert lone["x"].universe == (1.0, 3.0)  # jFuzzyLogic's point universe, widened by 1


def test_fcl_refuses_a_singleton_set_of_a_centroid_output_as_before() -> None:
    with pytest.raises(FisFormatError, match=re.escape(
            "<string>:9: term 'a': a singleton is the value of a COGS output (or an input's "
            "Point), not a membership function of an output without METHOD : COGS as here")):
        fcl_loads(FCL.replace("METHOD : COGS", "METHOD : COG"))

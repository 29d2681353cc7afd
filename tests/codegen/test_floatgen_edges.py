"""The float generator's edges, without a compiler: the comparison keys of table constants
(``-0.0`` and ``+0.0`` share one, the keys order as the floats do, each is the float's bits
mapped as the template expects), the literals (exact, and a constant beyond float's range
refused by name, at the rounding boundary), and the width of the rule index at its sentinel
(255 is the "no rule" value of an ``unsigned char`` index, so 255 indices need ``unsigned
short``)."""

from __future__ import annotations

import struct
import warnings

import numpy as np
import pytest

from it2track.codegen import RealType, generate_c
from it2track.codegen.floatgen import _key, literal
from it2track.fuzzy import Input, IT2Set, IT2Sugeno, Rule, Triangle
from it2track.io import UnsupportedFeatureError

F32_MAX = float(np.finfo(np.float32).max)
#: Half a float ulp above the largest float: rounds (to even) to inf.
HALFWAY = F32_MAX + 2.0**103


def bits(v: float) -> int:
    return int.from_bytes(struct.pack(">f", v), "big")


def expected_key(v: float) -> str:
    """The float's bits, sign flipped for positives and all bits flipped for negatives, so that
    the unsigned keys order as the floats; -0.0 is +0.0."""
    u = bits(0.0 if v == 0.0 else v)
    k = (u ^ 0xFFFFFFFF) if u >> 31 else (u | 0x80000000)
    return f"0x{k:08X}UL"


VALUES = [-F32_MAX, -1e30, -2.5, -1.0, -2.0**-149, -0.0, 0.0, 2.0**-149, 1e-30, 0.1, 1.0, 1.5,
          1e30, F32_MAX]


def test_float_keys_are_the_mapped_bits_and_zero_has_one():
    assert _key(-0.0, RealType.FLOAT) == _key(0.0, RealType.FLOAT) == "0x80000000UL"
    assert _key(1.0, RealType.FLOAT) == "0xBF800000UL"
    assert _key(-1.0, RealType.FLOAT) == "0x407FFFFFUL"
    for v in VALUES:
        assert _key(v, RealType.FLOAT) == expected_key(v), v


def test_float_keys_order_as_the_floats():
    keys = [int(_key(v, RealType.FLOAT)[2:-2], 16) for v in VALUES]
    for (a, ka), (b, kb) in zip(zip(VALUES, keys, strict=True), zip(VALUES[1:], keys[1:],
                                                                     strict=True), strict=False):
        assert (ka < kb) == (a < b) and (ka == kb) == (a == b), (a, b)


def test_a_double_key_is_its_literal_and_a_float_key_its_rounded_value():
    assert _key(0.1, RealType.DOUBLE) == "0.1" == literal(0.1, RealType.DOUBLE)
    assert _key(-0.0, RealType.DOUBLE) == "-0.0"
    assert _key(0.1, RealType.FLOAT) == _key(float(np.float32(0.1)), RealType.FLOAT)


@pytest.mark.parametrize(("value", "real", "text"), [
    (0.1, RealType.DOUBLE, "0.1"), (2.0, RealType.DOUBLE, "2.0"), (100, RealType.DOUBLE, "100.0"),
    (1e-7, RealType.DOUBLE, "1e-07"), (-0.0, RealType.DOUBLE, "-0.0"),
    (0.1, RealType.FLOAT, "0.10000000149011612f"), (1, RealType.FLOAT, "1.0f"),
    (1e-7, RealType.FLOAT, "1.0000000116860974e-07f"), (F32_MAX, RealType.FLOAT,
                                                        "3.4028234663852886e+38f"),
    (np.nextafter(HALFWAY, 0.0), RealType.FLOAT, "3.4028234663852886e+38f"),
])
def test_literals_are_exact(value, real, text):
    assert literal(value, real) == text


@pytest.mark.parametrize("value", [HALFWAY, 1e300, -1e300])
def test_a_constant_beyond_floats_range_is_refused_without_a_numpy_warning(value):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(UnsupportedFeatureError) as info:
            literal(value, RealType.FLOAT)
    assert str(info.value) == f"constant {value!r} overflows a 32-bit float"
    assert literal(value, RealType.DOUBLE) == repr(value)


@pytest.mark.parametrize("value", [float("inf"), float("-inf"), float("nan")])
def test_a_non_finite_constant_is_refused(value):
    for real in (RealType.FLOAT, RealType.DOUBLE):
        with pytest.raises(ValueError) as info:
            literal(value, real)
        assert str(info.value) == f"cannot write the non-finite constant {value!r} to C"


def many_rules(n: int) -> IT2Sugeno:
    """n rules over one input of two interval sets (4 rows, 5 extended): the largest index the
    C stores is the rule count, n + 1 values with the "none" one. Interval consequents whose
    upper ends order otherwise than their lower ends: the C gathers the rules by y_hi, marking
    the free places with the sentinel."""
    sets = [IT2Set(Triangle(-1, 0, 1), Triangle(-1, 0, 1, h=0.5), "n"),
            IT2Set(Triangle(0, 1, 2), Triangle(0, 1, 2, h=0.5), "p")]
    return IT2Sugeno(inputs=[Input("x", (-1.0, 2.0), sets)],
                     rules=[Rule(["np"[i % 2]], (float(i), i + 500.0 * (i % 2 == 0)))
                            for i in range(n)])


@pytest.mark.parametrize(("n", "idx", "none"), [(253, "unsigned char", 255),
                                                 (254, "unsigned short", 65535)])
def test_the_rule_index_width_at_its_sentinel(n, idx, none):
    fls = many_rules(n)
    assert (fls.tables.n_rows, fls.n_rules) == (4, n)
    code = generate_c(fls, real=RealType.FLOAT)
    assert f"typedef {idx} it2_idx;" in code.source
    assert f"pos[r] = {none};" in code.source
    assert ("pgm_read_byte" in code.source) == (idx == "unsigned char")

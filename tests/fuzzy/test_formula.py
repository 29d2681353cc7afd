"""The formula reader (fuzzylite's Function, jFuzzyLogic's FUNCTION): closed-form values,
precedence and associativity per each tool's grammar, the functions of each dialect, and every
refusal naming its token and position."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from it2track.fuzzy.formula import (
    MAX_CHARS,
    MAX_DEPTH,
    MAX_TOKENS,
    Formula,
    FormulaError,
    FormulaMembership,
)


def fl(text: str, *names: str) -> Formula:
    return Formula(text, "fuzzylite", names)


def jfl(text: str, *names: str) -> Formula:
    return Formula(text, "jfuzzylogic", names)


@pytest.mark.parametrize(("text", "fuzzylite", "jfuzzylogic"), [
    ("1 + 2 * 3", 7.0, 7.0),            # * before +
    ("(1 + 2) * 3", 9.0, 9.0),
    ("10 - 4 - 3", 3.0, 3.0),           # - left-associative
    ("64 / 4 / 2", 8.0, 8.0),           # / left-associative
    ("2 ^ 3 ^ 2", 512.0, 64.0),         # fuzzylite's ^ right-, jFuzzyLogic's left-associative
    ("2 * 3 ^ 2", 18.0, 18.0),          # ^ before *
    ("-2 ^ 2", -4.0, 4.0),              # fuzzylite: -(2^2); jFuzzyLogic's signed number -2
    ("2 ^ -1", 0.5, 0.5),
    ("-7 % 3", 2.0, -1.0),              # fuzzylite: np.remainder; jFuzzyLogic: Java's fmod
    ("7 % -3", -2.0, 1.0),
    ("2 * 7 % 4", 2.0, 6.0),            # fuzzylite: % beside *; jFuzzyLogic: % beside ^
    ("1 - -1", 2.0, 2.0),
    ("3 - 2 + 1", 2.0, 2.0),
    ("1.5e1 + .5", 15.5, 15.5),
])
def test_precedence_and_associativity_of_each_dialect(text: str, fuzzylite: float,
                                                      jfuzzylogic: float) -> None:
    assert fl(text).value() == fuzzylite
    assert jfl(text).value() == jfuzzylogic


def test_fuzzylites_own_operators() -> None:
    assert fl("2 ** 3 ** 2").value() == 512.0
    assert fl(".-2 ^ 2").value() == -4.0 and fl(".+2").value() == 2.0
    assert fl("~2 ^ 2").value() == 4.0  # ~ and ! bind tighter than ^
    assert fl("!0 + !3").value() == 1.0
    assert fl("1 and 0 or 1").value() == 1.0 and fl("1 and 0").value() == 0.0
    assert fl("0 or 0 and 1").value() == 0.0  # and before or
    assert fl("1 + 1 and 0").value() == 0.0  # + before and


def test_fuzzylites_functions_in_closed_form() -> None:
    x = np.array([0.25, 0.5, 0.75])
    cases = {
        "sin(x)": np.sin(x), "cos(x)": np.cos(x), "tan(x)": np.tan(x), "asin(x)": np.arcsin(x),
        "acos(x)": np.arccos(x), "atan(x)": np.arctan(x), "sinh(x)": np.sinh(x),
        "cosh(x)": np.cosh(x), "tanh(x)": np.tanh(x), "exp(x)": np.exp(x), "log(x)": np.log(x),
        "log10(x)": np.log10(x), "log1p(x)": np.log1p(x), "sqrt(x)": np.sqrt(x),
        "abs(x - 0.5)": np.abs(x - 0.5), "fabs(0.5 - x)": np.abs(0.5 - x),
        "ceil(x * 3)": np.ceil(x * 3), "floor(x * 3)": np.floor(x * 3),
        "asinh(x)": np.arcsinh(x), "acosh(x + 1)": np.arccosh(x + 1), "atanh(x)": np.arctanh(x),
        "pow(x, 3)": x**3, "atan2(x, 2)": np.arctan2(x, 2), "fmod(x * 3, 1)": np.fmod(x * 3, 1),
        "min(x, 0.5)": np.minimum(x, 0.5), "max(x, 0.5)": np.maximum(x, 0.5),
        "gt(x, 0.5)": [0.0, 0.0, 1.0], "ge(x, 0.5)": [0.0, 1.0, 1.0],
        "lt(x, 0.5)": [1.0, 0.0, 0.0], "le(x, 0.5)": [1.0, 1.0, 0.0],
        "eq(x, 0.5)": [0.0, 1.0, 0.0], "neq(x, 0.5)": [1.0, 0.0, 1.0],
        "round(x * 2 + 0.5)": [1.0, 2.0, 2.0],  # numpy's round: half to even (1.0, 1.5, 2.0)
        "2 * pi": [2 * math.pi] * 3, "pi() + x": math.pi + x,
    }
    for text, expected in cases.items():
        np.testing.assert_array_equal(fl(text, "x")(x), expected, err_msg=text)


def test_comparisons_take_two_nans_as_equal_as_fuzzylite() -> None:
    nan = math.nan
    assert fl("eq(a, b)", "a", "b")(nan, nan) == 1.0
    assert fl("neq(a, b)", "a", "b")(nan, nan) == 0.0
    assert fl("ge(a, b)", "a", "b")(nan, nan) == 1.0
    assert fl("le(a, b)", "a", "b")(nan, nan) == 1.0
    assert fl("gt(a, b)", "a", "b")(nan, nan) == 0.0
    assert fl("eq(a, b)", "a", "b")(nan, 1.0) == 0.0
    # Python's min/max: the first unless the second is strictly smaller/larger
    assert math.isnan(fl("min(a, b)", "a", "b")(nan, 1.0))
    assert fl("min(a, b)", "a", "b")(1.0, nan) == 1.0
    assert fl("max(a, b)", "a", "b")(1.0, nan) == 1.0


def test_jfuzzylogics_functions_in_any_case() -> None:
    x = np.array([0.5, 2.0])
    cases = {"EXP(x)": np.exp(x), "ln(x)": np.log(x), "Log(x)": np.log10(x),
             "SIN(x)": np.sin(x), "cos(x)": np.cos(x), "TAN(x)": np.tan(x),
             "ABS(x - 1)": np.abs(x - 1), "x ^ 2 % 3": np.fmod(x**2, 3)}
    for text, expected in cases.items():
        np.testing.assert_array_equal(jfl(text, "x")(x), expected, err_msg=text)
    # junit_functions.fcl's term 'high' at 2.0
    assert jfl("(inVar * 3.0) + 5 * SIN(inVar)", "inVar")(2.0) == 6.0 + 5.0 * math.sin(2.0)


def test_batches_broadcast_and_variables_bind_by_position() -> None:
    f = fl("a - 2 * b", "a", "b")
    assert f.used == frozenset({"a", "b"})
    out = f(np.array([[1.0], [2.0]]), np.array([10.0, 20.0, 30.0]))
    np.testing.assert_array_equal(out, [[-19.0, -39.0, -59.0], [-18.0, -38.0, -58.0]])
    assert fl("3", "a")(np.zeros(4)).tolist() == [3.0] * 4  # a constant has the batch shape
    assert fl("sin(b)", "a", "b").used == frozenset({"b"})
    with pytest.raises(ValueError, match=r"takes 2 values \(a, b\), got 1"):
        f(1.0)
    with pytest.raises(ValueError, match=r"reads \['a', 'b'\]"):
        f.value()


def test_floating_point_exceptions_give_nan_and_inf_silently() -> None:
    f = fl("sin(x) / x", "x")  # fuzzylite's approximation.fll at 0
    with np.errstate(all="raise"):
        y = f(np.array([0.0, math.pi / 2]))
    assert math.isnan(y[0]) and y[1] == 2.0 / math.pi
    assert fl("1 / x", "x")(0.0) == math.inf
    assert math.isnan(jfl("LN(x)", "x")(-1.0))


def test_equal_formulas_compare_equal_and_pickle_by_their_text() -> None:
    f = fl("x ^ 2", "x")
    assert f == fl("x ^ 2", "x") and hash(f) == hash(fl("x ^ 2", "x"))
    assert f != jfl("x ^ 2", "x") and f != fl("x ^ 2", "x", "y")
    again = pickle.loads(pickle.dumps(f))
    assert again == f and again(3.0) == 9.0


def test_a_membership_formula_is_floored_at_zero() -> None:
    tri = FormulaMembership(fl("1 - abs(x)", "x"))
    assert tri(np.array([-2.0, -0.5, 0.0, 2.0])).tolist() == [0.0, 0.5, 1.0, 0.0]
    assert math.isnan(tri(math.nan))
    with pytest.raises(ValueError, match="reads x only"):
        FormulaMembership(fl("a", "a"))


def _error(text: str, dialect: str = "fuzzylite", names: tuple[str, ...] = ("x",)
           ) -> FormulaError:
    with pytest.raises(FormulaError) as info:
        Formula(text, dialect, names)
    return info.value


@pytest.mark.parametrize(("text", "dialect", "message", "token", "position"), [
    ("", "fuzzylite", "is empty (at the end)", "", 0),
    ("   ", "fuzzylite", "is empty (at the end)", "", 3),
    ("x +", "fuzzylite", "ends where a number, name or '(' should follow (at the end)", "", 3),
    ("(x", "fuzzylite", "'(' at character 1 is not closed (at the end)", "", 2),
    ("(x x)", "fuzzylite", "unexpected 'x' where ')' should close the '(' at character 1 "
     "(at character 4)", "x", 3),
    ("x)", "fuzzylite", "unexpected ')' where the formula should end (at character 2)", ")", 1),
    ("x x", "fuzzylite", "unexpected 'x' where the formula should end (at character 3)", "x", 2),
    ("* x", "fuzzylite", "unexpected '*' where a number, name or '(' should be "
     "(at character 1)", "*", 0),
    ("y + 1", "fuzzylite", "unknown name 'y' (the formula may read: x; fuzzylite's functions: "
     "gt, ge, eq, neq, le, lt, min, max, acos, asin, atan, ceil, cos, cosh, exp, abs, fabs, "
     "floor, log, log10, round, sin, sinh, sqrt, tan, tanh, log1p, acosh, asinh, atanh, pow, "
     "atan2, fmod, pi) (at character 1)", "y", 0),
    ("SIN(x)", "fuzzylite", "unknown name 'SIN'", "SIN", 0),  # fuzzylite's names: lower case
    ("sqrt(x)", "jfuzzylogic", "unknown name 'sqrt' (the formula may read: x; jfuzzylogic's "
     "functions: EXP, LN, LOG, SIN, COS, TAN, ABS) (at character 1)", "sqrt", 0),
    ("sin x", "fuzzylite", "function 'sin' needs '(' and 1 argument (at character 5)", "x", 4),
    ("pow(x)", "fuzzylite", "function 'pow' takes 2 arguments (at character 6)", ")", 5),
    ("sin(x, 1)", "fuzzylite", "function 'sin' takes 1 argument (at character 6)", ",", 5),
    ("pow(x, 1, 2)", "fuzzylite", "function 'pow' takes 2 arguments (at character 9)", ",", 8),
    ("x $ 2", "fuzzylite", "unexpected character '$' (fuzzylite's formulas use numbers, names "
     "and ** .- .+ + - * / % ^ ! ~ ( )) (at character 3)", "$", 2),
    ("SIN(x, 1)", "jfuzzylogic", "unexpected character ',' (jfuzzylogic's formulas use "
     "numbers, names and + - * / % ^ ( )) (at character 6)", ",", 5),
    ("__import__('os')", "fuzzylite", "unexpected character \"'\"", "'", 11),
    ("x.real", "fuzzylite", "unexpected character '.'", ".", 1),
    ("1e999", "fuzzylite", "number '1e999' is out of range (at character 1)", "1e999", 0),
    ("~", "fuzzylite", "ends where a number, name or '(' should follow (at the end)", "", 1),
])
def test_every_refusal_names_the_token_and_its_position(
        text: str, dialect: str, message: str, token: str, position: int) -> None:
    err = _error(text, dialect)
    assert str(err).startswith(message)
    assert (err.token, err.position) == (token, position)


def test_hostile_sizes_are_refused_before_any_work() -> None:
    err = _error("x" + " " * MAX_CHARS)
    assert str(err) == (f"is {MAX_CHARS + 1} characters long; at most {MAX_CHARS} are read "
                        f"(at character {MAX_CHARS + 1})")
    err = _error("+".join(["1"] * (MAX_TOKENS // 2 + 1)))
    assert str(err) == f"has more than {MAX_TOKENS} tokens (at character {MAX_TOKENS + 1})"
    assert fl("(" * MAX_DEPTH + "x" + ")" * MAX_DEPTH, "x")(2.0) == 2.0
    err = _error("(" * (MAX_DEPTH + 1) + "x" + ")" * (MAX_DEPTH + 1))
    assert str(err) == f"nests deeper than {MAX_DEPTH} (at character {MAX_DEPTH + 1})"
    assert err.token == "("
    # a long chain nests as deep as it is long
    assert fl("+".join(["x"] * (MAX_DEPTH + 1)), "x")(1.0) == MAX_DEPTH + 1
    err = _error("+".join(["x"] * (MAX_DEPTH + 2)))
    assert str(err).startswith(f"nests deeper than {MAX_DEPTH}")
    err = _error("2^" * (MAX_DEPTH + 1) + "2")
    assert str(err).startswith(f"nests deeper than {MAX_DEPTH}")
    err = _error("-" * (MAX_DEPTH + 1) + "2")
    assert str(err).startswith(f"nests deeper than {MAX_DEPTH}")
    err = _error("sin(" * (MAX_DEPTH + 1) + "x" + ")" * (MAX_DEPTH + 1))
    assert str(err).startswith(f"nests deeper than {MAX_DEPTH}")


def test_bad_arguments() -> None:
    with pytest.raises(ValueError, match="dialect='python' must be one of"):
        Formula("1", "python")
    with pytest.raises(TypeError, match="a formula is text, got int"):
        Formula(1, "fuzzylite")  # type: ignore[arg-type]

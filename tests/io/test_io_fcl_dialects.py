"""FCL as jFuzzyLogic and fuzzylite write it, beside the IEC 61131-7 text of test_io_fcl.py:
their comments, named shapes (checked against the published formulas), several function
blocks, ``RANGE`` where jFuzzyLogic puts it, the universe jFuzzyLogic estimates, De Morgan
reductions, linear ``FUNCTION`` terms, fuzzylite's weighted sum, Tsukamoto and hybrid
engines, and refusals naming the line."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from it2track.cli.fis import fis
from it2track.fuzzy import (
    HybridSystem,
    Linear,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    WeightedDefuzzifier,
    ZeroFiringError,
)
from it2track.fuzzy.formula import Formula
from it2track.io import FisFormatError, FisFormatWarning, load, loads

DATA = Path(__file__).parent / "data"


def fcl(fuzzify: str, defuzzify: str, rules: str, *, name: str = "f",
        inputs: str = "x : REAL;", outputs: str = "y : REAL;") -> str:
    return (f"FUNCTION_BLOCK {name}\nVAR_INPUT\n{inputs}\nEND_VAR\nVAR_OUTPUT\n{outputs}\n"
            f"END_VAR\n{fuzzify}\n{defuzzify}\nRULEBLOCK r\n{rules}\nEND_RULEBLOCK\n"
            "END_FUNCTION_BLOCK\n")


ONE_IN = """FUZZIFY x
    TERM lo := (0, 1) (10, 0);
    TERM hi := (0, 0) (10, 1);
END_FUZZIFY"""
SINGLETONS = """DEFUZZIFY y
    TERM a := 2;
    TERM b := 8;
    METHOD : COGS;
END_DEFUZZIFY"""
TWO_RULES = """    RULE 1 : IF x IS lo THEN y IS a;
    RULE 2 : IF x IS hi THEN y IS b;"""


def test_comments_of_every_dialect_and_keywords_in_any_case() -> None:
    plain = loads(fcl(ONE_IN, SINGLETONS, TWO_RULES), "fcl")
    text = """/* jFuzzyLogic's block comment,
   over two lines */
function_block f  // fuzzylite's line comment
var_input x : real; end_var
(* the standard's comment *)
VAR_OUTPUT y : REAL; END_VAR
fuzzify x
    term lo := (0, 1) (10, 0);  /* inline */
    term hi := (0, 0) (10, 1);
end_fuzzify
defuzzify y term a := 2; term b := 8; method : cogs; end_defuzzify
ruleblock r
    rule 1 : if x is lo then y is a;
    rule 2 : if x is hi then y is b;  // the last
end_ruleblock
end_function_block
"""
    fls = loads(text, "fcl")
    assert isinstance(fls, T1Sugeno)
    x = np.linspace(0.0, 10.0, 11)
    assert np.array_equal(fls(x), plain(x))
    assert float(fls(2.5)) == pytest.approx(0.75 * 2 + 0.25 * 8, abs=1e-12)


def _formulas() -> dict[str, tuple[str, object]]:
    def trian(x, a, b, c):
        return np.clip(np.minimum((x - a) / (b - a), (c - x) / (c - b)), 0, 1)

    def trape(x, a, b, c, d):
        return np.clip(np.minimum(np.minimum((x - a) / (b - a), 1), (d - x) / (d - c)), 0, 1)

    def gauss(x, m, s):
        return np.exp(-((x - m) ** 2) / (2 * s * s))

    def gauss2(x, m1, s1, m2, s2):
        return np.where(x < m1, gauss(x, m1, s1), np.where(x > m2, gauss(x, m2, s2), 1.0))

    def sigm(x, gain, center):
        return 1 / (1 + np.exp(-gain * (x - center)))

    return {
        # jFuzzyLogic's parameter orders, as its MembershipFunction* classes read them
        "TRIAN 1 3 6": ("trian", lambda x: trian(x, 1, 3, 6)),
        "TRAPE 1 2 4 7": ("trape", lambda x: trape(x, 1, 2, 4, 7)),
        "GAUSS 5 1.5": ("gauss", lambda x: gauss(x, 5, 1.5)),
        "GAUSS2 3 1 6 2": ("gauss2", lambda x: gauss2(x, 3, 1, 6, 2)),
        "GBELL 2 3 5": ("gbell", lambda x: 1 / (1 + np.abs((x - 5) / 2) ** 6)),
        "SIGM 2 5": ("sigm", lambda x: sigm(x, 2, 5)),
        "DSIGM 2 3 2 7": ("dsigm", lambda x: np.maximum(sigm(x, 2, 3) - sigm(x, 2, 7), 0)),
        "COSINE 2 5": ("cosine", lambda x: np.where(
            np.abs(x - 5) <= 2, 0.5 * (1 + np.cos(np.pi * (x - 5) / 2)), 0.0)),
        # fuzzylite's names, in fuzzylite's order
        "Bell 5 2 3": ("bell", lambda x: 1 / (1 + np.abs((x - 5) / 2) ** 6)),
        "Sigmoid 5 2": ("sigmoid", lambda x: sigm(x, 2, 5)),
        "Gaussian 5 1.5": ("gaussian", lambda x: gauss(x, 5, 1.5)),
        "Trapezoid 1 2 4 7": ("trapezoid", lambda x: trape(x, 1, 2, 4, 7)),
    }


def test_named_shapes_follow_the_published_formulas() -> None:
    shapes = _formulas()
    terms = "\n".join(f"    TERM {name} := {spec};" for spec, (name, _) in shapes.items())
    rules = "\n".join(f"    RULE {k} : IF x IS {name} THEN y IS a;"
                      for k, (name, _) in enumerate(shapes.values(), 1))
    fls = loads(fcl(f"FUZZIFY x\n{terms}\n    RANGE := (0 .. 10);\nEND_FUZZIFY", SINGLETONS,
                    rules), "fcl")
    x = np.linspace(0.0, 10.0, 201)
    sets = {s.name: s for s in fls.inputs[0].sets}
    for name, formula in shapes.values():
        np.testing.assert_allclose(sets[name].upper(x), formula(x), rtol=0, atol=1e-12,
                                   err_msg=name)
        assert sets[name].upper == sets[name].lower


def test_fuzzylite_export_syntax() -> None:
    # fuzzylite 6's exporter: fixed-point numbers, lower-case rules without ';', nan default
    text = """//Code automatically generated with fuzzylite 6.0.

FUNCTION_BLOCK SimpleDimmer

VAR_INPUT
  Ambient: REAL;
END_VAR

VAR_OUTPUT
  Power: REAL;
END_VAR

FUZZIFY Ambient
  RANGE := (0.000 .. 1.000);
  TERM DARK := Triangle 0.000 0.250 0.500;
  TERM MEDIUM := Triangle 0.250 0.500 0.750;
  TERM BRIGHT := Triangle 0.500 0.750 1.000;
END_FUZZIFY

DEFUZZIFY Power
  RANGE := (0.000 .. 1.000);
  TERM LOW := 0.250;
  TERM MEDIUM := 0.500;
  TERM HIGH := Linear 0.5 0.25;
  METHOD : COGS;
  DEFAULT := nan;
END_DEFUZZIFY

RULEBLOCK
  RULE 1 : if Ambient is DARK then Power is HIGH
  RULE 2 : if Ambient is MEDIUM then Power is MEDIUM
  RULE 3 : if Ambient is BRIGHT then Power is LOW
END_RULEBLOCK

END_FUNCTION_BLOCK
"""
    fls = loads(text, "fcl")
    assert isinstance(fls, T1Sugeno) and fls.name == "SimpleDimmer"
    assert fls.on_zero_firing is None
    assert fls.rules[0].consequent == Linear([0.5], 0.25)
    assert float(fls(0.25)) == pytest.approx(0.5 * 0.25 + 0.25, abs=1e-12)
    assert float(fls(0.625)) == pytest.approx(0.5 * 0.5 + 0.5 * 0.25, abs=1e-12)


def test_weighted_sum_cogss() -> None:
    text = fcl(ONE_IN, SINGLETONS.replace("COGS", "COGSS"), TWO_RULES)
    fls = loads(text, "fcl")
    assert fls.defuzzifier is WeightedDefuzzifier.SUM
    assert float(fls(2.5)) == pytest.approx(0.75 * 2 + 0.25 * 8, abs=1e-12)
    assert float(fls(5.0)) == pytest.approx(0.5 * 2 + 0.5 * 8, abs=1e-12)


def two_blocks() -> str:
    first = fcl(ONE_IN, SINGLETONS, TWO_RULES, name="first")
    second = fcl(ONE_IN, SINGLETONS, TWO_RULES.replace("IS a", "IS c").replace("IS b", "IS a")
                 .replace("IS c", "IS b"), name="second")
    return first + "\n" + second


def test_several_function_blocks_are_selected_by_name(tmp_path) -> None:
    text = two_blocks()
    with pytest.warns(FisFormatWarning, match=r"2 FUNCTION_BLOCKs \('first', 'second'\)"):
        first = loads(text, "fcl")
    assert first.name == "first" and float(first(0.0)) == 2.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        second = loads(text, "fcl", block="second")
        assert second.name == "second" and float(second(0.0)) == 8.0
        path = tmp_path / "two.fcl"
        path.write_text(text)
        assert load(path, block="second") == second
    with pytest.raises(FisFormatError, match=r"no FUNCTION_BLOCK 'third' \(the file has "
                       r"'first', 'second'\)"):
        loads(text, "fcl", block="third")
    with pytest.raises(ValueError, match="block= names an FCL FUNCTION_BLOCK"):
        loads("", "fis", block="first")
    result = CliRunner().invoke(fis, ["convert", "--block", "second", str(path),
                                      str(tmp_path / "second.toml")])
    assert result.exit_code == 0, result.output
    assert load(tmp_path / "second.toml")(0.0) == 8.0


def test_range_after_the_var_input_declaration() -> None:
    # jFuzzyLogic lets RANGE follow the declaration
    text = fcl(ONE_IN.replace("(10, 0)", "(4, 0)").replace("(10, 1)", "(4, 1)"), SINGLETONS,
               TWO_RULES, inputs="x : REAL; RANGE := (-2 .. 12);")
    assert loads(text, "fcl").inputs[0].universe == (-2.0, 12.0)


@pytest.mark.parametrize(("terms", "universe"), [
    ("TERM a := (1, 0) (3, 1) (4, 0);", (1.0, 4.0)),
    ("TERM a := TRIAN 1 3 6; TERM b := TRAPE 0 2 4 5;", (0.0, 6.0)),
    ("TERM a := GAUSS 5 1.5;", (5.0 - 4 * 1.5, 5.0 + 4 * 1.5)),
    ("TERM a := COSINE 2 5;", (3.0, 7.0)),
    ("TERM a := SIGM 3 1;", (1.0 - 3.0, 1.0 + 3.0)),
])
def test_universe_estimated_as_jfuzzylogic_does_without_range(terms: str, universe) -> None:
    rule = "    RULE 1 : IF x IS a THEN y IS a;"
    fls = loads(fcl(f"FUZZIFY x\n    {terms}\nEND_FUZZIFY", SINGLETONS, rule), "fcl")
    assert fls.inputs[0].universe == pytest.approx(universe, abs=1e-12)


def test_de_morgan_reduces_a_negated_parenthesis() -> None:
    two = """FUZZIFY x
    TERM lo := (0, 1) (10, 0);
END_FUZZIFY
FUZZIFY z
    TERM hi := (0, 0) (10, 1);
END_FUZZIFY"""
    negated = fcl(two, SINGLETONS.replace("COGS;", "COGS;\n    DEFAULT := 0;"), "    AND : MIN;\n"
                  "    RULE 1 : IF NOT (x IS lo OR z IS hi) THEN y IS b;\n"
                  "    RULE 2 : IF x IS lo THEN y IS a;", inputs="x : REAL; z : REAL;")
    explicit = negated.replace("NOT (x IS lo OR z IS hi)", "x IS NOT lo AND z IS NOT hi")
    a, b = loads(negated, "fcl"), loads(explicit, "fcl")
    x, z = np.meshgrid(np.linspace(0, 10, 11), np.linspace(0, 10, 11))
    assert np.array_equal(a(x.ravel(), z.ravel()), b(x.ravel(), z.ravel()))
    # at x = 6, z = 2: rule 1 fires min(0.6, 0.8) = 0.6, rule 2 0.4
    assert float(a(6.0, 2.0)) == pytest.approx((0.6 * 8 + 0.4 * 2) / 1.0, abs=1e-12)


def test_linear_and_formula_function_terms_and_the_refused_ones() -> None:
    outputs = """DEFUZZIFY y
    TERM a := FUNCTION (x * 2.0) + 1;
    TERM b := FUNCTION 3 - x * 0.5;
    METHOD : COGF;
END_DEFUZZIFY"""
    fls = loads(fcl(ONE_IN, outputs, TWO_RULES), "fcl")
    assert fls.rules[0].consequent == Linear([2.0], 1.0)
    assert fls.rules[1].consequent == Linear([-0.5], 3.0)
    assert float(fls(4.0)) == pytest.approx(0.6 * 9.0 + 0.4 * 1.0, abs=1e-12)
    # not linear: a jFuzzyLogic formula, evaluated per sample (junit_functions.fcl's term)
    sine = outputs.replace("3 - x * 0.5", "(x * 3.0) + 5 * SIN(x)")
    fls = loads(fcl(ONE_IN, sine, TWO_RULES), "fcl")
    assert fls.rules[0].consequent == Linear([2.0], 1.0)
    assert isinstance(fls.rules[1].consequent, Formula)
    x = np.array([4.0, 7.5])
    lo, hi = 1.0 - x / 10.0, x / 10.0  # TWO_RULES: lo = (0, 1) (10, 0), hi = (0, 0) (10, 1)
    expected = (lo * (x * 2.0 + 1.0) + hi * (x * 3.0 + 5.0 * np.sin(x))) / (lo + hi)
    np.testing.assert_allclose(fls(x), expected, rtol=0, atol=1e-12)
    # fuzzylite's FCL export writes its Function term: fuzzylite's grammar (^ right-associative)
    fuzzylite = outputs.replace("FUNCTION 3 - x * 0.5", "Function 2 ^ x ^ 0.5 - fabs(x)")
    fls = loads(fcl(ONE_IN, fuzzylite, TWO_RULES), "fcl")
    assert fls.rules[1].consequent == Formula("2 ^ x ^ 0.5 - fabs ( x )", "fuzzylite", ("x",))
    expected = (lo * (x * 2.0 + 1.0) + hi * (2.0 ** np.sqrt(x) - x)) / (lo + hi)
    np.testing.assert_allclose(fls(x), expected, rtol=0, atol=1e-12)
    for bad, message in [
        ("(x * 3.0) + 5 * SIN(x", "FUNCTION '( x * 3.0 ) + 5 * SIN ( x': '(' at character 23 "
         "is not closed (at the end)"),
        ("(x * 3.0) + w", "FUNCTION '( x * 3.0 ) + w': unknown name 'w' (the formula may read: "
         "x; jfuzzylogic's functions: EXP, LN, LOG, SIN, COS, TAN, ABS) (at character 15)"),
        ("x ** 2", "FUNCTION 'x * * 2': unexpected '*' where a number, name or '(' should be "
         "(at character 5)"),
        ("(x * 3.0) + y", "FUNCTION '( x * 3.0 ) + y' reads the output 'y': it2track reads a "
         "jFuzzyLogic FUNCTION of the inputs only (fuzzylite's chained Function, in its own "
         "grammar, reads the outputs declared before its own)"),
    ]:
        text = fcl(ONE_IN, outputs.replace("3 - x * 0.5", bad), TWO_RULES)
        with pytest.raises(FisFormatError) as info:
            loads(text, "fcl", path="f.fcl")
        assert info.value.line == text.split("\n").index(f"    TERM b := FUNCTION {bad};") + 1
        assert info.value.message == f"term 'b': {message}"


def test_jfuzzylogics_lenient_default_without_assign_or_semicolon() -> None:
    # junit_functions.fcl: jFuzzyLogic's lexer drops the '=' and its parser puts in ':=' and ';'
    lenient = SINGLETONS.replace("METHOD : COGS;", "DEFAULT = 5\n    METHOD : COGS;")
    text = fcl(ONE_IN, lenient, "    RULE 1 : IF x IS lo THEN y IS a;")
    with pytest.warns(FisFormatWarning, match=r"DEFAULT = 5: read as jFuzzyLogic reads it, "
                      r"DEFAULT := 5;") as caught:
        fls = loads(text, "fcl")
    assert caught[0].message.line == text.split("\n").index("    DEFAULT = 5") + 1
    assert float(fls(10.0)) == 5.0  # nothing fires at x = 10: the default
    assert float(fls(5.0)) == 2.0
    with pytest.warns(FisFormatWarning):
        same = loads(text.replace("DEFAULT = 5", "DEFAULT = 5;"), "fcl")
    assert float(same(10.0)) == 5.0
    with pytest.raises(FisFormatError, match=r"expected a default value \(a number\), got '='"):
        loads(text.replace("DEFAULT = 5", "DEFAULT == 5"), "fcl")
    with pytest.raises(FisFormatError, match="expected ':=', got '5'"):
        loads(text.replace("DEFAULT = 5", "DEFAULT 5"), "fcl")


def test_an_output_no_rule_concludes_is_its_default_as_jfuzzylogic() -> None:
    # arm.fcl: torque2 has terms and DEFAULT := 0 but its rules are commented out;
    # jFuzzyLogic's defuzzifier gives NaN there and the variable keeps its DEFAULT
    idle = SINGLETONS.replace("DEFUZZIFY y", "DEFUZZIFY z").replace("COGS;", "COGS;\n"
                                                                      "    DEFAULT := 4;")
    first = SINGLETONS.replace("COGS;", "COGS;\n    DEFAULT := 0;")
    text = fcl(ONE_IN, first + "\n" + idle, TWO_RULES, outputs="y : REAL; z : REAL;")
    fls = loads(text, "fcl")
    np.testing.assert_allclose(fls(np.array([0.0, 5.0])), [[2.0, 4.0], [5.0, 4.0]],
                               rtol=0, atol=1e-12)
    with pytest.raises(ZeroFiringError, match="concludes output 2, and it has no "
                       "on_zero_firing value"):
        loads(text.replace("    DEFAULT := 4;\n", "").replace("    DEFAULT := 0;\n", ""),
              "fcl")(1.0)


def test_tsukamoto_and_hybrid_engines() -> None:
    monotonic = """DEFUZZIFY y
    RANGE := (0 .. 1);
    TERM a := Ramp 0.000 0.250;
    TERM b := Ramp 1.000 0.500;
    METHOD : COGS;
END_DEFUZZIFY"""
    fls = loads(fcl(ONE_IN, monotonic, TWO_RULES), "fcl")
    assert isinstance(fls, T1Tsukamoto)
    # x = 2.5: lo 0.75 -> a at 0.1875; hi 0.25 -> b at 0.875
    assert float(fls(2.5)) == pytest.approx((0.75 * 0.1875 + 0.25 * 0.875) / 1.0, abs=1e-12)
    mamdani = """DEFUZZIFY m
    RANGE := (0 .. 10);
    TERM a := TRIAN 0 5 10;
    METHOD : COG;
    ACCU : MAX;
END_DEFUZZIFY"""
    hybrid = loads(fcl(ONE_IN, SINGLETONS + "\n" + mamdani,
                       TWO_RULES + "\n    RULE 3 : IF x IS lo THEN m IS a;",
                       outputs="y : REAL; m : REAL;"), "fcl")
    assert isinstance(hybrid, HybridSystem)
    assert [type(p) for p in hybrid.systems] == [T1Sugeno, T1Mamdani]
    y, m = hybrid(2.5)
    assert float(y) == pytest.approx(3.5, abs=1e-12) and float(m) == pytest.approx(5.0, abs=1e-9)


@pytest.mark.parametrize(("old", "new", "needle", "problem"), [
    ("IF x IS lo THEN", "IF x IS very nope THEN", "RULE 1", "has no term 'nope'"),
    ("TERM a := 2;", "TERM a := 2;\n    DEFAULT := 1 | XX;", "DEFAULT", "expected 'NC'"),
    ("TERM lo := (0, 1) (10, 0);", "TERM lo := TRIAN 0 m 10;", "TERM lo",
     "parameter 'm' is not a declared variable"),
    ("METHOD : COGS;", "METHOD : COGS;\n    ACCU : NOPE;", "ACCU", "ACCU : NOPE"),
    ("TERM hi := (0, 0) (10, 1);", "TERM hi := GAUSS2 6 1 3 1;", "TERM hi", "mean1 > mean2"),
])
def test_dialect_refusals_name_the_line(old: str, new: str, needle: str, problem: str) -> None:
    text = fcl(ONE_IN, SINGLETONS, TWO_RULES)
    assert old in text
    text = text.replace(old, new, 1)
    with pytest.raises(FisFormatError) as info:
        loads(text, "fcl", path="d.fcl")
    assert problem in info.value.message, info.value
    assert info.value.line == next(k for k, line in enumerate(text.split("\n"), 1)
                                   if needle in line), info.value
    assert str(info.value).startswith(f"d.fcl:{info.value.line}: ")


def test_sigmoid_universe_uses_the_gain() -> None:
    # jFuzzyLogic: center +- 9 / |gain| (where the sigmoid is within ~1e-4 of 0 or 1)
    rule = "    RULE 1 : IF x IS a THEN y IS a;"
    fls = loads(fcl("FUZZIFY x\n    TERM a := SIGM -4.5 2;\nEND_FUZZIFY", SINGLETONS, rule),
                "fcl")
    assert fls.inputs[0].universe == pytest.approx((0.0, 4.0), abs=1e-12)
    assert math.isclose(float(fls.inputs[0].sets[0].upper(np.array([2.0]))[0]), 0.5)


def test_the_jfuzzylogic_fixture_agrees_with_jfuzzylogic() -> None:
    # values printed by tests/conformance/JflReference.java (jFuzzyLogic commit 1f421d1b,
    # 1001-point centroid) for each function block cut into its own file
    path = DATA / "jfl_dialect.fcl"
    with pytest.warns(FisFormatWarning, match="'tipper', 'linear'"):
        tipper = load(path)
    for service, food, tip in [(5.0, 5.0, 14.923483027141328), (8.0, 2.0, 5.894728989057832),
                               (8.5, 9.0, 24.752309766320106)]:
        assert float(tipper(service, food)) == pytest.approx(tip, abs=30 * 1e-9)
    assert tipper.inputs[1].universe == (0.0, 9.0)  # jFuzzyLogic's estimate, no RANGE
    assert float(load(path, block="linear")(4.0)) == pytest.approx(0.6 * 6.0 + 0.4 * 2.0,
                                                                  abs=1e-12)

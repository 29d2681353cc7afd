"""FCL reader edges: each refusal's line and message to the letter, each setting's default and
each boundary -- what the mutation run of ``io/fcl.py`` and its parts (``_fclparse``,
``_fclbuild``, ``_fclsystem``) showed no other test pinned."""

from __future__ import annotations

import math
import sys
import warnings

import numpy as np
import pytest

from it2track.fuzzy import (
    Aggregation,
    Bell,
    Cosine,
    Defuzzifier,
    Discrete,
    FootedTrapezoid,
    Gaussian,
    GaussianProduct,
    Hedge,
    HybridSystem,
    Implication,
    Linear,
    Sigmoid,
    SigmoidDifference,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TNorm,
    Trapezoid,
    Triangle,
    WeightedDefuzzifier,
)
from it2track.fuzzy.formula import Formula
from it2track.io import FisFormatError, FisFormatWarning, loads
from it2track.io import fcl as fcl_reader
from it2track.io._fclparse import FunctionBlock, Parser, RuleNode, Tok
from it2track.io._ruletree import Compound, Negation, Proposition

TINY = sys.float_info.min  # 2.2250738585072014e-308, the smallest normal float


def fcl(fuzzify: str, defuzzify: str, rules: str = "    RULE 1 : IF x IS a THEN y IS b;",
        *, block: str = "", inputs: str = "x : REAL;", outputs: str = "y : REAL;") -> str:
    """Line 1 FUNCTION_BLOCK f, 2 VAR_INPUT, 3 ``inputs``, 4 END_VAR, 5 VAR_OUTPUT,
    6 ``outputs``, 7 END_VAR, then ``fuzzify``, ``defuzzify``, RULEBLOCK r, ``block``,
    ``rules``."""
    return (f"FUNCTION_BLOCK f\nVAR_INPUT\n{inputs}\nEND_VAR\nVAR_OUTPUT\n{outputs}\nEND_VAR\n"
            f"{fuzzify}\n{defuzzify}\nRULEBLOCK r\n{block}{rules}\nEND_RULEBLOCK\n"
            "END_FUNCTION_BLOCK\n")


def refusal(text: str) -> FisFormatError:
    with pytest.raises(FisFormatError) as info:
        loads(text, "fcl", path="e.fcl")
    return info.value


IN_A = "FUZZIFY x\n    TERM a := (0, 1) (1, 0);\nEND_FUZZIFY"  # lines 8-10
OUT_B = "DEFUZZIFY y\n    TERM b := (0, 0) (1, 1);\n    METHOD : COG;\nEND_DEFUZZIFY"  # 11-14


# -- a polyline narrower than the smallest normal float ----------------------------------------
SUBNORMAL = "term 'a': the points at x = 0.0 and x = 1e-320 are closer than the smallest " \
    "normal float (2.2250738585072014e-308): the slope between them overflows"


@pytest.mark.parametrize("range_", ["", "\n    RANGE := (0 .. 1);"])
@pytest.mark.parametrize("points", ["(0, 1) (1e-320, 0)", "(0, 0) (1e-320, 1) (1, 0)",
                                    "(0, 0) (1e-320, 1) (1e-320, 0.5) (1, 0)"])
def test_a_subnormal_width_polyline_is_refused_naming_the_line_and_term(
        points: str, range_: str) -> None:
    text = fcl(f"FUZZIFY x\n    TERM a := {points};{range_}\nEND_FUZZIFY", OUT_B)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning on the way
        err = refusal(text)
    assert (err.line, err.message) == (9, SUBNORMAL)
    assert str(err) == f"e.fcl:9: {SUBNORMAL}"


def test_a_subnormal_width_output_term_is_refused_too() -> None:
    out = "DEFUZZIFY y\n    TERM b := (0, 0) (1, 1) (1.00000000001, 0);\n    METHOD : COG;\n" \
        "    TERM a := (0, 1) (1e-320, 0);\nEND_DEFUZZIFY"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        err = refusal(fcl(IN_A, out, "    RULE 1 : IF x IS a THEN y IS b;"))
    assert (err.line, err.message) == (14, SUBNORMAL)


def test_a_polyline_as_narrow_as_the_smallest_normal_float_is_read() -> None:
    # the boundary: 1 / TINY = 4.5e307 is finite, so no slope overflows on a unit universe
    text = fcl(f"FUZZIFY x\n    TERM a := (0, 1) ({TINY!r}, 0);\n    RANGE := (0 .. 1);\n"
               "END_FUZZIFY", OUT_B)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fls = loads(text, "fcl")
    mf = fls.inputs[0].sets[0].upper
    assert mf(np.array([0.0, TINY / 2, TINY, 1.0])).tolist() == [1.0, 0.5, 0.0, 0.0]
    below = float(np.nextafter(TINY, 0.0))  # subnormal: refused
    err = refusal(text.replace(repr(TINY), repr(below)))
    assert err.line == 9 and err.message.startswith(
        f"term 'a': the points at x = 0.0 and x = {below!r} are closer than")


# -- the parser's refusals, each with its line and its whole message ---------------------------
def _swap(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


BASE = fcl(IN_A, OUT_B)  # rules at line 16, END_RULEBLOCK 17, END_FUNCTION_BLOCK 18
IN_RANGE = _swap(IN_A, "END_FUZZIFY", "    RANGE := (0 .. 1);\nEND_FUZZIFY")
PARSE_REFUSALS = {
    "(* unterminated": ("(* open\n" + BASE, 1, "unterminated comment (* ... *)"),
    "/* unterminated": (BASE + "/* open", 19, "unterminated comment /* ... */"),
    "character": (_swap(BASE, "(0, 1) (1, 0)", "(0, 1) @ (1, 0)"), 9,
                  "unexpected character '@'"),
    "end of file": (_swap(BASE, "END_FUNCTION_BLOCK\n", ""), 17,
                    "unexpected end of file: expected END_FUNCTION_BLOCK"),
    "end of file in a term": ("FUNCTION_BLOCK f\nVAR_INPUT\nx : REAL;\nEND_VAR\nFUZZIFY x\n"
                              "TERM a := (0, ", 6,
                              "unexpected end of file: expected a membership degree"),
    "end of file in FUZZIFY": ("FUNCTION_BLOCK f\nVAR_INPUT x : REAL; END_VAR\nFUZZIFY x\n"
                               "TERM a := (0, 1);", 4,
                               "unexpected end of file: expected END_FUZZIFY"),
    "end of file in a shape": ("FUNCTION_BLOCK f\nVAR_INPUT x : REAL; END_VAR\nFUZZIFY x\n"
                               "TERM a := TRIAN 0 1", 4, "unexpected end of file: expected ';'"),
    "end of file in RULEBLOCK": ("FUNCTION_BLOCK f\nRULEBLOCK r\nAND : MIN;", 3,
                                 "unexpected end of file: expected END_RULEBLOCK"),
    "singleton not a number": (fcl(_swap(IN_A, "(0, 1) (1, 0)", "- ;"), OUT_B), 9,
                               "expected a singleton value (a number), got ';'"),
    "default not a number": (fcl(IN_A, _swap(OUT_B, "METHOD : COG;", "DEFAULT := d;")), 13,
                             "expected a default value (a number), got 'd': values given by "
                             "variables (jFuzzyLogic) are not supported"),
    "end of file at an expected word": ("FUNCTION_BLOCK f\nVAR_INPUT x", 2,
                                        "unexpected end of file: expected ':'"),
    "end of file at a name": ("FUNCTION_BLOCK f\nVAR_INPUT", 2,
                              "unexpected end of file: expected a variable name"),
    "FUZZIFY of a number": (fcl(_swap(IN_A, "FUZZIFY x", "FUZZIFY 3"), OUT_B), 8,
                            "expected a variable name, got '3'"),
    "no block": ("  (* nothing *) \n// nor here\n", 1, "no FUNCTION_BLOCK"),
    "no block first": ("VAR_INPUT x : REAL; END_VAR", 1, "expected FUNCTION_BLOCK: 'VAR_INPUT'"),
    "text after": (BASE + "junk", 19, "text after END_FUNCTION_BLOCK: 'junk'"),
    "nested": (_swap(BASE, "RULEBLOCK r", "FUNCTION_BLOCK g\nRULEBLOCK r"), 15,
               "FUNCTION_BLOCK inside FUNCTION_BLOCK f (line 1): missing END_FUNCTION_BLOCK"),
    "unknown section": (_swap(BASE, "RULEBLOCK r", "THING\nRULEBLOCK r"), 15,
                        "unexpected 'THING' (expected VAR_INPUT, VAR_OUTPUT, FUZZIFY, "
                        "DEFUZZIFY, RULEBLOCK or END_FUNCTION_BLOCK)"),
    "declared twice": (fcl(IN_A, OUT_B, outputs="x : REAL;"), 6,
                       "variable 'x' declared twice"),
    "declared twice in one section": (fcl(IN_A, OUT_B, inputs="x : REAL; x : REAL;"), 3,
                                      "variable 'x' declared twice"),
    "type": (fcl(IN_A, OUT_B, inputs="x : INT;"), 3,
             "variable 'x' has type INT: only REAL is supported"),
    "type not a word": (fcl(IN_A, OUT_B, inputs="x : 3;"), 3, "expected a type, got '3'"),
    "variable not a word": (fcl(IN_A, OUT_B, inputs="3 : REAL;"), 3,
                            "expected a variable name, got '3'"),
    "declaration without ':'": (fcl(IN_A, OUT_B, inputs="x REAL;"), 3,
                                "expected ':', got 'REAL'"),
    "range reversed": (fcl(_swap(IN_A, "END_FUZZIFY", "RANGE := (1 .. 0);\nEND_FUZZIFY"),
                           OUT_B), 10, "RANGE (1 .. 0) must satisfy lo < hi"),
    "range twice": (fcl(_swap(IN_RANGE, "END_FUZZIFY", "RANGE := (0 .. 2);\nEND_FUZZIFY"),
                        OUT_B), 11, "a second RANGE for 'x' (first at line 10)"),
    "range in the declaration and the block": (
        fcl(_swap(IN_A, "END_FUZZIFY", "RANGE := (0 .. 2);\nEND_FUZZIFY"), OUT_B,
            inputs="x : REAL;\nRANGE := (0 .. 1);"), 11,
        "a second RANGE for 'x' (first at line 4)"),
    "range start not a number": (
        fcl(_swap(IN_A, "END_FUZZIFY", "RANGE := (lo .. 1);\nEND_FUZZIFY"), OUT_B), 10,
        "expected the range start (a number), got 'lo': values given by variables "
        "(jFuzzyLogic) are not supported"),
    "range end not a number": (
        fcl(_swap(IN_A, "END_FUZZIFY", "RANGE := (0 .. ;);\nEND_FUZZIFY"), OUT_B), 10,
        "expected the range end (a number), got ';'"),
    "range without '..'": (fcl(_swap(IN_A, "END_FUZZIFY", "RANGE := (0, 1);\nEND_FUZZIFY"),
                               OUT_B), 10, "expected '..', got ','"),
    "output not declared": (fcl(IN_A, _swap(OUT_B, "DEFUZZIFY y", "DEFUZZIFY z")), 11,
                            "DEFUZZIFY z: not declared in VAR_OUTPUT"),
    "input not declared": (fcl(_swap(IN_A, "FUZZIFY x", "FUZZIFY w"), OUT_B), 8,
                           "FUZZIFY w: not declared in VAR_INPUT"),
    "second FUZZIFY": (fcl(IN_A + "\n" + IN_A, OUT_B), 11,
                       "second FUZZIFY block for 'x' (first at line 8)"),
    "second DEFUZZIFY": (fcl(IN_A, OUT_B + "\n" + OUT_B), 15,
                         "second DEFUZZIFY block for 'y' (first at line 11)"),
    "METHOD of an input": (fcl(_swap(IN_A, "END_FUZZIFY", "METHOD : COG;\nEND_FUZZIFY"), OUT_B),
                           10, "unexpected 'METHOD' in FUZZIFY x"),
    "ACCU of an input": (fcl(_swap(IN_A, "END_FUZZIFY", "ACCU : MAX;\nEND_FUZZIFY"), OUT_B),
                         10, "unexpected 'ACCU' in FUZZIFY x"),
    "DEFAULT of an input": (fcl(_swap(IN_A, "END_FUZZIFY", "DEFAULT := 0;\nEND_FUZZIFY"),
                                OUT_B), 10, "unexpected 'DEFAULT' in FUZZIFY x"),
    "METHOD without ':'": (fcl(IN_A, _swap(OUT_B, "METHOD : COG;", "METHOD COG;")), 13,
                           "expected ':', got 'COG'"),
    "ACCU without ':'": (fcl(IN_A, _swap(OUT_B, "METHOD : COG;", "ACCU MAX;")), 13,
                         "expected ':', got 'MAX'"),
    "DEFAULT without ':='": (fcl(IN_A, _swap(OUT_B, "METHOD : COG;", "DEFAULT : 1;")), 13,
                             "expected ':=', got ':'"),
    "DEFAULT := nan | 3": (fcl(IN_A, _swap(OUT_B, "END_DEFUZZIFY",
                                           "DEFAULT := nan | 3;\nEND_DEFUZZIFY")), 14,
                           "expected 'NC', got '3'"),
    "DEFAULT without ';'": (fcl(IN_A, _swap(OUT_B, "METHOD : COG;", "DEFAULT := 1 METHOD")),
                            13, "expected ';', got 'METHOD'"),
    "output without terms": (fcl(IN_A, "DEFUZZIFY y\nMETHOD : COG;\nEND_DEFUZZIFY"), 11,
                             "DEFUZZIFY y: no TERM"),
    "term of nothing": (fcl(_swap(IN_A, "(0, 1) (1, 0)", ""), OUT_B), 9,
                        "term 'a': expected points (x, m), a value or a shape"),
    "term without ':='": (fcl(_swap(IN_A, "a :=", "a ="), OUT_B), 9,
                          "expected ':=', got '='"),
    "term name": (fcl(_swap(IN_A, "TERM a", "TERM 1"), OUT_B), 9,
                  "expected a term name, got '1'"),
    "point without ','": (fcl(_swap(IN_A, "(1, 0)", "(1 0)"), OUT_B), 9,
                          "expected ',', got '0'"),
    "point without ')'": (fcl(_swap(IN_A, "(1, 0)", "(1, 0;"), OUT_B), 9,
                          "expected ')', got ';'"),
    "term without ';'": (fcl(_swap(IN_A, "(1, 0);", "(1, 0)\nEND_FUZZIFY"), OUT_B), 10,
                         "expected ';', got 'END_FUZZIFY'"),
    "number from a variable": (fcl(_swap(IN_A, "END_FUZZIFY", "    RANGE := (q .. 1);\n"
                                         "END_FUZZIFY"), OUT_B), 10,
                               "expected the range start (a number), got 'q': values given by "
                               "variables (jFuzzyLogic) are not supported"),
    "number from punctuation": (fcl(_swap(IN_A, "(1, 0)", "(;, 0)"), OUT_B), 9,
                                "expected x (a number), got ';'"),
    "number of 81 characters": (fcl(_swap(IN_A, "(1, 0)", f"({'1' * 81}, 0)"), OUT_B), 9,
                                f"expected x (a number), got '{'1' * 81}'"),
    "number out of range": (fcl(_swap(IN_A, "(1, 0)", "(1e309, 0)"), OUT_B), 9,
                            "number '1e309' is out of range"),
    "operators differ": (fcl(IN_A, OUT_B, block="AND : MIN;\nand : prod;\n"), 17,
                         "AND : prod differs from the earlier AND : MIN (line 16); one "
                         "setting per system"),
    "OR differs": (fcl(IN_A, OUT_B, block="OR : MAX;\nOR : ASUM;\n"), 17,
                   "OR : ASUM differs from the earlier OR : MAX (line 16); one setting per "
                   "system"),
    "operator without ':'": (fcl(IN_A, OUT_B, block="ACT MIN;\n"), 16,
                             "expected ':', got 'MIN'"),
    "operator without ';'": (fcl(IN_A, OUT_B, block="ACT : MIN\n"), 17,
                             "expected ';', got 'RULE'"),
    "unknown rule block entry": (fcl(IN_A, OUT_B, block="FOO : MIN;\n"), 16,
                                 "unexpected 'FOO' in RULEBLOCK"),
    "operator not a word": (fcl(IN_A, OUT_B, block="ACCU : 3;\n"), 16,
                            "expected an ACCU operator, got '3'"),
    "rule number at the end of the file": ("FUNCTION_BLOCK f\nRULEBLOCK r\nRULE", 3,
                                           "unexpected end of file: expected a rule number"),
    "rule number": (fcl(IN_A, OUT_B, "RULE ( : IF x IS a THEN y IS b;"), 16,
                    "expected a rule number, got '('"),
    "rule without ':'": (fcl(IN_A, OUT_B, "RULE 1 IF x IS a THEN y IS b;"), 16,
                         "expected ':', got 'IF'"),
    "rule without IF": (fcl(IN_A, OUT_B, "RULE 1 : x IS a THEN y IS b;"), 16,
                        "expected 'IF', got 'x'"),
    "rule without THEN": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a y IS b;"), 16,
                          "expected 'THEN', got 'y'"),
    "condition without IS": (fcl(IN_A, OUT_B, "RULE 1 : IF x a THEN y IS b;"), 16,
                             "expected 'IS', got 'a'"),
    "conclusion without IS": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y b;"), 16,
                              "expected 'IS', got 'b'"),
    "unclosed condition": (fcl(IN_A, OUT_B, "RULE 1 : IF (x IS a THEN y IS b;"), 16,
                           "expected ')', got 'THEN'"),
    "unclosed conclusion": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN (y IS b;"), 16,
                            "expected ')', got ';'"),
    "input not a word": (fcl(IN_A, OUT_B, "RULE 1 : IF 1 IS a THEN y IS b;"), 16,
                         "expected an input variable, got '1'"),
    "output not a word": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN 1 IS b;"), 16,
                          "expected an output variable, got '1'"),
    "condition term not a word": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS 1 THEN y IS b;"), 16,
                                  "expected a term, got '1'"),
    "conclusion term not a word": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS 1;"), 16,
                                   "expected a term, got '1'"),
    "hedge as the term": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS very THEN y IS b;"), 16,
                          "input 'x' has no term 'very'"),
    "weight": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS b WITH w;"), 16,
               "expected a weight (a number), got 'w': values given by variables "
               "(jFuzzyLogic) are not supported"),
    "rule without ';' at the end of the file": (
        _swap(fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS b WITH 0.5"),
              "\nEND_RULEBLOCK\nEND_FUNCTION_BLOCK\n", ""), 16,
        "expected ';' after the rule, got the end of the file"),
    "rule without ';'": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS b\n)"), 17,
                         "expected ';' after the rule, got ')'"),
    "method not a word": (fcl(IN_A, _swap(OUT_B, "METHOD : COG;", "METHOD : 3;")), 13,
                          "expected a defuzzification method, got '3'"),
    "accumulation not a word": (fcl(IN_A, _swap(OUT_B, "METHOD : COG;", "ACCU : 3;")), 13,
                                "expected an accumulation method, got '3'"),
}


@pytest.mark.parametrize(("text", "line", "message"), PARSE_REFUSALS.values(),
                         ids=PARSE_REFUSALS.keys())
def test_each_parser_refusal_names_its_line_and_says_why(text: str, line: int,
                                                         message: str) -> None:
    err = refusal(text)
    assert (err.line, err.message) == (line, message)
    assert str(err) == f"e.fcl:{line}: {message}"


# -- what the parser reads: the syntax tree ----------------------------------------------------
def tree(text: str) -> list[FunctionBlock]:
    return Parser(text, "t.fcl").function_blocks()


def test_tokens_numbers_ranges_and_lines() -> None:
    p = Parser("a 0..1 1. .5 2e3 -3E-2 (* x\n*) /* \n\n */ b // c\n:= ; ( ) , | * / + -", "t")
    assert [(t.kind, t.text, t.line) for t in p.toks] == [
        ("ident", "a", 1), ("num", "0", 1), ("range", "..", 1), ("num", "1", 1),
        ("num", "1.", 1), ("num", ".5", 1), ("num", "2e3", 1), ("punct", "-", 1),
        ("num", "3E-2", 1), ("ident", "b", 4), ("assign", ":=", 5), ("punct", ";", 5),
        ("punct", "(", 5), ("punct", ")", 5), ("punct", ",", 5), ("punct", "|", 5),
        ("punct", "*", 5), ("punct", "/", 5), ("punct", "+", 5), ("punct", "-", 5)]
    assert Parser("", "t").last_line() == 1 and Parser("\n\nx", "t").last_line() == 3
    assert Tok("ident", "Max", 1).upper == "MAX"


def test_numbers_with_signs_nan_and_infinity() -> None:
    def number(text: str) -> float:
        return Parser(text, "t").number("a value")

    assert number("-2.5") == -2.5 and number("+3") == 3.0 and number("7") == 7.0
    assert math.isnan(number("nan")) and math.isnan(number("-NaN"))
    assert number("inf") == math.inf and number("-INF") == -math.inf and number("+Inf") == math.inf
    assert number("0" * 79 + "2") == 2.0  # 80 characters: read
    assert number("1e308") == 1e308


def test_the_parts_of_a_function_block_and_their_lines() -> None:
    text = ("FUNCTION_BLOCK\nVAR_INPUT x : REAL; RANGE := (-1 .. +1); END_VAR\n"
            "VAR_OUTPUT y : REAL; z : REAL; END_VAR\n"
            "FUZZIFY x TERM a := (-1, 1) (1, 0); TERM s := 0.5; END_FUZZIFY\n"
            "DEFUZZIFY y TERM b := -2; TERM g := GAUSS 0 1; METHOD : COGS; ACCU : MAX;\n"
            "DEFAULT := -3; END_DEFUZZIFY\n"
            "DEFUZZIFY z TERM c := +4; DEFAULT := nan; END_DEFUZZIFY\n"
            "RULEBLOCK\nRULE 1 : IF x IS a THEN y IS b\nRULE r2 : IF x IS NOT a THEN z IS c\n"
            "END_RULEBLOCK\nRULEBLOCK two AND : MIN; END_RULEBLOCK\nEND_FUNCTION_BLOCK")
    (fb,) = tree(text)
    assert (fb.name, fb.line, list(fb.inputs), list(fb.outputs)) == ("", 1, ["x"], ["y", "z"])
    x, y, z = fb.inputs["x"], fb.outputs["y"], fb.outputs["z"]
    assert (x.line, x.range, x.range_line, x.block_line) == (2, (-1.0, 1.0), 2, 4)
    assert x.terms["a"].kind == "points" and x.terms["a"].points == [(-1.0, 1.0), (1.0, 0.0)]
    assert (x.terms["s"].kind, x.terms["s"].value, x.terms["s"].line) == ("singleton", 0.5, 4)
    assert (y.terms["b"].kind, y.terms["b"].value) == ("singleton", -2.0)
    g = y.terms["g"]
    assert (g.kind, g.shape, [t.text for t in g.params]) == ("shape", "GAUSS", ["0", "1"])
    assert y.method is not None and (y.method.text, y.method.line) == ("COGS", 5)
    assert y.accu is not None and y.accu.text == "MAX"
    assert (y.default, y.range, y.block_line) == ((-3.0, 6), None, 5)
    assert z.default is not None and math.isnan(z.default[0]) and z.default[1] == 7
    assert (z.terms["c"].value, z.method, z.accu) == (4.0, None, None)
    first, second = fb.blocks
    assert (first.name, first.line, first.ops) == ("", 8, {})
    assert [(r.line, r.conclusions, r.weight) for r in first.rules] == [
        (9, [("y", "b", ())], 1.0), (10, [("z", "c", ())], 1.0)]
    assert first.rules[1].condition == Proposition("x", "a", True, ())
    assert (second.name, second.line, list(second.ops)) == ("two", 12, ["AND"])


def test_a_block_named_like_a_section_has_no_name() -> None:
    for word in ("VAR_INPUT", "VAR_OUTPUT", "FUZZIFY", "DEFUZZIFY", "RULEBLOCK"):
        p = Parser(f"FUNCTION_BLOCK {word}", "t")
        p.next("FUNCTION_BLOCK")
        assert p.peek() == Tok("ident", word, 1)
    (fb,) = tree("FUNCTION_BLOCK END_FUNCTION_BLOCK")
    assert fb.name == ""
    text = "FUNCTION_BLOCK f RULEBLOCK {} RULE 1 : IF x IS a THEN y IS b; END_RULEBLOCK " \
        "END_FUNCTION_BLOCK"
    for word in ("AND : MIN;", "OR : MAX;", "ACT : MIN;", "ACCU : MAX;", ""):
        (fb,) = tree(text.format(word))
        assert fb.blocks[0].name == "" and len(fb.blocks[0].rules) == 1
    (fb,) = tree("FUNCTION_BLOCK f RULEBLOCK END_RULEBLOCK END_FUNCTION_BLOCK")
    assert fb.blocks[0].name == "" and fb.blocks[0].rules == []


def test_an_operator_repeated_with_the_same_value_is_one_setting() -> None:
    (fb,) = tree("FUNCTION_BLOCK f RULEBLOCK r AND : MIN; and : min; OR : MAX; ACT : PROD; "
                 "ACCU : NSUM; END_RULEBLOCK END_FUNCTION_BLOCK")
    ops = fb.blocks[0].ops
    assert {k: (t.text, t.line) for k, t in ops.items()} == {
        "AND": ("MIN", 1), "OR": ("MAX", 1), "ACT": ("PROD", 1), "ACCU": ("NSUM", 1)}


def rules_of(rules: str) -> list[RuleNode]:
    (fb,) = tree(f"FUNCTION_BLOCK f\nRULEBLOCK r\n{rules}\nEND_RULEBLOCK\nEND_FUNCTION_BLOCK")
    return fb.blocks[0].rules


def test_conclusions_hedges_and_weights() -> None:
    r1, r2, r3, r4 = rules_of(
        "RULE 1 : IF x IS a THEN y IS b, z IS very c WITH 0.25;\n"
        "RULE 2 : IF x IS a THEN (y IS somewhat b) AND z IS extremely c AND w IS d\n"
        "RULE 3 : IF x IS a THEN y IS not b;\n"
        "RULE 4 : IF x IS a THEN y IS very not seldom b WITH 1")
    assert (r1.line, r1.conclusions, r1.weight) == (
        3, [("y", "b", ()), ("z", "c", ("very",))], 0.25)
    # fuzzylite hands a conclusion's hedges on to the conclusions after it
    assert r2.conclusions == [("y", "b", ("somewhat",)), ("z", "c", ("extremely", "somewhat")),
                              ("w", "d", ("extremely", "somewhat"))]
    assert r3.conclusions == [("y", "b", ("not",))]
    assert (r4.conclusions, r4.weight) == ([("y", "b", ("very", "not", "seldom"))], 1.0)


def test_conditions_with_not_parentheses_and_hedges() -> None:
    (rule,) = rules_of("RULE 1 : IF NOT (x IS a OR x IS NOT b) AND (w IS very any c) "
                       "AND NOT NOT v IS SOMEWHAT Extremely d THEN y IS e;")
    assert rule.condition == Compound("and", (
        Negation(Compound("or", (Proposition("x", "a"), Proposition("x", "b", True)))),
        Proposition("w", "c", False, ("very", "any")),
        Negation(Negation(Proposition("v", "d", False, ("somewhat", "extremely"))))))
    (rule,) = rules_of("RULE 1 : IF a IS b OR c IS d AND e IS f OR g IS h THEN y IS e;")
    assert rule.condition == Compound("or", (
        Proposition("a", "b"), Compound("and", (Proposition("c", "d"), Proposition("e", "f"))),
        Proposition("g", "h")))
    (rule,) = rules_of("RULE 1 : IF x IS NOT very a THEN y IS e;")
    assert rule.condition == Proposition("x", "a", True, ("very",))


def test_a_duplicate_term_warns_and_the_last_one_is_read() -> None:
    text = fcl("FUZZIFY x\n    TERM a := (0, 1) (1, 0);\n    TERM a := (0, 0) (1, 1);\n"
               "END_FUZZIFY", OUT_B)
    with pytest.warns(FisFormatWarning) as record:
        fls = loads(text, "fcl", path="d.fcl")
    assert [str(w.message) for w in record] == [
        "d.fcl:10: duplicate term 'a' of 'x' (first at line 9): rules naming it take this one"]
    with pytest.warns(FisFormatWarning) as record:  # attributed to a caller of the reader
        fcl_reader.loads(text, "d.fcl")
    assert not record[0].filename.endswith(("fcl.py", "_fclparse.py"))
    assert fls.inputs[0].sets[0].upper(np.array([0.0, 1.0])).tolist() == [0.0, 1.0]
    assert [s.name for s in fls.inputs[0].sets] == ["a"]


@pytest.mark.parametrize(("term", "message"), [
    ("TRIAN 2 1 0", "term 'a': Triangle(2.0, 1.0, 0.0, h=1.0): feet and peak must satisfy "
     "a <= b <= c, a < c"),
    ("TRAPE 3 2 2 1", "term 'a': Trapezoid(3.0, 2.0, 2.0, 1.0, h=1.0): feet and shoulders must "
     "satisfy "
     "a <= b <= c <= d, a < d"),
])
def test_a_term_with_reversed_feet_is_named_not_taken_for_a_point_range(term: str,
                                                                        message: str) -> None:
    # without RANGE the universe is the terms' span, here (2, 0): the term is at fault, not
    # a RANGE the file does not have
    err = refusal(fcl(_swap(IN_A, "(0, 1) (1, 0)", term), OUT_B))
    assert (err.line, err.message) == (9, message)


# -- the meaning of terms: refusals and what is read -------------------------------------------
def in_term(spec: str, range_: str = "") -> str:
    return fcl(_swap(IN_A, "(0, 1) (1, 0);", f"{spec};{range_}"), OUT_B)


def out_term(spec: str, method: str = "COGS") -> str:
    return fcl(IN_A, f"DEFUZZIFY y\n    TERM b := {spec};\n    METHOD : {method};\nEND_DEFUZZIFY")


BUILD_REFUSALS = {
    "parameter from a variable": (in_term("TRIAN 0 m 1"), 9, "term 'a' of 'x': parameter 'm' "
                                  "is not a declared variable"),
    "punctuation in the parameters": (in_term("TRIAN 0 ( 1"), 9,
                                      "term 'a': unexpected '(' in the parameters"),
    # NaN and infinities are no variables (_fclvars lets them through): no number either
    "infinity in the parameters": (in_term("TRIAN 0 inf 1"), 9,
                                   "term 'a': unexpected 'inf' in the parameters"),
    "NaN in the parameters": (in_term("GAUSS NaN 1"), 9,
                              "term 'a': unexpected 'NaN' in the parameters"),
    "a trailing sign": (in_term("TRIAN 0 0.5 1 -"), 9,
                        "term 'a': unexpected '-' in the parameters"),
    "decreasing x": (in_term("(0, 1) (1, 0.5) (0.5, 0)"), 9, "term 'a': the points [(0.0, 1.0), "
                     "(1.0, 0.5), (0.5, 0.0)] must have increasing x"),
    "membership above 1": (in_term("(0, 1) (1, 1.5)"), 9,
                           "term 'a': memberships must lie in [0, 1]"),
    "membership below 0": (in_term("(0, -0.5) (1, 1)"), 9,
                           "term 'a': memberships must lie in [0, 1]"),
    "generalized singletons": (in_term("singletons 1 2"), 9, "term 'a': jFuzzyLogic's "
                               "generalized singletons are not supported"),
    "parameter count": (in_term("TRIAN 0 1", " RANGE := (0 .. 1);"), 9,
                        "term 'a': TRIAN needs 3 parameters, got 2"),
    "parameter count of the span": (in_term("GAUSS 1"), 9,
                                     "term 'a': GAUSS needs 2 parameters, got 1"),
    "unknown shape": (in_term("BLOB 1 2", " RANGE := (0 .. 1);"), 9,
                      "term 'a': unknown shape 'BLOB' (known: TRIAN, TRAPE, GAUSS, GAUSS2, "
                      "GBELL, SIGM, DSIGM, COSINE, Triangle, Trapezoid, Gaussian, "
                      "GaussianProduct, Bell, Sigmoid, SigmoidDifference, SigmoidProduct, "
                      "SShape, ZShape, PiShape, Cosine, Spike, Concave, Ramp, Rectangle, "
                      "Binary, Arc, SemiEllipse, Discrete)"),
    "unknown shape without RANGE": (in_term("BLOB 1"), 9, "term 'a': unknown shape 'BLOB' "
                                    "(known: TRIAN, TRAPE, GAUSS, GAUSS2, GBELL, SIGM, DSIGM, "
                                    "COSINE, Triangle, Trapezoid, Gaussian, GaussianProduct, "
                                    "Bell, Sigmoid, SigmoidDifference, SigmoidProduct, SShape, "
                                    "ZShape, PiShape, Cosine, Spike, Concave, Ramp, Rectangle, "
                                    "Binary, Arc, SemiEllipse, Discrete)"),
    "GAUSS2 means reversed": (in_term("GAUSS2 6 1 3 1"), 9, "term 'a': GAUSS2 with mean1 > "
                              "mean2 (6 > 3) is not MATLAB's gauss2mf in jFuzzyLogic; not "
                              "supported"),
    "DSIGM gains differ": (in_term("DSIGM 2 3 3 7"), 9, "term 'a': jFuzzyLogic's DSIGM is "
                           "max(s1 - s2, 0), MATLAB's dsigmf |s1 - s2|: they agree (and "
                           "it2track reads it) for equal gains and a plateau only"),
    "DSIGM centers reversed": (in_term("DSIGM 2 7 2 3"), 9, "term 'a': jFuzzyLogic's DSIGM is "
                               "max(s1 - s2, 0), MATLAB's dsigmf |s1 - s2|: they agree (and "
                               "it2track reads it) for equal gains and a plateau only"),
    "DSIGM negative gains, centers in order": (in_term("DSIGM -2 3 -2 7"), 9, "term 'a': "
                                               "jFuzzyLogic's DSIGM is max(s1 - s2, 0), "
                                               "MATLAB's dsigmf |s1 - s2|: they agree (and "
                                               "it2track reads it) for equal gains and a "
                                               "plateau only"),
    "DSIGM zero gains": (in_term("DSIGM 0 3 0 7", " RANGE := (0 .. 10);"), 9, "term 'a': "
                         "jFuzzyLogic's DSIGM is max(s1 - s2, 0), MATLAB's dsigmf |s1 - s2|: "
                         "they agree (and it2track reads it) for equal gains and a plateau "
                         "only"),
    "COSINE of zero width": (in_term("COSINE 0 5"), 9,
                             "term 'a': COSINE half width 0 must be > 0"),
    "fuzzylite shape without RANGE": (in_term("Triangle 0 1 2"), 9, "term 'a': its variable "
                                      "needs a RANGE (it2track estimates one from "
                                      "jFuzzyLogic's shapes and points only)"),
    "FUNCTION of an input without RANGE": (in_term("FUNCTION 1"), 9, "term 'a': its variable "
                                           "needs a RANGE (it2track estimates one from "
                                           "jFuzzyLogic's shapes and points only)"),
    "FUNCTION input": (in_term("FUNCTION 1", " RANGE := (0 .. 1);"), 9,
                       "term 'a': FUNCTION is a COGF output term"),
    "singleton of a COG output": (out_term("2", "COG"), 12, "term 'b': a singleton is the "
                                  "value of a COGS output (or an input's Point), not a "
                                  "membership function of an output without METHOD : COGS as "
                                  "here"),
    "values and sets mixed": (fcl(IN_A, "DEFUZZIFY y\n    TERM b := 2;\n    TERM c := (0, 0) "
                                  "(1, 1);\n    METHOD : COGS;\nEND_DEFUZZIFY"), 11,
                              "the terms of 'y' mix values and membership functions"),
    "FUNCTION unclosed": (out_term("FUNCTION (x + 1"), 12,
                          "term 'b': FUNCTION '( x + 1': '(' at character 1 is not closed "
                          "(at the end)"),
    "FUNCTION unclosed by another": (out_term("FUNCTION (x + 1 * 2"), 12,
                                     "term 'b': FUNCTION '( x + 1 * 2': '(' at character 1 is "
                                     "not closed (at the end)"),
    "FUNCTION ends early": (out_term("FUNCTION x +"), 12,
                            "term 'b': FUNCTION 'x +': ends where a number, name or '(' should "
                            "follow (at the end)"),
    "FUNCTION empty": (out_term("FUNCTION"), 12, "term 'b': FUNCTION '': is empty (at the end)"),
    "FUNCTION goes on": (out_term("FUNCTION x 1"), 12,
                         "term 'b': FUNCTION 'x 1': unexpected '1' where the formula should end "
                         "(at character 3)"),
    "FUNCTION of an output": (out_term("FUNCTION y"), 12,
                              "term 'b': FUNCTION 'y' reads the output 'y': it2track reads a "
                              "jFuzzyLogic FUNCTION of the inputs only (fuzzylite's chained "
                              "Function, in its own grammar, reads the outputs declared before "
                              "its own)"),
    "FUNCTION of an operator": (out_term("FUNCTION x + * 2"), 12,
                                "term 'b': FUNCTION 'x + * 2': unexpected '*' where a number, "
                                "name or '(' should be (at character 5)"),
    "Linear of the wrong length": (out_term("Linear 1 2 3"), 12, "term 'b': Linear needs 1 "
                                   "coefficients (one per input) and an optional constant, got "
                                   "3 [1 2 3]"),
    "Constant of two values": (out_term("Constant 1 2"), 12,
                               "term 'b': Constant needs one finite value, got [1 2]"),
    "a shape as a COGS value": (out_term("GAUSS 0 1") .replace("TERM b", "TERM c := 1;\n    "
                                                              "TERM b"), 11,
                                "the terms of 'y' mix values and membership functions"),
}


@pytest.mark.parametrize(("text", "line", "message"), BUILD_REFUSALS.values(),
                         ids=BUILD_REFUSALS.keys())
def test_each_term_refusal_names_its_line_and_says_why(text: str, line: int,
                                                       message: str) -> None:
    err = refusal(text)
    assert (err.line, err.message) == (line, message)


@pytest.mark.parametrize(("terms", "universe"), [
    ("TERM a := GAUSS2 1 0.5 3 0.25;", (1.0 - 2.0, 3.0 + 1.0)),
    ("TERM a := GBELL 2 1 5;", (5.0 - 999.0 ** 0.5 * 2, 5.0 + 999.0 ** 0.5 * 2)),
    ("TERM a := GBELL 1 2 0;", (-(999.0 ** 0.25), 999.0 ** 0.25)),
    ("TERM a := DSIGM 2 3 2 7;", (3.0 - 4.5, 7.0 + 4.5)),
    ("TERM a := DSIGM -3 7 -3 3;", (3.0 - 3.0, 7.0 + 3.0)),
    ("TERM a := SIGM -4.5 2;", (0.0, 4.0)),
    ("TERM a := TRIAN -1 + 0 1;", (-1.0, 1.0)),
    ("TERM a := TRAPE 1 2 3 4; TERM b := (-2, 0) (0, 1);", (-2.0, 4.0)),
    ("TERM a := (2, 1);", (1.0, 3.0)),  # one point: widened by 1 either side
    ("TERM a := (2, 0) (2, 1);", (1.0, 3.0)),
    ("TERM a := TRIAN 1 1 1.5; TERM b := (0.5, 1) (1, 0);", (0.5, 1.5)),
])
def test_more_universes_estimated_as_jfuzzylogic_does(terms: str, universe) -> None:
    fls = loads(fcl(f"FUZZIFY x\n    {terms}\nEND_FUZZIFY", OUT_B), "fcl")
    assert fls.inputs[0].universe == universe


@pytest.mark.parametrize("term", ["GBELL 1 0 5", "SIGM 0 1", "DSIGM 2 3 0 7",
                                  "GAUSS 0 1e308", "GAUSS2 0 1 1e308 1e308"])
def test_a_universe_that_cannot_be_estimated_asks_for_a_range(term: str) -> None:
    err = refusal(in_term(term))
    assert (err.line, err.message) == (8, "'x': give a RANGE")


def test_function_terms_are_read_as_linear_forms() -> None:
    two = "FUZZIFY x\n    TERM a := (0, 1) (1, 0);\nEND_FUZZIFY\nFUZZIFY w\n" \
        "    TERM a := (0, 1) (1, 0);\nEND_FUZZIFY"
    terms = {"-(x * 2) / 4 + +3 - 2 * x": ([-2.5, 0.0], 3.0),
             "w * -1 - (1 - x) * 3": ([3.0, -1.0], -3.0),
             "(2)": ([0.0, 0.0], 2.0),
             "x / 2 / 2 + w - w": ([0.25, 0.0], 0.0),
             "1.5 * (x + w * 2)": ([1.5, 3.0], 0.0)}
    for function, (coefs, constant) in terms.items():
        out = f"DEFUZZIFY y\n    TERM b := FUNCTION {function};\n    METHOD : COGF;\n" \
            "END_DEFUZZIFY"
        fls = loads(fcl(two, out, "    RULE 1 : IF x IS a THEN y IS b;",
                        inputs="x : REAL; w : REAL;"), "fcl")
        assert fls.rules[0].consequent == Linear(coefs, constant), function


def test_singleton_and_fuzzylite_values_of_a_cogs_output() -> None:
    out = "DEFUZZIFY y\n    TERM b := -2;\n    TERM c := Constant 3.5;\n" \
        "    TERM d := Linear 2 -1;\n    METHOD : COGS;\nEND_DEFUZZIFY"
    fls = loads(fcl(IN_A, out, "    RULE 1 : IF x IS a THEN y IS b;\n"
                    "    RULE 2 : IF x IS a THEN y IS c;\n    RULE 3 : IF x IS a THEN y IS d;"),
                "fcl")
    assert [r.consequent for r in fls.rules] == [(-2.0, -2.0), (3.5, 3.5), Linear([2.0], -1.0)]


# -- settings the whole system must agree on -----------------------------------------------------
IN_XW = IN_A + "\nFUZZIFY w\n    TERM a := (0, 1) (1, 0);\nEND_FUZZIFY"  # lines 8-13


def two_inputs(out: str, rules: str, block: str = "") -> str:
    """y's DEFUZZIFY at 14, RULEBLOCK r at 18 (19 with ``block``'s one line)."""
    return fcl(IN_XW, out, rules, inputs="x : REAL; w : REAL;", block=block)


BOTH = "RULE {} : IF x IS a AND w IS a THEN y IS b;"
SECOND_BLOCK = "\nEND_RULEBLOCK\nRULEBLOCK s\n{}\n"


@pytest.mark.parametrize(("text", "line", "message"), [
    # a block without AND takes the minimum: a second block's PROD differs from it
    (two_inputs(OUT_B, BOTH.format(1) + SECOND_BLOCK.format("AND : PROD;") + BOTH.format(2)),
     22, "AND : PROD differs from the earlier AND : the default (line 18); one setting per "
     "system"),
    (two_inputs(OUT_B, BOTH.format(1) + SECOND_BLOCK.format("") + BOTH.format(2),
                "AND : PROD;\n"), 22, "AND : the default differs from the earlier AND : PROD "
     "(line 19); one setting per system"),
    (two_inputs(OUT_B, BOTH.format(1) + SECOND_BLOCK.format("AND : MIN;") + BOTH.format(2),
                "AND : PROD;\n"), 23, "AND : MIN differs from the earlier AND : PROD "
     "(line 19); one setting per system"),
    # OR : ASUM implies AND : PROD, its De Morgan partner
    (two_inputs(OUT_B, BOTH.format(1) + SECOND_BLOCK.format("OR : ASUM;") + BOTH.format(2)),
     22, "AND : ASUM differs from the earlier AND : the default (line 18); one setting per "
     "system"),
    (two_inputs(OUT_B, BOTH.format(1).replace("AND", "OR") + SECOND_BLOCK.format("OR : ASUM;")
                + BOTH.format(2).replace("AND", "OR")), 22,
     "OR : ASUM differs from the earlier OR : the default (line 18); one setting per system"),
    (two_inputs(OUT_B, "RULE 1 : IF x IS a THEN y IS b;" + SECOND_BLOCK.format("ACT : PROD;")
                + "RULE 2 : IF x IS a THEN y IS b;"), 22,
     "ACT : PROD differs from the earlier ACT : the default (line 18); one setting per system"),
    (two_inputs(OUT_B + "\n" + _swap(OUT_B, "DEFUZZIFY y", "DEFUZZIFY z").replace("COG", "COA"),
                "RULE 1 : IF x IS a THEN y IS b, z IS b;").replace("y : REAL;",
                                                                   "y : REAL; z : REAL;"), 20,
     "METHOD : COA differs from the earlier METHOD : COG (line 16); one setting per system"),
    (two_inputs(_swap(OUT_B, "    METHOD : COG;\n", "") + "\n" +
                _swap(OUT_B, "DEFUZZIFY y", "DEFUZZIFY z").replace("COG", "COA"),
                "RULE 1 : IF x IS a THEN y IS b, z IS b;").replace("y : REAL;",
                                                                   "y : REAL; z : REAL;"), 19,
     "METHOD : COA differs from the earlier METHOD : the default (line 14); one setting per "
     "system"),
])
def test_settings_of_several_blocks_or_outputs_must_agree(text: str, line: int,
                                                          message: str) -> None:
    err = refusal(text)
    assert (err.line, err.message) == (line, message)


def test_settings_that_agree_with_the_default_are_one() -> None:
    text = two_inputs(OUT_B, BOTH.format(1) + SECOND_BLOCK.format("AND : MIN; ACT : MIN; "
                                                                  "OR : MAX;") + BOTH.format(2))
    fls = loads(text, "fcl")
    assert (fls.tnorm, fls.snorm, fls.implication) == (TNorm.MINIMUM, SNorm.MAXIMUM,
                                                       Implication.MINIMUM)
    # a rule on one input joins nothing: its block's default AND sets nothing
    prod = loads(two_inputs(OUT_B, "RULE 1 : IF x IS a THEN y IS b;" + SECOND_BLOCK.format(
        "AND : PROD;") + BOTH.format(2)), "fcl")
    assert prod.tnorm is TNorm.PRODUCT


SYSTEM_REFUSALS = {
    "no inputs": ("FUNCTION_BLOCK f\nVAR_OUTPUT y : REAL; END_VAR\n" + OUT_B
                  + "\nRULEBLOCK r\nEND_RULEBLOCK\nEND_FUNCTION_BLOCK", 1,
                  "no VAR_INPUT variables"),
    "no outputs": ("FUNCTION_BLOCK f\nVAR_INPUT x : REAL; END_VAR\n" + IN_A
                   + "\nEND_FUNCTION_BLOCK", 1, "no VAR_OUTPUT variables (a function block "
                   "without outputs is not a fuzzy system)"),
    "no FUZZIFY": (fcl("", OUT_B), 3, "variable 'x' has no FUZZIFY block"),
    "no DEFUZZIFY": (fcl(IN_A, ""), 6, "variable 'y' has no DEFUZZIFY block"),
    "input RANGE a point": (fcl(IN_A.replace("END_FUZZIFY", "RANGE := (1 .. 1);\nEND_FUZZIFY"),
                                OUT_B), 10, "RANGE of 'x' is a point; an input needs lo < hi"),
    "output RANGE a point": (fcl(IN_A, _swap(OUT_B, "END_DEFUZZIFY",
                                             "RANGE := (1 .. 1);\nEND_DEFUZZIFY")), 14,
                             "RANGE of 'y' is a point; an output with sets needs lo < hi"),
    "no rule": (fcl(IN_A, OUT_B, ""), 1, "FUNCTION_BLOCK f: no RULE"),
    "a rule on an unknown variable": (fcl(IN_A, OUT_B, "RULE 1 : IF q IS a THEN y IS b;"), 16,
                                      "rule names 'q', which is not an input"),
    "a rule concluding an input": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN x IS a;"), 16,
                                   "rule concludes 'x', which is not an output"),
    "a rule concluding an input beside an output": (
        fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS b, x IS a;"), 16,
        "rule concludes 'x', which is not an output"),
    "an unknown output term": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS q;"), 16,
                               "output 'y' has no term 'q'"),
    "an unknown input term": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS q THEN y IS b;"), 16,
                              "input 'x' has no term 'q'"),
    "an infinite singleton": (out_term("-inf"), 16,
                              "rule ['a']: consequent 1 (-inf, -inf) must be finite, lo <= hi"),
    "'x is any' on an input without terms": (
        fcl("FUZZIFY x\n    RANGE := (0 .. 1);\nEND_FUZZIFY", OUT_B,
            "RULE 1 : IF x IS any THEN y IS b;"), 16,
        "input 'x' has no term (for 'x is any')"),
    "a weight above 1": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS b WITH 1.5;"), 16,
                         "rule weight 1.5 must be in [0, 1]"),
    "a negative weight": (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS b WITH -0.5;"), 16,
                          "rule weight -0.5 must be in [0, 1]"),
    "OR unknown": (fcl(IN_A, OUT_B, block="OR : FOO;\n"), 16, "OR : FOO is not supported (MAX, "
                   "ASUM, BSUM, DSUM, ESUM, EINSTEIN, HSUM, HAMACHER, NMAX, NIPMAX, DMAX, SUM)"),
    "AND unknown": (fcl(IN_A, OUT_B, block="AND : FOO;\n"), 16, "AND : FOO is not supported "
                    "(MIN, PROD, BDIF, DPROD, EPROD, EINSTEIN, HPROD, HAMACHER, NMIN, NIPMIN, "
                    "DMIN)"),
    "ACT unknown": (fcl(IN_A, OUT_B, block="ACT : FOO;\n"), 16, "ACT : FOO is not supported "
                    "(MIN, PROD, BDIF, DPROD, EPROD, EINSTEIN, HPROD, HAMACHER, NMIN, NIPMIN, "
                    "DMIN)"),
    "ACCU unknown": (fcl(IN_A, OUT_B, block="ACCU : FOO;\n"), 16, "ACCU : FOO is not supported "
                     "(MAX, ASUM, BSUM, DSUM, ESUM, EINSTEIN, HSUM, HAMACHER, NMAX, NIPMAX, "
                     "DMAX, SUM, NSUM, PROBOR)"),
    "ACCU of the output unknown": (fcl(IN_A, _swap(OUT_B, "METHOD : COG;",
                                                   "METHOD : COG; ACCU : FOO;")), 13,
                                   "ACCU : FOO is not supported (MAX, ASUM, BSUM, DSUM, ESUM, "
                                   "EINSTEIN, HSUM, HAMACHER, NMAX, NIPMAX, DMAX, SUM, NSUM, "
                                   "PROBOR)"),
    "METHOD unknown": (fcl(IN_A, _swap(OUT_B, "COG", "FOO")), 13, "METHOD FOO is not supported "
                       "(COG, COA, LM, RM, MM, COGS, COGF, COGSS)"),
    "an output no rule concludes": (
        fcl(IN_A, OUT_B + "\nDEFUZZIFY z\n    TERM b := 2;\n    METHOD : COGS;\nEND_DEFUZZIFY",
            outputs="y : REAL; z : REAL;"), 15, "no rule concludes ['z']"),
    "DEFAULT for some outputs": (
        fcl(IN_A, OUT_B + "\n" + _swap(OUT_B, "DEFUZZIFY y", "DEFUZZIFY z").replace(
            "END_DEFUZZIFY", "DEFAULT := 1;\nEND_DEFUZZIFY"),
            "RULE 1 : IF x IS a THEN y IS b, z IS b;", outputs="y : REAL; z : REAL;"), 11,
        "give DEFAULT for every output or for none"),
    "DEFAULT nan for some outputs": (
        fcl(IN_A, _swap(OUT_B, "END_DEFUZZIFY", "DEFAULT := 2;\nEND_DEFUZZIFY") + "\n" +
            _swap(OUT_B, "DEFUZZIFY y", "DEFUZZIFY z").replace(
                "END_DEFUZZIFY", "DEFAULT := NaN;\nEND_DEFUZZIFY"),
            "RULE 1 : IF x IS a THEN y IS b, z IS b;", outputs="y : REAL; z : REAL;"), 16,
        "give DEFAULT for every output or for none"),
    "a condition on an output no rule before concludes": (
        fcl(IN_A, OUT_B, "RULE 1 : IF y IS b THEN y IS b;"), 16, "the condition reads y is b, "
        "which no rule before it concludes (its degree is always 0)"),
}


@pytest.mark.parametrize(("text", "line", "message"), SYSTEM_REFUSALS.values(),
                         ids=SYSTEM_REFUSALS.keys())
def test_each_system_refusal_names_its_line_and_says_why(text: str, line: int,
                                                         message: str | None) -> None:
    err = refusal(text)
    assert (err.line, err.message) == (line, message)


# -- operators by name, and their De Morgan partners ----------------------------------------------
AND_OR = "RULE 1 : IF x IS a AND w IS a THEN y IS b;\nRULE 2 : IF x IS a OR w IS a THEN y IS b;"


@pytest.mark.parametrize(("ops", "tnorm", "snorm"), [
    ("", TNorm.MINIMUM, SNorm.MAXIMUM),
    ("AND : MIN;", TNorm.MINIMUM, SNorm.MAXIMUM), ("AND : PROD;", TNorm.PRODUCT, SNorm.PROBOR),
    ("AND : BDIF;", TNorm.BOUNDED_DIFFERENCE, SNorm.BOUNDED_SUM),
    ("AND : DPROD;", TNorm.DRASTIC_PRODUCT, SNorm.DRASTIC_SUM),
    ("AND : DMIN;", TNorm.DRASTIC_PRODUCT, SNorm.DRASTIC_SUM),
    ("AND : EPROD;", TNorm.EINSTEIN_PRODUCT, SNorm.EINSTEIN_SUM),
    ("AND : EINSTEIN;", TNorm.EINSTEIN_PRODUCT, SNorm.EINSTEIN_SUM),
    ("AND : HPROD;", TNorm.HAMACHER_PRODUCT, SNorm.HAMACHER_SUM),
    ("AND : HAMACHER;", TNorm.HAMACHER_PRODUCT, SNorm.HAMACHER_SUM),
    ("AND : NMIN;", TNorm.NILPOTENT_MINIMUM, SNorm.NILPOTENT_MAXIMUM),
    ("AND : NIPMIN;", TNorm.NILPOTENT_MINIMUM, SNorm.NILPOTENT_MAXIMUM),
    ("OR : MAX;", TNorm.MINIMUM, SNorm.MAXIMUM), ("OR : ASUM;", TNorm.PRODUCT, SNorm.PROBOR),
    ("OR : BSUM;", TNorm.BOUNDED_DIFFERENCE, SNorm.BOUNDED_SUM),
    ("OR : DSUM;", TNorm.DRASTIC_PRODUCT, SNorm.DRASTIC_SUM),
    ("OR : DMAX;", TNorm.DRASTIC_PRODUCT, SNorm.DRASTIC_SUM),
    ("OR : ESUM;", TNorm.EINSTEIN_PRODUCT, SNorm.EINSTEIN_SUM),
    ("OR : EINSTEIN;", TNorm.EINSTEIN_PRODUCT, SNorm.EINSTEIN_SUM),
    ("OR : HSUM;", TNorm.HAMACHER_PRODUCT, SNorm.HAMACHER_SUM),
    ("OR : HAMACHER;", TNorm.HAMACHER_PRODUCT, SNorm.HAMACHER_SUM),
    ("OR : NMAX;", TNorm.NILPOTENT_MINIMUM, SNorm.NILPOTENT_MAXIMUM),
    ("OR : NIPMAX;", TNorm.NILPOTENT_MINIMUM, SNorm.NILPOTENT_MAXIMUM),
    ("OR : SUM;", TNorm.MINIMUM, SNorm.UNBOUNDED_SUM),  # no partner: the minimum
    ("and : prod; or : max;", TNorm.PRODUCT, SNorm.MAXIMUM),
])
def test_and_or_by_name_and_the_partner_each_implies(ops: str, tnorm: TNorm,
                                                     snorm: SNorm) -> None:
    fls = loads(two_inputs(OUT_B, AND_OR, ops + "\n"), "fcl")
    assert (fls.tnorm, fls.snorm) == (tnorm, snorm)


@pytest.mark.parametrize(("act", "implication"), [
    ("", Implication.MINIMUM), ("ACT : MIN;", Implication.MINIMUM),
    ("ACT : PROD;", Implication.PRODUCT), ("act : Prod;", Implication.PRODUCT),
    ("ACT : BDIF;", Implication.BOUNDED_DIFFERENCE),
    ("ACT : DPROD;", Implication.DRASTIC_PRODUCT),
    ("ACT : EPROD;", Implication.EINSTEIN_PRODUCT),
    ("ACT : HPROD;", Implication.HAMACHER_PRODUCT),
    ("ACT : NMIN;", Implication.NILPOTENT_MINIMUM),
])
def test_act_by_name(act: str, implication: Implication) -> None:
    assert loads(fcl(IN_A, OUT_B, block=act + "\n"), "fcl").implication is implication


@pytest.mark.parametrize(("accu", "aggregation"), [
    ("", Aggregation.SUM), ("ACCU : MAX;", Aggregation.MAXIMUM),
    ("ACCU : NSUM;", Aggregation.SUM), ("ACCU : SUM;", Aggregation.SUM),
    ("ACCU : ASUM;", Aggregation.PROBOR), ("ACCU : PROBOR;", Aggregation.PROBOR),
    ("ACCU : BSUM;", Aggregation.BOUNDED_SUM), ("ACCU : DSUM;", Aggregation.DRASTIC_SUM),
    ("ACCU : ESUM;", Aggregation.EINSTEIN_SUM), ("ACCU : HSUM;", Aggregation.HAMACHER_SUM),
    ("ACCU : NMAX;", Aggregation.NILPOTENT_MAXIMUM),
])
def test_accu_by_name_in_the_rule_block_or_the_output(accu: str,
                                                      aggregation: Aggregation) -> None:
    assert loads(fcl(IN_A, OUT_B, block=accu + "\n"), "fcl").aggregation is aggregation
    out = _swap(OUT_B, "METHOD : COG;", f"METHOD : COG; {accu}")
    assert loads(fcl(IN_A, out), "fcl").aggregation is aggregation


@pytest.mark.parametrize(("method", "defuzzifier"), [
    ("", Defuzzifier.CENTROID), ("METHOD : COG;", Defuzzifier.CENTROID),
    ("METHOD : COA;", Defuzzifier.BISECTOR), ("METHOD : LM;", Defuzzifier.SOM),
    ("METHOD : RM;", Defuzzifier.LOM), ("METHOD : mm;", Defuzzifier.MOM),
])
def test_mamdani_methods(method: str, defuzzifier: Defuzzifier) -> None:
    fls = loads(fcl(IN_A, _swap(OUT_B, "METHOD : COG;", method)), "fcl")
    assert isinstance(fls, T1Mamdani) and fls.defuzzifier is defuzzifier
    assert fls.resolution == 1001 and fls.outputs[0].universe == (0.0, 1.0)


@pytest.mark.parametrize(("method", "defuzzifier"), [
    ("COGS", WeightedDefuzzifier.AVERAGE), ("COGF", WeightedDefuzzifier.AVERAGE),
    ("cogss", WeightedDefuzzifier.SUM),
])
def test_sugeno_methods(method: str, defuzzifier: WeightedDefuzzifier) -> None:
    out = f"DEFUZZIFY y\n    TERM b := 2;\n    METHOD : {method};\nEND_DEFUZZIFY"
    fls = loads(fcl(IN_A, out), "fcl")
    assert isinstance(fls, T1Sugeno) and fls.defuzzifier is defuzzifier
    assert fls.outputs == ("y",) and fls.aggregation is None
    named = loads(fcl(IN_A, out.replace("DEFUZZIFY y", "DEFUZZIFY output1"),
                      "    RULE 1 : IF x IS a THEN output1 IS b;", outputs="output1 : REAL;"),
                  "fcl")
    assert named.outputs == ()  # the plain single output


# -- defaults, shared singletons, several conclusions, several blocks -----------------------------
SING_Y = "DEFUZZIFY y\n    TERM b := 2;\n    TERM c := 8;\n    METHOD : COGS;\nEND_DEFUZZIFY"


def test_default_is_on_zero_firing_one_per_output_and_nan_is_none() -> None:
    one = loads(fcl(IN_A, _swap(SING_Y, "END_DEFUZZIFY", "DEFAULT := -1.5;\nEND_DEFUZZIFY")),
                "fcl")
    assert one.on_zero_firing == -1.5
    z = SING_Y.replace("DEFUZZIFY y", "DEFUZZIFY z")
    two = fcl(IN_A, _swap(SING_Y, "END_DEFUZZIFY", "DEFAULT := 1;\nEND_DEFUZZIFY") + "\n"
              + _swap(z, "END_DEFUZZIFY", "DEFAULT := 2;\nEND_DEFUZZIFY"),
              "RULE 1 : IF x IS a THEN y IS b, z IS c;", outputs="y : REAL; z : REAL;")
    both = loads(two, "fcl")
    assert both.on_zero_firing == (1.0, 2.0) and both.outputs == ("y", "z")
    assert both.rules[0].consequents == ((2.0, 2.0), (8.0, 8.0))
    assert loads(two.replace("DEFAULT := 1;", "DEFAULT := nan;").replace(
        "DEFAULT := 2;", "DEFAULT := NAN;"), "fcl").on_zero_firing is None
    assert loads(fcl(IN_A, SING_Y), "fcl").on_zero_firing is None


def test_a_shared_singleton_takes_the_accumulation_otherwise_the_sum() -> None:
    shared = "RULE 1 : IF x IS a THEN y IS b;\nRULE 2 : IF x IS NOT a THEN y IS b;\n" \
        "RULE 3 : IF x IS a THEN y IS c;"
    assert loads(fcl(IN_A, SING_Y, shared, block="ACCU : MAX;\n"), "fcl").aggregation is (
        Aggregation.MAXIMUM)
    assert loads(fcl(IN_A, SING_Y, shared, block="ACCU : NSUM;\n"), "fcl").aggregation is None
    assert loads(fcl(IN_A, SING_Y, shared), "fcl").aggregation is None
    apart = "RULE 1 : IF x IS a THEN y IS b;\nRULE 2 : IF x IS NOT a THEN y IS c;"
    assert loads(fcl(IN_A, SING_Y, apart, block="ACCU : MAX;\n"), "fcl").aggregation is None
    # equal values are one singleton, whatever the term's name (jFuzzyLogic)
    same = _swap(SING_Y, "TERM c := 8;", "TERM c := 2.0;")
    assert loads(fcl(IN_A, same, apart, block="ACCU : MAX;\n"), "fcl").aggregation is (
        Aggregation.MAXIMUM)


def test_a_second_conclusion_on_one_output_is_the_rule_again() -> None:
    fls = loads(fcl(IN_A, SING_Y, "RULE 1 : IF x IS a THEN y IS b, y IS c, y IS b WITH 0.5;"),
                "fcl")
    assert [(r.consequents, r.weight) for r in fls.rules] == [
        (((2.0, 2.0),), 0.5), (((8.0, 8.0),), 0.5), (((2.0, 2.0),), 0.5)]
    mamdani = loads(fcl(IN_A, _swap(OUT_B, "TERM b := (0, 0) (1, 1);",
                                    "TERM b := (0, 0) (1, 1);\n    TERM c := (0, 1) (1, 0);"),
                        "RULE 1 : IF x IS a THEN y IS very b, y IS c;"), "fcl")
    assert [(r.consequents, r.consequent_hedges) for r in mamdani.rules] == [
        (("b",), ((Hedge("very"),),)), (("c",), ((Hedge("very"),),))]


def test_tsukamoto_takes_the_accumulation_it_is_given() -> None:
    ramps = "DEFUZZIFY y\n    RANGE := (0 .. 1);\n    TERM b := Ramp 0 1;\n" \
        "    TERM c := Ramp 1 0;\n    METHOD : COGS;\nEND_DEFUZZIFY"
    plain = loads(fcl(IN_A, ramps), "fcl")
    assert isinstance(plain, T1Tsukamoto) and plain.aggregation is Aggregation.SUM
    assert loads(fcl(IN_A, ramps, block="ACCU : MAX;\n"), "fcl").aggregation is (
        Aggregation.MAXIMUM)


def test_hybrid_runs_keep_their_rules_and_operators() -> None:
    text = fcl(IN_A, SING_Y + "\n" + OUT_B.replace("DEFUZZIFY y", "DEFUZZIFY m") + "\n"
               + SING_Y.replace("DEFUZZIFY y", "DEFUZZIFY z"),
               "RULE 1 : IF x IS a THEN y IS b, m IS b;\nRULE 2 : IF x IS NOT a THEN z IS c;",
               outputs="y : REAL; m : REAL; z : REAL;", block="ACT : PROD;\n")
    fls = loads(text, "fcl")
    assert isinstance(fls, HybridSystem) and fls.name == "f"
    y, m, z = fls.systems
    assert (type(y), type(m), type(z)) == (T1Sugeno, T1Mamdani, T1Sugeno)
    assert [r.consequents for r in y.rules] == [((2.0, 2.0),)]
    assert [r.consequents for r in m.rules] == [("b",)]
    assert [r.consequents for r in z.rules] == [((8.0, 8.0),)]
    assert m.implication is Implication.PRODUCT and m.aggregation is Aggregation.SUM
    assert (y.outputs, z.outputs) == (("y",), ("z",))


def test_several_blocks_warn_naming_them_and_block_selects_one() -> None:
    text = fcl(IN_A, OUT_B) + fcl(IN_A, OUT_B).replace("FUNCTION_BLOCK f", "FUNCTION_BLOCK g")
    with pytest.warns(FisFormatWarning) as record:
        first = loads(text, "fcl", path="two.fcl")
    assert [str(w.message) for w in record] == [
        "two.fcl:1: 2 FUNCTION_BLOCKs ('f', 'g'); read the first, 'f' (block= selects another)"]
    assert first.name == "f"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert loads(text, "fcl", block="g").name == "g"
        assert loads(fcl(IN_A, OUT_B), "fcl").name == "f"
    with pytest.raises(FisFormatError) as info:
        loads(text, "fcl", path="two.fcl", block="h")
    assert (info.value.line, info.value.message) == (
        None, "no FUNCTION_BLOCK 'h' (the file has 'f', 'g')")


# -- point lists: the shapes they are, with their height ------------------------------------------
@pytest.mark.parametrize(("points", "mf"), [
    ("(0, 1) (1, 0)", Triangle(0.0, 0.0, 1.0)),
    ("(0, 0.5) (1, 0)", Triangle(0.0, 0.0, 1.0, 0.5)),
    ("(0, 0) (1, 0.5)", Triangle(0.0, 1.0, 1.0, 0.5)),
    ("(0, 0) (0.25, 0.5) (1, 0)", Triangle(0.0, 0.25, 1.0, 0.5)),
    ("(0, 0.5) (0.25, 0.5) (1, 0)", Triangle(0.25, 0.25, 1.0, 0.5)),
    ("(0, 0) (0.25, 0.5) (1, 0.5)", Triangle(0.0, 0.25, 0.25, 0.5)),
    ("(0, 0) (0.25, 0.5) (0.5, 0.5) (1, 0)", Trapezoid(0.0, 0.25, 0.5, 1.0, 0.5)),
    ("(0, 0) (0.25, 1) (0.5, 1) (1, 0)", Trapezoid(0.0, 0.25, 0.5, 1.0)),
])
def test_a_triangle_or_trapezoid_of_points_is_one(points: str, mf) -> None:
    fls = loads(in_term(points, " RANGE := (0 .. 1);"), "fcl")
    assert fls.inputs[0].sets[0].upper == mf


@pytest.mark.parametrize("points", [
    "(0, 1) (0.5, 0.5) (1, 0)",  # a degree between 0 and the height
    "(0, 0.5) (1, 0.5)",  # flat
    "(0, 0) (0.5, 0) (1, 0)",  # all zero: no height
    "(0, 0) (0.5, 1) (0.5, 0.5) (1, 0)",  # a vertical step
    "(0, 1) (0.25, 0) (0.5, 1) (1, 0)",  # two peaks
    "(0, 0) (0.25, 1) (0.5, 1) (0.75, 1) (1, 0)",  # a plateau of three points
    "(0.5, 1)",  # one point
    "(0, 0.5) (1, 1)",  # a degree between 0 and the height where a triangle has its foot
    "(0, 0.5) (0.5, 1) (1, 0)",
])
def test_other_polylines_are_discrete(points: str) -> None:
    fls = loads(in_term(points, " RANGE := (0 .. 1);"), "fcl")
    pts = [tuple(float(v) for v in p.strip("() ").split(",")) for p in points.split(") (")]
    assert fls.inputs[0].sets[0].upper == Discrete(pts)


@pytest.mark.parametrize(("term", "range_", "mf"), [
    ("TRIAN 2 2 5", " RANGE := (0 .. 10);", FootedTrapezoid(2.0, 2.0, 2.0, 5.0, 1.0)),
    ("Triangle 2 2 5", " RANGE := (0 .. 10);", FootedTrapezoid(2.0, 2.0, 2.0, 5.0, 1.0)),
    ("TRAPE 0 1 4 4", " RANGE := (0 .. 10);", FootedTrapezoid(0.0, 1.0, 4.0, 4.0, 1.0)),
    ("TRIAN 0 0 5", " RANGE := (0 .. 10);", Triangle(0.0, 0.0, 5.0)),  # shoulder at the end
    ("TRIAN 2 2 5", "", Triangle(2.0, 2.0, 5.0)),  # the estimated universe starts at 2
])
def test_a_named_shape_with_a_shoulder_inside_the_range_drops_to_0_beyond_its_foot(
        term: str, range_: str, mf) -> None:
    assert loads(in_term(term, range_), "fcl").inputs[0].sets[0].upper == mf


@pytest.mark.parametrize(("block", "accu", "z"), [
    ("", "", (1.0 + 0.75 * 5.0) / (1.0 + 0.75)),  # y IS b: 0.75 + 0.25, the sum
    ("ACCU : MAX;\n", "", (0.75 + 0.75 * 5.0) / (0.75 + 0.75)),  # max(0.75, 0.25)
    ("", " ACCU : MAX;", (0.75 + 0.75 * 5.0) / (0.75 + 0.75)),  # the output's ACCU
])
def test_a_chained_proposition_reads_the_earlier_rules_by_the_outputs_accumulation(
        block: str, accu: str, z: float) -> None:
    out_z = "DEFUZZIFY z\n    TERM d := 1;\n    TERM e := 5;\n    METHOD : COGS;\nEND_DEFUZZIFY"
    rules = "RULE 1 : IF x IS a THEN y IS b;\nRULE 2 : IF x IS NOT a THEN y IS b;\n" \
        "RULE 3 : IF y IS b THEN z IS d;\nRULE 4 : IF x IS a THEN z IS e;"
    out_y = SING_Y.replace("METHOD : COGS;", "METHOD : COGS;" + accu)
    fls = loads(fcl(IN_A, out_y + "\n" + out_z, rules, outputs="y : REAL; z : REAL;",
                    block=block), "fcl")
    assert fls(0.25).tolist() == pytest.approx([2.0, z], abs=1e-15)


def test_comment_edges() -> None:
    for text in ("FUNCTION_BLOCK f (*) END_FUNCTION_BLOCK", "FUNCTION_BLOCK f\n/*/"):
        opener = "(*" if "(*" in text else "/*"
        closer = "*)" if opener == "(*" else "*/"
        with pytest.raises(FisFormatError) as info:
            tree(text)
        assert (info.value.line, info.value.message) == (
            text.count("\n", 0, text.index(opener)) + 1,
            f"unterminated comment {opener} ... {closer}")
    assert [t.text for t in Parser("a (**) b /**/ c //\nd", "t").toks] == ["a", "b", "c", "d"]


def test_a_conclusion_term_may_be_named_like_a_hedge() -> None:
    (rule,) = rules_of("RULE 1 : IF x IS a THEN y IS very;")
    assert rule.conclusions == [("y", "very", ())]
    (rule,) = rules_of("RULE 1 : IF x IS a THEN y IS very somewhat, z IS not b")
    assert rule.conclusions == [("y", "somewhat", ("very",)), ("z", "b", ("not", "very"))]


def test_an_input_without_terms_may_feed_a_function() -> None:
    inputs = "FUZZIFY x\n    RANGE := (0 .. 4);\nEND_FUZZIFY\nFUZZIFY w\n" \
        "    TERM a := (0, 1) (1, 0);\nEND_FUZZIFY"
    out = "DEFUZZIFY y\n    TERM f := FUNCTION 2 * x;\n    METHOD : COGF;\nEND_DEFUZZIFY"
    fls = loads(fcl(inputs, out, "RULE 1 : IF w IS a THEN y IS f;",
                    inputs="x : REAL; w : REAL;"), "fcl")
    assert fls.inputs[0].sets == () and fls.inputs[0].universe == (0.0, 4.0)
    assert float(fls(3.0, 0.5)) == 6.0


def test_act_is_ignored_by_a_sugeno_system() -> None:
    fls = loads(fcl(IN_A, SING_Y, "RULE 1 : IF x IS a THEN y IS b;" + SECOND_BLOCK.format(
        "ACT : PROD;") + "RULE 2 : IF x IS NOT a THEN y IS c;", block="ACT : MIN;\n"), "fcl")
    assert isinstance(fls, T1Sugeno) and len(fls.rules) == 2


def test_a_rules_negations_and_hedges_reach_the_built_rule() -> None:
    fls = loads(two_inputs(OUT_B, "RULE 1 : IF x IS NOT very a AND w IS somewhat a "
                           "THEN y IS b WITH 0.5;"), "fcl")
    (rule,) = fls.rules
    assert (rule.antecedent, rule.negated, rule.hedges, rule.weight) == (
        ("a", "a"), (True, False), ((Hedge("very"),), (Hedge("somewhat"),)), 0.5)
    (rule,) = loads(two_inputs(OUT_B, "RULE 1 : IF w IS a THEN y IS b;"), "fcl").rules
    assert (rule.antecedent, rule.negated, rule.hedges) == ((None, "a"), (False, False),
                                                            ((), ()))


def test_an_overflow_on_the_universe_is_refused_at_the_block() -> None:
    err = refusal(in_term("(0, 1) (1e-300, 0)", " RANGE := (0 .. 1e10);"))
    assert (err.line, err.message) == (8, "numeric overflow (overflow encountered in divide)")


@pytest.mark.parametrize(("term", "mf"), [
    ("GAUSS2 3 1 3 2", GaussianProduct(3.0, 1.0, 3.0, 2.0)),  # equal means
    ("DSIGM 2 3 2 3", SigmoidDifference(3.0, 2.0, 2.0, 3.0)),  # equal centers
    ("DSIGM -2 7 -2 3", SigmoidDifference(7.0, -2.0, -2.0, 3.0)),
    ("DSIGM -2 5 -2 5", SigmoidDifference(5.0, -2.0, -2.0, 5.0)),
    ("COSINE 1e-3 5", Cosine(5.0, 2e-3)),
    ("GBELL 2 1 5", Bell(5.0, 2.0, 1.0)),
    ("SIGM 3 1", Sigmoid(1.0, 3.0)),
])
def test_named_shapes_at_their_boundaries(term: str, mf) -> None:
    assert loads(in_term(term, " RANGE := (0 .. 10);"), "fcl").inputs[0].sets[0].upper == mf


def test_the_reader_names_a_string_without_a_path() -> None:
    with pytest.raises(FisFormatError) as info:
        fcl_reader.loads("FUNCTION_BLOCK f END_FUNCTION_BLOCK")
    assert str(info.value) == "<string>:1: no VAR_INPUT variables"


def test_the_several_blocks_warning_is_not_attributed_to_the_reader() -> None:
    text = fcl(IN_A, OUT_B) + fcl(IN_A, OUT_B).replace("FUNCTION_BLOCK f", "FUNCTION_BLOCK g")
    with pytest.warns(FisFormatWarning) as record:
        fcl_reader.loads(text, "two.fcl")
    assert not record[0].filename.endswith("fcl.py")  # stacklevel: a caller of loads


def test_underflow_is_no_refusal() -> None:
    # exp(-(10 / 0.01)^2 / 2) underflows to 0 on the universe: that is the value, not an error
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fls = loads(in_term("GAUSS 0 0.01", " RANGE := (0 .. 10);"), "fcl")
    assert fls.inputs[0].sets[0].upper == Gaussian(0.0, 0.01)


def test_weights_0_and_1_are_read() -> None:
    fls = loads(fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS b WITH 0;\n"
                    "RULE 2 : IF x IS NOT a THEN y IS b WITH 1.0;"), "fcl")
    assert [r.weight for r in fls.rules] == [0.0, 1.0]


def test_an_input_named_twice_is_a_condition_tree() -> None:
    from it2track.fuzzy.conditions import Is, Join, Not

    (rule,) = loads(fcl(IN_A, OUT_B, "RULE 1 : IF x IS a AND x IS NOT a THEN y IS b;"),
                    "fcl").rules
    assert (rule.antecedent, rule.connective.value) == ((None,), "and")
    assert rule.condition == Join("and", (Is(0, "a"), Not(Is(0, "a"))), norm=TNorm.MINIMUM)
    (rule,) = loads(fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS b;"), "fcl").rules
    assert (rule.antecedent, rule.condition) == (("a",), None)


def test_the_rule_again_comes_right_after_the_rule() -> None:
    fls = loads(fcl(IN_A, SING_Y, "RULE 1 : IF x IS a THEN y IS b, y IS c;\n"
                    "RULE 2 : IF x IS NOT a THEN y IS b;"), "fcl")
    assert [(r.consequents, r.negated) for r in fls.rules] == [
        (((2.0, 2.0),), (False,)), (((8.0, 8.0),), (False,)), (((2.0, 2.0),), (True,))]


@pytest.mark.parametrize(("text", "line", "message"), [
    (fcl(IN_A, _swap(OUT_B, "METHOD : COG;", "METHOD : COG; ACCU : MAX;"),
         "RULE 1 : IF x IS a THEN y IS b;", block="ACCU : SUM;\n"), 16,
     "ACCU : SUM differs from the earlier ACCU : MAX (line 13); one setting per system"),
    (fcl(IN_A, _swap(OUT_B, "METHOD : COG;", "METHOD : COG; ACCU : MAX;") + "\n"
         + _swap(OUT_B, "DEFUZZIFY y", "DEFUZZIFY z").replace("METHOD : COG;",
                                                              "METHOD : COG; ACCU : SUM;"),
         "RULE 1 : IF x IS a THEN y IS b, z IS b;", outputs="y : REAL; z : REAL;"), 17,
     "ACCU : SUM differs from the earlier ACCU : MAX (line 13); one setting per system"),
    (fcl(IN_A, OUT_B, "RULE 1 : IF x IS a THEN y IS b;" + SECOND_BLOCK.format("ACCU : FOO;")
         + "RULE 2 : IF x IS a THEN y IS b;", block="ACCU : MAX;\n"), 20,
     "ACCU : FOO is not supported (MAX, ASUM, BSUM, DSUM, ESUM, EINSTEIN, HSUM, HAMACHER, NMAX, "
     "NIPMAX, DMAX, SUM, NSUM, PROBOR)"),
    # an OR rule in a block with AND : PROD only: its OR is PROD's partner, set by that line
    (two_inputs(OUT_B, BOTH.format(1).replace("AND", "OR") + SECOND_BLOCK.format("OR : MAX;")
                + BOTH.format(2).replace("AND", "OR"), "AND : PROD;\n"), 23,
     "OR : MAX differs from the earlier OR : PROD (line 19); one setting per system"),
])
def test_accumulations_and_partners_must_agree(text: str, line: int, message: str) -> None:
    err = refusal(text)
    assert (err.line, err.message) == (line, message)


def test_a_mamdani_output_shape_is_footed_on_its_range() -> None:
    out = _swap(OUT_B, "TERM b := (0, 0) (1, 1);", "TERM b := TRIAN 2 2 5; RANGE := (0 .. 10);")
    fls = loads(fcl(IN_A, out), "fcl")
    assert fls.outputs[0].sets[0].upper == FootedTrapezoid(2.0, 2.0, 2.0, 5.0, 1.0)


def test_de_morgan_flattens_where_the_norms_are_duals_and_the_tree_keeps_the_or() -> None:
    (rule,) = loads(two_inputs(OUT_B, "RULE 1 : IF NOT (x IS a OR w IS a) THEN y IS b;"),
                    "fcl").rules
    assert (rule.antecedent, rule.negated, rule.connective.value, rule.condition) == (
        ("a", "a"), (True, True), "and", None)
    (rule,) = loads(two_inputs(OUT_B, "RULE 1 : IF x IS a AND (w IS a OR x IS a) THEN y IS b;",
                               "OR : ASUM;\n"), "fcl").rules
    from it2track.fuzzy.conditions import Is, Join

    assert rule.condition == Join("and", (Is(0, "a"), Join("or", (Is(1, "a"), Is(0, "a")),
                                                            norm=SNorm.PROBOR)),
                                  norm=TNorm.PRODUCT)


def test_a_function_over_two_lines_is_refused_at_the_token_it_stops_at() -> None:
    err = refusal(out_term("FUNCTION x *\n* x"))
    assert (err.line, err.message) == (13, "term 'b': FUNCTION 'x * * x': unexpected '*' where "
                                       "a number, name or '(' should be (at character 5)")


@pytest.mark.parametrize(("text", "line", "message"), [
    (in_term("Triangle 2 1 0", " RANGE := (0 .. 10);"), 9, "term 'a': Triangle [2 1 0]: "
     "Triangle(2.0, 1.0, 0.0, h=1.0): feet and peak must satisfy a <= b <= c, a < c"),
    (in_term("DSIGM 0 7 0 3", " RANGE := (0 .. 10);"), 9, "term 'a': jFuzzyLogic's DSIGM is "
     "max(s1 - s2, 0), MATLAB's dsigmf |s1 - s2|: they agree (and it2track reads it) for "
     "equal gains and a plateau only"),
    (in_term("DSIGM 0.5 7 0.5 3", " RANGE := (0 .. 10);"), 9, "term 'a': jFuzzyLogic's DSIGM "
     "is max(s1 - s2, 0), MATLAB's dsigmf |s1 - s2|: they agree (and it2track reads it) for "
     "equal gains and a plateau only"),
    (out_term("FUNCTION 1e308 * 10 + x"), 12,
     "term 'b': linear constant c0 (inf, inf) must be finite, lo <= hi"),
    (out_term("FUNCTION 1e308 * 10 * x"), 12,
     "term 'b': linear coefficient c1 (inf, inf) must be finite, lo <= hi"),
])
def test_what_the_shapes_and_functions_refuse_is_named_with_the_term(text: str, line: int,
                                                                     message: str) -> None:
    err = refusal(text)
    assert (err.line, err.message) == (line, message)


def test_plus_signs_and_small_gains() -> None:
    assert loads(in_term("TRIAN + 1 2 + 3"), "fcl").inputs[0].sets[0].upper == Triangle(
        1.0, 2.0, 3.0)
    fls = loads(in_term("DSIGM 0.5 3 0.5 7", " RANGE := (0 .. 10);"), "fcl")
    assert fls.inputs[0].sets[0].upper == SigmoidDifference(3.0, 0.5, 0.5, 7.0)


def test_a_subnormal_width_below_zero_is_refused_too() -> None:
    err = refusal(in_term("(-1e-320, 1) (0, 0)"))
    assert (err.line, err.message) == (9, "term 'a': the points at x = -1e-320 and x = 0.0 are "
                                       "closer than the smallest normal float "
                                       "(2.2250738585072014e-308): the slope between them "
                                       "overflows")


# -- the second mutation run of _fclbuild ------------------------------------------------------
def test_numeric_errors_are_refused_whatever_numpy_is_set_to() -> None:
    # inf - inf on the universe: refused even where the caller ignores invalid values
    with np.errstate(all="ignore"):
        err = refusal(in_term("SemiEllipse -1e308 1e308", " RANGE := (0 .. 10);"))
    assert (err.line, err.message) == (8, "numeric overflow (invalid value encountered in "
                                       "subtract)")
    # ... and an underflow (exp(-(10 / 0.01)^2 / 2) = 0) is a value where the caller raises
    with np.errstate(under="raise"):
        fls = loads(in_term("GAUSS 0 0.01", " RANGE := (0 .. 10);"), "fcl")
    assert fls.inputs[0].sets[0].upper == Gaussian(0.0, 0.01)


@pytest.mark.parametrize(("points", "message"), [
    ("(0, 0) (inf, 1)", "term 'a': Triangle(0.0, inf, inf, h=1.0): parameter b=inf must be a "
     "finite number"),
    ("(nan, 0) (1, 1)", "term 'a': Triangle(nan, 1.0, 1.0, h=1.0): parameter a=nan must be a "
     "finite number"),
    ("(0, 0) (1, 0.5) (inf, 1)", "term 'a': Discrete(points=((0.0, 0.0), (1.0, 0.5), (inf, "
     "1.0)), h=1.0): parameter x3=inf must be a finite number"),
])
def test_points_at_an_infinite_or_nan_x_are_refused_naming_the_term(points: str,
                                                                    message: str) -> None:
    err = refusal(in_term(points, " RANGE := (0 .. 1);"))
    assert (err.line, err.message) == (9, message)


@pytest.mark.parametrize(("function", "linear"), [
    ("FUNCTION x / 1", Linear([1.0, 0.0], 0.0)),
    ("FUNCTION (x) * (2) - (w)", Linear([2.0, -1.0], 0.0)),
    ("Function 2 * x + 1", Linear([2.0, 0.0], 1.0)),
    ("FUNCTION x / 0", None),  # by zero
    ("FUNCTION x / w", None),  # by an input
    ("FUNCTION x * w", None),  # input times input
    ("Function x + pi", None),  # a name that is no input (fuzzylite's pi)
    ("FUNCTION x ^ 2", None),
    ("FUNCTION (x ^ 2)", None),
    ("FUNCTION abs(x)", None),
])
def test_a_function_not_linear_in_the_inputs_is_its_formula(function: str,
                                                            linear: Linear | None) -> None:
    two = "FUZZIFY x\n    TERM a := (0, 1) (1, 0);\nEND_FUZZIFY\nFUZZIFY w\n" \
        "    TERM a := (0, 1) (1, 0);\nEND_FUZZIFY"
    out = f"DEFUZZIFY y\n    TERM b := {function};\n    METHOD : COGF;\nEND_DEFUZZIFY"
    fls = loads(fcl(two, out, inputs="x : REAL; w : REAL;"), "fcl")
    word, text = function.split(" ", 1)
    tokens = " ".join(text.replace("(", " ( ").replace(")", " ) ").split())
    dialect = "fuzzylite" if word == "Function" else "jfuzzylogic"
    assert fls.rules[0].consequent == (linear or Formula(tokens, dialect, ("x", "w"))), function


def test_a_fuzzylite_function_is_refused_in_its_own_spelling() -> None:
    err = refusal(out_term("Function x +"))
    assert (err.line, err.message) == (12, "term 'b': Function 'x +': ends where a number, name "
                                       "or '(' should follow (at the end)")


# -- the second mutation run of _fclparse ------------------------------------------------------
def test_x_is_any_names_no_term_and_keeps_its_hedges_and_negation() -> None:
    r1, r2, r3 = rules_of("RULE 1 : IF x IS any THEN y IS e;\n"
                          "RULE 2 : IF x IS NOT very ANY AND w IS Any THEN y IS e;\n"
                          "RULE 3 : IF x IS any a THEN y IS e;")
    assert r1.condition == Proposition("x", "", False, ("any",))
    assert r2.condition == Compound("and", (Proposition("x", "", True, ("very", "any")),
                                            Proposition("w", "", False, ("any",))))
    assert r3.condition == Proposition("x", "a", False, ("any",))  # the hedge before a term


@pytest.mark.parametrize(("default", "value", "nc"), [
    ("DEFAULT := NC;", None, True), ("DEFAULT := 0.5 | NC;", (0.5, 3), True),
    ("DEFAULT := nc;", None, True), ("DEFAULT := -1;", (-1.0, 3), False), ("", None, False)])
def test_default_nc_is_no_change(default: str, value: tuple[float, int] | None,
                                 nc: bool) -> None:
    (fb,) = tree("FUNCTION_BLOCK f\nVAR_OUTPUT y : REAL; END_VAR\n"
                 f"DEFUZZIFY y TERM b := 1; {default} END_DEFUZZIFY\nEND_FUNCTION_BLOCK")
    y = fb.outputs["y"]
    assert (y.default, y.nc) == (value, nc)


def test_point_values_given_by_variables_are_nan_with_their_names_in_refs() -> None:
    (fb,) = tree("FUNCTION_BLOCK f\nVAR_INPUT x : REAL; END_VAR\n"
                 "FUZZIFY x TERM a := (0, lo) (mid, 1) (2, top) (inf, 0); END_FUZZIFY\n"
                 "END_FUNCTION_BLOCK")
    a = fb.inputs["x"].terms["a"]
    assert a.refs == {1: "lo", 2: "mid", 5: "top"}  # 2k: point k's x, 2k + 1: its degree
    assert math.isnan(a.points[1][0]) and a.points[1][1] == 1.0
    assert math.isnan(a.points[0][1]) and math.isnan(a.points[2][1])
    assert (a.points[0][0], a.points[2][0], a.points[3]) == (0.0, 2.0, (math.inf, 0.0))

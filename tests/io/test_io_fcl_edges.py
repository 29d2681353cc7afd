"""FCL reading at its edges: every refusal's line and message to the letter, keywords in any
case, comments spanning lines, NOT in either place, the operators' defaults and De Morgan
partners, each METHOD, the universes without RANGE, DEFAULT for several outputs.

Written from the cases a mutation test of ``io/fcl.py`` found unpinned (docs/guide/mutation.md).
"""

from __future__ import annotations

import pytest

from it2track.fuzzy import (
    Aggregation,
    Defuzzifier,
    Implication,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
)
from it2track.io import FisFormatError
from it2track.io.fcl import loads

BASE = """FUNCTION_BLOCK f
VAR_INPUT
    x : REAL;
END_VAR
VAR_OUTPUT
    y : REAL;
END_VAR
FUZZIFY x
    TERM lo := (0, 1) (1, 0);
    TERM hi := (0, 0) (1, 1);
END_FUZZIFY
DEFUZZIFY y
    TERM a := (0, 0) (5, 1) (10, 0);
    TERM b := (5, 0) (10, 1);
    METHOD : COG;
END_DEFUZZIFY
RULEBLOCK r
    AND : MIN;
    RULE 1 : IF x IS lo THEN y IS a;
    RULE 2 : IF x IS hi THEN y IS b;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""

SUGENO = BASE.replace("TERM a := (0, 0) (5, 1) (10, 0);", "TERM a := 2;").replace(
    "TERM b := (5, 0) (10, 1);", "TERM b := 8;").replace("METHOD : COG;", "METHOD : COGS;")


def line_of(text: str, needle: str) -> int:
    return next(i for i, line in enumerate(text.split("\n"), 1) if needle in line)


def refusal(text: str) -> tuple[int | None, str]:
    with pytest.raises(FisFormatError) as info:
        loads(text, "c.fcl")
    err = info.value
    assert err.path == "c.fcl"
    return err.line, err.message


# (old, new, the line blamed (a needle in the new text, or a number), the message)
CASES = [
    ("TERM lo := (0, 1) (1, 0);", "TERM lo := (0, 1) (1, 0) @;", "TERM lo",
     "unexpected character '@'"),
    ("    x : REAL;", "    x REAL;", "x REAL", "expected ':', got 'REAL'"),
    ("    x : REAL;", "    1 : REAL;", "1 : REAL", "expected a variable name, got '1'"),
    ("    x : REAL;", "    x : 1;", "x : 1", "expected a type, got '1'"),
    ("(0, 1) (1, 0)", "(z, 1) (1, 0)", "TERM lo", "expected x (a number), got 'z'"),
    ("(0, 1) (1, 0)", "(0, z) (1, 0)", "TERM lo",
     "expected a membership degree (a number), got 'z'"),
    ("(0, 1) (1, 0)", "(0, 1) (1e999, 0)", "TERM lo", "number '1e999' is out of range"),
    ("(0, 1) (1, 0)", "(1, 1) (1, 0)", "TERM lo",
     "term points [(1.0, 1.0), (1.0, 0.0)] must have strictly increasing x"),
    ("(0, 1) (1, 0)", "(0, 1.5) (1, 0)", "TERM lo",
     "term points [(0.0, 1.5), (1.0, 0.0)]: memberships must lie in [0, 1]"),
    ("(0, 1) (1, 0)", "(0, -0.5) (1, 0)", "TERM lo",
     "term points [(0.0, -0.5), (1.0, 0.0)]: memberships must lie in [0, 1]"),
    ("(0, 1) (1, 0)", "(0, 0) (1, 0)", "TERM lo",
     "term shape [(0.0, 0.0), (1.0, 0.0)] is not supported: it2track reads triangles "
     "(a,0)(b,h)(c,0), trapezoids (a,0)(b,h)(c,h)(d,0) and shoulders"),
    ("(0, 1) (1, 0)", "(0, 1) (1, 0.5)", "TERM lo",
     "term shape [(0.0, 1.0), (1.0, 0.5)] is not supported: it2track reads triangles "
     "(a,0)(b,h)(c,0), trapezoids (a,0)(b,h)(c,h)(d,0) and shoulders"),
    ("    y : REAL;\nEND_VAR", "    x : REAL;\nEND_VAR", 6, "variable 'x' declared twice"),
    ("    x : REAL;", "    x : REAL;\n    x : REAL;", 4, "variable 'x' declared twice"),
    ("    x : REAL;", "    x : INT;", "x : INT", "variable 'x' has type INT: only REAL is "
     "supported"),
    ("FUZZIFY x", "RULES\nFUZZIFY x", "RULES",
     "unexpected 'RULES' (expected VAR_INPUT, VAR_OUTPUT, FUZZIFY, DEFUZZIFY, RULEBLOCK or "
     "END_FUNCTION_BLOCK)"),
    ("END_FUNCTION_BLOCK\n", "END_FUNCTION_BLOCK\nFUZZIFY\n", 23,
     "text after END_FUNCTION_BLOCK: 'FUZZIFY'"),
    ("FUZZIFY x", "FUZZIFY y", "FUZZIFY y", "FUZZIFY y: not declared in VAR_INPUT"),
    ("DEFUZZIFY y", "DEFUZZIFY x", "DEFUZZIFY x", "DEFUZZIFY x: not declared in VAR_OUTPUT"),
    ("END_FUZZIFY\n", "END_FUZZIFY\nFUZZIFY x\n    TERM m := (0, 0) (1, 1);\nEND_FUZZIFY\n",
     12, "second FUZZIFY block for 'x' (first at line 8)"),
    ("TERM hi := (0, 0) (1, 1);", "TERM lo := (0, 0) (1, 1);", 10, "duplicate term 'lo' of 'x'"),
    ("TERM lo := (0, 1) (1, 0);", "TERM lo := 3;", "TERM lo",
     "a singleton input term is not supported"),
    ("TERM lo := (0, 1) (1, 0);", "TERM lo := (0, 1);", "TERM lo",
     "term 'lo' needs at least two points (x, membership)"),
    ("TERM lo := (0, 1) (1, 0);", "TERM lo := ;", "TERM lo",
     "term 'lo' needs at least two points (x, membership)"),
    ("END_FUZZIFY", "    RANGE := (1 .. 1);\nEND_FUZZIFY", "RANGE",
     "RANGE (1.0 .. 1.0) must satisfy lo < hi"),
    ("METHOD : COG;", "METHOD : MEAN;", "METHOD", "METHOD MEAN is not supported (COG, COGS, "
     "COA, LM, RM)"),
    ("METHOD : COG;", "METHOD : COG;\n    DEFAULT := NC;", "DEFAULT",
     "DEFAULT := NC (keep the last output) needs state, which it2track systems do not have; "
     "give a value"),
    ("METHOD : COG;", "METHOD : COG;\n    ACCU : MAX;", "ACCU", "put ACCU in the RULEBLOCK"),
    ("END_FUZZIFY", "    METHOD : COG;\nEND_FUZZIFY", 11,
     "unexpected 'METHOD' in FUZZIFY x"),
    ("END_FUZZIFY", "    DEFAULT := 0;\nEND_FUZZIFY", "DEFAULT",
     "unexpected 'DEFAULT' in FUZZIFY x"),
    ("END_FUZZIFY", "    ACCU : MAX;\nEND_FUZZIFY", "ACCU", "unexpected 'ACCU' in FUZZIFY x"),
    ("    TERM lo := (0, 1) (1, 0);\n    TERM hi := (0, 0) (1, 1);\n", "", "FUZZIFY x",
     "FUZZIFY x: no TERM"),
    ("AND : MIN;", "AND : BDIF;", "AND :", "AND : BDIF is not supported (MIN, PROD)"),
    ("AND : MIN;", "OR : BSUM;", "OR :", "OR : BSUM is not supported (MAX, ASUM)"),
    ("AND : MIN;", "ACT : MAX;", "ACT :", "ACT : MAX is not supported (MIN, PROD)"),
    ("AND : MIN;", "ACCU : BSUM;", "ACCU :", "ACCU : BSUM is not supported (MAX, NSUM)"),
    ("AND : MIN;", "AND : MIN;\n    AND : PROD;", "AND : PROD",
     "AND : PROD differs from the earlier AND : MIN (line 18); one setting per system"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF (x IS lo) THEN y IS a;", "RULE 1",
     "parentheses in rule conditions are not supported"),
    ("RULE 1 : IF x IS lo THEN y IS a;",
     "RULE 1 : IF x IS lo OR x IS hi AND x IS lo THEN y IS a;", "RULE 1",
     "a rule mixing AND and OR needs parentheses, which are not supported"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULES 1 : IF x IS lo THEN y IS a;", "RULES 1",
     "unexpected 'RULES' in RULEBLOCK"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF z IS lo THEN y IS a;", "RULE 1",
     "rule names 'z', which is not an input"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS mid THEN y IS a;", "RULE 1",
     "input 'x' has no term 'mid'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo AND x IS hi THEN y IS a;",
     "RULE 1", "rule names input 'x' twice"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo THEN z IS a;", "RULE 1",
     "rule concludes 'z', which is not an output"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo THEN y IS c;", "RULE 1",
     "output 'y' has no term 'c'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo THEN y IS a WITH 1.5;", "RULE 1",
     "rule weight 1.5 must be in [0, 1]"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo THEN y IS a WITH -0.25;",
     "RULE 1", "rule weight -0.25 must be in [0, 1]"),
    ("    x : REAL;", "    x : REAL;\n    w : REAL;", "w : REAL", "variable 'w' has no FUZZIFY "
     "block"),
    ("    y : REAL;", "    y : REAL;\n    v : REAL;", "v : REAL", "variable 'v' has no "
     "DEFUZZIFY block"),
    ("    RULE 1 : IF x IS lo THEN y IS a;\n    RULE 2 : IF x IS hi THEN y IS b;\n", "",
     "END_FUNCTION_BLOCK", "no RULE"),
    ("    RULE 1", "    RULE 1 : IF x IS lo THEN y IS a\n    RULE 1", 20,
     "expected ';', got 'RULE'"),
    ("END_RULEBLOCK\nEND_FUNCTION_BLOCK\n", "END_RULEBLOCK\n", "END_RULEBLOCK",
     "unexpected end of file: expected END_FUNCTION_BLOCK"),
    ("END_RULEBLOCK\nEND_FUNCTION_BLOCK\n", "", "RULE 2",
     "unexpected end of file: expected END_RULEBLOCK"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : x IS lo THEN y IS a;", "RULE 1",
     "expected 'IF', got 'x'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x lo THEN y IS a;", "RULE 1",
     "expected 'IS', got 'lo'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo y IS a;", "RULE 1",
     "expected 'THEN', got 'y'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo THEN y a;", "RULE 1",
     "expected 'IS', got 'a'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS 1 THEN y IS a;", "RULE 1",
     "expected a term, got '1'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo THEN y IS 1;", "RULE 1",
     "expected a term, got '1'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF 2 IS lo THEN y IS a;", "RULE 1",
     "expected an input variable, got '2'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo THEN 2 IS a;", "RULE 1",
     "expected an output variable, got '2'"),
    ("RULE 1 : IF x IS lo THEN y IS a;", "RULE 1 : IF x IS lo THEN y IS a WITH w;", "RULE 1",
     "expected a weight (a number), got 'w'"),
    ("TERM lo := (0, 1) (1, 0);", "TERM 1 := (0, 1) (1, 0);", "TERM 1",
     "expected a term name, got '1'"),
    ("RULEBLOCK r", "RULEBLOCK 1", "RULEBLOCK 1", "expected a rule block name, got '1'"),
    ("AND : MIN;", "AND : 1;", "AND : 1", "expected an AND operator, got '1'"),
    ("METHOD : COG;", "METHOD : 1;", "METHOD : 1",
     "expected a defuzzification method, got '1'"),
    ("TERM a := (0, 0) (5, 1) (10, 0);", "TERM a := (0, 0) (5, 1) (10, 0);\n"
     "    DEFAULT := x;", "DEFAULT", "expected a default value (a number), got 'x'"),
    ("END_FUZZIFY", "    RANGE := (0 .. z);\nEND_FUZZIFY", "RANGE",
     "expected the range end (a number), got 'z'"),
    ("END_FUZZIFY", "    RANGE := (z .. 1);\nEND_FUZZIFY", "RANGE",
     "expected the range start (a number), got 'z'"),
]


@pytest.mark.parametrize(("old", "new", "where", "message"), CASES, ids=[c[3][:40] for c in CASES])
def test_refusals_name_the_line_and_say_what_is_wrong(old, new, where, message):
    assert old in BASE
    text = BASE.replace(old, new, 1)
    line = where if isinstance(where, int) else line_of(text, where)
    assert refusal(text) == (line, message)


def test_no_inputs_or_no_outputs():
    no_in = BASE.replace("VAR_INPUT\n    x : REAL;\nEND_VAR\n", "VAR_INPUT\nEND_VAR\n")
    no_in = no_in[:no_in.index("FUZZIFY x")] + no_in[no_in.index("DEFUZZIFY y"):]
    assert refusal(no_in) == (1, "no VAR_INPUT variables")
    no_out = BASE.replace("VAR_OUTPUT\n    y : REAL;\nEND_VAR\n", "VAR_OUTPUT\nEND_VAR\n")
    no_out = no_out[:no_out.index("DEFUZZIFY y")] + no_out[no_out.index("RULEBLOCK"):]
    assert refusal(no_out) == (1, "no VAR_OUTPUT variables")


def test_an_empty_file_and_a_missing_block_keyword():
    assert refusal("") == (1, "unexpected end of file: expected 'FUNCTION_BLOCK'")
    assert refusal("\n\nFUNCTION f") == (3, "expected 'FUNCTION_BLOCK', got 'FUNCTION'")


def test_an_empty_comment_is_a_comment():
    fls = loads(BASE.replace("FUNCTION_BLOCK f", "FUNCTION_BLOCK f (**)"))
    assert fls.name == "f"


def test_unterminated_comment_names_its_line():
    text = BASE.replace("END_FUZZIFY", "(* open\nEND_FUZZIFY", 1)
    assert refusal(text) == (line_of(text, "(* open"), "unterminated comment (* ... *)")


def test_sugeno_refusals():
    shared = SUGENO.replace("THEN y IS b;", "THEN y IS a;")
    assert refusal(shared) == (
        line_of(shared, "RULE 2"),
        "singleton 'a' of 'y' is concluded by this rule and the one at line 19: with COGS and "
        "ACCU : MAX that is not a weighted average of rules (use ACCU : NSUM, or one rule per "
        "singleton)")
    mixed = SUGENO.replace("TERM b := 8;", "TERM b := (5, 0) (10, 1);")
    assert refusal(mixed) == (line_of(mixed, "TERM b"), "term 'b': METHOD COGS needs "
                              "singletons (TERM t := value) and the other methods need point "
                              "lists")
    points = BASE.replace("TERM b := (5, 0) (10, 1);", "TERM b := 8;")
    assert refusal(points) == (line_of(points, "TERM b"), "term 'b': METHOD COGS needs "
                               "singletons (TERM t := value) and the other methods need point "
                               "lists")


TWO_OUT = BASE.replace("    y : REAL;", "    y : REAL;\n    z : REAL;").replace(
    "END_DEFUZZIFY\n", "END_DEFUZZIFY\nDEFUZZIFY z\n    TERM c := (0, 0) (1, 1);\n"
    "    METHOD : COG;\nEND_DEFUZZIFY\n").replace("THEN y IS a;", "THEN y IS a, z IS c;")


def test_several_outputs_share_a_method_and_give_defaults_all_or_none():
    fls = loads(TWO_OUT)
    assert isinstance(fls, T1Mamdani) and fls.output_names == ("y", "z")
    assert fls.rules[0].consequents == ("a", "c") and fls.rules[1].consequents == ("b", None)
    assert fls.on_zero_firing is None
    methods = TWO_OUT.replace("    METHOD : COG;\nEND_DEFUZZIFY\nDEFUZZIFY z",
                              "    METHOD : COA;\nEND_DEFUZZIFY\nDEFUZZIFY z")
    assert refusal(methods) == (6, "outputs use different METHODs ['COA', 'COG']: one per "
                                "system")
    one = TWO_OUT.replace("    TERM c := (0, 0) (1, 1);", "    TERM c := (0, 0) (1, 1);\n"
                          "    DEFAULT := 0.5;")
    assert refusal(one) == (6, "give DEFAULT for every output or for none")
    both = one.replace("    METHOD : COG;\nEND_DEFUZZIFY\nDEFUZZIFY z",
                       "    METHOD : COG;\n    DEFAULT := 2;\nEND_DEFUZZIFY\nDEFUZZIFY z")
    assert loads(both).on_zero_firing == (2.0, 0.5)


def test_default_of_one_output_is_a_number():
    fls = loads(BASE.replace("METHOD : COG;", "METHOD : COG;\n    DEFAULT := 7;"))
    assert fls.on_zero_firing == 7.0


@pytest.mark.parametrize(("ops", "tnorm", "snorm"), [
    ("", TNorm.MINIMUM, SNorm.MAXIMUM),
    ("AND : MIN;", TNorm.MINIMUM, SNorm.MAXIMUM),
    ("AND : PROD;", TNorm.PRODUCT, SNorm.PROBOR),
    ("OR : ASUM;", TNorm.PRODUCT, SNorm.PROBOR),
    ("OR : MAX;", TNorm.MINIMUM, SNorm.MAXIMUM),
    ("AND : PROD;\n    OR : MAX;", TNorm.PRODUCT, SNorm.MAXIMUM),
    ("or : asum;\n    and : min;", TNorm.MINIMUM, SNorm.PROBOR),
])
def test_and_or_default_to_their_de_morgan_partner(ops, tnorm, snorm):
    fls = loads(BASE.replace("AND : MIN;", ops))
    assert (fls.tnorm, fls.snorm) == (tnorm, snorm)


@pytest.mark.parametrize(("ops", "implication", "aggregation"), [
    ("", Implication.MINIMUM, Aggregation.MAXIMUM),
    ("ACT : PROD;", Implication.PRODUCT, Aggregation.MAXIMUM),
    ("ACT : MIN;\n    ACCU : NSUM;", Implication.MINIMUM, Aggregation.SUM),
    ("ACCU : MAX;", Implication.MINIMUM, Aggregation.MAXIMUM),
])
def test_act_and_accu(ops, implication, aggregation):
    fls = loads(BASE.replace("AND : MIN;", ops))
    assert (fls.implication, fls.aggregation) == (implication, aggregation)


@pytest.mark.parametrize(("method", "defuzzifier"), [
    ("COG", Defuzzifier.CENTROID), ("COA", Defuzzifier.BISECTOR), ("LM", Defuzzifier.SOM),
    ("RM", Defuzzifier.LOM), ("cog", Defuzzifier.CENTROID)])
def test_each_method(method, defuzzifier):
    fls = loads(BASE.replace("METHOD : COG;", f"METHOD : {method};"))
    assert fls.defuzzifier is defuzzifier


def test_without_method_the_default_is_cog():
    fls = loads(BASE.replace("    METHOD : COG;\n", ""))
    assert isinstance(fls, T1Mamdani) and fls.defuzzifier is Defuzzifier.CENTROID


def test_negation_in_either_place_and_twice():
    for cond, neg in (("x IS NOT lo", True), ("NOT x IS lo", True), ("NOT x IS NOT lo", False),
                      ("x IS lo", False)):
        fls = loads(BASE.replace("IF x IS lo THEN", f"IF {cond} THEN"))
        assert fls.rules[0].negated == (neg,), cond


def test_or_rules_and_several_rule_blocks():
    two = BASE.replace("    x : REAL;", "    x : REAL;\n    w : REAL;").replace(
        "FUZZIFY x", "FUZZIFY w\n    TERM p := (0, 0) (1, 1);\nEND_FUZZIFY\nFUZZIFY x").replace(
        "IF x IS lo THEN", "IF w IS p OR x IS lo THEN")
    fls = loads(two)
    assert fls.rules[0].connective.value == "or" and fls.rules[1].connective.value == "and"
    assert fls.rules[0].antecedent == ("lo", "p")  # in VAR_INPUT order (x, w), not the rule's
    blocks = BASE.replace("    RULE 2 : IF x IS hi THEN y IS b;\n",
                          "END_RULEBLOCK\nRULEBLOCK s\n    AND : MIN;\n"
                          "    RULE 2 : IF x IS hi THEN y IS b WITH 0.5;\n")
    fls = loads(blocks)
    assert [r.weight for r in fls.rules] == [1.0, 0.5]


def test_universes_from_range_or_from_the_terms():
    fls = loads(BASE)
    assert fls.inputs[0].universe == (0.0, 1.0) and fls.outputs[0].universe == (0.0, 10.0)
    ranged = BASE.replace("    METHOD : COG;", "    METHOD : COG;\n    RANGE := (-5 .. 20);")
    assert loads(ranged).outputs[0].universe == (-5.0, 20.0)
    sug = loads(SUGENO)
    assert isinstance(sug, T1Sugeno) and sug.inputs[0].universe == (0.0, 1.0)
    assert sug([0.0, 1.0]).tolist() == [2.0, 8.0]
    wide = BASE.replace("TERM hi := (0, 0) (1, 1);", "TERM hi := (-3, 0) (7, 1);")
    assert loads(wide).inputs[0].universe == (-3.0, 7.0)


def test_keywords_case_comments_and_the_name():
    text = ("function_block (* a comment\nover two lines *) tip // and one to the end\n"
            + BASE.split("\n", 1)[1].replace("END_VAR", "end_var").replace("TERM", "term"))
    fls = loads(text)
    assert fls.name == "tip" and isinstance(fls, T1Mamdani)
    bad = text.replace("term lo := (0, 1) (1, 0);", "term lo := (0, 1) (1, 0) %;")
    assert refusal(bad) == (line_of(bad, "term lo"), "unexpected character '%'")
    assert loads(BASE.replace("FUNCTION_BLOCK f", "FUNCTION_BLOCK")).name == ""


def test_shapes_of_every_supported_polyline():
    def term(points: str):
        text = BASE.replace("TERM lo := (0, 1) (1, 0);", f"TERM lo := {points};")
        return next(s for s in loads(text).inputs[0].sets if s.name == "lo").upper

    assert term("(0, 1) (1, 0)") == Triangle(0, 0, 1)
    assert term("(0, 0.5) (1, 0)") == Triangle(0, 0, 1, h=0.5)
    assert term("(0, 0) (1, 0.5)") == Triangle(0, 1, 1, h=0.5)
    assert term("(0, 0) (0.5, 0.7) (1, 0)") == Triangle(0, 0.5, 1, h=0.7)
    assert term("(0, 0.6) (0.5, 0.6) (1, 0)") == Triangle(0.5, 0.5, 1, h=0.6)
    assert term("(0, 0) (0.5, 0.9) (1, 0.9)") == Triangle(0, 0.5, 0.5, h=0.9)
    assert term("(0.25, 0) (0.5, 1) (0.75, 0)") == Triangle(0.25, 0.5, 0.75)
    assert term("(0, 0) (0.25, 0.8) (0.5, 0.8) (1, 0)") == Trapezoid(0, 0.25, 0.5, 1, h=0.8)


@pytest.mark.parametrize("first", ["VAR_INPUT", "VAR_OUTPUT", "FUZZIFY", "DEFUZZIFY", "RULEBLOCK",
                                   "END_FUNCTION_BLOCK"])
def test_an_unnamed_block_reads_as_a_named_one(first):
    # the block's first word is not taken for its name: the text after "FUNCTION_BLOCK" reads
    # the same with and without a name (same system, or the same refusal on the same line)
    body = BASE.split("\n", 1)[1]
    body = body[body.index(first):] if first != "VAR_INPUT" else body
    named, unnamed = "FUNCTION_BLOCK f\n" + body, "FUNCTION_BLOCK\n" + body
    try:
        want = loads(named, "c.fcl")
    except FisFormatError as exc:
        assert refusal(unnamed) == (exc.line, exc.message)
    else:
        got = loads(unnamed, "c.fcl")
        assert (got.name, want.name) == ("", "f") and got.rules == want.rules


def test_a_universe_too_wide_is_blamed_on_its_block():
    text = BASE.replace("TERM lo := (0, 1) (1, 0);", "TERM lo := (-1e308, 1) (1e308, 0);")
    assert refusal(text) == (8, "input 'x': universe=(-1e+308, 1e+308) must be finite, "
                             "lo < hi, with a finite width hi - lo")


def test_weights_zero_and_one_are_accepted():
    text = BASE.replace("THEN y IS a;", "THEN y IS a WITH 0;").replace(
        "THEN y IS b;", "THEN y IS b WITH 1;")
    assert [r.weight for r in loads(text).rules] == [0.0, 1.0]

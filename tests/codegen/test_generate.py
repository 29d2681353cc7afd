"""What ``codegen/generate.py`` decides, without a compiler: the prefix rule at its limits, every
refusal's message to the letter (it names the system, the feature and what is carried), the
checks that apply only to some systems (s-norm only with OR rules, implication and aggregation
only for a centroid Mamdani system, the fixed-point refusals only for q15), and what
``generate_c`` returns for each arithmetic."""

from __future__ import annotations

import dataclasses

import pytest

import it2track
from it2track.codegen import RealType, generate_c
from it2track.codegen.fixedpoint import FixedFormat
from it2track.codegen.generate import check_prefix, check_supported
from it2track.fuzzy import (
    EKM,
    Aggregation,
    Defuzzifier,
    Gaussian,
    Implication,
    Input,
    IT2Mamdani,
    IT2Set,
    IT2Sugeno,
    Linear,
    Output,
    Rule,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Triangle,
    TypeReduction,
    WeightedDefuzzifier,
)
from it2track.io import UnsupportedFeatureError

A_SET, B_SET = Triangle(0, 1, 3), Triangle(1, 3, 4)
PREFIX_RULE = ("must be a lower-case C identifier: a letter, then up to 30 letters, digits or "
               "'_', and not a C keyword")
#: C keywords and the library names the generated code uses: never a prefix.
RESERVED = ["auto", "break", "case", "char", "const", "continue", "default", "do", "double",
            "else", "enum", "extern", "float", "for", "goto", "if", "inline", "int", "long",
            "register", "restrict", "return", "short", "signed", "sizeof", "static", "struct",
            "switch", "typedef", "union", "unsigned", "void", "volatile", "while", "main", "exp",
            "expf", "math"]


def refusal(call) -> str:
    with pytest.raises(UnsupportedFeatureError) as info:
        call()
    return str(info.value)


def sugeno(name: str = "s", **kw) -> IT2Sugeno:
    x = Input("x", (0, 4), [IT2Set.type1(A_SET, "a"), IT2Set.type1(B_SET, "b")])
    return IT2Sugeno(inputs=[x], rules=[Rule(["a"], -1.0), Rule(["b"], 2.0)], name=name, **kw)


def mamdani(cls=IT2Mamdani, name: str = "m", **kw):
    x = Input("x", (0, 4), [IT2Set.type1(A_SET, "a"), IT2Set.type1(B_SET, "b")])
    if cls is T1Mamdani:
        y = Output("y", (0, 4), [IT2Set.type1(Triangle(0, 0, 4), "small"),
                                 IT2Set.type1(Triangle(0, 4, 4), "big")])
    else:
        y = Output("y", (0, 4), [IT2Set(Triangle(0, 0, 4), Triangle(0, 0, 2), "small"),
                                 IT2Set(Triangle(0, 4, 4), Triangle(2, 4, 4), "big")])
    return cls(inputs=[x], outputs=[y], rules=[Rule(["a"], "small"), Rule(["b"], "big")],
               resolution=5, name=name, **kw)


def odd(system, **fields):
    """The system with fields set past its validation (an enum member added later, say)."""
    out = dataclasses.replace(system)
    for k, v in fields.items():
        object.__setattr__(out, k, v)
    return out


# --- check_prefix -----------------------------------------------------------------------------

@pytest.mark.parametrize("prefix", ["a", "z", "a" + "b" * 30, "a_", "x9", "k0_z9_", "it2"])
def test_prefixes_at_the_limits_are_accepted_and_returned(prefix):
    assert check_prefix(prefix) is prefix


@pytest.mark.parametrize("prefix", ["", "a" * 32, "_a", "9a", "aB", "A", "a-b", "a b", "a.b",
                                    "é", "a\n", None, 7, b"abc"])
def test_bad_prefixes_are_refused_with_the_rule(prefix):
    with pytest.raises(ValueError) as info:
        check_prefix(prefix)  # type: ignore[arg-type]
    assert str(info.value) == f"prefix={prefix!r} {PREFIX_RULE}"


@pytest.mark.parametrize("word", RESERVED)
def test_each_c_keyword_and_library_name_is_refused(word):
    with pytest.raises(ValueError) as info:
        check_prefix(word)
    assert str(info.value) == f"prefix={word!r} {PREFIX_RULE}"
    assert check_prefix(word + "_") == word + "_"  # the word with more is a name


def test_generate_c_checks_the_prefix_and_the_arithmetic_first():
    with pytest.raises(ValueError) as info:
        generate_c(sugeno(), prefix="int")
    assert str(info.value) == f"prefix='int' {PREFIX_RULE}"
    for real in ("float", None, 32):
        with pytest.raises(ValueError) as info:
            generate_c(sugeno(), real=real)  # type: ignore[arg-type]
        assert str(info.value) == f"real={real!r} must be a RealType"


# --- check_supported: each refusal to the letter ----------------------------------------------

def test_a_type_that_is_not_a_supported_system_is_refused_by_name():
    class Mine(T1Sugeno):
        pass

    base = T1Sugeno(inputs=[Input("x", (0, 4), [("a", A_SET)])], rules=[Rule(["a"], 1.0)])
    for obj, name in ((object(), "object"), (Mine(inputs=base.inputs, rules=base.rules), "Mine"),
                      (None, "NoneType")):
        assert refusal(lambda o=obj: check_supported(o)) == (
            f"cannot generate C for a {name}: supported are Sugeno/TSK systems (IT2Sugeno, "
            "T1Sugeno) and Mamdani systems (IT2Mamdani, T1Mamdani)")
    for system in (base, sugeno(), mamdani(), mamdani(T1Mamdani)):
        check_supported(system)  # each exact type: carried


def test_a_type1_sugeno_aggregation_is_refused():
    t1 = T1Sugeno(inputs=[Input("x", (0, 4), [("a", A_SET)])], rules=[Rule(["a"], 1.0)],
                  aggregation=Aggregation.MAXIMUM, name="agg")
    assert refusal(lambda: check_supported(t1)) == (
        "system 'agg' groups its rules by consequent value (T1Sugeno aggregation, jFuzzyLogic's "
        "ACCU), which C generation does not implement")


def test_features_outside_the_allow_list_are_named_in_order(monkeypatch):
    fls = sugeno("feat")
    monkeypatch.setattr(fls.tables, "features",
                        frozenset({"zzz", "outputs", "mamdani", "not", "linear"}))
    assert refusal(lambda: check_supported(fls)) == (
        "system 'feat' uses rule-language feature(s) a Mamdani output, several outputs (export "
        "one with select_output()), zzz that C generation does not implement (it implements: "
        "linear, not, or, weights)")
    monkeypatch.setattr(fls.tables, "features", frozenset({"not", "or", "weights", "linear"}))
    check_supported(fls)  # the whole allow-list: carried


def test_a_membership_function_without_c_is_named_with_its_own_input():
    # rows: x a, x b, w t, w G upper (a Gaussian: carried), w G lower (scaled-lagged: not)
    g = IT2Set.from_scale_lag(Gaussian(-1, 0.5), scale=0.8, lag=0.2, name="G")
    w = Input("w", (-2, 2), [IT2Set.type1(A_SET, "t"), g])
    x = Input("x", (0, 4), [IT2Set.type1(A_SET, "a"), IT2Set.type1(B_SET, "b")])
    fls = IT2Sugeno(inputs=[x, w], rules=[Rule(["a", "t"], 1.0), Rule(["b", "G"], 2.0)])
    assert refusal(lambda: check_supported(fls)) == (
        f"input 'w': membership function {g.lower!r} has no C implementation (supported: "
        "triangle, trapezoid, Gaussian, uncertain-mean Gaussian)")
    assert repr(g.lower).startswith("ScaledLagged(")


def test_every_carried_membership_kind_is_accepted():
    sets = [IT2Set.type1(Triangle(0, 1, 3), "t"), IT2Set.type1(Gaussian(2, 1), "g"),
            IT2Set.gaussian_uncertain_mean(1, 2, 0.5, "u")]
    fls = IT2Sugeno(inputs=[Input("x", (0, 4), sets)],
                    rules=[Rule([s.name], float(i)) for i, s in enumerate(sets)])
    assert sorted(set(fls.tables.mf_kind.tolist())) == [0, 1, 2, 3]
    check_supported(fls)


def test_the_tnorm_is_refused_by_name_with_the_carried_ones():
    for system in (sugeno("tn"), mamdani(name="tn")):
        bad = odd(system, tnorm=TNorm.EINSTEIN_PRODUCT)
        assert refusal(lambda b=bad: check_supported(b)) == (
            "system 'tn': t-norm 'einstein_product' has no C implementation (supported: min, "
            "product)")
        assert refusal(lambda s=system: check_supported(odd(s, tnorm="mine"))) == (
            "system 'tn': t-norm 'mine' has no C implementation (supported: min, product)")
        for tn in (TNorm.PRODUCT, TNorm.MINIMUM):
            check_supported(odd(system, tnorm=tn))


def test_the_snorm_is_checked_only_where_a_rule_uses_or():
    x = Input("x", (0, 4), [IT2Set.type1(A_SET, "a"), IT2Set.type1(B_SET, "b")])
    z = Input("z", (0, 4), [IT2Set.type1(A_SET, "a")])
    rules = [Rule(["a", "a"], 1.0, connective="or"), Rule(["b", None], 2.0)]
    with_or = IT2Sugeno(inputs=[x, z], rules=rules, snorm=SNorm.BOUNDED_SUM, name="or")
    assert refusal(lambda: check_supported(with_or)) == (
        "system 'or': s-norm 'bounded_sum' has no C implementation (supported: max, probor)")
    for sn in (SNorm.MAXIMUM, SNorm.PROBOR):
        check_supported(dataclasses.replace(with_or, snorm=sn))
    check_supported(sugeno(snorm=SNorm.BOUNDED_SUM))  # no OR rule: the s-norm is never used


def test_a_weighted_sum_type1_sugeno_is_refused():
    t1 = T1Sugeno(inputs=[Input("x", (0, 4), [("a", A_SET)])], rules=[Rule(["a"], 1.0)],
                  defuzzifier=WeightedDefuzzifier.SUM)
    assert refusal(lambda: check_supported(t1)) == (
        "defuzzifier <WeightedDefuzzifier.SUM: 'wtsum'> has no C implementation (weighted "
        "average only)")


@pytest.mark.parametrize("cls", [IT2Mamdani, T1Mamdani])
def test_a_centroid_mamdani_systems_implication_and_aggregation_are_checked(cls):
    bad = odd(mamdani(cls, "cm"), implication=Implication.HAMACHER_PRODUCT)
    assert refusal(lambda: check_supported(bad)) == (
        "system 'cm': implication 'hamacher_product' has no C implementation (supported: min, "
        "product)")
    bad = odd(mamdani(cls, "cm"), aggregation=Aggregation.BOUNDED_SUM)
    assert refusal(lambda: check_supported(bad)) == (
        "system 'cm': aggregation 'bounded_sum' has no C implementation (supported: max, "
        "probor, sum)")
    for imp in (Implication.MINIMUM, Implication.PRODUCT):
        for agg in (Aggregation.MAXIMUM, Aggregation.SUM, Aggregation.PROBOR):
            check_supported(mamdani(cls, implication=imp, aggregation=agg))


def test_a_centre_of_sets_mamdani_system_uses_neither_implication_nor_aggregation():
    cos = mamdani(type_reduction=TypeReduction.CENTRE_OF_SETS)
    check_supported(odd(cos, implication=Implication.HAMACHER_PRODUCT,
                        aggregation=Aggregation.BOUNDED_SUM))


@pytest.mark.parametrize("d", [Defuzzifier.BISECTOR, Defuzzifier.MOM, Defuzzifier.SOM,
                               Defuzzifier.LOM])
def test_a_type1_mamdani_defuzzifier_other_than_the_centroid_is_refused(d):
    assert refusal(lambda: check_supported(mamdani(T1Mamdani, "t1", defuzzifier=d))) == (
        f"system 't1': defuzzifier {d.value!r} has no C implementation (supported: centroid): "
        "it picks grid points by exact comparisons, so a last-bit difference in the aggregated "
        "set moves it by whole grid steps")


def test_fixed_point_refusals_only_for_q15():
    for cls, name in ((IT2Mamdani, "IT2Mamdani"), (T1Mamdani, "T1Mamdani")):
        m = mamdani(cls, "fx")
        assert refusal(lambda m=m: check_supported(m, RealType.Q15)) == (
            f"{name} 'fx': Mamdani systems have no fixed-point implementation (the q15 build's "
            "scaling and error bound are derived for zero-order Sugeno consequents); use --real "
            "float")
        assert refusal(lambda m=m: generate_c(m, real=RealType.Q15)).startswith(name + " 'fx'")
    cos = mamdani(name="fx", type_reduction=TypeReduction.CENTRE_OF_SETS)
    assert "Mamdani systems have no fixed-point" in refusal(
        lambda: check_supported(cos, RealType.Q15))
    x = Input("x", (0, 4), [IT2Set.type1(A_SET, "a"), IT2Set.type1(B_SET, "b")])
    tsk = IT2Sugeno(inputs=[x], rules=[Rule(["a"], Linear([2.0], 0.5)), Rule(["b"], 1.0)],
                    name="lin")
    assert refusal(lambda: check_supported(tsk, RealType.Q15)) == (
        "system 'lin' has first-order (linear) consequents, which have no fixed-point "
        "implementation (their products with the inputs and the per-step sort of the rules "
        "are not scaled nor bounded in q15); use --real float")
    assert "first-order (linear)" in refusal(lambda: generate_c(tsk, real=RealType.Q15))
    for real in (None, RealType.FLOAT, RealType.DOUBLE):
        for system in (tsk, mamdani(), mamdani(T1Mamdani)):
            check_supported(system, real)
    check_supported(sugeno(), RealType.Q15)


# --- generate_c -------------------------------------------------------------------------------

@pytest.mark.parametrize("real", [RealType.FLOAT, RealType.DOUBLE])
def test_generate_c_fills_the_float_templates(real):
    fls = it2track.heading_fls(0.2)
    fls = dataclasses.replace(fls, reducer=EKM)
    code = generate_c(fls, real=real, prefix="hd")
    assert (code.prefix, code.real, code.reducer) == ("hd", real, "ekm")
    assert (code.n_inputs, code.n_rules) == (fls.n_inputs, fls.n_rules) == (2, 9)
    assert (code.header_name, code.source_name, code.fixed) == ("hd.h", "hd.c", None)
    assert "hd_eval(" in code.header and '#include "hd.h"' in code.source
    assert f"typedef {real.value} hd_real;" in code.header
    # the norm combiners are rendered with the prefix (the product t-norm: acc *= expr)
    assert "*= " in code.source and "HD_LT(" in code.source
    assert generate_c(fls, real=real).header_name == "it2.h"  # the default prefix


def test_generate_c_fills_the_fixed_point_templates():
    fls = it2track.heading_fls(0.0)
    code = generate_c(fls, real=RealType.Q15, prefix="fx")
    assert (code.prefix, code.real, code.reducer) == ("fx", RealType.Q15, "type-1")
    assert (code.n_inputs, code.n_rules) == (2, 9)
    assert (code.header_name, code.source_name) == ("fx.h", "fx.c")
    assert isinstance(code.fixed, FixedFormat) and code.fixed.width == 16
    assert " * Fixed point (q15): integer-only arithmetic" in code.header
    assert "typedef int16_t fx_real;" in code.header and '#include "fx.h"' in code.source
    assert "double" not in code.source and "float" not in code.source  # integer-only


def test_the_default_arithmetic_is_double():
    code = generate_c(sugeno())
    assert code.real is RealType.DOUBLE and code.reducer == "exhaustive"
    assert code.n_inputs == 1 and code.n_rules == 2

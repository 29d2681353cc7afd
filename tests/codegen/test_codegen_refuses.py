"""What the generator refuses: an explicit allow-list, so that anything it does not implement --
including a rule-language feature added to the fuzzy layer later -- is refused with
UnsupportedFeatureError before any file is written."""

from __future__ import annotations

import dataclasses

import pytest

import it2track
from it2track.codegen import SUPPORTED_FEATURES, RealType, check_supported, generate_c, write_c
from it2track.fuzzy import KM, Gaussian, Input, IT2Set, IT2Sugeno, Rule, TypeReducer
from it2track.io import UnsupportedFeatureError


def test_rule_language_features_outside_the_allow_list_are_refused(monkeypatch, tmp_path):
    fls = it2track.heading_fls(0.2)
    for feature in ("weights", "or", "a-feature-from-the-future"):
        if feature in SUPPORTED_FEATURES:
            continue
        monkeypatch.setattr(fls.tables, "features", frozenset({feature}))
        with pytest.raises(UnsupportedFeatureError, match=feature):
            generate_c(fls)
    assert list(tmp_path.iterdir()) == []


def test_features_it_does_not_implement_are_refused_in_real_systems():
    from it2track.fuzzy import Aggregation, Implication, IT2Mamdani, Linear, Output, Triangle
    sets = [IT2Set.from_fou(Triangle(-1, -1, 1), 0.2, "N"),
            IT2Set.from_fou(Triangle(-1, 1, 1), 0.2, "P")]
    x = Input("x", (-1, 1), sets)
    two = IT2Sugeno(inputs=[x], rules=[Rule(["N"], consequents=[1.0, 2.0]),
                                       Rule(["P"], consequents=[-1.0, 0.0])])
    with pytest.raises(UnsupportedFeatureError, match="several outputs"):
        generate_c(two)
    y = Output("y", (0, 4), [IT2Set(Triangle(0, 0, 4), Triangle(0, 0, 2), "small"),
                             IT2Set(Triangle(0, 4, 4), Triangle(2, 4, 4), "big")])
    mamdani = IT2Mamdani(inputs=[x], outputs=[y],
                         rules=[Rule(["N"], "small"), Rule(["P"], "big")], resolution=5)
    tsk = IT2Sugeno(inputs=[x], rules=[Rule(["N"], Linear([2.0], 0.5)), Rule(["P"], 1.0)])
    for system in (mamdani, tsk):  # carried in float and double, refused in fixed point
        assert "it2_eval" in generate_c(system, real=RealType.FLOAT).source
    with pytest.raises(UnsupportedFeatureError, match="Mamdani systems have no fixed-point"):
        generate_c(mamdani, real=RealType.Q15)
    with pytest.raises(UnsupportedFeatureError, match=r"first-order \(linear\) consequents"):
        generate_c(tsk, real=RealType.Q15)
    # an operator outside the allow-list is refused by name (an enum member added later, say)
    for field, value, what in (("implication", "lukasiewicz", "implication 'lukasiewicz'"),
                               ("aggregation", "bounded-sum", "aggregation 'bounded-sum'"),
                               ("tnorm", "einstein", "t-norm 'einstein'")):
        odd = dataclasses.replace(mamdani)
        object.__setattr__(odd, field, value)
        with pytest.raises(UnsupportedFeatureError, match=what):
            generate_c(odd)
    assert Implication.PRODUCT and Aggregation.PROBOR  # the members it does carry
    weighted = IT2Sugeno(inputs=[x], rules=[Rule(["N"], 1.0, weight=0.5),
                                            Rule(["P"], -1.0, negated=[True])])
    assert {"weights", "not"} <= weighted.tables.features
    assert "it2_eval" in generate_c(weighted).source  # implemented: accepted


def test_python_callable_membership_is_refused():
    a = IT2Set.from_scale_lag(Gaussian(-1, 0.5), scale=0.8, lag=0.2, name="A")
    fls = IT2Sugeno(inputs=[Input("x", (-2, 2), [a])], rules=[Rule(["A"], 1.0)])
    with pytest.raises(UnsupportedFeatureError, match="no C implementation"):
        check_supported(fls)


def test_unknown_system_types_are_refused():
    class Custom(IT2Sugeno):
        pass

    base = it2track.heading_fls(0.2)
    sub = Custom(inputs=base.inputs, rules=base.rules)
    for obj in (sub, object(), "it2"):
        with pytest.raises(UnsupportedFeatureError, match="supported are Sugeno/TSK"):
            generate_c(obj)  # type: ignore[arg-type]


def test_a_reducer_that_is_not_a_builtin_is_refused():
    fake = TypeReducer(name="km", exact=True, _left=KM._right, _right=KM._left)
    fls = dataclasses.replace(it2track.heading_fls(0.2), reducer=fake)
    with pytest.raises(UnsupportedFeatureError, match="built-in"):
        generate_c(fls)
    ok = dataclasses.replace(it2track.heading_fls(0.2), reducer=KM.with_max_iter(7))
    assert "for (it = 0; it < 7; ++it)" in generate_c(ok).source


@pytest.mark.parametrize("prefix", ["", "1abc", "ABC", "with-dash", "int", "a" * 32, None])
def test_bad_prefixes(prefix):
    with pytest.raises(ValueError, match="prefix"):
        generate_c(it2track.heading_fls(0.2), prefix=prefix)  # type: ignore[arg-type]


def test_bad_real_type():
    with pytest.raises(ValueError, match="RealType"):
        generate_c(it2track.heading_fls(0.2), real="float")  # type: ignore[arg-type]
    assert RealType.from_name(" Float ") is RealType.FLOAT
    with pytest.raises(ValueError, match="'half'"):
        RealType.from_name("half")


def test_write_c_checks_before_writing(tmp_path):
    code = generate_c(it2track.heading_fls(0.2))
    (tmp_path / "it2.h").write_text("mine")
    with pytest.raises(FileExistsError, match="cannot prove it wrote it"):
        write_c(code, tmp_path)
    assert not (tmp_path / "it2.c").exists()
    with pytest.raises(FileNotFoundError):
        write_c(code, "")
    with pytest.raises(NotADirectoryError):
        write_c(code, tmp_path / "it2.h")
    written = write_c(code, tmp_path / "new")
    assert [p.name for p in written] == ["it2.h", "it2.c"]
    assert write_c(code, tmp_path / "new") == written  # its own files: replaced

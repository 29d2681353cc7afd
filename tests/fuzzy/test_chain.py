"""Chained outputs (fuzzylite's Function reading an output it defuzzified before): the outputs
are evaluated in order, each as committed (its own value, else ``on_zero_firing``, else none;
in a sequence after ``lock_previous``) before a later formula reads it.

The system below is ``chain.fll`` of the io test (``tests/io/test_io_chain.py``): every value
pinned here is pyfuzzylite 8.0.6's ``Engine.process`` on that file, and by hand: at ``u``,
``lo = 1 - u/10``, ``hi = u/10``; ``a = 6`` where ``hi > 0``; ``b = lo (a + u) + hi (10 a -
u)``; ``c = b - a`` where ``hi > 0``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from it2track.codegen import generate_c
from it2track.fuzzy import Input, IT2Sugeno, Rule, T1Sugeno, Triangle, ZeroFiringError, kernels
from it2track.fuzzy.chain import chained_outputs
from it2track.fuzzy.formula import Formula
from it2track.fuzzy.sequence import chain_outputs
from it2track.io import UnsupportedFeatureError

U = Input("u", (0, 10), [("lo", Triangle(0, 0, 10)), ("hi", Triangle(0, 10, 10))])


def _f(text: str, *names: str) -> Formula:
    return Formula(text, "fuzzylite", ("u", *names))


def chain(**options) -> T1Sugeno:
    return T1Sugeno(inputs=[U], outputs=("a", "b", "c"), rules=[
        Rule(["hi"], consequents=[(6.0, 6.0), None, None]),
        Rule(["lo"], consequents=[None, _f("a + u", "a"), None]),
        Rule(["hi"], consequents=[None, _f("a*10 - u", "a"), None]),
        Rule(["hi"], consequents=[None, None, _f("b - a", "a", "b")]),
    ], **options)


def test_a_formula_reads_the_outputs_before_it_at_this_evaluation() -> None:
    fls = chain()
    assert [c.features >= {"chain"} for c in fls.tables.outputs] == [False, True, True]
    assert chained_outputs(fls, 1) == ("a",) and chained_outputs(fls, 2) == ("a", "b")
    # u = 2.5: b = 0.75 (6 + 2.5) + 0.25 (60 - 2.5) = 20.75, c = 20.75 - 6 (pyfuzzylite's)
    assert fls(2.5).tolist() == [6.0, 20.75, 14.75]
    np.testing.assert_array_equal(fls(np.array([2.5, 5.0])), [[6.0, 20.75, 14.75],
                                                              [6.0, 33.0, 27.0]])
    assert fls.evaluate(np.array([[5.0]])).tolist() == [[6.0, 33.0, 27.0]]


def test_an_output_without_a_value_is_read_as_committed_default_first() -> None:
    # u = 0: no rule of a or c fires. fuzzylite commits a's default -1 before b reads it:
    # b = 1 * (-1 + 0) = -1, not b's own default 50 (which a NaN read would give)
    fls = chain(on_zero_firing=(-1.0, 50.0, 70.0))
    np.testing.assert_array_equal(fls(np.array([2.5, 0.0, 5.0])),
                                  [[6.0, 20.75, 14.75], [-1.0, -1.0, 70.0], [6.0, 33.0, 27.0]])
    # no default: a has none at 0, so neither has b (NaN read) nor c; __call__ raises
    bare = chain()
    with pytest.raises(ZeroFiringError, match=r"fires at \(u=0\)"):
        bare(0.0)
    got = chain_outputs(bare, np.array([[0.0], [2.5]]))
    assert np.isnan(got[0]).all() and got[1].tolist() == [6.0, 20.75, 14.75]


def test_a_sequence_fills_each_output_before_a_later_one_reads_it() -> None:
    # lock_previous on a: at u = 0 it keeps 6, and b reads the 6 kept: b = 6 + 0
    fls = chain(on_zero_firing=(-1.0, 50.0, 70.0), lock_previous=(True, False, False))
    x = np.array([[0.0], [2.5], [0.0]])
    y, state = fls.evaluate_sequence(x)
    np.testing.assert_array_equal(y, [[-1.0, -1.0, 70.0], [6.0, 20.75, 14.75],
                                      [6.0, 6.0, 70.0]])  # pyfuzzylite, rows in order
    assert state.tolist() == [6.0, 6.0, 70.0]
    # chunks with the state passed on: the same bits; a previous value is read as kept
    first, s1 = fls.evaluate_sequence(x[:2])
    rest, _ = fls.evaluate_sequence(x[2:], s1)
    np.testing.assert_array_equal(np.vstack([first, rest]), y)
    y, _ = fls.evaluate_sequence(np.array([[0.0]]), previous=[4.0, 0.0, 0.0])
    assert y.tolist() == [[4.0, 4.0, 70.0]]
    # stateless __call__ ignores lock_previous
    assert fls(0.0).tolist() == [-1.0, -1.0, 70.0]


def test_a_sequence_without_defaults_has_no_value_where_fuzzylite_has_nan() -> None:
    fls = chain(lock_previous=(True, False, False))
    rows = np.array([[2.5], [0.0], [0.0], [5.0], [0.0]])
    got = chain_outputs(fls, rows, sequence=True)  # pyfuzzylite processing the rows in order
    expected = [[6.0, 20.75, 14.75], [6.0, 6.0, math.nan], [6.0, 6.0, math.nan],
                [6.0, 33.0, 27.0], [6.0, 6.0, math.nan]]
    np.testing.assert_array_equal(got, expected)
    with pytest.raises(ZeroFiringError, match=r"output 'c' fires at row 1 \(u=0\)"):
        fls.evaluate_sequence(rows)
    y, _ = fls.evaluate_sequence(rows[:1])
    assert y.tolist() == [[6.0, 20.75, 14.75]]


def test_what_a_chained_formula_may_read_is_checked() -> None:
    with pytest.raises(ValueError, match=r"formula 'b - a' of output 'c' reads \['u', 'b', "
                       r"'a'\]; a formula reads the inputs, then the outputs before its own in "
                       r"order: \['u', 'a', 'b'\]"):
        T1Sugeno(inputs=[U], outputs=("a", "b", "c"), rules=[
            Rule(["hi"], consequents=[1.0, 2.0, _f("b - a", "b", "a")])])
    # its own output, or a later one: fuzzylite's previous evaluation, not read
    with pytest.raises(ValueError, match=r"rule 0: formula 'a' of output 'a' reads \['u', "
                       r"'a'\]; a formula reads the inputs, then the outputs before its own in "
                       r"order: \['u'\]$"):
        T1Sugeno(inputs=[U], outputs=("a", "b"), rules=[Rule(["hi"], consequents=[
            _f("a", "a"), 1.0])])
    with pytest.raises(ValueError, match=r"rule 1: formula 'a \+ b' of output 'b' reads "
                       r"\['u', 'a', 'b'\]; .* order: \['u', 'a'\]$"):
        T1Sugeno(inputs=[U], outputs=("a", "b"), rules=[Rule(["lo"], consequents=[1.0, 2.0]),
                                                         Rule(["hi"], consequents=[
                                                             1.0, _f("a + b", "a", "b")])])
    # names beyond the inputs that the formula does not read: more names than the tables take
    with pytest.raises(ValueError, match=r"rule 0: formula 'u \+ 1' reads 3 names for 1 "
                       r"inputs and the 1 outputs before this one$"):
        T1Sugeno(inputs=[U], outputs=("a", "b"), rules=[Rule(["hi"], consequents=[
            1.0, _f("u + 1", "a", "b")])])
    with pytest.raises(ValueError, match=r"rule 0: formula 'u \+ 1' reads 2 names for 1 "
                       r"inputs$"):
        T1Sugeno(inputs=[U], outputs=("a", "b"), rules=[Rule(["hi"], consequents=[
            _f("u + 1", "a"), 1.0])])
    with pytest.raises(ValueError, match="only T1Sugeno evaluates formulas of outputs"):
        IT2Sugeno(inputs=[U], outputs=("a", "b"), rules=[Rule(["hi"], consequents=[
            1.0, _f("a", "a")])])


def test_a_chained_output_is_not_evaluated_alone_nor_compiled() -> None:
    fls = chain()
    assert fls.select_output("a")(2.5) == 6.0  # a reads no output
    with pytest.raises(ValueError, match=r"output 'c' reads the outputs \['a', 'b'\] "
                       "evaluated before it"):
        fls.select_output("c")
    assert kernels.supported(fls) == "rule features ['chain', 'formula', 'linear', 'outputs'] "\
        "are not compiled"  # every output's features: c's chain too, not a's alone
    # the C export: a chain has several outputs, and its chained ones are not selected alone
    with pytest.raises(UnsupportedFeatureError, match="several outputs"):
        generate_c(fls)

"""The public example files of MATLAB, Octave, fuzzylite and jFuzzyLogic: each loads and agrees
with its reference (an independent engine's outputs, at matched sampling), or differs for a
reason ``notes.py`` gives, or is refused naming its line; the docs page lists them all and is
current; the publishers' own published values are reproduced. Where pyfuzzylite is installed
(``pip install -e '.[test]'`` brings it, with numpy < 2), the notes' claims and a sample of the
reference tables are re-checked live against it."""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from catalog import CORRECTED, FILES, REFERENCES, examples, twins
from harness import check, check_reading, results
from make_table import PAGE, render
from notes import CORRECTIONS, NOTES, PUBLISHER, refusal_cause

from it2track.fuzzy import Aggregation
from it2track.io import FisFormatError, FisFormatWarning, load, load_terms

EXAMPLES = examples()


@pytest.mark.parametrize("example", EXAMPLES, ids=[e.path for e in EXAMPLES])
def test_example_agrees_differs_as_noted_or_is_refused_with_its_line(example) -> None:
    result = check(example)
    if result.status == "refused":
        assert example.path not in NOTES, "a refused file needs no note"
        assert result.detail, "a refusal says why"
        assert refusal_cause(result.detail), f"notes.REFUSALS has no cause for {result.detail}"
        return
    if example.path in CORRECTED:  # compared with the corrected twin, the original kept
        assert result.table == CORRECTED[example.path] and result.original, example.path
        assert result.original != "agrees", f"{example.path}: the correction changes nothing"
    if example.path in NOTES:
        assert result.status == "differs", f"the note on {example.path} is stale: it agrees"
        return
    assert result.status == "agrees" or (result.status == "loads" and example.reference is None), (
        f"{example.path}: {result.detail}")


def test_every_twin_has_its_reference_table_and_no_table_is_stale() -> None:
    names = set()
    for twin, resolutions in twins().items():
        stem = twin.replace("/", "__")
        found = [p.name for p in REFERENCES.glob(f"{stem}*.csv") if "@jfl" not in p.name]
        assert found, f"no reference table for {twin}"
        names.update(found)
        assert all(r is None or any(f"@{r}" in n for n in found) or f"{stem}.csv" in found
                   for r in resolutions)
    names.update(p.name for p in REFERENCES.glob("*@jfl.csv"))
    names.update(p.name for p in REFERENCES.glob("*@jfl-terms.csv"))
    names.update(p.name for p in REFERENCES.glob("*@octave.csv"))
    assert names == {p.name for p in REFERENCES.glob("*.csv")}


#: the files that agree as term libraries (no fuzzy system; their input terms against
#: jFuzzyLogic's Variable.getMembership), and the term files that stay refused
TERM_LIBRARIES = ["jfuzzylogic/fcl/scarledOLD.fcl", "jfuzzylogic/fcl/membershipFunctionsDemo.fcl",
                  "jfuzzylogic/tests/junit4.fcl", *(
    f"jfuzzylogic/tests/junit_{n}.fcl"
    for n in ("cosine", "gauss", "gbell", "piecewise_linear", "sigmoid", "singletons", "trape",
              "triang"))]
TERMS_REFUSED = {"jfuzzylogic/tests/junit_dsigm.fcl": "DSIGM"}


def test_term_libraries_are_files_refused_as_systems_and_agree_term_by_term() -> None:
    # a term table only for a file load() refuses as no system; every such file compared
    # term by term, the agreeing ones counted apart (table "terms"), the others refused with
    # the system's reason and the term reader's
    from make_table import not_a_system, term_library

    with_terms = [e for e in EXAMPLES if e.terms is not None]
    assert {e.path for e in with_terms} == set(TERM_LIBRARIES) | set(TERMS_REFUSED)
    for example in with_terms:
        with pytest.raises(FisFormatError), warnings.catch_warnings():
            warnings.simplefilter("ignore", FisFormatWarning)  # scarledOLD: two blocks
            load(FILES / example.path)
        result = check(example)
        assert not_a_system(result), example.path
        if example.path in TERMS_REFUSED:
            assert result.status == "refused" and not term_library(result)
            system, terms = result.detail.split("; its terms: ")
            assert refusal_cause(system)[0].startswith("not a fuzzy system"), system
            assert TERMS_REFUSED[example.path] in terms and terms.startswith("line ")
        else:
            assert result.status == "agrees" and result.table == "terms", result.detail
            assert term_library(result) and result.error is not None
            assert result.error <= 1e-9 and result.points >= 303
    # the files with no term jFuzzyLogic values stay refused as no system, with no table
    for path in ("jfuzzylogic/tests/noRules.fcl", "jfuzzylogic/tests/on_line_variable.fcl"):
        (example,) = [e for e in EXAMPLES if e.path == path]
        assert example.terms is None and check(example).status == "refused"


def test_term_tables_are_jfuzzylogics_universe_sampled_and_cover_every_term() -> None:
    # 101 points per input over jFuzzyLogic's universe, both ends; every term of every input
    # at each; memberships in [0, 1] at full precision (not rounded as junit_*.txt are)
    for path in TERM_LIBRARIES:
        (example,) = [e for e in EXAMPLES if e.path == path]
        assert example.terms is not None
        lines = example.terms.read_text().splitlines()
        assert lines[0].startswith("# jFuzzyLogic (commit 1f421d1b176b): ") and path in lines[0]
        rows = [line.split(",") for line in lines[3:]]
        assert lines[2] == "block,input,x,term,membership"
        blocks = dict.fromkeys(r[0] for r in rows)
        read = {b: load_terms(FILES / path, block=b) for b in blocks}
        for block, inputs in read.items():
            for name, variable in inputs.items():
                xs = sorted({float(r[2]) for r in rows if r[:2] == [block, name]})
                assert len(xs) == 101, (path, name)
                terms = {r[3] for r in rows if r[:2] == [block, name]}
                assert terms == {s.name for s in variable.sets}
        mus = np.array([float(r[4]) for r in rows])
        assert ((mus >= 0) & (mus <= 1)).all()
        smooth = any(f"junit_{n}." in path for n in ("gauss", "gbell", "sigmoid", "cosine"))
        if smooth:  # a Gaussian, bell, sigmoid, cosine: not the x100-rounded values
            assert np.any(np.abs(mus * 100 - np.round(mus * 100)) > 1e-6), path


JUNIT = ["cosine", "gauss", "gbell", "piecewise_linear", "sigmoid", "singletons", "trape",
         "triang"]


@pytest.mark.parametrize("name", JUNIT)
def test_jfuzzylogic_recorded_memberships(name) -> None:
    # jFuzzyLogic's TestCaseJfuzzy.checkMembershipFunction: junit_NAME.txt records inVar and
    # the memberships of poor, good, excellent times 100, each rounded by Math.round
    # (floor(v + 0.5)); it2track's terms give every recorded value
    data = np.loadtxt(FILES / f"jfuzzylogic/tests/junit_{name}.txt", skiprows=1)
    inputs = load_terms(FILES / f"jfuzzylogic/tests/junit_{name}.fcl")
    variable = inputs["inVar"]
    assert len(data) >= 100
    for k, term in enumerate(("poor", "good", "excellent")):
        mf = variable.sets[variable.set_index(term)]
        lower, upper = mf(data[:, 0] / 100.0)
        np.testing.assert_array_equal(lower, upper)
        np.testing.assert_array_equal(np.floor(np.asarray(upper) * 100 + 0.5), data[:, k + 1],
                                      err_msg=f"{name}: {term}")


def test_octave_files_have_the_toolkits_own_evalfis_of_the_files_commit() -> None:
    # make_octave_references.py: the toolkit at the commit SOURCES.md names (0.6.2, whose
    # 'centroid' is MATLAB's), one table per Octave file, and no other; the reference of the
    # file without a twin, a second (publisher's) table beside the twin's of the others
    from make_octave_references import SUFFIX, files_commit, wanted

    own = wanted()
    assert [e.path for e in own] == [e.path for e in EXAMPLES if e.path.startswith("octave/")]
    assert len(own) == 6
    assert set(PUBLISHER) == {e.path for e in own if e.twin is None}
    assert {p.name for p in REFERENCES.glob(f"*{SUFFIX}")} == {
        e.path.replace("/", "__") + SUFFIX for e in own}
    for example in own:
        assert example.publisher == REFERENCES / (example.path.replace("/", "__") + SUFFIX)
        if example.twin is None:
            assert example.reference == example.publisher
        else:
            assert example.reference is not None and "@octave" not in example.reference.name
        first = example.publisher.read_text().split("\n", 1)[0]
        assert f"fuzzy-logic-toolkit 0.6.2 (commit {files_commit()[:12]}): evalfis of " \
               f"{example.path}" in first, first
    assert check(own[[e.twin for e in own].index(None)]).status == "agrees"


OCTAVE = [e for e in EXAMPLES if e.source == "octave"]


@pytest.mark.parametrize("example", OCTAVE, ids=[e.path for e in OCTAVE])
def test_octave_file_read_as_octave_agrees_with_octaves_own_evalfis(example) -> None:
    ours = check_reading(example, "octave")
    assert ours.status == "agrees", f"{example.path}: {ours.detail}"
    assert ours.points >= 33 and ours.error is not None and ours.error <= 1e-9
    # the default reading stays MATLAB's: its own reference (the twin's) still agrees, and
    # it differs from Octave's engine exactly where the toolkit's semantics are not MATLAB's
    matlab = check_reading(example, None)
    merged = load(FILES / example.path, dialect="octave")
    merges = getattr(merged, "aggregation", None) not in (None, Aggregation.SUM) and \
        not hasattr(merged, "implication")  # a Sugeno system's max/probor/...: not MATLAB's
    if "centroid_integral" in (FILES / example.path).read_text():
        assert matlab.status == check(example).status == "refused"
        assert "dialect='octave'" in matlab.detail and matlab.detail.startswith("line 36: ")
    else:
        assert check(example).status == "agrees"
        assert matlab.status == "agrees" or (merges and matlab.status == "differs"), (
            f"{example.path}: {matlab.detail}")


def test_the_toolkits_merging_of_equal_sugeno_conclusions_moves_two_files() -> None:
    # aggregate_output_sugeno with AggMethod='max': MATLAB's reading is off Octave's engine
    # where two firing rules conclude the same value (the finding of issue 20)
    moved = {e.path: check_reading(e, None).error for e in OCTAVE
             if check_reading(e, None).status == "differs"}
    assert moved == {"octave/inst/heart_disease_risk.fis": pytest.approx(1 / 32, rel=1e-9),
                     "octave/inst/linear_tip_calculator.fis":
                         pytest.approx(0.0293233082706767, rel=1e-9)}


def test_the_toolkits_older_centroid_is_beyond_the_tolerance_for_the_tip_calculator() -> None:
    # the note on the Octave reference: before 0.6.2 the toolkit's centroid was
    # trapz(x, x.*y) / trapz(x, y); it2track's aggregated set defuzzified so is off the 0.6.2
    # table by more than the tolerance (Debian's 0.4.6 itself, run by
    # make_octave_references.py --installed --check, is off by 5.14e-08 of the range), while
    # it2track's centroid (the weighted average) agrees
    from harness import TOLERANCE
    from make_table import trapezoid_gap

    (example,) = [e for e in EXAMPLES if e.path == "octave/inst/mamdani_tip_calculator.fis"]
    result = check(example)
    assert result.error is not None and result.error <= TOLERANCE
    assert trapezoid_gap(result) == pytest.approx(5.14e-8, rel=1e-2)
    assert "{older}" in PUBLISHER[example.path]


def test_every_correction_has_its_note_and_its_table_says_what_it_changed() -> None:
    assert set(CORRECTIONS) == set(CORRECTED)
    for example in (e for e in EXAMPLES if e.correction is not None):
        table = example.variant(example.correction)
        assert table is not None, f"no corrected reference for {example.path}"
        header = [line for line in table.read_text().splitlines() if line.startswith("#")]
        assert any(line.startswith(f"# corrected ({example.correction}, ") for line in header)


def test_sequence_tables_differ_only_where_the_stateless_one_has_no_output() -> None:
    # lock-previous keeps a previous output where none is: every other value is the same
    tables = sorted(REFERENCES.glob("*@sequence.csv"))
    assert tables, "no twin with lock-previous"
    for table in tables:
        plain = REFERENCES / table.name.replace("@sequence", "")
        body = [[line for line in t.read_text().splitlines() if not line.startswith("#")]
                for t in (table, plain)]
        assert body[0][0] == body[1][0], table.name  # the same columns
        rows = [np.array([[float(v) for v in line.split(",")] for line in b[1:]]) for b in body]
        seq, base = rows
        same = ~np.isnan(base)
        np.testing.assert_array_equal(seq[same], base[same], err_msg=table.name)
        assert (np.isnan(base) & ~np.isnan(seq)).any(), f"{table.name} fills nothing"


def test_the_docs_page_is_current() -> None:
    assert PAGE.read_text() == render(results()), (
        "docs/guide/conformance.md is stale: run python tests/conformance/make_table.py")


def test_matlab_documented_evalfis_values() -> None:
    # MATLAB's evalfis documentation (mamfis.evalfis): tipper.fis at (2,1), (4,5), (7,8)
    fls = load(FILES / "fuzzylite/examples/original/mamdani/matlab/tipper.fis")
    got = [round(float(fls(*p)), 4) for p in [(2.0, 1.0), (4.0, 5.0), (7.0, 8.0)]]
    assert got == [7.0169, 14.4585, 20.3414]


def test_jfuzzylogic_recorded_outputs() -> None:
    fls = load(FILES / "jfuzzylogic/tests/tipper.fcl")
    data = np.loadtxt(FILES / "jfuzzylogic/tests/tipper.txt")
    np.testing.assert_allclose(fls(data[:, 0], data[:, 1]), data[:, 2], rtol=0, atol=1e-12)
    fls = load(FILES / "jfuzzylogic/tests/junit_tipper.fcl")
    data = np.loadtxt(FILES / "jfuzzylogic/tests/junit_tipper.txt", skiprows=1)
    np.testing.assert_array_equal(np.round(fls(data[:, 0] / 100, data[:, 1] / 100) * 100),
                                  data[:, 2])


# -- the notes' claims, re-checked with pyfuzzylite where it is installed -------------------


def _pyfuzzylite():
    return pytest.importorskip("fuzzylite", reason="pip install pyfuzzylite (its own "
                               "environment: it pins numpy < 2)")


def test_fuzzylite_read_matlab_sum_as_probor_and_sum_agrees() -> None:
    fl = _pyfuzzylite()
    path = "fuzzylite/examples/original/mamdani/octave/mamdani_tip_calculator"
    ours = load(FILES / f"{path}.fis")
    assert ours.aggregation is Aggregation.SUM
    engine = fl.FllImporter().from_file(FILES / f"{path}.fll")
    assert type(engine.output_variables[0].aggregation).__name__ == "AlgebraicSum"
    original = fl.Op.midpoints
    fl.Op.midpoints = staticmethod(lambda start, end, n: np.linspace(start, end, n))
    try:
        for ov in engine.output_variables:
            ov.aggregation = fl.UnboundedSum()
            ov.defuzzifier.resolution = 101
        x = np.array([[3.0, 7.0], [5.5, 2.0], [9.0, 9.0]])
        engine.input_values = x
        engine.process()
        np.testing.assert_allclose(ours.evaluate(x), engine.output_values, rtol=1e-14)
    finally:
        fl.Op.midpoints = original


def test_juggler_reference_binds_every_rule_to_one_term() -> None:
    fl = _pyfuzzylite()
    with pytest.warns(FisFormatWarning, match="gbellmf uses the first 3"):
        ours = load(FILES / "fuzzylite/examples/original/takagi-sugeno/matlab/juggler.fis")
    engine = fl.FllImporter().from_file(
        FILES / "fuzzylite/examples/original/takagi-sugeno/matlab/juggler.fll")
    for k, term in enumerate(engine.output_variables[0].terms):
        term.name = f"out1mf{k + 1}"
    block = engine.rule_blocks[0]
    texts = [r.text for r in block.rules]
    block.rules = [fl.Rule.create(t.replace("out1mf", f"out1mf{k + 1}"), engine)
                   for k, t in enumerate(texts)]
    x = np.array([[1.0, 1.0], [-2.0, 2.5], [3.5, 0.3]])
    engine.input_values = x
    engine.process()
    np.testing.assert_allclose(ours.evaluate(x), engine.output_values[:, 0], rtol=1e-13)


def test_reference_tables_are_pyfuzzylites_outputs_live() -> None:
    # every 8th twin re-evaluated by the installed pyfuzzylite (make_references.py's
    # evaluation); numerically, as another numpy may round the last bit differently
    _pyfuzzylite()
    from make_references import mamdani, table

    for twin, resolutions in sorted(twins().items())[::8]:
        for resolution in ({None} if not mamdani(FILES / twin) else resolutions):
            stem = twin.replace("/", "__")
            name = f"{stem}.csv" if resolution is None else f"{stem}@{resolution}.csv"
            live = [line for line in table(twin, resolution).splitlines()
                    if not line.startswith("#")]
            kept = [line for line in (REFERENCES / name).read_text().splitlines()
                    if not line.startswith("#")]
            assert live[0] == kept[0], name
            np.testing.assert_allclose(
                np.array([[float(v) for v in row.split(",")] for row in live[1:]]),
                np.array([[float(v) for v in row.split(",")] for row in kept[1:]]),
                rtol=1e-12, atol=1e-12, err_msg=name)


def test_octave_hedges_are_powers_pyfuzzylite_agrees_given_them() -> None:
    # the note on Octave's .fis hedges: pyfuzzylite with Octave's powers in place of its
    # hedges (antecedent mu ** p, conclusion firing ** (1 / p), one rule per conclusion)
    fl = _pyfuzzylite()
    import re

    factory = fl.settings.factory_manager.hedge
    for word, p in {"somewhat": 0.5, "very": 2.0, "extremely": 3.0}.items():
        factory.constructors[f"p{word}"] = lambda p=p, w=word: fl.HedgeLambda(
            f"p{w}", lambda x: np.asarray(x) ** p)
        factory.constructors[f"r{word}"] = lambda p=p, w=word: fl.HedgeLambda(
            f"r{w}", lambda x: np.asarray(x) ** (1.0 / p))
    hedge = re.compile(r"\b(somewhat|very|extremely)\b")
    original = fl.Op.midpoints
    fl.Op.midpoints = staticmethod(lambda start, end, n: np.linspace(start, end, n))
    try:
        for path in ("fuzzylite/examples/original/mamdani/octave/investment_portfolio",
                     "fuzzylite/examples/original/takagi-sugeno/octave/sugeno_tip_calculator"):
            ours = load(FILES / f"{path}.fis")
            engine = fl.FllImporter().from_file(FILES / f"{path}.fll")
            for ov in engine.output_variables:
                if hasattr(ov.defuzzifier, "resolution"):
                    ov.defuzzifier.resolution = 101
            block = engine.rule_blocks[0]
            rules = []
            for text in [r.text for r in block.rules]:
                cond, then = text.split(" then ")
                then, _, weight = then.partition(" with ")
                cond = hedge.sub(r"p\1", cond)
                for part in then.split(" and "):
                    part = hedge.sub(r"r\1", part)
                    rules.append(fl.Rule.create(
                        f"{cond} then {part}" + (f" with {weight}" if weight else ""), engine))
            block.rules = rules
            x = np.array([[a, b] for a in (2.0, 4.5, 7.0, 9.5) for b in (1.5, 5.0, 8.5)])
            if "investment" in path:
                x = x * np.array([10.0, 1.0]) + np.array([5.0, 0.0])
            engine.input_values = x
            engine.process()
            np.testing.assert_allclose(ours.evaluate(x).reshape(len(x), -1),
                                       np.asarray(engine.output_values).reshape(len(x), -1),
                                       rtol=1e-12)
    finally:
        fl.Op.midpoints = original

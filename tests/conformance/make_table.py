"""Write ``docs/guide/conformance.md``: every conformance file with its result, the differences
and why, the refusals and why, and the publisher's own values, all computed now.

    python tests/conformance/make_table.py          # write the page
    python tests/conformance/make_table.py --check  # exit 1 if the page is not current

``test_conformance.py`` checks that the page is current.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from catalog import FILES
from harness import TOLERANCE, Result, check_reading, results
from notes import CORRECTIONS, NOTES, OCTAVE_READINGS, PUBLISHER, refusal_cause

from it2track.io import load

PAGE = Path(__file__).parents[2] / "docs" / "guide" / "conformance.md"
SOURCES = {
    "fuzzylite": ("fuzzylite 6 examples and the MATLAB/Octave originals it ships",
                  "https://github.com/fuzzylite/fuzzylite"),
    "pyfuzzylite": ("fuzzylite 8 examples (pyfuzzylite)", "https://github.com/fuzzylite/pyfuzzylite"),
    "octave": ("Octave Fuzzy Logic Toolkit examples",
               "https://github.com/lmarkowsky/fuzzy-logic-toolkit"),
    "jfuzzylogic": ("jFuzzyLogic's FCL files", "https://github.com/pcingola/jFuzzyLogic"),
}
STATUS = {"agrees": "agrees", "differs": "differs (see below)", "refused": "refused",
          "loads": "loads, no reference"}


def _magnitude(error: float | None) -> str:
    """The largest difference as a power of ten bound (stable in the last digits)."""
    if error is None:
        return ""
    if error == 0.0:
        return "0"
    if error > TOLERANCE:
        return f"{error:.2g}"
    return f"≤ 1e{math.ceil(math.log10(error))}"


def publisher_values() -> list[str]:
    """The tools' own published outputs, recomputed."""
    lines = []
    tipper = load(FILES / "fuzzylite/examples/original/mamdani/matlab/tipper.fis")
    points = [(2.0, 1.0), (4.0, 5.0), (7.0, 8.0)]
    ours = ", ".join(f"{float(tipper(*p)):.4f}" for p in points)
    lines.append(f"- MATLAB's `tipper.fis` (as fuzzylite ships it): MATLAB's `evalfis` "
                 f"documentation prints 7.0169, 14.4585 and 20.3414 at (2, 1), (4, 5), (7, 8); "
                 f"it2track gives {ours}.")
    fcl = load(FILES / "jfuzzylogic/tests/tipper.fcl")
    data = np.loadtxt(FILES / "jfuzzylogic/tests/tipper.txt")
    worst = float(np.max(np.abs(fcl(data[:, 0], data[:, 1]) - data[:, 2])))
    lines.append(f"- jFuzzyLogic's `tests/tipper.txt`, the outputs its unit test records for "
                 f"`tests/tipper.fcl`: {len(data)} points, largest difference "
                 f"{worst:.1e}.")
    fcl = load(FILES / "jfuzzylogic/tests/junit_tipper.fcl")
    data = np.loadtxt(FILES / "jfuzzylogic/tests/junit_tipper.txt", skiprows=1)
    rounded = np.round(fcl(data[:, 0] / 100, data[:, 1] / 100) * 100)
    same = int(np.sum(rounded == data[:, 2]))
    lines.append(f"- jFuzzyLogic's `tests/junit_tipper.txt` (inputs and outputs times 100, "
                 f"rounded): {same} of {len(data)} outputs equal.")
    return lines


def trapezoid_gap(r: Result) -> float:
    """The largest difference, relative to the output's range, between ``r``'s reference and
    it2track's aggregated sets defuzzified by the Octave toolkit's centroid before 0.6.2:
    ``trapz(x, x.*y) / trapz(x, y)`` over the same points."""
    system = load(FILES / r.example.path)
    table = r.example.reference
    assert table is not None
    lines = table.read_text().splitlines()
    rows = np.array([[float(v) for v in line.split(",")]
                     for line in [line for line in lines if not line.startswith("#")][1:]])
    n_in, worst = system.n_inputs, 0.0
    for k in range(system.n_outputs):
        part = system.select_output(k)
        _, mu = part.aggregated(*rows[:, :n_in].T)
        y = part.tables.grids[0]
        older = np.trapezoid(mu * y, y, axis=-1) / np.trapezoid(mu, y, axis=-1)
        worst = max(worst, float(np.max(np.abs(older - rows[:, n_in + k]))) / float(y[-1] - y[0]))
    return worst


def _versus(r: Result) -> str:
    if r.status == "agrees":
        return f"agrees ({_magnitude(r.error)})"
    if r.status == "differs":
        return f"differs by {_magnitude(r.error)} of the range"
    return r.status


def octave_readings(found: list[Result]) -> list[str]:
    """The section comparing each Octave toolkit file, under each reading, with Octave's own
    evalfis table (``make_octave_references.py``)."""
    mine = [r.example for r in found if r.example.publisher is not None]
    if not mine:
        return []
    engine = mine[0].publisher.read_text().split("\n", 1)[0].removeprefix("# ").split(": ")[0]
    rows, octave, default = [], Counter(), Counter()
    for example in mine:
        matlab, own = check_reading(example, None), check_reading(example, "octave")
        default[matlab.status] += 1
        octave[own.status] += 1
        system = load(FILES / example.path, dialect="octave")
        agg = getattr(getattr(system, "aggregation", None), "value", "")
        why = ("centroid_integral" if matlab.status == "refused" else
               "merge" if matlab.status == "differs" else
               "same-mamdani" if hasattr(system, "implication") else
               "same-sum" if agg == "sum" else "same-apart")
        rows.append(f"| `{example.path}` | {_versus(matlab)} | {_versus(own)} | "
                    f"{OCTAVE_READINGS[why].format(agg=agg)} |")
    only = [r.example.path for r in found if r.example.publisher is not None
            and r.status == "refused" and check_reading(r.example, "octave").status == "agrees"]
    return ["", "## The Octave toolkit's files under each reading", "",
            f"Every file of the Octave toolkit also has Octave's own `evalfis` table "
            f"(`...@octave.csv`, {engine}; `make_octave_references.py`), a second reference "
            "beside its twin's. it2track reads a `.fis` as MATLAB evaluates it "
            "(`load(path)`, the reading every count on this page is of), or, on request, as "
            "the toolkit evaluates it (`load(path, dialect=\"octave\")`, CLI "
            f"`--dialect octave`). With `dialect=\"octave\"` {octave['agrees']} of "
            f"{len(mine)} files agree with Octave's engine; with the default reading "
            f"{default['agrees']} agree, {default['differs']} differ and "
            f"{default['refused']} {'is' if default['refused'] == 1 else 'are'} refused.",
            "",
            "| file | default (MATLAB's) reading vs Octave | `dialect=\"octave\"` vs Octave | "
            "why the readings differ |", "|---|---|---|---|", *rows, "",
            f"{', '.join(f'`{p}`' for p in only) or 'No file'} loads and agrees only with "
            "`dialect=\"octave\"`; it is counted as refused above: `load(path)` is what a user "
            "calls, and it reads MATLAB's format, whose readers refuse the file naming the "
            "line and the feature (and point to the dialect). Reading Octave's own files "
            "with the Octave dialect by default would count them, but would also make the "
            "twin references, MATLAB's semantics, disagree where the toolkit merges "
            "conclusions; the choice of reading is the user's, so it is reported apart."]


#: refusal causes (notes.REFUSALS) of files that are not fuzzy systems
NOT_A_SYSTEM = "not a fuzzy system"


def term_library(r: Result) -> bool:
    """Whether ``r`` is a file that is no fuzzy system and agrees as a term library (its
    input terms' memberships against jFuzzyLogic's, ``harness._term_library``)."""
    return r.table == "terms" and r.status == "agrees"


def not_a_system(r: Result) -> bool:
    """Whether ``r`` is a file that is no fuzzy system (no output, an output without terms,
    no rules): refused so, or compared as a term library."""
    if r.table == "terms":
        return True
    cause = refusal_cause(r.detail) if r.status == "refused" else None
    return cause is not None and cause[0].startswith(NOT_A_SYSTEM)


def _count(found: list[Result]) -> Counter:
    """Statuses, a term library's agreement counted as ``terms``, apart from the systems'."""
    return Counter("terms" if term_library(r) else r.status for r in found)


def term_libraries(found: list[Result]) -> list[str]:
    """The section on the files compared as term libraries."""
    mine = [r for r in found if r.table == "terms"]
    if not mine:
        return []
    lines = ["", "## Term libraries", "",
             "These files are no fuzzy systems: their function blocks declare inputs with terms "
             "and no output, or an output without terms (jFuzzyLogic's unit tests read their "
             "terms' memberships directly). `load(path)` refuses them as systems; "
             "`it2track.io.load_terms(path)` reads their inputs' terms, and every membership is "
             "compared with jFuzzyLogic's own (`Variable.getMembership`, full precision: "
             "`...@jfl-terms.csv`, written by `make_jfl_references.py` at 101 points over each "
             "input's universe as jFuzzyLogic estimates it, both ends included). A file agrees "
             f"as a term library when every membership is within {TOLERANCE:g} (absolute: "
             "memberships are in [0, 1]). They are counted apart from the systems.", "",
             "| file | result | memberships compared | largest difference |", "|---|---|---|---|"]
    for r in mine:
        lines.append(f"| `{r.example.path}` | {STATUS[r.status]} | {r.points} | "
                     f"{_magnitude(r.error)} |")
    return lines


def render(found: list[Result]) -> str:
    """The page's text."""
    total = len(found)
    agree = sum(r.status == "agrees" and not term_library(r) for r in found)
    libraries = sum(term_library(r) for r in found)
    systems = [r for r in found if not not_a_system(r)]
    agree_systems = sum(r.status == "agrees" for r in systems)
    in_order = [r for r in found if r.table == "sequence"]
    corrected = [r for r in found if r.example.correction is not None]
    lines = [
        "# Conformance: the files users already have",
        "",
        "<!-- Generated by tests/conformance/make_table.py; do not edit. -->",
        "",
        f"it2track loads the public example files of MATLAB, Octave, fuzzylite and "
        f"jFuzzyLogic unmodified and compares each with a reference: **{agree} of {total} "
        f"files ({100 * agree / total:.1f} %) load and agree**. Of the {len(systems)} files "
        f"that are fuzzy systems (the other {total - len(systems)} declare no output, an "
        "output without terms, or no rules: see the term libraries and the refusals "
        f"below), **{agree_systems} "
        f"({100 * agree_systems / len(systems):.1f} %) load and agree**. Of those "
        f"{total - len(systems)}, {libraries} are term libraries that agree as such: "
        "jFuzzyLogic's membership-function files, whose input terms (`it2track.io.load_terms`) "
        f"have jFuzzyLogic's memberships to {TOLERANCE:g} at every point of its table (see "
        "*Term libraries* below); counting them, **"
        f"{agree + libraries} of {total} files ({100 * (agree + libraries) / total:.1f} %) "
        "load and agree, as systems or as term libraries**. The files, their "
        "licences and where each came from are in `tests/conformance/files/` (`SOURCES.md`); "
        "the test `tests/conformance/test_conformance.py` runs them all.",
        "",
        "A file *agrees* when at every point of its reference table each output is within "
        f"{TOLERANCE:g} of the output's range of the reference, and where the reference has no "
        "output (no rule fires) it2track has none either, or for a MATLAB `.fis` MATLAB's "
        "documented middle of the range at a point where none of its rules fires. The "
        "references are independent engines: pyfuzzylite 8.0.6 evaluating the file's twin "
        "`.fll` (a `.fll` itself; the `.fll` fuzzylite exported beside its `.fis`/`.fcl`; the "
        "`.fll` fuzzylite wrote for each MATLAB and Octave original), and the publishers' "
        "engines where there is no twin: jFuzzyLogic itself for its own files, Octave's "
        "`evalfis` for the Octave toolkit's example without one. Mamdani outputs are compared "
        "at matched sampling: MATLAB's (and Octave's) 101 points for `.fis`, jFuzzyLogic's "
        "1000 intervals for `.fcl`, fuzzylite's own midpoints for `.fll` "
        "(`tests/conformance/make_references.py`, `make_jfl_references.py` and "
        "`make_octave_references.py` regenerate the tables and explain how).",
        "",
        "A file that keeps an output's previous value where no rule fires (fuzzylite's "
        "`lock-previous: true`, `LockPrevious=1`, FCL's `DEFAULT := ... NC`) is evaluated as "
        "a sequence, its reference table's rows in order from a fresh start "
        "(`system.evaluate_sequence`), against its twin evaluated by pyfuzzylite in the same "
        f"order with the same setting (`...@sequence.csv`); {len(in_order)} files are "
        "evaluated so. "
        f"{len(corrected)} files are compared with a corrected reference, where the twin has a "
        "documented defect (listed below with the correction and the original reference's "
        "difference).",
        "",
        "## Summary",
        "",
        "| source | files | agree (systems) | agree as term libraries | differ (explained "
        "below) | refused | no reference |",
        "|---|---|---|---|---|---|---|",
    ]
    for source in SOURCES:
        mine = [r for r in found if r.example.source == source]
        count = _count(mine)
        lines.append(f"| [{SOURCES[source][0]}]({SOURCES[source][1]}) | {len(mine)} | "
                     f"{count['agrees']} | {count['terms']} | {count['differs']} | "
                     f"{count['refused']} | {count['loads']} |")
    count = _count(found)
    lines.append(f"| **all** | **{total}** | **{count['agrees']}** | **{count['terms']}** | "
                 f"**{count['differs']}** | **{count['refused']}** | **{count['loads']}** |")
    lines += ["", "By format:", "", "| format | files | agree (systems) | agree as term "
              "libraries | refused |", "|---|---|---|---|---|"]
    for suffix in (".fis", ".fll", ".fcl"):
        mine = [r for r in found if r.example.suffix == suffix]
        c = _count(mine)
        lines.append(f"| `{suffix}` | {len(mine)} | {c['agrees']} | {c['terms']} | "
                     f"{c['refused']} |")
    lines += term_libraries(found)
    lines += ["", "## The publishers' own values", "", *publisher_values()]
    lines += ["", "## Compared with a corrected reference", "",
              "The twin of each of these files has a defect, corrected in the reference it is "
              "compared with (`tests/conformance/make_references.py` applies the correction; "
              "the table's header names it). The original reference and its difference stay "
              "reported:", ""]
    for r in corrected:
        table = r.example.variant(r.example.correction or "")
        name = table.name if table is not None else "(missing)"
        result = "agrees" if r.status == "agrees" else r.detail
        lines += [f"- `{r.example.path}`: {result} with the corrected reference "
                  f"`{name}` ({_magnitude(r.error)}); against the original reference: "
                  f"{r.original or r.status}. {CORRECTIONS.get(r.example.path, '')}"]
    lines += ["", "## Compared with the publisher's own engine", "",
              "These files have no independent twin: their reference is the engine of the "
              "tool they came with, named with its version in the table's first line (as "
              "jFuzzyLogic's own outputs are the reference of its files):", ""]
    for r in found:
        if r.example.path in PUBLISHER and r.example.reference is not None:
            table = r.example.reference
            engine = table.read_text().split("\n", 1)[0].removeprefix("# ").split(": ")[0]
            result = "agrees" if r.status == "agrees" else r.detail
            note = PUBLISHER[r.example.path].format(older=f"{trapezoid_gap(r):.2g}")
            lines += [f"- `{r.example.path}`: {result} with `{table.name}`, {engine} "
                      f"({_magnitude(r.error)}). {note}"]
    lines += octave_readings(found)
    lines += ["", "## Where it2track differs from the reference", ""]
    for r in found:
        if r.status == "differs":
            lines += [f"- `{r.example.path}` ({r.detail}): {NOTES.get(r.example.path, '')}"]
    causes: dict[str, tuple[str, list[str]]] = {}
    for r in found:
        if r.status == "refused":
            cause, why = refusal_cause(r.detail) or ("(no cause recorded)", "")
            causes.setdefault(cause, (why, []))[1].append(r.example.path)
    lines += ["", "## Why the remaining files stay refused", "",
              "| cause | files | why it2track leaves it refused |", "|---|---|---|"]
    for cause, (why, paths) in sorted(causes.items(), key=lambda kv: -len(kv[1][1])):
        lines.append(f"| {cause} | {len(paths)} | {why} |")
    lines += ["", "## Refused files", "",
              "Each is refused with a `FisFormatError` naming the file, the line and the "
              "feature:", "", "| file | reason |", "|---|---|"]
    for r in found:
        if r.status == "refused":
            lines.append(f"| `{r.example.path}` | {r.detail.replace('|', '/')} |")
    lines += ["", "## Every file", "", "| file | result | largest difference (of the range) |",
              "|---|---|---|"]
    for r in found:
        how = {"": "", "sequence": " (in order)", "terms": " as a term library"}.get(
            r.table, " (corrected reference)")
        lines.append(f"| `{r.example.path}` | {STATUS[r.status]}{how} | "
                     f"{_magnitude(r.error)} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="exit 1 if the page is stale")
    args = parser.parse_args(argv)
    text = render(results())
    if args.check:
        current = PAGE.read_text() if PAGE.exists() else ""
        print("current" if current == text else f"{PAGE} is stale")
        return 0 if current == text else 1
    PAGE.write_text(text)
    print(f"wrote {PAGE}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

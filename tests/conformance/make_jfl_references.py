"""Write the reference tables of jFuzzyLogic's ``.fcl`` files: jFuzzyLogic's own outputs, at
it2track's resolution, on the grid of ``grids.py``.

jFuzzyLogic's files have no ``.fll`` twin, so their reference is the tool that wrote them. The
script extracts jFuzzyLogic's compiled classes (``bin/``, and the ANTLR runtime in ``org/``)
from a bare clone of https://github.com/pcingola/jFuzzyLogic, compiles ``JflReference.java``
against them and runs it per file (``java`` and ``javac`` 17 or later)::

    git clone --bare https://github.com/pcingola/jFuzzyLogic /tmp/jfl.git
    python tests/conformance/make_jfl_references.py /tmp/jfl.git

Matched resolution: a continuous defuzzifier samples 1001 points over jFuzzyLogic's universe,
both ends included (it2track's reading of an FCL output: jFuzzyLogic's 1000 intervals, its
own universe estimate when there is no RANGE); each evaluation starts from no output
(``DEFAULT`` or NaN, where jFuzzyLogic would keep the previous evaluation's). Inputs are
sampled over jFuzzyLogic's universes, or :data:`SAMPLED`'s where it has none.

A file jFuzzyLogic does not evaluate as a system whose function blocks have no output with
terms (its membership-function files: inputs only, or an output without terms) gets a term
table instead (``@jfl-terms.csv``): jFuzzyLogic's ``Variable.getMembership`` of every term of
every input with terms, at :data:`TERM_POINTS` points over the input's universe as jFuzzyLogic
estimates it (``numpy.linspace``, both ends included), full precision. A file with a term
jFuzzyLogic gives no value there (a term given by other variables, NaN until they are set) or
with no term at all gets none. ``--check``
compares instead of writing; without it only new or changed tables are written (and tables of
files jFuzzyLogic no longer evaluates removed).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
import numpy as np
from catalog import FILES, POINTS, REFERENCES, examples
from grids import grid

HERE = Path(__file__).parent

#: inputs whose universe jFuzzyLogic cannot estimate (NaN) or estimates as a point, sampled
#: over these ranges instead (file -> input -> (lo, hi)); jFuzzyLogic evaluates the file as
#: ever, at those points
SAMPLED: dict[str, dict[str, tuple[float, float]]] = {
    # inVar's term good is GAUSS meanGood stdGood, so jFuzzyLogic's estimate of inVar is NaN
    # (the variables are NaN when it loads the file): inVar over its fixed terms' estimate,
    # poor GAUSS 1 2 (1 -+ 4 * 2) and excellent GAUSS 9 1 (9 -+ 4 * 1), it2track's universe;
    # meanGood and stdGood have no terms (jFuzzyLogic: the point 0), sampled where good is a
    # Gaussian within that universe
    "jfuzzylogic/fcl/cinthia.fcl": {"inVar": (-7.0, 13.0), "meanGood": (-7.0, 13.0),
                                    "stdGood": (0.5, 5.0)},
}


#: points per input of a term table (over jFuzzyLogic's universe, both ends included)
TERM_POINTS = 101


def _setup(mirror: str, work: Path) -> str:
    """Extract jFuzzyLogic's classes, compile the driver; the class path."""
    archive = subprocess.run(["git", "--git-dir", mirror, "archive", "HEAD", "bin", "org"],
                             check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(work)], input=archive, check=True)
    classpath = f"{work}:{work / 'bin'}:{work}"
    subprocess.run(["javac", "-nowarn", "-cp", classpath, "-d", str(work),
                    str(HERE / "JflReference.java")], check=True, capture_output=True)
    return classpath


def table(path: str, classpath: str, commit: str) -> str | None:
    """The reference table of one file, or ``None`` where jFuzzyLogic does not evaluate it."""
    command = ["java", "-cp", classpath, "JflReference", str(FILES / path),
               str(POINTS[".fcl"])]
    head = subprocess.run(command, input="", capture_output=True, text=True, timeout=120)
    lines = head.stdout.splitlines()
    if head.returncode != 0 or len(lines) < 2 or not lines[0].startswith("inputs"):
        return None
    ins, outs = lines[0].split()[1:], lines[1].split()[1:]
    names = ins[0::3]
    ranges = [(float(lo), float(hi)) for lo, hi in zip(ins[1::3], ins[2::3], strict=True)]
    sampled = SAMPLED.get(path, {})
    ranges = [sampled.get(name, span) for name, span in zip(names, ranges, strict=True)]
    if not names or not outs or any(not lo <= hi for lo, hi in ranges):
        return None
    x = grid(ranges)
    run = subprocess.run(command, input="\n".join(" ".join(repr(float(v)) for v in row)
                                                  for row in x) + "\n",
                         capture_output=True, text=True, timeout=600)
    rows = run.stdout.splitlines()[2:]
    if run.returncode != 0 or len(rows) != len(x):
        return None
    out_names = outs[0::3]
    spans = "; ".join(f"{float(lo)!r} {float(hi)!r}" for lo, hi in zip(outs[1::3], outs[2::3],
                                                                      strict=True))
    body = [",".join([*(repr(float(v)) for v in xi), *(repr(float(v)) for v in row.split())])
            for xi, row in zip(x, rows, strict=True)]
    return "\n".join([f"# jFuzzyLogic (commit {commit[:12]}) evaluating {path}",
                      f"# at {POINTS['.fcl']} points, both ends included",
                      f"# output ranges: {spans}", ",".join(names + out_names), *body]) + "\n"


def terms_table(path: str, classpath: str, commit: str) -> str | None:
    """The term table of one file, or ``None`` (jFuzzyLogic gives a term no value, the file
    has an output with terms or no term at all)."""
    command = ["java", "-cp", classpath, "JflReference", str(FILES / path), "terms"]
    head = subprocess.run(command, input="", capture_output=True, text=True, timeout=120)
    if head.returncode != 0:
        return None
    queries, rows, block = [], [], ""
    for line in head.stdout.splitlines():
        words = line.split()
        if words[0] == "block":
            block = words[1]
            continue
        name, lo, hi, terms = words[1], float(words[2]), float(words[3]), words[4:]
        if not lo < hi:  # NaN: terms given by variables; a point: nothing to sample
            return None
        for x in np.linspace(lo, hi, TERM_POINTS):
            queries.append(f"{block} {name} {float(x)!r}")
            rows.append((block, name, float(x), terms))
    if not rows:
        return None
    run = subprocess.run(command, input="\n".join(queries) + "\n", capture_output=True,
                         text=True, timeout=600)
    values = run.stdout.splitlines()[len(head.stdout.splitlines()):]
    if run.returncode != 0 or len(values) != len(rows):
        return None
    body = []
    for (blk, name, x, terms), line in zip(rows, values, strict=True):
        mus = [float(v) for v in line.split()]
        if any(not 0.0 <= mu <= 1.0 for mu in mus):  # NaN included
            return None
        body += [f"{blk},{name},{x!r},{term},{mu!r}" for term, mu in zip(terms, mus, strict=True)]
    return "\n".join([f"# jFuzzyLogic (commit {commit[:12]}): the memberships of the input "
                      f"terms of {path} (Variable.getMembership)",
                      f"# at {TERM_POINTS} points over each input's universe as jFuzzyLogic "
                      "estimates it, both ends included",
                      "block,input,x,term,membership", *body]) + "\n"


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mirror", help="a bare clone of pcingola/jFuzzyLogic")
    parser.add_argument("--check", action="store_true", help="compare, do not write")
    args = parser.parse_args(argv)
    REFERENCES.mkdir(exist_ok=True)
    wanted = {}
    commit = subprocess.run(["git", "--git-dir", args.mirror, "rev-parse", "HEAD"], check=True,
                            capture_output=True, text=True).stdout.strip()
    with tempfile.TemporaryDirectory() as work:
        classpath = _setup(args.mirror, Path(work))
        for example in examples():
            if example.source != "jfuzzylogic":
                continue
            text = table(example.path, classpath, commit)
            name = example.path.replace("/", "__") + "@jfl.csv"
            if text is not None:
                wanted[name] = text
                continue
            terms = terms_table(example.path, classpath, commit)
            if terms is None:
                print(f"{example.path}: jFuzzyLogic does not evaluate it")
            else:
                print(f"{example.path}: not a system; its terms' memberships")
                wanted[name.replace("@jfl.csv", "@jfl-terms.csv")] = terms
    stale = sorted(p.name for p in [*REFERENCES.glob("*@jfl.csv"),
                                    *REFERENCES.glob("*@jfl-terms.csv")]
                   if p.name not in wanted)
    changed = [n for n, text in wanted.items()
               if not (REFERENCES / n).exists() or (REFERENCES / n).read_text() != text]
    if args.check:
        for name in changed + stale:
            print(f"differs: {name}")
        return 1 if changed or stale else 0
    for name in changed:
        (REFERENCES / name).write_text(wanted[name])
    for name in stale:
        (REFERENCES / name).unlink()
    print(f"{len(wanted)} tables, {len(changed)} written, {len(stale)} removed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

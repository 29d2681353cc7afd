"""Write the reference tables of the Octave Fuzzy Logic Toolkit's example files: Octave's own
``evalfis`` of the file, on the grid of ``grids.py``. For the file with no ``.fll`` twin
(``mamdani_tip_calculator.fis``) it is the reference; for the others a second reference, the
publisher's, beside their twin's (``catalog.Example.publisher``): the conformance test reads
every one with ``dialect="octave"`` and compares it with this table.

The publisher's engine is the toolkit itself, run by GNU Octave. The script extracts the
toolkit's ``inst/`` at the commit the files were copied from (``files/SOURCES.md``) from a bare
clone of https://github.com/lmarkowsky/fuzzy-logic-toolkit and puts it on Octave's path, so the
reference is the toolkit the file belongs to (``octave-cli`` 7 or later, e.g. Debian's
``apt-get install octave``)::

    git clone --bare https://github.com/lmarkowsky/fuzzy-logic-toolkit /tmp/flt.git
    python tests/conformance/make_octave_references.py /tmp/flt.git

Matched resolution: ``evalfis(x, fis)`` with the toolkit's default 101 points over each
output's range, both ends included (``linspace``: MATLAB's ``evalfis`` points, it2track's
reading of a ``.fis``).

The toolkit's version matters. From 0.6.2 (the files' commit) ``DefuzzMethod='centroid'`` is
the weighted average of the 101 points (``wtaver``: MATLAB's and it2track's centroid); up to
0.6.1, Debian's 0.4.6 included, it was ``trapz(x, x.*y) / trapz(x, y)``, which 0.6.2 keeps as
``'centroid_integral'``. ``--installed`` runs the toolkit Octave has installed
(``pkg load fuzzy-logic-toolkit``, e.g. Debian's ``octave-fuzzy-logic-toolkit``) instead; it
only compares, never writes.

``--check`` compares the tables with the files' instead of writing (exit 1 on a difference).
``--cross-check`` evaluates the other Octave files, which have a reference from pyfuzzylite
(corrected where their twin is), with Octave at their tables' inputs and prints the largest
difference relative to each output's range (exit 1 above the conformance tolerance, 1e-9).
It does not agree everywhere: the toolkit's Sugeno systems merge the rules that conclude the
same value with the file's ``AggMethod`` (``aggregate_output_sugeno``: ``'max'`` in
``heart_disease_risk.fis`` and ``linear_tip_calculator.fis``), where MATLAB, fuzzylite and
it2track's default ``.fis`` reading count every rule; and ``investment_portfolio.fis`` says
``'centroid_integral'``, which its pyfuzzylite reference (a centroid) is not. it2track's
``load(path, dialect="octave")`` reads both as the toolkit does, and agrees with these tables.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from catalog import FILES, REFERENCES, Example, examples
from grids import grid

#: what the table's name adds to the file's path (``catalog.Example.reference`` finds it)
SUFFIX = "@octave.csv"
TOLERANCE = 1e-9

#: prints the file's input ranges and its outputs' names and ranges, then (with an input
#: file) evalfis at every row; TOOLKIT, FIS and INPUTS are filled in
_DRIVER = """\
TOOLKIT
fis = readfis ('FIS');
for v = fis.input
  fprintf ('input %s %.17g %.17g\\n', v.name, v.range(1), v.range(2));
endfor
for v = fis.output
  fprintf ('output %s %.17g %.17g\\n', v.name, v.range(1), v.range(2));
endfor
if (! isempty ('INPUTS'))
  y = evalfis (load ('-ascii', 'INPUTS'), fis);
  fprintf ([repmat(' %.17g', 1, columns (y)) '\\n'], y');
endif
"""


def files_commit() -> str:
    """The toolkit commit the ``octave/`` files were copied from (``files/SOURCES.md``)."""
    text = (FILES / "SOURCES.md").read_text()
    section = text[text.index("## octave/"):]
    found = re.search(r"at commit `([0-9a-f]{40})`", section)
    assert found, "files/SOURCES.md names no commit for octave/"
    return found.group(1)


def toolkit(mirror: str | None, work: Path) -> tuple[str, str]:
    """``(Octave statement putting the toolkit on the path, its description)``."""
    version = subprocess.run(["octave-cli", "--version"], check=True, capture_output=True,
                             text=True).stdout.split("\n", 1)[0]
    version = "GNU Octave " + version.rsplit(" ", 1)[-1]
    if mirror is None:
        code = ("pkg load fuzzy-logic-toolkit; d = pkg ('describe', 'fuzzy-logic-toolkit');"
                "printf ('%s\\n', d{1}.version);")
        installed = subprocess.run(["octave-cli", "--norc", "--quiet", "--eval", code],
                                   check=True, capture_output=True, text=True).stdout.strip()
        return "pkg load fuzzy-logic-toolkit;", (f"{version}, fuzzy-logic-toolkit "
                                                 f"{installed} (installed)")
    commit = files_commit()
    archive = subprocess.run(["git", "--git-dir", mirror, "archive", commit, "inst",
                              "DESCRIPTION"], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(work)], input=archive, check=True)
    described = (work / "DESCRIPTION").read_text()
    release = re.search(r"^Version:\s*(\S+)", described, re.MULTILINE)
    assert release, "the toolkit's DESCRIPTION has no Version"
    return (f"addpath ('{work / 'inst'}');",
            f"{version}, fuzzy-logic-toolkit {release.group(1)} (commit {commit[:12]})")


def run(setup: str, path: Path, x: np.ndarray | None, work: Path
        ) -> tuple[list[tuple[str, float, float]], list[tuple[str, float, float]], np.ndarray]:
    """``(inputs, outputs, y)``: the file's variables as Octave reads them (name, range) and
    ``evalfis`` at the rows of ``x`` (an empty array without ``x``)."""
    inputs = ""
    if x is not None:
        inputs = str(work / "inputs.txt")
        np.savetxt(inputs, x, fmt="%.17g")
    code = (_DRIVER.replace("TOOLKIT", setup).replace("FIS", str(path))
            .replace("INPUTS", inputs))
    done = subprocess.run(["octave-cli", "--norc", "--quiet", "--no-history", "--eval", code],
                          check=True, capture_output=True, text=True, timeout=600)
    lines = done.stdout.splitlines()
    variables: dict[str, list[tuple[str, float, float]]] = {"input": [], "output": []}
    rows = []
    for line in lines:
        kind, _, rest = line.partition(" ")
        if kind in variables:
            name, lo, hi = rest.rsplit(" ", 2)
            variables[kind].append((name, float(lo), float(hi)))
        else:
            rows.append([float(v) for v in line.split()])
    return variables["input"], variables["output"], np.array(rows)


def table(example: Example, setup: str, described: str, work: Path) -> str:
    """The reference table of one file: Octave's evalfis on the file's grid."""
    path = FILES / example.path
    ins, outs, _ = run(setup, path, None, work)
    x = grid([(lo, hi) for _, lo, hi in ins])
    _, _, y = run(setup, path, x, work)
    assert y.shape == (len(x), len(outs)), f"{example.path}: evalfis gave {y.shape}"
    spans = "; ".join(f"{lo!r} {hi!r}" for _, lo, hi in outs)
    body = [",".join(repr(float(v)) for v in [*xi, *yi]) for xi, yi in zip(x, y, strict=True)]
    return "\n".join([f"# {described}: evalfis of {example.path}",
                      "# at the toolkit's default 101 points, both ends included",
                      f"# output ranges: {spans}",
                      ",".join(n for n, _, _ in [*ins, *outs]), *body]) + "\n"


def wanted() -> list[Example]:
    """The Octave toolkit's files (``octave/``)."""
    return [e for e in examples() if e.source == "octave"]


def cross_check(setup: str, work: Path) -> float:
    """Octave at the inputs of every other Octave file's reference table; the largest
    difference relative to the output's range, printed per file."""
    worst = 0.0
    # a twin with a documented defect: its corrected table, whichever file it is corrected for
    corrected = {e.twin: e.correction for e in examples() if e.correction is not None}
    for example in examples():
        if example.source != "octave" or example.twin is None or example.reference is None:
            continue
        tag = corrected.get(example.twin)
        reference = (example.variant(tag) if tag else None) or example.reference
        lines = reference.read_text().splitlines()
        spans = [tuple(float(v) for v in part.split()) for part in
                 next(line for line in lines if line.startswith("# output ranges: "))
                 .removeprefix("# output ranges: ").split("; ")]
        rows = np.array([[float(v) for v in line.split(",")]
                         for line in [line for line in lines if not line.startswith("#")][1:]])
        n_in = rows.shape[1] - len(spans)
        try:
            _, _, y = run(setup, FILES / example.path, rows[:, :n_in], work)
        except subprocess.CalledProcessError as err:
            print(f"{example.path}: Octave does not evaluate it: "
                  f"{err.stderr.strip().splitlines()[-1:]}")
            continue
        scale = np.array([hi - lo for lo, hi in spans])
        error = float(np.max(np.abs(y - rows[:, n_in:]) / scale))
        worst = max(worst, error)
        print(f"{example.path}: {len(rows)} points, largest difference {error:.3g} of the "
              f"range (reference {reference.name})")
    return worst


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mirror", nargs="?", help="a bare clone of "
                        "lmarkowsky/fuzzy-logic-toolkit (the files' commit is used)")
    parser.add_argument("--installed", action="store_true",
                        help="Octave's installed toolkit instead (compares only)")
    parser.add_argument("--check", action="store_true", help="compare, do not write")
    parser.add_argument("--cross-check", action="store_true",
                        help="compare Octave with the other Octave files' references")
    args = parser.parse_args(argv)
    if (args.mirror is None) != args.installed:
        parser.error("give a bare clone of the toolkit, or --installed")
    if args.installed and not (args.check or args.cross_check):
        parser.error("--installed compares only: the tables are the files' own toolkit's")
    with tempfile.TemporaryDirectory() as scratch:
        work = Path(scratch)
        setup, described = toolkit(args.mirror, work)
        print(f"Octave: {described}")
        if args.cross_check:
            worst = cross_check(setup, work)
            print(f"largest difference {worst:.3g} of the range")
            return 1 if worst > TOLERANCE else 0
        tables = {e.path.replace("/", "__") + SUFFIX: table(e, setup, described, work)
                  for e in wanted()}
    stale = sorted(p.name for p in REFERENCES.glob(f"*{SUFFIX}") if p.name not in tables)
    changed = [n for n, text in tables.items()
               if not (REFERENCES / n).exists() or (REFERENCES / n).read_text() != text]
    if args.check:
        for name in changed + stale:
            print(f"differs: {name}")
            kept, made = (REFERENCES / name), tables.get(name)
            if kept.exists() and made is not None:
                _difference(kept.read_text(), made)
        return 1 if changed or stale else 0
    for name in changed:
        (REFERENCES / name).write_text(tables[name])
    for name in stale:
        (REFERENCES / name).unlink()
    print(f"{len(tables)} tables, {len(changed)} written, {len(stale)} removed")
    return 0


def _difference(kept: str, made: str) -> None:
    """Print the largest difference of two tables of the same inputs, relative to the range."""
    def parse(text: str) -> tuple[np.ndarray, np.ndarray]:
        lines = text.splitlines()
        spans = np.array([[float(v) for v in part.split()] for part in
                          next(line for line in lines if line.startswith("# output ranges: "))
                          .removeprefix("# output ranges: ").split("; ")])
        rows = np.array([[float(v) for v in line.split(",")]
                         for line in [line for line in lines if not line.startswith("#")][1:]])
        return spans, rows

    spans, a = parse(kept)
    _, b = parse(made)
    m = len(spans)
    if a.shape != b.shape or not np.array_equal(a[:, :-m], b[:, :-m]):
        print("  not the same inputs")
        return
    error = np.max(np.abs(a[:, -m:] - b[:, -m:]) / (spans[:, 1] - spans[:, 0]))
    print(f"  largest difference {error:.3g} of the range")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

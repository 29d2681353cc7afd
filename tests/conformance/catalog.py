"""The conformance suite's files and, for each, the file its reference comes from.

Standard library only: ``make_references.py`` imports it in an environment that has
pyfuzzylite but not it2track (pyfuzzylite 8 pins numpy < 2).

Every example file (``.fis``, ``.fll``, ``.fcl`` under ``files/``) is compared with an
independent engine's reading of its *twin*: a ``.fll`` describing the same system, evaluated by
pyfuzzylite. A ``.fll`` is its own twin. fuzzylite's exported ``.fis``/``.fcl`` files have the
``.fll`` exported beside them (the same rounded numbers); the MATLAB and Octave originals have
the ``.fll`` fuzzylite wrote for them under ``examples/original/`` (fuzzylite's examples/
README: "to include scalar values with at least the same number of decimal places").
jFuzzyLogic's ``.fcl`` files have no twin; nor has the Octave toolkit's
``mamdani_tip_calculator.fis`` (below). Their references are the publishers' engines:
``make_jfl_references.py`` (``@jfl.csv``; ``@jfl-terms.csv`` for a file that is no system
but a term library) and ``make_octave_references.py`` (``@octave.csv``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).parent
FILES = HERE / "files"
REFERENCES = HERE / "references"
SUFFIXES = (".fis", ".fll", ".fcl")
#: Mamdani output points by format: MATLAB's evalfis 101 for .fis; for .fcl jFuzzyLogic's
#: 1000 intervals (1001 points); a .fll's own Centroid N gives N + 1 (None)
POINTS = {".fis": 101, ".fcl": 1001, ".fll": None}
_TWIN_EXCEPTIONS: dict[str, str | None] = {
    # MATLAB's sltbu.fis writes its ranges as pi/4; fuzzylite's copy sltbu_fl.fis as numbers
    "fuzzylite/examples/original/takagi-sugeno/matlab/sltbu.fis":
        "fuzzylite/examples/original/takagi-sugeno/matlab/sltbu_fl.fll",
    # fuzzylite's .fll is of the 2012 file (AndMethod 'prod', AggMethod 'sum'); Octave's file
    # now has 'min' and 'max': not the same system
    "octave/inst/mamdani_tip_calculator.fis": None,
}
#: outputs named apart from the twin's (it2track's name -> the twin's), compared by name
OUTPUT_NAMES: dict[str, dict[str, str]] = {
    # fuzzylite's .fll of its 2012 Tsukamoto example renamed the outputs and added Concaves;
    # Ramps, Sigmoids and ZSShapes have the .fis's terms and rules (outputs are independent)
    "fuzzylite/examples/original/tsukamoto/tsukamoto.fis":
        {"A": "Ramps", "B": "Sigmoids", "C": "ZSShapes"},
}

#: files compared with a *corrected* reference: their twin evaluated by pyfuzzylite with a
#: documented defect of the twin corrected (``make_references.py`` applies the correction,
#: the table's header says what it changed, ``notes.CORRECTIONS`` why); the original
#: reference stays reported beside it
CORRECTED: dict[str, str] = {
    # fuzzylite's .fll names the nine output terms alike; the .fis's rules index them
    "fuzzylite/examples/original/takagi-sugeno/matlab/juggler.fis": "terms-apart",
    "fuzzylite/examples/takagi-sugeno/matlab/juggler.fis": "terms-apart",
    # fuzzylite's importer read MATLAB's AggMethod='sum' as probabilistic OR
    "fuzzylite/examples/original/mamdani/octave/mamdani_tip_calculator.fis": "unbounded-sum",
    # fuzzylite read Octave's hedge fractions as its own hedges, not Octave's powers
    "fuzzylite/examples/original/mamdani/octave/investment_portfolio.fis": "octave-powers",
    "fuzzylite/examples/original/takagi-sugeno/octave/sugeno_tip_calculator.fis":
        "octave-powers",
    "octave/inst/sugeno_tip_calculator.fis": "octave-powers",
    # fuzzylite 6's .fis has no Default: MATLAB's middle of the range, read by a chained
    # Function (the twin's default nan hides it only where no rule of any output fires)
    "fuzzylite/examples/takagi-sugeno/approximation.fis": "matlab-default",
}


@dataclass(frozen=True)
class Example:
    """One example file: its path under ``files/``, its source, and its twin (or None)."""

    path: str
    twin: str | None

    @property
    def source(self) -> str:
        return self.path.split("/", 1)[0]

    @property
    def suffix(self) -> str:
        return Path(self.path).suffix

    @property
    def reference(self) -> Path | None:
        """The reference table under ``references/`` (``None``: no twin, or no table).

        A ``.fll`` is evaluated at its own defuzzifier's resolution (``N + 1`` points); a
        ``.fis`` or ``.fcl`` at it2track's for the format (:data:`POINTS`, ``@101`` in the
        name), where it matters: a twin without a Mamdani output has one table.
        """
        if self.source == "jfuzzylogic" or (self.source == "octave" and self.twin is None):
            # the publisher's engine: jFuzzyLogic's outputs; Octave's evalfis (no twin .fll)
            own = "jfl" if self.source == "jfuzzylogic" else "octave"
            table = REFERENCES / (self.path.replace("/", "__") + f"@{own}.csv")
            return table if table.exists() else None
        if self.twin is None:
            return None
        stem = self.twin.replace("/", "__")
        points = POINTS[self.suffix]
        names = [f"{stem}.csv"] if points is None else [f"{stem}@{points}.csv", f"{stem}.csv"]
        return next((REFERENCES / n for n in names if (REFERENCES / n).exists()), None)

    @property
    def publisher(self) -> Path | None:
        """The Octave toolkit's own ``evalfis`` table of an ``octave/`` file
        (``make_octave_references.py``), or None: the reference of the file read with
        ``dialect="octave"`` (for a file with no twin, also :attr:`reference`)."""
        if self.source != "octave":
            return None
        table = REFERENCES / (self.path.replace("/", "__") + "@octave.csv")
        return table if table.exists() else None

    @property
    def terms(self) -> Path | None:
        """jFuzzyLogic's table of the memberships of the file's input terms
        (``@jfl-terms.csv``, ``make_jfl_references.py``), or None: the reference of a
        jFuzzyLogic file that is no fuzzy system but a term library (inputs only, or an
        output without terms)."""
        table = REFERENCES / (self.path.replace("/", "__") + "@jfl-terms.csv")
        return table if table.exists() else None

    def variant(self, tag: str) -> Path | None:
        """The reference table ``tag`` of :attr:`reference` (``@tag`` before ``.csv``), or
        None: ``sequence`` (the twin evaluated in order with its ``lock-previous``) or a
        correction of :data:`CORRECTED`."""
        base = self.reference
        if base is None:
            return None
        table = base.with_name(base.name.removesuffix(".csv") + f"@{tag}.csv")
        return table if table.exists() else None

    @property
    def correction(self) -> str | None:
        """The correction of this file's reference (:data:`CORRECTED`), or None."""
        return CORRECTED.get(self.path)


def twin_of(path: str) -> str | None:
    """The ``.fll`` whose pyfuzzylite evaluation is ``path``'s reference."""
    if path in _TWIN_EXCEPTIONS:
        return _TWIN_EXCEPTIONS[path]
    p = Path(path)
    if p.suffix == ".fll":
        return path
    if path.startswith("fuzzylite/examples/"):
        candidate = p.with_suffix(".fll")
        return candidate.as_posix() if (FILES / candidate).exists() else None
    if path.startswith("octave/inst/"):
        for kind in ("mamdani", "takagi-sugeno"):
            candidate = f"fuzzylite/examples/original/{kind}/octave/{p.stem}.fll"
            if (FILES / candidate).exists():
                return candidate
    return None


def examples() -> list[Example]:
    """Every example file, sorted by path."""
    found = sorted(p.relative_to(FILES).as_posix() for p in FILES.rglob("*")
                   if p.suffix in SUFFIXES)
    return [Example(path, twin_of(path)) for path in found]


def corrections() -> dict[tuple[str, int | None], set[tuple[str, str]]]:
    """``(twin, resolution)`` -> the ``(correction, example path)`` pairs it is needed for."""
    needed: dict[tuple[str, int | None], set[tuple[str, str]]] = {}
    for example in examples():
        if example.correction is not None and example.twin is not None:
            key = (example.twin, POINTS[example.suffix])
            needed.setdefault(key, set()).add((example.correction, example.path))
    return needed


def twins() -> dict[str, set[int | None]]:
    """Each twin and the resolutions its readers need (``None``: the ``.fll``'s own)."""
    needed: dict[str, set[int | None]] = {}
    for example in examples():
        if example.twin is not None:
            needed.setdefault(example.twin, set()).add(POINTS[example.suffix])
    return needed

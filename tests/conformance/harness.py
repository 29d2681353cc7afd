"""Load every conformance file with it2track and compare with its reference table.

``check(example)`` gives a :class:`Result`: the file loads and agrees with pyfuzzylite's
reading of its twin (``≤ 1e-9`` relative to the output range, Mamdani at matched resolution),
loads and differs (``notes.py`` must say which is right and why), loads with no reference, or
is refused (the :class:`~it2track.io.FisFormatError`, naming the line and the feature).

Where the reference has no output (fuzzylite's ``default: nan`` where no rule fires, ``inf``
where a Tsukamoto set is read beyond its range) it2track must have none either -- a
:class:`~it2track.fuzzy.ZeroFiringError` or the ``ValueError`` of a set without an inverse --
or, for a MATLAB ``.fis``, MATLAB's documented fallback (the middle of the output range) at a
point where none of its rules fires.

A file that keeps an output's previous value where no rule fires (fuzzylite's
``lock-previous``, FCL's ``NC``) is evaluated as a sequence, the reference table's rows in
order from a fresh start (``evaluate_sequence``), against the twin evaluated so
(``...@sequence.csv``). A file of ``catalog.CORRECTED`` is compared with its corrected
reference; its difference from the original reference is kept for the docs.

A jFuzzyLogic file refused as a system because it is none (its function blocks have no output
with terms) but with jFuzzyLogic's table of its input terms (``catalog.Example.terms``) is
compared as a term library: ``table="terms"``, every membership of ``load_terms`` within
``1e-9`` of jFuzzyLogic's; counted apart from the systems.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from catalog import FILES, OUTPUT_NAMES, Example, examples

from it2track.fuzzy import HybridSystem
from it2track.fuzzy.sequence import chain_outputs
from it2track.io import FisFormatError, load, load_terms

#: agreement bound, relative to the output's range
TOLERANCE = 1e-9


@dataclass(frozen=True)
class Result:
    """What happened to one example file."""

    example: Example
    status: str  # "agrees", "differs", "loads", "refused"
    detail: str = ""
    error: float | None = None  # largest |ours - reference| / range
    points: int = 0
    fallback: int = 0  # points where neither engine has a rule firing
    warnings: tuple[str, ...] = field(default=())
    table: str = ""  # "sequence", a correction of catalog.CORRECTED, or "" (the twin as is)
    original: str = ""  # with a correction: the comparison with the uncorrected reference


def _reference(path: Path) -> tuple[list[str], list[tuple[float, float]], np.ndarray]:
    lines = path.read_text().splitlines()
    spans_line = next(line for line in lines if line.startswith("# output ranges: "))
    spans = [tuple(float(v) for v in part.split())
             for part in spans_line.removeprefix("# output ranges: ").split("; ")]
    body = [line for line in lines if not line.startswith("#")]
    names = body[0].split(",")
    rows = np.array([[float(v) for v in line.split(",")] for line in body[1:]])
    return names, spans, rows  # type: ignore[return-value]


def _single(system, k: int):
    """The system of output ``k`` alone (its rules, its zero-firing value)."""
    if isinstance(system, HybridSystem):
        for part in system.systems:
            if k < part.n_outputs:
                return _single(part, k)
            k -= part.n_outputs
    if system.n_outputs == 1:
        return system
    rules = [r.with_consequents([r.consequents[k]], [k])
             for r in system.rules if r.consequents[k] is not None]
    outputs = system.outputs
    if outputs:
        outputs = (outputs[k],)
    return dataclasses.replace(system, rules=tuple(rules), outputs=outputs,
                               on_zero_firing=system.zero_firing_value(k),
                               lock_previous=system.keeps_previous(k))


def _locks(system) -> bool:
    return any(system.keeps_previous(k) for k in range(system.n_outputs))


def _ours_in_order(system, x: np.ndarray) -> np.ndarray:
    """Outputs ``(N, m)`` of the rows evaluated in order from a fresh start, each output
    keeping its previous value where it has one; NaN where it2track has none (no rule fires,
    and no previous output and no default), the state then unchanged, as fuzzylite's."""
    m = system.n_outputs
    if getattr(system, "_chained", False):  # outputs read outputs: NaN where one has none
        return chain_outputs(system, x, sequence=True)
    try:
        y, _ = system.evaluate_sequence(x)
        return np.asarray(y, dtype=float).reshape(len(x), m)
    except ValueError:
        out = np.empty((len(x), m))
        parts = [_single(system, k) for k in range(m)]
        state = [None] * m
        for i in range(len(x)):
            for k, part in enumerate(parts):
                try:
                    y, state[k] = part.evaluate_sequence(x[i:i + 1], state[k])
                    out[i, k] = float(y[0])
                except ValueError:
                    out[i, k] = np.nan
        return out


def _ours(system, x: np.ndarray) -> np.ndarray:
    """Outputs ``(N, m)``; NaN where it2track has none: ZeroFiringError (no rule fires), or
    the ValueError of a Tsukamoto set fired beyond its range (no inverse)."""
    m = system.n_outputs
    if getattr(system, "_chained", False):
        return chain_outputs(system, x)
    try:
        y = np.asarray(system.evaluate(x), dtype=float)
        return y.reshape(len(x), m)
    except ValueError:
        out = np.empty((len(x), m))
        for i, row in enumerate(x):
            for k in range(m):
                part = _single(system, k)
                try:
                    out[i, k] = float(np.asarray(part.evaluate(row), dtype=float))
                except ValueError:
                    out[i, k] = np.nan
        return out


def _nothing_fires(system, x: np.ndarray) -> np.ndarray:
    _, upper = system.firing(*x.T)
    return np.asarray(upper).reshape(len(x), -1).sum(axis=1) == 0


@functools.cache
def check(example: Example) -> Result:
    """Load ``example`` and compare it with its reference."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            system = load(FILES / example.path)
        except FisFormatError as err:
            where = f"line {err.line}: " if err.line is not None else ""
            refused = Result(example, "refused", where + err.message)
            return refused if example.terms is None else _term_library(refused, example.terms)
    noted = tuple(str(w.message).split(": ", 1)[-1] for w in caught)
    if example.reference is None:
        why = "no twin .fll" if example.twin is None else "pyfuzzylite cannot evaluate its twin"
        return Result(example, "loads", why, warnings=noted)
    tag = "sequence" if _locks(system) else example.correction or ""
    table = example.variant(tag) if tag else example.reference
    if table is None:
        return Result(example, "loads", f"no {tag} reference table", warnings=noted, table=tag)
    result = _compare(example, system, table, noted, in_order=tag == "sequence")
    if example.correction is None or tag == "sequence":
        return result
    original = _compare(example, system, example.reference, noted, in_order=False)
    return dataclasses.replace(result, table=tag, original=original.detail or "agrees")


def _term_library(refused: Result, table: Path) -> Result:
    """A file refused as a system, compared as a term library: every membership of
    :func:`~it2track.io.load_terms`'s input terms with jFuzzyLogic's ``table`` (``agrees`` with
    ``table="terms"`` within :data:`TOLERANCE`, absolute: memberships are in [0, 1]). Where
    the terms are refused too, the file stays refused, the term reader's reason added."""
    example = refused.example
    lines = [line for line in table.read_text().splitlines() if not line.startswith("#")][1:]
    rows = [line.split(",") for line in lines]
    blocks = dict.fromkeys(row[0] for row in rows)
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        try:
            read = {b: load_terms(FILES / example.path, block=b) for b in blocks}
        except FisFormatError as err:
            where = f"line {err.line}: " if err.line is not None else ""
            return dataclasses.replace(refused, detail=f"{refused.detail}; its terms: "
                                       f"{where}{err.message}")
    worst, problems = 0.0, []
    for block, name, x, term, mu in rows:
        variable = read[block].get(name)
        names = [s.name for s in variable.sets] if variable is not None else []
        if term not in names:
            problems.append(f"{block}.{name} has no term {term!r}")
            continue
        assert variable is not None
        lower, upper = variable.sets[names.index(term)](float(x))
        if float(lower) != float(upper):
            problems.append(f"{block}.{name}.{term} is not type-1 at {x}")
            continue
        worst = max(worst, abs(float(upper) - float(mu)))
    ours = {(b, v.name, s.name) for b in blocks for v in read[b].values() for s in v.sets}
    theirs = {(row[0], row[1], row[3]) for row in rows}
    if ours != theirs:
        problems.append(f"terms {sorted(ours ^ theirs)} in one reading only")
    if problems:
        return Result(example, "differs", f"as a term library: {problems[0]}", worst,
                      len(rows), table="terms")
    status = "agrees" if worst <= TOLERANCE else "differs"
    detail = "" if status == "agrees" else f"as a term library: largest difference {worst:.3g}"
    return Result(example, status, detail, worst, len(rows), table="terms")


def _compare(example: Example, system, table: Path, noted: tuple[str, ...], *, in_order: bool
             ) -> Result:
    """``system`` against the reference ``table`` (its rows in order with ``in_order``)."""
    names, spans, rows = _reference(table)
    n_in = len(names) - len(spans)
    x, ref = rows[:, :n_in], rows[:, n_in:]
    # jFuzzyLogic sorts its variables by name: put them in it2track's order
    ours_in, outs = [i.name for i in system.inputs], list(system.output_names)
    if sorted(names[:n_in]) == sorted(ours_in):
        x = x[:, [names.index(n) for n in ours_in]]
    rename = OUTPUT_NAMES.get(example.path)
    if rename is not None:  # the twin's outputs of these names, in it2track's order
        outs = [rename.get(n, n) for n in outs]
        if set(outs) <= set(names[n_in:]):
            columns = [names[n_in:].index(n) for n in outs]
            ref, spans, names = ref[:, columns], [spans[c] for c in columns], names[:n_in] + outs
    if sorted(names[n_in:]) == sorted(outs):
        columns = [names[n_in:].index(n) for n in outs]
        ref, spans = ref[:, columns], [spans[c] for c in columns]
    if system.n_inputs != n_in or system.n_outputs != ref.shape[1]:
        return Result(example, "differs", f"{system.n_inputs} inputs and {system.n_outputs} "
                      f"outputs; the reference has {n_in} and {ref.shape[1]}", warnings=noted)
    ours = _ours_in_order(system, x) if in_order else _ours(system, x)
    worst, fallback, problems = 0.0, 0, []
    idle = None
    for k in range(ref.shape[1]):
        lo, hi = spans[k]
        finite = ref[np.isfinite(ref[:, k]), k]
        scale = hi - lo if hi > lo else (float(np.ptp(finite)) if finite.size else 0.0) or 1.0
        for i in range(len(x)):
            r, o = ref[i, k], ours[i, k]
            if not math.isfinite(r):  # fuzzylite: nan (no rule fires), inf (no inverse)
                if math.isnan(o):
                    fallback += 1
                    continue
                idle = _nothing_fires(system, x) if idle is None else idle
                if idle[i] and o == system.zero_firing_value(k):
                    fallback += 1
                    continue
                problems.append(f"output {k + 1} at {x[i].tolist()}: reference has none, "
                                f"it2track {o!r}")
            elif math.isnan(o):
                problems.append(f"output {k + 1} at {x[i].tolist()}: it2track has none (no rule "
                                f"fires), reference {r!r}")
            else:
                worst = max(worst, abs(o - r) / scale)
    tag = "sequence" if in_order else ""
    if problems:
        return Result(example, "differs", f"{len(problems)} points: {problems[0]}", worst,
                      len(x), fallback, noted, tag)
    status = "agrees" if worst <= TOLERANCE else "differs"
    detail = "" if status == "agrees" else f"largest difference {worst:.3g} of the range"
    return Result(example, status, detail, worst, len(x), fallback, noted, tag)


@functools.cache
def check_reading(example: Example, dialect: str | None) -> Result:
    """``example`` read with ``load(..., dialect=dialect)`` (``None``: the default, MATLAB's
    reading of a ``.fis``) against the Octave toolkit's own ``evalfis`` table of it
    (``example.publisher``; status ``loads`` without one)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            system = load(FILES / example.path, dialect=dialect)
        except FisFormatError as err:
            where = f"line {err.line}: " if err.line is not None else ""
            return Result(example, "refused", where + err.message)
    noted = tuple(str(w.message).split(": ", 1)[-1] for w in caught)
    if example.publisher is None:
        return Result(example, "loads", "no table of Octave's evalfis", warnings=noted)
    return _compare(example, system, example.publisher, noted, in_order=False)


def results() -> list[Result]:
    """Every example's result, by path."""
    return [check(example) for example in examples()]

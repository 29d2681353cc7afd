"""What the float and the fixed-point generators share: the reducer they carry, the rows' labels
and evaluation order, the reducers' titles and the template environment."""

from __future__ import annotations

from typing import Any

import jinja2

from ..fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    IT2Sugeno,
    MFKind,
    T1Sugeno,
    TypeReducer,
)
from ..io.errors import UnsupportedFeatureError

__all__ = ["REDUCERS", "TITLES", "dependencies", "environment", "reducer_of", "row_label"]

#: The built-in reducers, by name (a reducer is accepted only if it *is* one of these, up to
#: its iteration cap).
REDUCERS: dict[str, TypeReducer] = {
    r.name: r for r in (EXHAUSTIVE, KM, EKM, EIASC, NIE_TAN, WU_MENDEL)
}
#: What the header and the comments call each reducer.
TITLES = {
    "type-1": "type-1 weighted average", "exhaustive": "exhaustive (exact, non-iterative)",
    "km": "Karnik-Mendel (exact, iterative)", "ekm": "enhanced Karnik-Mendel (exact, "
    "iterative)", "eiasc": "EIASC (exact, iterative)", "nie-tan": "Nie-Tan (closed-form "
    "approximation)", "wu-mendel": "Wu-Mendel uncertainty bounds (closed-form "
    "approximation)",
}


def reducer_of(system: IT2Sugeno | T1Sugeno) -> TypeReducer | None:
    if type(system) is T1Sugeno:
        return None
    assert isinstance(system, IT2Sugeno)
    red = system.reducer
    known = REDUCERS.get(red.name)
    same = known is not None and (
        red._left is known._left and red._right is known._right
        and red._approx is known._approx and red.exact == known.exact
    )
    if not same:
        raise UnsupportedFeatureError(
            f"type reducer {red!r} is not one of it2track's built-in reducers "
            f"({', '.join(REDUCERS)}); C generation needs one of them"
        )
    return red


def row_label(system: IT2Sugeno | T1Sugeno, row: int) -> str:
    tables = system.tables
    inp = system.inputs[int(tables.mf_input[row])]
    for s in inp.sets:
        if s.upper is tables.mfs[row] or s.upper == tables.mfs[row]:
            return f"row {row}: {inp.name} {s.name} upper"
        if s.lower is tables.mfs[row] or s.lower == tables.mfs[row]:
            return f"row {row}: {inp.name} {s.name} lower"
    return f"row {row}: {inp.name}"  # pragma: no cover - every row belongs to a set


def environment() -> jinja2.Environment:
    env = jinja2.Environment(
        loader=jinja2.PackageLoader("it2track.codegen", "templates"),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )
    return env


_GROUP = {MFKind.TRAPEZOID: 0, MFKind.GAUSSIAN: 1, MFKind.UM_GAUSSIAN_UPPER: 2,
          MFKind.UM_GAUSSIAN_LOWER: 2}


def dependencies(tables: Any) -> list[int]:
    """For each row, the upper row it is only ever read together with as a lower row (so it
    need not be evaluated where that upper row is 0), or ``n_rows`` (the constant-1 row: none).

    A row qualifies if it is never an upper row, every rule reads it as the lower partner of
    the same upper row, and that row is of the same table (evaluated in the same loop)."""
    n_rows = tables.n_rows
    uppers = set(tables.upper_rows_s.ravel().tolist())
    partners: dict[int, set[int]] = {}
    for lower, upper in zip(tables.lower_rows_s.ravel().tolist(),
                            tables.upper_rows_s.ravel().tolist(), strict=True):
        partners.setdefault(lower, set()).add(upper)
    out = []
    for k in range(n_rows):
        ups = partners.get(k, set())
        if k in uppers or len(ups) != 1:
            out.append(n_rows)
            continue
        (u,) = ups
        same = u != n_rows and _GROUP[MFKind(int(tables.mf_kind[u]))] == _GROUP[
            MFKind(int(tables.mf_kind[k]))]
        out.append(u if same else n_rows)
    return out



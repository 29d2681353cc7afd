"""The paper's heading controller (Tables 1, 2 and 4), for any Footprint-of-Uncertainty width.

Two inputs, the heading error ``e`` and its change ``de``, each with the sets N, Z, P on
``[-1, 1]``; nine rules with crisp consequents in volts (Table 2). For FoU width ``w`` the sets are
the type-1 centre lines N ``[-1 -1 -0.2]``, Z ``[-0.8 0 0.8]``, P ``[0.2 1 1]`` widened by ``w/2``
on each sloped side (DESIGN.md sec. 3): ``w = 0.2`` is Table 1, ``w = 0.1, 0.3`` are Table 4 and
``w = 0`` is the paper's ordinary type-1 FLC.

Near the origin only the Z sets fire, so the type-1 FLC has a dead zone ``|e| < 0.2`` (for small
``de``); the FoU narrows it to ``0.2 - w/2``. :func:`dead_zone_matched_fls` is the fair type-1
baseline with the same dead zone as the IT2FLC of width ``w``.
"""

from __future__ import annotations

from collections.abc import Sequence
from numbers import Real

from .fuzzy import (
    EXHAUSTIVE,
    Input,
    IT2Set,
    IT2Sugeno,
    Rule,
    T1Sugeno,
    TNorm,
    Triangle,
    TypeReducer,
    rules_from_table,
)

__all__ = [
    "CENTRE_SETS",
    "RULE_TABLE",
    "dead_zone_matched_fls",
    "heading_fls",
    "heading_fls_widths",
]

#: Type-1 centre lines of the three sets (``[a b c]``), shared by both inputs.
CENTRE_SETS: dict[str, Triangle] = {
    "N": Triangle(-1.0, -1.0, -0.2),
    "Z": Triangle(-0.8, 0.0, 0.8),
    "P": Triangle(0.2, 1.0, 1.0),
}
#: Table 2: rows e in (N, Z, P), columns de in (N, Z, P), consequents in volts.
RULE_TABLE: tuple[tuple[float, float, float], ...] = (
    (-12.0, -8.0, -4.0),
    (-8.0, 0.0, 8.0),
    (4.0, 8.0, 12.0),
)
LABELS = ("N", "Z", "P")
#: Largest FoU width for which every lower MF keeps a positive support (Z: 0.8 - w/2 > 0 and
#: N/P: the lower foot must stay inside the universe).
MAX_FOU = 1.6


def _width(value: object, name: str) -> float:
    """A FoU width as a float; strings and booleans are refused, not converted
    (``heading_fls("0.2")`` or ``heading_fls(True)`` would silently build FoU 0.2 or 1)."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise ValueError(f"{name}={value!r} must be a real number (a FoU width)")
    return float(value)


def _rules() -> tuple[Rule, ...]:
    return rules_from_table(LABELS, LABELS, RULE_TABLE)


def heading_fls(
    fou: float,
    *,
    reducer: TypeReducer = EXHAUSTIVE,
    tnorm: TNorm = TNorm.PRODUCT,
) -> IT2Sugeno | T1Sugeno:
    """The paper's heading controller with FoU width ``fou``.

    Parameters
    ----------
    fou : float
        FoU width ``w >= 0``. ``0`` returns the type-1 FLC (a :class:`T1Sugeno`).
    reducer : TypeReducer
        Type reducer for ``fou > 0`` (the paper used KM; all exact reducers agree to 1e-12).
    tnorm : TNorm
        Product (paper) or minimum.

    Returns
    -------
    IT2Sugeno or T1Sugeno
        Call as ``fls(e, de)`` with arrays (broadcasting) -> ``u`` in volts;
        ``fls.interval(e, de)`` -> ``(yl, yr)``. Inputs are clipped to ``[-1, 1]``.

    Examples
    --------
    >>> fls = heading_fls(0.2)
    >>> fls(0.5, 0.0)
    4.0
    >>> [round(float(v), 6) for v in fls.interval(0.5, 0.0)]
    [3.130435, 4.869565]
    >>> heading_fls(0.0)(0.1, 0.0)  # inside the type-1 dead zone
    0.0
    """
    fou = _width(fou, "fou")
    if not 0.0 <= fou < MAX_FOU:
        raise ValueError(f"fou={fou!r} must satisfy 0 <= fou < {MAX_FOU}")
    return heading_fls_widths(
        (fou, fou, fou), (fou, fou, fou), reducer=reducer, tnorm=tnorm,
        name=f"paper IT2FLC (FoU {fou:g})" if fou > 0.0 else "paper FLC (type-1)",
    )


def heading_fls_widths(
    e_widths: Sequence[float],
    de_widths: Sequence[float],
    *,
    reducer: TypeReducer = EXHAUSTIVE,
    tnorm: TNorm = TNorm.PRODUCT,
    name: str = "",
) -> IT2Sugeno | T1Sugeno:
    """The paper's controller with its own FoU width for every set of every input.

    Parameters
    ----------
    e_widths, de_widths : sequence of 3 floats
        FoU widths of the sets N, Z, P of the error ``e`` and of its change ``de``.
    reducer, tnorm
        As in :func:`heading_fls`.
    name : str
        The system's name (default: ``"paper IT2FLC (FoU e ... de ...)"`` with the widths, or
        ``"paper FLC (type-1)"`` when every width is 0).

    Returns
    -------
    IT2Sugeno or T1Sugeno
        A :class:`T1Sugeno` when every width is 0. ``heading_fls(w)`` is
        ``heading_fls_widths((w, w, w), (w, w, w))``.

    Raises
    ------
    ValueError
        If a width is negative or too large for its set.
    """
    inputs = []
    for label, widths in (("e", e_widths), ("de", de_widths)):
        try:
            if isinstance(widths, str | bytes):
                raise TypeError
            items = list(widths)
        except TypeError:
            raise ValueError(
                f"{label}_widths={widths!r} must be a sequence of 3 widths (N, Z, P)"
            ) from None
        ws = [_width(w, f"{label}_widths") for w in items]
        if len(ws) != len(LABELS):
            raise ValueError(f"{label}_widths={list(widths)!r} must be 3 widths (N, Z, P)")
        for k, w in zip(LABELS, ws, strict=True):
            if not 0.0 <= w < MAX_FOU:
                raise ValueError(
                    f"{label} set {k}: FoU width {w!r} must satisfy 0 <= w < {MAX_FOU}"
                )
        sets = [IT2Set.from_fou(CENTRE_SETS[k], w, k) for k, w in zip(LABELS, ws, strict=True)]
        inputs.append(Input(label, (-1.0, 1.0), sets))
    type1 = all(s.is_type1 for inp in inputs for s in inp.sets)
    if not name:
        name = "paper FLC (type-1)" if type1 else "paper IT2FLC (FoU e {} de {})".format(
            ",".join(f"{w:g}" for w in e_widths), ",".join(f"{w:g}" for w in de_widths)
        )
    if type1:
        return T1Sugeno(inputs=tuple(inputs), rules=_rules(), tnorm=tnorm, name=name)
    return IT2Sugeno(
        inputs=tuple(inputs), rules=_rules(), tnorm=tnorm, reducer=reducer, name=name
    )


def dead_zone_matched_fls(fou: float, *, tnorm: TNorm = TNorm.PRODUCT) -> T1Sugeno:
    """Type-1 FLC built from the upper MFs of :func:`heading_fls` ``(fou)``.

    Its sets are the centre lines moved by ``fou/2`` (N and P inwards, Z widened), so its dead
    zone ``|e| < 0.2 - fou/2`` equals the IT2FLC's: comparing the two isolates the effect of the
    footprint itself from the effect of a narrower dead zone. ``tnorm`` as in
    :func:`heading_fls`.
    """
    fou = _width(fou, "fou")
    if not 0.0 <= fou < MAX_FOU:
        raise ValueError(f"fou={fou!r} must satisfy 0 <= fou < {MAX_FOU}")
    sets = [IT2Set.from_fou(CENTRE_SETS[k], fou, k).upper for k in LABELS]
    named = [IT2Set.type1(mf, k) for mf, k in zip(sets, LABELS, strict=True)]
    inputs = (Input("e", (-1.0, 1.0), named), Input("de", (-1.0, 1.0), named))
    return T1Sugeno(
        inputs=inputs, rules=_rules(), tnorm=tnorm, name=f"type-1 FLC, dead zone of FoU {fou:g}"
    )

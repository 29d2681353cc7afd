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
from typing import Any

from .fuzzy import (
    EXHAUSTIVE,
    Input,
    IT2Mamdani,
    IT2Set,
    IT2Sugeno,
    Linear,
    Output,
    Rule,
    T1Mamdani,
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
    "heading_mamdani",
    "heading_tsk",
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


def _voltage(rule: Rule) -> float:
    """The voltage of a rule of Table 2 (a crisp zero-order consequent)."""
    cons = rule.consequents[0]
    assert isinstance(cons, tuple)
    return float(cons[0])


#: The output sets of :func:`heading_mamdani`: a triangle around each voltage of Table 2.
MAMDANI_VOLTS: dict[str, float] = {"NH": -12.0, "NM": -8.0, "NL": -4.0, "Z": 0.0, "PL": 4.0,
                                   "PM": 8.0, "PH": 12.0}


def heading_mamdani(fou: float = 0.2, *, reducer: TypeReducer = EXHAUSTIVE, type1: bool = False,
                    output_fou: float = 2.0, **options: Any) -> IT2Mamdani | T1Mamdani:
    """The paper's controller as a Mamdani system (not in the paper: a variant for comparison
    and for the C generator's cost table).

    The inputs and rule table of :func:`heading_fls` ``(fou)``, each rule's voltage replaced by
    an output set: a triangle 4 V wide on each side around it (shoulders at +-12 V) on
    ``[-12, 12]`` V, widened by ``output_fou`` into an IT2 set; product t-norm, and the
    Mamdani defaults otherwise (min implication, max aggregation, 101-point grid).

    Parameters
    ----------
    fou : float
        FoU width of the input sets (as :func:`heading_fls`).
    reducer : TypeReducer
        The type reducer of the IT2 system.
    type1 : bool
        The type-1 system instead: the upper MFs of the inputs (the type-1 FLC's sets when
        ``fou = 0``) and of the output sets, defuzzified by the centroid.
    output_fou : float
        FoU width of the output sets (volts).
    **options
        Further fields of :class:`~it2track.fuzzy.IT2Mamdani` / ``T1Mamdani``
        (``implication``, ``aggregation``, ``resolution``, ``tnorm``, ...).

    Returns
    -------
    IT2Mamdani or T1Mamdani

    Examples
    --------
    >>> fls = heading_mamdani(0.2)
    >>> round(float(fls(0.5, 0.0)), 6), round(float(heading_mamdani(type1=True)(0.5, 0.0)), 6)
    (3.936795, 3.903585)
    """
    base = heading_fls(fou)
    sets = []
    for label, v in MAMDANI_VOLTS.items():
        left = v if v == -12.0 else v - 4.0
        right = v if v == 12.0 else v + 4.0
        s = IT2Set.from_fou(Triangle(left, v, right), output_fou, label)
        sets.append(IT2Set.type1(s.upper, label) if type1 else s)
    out = Output("u", (-12.0, 12.0), sets)
    label_of = {v: k for k, v in MAMDANI_VOLTS.items()}
    rules = [Rule(r.antecedent, label_of[_voltage(r)]) for r in base.rules]
    options.setdefault("tnorm", TNorm.PRODUCT)
    if type1:
        inputs = tuple(Input(i.name, i.universe, [IT2Set.type1(s.upper, s.name) for s in i.sets])
                       for i in base.inputs)
        return T1Mamdani(inputs=inputs, outputs=(out,), rules=tuple(rules),
                         name=f"paper Mamdani FLC, type-1 (FoU {fou:g})", **options)
    return IT2Mamdani(inputs=base.inputs, outputs=(out,), rules=tuple(rules),
                      reducer=reducer, name=f"paper Mamdani IT2FLC (FoU {fou:g})", **options)


def heading_tsk(fou: float = 0.2, *, reducer: TypeReducer = EXHAUSTIVE,
                slopes: tuple[object, object] = (1.5, (-0.5, 0.5))) -> IT2Sugeno | T1Sugeno:
    """The paper's controller with first-order (TSK) consequents (not in the paper: a variant
    for the C generator's tests and cost table): each rule's voltage ``y`` of Table 2 becomes
    ``y + a e + b de`` with ``(a, b) = slopes`` -- numbers or intervals ``(lo, hi)`` (interval
    coefficients need an IT2 system, ``fou > 0``).

    Parameters
    ----------
    fou : float
        FoU width of the input sets (``0``: a type-1 system).
    reducer : TypeReducer
        The type reducer (``fou > 0``).
    slopes : (a, b)
        Coefficients of ``e`` and ``de`` in every rule.

    Returns
    -------
    IT2Sugeno or T1Sugeno

    Examples
    --------
    >>> round(float(heading_tsk(0.2)(0.5, 0.0)), 6)
    4.75
    """
    base = heading_fls(fou, reducer=reducer)
    rules = [Rule(r.antecedent, Linear(list(slopes), _voltage(r)))  # type: ignore[arg-type]
             for r in base.rules]
    name = f"paper TSK FLC (FoU {fou:g})"
    if isinstance(base, T1Sugeno):
        return T1Sugeno(inputs=base.inputs, rules=tuple(rules), tnorm=base.tnorm, name=name)
    return IT2Sugeno(inputs=base.inputs, rules=tuple(rules), tnorm=base.tnorm, reducer=reducer,
                     name=name)

"""Decide whether a fuzzy system can be carried to C, and fill the templates.

What the generated code does is described in the header it writes (see
``templates/controller.h.j2``) and in :mod:`it2track.codegen`. This module decides *whether* a
system can be carried (an explicit allow-list: anything not listed is refused with
:class:`~it2track.io.UnsupportedFeatureError` naming the feature), then renders the templates
from the context :mod:`.floatgen` (float, double; with :mod:`.mamdani_c` for Mamdani systems)
or :mod:`.fixedpoint` (q15) computes.
"""

from __future__ import annotations

import re
from typing import Any

from ..fuzzy import (
    Aggregation,
    Defuzzifier,
    Implication,
    IT2Mamdani,
    IT2Sugeno,
    MFKind,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    WeightedDefuzzifier,
)
from ..fuzzy.mamdani import TypeReduction
from ..io.errors import UnsupportedFeatureError
from .code import CCode, RealType
from .fixedpoint import fixed_context
from .floatgen import float_context, norm_combiners
from .lowering import antecedent_tables, environment, reducer_of

__all__ = [
    "SUPPORTED_FEATURES",
    "CCode",
    "RealType",
    "check_supported",
    "generate_c",
]

#: Rule-language features of :attr:`SystemTables.features` the generator implements. Anything
#: else (a feature added to the fuzzy layer later included) is refused.
SUPPORTED_FEATURES: frozenset[str] = frozenset({"not", "or", "weights", "linear"})
#: What each feature the generator refuses is, for the message.
_FEATURE_TEXT = {"outputs": "several outputs (export one with select_output())",
                 "mamdani": "a Mamdani output",
                 "formula": "a formula consequent (fuzzylite's Function, jFuzzyLogic's "
                            "FUNCTION)",
                 "idle": "an output no rule concludes"}
#: The system types the generator knows (exact types: a subclass may change the semantics).
SUPPORTED_SYSTEMS: tuple[type, ...] = (IT2Sugeno, T1Sugeno, IT2Mamdani, T1Mamdani)
#: The operators the generated C implements, per kind (anything else is refused by name).
SUPPORTED_TNORMS = frozenset({TNorm.PRODUCT, TNorm.MINIMUM})
SUPPORTED_SNORMS = frozenset({SNorm.MAXIMUM, SNorm.PROBOR})
SUPPORTED_IMPLICATIONS = frozenset({Implication.MINIMUM, Implication.PRODUCT})
SUPPORTED_AGGREGATIONS = frozenset({Aggregation.MAXIMUM, Aggregation.SUM, Aggregation.PROBOR})
#: A type-1 Mamdani system's defuzzifier: the centroid. Bisector, MOM, SOM and LOM pick grid
#: points by exact comparisons (the running sum reaching half the total, the points equal to
#: the maximum), so a last-bit difference in the aggregated set -- which the C's memberships
#: may have against numpy's -- moves them by whole grid steps: they could be neither verified
#: against Python nor bounded in float.
SUPPORTED_DEFUZZIFIERS = frozenset({Defuzzifier.CENTROID})
#: Membership row kinds with a C implementation.
SUPPORTED_KINDS = frozenset({MFKind.TRAPEZOID, MFKind.GAUSSIAN, MFKind.UM_GAUSSIAN_UPPER,
                             MFKind.UM_GAUSSIAN_LOWER})
_IDENT = re.compile(r"[a-z][a-z0-9_]{0,30}")
#: C keywords and library names a prefix must not be (``prefix_*`` names are then safe).
_RESERVED = frozenset({
    "auto", "break", "case", "char", "const", "continue", "default", "do", "double", "else",
    "enum", "extern", "float", "for", "goto", "if", "inline", "int", "long", "register",
    "restrict", "return", "short", "signed", "sizeof", "static", "struct", "switch",
    "typedef", "union", "unsigned", "void", "volatile", "while", "main", "exp", "expf", "math",
})


def check_prefix(prefix: str) -> str:
    """Return ``prefix`` if it is a usable C name prefix, else raise ``ValueError``."""
    if not isinstance(prefix, str) or not _IDENT.fullmatch(prefix) or prefix in _RESERVED:
        raise ValueError(
            f"prefix={prefix!r} must be a lower-case C identifier: a letter, then up to 30 "
            "letters, digits or '_', and not a C keyword"
        )
    return prefix


def _operator(value: object, allowed: frozenset[Any], what: str, system: Any,
              why: str = "") -> None:
    if value not in allowed:
        shown = getattr(value, "value", value)
        raise UnsupportedFeatureError(
            f"system {system.name!r}: {what} {shown!r} has no C implementation "
            f"(supported: {', '.join(sorted(str(v.value) for v in allowed))})" + why)


def check_supported(system: object, real: RealType | None = None) -> None:
    """Raise :class:`~it2track.io.UnsupportedFeatureError` unless C can be generated for
    ``system`` (in the arithmetic ``real``, when given).

    Allowed: exactly :class:`~it2track.fuzzy.IT2Sugeno` or :class:`~it2track.fuzzy.T1Sugeno`
    (zero-order, or first-order with crisp or interval coefficients), or
    :class:`~it2track.fuzzy.IT2Mamdani` / :class:`~it2track.fuzzy.T1Mamdani` (centroid on the
    output grid or centre-of-sets); one output; membership rows of the kinds
    trapezoid/triangle, Gaussian and uncertain-mean Gaussian; the t-norms, s-norms,
    implications, aggregations and defuzzifiers listed in this module; a built-in type reducer;
    no rule-language feature outside :data:`SUPPORTED_FEATURES`. The fixed-point build carries
    zero-order Sugeno systems only (see :mod:`.fixedpoint`).

    Parameters
    ----------
    system : object
        The system to check (anything: what is not a supported system is refused).
    real : RealType, optional
        The arithmetic; ``None`` checks what every arithmetic's build shares.

    Raises
    ------
    UnsupportedFeatureError
        Naming what is not carried.
    """
    if type(system) not in SUPPORTED_SYSTEMS:
        raise UnsupportedFeatureError(
            f"cannot generate C for a {type(system).__name__}: supported are Sugeno/TSK "
            "systems (IT2Sugeno, T1Sugeno) and Mamdani systems (IT2Mamdani, T1Mamdani)"
        )
    assert isinstance(system, IT2Sugeno | T1Sugeno | IT2Mamdani | T1Mamdani)
    if getattr(system, "aggregation", None) is not None and isinstance(system, T1Sugeno):
        raise UnsupportedFeatureError(
            f"system {system.name!r} groups its rules by consequent value (T1Sugeno "
            "aggregation, jFuzzyLogic's ACCU), which C generation does not implement")
    tables = antecedent_tables(system)
    features = tables.features
    extra = sorted(features - SUPPORTED_FEATURES)
    if extra:
        raise UnsupportedFeatureError(
            f"system {system.name!r} uses rule-language feature(s) "
            f"{', '.join(_FEATURE_TEXT.get(f, f) for f in extra)} that C generation does not "
            f"implement (it implements: {', '.join(sorted(SUPPORTED_FEATURES))})"
        )
    for k, kind in enumerate(tables.mf_kind.tolist()):
        if kind not in SUPPORTED_KINDS:
            inp = system.inputs[int(tables.mf_input[k])]
            raise UnsupportedFeatureError(
                f"input {inp.name!r}: membership function {tables.mfs[k]!r} has no C "
                "implementation (supported: triangle, trapezoid, Gaussian, uncertain-mean "
                "Gaussian)"
            )
    _operator(system.tnorm, SUPPORTED_TNORMS, "t-norm", system)
    if "or" in features:
        _operator(tables.snorm, SUPPORTED_SNORMS, "s-norm", system)
    if isinstance(system, T1Sugeno) and system.defuzzifier is not WeightedDefuzzifier.AVERAGE:
        raise UnsupportedFeatureError(
            f"defuzzifier {system.defuzzifier!r} has no C implementation (weighted average only)")
    mamdani = isinstance(system, IT2Mamdani | T1Mamdani)
    centroid = mamdani and not (isinstance(system, IT2Mamdani) and
                                system.type_reduction is TypeReduction.CENTRE_OF_SETS)
    if centroid:
        assert isinstance(system, IT2Mamdani | T1Mamdani)
        _operator(system.implication, SUPPORTED_IMPLICATIONS, "implication", system)
        _operator(system.aggregation, SUPPORTED_AGGREGATIONS, "aggregation", system)
    if isinstance(system, T1Mamdani):
        why = (" (Octave's trapezoid-rule centroid is not generated)"
               if system.defuzzifier is Defuzzifier.CENTROID_INTEGRAL else
               ": it picks grid points by exact comparisons, so a last-bit difference in the "
               "aggregated set moves it by whole grid steps")
        _operator(system.defuzzifier, SUPPORTED_DEFUZZIFIERS, "defuzzifier", system, why)
    reducer_of(system)
    if real is not None and real.fixed:
        if mamdani:
            raise UnsupportedFeatureError(
                f"{type(system).__name__} {system.name!r}: Mamdani systems have no fixed-point "
                "implementation (the q15 build's scaling and error bound are derived for "
                "zero-order Sugeno consequents); use --real float")
        if "linear" in features:
            raise UnsupportedFeatureError(
                f"system {system.name!r} has first-order (linear) consequents, which have no "
                "fixed-point implementation (their products with the inputs and the per-step "
                "sort of the rules are not scaled nor bounded in q15); use --real float")


def generate_c(
    system: IT2Sugeno | T1Sugeno | IT2Mamdani | T1Mamdani,
    *,
    real: RealType = RealType.DOUBLE,
    prefix: str = "it2",
) -> CCode:
    """Generate C99 source for ``system``.

    Parameters
    ----------
    system : IT2Sugeno, T1Sugeno, IT2Mamdani or T1Mamdani
        The controller, with its type reducer (or defuzzifier), norms and ``on_zero_firing``
        policy.
    real : RealType
        Arithmetic type of the generated code.
    prefix : str
        Prefix of every external C name and of the file names (``<prefix>.h``, ``<prefix>.c``);
        two controllers with different prefixes link into one program.

    Returns
    -------
    CCode

    Raises
    ------
    UnsupportedFeatureError
        If the system uses something the generator does not implement (see
        :func:`check_supported`).
    ValueError
        For a bad ``prefix`` or ``real``.
    """
    check_prefix(prefix)
    if not isinstance(real, RealType):
        raise ValueError(f"real={real!r} must be a RealType")
    check_supported(system, real)
    if real.fixed:
        assert isinstance(system, IT2Sugeno | T1Sugeno)
        context, fmt = fixed_context(system, prefix, real.value, real.width)
        env = environment()
        header = env.get_template("controller_fixed.h.j2").render(**context)
        source = env.get_template("controller_fixed.c.j2").render(**context)
        return CCode(
            prefix=prefix, real=real, reducer=context["reducer"], n_inputs=system.n_inputs,
            n_rules=system.n_rules, header_name=f"{prefix}.h", source_name=f"{prefix}.c",
            header=header, source=source, fixed=fmt,
        )
    context = float_context(system, real, prefix)
    env = environment()
    env.globals.update(norm_combiners(system, prefix))
    header = env.get_template("controller.h.j2").render(**context)
    source = env.get_template("controller.c.j2").render(**context)
    return CCode(
        prefix=prefix, real=real, reducer=context["reducer"], n_inputs=system.n_inputs,
        n_rules=system.n_rules, header_name=f"{prefix}.h", source_name=f"{prefix}.c",
        header=header, source=source,
    )

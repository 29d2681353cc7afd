"""Lower a Sugeno system's :class:`~it2track.fuzzy.tables.SystemTables` to C99 source text.

What the generated code does is described in the header it writes (see
``templates/controller.h.j2``) and in :mod:`it2track.codegen`. This module decides *whether* a
system can be carried (an explicit allow-list: anything not listed is refused with
:class:`~it2track.io.UnsupportedFeatureError`), then fills the templates: constants are written
with enough digits to round-trip (``repr`` of the double, or of the float32 value with an ``f``
suffix), so the C tables hold exactly the values Python evaluates with (rounded once to float
for a float build).
"""

from __future__ import annotations

import enum
import hashlib
import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import __version__
from ..fuzzy import IT2Sugeno, MFKind, T1Sugeno, TNorm, WeightedDefuzzifier
from ..io.errors import UnsupportedFeatureError
from .fixedpoint import FixedFormat, fixed_context
from .lowering import TITLES, dependencies, environment, reducer_of, row_label

__all__ = [
    "SUPPORTED_FEATURES",
    "CCode",
    "RealType",
    "check_supported",
    "generate_c",
]

#: Rule-language features of :attr:`SystemTables.features` the generator implements. Anything
#: else (a feature added to the fuzzy layer later included) is refused.
SUPPORTED_FEATURES: frozenset[str] = frozenset({"not", "or", "weights"})
#: The system types the generator knows (exact types: a subclass may change the semantics).
SUPPORTED_SYSTEMS: tuple[type, ...] = (IT2Sugeno, T1Sugeno)
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


class RealType(enum.Enum):
    """The arithmetic of the generated code and the type of its values (``it2_real``):
    ``DOUBLE`` and ``FLOAT`` floating point, ``Q15`` integer-only fixed point with ``int16_t``
    values (see :mod:`it2track.codegen.fixedpoint`)."""

    DOUBLE = "double"
    FLOAT = "float"
    Q15 = "q15"

    @property
    def fixed(self) -> bool:
        """True for a fixed-point (integer) build."""
        return self is RealType.Q15

    @property
    def width(self) -> int:
        """Bits of ``it2_real``."""
        return {RealType.DOUBLE: 64, RealType.FLOAT: 32, RealType.Q15: 16}[self]

    @classmethod
    def from_name(cls, name: str) -> RealType:
        key = name.strip().lower()
        for member in cls:
            if key == member.value:
                return member
        raise ValueError(f"unknown real type {name!r}; choose "
                         f"{', '.join(repr(m.value) for m in cls)}")


@dataclass(frozen=True, kw_only=True)
class CCode:
    """Generated C for one controller.

    Attributes
    ----------
    prefix : str
        Prefix of every external name (``<prefix>_eval``, ``<prefix>_real``, ``<PREFIX>_OK``).
    real : RealType
    reducer : str
        Name of the type reducer compiled in (``"type-1"`` for a type-1 system).
    n_inputs, n_rules : int
    header_name, source_name : str
        File names, ``<prefix>.h`` and ``<prefix>.c``.
    header, source : str
        The text of the two files.
    fixed : FixedFormat or None
        For a fixed-point build, its scaling (how real values map to the integers of the
        interface); None for float and double.
    """

    prefix: str
    real: RealType
    reducer: str
    n_inputs: int
    n_rules: int
    header_name: str
    source_name: str
    header: str
    source: str
    fixed: FixedFormat | None = None

    def files(self) -> dict[str, str]:
        """File name -> text, header first."""
        return {self.header_name: self.header, self.source_name: self.source}

    def digest(self) -> str:
        """SHA-256 of both files (identifies a build)."""
        h = hashlib.sha256()
        for name, text in self.files().items():
            h.update(name.encode())
            h.update(b"\0")
            h.update(text.encode())
            h.update(b"\0")
        return h.hexdigest()


def check_prefix(prefix: str) -> str:
    """Return ``prefix`` if it is a usable C name prefix, else raise ``ValueError``."""
    if not isinstance(prefix, str) or not _IDENT.fullmatch(prefix) or prefix in _RESERVED:
        raise ValueError(
            f"prefix={prefix!r} must be a lower-case C identifier: a letter, then up to 30 "
            "letters, digits or '_', and not a C keyword"
        )
    return prefix


def check_supported(system: object) -> None:
    """Raise :class:`~it2track.io.UnsupportedFeatureError` unless C can be generated for
    ``system``.

    Allowed: exactly :class:`~it2track.fuzzy.IT2Sugeno` or :class:`~it2track.fuzzy.T1Sugeno`,
    membership rows of the kinds trapezoid/triangle, Gaussian and uncertain-mean Gaussian,
    product or minimum t-norm, a built-in type reducer, and no rule-language feature outside
    :data:`SUPPORTED_FEATURES`.
    """
    if type(system) not in SUPPORTED_SYSTEMS:
        raise UnsupportedFeatureError(
            f"cannot generate C for a {type(system).__name__}: only zero-order Sugeno systems "
            "(IT2Sugeno, T1Sugeno) are supported"
        )
    assert isinstance(system, IT2Sugeno | T1Sugeno)
    if getattr(system, "aggregation", None) is not None:
        raise UnsupportedFeatureError(
            f"system {system.name!r} groups its rules by consequent value (T1Sugeno "
            "aggregation, jFuzzyLogic's ACCU), which C generation does not implement")
    tables = system.tables
    features = frozenset(getattr(tables, "features", frozenset()))
    extra = sorted(features - SUPPORTED_FEATURES)
    if extra:
        raise UnsupportedFeatureError(
            f"system {system.name!r} uses rule-language feature(s) {', '.join(extra)} that C "
            f"generation does not implement (it implements: "
            f"{', '.join(sorted(SUPPORTED_FEATURES)) or 'plain AND rules only'})"
        )
    for k, kind in enumerate(tables.mf_kind.tolist()):
        if kind not in SUPPORTED_KINDS:
            inp = system.inputs[int(tables.mf_input[k])]
            raise UnsupportedFeatureError(
                f"input {inp.name!r}: membership function {tables.mfs[k]!r} has no C "
                "implementation (supported: triangle, trapezoid, Gaussian, uncertain-mean "
                "Gaussian)"
            )
    if system.tnorm not in (TNorm.PRODUCT, TNorm.MINIMUM):
        raise UnsupportedFeatureError(f"t-norm {system.tnorm!r} has no C implementation")
    if isinstance(system, T1Sugeno) and system.defuzzifier is not WeightedDefuzzifier.AVERAGE:
        raise UnsupportedFeatureError(
            f"defuzzifier {system.defuzzifier!r} has no C implementation (weighted average only)")
    reducer_of(system)


def _literal(value: float, real: RealType) -> str:
    """A C floating constant that is exactly ``value`` (rounded once to float for FLOAT)."""
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"cannot write the non-finite constant {v!r} to C")
    if real is RealType.FLOAT:
        f32 = float(np.float32(v))
        if not math.isfinite(f32):
            raise UnsupportedFeatureError(f"constant {v!r} overflows a 32-bit float")
        text = repr(f32)
        suffix = "f"
    else:
        text = repr(v)
        suffix = ""
    if "e" not in text and "." not in text:
        text += ".0"
    return text + suffix


def _key(value: float, real: RealType) -> str:
    """The comparison key of a table constant (see ``<PREFIX>_K`` in the template)."""
    if real is RealType.DOUBLE:
        return _literal(value, real)
    f = float(np.float32(value))
    if f == 0.0:
        f = 0.0  # -0 and +0 share a key
    u = int(np.array(f, dtype=np.float32).view(np.uint32))
    k = (~u & 0xFFFFFFFF) if u & 0x80000000 else (u | 0x80000000)
    return f"0x{k:08X}UL"


def generate_c(
    system: IT2Sugeno | T1Sugeno,
    *,
    real: RealType = RealType.DOUBLE,
    prefix: str = "it2",
) -> CCode:
    """Generate C99 source for ``system``.

    Parameters
    ----------
    system : IT2Sugeno or T1Sugeno
        The controller, with its type reducer, t-norm and ``on_zero_firing`` policy.
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
    check_supported(system)
    if real.fixed:
        context, fmt = fixed_context(system, prefix, real.value, real.width)
        env = environment()
        header = env.get_template("controller_fixed.h.j2").render(**context)
        source = env.get_template("controller_fixed.c.j2").render(**context)
        return CCode(
            prefix=prefix, real=real, reducer=context["reducer"], n_inputs=system.n_inputs,
            n_rules=system.n_rules, header_name=f"{prefix}.h", source_name=f"{prefix}.c",
            header=header, source=source, fixed=fmt,
        )
    context = _context(system, real, prefix)
    env = environment()
    env.globals["combine"] = _combiner(system.tnorm, prefix, real)
    env.globals["scombine"] = _s_combiner(getattr(system.tables, "snorm", None), prefix)
    header = env.get_template("controller.h.j2").render(**context)
    source = env.get_template("controller.c.j2").render(**context)
    return CCode(
        prefix=prefix, real=real, reducer=context["reducer"], n_inputs=system.n_inputs,
        n_rules=system.n_rules, header_name=f"{prefix}.h", source_name=f"{prefix}.c",
        header=header, source=source,
    )


def _combiner(tnorm: TNorm, prefix: str, real: RealType) -> Any:
    del real

    def combine(acc: str, expr: str) -> str:
        if tnorm is TNorm.PRODUCT:
            return f"{acc} *= {expr};"
        return (f"{{ const {prefix}_real t_ = {expr}; if ({prefix.upper()}_LT(t_, {acc})) "
                f"{{ {acc} = t_; }} }}")

    return combine


def _s_combiner(snorm: Any, prefix: str) -> Any:
    from ..fuzzy.norms import SNorm

    P = prefix.upper()

    def combine(acc: str, expr: str) -> str:
        if snorm is SNorm.PROBOR:  # a + b - a b, as SNorm.pair
            return (f"{{ const {prefix}_real t_ = {expr}; {acc} = {acc} + t_ - {acc} * t_; }}")
        return f"{{ const {prefix}_real t_ = {expr}; if ({P}_GT(t_, {acc})) {{ {acc} = t_; }} }}"

    return combine


def _context(system: IT2Sugeno | T1Sugeno, real: RealType, prefix: str) -> dict[str, Any]:
    tables = system.tables
    lit = lambda v: _literal(v, real)  # noqa: E731
    key = lambda v: _key(v, real)  # noqa: E731
    n_in, n_rules, n_rows = system.n_inputs, system.n_rules, tables.n_rows
    reducer = reducer_of(system)
    red_name = "type-1" if reducer is None else reducer.name
    features = frozenset(getattr(tables, "features", frozenset()))
    general = bool(features & {"not", "or", "weights"})
    type1 = bool(tables.type1_firing if general else tables.type1)
    crisp = bool(tables.crisp)
    exact = reducer is None or reducer.exact
    type1_exact = type1 and exact
    n_ext = 2 * n_rows + 2 if general else n_rows + 1
    biggest = max(n_ext, n_rules + 1, n_in)
    idx_bytes = 1 if biggest < 255 else 2
    if biggest >= 65535:
        raise UnsupportedFeatureError(
            f"system {system.name!r} is too large for the C generator ({n_rules} rules, "
            f"{n_rows} membership rows; at most 65534)"
        )
    lo = [float(v) for v in tables.lo]
    hi = [float(v) for v in tables.hi]
    dep = dependencies(tables)
    trap, gauss, umg = [], [], []
    h1 = True
    for k in range(n_rows):
        kind = MFKind(int(tables.mf_kind[k]))
        p = [float(v) for v in tables.mf_params[k]]
        i = int(tables.mf_input[k])
        label = row_label(system, k)
        if kind is MFKind.TRAPEZOID:
            a, wl, d, wr, h = p
            left_sh = math.isinf(a)
            right_sh = math.isinf(d)
            b = lo[i] if left_sh else a + wl
            c = hi[i] if right_sh else d - wr
            h1 = h1 and h == 1.0
            trap.append({
                "a": lit(b if left_sh else a), "b": lit(b), "c": lit(c),
                "d": lit(c if right_sh else d),
                "ka": key(b if left_sh else a), "kb": key(b), "kc": key(c),
                "kd": key(c if right_sh else d),
                "il": lit(0.0 if left_sh else 1.0 / wl), "ir": lit(0.0 if right_sh else 1.0 / wr),
                "h": lit(h), "inp": i, "row": k, "label": label, "dep": dep[k],
            })
        elif kind is MFKind.GAUSSIAN:
            mean, sigma, h = p[:3]
            gauss.append({"mean": lit(mean), "inv_sigma": lit(1.0 / sigma), "h": lit(h),
                          "inp": i, "row": k, "label": label, "dep": dep[k]})
        else:
            m1, m2, sigma, h = p[:4]
            umg.append({"m1": lit(m1), "m2": lit(m2), "km1": key(m1), "km2": key(m2),
                        "kmid": key(0.5 * (m1 + m2)),
                        "inv_sigma": lit(1.0 / sigma), "h": lit(h), "inp": i, "row": k,
                        "lower": int(kind is MFKind.UM_GAUSSIAN_LOWER), "label": label,
                        "dep": dep[k]})
    # Rows that depend on another row come after the rows of their table they depend on.
    for table in (trap, gauss, umg):
        table.sort(key=lambda e: e["dep"] != n_rows)
    ord_hi = [int(v) for v in tables.order_hi_s]
    iterative = red_name in ("km", "ekm", "eiasc")
    need_hi_gather = (not crisp and not type1_exact and red_name in ("exhaustive", "km", "ekm",
                                                                      "eiasc")
                      and ord_hi != list(range(n_rules)))
    y_lo = tables.y_lo_s
    y_hi = tables.y_hi_s
    eps = float(np.finfo(np.float32 if real is RealType.FLOAT else np.float64).eps)
    # As reducers._switch_iterations: ties within (8 + 2R) eps max(1, max|y|), per side.
    km_tol_l = (8.0 + 2.0 * n_rules) * eps * max(1.0, float(np.abs(y_lo).max()))
    km_tol_r = (8.0 + 2.0 * n_rules) * eps * max(1.0, float(np.abs(y_hi).max()))
    max_iter = reducer._cap(n_rules) if (reducer is not None and iterative) else 0
    wm = {
        "y1l": lit(float(y_lo.min())), "yml": lit(float(y_lo.max())),
        "y1r": lit(float(y_hi.min())), "ymr": lit(float(y_hi.max())),
    }
    needs_exp = bool(gauss or umg)
    kind_name = type(system).__name__
    description = (
        f"{kind_name} {system.name!r}: {n_in} input(s), {n_rules} rules, {n_rows} membership "
        f"rows, {system.tnorm.value} t-norm, "
        f"{'type-1' if type1 else 'interval type-2'} sets, "
        f"{'crisp' if crisp else 'interval'} consequents."
    )
    zero = system.on_zero_firing
    return {
        "banner": f"Generated by it2track {__version__} (it2track export c); do not edit.",
        "description": description,
        "p": prefix, "P": prefix.upper(), "ctype": real.value,
        "header_name": f"{prefix}.h",
        "inputs": [{"name": inp.name, "lo_text": repr(inp.universe[0]),
                    "hi_text": repr(inp.universe[1])} for inp in system.inputs],
        "n_in": n_in, "n_rules": n_rules, "n_rows": n_rows,
        "lo": [lit(v) for v in lo], "hi": [lit(v) for v in hi],
        "trap": trap, "trap_h1": h1, "gauss": gauss, "umg": umg,
        "needs_exp": needs_exp,
        "libm_text": "uses exp() from <math.h>" if needs_exp else "needs no library function",
        "idx_type": "unsigned char" if idx_bytes == 1 else "unsigned short",
        "idx_bytes": idx_bytes, "idx_none": 255 if idx_bytes == 1 else 65535,
        "ru": (tables.up_ext_s if general else tables.upper_rows_s).tolist(),
        "rl": (tables.lo_ext_s if general else tables.lower_rows_s).tolist(),
        "general": general, "n_ext": n_ext,
        "has_not": "not" in features, "has_or": "or" in features,
        "has_weights": "weights" in features,
        "is_or": [int(v) for v in getattr(tables, "is_or_s", np.zeros(n_rules, bool))],
        "weights": [lit(v) for v in getattr(tables, "weight_s", np.ones(n_rules))],
        "snorm": getattr(getattr(tables, "snorm", None), "value", "max"),
        "type1": type1, "crisp": crisp, "type1_exact": type1_exact,
        "y_lo": [lit(v) for v in y_lo], "y_hi": [lit(v) for v in y_hi],
        "need_ord_hi": need_hi_gather, "need_hi_gather": need_hi_gather, "ord_hi": ord_hi,
        "reducer": red_name, "reducer_title": TITLES[red_name].split(" (")[0],
        "reducer_text": TITLES[red_name],
        "km_tol_l": lit(km_tol_l), "km_tol_r": lit(km_tol_r), "max_iter": max_iter,
        "max_iter_text": f"{max_iter} iterations" if iterative else "(not iterative)",
        "wm": wm, "tnorm": system.tnorm.value,
        "keys": real is RealType.FLOAT,
        "klo": [key(v) for v in lo], "khi": [key(v) for v in hi],
        "kmax": key(float(np.finfo(np.float32 if real is RealType.FLOAT else np.float64).max)),
        "kmin": key(-float(np.finfo(np.float32 if real is RealType.FLOAT
                                    else np.float64).max)),
        "kzero": key(0.0),
        "zero_value": None if zero is None else lit(zero),
    }

r"""Fixed-point C for the Sugeno systems: the scaling, and every integer constant of the build.

``generate_c(system, real=RealType.Q15)`` writes integer-only C99 whose entry point has the same
shape as the float build's::

    int <prefix>_eval(const <prefix>_real in[N_IN], <prefix>_real *u, <prefix>_real *yl,
                      <prefix>_real *yr);

with ``<prefix>_real`` = ``int16_t``. This module decides the scaling (:class:`FixedFormat`,
which is also how a caller converts between real values and the integers the function takes
and returns) and computes the integer tables; :mod:`.errorbound` bounds the result against the
double system from the same plan (:class:`FixedPlan`), so the C and its bound cannot drift
apart.

Design (q15)
------------
*Inputs.* ``in[i]`` is the input in ``Q(F_i)``: ``x = in[i] / 2**F_i``, with ``F_i`` the
largest integer such that ``U_i 2**F_i <= 2**15`` (``U_i`` the largest magnitude of the
universe; a universe of ``[-1, 1]`` is plain Q15, its top end saturating at ``1 - 2**-15``).
Inputs are clipped, in integers, to ``[ceil(lo 2**F), floor(hi 2**F)]``.

*Memberships and firings* are unsigned ``Q24`` (``1.0 = 2**24``) in 32-bit words: the error
amplification of the type reducer (about ``sum |y - yl| / sum f_lower``, ~100 for the paper's
controller) makes 16-bit memberships too coarse for a millivolt output, and 24 fraction bits
keep every shift a whole number of bytes on an 8-bit machine. A piecewise-linear row is
evaluated on its slope as ``M = C + round((du K + c) / 2**s)``: ``du`` the integer distance of
the input from the slope's first grid point inside the universe (16 bits), ``K`` the slope per
input step and ``C + c / 2**s`` the row's value at that point, exactly rounded constants
(``s = 16``, or 8 for a slope steeper than 2**16 per input step); the result is clamped to the
row's height. Thresholds are compared in integers (``floor``/``ceil`` of the breakpoints), so
every branch is decided exactly. Firing products are rounded ``24 x 24 -> 24`` bit products (a
factor of exactly 1 is passed through).

*The C.* Rows and rules are unrolled into straight-line code with their constants inline (no
tables). On an AVR with a hardware multiplier the three exact products (16 x 32 -> 48 bits,
the same accumulated into a 48-bit sum, and the rounded 24 x 24 bit product: 8, 8 and 9 MUL
instructions) and the division are short inline assembly; elsewhere, or with
``<PREFIX>_PORTABLE`` defined, plain C computes the same bits (a test compiles both for the AVR
and compares them).

*Type reduction* runs on the integer firings (a lower firing that rounding put above the upper
one is clamped to it) with consequents ``y'`` = ``y`` in the output's
``Q(F_o)`` minus the smallest consequent (so everything is unsigned): sums ``sum f y'`` in
48 bits, ``sum f`` in 32. The exact reducers compare a candidate centroid with a consequent
by one multiplication (``y' den < num``), exactly, so exhaustive, KM, EKM and EIASC find the
same exact minimum / maximum of the integer firings' centroid and return the same bits; each
side ends with one division (a 20-step shift-and-subtract giving ``F_o + 4`` fraction bits).
Nie-Tan is one division. The Wu-Mendel bounds (eight divisions, and an approximation whose
purpose, avoiding iterations, the exhaustive reducer serves exactly) are not carried.

*Output.* ``u``, ``yl``, ``yr`` in ``Q(F_o)``, ``F_o`` the largest integer with
``Y 2**F_o <= 2**15 - 1`` (``Y`` the largest consequent magnitude or ``on_zero_firing``
value): ``yl``, ``yr`` correctly rounded (half up) from the exact integer quotient, ``u``
within ``1/2 + 2**-4`` of an output step. Nothing can overflow: the scaling is chosen so that
every intermediate fits its word (checked here, per system), and the only values that can leave
their range -- a slope's rounding past the row's height -- are clamped.

Gaussian rows (which need ``exp``) are refused for fixed point, as are rule weights, NOT and OR
(the float build carries them); so are systems with more rules than the 32-bit firing sum
holds (127; 63 or 31 for Nie-Tan).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import __version__
from ..fuzzy import IT2Sugeno, MFKind, T1Sugeno, TNorm
from ..io.errors import UnsupportedFeatureError
from .lowering import TITLES, dependencies, reducer_of, row_label

__all__ = ["EXTRA_BITS", "M_FRAC", "FixedFormat", "FixedPlan", "FixedRow", "FixedSlope",
           "check_fixed_supported", "fixed_context", "fixed_plan"]

#: Fraction bits of memberships and firings (1.0 = 2**24).
M_FRAC = 24
#: Extra fraction bits of the type reducer's quotient (beyond the output's).
EXTRA_BITS = 4
#: The reducers a fixed-point build carries (see the module docstring).
FIXED_REDUCERS = ("type-1", "exhaustive", "km", "ekm", "eiasc", "nie-tan")


@dataclass(frozen=True, kw_only=True)
class FixedFormat:
    """The integer scaling of a fixed-point build: how real values map to the C function's
    integers (its ABI) and back.

    Attributes
    ----------
    width : int
        Bits of ``<prefix>_real`` (16 for q15).
    in_frac : tuple of int
        Fraction bits ``F_i`` of each input: ``in[i] = round(x_i 2**F_i)``.
    in_lo, in_hi : tuple of int
        Each input's universe in those integers: the C clips ``in[i]`` to ``[in_lo, in_hi]``.
    out_frac : int
        Fraction bits ``F_o`` of ``u``, ``yl``, ``yr``: ``u = *u / 2**F_o``.
    m_frac : int
        Fraction bits of memberships and firings inside the C.
    extra_bits : int
        Fraction bits of the type reducer's quotient beyond ``out_frac``.
    """

    width: int
    in_frac: tuple[int, ...]
    in_lo: tuple[int, ...]
    in_hi: tuple[int, ...]
    out_frac: int
    m_frac: int
    extra_bits: int

    @property
    def dtype(self) -> type[np.signedinteger[Any]]:
        """The numpy type of ``<prefix>_real``."""
        return np.int16 if self.width == 16 else np.int32

    @property
    def int_min(self) -> int:
        return -(1 << (self.width - 1))

    @property
    def int_max(self) -> int:
        return (1 << (self.width - 1)) - 1

    def to_int(self, x: ArrayLike) -> NDArray[Any]:
        """Real inputs, shape ``(N, n_inputs)``, to the C function's integers: rounded to the
        nearest (ties to even) and saturated to the integer range.

        Raises
        ------
        ValueError
            For NaN (naming the input) or a wrong shape.
        """
        arr = np.asarray(x, dtype=np.float64)
        n_in = len(self.in_frac)
        if arr.ndim != 2 or arr.shape[1] != n_in:
            raise ValueError(f"x must have shape (N, {n_in}), got {arr.shape}")
        bad = np.isnan(arr)
        if bad.any():
            i = int(np.argwhere(bad)[0][1])
            raise ValueError(f"input {i} is NaN: a fixed-point input must be a number")
        scaled = np.ldexp(arr, np.array(self.in_frac))
        q = np.clip(np.rint(scaled), self.int_min, self.int_max)
        return q.astype(self.dtype)

    def inputs_seen(self, q: ArrayLike) -> NDArray[np.float64]:
        """The real inputs the C evaluates for integer inputs ``q`` (clipped to the universe,
        as the C clips them), shape ``(N, n_inputs)``."""
        arr = np.asarray(q, dtype=np.int64)
        clipped = np.clip(arr, np.array(self.in_lo), np.array(self.in_hi))
        return np.ldexp(clipped.astype(np.float64), -np.array(self.in_frac))

    def to_real(self, q: ArrayLike) -> NDArray[np.float64]:
        """Outputs (``u``, ``yl`` or ``yr`` integers) to real values."""
        return np.ldexp(np.asarray(q, dtype=np.float64), -self.out_frac)


@dataclass(frozen=True, kw_only=True)
class FixedSlope:
    """One slope of a piecewise-linear row: ``M(du) = cint + round((du k + cfrac) / 2**sh)``
    in units of ``2**-m_frac``; ``du`` runs from 0 (at grid point ``origin``) to ``du_max``.
    ``g`` and ``c0`` are the exact slope per input step and value at ``origin``."""

    origin: int
    k: int
    cint: int
    cfrac: int
    sh: int
    du_max: int
    g: Fraction
    c0: Fraction

    def const_error(self) -> Fraction:
        """Largest ``|M(du) - exact|`` over the slope before the final rounding, in units of
        ``2**-m_frac``: the constants' rounding."""
        if self.du_max < 0:
            return Fraction(0)
        scale = Fraction(1 << self.sh)
        dk = abs(Fraction(self.k) - self.g * scale)
        dc = abs(Fraction(self.cint) * scale + self.cfrac - self.c0 * scale)
        return (self.du_max * dk + dc) / scale


@dataclass(frozen=True, kw_only=True)
class FixedRow:
    """Integer constants of one piecewise-linear membership row (see the module docstring).

    The row is 0 for ``q <= qa`` or ``q >= qd``, ``height`` for ``qb <= q <= qc``, ``left`` on
    ``qa < q < qb`` and ``right`` on ``qc < q < qd`` (thresholds clamped to one step outside
    the input's integer universe, which leaves every comparison unchanged)."""

    row: int
    inp: int
    qa: int
    qb: int
    qc: int
    qd: int
    height: int
    h: float
    left: FixedSlope
    right: FixedSlope
    lipschitz: float

    def error(self) -> float:
        """Bound on ``|M - mu 2**m_frac|`` at any integer input, in units of ``2**-m_frac``:
        the constants' rounding, plus 1/2 for the final rounding, or the height's rounding."""
        h_err = abs(Fraction(self.height) - Fraction(self.h) * (1 << M_FRAC))
        slopes = [s.const_error() + Fraction(1, 2) for s in (self.left, self.right)
                  if s.du_max >= 0]
        return float(max([h_err, *slopes]))


@dataclass(frozen=True, kw_only=True)
class FixedPlan:
    """Everything a fixed-point build computes with: its :class:`FixedFormat`, the rows, and
    the consequents as integers (``y_lo_q``, ``y_hi_q`` in the tables' sorted rule order, in
    ``Q(out_frac)``; ``y_min`` the smallest of them), and the ``on_zero_firing`` value."""

    fmt: FixedFormat
    rows: tuple[FixedRow, ...]
    y_lo_q: tuple[int, ...]
    y_hi_q: tuple[int, ...]
    y_min: int
    zero_q: int | None
    reducer: str


def _ceil(v: Fraction) -> int:
    return math.ceil(v)


def _floor(v: Fraction) -> int:
    return math.floor(v)


def _in_frac(lo: float, hi: float, width: int, name: str) -> int:
    big = max(abs(lo), abs(hi))
    if not big > 0:
        raise UnsupportedFeatureError(f"input {name!r}: universe [{lo!r}, {hi!r}] has no "
                                      "extent to scale")
    f = (width - 1) - math.ceil(math.log2(big))
    while big * 2.0**f > 2.0 ** (width - 1):
        f -= 1
    while big * 2.0 ** (f + 1) <= 2.0 ** (width - 1):
        f += 1
    if not -60 <= f <= 60:
        raise UnsupportedFeatureError(f"input {name!r}: universe [{lo!r}, {hi!r}] is out of "
                                      "the range fixed point scales (|bound| 2**-60..2**60)")
    steps = (hi - lo) * 2.0**f
    if steps < 2.0 ** (width - 6):
        raise UnsupportedFeatureError(
            f"input {name!r}: universe [{lo!r}, {hi!r}] spans only {steps:.0f} steps of "
            f"Q{f}: too narrow for its magnitude (at least {2 ** (width - 6)}); shift it "
            "towards 0 or use --real float")
    return f


def _slope(origin: int, du_max: int, g: Fraction, c0: Fraction) -> FixedSlope:
    if du_max < 1:
        sh, k = 16, 0
    else:
        sh = 16 if g * (1 << 16) < 2**32 - 1 else 8
        k = round(g * (1 << sh))  # du_max >= 1: the slope spans > 1 step, g < 2**24
    scale = 1 << sh
    cint = _floor(c0)
    cfrac = round((c0 - cint) * scale)
    if cfrac >= scale:
        cint, cfrac = cint + 1, cfrac - scale
    return FixedSlope(origin=origin, k=k, cint=cint, cfrac=cfrac, sh=sh, du_max=du_max, g=g,
                      c0=c0)


def _row(system: IT2Sugeno | T1Sugeno, k: int, fmt: FixedFormat) -> FixedRow:
    t = system.tables
    i = int(t.mf_input[k])
    f = fmt.in_frac[i]
    s = Fraction(2) ** f
    loq, hiq = fmt.in_lo[i], fmt.in_hi[i]
    a, wl, d, wr, h = (float(v) for v in t.mf_params[k])
    one = Fraction(1 << M_FRAC)
    hh = Fraction(h)
    clamp = lambda v: min(max(v, loq - 1), hiq + 1)  # noqa: E731
    lip = 0.0
    empty = FixedSlope(origin=loq, k=0, cint=0, cfrac=0, sh=16, du_max=-1, g=Fraction(0),
                       c0=Fraction(0))
    if math.isinf(a):
        qa, qb, left = loq - 1, loq, empty
    else:
        aa = Fraction(a) * s
        bb = (Fraction(a) + Fraction(wl)) * s
        qa, qb = _floor(aa), _ceil(bb)
        q0 = max(qa + 1, loq)
        g = hh * one / (Fraction(wl) * s)
        left = _slope(q0, min(qb - 1, hiq) - q0, g, (q0 - aa) * g)
        lip = max(lip, h / wl)
    if math.isinf(d):
        qc, qd, right = hiq, hiq + 1, empty
    else:
        dd = Fraction(d) * s
        cc = (Fraction(d) - Fraction(wr)) * s
        qc, qd = _floor(cc), _ceil(dd)
        q1 = min(qd - 1, hiq)
        g = hh * one / (Fraction(wr) * s)
        right = _slope(q1, q1 - max(qc + 1, loq), g, (dd - q1) * g)
        lip = max(lip, h / wr)
    return FixedRow(row=k, inp=i, qa=clamp(qa), qb=clamp(qb), qc=clamp(qc), qd=clamp(qd),
                    height=round(hh * one), h=h, left=left, right=right, lipschitz=lip)


def check_fixed_supported(system: IT2Sugeno | T1Sugeno, reducer: str) -> None:
    """Raise :class:`~it2track.io.UnsupportedFeatureError` for what the fixed-point build does
    not carry (see the module docstring)."""
    t = system.tables
    for k, kind in enumerate(t.mf_kind.tolist()):
        if kind != MFKind.TRAPEZOID:
            inp = system.inputs[int(t.mf_input[k])]
            raise UnsupportedFeatureError(
                f"input {inp.name!r}: membership function {t.mfs[k]!r} has no fixed-point "
                "implementation (fixed point carries triangles and trapezoids; use --real "
                "float for Gaussian sets)")
    features = frozenset(getattr(t, "features", frozenset()))
    if features:
        raise UnsupportedFeatureError(
            f"system {system.name!r} uses rule-language feature(s) "
            f"{', '.join(sorted(features))} that the fixed-point build does not implement "
            "(use --real float)")
    if getattr(system, "aggregation", None) is not None:
        raise UnsupportedFeatureError(
            f"system {system.name!r} groups its rules by consequent value (T1Sugeno "
            "aggregation), which the fixed-point build does not implement")
    if reducer not in FIXED_REDUCERS:
        raise UnsupportedFeatureError(
            f"type reducer {reducer!r} has no fixed-point implementation (fixed point carries "
            f"{', '.join(FIXED_REDUCERS[1:])}); the Wu-Mendel bounds need eight divisions "
            "per step, more than the exact exhaustive reducer costs")
    weight = 2 if reducer == "nie-tan" else 1
    weight *= 1 if (reducer != "nie-tan" or t.crisp) else 2
    limit = (2**31 - 1) // (weight << M_FRAC)
    if t.n_rules > limit:
        raise UnsupportedFeatureError(
            f"system {system.name!r} has {t.n_rules} rules; the q15 build's 32-bit firing sum "
            f"holds at most {limit} with the {reducer} reducer")


def fixed_plan(system: IT2Sugeno | T1Sugeno, reducer: str, width: int = 16) -> FixedPlan:
    """The scaling and integer tables of a fixed-point build of ``system`` (with the named
    type reducer, ``"type-1"`` for a type-1 system).

    Raises
    ------
    UnsupportedFeatureError
        For what fixed point does not carry (see :func:`check_fixed_supported`) and for a
        universe or slope the scaling cannot hold.
    """
    check_fixed_supported(system, reducer)
    t = system.tables
    names = [inp.name for inp in system.inputs]
    in_frac = tuple(_in_frac(float(lo), float(hi), width, n)
                    for lo, hi, n in zip(t.lo, t.hi, names, strict=True))
    top = (1 << (width - 1)) - 1
    in_lo = tuple(max(_ceil(Fraction(float(lo)) * Fraction(2) ** f), -top - 1)
                  for lo, f in zip(t.lo, in_frac, strict=True))
    in_hi = tuple(min(_floor(Fraction(float(hi)) * Fraction(2) ** f), top)
                  for hi, f in zip(t.hi, in_frac, strict=True))
    zero_raw = system.on_zero_firing
    zero = None if zero_raw is None else float(zero_raw)  # type: ignore[arg-type]
    ys = [float(v) for v in (*t.y_lo_s, *t.y_hi_s)]
    big = max([abs(v) for v in ys] + ([abs(zero)] if zero is not None else []))
    out_frac = width - 1 if big == 0 else (width - 1) - math.ceil(math.log2(big))
    while big * 2.0**out_frac > top:
        out_frac -= 1
    while big > 0 and big * 2.0 ** (out_frac + 1) <= top:
        out_frac += 1
    if not -60 <= out_frac <= 60:
        raise UnsupportedFeatureError(f"consequents up to {big!r} are out of the range fixed "
                                      "point scales")
    fmt = FixedFormat(width=width, in_frac=in_frac, in_lo=in_lo, in_hi=in_hi,
                      out_frac=out_frac, m_frac=M_FRAC, extra_bits=EXTRA_BITS)
    rows = tuple(_row(system, k, fmt) for k in range(t.n_rows))
    scale = Fraction(2) ** out_frac
    y_lo_q = tuple(round(Fraction(float(v)) * scale) for v in t.y_lo_s)
    y_hi_q = tuple(round(Fraction(float(v)) * scale) for v in t.y_hi_s)
    zero_q = None if zero is None else round(Fraction(zero) * scale)
    return FixedPlan(fmt=fmt, rows=rows, y_lo_q=y_lo_q, y_hi_q=y_hi_q,
                     y_min=min(y_lo_q + y_hi_q), zero_q=zero_q, reducer=reducer)


def _c16(v: int) -> str:
    """An int16 constant (-32768 written so that it is an int, not a long, on 16-bit ints)."""
    return "(-32767 - 1)" if v == -32768 else str(v)


def _segments(row: FixedRow, loq: int, hiq: int) -> list[dict[str, Any]]:
    """The pieces of ``row`` met on the integer universe ``[loq, hiq]``, in order, each with
    the largest input it covers (the last one covers the rest): zero, left slope, plateau,
    right slope, zero."""
    pieces = [("zero", row.qa), ("left", row.qb - 1), ("plateau", row.qc),
              ("right", row.qd - 1), ("zero", hiq)]
    out: list[dict[str, Any]] = []
    below = loq - 1
    for kind, upto in pieces:
        top = min(upto, hiq)
        if top <= below:
            continue
        if out and out[-1]["kind"] == kind:
            out[-1]["upto"] = _c16(top)
        else:
            out.append({"kind": kind, "upto": _c16(top)})
        below = top
        if top >= hiq:
            break
    return out


def _fold(rows: list[int], tnorm: TNorm, prefix: str) -> str:
    """C expression of the firing of the memberships ``m[rows]`` (product or minimum)."""
    if not rows:
        return f"{prefix.upper()}_ONE"
    expr = f"m[{rows[0]}]"
    for r in rows[1:]:
        expr = (f"{prefix}_mul({expr}, m[{r}])" if tnorm is TNorm.PRODUCT
                else f"({expr} < m[{r}] ? {expr} : m[{r}])")
    return expr


def fixed_context(system: IT2Sugeno | T1Sugeno, prefix: str, real_name: str, width: int
                  ) -> tuple[dict[str, Any], FixedFormat]:
    """The template context of a fixed-point build, and its :class:`FixedFormat`."""
    if width != 16:
        raise ValueError(f"fixed point of {width} bits is not implemented (q15 only)")
    tables = system.tables
    reducer = reducer_of(system)
    red_name = "type-1" if reducer is None else reducer.name
    plan = fixed_plan(system, red_name, width)
    fmt = plan.fmt
    n_in, n_rules, n_rows = system.n_inputs, system.n_rules, tables.n_rows
    type1 = bool(tables.type1)
    crisp = bool(tables.crisp)
    type1_exact = type1 and (reducer is None or reducer.exact)
    dep = dependencies(tables)
    trap: list[dict[str, Any]] = []
    for row in plan.rows:
        segs = _segments(row, fmt.in_lo[row.inp], fmt.in_hi[row.inp])
        trap.append({
            "segments": segs, "sloped": any(g["kind"] in ("left", "right") for g in segs),
            "kl": row.left.k, "cl": row.left.cint, "fl": row.left.cfrac, "sl": row.left.sh,
            "ol_c": _c16(row.left.origin), "kr": row.right.k, "cr": row.right.cint,
            "fr": row.right.cfrac, "sr": row.right.sh, "or_c": _c16(row.right.origin),
            "h": row.height, "inp": row.inp, "row": row.row,
            "label": row_label(system, row.row),
            "dep": None if dep[row.row] == n_rows else dep[row.row],
        })
    trap.sort(key=lambda e: e["dep"] is not None)
    any_s8 = any((g["kind"] == "left" and e["sl"] == 8) or (g["kind"] == "right" and
                                                         e["sr"] == 8)
                 for e in trap for g in e["segments"])
    rules = []
    for r in range(n_rules):
        ups = [int(v) for v in tables.upper_rows_s[r] if v != n_rows]
        los = [int(v) for v in tables.lower_rows_s[r] if v != n_rows]
        rules.append({
            "index": r, "ups": ups, "fu": _fold(ups, system.tnorm, prefix),
            "fl": _fold(los, system.tnorm, prefix),
            "product": len(ups) > 1 and system.tnorm is TNorm.PRODUCT,
            "y": plan.y_lo_q[r] - plan.y_min, "ylo": plan.y_lo_q[r] - plan.y_min,
            "yhi": plan.y_hi_q[r] - plan.y_min,
        })
    ord_hi = [int(v) for v in tables.order_hi_s]
    iterative = red_name in ("km", "ekm", "eiasc")
    need_hi_gather = (not crisp and not type1_exact and red_name in ("exhaustive", "km", "ekm",
                                                                      "eiasc")
                      and ord_hi != list(range(n_rules)))
    if need_hi_gather and n_rules > 254:  # pragma: no cover - n_rules <= 127 (checked)
        raise UnsupportedFeatureError("too many rules")
    max_iter = reducer._cap(n_rules) if (reducer is not None and iterative) else 0
    names = [inp.name for inp in system.inputs]
    description = (
        f"{type(system).__name__} {system.name!r}: {n_in} input(s), {n_rules} rules, {n_rows} "
        f"membership rows, {system.tnorm.value} t-norm, "
        f"{'type-1' if type1 else 'interval type-2'} sets, "
        f"{'crisp' if crisp else 'interval'} consequents."
    )
    ctx = {
        "banner": f"Generated by it2track {__version__} (it2track export c); do not edit.",
        "description": description, "p": prefix, "P": prefix.upper(),
        "ctype": "int16_t", "real_name": real_name, "width": width,
        "header_name": f"{prefix}.h",
        "inputs": [{"name": n, "lo_text": repr(inp.universe[0]),
                    "hi_text": repr(inp.universe[1]), "frac": f, "lo_q": lo, "hi_q": hi,
                    "lo_c": _c16(lo), "hi_c": _c16(hi), "clip_lo": lo > fmt.int_min,
                    "clip_hi": hi < fmt.int_max}
                   for n, inp, f, lo, hi in zip(names, system.inputs, fmt.in_frac, fmt.in_lo,
                                                fmt.in_hi, strict=True)],
        "n_in": n_in, "n_rules": n_rules, "n_rows": n_rows,
        "trap": trap, "any_s8": any_s8, "rules": rules,
        "needs_mul": system.tnorm is TNorm.PRODUCT and any(
            len([v for v in rows if v != n_rows]) > 1
            for rows in (*tables.upper_rows_s.tolist(), *tables.lower_rows_s.tolist())),
        "type1": type1, "crisp": crisp, "type1_exact": type1_exact, "y_min": plan.y_min,
        "need_hi_gather": need_hi_gather, "ord_hi": ord_hi,
        "reducer": red_name, "reducer_title": TITLES[red_name].split(" (")[0],
        "reducer_text": TITLES[red_name], "max_iter": max_iter,
        "max_iter_text": f"{max_iter} iterations" if iterative else None,
        "tnorm": system.tnorm.value, "extra": fmt.extra_bits, "out_frac": fmt.out_frac,
        "zero_value": None if plan.zero_q is None else plan.zero_q,
    }
    return ctx, fmt

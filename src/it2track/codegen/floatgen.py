"""The float and double generator's template context: every table constant written so that the C
holds exactly the value Python evaluates with (``repr`` of the double, or of the float32 value
with an ``f`` suffix), the rows, rules and reducer of a Sugeno system, and the first-order
(TSK) consequents' coefficients. :mod:`.mamdani_c` adds a Mamdani system's output grid."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .. import __version__
from ..fuzzy import Aggregation, Implication, MFKind, SNorm, TNorm
from ..io.errors import UnsupportedFeatureError
from .code import RealType
from .lowering import TITLES, antecedent_tables, dependencies, reducer_of, row_label
from .mamdani_c import is_centroid_mamdani, mamdani_context

__all__ = ["float_context", "literal", "norm_combiners"]


def literal(value: float, real: RealType) -> str:
    """A C floating constant that is exactly ``value`` (rounded once to float for FLOAT)."""
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"cannot write the non-finite constant {v!r} to C")
    if real is RealType.FLOAT:
        with np.errstate(over="ignore"):  # refused just below, by name
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
        return literal(value, real)
    f = float(np.float32(value))
    if f == 0.0:
        f = 0.0  # -0 and +0 share a key
    u = int(np.array(f, dtype=np.float32).view(np.uint32))
    k = (~u & 0xFFFFFFFF) if u & 0x80000000 else (u | 0x80000000)
    return f"0x{k:08X}UL"


def norm_combiners(system: Any, prefix: str) -> dict[str, Any]:
    """The template's functions that write one norm operation as C: ``combine(acc, expr)``
    (the t-norm into ``acc``), ``scombine`` (the s-norm), and for a Mamdani system ``imp(f,
    mu)`` (the implication, an expression) and ``agg(acc, t)`` (a sum or probabilistic-OR
    aggregation step), each as the Python evaluation computes it."""
    P = prefix.upper()
    real = f"{prefix}_real"
    tables = antecedent_tables(system)
    snorm = getattr(tables, "snorm", None)

    def combine(acc: str, expr: str) -> str:
        if system.tnorm is TNorm.PRODUCT:
            return f"{acc} *= {expr};"
        return f"{{ const {real} t_ = {expr}; if ({P}_LT(t_, {acc})) {{ {acc} = t_; }} }}"

    def scombine(acc: str, expr: str) -> str:
        if snorm is SNorm.PROBOR:  # a + b - a b, as SNorm.pair
            return f"{{ const {real} t_ = {expr}; {acc} = {acc} + t_ - {acc} * t_; }}"
        return f"{{ const {real} t_ = {expr}; if ({P}_GT(t_, {acc})) {{ {acc} = t_; }} }}"

    def imp(f: str, mu: str) -> str:
        if getattr(system, "implication", None) is Implication.PRODUCT:
            return f"{mu} * {f}"  # mf * strength, as MamdaniTables.aggregate
        return f"({P}_LT({mu}, {f}) ? {mu} : {f})"

    def agg(acc: str, t: str) -> str:
        if getattr(system, "aggregation", None) is Aggregation.PROBOR:
            return f"{acc} += {t} - {acc} * {t};"
        return f"{acc} += {t};"

    return {"combine": combine, "scombine": scombine, "imp": imp, "agg": agg}


def float_context(system: Any, real: RealType, prefix: str) -> dict[str, Any]:
    """The template context of a float or double build of ``system`` (a Sugeno/TSK or a
    Mamdani system; a centre-of-sets Mamdani system is its centre-of-sets Sugeno system)."""
    tables = antecedent_tables(system)
    lit = lambda v: literal(v, real)  # noqa: E731
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
    linear = "linear" in features
    mam = mamdani_context(system, lit) if is_centroid_mamdani(system) else None
    # The reduction's "rules": the firing rules, or a Mamdani system's grid points.
    n_red = n_rules if mam is None else int(mam["n_grid"])
    if mam is not None:
        y_lo = y_hi = np.asarray(system.tables.grids[0])
    # As reducers._switch_iterations: ties within (8 + 2R) eps max(1, max|y|), per side.
    km_factor = (8.0 + 2.0 * n_red) * eps
    km_tol_l = km_factor * max(1.0, float(np.abs(y_lo).max()))
    km_tol_r = km_factor * max(1.0, float(np.abs(y_hi).max()))
    max_iter = reducer._cap(n_red) if (reducer is not None and iterative) else 0
    P = prefix.upper()
    wm = {
        "y1l": f"{P}_C({lit(float(y_lo.min()))})", "yml": f"{P}_C({lit(float(y_lo.max()))})",
        "y1r": f"{P}_C({lit(float(y_hi.min()))})", "ymr": f"{P}_C({lit(float(y_hi.max()))})",
    } if not linear else {k: k for k in ("y1l", "yml", "y1r", "ymr")}
    exact_reduction = red_name in ("exhaustive", "km", "ekm", "eiasc") and not type1_exact
    sort = linear and exact_reduction
    if linear or mam is not None:  # sorted at run time / the grid is sorted
        need_hi_gather = False
    coef_tables = []
    if linear:
        clo = [[lit(v) for v in row] for row in tables.coef_lo_s.tolist()]
        chi = [[lit(v) for v in row] for row in tables.coef_hi_s.tolist()]
        coef_tables = [("C", clo)] if crisp else [("CLO", clo), ("CHI", chi)]
    needs_exp = bool(gauss or umg)
    kind_name = type(system).__name__
    if mam is not None:
        what = (f"{'type-1' if mam['mam_t1'] else 'interval type-2'} Mamdani output "
                f"{mam['out_name']!r}: {mam['implication']} implication, {mam['aggregation']} "
                f"aggregation, {mam['n_grid']}-point grid")
    else:
        what = (f"{'crisp' if crisp else 'interval'} "
                f"{'first-order (linear)' if linear else 'zero-order'} consequents")
    description = (
        f"{kind_name} {system.name!r}: {n_in} input(s), {n_rules} rules, {n_rows} membership "
        f"rows, {system.tnorm.value} t-norm, "
        f"{'type-1' if type1 else 'interval type-2'} input sets, {what}."
    )
    zero = system.zero_firing_value(0)
    context: dict[str, Any] = {
        "mamdani": mam is not None, "mam_t1": False, "linear": linear,
        "coef_tables": coef_tables, "sort": sort, "sort_hi": sort and not crisp,
        "km_factor": lit(km_factor), "r_crisp": crisp if mam is None else True,
        "r_type1_exact": type1_exact and mam is None,
    }
    if mam is not None:
        context.update(mam)
    return context | {
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
        "max_iter_text": f"{max_iter} iterations" if iterative else None,
        "wm": wm, "tnorm": system.tnorm.value,
        "keys": real is RealType.FLOAT,
        "klo": [key(v) for v in lo], "khi": [key(v) for v in hi],
        "kmax": key(float(np.finfo(np.float32 if real is RealType.FLOAT else np.float64).max)),
        "kmin": key(-float(np.finfo(np.float32 if real is RealType.FLOAT
                                    else np.float64).max)),
        "kzero": key(0.0),
        "zero_value": None if zero is None else lit(zero),
    }

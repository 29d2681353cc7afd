"""``it2track fis show | convert | eval`` and ``it2track surface``: fuzzy-system files.

The files are ``.toml`` (ours), ``.t2fis`` (IT2FLS toolbox), ``.fis`` (MATLAB), ``.fll``
(fuzzylite), ``.fml`` (IEEE 1855) and ``.fcl`` (IEC 61131-7, read only); see
:mod:`it2track.io`. :func:`describe` is the text summary ``fis show`` prints.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import click
import numpy as np

from ..fuzzy import (
    AnySystem,
    Connective,
    Consequent,
    Gaussian,
    Input,
    IT2Mamdani,
    IT2Sugeno,
    Linear,
    MembershipFunction,
    Rule,
    ScaledLagged,
    T1Mamdani,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
)
from ..fuzzy.formula import Formula
from .outdir import check_output_file, write_output_file

__all__ = ["describe", "fis", "surface"]


def _num(x: float) -> str:
    return f"{float(x):.6g}"


def _mf_text(mf: MembershipFunction, *, of: MembershipFunction | None = None) -> str:
    """Short human text of one MF, e.g. ``triangle [-1 0 1]`` or ``gaussian mean=0 sigma=1``."""
    h = getattr(mf, "h", 1.0)
    height = "" if float(h) == 1.0 else f" h={_num(h)}"
    if type(mf) is Triangle:
        assert isinstance(mf, Triangle)
        return f"triangle [{_num(mf.a)} {_num(mf.b)} {_num(mf.c)}]{height}"
    if type(mf) is Trapezoid:
        assert isinstance(mf, Trapezoid)
        return f"trapezoid [{_num(mf.a)} {_num(mf.b)} {_num(mf.c)} {_num(mf.d)}]{height}"
    if type(mf) is Gaussian:
        assert isinstance(mf, Gaussian)
        return f"gaussian mean={_num(mf.mean)} sigma={_num(mf.sigma)}{height}"
    if type(mf) in (UncertainMeanGaussianUpper, UncertainMeanGaussianLower):
        assert isinstance(mf, UncertainMeanGaussianUpper | UncertainMeanGaussianLower)
        side = "upper" if isinstance(mf, UncertainMeanGaussianUpper) else "lower"
        return (f"uncertain-mean gaussian ({side}) mean=[{_num(mf.m1)} {_num(mf.m2)}] "
                f"sigma={_num(mf.sigma)}{height}")
    if type(mf) is ScaledLagged:
        assert isinstance(mf, ScaledLagged)
        base = "upper" if of is not None and (mf.upper is of or mf.upper == of) \
            else _mf_text(mf.upper)
        return f"scale {_num(mf.scale)}, lag {_num(mf.lag)} of {base}"
    return repr(mf)


def _kind_text(system: AnySystem) -> str:
    it2 = isinstance(system, IT2Sugeno | IT2Mamdani)
    level = "interval type-2" if it2 else "type-1"
    if isinstance(system, IT2Mamdani | T1Mamdani):
        return f"{level} Mamdani ({type(system).__name__})"
    linear = "linear" in system.tables.features
    order = "first-order (TSK)" if linear else "zero-order"
    return f"{level} {order} Sugeno ({type(system).__name__})"


def _sets_lines(var: Input, what: str) -> list[str]:
    lo, hi = var.universe
    lines = ["", f"{what} {var.name!r}  universe [{_num(lo)}, {_num(hi)}]"]
    width = max(len(s.name) for s in var.sets)
    for s in var.sets:
        if s.is_type1:
            lines.append(f"  {s.name:<{width}}  {_mf_text(s.upper)}")
        else:
            lines.append(f"  {s.name:<{width}}  upper {_mf_text(s.upper)}")
            lines.append(f"  {'':<{width}}  lower {_mf_text(s.lower, of=s.upper)}")
    return lines


def describe(system: AnySystem) -> str:
    """A readable multi-line summary: kind, operators, reducer, inputs (and Mamdani outputs)
    with their sets, rules."""
    zero_v = system.on_zero_firing
    zero = ("error (ZeroFiringError)" if zero_v is None
            else f"output {_num(zero_v)}" if isinstance(zero_v, int | float)
            else "outputs " + ", ".join(_num(v) for v in zero_v))
    lines = [
        system.name or "(unnamed system)",
        f"  kind         {_kind_text(system)}",
        f"  t-norm       {system.tnorm.value}",
    ]
    if any(r.connective is Connective.OR for r in system.rules):
        lines.append(f"  s-norm       {system.snorm.value}")
    if isinstance(system, IT2Mamdani | T1Mamdani):
        lines.append(f"  implication  {system.implication.value}")
        lines.append(f"  aggregation  {system.aggregation.value}")
        lines.append(f"  resolution   {system.resolution} points")
    if isinstance(system, IT2Sugeno | IT2Mamdani):
        reducer = system.reducer
        exact = "exact" if reducer.exact else "approximation"
        lines.append(f"  reducer      {reducer.name} ({exact})")
    if isinstance(system, IT2Mamdani):
        lines.append(f"  reduction    {system.type_reduction.value}")
    if isinstance(system, T1Mamdani):
        lines.append(f"  defuzzifier  {system.defuzzifier.value}")
    lines += [
        f"  no firing    {zero}",
        f"  size         {system.n_inputs} input(s), {system.n_outputs} output(s), "
        f"{system.n_rules} rule(s)",
    ]
    for inp in system.inputs:
        lines += _sets_lines(inp, "input")
    if isinstance(system, IT2Mamdani | T1Mamdani):
        for out in system.outputs:
            lines += _sets_lines(out, "output")
    lines += ["", "rules"]
    digits = len(str(system.n_rules))
    for k, rule in enumerate(system.rules, start=1):
        lines.append(f"  {k:>{digits}}  {rule_text(system, rule)}")
    return "\n".join(lines)


def _consequent_text(cons: Consequent, inputs: tuple[str, ...]) -> str:
    if isinstance(cons, str):
        return cons
    if isinstance(cons, Linear):
        def term(lo: float, hi: float) -> str:
            return _num(lo) if lo == hi else f"[{_num(lo)}, {_num(hi)}]"
        parts = [f"{term(lo, hi)}*{name}"
                 for lo, hi, name in zip(cons.lo, cons.hi, inputs, strict=True)]
        return " + ".join([*parts, term(cons.constant_lo, cons.constant_hi)])
    if isinstance(cons, Formula):
        return f"{cons.text}  ({cons.dialect}'s formula)"
    assert cons is not None
    lo, hi = cons
    return _num(lo) if lo == hi else f"[{_num(lo)}, {_num(hi)}]"


def rule_text(system: Any, rule: Rule) -> str:
    """One rule as text, e.g. ``if e is N or de is not P then u = -4 (weight 0.5)``."""
    terms = [
        f"{inp.name} is {'not ' if neg else ''}{''.join(f'{h} ' for h in hs)}{label}"
        for inp, label, neg, hs in zip(system.inputs, rule.antecedent, rule.negated,
                                       rule.hedges, strict=True)
        if label is not None
    ]
    if rule.condition is not None:
        terms = [_condition_text(system, rule.condition)[1:-1]]
    names = tuple(inp.name for inp in system.inputs)
    outs = system.output_names
    mamdani = any(isinstance(c, str) for c in rule.consequents)
    if len(outs) == 1 and not mamdani:
        then = _consequent_text(rule.consequent, names)
    else:
        then = ", ".join(
            f"{out} {'is' if mamdani else '='} {_consequent_text(cons, names)}"
            for out, cons in zip(outs, rule.consequents, strict=True) if cons is not None
        )
    weight = "" if rule.weight == 1.0 else f" (weight {_num(rule.weight)})"
    joiner = f" {rule.connective.value} "
    hedged = "".join(f" ({out}: {' '.join(map(str, hs))})"
                     for out, hs in zip(outs, rule.consequent_hedges, strict=True) if hs)
    return f"if {joiner.join(terms)} then {then}{weight}{hedged}"


def _condition_text(system: Any, node: Any) -> str:
    """A general condition (:mod:`it2track.fuzzy.conditions`) as text, in parentheses."""
    from ..fuzzy.conditions import Is, Join, Modified, Not

    if isinstance(node, Is):
        hedges = "".join(f"{h} " for h in node.hedges)
        return f"({system.inputs[node.input].name} is {hedges}{node.label})"
    if isinstance(node, Not):
        return f"(not {_condition_text(system, node.operand)})"
    if isinstance(node, Modified):
        hedges = "".join(f"{h} " for h in node.hedges)
        scale = "" if node.weight == 1.0 else f"{_num(node.weight)} * "
        return f"({hedges}{scale}{_condition_text(system, node.operand)})"
    assert isinstance(node, Join)
    norm = "" if node.norm is None else f" [{node.norm.value}]"
    return "(" + f" {node.op}{norm} ".join(_condition_text(system, c)
                                          for c in node.operands) + ")"


def _load(path: str, block: str | None = None, dialect: str | None = None) -> AnySystem:
    from ..io import load

    try:
        return load(path, block=block, dialect=dialect)
    except (ValueError, OSError) as exc:
        where = f"--block {block}: " if block is not None and "block" in str(exc) else ""
        where = f"--dialect {dialect}: " if dialect is not None and "dialect" in str(exc) \
            else where
        raise click.ClickException(f"{where}{exc}") from None


_FILE = click.Path(exists=True, dir_okay=False, path_type=str)
_DIALECT = click.option(
    "--dialect", type=click.Choice(["matlab", "octave"]), default=None,
    help="Read a .fis as MATLAB (the default) or the Octave fuzzy-logic-toolkit evaluates it "
         "(Sugeno rules of equal conclusions merged by AggMethod; 'centroid_integral').")


@click.group()
def fis() -> None:
    """Fuzzy-system files: .toml (it2track), .t2fis (IT2FLS toolbox), .fis (MATLAB), .fll
(fuzzylite), .fml (IEEE 1855), .fcl (IEC 61131-7, read only)."""


@fis.command()
@click.argument("file", type=_FILE)
@_DIALECT
def show(file: str, dialect: str | None) -> None:
    """Print a summary of the fuzzy system in FILE."""
    click.echo(describe(_load(file, dialect=dialect)))


_FORCE = click.option(
    "--force", is_flag=True,
    help="Replace an existing file of that name that it2track cannot prove it wrote.")


@fis.command()
@click.argument("source", type=_FILE)
@click.argument("target", type=click.Path(dir_okay=False, path_type=str))
@click.option("--block", metavar="NAME", default=None,
              help="The FUNCTION_BLOCK of an FCL SOURCE to read (default: the first).")
@_DIALECT
@_FORCE
def convert(source: str, target: str, block: str | None, dialect: str | None,
            force: bool) -> None:
    """Convert SOURCE to TARGET; the formats follow the suffixes (.toml, .t2fis, .fis, .fll,
    .fml; .fcl is read only).

    TARGET's SHA-256 goes to TARGET.sha256: the proof that lets a later run replace it.
    """
    from ..io import dumps, format_of

    try:
        fmt = format_of(target)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="TARGET") from None
    check_output_file(target, "TARGET", force=force)
    system = _load(source, block, dialect)
    try:
        text = dumps(system, fmt)
    except ValueError as exc:
        raise click.ClickException(f"cannot write TARGET {target}: {exc}") from None
    write_output_file(target, text.encode("utf-8"), "TARGET")
    click.echo(f"wrote {target}")


@fis.command(name="eval", context_settings={"ignore_unknown_options": True})
@click.argument("file", type=_FILE)
@click.argument("values", nargs=-1, required=True)
@_DIALECT
def evaluate(file: str, values: tuple[str, ...], dialect: str | None) -> None:
    """Evaluate FILE at one point: one VALUE per input, in order (negative values are fine:
    ``it2track fis eval heading.toml 0.3 -0.1``)."""
    system = _load(file, dialect=dialect)
    names = [inp.name for inp in system.inputs]
    if len(values) != system.n_inputs:
        raise click.ClickException(
            f"{file} takes {system.n_inputs} VALUES ({', '.join(names)}), got {len(values)}")
    numbers = []
    for k, (name, text) in enumerate(zip(names, values, strict=True), start=1):
        try:
            number = float(text)
        except ValueError:
            number = math.nan
        if not math.isfinite(number):
            raise click.BadParameter(
                f"VALUE {k} ({name}) {text!r} must be a finite number", param_hint="VALUES")
        numbers.append(number)
    try:
        yls, yrs = (np.atleast_1d(np.asarray(v, dtype=float))
                    for v in system.interval(*numbers))
    except ValueError as exc:
        raise click.ClickException(str(exc)) from None
    several = system.n_outputs > 1
    for name, yl, yr in zip(system.output_names, yls.tolist(), yrs.tolist(), strict=True):
        label = name if several else "u"
        click.echo(f"{label} = {(yl + yr) / 2:.10g}")
        if isinstance(system, IT2Sugeno | IT2Mamdani):
            click.echo(f"[yl, yr] = [{yl:.10g}, {yr:.10g}]")


def _parse_fixed(items: tuple[str, ...]) -> dict[str, float]:
    fixed: dict[str, float] = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise click.BadParameter(f"{item!r}: expected NAME=VALUE", param_hint="--fix")
        try:
            number = float(value)
        except ValueError:
            raise click.BadParameter(f"{item!r}: the value {value!r} of {name} is not a "
                                     "number", param_hint="--fix") from None
        if not math.isfinite(number):
            raise click.BadParameter(f"{item!r}: the value {value!r} of {name} must be a "
                                     "finite number", param_hint="--fix")
        if name in fixed:
            raise click.BadParameter(f"{item!r}: {name} is fixed twice", param_hint="--fix")
        fixed[name] = number
    return fixed


@click.command()
@click.argument("file", type=_FILE)
@click.option("--out", "out", required=True, type=click.Path(dir_okay=False, path_type=str),
              help="Image to write (.png, .svg, .pdf).")
@click.option("--points", default=101, show_default=True, type=click.IntRange(min=2),
              help="Grid points per axis.")
@click.option("--style", default="3d", show_default=True, type=click.Choice(["3d", "contour"]),
              help="3-D surface or filled contours.")
@click.option("--x", "x_input", default=None, help="Input on the x axis (default: the first).")
@click.option("--y", "y_input", default=None, help="Input on the y axis (default: the second).")
@click.option("--fix", "fix", multiple=True, metavar="NAME=VALUE",
              help="Value of an input not on the axes (default: middle of its universe).")
@click.option("--output", "output", default=None,
              help="Output to plot, for a system with several outputs.")
@_FORCE
def surface(file: str, out: str, points: int, style: str, x_input: str | None,
            y_input: str | None, fix: tuple[str, ...], output: str | None,
            force: bool) -> None:
    """Plot the control surface of FILE and each input's sets (FoUs for IT2) to --out
    (its SHA-256 to OUT.sha256: the proof that lets a later run replace it)."""
    from ..report.surface import FIGURE_FORMATS, figure_bytes, plot_system

    for option, given in (("--x", x_input), ("--y", y_input), ("--output", output)):
        if given == "":
            raise click.BadParameter("'' is empty: name an input" if option != "--output"
                                     else "'' is empty: name an output", param_hint=option)
    suffix = Path(out).suffix.lstrip(".").lower() or "png"
    if suffix not in FIGURE_FORMATS:
        raise click.BadParameter(
            f"{out!r}: the suffix must be one of {', '.join('.' + f for f in FIGURE_FORMATS)}",
            param_hint="--out")
    fixed = _parse_fixed(fix)
    check_output_file(out, "--out", force=force)
    system = _load(file)
    if system.n_outputs > 1 or output is not None:
        if output is None:
            raise click.BadParameter(
                f"{file} has {system.n_outputs} outputs ({', '.join(system.output_names)}); "
                "choose one", param_hint="--output")
        try:
            system = system.select_output(output)
        except ValueError as exc:
            raise click.BadParameter(str(exc), param_hint="--output") from None
    inputs: Any = None
    names = [inp.name for inp in system.inputs]
    for option, given in (("--x", x_input), ("--y", y_input)):
        if given is not None and given not in names:
            raise click.BadParameter(
                f"{given!r}: {file} has no input of that name (its inputs: "
                f"{', '.join(names)})", param_hint=option)
    for name in fixed:
        if name not in names:
            raise click.BadParameter(
                f"{name}={fixed[name]!r}: {file} has no input {name!r} (its inputs: "
                f"{', '.join(names)})", param_hint="--fix")
    if system.n_inputs >= 2:
        x = x_input or names[0]
        y = y_input or next(n for n in names if n != x)
        if x == y:
            raise click.BadParameter(f"--x and --y are both {x!r}: choose two inputs",
                                     param_hint="--y")
        inputs = (x, y)
    elif x_input or y_input:
        raise click.BadParameter("a one-input system has no axes to choose", param_hint="--x")
    try:
        fig = plot_system(system, None, inputs=inputs, fixed=fixed, points=points, style=style)
        data = figure_bytes(fig, suffix)
    except (ValueError, OSError) as exc:
        raise click.ClickException(str(exc)) from None
    write_output_file(out, data, "--out")
    click.echo(f"wrote {os.fspath(Path(out))}")

"""``it2track export c``: a fuzzy controller as self-contained C99 (see :mod:`it2track.codegen`).

Everything given on the command line is checked before any file is read or written: the
system file must be a regular file of a known suffix and sane size, ``--paper`` a valid FoU
width, ``--prefix`` a C identifier, ``--reducer`` only for a type-2 system, and ``--out`` a
directory (or a new one in an existing directory) holding no foreign files of the target names
(unless ``--force``, and never anything but regular files).
"""

from __future__ import annotations

import dataclasses
import math
import os
import stat
from pathlib import Path

import click

__all__ = ["export"]

#: Largest fuzzy-system file read (a real one is a few kilobytes).
MAX_SYSTEM_BYTES = 16 * 1024 * 1024
REDUCERS = ["exhaustive", "km", "ekm", "eiasc", "nie-tan", "wu-mendel"]


@click.group()
def export() -> None:
    """Export a controller for deployment."""


@export.command("c")
@click.argument("system", required=False, type=click.Path(path_type=Path))
@click.option("--paper", "fou", type=float, default=None,
              help="The paper's controller with this FoU width instead of SYSTEM "
              "(0 = the type-1 FLC).")
@click.option("--out", "out_text", required=True, type=click.Path(),
              help="Directory for <prefix>.h and <prefix>.c (created if missing).")
@click.option("--real", type=click.Choice(["float", "double", "q15"]), default="double",
              show_default=True, help="C arithmetic: float or double, or q15 -- integer-only "
              "fixed point with int16_t inputs and outputs (for an 8-bit AVR without an FPU; "
              "the header gives each value's Q format).")
@click.option("--reducer", type=click.Choice(REDUCERS), default=None,
              help="Type reducer compiled in (default: the system's own).")
@click.option("--prefix", default="it2", show_default=True,
              help="Prefix of the file names and of every C name, so that several "
              "controllers link into one program.")
@click.option("--force", is_flag=True,
              help="Replace existing regular files of the target names that it2track did not "
              "write.")
def c_command(system: Path | None, fou: float | None, out_text: str, real: str,
              reducer: str | None, prefix: str, force: bool) -> None:
    """Generate C99 for the controller in SYSTEM (.t2fis, .fis or .toml) or --paper FOU.

    The code needs no heap and no library beyond <math.h> (for Gaussian sets); one call,
    <prefix>_eval(in, &u, &yl, &yr), evaluates a step and returns a status (0 = OK). With
    --real q15 everything is integer arithmetic: the inputs and outputs are int16_t in the Q
    formats the header defines (<PREFIX>_IN_FRAC_i, <PREFIX>_OUT_FRAC).
    """
    from ..codegen import RealType, check_prefix, check_supported, generate_c, write_c
    from ..io import UnsupportedFeatureError

    # -- check every option before reading or writing anything --------------------------------
    if (system is None) == (fou is None):
        raise click.UsageError("give a SYSTEM file or --paper FOU (exactly one)")
    try:
        check_prefix(prefix)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--prefix") from None
    if fou is not None and not (math.isfinite(fou) and fou >= 0):
        raise click.BadParameter(f"FoU width {fou!r} must be finite and >= 0",
                                 param_hint="--paper")
    if system is not None:
        _check_system_file(system)
    if out_text == "":
        raise click.BadParameter("must name a directory, not ''", param_hint="--out")
    out = Path(out_text)
    _check_out_dir(out)

    # -- build the system ---------------------------------------------------------------------
    from ..fuzzy import IT2Sugeno, Reducer, T1Sugeno

    loaded: object
    try:
        if fou is not None:
            from ..paper import heading_fls

            loaded = heading_fls(fou)
        else:
            from ..io import load

            assert system is not None
            loaded = load(system)
    except ValueError as exc:
        where = "--paper" if fou is not None else "SYSTEM"
        raise click.BadParameter(str(exc), param_hint=where) from None
    except OSError as exc:
        raise click.BadParameter(f"cannot read {system}: {exc.strerror}",
                                 param_hint="SYSTEM") from None
    where = "--paper" if fou is not None else "SYSTEM"
    try:
        check_supported(loaded)  # before anything else: a Mamdani system, say, is named as such
    except UnsupportedFeatureError as exc:
        raise click.BadParameter(f"cannot generate C: {exc}", param_hint=where) from None
    assert isinstance(loaded, IT2Sugeno | T1Sugeno)
    fls = loaded
    if reducer is not None:
        if not isinstance(fls, IT2Sugeno):
            raise click.BadParameter(
                f"{type(fls).__name__} {fls.name!r} is a type-1 system: it has no type "
                "reducer", param_hint="--reducer")
        fls = dataclasses.replace(fls, reducer=Reducer.from_name(reducer).value)

    # -- generate and write -------------------------------------------------------------------
    try:
        code = generate_c(fls, real=RealType.from_name(real), prefix=prefix)
    except UnsupportedFeatureError as exc:
        raise click.BadParameter(f"cannot generate C: {exc}", param_hint=where) from None
    try:
        written = write_c(code, out, force=force)
    except (FileExistsError, NotADirectoryError, FileNotFoundError) as exc:
        raise click.BadParameter(str(exc), param_hint="--out") from None
    except OSError as exc:
        raise click.ClickException(f"cannot write to --out {out}: {exc.strerror}") from None
    for path in written:
        click.echo(f"wrote {path}")
    click.echo(f"{code.n_inputs} inputs, {code.n_rules} rules, {real}, reducer {code.reducer}: "
               f"call {prefix}_eval(in, &u, &yl, &yr) (returns {prefix.upper()}_OK = 0)")
    if code.fixed is not None:
        fracs = ", ".join(f"in[{i}] Q{f}" for i, f in enumerate(code.fixed.in_frac))
        click.echo(f"fixed point: {fracs}; u, yl, yr Q{code.fixed.out_frac} "
                   f"(value = integer / 2^frac)")


def _check_system_file(path: Path) -> None:
    from ..io import format_of

    try:
        format_of(path)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="SYSTEM") from None
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise click.BadParameter(f"{path}: no such file", param_hint="SYSTEM") from None
    except OSError as exc:
        raise click.BadParameter(f"{path}: {exc.strerror}", param_hint="SYSTEM") from None
    if not stat.S_ISREG(st.st_mode):
        raise click.BadParameter(f"{path}: not a regular file", param_hint="SYSTEM")
    if st.st_size > MAX_SYSTEM_BYTES:
        raise click.BadParameter(
            f"{path}: {st.st_size} bytes, more than the {MAX_SYSTEM_BYTES} a fuzzy-system file "
            "can reasonably be", param_hint="SYSTEM")


def _check_out_dir(out: Path) -> None:
    if out.exists() and not out.is_dir():
        raise click.BadParameter(f"{out}: exists and is not a directory", param_hint="--out")
    if not out.exists() and not out.parent.is_dir():
        raise click.BadParameter(f"{out}: parent directory {out.parent} does not exist",
                                 param_hint="--out")
    target = out if out.exists() else out.parent
    if not os.access(target, os.W_OK | os.X_OK):
        raise click.BadParameter(f"{target}: not writable", param_hint="--out")

"""``it2track config show NAME [--out FILE]`` and the ``--config`` option type.

The example configs ship inside the package (:mod:`it2track.configs`); ``config show`` prints
one or writes a copy to edit, and every ``--config`` option takes a file or a packaged name.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import click

__all__ = ["ConfigFile", "config"]


class ConfigFile(click.ParamType):
    """A ``--config`` value: an existing file, else the name of a packaged config.

    Converts to the path to read (a string); the reader then checks the file itself (regular,
    UTF-8, size) and names it in its errors.
    """

    name = "FILE|NAME"

    def convert(self, value: Any, param: click.Parameter | None,
                ctx: click.Context | None) -> str:
        """Resolve ``value`` with :func:`it2track.configs.resolve` (a usage error if it
        is neither a file nor a packaged name)."""
        from .. import configs

        if isinstance(value, Path):
            value = str(value)
        try:
            return str(configs.resolve(value))
        except ValueError as exc:
            self.fail(str(exc), param, ctx)


@click.group()
def config() -> None:
    """The example configs shipped with it2track (paper, sweep, optimize)."""


@config.command("show")
@click.argument("name")
@click.option("--out", "out", type=click.Path(), default=None,
              help="Write the config to this new file (to edit) instead of printing it.")
@click.option("--force", is_flag=True,
              help="Replace an existing regular file given as --out.")
def show(name: str, out: str | None, force: bool) -> None:
    """Print the packaged config NAME, or write it to --out FILE.

    NAME is one of the packaged configs: paper (the study reproduce runs by default), sweep
    (an example sweep) or optimize (the FoU optimisation). Every --config option takes the
    name or the file this writes.
    """
    from .. import configs
    from ..atomicfile import NotRegularFileError, atomic_write_text, check_replaceable

    try:
        text = configs.text(name)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="NAME") from None
    if out is None:
        click.echo(text, nl=False)
        return
    if out == "":
        raise click.BadParameter("'' is empty: give a file name", param_hint="--out")
    try:
        check_replaceable(out)
    except NotRegularFileError as exc:
        raise click.BadParameter(f"{out}: {exc.strerror}", param_hint="--out") from None
    if os.path.lexists(out) and not force:
        raise click.BadParameter(f"{out} exists; give another name, or --force to replace it",
                                 param_hint="--out")
    parent = Path(out).parent
    if not parent.is_dir():
        raise click.BadParameter(f"{out}: the folder {parent} does not exist",
                                 param_hint="--out")
    try:
        atomic_write_text(out, text)
    except OSError as exc:
        raise click.ClickException(f"cannot write --out {out}: {exc.strerror or exc}") from None
    click.echo(f"wrote {out} (the packaged config {name!r}; run it with --config {out})")

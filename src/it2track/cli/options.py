"""Command-line types of the shared value ranges (:mod:`it2track._ranges`): an option is
checked when it is parsed -- before any work -- by the same :class:`~it2track._ranges.Range`
the configuration tables and the library use, and the error names the option, the value as
typed and the range (``Invalid value for '--worker-timeout': 'nan' must be a finite number
in 0 < x <= 604800 s``)."""

from __future__ import annotations

from typing import Any

import click

from .._ranges import DURATION, WORKER_TIMEOUT, Range

__all__ = ["DURATION_TYPE", "FINITE", "POSITIVE", "WORKER_TIMEOUT_TYPE", "RealRange"]


class RealRange(click.ParamType):
    """A real number inside ``allowed`` (finite, whatever the range says)."""

    name = "float"

    def __init__(self, allowed: Range) -> None:
        self.allowed = allowed

    def convert(self, value: Any, param: click.Parameter | None,
                ctx: click.Context | None) -> float:
        if isinstance(value, float) and value in self.allowed:
            return value  # a default
        try:
            number = float(value)
        except (TypeError, ValueError):
            self.fail(f"{value!r} is not a number", param, ctx)
        if number not in self.allowed:
            shown = value if isinstance(value, str) else repr(value)
            self.fail(f"{shown!r} must be {self.allowed.requirement()}", param, ctx)
        return number

    def __repr__(self) -> str:
        return f"RealRange({self.allowed.text()})"


#: Any finite number (no NaN, no infinity).
FINITE = RealRange(Range())
#: A finite number > 0.
POSITIVE = RealRange(Range(0.0, lo_open=True))
#: ``--duration``: the cap every command shares.
DURATION_TYPE = RealRange(DURATION)
#: ``--worker-timeout`` of ``sweep``, ``optimize`` and ``reproduce``.
WORKER_TIMEOUT_TYPE = RealRange(WORKER_TIMEOUT)

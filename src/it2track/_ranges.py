"""The allowed ranges of the values every command and configuration table shares: one table,
one check, one wording.

A value that reaches a simulation -- from a command-line option, a TOML table or the Python
API -- is checked against the same :class:`Range` wherever it comes from: ``simulate
--duration`` and a sweep's ``[simulation] duration`` have one cap, ``--worker-timeout`` is
checked the same way by ``sweep``, ``optimize`` and ``reproduce``. A check refuses what is not
a real number (``True``, a string), NaN, infinities and magnitudes outside the range, with a
message naming the value as given, the name the caller passes (the option, the key or the
field) and the range allowed:

>>> DURATION.check(3601, "duration")
Traceback (most recent call last):
...
ValueError: duration=3601 must be a finite number in 0 < x <= 3600 s

Standard library only (imported by ``plant``, ``tracking``, ``experiments`` and ``cli``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real

__all__ = [
    "DURATION",
    "MAX_DURATION",
    "MAX_WORKER_TIMEOUT",
    "START_HEADING",
    "START_POSITION",
    "WORKER_TIMEOUT",
    "Range",
]


@dataclass(frozen=True)
class Range:
    """An interval of allowed real values.

    Parameters
    ----------
    lo, hi : float
        Bounds (``-inf``/``inf`` for none; the value itself must be finite anyway).
    lo_open, hi_open : bool
        Exclude the bound (``lo < x`` instead of ``lo <= x``).
    unit : str
        Unit shown in messages (``"s"``, ``"rad"``).
    why : str
        Appended to the message: why the range is what it is.
    """

    lo: float = -math.inf
    hi: float = math.inf
    lo_open: bool = False
    hi_open: bool = False
    unit: str = ""
    why: str = ""

    def __contains__(self, value: object) -> bool:
        if isinstance(value, bool) or not isinstance(value, Real):
            return False
        try:
            x = float(value)
        except OverflowError:  # an integer beyond the floats
            return False
        if not math.isfinite(x):
            return False
        above = x > self.lo if self.lo_open else x >= self.lo
        below = x < self.hi if self.hi_open else x <= self.hi
        return above and below

    def text(self) -> str:
        """The range as it reads in messages, e.g. ``0 < x <= 3600 s`` (``""`` if unbounded)."""
        parts = []
        if math.isfinite(self.lo):
            parts.append(f"{self.lo:.10g} {'<' if self.lo_open else '<='} ")
        parts.append("x")
        if math.isfinite(self.hi):
            parts.append(f" {'<' if self.hi_open else '<='} {self.hi:.10g}")
        if len(parts) == 1:
            return ""
        return "".join(parts) + (f" {self.unit}" if self.unit else "")

    def requirement(self) -> str:
        """``"a finite number in 0 < x <= 3600 s"`` (or just ``"a finite number"``)."""
        text = self.text()
        return "a finite number" + (f" in {text}" if text else "")

    def check(self, value: object, name: str) -> float:
        """``value`` as a float if it lies in the range, else a ``ValueError`` naming ``name``
        and the value as given (``repr``)."""
        if value in self:
            assert isinstance(value, Real)
            return float(value)
        message = f"{name}={value!r} must be {self.requirement()}"
        if self.why:
            message += f" ({self.why})"
        raise ValueError(message)


#: Longest simulated time, s: one hour of a 10-s paper scenario's dynamics is already 360 000
#: control periods at the default 0.01 s.
MAX_DURATION = 3600.0
DURATION = Range(0.0, MAX_DURATION, lo_open=True, unit="s")

#: Start pose: a position within 1000 km of the origin (the paper's paths stay within 30 m;
#: beyond, squared position errors lose their digits) and a heading within one turn either
#: way, in radians (a heading of 90 or 180 is a heading in degrees).
START_POSITION = Range(-1e6, 1e6, unit="m")
START_HEADING = Range(-2 * math.pi, 2 * math.pi, unit="rad",
                      why="one turn either way, in radians")

#: Longest wait for a Dask worker, s (one week): longer is a wait that never ends.
MAX_WORKER_TIMEOUT = 7 * 24 * 3600.0
WORKER_TIMEOUT = Range(0.0, MAX_WORKER_TIMEOUT, lo_open=True, unit="s")

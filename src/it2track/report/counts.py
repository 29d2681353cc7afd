"""Counts a page prints, taken from the rows they describe (never from a config or a first row).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

__all__ = ["count_text", "realisation_counts", "realisations_text"]


def count_text(values: Iterable[int]) -> str:
    """``"100"`` when every value is 100, ``"100–400"`` for a range; ``"0"`` for none.

    Examples
    --------
    >>> count_text([100, 400, 200]), count_text([6, 6])
    ('100–400', '6')
    """
    v = sorted({int(x) for x in values})
    if not v:
        return "0"
    return str(v[0]) if len(v) == 1 else f"{v[0]}–{v[-1]}"


def realisation_counts(summary: Sequence[Mapping[str, Any]], experiment: str, *,
                       sigma: float | None = None) -> list[int]:
    """The ``n`` of every noisy summary row of ``experiment`` (at ``sigma`` if given):
    noise-free rows (one deterministic run) are not realisation counts."""
    return [int(r["n"]) for r in summary
            if r.get("experiment") == experiment and float(r["noise_std"]) > 0.0
            and (sigma is None or float(r["noise_std"]) == sigma)]


def realisations_text(summary: Sequence[Mapping[str, Any]], experiment: str, *,
                      sigma: float | None = None) -> str:
    """:func:`count_text` of :func:`realisation_counts`."""
    return count_text(realisation_counts(summary, experiment, sigma=sigma))

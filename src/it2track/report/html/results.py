"""The page's figures: one numbering over the page, each embedded as a data URI with its
caption; the results section shows those that are not part of another section."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from markupsafe import Markup

from ...experiments.study import StudyResult
from .captions import _ordered_keys, figure_captions
from .env import data_uri, render

__all__ = ["SECTION_FIGURES", "figure_refs", "results_section"]

#: Figures shown in their own section (robustness, microcontroller cost), not under Results, in
#: page order.
SECTION_FIGURES = ("robustness", "sensitivity", "mcu_costs")


def figure_refs(result: StudyResult, summary: Sequence[Mapping[str, Any]],
                figures: Mapping[str, Path]) -> dict[str, dict[str, Any]]:
    """Key -> ``key, number, title, caption, src`` (data URI) ``, name`` of every figure, in
    page order: the results first, then :data:`SECTION_FIGURES`."""
    caps = figure_captions(result, summary)
    keys = _ordered_keys(figures, result)
    order = [k for k in keys if k not in SECTION_FIGURES]
    order += [k for k in SECTION_FIGURES if k in figures]
    refs = {}
    for number, key in enumerate(order, start=1):
        path = Path(figures[key])
        title, caption = caps.get(key, (key.replace("_", " "), ""))
        refs[key] = {"key": key, "number": number, "title": title, "caption": caption,
                     "src": data_uri(path), "name": path.name}
    return refs


def results_section(refs: Mapping[str, Mapping[str, Any]]) -> Markup:
    """The figures of :func:`figure_refs` that belong to no other section."""
    return render("sections/results.html.j2",
                  figures=[r for k, r in refs.items() if k not in SECTION_FIGURES])

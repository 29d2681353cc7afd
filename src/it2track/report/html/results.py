"""The page's results section: every figure, embedded as a data URI, with its caption."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from markupsafe import Markup

from ...experiments.study import StudyResult
from .captions import _ordered_keys, figure_captions
from .env import render

__all__ = ["results_section"]


def results_section(result: StudyResult, summary: Sequence[Mapping[str, Any]],
                    figures: Mapping[str, Path]) -> Markup:
    """The figures in report order, numbered, each with its title and caption."""
    caps = figure_captions(result, summary)
    items = []
    for key in _ordered_keys(figures, result):
        path = Path(figures[key])
        title, caption = caps.get(key, (key.replace("_", " "), ""))
        items.append({"key": key, "path": path, "name": path.name, "title": title,
                      "caption": caption})
    return render("sections/results.html.j2", figures=items)

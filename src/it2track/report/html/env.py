"""The Jinja2 environment of the report and the small formatting helpers its templates use.

Templates live in ``it2track/report/templates`` (package data). Autoescaping is on for every
template: any value from the study (labels, statements, file names, the command) is escaped;
only the output of another of our templates is inserted as markup.
"""

from __future__ import annotations

import base64
import math
from collections.abc import Mapping
from functools import cache
from pathlib import Path
from typing import Any

import jinja2
import numpy as np
from markupsafe import Markup

__all__ = ["fmt", "plain", "render"]

_MIME = {".png": "image/png", ".svg": "image/svg+xml", ".jpg": "image/jpeg",
         ".jpeg": "image/jpeg", ".gif": "image/gif", ".webp": "image/webp"}


def plain(v: Any) -> Any:
    """JSON-ready copy (numpy scalars and arrays, tuples, paths)."""
    if isinstance(v, Mapping):
        return {str(k): plain(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [plain(x) for x in v]
    if isinstance(v, np.ndarray):
        return [plain(x) for x in v.tolist()]
    if isinstance(v, np.bool_):
        return bool(v)
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, np.floating):
        return float(v)
    if isinstance(v, Path):
        return str(v)
    return v


def fmt(v: Any, digits: int = 4) -> str:
    """A cell value as text: numbers to ``digits`` significant digits, booleans yes/no,
    ``None`` as a dash."""
    if isinstance(v, bool | np.bool_):
        return "yes" if v else "no"
    if isinstance(v, int | np.integer):
        return str(int(v))
    if isinstance(v, float | np.floating):
        f = float(v)
        if not math.isfinite(f):
            return str(f)
        return f"{f:.{digits}g}"
    if v is None:
        return "—"
    return str(v)


def num(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def data_uri(path: Path) -> str:
    """The file as a base64 ``data:`` URI (the page embeds its figures)."""
    path = Path(path)
    mime = _MIME.get(path.suffix.lower(), "application/octet-stream")
    return f"data:{mime};base64," + base64.b64encode(path.read_bytes()).decode("ascii")


@cache
def environment() -> jinja2.Environment:
    """The report's template environment (autoescaping on, strict about undefined names)."""
    env = jinja2.Environment(
        loader=jinja2.PackageLoader("it2track.report", "templates"),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
    )
    env.filters["fmt"] = fmt
    env.filters["data_uri"] = data_uri
    return env


def render(template: str, **context: Any) -> Markup:
    """Render ``template`` (a name under ``templates/``) with ``context``; the result is markup
    that another template may insert as it is."""
    return Markup(environment().get_template(template).render(**context))

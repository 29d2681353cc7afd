"""Plain-text outputs of the study: metrics.csv, summary.csv, claims.md, manifest.json.

Every writer is atomic (:mod:`it2track.atomicfile`), and the CSV writers use
``repr`` for floats, so a rerun with the same config and seeds reproduces them byte for byte.
"""

from __future__ import annotations

import csv
import io
import json
import platform
import subprocess
import sys
from collections.abc import Iterable, Mapping, Sequence
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

from ..atomicfile import atomic_write_text

__all__ = [
    "manifest",
    "write_claims_md",
    "write_metrics_csv",
    "write_summary_csv",
]


def _cell(v: Any) -> str:
    if isinstance(v, float | np.floating):
        return repr(float(v))
    if isinstance(v, np.integer):
        return str(int(v))
    return str(v)


def _csv_text(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for row in rows:
        w.writerow([_cell(v) for v in row])
    return buf.getvalue()


def write_metrics_csv(path: Path, rows: Mapping[str, np.ndarray], columns: Sequence[str]) -> Path:
    """One line per run, columns in the given order."""
    cols = [rows[c] for c in columns]
    n = len(cols[0]) if cols else 0
    return atomic_write_text(path, _csv_text(columns, (tuple(c[i] for c in cols)
                                                       for i in range(n))))


def write_summary_csv(path: Path, summary: Sequence[Mapping[str, Any]]) -> Path:
    if not summary:
        raise ValueError("empty summary")
    header = list(summary[0])
    return atomic_write_text(path, _csv_text(header, ([r[h] for h in header] for r in summary)))


def write_claims_md(path: Path, claims: Sequence[Any], *, preamble: str) -> Path:
    """``claims.md``: a verdict table, then each claim with its criterion and evidence."""
    lines = [preamble.rstrip(), "", "| claim | statement | verdict |", "|---|---|---|"]
    for c in claims:
        detail = f" ({c.detail})" if getattr(c, "detail", "") else ""
        lines.append(f"| {c.id} | {c.statement} | **{c.verdict}**{detail} |")
    lines.append("")
    for c in claims:
        lines.append(c.to_markdown())
    return atomic_write_text(path, "\n".join(lines) + "\n")


def _git_revision() -> str | None:
    here = Path(__file__).resolve().parent
    try:
        rev = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=here, capture_output=True, text=True, timeout=5,
            check=True,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"], cwd=here,
            capture_output=True, text=True, timeout=5, check=True,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return rev + ("+dirty" if dirty else "")


def manifest(*, config: Mapping[str, Any], command: str, elapsed_s: float,
             extra: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Provenance of a run: config, command, versions, git revision, platform, timing."""
    versions: dict[str, str | None] = {}
    for pkg in ("it2track", "numpy", "scipy", "matplotlib", "click", "tqdm"):
        try:
            versions[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            versions[pkg] = None
    return {
        "command": command,
        "config": config,
        "versions": {"python": sys.version.split()[0], **versions},
        "git_revision": _git_revision(),
        "platform": platform.platform(),
        "elapsed_s": round(elapsed_s, 3),
        **(extra or {}),
    }


def write_json(path: Path, data: Mapping[str, Any]) -> Path:
    text = json.dumps(data, indent=2, sort_keys=False, allow_nan=False)
    return atomic_write_text(path, text + "\n")

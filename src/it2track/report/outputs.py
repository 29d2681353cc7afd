"""Plain-text outputs of the study: metrics.csv, summary.csv, verdicts.csv, robustness.csv,
sensitivity.csv, manifest.json (claims.md: :mod:`.claims_md`).

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
from .claims_md import (
    MODEL_DOC,
    SMOKE,
    claims_preamble,
    levels_markdown,
    robustness_markdown,
    study_sections,
    write_claims_md,
)

__all__ = [
    "MODEL_DOC",
    "SMOKE",
    "claims_preamble",
    "levels_markdown",
    "manifest",
    "robustness_markdown",
    "study_sections",
    "write_claims_md",
    "write_metrics_csv",
    "write_robustness_csv",
    "write_sensitivity_csv",
    "write_summary_csv",
    "write_verdicts_csv",
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


def write_rows_csv(path: Path, rows: Sequence[Mapping[str, Any]]) -> Path:
    """A list of same-keyed dicts as CSV (header from the first row)."""
    if not rows:
        raise ValueError(f"no rows to write to {path.name}")
    header = list(rows[0])
    return atomic_write_text(path, _csv_text(header, ([r[h] for h in header] for r in rows)))


def write_robustness_csv(path: Path, robustness: Any) -> Path:
    """``robustness.csv``: one row per claim, variant and evidence cell
    (:attr:`~it2track.experiments.robustness.RobustnessResult.cells`)."""
    return write_rows_csv(path, robustness.cells)


def write_sensitivity_csv(path: Path, robustness: Any) -> Path:
    """``sensitivity.csv``: the Morris indices of every output and factor, then the ranking
    is in claims.md (:attr:`~it2track.experiments.robustness.RobustnessResult.sensitivity`)."""
    return write_rows_csv(path, robustness.sensitivity)


def write_verdicts_csv(path: Path, rows: Sequence[Mapping[str, Any]]) -> Path:
    """``verdicts.csv``: one row per claim x path (and all) x noise level
    (:func:`~it2track.experiments.verdicts.verdict_rows`)."""
    return write_rows_csv(path, rows)


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

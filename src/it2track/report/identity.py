"""Who is who in a :class:`StudyResult`: controller identity, summary look-up, trajectory slugs.

Shared by the figures and the HTML page; numpy only (no matplotlib), so the page can be built
without the plotting stack. Controllers are identified by their
:class:`~it2track.experiments.specs.ControllerSpec` (the study's ``trace_specs``,
``surface_specs``, PD and extra controllers) or by the ``kind`` and ``fou`` columns of the metrics
table, never by the text of their labels.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..experiments.specs import ControllerKind, ControllerSpec
from ..experiments.study import StudyResult

__all__ = [
    "INTEGRAL_UNITS",
    "PAPER_FIGURE_NUMBER",
    "controller_specs",
    "slug",
    "surface_limit",
]

#: Units of the integral criteria (the heading error in rad, time in s).
INTEGRAL_UNITS = {"IAE": "rad·s", "ITAE": "rad·s²", "ISE": "rad²·s", "ITSE": "rad²·s²"}
#: Paper figure numbers of the built-in trajectories.
PAPER_FIGURE_NUMBER = {"straight": 7, "curved": 8, "sinusoidal": 9}


def slug(name: str) -> str:
    """File-name-safe form of a trajectory name (CSV paths become their stem).

    Examples
    --------
    >>> slug("curved"), slug("data/my path.csv")
    ('curved', 'my_path')
    """
    text = re.split(r"[\\/]", name)[-1]
    if text.lower().endswith(".csv"):
        text = text[:-4]
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_") or "trajectory"


def controller_specs(result: StudyResult) -> dict[str, ControllerSpec]:
    """Label -> :class:`ControllerSpec` of every controller ``result`` knows the spec of: the
    traced ones, those with a control surface, the PD baseline, the tuned fuzzy controllers and
    the user's extras.

    Controllers seen only in the metrics table (e.g. the FoU sweep's widths) have no entry;
    their ``kind`` and ``fou`` are columns of ``result.rows``.
    """
    specs: dict[str, ControllerSpec] = {}
    for spec in result.config.extra_controllers:
        specs[spec.label] = spec
    if result.pd is not None:
        specs[result.pd.label] = result.pd
    for spec in result.tuned.values():
        specs[spec.label] = spec
    for label, spec in result.surface_specs.items():
        specs[label] = spec
    for label, spec in zip(result.trace_controllers, result.trace_specs, strict=False):
        specs[label] = spec
    return specs


@dataclass(frozen=True)
class _Ctrl:
    label: str
    kind: ControllerKind | None  # None: unknown
    fou: float
    spec: ControllerSpec | None = None
    tuned: bool = False  # one of the study's tuned fuzzy controllers (StudyResult.tuned)


_FLC, _IT2, _T1M, _PD = (ControllerKind.FLC, ControllerKind.IT2, ControllerKind.T1_MATCHED,
                         ControllerKind.PD)
_T1S = ControllerKind.T1_SLOPE_MATCHED
#: The paper's fuzzy controllers and their type-1 baselines: the sets of docs/model.md (or,
#: slope-matched, their dead zone 0.2 - w/2 and slope; docs/model.md, fair baselines).
_PAPER_FUZZY = (_FLC, _IT2, _T1M, _T1S)
#: The type-1 baselines matched to the IT2FLC of the same width.
_MATCHED = (_T1M, _T1S)
#: Kinds whose ``fou`` names the IT2FLC they belong to (the matched type-1 baselines).
_FOU_KINDS = (_IT2, _T1M, _T1S)


def _kind_of(value: Any) -> ControllerKind | None:
    if isinstance(value, ControllerKind):
        return value
    try:
        return ControllerKind(str(value))
    except ValueError:
        return None


def _controller_table(result: StudyResult) -> dict[str, _Ctrl]:
    """Label -> identity, from the controllers' specs and the metrics table's ``kind`` and
    ``fou`` columns (labels are names only: nothing is inferred from their text)."""
    table: dict[str, _Ctrl] = {}
    rows = result.rows
    labels = np.asarray(rows["controller"]).astype(str)
    _, first = np.unique(labels, return_index=True)
    for i in sorted(first):
        table[labels[i]] = _Ctrl(labels[i], _kind_of(rows["kind"][i]), float(rows["fou"][i]))
    tuned = {s.label for s in result.tuned.values()}
    for label, spec in controller_specs(result).items():
        fou = spec.fou if spec.kind in _FOU_KINDS else 0.0
        table[label] = _Ctrl(label, spec.kind, fou, spec, tuned=label in tuned)
    return table


def _info(ctrls: Mapping[str, _Ctrl], label: str) -> _Ctrl:
    return ctrls.get(label) or _Ctrl(label, None, 0.0)


def _trace_info(result: StudyResult, i: int) -> _Ctrl:
    """Identity of the controller of trace run ``i`` (from ``trace_specs``)."""
    spec = result.trace_specs[i]
    return _Ctrl(result.trace_controllers[i], spec.kind,
                 spec.fou if spec.kind in _FOU_KINDS else 0.0, spec)


def _surface_info(result: StudyResult, ctrls: Mapping[str, _Ctrl], label: str) -> _Ctrl:
    """Identity of the controller behind a stored surface: its ``surface_specs`` entry first."""
    spec = result.surface_specs.get(label)
    if spec is None:
        return _info(ctrls, label)
    return _Ctrl(label, spec.kind, spec.fou if spec.kind in _FOU_KINDS else 0.0, spec)


def _order_key(c: _Ctrl) -> tuple[int, int, float, str]:
    """Report order: the paper's controllers and their type-1 baselines, the tuned fuzzy
    controllers, the PD, then anything else; by kind and FoU width within each."""
    rank = {_FLC: 0, _IT2: 1, _T1M: 2, _T1S: 3, _PD: 4}.get(c.kind, 5) if c.kind else 5
    group = 1 if c.tuned else {4: 2, 5: 3}.get(rank, 0)
    return group, rank, c.fou, c.label


# ---------------------------------------------------------------------------------------------
# Summary access
# ---------------------------------------------------------------------------------------------


class _Summary:
    """Index of the summary rows by (experiment, trajectory, controller, noise_std, metric)."""

    def __init__(self, summary: Sequence[Mapping[str, Any]]) -> None:
        self.rows: dict[tuple[str, str, str, float, str], Mapping[str, Any]] = {}
        for r in summary:
            key = (
                str(r["experiment"]), str(r["trajectory"]), str(r["controller"]),
                float(r["noise_std"]), str(r["metric"]),
            )  # fmt: skip
            self.rows[key] = r

    def controllers(self, experiment: str) -> list[str]:
        seen: dict[str, None] = {}
        for e, _, c, _, _ in self.rows:
            if e == experiment:
                seen.setdefault(c)
        return list(seen)

    def levels(self, experiment: str) -> list[float]:
        return sorted({s for e, _, _, s, _ in self.rows if e == experiment})

    def get(self, experiment: str, traj: str, ctrl: str, sigma: float,
            metric: str) -> Mapping[str, Any] | None:
        return self.rows.get((experiment, traj, ctrl, float(sigma), metric))

    def has(self, experiment: str) -> bool:
        return any(k[0] == experiment for k in self.rows)


def _num(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def _trace_index(result: StudyResult, kind: ControllerKind,
                 fou: float | None = None) -> int | None:
    """Run index in the traces of the first traced controller of ``kind`` (and width ``fou``)."""
    for i, spec in enumerate(result.trace_specs):
        if spec.kind is kind and (fou is None or math.isclose(spec.fou, fou, abs_tol=1e-12)):
            return i
    return None


# ---------------------------------------------------------------------------------------------
# Fuzzy controllers: dead zone, input gains, surfaces
# ---------------------------------------------------------------------------------------------


def _dead_zone(c: _Ctrl) -> float | None:
    """Half-width of the dead zone of the paper's fuzzy controllers in the fuzzy system's input
    units (``Ke e``, ``Kde de``): only the Z sets fire while both inputs are below it."""
    if c.kind in _PAPER_FUZZY:
        return 0.2 - c.fou / 2.0
    return None


def _input_gains(specs: Iterable[ControllerSpec | None]) -> tuple[float, float] | None:
    """The (Ke, Kde) shared by every fuzzy controller among ``specs`` (None if they differ)."""
    gains = {(s.ke, s.kde) for s in specs if s is not None and s.kind is not _PD}
    return next(iter(gains)) if len(gains) == 1 else None


def surface_limit(result: StudyResult) -> float:
    """The largest ``|u|`` over the stored control surfaces, V (the paper's rules: 12)."""
    return max((float(np.max(np.abs(u))) for _, _, u in result.surfaces.values()), default=0.0)

"""The physics check's outputs: ``physics_verdicts.csv``, ``physics_metrics.csv``, the
side-by-side animation and the claims.md section (the page's is :mod:`.html.physics`).

:class:`PhysicsOutcome` carries what ``it2track reproduce`` found -- the check's result, or
why it was skipped -- to every writer. Every number is taken from the result.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..experiments.physics import (
    PHYSICS_COLUMNS,
    PhysicsCheck,
    PhysicsResult,
    physics_traces,
    survival,
)
from .outputs import write_rows_csv

__all__ = ["GIF_NAME", "INSTALL", "METRICS_NAME", "VERDICTS_NAME", "PhysicsOutcome",
           "counts_markdown", "physics_markdown", "survivor_counts", "survivors_text",
           "write_physics_files"]

VERDICTS_NAME = "physics_verdicts.csv"
METRICS_NAME = "physics_metrics.csv"
GIF_NAME = "physics_tracking.gif"
#: How to get the MuJoCo robot.
INSTALL = "pip install 'it2track[mujoco]'"


@dataclass
class PhysicsOutcome:
    """The physics check of one ``reproduce`` run.

    Attributes
    ----------
    result : PhysicsResult or None
        None when skipped.
    reason : str
        Why it was skipped ("" when it ran).
    survival : list of dict
        :func:`~it2track.experiments.physics.survival` against the kinematic verdicts.
    gif : Path or None
        The animation, when written.
    seconds : float
        Wall time of the check, s.
    smoke : bool
        Run with ``--quick`` (3 s runs, tiny design): not evidence.
    cached : int
        Rounds read back from the cache of an interrupted run instead of simulated.
    """

    result: PhysicsResult | None = None
    reason: str = ""
    survival: list[dict[str, Any]] = field(default_factory=list)
    gif: Path | None = None
    seconds: float = 0.0
    smoke: bool = False
    cached: int = 0

    @classmethod
    def skipped(cls, reason: str) -> PhysicsOutcome:
        """Not run, because ``reason``."""
        return cls(reason=reason)

    def provenance(self) -> dict[str, Any]:
        """For the manifest."""
        if self.result is None:
            return {"status": "skipped", "reason": self.reason}
        return {"status": "run", "check": self.result.check.to_dict(),
                "design": self.result.design.to_dict(), "runs": self.result.runs,
                "seconds": round(self.seconds, 3), "smoke": self.smoke,
                "rounds_from_cache": self.cached}


def write_physics_files(folder: Path, outcome: PhysicsOutcome, config: Any,
                        kinematic: Sequence[Mapping[str, Any]], *, frames: int = 60) -> None:
    """Write the CSVs and the animation of a check that ran into ``folder``, and fill in
    ``outcome.survival`` and ``outcome.gif``."""
    from ..tracking import METRIC_NAMES
    from .outputs import write_metrics_csv

    result = outcome.result
    if result is None:
        return
    rows = result.verdict_rows()
    write_rows_csv(folder / VERDICTS_NAME, [{k: r[k] for k in PHYSICS_COLUMNS} for r in rows])
    table = result.rows()
    from ..experiments.study import ROW_KEYS

    write_metrics_csv(folder / METRICS_NAME, table, ["surface", "mu", *ROW_KEYS,
                                                     *METRIC_NAMES])
    outcome.survival = survival(kinematic, result)
    panels = physics_traces(config, result.check)
    # drawn by a worker process, as every figure: the main process imports no matplotlib
    from concurrent.futures import ProcessPoolExecutor

    from .render import _context

    with ProcessPoolExecutor(1, mp_context=_context()) as pool:
        outcome.gif = pool.submit(_draw_gif, panels, folder / GIF_NAME, frames).result()


def _draw_gif(panels: Sequence[tuple[str, Any, tuple[str, ...]]], path: Path,
              frames: int) -> Path:
    """Worker job: the animation of :func:`~it2track.experiments.physics.physics_traces`."""
    from .animation import AnimationPanel, tracking_gif

    return tracking_gif([AnimationPanel(*p) for p in panels], path, frames=frames)


def _resumed(outcome: PhysicsOutcome) -> str:
    if not outcome.cached:
        return ""
    return (f" (resumed: {outcome.cached} round(s) read back from an interrupted run's "
            "cache)")


def _status(row: Mapping[str, Any], key: str) -> str:
    status = str(row.get(key, ""))
    if not status:
        return "—"
    settled = row.get(f"{key}_settled") if key != "kinematic" else row["kinematic_settled"]
    return status if settled else f"*{status}*"


def physics_markdown(outcome: PhysicsOutcome, check: PhysicsCheck | None = None) -> str:
    """claims.md's section: which kinematic verdicts survive on each surface, or why the
    check was skipped."""
    head = "## Physics check: the claims on the MuJoCo robot"
    if outcome.result is None:
        return (f"{head}\n\nSkipped ({outcome.reason}). With the MuJoCo extra installed "
                f"(`{INSTALL}`), `it2track reproduce` re-judges the claims on a physical robot "
                "(masses, inertias, tyre friction, wheel slip) on dry, wet and icy ground.\n")
    r = outcome.result
    d = r.design
    names = [s.surface for s in r.surfaces]
    mus = ", ".join(f"{s.surface} μ = {s.mu:g}" for s in r.surfaces)
    noisy = [n for s in r.surfaces for k, n in s.settled.n.items() if k[2] > 0.0]
    lines = [head, ""]
    if outcome.smoke:
        lines += ["**Smoke run — not evidence** (`--quick`: 3 s runs, a tiny design).", ""]
    lines += [
        f"The noise experiment run again with the robot simulated in MuJoCo "
        f"(`it2track.plant.mujoco_plant`; chassis and wheel masses, tyre-ground friction, "
        f"wheel slip) on each surface ({mus}), with the same controllers the claims compare "
        f"({', '.join(r.controllers)}), paths, noise levels, duration and period, judged by "
        f"the same rules and the same sequential design with fewer realisations: "
        f"{d.first} per controller, path and σ first, up to {d.batch} more per round while "
        f"a level is unsettled, at most {d.cap} (this run: {min(noisy)}–{max(noisy)}); "
        f"replication target {d.target:g}, {d.resamples} bootstrap resamples. "
        f"{r.runs} simulations{_resumed(outcome)} (their time: `manifest.json`). Every level: "
        f"`physics_verdicts.csv`; every run: `physics_metrics.csv`.",
        "",
        "All paths together, noisy levels: the kinematic robot's status beside each "
        "surface's (replication probability, realisations). Italics: unsettled (no "
        "verdict); ✓: settled on both robots with the same status.",
        "",
        "| claim | σ | kinematic | " + " | ".join(names) + " |",
        "|---|---|---|" + "---|" * len(names),
    ]
    for row in outcome.survival:
        cells = []
        for s in names:
            if s not in row:
                cells.append("—")
                continue
            mark = " ✓" if row[f"{s}_same"] else ""
            cells.append(f"{_status(row, s)} {row[f'{s}_replication']:.2f} "
                         f"(n {row[f'{s}_n']}){mark}")
        lines.append(f"| {row['claim']} | {row['sigma']:g} | {_status(row, 'kinematic')} | "
                     + " | ".join(cells) + " |")
    lines += ["", survivors_text(outcome.survival, names), "",
              *counts_markdown(outcome.survival, names), ""]
    return "\n".join(lines)


def survivor_counts(rows: Sequence[Mapping[str, Any]],
                    names: Sequence[str]) -> list[dict[str, Any]]:
    """Per claim, over its noisy levels settled on the kinematic robot (``levels``): per
    surface how many are settled there with the same status (``same``), settled with another
    (``different``) and unsettled there (``unsettled``)."""
    out: dict[str, dict[str, Any]] = {}
    for row in rows:
        if not row["kinematic_settled"]:
            continue
        c = out.setdefault(str(row["claim"]), {
            "claim": str(row["claim"]), "levels": 0,
            **{s: {"same": 0, "different": 0, "unsettled": 0} for s in names}})
        c["levels"] += 1
        for s in names:
            if s not in row:
                continue
            if not row[f"{s}_settled"]:
                c[s]["unsettled"] += 1
            elif row[f"{s}_same"]:
                c[s]["same"] += 1
            else:
                c[s]["different"] += 1
    return list(out.values())


def survivors_text(rows: Sequence[Mapping[str, Any]], names: Sequence[str]) -> str:
    """Per surface, the claims whose every kinematically settled noisy level is settled with
    the same status on that surface, and those with a level settled the other way."""
    counts = survivor_counts(rows, names)
    parts = []
    for s in names:
        keep = [c["claim"] for c in counts if c[s]["same"] == c["levels"]]
        other = [c["claim"] for c in counts if c[s]["different"]]
        parts.append(f"**{s}**: every level as on the kinematic robot: "
                     f"{', '.join(keep) or 'none'}; some level settled otherwise: "
                     f"{', '.join(other) or 'none'}.")
    return ("By surface, over the levels settled on the kinematic robot (the table below "
            "counts them): " + " ".join(parts))


def counts_markdown(rows: Sequence[Mapping[str, Any]], names: Sequence[str]) -> list[str]:
    """The table of :func:`survivor_counts`."""
    lines = ["| claim | levels settled on the kinematic robot | "
             + " | ".join(f"{s}: same / other / unsettled" for s in names) + " |",
             "|---|---|" + "---|" * len(names)]
    for c in survivor_counts(rows, names):
        lines.append(f"| {c['claim']} | {c['levels']} | " + " | ".join(
            f"{c[s]['same']} / {c[s]['different']} / {c[s]['unsettled']}" for s in names)
            + " |")
    return lines

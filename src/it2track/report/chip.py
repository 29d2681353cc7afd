"""The verdicts on the chip in the outputs: ``chip_verdicts.csv``, the claims.md section and
the data of the page's section (:mod:`it2track.report.html.chip`), all from a
:class:`~it2track.experiments.chip.ChipResult`, or the reason it was not run."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..experiments.chip import CHIP_CLAIMS, ChipResult, survival
from .claims_md import SMOKE
from .outputs import write_rows_csv

__all__ = ["CHIP_CSV", "ChipOutcome", "chip_markdown", "chip_summary", "replay_sentence",
           "write_chip_csv"]

#: The file of the chip's verdicts.
CHIP_CSV = "chip_verdicts.csv"


@dataclass(frozen=True)
class ChipOutcome:
    """The chip experiment as the outputs see it: its result, or why there is none.

    Attributes
    ----------
    result : ChipResult or None
    reason : str
        Why it did not run (empty when it ran).
    smoke : bool
        A ``--quick`` run's tiny version.
    """

    result: ChipResult | None
    reason: str = ""
    smoke: bool = False


def write_chip_csv(path: Path, result: ChipResult) -> Path:
    """``chip_verdicts.csv``: one row per reducer x claim x path (and all) x noise level
    (:data:`~it2track.experiments.chip.CHIP_COLUMNS`)."""
    return write_rows_csv(path, result.rows)


def _pct(x: float) -> str:
    return f"{100 * x:.1f} %"


def _levels_text(levels: Sequence[tuple[float, str, str, Any]]) -> str:
    """``σ 0.02: holds → not shown (0.612)`` per level (the chip's replication probability,
    3 decimals: 0.949 must not read as the target 0.95)."""
    return ", ".join(f"σ {sig:g}: {a} → {b} ({float(rep):.3f})" if rep != ""
                     else f"σ {sig:g}: {a} → {b}" for sig, a, b, rep in levels) or "none"


def chip_summary(result: ChipResult) -> dict[str, Any]:
    """What the section says, computed from the result: per reducer, the claims' settled
    levels that keep the study's status, the latency's cost and the replay's match."""
    surv = survival(result.rows)
    per: dict[str, Any] = {}
    for s in surv:
        per.setdefault(s["reducer"], []).append(s)
    costs = {c["reducer"]: c for c in result.costs}
    replays: dict[str, list[dict[str, Any]]] = {}
    for r in result.replay:
        replays.setdefault(r["reducer"], []).append(r)
    reducers = []
    for reducer, claims in per.items():
        c = costs[reducer]
        mine = replays.get(reducer, [])
        reducers.append({
            "reducer": reducer,
            "claims": [{
                "claim": s["claim"], "kept": s["kept"], "judged": s["host_settled"],
                "changed": _levels_text(s["changed"]), "open": _levels_text(s["open"]),
                "levels": ", ".join(f"σ {sig:g} {st}{'' if settled else ' (unsettled)'}"
                                    for sig, st, settled, _ in s["levels"]),
            } for s in claims],
            "cycles_max": f"{c['cycles_max']:,}", "cycles_mean": f"{c['cycles_mean']:,.0f}",
            "latency_max_ms": f"{c['latency_max_ms']:.3f}",
            "share_max": _pct(c["period_share_max"]), "share_mean": _pct(c["period_share_mean"]),
            "grid": c["grid"],
            "run_cycles_max": "—" if not mine else f"{c['run_cycles_max']:,}",
            "run_cycles_mean": "—" if not mine else f"{c['run_cycles_mean']:,.0f}",
            "replays": len(mine),
            "replay_equal": sum(r["outputs_equal"] for r in mine),
            "replay_steps": sum(r["steps"] for r in mine),
            "replay_cycles_diff": max((r["cycles_max_diff"] for r in mine), default=0),
            "replay_metric_diff": max((r["metric_max_rel_diff"] for r in mine), default=0.0),
        })
    return {"reducers": reducers, "matches": result.matches,
            "ts_ms": f"{1e3 * result.ts:g}", "design": result.design,
            "levels": ", ".join(f"{s:g}" for s in result.levels),
            "seconds": result.seconds, "claims": ", ".join(CHIP_CLAIMS)}


def chip_markdown(outcome: ChipOutcome | None) -> str:
    """claims.md's section "The verdicts on the chip" (empty for ``None``: not asked)."""
    if outcome is None:
        return ""
    head = "## The verdicts on the chip (ATmega328P, float32, measured latency)"
    if outcome.result is None:
        return f"{head}\n\nNot run: {outcome.reason}.\n"
    s = chip_summary(outcome.result)
    d = s["design"]
    lines = [head + (f" ({SMOKE})" if outcome.smoke else ""), "",
             f"{s['claims']} judged again with every compared controller as the simulated "
             "ATmega328P runs it: the generated C in float32, its output applied after the "
             f"call's cycles at 16 MHz (control period {s['ts_ms']} ms), for each type reducer "
             f"of the IT2FLCs, at σ = {s['levels']}; realisations by need from {d.first} to at "
             f"most {d.cap} per controller, path and σ, replication target {d.target:g} "
             "(chip_verdicts.csv gives every level with the study's status beside it). The "
             "runs use the host-compiled float C with the cycles simavr measured on a "
             "grid of the inputs (nearest point); a sample is replayed on simavr step for step.",
             "", "A settled study level *keeps its status* when the chip settles it with the same "
             "status; *changed*: settled on the chip with another; *unsettled on the chip*: "
             "its replication probability stays below the target at the chip's cap (study "
             "status → chip status, the chip's replication probability).", "",
             "| reducer | claim | settled study levels that keep their status | changed "
             "| unsettled on the chip | chip statuses (all paths) |", "|---|---|---|---|---|---|"]
    for r in s["reducers"]:
        for c in r["claims"]:
            lines.append(f"| {r['reducer']} | {c['claim']} | {c['kept']} of {c['judged']} | "
                         f"{c['changed']} | {c['open']} | {c['levels']} |")
    lines += ["", "What each reducer's latency costs (the main IT2FLC; worst and mean cycles "
              "over the latency table's input grid, and over the replayed runs' steps):", "",
              "| reducer | worst cycles | mean cycles | worst latency | worst / period "
              "| mean / period | replayed steps: worst, mean cycles |",
              "|---|---|---|---|---|---|---|"]
    for r in s["reducers"]:
        lines.append(f"| {r['reducer']} | {r['cycles_max']} | {r['cycles_mean']} | "
                     f"{r['latency_max_ms']} ms | {r['share_max']} | {r['share_mean']} | "
                     f"{r['run_cycles_max']}, {r['run_cycles_mean']} |")
    lines += ["", replay_sentence(s), ""]
    return "\n".join(lines)


def replay_sentence(s: dict[str, Any]) -> str:
    """The replay's sentence (match or not, cycles, metrics) from :func:`chip_summary`."""
    rows: Sequence[dict[str, Any]] = s["reducers"]
    n = sum(r["replays"] for r in rows)
    if not n:
        return "No run was replayed on simavr (replay = 0)."
    steps = sum(r["replay_steps"] for r in rows)
    equal = sum(r["replay_equal"] for r in rows)
    verdict = ("match: every output equals the simulated MCU's bit for bit" if s["matches"]
               else "**NO MATCH: some outputs differ from the simulated MCU's**")
    cyc = max(r["replay_cycles_diff"] for r in rows)
    met = max(r["replay_metric_diff"] for r in rows)
    return (f"Replay on simavr: {n} runs ({steps:,} steps), {equal} of {n} with every step's "
            f"output equal — {verdict}. The tabled cycles differ from the MCU's at the same "
            f"inputs by at most {cyc:,} cycles; the same runs closed through the MCU "
            f"itself (latency measured) differ in IAE, ITAE, ISE and ITSE by at most "
            f"{_pct(met)}.")

"""Plain-text outputs of the study: metrics.csv, summary.csv, robustness.csv, sensitivity.csv,
claims.md, manifest.json.

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
    "claims_preamble",
    "manifest",
    "study_sections",
    "write_claims_md",
    "write_metrics_csv",
    "write_robustness_csv",
    "write_sensitivity_csv",
    "write_summary_csv",
]

#: Where the modelling decisions are documented (cited by claims.md and the report).
MODEL_DOC = "docs/model.md"


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


def write_claims_md(path: Path, claims: Sequence[Any], *, preamble: str,
                    sections: str = "") -> Path:
    """``claims.md``: a verdict table, then each claim with its criterion and evidence, then
    ``sections`` (e.g. :func:`study_sections`: robustness, tuned baselines, ...)."""
    lines = [preamble.rstrip(), "", "| claim | statement | verdict |", "|---|---|---|"]
    for c in claims:
        detail = f" ({c.detail})" if getattr(c, "detail", "") else ""
        lines.append(f"| {c.id} | {c.statement} | **{c.verdict}**{detail} |")
    lines.append("")
    if sections:
        lines.append(sections.rstrip())
        lines.append("")
    for c in claims:
        lines.append(c.to_markdown())
    return atomic_write_text(path, "\n".join(lines) + "\n")


def claims_preamble(config: Any) -> str:
    """The opening of claims.md: what was run and how a verdict is reached."""
    levels = ", ".join(f"{s:g}" for s in config.noise_levels)
    return (
        "# Claims of the paper, tested\n\n"
        "Computed by `it2track reproduce` from the `noise` experiment: "
        f"{config.sweep_seeds} noise realisations per cell (common random numbers across "
        f"controllers), noise levels sigma = {levels} rad, trajectories "
        f"{', '.join(config.trajectories)}, {config.loop.duration:g} s at "
        f"{1 / config.loop.ts:g} Hz. The modelling choices behind these runs, and the "
        f"alternatives tried below, are documented in `{MODEL_DOC}`.\n\n"
        "A comparison cell (noise level x trajectory x metric x compared pair) *supports* a "
        "claim when the 95 % Student-t interval of the paired per-seed difference lies on the "
        "claimed side of zero; a level *holds* when every cell supports the claim (an "
        "intersection-union test: no multiplicity correction is needed). A cell *contradicts* "
        "the claim when the one-sided paired t test of the opposite direction rejects at "
        "family-wise level 0.025 after the Holm-Bonferroni correction over all the claim's "
        "noisy cells (`p_holm` below); a level is contradicted when any cell contradicts it, "
        "and *not shown* otherwise. Without noise (sigma = 0) a cell is one deterministic run "
        "(n = 1): it is reported as *deterministic* with the exact sign of the difference, "
        "never with an interval, and the verdicts are over the noisy levels. C3 is symmetric: "
        "the interval must lie inside the band [0.003/sqrt(10), 0.003 sqrt(10)] to support it "
        "and wholly outside it to contradict it. Every verdict below is computed from the data "
        "in metrics.csv (robustness: robustness.csv)."
    )


def _f(v: Any, digits: int = 3) -> str:
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def study_sections(result: Any, claims: Sequence[Any]) -> str:
    """claims.md sections beyond the paper's claims: per-trajectory verdicts, C3's sigma
    range, the single-realisation probability of the paper's ordering, tuned-vs-tuned
    baselines, and the robustness to the open modelling choices."""
    from ..experiments.analysis import c3_sigma_range

    out: list[str] = []
    by_id = {c.id: c for c in claims}
    out += ["## Verdicts per trajectory", "",
            "The same cells, judged one trajectory at a time (C3 concerns the straight line "
            "only).", "",
            "| claim | " + " | ".join(result.config.trajectories) + " |",
            "|---|" + "---|" * len(result.config.trajectories)]
    for c in claims:
        if c.per_trajectory:
            out.append(f"| {c.id} | " + " | ".join(
                c.per_trajectory[t]["verdict"] for t in result.config.trajectories) + " |")
    out.append("")
    c3 = by_id.get("C3")
    if c3 is not None and c3.evidence:
        rng = c3_sigma_range(c3)
        lo, hi = rng["band"]
        out += ["## C3 as what it is: the noise range that gives ISE ~ 0.003", ""]
        text = (f"The smallest straight-line ISE lies in the band [{lo:.2g}, {hi:.2g}] at the "
                "levels sigma = " + (", ".join(f"{s:g}" for s in rng["levels_in_band"])
                                     or "(none)") + " rad.")
        for key, what in (("enters", "enters"), ("leaves", "leaves")):
            cross = rng[key]
            if cross is not None:
                a, b = cross["range"]
                span = (f" (from the interval bounds: {_f(a)} to {_f(b)})"
                        if a is not None and b is not None else "")
                text += (f" Interpolating between levels (log-log; linearly from an ISE of 0), "
                         f"the mean {what} the band at sigma = {_f(cross['sigma'])} rad{span}.")
        out += [text, ""]
    if result.ordering:
        out += ["## How likely were the paper's single-run figures?", "",
                "Probability that one noise realisation shows the paper's strict ordering "
                "FLC > FoU 0.1 > 0.2 > 0.3 on all four integrals (`all`: on every trajectory "
                "at once, as the paper's figures do), with exact (Clopper-Pearson) 95 % "
                "intervals; sigma = 0 is one deterministic run.", "",
                "| sigma | trajectory | k / n | p | 95 % interval |", "|---|---|---|---|---|"]
        for r in result.ordering:
            iv = "deterministic" if r["deterministic"] else (
                f"[{_f(r['ci_low'])}, {_f(r['ci_high'])}]")
            out.append(f"| {r['sigma']:g} | {r['trajectory']} | {r['k']} / {r['n']} | "
                       f"{_f(r['p'])} | {iv} |")
        out.append("")
    if result.tuned:
        out += ["## Tuned against tuned", "",
                "Each fuzzy controller tuned like the PD baseline (same tuning realisations, "
                "same number of candidates, same effort limit; Ke, Kde and an output gain "
                "scaling the consequents): the claims judged on the tuned controllers at "
                f"sigma = {result.config.noise_std:g} rad ({result.config.seeds} realisations; "
                "`paper` experiment). The untuned paper controllers stay beside them in "
                "summary.csv.", "",
                "| controller | Ke | Kde | output gain | tuning ISE (untuned) | effort (limit) "
                "| on grid edge |", "|---|---|---|---|---|---|---|"]
        for label, rec in result.tuning.items():
            un = rec["untuned"]
            out.append(
                f"| {label} | {rec['ke']:g} | {rec['kde']:g} | {rec['gain']:g} | "
                f"{_f(rec['objective'])} ({_f(un['ise'])}) | {_f(rec['effort'])} "
                f"({_f(rec['effort_limit'])}) | {'yes' if rec['on_grid_edge'] else 'no'} |")
        if result.pd is not None and result.pd_tuning.get("objective") is not None:
            out.append(f"| {result.pd.label} | kp {result.pd.kp:g} | kd {result.pd.kd:g} | - "
                       f"| {_f(result.pd_tuning['objective'])} | "
                       f"{_f(result.pd_tuning['effort'])} | "
                       f"{'yes' if result.pd_tuning['on_grid_edge'] else 'no'} |")
        out.append("")
        if result.tuned_claims:
            out += ["| claim (tuned controllers) | verdict |", "|---|---|"]
            for c in result.tuned_claims:
                detail = f" ({c.detail})" if c.detail else ""
                out.append(f"| {c.id} | {c.verdict}{detail} |")
            out.append("")
    if result.robustness is not None:
        out += robustness_markdown(result.robustness, result.config)
    return "\n".join(out)


def robustness_markdown(rob: Any, config: Any) -> list[str]:
    """The robustness section of claims.md."""
    levels = ", ".join(f"{s:g}" for s in rob.config.noise_levels)
    out = [
        "## Robustness to the paper's open modelling choices", "",
        f"Every claim re-judged under each alternative of each open choice ({MODEL_DOC}), one "
        f"at a time, at sigma = {levels} rad with {rob.config.seeds} realisations per cell, "
        "with the same rules as above. A variant leaves a claim *unchanged* (the same status "
        "at every level as the paper-faithful baseline judged the same way), *changes* it (a "
        "level moves to or from 'not shown') or *flips* it (a level goes from holds to "
        "contradicted or back). A noise reading is judged at its own sigma and compared with "
        f"the baseline at sigma = {config.noise_std:g} rad. Cell by cell: robustness.csv.", "",
    ]
    out += ["| choice | sets | default | alternatives | what is open | docs/model.md |",
            "|---|---|---|---|---|---|"]
    for c in rob.config.choices:
        out.append(f"| {c.name} | {', '.join(c.sets)} | {c.label(c.default)} | "
                   + "; ".join(c.label(a) for a in c.alternatives)
                   + f" | {c.description} | #{c.doc} |")
    out.append("")
    for cid, groups in rob.flips.items():
        base = next((v for v in rob.verdicts if v["claim"] == cid and v["part"] == "baseline"),
                    None)
        if base is None:
            continue
        out.append(f"- **{cid}** (baseline: {base['verdict']}). "
                   + ". ".join(f"{k.capitalize()} by: " + ("; ".join(groups[k]) or "none")
                               for k in ("flipped", "changed"))
                   + ". Unchanged under: " + ("; ".join(groups["unchanged"]) or "none") + ".")
    out.append("")
    claims = list(dict.fromkeys(v["claim"] for v in rob.verdicts))
    mark = {"unchanged": "", "changed": " (changed)", "flipped": " (**flipped**)"}
    out += ["| choice | value | " + " | ".join(claims) + " |",
            "|---|---|" + "---|" * len(claims)]
    table: dict[tuple[str, str], dict[str, str]] = {}
    for v in rob.verdicts:
        table.setdefault((v["choice"], v["value"]), {})[v["claim"]] = (
            v["verdict"] + mark[v["change"]])
    for (choice, value), cells in table.items():
        out.append(f"| {choice} | {value} | " + " | ".join(cells.get(c, "") for c in claims)
                   + " |")
    out.append("")
    if rob.ranking:
        out += ["Choices ranked by the (claim, level) statuses their alternatives move, one "
                "at a time (2 per flip, 1 per change): " + ", ".join(
                    f"{r['choice']} ({r['score']})" for r in rob.ranking) + ".", ""]
    if rob.config.factorial:
        out += [f"The factorial crosses {' x '.join(rob.config.factorial)} (every combination "
                "with two or more alternatives; rows with ' x ' above).", ""]
    if rob.sensitivity_ranking:
        sens = rob.config.sensitivity
        out += ["### Global sensitivity (Morris screening, SALib)", "",
                f"{rob.sensitivity_points} design points ({sens.trajectories} Morris "
                f"trajectories over {len(sens.factors)} factors, {sens.num_levels} levels "
                f"each, {sens.seeds} realisations per point). Outputs: the paired mean ISE "
                "differences per trajectory (sensitivity.csv). Ranking by the mean over "
                "outputs of mu* / max mu*:", "",
                "| rank | factor | levels | score |", "|---|---|---|---|"]
        levels_of = {f.name: f.levels for f in sens.factors}
        for r in rob.sensitivity_ranking:
            lv = ", ".join(f"{x:g}" for x in levels_of[r["factor"]])
            out.append(f"| {r['rank']} | {r['factor']} | {lv} | {r['score']:.2f} |")
        out.append("")
    return out


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

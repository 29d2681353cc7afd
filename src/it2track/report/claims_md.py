"""``claims.md``: the verdicts, every level with its replication probability, and the study's
sections beyond the paper (per path, C3's noise range, single-realisation probabilities,
surfaces compared, tuned baselines, robustness with the baseline's seed spread).

Every number is taken from the data the section describes; nothing is typed by hand.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..atomicfile import atomic_write_text
from ..experiments.judgement import levels_text
from ..experiments.stats import interval_text
from .counts import count_text

__all__ = [
    "MODEL_DOC",
    "SMOKE",
    "claims_preamble",
    "levels_markdown",
    "robustness_markdown",
    "study_sections",
    "surfaces_markdown",
    "write_claims_md",
]

#: Where the modelling decisions are documented (cited by claims.md and the report).
MODEL_DOC = "docs/model.md"
#: How a ``--quick`` run marks every verdict it prints.
SMOKE = "smoke run — not evidence"


def _f(v: Any, digits: int = 3) -> str:
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def write_claims_md(path: Path, claims: Sequence[Any], *, preamble: str, sections: str = "",
                    levels: str = "", smoke: bool = False) -> Path:
    """``claims.md``: a verdict table, every level's status and replication probability
    (``levels``, :func:`levels_markdown`), ``sections`` (:func:`study_sections`), then each
    claim with its criterion and evidence. ``smoke``: a ``--quick`` run, marked as such above
    the verdicts."""
    lines = [preamble.rstrip(), ""]
    title = "| claim | statement | verdict |"
    if smoke:
        lines += [f"**{SMOKE.capitalize()}** (`--quick`: few realisations of short runs; "
                  "the verdicts below only show that every part of the study runs).", ""]
        title = f"| claim | statement | verdict ({SMOKE}) |"
    lines += [title, "|---|---|---|"]
    for c in claims:
        detail = f" ({c.detail})" if getattr(c, "detail", "") else ""
        lines.append(f"| {c.id} | {c.statement} | **{c.verdict}**{detail} |")
    lines.append("")
    if levels:
        lines += [levels.rstrip(), ""]
    if sections:
        lines += [sections.rstrip(), ""]
    for c in claims:
        lines.append(c.to_markdown())
    return atomic_write_text(path, "\n".join(lines) + "\n")


def claims_preamble(config: Any, *,
                    seeds: Mapping[tuple[str, str, float], int] | None = None,
                    smoke: bool = False) -> str:
    """The opening of claims.md: what was run and how a verdict is reached; ``seeds``: the
    realisations each (controller, path, sigma) got (the sequential design's outcome)."""
    design = getattr(config, "verdicts", None)
    levels = levels_text(config.noise_levels)
    noisy = [n for key, n in (seeds or {}).items() if key[-1] > 0.0]
    if design is not None:
        how = (f"noise realisations by need: every controller, path and σ starts with "
               f"{design.first} (common random numbers across controllers); while a level's "
               f"status is unsettled, the controllers it compares on its paths get up to "
               f"{design.batch} more per round, at most {design.cap}; this run used "
               f"{count_text(noisy) if noisy else design.first} per controller, path and σ "
               "(verdicts.csv gives each level's)")
    else:
        how = (f"{count_text(noisy) if noisy else config.sweep_seeds} noise realisations per "
               "cell (common random numbers across controllers)")
    target = getattr(design, "target", 0.95)
    resamples = getattr(design, "resamples", 1000)
    head = "# Claims of the paper, tested" + (f" ({SMOKE})" if smoke else "")
    return (
        f"{head}\n\n"
        f"Computed by `it2track reproduce` from the `noise` experiment: {how}; noise levels "
        f"{levels}, trajectories {', '.join(config.trajectories)}, "
        f"{config.loop.duration:g} s at {1 / config.loop.ts:g} Hz. The modelling choices "
        f"behind these runs, and the alternatives tried below, are documented in "
        f"`{MODEL_DOC}`.\n\n"
        "A comparison cell (noise level × trajectory × metric × compared pair) *supports* a "
        "claim when the 95 % Student-t interval of the paired per-seed difference lies on the "
        "claimed side of zero; a level *holds* when every cell supports the claim (an "
        "intersection-union test: no multiplicity correction is needed). A cell *contradicts* "
        "the claim when the one-sided paired t test of the opposite direction rejects at "
        "family-wise level 0.025 after the Holm-Bonferroni correction over all the claim's "
        "noisy cells (`p_holm` below); a level is contradicted when any cell contradicts it, "
        "and *not shown* otherwise. Without noise (σ = 0) a cell is one deterministic run "
        "(n = 1): it is reported as *deterministic* with the exact sign of the difference, "
        "never with an interval, and the verdicts are over the noisy levels. C3 and D3 are "
        "symmetric: the interval must lie inside the band (C3: [0.003/√10, 0.003·√10]; D3: "
        "±1 % of the IT2FLC's mean) to support them and wholly outside it to contradict them.\n\n"
        "Every level's status has a *replication probability*: the probability that an "
        "independent seed set of the same size gives the same status, estimated by the "
        f"bootstrap ({resamples} resamples of the seeds, the whole claim re-judged on each; "
        f"{MODEL_DOC}#seeds-by-need). A level is *settled* when it is at least {target:g}; "
        "the verdicts speak of settled levels only and call the others *unsettled*. Every "
        "verdict below is computed from the data in metrics.csv (levels: verdicts.csv; "
        "robustness: robustness.csv)."
    )


def levels_markdown(claims: Sequence[Any], rows: Sequence[Mapping[str, Any]]) -> str:
    """Every level of every claim (all paths together, then per path): status, replication
    probability and realisations, from ``verdicts.csv``'s rows."""
    if not rows:
        return ""
    out = ["## Every level: status, replication probability, realisations", "",
           "Each cell: the status at that σ, its replication probability and the realisations "
           "behind it; *unsettled* (replication below the target) statuses are in italics and "
           "are no verdict. σ = 0 is one noise-free run (deterministic).", ""]
    by_claim: dict[str, list[Mapping[str, Any]]] = {}
    for r in rows:
        by_claim.setdefault(str(r["claim"]), []).append(r)
    for c in claims:
        mine = by_claim.get(c.id)
        if not mine:
            continue
        sigmas = sorted({float(r["sigma"]) for r in mine})
        paths = list(dict.fromkeys(str(r["path"]) for r in mine))
        out += [f"**{c.id}**", "", "| path | " + " | ".join(f"σ = {s:g}" for s in sigmas)
                + " |", "|---|" + "---|" * len(sigmas)]
        cell = {(str(r["path"]), float(r["sigma"])): r for r in mine}
        for p in paths:
            texts = []
            for s in sigmas:
                lv = cell.get((p, s))
                if lv is None:
                    texts.append("")
                elif lv["status"] == "deterministic":
                    texts.append(f"deterministic ({lv['decisive']})")
                else:
                    status = str(lv["status"]) if lv["settled"] else f"*{lv['status']}*"
                    texts.append(f"{status} {float(lv['replication']):.2f} (n {lv['n']})")
            out.append(f"| {p} | " + " | ".join(texts) + " |")
        out.append("")
    return "\n".join(out)


def surfaces_markdown(result: Any) -> list[str]:
    """The control surfaces compared (RMS differences over the input square, outputs at
    (0.5, 0)), and the surface copy's interpolation error: what D1, D2 and D3 compare."""
    surfaces = getattr(result, "surfaces", {})
    cfg = result.config
    main = f"IT2FLC FoU {cfg.main_fou:g}"
    if main not in surfaces:
        return []
    u_main = surfaces[main][2]
    others = [lb for lb in ("FLC", f"T1 slope-matched {cfg.main_fou:g}",
                            f"T1 dead-zone-matched {cfg.main_fou:g}") if lb in surfaces]
    out = ["## Control surfaces compared", "",
           f"RMS difference from the {main}'s u(e, Δe) over the input square "
           f"({u_main.shape[0]} × {u_main.shape[1]} grid), and the output at e = 0.5, Δe = 0 "
           "(from each controller itself):", "",
           "| controller | RMS difference (V) | u(0.5, 0) (V) |", "|---|---|---|"]
    specs = getattr(result, "surface_specs", {})

    def at(label: str) -> str:
        spec = specs.get(label)
        if spec is None:
            return ""
        c = spec.build()
        u = c.output(np.array([0.5]), np.array([0.0]), c.initial_state(1, 0.01))
        return f"{float(u[0]):.3g}"

    out.append(f"| {main} | 0 | {at(main)} |")
    for lb in others:
        d = surfaces[lb][2] - u_main
        out.append(f"| {lb} | {float(np.sqrt(np.mean(d * d))):.3g} | {at(lb)} |")
    copy = getattr(result, "surface_copy", None)
    if copy:
        out += ["", f"The {copy['label']} (D3) is the {main}'s output tabulated on a "
                f"{copy['grid']} × {copy['grid']} grid and interpolated bilinearly (exactly a "
                "type-1 Sugeno system with one triangular set per node): largest surface error "
                f"{copy['max']:.2g} V, RMS {copy['rms']:.2g} V (on a {copy['points']} × "
                f"{copy['points']} grid offset from the nodes)."]
    out.append("")
    return out


def study_sections(result: Any, claims: Sequence[Any]) -> str:
    """claims.md sections beyond the paper's claims: per-trajectory verdicts, C3's sigma
    range, the single-realisation probability of the paper's ordering, the control surfaces
    compared, tuned-vs-tuned baselines, and the robustness to the open modelling choices."""
    from ..experiments.analysis import c3_sigma_range

    out: list[str] = []
    by_id = {c.id: c for c in claims}
    trajs = result.config.trajectories
    out += ["## Verdicts per trajectory", "",
            "The same cells, judged one trajectory at a time (C3 concerns the straight line "
            "only).", "",
            "| claim | " + " | ".join(trajs) + " |", "|---|" + "---|" * len(trajs)]
    for c in claims:
        if c.per_trajectory:
            out.append(f"| {c.id} | " + " | ".join(
                c.per_trajectory[t]["verdict"] for t in trajs) + " |")
    out.append("")
    c3 = by_id.get("C3")
    if c3 is not None and c3.evidence:
        rng = c3_sigma_range(c3)
        lo, hi = rng["band"]
        out += ["## C3 as what it is: the noise range that gives ISE ~ 0.003", ""]
        inside = rng["levels_in_band"]
        text = (f"The smallest straight-line mean ISE lies in the band [{lo:.2g}, {hi:.2g}] at "
                + (levels_text(inside) if inside else "no noise level") + ".")
        for key in ("enters", "leaves"):
            cross = rng[key]
            if cross is not None:
                a, b = cross["range"]
                span = (f" (from the interval bounds: {_f(a)} to {_f(b)})"
                        if a is not None and b is not None else "")
                text += (f" Interpolating between levels (log-log; linearly from an ISE of 0), "
                         f"the mean {key} the band at σ = {_f(cross['sigma'])} rad{span}.")
        out += [text, ""]
    if result.ordering:
        out += ["## How likely were the paper's single-run figures?", "",
                "Probability that one noise realisation shows the paper's strict ordering "
                "FLC > FoU 0.1 > 0.2 > 0.3 on all four integrals (`all`: on every trajectory "
                "at once, as the paper's figures do), with exact (Clopper-Pearson) 95 % "
                "intervals; σ = 0 is one deterministic run.", "",
                "| σ | trajectory | k / n | p [95 % interval] |", "|---|---|---|---|"]
        for r in result.ordering:
            iv = (f"{_f(r['p'])} (deterministic)" if r["deterministic"]
                  else interval_text(r["p"], r["ci_low"], r["ci_high"]))
            out.append(f"| {r['sigma']:g} | {r['trajectory']} | {r['k']} / {r['n']} | {iv} |")
        out.append("")
    out += surfaces_markdown(result)
    if result.tuned:
        out += _tuned_markdown(result)
    if result.robustness is not None:
        out += robustness_markdown(result.robustness, result.config)
    return "\n".join(out)


def _tuned_markdown(result: Any) -> list[str]:
    n = count_text(int(e["n"]) for c in result.tuned_claims for e in c.evidence
                   if float(e["sigma"]) > 0.0)
    out = ["## Tuned against tuned", "",
           "Each fuzzy controller tuned like the PD baseline (same tuning realisations, same "
           "number of candidates, same effort limit; Ke, Kde and an output gain scaling the "
           "consequents): the claims judged on the tuned controllers at σ = "
           f"{result.config.noise_std:g} rad ({n} realisations; `paper` experiment), with "
           "the replication probability of that level. The untuned paper controllers stay "
           "beside them in summary.csv.", "",
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
        out += ["| claim (tuned controllers) | verdict | status (replication probability) |",
                "|---|---|---|"]
        for c in result.tuned_claims:
            detail = f" ({c.detail})" if c.detail else ""
            reps = ", ".join(f"{c.level_status[s]} ({p:.2f})"
                             for (path, s), p in sorted(c.replication.items())
                             if path == "all" and s > 0.0)
            out.append(f"| {c.id} | {c.verdict}{detail} | {reps} |")
        out.append("")
    return out


def robustness_markdown(rob: Any, config: Any) -> list[str]:
    """The robustness section of claims.md."""
    levels = levels_text(rob.config.noise_levels)
    n = count_text(int(c["n"]) for c in rob.cells if float(c["sigma"]) > 0.0)
    k = rob.config.baseline_batches
    out = [
        "## Robustness to the paper's open modelling choices", "",
        f"Every claim re-judged under each alternative of each open choice ({MODEL_DOC}), one "
        f"at a time and in the factorial, at {levels} with {n} realisations per cell, with "
        "the same rules as above and each level's replication probability. At this size a "
        "status moves with the seed set by itself, so the paper's choices (the baseline) "
        f"were judged on {k} independent seed batches of the same size; the *spread* below is "
        "the statuses they gave. A variant's level is *unsettled* when its status has a "
        f"replication probability below {rob.target:g}, *unchanged* when its status is in "
        "the baseline's spread, *flipped* when the spread holds the opposite status (holds vs "
        "contradicted) and not its own, *changed* otherwise. A noise reading is judged at its "
        f"own σ and compared with the baseline at σ = {config.noise_std:g} rad. The baseline "
        "row is judged like every variant (so it can differ from the headline verdicts, "
        "which have up to "
        f"{getattr(getattr(config, 'verdicts', None), 'cap', '')} realisations). "
        "Cell by cell: robustness.csv.", "",
        "### The baseline's spread over independent seed batches", "",
        "| claim | σ | statuses over the batches | two batches agree | bootstrap estimate |",
        "|---|---|---|---|---|",
    ]
    for r in rob.spread:
        out.append(f"| {r['claim']} | {r['sigma']:g} | {r['spread']} | "
                   f"{r['agreement']:.2f} | {r['replication_mean']:.2f} |")
    out += ["", "Two batches agree: the fraction of pairs of batches giving the same status "
            "(the observed replication rate at this size); bootstrap estimate: the mean over "
            "the batches of the bootstrap's replication probability.", ""]
    out += ["| choice | sets | default | alternatives | what is open | docs/model.md |",
            "|---|---|---|---|---|---|"]
    for c in rob.config.choices:
        out.append(f"| {c.name} | {', '.join(c.sets)} | {c.describe(c.default)} | "
                   + "; ".join(c.describe(a) for a in c.alternatives)
                   + f" | {c.description} | #{c.doc} |")
    out.append("")
    for cid, groups in rob.flips.items():
        base = next((v for v in rob.verdicts if v["claim"] == cid and v["part"] == "baseline"),
                    None)
        if base is None:
            continue
        out.append(f"- **{cid}** (baseline: {base['verdict']}). "
                   + ". ".join(f"{key.capitalize()} by: " + ("; ".join(groups[key]) or "none")
                               for key in ("flipped", "changed"))
                   + ". Unchanged under: " + ("; ".join(groups["unchanged"]) or "none")
                   + ". Unsettled under: " + ("; ".join(groups["unsettled"]) or "none") + ".")
    out.append("")
    claims = list(dict.fromkeys(v["claim"] for v in rob.verdicts))
    mark = {"unchanged": "", "changed": " (changed)", "flipped": " (**flipped**)",
            "unsettled": " (unsettled)", "baseline": ""}
    out += ["| variant | " + " | ".join(claims) + " |", "|---|" + "---|" * len(claims)]
    table: dict[str, dict[str, str]] = {}
    for v in rob.verdicts:
        row = "baseline: the paper's choices" if v["part"] == "baseline" else v["label"]
        table.setdefault(row, {})[v["claim"]] = v["verdict"] + mark[v["change"]]
    for row, cells in table.items():
        out.append(f"| {row} | " + " | ".join(cells.get(c, "") for c in claims) + " |")
    out.append("")
    if rob.ranking:
        out += ["Choices ranked by the (claim, level) statuses their alternatives move beyond "
                "the baseline's spread, one at a time (2 per flip, 1 per change): "
                + ", ".join(f"{r['choice']} ({r['score']})" for r in rob.ranking) + ".", ""]
    if rob.config.factorial:
        out += [f"The factorial crosses {' × '.join(rob.config.factorial)} (every combination "
                "with two or more alternatives; rows with several settings above).", ""]
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

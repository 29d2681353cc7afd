"""``reproduce``'s chip experiment (``--chip``): the verdicts on the simulated ATmega328P, run
in a spawned process while the study simulates (:mod:`it2track.experiments.chip`)."""

from __future__ import annotations

from typing import Any

import click

#: The chip experiment of ``--quick --chip``: a smoke version (3 realisations, no extension
#: round, a 9-point latency grid, one replay per reducer).
QUICK_CHIP = {"first": 3, "batch": 1, "cap": 3, "points": 9, "replay": 1}


class _ChipJob:
    """The chip experiment (:func:`~it2track.experiments.chip.run_chip`) in a spawned process
    while the study runs (it needs nothing of the study but its config; the comparison with
    the study's verdicts is made when both are done), or why it does not run."""

    def __init__(self, outcome: Any = None, pool: Any = None, pending: Any = None,
                 quick: bool = False) -> None:
        self.outcome = outcome
        self._pool = pool
        self._pending = pending
        self._quick = quick

    @classmethod
    def start(cls, config: Any, chip: bool | None, *, quick: bool) -> _ChipJob:
        """Start it, or record why not: ``--no-chip`` (nothing is written), ``--quick``
        without ``--chip``, a missing toolchain."""
        import multiprocessing

        from ..codegen.tools import PIL_TOOLS, missing_tools
        from ..experiments.chip import ChipConfig, run_chip
        from ..report.chip import ChipOutcome

        if chip is False:
            return cls()
        if chip is None and quick:
            return cls(ChipOutcome(None, reason="skipped with --quick (add --chip for a smoke "
                                                "version)"))
        missing = missing_tools(PIL_TOOLS)
        if missing:
            why = f"the toolchain is missing: install the Debian package(s) {', '.join(missing)}"
            click.echo(f"note: the verdicts on the chip were not judged ({why}); the report "
                       "says so", err=True)
            return cls(ChipOutcome(None, reason=why))
        settings = ChipConfig(**QUICK_CHIP) if quick else ChipConfig.for_study(config)
        pool = multiprocessing.get_context("spawn").Pool(1)
        return cls(pool=pool, pending=pool.apply_async(run_chip, (config, settings)),
                   quick=quick)

    def result(self, host_rows: Any) -> Any:
        """The outcome, compared with the study's ``verdicts.csv`` rows (waits for it)."""
        from dataclasses import replace

        from ..codegen.tools import BuildError, ToolMissingError
        from ..experiments.chip import with_study
        from ..report.chip import ChipOutcome

        if self._pending is None:
            return self.outcome
        try:
            got = self._pending.get()
        except (ToolMissingError, BuildError, OSError, ValueError) as exc:
            why = f"it failed: {type(exc).__name__}: {exc}"
            click.echo(f"note: the verdicts on the chip were not judged ({why})", err=True)
            return ChipOutcome(None, reason=why)
        finally:
            self.cancel()
        if not got.matches:
            click.echo("warning: the replay on simavr did not match the host C's outputs (see "
                       "claims.md)", err=True)
        return ChipOutcome(replace(got, rows=with_study(got.rows, host_rows)), smoke=self._quick)

    def cancel(self) -> None:
        """Stop the process (idempotent)."""
        pool, self._pool, self._pending = self._pool, None, None
        if pool is not None:
            pool.terminate()
            pool.join()


def _chip(config: Any, result: Any, chip: bool | None, *, quick: bool) -> Any:
    """The chip experiment's outcome, run to the end here (see :class:`_ChipJob`)."""
    job = _ChipJob.start(config, chip, quick=quick)
    try:
        return job.result(() if result is None else result.verdict_rows)
    finally:
        job.cancel()


def _chip_provenance(outcome: Any) -> Any:
    if outcome is None:
        return None
    if outcome.result is None:
        return {"skipped": outcome.reason}
    r = outcome.result
    return {"config": r.config.to_dict(), "design": r.design.to_dict(), "seconds": r.seconds,
            "replay_matches": r.matches, "replays": len(r.replay)}


def _chip_lines(outcome: Any) -> list[str]:
    """The terminal's lines on the chip's verdicts."""
    from ..experiments.chip import survival

    if outcome is None:
        return []
    if outcome.result is None:
        return [f"chip: not judged ({outcome.reason})"]
    r = outcome.result
    lines = []
    for s in survival(r.rows):
        lines.append(f"chip {s['reducer']} {s['claim']}: {s['kept']} of {s['host_settled']} "
                     f"settled study levels keep their status ({len(s['changed'])} changed, "
                     f"{len(s['open'])} unsettled on the chip)")
    n = len(r.replay)
    lines.append(f"chip replay on simavr: {n} runs, "
                 + ("outputs match bit for bit" if r.matches else "outputs DO NOT match"))
    return lines


#: Where an unfinished physics check keeps its finished rounds (inside --out).

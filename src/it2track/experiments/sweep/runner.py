"""Running (or resuming) a sweep into its store: :func:`run_sweep`, and what it did,
:class:`SweepSummary`.
"""

from __future__ import annotations

import hashlib
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from tqdm import tqdm

from ...atomicfile import remove_stale_temporaries
from ..executors import Executor, InProcessExecutor, peak_rss_bytes
from .chunks import simulate_grid_chunk
from .plan import SweepPlan
from .store import _assemble, _chunk_digest, _locked, _prepare_store, _write_chunk, chunk_path

__all__ = ["SweepSummary", "run_sweep"]


@dataclass(frozen=True)
class SweepSummary:
    """What :func:`run_sweep` did."""

    out: Path
    n_runs: int
    n_chunks: int
    chunks_computed: int
    chunks_skipped: int
    runs_computed: int
    seconds: float
    driver_peak_rss: int
    worker_peak_rss: int
    workers: tuple[str, ...]

    @property
    def runs_per_second(self) -> float:
        return self.runs_computed / self.seconds if self.seconds > 0 else math.nan


def run_sweep(
    plan: SweepPlan,
    out: str | Path,
    *,
    executor: Executor | None = None,
    resume: bool = False,
    progress: bool = True,
    max_pending: int | None = None,
) -> SweepSummary:
    """Run (or resume) ``plan`` into the store ``out``; see the module docstring.

    Parameters
    ----------
    plan : SweepPlan
    out : path
        Store directory (created if missing).
    executor : Executor, optional
        Where chunks run; default :class:`~.executors.InProcessExecutor`. Not closed here.
    resume : bool
        Continue the sweep already in ``out`` (its configuration hash must match); without it,
        an existing sweep in ``out`` is an error.
    progress : bool
        Show a tqdm bar with ETA on stderr.

    Raises
    ------
    StoreError
        If ``out`` holds another sweep, a different configuration, or is locked.
    """
    executor = executor or InProcessExecutor()
    out = Path(out)
    (out / "chunks").mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    with _locked(out):
        _prepare_store(plan, out, resume=resume)
        header_line = plan.header_csv()
        chunks = plan.chunks()
        # Temporaries a killed run of ours left (our naming, dead writer); nothing else.
        remove_stale_temporaries(out, ("sweep.json", "results.csv"))
        names = {chunk_path(out, c.id).name for c in chunks}
        remove_stale_temporaries(out / "chunks", names | {n + ".sha256" for n in names})
        digests: dict[int, str] = {}
        todo = []
        for c in chunks:
            digest = _chunk_digest(chunk_path(out, c.id), header_line, c.size)
            if digest is None:
                todo.append(c)
            else:
                digests[c.id] = digest
        done_runs = plan.n_runs - sum(c.size for c in todo)
        by_id = {c.id: c for c in todo}
        workers: set[str] = set()
        worker_rss = 0
        runs_computed = 0
        bar = tqdm(
            total=plan.n_runs, initial=done_runs, unit="run", desc="sweep",
            disable=not progress, file=sys.stderr, dynamic_ncols=True,
        )  # fmt: skip
        try:
            tasks = (plan.task(c) for c in todo)
            for task, result in executor.imap_unordered(
                simulate_grid_chunk, tasks, max_pending=max_pending
            ):
                chunk = by_id[task.chunk_id]
                data = (header_line + plan.rows_csv(chunk, result.metrics)).encode("utf-8")
                _write_chunk(chunk_path(out, chunk.id), data)
                digests[chunk.id] = hashlib.sha256(data).hexdigest()
                workers.add(result.worker)
                worker_rss = max(worker_rss, result.peak_rss)
                runs_computed += chunk.size
                bar.update(chunk.size)
        finally:
            bar.close()
        _assemble(plan, out, header_line, digests)
    return SweepSummary(
        out=out,
        n_runs=plan.n_runs,
        n_chunks=len(chunks),
        chunks_computed=len(todo),
        chunks_skipped=len(chunks) - len(todo),
        runs_computed=runs_computed,
        seconds=time.perf_counter() - t0,
        driver_peak_rss=peak_rss_bytes(),
        worker_peak_rss=worker_rss,
        workers=tuple(sorted(workers)),
    )

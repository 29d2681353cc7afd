"""The verdicts on the chip: C1, C2 and D1 re-judged with the controllers as the ATmega328P
runs them (issue 22, point 2).

The study's controllers compute in double precision and act at once. On the 8-bit MCU the
generated C computes in float32 (avr-gcc's ``double`` is 32-bit) and its output reaches the
motors only after the call's cycles at 16 MHz (the ``measured`` latency model of
:mod:`it2track.tracking.pil`). This experiment judges the claims C1, C2 and D1 again with every
compared controller in that form -- the FLC, the IT2FLCs of every FoU width and the
slope-matched type-1 FLC -- once per type reducer of the IT2FLCs (exhaustive, EIASC, KM), at
the study's noise levels, with the study's own machinery: the sequential design
(:func:`~.sequential.settle`), the bootstrap replication probabilities
(:mod:`.replication`) and the level rows of ``verdicts.csv`` (:func:`~.verdicts.verdict_rows`).

**How it runs.** The float32 outputs of the host-compiled C equal the AVR's bit for bit, so
the bulk of the runs use :class:`~it2track.tracking.pil.TabledLatencyController`: the host C
with, at each step, the cycles the simulated MCU measured at the nearest point of a grid of
its inputs (:class:`~it2track.tracking.pil.LatencyTable`, ``points`` per input). A sample of
runs (``replay`` per reducer: the main IT2FLC at the study's sigma) is replayed on the
simulated MCU itself: every step's inputs of the tabled run go through the firmware on simavr,
whose outputs must equal the tabled run's bit for bit (the *match*); the same run in the loop
with the MCU (:class:`~it2track.tracking.pil.PilHeadingController`, latency ``measured``) says
how far the tabled cycles move the metrics.

The type-1 controllers have no reducer: their runs are simulated once and shared by the three
reducers' judgements (a run depends on its own controller, path, sigma and seed only).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .claimcells import ClaimDef, claim_definitions
from .judgement import ALL, ClaimResult
from .sequential import SeedBatch, SequentialDesign, settle
from .specs import ControllerKind, ControllerSpec
from .verdicts import verdict_rows

__all__ = ["CHIP_CLAIMS", "CHIP_COLUMNS", "CHIP_REDUCERS", "ChipConfig", "ChipResult",
           "chip_specs", "run_chip", "survival", "with_study"]

#: The claims judged on the chip.
CHIP_CLAIMS = ("C1", "C2", "D1")
#: The IT2FLCs' type reducers, each judged on its own.
CHIP_REDUCERS = ("exhaustive", "eiasc", "km")
#: ``chip_verdicts.csv``'s columns: the level rows of ``verdicts.csv`` per reducer, with the
#: study's (double precision, no latency) status of the same level beside.
CHIP_COLUMNS = ("reducer", "claim", "path", "sigma", "status", "settled", "replication", "n",
                "host_status", "host_settled", "survives", "decisive", "estimate", "ci_low",
                "ci_high")


def _int(v: Any, key: str, least: int) -> None:
    if isinstance(v, bool) or not isinstance(v, int) or v < least:
        raise ValueError(f"chip {key}={v!r} must be an integer >= {least}")


@dataclass(frozen=True, kw_only=True)
class ChipConfig:
    """Size of the chip experiment (module docstring).

    Parameters
    ----------
    first, batch, cap : int
        The sequential design's realisations per (path, sigma) unit: first round, added per
        round to a unit behind an unsettled level, most (the study's target replication
        probability, resamples and bootstrap seed are kept).
    points : int
        Grid points per input of each latency table (>= 2).
    replay : int
        Runs per reducer replayed on the simulated MCU (>= 0).
    """

    first: int = 50
    batch: int = 50
    cap: int = 100
    points: int = 65
    replay: int = 1

    def __post_init__(self) -> None:
        _int(self.first, "first", 2)
        _int(self.batch, "batch", 1)
        _int(self.cap, "cap", 2)
        _int(self.points, "points", 2)
        _int(self.replay, "replay", 0)
        if self.cap < self.first:
            raise ValueError(f"chip cap={self.cap!r} must be >= first={self.first!r}")

    @classmethod
    def for_study(cls, config: Any, *, points: int = 65, replay: int = 1) -> ChipConfig:
        """The study's sequential design scaled down: half its first round and batch, a
        quarter of its cap (at least 2, 1 and the first round): 50, 50 and 100 for the
        default study.

        Parameters
        ----------
        config : StudyConfig
        points, replay : int
            As for the class.

        Returns
        -------
        ChipConfig
        """
        d = config.verdicts
        first = max(2, d.first // 2)
        return cls(first=first, batch=max(1, d.batch // 2), cap=max(first, d.cap // 4),
                   points=points, replay=replay)

    def design(self, base: SequentialDesign) -> SequentialDesign:
        """``base`` (the study's design) with this experiment's realisations."""
        return replace(base, first=self.first, batch=self.batch, cap=self.cap)

    def to_dict(self) -> dict[str, Any]:
        return {"first": self.first, "batch": self.batch, "cap": self.cap,
                "points": self.points, "replay": self.replay}


@dataclass
class ChipResult:
    """What :func:`run_chip` found.

    Attributes
    ----------
    rows : list of dict
        ``chip_verdicts.csv`` (columns :data:`CHIP_COLUMNS`).
    claims : dict of str -> list of ClaimResult
        Per reducer, C1, C2 and D1 judged on the chip.
    metrics : dict of str -> dict of str -> ndarray
        Per reducer, every run's metrics rows (the type-1 controllers' shared).
    costs : list of dict
        Per reducer, the main IT2FLC's latency: the table's worst and mean cycles over its
        input grid, the replayed runs' worst and mean per step, and the worst as a fraction of
        the control period.
    replay : list of dict
        Per replayed run: the steps, whether the MCU's outputs equal the tabled run's bit for
        bit, the cycles' largest difference from the table's, and the metrics' largest
        relative difference from the run in the loop with the MCU.
    config : ChipConfig
    design : SequentialDesign
    levels : tuple of float
    ts : float
        Control period, s.
    seconds : dict of str -> float
        Wall time of the tables, the runs, the replay and in all (``total``), and the CPU time
        of this process in all (``cpu``: the simulated MCUs run in it; compilers do not).
    """

    rows: list[dict[str, Any]]
    claims: dict[str, list[ClaimResult]]
    metrics: dict[str, dict[str, np.ndarray]]
    costs: list[dict[str, Any]]
    replay: list[dict[str, Any]]
    config: ChipConfig
    design: SequentialDesign
    levels: tuple[float, ...]
    ts: float
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def matches(self) -> bool:
        """Every replayed run's outputs equal the MCU's bit for bit (True without replays)."""
        return all(r["outputs_equal"] for r in self.replay)


def chip_specs(config: Any, reducer: str) -> list[ControllerSpec]:
    """The controllers C1, C2 and D1 compare, with the IT2FLCs' reducer set to ``reducer``
    and the study's labels kept (the claims find controllers by label)."""
    keep = {"FLC", f"T1 slope-matched {config.main_fou:g}",
            *(f"IT2FLC FoU {w:g}" for w in config.fous)}
    out = []
    for s in config.paper_fuzzy() + config.matched_baselines([config.main_fou]):
        if s.label not in keep:
            continue
        if s.kind is ControllerKind.IT2:
            s = replace(s, reducer=reducer)  # the label is explicit: kept
        out.append(s)
    return out


def _chip_definitions(config: Any, labels: Sequence[str]) -> list[ClaimDef]:
    defs = claim_definitions(fous=config.fous, main_fou=config.main_fou,
                             trajectories=config.trajectories, available=labels)
    return [d for d in defs if d.id in CHIP_CLAIMS]


class _Builder:
    """The chip form of each controller (host C + latency table), built once."""

    def __init__(self, points: int, build_dir: str | None) -> None:
        self.points = points
        self.build_dir = build_dir
        self._made: dict[ControllerSpec, Any] = {}
        self.table_seconds = 0.0

    def __call__(self, spec: ControllerSpec) -> Any:
        from ..codegen import CHeadingController, RealType, generate_c
        from ..tracking.pil import TabledLatencyController

        got = self._made.get(spec)
        if got is None:
            fuzzy = spec.build()
            fls = fuzzy.fls  # type: ignore[attr-defined]
            code = generate_c(fls, real=RealType.FLOAT)
            started = time.perf_counter()
            table = self._table(code, [i.universe for i in fls.inputs])
            self.table_seconds += time.perf_counter() - started
            host = CHeadingController(code=code, ke=fuzzy.ke,  # type: ignore[attr-defined]
                                      kde=fuzzy.kde,  # type: ignore[attr-defined]
                                      name=spec.label, build_dir=self.build_dir)
            got = TabledLatencyController(host=host, table=table, name=spec.label)
            self._made[spec] = got
        return got

    def _table(self, code: Any, universes: Sequence[tuple[float, float]]) -> Any:
        """The latency table of ``code``, measured once and cached in the build folder by the
        code's digest, the grid and the universes (simavr's cycle counts are deterministic)."""
        import hashlib
        import os
        import secrets
        from pathlib import Path

        from ..codegen.controller import default_build_dir
        from ..tracking.pil import LatencyTable

        root = Path(self.build_dir) if self.build_dir else default_build_dir()
        key = hashlib.sha256(f"{code.digest()} {self.points} {list(universes)}".encode()
                             ).hexdigest()[:20]
        path = root / f"latency-{key}.npy"
        lo = tuple(float(a) for a, _ in universes)
        hi = tuple(float(b) for _, b in universes)
        if path.is_file():
            try:
                cycles = np.load(path, allow_pickle=False)
                if cycles.shape == (self.points,) * len(universes):
                    return LatencyTable(lo=lo, hi=hi, cycles=cycles)
            except (OSError, ValueError):
                pass  # measured again below
        table = LatencyTable.measure(code, universes, points=self.points,
                                     build_dir=self.build_dir)
        root.mkdir(parents=True, exist_ok=True)
        tmp = root / f".latency-{key}-{secrets.token_hex(4)}.npy"
        np.save(tmp, table.cycles, allow_pickle=False)
        os.replace(tmp, path)
        return table


def run_chip(
    config: Any,
    chip: ChipConfig,
    *,
    host_rows: Sequence[Mapping[str, Any]] = (),
    reducers: Sequence[str] = CHIP_REDUCERS,
    build_dir: str | None = None,
    progress: Callable[[int], object] | None = None,
) -> ChipResult:
    """Judge C1, C2 and D1 on the chip for each reducer (module docstring).

    Parameters
    ----------
    config : StudyConfig
        The study: paths, FoU widths, noise levels, loop, and the design whose target,
        resamples and seed are kept.
    chip : ChipConfig
        Realisations, latency-table grid and replays.
    host_rows : sequence of dict
        The study's ``verdicts.csv`` rows (double precision, no latency) to compare with.
    reducers : sequence of str
        The IT2FLCs' reducers (default exhaustive, EIASC, KM).
    build_dir : str or None
        Build cache of the host libraries, firmware and shim.
    progress : callable, optional
        Called with the number of runs finished.

    Returns
    -------
    ChipResult

    Raises
    ------
    ToolMissingError
        Without gcc, libsimavr-dev, gcc-avr, avr-libc or binutils-avr.
    """
    from ..codegen.tools import PIL_TOOLS, require
    from ..tracking import RunTable, get_trajectory, simulate_metrics

    require(PIL_TOOLS)
    if not reducers:
        raise ValueError("run_chip: reducers must name at least one reducer")
    design = chip.design(config.verdicts)
    trajectories = tuple(get_trajectory(t) for t in config.trajectories)
    path_index = {t: i for i, t in enumerate(config.trajectories)}
    build = _Builder(chip.points, build_dir)
    shared: dict[tuple[str, str, float, int], dict[str, float]] = {}
    started, cpu = time.perf_counter(), time.process_time()
    claims: dict[str, list[ClaimResult]] = {}
    metrics: dict[str, dict[str, np.ndarray]] = {}
    rows: list[dict[str, Any]] = []
    run_seconds = 0.0
    for reducer in reducers:
        specs = chip_specs(config, reducer)
        labels = [s.label for s in specs]
        spec_of = dict(zip(labels, specs, strict=True))
        typed = {s.label for s in specs if s.kind is not ControllerKind.IT2}

        def simulate(batches: Sequence[SeedBatch], spec_of: Mapping[str, ControllerSpec] = spec_of,
                     typed: set[str] = typed) -> dict[str, np.ndarray]:
            wanted = [(c, p, s, int(seed)) for b in batches for c, p, s in b.cells
                      for seed in b.seeds]
            todo = [k for k in wanted if not (k[0] in typed and k in shared)]
            used = list(dict.fromkeys(k[0] for k in todo))
            done: dict[tuple[str, str, float, int], dict[str, float]] = {}
            if todo:
                ctrls = [build(spec_of[c]) for c in used]
                index = {c: i for i, c in enumerate(used)}
                runs = RunTable(np.array([index[k[0]] for k in todo], dtype=np.int64),
                                np.array([path_index[k[1]] for k in todo], dtype=np.int64),
                                np.array([k[2] for k in todo], dtype=np.float64),
                                np.array([k[3] for k in todo], dtype=np.int64))
                got = simulate_metrics(ctrls, trajectories, runs, config.loop,
                                       batch_size=config.batch_size, progress=progress)
                for j, k in enumerate(todo):
                    done[k] = {m: float(v[j]) for m, v in got.items()}
                    if k[0] in typed:
                        shared[k] = done[k]
            values = [done.get(k) or shared[k] for k in wanted]
            out: dict[str, np.ndarray] = {
                "experiment": np.full(len(wanted), "chip", dtype=object),
                "trajectory": np.array([k[1] for k in wanted], dtype=object),
                "controller": np.array([k[0] for k in wanted], dtype=object),
                "noise_std": np.array([k[2] for k in wanted], dtype=np.float64),
                "seed": np.array([k[3] for k in wanted], dtype=np.int64),
            }
            for m in values[0] if values else ():
                out[m] = np.array([v[m] for v in values])
            return out

        defs = _chip_definitions(config, labels)
        t0 = time.perf_counter()
        settled = settle(simulate, claims=defs, controllers=labels,
                         trajectories=config.trajectories, levels=config.noise_levels,
                         design=design, experiment="chip", fous=config.fous,
                         main_fou=config.main_fou)
        run_seconds += time.perf_counter() - t0
        claims[reducer] = settled.claims
        metrics[reducer] = settled.rows
        rows += [{"reducer": reducer, **r} for r in verdict_rows(defs, settled.claims)]
    rows = with_study(rows, host_rows)
    t0 = time.perf_counter()
    replays = _replay(config, chip, reducers, build, build_dir)
    replay_seconds = time.perf_counter() - t0
    costs = _costs(config, reducers, build, replays)
    return ChipResult(rows=rows, claims=claims, metrics=metrics, costs=costs, replay=replays,
                      config=chip, design=design, levels=tuple(config.noise_levels),
                      ts=config.loop.ts,
                      seconds={"tables": round(build.table_seconds, 3),
                               "runs": round(run_seconds - build.table_seconds, 3),
                               "replay": round(replay_seconds, 3),
                               "total": round(time.perf_counter() - started, 3),
                               "cpu": round(time.process_time() - cpu, 3)})


def with_study(rows: Sequence[Mapping[str, Any]],
               host_rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """``rows`` (the chip's level rows, with a ``reducer``) in the columns
    :data:`CHIP_COLUMNS`, with the study's status of the same level beside each: its status,
    whether it is settled, and ``survives``: the chip settled the level with the same status;
    all three empty where the study has no such level.

    Parameters
    ----------
    rows : sequence of dict
        The chip's rows (:func:`~.verdicts.verdict_rows` with a ``reducer`` key).
    host_rows : sequence of dict
        The study's ``verdicts.csv`` rows.

    Returns
    -------
    list of dict
    """
    host = {(str(r["claim"]), str(r["path"]), float(r["sigma"])): r for r in host_rows}
    out = []
    for r in rows:
        h = host.get((str(r["claim"]), str(r["path"]), float(r["sigma"])))
        row = {k: r.get(k, "") for k in CHIP_COLUMNS}
        row.update(host_status="" if h is None else h["status"],
                   host_settled="" if h is None else h["settled"],
                   survives="" if h is None else bool(r["settled"] is True
                                                      and r["status"] == h["status"]))
        out.append(row)
    return out


def _main_spec(config: Any, reducer: str) -> ControllerSpec:
    label = f"IT2FLC FoU {config.main_fou:g}"
    return next(s for s in chip_specs(config, reducer) if s.label == label)


def _replay_sigma(config: Any) -> float:
    noisy = [s for s in config.noise_levels if s > 0.0]
    if config.noise_std in noisy or not noisy:
        return float(config.noise_std)
    return float(min(noisy, key=lambda s: abs(s - config.noise_std)))


def _replay(config: Any, chip: ChipConfig, reducers: Sequence[str], build: _Builder,
            build_dir: str | None) -> list[dict[str, Any]]:
    """Replay ``chip.replay`` runs per reducer on the simulated MCU (module docstring)."""
    import os

    from ..codegen.controller import default_build_dir
    from ..codegen.pil import AvrInTheLoop
    from ..tracking import RunTable, get_trajectory, simulate
    from ..tracking.pil import Latency, PilHeadingController

    where = build_dir or os.fspath(default_build_dir())
    sigma = _replay_sigma(config)
    out = []
    for reducer in reducers:
        tabled = build(_main_spec(config, reducer))
        code = tabled.host.code
        pil = PilHeadingController(code=code, ke=tabled.host.ke, kde=tabled.host.kde,
                                   latency=Latency.MEASURED, name=f"{tabled.name} on the MCU",
                                   build_dir=where)
        for k in range(chip.replay):
            path = config.trajectories[k % len(config.trajectories)]
            seed = k // len(config.trajectories)
            trace = simulate([tabled, pil], [get_trajectory(path)],
                             RunTable([0, 1], 0, sigma, seed), config.loop)
            x = np.stack([trace["e_meas"][0] * tabled.host.ke,
                          trace["de"][0] * tabled.host.kde], axis=1)
            with AvrInTheLoop(code, build_dir=where) as mcu:
                u, raw = mcu.step(x)
            tab = trace["cycles"][0].astype(np.int64)
            rel = {m: abs(float(trace.metrics[m][0]) / float(trace.metrics[m][1]) - 1.0)
                   for m in ("IAE", "ITAE", "ISE", "ITSE")}
            out.append({
                "reducer": reducer, "controller": tabled.name, "trajectory": path,
                "sigma": sigma, "seed": seed, "steps": int(x.shape[0]),
                "outputs_equal": bool(u.tobytes() == np.asarray(trace["u"][0]).tobytes()),
                "cycles_equal": int(np.sum(raw.cycles == tab)),
                "cycles_max_diff": int(np.max(np.abs(raw.cycles - tab))),
                "mcu_cycles_max": int(raw.cycles.max()),
                "mcu_cycles_mean": float(raw.cycles.mean()),
                "metric_max_rel_diff": max(rel.values()),
            })
    return out


def _costs(config: Any, reducers: Sequence[str], build: _Builder,
           replays: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    from ..codegen.mcu import AVR_CLOCK_HZ

    ts = config.loop.ts
    out = []
    for reducer in reducers:
        table = build(_main_spec(config, reducer)).table.cycles
        mine = [r for r in replays if r["reducer"] == reducer]
        worst = int(table.max())
        out.append({
            "reducer": reducer, "controller": f"IT2FLC FoU {config.main_fou:g}",
            "grid": int(table.shape[0]),
            "cycles_max": worst, "cycles_mean": float(table.mean()),
            "latency_max_ms": 1e3 * worst / AVR_CLOCK_HZ,
            "period_share_max": worst / AVR_CLOCK_HZ / ts,
            "period_share_mean": float(table.mean()) / AVR_CLOCK_HZ / ts,
            "run_cycles_max": max((r["mcu_cycles_max"] for r in mine), default=math.nan),
            "run_cycles_mean": (float(np.mean([r["mcu_cycles_mean"] for r in mine]))
                                if mine else math.nan),
        })
    return out


def survival(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Per reducer and claim, over all paths together, the noisy levels the study settled:
    how many keep their status on the chip (settled there with the same status), which change
    (settled there with another) and which the chip leaves unsettled; and the chip's status of
    every noisy level.

    Parameters
    ----------
    rows : sequence of dict
        :func:`with_study`'s rows.

    Returns
    -------
    list of dict
        ``reducer, claim, host_settled, kept, changed, open, levels``; ``changed`` and
        ``open`` list ``(sigma, study status, chip status, chip replication)``, ``levels``
        ``(sigma, status, settled, replication)``.
    """
    out = []
    keys = dict.fromkeys((str(r["reducer"]), str(r["claim"])) for r in rows)
    for reducer, claim in keys:
        mine = [r for r in rows if r["reducer"] == reducer and r["claim"] == claim
                and r["path"] == ALL and float(r["sigma"]) > 0.0]
        judged = [r for r in mine if r["host_settled"] is True]

        def level(r: Mapping[str, Any]) -> tuple[float, str, str, Any]:
            return (float(r["sigma"]), r["host_status"], r["status"], r["replication"])

        out.append({"reducer": reducer, "claim": claim, "host_settled": len(judged),
                    "kept": sum(r["survives"] is True for r in judged),
                    "changed": [level(r) for r in judged
                                if r["settled"] is True and r["survives"] is not True],
                    "open": [level(r) for r in judged if r["settled"] is not True],
                    "levels": [(float(r["sigma"]), r["status"], r["settled"], r["replication"])
                               for r in mine]})
    return out

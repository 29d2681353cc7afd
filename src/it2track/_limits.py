"""Memory estimates checked before big allocations: refuse with the setting, its value and the
estimate, instead of a ``MemoryError`` (or the machine swapping) halfway through a run.

One place for the arithmetic, used by the closed loop (:class:`~it2track.tracking.LoopConfig`,
``simulate``), the sweep planner, the optimiser, the study's command and the control-surface
plots. The estimates are deliberately simple upper bounds of the arrays the code allocates
(float64 = 8 bytes); they are compared with the memory available now:

- ``IT2TRACK_MEMORY_LIMIT`` (environment) when set: bytes, or a number with a ``K``, ``M``,
  ``G`` or ``T`` suffix (powers of 1024), e.g. ``IT2TRACK_MEMORY_LIMIT=8G``;
- else Linux's ``MemAvailable`` (``/proc/meminfo``);
- else the physical memory (``os.sysconf``), else no limit.

Standard library only (imported by ``plant`` and ``tracking``).
"""

from __future__ import annotations

import os

__all__ = [
    "ResourceLimitError",
    "available_memory",
    "check_memory",
    "format_bytes",
    "fuzzy_batch_bytes",
    "loop_bytes",
]

_SUFFIX = {"": 1, "B": 1, "K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}
#: Bytes per float64 element.
F8 = 8


class ResourceLimitError(ValueError):
    """A setting would need more memory than the machine has available."""


def _parse_size(text: str) -> int | None:
    t = text.strip().upper().removesuffix("IB").removesuffix("B")
    unit = t[-1:] if t[-1:] in _SUFFIX else ""
    number = t[: len(t) - len(unit)] if unit else t
    try:
        value = float(number)
    except ValueError:
        return None
    if not value > 0 or value != value or value == float("inf"):
        return None
    return int(value * _SUFFIX[unit])


def available_memory() -> int | None:
    """Bytes a run may use (see the module docstring), or None when unknown."""
    override = os.environ.get("IT2TRACK_MEMORY_LIMIT")
    if override:
        size = _parse_size(override)
        if size is not None:
            return size
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_PHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, OSError, ValueError):  # pragma: no cover - exotic platforms
        return None


def format_bytes(n: float) -> str:
    """``1536`` -> ``'1.5 KiB'``; ``8e12`` -> ``'7.3 TiB'``."""
    value = float(n)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(value) < 1024 or unit == "PiB":
            return f"{value:.0f} B" if unit == "B" else f"{value:.3g} {unit}"
        value /= 1024
    raise AssertionError("unreachable")  # pragma: no cover


def check_memory(need: float, *, what: str, hint: str = "") -> None:
    """Raise :class:`ResourceLimitError` if ``need`` bytes exceed the available memory.

    Parameters
    ----------
    need : float
        Estimated bytes (may be astronomically large: it is never allocated).
    what : str
        The setting(s) and value(s) responsible, e.g. ``"duration=1e9 with ts=0.01"``.
    hint : str
        What to change, appended to the message.
    """
    limit = available_memory()
    if limit is None or need <= limit:
        return
    message = (
        f"{what} needs an estimated {format_bytes(need)} of memory, more than the "
        f"{format_bytes(limit)} available"
    )
    if hint:
        message += f"; {hint}"
    raise ResourceLimitError(message)


def loop_bytes(
    *,
    n_steps: int,
    runs: int,
    trajectories: int = 1,
    noise_samples: int = 1,
    record: bool = False,
) -> int:
    """Peak bytes of one batched closed-loop call (``simulate`` / one ``simulate_metrics``
    batch) of ``runs`` runs over ``n_steps`` periods.

    Per trajectory and instant: the sampled reference and its derived rows (~14 floats);
    per run and held noise sample: the noise rows (2 floats); per run: ~80 work rows and
    metric accumulators; with ``record``, the 17 recorded series twice (filled, then
    transposed for the trace).
    """
    instants = n_steps + 1
    total = F8 * instants * (14 * trajectories + 2)
    total += F8 * noise_samples * 2 * runs
    total += F8 * 80 * runs
    if record:
        total += 2 * 17 * F8 * instants * runs
    return int(total)


def fuzzy_batch_bytes(samples: int, n_inputs: int) -> int:
    """Bytes of a fuzzy system evaluated on ``samples`` points: the inputs (broadcast and
    stacked), the outputs and their intervals; the rule-level work is done in fixed-size
    blocks (a few MiB)."""
    return int(F8 * samples * (2 * n_inputs + 3) + (8 << 20))

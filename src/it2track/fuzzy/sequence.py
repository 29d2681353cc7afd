"""Evaluating a sequence of inputs in order, with fuzzylite's ``lock-previous``: an output
keeps its previous value where it has none of its own (no rule of it fires).

A system's ``__call__`` is a pure function of its inputs: where no rule of an output fires it
gives ``on_zero_firing`` or raises :class:`~.reducers.ZeroFiringError`, whatever came before.
fuzzylite's ``lock-previous: true`` (``LockPrevious=1`` in its ``.fis``, ``DEFAULT := ... NC``
in FCL, "no change") instead keeps the output's last value there, which makes the output depend
on the order of evaluation. :func:`evaluate_sequence` is that order made explicit: the rows of
``x`` are successive evaluations, and the state (the last output row) is passed in and handed
back, so a long sequence can be evaluated in chunks with the same bits.

Semantics (pyfuzzylite 8's ``OutputVariable.defuzzify``, which fills every NaN with the
previous value before applying ``default``): for an output with ``lock_previous``, at a row
where it has no value of its own -- none of its rules fires, or its value is undefined there
(a Sugeno formula's 0/0) -- the value is the output's value at the row before (the previous
chunk's last row, ``previous``, for the first); where there is none (``previous`` not given or
NaN for it, and no earlier row) it is what ``__call__`` gives there: ``on_zero_firing``, or
``ZeroFiringError``. Everywhere else the value is ``__call__``'s, bit for bit. fuzzylite's
``lock-range`` (clipping the output to its range) does not interact: the readers accept it only
where it changes nothing, so a previous value is already inside the range. (A Mamdani output
whose rules fire but whose set is empty on the grid raises, as ``__call__`` does.)

A system whose formulas read earlier outputs (:mod:`.chain`) fills its outputs in order, each
before a later one reads it (fuzzylite's ``Engine.process``), in one pass.

Cost: where an output keeps its previous value the system is evaluated twice, with two
placeholder ``on_zero_firing`` values, so that the rows where it has no value of its own are
exactly those where the two differ.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .chain import chain_values
from .reducers import ZeroFiringError

__all__ = ["chain_outputs", "evaluate_sequence", "lock_flags", "previous_state"]

FloatArray = NDArray[np.float64]


def lock_flags(value: Any, n_outputs: int) -> bool | tuple[bool, ...]:
    """``lock_previous`` checked and made canonical: one bool when all outputs agree."""
    flags = (value,) * n_outputs if not isinstance(value, tuple | list) else tuple(value)
    if len(flags) != n_outputs or not all(isinstance(f, bool | np.bool_) for f in flags):
        raise ValueError(f"lock_previous={value!r} must be a bool or one bool per output "
                         f"({n_outputs})")
    flags = tuple(bool(f) for f in flags)
    return flags[0] if len(set(flags)) == 1 else flags


def previous_state(previous: ArrayLike | None, n_outputs: int) -> FloatArray:
    """``previous`` as an array of shape ``(n_outputs,)`` (NaN: no previous output)."""
    if previous is None:
        return np.full(n_outputs, np.nan)
    arr = np.asarray(previous)
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"previous={previous!r} must be real numbers (NaN: none)")
    arr = arr.astype(np.float64)
    if arr.ndim == 0 and n_outputs == 1:
        arr = arr.reshape(1)
    if arr.shape != (n_outputs,):
        raise ValueError(f"previous must have shape ({n_outputs},) (one value per output, NaN "
                         f"for none), got {arr.shape}")
    if np.isinf(arr).any():
        raise ValueError(f"previous={arr.tolist()!r}: an output value is finite (or NaN: none)")
    return arr.copy()


def _rows(system: Any, x: FloatArray) -> FloatArray:
    arr = np.asarray(x, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != system.n_inputs:
        raise ValueError(f"a sequence of inputs has shape (N, {system.n_inputs}), one row per "
                         f"evaluation, got {arr.shape}")
    return arr


def _twins(system: Any) -> tuple[Any, Any]:
    """``system`` with two placeholder ``on_zero_firing`` values (cached): evaluated with each,
    the outputs agree wherever ``__call__`` has an output and differ exactly where it has none
    (and would raise): those are filled or refused here, never passed on."""
    twins = system.__dict__.get("_sequence_twins")
    if twins is None:
        twins = (replace(system, on_zero_firing=0.0), replace(system, on_zero_firing=1.0))
        object.__setattr__(system, "_sequence_twins", twins)  # immutable system: derived cache
    return twins


def evaluate_sequence(system: Any, x: FloatArray, previous: ArrayLike | None = None
                      ) -> tuple[FloatArray, FloatArray]:
    """Outputs of the rows of ``x`` evaluated in order (see the module docstring).

    Parameters
    ----------
    system : a system of :mod:`it2track.fuzzy` (not a HybridSystem: it evaluates its parts)
    x : ndarray, shape (N, n_inputs)
        One row per evaluation, in order (real numbers: the system's ``real_input`` checked).
    previous : array_like, shape (n_outputs,), optional
        The last output row before ``x`` (the state returned by the previous call); NaN for
        an output without one. ``None``: a fresh start (fuzzylite's ``restart()``).

    Returns
    -------
    y : ndarray, shape (N,) or (N, n_outputs)
        As :meth:`evaluate` gives them, with the previous values kept where an output with
        ``lock_previous`` has no rule firing.
    state : ndarray, shape (n_outputs,)
        The last row of ``y`` (``previous`` for an empty ``x``): pass it on as ``previous``.
    """
    arr = _rows(system, x)
    m = system.n_outputs
    state = previous_state(previous, m)
    n = arr.shape[0]
    if n == 0:
        return np.empty((0,) if m == 1 else (0, m)), state
    if getattr(system, "_chained", False):  # outputs read outputs: filled in order
        x_in, _ = system._prepare(tuple(arr.T))
        y = chain_values(system, x_in, state)
        bad = np.isnan(y)
        if bad.any():
            k = int(np.argmax(bad.any(axis=0)))
            _raise(system, arr, k, int(np.argmax(bad[:, k])))
        return (y[:, 0] if m == 1 else y), y[-1].copy()
    locks = [system.keeps_previous(k) for k in range(m)]
    if not any(locks):
        y = np.asarray(system.evaluate(arr), dtype=np.float64).reshape(n, m)
        return (y[:, 0] if m == 1 else y), y[-1].copy()
    a, b = (np.asarray(t.evaluate(arr), dtype=np.float64).reshape(n, m) for t in _twins(system))
    y, undefined = a.copy(), a != b  # undefined: where __call__ has no output of the system's
    index = np.arange(n)
    for k in range(m):
        none = undefined[:, k]
        if not none.any():
            continue
        # the output's own value (__call__'s): where it has one, and before any previous
        own = ~none
        if not locks[k] or np.isnan(state[k]):
            own[:int(np.argmax(own)) if locks[k] and own.any() else n] = True
        bad = own & none
        if bad.any():
            zero = system.zero_firing_value(k)
            if zero is None:
                _raise(system, arr, k, int(np.argmax(bad)))
            y[bad, k] = zero
        if own.all():
            continue
        last = np.maximum.accumulate(np.where(own, index, -1))
        y[:, k] = np.where(last >= 0, y[np.maximum(last, 0), k], state[k])
    return (y[:, 0] if m == 1 else y), y[-1].copy()


def _raise(system: Any, arr: FloatArray, k: int, i: int) -> None:
    """The ZeroFiringError of output ``k`` at row ``i`` (as ``__call__`` raises there)."""
    _, upper = system.firing(*arr[i:i + 1].T)
    rules = [r for r, rule in enumerate(system.rules) if rule.consequents[k] is not None]
    point = ", ".join(f"{inp.name}={arr[i, j]:.6g}" for j, inp in enumerate(system.inputs))
    what, out = f"{type(system).__name__} {system.name!r}", system.output_names[k]
    if upper[0, rules].sum() > 0:
        raise ZeroFiringError(f"{what} has no output {out!r} at row {i} ({point}), where its "
                              "rules fire, and there is no previous output")
    raise ZeroFiringError(
        f"no rule of {what} for output {out!r} fires at row {i} ({point}) and there is no "
        "previous output; pass previous=, or on_zero_firing=<value> to define it there")


def chain_outputs(system: Any, x: Any, previous: Any = None, *, sequence: bool = False
                  ) -> FloatArray:
    """The outputs ``(N, m)`` of the rows of ``x`` (shape ``(N, n_inputs)``) of a chained
    system, as fuzzylite has them: NaN where an output has no value (where ``__call__`` and
    :meth:`evaluate_sequence` raise ``ZeroFiringError``). With ``sequence`` the rows are
    evaluated in order from ``previous`` (see :func:`~.chain.chain_values`); else each alone."""
    arr = _rows(system, np.asarray(x, dtype=np.float64))
    prepared, _ = system._prepare(tuple(arr.T))
    state = previous_state(previous, system.n_outputs) if sequence else None
    return chain_values(system, prepared, state)

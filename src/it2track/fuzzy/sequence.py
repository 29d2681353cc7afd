"""Evaluating a sequence of inputs in order, with fuzzylite's ``lock-previous``: an output
keeps its previous value where none of its rules fires.

A system's ``__call__`` is a pure function of its inputs: where no rule of an output fires it
gives ``on_zero_firing`` or raises :class:`~.reducers.ZeroFiringError`, whatever came before.
fuzzylite's ``lock-previous: true`` (``LockPrevious=1`` in its ``.fis``, ``DEFAULT := ... NC``
in FCL, "no change") instead keeps the output's last value there, which makes the output depend
on the order of evaluation. :func:`evaluate_sequence` is that order made explicit: the rows of
``x`` are successive evaluations, and the state (the last output row) is passed in and handed
back, so a long sequence can be evaluated in chunks with the same bits.

Semantics (pyfuzzylite 8's ``OutputVariable.defuzzify``): for an output with
``lock_previous``, at a row where none of its rules fires, the value is the output's value at
the row before (the previous chunk's last row, ``previous``, for the first); where there is
none (``previous`` not given or NaN for it, and no earlier row) it is what ``__call__`` gives
there: ``on_zero_firing``, or ``ZeroFiringError``. Everywhere else the value is
``__call__``'s, bit for bit. fuzzylite's ``lock-range`` (clipping the output to its range) does
not interact: the readers accept it only where it changes nothing, so a previous value is
already inside the range.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .reducers import ZeroFiringError

__all__ = ["evaluate_sequence", "lock_flags", "previous_state"]

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


def _twin(system: Any) -> Any:
    """``system`` with a placeholder ``on_zero_firing`` (cached), so that evaluating it never
    raises where no rule fires: those values are replaced or refused here."""
    if system.on_zero_firing is not None:
        return system
    twin = system.__dict__.get("_sequence_twin")
    if twin is None:
        twin = replace(system, on_zero_firing=0.0)
        object.__setattr__(system, "_sequence_twin", twin)  # immutable system: a derived cache
    return twin


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
    locks = [system.keeps_previous(k) for k in range(m)]
    if not any(locks):
        y = np.asarray(system.evaluate(arr), dtype=np.float64).reshape(n, m)
        return (y[:, 0] if m == 1 else y), y[-1].copy()
    _, upper = system.firing(*arr.T)
    y = np.asarray(_twin(system).evaluate(arr), dtype=np.float64).reshape(n, m).copy()
    index = np.arange(n)
    for k in range(m):
        rules = [r for r, rule in enumerate(system.rules) if rule.consequents[k] is not None]
        fires = upper[:, rules].sum(axis=1) > 0
        if fires.all():
            continue
        # the output's own value (__call__'s): where a rule fires, or before any previous
        first = int(np.argmax(fires)) if fires.any() else n
        own = fires.copy()
        if not locks[k] or np.isnan(state[k]):
            own[:first if locks[k] else n] = True
        idle = own & ~fires
        if idle.any() and system.zero_firing_value(k) is None:
            i = int(np.argmax(idle))
            point = ", ".join(f"{inp.name}={arr[i, j]:.6g}"
                              for j, inp in enumerate(system.inputs))
            raise ZeroFiringError(
                f"no rule of {type(system).__name__} {system.name!r} for output "
                f"{system.output_names[k]!r} fires at row {i} ({point}) and there is no "
                "previous output; pass previous=, or on_zero_firing=<value> to define it there")
        if own.all():
            continue
        last = np.maximum.accumulate(np.where(own, index, -1))
        filled = np.where(last >= 0, y[np.maximum(last, 0), k], state[k])
        y[:, k] = filled
    return (y[:, 0] if m == 1 else y), y[-1].copy()

"""Hybrid systems: several fuzzy systems over the same inputs, each with its own outputs --
fuzzylite's "hybrid" engines, where a Mamdani output and a Takagi-Sugeno output (each with its
rule block and operators) share the inputs.

:class:`HybridSystem` evaluates each part and concatenates their outputs in order; a part is
any system of this package (Sugeno, TSK, Mamdani, Tsukamoto; type-1 or interval type-2).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .sequence import previous_state

__all__ = ["HybridSystem"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class HybridSystem:
    """Systems sharing their inputs, their outputs side by side.

    Parameters
    ----------
    systems : sequence of systems
        Each with the same inputs (names, universes and sets); outputs named distinctly.
    name : str

    Examples
    --------
    >>> from it2track.fuzzy import Input, Output, Rule, T1Mamdani, T1Sugeno, Triangle
    >>> x = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    >>> m = T1Mamdani(inputs=[x], outputs=[Output("m", (0, 1), [
    ...     ("a", Triangle(0, 0, 1)), ("b", Triangle(0, 1, 1))])],
    ...     rules=[Rule(["lo"], "a"), Rule(["hi"], "b")])
    >>> s = T1Sugeno(inputs=[x], rules=[Rule(["lo"], 0.0), Rule(["hi"], 1.0)], outputs=("s",))
    >>> fls = HybridSystem((m, s))
    >>> fls.output_names, fls(0.25).tolist() == [m(0.25), s(0.25)]
    (('m', 's'), True)
    """

    systems: tuple[Any, ...]
    name: str = ""

    def __post_init__(self) -> None:
        systems = tuple(self.systems)
        object.__setattr__(self, "systems", systems)
        if not systems:
            raise ValueError("HybridSystem needs at least one system")
        first = systems[0].inputs
        for k, system in enumerate(systems[1:], start=1):
            if tuple(system.inputs) != tuple(first):
                raise ValueError(f"HybridSystem: system {k} ({system.name!r}) has other inputs "
                                 "than system 0; every part must share the same inputs")
        names = self.output_names
        if len(set(names)) != len(names):
            raise ValueError(f"HybridSystem: output names {list(names)} must be distinct")

    @property
    def inputs(self) -> tuple[Any, ...]:
        """The shared inputs."""
        return tuple(self.systems[0].inputs)

    @property
    def n_inputs(self) -> int:
        return len(self.inputs)

    @property
    def n_outputs(self) -> int:
        """Outputs of all parts together."""
        return sum(int(s.n_outputs) for s in self.systems)

    @property
    def output_names(self) -> tuple[str, ...]:
        """The parts' output names, in order."""
        return tuple(n for s in self.systems for n in s.output_names)

    @property
    def lock_previous(self) -> tuple[bool, ...]:
        """Each output's ``lock_previous`` (its part's), in order."""
        return tuple(s.keeps_previous(k) for s in self.systems for k in range(s.n_outputs))

    def keeps_previous(self, k: int = 0) -> bool:
        """Whether output ``k`` keeps its previous value where no rule fires, in
        :meth:`evaluate_sequence`."""
        return self.lock_previous[k]

    def evaluate_sequence(self, x: ArrayLike, previous: ArrayLike | None = None
                          ) -> tuple[FloatArray, FloatArray]:
        """Each part's :meth:`evaluate_sequence`, outputs side by side: ``(y, state)``,
        ``y`` of shape ``(N,)`` or ``(N, m)``, ``state`` the last row ``(m,)``."""
        state = previous_state(previous, self.n_outputs)
        ys, states, start = [], [], 0
        for s in self.systems:
            y, last = s.evaluate_sequence(x, state[start:start + s.n_outputs])
            ys.append(np.asarray(y).reshape(len(y), -1))
            states.append(last)
            start += s.n_outputs
        out = np.concatenate(ys, axis=-1)
        return (out[:, 0] if out.shape[-1] == 1 else out), np.concatenate(states)

    def __call__(self, *xs: ArrayLike) -> FloatArray:
        """Crisp outputs: the broadcast input shape ``S``, ``S + (m,)`` for ``m > 1``
        outputs (the parts' outputs concatenated in order)."""
        parts = []
        for s in self.systems:
            y = np.asarray(s(*xs), dtype=np.float64)
            parts.append(y[..., None] if s.n_outputs == 1 else y)
        out = np.concatenate(parts, axis=-1)
        return out[..., 0] if out.shape[-1] == 1 else out

    def evaluate(self, x: ArrayLike) -> FloatArray:
        """Crisp outputs for inputs stacked on the last axis, shape ``(..., n_inputs)``."""
        arr = np.asarray(x, dtype=np.float64)
        if arr.ndim == 0 or arr.shape[-1] != self.n_inputs:
            raise ValueError(f"stacked inputs must have shape (..., {self.n_inputs}), "
                             f"got {arr.shape}")
        return self(*(arr[..., i] for i in range(self.n_inputs)))

    def select_output(self, output: int | str) -> Any:
        """The part's system with that one output (its index or name)."""
        names = self.output_names
        if isinstance(output, str) and output in names:
            k = names.index(output)
        elif isinstance(output, int) and not isinstance(output, bool) and 0 <= output < len(names):
            k = output
        else:
            raise ValueError(f"output={output!r} must be an output name {list(names)} or an "
                             f"index 0..{len(names) - 1}")
        for s in self.systems:
            if k < s.n_outputs:
                return s.select_output(k)
            k -= s.n_outputs
        raise AssertionError("unreachable")

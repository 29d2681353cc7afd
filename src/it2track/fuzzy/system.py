"""What every fuzzy system shares: definition checks, input preparation (batch shapes,
clipping, NaN checks), rule firing, several outputs, and the zero-firing policy.

:class:`_SystemBase` is the common base of the Sugeno/TSK systems (:mod:`.sugeno`) and the
Mamdani systems (:mod:`.mamdani`); each subclass supplies ``_interval_of`` (the type reduction
of one output) and may override ``_lower`` (the lowering to arrays). It is internal: use the
concrete classes.

Shapes
------
``system(x1, x2, ..., xn)`` takes one array per input; they broadcast together to a batch shape
``S`` and the output has shape ``S`` (``S + (m,)`` for ``m > 1`` outputs).
``system.evaluate(X)`` takes the inputs stacked on the last axis, ``X.shape == S + (n,)``.
Firing strengths have the rules on the last axis: ``S + (R,)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import kernels as _kernels
from .chain import chained_outputs, check_chain
from .norms import SNorm, TNorm
from .reducers import ZeroFiringError
from .rules import Input, Rule
from .sequence import evaluate_sequence, lock_flags
from .tables import SystemTables

__all__ = ["BLOCK", "real_input"]

FloatArray = NDArray[np.float64]


def real_input(x: ArrayLike, name: str) -> FloatArray:
    """``x`` as a float64 array, refusing what a conversion would silently change.

    Accepted: Python and NumPy integers and floats, and arrays (or nested sequences) of them.
    Refused with a ``ValueError`` naming the input: ``None``, strings, booleans, complex
    numbers (the imaginary part would be dropped), objects, and masked arrays with masked
    entries (the mask would be ignored).
    """
    if x is None:
        raise ValueError(f"input {name!r} is None; give a number or an array of numbers")
    if isinstance(x, np.ma.MaskedArray):
        if np.ma.getmaskarray(x).any():
            raise ValueError(
                f"input {name!r} is a masked array with masked entries; fill or drop them "
                "(the mask would be ignored)"
            )
        x = x.data
    try:
        arr = np.asarray(x)
    except (TypeError, ValueError) as exc:  # ragged nested sequences
        raise ValueError(f"input {name!r} is not an array of numbers: {exc}") from None
    if arr.dtype.kind not in "iuf":
        example = arr.reshape(-1)[:1].tolist()[0] if arr.size else arr.tolist()
        kind = {"b": "booleans", "c": "complex numbers", "U": "strings", "S": "bytes",
                "O": "Python objects"}.get(arr.dtype.kind, str(arr.dtype))
        raise ValueError(
            f"input {name!r} must be real numbers, got {kind} (e.g. {example!r})"
        )
    return arr.astype(np.float64, copy=False)


#: Samples per internal block: keeps the working set of one block in the CPU cache.
BLOCK = 4096


@dataclass(frozen=True, kw_only=True)
class _SystemBase:
    inputs: tuple[Input, ...]
    rules: tuple[Rule, ...]
    tnorm: TNorm = TNorm.PRODUCT
    on_zero_firing: float | tuple[float, ...] | None = None
    name: str = ""
    snorm: SNorm = SNorm.MAXIMUM
    outputs: tuple[Any, ...] = ()
    lock_previous: bool | tuple[bool, ...] = False
    _c: SystemTables = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "inputs", tuple(self.inputs))
        object.__setattr__(self, "rules", tuple(self.rules))
        if not self.inputs:
            raise ValueError("a fuzzy system needs at least one input")
        if not self.rules:
            raise ValueError("a fuzzy system needs at least one rule")
        if not isinstance(self.tnorm, TNorm):
            raise ValueError(f"tnorm={self.tnorm!r} must be a TNorm member")
        if not isinstance(self.snorm, SNorm):
            raise ValueError(f"snorm={self.snorm!r} must be an SNorm member")
        object.__setattr__(self, "outputs", tuple(self.outputs))
        n_out = len(self.rules[0].consequents)
        if self.outputs and len(self.outputs) != n_out:
            raise ValueError(
                f"outputs={self.outputs!r} names {len(self.outputs)} outputs, but the rules have "
                f"{n_out} consequents each"
            )
        self._check_outputs()
        names = [inp.name for inp in self.inputs]
        if len(set(names)) != len(names):
            raise ValueError(f"input names {names!r} must be unique")
        for k, rule in enumerate(self.rules):
            if len(rule.antecedent) != len(self.inputs):
                raise ValueError(
                    f"rule {k} {rule.antecedent!r} has {len(rule.antecedent)} antecedents for "
                    f"{len(self.inputs)} inputs"
                )
            if all(label is None for label in rule.antecedent) and rule.condition is None:
                raise ValueError(f"rule {k} mentions no input")
            if len(rule.consequents) != n_out:
                raise ValueError(
                    f"rule {k} has {len(rule.consequents)} consequents, rule 0 has {n_out}"
                )
            for label, inp in zip(rule.antecedent, self.inputs, strict=True):
                if label is not None:
                    inp.set_index(label)
        zero = self.on_zero_firing
        if zero is not None:
            scalar = np.ndim(zero) == 0
            values: tuple[Any, ...] = (zero,) * n_out if scalar else tuple(zero)  # type: ignore[arg-type]
            number = int | float | np.floating | np.integer
            if len(values) != n_out or not all(
                isinstance(v, number) and not isinstance(v, bool) and math.isfinite(v)
                for v in values
            ):
                raise ValueError(
                    f"on_zero_firing={zero!r} must be None, a finite number, or one finite "
                    f"number per output ({n_out})"
                )
            if n_out == 1:
                object.__setattr__(self, "on_zero_firing", float(values[0]))
            elif not scalar:
                object.__setattr__(self, "on_zero_firing", tuple(float(v) for v in values))
        object.__setattr__(self, "lock_previous", lock_flags(self.lock_previous, n_out))
        check_chain(self)
        object.__setattr__(self, "_c", self._lower())

    def _check_outputs(self) -> None:
        if len(set(self.outputs)) != len(self.outputs) or not all(
            isinstance(o, str) and o for o in self.outputs
        ):
            raise ValueError(f"outputs={self.outputs!r} must be distinct non-empty names")

    def _lower(self) -> SystemTables:
        return SystemTables(self.inputs, self.rules, snorm=self.snorm)

    # -- shapes and checks --------------------------------------------------------------------
    @property
    def n_inputs(self) -> int:
        return len(self.inputs)

    @property
    def tables(self) -> SystemTables:
        """The system lowered to arrays (:class:`~it2track.fuzzy.tables.SystemTables`), the
        representation compiled kernels and code generators work from."""
        return self._c

    @property
    def n_rules(self) -> int:
        return len(self.rules)

    @property
    def n_outputs(self) -> int:
        """Number of outputs (one consequent per output in every rule)."""
        return self._c.n_outputs

    @property
    def output_names(self) -> tuple[str, ...]:
        """The outputs' names (``outputs``, or ``("output1", ...)`` where none were given)."""
        if self.outputs:
            return tuple(o if isinstance(o, str) else o.name for o in self.outputs)
        return tuple(f"output{k + 1}" for k in range(self.n_outputs))

    def zero_firing_value(self, k: int = 0) -> float | None:
        """The output ``k``'s value where no rule fires (``None``: ZeroFiringError)."""
        zero = self.on_zero_firing
        if zero is None or isinstance(zero, int | float):
            return zero
        return float(zero[k])

    def keeps_previous(self, k: int = 0) -> bool:
        """Whether output ``k`` keeps its previous value where no rule fires, in
        :meth:`evaluate_sequence` (``lock_previous``; ``__call__`` is stateless)."""
        flags = self.lock_previous
        return flags if isinstance(flags, bool) else flags[k]

    def evaluate_sequence(self, x: ArrayLike, previous: ArrayLike | None = None
                          ) -> tuple[FloatArray, FloatArray]:
        """Outputs of the rows of ``x`` (shape ``(N, n_inputs)``) evaluated in order, an output
        with ``lock_previous`` keeping its previous value where it has none of its own (no rule
        of it fires, or its value is undefined: fuzzylite fills every NaN); returns
        ``(y, state)``, ``state`` the last output row to pass on as ``previous`` (see
        :mod:`it2track.fuzzy.sequence`). Chunks evaluated with the state passed on give the
        same bits as the whole sequence."""
        return evaluate_sequence(self, real_input(x, "sequence inputs"), previous)

    def select_output(self, output: int | str) -> Any:
        """The same system with one output: ``output`` is its index or name.

        Rules without a consequent for it are left out. Returns the system itself for a
        one-output system asked for output 0.
        """
        names = self.output_names
        if isinstance(output, str):
            if output not in names:
                raise ValueError(f"output={output!r}: the outputs are {list(names)}")
            k = names.index(output)
        elif isinstance(output, int) and not isinstance(output, bool) and 0 <= output < len(names):
            k = output
        else:
            raise ValueError(f"output={output!r} must be an output name {list(names)} or an "
                             f"index 0..{len(names) - 1}")
        if self.n_outputs == 1:
            return self
        read = chained_outputs(self, k)
        if read:
            raise ValueError(f"output {names[k]!r} reads the outputs {list(read)} evaluated "
                             "before it (a chained formula): it is not evaluated alone")
        rules = tuple(
            r.with_consequents([r.consequents[k]], [k])
            for r in self.rules if r.consequents[k] is not None
        )
        return replace(self, rules=rules, outputs=(names[k],) if self.outputs else (),
                       on_zero_firing=self.zero_firing_value(k),
                       lock_previous=self.keeps_previous(k))

    def _prepare(self, xs: tuple[ArrayLike, ...]) -> tuple[FloatArray, tuple[int, ...]]:
        if len(xs) != self.n_inputs:
            raise ValueError(
                f"{type(self).__name__} {self.name!r} takes {self.n_inputs} inputs "
                f"({', '.join(i.name for i in self.inputs)}), got {len(xs)}"
            )
        arrays = [real_input(x, inp.name) for x, inp in zip(xs, self.inputs, strict=True)]
        for inp, arr in zip(self.inputs, arrays, strict=True):
            # One cheap reduction first; the exact elementwise check only if it is not finite
            # (it can overflow to inf on finite but huge values, which must not warn).
            with np.errstate(over="ignore", invalid="ignore"):
                total = float(np.add.reduce(arr, axis=None))
            if not math.isfinite(total) and not bool(np.isfinite(arr).all()):
                raise ValueError(f"input {inp.name!r} contains NaN or inf")
        try:
            shape = np.broadcast_shapes(*(a.shape for a in arrays))
        except ValueError:
            shapes = ", ".join(
                f"{i.name}: {a.shape}" for i, a in zip(self.inputs, arrays, strict=True)
            )
            raise ValueError(f"input shapes do not broadcast together ({shapes})") from None
        n = math.prod(shape)
        x = np.empty((self.n_inputs, n))
        c = self._c
        for i, arr in enumerate(arrays):
            row = x[i].reshape(shape)
            np.maximum(arr, c.lo[i], out=row)
            np.minimum(row, c.hi[i], out=row)
        return x, shape

    def _stacked(self, x: ArrayLike) -> tuple[FloatArray, ...]:
        arr = real_input(x, "stacked inputs")
        if arr.ndim == 0 or arr.shape[-1] != self.n_inputs:
            raise ValueError(
                f"stacked inputs must have shape (..., {self.n_inputs}), got {arr.shape}"
            )
        return tuple(arr[..., i] for i in range(self.n_inputs))

    def _scalar_inputs(self, xs: tuple[ArrayLike, ...]) -> list[float] | None:
        """Plain floats (clipped) if every input is a finite scalar, else None."""
        if len(xs) != self.n_inputs:
            return None
        out = []
        for i, x in enumerate(xs):
            if type(x) is float or type(x) is int or isinstance(x, np.floating):
                v = float(x)
                if not math.isfinite(v):
                    return None
                lo, hi = self.inputs[i].universe
                out.append(lo if v < lo else hi if v > hi else v)
            else:
                return None
        return out

    # -- firing -------------------------------------------------------------------------------
    def _firing_block(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Firing of a block ``x`` (n_inputs, N) -> ``(fl, fu)`` (R, N), rules in sorted order.

        The returned arrays are workspace views, valid until the next block.
        """
        return self._c.firing_block(x, self.tnorm)

    def _firing_scalar(self, x: list[float]) -> tuple[list[float], list[float]]:
        c = self._c
        m = c.memberships_scalar(x)
        prod = self.tnorm is TNorm.PRODUCT
        fu, fl = [], []
        ur, lr = c.upper_rows_s_list, c.lower_rows_s_list
        for r in range(self.n_rules):
            u = m[ur[r][0]]
            lw = m[lr[r][0]]
            for i in range(1, self.n_inputs):
                if prod:
                    u *= m[ur[r][i]]
                    lw *= m[lr[r][i]]
                else:
                    u = min(u, m[ur[r][i]])
                    lw = min(lw, m[lr[r][i]])
            fu.append(u)
            fl.append(lw)
        return fl, fu

    def firing(self, *xs: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Rule firing intervals.

        Returns
        -------
        lower, upper : ndarray, shape ``S + (R,)``
            Lower and upper firing strength of every rule (equal for a type-1 system), after
            NOT, AND/OR and the rule weight.
        """
        x, shape = self._prepare(xs)
        n = x.shape[1]
        lower = np.empty((n, self.n_rules))
        upper = np.empty((n, self.n_rules))
        for c in self._c.outputs:
            inv = c.inv_perm
            cols = c.rule_index
            for start in range(0, n, BLOCK):
                stop = min(start + BLOCK, n)
                fl, fu = c.firing_block(x[:, start:stop], self.tnorm)
                if c.n_rules == self.n_rules:
                    lower[start:stop] = fl[inv].T
                    upper[start:stop] = fu[inv].T
                else:
                    lower[start:stop, cols] = fl[inv].T
                    upper[start:stop, cols] = fu[inv].T
        return lower.reshape((*shape, self.n_rules)), upper.reshape((*shape, self.n_rules))

    def _zero_firing(self, x: FloatArray, bad: NDArray[np.bool_]) -> None:
        j = int(np.argmax(bad))
        point = ", ".join(f"{inp.name}={x[i, j]:.6g}" for i, inp in enumerate(self.inputs))
        raise ZeroFiringError(
            f"no rule of {type(self).__name__} {self.name!r} fires at ({point}); pass "
            "on_zero_firing=<value> to define the output there"
        )

    def _interval_of(
        self, c: SystemTables, x: FloatArray, k: int
    ) -> tuple[FloatArray, FloatArray]:
        raise NotImplementedError

    def _idle(self, x: FloatArray, k: int) -> tuple[FloatArray, FloatArray]:
        """Output ``k``, which no rule concludes: no rule fires for it anywhere, so it is its
        ``on_zero_firing`` value (jFuzzyLogic's DEFAULT, MATLAB's middle of the range) or a
        :class:`ZeroFiringError`."""
        zero = self.zero_firing_value(k)
        if zero is None:
            raise ZeroFiringError(
                f"no rule of {type(self).__name__} {self.name!r} concludes output {k + 1}, and "
                "it has no on_zero_firing value")
        y = np.full(x.shape[1], float(zero))
        return y, y.copy()

    def _interval_blocks(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``(yl, yr)`` of shape ``(N,)``, or ``(N, m)`` for ``m > 1`` outputs."""
        if self._c.n_outputs == 1:
            return self._interval_of(self._c, x, 0)
        pairs = [self._interval_of(c, x, k) if c.n_rules else self._idle(x, k)
                 for k, c in enumerate(self._c.outputs)]
        return (np.stack([p[0] for p in pairs], axis=-1),
                np.stack([p[1] for p in pairs], axis=-1))

    def _out_shape(self, shape: tuple[int, ...]) -> tuple[int, ...]:
        return shape if self._c.n_outputs == 1 else (*shape, self._c.n_outputs)

    def _undefined(
        self, c: SystemTables, x: FloatArray, k: int, yl: FloatArray, yr: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """Replace NaN (no output) by ``on_zero_firing`` or raise the error that explains it."""
        if math.isnan(float(np.add.reduce(yl)) + float(np.add.reduce(yr))):
            bad = np.isnan(yl) | np.isnan(yr)
            where = np.flatnonzero(bad)
            for start in range(0, where.size, BLOCK):
                j = where[start : start + BLOCK]
                _, fu = c.firing_block(np.ascontiguousarray(x[:, j]), self.tnorm)
                fires = fu.sum(axis=0) > 0
                if fires.any():
                    i = int(j[np.argmax(fires)])
                    point = ", ".join(
                        f"{inp.name}={x[n, i]:.6g}" for n, inp in enumerate(self.inputs)
                    )
                    raise ZeroFiringError(self._no_output_message(point))
            zero = self.zero_firing_value(k)
            if zero is None:
                self._zero_firing(x, bad)
            yl[bad] = yr[bad] = zero
        return yl, yr

    def _no_output_message(self, point: str) -> str:
        return f"{type(self).__name__} {self.name!r} has no output at ({point})"

    def interval(self, *xs: ArrayLike) -> tuple[Any, Any]:
        """Type-reduced interval ``(yl, yr)``, each of the broadcast input shape ``S``
        (``S + (m,)`` for ``m > 1`` outputs).

        Called with Python/NumPy real scalars (as :meth:`__call__` takes them), a one-output
        system returns two Python floats, as ``__call__`` returns one.
        """
        x, shape = self._prepare(xs)
        fast = _kernels.interval(self, x, crisp=False)  # compiled when supported (same bits)
        yl, yr = fast if fast is not None else self._interval_blocks(x)
        assert yr is not None
        out = self._out_shape(shape)
        if out == () and all(type(v) is float or type(v) is int or isinstance(v, np.floating)
                             for v in xs):
            return float(yl[0]), float(yr[0])
        return yl.reshape(out), yr.reshape(out)

    def __call__(self, *xs: ArrayLike) -> Any:
        """Crisp output ``u = (yl + yr) / 2`` (eq. 18), shape of the broadcast inputs
        (``S + (m,)`` for ``m > 1`` outputs).

        A call with Python/NumPy float scalars returns a Python float through a fast path
        (bit-for-bit equal to the array path) meant for real-time loops.
        """
        u = _kernels.output(self, xs)  # compiled scalar call when supported (same bits)
        if u is not None:
            return u
        scalars = self._scalar_inputs(xs)
        if scalars is not None:
            fast = self._scalar_output(scalars)
            if fast is not None:
                return fast
        x, shape = self._prepare(xs)
        compiled = _kernels.interval(self, x, crisp=True)
        if compiled is not None:
            out = compiled[0].reshape(shape)
        else:
            yl, yr = self._interval_blocks(x)
            np.add(yl, yr, out=yl)
            yl *= 0.5
            out = yl.reshape(self._out_shape(shape))
        # Scalar inputs give a Python float whatever the engine, reducer or path took them.
        return float(out) if scalars is not None and out.shape == () else out

    def evaluate(self, x: ArrayLike) -> FloatArray:
        """Crisp output for inputs stacked on the last axis, shape ``(..., n_inputs)``."""
        result: FloatArray = np.asarray(self(*self._stacked(x)))
        return result

    def _scalar_output(self, x: list[float]) -> float | None:
        return None



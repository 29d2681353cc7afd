"""Reference signals ``r(t)`` for single-input plants (a speed, a level, an angle...).

A :class:`Reference` maps a time array ``t`` (shape ``(n,)``) to the reference values, shape
``(n,)``. Giving references instead of trajectories to :func:`~it2track.tracking.simulate`
selects the reference-tracking task (:mod:`.siso`): ``e = r - y`` on the plant's first output.
Built-in: :class:`StepReference`; users add their own from a Python callable
(:class:`FunctionReference`). Configuration files never evaluate strings as code.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from numbers import Real

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["FunctionReference", "Reference", "StepReference", "reference_from_dict"]

FloatArray = NDArray[np.float64]


class Reference:
    """Base class: ``ref(t) -> ndarray (n,)``, the reference at the times ``t`` (s)."""

    name: str

    def __call__(self, t: ArrayLike) -> FloatArray:
        raise NotImplementedError

    def sample(self, t: ArrayLike) -> FloatArray:
        """Evaluate on ``t`` and check the result.

        Parameters
        ----------
        t : array_like, shape (n,)
            Times, s.

        Returns
        -------
        ndarray, shape (n,)
            The reference values.

        Raises
        ------
        ValueError
            If the result does not have shape ``(n,)`` or holds NaN or inf.
        """
        tt = np.atleast_1d(np.asarray(t, dtype=np.float64))
        out = np.asarray(self(tt), dtype=np.float64)
        if out.shape != (tt.size,):
            raise ValueError(
                f"reference {self.name!r} returned shape {out.shape}, expected ({tt.size},)"
            )
        if not np.isfinite(out).all():
            raise ValueError(f"reference {self.name!r} returned NaN or inf")
        return out


def _real(owner: str, key: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value):
        raise ValueError(f"{owner}: {key}={value!r} must be a finite number")
    return float(value)


@dataclass(frozen=True, kw_only=True)
class StepReference(Reference):
    """A step: ``initial`` before ``at``, ``amplitude`` from ``at`` on (``r(at) = amplitude``).

    Parameters
    ----------
    amplitude : float
        Value after the step (default 1).
    at : float
        Time of the step, s (default 0: the reference is ``amplitude`` from the start).
    initial : float
        Value before the step (default 0).
    name : str
        Label in results (default ``"step"``).

    Raises
    ------
    ValueError
        If a number is not finite, or ``name`` is not a non-empty string.

    Examples
    --------
    >>> StepReference(amplitude=2.0, at=0.5).sample([0.0, 0.49, 0.5, 1.0]).tolist()
    [0.0, 0.0, 2.0, 2.0]
    """

    amplitude: float = 1.0
    at: float = 0.0
    initial: float = 0.0
    name: str = "step"

    def __post_init__(self) -> None:
        for key in ("amplitude", "at", "initial"):
            object.__setattr__(self, key, _real("StepReference", key, getattr(self, key)))
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"StepReference: name={self.name!r} must be a non-empty string")

    def __call__(self, t: ArrayLike) -> FloatArray:
        tt = np.asarray(t, dtype=np.float64)
        return np.where(tt >= self.at, self.amplitude, self.initial)

    def to_dict(self) -> dict[str, object]:
        """The table that :func:`reference_from_dict` reads back.

        Returns
        -------
        dict
            ``kind = "step"`` and the fields.
        """
        return {"kind": "step", "amplitude": self.amplitude, "at": self.at,
                "initial": self.initial, "name": self.name}


@dataclass(frozen=True)
class FunctionReference(Reference):
    """A reference from a callable ``fn(t) -> (n,)`` array.

    Parameters
    ----------
    name : str
        Label in results.
    fn : callable
        Receives times of shape ``(n,)`` in s. Use a module-level function (not a lambda) if
        the reference must travel to worker processes (it is pickled).

    Examples
    --------
    >>> import numpy as np
    >>> FunctionReference("ramp", lambda t: 2.0 * t).sample([0.0, 1.5]).tolist()
    [0.0, 3.0]
    """

    name: str
    fn: Callable[[FloatArray], ArrayLike]

    def __call__(self, t: ArrayLike) -> FloatArray:
        return np.asarray(self.fn(np.asarray(t, dtype=np.float64)), dtype=np.float64)


def reference_from_dict(table: object, where: str = "reference") -> StepReference:
    """A built-in reference from a TOML/JSON table (``kind = "step"``; unknown keys refused).

    Parameters
    ----------
    table : dict
        ``{"kind": "step", "amplitude": ..., "at": ..., "initial": ..., "name": ...}``
        (all but ``kind`` optional).
    where : str
        How error messages name the table (e.g. the file and key).

    Returns
    -------
    StepReference
        (the one built-in reference; others are given from Python)

    Raises
    ------
    ValueError
        Naming ``where``, the key and the value, for an unknown kind or key or a bad value.
    """
    if not isinstance(table, dict):
        raise ValueError(f"{where} must be a table, got {table!r}")
    kind = table.get("kind")
    if kind != "step":
        raise ValueError(f"{where}: kind={kind!r} must be 'step' (the built-in reference; "
                         "others are given from Python as FunctionReference)")
    allowed = {"kind", "amplitude", "at", "initial", "name"}
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {unknown}; allowed: {sorted(allowed)}")
    try:
        return StepReference(**{k: v for k, v in table.items() if k != "kind"})
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None

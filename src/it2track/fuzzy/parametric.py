"""Terms whose parameters are other inputs' values, read at every evaluation (jFuzzyLogic's
membership functions with variables: ``TERM good := (lo, 0) (mid, 1) (hi, 0);``,
``GAUSS meanGood stdGood``).

A :class:`Parametric` term names, for each parameter, a number or an input of its system
(:class:`Ref`: the input's index). Its system evaluates it on a block ``x`` of shape
``(n_inputs, N)`` (:meth:`Parametric.evaluate`): sample ``j``'s membership is the shape with
the parameters of sample ``j`` -- the referenced inputs' values after clipping to their
universes, as every input is clipped -- at its own input's value, vectorised over the block.
This is jFuzzyLogic's semantics (``Value.getValue`` reads the variable when the membership is
asked for, after the inputs are set), so the sets change with every evaluation.

Shapes (``family``):

- ``"points"``: jFuzzyLogic's piecewise linear function of points ``(x_k, y_k)``
  (``MembershipFunctionPieceWiseLinear.membership``): ``y_0`` for ``v <= x_0``, ``y_n`` for
  ``v > x_n``, else ``y_{k-1} + (y_k - y_{k-1}) * ((v - x_{k-1}) / (x_k - x_{k-1}))`` on the
  first ``k`` with ``v <= x_k``; parameters ``x_0, y_0, x_1, y_1, ...``.
- ``"gauss"``: ``gaussmf(v, mean, sigma)`` (:func:`~.membership.gaussmf`: the bits of a fixed
  :class:`~.membership.Gaussian` with the same parameters); parameters ``mean, sigma``.

Per sample, the parameters must make a membership function: ``sigma > 0``; points with
non-decreasing ``x`` and ``y`` in ``[0, 1]``. Otherwise :meth:`Parametric.evaluate` raises a
``ValueError`` naming the term, the parameter, the sample and its value (jFuzzyLogic checks
them once, when it loads the file, while the variables are still NaN, and not afterwards).

A system with a parametric term keeps every fixed term as it was (the same rows, the same
bits); its parametric rows are :attr:`~.kinds.MFKind.OTHER` rows, so the compiled kernels and
the C code generators leave the system to the numpy evaluation (the kernels) or refuse it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .membership import gaussmf

__all__ = ["Parametric", "Ref"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Ref:
    """A parameter given by an input: its index in the system's inputs and its name."""

    input: int
    name: str

    def __post_init__(self) -> None:
        if not isinstance(self.input, int) or isinstance(self.input, bool) or self.input < 0:
            raise ValueError(f"Ref {self.name!r}: input index {self.input!r} must be an int >= 0")


@dataclass(frozen=True)
class Parametric:
    """A membership function whose parameters are numbers or inputs (:class:`Ref`).

    Parameters
    ----------
    family : str
        ``"points"`` or ``"gauss"`` (see the module docstring).
    params : tuple of float or Ref
        ``x_0, y_0, x_1, y_1, ...`` for ``"points"``; ``mean, sigma`` for ``"gauss"``.
    name : str
        The term's name, for messages.

    Examples
    --------
    >>> mf = Parametric("points", (Ref(1, "lo"), 0.0, Ref(2, "hi"), 1.0), "rising")
    >>> x = np.array([[1.0, 1.0], [0.0, 0.0], [4.0, 2.0]])  # the input, lo, hi per sample
    >>> mf.evaluate(x, 0).tolist()
    [0.25, 0.5]
    """

    family: str
    params: tuple[float | Ref, ...]
    name: str = ""

    FAMILIES: ClassVar[dict[str, str]] = {"points": "x0 y0 x1 y1 ...", "gauss": "mean sigma"}

    def __post_init__(self) -> None:
        params = tuple(self.params)
        object.__setattr__(self, "params", params)
        owner = f"parametric term {self.name!r}"
        if self.family not in self.FAMILIES:
            raise ValueError(f"{owner}: family {self.family!r} must be one of "
                             f"{sorted(self.FAMILIES)}")
        count = len(params)
        if (self.family == "gauss" and count != 2) or (
                self.family == "points" and (count < 2 or count % 2)):
            raise ValueError(f"{owner}: {self.family} takes [{self.FAMILIES[self.family]}], "
                             f"got {count} parameters")
        for k, p in enumerate(params):
            if isinstance(p, Ref):
                continue
            if (not isinstance(p, int | float | np.floating | np.integer) or isinstance(p, bool)
                    or not math.isfinite(p)):
                raise ValueError(f"{owner}: parameter {k + 1} = {p!r} must be a finite number "
                                 "or a Ref")
        if not any(isinstance(p, Ref) for p in params):
            raise ValueError(f"{owner}: no parameter is an input (use the fixed shape)")

    @property
    def reads(self) -> tuple[int, ...]:
        """The indices of the inputs its parameters are, in parameter order."""
        return tuple(p.input for p in self.params if isinstance(p, Ref))

    def __call__(self, x: ArrayLike) -> FloatArray:
        raise TypeError(f"parametric term {self.name!r}: its parameters are the inputs "
                        f"{[p.name for p in self.params if isinstance(p, Ref)]}, so it is "
                        "evaluated with them (evaluate(x, i)), not on its own")

    def _values(self, x: FloatArray) -> list[FloatArray | float]:
        n_inputs = x.shape[0]
        values: list[FloatArray | float] = []
        for p in self.params:
            if isinstance(p, Ref):
                if p.input >= n_inputs:
                    raise ValueError(f"parametric term {self.name!r}: input {p.name!r} "
                                     f"(index {p.input}) is not among the {n_inputs} inputs")
                values.append(x[p.input])
            else:
                values.append(float(p))
        return values

    def _fail(self, k: int, what: str, bad: NDArray[np.bool_], value: FloatArray | float
              ) -> ValueError:
        j = int(np.argmax(np.broadcast_to(bad, np.shape(bad) or (1,))))
        v = float(np.broadcast_to(value, np.shape(bad) or (1,))[j])
        p = self.params[k]
        label = p.name if isinstance(p, Ref) else f"parameter {k + 1}"
        return ValueError(f"parametric term {self.name!r}: {label} = {v!r} at sample {j} "
                          f"{what}")

    def evaluate(self, x: FloatArray, i: int) -> FloatArray:
        """Memberships of input ``i`` of the block ``x`` ``(n_inputs, N)``: shape ``(N,)``,
        sample ``j`` with the parameters of sample ``j``."""
        x = np.asarray(x, dtype=np.float64)
        v = x[i]
        p = self._values(x)
        if self.family == "gauss":
            bad = ~(np.asarray(p[1]) > 0.0)
            if bad.any():
                raise self._fail(1, "must be > 0 (a Gaussian's sigma)", bad, p[1])
            mean, sigma = p  # arrays: gaussmf broadcasts its parameters
            return np.asarray(gaussmf(v, mean, sigma), dtype=np.float64)  # type: ignore[arg-type]
        xs, ys = p[0::2], p[1::2]
        for k, y in enumerate(ys):
            bad = ~((np.asarray(y) >= 0.0) & (np.asarray(y) <= 1.0))
            if bad.any():
                raise self._fail(2 * k + 1, "must lie in [0, 1] (a membership degree)", bad, y)
        for k in range(1, len(xs)):
            bad = np.asarray(xs[k]) < np.asarray(xs[k - 1])
            if bad.any():
                raise self._fail(2 * k, f"is below the x of point {k} (the points' x must "
                                 "not decrease)", bad, xs[k])
        n = v.shape[0]
        full = [np.broadcast_to(np.asarray(a, dtype=np.float64), (n,)) for a in p]
        fx, fy = full[0::2], full[1::2]
        out = np.array(fy[-1], dtype=np.float64)  # v > x_n (and a single point)
        todo = ~(v <= fx[0])
        out[~todo] = fy[0][~todo]
        for k in range(1, len(fx)):
            sel = todo & (v <= fx[k])
            if sel.any():
                x0, x1, y0, y1 = fx[k - 1][sel], fx[k][sel], fy[k - 1][sel], fy[k][sel]
                out[sel] = y0 + (y1 - y0) * ((v[sel] - x0) / (x1 - x0))
                todo &= ~sel
        return out

"""A heading controller that is a table of another controller's control surface.

``u = bilinear interpolation of table(clip(ke e), clip(kde de))`` on a grid of inputs. A
bilinear table over a grid is exactly a type-1 zero-order Sugeno system: one triangular set
per grid node on each input (feet at the neighbouring nodes, shoulders at the ends: a
partition of unity), the product t-norm, and one rule per pair of nodes whose consequent is the
tabulated value (:meth:`SurfaceTableController.as_sugeno` builds it; a test checks the two
agree). Tabulating an interval type-2 Sugeno system with crisp consequents -- a static map
``u(e, de)`` -- on a fine grid therefore gives a type-1 FLC with (up to the interpolation
error, :meth:`SurfaceTableController.surface_error`) the same control surface: the fair
baseline that separates "interval type-2" from "this surface" (docs/model.md#fair-baselines).

It runs on the numpy engine (the compiled loop serves the built-in controllers only).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..fuzzy import Input, IT2Set, T1Sugeno, TNorm, Triangle, rules_from_table
from .controllers import HeadingController, _check

__all__ = ["SurfaceTableController"]

FloatArray = NDArray[np.float64]

#: Largest table side accepted (memory: side^2 doubles).
MAX_POINTS = 4001


def _nodes(values: Any, name: str) -> FloatArray:
    g = np.asarray(values, dtype=np.float64)
    if g.ndim != 1 or g.size < 2 or not np.isfinite(g).all() or not (np.diff(g) > 0).all():
        raise ValueError(f"SurfaceTableController: {name} must be >= 2 finite, strictly "
                         "increasing values")
    return g


@dataclass(frozen=True, kw_only=True, eq=False)
class SurfaceTableController(HeadingController):
    """A tabulated control surface ``u(e, de)``, interpolated bilinearly.

    Parameters
    ----------
    e_nodes, de_nodes : ndarray, shape (n_e,), (n_de,)
        Strictly increasing grid of the (scaled) inputs; inputs are clipped to
        ``[nodes[0], nodes[-1]]``.
    table : ndarray, shape (n_e, n_de)
        Output at every grid node, V.
    ke, kde : float
        Input gains applied before the lookup (as for the fuzzy controllers).
    name : str

    Examples
    --------
    >>> import numpy as np
    >>> g = np.array([-1.0, 0.0, 1.0])
    >>> c = SurfaceTableController(e_nodes=g, de_nodes=g, table=np.add.outer(g, 2 * g))
    >>> float(c.output(np.array([0.5]), np.array([-0.25]), c.initial_state(1, 0.01))[0])
    0.0
    """

    e_nodes: FloatArray
    de_nodes: FloatArray
    table: FloatArray
    ke: float = 1.0
    kde: float = 1.0
    name: str = "surface table"

    def __post_init__(self) -> None:
        e = _nodes(self.e_nodes, "e_nodes")
        de = _nodes(self.de_nodes, "de_nodes")
        t = np.asarray(self.table, dtype=np.float64)
        if t.shape != (e.size, de.size) or not np.isfinite(t).all():
            raise ValueError(f"SurfaceTableController: table must be finite with shape "
                             f"({e.size}, {de.size}), got {t.shape}")
        for key, v in (("e_nodes", e), ("de_nodes", de), ("table", t)):
            v = v.copy()
            v.flags.writeable = False
            object.__setattr__(self, key, v)
        _check("SurfaceTableController", ke=self.ke, kde=self.kde)

    @classmethod
    def from_system(cls, system: Any, *, points: int = 401, ke: float = 1.0, kde: float = 1.0,
                    name: str = "") -> SurfaceTableController:
        """The table of a two-input system's output on a ``points x points`` grid spanning its
        input universes.

        Raises
        ------
        ValueError
            Unless ``2 <= points <= 4001`` and the system has two inputs and one output.
        """
        if isinstance(points, bool) or not isinstance(points, int) or not (
                2 <= points <= MAX_POINTS):
            raise ValueError(f"points={points!r} must be an integer in [2, {MAX_POINTS}]")
        if system.n_inputs != 2 or system.n_outputs != 1:
            raise ValueError("a surface table needs a system with two inputs and one output")
        axes = [np.linspace(float(inp.universe[0]), float(inp.universe[1]), points)
                for inp in system.inputs]
        e, de = np.meshgrid(*axes, indexing="ij")
        table = np.asarray(system(e, de), dtype=np.float64)
        return cls(e_nodes=axes[0], de_nodes=axes[1], table=table, ke=ke, kde=kde,
                   name=name or f"table of {system.name}".strip())

    def lookup(self, x1: FloatArray, x2: FloatArray) -> FloatArray:
        """The interpolated surface at already-scaled inputs (clipped to the grid)."""
        g1, g2, t = self.e_nodes, self.de_nodes, self.table
        x1 = np.clip(x1, g1[0], g1[-1])
        x2 = np.clip(x2, g2[0], g2[-1])
        i = np.clip(np.searchsorted(g1, x1, side="right") - 1, 0, g1.size - 2)
        j = np.clip(np.searchsorted(g2, x2, side="right") - 1, 0, g2.size - 2)
        a = (x1 - g1[i]) / (g1[i + 1] - g1[i])
        b = (x2 - g2[j]) / (g2[j + 1] - g2[j])
        low = t[i, j] + b * (t[i, j + 1] - t[i, j])
        high = t[i + 1, j] + b * (t[i + 1, j + 1] - t[i + 1, j])
        return np.asarray(low + a * (high - low), dtype=np.float64)

    def output(self, e: FloatArray, de: FloatArray, state: FloatArray) -> FloatArray:
        x1 = e * self.ke if self.ke != 1.0 else e
        x2 = de * self.kde if self.kde != 1.0 else de
        return self.lookup(np.asarray(x1, dtype=np.float64), np.asarray(x2, dtype=np.float64))

    def surface_error(self, system: Any, *, points: int = 1001) -> dict[str, float]:
        """Largest and RMS difference table - system on a ``points x points`` grid offset from
        the table's nodes (a grid of the same span shifted by a third of its step, clipped),
        V."""
        axes = []
        for inp in system.inputs:
            lo, hi = inp.universe
            x = np.linspace(lo, hi, points) + (hi - lo) / (3.0 * (points - 1))
            axes.append(np.clip(x, lo, hi))
        e, de = np.meshgrid(*axes, indexing="ij")
        ref = np.asarray(system(e, de), dtype=np.float64)
        err = self.lookup(e.ravel(), de.ravel()).reshape(e.shape) - ref
        return {"max": float(np.abs(err).max()), "rms": float(np.sqrt(np.mean(err * err))),
                "points": points}

    def as_sugeno(self) -> T1Sugeno:
        """The type-1 zero-order Sugeno system equal to this table (module docstring): one
        triangular set per node and input, the product t-norm, one rule per node pair."""

        def sets(g: FloatArray, prefix: str) -> list[IT2Set]:
            out = []
            for k, x in enumerate(g):
                a = g[k - 1] if k else x
                c = g[k + 1] if k < g.size - 1 else x
                out.append(IT2Set.type1(Triangle(float(a), float(x), float(c)), f"{prefix}{k}"))
            return out

        se, sde = sets(self.e_nodes, "e"), sets(self.de_nodes, "d")
        inputs = (Input("e", (float(self.e_nodes[0]), float(self.e_nodes[-1])), se),
                  Input("de", (float(self.de_nodes[0]), float(self.de_nodes[-1])), sde))
        rules = rules_from_table([s.name for s in se], [s.name for s in sde],
                                 [[float(v) for v in row] for row in self.table])
        return T1Sugeno(inputs=inputs, rules=rules, tnorm=TNorm.PRODUCT, name=self.name)

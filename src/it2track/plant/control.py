"""python-control systems as it2track plants (DESIGN.md sec. 10; needs ``it2track[control]``).

:func:`from_control` takes any system of python-control (``control`` on PyPI):

* an LTI system (``ss``, ``tf``, an interconnection of them) becomes a
  :class:`~it2track.plant.linear.LinearSpec` of its state-space matrices: discretised exactly by
  zero-order hold at the loop's period if continuous, used as is if discrete (its ``dt`` must be
  the loop's period or ``True``). Nothing of python-control is needed to simulate it.
* a nonlinear system (``nlsys``, or an interconnection with nonlinear parts) becomes a
  :class:`NonlinearSpec`: a continuous one is integrated over each period by
  :func:`scipy.integrate.solve_ivp` with the input held (zero-order hold), run by run; a
  discrete one is stepped by its own update function (its ``dt`` must be the loop's period or
  ``True``).

The result goes into :class:`~it2track.tracking.LoopConfig` (``plant=``); names of inputs and
outputs come from the system's labels. The system's first output is the one a reference
signal controls; a system with inputs ``("v_right", "v_left")`` and outputs
:data:`~it2track.plant.base.ROBOT_OUTPUTS` is a robot and tracks trajectories.

python-control is imported only inside these functions.

Examples
--------
>>> import control as ct                                          # doctest: +SKIP
>>> from it2track.tracking import LoopConfig                      # doctest: +SKIP
>>> motor = ct.tf([0.1], [8.1e-7, 7.5e-4, 0.0105])                # doctest: +SKIP
>>> config = LoopConfig(duration=1.0, ts=0.001, plant=from_control(motor))  # doctest: +SKIP
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from numbers import Integral, Real
from typing import Any

import numpy as np
import scipy.integrate
from numpy.typing import ArrayLike, NDArray

from .._extras import require
from .linear import DT_RTOL, LinearSpec, limit_text

__all__ = ["NonlinearPlant", "NonlinearSpec", "from_control"]

FloatArray = NDArray[np.float64]

#: Methods of :func:`scipy.integrate.solve_ivp` a :class:`NonlinearSpec` may name.
IVP_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


def _control() -> Any:
    return require("control", "control", "a python-control system")


def from_control(
    sys: Any,
    *,
    input_limits: Any = None,
    x0: ArrayLike | None = None,
    method: str = "RK45",
    rtol: float = 1e-9,
    atol: float = 1e-12,
    params: Mapping[str, Any] | None = None,
) -> LinearSpec | NonlinearSpec:
    """An it2track plant description of a python-control system.

    Parameters
    ----------
    sys : control.InputOutputSystem
        ``StateSpace``, ``TransferFunction`` (LTI) or ``NonlinearIOSystem``.
    input_limits : sequence of (float, float), optional
        ``(low, high)`` per input; default unbounded.
    x0 : array_like, optional
        Initial state (default zeros).
    method : str
        Integration method for a continuous nonlinear system (one of :data:`IVP_METHODS`;
        ``"Radau"``/``"BDF"``/``"LSODA"`` for stiff ones). Ignored otherwise.
    rtol, atol : float
        Tolerances of that integration (defaults 1e-9, 1e-12).
    params : mapping, optional
        Parameters passed to a nonlinear system's functions (default: its own).

    Returns
    -------
    LinearSpec or NonlinearSpec
        Ready for ``LoopConfig(plant=...)``.

    Raises
    ------
    it2track._extras.MissingExtraError
        If python-control is not installed (an ``ImportError`` naming ``it2track[control]``).
    ValueError
        If ``sys`` is not a python-control system, a transfer function is improper (no
        state-space form), or an option is invalid.
    """
    ct = _control()
    if isinstance(sys, ct.LTI):
        try:
            ss = ct.ss(sys)
        except (ValueError, TypeError) as exc:
            raise ValueError(f"from_control: {sys.name!r} has no state-space form: {exc}") \
                from None
        dt = 0.0 if ss.dt is None else ss.dt
        if ss.nstates == 0:
            raise ValueError(f"from_control: {sys.name!r} is a static gain (no state); a plant "
                             "needs dynamics")
        return LinearSpec(
            a=np.asarray(ss.A), b=np.asarray(ss.B), c=np.asarray(ss.C), d=np.asarray(ss.D),
            dt=dt, input_limits=None if input_limits is None else _pairs(input_limits),
            x0=None if x0 is None else tuple(np.ravel(x0)),
            input_names=tuple(ss.input_labels), output_names=tuple(ss.output_labels),
            name=str(sys.name),
        )
    if isinstance(sys, ct.NonlinearIOSystem):
        return NonlinearSpec(system=sys, input_limits=None if input_limits is None
                             else _pairs(input_limits), x0=x0, method=method, rtol=rtol,
                             atol=atol, params=params)  # fmt: skip
    raise ValueError(f"from_control: sys={sys!r} is not a python-control system (ss, tf or "
                     "nlsys)")


def _pairs(limits: Any) -> tuple[tuple[float, float], ...]:
    try:
        return tuple((lo, hi) for lo, hi in limits)
    except (TypeError, ValueError):
        raise ValueError(f"input_limits={limits!r} must be (low, high) pairs, one per input") \
            from None


def _real(key: str, value: object, *, positive: bool) -> float:
    if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value) \
            or (positive and value <= 0):
        raise ValueError(f"NonlinearSpec: {key}={value!r} must be a finite number"
                         + (" > 0" if positive else ""))
    return float(value)


@dataclass(frozen=True, kw_only=True, eq=False)
class NonlinearSpec:
    """A python-control nonlinear system as a plant description (see :func:`from_control`).

    Parameters
    ----------
    system : control.NonlinearIOSystem
        Continuous (``dt = 0``) or discrete (``dt`` the loop's period, or ``True``).
    input_limits : sequence of (float, float), optional
        ``(low, high)`` per input; default unbounded.
    x0 : array_like, optional
        Initial state (default zeros).
    method : str
        :func:`scipy.integrate.solve_ivp` method for a continuous system (:data:`IVP_METHODS`).
    rtol, atol : float
        Its tolerances.
    params : mapping, optional
        Passed to the system's update and output functions.

    Raises
    ------
    ValueError
        Naming the field: not a nonlinear system, a negative ``dt``, limits not one
        ``low < high`` pair per input, ``x0`` of the wrong length or not finite, an unknown
        method, tolerances not finite and > 0.

    Notes
    -----
    Equality is identity (two specs of the same system object are different descriptions).
    It pickles when the system does (module-level functions, not lambdas).
    """

    system: Any
    input_limits: tuple[tuple[float, float], ...] | None = None
    x0: Any = None
    method: str = "RK45"
    rtol: float = 1e-9
    atol: float = 1e-12
    params: Mapping[str, Any] | None = None
    kind: str = field(default="nlsys", init=False)

    def __post_init__(self) -> None:
        ct = _control()
        sys = self.system
        if not isinstance(sys, ct.NonlinearIOSystem) or isinstance(sys, ct.LTI):
            raise ValueError(f"NonlinearSpec: system={sys!r} must be a python-control "
                             "NonlinearIOSystem (LTI systems go through from_control)")
        dt = sys.dt
        if dt is not None and dt is not True and not (isinstance(dt, int | float) and dt >= 0):
            raise ValueError(f"NonlinearSpec: the system's dt={dt!r} is not a timebase")
        m = sys.ninputs
        limits = self.input_limits
        pairs = ((-math.inf, math.inf),) * m if limits is None else limits
        ok = isinstance(pairs, tuple) and len(pairs) == m
        if ok:
            for pair in pairs:
                if not (isinstance(pair, tuple | list) and len(pair) == 2 and all(
                        isinstance(v, Real) and not isinstance(v, bool) for v in pair)
                        and pair[0] < pair[1]):
                    ok = False
        if not ok:
            raise ValueError(f"NonlinearSpec: input_limits={limits!r} must be one (low, high) "
                             f"pair of numbers with low < high per input ({m})")
        object.__setattr__(self, "input_limits",
                           tuple((float(lo), float(hi)) for lo, hi in pairs))
        x0 = np.zeros(sys.nstates) if self.x0 is None else np.ravel(
            np.asarray(self.x0, dtype=np.float64))
        if x0.shape != (sys.nstates,) or not np.isfinite(x0).all():
            raise ValueError(f"NonlinearSpec: x0={self.x0!r} must be {sys.nstates} finite "
                             "numbers")
        object.__setattr__(self, "x0", tuple(float(v) for v in x0))
        if self.method not in IVP_METHODS:
            raise ValueError(f"NonlinearSpec: method={self.method!r} must be one of "
                             f"{list(IVP_METHODS)}")
        object.__setattr__(self, "rtol", _real("rtol", self.rtol, positive=True))
        object.__setattr__(self, "atol", _real("atol", self.atol, positive=True))
        if self.params is not None and not isinstance(self.params, Mapping):
            raise ValueError(f"NonlinearSpec: params={self.params!r} must be a mapping")
        if self.params is not None:
            object.__setattr__(self, "params", dict(self.params))

    def build(self, *, ts: float, robot: object = None) -> NonlinearPlant:
        """The plant for control period ``ts`` (``robot`` is ignored).

        Parameters
        ----------
        ts : float
            Control period, s.
        robot : RobotParams, optional
            Ignored.

        Returns
        -------
        NonlinearPlant

        Raises
        ------
        ValueError
            If ``ts`` is not a finite number > 0 or a discrete system's ``dt`` differs from it.
        """
        return NonlinearPlant(self, ts)

    def to_dict(self) -> dict[str, Any]:
        """A description for records (it cannot be read back: the system is code).

        Returns
        -------
        dict
            ``kind = "nlsys"``, the system's name, dt, labels and the integration options.
        """
        sys = self.system
        return {
            "kind": self.kind, "name": str(sys.name),
            "dt": 0.0 if sys.dt is None else sys.dt,
            "inputs": list(sys.input_labels), "outputs": list(sys.output_labels),
            "states": list(sys.state_labels), "x0": list(self.x0),
            "input_limits": [[limit_text(v) for v in p] for p in self.input_limits or ()],
            "method": self.method, "rtol": self.rtol, "atol": self.atol,
        }  # fmt: skip


class NonlinearPlant:
    """A :class:`NonlinearSpec` at one control period (the runtime plant).

    Parameters
    ----------
    spec : NonlinearSpec
        The system and its options.
    ts : float
        Control period, s.

    Raises
    ------
    ValueError
        As :meth:`NonlinearSpec.build`.

    Notes
    -----
    The state is ``(x (n, B), u_prev (m, B), t)``. Every run is advanced on its own (one
    ``solve_ivp`` call per run and period for a continuous system), so its numbers do not depend
    on the batch; this is far slower than a linear plant and meant for small batches.
    """

    spec: NonlinearSpec
    ts: float
    continuous: bool
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    input_limits: tuple[tuple[float, float], ...]

    def __init__(self, spec: NonlinearSpec, ts: float) -> None:
        if not isinstance(spec, NonlinearSpec):
            raise ValueError(f"spec must be a NonlinearSpec, got {spec!r}")
        if isinstance(ts, bool) or not isinstance(ts, Real) or not math.isfinite(ts) or ts <= 0:
            raise ValueError(f"ts={ts!r} must be a finite number > 0")
        sys = spec.system
        dt = sys.dt
        self.continuous = bool(dt is None or (dt is not True and dt == 0))
        if not self.continuous and dt is not True and abs(dt - ts) > DT_RTOL * ts:
            raise ValueError(f"the system {sys.name!r} is discrete with dt={dt!r}, but the "
                             f"loop's period is ts={ts!r}")
        self.spec = spec
        self.ts = float(ts)
        self.input_names = tuple(sys.input_labels)
        self.output_names = tuple(sys.output_labels)
        self.input_limits = spec.input_limits or ()
        self._x0 = np.array(spec.x0, dtype=np.float64)

    def __repr__(self) -> str:
        return f"NonlinearPlant({self.spec.system.name!r}, ts={self.ts!r})"

    def initial_state(self, n: int) -> tuple[FloatArray, FloatArray, float]:
        """``n`` runs at ``x0`` at ``t = 0`` with no input applied yet.

        Parameters
        ----------
        n : int
            Number of runs (>= 0).

        Returns
        -------
        tuple
            ``(x (n_states, n), u_prev (n_inputs, n), t)``.
        """
        if isinstance(n, bool) or not isinstance(n, Integral) or n < 0:
            raise ValueError(f"n={n!r} must be an integer >= 0")
        x = np.repeat(self._x0[:, None], int(n), axis=1)
        return x, np.zeros((len(self.input_names), int(n))), 0.0

    def step(
        self, state: tuple[FloatArray, FloatArray, float], u: FloatArray, t: float
    ) -> tuple[FloatArray, FloatArray, float]:
        """One period from ``t`` with ``u`` held, run by run.

        Parameters
        ----------
        state : tuple
            ``(x, u_prev, t)``.
        u : ndarray, shape (n_inputs, B)
            Inputs (the loop saturates them).
        t : float
            Start of the period, s.

        Returns
        -------
        tuple
            ``(x, u, t + ts)`` (new arrays).

        Raises
        ------
        ValueError
            If the integration fails or the state becomes NaN or infinite (naming the run
            and time).
        """
        x, _, _ = state
        sys = self.spec.system
        params = self.spec.params
        nxt = np.empty_like(x)
        for r in range(x.shape[1] if x.shape[0] else 0):  # no state: nothing to advance
            ur = np.array(u[:, r], dtype=np.float64)
            if self.continuous:
                sol = scipy.integrate.solve_ivp(
                    lambda tt, xx, ur=ur: sys.dynamics(tt, xx, ur, params),
                    (t, t + self.ts), x[:, r], method=self.spec.method, rtol=self.spec.rtol,
                    atol=self.spec.atol,
                )
                if not sol.success:
                    raise ValueError(f"{sys.name!r}: integration failed for run {r} at "
                                     f"t={t:g} s: {sol.message}")
                nxt[:, r] = sol.y[:, -1]
            else:
                nxt[:, r] = np.asarray(sys.dynamics(t, x[:, r], ur, params), dtype=np.float64)
        if not np.isfinite(nxt).all():
            bad = int(np.flatnonzero(~np.isfinite(nxt).all(axis=0))[0])
            raise ValueError(f"{sys.name!r}: the state of run {bad} is not finite at "
                             f"t={t + self.ts:g} s")
        return nxt, np.array(u, dtype=np.float64, copy=True), t + self.ts

    def outputs(self, state: tuple[FloatArray, FloatArray, float]) -> FloatArray:
        """The system's outputs at the state's time with the previous input, ``(p, B)``.

        Parameters
        ----------
        state : tuple
            ``(x, u_prev, t)``.

        Returns
        -------
        ndarray, shape (n_outputs, B)
        """
        x, u_prev, t = state
        sys = self.spec.system
        y = np.empty((len(self.output_names), x.shape[1]))
        for r in range(x.shape[1]):
            y[:, r] = np.asarray(sys.output(t, x[:, r], u_prev[:, r], self.spec.params),
                                 dtype=np.float64).reshape(-1)
        return y

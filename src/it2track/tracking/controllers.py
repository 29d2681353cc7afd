"""Heading controllers: map the heading error ``e`` and its change ``de`` to a voltage ``u``.

A heading controller is evaluated on a batch of runs at each control instant::

    state = controller.initial_state(n, ts)      # ndarray (n_state, n), possibly (0, n)
    u = controller.output(e, de, state)           # e, de, u: (n,); updates state in place

``e`` and ``de`` are views of the loop's work buffers, valid during the call only: a
controller must not modify them, and copies what it keeps (e.g. into ``state``).

The closed loop turns ``u`` into wheel voltages ``V_R = V0 + u``, ``V_L = V0 - u`` (DESIGN.md
sec. 5). Controllers are immutable descriptions (frozen dataclasses), so one controller object
can serve any number of runs; their per-run memory lives in ``state``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..fuzzy import IT2Mamdani, IT2Sugeno, T1Mamdani, T1Sugeno

__all__ = [
    "FuzzyHeadingController",
    "HeadingController",
    "IncrementalController",
    "PDHeadingController",
]

FloatArray = NDArray[np.float64]


class HeadingController:
    """Interface of a batch heading controller (see the module docstring).

    Two optional capabilities, off by default, serve controllers that run somewhere real (the
    processor-in-the-loop controller, :mod:`it2track.tracking.pil`):

    - ``delays_output = True``: the output computed at ``t_k`` reaches the motors
      :meth:`output_delay` seconds later (in ``[0, ts]``); until then they keep the previous
      period's voltages (0 V before the first output). The loop advances the robot exactly
      over the two parts of the period
      (:class:`~it2track.plant.switched.SwitchedDrive`).
    - ``trace_series``: names of per-step values the controller reports
      (:meth:`step_series`), which :func:`~it2track.tracking.simulate` records beside its own
      series (NaN for runs of other controllers).
    """

    name: str
    #: Whether :meth:`output_delay` gives the instant each output reaches the motors.
    delays_output: bool = False
    #: Names of the extra per-step series :meth:`step_series` reports.
    trace_series: tuple[str, ...] = ()

    def initial_state(self, n: int, ts: float) -> FloatArray:
        """Per-run state at ``t = 0`` for ``n`` runs, period ``ts``: ``(n_state, n)``."""
        return np.zeros((0, n))

    def output(self, e: FloatArray, de: FloatArray, state: FloatArray) -> FloatArray:
        """Control voltage ``u`` (shape ``(n,)``) for errors ``e`` and changes ``de``."""
        raise NotImplementedError

    def output_delay(self, state: FloatArray) -> FloatArray:
        """Seconds after ``t_k`` at which the output just computed reaches the motors, per
        run (shape ``(n,)``, in ``[0, ts]``); called after :meth:`output` when
        ``delays_output``."""
        raise NotImplementedError

    def step_series(self, state: FloatArray) -> dict[str, FloatArray]:
        """The :attr:`trace_series` values of the step just computed, each of shape ``(n,)``."""
        return {}


#: Largest magnitude of a gain: beyond it a controller is pure bang-bang anyway (inputs are
#: clipped to [-1, 1], outputs to the voltage limit) and products such as ``kp * e + kd * D``
#: could overflow to inf - inf = NaN.
MAX_GAIN = 1e6
_GAINS = ("ke", "kde", "kp", "kd")


def _check(owner: str, **values: float) -> None:
    for key, value in values.items():
        ok = isinstance(value, int | float) and not isinstance(value, bool)
        if not ok or not math.isfinite(value):
            raise ValueError(f"{owner}: {key}={value!r} must be a finite number")
        if key in _GAINS and abs(value) > MAX_GAIN:
            raise ValueError(
                f"{owner}: {key}={value!r} exceeds {MAX_GAIN:g} in magnitude (such a "
                "controller is bang-bang, and its arithmetic could overflow)"
            )


@dataclass(frozen=True, kw_only=True)
class FuzzyHeadingController(HeadingController):
    """Fuzzy heading controller: ``u = fls(clip(ke e), clip(kde de))`` (paper Fig. 3).

    Parameters
    ----------
    fls : IT2Sugeno, T1Sugeno, IT2Mamdani or T1Mamdani
        A two-input system (error, change of error); its inputs are clipped to its universes.
        Sugeno and TSK systems with the paper's rule form run on the compiled engine where it
        is available; every other system (Mamdani, or rules using NOT/OR/weights) runs on the
        numpy evaluation.
    ke, kde : float
        Input gains (default 1, as in the paper).
    name : str
        Label used in results (default: the system's name).
    fls_output : int or str, optional
        For a system with several outputs, the one that drives the wheels (its index or name);
        ``fls`` is then replaced by that one-output system (``fls.select_output(...)``).
        A system with several outputs and no ``fls_output`` is refused.
    """

    fls: IT2Sugeno | T1Sugeno | IT2Mamdani | T1Mamdani
    ke: float = 1.0
    kde: float = 1.0
    name: str = ""
    fls_output: int | str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.fls, IT2Sugeno | T1Sugeno | IT2Mamdani | T1Mamdani):
            raise ValueError(
                f"fls must be an IT2Sugeno, T1Sugeno, IT2Mamdani or T1Mamdani, got "
                f"{type(self.fls).__name__}"
            )
        if self.fls.n_inputs != 2:
            raise ValueError(f"fls must have 2 inputs (e, de), has {self.fls.n_inputs}")
        if self.fls_output is not None:
            object.__setattr__(self, "fls", self.fls.select_output(self.fls_output))
        elif self.fls.n_outputs != 1:
            raise ValueError(
                f"fls {self.fls.name!r} has {self.fls.n_outputs} outputs "
                f"({', '.join(self.fls.output_names)}); choose the one that drives the wheels "
                "with fls_output=<name or index>"
            )
        _check("FuzzyHeadingController", ke=self.ke, kde=self.kde)
        if not self.name:
            object.__setattr__(self, "name", self.fls.name or "fuzzy")

    def output(self, e: FloatArray, de: FloatArray, state: FloatArray) -> FloatArray:
        x1 = e * self.ke if self.ke != 1.0 else e
        x2 = de * self.kde if self.kde != 1.0 else de
        if x1.size == 1:
            # One run: the system's scalar fast path (bit-for-bit equal to the array path)
            # costs ~10 us instead of ~90 us of numpy call overhead.
            return np.array([self.fls(float(x1[0]), float(x2[0]))], dtype=np.float64)
        return np.asarray(self.fls(x1, x2), dtype=np.float64)


@dataclass(frozen=True, kw_only=True)
class PDHeadingController(HeadingController):
    """PD heading controller with a first-order filter on the derivative.

    ``u = clip(kp e + kd D, -u_max, u_max)``, where ``D`` is the derivative of ``e`` through
    the filter ``1 / (tf s + 1)``, discretised by backward Euler on the control grid::

        D_k = (tf D_{k-1} + de_k) / (tf + ts),     D_0 = 0

    (``de_k = e_k - e_{k-1}``; ``tf = 0`` gives the raw backward difference ``de_k / ts``).

    Parameters
    ----------
    kp : float
        Proportional gain, V/rad.
    kd : float
        Derivative gain, V s/rad.
    tf : float
        Derivative filter time constant, s (>= 0).
    u_max : float
        Output limit, V (default 12, the fuzzy controllers' output range).
    name : str
    """

    kp: float
    kd: float = 0.0
    tf: float = 0.02
    u_max: float = 12.0
    name: str = "PD"

    def __post_init__(self) -> None:
        _check("PDHeadingController", kp=self.kp, kd=self.kd, tf=self.tf, u_max=self.u_max)
        if self.tf < 0:
            raise ValueError(f"PDHeadingController: tf={self.tf!r} must be >= 0")
        if self.u_max <= 0:
            raise ValueError(f"PDHeadingController: u_max={self.u_max!r} must be > 0")

    def initial_state(self, n: int, ts: float) -> FloatArray:
        # Row 0: filtered derivative D; row 1 holds ts (constant) so output() needs no extra
        # argument.
        state = np.zeros((2, n))
        state[1] = ts
        return state

    def output(self, e: FloatArray, de: FloatArray, state: FloatArray) -> FloatArray:
        d = state[0]
        ts = state[1]
        d *= self.tf
        d += de
        d /= self.tf + ts
        u = self.kp * e + self.kd * d
        return np.clip(u, -self.u_max, self.u_max)


@dataclass(frozen=True, kw_only=True)
class IncrementalController(HeadingController):
    """Incremental (velocity-form) controller: the inner controller's output is a *change*.

    ``u_k = clip(u_(k-1) + gain * inner(e_k, de_k), u_min, u_max)``, ``u_(-1) = u0``. With a
    fuzzy PD-type ``inner`` (``e``, ``de`` in) this is the classical fuzzy PI controller: the
    integral action removes the steady-state error of a speed or level loop, and clipping the
    accumulated ``u`` to the actuator range is its anti-windup.

    Parameters
    ----------
    inner : HeadingController
        Maps ``(e, de)`` to the increment (e.g. a :class:`FuzzyHeadingController`).
    gain : float
        Scale of the increment (default 1).
    u_min, u_max : float
        Range of the accumulated output (``u_min < u_max``; default -12, 12).
    u0 : float
        Output before the first instant (default 0), inside ``[u_min, u_max]``.
    name : str
        Label in results (default ``"PI(" + inner.name + ")"``).

    Raises
    ------
    ValueError
        If ``inner`` is not a HeadingController or a number is not finite or out of order.

    Examples
    --------
    >>> import numpy as np
    >>> pi = IncrementalController(inner=PDHeadingController(kp=1.0, kd=0.0, tf=0.0), u_max=2.5)
    >>> state = pi.initial_state(1, 0.01)
    >>> [float(pi.output(np.array([1.0]), np.array([0.0]), state)[0]) for _ in range(3)]
    [1.0, 2.0, 2.5]
    """

    inner: HeadingController
    gain: float = 1.0
    u_min: float = -12.0
    u_max: float = 12.0
    u0: float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.inner, HeadingController):
            raise ValueError(f"IncrementalController: inner={self.inner!r} must be a "
                             "HeadingController")
        _check("IncrementalController", gain=self.gain, u_min=self.u_min, u_max=self.u_max,
               u0=self.u0)
        if not self.u_min < self.u_max:
            raise ValueError(f"IncrementalController: u_min={self.u_min!r} must be < "
                             f"u_max={self.u_max!r}")
        if not self.u_min <= self.u0 <= self.u_max:
            raise ValueError(f"IncrementalController: u0={self.u0!r} must lie in "
                             f"[u_min, u_max] = [{self.u_min!r}, {self.u_max!r}]")
        if not self.name:
            object.__setattr__(self, "name", f"PI({self.inner.name})")

    def initial_state(self, n: int, ts: float) -> FloatArray:
        # Row 0: the accumulated output; the rows below: the inner controller's state.
        inner = self.inner.initial_state(n, ts)
        state = np.empty((1 + inner.shape[0], n))
        state[0] = self.u0
        state[1:] = inner
        return state

    def output(self, e: FloatArray, de: FloatArray, state: FloatArray) -> FloatArray:
        inner = state[1:]
        du = self.inner.output(e, de, inner)
        acc = state[0]
        acc += self.gain * du if self.gain != 1.0 else du
        np.clip(acc, self.u_min, self.u_max, out=acc)
        return acc.copy()

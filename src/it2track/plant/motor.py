"""Armature-controlled DC motor (paper §II.A, Table 3).

Each wheel is driven by a permanent-magnet DC motor with state ``(i, omega)``
(armature current in A, shaft speed in rad/s)::

    L di/dt     = V - R i - K omega
    J domega/dt = K i - b omega

The model is linear and stiff (for the Table-3 values the electrical pole is
about -912 s^-1, the mechanical one about -14.2 s^-1), so it is discretised
exactly (zero-order hold, matrix exponential) rather than with an explicit
fixed-step integrator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from numbers import Real

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike, NDArray

__all__ = ["MotorParams"]


#: Largest value of any motor parameter in SI units (ohm, H, kg m^2, N m s, N m/A, V): far
#: beyond any motor, far below where the discretisation's products overflow.
MAX_MOTOR_PARAMETER = 1e12


def _check_positive_finite(obj: object) -> None:
    """Coerce every dataclass field of ``obj`` to ``float``; require finite and > 0.

    Raises
    ------
    ValueError
        Naming the first offending field and its value.
    """
    for f in fields(obj):  # type: ignore[arg-type]
        value = getattr(obj, f.name)
        if isinstance(value, bool) or not isinstance(value, Real):
            raise ValueError(f"{f.name} must be a real number, got {value!r}")
        value = float(value)
        if not (math.isfinite(value) and value > 0.0):
            raise ValueError(f"{f.name} must be finite and > 0, got {value!r}")
        if value > MAX_MOTOR_PARAMETER:
            raise ValueError(f"{f.name} must be at most {MAX_MOTOR_PARAMETER:g} (SI units), "
                             f"got {value!r}")
        object.__setattr__(obj, f.name, value)


@dataclass(frozen=True, kw_only=True)
class MotorParams:
    """Parameters of one armature-controlled DC motor (defaults: paper Table 3).

    Parameters
    ----------
    resistance : float, default 5.0
        Armature resistance R in ohm.
    inductance : float, default 0.0054
        Armature inductance L in H.
    inertia : float, default 0.00015
        Rotor (plus wheel) inertia J in kg m^2.
    friction : float, default 0.0001
        Viscous friction coefficient b in N m s.
    torque_constant : float, default 0.1
        Torque constant K in N m / A, equal to the back-emf constant in V s / rad.
    voltage_limit : float, default 12.0
        Supply limit in V: admissible voltages satisfy ``|V| <= voltage_limit``.

    Raises
    ------
    ValueError
        If any field is not a finite real number in (0, 1e12]; the message names the field
        and the offending value.

    Examples
    --------
    >>> m = MotorParams()
    >>> round(m.dc_gain, 6)
    9.52381
    >>> m.saturate([-20.0, 3.0, 15.0]).tolist()
    [-12.0, 3.0, 12.0]
    """

    resistance: float = 5.0
    inductance: float = 0.0054
    inertia: float = 0.00015
    friction: float = 0.0001
    torque_constant: float = 0.1
    voltage_limit: float = 12.0

    def __post_init__(self) -> None:
        _check_positive_finite(self)

    @property
    def dc_gain(self) -> float:
        """Steady-state shaft speed per volt, ``K / (R b + K^2)`` in rad/s/V."""
        k = self.torque_constant
        return k / (self.resistance * self.friction + k * k)

    def state_matrices(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Continuous-time state-space matrices of ``d(i, omega)/dt = A (i, omega) + B V``.

        Returns
        -------
        A : ndarray, shape (2, 2)
            ``[[-R/L, -K/L], [K/J, -b/J]]``.
        B : ndarray, shape (2,)
            ``[1/L, 0]``.
        """
        r, l_, j = self.resistance, self.inductance, self.inertia
        b, k = self.friction, self.torque_constant
        a = np.array([[-r / l_, -k / l_], [k / j, -b / j]])
        bvec = np.array([1.0 / l_, 0.0])
        return a, bvec

    def discrete_matrices(self, ts: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Exact zero-order-hold discretisation over one period.

        With the voltage held at ``V`` on ``[t_k, t_k + ts)``, the state after one
        period is exactly ``x_{k+1} = Ad x_k + Bd V``, where
        ``expm([[A, B], [0, 0]] ts) = [[Ad, Bd], [0, 1]]``.

        Parameters
        ----------
        ts : float
            Period in s, finite and > 0.

        Returns
        -------
        Ad : ndarray, shape (2, 2)
            State transition matrix ``expm(A ts)``.
        Bd : ndarray, shape (2,)
            Input vector ``int_0^ts expm(A s) ds B``.

        Raises
        ------
        ValueError
            If ``ts`` is not finite and > 0.
        """
        ts = _check_period(ts)
        a, bvec = self.state_matrices()
        aug = np.zeros((3, 3))
        aug[:2, :2] = a
        aug[:2, 2] = bvec
        e = scipy.linalg.expm(aug * ts)
        return e[:2, :2].copy(), e[:2, 2].copy()

    def saturate(self, v: ArrayLike) -> NDArray[np.float64]:
        """Clip voltages to ``[-voltage_limit, voltage_limit]``.

        Parameters
        ----------
        v : array_like, any shape
            Voltages in V.

        Returns
        -------
        ndarray of float, same shape as ``v``
            The clipped voltages (a new array).
        """
        return np.clip(np.asarray(v, dtype=np.float64), -self.voltage_limit, self.voltage_limit)


def _check_period(ts: object, name: str = "ts") -> float:
    """Return ``ts`` as a float after checking it is a finite real number > 0."""
    if isinstance(ts, bool) or not isinstance(ts, Real):
        raise ValueError(f"{name} must be a real number, got {ts!r}")
    value = float(ts)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be finite and > 0, got {ts!r}")
    return value

"""The plant protocol: what the closed loop needs from any plant (DESIGN.md sec. 1 and 10).

A *plant* is a batch of ``B`` independent copies of one dynamic system, sampled every control
period ``ts``. The closed loop (:mod:`it2track.tracking`) drives it through these members and
knows nothing else about it::

    state = plant.initial_state(B)                  # B runs at rest (robots: pose=...)
    for k in range(N + 1):
        y = plant.outputs(state)                    # (n_outputs, B): measured at t_k
        u = ...                                     # (n_inputs, B): controller + task, saturated
        if k < N:                                   # to plant.input_limits
            state = plant.step(state, u, k * ts)    # one period, u held (zero-order hold)

**Members of a plant.**

``ts`` : float
    The control period, s, the plant was built (discretised) for.
``input_names``, ``output_names`` : tuple of str
    Names of the rows of ``u`` and of ``outputs(state)``, in order.
``input_limits`` : tuple of (float, float)
    Per input, the ``(low, high)`` range the actuator accepts (``(-inf, inf)`` for none). The
    loop saturates ``u`` to it before :meth:`Plant.step` and counts the saturated periods.
``initial_state(n)``
    The state of ``n`` runs at the plant's initial condition. The state is *opaque*: any
    object the plant understands (a tuple of arrays, a list of simulator handles...). The loop
    only passes it back to ``step`` and ``outputs``.
``step(state, u, t)``
    Advance every run by one period ``[t, t + ts)`` with ``u`` (shape ``(n_inputs, B)``,
    float64, already saturated) held constant; return the new state (a new object, or
    ``state`` updated in place). ``u`` belongs to the caller: do not modify or keep it.
``outputs(state)``
    The measured outputs at the state's instant, shape ``(n_outputs, B)`` float64, a function of
    the state only (the output at ``t_k`` is read before the input of period ``k`` is chosen:
    a plant with direct feedthrough reports the output just before the new input is applied).
    The caller may read it until the next ``step`` and must not modify it.
``step_switched(state, u_before, u_after, switch, t)`` (optional)
    Like ``step``, but run ``b``'s inputs are ``u_before[:, b]`` over ``[t, t + switch[b])``
    and ``u_after[:, b]`` over the rest of the period (``switch`` shape ``(B,)``, in
    ``[0, ts]``). The loop uses it only for controllers that apply their outputs late
    (processor in the loop with a latency, :mod:`it2track.tracking.pil`); a switch at 0 must
    equal ``step`` with ``u_after`` bit for bit. The kinematic robot implements it exactly.

**Rules every plant follows.**

* **Batch independence.** Run ``b``'s numbers depend on run ``b``'s initial state and inputs
  only, bit for bit, whatever the batch size or the other runs: no reductions or BLAS calls
  across runs (their summation order changes with the batch), no shared random state. This is
  what makes results independent of ``batch_size``, workers and engine.
* **Determinism.** The same inputs give the same bits on every call; randomness, if any, comes
  from an explicit seed fixed at construction.
* **No noise.** Outputs are the true ones; the loop adds measurement noise (common random
  numbers shared across controllers are the loop's business).

**Robots.** The heading-tracking task (the paper's loop, DESIGN.md sec. 5) needs a
:class:`RobotPlant`: a differential-drive robot with inputs :data:`ROBOT_INPUTS` (wheel
voltages, V) and outputs :data:`ROBOT_OUTPUTS` (pose, wheel speeds, body speeds), whose
``initial_state`` also takes the start ``pose`` of every run (at rest there). The paper's
kinematic robot (:class:`~it2track.plant.kinematic.KinematicPlant`) is the reference
implementation.

**Describing a plant in a configuration.** A :class:`~it2track.tracking.LoopConfig` names
its plant by a :class:`PlantSpec`: a frozen, picklable description (safe to send to worker
processes) whose ``build(ts=..., robot=...)`` returns the :class:`Plant` for one control
period and one robot geometry (robot plants build from ``robot``; other plants ignore it).
``kind`` names the family in TOML tables (``[plant] kind = "..."``) and ``to_dict()`` gives the
table back (plain values, including ``kind``). ``LoopConfig(plant=None)`` is the paper's
kinematic robot, which the compiled engine runs; every other plant runs on the numpy engine
through this protocol.
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from .drive import RobotParams

__all__ = [
    "ROBOT_INPUTS",
    "ROBOT_OUTPUTS",
    "Plant",
    "PlantSpec",
    "RobotPlant",
    "check_plant",
    "check_robot_plant",
]

FloatArray = NDArray[np.float64]

#: Inputs of a :class:`RobotPlant`: right and left wheel-motor voltages, V.
ROBOT_INPUTS: tuple[str, ...] = ("v_right", "v_left")
#: Outputs of a :class:`RobotPlant`: pose ``x`` (m), ``y`` (m), heading ``theta`` (rad,
#: not wrapped), wheel speeds ``omega_right``, ``omega_left`` (rad/s), body translational speed
#: ``v`` (m/s) and rotational speed ``omega`` (rad/s).
ROBOT_OUTPUTS: tuple[str, ...] = (
    "x", "y", "theta", "omega_right", "omega_left", "v", "omega",
)  # fmt: skip


@runtime_checkable
class Plant(Protocol):
    """A batch of runs of one dynamic system sampled every ``ts`` (see the module docstring).

    Attributes
    ----------
    ts : float
        Control period, s.
    input_names : tuple of str
        Names of the input rows.
    output_names : tuple of str
        Names of the output rows.
    input_limits : tuple of (float, float)
        ``(low, high)`` per input.
    """

    ts: float
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    input_limits: tuple[tuple[float, float], ...]

    def initial_state(self, n: int) -> Any:
        """State of ``n`` runs at the plant's initial condition.

        Parameters
        ----------
        n : int
            Number of runs B (>= 0).

        Returns
        -------
        object
            The state, opaque to the caller.
        """
        ...

    def step(self, state: Any, u: FloatArray, t: float) -> Any:
        """Advance every run by one period with its inputs held.

        Parameters
        ----------
        state : object
            From :meth:`initial_state` or a previous :meth:`step`.
        u : ndarray, shape (n_inputs, B)
            Inputs held over ``[t, t + ts)``, saturated to ``input_limits``; read-only.
        t : float
            Start of the period, s.

        Returns
        -------
        object
            The state at ``t + ts`` (a new object or ``state`` updated in place).
        """
        ...

    def outputs(self, state: Any) -> FloatArray:
        """Measured outputs at the state's instant (before the next input is applied).

        Parameters
        ----------
        state : object
            A state of this plant.

        Returns
        -------
        ndarray, shape (n_outputs, B)
            Read-only for the caller, valid until the next :meth:`step`.
        """
        ...


@runtime_checkable
class RobotPlant(Plant, Protocol):
    """A differential-drive robot: :data:`ROBOT_INPUTS` in, :data:`ROBOT_OUTPUTS` out."""

    def initial_state(self, n: int, pose: FloatArray | None = None) -> Any:
        """``n`` robots at rest (motors unpowered, wheels still) at ``pose``.

        Parameters
        ----------
        n : int
            Number of runs B (>= 0).
        pose : ndarray, shape (3, n), optional
            Rows x (m), y (m), theta (rad); default zeros.

        Returns
        -------
        object
            The state, opaque to the caller.
        """
        ...


@runtime_checkable
class PlantSpec(Protocol):
    """A frozen, picklable description of a plant that builds it for a control period.

    Attributes
    ----------
    kind : str
        The family's name in TOML (``[plant] kind = ...``).
    """

    kind: str

    def build(self, *, ts: float, robot: RobotParams) -> Plant:
        """The plant, discretised for one control period.

        Parameters
        ----------
        ts : float
            Control period, s.
        robot : RobotParams
            The loop's robot geometry and motors (robot plants build from them; other plants
            ignore them).

        Returns
        -------
        Plant
            With ``plant.ts == ts``.

        Raises
        ------
        ValueError
            If the description cannot be realised at this period (naming what and why).
        """
        ...

    def to_dict(self) -> dict[str, Any]:
        """The description as plain values.

        Returns
        -------
        dict
            TOML/JSON-ready, ``kind`` included.
        """
        ...


def check_plant(plant: object, ts: float, *, what: str = "plant") -> Plant:
    """Check that ``plant`` follows the :class:`Plant` protocol for control period ``ts``.

    Parameters
    ----------
    plant : object
        The candidate.
    ts : float
        The loop's control period, s; ``plant.ts`` must equal it.
    what : str
        How error messages name the plant.

    Returns
    -------
    Plant
        ``plant`` itself.

    Raises
    ------
    ValueError
        If a member is missing, the names are not unique strings, the limits are not one
        ``(low, high)`` pair per input with ``low < high`` (NaN refused), or ``plant.ts``
        differs from ``ts``.
    """
    if not isinstance(plant, Plant):
        missing = [m for m in ("ts", "input_names", "output_names", "input_limits",
                               "initial_state", "step", "outputs")
                   if not hasattr(plant, m)]  # fmt: skip
        raise ValueError(f"{what} {plant!r} is not a Plant: it lacks {', '.join(missing)}")
    for attr in ("input_names", "output_names"):
        names = getattr(plant, attr)
        if (not isinstance(names, tuple) or not names
                or not all(isinstance(s, str) and s for s in names)
                or len(set(names)) != len(names)):
            raise ValueError(f"{what}.{attr}={names!r} must be a non-empty tuple of distinct, "
                             "non-empty strings")
    limits = plant.input_limits
    ok = isinstance(limits, tuple) and len(limits) == len(plant.input_names)
    if ok:
        for pair in limits:
            if not (isinstance(pair, tuple) and len(pair) == 2
                    and all(isinstance(v, float | int) and not isinstance(v, bool) for v in pair)
                    and pair[0] < pair[1]):
                ok = False
    if not ok:
        raise ValueError(
            f"{what}.input_limits={limits!r} must hold one (low, high) pair of numbers with "
            f"low < high per input ({len(plant.input_names)} inputs)"
        )
    if plant.ts != ts:
        raise ValueError(f"{what}.ts={plant.ts!r} differs from the loop's control period "
                         f"ts={ts!r}")
    return plant


def check_robot_plant(plant: object, ts: float, *, what: str = "plant") -> RobotPlant:
    """:func:`check_plant`, plus the robot's input and output names.

    Parameters
    ----------
    plant : object
        The candidate.
    ts : float
        The loop's control period, s.
    what : str
        How error messages name the plant.

    Returns
    -------
    RobotPlant
        ``plant`` itself.

    Raises
    ------
    ValueError
        As :func:`check_plant`, or if the inputs are not :data:`ROBOT_INPUTS` or the outputs
        not :data:`ROBOT_OUTPUTS` (the heading-tracking task drives wheel voltages and reads
        the pose).
    """
    p = check_plant(plant, ts, what=what)
    names = (p.input_names, p.output_names)
    if not isinstance(p, RobotPlant) or names != (ROBOT_INPUTS, ROBOT_OUTPUTS):
        raise ValueError(
            f"{what} has inputs {p.input_names} and outputs {p.output_names}; tracking a "
            f"trajectory needs a robot plant with inputs {ROBOT_INPUTS} and outputs "
            f"{ROBOT_OUTPUTS} (a single-input plant tracks a reference signal instead)"
        )
    return p

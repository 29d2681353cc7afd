"""When controller outputs reach the plant, and what controllers report per step: the loop's
side of :attr:`HeadingController.delays_output <.controllers.HeadingController.delays_output>`
and :attr:`~.controllers.HeadingController.trace_series`.

Both reference engines (the heading task, :mod:`.heading`, and the reference task,
:mod:`.siso`) make one :class:`Actuation` per batch. Without a delaying controller in the batch
the plant steps as before (``plant.step`` with this period's inputs), bit for bit. With one,
each run's inputs change inside the period: the previous period's inputs (0 before the first
output) until the run's delay, this period's after it, through the plant's optional
``step_switched`` member (:mod:`it2track.plant.base`; the kinematic robot has it, exactly:
:class:`~it2track.plant.switched.SwitchedDrive`). Runs of controllers that do not delay switch
at 0, which is exactly the plain step.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .controllers import HeadingController

__all__ = ["Actuation"]

FloatArray = NDArray[np.float64]


class Actuation:
    """Per-batch state of output delays and reported series (see the module docstring).

    Parameters
    ----------
    groups : sequence of (HeadingController, slice)
        The batch's controllers and their runs (contiguous slices).
    plant : Plant
        The plant the batch drives.
    n_inputs : int
        Rows of the plant's input.
    n_steps : int
        Control periods N (series have N + 1 rows).
    record : bool
        Whether reported series are kept.

    Raises
    ------
    ValueError
        If a controller delays its output and the plant has no ``step_switched``.
    """

    def __init__(self, groups: Sequence[tuple[HeadingController, slice]], plant: Any,
                 n_inputs: int, n_steps: int, *, record: bool) -> None:
        n = max((sl.stop for _, sl in groups), default=0)
        self.plant = plant
        delaying = [c for c, _ in groups if c.delays_output]
        self.delayed = bool(delaying)
        if self.delayed and not callable(getattr(plant, "step_switched", None)):
            raise ValueError(
                f"{delaying[0].name} applies its output late, which needs a plant that can "
                f"switch its inputs inside a period (step_switched); {plant!r} cannot (the "
                "kinematic robot can)")
        self.delay = np.zeros(n)
        self.before = np.zeros((n_inputs, n))  # the plant's inputs are 0 until the first output
        names: dict[str, None] = {}
        if record:
            for c, _ in groups:
                names.update(dict.fromkeys(c.trace_series))
        self.series = {name: np.full((n_steps + 1, n), np.nan) for name in names}

    def after_output(self, k: int, controller: HeadingController, runs: slice,
                     state: FloatArray) -> None:
        """Collect the delay and the reported values of ``controller``'s runs at step ``k``.

        Parameters
        ----------
        k : int
            The control instant.
        controller : HeadingController
            The controller that just computed its output.
        runs : slice
            Its runs in the batch.
        state : ndarray
            Its state after :meth:`~.controllers.HeadingController.output`.
        """
        if controller.delays_output:
            self.delay[runs] = controller.output_delay(state)
        if self.series and controller.trace_series:
            for name, value in controller.step_series(state).items():
                self.series[name][k, runs] = value

    def step(self, plant_state: Any, u: FloatArray, t: float) -> Any:
        """Advance the plant one period with inputs ``u`` applied as the delays say.

        Parameters
        ----------
        plant_state : object
            The plant's state.
        u : ndarray, shape (n_inputs, B)
            This period's (saturated) inputs.
        t : float
            Start of the period, s.

        Returns
        -------
        object
            The plant's next state.
        """
        if not self.delayed:
            return self.plant.step(plant_state, u, t)
        out = self.plant.step_switched(plant_state, self.before, u, self.delay, t)
        self.before[...] = u
        return out

    def recorded(self) -> dict[str, FloatArray]:
        """The reported series, ``(N + 1, B)`` each, in the batch's run order."""
        return self.series

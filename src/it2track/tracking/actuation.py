"""When controller outputs reach the motors, and what controllers report per step: the loop's
side of :attr:`HeadingController.delays_output <.controllers.HeadingController.delays_output>`
and :attr:`~.controllers.HeadingController.trace_series`.

The reference engine (:mod:`.simulate`) makes one :class:`Actuation` per batch. Without a
delaying controller in the batch it steps the robot as before (``drive.step`` with this
period's voltages), bit for bit. With one, each run's voltages switch inside the period: the
previous period's voltages (0 V before the first output) until the run's delay, this period's
after it (:class:`~it2track.plant.switched.SwitchedDrive`); runs of controllers that do not
delay switch at 0, which is exactly the plain step.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..plant import DifferentialDrive
from ..plant.switched import SwitchedDrive
from .controllers import HeadingController

__all__ = ["Actuation"]

FloatArray = NDArray[np.float64]


@functools.lru_cache(maxsize=8)
def _switched(drive: DifferentialDrive) -> SwitchedDrive:
    """One :class:`SwitchedDrive` per drive, so its cache of sub-period maps is shared."""
    return SwitchedDrive(drive)


class Actuation:
    """Per-batch state of output delays and reported series (see the module docstring).

    Parameters
    ----------
    groups : sequence of (HeadingController, slice)
        The batch's controllers and their runs (contiguous slices).
    drive : DifferentialDrive
        The robot.
    n_steps : int
        Control periods N (series have N + 1 rows).
    record : bool
        Whether reported series are kept.
    """

    def __init__(self, groups: Sequence[tuple[HeadingController, slice]],
                 drive: DifferentialDrive, n_steps: int, *, record: bool) -> None:
        n = max((sl.stop for _, sl in groups), default=0)
        self.drive = drive
        self.delayed = any(c.delays_output for c, _ in groups)
        self.delay = np.zeros(n)
        self.volts_before = np.zeros((2, n))  # motors unpowered until the first output lands
        names: dict[str, None] = {}
        if record:
            for c, _ in groups:
                names.update(dict.fromkeys(c.trace_series))
        self.series = {name: np.full((n_steps + 1, n), np.nan) for name in names}

    def after_output(self, k: int, controller: HeadingController, runs: slice,
                     state: FloatArray) -> None:
        """Collect the delay and the reported values of ``controller``'s runs at step ``k``."""
        if controller.delays_output:
            self.delay[runs] = controller.output_delay(state)
        if self.series and controller.trace_series:
            for name, value in controller.step_series(state).items():
                self.series[name][k, runs] = value

    def step(self, pose: FloatArray, wheels: FloatArray,
             volts: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Advance the robot one period with ``volts`` applied as the delays say."""
        if not self.delayed:
            return self.drive.step(pose, wheels, volts)
        out = _switched(self.drive).step(pose, wheels, self.volts_before, volts, self.delay)
        self.volts_before[...] = volts
        return out

    def recorded(self) -> dict[str, FloatArray]:
        """The reported series, ``(N + 1, B)`` each, in the batch's run order."""
        return self.series

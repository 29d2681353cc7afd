"""
An IT2FLC on a DC-motor speed loop, with python-control
=======================================================

The paper's controller on another plant: its own DC motor (Table 3), written as a
python-control transfer function from voltage to shaft speed,

    omega(s) / V(s) = K / ((J s + b)(L s + R) + K^2),

and handed to it2track's loop with :func:`it2track.plant.control.from_control` (discretised
exactly, zero-order hold, at the 2 ms control period). A speed loop needs integral action, so
the fuzzy system's output is an *increment* of the voltage (the classical fuzzy PI:
:class:`~it2track.tracking.IncrementalController`), clipped to the +-12 V supply.

The step responses show what DESIGN.md sec. 3 predicts from the sets: near zero error only
the Z sets fire, so the type-1 FLC has a dead zone ``|ke e| < 0.2`` in which the voltage stops
changing and the speed settles short of the set point; the FoU narrows the dead zone to
``0.2 - w/2``, and at ``w = 0.4`` it is gone.

Last, the same loop is built *in python-control*: the fuzzy system becomes a discrete-time
``nlsys`` block (:func:`it2track.io.control.to_control`), joined to the motor by
``interconnect`` and simulated by ``input_output_response``; it gives it2track's numbers.

Needs ``pip install 'it2track[control]'``. Run: ``python examples/plot_dc_motor_speed_it2flc.py``
"""

import control as ct
import matplotlib.pyplot as plt
import numpy as np

from it2track import heading_fls
from it2track.io.control import to_control
from it2track.plant.control import from_control
from it2track.tracking import (
    FuzzyHeadingController,
    IncrementalController,
    LoopConfig,
    StepReference,
    run_grid,
    simulate,
)

R, L, J, B, K = 5.0, 0.0054, 0.00015, 0.0001, 0.1  # the paper's Table 3
motor = ct.tf([K], [J * L, J * R + B * L, B * R + K * K], inputs="V", outputs="omega",
              name="motor")
TS, KE, KDE, GAIN, SETPOINT = 0.002, 1 / 20, 1 / 2, 0.2, 60.0  # s, 1/(rad/s), -, -, rad/s

config = LoopConfig(duration=1.0, ts=TS, plant=from_control(motor, input_limits=[(-12, 12)]))
fous = (0.0, 0.2, 0.4)
controllers = [
    IncrementalController(
        inner=FuzzyHeadingController(fls=heading_fls(w), ke=KE, kde=KDE), gain=GAIN,
        u_min=-12.0, u_max=12.0, name="type-1 FLC" if w == 0 else f"IT2FLC FoU {w}")
    for w in fous
]
trace = simulate(controllers, [StepReference(amplitude=SETPOINT)],
                 run_grid(len(controllers), 1, [0.0], 1), config)

for i, c in enumerate(controllers):
    dead = (0.2 - fous[i] / 2) / KE
    print(f"{c.name:16s} IAE {trace.metrics['IAE'][i]:6.3f} rad   final error "
          f"{trace.metrics['pos_final'][i]:5.3f} rad/s   (dead zone |e| < {dead:.1f} rad/s)")

# The same loop in python-control: error and its change -> fuzzy nlsys -> voltage accumulator
# -> motor (discretised by python-control's own c2d).
def error_out(t, x, u, params):
    e = u[0] - u[1]
    return np.array([KE * e, KDE * (e - x[0]) if x[1] else 0.0])


def accumulate(t, x, u, params):
    return np.clip(x + GAIN * u[0], -12.0, 12.0)


error = ct.nlsys(lambda t, x, u, p: np.array([u[0] - u[1], 1.0]), error_out, states=2,
                 inputs=["r", "omega"], outputs=["e", "de"], dt=TS, name="error")
pi = ct.nlsys(accumulate, accumulate, states=1, inputs=["du"], outputs=["V"], dt=TS, name="pi")
flc = to_control(heading_fls(0.2), TS, name="it2flc", outputs=["du"])
loop = ct.interconnect([error, flc, pi, ct.c2d(motor, TS)], inplist=["r"],
                       outlist=["omega", "V"], dt=TS)
resp = ct.input_output_response(loop, trace.t, np.full(trace.t.size, SETPOINT))
diff = np.abs(np.asarray(resp.outputs)[0] - trace["y"][1]).max()
print(f"python-control interconnect vs it2track, IT2FLC FoU 0.2: max speed difference "
      f"{diff:.1e} rad/s")

fig, (ax_w, ax_v) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, layout="constrained")
ax_w.axhline(SETPOINT, color="k", ls="--", lw=1, label="set point")
for i, c in enumerate(controllers):
    ax_w.plot(trace.t, trace["y"][i], label=c.name)
    ax_v.plot(trace.t, trace["u_applied"][i], label=c.name)
ax_w.set(ylabel="speed [rad/s]", title="DC-motor speed step response (fuzzy PI)")
ax_v.set(xlabel="t [s]", ylabel="voltage [V]")
ax_w.legend()
plt.show()

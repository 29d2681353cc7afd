"""
An IT2FLC on a nonlinear tank (a python-control ``nlsys``)
==========================================================

A second plant, nonlinear and one-sided: a tank filled by a pump and drained through an
orifice (Torricelli),

    A dh/dt = k_p u - a sqrt(2 g h),      0 <= u <= 12 V (a pump cannot pump backwards).

Written as a python-control ``nlsys``, it becomes an it2track plant with
:func:`it2track.plant.control.from_control`: the loop integrates it over every control period
with the pump voltage held (``scipy.integrate.solve_ivp``), run by run. The level starts at
0.5 m, the set point steps to 1.0 m and, at 30 s, down to 0.6 m: the pump switches off (the
lower limit) while the tank drains, and the outflow's square root makes the loop gain depend on
the level. The level sensor is noisy (sigma = 5 mm); all controllers see the same noise.

As for the motor, the fuzzy system drives the pump through an incremental (PI) form: the
type-1 FLC's dead zone lets the level wander, the IT2FLCs' narrower ones hold it tighter.

Needs ``pip install 'it2track[control]'``. Run: ``python examples/plot_tank_level_it2flc.py``
"""

import control as ct
import matplotlib.pyplot as plt
import numpy as np

from it2track import heading_fls
from it2track.plant.control import from_control
from it2track.tracking import (
    FunctionReference,
    FuzzyHeadingController,
    IncrementalController,
    LoopConfig,
    run_grid,
    simulate,
)

AREA, ORIFICE, G, PUMP = 0.05, 0.002, 9.81, 0.001  # m^2, m^2, m/s^2, m^3/s per V


def tank_dynamics(t, x, u, params):
    """dh/dt of the tank (a module-level function: the plant can travel to worker processes)."""
    level = max(x[0], 0.0)
    return np.array([(PUMP * u[0] - ORIFICE * np.sqrt(2 * G * level)) / AREA])


def setpoint(t):
    return np.where(t < 30.0, 1.0, 0.6)


tank = ct.nlsys(tank_dynamics, None, states=["level"], inputs=["pump"], outputs=["level"],
                name="tank")
plant = from_control(tank, input_limits=[(0.0, 12.0)], x0=[0.5], rtol=1e-7, atol=1e-10)
config = LoopConfig(duration=60.0, ts=0.2, noise_rate=5.0, plant=plant)

fous = (0.0, 0.2, 0.4)
controllers = [
    IncrementalController(
        inner=FuzzyHeadingController(fls=heading_fls(w), ke=2.0, kde=10.0), gain=0.5,
        u_min=0.0, u_max=12.0, name="type-1 FLC" if w == 0 else f"IT2FLC FoU {w}")
    for w in fous
]
trace = simulate(controllers, [FunctionReference("set point", setpoint)],
                 run_grid(len(controllers), 1, [0.005], [0]), config)

steady = np.sqrt(2 * G * 1.0) * ORIFICE / PUMP
print(f"pump voltage that holds 1.0 m: {steady:.2f} V")
for i, c in enumerate(controllers):
    print(f"{c.name:16s} IAE {trace.metrics['IAE'][i]:6.3f} m s   RMS error "
          f"{trace.metrics['pos_rms'][i] * 1000:5.1f} mm   pump at 0 V for "
          f"{np.sum(trace['u_applied'][i][:-1] == 0.0) * config.ts:4.1f} s")

fig, (ax_h, ax_u) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, layout="constrained")
ax_h.plot(trace.t, trace["r"][0], "k--", lw=1, label="set point")
for i, c in enumerate(controllers):
    ax_h.plot(trace.t, trace["y"][i], label=c.name)
    ax_u.plot(trace.t, trace["u_applied"][i], label=c.name)
ax_h.set(ylabel="level [m]", title="tank level step responses (noisy level sensor)")
ax_u.set(xlabel="t [s]", ylabel="pump [V]")
ax_h.legend()
plt.show()

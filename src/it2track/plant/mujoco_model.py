"""The differential-drive robot as a physical body: parameters, surfaces and its MJCF model.

The kinematic robot (:mod:`.drive`) has wheels that never slip, a mass-less chassis and motors
loaded only by their own inertia. :class:`PhysicsParams` adds what it leaves out and
:func:`robot_mjcf` writes the MuJoCo model (MJCF text) of the result; :mod:`.mujoco_robot`
steps it. This module needs neither MuJoCo nor anything beyond the standard library and numpy:
the model is plain text, checked on its own.

The model (x forward, y left, z up; the body frame's origin is the middle of the wheel axle):

- **chassis**: a free body; a uniform box of ``chassis_mass``, ``chassis_length`` (along x)
  by the track ``2 l - wheel_width`` (along y) by ``chassis_height``, whose centre lies a
  quarter of its length behind the axle, its centre of mass ``com_below_axle`` below it;
- **wheels**: two hinge joints about y at ``y = -l`` (right) and ``y = +l`` (left), each a
  uniform disc of ``wheel_mass``, radius r and ``wheel_width``; the motor's rotor inertia J is
  the joint's *armature* and its viscous friction b the joint's *damping* (both act between
  wheel and chassis, as in the motor; MuJoCo's armature spins with the joint, so the rotor's
  gyroscopic coupling to the chassis' own rotation, a correction of order chassis rate over
  wheel speed, is left out); the tyre touches the ground as a sphere of radius r (one
  contact point under the hub, torsional friction standing in for the tread's width);
- **caster**: a frictionless sphere of radius r at the chassis' rear edge (three quarters of
  its length behind the axle), so that the caster carries a third of the chassis' weight and
  each wheel a third;
- **ground**: a plane; tyre-ground contacts have sliding friction ``surface.mu``, torsional
  friction ``2/3 mu a`` (a uniformly loaded circular patch of radius
  ``a = contact_patch_radius`` pivoting) and rolling friction ``C_rr r`` (rolling resistance
  coefficient ``C_rr = rolling_resistance`` times the lever arm r); elliptic friction cones; the
  grip builds up with its own time constant (a tyre's relaxation).

Defaults (:class:`PhysicsParams`) and the reasoning behind each are in its docstring;
:meth:`PhysicsParams.no_slip_limit` is the light, high-friction robot in which the model must
reproduce the kinematic plant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real

from .drive import RobotParams

__all__ = [
    "ARENA_BYTES",
    "GRAVITY",
    "SURFACES",
    "PhysicsParams",
    "Surface",
    "robot_mjcf",
    "substeps_per_period",
]

#: Standard gravity, m/s^2.
GRAVITY = 9.80665

#: MuJoCo's arena per run (contacts, constraints, solver scratch), bytes. The robot has three
#: contact pairs and uses ~10 kB at most; MuJoCo's default for this model would be 13 MB per
#: run, which a batch of thousands of runs could not afford. A run that ever needed more would
#: stop with an error naming it (``mujoco_robot.PhysicsDivergedError``), never drop contacts.
ARENA_BYTES = 64 * 1024


@dataclass(frozen=True, kw_only=True)
class Surface:
    """A ground surface: the tyre-ground friction coefficient and a name for reports.

    Parameters
    ----------
    mu : float
        Coulomb coefficient of sliding friction between tyre and ground (MuJoCo's friction
        cone: the contact sticks while the tangential force is below ``mu`` times the normal
        force). Finite, in ``(0, 1000]``.
    name : str, default ""
        Label in reports; empty means ``"mu=<mu>"``.

    Raises
    ------
    ValueError
        If ``mu`` is not a finite number in ``(0, 1000]`` or ``name`` is not a string.

    Examples
    --------
    >>> Surface.named("icy").mu
    0.1
    >>> Surface(mu=0.35).name
    'mu=0.35'
    """

    mu: float
    name: str = ""

    def __post_init__(self) -> None:
        mu = self.mu
        if isinstance(mu, bool) or not isinstance(mu, Real) or not math.isfinite(mu):
            raise ValueError(f"Surface.mu={mu!r} must be a finite number")
        if not 0.0 < float(mu) <= MAX_MU:
            raise ValueError(f"Surface.mu={mu!r} must be in (0, {MAX_MU:g}]")
        object.__setattr__(self, "mu", float(mu))
        if not isinstance(self.name, str):
            raise ValueError(f"Surface.name={self.name!r} must be a string")
        if not self.name:
            object.__setattr__(self, "name", f"mu={self.mu:g}")

    @classmethod
    def named(cls, name: str) -> Surface:
        """The surface of :data:`SURFACES` called ``name`` (``"dry"``, ``"wet"``, ``"icy"``).

        Parameters
        ----------
        name : str
            The surface's name.

        Returns
        -------
        Surface

        Raises
        ------
        ValueError
            If ``name`` is not one of them; the message lists them.
        """
        try:
            return SURFACES[name]
        except (KeyError, TypeError):
            raise ValueError(
                f"surface {name!r} is not one of {sorted(SURFACES)} (or give a friction "
                "coefficient mu)"
            ) from None


#: Largest friction coefficient accepted: real tyres stay below ~2 (racing slicks); the
#: no-slip limit uses 100, and beyond ~1000 the friction cone's regularisation degrades.
MAX_MU = 1000.0

#: Tyre-ground friction of the three named surfaces. Peak coefficients of road adhesion of a
#: pneumatic tyre, lower end of the ranges in J. Y. Wong, *Theory of Ground Vehicles*, 4th ed.
#: (Wiley, 2008), Table 1.3 (values from Bosch's Automotive Handbook): asphalt and concrete
#: dry 0.8-0.9, asphalt wet 0.5-0.7, ice 0.1 (sliding values 0.75, 0.45-0.6, 0.07). MuJoCo's
#: Coulomb cone has one coefficient, so the peak (the onset of slip) is used; taking the lower
#: end of each range errs towards slip, the effect this sweep is for.
SURFACES: dict[str, Surface] = {
    "dry": Surface(mu=0.8, name="dry"),
    "wet": Surface(mu=0.5, name="wet"),
    "icy": Surface(mu=0.1, name="icy"),
}

_NONNEGATIVE = ("rolling_resistance", "com_below_axle")
_POSITIVE = (
    "chassis_mass", "chassis_length", "chassis_height", "wheel_mass", "wheel_width",
    "contact_patch_radius", "max_timestep", "impratio", "contact_timeconst",
    "contact_dampratio", "friction_timeconst",
)  # fmt: skip


@dataclass(frozen=True, kw_only=True)
class PhysicsParams:
    """What the kinematic model leaves out: masses, inertias, tyre-ground contact, time step.

    The geometry (half-track l, wheel radius r) and the motors come from
    :class:`~it2track.plant.drive.RobotParams`; these parameters complete the physical robot.

    The defaults describe the heaviest robot the paper's motors can drive along the paper's
    paths. The motors are small (stall torque ``K V_max / R = 0.24 N m``, 1.2 N at a 0.2 m
    tyre; at most ``V_max^2 / 4R = 7.2 W`` each) and drive the wheels directly, and the loop
    has no speed control: the feed-forward voltage ``V0`` only sets the speed the *unloaded*
    motor would reach. A robot of total mass ``M`` reflects ``M r^2 / 2`` onto each motor, so it
    reaches the reference speed with the time constant ``(J + m_w r^2/2 + M r^2/2) R / K^2``,
    about ``10 M`` seconds per kilogram: 0.1 kg (these defaults) already takes ~1.1 s, a tenth
    of the paper's 10 s run, where the kinematic robot takes 0.07 s; a 1 kg robot ends a
    straight run 16 m behind its reference. A real robot with 0.4 m wheels and an 11.2 m track
    would weigh tens of kilograms: the paper's motors could not move it at all. The defaults are
    therefore light (a model-aircraft build), and the sweep that matters physically is the
    friction (:data:`SURFACES`). See ``docs/guide/mujoco.md``.

    Parameters
    ----------
    surface : Surface or str or float, default "dry"
        Tyre-ground friction: a :class:`Surface`, the name of one of :data:`SURFACES`
        (``"dry"`` mu = 0.8, ``"wet"`` 0.5, ``"icy"`` 0.1) or a friction coefficient.
    chassis_mass : float, default 0.08
        Mass of the chassis (frame, battery, electronics), kg; with the wheels the robot
        weighs 0.1 kg (see above for why so little).
    chassis_length : float, default 1.0
        Front-to-back length of the chassis box, m (its width is the track). The centre of
        mass lies a quarter of it behind the axle and the caster three quarters: long enough
        that braking or accelerating at the tyres' grip (``mu g``) neither lifts the caster
        nor the drive wheels (the load transfer ``a h / g`` stays below 0.25 m).
    chassis_height : float, default 0.05
        Height of the chassis box, m (a flat frame; inertia and drawing).
    com_below_axle : float, default 0.0
        How far the chassis' centre of mass sits below the axle, m, in ``[0, r)``: 0 puts it at
        axle height. A low centre of mass reduces the load transfer when accelerating.
    wheel_mass : float, default 0.01
        Mass of each wheel, kg: a foam or thin-plastic 0.4 m wheel. Its spin inertia
        ``wheel_mass r^2 / 2`` (2e-4 kg m^2 by default) adds to the motor's J = 1.5e-4 kg m^2.
    wheel_width : float, default 0.04
        Width of each wheel, m (inertia and drawing only: the tyre touches as a sphere).
    rolling_resistance : float, default 0.01
        Rolling resistance coefficient C_rr of tyre on ground (resisting torque
        ``C_rr N r``): about 0.01-0.015 for tyres on hard, smooth ground (J. Y. Wong, *Theory
        of Ground Vehicles*, ch. 1: 0.013 for car tyres on concrete or asphalt); >= 0, 0
        disables it. It does not change with the surface's wetness.
    contact_patch_radius : float, default 0.005
        Radius a of the tyre's contact patch, m, for the torsional (pivoting) friction
        ``2/3 mu a N`` of a uniformly loaded disc: a light wheel flattens by millimetres.
    max_timestep : float, default 0.001
        Longest physics step, s: each control period is split into the fewest equal steps not
        longer than this (:func:`substeps_per_period`). 1 ms resolves the 2 ms contact (MuJoCo
        requires ``contact_timeconst`` of at least two steps) and is about the electrical time
        constant L/R = 1.08 ms, which the motor model integrates exactly within a step.
    impratio : float, default 10.0
        MuJoCo's ratio of frictional to normal constraint impedance (elliptic cones): values
        above 1 make friction stiffer, so that a sticking tyre creeps less (MuJoCo's
        documentation suggests 10 against slipping).
    contact_timeconst : float, default 0.002
        Time constant of MuJoCo's soft contact in the normal direction (``solref[0]``), s: the
        stiffest that the 1 ms step resolves (a rigid wheel on hard ground).
    contact_dampratio : float, default 1.0
        Damping ratio of the soft contact (``solref[1]`` and ``solreffriction[1]``): critical,
        MuJoCo's default.
    friction_timeconst : float, default 0.02
        Time constant of the tyre's grip (MuJoCo's ``solreffriction[0]``), s: the friction
        force builds up towards the slip-stopping force at this rate, as a tyre's does over its
        relaxation length (0.04 m at the paths' 2 m/s, a fifth of the wheel radius). Stiffer
        grip has a side effect in MuJoCo's convex contact model, in which a contact can only
        start sliding by moving apart: the light robot tracking the paths with its wheels
        slipping then hops (its axle rises by up to 4 cm on dry ground with 0.002 s, 1 mm with
        0.02 s). The no-slip limit, which never slides, uses 0.002 s: with 0.02 s its tyres
        creep and its integrals differ from the kinematic robot's by up to 7 % instead of
        under 1 %.

    Raises
    ------
    ValueError
        If a field is not a finite number > 0 (``rolling_resistance`` and ``com_below_axle``
        >= 0), or ``surface`` is not a Surface, a surface name or a valid friction
        coefficient, or ``contact_timeconst`` or ``friction_timeconst`` is shorter than twice
        ``max_timestep``; the message names the field.

    Examples
    --------
    >>> PhysicsParams(surface="wet").surface.mu
    0.5
    >>> PhysicsParams.no_slip_limit().surface.mu
    100.0
    """

    surface: Surface = SURFACES["dry"]
    chassis_mass: float = 0.08
    chassis_length: float = 1.0
    chassis_height: float = 0.05
    com_below_axle: float = 0.0
    wheel_mass: float = 0.01
    wheel_width: float = 0.04
    rolling_resistance: float = 0.01
    contact_patch_radius: float = 0.005
    max_timestep: float = 0.001
    impratio: float = 10.0
    contact_timeconst: float = 0.002
    contact_dampratio: float = 1.0
    friction_timeconst: float = 0.02

    def __post_init__(self) -> None:
        surface = self.surface
        if isinstance(surface, str):
            surface = Surface.named(surface)
        elif isinstance(surface, Real) and not isinstance(surface, bool):
            surface = Surface(mu=float(surface))
        elif not isinstance(surface, Surface):
            raise ValueError(
                f"PhysicsParams.surface={surface!r} must be a Surface, one of "
                f"{sorted(SURFACES)} or a friction coefficient"
            )
        object.__setattr__(self, "surface", surface)
        for name in (*_POSITIVE, *_NONNEGATIVE):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value):
                raise ValueError(f"PhysicsParams.{name}={value!r} must be a finite number")
            value = float(value)
            low_ok = value >= 0.0 if name in _NONNEGATIVE else value > 0.0
            if not low_ok or value > _UPPER[name]:
                bound = ">= 0" if name in _NONNEGATIVE else "> 0"
                raise ValueError(
                    f"PhysicsParams.{name}={value!r} must be {bound} and <= {_UPPER[name]:g}"
                )
            object.__setattr__(self, name, value)
        for name in ("contact_timeconst", "friction_timeconst"):
            if getattr(self, name) < 2.0 * self.max_timestep:
                raise ValueError(
                    f"PhysicsParams.{name}={getattr(self, name)!r} must be at least twice "
                    f"max_timestep={self.max_timestep!r} (MuJoCo cannot resolve a stiffer "
                    "contact)"
                )

    @classmethod
    def no_slip_limit(cls, robot: RobotParams | None = None) -> PhysicsParams:
        """The robot in which the physics must reproduce the kinematic plant.

        A chassis of 0.1 g and wheels of 0.01 mg reflect about 1 % of the rotor's J onto each
        motor (``M r^2 / 2``); no rolling resistance; a friction coefficient of 100, because
        the grip a light robot needs scales with its acceleration, not its mass (the paper's
        motors accelerate a mass-less robot at up to ~300 m/s^2). So that such accelerations
        neither lift the drive wheels nor the caster (load transfer ``a h / g``), the chassis
        is 4 m long with its centre of mass 2 cm above the ground (``com_below_axle = 0.9 r``);
        and a rigid tyre (``friction_timeconst`` 0.002 s) grips without creeping.

        Parameters
        ----------
        robot : RobotParams, optional
            The robot whose wheel radius places the centre of mass (default: Table 3).

        Returns
        -------
        PhysicsParams
        """
        r = (robot or RobotParams()).wheel_radius
        return cls(surface=Surface(mu=100.0, name="no-slip"), chassis_mass=1e-4,
                   wheel_mass=1e-8, rolling_resistance=0.0, chassis_length=4.0,
                   com_below_axle=0.9 * r, friction_timeconst=0.002)  # fmt: skip

    def chassis_inertia(self, robot: RobotParams) -> tuple[float, float, float]:
        """Principal moments of inertia of the chassis box about its centre, kg m^2.

        Parameters
        ----------
        robot : RobotParams
            The geometry (half-track l, wheel radius r).

        Returns
        -------
        (Ixx, Iyy, Izz) : tuple of float
            Roll, pitch and yaw moments of a uniform box ``chassis_length`` x
            ``2 l - wheel_width`` x ``chassis_height``.
        """
        a, w, h = self.chassis_length, self.track_width(robot), self.chassis_height
        m = self.chassis_mass
        return m * (w * w + h * h) / 12.0, m * (a * a + h * h) / 12.0, m * (a * a + w * w) / 12.0

    def reflected_inertia(self, robot: RobotParams) -> tuple[float, float]:
        """Inertia the rolling robot adds to each motor's rotor, kg m^2, without slip.

        With the wheels rolling without slip, the robot's kinetic energy is that of two
        rotors of inertia ``J + J_c`` in the common mode (both wheels turning alike: straight
        motion) and ``J + J_d`` in the differential mode (turning on the spot).

        Parameters
        ----------
        robot : RobotParams
            The geometry (half-track l, wheel radius r).

        Returns
        -------
        (J_c, J_d) : tuple of float
            ``I_w + M r^2 / 2`` and ``I_w + I_z r^2 / (2 l^2)``, with ``I_w`` a wheel's spin
            inertia, ``M`` the robot's mass and ``I_z`` its yaw inertia about the axle centre.
        """
        r, l_ = robot.wheel_radius, robot.half_track
        spin, diam = self.wheel_inertia(robot)
        mass = self.chassis_mass + 2.0 * self.wheel_mass
        offset = self.chassis_length / 4.0  # centre of mass behind the axle
        yaw = (self.chassis_inertia(robot)[2] + self.chassis_mass * offset * offset
               + 2.0 * (diam + self.wheel_mass * l_ * l_))
        return spin + mass * r * r / 2.0, spin + yaw * r * r / (2.0 * l_ * l_)

    def track_width(self, robot: RobotParams) -> float:
        """Width of the chassis between the wheels' inner faces, ``2 l - wheel_width``, m.

        Parameters
        ----------
        robot : RobotParams
            The geometry (half-track l, wheel radius r).

        Returns
        -------
        float
        """
        return 2.0 * robot.half_track - self.wheel_width

    def wheel_inertia(self, robot: RobotParams) -> tuple[float, float]:
        """Moments of inertia of one wheel (uniform disc), kg m^2.

        Parameters
        ----------
        robot : RobotParams
            The geometry (half-track l, wheel radius r).

        Returns
        -------
        (spin, diametral) : tuple of float
            ``m r^2 / 2`` about the axle and ``m (3 r^2 + w^2) / 12`` about a diameter.
        """
        m, r, w = self.wheel_mass, robot.wheel_radius, self.wheel_width
        return m * r * r / 2.0, m * (3.0 * r * r + w * w) / 12.0


_UPPER = {
    "chassis_mass": 1e4, "chassis_length": 1e3, "chassis_height": 1e3, "com_below_axle": 1e3,
    "wheel_mass": 1e3, "wheel_width": 1e3, "rolling_resistance": 1.0, "contact_patch_radius": 1.0,
    "max_timestep": 0.1, "impratio": 1e4, "contact_timeconst": 10.0, "contact_dampratio": 100.0,
    "friction_timeconst": 10.0,
}  # fmt: skip


def substeps_per_period(ts: float, max_timestep: float) -> int:
    """Physics steps per control period: the fewest equal steps of at most ``max_timestep``.

    Parameters
    ----------
    ts : float
        Control period, s (> 0).
    max_timestep : float
        Longest physics step allowed, s (> 0).

    Returns
    -------
    int
        ``n = ceil(ts / max_timestep)`` (a period within 1e-9 relative of a whole number of
        steps counts as that number), so the step ``ts / n`` is at most ``max_timestep``.

    Raises
    ------
    ValueError
        If either is not a finite number > 0, or the period needs more than 1e6 steps.

    Examples
    --------
    >>> substeps_per_period(0.01, 0.001), substeps_per_period(0.01, 0.003)
    (10, 4)
    """
    for name, value in (("ts", ts), ("max_timestep", max_timestep)):
        if (isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value)
                or value <= 0):
            raise ValueError(f"{name}={value!r} must be a finite number > 0")
    ratio = float(ts) / float(max_timestep)
    n = round(ratio)
    if abs(ratio - n) > 1e-9 * max(1.0, ratio):
        n = math.ceil(ratio)
    n = max(1, n)
    if n > 1_000_000:
        raise ValueError(
            f"ts={ts!r} s needs {n} physics steps of at most max_timestep={max_timestep!r} s "
            "per control period (more than 1e6): lengthen max_timestep or shorten ts"
        )
    return n


def _fmt(x: float) -> str:
    """A float as MJCF text, exactly (repr round-trips)."""
    return repr(float(x))


def robot_mjcf(
    robot: RobotParams, physics: PhysicsParams, timestep: float, *, bench: bool = False
) -> str:
    """The MJCF text of the robot.

    Parameters
    ----------
    robot : RobotParams
        Half-track l, wheel radius r and the motors (J becomes each wheel joint's armature,
        b its damping).
    physics : PhysicsParams
        Masses, inertias, contact and surface.
    timestep : float
        MuJoCo's time step, s (finite, > 0).
    bench : bool, default False
        A motor bench test: the chassis is fixed in the air (no free joint, wheels clear of
        the ground), so each wheel is a motor loaded only by its own inertia and damping.

    Returns
    -------
    str
        A complete ``<mujoco>`` document. Bodies ``chassis``, ``wheel_right``,
        ``wheel_left``; hinge joints ``right`` and ``left`` (positive rotation drives the
        robot forward); geoms ``floor``, ``tyre_right``, ``tyre_left``, ``caster``.

    Raises
    ------
    ValueError
        If ``robot`` or ``physics`` has the wrong type or ``timestep`` is not finite > 0.

    Examples
    --------
    >>> text = robot_mjcf(RobotParams(), PhysicsParams(), 0.001)
    >>> text.startswith("<mujoco") and 'armature="0.00015"' in text
    True
    """
    if not isinstance(robot, RobotParams):
        raise ValueError(f"robot={robot!r} must be a RobotParams")
    if not isinstance(physics, PhysicsParams):
        raise ValueError(f"physics={physics!r} must be a PhysicsParams")
    if (isinstance(timestep, bool) or not isinstance(timestep, Real)
            or not math.isfinite(timestep) or timestep <= 0):
        raise ValueError(f"timestep={timestep!r} must be a finite number > 0")
    p, m = physics, robot.motor
    r, l_ = robot.wheel_radius, robot.half_track
    if not p.com_below_axle < r:
        raise ValueError(
            f"PhysicsParams.com_below_axle={p.com_below_axle!r} m must be below the wheel "
            f"radius {r!r} m (the centre of mass would be under the ground)"
        )
    if not p.wheel_width < 2.0 * l_:
        raise ValueError(
            f"PhysicsParams.wheel_width={p.wheel_width!r} m must be narrower than the track "
            f"2 l = {2.0 * l_!r} m"
        )
    a = p.chassis_length
    ixx, iyy, izz = p.chassis_inertia(robot)
    spin, diam = p.wheel_inertia(robot)
    mu = p.surface.mu
    torsion = 2.0 / 3.0 * mu * p.contact_patch_radius
    rolling = p.rolling_resistance * r
    f = _fmt
    lift = 2.0 * r if bench else 0.0  # bench: the wheels spin in the air
    root = "" if bench else "\n      <freejoint name=\"root\"/>"
    tyre_pair = (
        'condim="6" friction="{mu} {mu} {t} {rr} {rr}" solref="{tc} {dr}" '
        'solreffriction="{ft} {dr}"'.format(
            mu=f(mu), t=f(torsion), rr=f(rolling), tc=f(p.contact_timeconst),
            ft=f(p.friction_timeconst), dr=f(p.contact_dampratio))
    )
    solref = f'solref="{f(p.contact_timeconst)} {f(p.contact_dampratio)}"'
    wheels = []
    for side, y in (("right", -l_), ("left", l_)):
        wheels.append(f"""
      <body name="wheel_{side}" pos="0 {f(y)} 0">
        <joint name="{side}" type="hinge" axis="0 1 0" armature="{f(m.inertia)}" \
damping="{f(m.friction)}"/>
        <inertial pos="0 0 0" mass="{f(p.wheel_mass)}" diaginertia="{f(diam)} {f(spin)} \
{f(diam)}"/>
        <geom name="wheel_{side}_visual" type="cylinder" size="{f(r)} {f(p.wheel_width / 2)}" \
zaxis="0 1 0" contype="0" conaffinity="0" mass="0" rgba="0.15 0.15 0.15 1"/>
        <geom name="tyre_{side}" type="sphere" size="{f(r)}" contype="0" conaffinity="0" \
mass="0" group="3"/>
      </body>""")
    return f"""<mujoco model="it2track_ddwmr">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{f(timestep)}" integrator="implicitfast" cone="elliptic" \
impratio="{f(p.impratio)}" gravity="0 0 {f(-GRAVITY)}">
    <flag autoreset="disable"/>
  </option>
  <size memory="{ARENA_BYTES // 1024}K"/>
  <visual><global offwidth="640" offheight="480"/></visual>
  <worldbody>
    <light pos="0 0 30" dir="0 0 -1" directional="true"/>
    <geom name="floor" type="plane" size="0 0 1" contype="0" conaffinity="0" \
rgba="0.85 0.85 0.8 1"/>
    <body name="chassis" pos="0 0 {f(r + lift)}">{root}
      <inertial pos="{f(-a / 4)} 0 {f(-p.com_below_axle)}" mass="{f(p.chassis_mass)}" \
diaginertia="{f(ixx)} {f(iyy)} {f(izz)}"/>
      <geom name="chassis_visual" type="box" size="{f(a / 2)} {f(p.track_width(robot) / 2)} \
{f(p.chassis_height / 2)}" pos="{f(-a / 4)} 0 0" contype="0" conaffinity="0" mass="0" \
rgba="0.2 0.4 0.8 1"/>
      <geom name="caster" type="sphere" size="{f(r)}" pos="{f(-3 * a / 4)} 0 0" contype="0" \
conaffinity="0" mass="0" rgba="0.5 0.5 0.5 1"/>{"".join(wheels)}
    </body>
  </worldbody>
  <contact>
    <pair geom1="floor" geom2="tyre_right" {tyre_pair}/>
    <pair geom1="floor" geom2="tyre_left" {tyre_pair}/>
    <pair geom1="floor" geom2="caster" condim="1" {solref}/>
  </contact>
</mujoco>
"""

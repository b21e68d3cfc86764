"""A scenario's scene as an ``MjSpec``: the water, the (possibly sloped) seabed, the ship, and the
robot end (a walker standing on the seabed, a free-swimming vehicle from its vehicle file, or an
anchor point); and the typed configuration's water column, tether, line make-up and winch as the
library's objects.

The tether itself is added once its start is known (``start``), by ``runner.ScenarioRun``.

The ship is a mocap body at the surface whose site ``ship/fairlead`` holds the tether's node 0;
a mocap body has no velocity, so the soft ``connect`` trails a moving ship by about 4 dt times
its speed. With ``ship.vessel`` it is a surface vessel instead (a body ``ship`` from its vehicle
file, floating on its hydrostatics, flown by its autopilot), the fairlead at its tow point.
Units SI, world frame (z up, surface z = 0); the scenario's degrees become radians here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import mujoco
import numpy as np

from mjtether.cable import builder
from mjtether.cable.makeup import LineMakeup
from mjtether.cable.tether import TetherSpec
from mjtether.cable.winch import Winch
from mjtether.physics import water as wm
from mjtether.physics.bathymetry import Bathymetry
from mjtether.physics.rigidbody import add_body_hydro
from mjtether.scenario import Scenario
from mjtether.vehicles.files import VehicleSpec, build_vehicle, load_vehicle
from mjtether.walker import HYDRO as WALKER_HYDRO
from mjtether.walker import walker_spec

from .controllers import Ship
from .sea import wave_field

if TYPE_CHECKING:
    from .robot_ends import RobotEnd

WALKER_STAND_HEIGHT = 0.9
"""Height (m) of the walker's torso above the seabed when it is placed."""
WALKER_PATCH = 2.0
"""Radius (m) of the patch of a bathymetry grid that the walker's plane is fitted to (its legs
span about 1.6 m)."""
VEHICLE = "vehicle"
"""Name of a vehicle robot's body (its actuators and sites are prefixed ``vehicle/``)."""


def water_from(sc: Scenario) -> wm.WaterColumn:
    """The scenario's water column (headings from degrees to radians), with its sea state
    (``[waves]``: ``sea.wave_field``)."""
    d = sc.water.density
    if d.type == "constant":
        density = wm.ConstantDensity(d.rho)
    elif d.type == "linear":
        density = wm.LinearDensity(d.rho_surface, d.rho_ref, d.depth_ref)
    else:
        density = wm.TabulatedDensity(d.depths, d.values)
    current = current_from(sc.water.current, sc.water.depth, stepped=True)
    return wm.WaterColumn(depth=sc.water.depth, density=density, current=current,
                          gravity=sc.water.gravity, waves=wave_field(sc.waves, sc.water.depth, sc.water.gravity))


def current_from(c, depth: float, stepped: bool = False):
    """The ``physics.water`` current of a ``[water.current]`` section ``c`` in water ``depth`` m
    deep (headings from degrees to radians): a scenario's, or a network's; with noise in
    ``c.gauss_markov``, the Gauss-Markov current about its speed and heading (``weather``), for
    a run that steps it (``stepped``: a scenario's; elsewhere it is refused)."""
    from .weather import gauss_markov_current
    varying = gauss_markov_current(c)
    if varying is not None:
        if not stepped:
            from .config import ConfigError
            raise ConfigError("water.current.gauss_markov: a varying current is stepped by a scenario's run only; "
                              "here the current is steady (give no noise: sigma = heading_sigma_deg = 0)",
                              "water.current.gauss_markov")
        return varying
    heading = math.radians(c.heading_deg)
    if c.type == "constant":
        return wm.ConstantCurrent(c.speed, heading)
    if c.type == "linear":
        return wm.LinearCurrent(c.surface_speed, c.bottom_speed, c.bottom_depth, heading=heading)
    if c.type == "exponential":
        return wm.ExponentialCurrent(c.surface_speed, c.decay_depth, heading)
    if c.type == "power":
        return wm.PowerLawCurrent(c.surface_speed, depth, c.exponent, heading)
    headings = None if c.headings_deg is None else [math.radians(h) for h in c.headings_deg]
    return wm.TabulatedCurrent(c.depths, c.speeds, headings)


def tether_from(sc: Scenario) -> TetherSpec:
    t = sc.tether
    return TetherSpec(length=t.length, segments=t.segments, diameter=t.diameter,
                      density=None if t.mass_per_length > 0 else t.density,
                      mass_per_length=t.mass_per_length or None, cd_normal=t.cd_normal,
                      cd_tangential=t.cd_tangential, ca_normal=t.ca_normal, EA=t.EA or None, EI=t.EI,
                      added_mass=t.added_mass, drag_law=t.drag_law)


def makeup_from(sc: Scenario) -> LineMakeup:
    """The scenario's line make-up (sections, point loads, floats); a uniform tether is its
    one-section make-up (``LineMakeup.uniform``), with point loads and floats on it if any."""
    t = sc.tether
    uniform = LineMakeup.uniform(tether_from(sc))
    if not t.is_makeup:
        return uniform
    sections = [x.to_makeup() for x in t.sections] or list(uniform.sections)
    return LineMakeup(sections, [p.to_makeup() for p in (*t.point_loads, *t.floats)])


def winch_from(sc: Scenario) -> Winch:
    w = sc.winch
    return Winch(length=sc.tether.length, mode=w.mode, min_length=w.min_length, max_length=w.max_length,
                 rate=w.rate, max_rate=w.max_rate, max_accel=w.max_accel, band=w.band, drum_damping=w.drum_damping)


@dataclass
class Scene:
    """A scenario's parts before the tether is added: the spec (seabed, ship, robot end), the
    water, the line, the winch and the ship's kinematics."""

    sc: Scenario
    spec: mujoco.MjSpec
    water: wm.WaterColumn
    tether_spec: TetherSpec
    makeup: LineMakeup  # the line (a uniform tether: its one section)
    winch: Winch
    ship: Ship
    slope: float  # rad
    slope_heading: float  # rad
    robot_end: RobotEnd  # the walker, the anchor or the vehicle (``robot_ends``)
    bodies: list = field(default_factory=list)  # rigid-body hydrodynamics (a vessel, the walker's torso, a vehicle)
    vehicle: VehicleSpec | None = None  # a vehicle robot's parameter file
    vessel: VehicleSpec | None = None  # the surface vessel carrying the winch (ship.vessel), if any
    grid: Bathymetry | None = None  # the seabed from a bathymetry grid (water.bathymetry); slope is then its
    # plane fitted around the robot's start (the walker stands square to it)

    @property
    def line(self):
        """What the quasi-static solver and the builder take: the line's make-up."""
        return self.makeup

    @property
    def contact_diameter(self) -> float:
        """Diameter (m) of the cable's seabed contact: the cable's, or a make-up's widest section's
        (the builder gives the whole flex that radius), so that its axis rests one such radius
        above the seabed. (A make-up's anchor placed one radius of its thinner last section up
        sat inside the contact of the wider ones: 11.8 MN at the anchor.)"""
        return float(self.makeup.element_diameter.max())

    def fairlead_start(self) -> np.ndarray:
        """Where the tether leaves the ship at the start (m, world): the prescribed ship's
        fairlead, or a vessel's tow point, the vessel level at ``ship.heading_deg``."""
        if self.vessel is None:
            return np.array(self.spec.body("ship").pos, dtype=float)
        R = np.zeros(9)
        mujoco.mju_quat2Mat(R, heading_quat(math.radians(self.sc.ship.heading_deg)))
        x, y = self.sc.ship.position
        return np.array([x, y, 0.0]) + R.reshape(3, 3) @ np.asarray(self.vessel.tow_point, dtype=float)

    def seabed_z(self, x, y):
        """Height (m) of the (possibly sloped, or gridded) seabed at ``x``, ``y`` (m)."""
        if self.grid is not None:
            return self.grid.height(x, y)
        return builder.seabed_height(self.water, x, y, self.slope, self.slope_heading)

    @property
    def tilt(self) -> np.ndarray:
        """The quaternion turning +z onto the seabed's normal (``slope``, ``slope_heading``)."""
        return np.array(builder.slope_quat(self.slope, self.slope_heading))

    @property
    def walker(self) -> bool:
        """Whether the robot end is the walker."""
        return self.robot_end.walker

    @property
    def heading(self) -> float | None:
        """The walker's or vehicle's heading at the start (rad; None for an anchor)."""
        return self.robot_end.heading

    @property
    def ground(self):
        """The seabed and water the walker stands on (``robot_ends.Ground``)."""
        from .robot_ends import Ground
        return Ground(self.water, self.slope, self.slope_heading, self.sc.water.seabed_friction, self.seabed_z,
                      self.grid, self.sc.water.bathymetry)

    def anchor_point(self) -> np.ndarray:
        """An anchor's tow point (m, world): the scenario's position, the cable's axis held at
        least one radius above a seabed there (``robot_ends.Anchor.tow_point``)."""
        from .robot_ends import Anchor
        return Anchor(self.sc.robot).tow_point(self)


def build_scene(sc: Scenario) -> Scene:
    """The scenario's spec (options, seabed, ship, and the robot end's bodies: the walker placed on
    the seabed or the vehicle at its start, if the robot is one; ``robot_ends``, the part for
    ``robot.type``) and the objects the run needs; the tether is added by the run."""
    from .robot_ends import ROBOT_ENDS  # (robot_ends builds on this module)
    water = water_from(sc)
    wsc = sc.water
    end = ROBOT_ENDS[sc.robot.type](sc.robot)
    grid = wsc.grid
    if grid is not None:  # the plane of the seabed the walker stands on (or the anchor lies on)
        slope, slope_heading = grid.plane_at(*end.place, WALKER_PATCH)
    else:
        slope, slope_heading = math.radians(wsc.seabed_slope_deg), math.radians(wsc.seabed_slope_heading_deg)
    spec = seabed_spec(water, sc.simulation.timestep, wsc.seabed_friction, slope, slope_heading, grid=grid)
    ship = Ship.from_scenario(sc, water.waves)
    scene = Scene(sc, spec, water, tether_from(sc), makeup_from(sc), winch_from(sc), ship, slope, slope_heading,
                  end, grid=grid)
    if sc.ship.vessel:  # a surface vessel carries the winch; its tow point is the fairlead
        scene.vessel = load_vehicle(sc.ship.vessel)
        x, y = sc.ship.position
        scene.bodies.append(build_vehicle(spec, scene.vessel, "ship", pos=(x, y, 0.0)))
        spec.body("ship").add_site(name="ship/fairlead", pos=list(scene.vessel.tow_point))
    else:
        body = spec.worldbody.add_body(name="ship", mocap=True, pos=ship.advance(0.0, 0.0, np.zeros(3)))
        body.add_site(name="ship/fairlead")
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[4.0, 1.5, 1.0], pos=[0, 0, 1.0], contype=0,
                      conaffinity=0, rgba=[0.8, 0.8, 0.85, 1])
    end.add_to(scene)
    return scene


def heading_quat(heading: float) -> np.ndarray:
    """The quaternion (w, x, y, z) of a turn by ``heading`` (rad) about z: a level body facing it."""
    return np.array([math.cos(heading / 2), 0.0, 0.0, math.sin(heading / 2)])


def seabed_spec(water: wm.WaterColumn, timestep: float, friction: float, slope: float = 0.0,
                slope_heading: float = 0.0, *, grid: Bathymetry | None = None, point=None) -> mujoco.MjSpec:
    """A scenario's spec before its ship and robot: the options (``timestep`` in s, the
    implicit-fast integrator, the water's gravity) and the seabed: the height field of ``grid``
    (``builder.add_seabed_grid``), or the plane (``builder.add_seabed``, through ``point``)."""
    spec = mujoco.MjSpec()
    spec.option.timestep = timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.gravity = [0.0, 0.0, -water.gravity]
    spec.modelname = "mjtether_scenario"
    if grid is not None:
        builder.add_seabed_grid(spec, grid, friction=friction)
    else:
        builder.add_seabed(spec, water, friction=friction, slope=slope, slope_heading=slope_heading, point=point)
    return spec


def place_walker(spec: mujoco.MjSpec, seabed_point, heading: float, tilt=None):
    """Attach the walker (``walker/`` prefix) over ``seabed_point`` (m, world; on the seabed
    geom ``seabed``), its torso ``WALKER_STAND_HEIGHT`` over the seabed, its legs square to a
    sloped seabed (``tilt``: the quaternion turning +z onto its normal; default: the seabed
    plane's own), facing ``heading`` (rad from +x); returns its rigid-body hydrodynamics."""
    tilt = np.array(spec.geom("seabed").quat if tilt is None else tilt)
    quat = np.zeros(4)
    mujoco.mju_mulQuat(quat, tilt, heading_quat(heading))
    normal = np.zeros(9)
    mujoco.mju_quat2Mat(normal, tilt)
    torso = walker_spec().body("torso")
    # (the torso sits at its own height in walker.xml, which the frame carries along the normal)
    lift = WALKER_STAND_HEIGHT - float(torso.pos[2])
    frame = spec.worldbody.add_frame(pos=np.asarray(seabed_point, dtype=float) + lift * normal[[2, 5, 8]], quat=quat)
    frame.attach_body(torso, "walker/", "")
    return add_body_hydro(spec, "walker/torso", WALKER_HYDRO)

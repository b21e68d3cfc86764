"""The robot end of a scenario's tether as a part, in the manner of dm_control's composer entities:
a ``Walker`` (the hexapod of ``mjtether.walker`` standing on the seabed), an ``Anchor`` (a fixed
tow point) or a ``Vehicle`` (a free-swimming vehicle from its vehicle file, on its autopilot or a
prescribed path), chosen once from ``robot.type`` by ``ROBOT_ENDS``. The scene and the run ask
the part instead of testing the type.

Every part has the same interface, used in this order:

* ``place``: the (x, y) (m, world) the seabed's plane is fitted around on a bathymetry grid;
* ``add_to(scene)``: its bodies in the scene's spec, its rigid-body hydrodynamics in ``scene.bodies``;
* ``tow_point(scene, dt, replay)``: where the tether's last node is at the start (m, world);
* ``tether_end()`` and ``end_at(tow_point)``: the tether's end for ``cable.builder.add_tether``;
* ``hold(spec)``: what holds it while the cable settles onto the seabed;
* ``start(run)``: after compile, its pose and its controllers (``controllers``: what the run
  updates before each step, ahead of the ship and the winch).

Units SI, world frame (z up, surface z = 0); headings in radians here (degrees in the scenario).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable

import mujoco
import numpy as np

from mjtether.cable import builder
from mjtether.physics import water as wm
from mjtether.physics.bathymetry import Bathymetry
from mjtether.vehicles.files import build_vehicle, load_vehicle

from . import start as _start
from .controllers import GaitDrive, Manoeuvre, PathDrive, VehiclePilot
from .scene import VEHICLE, heading_quat, place_walker


class RobotEnd:
    """What every robot end has (an anchor's answers: no body, no heading, nothing to drive).

    ``walker``, ``is_vehicle``: what the run's readers (``run.walker``, ``run.is_vehicle``) are
    told; ``body``, ``site``: the names of its body and of its tow point site (None: the tow
    point is fixed in the world); ``held``: how the settling note says it is kept in place."""

    walker = False
    is_vehicle = False
    body: str | None = None
    site: str | None = None
    held = "held"

    def __init__(self, robot):
        self.robot = robot  # the scenario's [robot] section
        self.heading: float | None = None  # rad from +x towards +y, at the start
        self.gait_drive: GaitDrive | None = None
        self.pilot = None  # a vehicle's VehiclePilot or PathDrive
        self.vehicle = None  # a vehicle's rigid-body hydrodynamics (``physics.rigidbody``)
        self.stand_pose: dict = {}  # the walker's joints {(body, index in body): (qpos, qvel)}
        self.stand_ctrl: dict = {}  # and its actuators' controls {name: ctrl} where it stands

    @property
    def place(self) -> tuple[float, float]:
        """(x, y) (m, world) of the robot's start: where a bathymetry grid's plane is fitted."""
        x, y = self.robot.position[:2]
        return x, y

    def add_to(self, scene) -> None:
        """Its bodies in ``scene.spec``, their hydrodynamics in ``scene.bodies`` (none here)."""

    def tow_point(self, scene, dt: float, replay: bool = False) -> np.ndarray:
        raise NotImplementedError

    def tether_end(self):
        """The tether's end on the robot (``cable.builder``): its tow point site."""
        return builder.SitePoint(self.site)

    def end_at(self, tow_point):
        """Where ``add_tether`` places the tether's end before compile (m, world): the tow point
        of a robot with a body (its site's place is not known before compile), None otherwise."""
        return tow_point

    def hold(self, spec: mujoco.MjSpec) -> None:
        """Hold it while the cable settles (nothing here)."""

    def start(self, run) -> None:
        """After compile (``run.sim``): its pose and its controllers (nothing here)."""

    @property
    def controllers(self) -> list:
        """What the run updates before each step for it (its gait or its pilot)."""
        return [c for c in (self.gait_drive, self.pilot) if c is not None]


class Anchor(RobotEnd):
    """A fixed tow point at ``robot.position``, the cable's axis held at least one contact
    radius above the seabed there (``tow_point``, which ``tether_end`` then holds)."""

    def __init__(self, robot):
        super().__init__(robot)
        self.position: np.ndarray | None = None  # m, world: the tow point, once ``tow_point`` has placed it

    def tow_point(self, scene, dt: float = 0.0, replay: bool = False) -> np.ndarray:
        """``robot.position`` (m, world), raised where the cable there would be inside the seabed:
        its axis one radius (``scene.contact_diameter / 2``) above it along the seabed's normal,
        i.e. radius / cos(slope) above the seabed's height at (x, y)."""
        robot = np.array(self.robot.position, dtype=float)
        radius = scene.contact_diameter / 2
        robot[2] = max(robot[2], scene.seabed_z(robot[0], robot[1]) + radius / math.cos(scene.slope))
        self.position = robot
        return robot

    def tether_end(self):
        return builder.FixedPoint(self.position)

    def end_at(self, tow_point):
        return None


class Walker(RobotEnd):
    """The seabed walker (bodies ``walker/...``), standing at ``robot.start`` facing
    ``robot.heading_deg`` and walking ``robot.commands`` on its gait drive; held by a weld
    (``walker/hold``) while the cable settles."""

    walker = True
    body, site = "walker/torso", "walker/tow_point"

    def __init__(self, robot):
        super().__init__(robot)
        self.heading = math.radians(robot.heading_deg)
        commands = np.array(robot.commands, dtype=float)  # (s, m/s, rad/s)
        commands[:, 2] = np.radians(commands[:, 2])
        self.gait_drive = GaitDrive(commands, robot.gait_period, self.heading)

    @property
    def place(self) -> tuple[float, float]:
        x, y = self.robot.start
        return x, y

    def add_to(self, scene) -> None:
        """Attach the walker over the seabed at ``robot.start``, its legs square to the seabed's
        plane there, facing its heading (``scene.place_walker``)."""
        x, y = self.place
        scene.bodies.append(place_walker(scene.spec, (x, y, float(scene.seabed_z(x, y))), self.heading, scene.tilt))

    def stand(self, ground, gait, dt: float):
        """Its standing pose on ``ground`` (a ``Ground``: the seabed and water it stands on), after
        ``scenario.start.stand_walker`` at step ``dt`` (s): ({(body, index in body): (qpos, qvel)},
        {actuator: control}, tow point m, world); ``gait`` (a ``walker.Tripod``) is left at the
        phase it stood in."""
        return _start.stand_walker(_Standing(ground, self), gait, dt)

    def tow_point(self, scene, dt: float, replay: bool = False) -> np.ndarray:
        """Its tow point standing (m, world): it stands on the seabed first, alone (``stand``),
        and the run starts in that pose. ``replay``: no stand; about where it stands (the replay
        puts it where it was)."""
        if replay:
            self.stand_pose, self.stand_ctrl = {}, {}
            x, y = self.place
            return np.array([x, y, float(scene.seabed_z(x, y)) + 1.0])
        self.stand_pose, self.stand_ctrl, robot = self.stand(scene.ground, self.gait_drive.gait, dt)
        return robot

    def hold(self, spec: mujoco.MjSpec) -> None:
        """A weld of the torso where it is (``walker/hold``; ``start.preroll`` releases it)."""
        hold = spec.add_equality(name="walker/hold", type=mujoco.mjtEq.mjEQ_WELD, objtype=mujoco.mjtObj.mjOBJ_BODY,
                                 name1=self.body)
        hold.active = True

    def start(self, run) -> None:
        """Bind its gait drive to the compiled model (its pose is set by ``start.preroll``)."""
        m = run.sim.model
        self.gait_drive.bind(m, run.sim.data, m.body(self.body).id)


class Vehicle(RobotEnd):
    """A free-swimming vehicle from its vehicle file (``robot.vehicle``; body ``vehicle``, its
    parts ``vehicle/...``), its origin at ``robot.position``, level at ``robot.heading_deg`` and
    at rest at the start; flown by its autopilot (``VehiclePilot``) or moved along ``robot.path``
    (``PathDrive``)."""

    is_vehicle = True
    body, site = VEHICLE, f"{VEHICLE}/tow_point"
    held = "on its autopilot"

    def __init__(self, robot):
        super().__init__(robot)
        self.heading = math.radians(robot.heading_deg)
        self.spec = None  # its vehicle file (``vehicles.files.VehicleSpec``), loaded by ``add_to``

    def add_to(self, scene) -> None:
        """Load its vehicle file (``scene.vehicle``) and build it at ``robot.position``; moved along
        ``robot.path``, its trim plays no part (no ``TrimDensityWarning``)."""
        spec = load_vehicle(self.robot.vehicle)
        self.spec = scene.vehicle = spec if self.robot.path is None else replace(spec, trimmed=False)
        scene.bodies.append(build_vehicle(scene.spec, self.spec, VEHICLE, pos=self.robot.position))

    def tow_point(self, scene=None, dt: float = 0.0, replay: bool = False) -> np.ndarray:
        """Its tow point at the start (m, world): its origin at ``robot.position``, level, turned
        to its heading: position + R_z(heading) @ the vehicle file's tow point."""
        R = np.zeros(9)
        mujoco.mju_quat2Mat(R, heading_quat(self.heading))
        return np.asarray(self.robot.position, dtype=float) + R.reshape(3, 3) @ np.asarray(self.spec.tow_point)

    def start(self, run) -> None:
        """Level, at its start heading, at rest; then its pilot (``pilot``), and ``vehicle``: its
        rigid-body hydrodynamics in the simulation (the last of ``scene.bodies``)."""
        sim, r, vs = run.sim, self.robot, self.spec
        m = sim.model
        adr = m.joint(f"{VEHICLE}/ball").qposadr[0]
        sim.data.qpos[adr:adr + 4] = heading_quat(self.heading)
        sim.forward()
        self.vehicle = sim.bodies[-1]
        sp = np.array(r.setpoints, dtype=float)
        sp[:, 2] = np.radians(sp[:, 2])
        acts = np.array([m.actuator(f"{VEHICLE}/{t.name}").id for t in vs.thrusters], dtype=int)
        fins = np.array([m.actuator(f"{VEHICLE}/{f.name}").id for f in vs.fins], dtype=int)
        prop = None if vs.propeller is None else m.actuator(f"{VEHICLE}/{vs.propeller.name}").id
        if r.path is not None:  # moved along its path instead of flown
            rows = np.array(r.path, dtype=float)
            rows[:, 2:] = np.radians(rows[:, 2:])
            self.pilot = PathDrive(rows, r.position, r.position, m, self.vehicle)
            return
        self.pilot = VehiclePilot(sp, vs.autopilot, vs.thrusters, acts, route=r.waypoints, start=r.position,
                                  lookahead=r.lookahead, acceptance_radius=r.acceptance_radius, fins=vs.fins,
                                  fin_actuators=fins, propeller=vs.propeller, propeller_actuator=prop,
                                  manoeuvre=manoeuvre_from(r, vs), surface=vs.hydro.surface is not None,
                                  los_integral_gain=r.los_integral_gain,
                                  interpolate=r.setpoint_interpolation == "linear",
                                  pitch_schedule=None if r.pitch_schedule is None else
                                  [(t, math.radians(a)) for t, a in r.pitch_schedule])


ROBOT_ENDS = {"walker": Walker, "anchor": Anchor, "vehicle": Vehicle}
"""The part for each ``robot.type`` (the config refuses any other)."""


def manoeuvre_from(robot, vs) -> Manoeuvre | None:
    """The scenario's manoeuvre (``robot.manoeuvre``) for the vehicle ``vs``, or None."""
    if robot.manoeuvre == "none":
        return None
    yaw = sum(f.yaw_per_angle for f in vs.fins)  # a positive rudder's yaw moment: its sign turns the vehicle
    return Manoeuvre(robot.manoeuvre, robot.manoeuvre_start_s, math.radians(robot.rudder_deg),
                     math.radians(robot.zigzag_heading_deg), [math.radians(a) for a in robot.spiral_rudders_deg],
                     robot.spiral_step_s, turn_sign=math.copysign(1.0, yaw))


@dataclass(frozen=True)
class Ground:
    """The seabed and water a walker stands on (``Walker.stand``): the water column, the seabed's
    plane under the walker (``slope``, and the heading it rises towards, ``slope_heading``, rad;
    on a bathymetry ``grid`` its plane fitted around the walker), the seabed's Coulomb
    ``friction``, its height ``seabed_z(x, y)`` (m), and ``bathymetry``: what names the grid
    (its file; part of what a kept stand is told by)."""

    water: wm.WaterColumn
    slope: float
    slope_heading: float
    friction: float
    seabed_z: Callable
    grid: Bathymetry | None = None
    bathymetry: object = None


@dataclass(frozen=True)
class _Keys:
    """The scenario keys ``start.stand_walker`` reads: ``water.seabed_friction``,
    ``water.bathymetry`` (``_WaterKeys``) and ``robot.start`` (the walker's [robot] section)."""

    water: "_WaterKeys"
    robot: object


@dataclass(frozen=True)
class _WaterKeys:
    seabed_friction: float
    bathymetry: object


@dataclass(frozen=True)
class _Standing:
    """What ``start.stand_walker`` reads of a scenario's ``Scene``, from a ``Ground`` and a
    ``Walker``: the water, the seabed's plane and height, the walker's heading, and the scenario
    keys (``sc``: ``_Keys``)."""

    ground: Ground
    part: Walker

    @property
    def water(self) -> wm.WaterColumn:
        return self.ground.water

    @property
    def grid(self):
        return self.ground.grid

    @property
    def slope(self) -> float:
        return self.ground.slope

    @property
    def slope_heading(self) -> float:
        return self.ground.slope_heading

    @property
    def heading(self) -> float:
        return self.part.heading

    @property
    def tilt(self) -> np.ndarray:
        return np.array(builder.slope_quat(self.ground.slope, self.ground.slope_heading))

    @property
    def sc(self) -> _Keys:
        return _Keys(_WaterKeys(self.ground.friction, self.ground.bathymetry), self.part.robot)

    def seabed_z(self, x, y):
        return self.ground.seabed_z(x, y)

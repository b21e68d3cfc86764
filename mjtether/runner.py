"""Run a scenario: build the MuJoCo model (seabed, ship, tether, robot end), start it from the
quasi-static steady state, step it with the ship's motion and the winch, and record.

The ship is a mocap body at the surface whose site ``ship/fairlead`` holds the tether's node 0.
Modes: ``fixed`` (dynamic positioning), ``follow`` (keeps ``offset`` from the robot, moving at
most at ``speed``), ``waypoints`` (visits them in order at ``speed``); the fairlead may heave
sinusoidally. A mocap body has no velocity, so the soft ``connect`` trails a moving ship by
about 4 dt times its speed. The tether starts from the quasi-static steady state of its initial
configuration; before t = 0 the model is held still for ``PREROLL_S`` so that the seabed
contacts under the laid cable load up.

Recorded every ``output_interval`` (``RECORD_FIELDS`` lists the columns, SI units, world frame
unless the name says ``body``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import mujoco
import numpy as np

from . import builder, water as wm
from .quasistatic import initial_state, steady_state
from .rigidbody import add_body_hydro
from .scenario import Scenario
from .simulation import Simulation
from .walker import HYDRO as WALKER_HYDRO
from .walker import Tripod, walker_spec
from .makeup import LineMakeup
from .tether import TetherSpec
from .winch import Winch

RECORD_FIELDS = [
    ("time", "s", "simulated time"),
    ("ship_tension", "N", "tension at the ship (magnitude of the force on the fairlead)"),
    ("ship_force_x", "N", "force of the tether on the ship, world x"),
    ("ship_force_y", "N", "... world y"),
    ("ship_force_z", "N", "... world z"),
    ("tow_tension", "N", "tension at the robot's tow point"),
    ("tow_force_x", "N", "force of the tether on the robot, world x"),
    ("tow_force_y", "N", "... world y"),
    ("tow_force_z", "N", "... world z"),
    ("tow_force_body_x", "N", "the same force in the robot's body frame (x forward)"),
    ("tow_force_body_y", "N", "... body y (left)"),
    ("tow_force_body_z", "N", "... body z (up)"),
    ("cable_moment_x", "N m", "M_c = r_c x T_c about the robot's centre of mass (Khan Eq. 38), world x"),
    ("cable_moment_y", "N m", "... world y"),
    ("cable_moment_z", "N m", "... world z"),
    ("deployed_length", "m", "unstretched deployed length"),
    ("payout_rate", "m/s", "winch payout rate (negative: reel-in)"),
    ("ship_x", "m", "ship position x"),
    ("ship_y", "m", "ship position y"),
    ("robot_x", "m", "robot (tow point) position x"),
    ("robot_y", "m", "... y"),
    ("robot_z", "m", "... z"),
    ("robot_heading", "deg", "robot heading, from +x towards +y, in (-180, 180]"),
    ("robot_roll", "deg", "robot roll (about its body x, forward), 0 standing level"),
    ("robot_pitch", "deg", "robot pitch (about its body y, left), positive nose down"),
    ("robot_speed", "m/s", "robot horizontal speed"),
    ("tether_lowest_z", "m", "height of the tether's lowest node"),
    ("length_on_seabed", "m", "tether length lying on the seabed (elements with both nodes within one diameter of it)"),
    ("slack_elements", "", "deployed elements carrying no tension"),
]


PREROLL_S = 1.0
"""Seconds simulated before t = 0 with the ship and winch still (see ``ScenarioRun``)."""
WALK_ACCEL = 0.2
"""Largest change of the walker's commanded speed (m/s^2)."""
HEADING_GAIN = 2.0
"""Heading hold of the walker (1/s): turn rate added per radian of heading error."""
MAX_TURN = 0.5
"""Largest turn rate (rad/s) the heading hold asks of the gait."""
MAX_START_STRAIN = 0.1
"""A steady state stretching the tether by more than this is not taken as a start."""
STAND_S = 2.0
"""Seconds the walker stands alone on the seabed to find its resting pose before the run is built."""
SETTLE_S = 10.0
"""Seconds a ``start = "settle"`` run lets the cable fall into place with the robot held."""
FALLBACK_SUBSTEPS = 4
"""Pre-roll sub-steps per time step when the run starts from a guessed shape."""
CONTROL_HZ = 100.0
"""Rate (Hz) at which the gait updates the walker's joint targets."""
WALKER_STAND_HEIGHT = 0.9
"""Height (m) of the walker's torso above the seabed when it is placed."""


def roll_pitch(R: np.ndarray) -> tuple[float, float]:
    """Roll and pitch (rad) of a body with rotation matrix ``R`` (body to world, z-y-x Euler
    angles: heading, then pitch about the body's y, then roll about its x)."""
    return math.atan2(R[2, 1], R[2, 2]), math.asin(max(-1.0, min(1.0, -R[2, 0])))


class RunFailed(RuntimeError):
    """The run stopped: divergence, or the tether's rated load was exceeded."""


def water_from(sc: Scenario) -> wm.WaterColumn:
    """The scenario's water column (headings from degrees to radians)."""
    d, c = sc.water.density, sc.water.current
    if d.type == "constant":
        density = wm.ConstantDensity(d.rho)
    elif d.type == "linear":
        density = wm.LinearDensity(d.rho_surface, d.rho_ref, d.depth_ref)
    else:
        density = wm.TabulatedDensity(d.depths, d.values)
    heading = math.radians(c.heading_deg)
    if c.type == "constant":
        current = wm.ConstantCurrent(c.speed, heading)
    elif c.type == "linear":
        current = wm.LinearCurrent(c.surface_speed, c.bottom_speed, c.bottom_depth, heading=heading)
    elif c.type == "exponential":
        current = wm.ExponentialCurrent(c.surface_speed, c.decay_depth, heading)
    elif c.type == "power":
        current = wm.PowerLawCurrent(c.surface_speed, sc.water.depth, c.exponent, heading)
    else:
        headings = None if c.headings_deg is None else [math.radians(h) for h in c.headings_deg]
        current = wm.TabulatedCurrent(c.depths, c.speeds, headings)
    return wm.WaterColumn(depth=sc.water.depth, density=density, current=current, gravity=sc.water.gravity)


def tether_from(sc: Scenario) -> TetherSpec:
    t = sc.tether
    return TetherSpec(length=t.length, segments=t.segments, diameter=t.diameter,
                      density=None if t.mass_per_length > 0 else t.density,
                      mass_per_length=t.mass_per_length or None, cd_normal=t.cd_normal,
                      cd_tangential=t.cd_tangential, ca_normal=t.ca_normal, EA=t.EA or None, EI=t.EI,
                      added_mass=t.added_mass)


def makeup_from(sc: Scenario) -> LineMakeup | None:
    """The scenario's line make-up (sections, point loads, floats), or None for a uniform tether.
    Point loads and floats on a uniform tether make a one-section make-up of it."""
    t = sc.tether
    if not t.is_makeup:
        return None
    sections = [x.to_makeup() for x in t.sections] or list(LineMakeup.uniform(tether_from(sc)).sections)
    return LineMakeup(sections, [p.to_makeup() for p in (*t.point_loads, *t.floats)])


def winch_from(sc: Scenario) -> Winch:
    w = sc.winch
    return Winch(length=sc.tether.length, mode=w.mode, min_length=w.min_length, max_length=w.max_length,
                 rate=w.rate, max_rate=w.max_rate, max_accel=w.max_accel, band=w.band, drum_damping=w.drum_damping)


@dataclass
class Ship:
    """Kinematics of the ship's fairlead (m, world; z = ``ship.fairlead_z`` plus heave)."""

    mode: str
    position: np.ndarray
    offset: np.ndarray
    waypoints: list
    speed: float
    heave_amplitude: float
    heave_period: float
    _wp: int = field(default=0)

    @classmethod
    def from_scenario(cls, sc: Scenario) -> "Ship":
        s = sc.ship
        return cls(s.mode, np.array([*s.position, s.fairlead_z]), np.array([*s.offset, 0.0]),
                   [np.array([*p, s.fairlead_z]) for p in (s.waypoints or ())], s.speed, s.heave_amplitude,
                   s.heave_period)

    def advance(self, dt: float, t: float, robot: np.ndarray) -> np.ndarray:
        """Move the ship over ``dt`` (s) and return the fairlead position."""
        p = self.position
        if self.mode == "follow":
            target = np.array([robot[0], robot[1], p[2]]) + self.offset
        elif self.mode == "waypoints" and self._wp < len(self.waypoints):
            target = self.waypoints[self._wp]
            if np.linalg.norm(target - p) < 1e-6:
                self._wp += 1
        else:
            target = None  # holding station
        if target is not None:
            step = target - p
            dist = float(np.linalg.norm(step))
            if dist > 0:
                p = p + step * min(1.0, self.speed * dt / dist)
            self.position = p
        if not self.heave_amplitude:
            return p
        heave = self.heave_amplitude * math.sin(2 * math.pi * t / self.heave_period)
        return p + (0.0, 0.0, heave)


class ScenarioRun:
    """A compiled scenario, ready to step. ``record()`` returns one row of ``RECORD_FIELDS``."""

    def __init__(self, sc: Scenario):
        self.sc = sc
        self.water = water_from(sc)
        self.tether_spec = tether_from(sc)
        self.makeup = makeup_from(sc)
        # what the quasi-static solver and the builder take: the make-up, or the uniform cable
        self.line = self.makeup if self.makeup is not None else self.tether_spec
        self.winch = winch_from(sc)
        self.ship = Ship.from_scenario(sc)
        dt = sc.simulation.timestep
        spec = mujoco.MjSpec()
        spec.option.timestep = dt
        spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
        spec.option.gravity = [0.0, 0.0, -self.water.gravity]
        spec.modelname = "mjtether_scenario"
        wsc = sc.water
        self.slope, self.slope_heading = math.radians(wsc.seabed_slope_deg), math.radians(wsc.seabed_slope_heading_deg)
        builder.add_seabed(spec, self.water, friction=wsc.seabed_friction, slope=self.slope,
                           slope_heading=self.slope_heading)
        ship = spec.worldbody.add_body(name="ship", mocap=True, pos=self.ship.advance(0.0, 0.0, np.zeros(3)))
        ship.add_site(name="ship/fairlead")
        ship.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[4.0, 1.5, 1.0], pos=[0, 0, 1.0], contype=0,
                      conaffinity=0, rgba=[0.8, 0.8, 0.85, 1])
        radius = self.end_diameter / 2
        r = sc.robot
        self.walker = r.type == "walker"
        self.heading = math.radians(r.heading_deg) if self.walker else None
        bodies = []
        if self.walker:
            x, y = r.start
            yaw = self.heading
            # stand it at its height over the seabed, its legs square to a sloped seabed
            tilt = np.array(spec.geom("seabed").quat)
            quat = np.zeros(4)
            mujoco.mju_mulQuat(quat, tilt, [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])
            normal = np.zeros(9)
            mujoco.mju_quat2Mat(normal, tilt)
            pos = np.array([x, y, self.seabed_z(x, y)]) + WALKER_STAND_HEIGHT * normal[[2, 5, 8]]
            frame = spec.worldbody.add_frame(pos=pos, quat=quat)
            frame.attach_body(walker_spec().body("torso"), "walker/", "")
            bodies.append(add_body_hydro(spec, "walker/torso", WALKER_HYDRO))
            end = builder.SitePoint("walker/tow_point")
            self.commands = np.array(r.commands, dtype=float)  # (s, m/s, rad/s)
            self.commands[:, 2] = np.radians(self.commands[:, 2])
            self.manual_command = None
            self.gait = Tripod(period=r.gait_period)
            # the walker stands on the seabed first, alone; the tether's steady state is solved to
            # its tow point standing, and the run starts with the walker in that pose
            self._stand, robot = self._standing_pose(spec, bodies, dt)
        else:
            robot = np.array(r.position, dtype=float)
            # a tow point on the seabed holds the cable's axis one radius above it
            robot[2] = max(robot[2], self.seabed_z(robot[0], robot[1]) + radius / math.cos(self.slope))
            end = builder.FixedPoint(robot)
        self.robot_position = robot
        top = np.array(spec.body("ship").pos)
        self.initial, self.initial_note = self._initial_state(top, robot, dt)
        start = sc.simulation.start
        if start == "settle" or (start == "auto" and self.initial is None):
            settle, self.initial = True, None
            self.initial_note = "settled with the robot held" + (
                "" if start == "settle" else f" (no steady state: {self.initial_note})")
        elif self.initial is None:
            raise RunFailed(f"no consistent start: {self.initial_note}; set simulation.start = \"settle\" to let "
                            "the cable fall into place while the robot is held")
        else:
            settle = False
        nodes = self._fallback_nodes(top, robot) if settle else self.initial.nodes
        if settle and self.walker:  # held in place while the cable settles
            hold = spec.add_equality(name="walker/hold", type=mujoco.mjtEq.mjEQ_WELD, objtype=mujoco.mjtObj.mjOBJ_BODY,
                                     name1="walker/torso")
            hold.active = True
        self.tm = builder.add_tether(spec, self.line, builder.SitePoint("ship/fairlead"), end,
                                     water=self.water, nodes=nodes, seabed_friction=sc.tether.seabed_friction,
                                     seabed_stiffness=sc.water.seabed_stiffness or None,
                                     seabed_damping=sc.water.seabed_damping,
                                     max_length=None if self.makeup is not None else self.winch.max_length,
                                     end_at=robot if self.walker else None, added_mass=sc.tether.added_mass)
        self.sim = Simulation(spec, self.water, tethers=[self.tm], bodies=bodies)
        try:
            if self.initial is not None:  # the steady state's seabed friction, carried into the run
                self.sim.tether().preload_friction(self.sim.data, self.initial.tension)
            self._start(sc, dt, settle)
        except BaseException:
            self.sim.close()  # a run that cannot start leaves nothing registered
            raise

    def _start(self, sc: Scenario, dt: float, settle: bool) -> None:
        """Bind the controllers, set the walker's standing pose and pre-roll (see __init__)."""
        self.bt = self.sim.tether()
        m = self.sim.model
        self._since_control = 1.0 / CONTROL_HZ  # the first call sets the targets
        self.heading_ref = self.heading  # rad, the commanded heading (the turn rate integrated)
        self._speed = 0.0  # m/s, the speed the gait is given (ramped towards the command)
        self._vel6 = np.zeros(6)  # mj_objectVelocity's output
        if self.walker:
            self.gait.bind(m, prefix="walker/")
            self.torso = m.body("walker/torso").id
            self.tow_site = m.site("walker/tow_point").id
            d = self.sim.data
            for (body, k), (q, v) in self._stand.items():
                j = m.body_jntadr[m.body(body).id] + k
                d.qpos[m.jnt_qposadr[j]:m.jnt_qposadr[j] + len(q)] = q
                d.qvel[m.jnt_dofadr[j]:m.jnt_dofadr[j] + len(v)] = v
            d.ctrl[:] = self._stand_ctrl
            self.sim.forward()
        # pre-roll: soft contacts carry the laid cable's (and the walker's) weight only once they
        # are pressed in; PREROLL_S of standing still lets them load, then t is reset to 0
        # (a settling start is far from equilibrium: it settles for SETTLE_S with finer steps,
        # the walker held, then PREROLL_S released)
        sub = 1 if not settle else FALLBACK_SUBSTEPS
        m.opt.timestep = dt / sub
        try:
            if settle:
                for _ in range(max(1, int(round(SETTLE_S / dt))) * sub):
                    self._drive(dt / sub, 0.0, 0.0)
                    self.sim.step()
                if self.walker:
                    self.sim.data.eq_active[m.equality("walker/hold").id] = 0
            for _ in range(max(1, int(round(PREROLL_S / dt))) * sub):
                self._drive(dt / sub, 0.0, 0.0)
                self.sim.step()
        finally:
            m.opt.timestep = dt
        self.sim.data.time = 0.0
        self.sim.forward()
        self.ship_mocap = m.body("ship").mocapid[0]
        self.rated_load = sc.tether.rated_load

    def _standing_pose(self, spec, bodies, dt):
        """Let the walker stand (stepping in place) on the seabed for STAND_S without the tether,
        with its hydrodynamics, then put it back at its commanded position and heading; returns
        ({joint: (qpos, qvel)}, tow point (m, world)) of that pose."""
        with Simulation(spec.copy(), self.water, bodies=bodies) as sim:
            m, d = sim.model, sim.data
            gait = Tripod(period=self.gait.period).bind(m, prefix="walker/")
            every = max(1, int(round(1.0 / (CONTROL_HZ * dt))))
            for _ in range(max(1, int(round(STAND_S / (every * dt))))):
                d.ctrl[gait.actuators] = gait.targets(every * dt, 0.0, 0.0)
                sim.step(every)
            # it may have turned or slid a little while its feet found the seabed: put it back at
            # the commanded position and heading, turning it about the seabed's normal
            torso = m.body("walker/torso")
            adr = m.jnt_qposadr[torso.jntadr[0]]
            tilt = np.array(spec.geom("seabed").quat)
            normal = np.zeros(9)
            mujoco.mju_quat2Mat(normal, tilt)
            n = normal[[2, 5, 8]]
            R = d.xmat[torso.id].reshape(3, 3)
            fwd = R[:, 0] - (R[:, 0] @ n) * n  # the body's forward axis in the seabed's plane
            want = np.array([math.cos(self.heading), math.sin(self.heading), 0.0])
            want = want - (want @ n) * n
            turn = math.atan2(np.cross(fwd, want) @ n, fwd @ want)
            q_turn = np.zeros(4)
            mujoco.mju_axisAngle2Quat(q_turn, n, turn)
            q = np.zeros(4)
            mujoco.mju_mulQuat(q, q_turn, d.qpos[adr + 3:adr + 7].copy())
            x, y = self.sc.robot.start
            start = np.array([x, y, self.seabed_z(x, y)])
            p = d.qpos[adr:adr + 3].copy()
            p = start + (p - start) @ n * n  # same height over the seabed, at the commanded place
            d.qpos[adr:adr + 3], d.qpos[adr + 3:adr + 7] = p, q / np.linalg.norm(q)
            d.qvel[:6] = 0.0
            sim.forward()
            pose = {}
            for j in range(m.njnt):  # every joint of the walker's bodies, by (body, index in body)
                body = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(m.jnt_bodyid[j])) or ""
                if body.startswith("walker/"):
                    adr, dof = m.jnt_qposadr[j], m.jnt_dofadr[j]
                    nq, nv = {0: (7, 6), 1: (4, 3), 2: (1, 1), 3: (1, 1)}[int(m.jnt_type[j])]
                    key = (body, j - int(m.body_jntadr[m.jnt_bodyid[j]]))
                    pose[key] = (d.qpos[adr:adr + nq].copy(), d.qvel[dof:dof + nv].copy())
            self._stand_ctrl = d.ctrl.copy()
            self.gait.phase = gait.phase  # the run goes on stepping from where it stood
            return pose, d.site_xpos[m.site("walker/tow_point").id].copy()

    @property
    def end_diameter(self) -> float:
        """Diameter (m) of the cable at the robot end (of the last section of a make-up)."""
        return float(self.makeup.element_diameter[-1]) if self.makeup is not None else self.tether_spec.diameter

    def seabed_z(self, x, y):
        """Height (m) of the (possibly sloped) seabed at ``x``, ``y`` (m)."""
        return builder.seabed_height(self.water, x, y, self.slope, self.slope_heading)

    def _initial_state(self, top, robot, dt):
        """The quasi-static steady state to start from (with the tow point on the seabed the
        seabed is taken one cable radius lower, where the cable's axis lies), or ``None`` and
        why, if there is none; the run then stops, or starts from ``_fallback_nodes`` and
        settles where the scenario asks for it (``simulation.start``)."""
        radius = self.end_diameter / 2
        # the cable's axis rests one radius above the seabed; a walker's tow point is higher: the
        # steady state is solved to the point on the seabed under it, for the length less that
        # height, and the cable then rises straight up to the tow point (on a sloped seabed: a
        # flat one at the depth under the tow point, kept if the line it gives stays clear of
        # the slope)
        depth = -self.seabed_z(robot[0], robot[1]) - radius
        rise = max(robot[2] + depth, 0.0) if self.walker else 0.0
        foot = np.array([robot[0], robot[1], robot[2] - rise])
        water = wm.WaterColumn(depth=depth, density=self.water.density,
                               current=self.water.current, gravity=self.water.gravity)
        L = self.line.length
        reach = float(np.linalg.norm(robot - top))
        if self.makeup is None and self.tether_spec.EA is None and reach >= L:
            return None, (f"no steady state (an inextensible tether of {L:g} m cannot reach from the ship to the "
                          f"robot, {reach:.2f} m away)")
        if rise >= 0.5 * L:
            return None, f"no steady state (the tow point is {rise:.2f} m above the seabed, the tether {L:g} m long)"
        ss, note = self._solve_start(water, top, foot, dt, length=L - rise)
        if ss is None:
            return None, note
        if rise > 0:  # the nodes' material points on the solved line, then up to the tow point
            s_solved = self._arc_lengths(L - rise)
            pts = np.vstack([ss.nodes, robot])
            s_pts = np.r_[s_solved, L]
            s_new = self._arc_lengths(L)
            nodes = np.c_[[np.interp(s_new, s_pts, pts[:, k]) for k in range(3)]].T
            ss = replace(ss, nodes=nodes, velocity=np.zeros_like(nodes), tension=np.interp(
                0.5 * (s_new[1:] + s_new[:-1]), 0.5 * (s_solved[1:] + s_solved[:-1]), ss.tension))
        x = ss.nodes
        EA = self.tether_spec.EA if self.makeup is None else self.makeup.element_EA  # (inf or NaN: inextensible)
        strain = np.nan_to_num(ss.tension / (np.inf if EA is None else EA), nan=0.0)
        if strain.max() > MAX_START_STRAIN:
            j = int(np.argmax(strain))
            return None, (f"no steady state within the tether's strength (it would be stretched by "
                          f"{100 * strain[j]:.0f} %, at {ss.tension[j]:.3g} N)")
        below = float(np.max(self.seabed_z(x[:, 0], x[:, 1]) + radius - x[:, 2]))
        if below > 2 * radius:
            return None, f"no steady state clear of the sloped seabed (it crosses it by {below:.2f} m)"
        return ss, note

    def _solve_start(self, water, top, robot, dt, length=None):
        """``initial_state`` for the scenario's tether, with retries: the laid part's tension
        has a kink where seabed friction takes it all, and a coarse tether's touchdown jumps
        from element to element; either can stall Newton. So: as given; with 4N elements,
        keeping every 4th node (the same material points); then both without friction (the
        run then starts with the friction the laid cable's geometry needs, up to mu w: see
        ``BoundTether.preload_friction``).
        Returns (state, note) or (None, why)."""
        cb = self.sc.tether.seabed_friction
        if self.makeup is not None:
            return self._solve_makeup_start(water, top, robot, length)
        spec = self.tether_spec if length is None else replace(self.tether_spec, length=length)
        sim = self.sc.simulation
        layout = dict(layout=sim.laid_layout, layout_angle=math.radians(sim.laid_layout_angle_deg))
        if self.walker:  # slack cable lies back along the walker's track
            layout["layout_direction"] = (-math.cos(self.heading), -math.sin(self.heading))
        n4 = f" solved with {4 * spec.segments} elements"
        tries = [(1, cb, ""), (4, cb, n4)]
        if cb > 0:
            tries += [(1, 0.0, " without seabed friction"), (4, 0.0, n4 + " without seabed friction")]
        first = None
        for k, friction, how in tries:
            try:
                ss = initial_state(replace(spec, segments=k * spec.segments), water, top, robot, timestep=dt,
                                   seabed=True, seabed_friction=friction, **layout)
            except RuntimeError as exc:  # Newton stalled: try the next way
                first = first or exc
                continue
            except ValueError as exc:  # no steady state exists
                return None, f"no steady state ({exc})"
            if k > 1:
                ss = replace(ss, nodes=ss.nodes[::k].copy(), velocity=ss.velocity[::k].copy(),
                             tension=ss.tension.reshape(-1, k).mean(axis=1), jacobian=None)
            return ss, "quasi-static steady state" + (f"{how} (as given: {first})" if how else "")
        return None, f"no steady state (the solver did not converge: {first})"

    def _solve_makeup_start(self, water, top, robot, length=None):
        """``_solve_start`` for a line make-up: its steady state (``steady_state`` with each
        section's EA; a slack laid make-up is not solved), with seabed friction, then without."""
        line = self.makeup if length is None else self.makeup.truncated(length)
        cb = self.sc.tether.seabed_friction
        first = None
        for friction, how in ((cb, ""), (0.0, " without seabed friction")) if cb > 0 else ((0.0, ""),):
            try:
                ss = steady_state(line, water, top, robot, seabed=True, seabed_friction=friction)
            except RuntimeError as exc:  # Newton stalled (NotImplementedError: a slack make-up)
                if isinstance(exc, NotImplementedError):
                    return None, f"no steady state ({exc})"
                first = first or exc
                continue
            except ValueError as exc:
                return None, f"no steady state ({exc})"
            return ss, "quasi-static steady state of the line make-up" + (f"{how} (as given: {first})" if how else "")
        return None, f"no steady state (the solver did not converge: {first})"

    def _arc_lengths(self, length: float) -> np.ndarray:
        """Unstretched arc lengths (m, from the ship) of the nodes of the tether cut to ``length``
        m (the whole of it, or less its rise to a walker's tow point)."""
        if self.makeup is None:
            return np.linspace(0.0, length, self.tether_spec.segments + 1)
        return self.makeup.truncated(length).node_arc_length

    def _fallback_nodes(self, top, robot) -> np.ndarray:
        """A start that stays above the seabed when there is no steady state: the cable hangs
        straight down from the ship to the seabed, then runs along it to the tow point, with any
        excess length laid as a sideways detour (a slack tether coils on the bottom)."""
        L = self.line.length
        lift = self.end_diameter / 2 / math.cos(self.slope)  # the cable's axis over the seabed

        def on_floor(p):
            return np.array([p[0], p[1], float(self.seabed_z(p[0], p[1])) + lift])

        a = on_floor(top)
        b = on_floor(robot)
        run = np.array([b[0] - a[0], b[1] - a[1], 0.0])
        span = float(np.linalg.norm(b - a))
        excess = L - (top[2] - a[2]) - span - (robot[2] - b[2])
        side = np.array([-run[1], run[0], 0.0]) / max(np.linalg.norm(run), 1e-9) if span > 1e-9 \
            else np.array([0.0, 1.0, 0.0])
        detour = [on_floor(a + side * excess / 2), on_floor(b + side * excess / 2)] if excess > 0 else []
        pts = np.array([top, a, *detour, b, robot])
        seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        s = np.r_[0.0, np.cumsum(seg)]
        u = self._arc_lengths(L) * (s[-1] / L)
        return np.c_[[np.interp(u, s, pts[:, k]) for k in range(3)]].T

    def command(self, t: float) -> tuple[float, float]:
        """The walker's commanded (speed m/s, turn rate rad/s) at time ``t`` (s): the one set
        with ``set_command``, else the scenario's schedule."""
        if self.manual_command is not None:
            return self.manual_command
        k = int(np.searchsorted(self.commands[:, 0], t, side="right")) - 1
        return float(self.commands[k, 1]), float(self.commands[k, 2])

    def set_command(self, speed: float, turn_rate: float) -> None:
        """Command the walker directly (m/s, rad/s), overriding the schedule from now on."""
        self.manual_command = (float(speed), float(turn_rate))

    def _drive(self, dt: float, speed: float, turn_rate: float) -> None:
        """Gait targets at CONTROL_HZ (the position servos run at every step)."""
        if not self.walker:
            return
        self._since_control += dt
        self.heading_ref += turn_rate * dt
        if self._since_control >= 1.0 / CONTROL_HZ - 1e-9:
            # heading hold: the open-loop gait drifts, and the tether's pull turns the walker
            R = self.sim.data.xmat[self.torso].reshape(3, 3)
            err = (self.heading_ref - math.atan2(R[1, 0], R[0, 0]) + math.pi) % (2 * math.pi) - math.pi
            turn = max(-MAX_TURN, min(MAX_TURN, turn_rate + HEADING_GAIN * err))
            # speed changes ramp at WALK_ACCEL: a step in stride jerks the stance legs
            dv = WALK_ACCEL * self._since_control
            self._speed = max(self._speed - dv, min(self._speed + dv, speed))
            self.sim.data.ctrl[self.gait.actuators] = self.gait.targets(self._since_control, self._speed, turn)
            self._since_control = 0.0

    def robot_state(self):
        """(tow point position, yaw (rad), horizontal speed (m/s), body rotation matrix)."""
        d = self.sim.data
        if not self.walker:
            return self.robot_position, 0.0, 0.0, np.eye(3)
        R = d.xmat[self.torso].reshape(3, 3)
        vel = np.zeros(6)  # (angular, linear), world frame, at the torso frame's origin
        mujoco.mj_objectVelocity(self.sim.model, d, mujoco.mjtObj.mjOBJ_BODY, self.torso, vel, 0)
        return d.site_xpos[self.tow_site].copy(), math.atan2(R[1, 0], R[0, 0]), float(np.hypot(*vel[3:5])), R

    def progress_rate(self) -> float:
        """The robot's velocity (m/s) along the cable's direction at the robot, away from the
        ship: the horizontal direction from the cable's node one nominal element back (or the
        ship, if it is straight above) to the tow point."""
        if not self.walker:
            return 0.0
        d = self.sim.data
        bt = self.bt
        x = d.flexvert_xpos[bt.vertadr + bt.n - 1:bt.vertadr + bt.n + 1]  # the last two nodes
        ex, ey = float(x[1, 0] - x[0, 0]), float(x[1, 1] - x[0, 1])
        if math.hypot(ex, ey) < 1e-3 * bt.l0:
            ship = d.mocap_pos[self.ship_mocap]
            ex, ey = float(x[1, 0] - ship[0]), float(x[1, 1] - ship[1])
        vel = self._vel6
        mujoco.mj_objectVelocity(self.sim.model, d, mujoco.mjtObj.mjOBJ_SITE, self.tow_site, vel, 0)
        return float(vel[3] * ex + vel[4] * ey) / max(math.hypot(ex, ey), 1e-9)

    def step(self) -> None:
        sim, dt = self.sim, self.sim.timestep
        t = sim.time
        tow = self.sim.data.site_xpos[self.tow_site] if self.walker else self.robot_position
        if self.walker:
            self._drive(dt, *self.command(t))
        fair = self.ship.advance(dt, t, tow)
        sim.data.mocap_pos[self.ship_mocap] = fair
        tension = self.bt.end_tension(sim.data, "start")
        progress = self.progress_rate() if self.winch.mode == "follow" else 0.0
        self.bt.set_length(self.winch.advance(dt, t, tension, progress), rate=self.winch.current_rate)
        sim.step()
        tension = self.bt.end_tension(sim.data, "start")
        if tension > self.rated_load:
            raise RunFailed(f"ship-end tension {tension:.0f} N exceeded the "
                            f"tether's rated load {self.rated_load:g} N at t = {sim.time:.2f} s")

    def record(self) -> list:
        d = self.sim.data
        fs = self.bt.end_force(d, "start")
        fe = self.bt.end_force(d, "end")
        x = self.bt.nodes(d)
        on_bottom = self.length_on_seabed(x)
        ship = d.mocap_pos[self.ship_mocap]
        tow, yaw, speed, R = self.robot_state()
        if self.walker:  # Khan et al. Eq. 38 about the walker's centre of mass
            moment = np.cross(tow - d.subtree_com[self.torso], fe)
        else:
            moment = np.zeros(3)  # an anchor has no centre of mass of its own
        roll, pitch = roll_pitch(R)
        return [d.time, float(np.linalg.norm(fs)), *fs, float(np.linalg.norm(fe)), *fe, *(R.T @ fe), *moment,
                self.bt.deployed_length, self.winch.current_rate, ship[0], ship[1], *tow, math.degrees(yaw),
                math.degrees(roll), math.degrees(pitch), speed, float(x[:, 2].min()), on_bottom,
                self.bt.slack_count(d)]

    def length_on_seabed(self, x: np.ndarray | None = None) -> float:
        """Unstretched tether length (m) lying on the seabed: the deployed elements with both
        nodes within one diameter of it (``x``: the deployed nodes, if already read)."""
        x = self.bt.nodes(self.sim.data) if x is None else x
        on = x[:, 2] < self.seabed_z(x[:, 0], x[:, 1]) + self.end_diameter
        return float(self.bt.rest_lengths[self.bt.first:][on[1:] & on[:-1]].sum())

    def element_record(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(every node (n+1, 3) m, element tension (n,) N, element length (n,) m), numbered
        from the drum's core; nodes on the drum at the fairlead, their elements 0."""
        d = self.sim.data
        return self.bt.all_nodes(d), self.bt.element_tension(d), self.bt.element_length(d)

    def close(self) -> None:
        self.sim.close()


def run(sc: Scenario, progress=None, keep_nodes: bool = True, video=None, on_start=None, on_end=None):
    """Simulate ``sc``; returns (rows (n, len(RECORD_FIELDS)), history, info). ``history`` has
    ``nodes`` (n, e+1, 3) m, ``tension`` (n, e) N and ``element_length`` (n, e) m for every one
    of the e elements allocated (numbered from the drum's core; see ``element_record``), each
    sample (only the first with ``keep_nodes=False``).
    ``progress(k, n)`` is called as it goes. ``video(runner)`` makes a ``render.VideoRecorder``
    for the built run; frames are then taken as they fall due and the file is finished, or
    deleted if the run fails. ``on_start(runner)`` is called once the run is built and started,
    ``on_end(runner)`` after its last step (not if it fails), e.g. to read what the records do
    not hold. Raises ``RunFailed`` (or ``SimulationDiverged``)."""
    dt = sc.simulation.timestep
    n_steps = int(round(sc.simulation.duration / dt))
    every = max(1, int(round(sc.simulation.output_interval / dt)))
    rows, hist = [], []
    t0 = time.perf_counter()
    runner = ScenarioRun(sc)
    rec = None
    try:
        if on_start is not None:
            on_start(runner)
        rec = video(runner) if video is not None else None
        rows.append(runner.record())
        hist.append(runner.element_record())
        if rec is not None and rec.due(runner.sim.time):
            rec.capture()
        for k in range(1, n_steps + 1):
            runner.step()
            if k % every == 0:
                rows.append(runner.record())
                if keep_nodes:
                    hist.append(runner.element_record())
            if rec is not None and rec.due(runner.sim.time):
                rec.capture()
            if progress and (k % every == 0 or k == n_steps):
                progress(k, n_steps)
        wall = time.perf_counter() - t0
        rows = np.array(rows)
        if not np.all(np.isfinite(rows)):
            raise RunFailed("the run produced non-finite values")
        if on_end is not None:
            on_end(runner)
        if rec is not None:
            rec.finish()
    except BaseException:
        if rec is not None:
            rec.abort()
        raise
    finally:
        runner.close()
    info = {"initial_state": runner.initial_note, "wall_time_s": wall, "simulated_s": n_steps * dt,
            "realtime_factor": n_steps * dt / wall if wall > 0 else math.inf, "steps": n_steps}
    if rec is not None:
        info["video"] = {"file": str(rec.path), "frames": rec.frames, "fps": rec.s.fps, "camera": rec.s.camera,
                         "tension_scale_N": rec.scale}
    history = {"nodes": np.array([h[0] for h in hist]), "tension": np.array([h[1] for h in hist]),
               "element_length": np.array([h[2] for h in hist])}
    return rows, history, info

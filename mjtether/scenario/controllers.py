"""What drives a scenario between physics steps: the walker's gait, the ship's motion, the winch.

Each controller has ``update(run, t, dt)``, called before every physics step with the time at
the step's start (s) and the step (s); it reads the run's state (``run.named``, the simulation)
and writes its commands (joint targets, the ship's mocap position, the deployed length). A
``ScenarioRun`` calls its controllers in a fixed order: the gait, the ship, the winch.

Units SI, world frame; headings in radians from +x towards +y.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field

import numpy as np

from mjtether.vehicles.allocation import allocate
from mjtether.vehicles.files import thrust_matrix
from mjtether.walker import Tripod

from .readouts import roll_pitch

WALK_ACCEL = 0.2
"""Largest change of the walker's commanded speed (m/s^2)."""
HEADING_GAIN = 2.0
"""Heading hold of the walker (1/s): turn rate added per radian of heading error."""
MAX_TURN = 0.5
"""Largest turn rate (rad/s) the heading hold asks of the gait."""
CONTROL_HZ = 100.0
"""Rate (Hz) at which the gait updates the walker's joint targets."""


def heading_error(want: float, have: float) -> float:
    """want - have (rad), wrapped to [-pi, pi)."""
    return (want - have + math.pi) % (2 * math.pi) - math.pi


@dataclass
class Ship:
    """Kinematics of the ship's fairlead (m, world; z = ``ship.fairlead_z`` plus heave).

    Modes: ``fixed`` (dynamic positioning), ``follow`` (keeps ``offset`` from the robot, moving
    at most at ``speed``), ``waypoints`` (visits them in order at ``speed``); the fairlead may
    heave sinusoidally (``heave_amplitude``, ``heave_period``), or ride on the ship's
    wave-frequency motion (``motion``: a ``physics.vessel_motion.ShipMotion`` from the ship's
    RAOs in the scenario's sea, the fairlead at ``fairlead_body`` m in ship axes from its
    reference point), added to its path."""

    mode: str
    position: np.ndarray
    offset: np.ndarray
    waypoints: list
    speed: float
    heave_amplitude: float
    heave_period: float
    _wp: int = field(default=0)
    motion: object = None
    fairlead_body: np.ndarray = field(default_factory=lambda: np.zeros(3))

    @classmethod
    def from_scenario(cls, sc, waves=None) -> "Ship":
        """The scenario's ship; ``waves``: the sea (``physics.waves.WaveField``) its RAOs
        (``ship.motion``) answer, None for a flat sea (no wave-frequency motion)."""
        s = sc.ship
        ship = cls(s.mode, np.array([*s.position, s.fairlead_z]), np.array([*s.offset, 0.0]),
                   [np.array([*p, s.fairlead_z]) for p in (s.waypoints or ())], s.speed, s.heave_amplitude,
                   s.heave_period)
        if s.motion.type == "rao" and waves is not None:
            from mjtether.physics.vessel_motion import RAOTable, ShipMotion
            h, r = math.radians(s.heading_deg), np.array(s.motion.fairlead_m, dtype=float)
            origin = np.array(s.position) - [math.cos(h) * r[0] - math.sin(h) * r[1],
                                             math.sin(h) * r[0] + math.cos(h) * r[1]]
            ship.motion = ShipMotion(RAOTable.from_csv(s.motion.rao_file), waves.components, h, origin=origin,
                                     outside="short_zero" if s.motion.short_waves == "zero" else "error",
                                     ramp_s=waves.ramp_s)
            ship.fairlead_body = r
        return ship

    def wave_motion(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """The fairlead's displacement (m) and velocity (m/s), world, from its path at time
        ``t`` (s): the sinusoidal heave, or the RAOs' response (zeros without either)."""
        if self.motion is not None:
            m = self.motion.point(self.fairlead_body, t)
            return m.offset, m.velocity
        if not self.heave_amplitude:
            return np.zeros(3), np.zeros(3)
        w = 2 * math.pi / self.heave_period
        return (np.array([0.0, 0.0, self.heave_amplitude * math.sin(w * t)]),
                np.array([0.0, 0.0, self.heave_amplitude * w * math.cos(w * t)]))

    def advance(self, dt: float, t: float, robot: np.ndarray) -> np.ndarray:
        """Move the ship over ``dt`` (s) and return the fairlead position."""
        p = self._sail(dt, robot)
        if self.motion is not None:
            return p + self.motion.point(self.fairlead_body, t).offset
        if not self.heave_amplitude:
            return p
        heave = self.heave_amplitude * math.sin(2 * math.pi * t / self.heave_period)
        return p + (0.0, 0.0, heave)

    def _sail(self, dt: float, robot: np.ndarray) -> np.ndarray:
        """Move the ship along its path over ``dt`` (s); the fairlead's position (m, world) on a
        flat sea."""
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
        return p

    @property
    def idle(self) -> bool:
        """Whether ``update`` writes the same pose at every step: holding station on a flat sea,
        with no heave (``ScenarioRun.advance`` then steps in blocks)."""
        return self.mode == "fixed" and self.motion is None and not self.heave_amplitude

    def update(self, run, t: float, dt: float) -> None:
        """Move the ship's mocap body, following the robot's tow point where it follows (with
        RAOs, turned by the ship's roll, pitch and yaw about the fairlead: the fairlead's motion
        is the RAOs' at its place, the hull drawn about it)."""
        tow = run.robot_position if run.named.tow_site is None else run.sim.data.site_xpos[run.named.tow_site]
        d, body = run.sim.data, run.named.ship_mocap
        if self.motion is None:
            d.mocap_pos[body] = self.advance(dt, t, tow)
            return
        offset, attitude = self.motion.hull(self.fairlead_body, t)  # (one evaluation of the step's motion)
        d.mocap_pos[body] = self._sail(dt, tow) + offset
        d.mocap_quat[body] = attitude


class WinchDrive:
    """The winch (``winch.Winch``) on the tether's drum: its law gives the deployed length from
    the ship-end tension (and, following, the robot's progress along the cable); a heave
    ``compensator`` (``cable.heave_compensation``: active, from the fairlead's heave that
    ``ship.wave_motion`` gives; passive, from the tension) adds its offset to that length."""

    def __init__(self, winch, compensator=None, ship=None):
        self.winch, self.compensator, self.ship = winch, compensator, ship

    @property
    def idle(self) -> bool:
        """Whether ``update`` leaves the length as it is at every step: a fixed winch at rest with
        no heave compensator (``ScenarioRun.advance`` then steps in blocks)."""
        return self.winch.mode == "fixed" and self.compensator is None and self.winch.current_rate == 0.0

    def update(self, run, t: float, dt: float) -> None:
        tension = run.ship_end_tension()
        progress = run.named.progress_rate() if self.winch.mode == "follow" else 0.0
        drum = run.bt.drum_element() if self.winch.mode == "free" else None
        length, rate = self.winch.advance(dt, t, tension, progress, drum), self.winch.current_rate
        c = self.compensator
        if c is not None:  # (the fairlead's heave at t: where the ship puts it for this step)
            offset, velocity = self.ship.wave_motion(t)
            if hasattr(c, "stiffness"):  # (its stroke is 0 at the tension the run starts with)
                if c.preload_N == 0.0 and c.length == 0.0:
                    c.preload_N = tension
                c.update(t, dt, tension, float(offset[2]))
            else:
                c.update(t, dt, (float(offset[2]), float(velocity[2])))
            length, rate = length + c.length, rate + c.rate
        run.bt.set_length(length, rate=rate)


class GaitDrive:
    """The walker's gait with a heading hold: commanded speed (m/s) and turn rate (rad/s) from
    the scenario's schedule ``commands`` (rows of time s, speed m/s, turn rate rad/s) or from
    ``set_command``; the gait's joint targets at CONTROL_HZ, the speed ramped at WALK_ACCEL."""

    def __init__(self, commands: np.ndarray, gait_period: float, heading: float):
        self.commands = commands
        self._times = [float(t) for t in commands[:, 0]]  # (bisect on a list: the schedule is read every step)
        self._rows = [(float(v), float(w)) for v, w in commands[:, 1:3]]
        self.manual_command = None
        self.gait = Tripod(period=gait_period)
        self.heading_ref = heading  # rad, the commanded heading (the turn rate integrated)
        self._since_control = 1.0 / CONTROL_HZ  # the first call sets the targets
        self._speed = 0.0  # m/s, the speed the gait is given (ramped towards the command)
        self._torso = self._data = self._xmat = self._ctrl = None

    def bind(self, model, data, torso: int) -> None:
        self.gait.bind(model, prefix="walker/")
        self._torso, self._data = torso, data
        self._xmat, self._ctrl = data.xmat, data.ctrl  # (views: mjData's arrays never move)

    def command(self, t: float) -> tuple[float, float]:
        """The commanded (speed m/s, turn rate rad/s) at time ``t`` (s): the one set with
        ``set_command``, else the scenario's schedule."""
        if self.manual_command is not None:
            return self.manual_command
        return self._rows[bisect.bisect_right(self._times, t) - 1]

    def set_command(self, speed: float, turn_rate: float) -> None:
        """Command the walker directly (m/s, rad/s), overriding the schedule from now on."""
        self.manual_command = (float(speed), float(turn_rate))

    def drive(self, dt: float, speed: float, turn_rate: float) -> None:
        """Gait targets at CONTROL_HZ (the position servos run at every step)."""
        self._since_control += dt
        self.heading_ref += turn_rate * dt
        if self._since_control >= 1.0 / CONTROL_HZ - 1e-9:
            # heading hold: the open-loop gait drifts, and the tether's pull turns the walker
            R = self._xmat[self._torso]  # (row-major: R[1, 0], R[0, 0])
            err = heading_error(self.heading_ref, math.atan2(R[3], R[0]))
            turn = max(-MAX_TURN, min(MAX_TURN, turn_rate + HEADING_GAIN * err))
            # speed changes ramp at WALK_ACCEL: a step in stride jerks the stance legs
            dv = WALK_ACCEL * self._since_control
            self._speed = max(self._speed - dv, min(self._speed + dv, speed))
            self._ctrl[self.gait.actuators] = self.gait.targets(self._since_control, self._speed, turn)
            self._since_control = 0.0

    def update(self, run, t: float, dt: float) -> None:
        self.drive(dt, *self.command(t))


PILOT_HZ = 20.0
"""Rate (Hz) at which a vehicle's autopilot updates its thrusters' commands."""
PILOT_BANDS = (math.inf, 0.5, 1.0)
"""Largest speed (m/s), heading (rad) and depth (m) error the autopilot's proportional terms
see, and beyond which its integrals stop (conditional integration against wind-up): a large
heading or depth step is flown at the moment and force these give, not at one that saturates
every thruster (a speed beyond the vehicle's is asked for in full: its thrusters saturate)."""
MOMENT_WEIGHT = 10.0
"""Weight (1/m) of the moments against the forces in the thrust allocation's least squares (the
least-thrust answer within the limits); where the thrusters cannot give everything, the moments
come first (``vehicles.allocation.allocate``): attitude is kept before a force is met."""


class Manoeuvre:
    """A standard manoeuvre of a vehicle with a rudder (ITTC's free-running trials): from
    ``start`` (s) the rudder is set by it, not by the heading loop, and the propeller's shaft
    speed is held at what it was then. Kinds: ``turning_circle`` (``rudder`` rad held),
    ``zigzag`` (+-``rudder``, reversed each time the heading has changed by ``zigzag_heading``
    rad the way the rudder turns it; the first to the rudder's positive side) and ``spiral``
    (the angles of ``spiral_rudders`` rad, each held ``spiral_step`` s)."""

    def __init__(self, kind: str, start: float, rudder: float = 0.0, zigzag_heading: float = 0.0,
                 spiral_rudders=(), spiral_step: float = 60.0, turn_sign: float = -1.0):
        self.kind, self.start, self.rudder = kind, float(start), float(rudder)
        self.zigzag_heading, self.spiral_rudders = float(zigzag_heading), tuple(spiral_rudders)
        self.spiral_step = float(spiral_step)
        self.turn_sign = turn_sign  # the sign of the heading change a positive rudder makes
        self.rpm = None  # the shaft speed held (rpm), set when the manoeuvre starts
        self._heading0 = None
        self._angle = self.rudder

    def angle(self, t: float, heading: float) -> float | None:
        """The rudder angle (rad) at ``t`` (s), the vehicle heading ``heading`` (rad); None
        before the manoeuvre starts."""
        if t < self.start:
            return None
        if self._heading0 is None:
            self._heading0 = heading
        if self.kind == "turning_circle":
            return self.rudder
        if self.kind == "spiral":
            k = min(int((t - self.start) // self.spiral_step), len(self.spiral_rudders) - 1)
            return self.spiral_rudders[k]
        turned = heading_error(heading, self._heading0) * self.turn_sign * math.copysign(1.0, self._angle)
        if turned >= self.zigzag_heading:  # the heading has gone far enough the rudder's way: reverse it
            self._angle = -self._angle
        return self._angle


class PathDrive:
    """A vehicle moved along a prescribed path (``robot.path``) instead of flown: before each
    physics step its pose and velocity are set to the path's, so that whatever the cable and the
    water do, it moves as given (the fibre-paying AUV study's "AUV moving at equilibrium
    conditions": its thrust makes up the cable's pull, which is the output).

    ``rows``: (time s, speed through the water m/s along the body's x axis, heading rad, pitch
    rad, positive nose down), linear between rows and held after the last; the current at the
    vehicle's depth carries it besides (from the path's second row on; ramped in before it);
    ``start``: the origin's position at t = 0 (m, world); ``body``: the vehicle's
    ``BoundVehicle`` (its joints: three slides from the position it was built at, ``origin0``,
    and a ball)."""

    def __init__(self, rows, start, origin0, model, body):
        self.rows = np.asarray(rows, dtype=float)
        self._p = np.asarray(start, dtype=float).copy()
        self._origin0 = np.asarray(origin0, dtype=float)
        self._t = 0.0
        self._slide = body._v
        ball = model.joint(f"{body.name}/ball")
        self._qball = int(ball.qposadr[0])
        self._wball = body._w

    def _at(self, t: float):
        """(speed, heading, pitch) at t, and the heading's and pitch's rates (rad/s)."""
        r = self.rows
        k = int(np.searchsorted(r[:, 0], t, side="right")) - 1
        if k >= len(r) - 1:
            return float(r[-1, 1]), float(r[-1, 2]), float(r[-1, 3]), 0.0, 0.0
        f = (t - r[k, 0]) / (r[k + 1, 0] - r[k, 0])
        a, b = r[k], r[k + 1]
        span = b[0] - a[0]
        return (float(a[1] + f * (b[1] - a[1])), float(a[2] + f * (b[2] - a[2])), float(a[3] + f * (b[3] - a[3])),
                float((b[2] - a[2]) / span), float((b[3] - a[3]) / span))

    @staticmethod
    def rotation(heading: float, pitch: float) -> np.ndarray:
        """Body to world: R = Rz(heading) Ry(pitch) (z up; a positive pitch turns the nose down)."""
        cp, sp, ch, sh = math.cos(pitch), math.sin(pitch), math.cos(heading), math.sin(heading)
        return np.array([[ch * cp, -sh, ch * sp], [sh * cp, ch, sh * sp], [-sp, 0.0, cp]])

    def carried(self, t: float) -> float:
        """How much of the current carries the vehicle at t: from 0 at rest at the start to all
        of it at the path's second row (its start-up), linearly; a vehicle held at the fairlead
        does not jump to the current's speed, which no drum could follow."""
        t1 = float(self.rows[1, 0]) if len(self.rows) > 1 else 0.0
        return 1.0 if t1 <= 0.0 else min(max(t / t1, 0.0), 1.0)

    def velocity(self, t: float, current) -> np.ndarray:
        """The origin's velocity (m/s, world) at t: the path's speed along the nose through the
        water, plus the ``current`` (m/s, world) that carries it (``carried``)."""
        U, psi, th, _, _ = self._at(t)
        return U * self.rotation(psi, th)[:, 0] + self.carried(t) * current

    def update(self, run, t: float, dt: float) -> None:
        current = run.named.current_at(min(float(self._p[2]), 0.0))
        if t > self._t:  # the origin moves on by the midpoint rule (called again at the same t: no move)
            self._p += (t - self._t) * self.velocity(0.5 * (self._t + t), current)
            self._t = t
        U, psi, th, dpsi, dth = self._at(t)
        R = self.rotation(psi, th)
        d = run.sim.data
        d.qpos[self._slide] = self._p - self._origin0
        d.qvel[self._slide] = U * R[:, 0] + self.carried(t) * current
        cz, sz, cy, sy = math.cos(0.5 * psi), math.sin(0.5 * psi), math.cos(0.5 * th), math.sin(0.5 * th)
        d.qpos[self._qball:self._qball + 4] = [cz * cy, -sz * sy, cz * sy, sz * cy]  # q_z(psi) q_y(pitch)
        w_world = np.array([0.0, 0.0, dpsi]) + dth * R[:, 1]
        d.qvel[self._wball] = R.T @ w_world


class VesselFollow:
    """A vessel carrying the winch that follows the robot (``ship.mode = "follow"`` with
    ``ship.vessel``): its autopilot (``pilot``, a ``VehiclePilot``) holds a station at the
    robot's tow point plus ``offset`` (m, world x, y) moving with the robot's horizontal velocity,
    at ``heading`` (rad)."""

    def __init__(self, pilot, offset, heading: float):
        self.pilot = pilot
        self.offset = np.asarray(offset, dtype=float)[:2]
        self.heading = float(heading)

    def update(self, run, t: float, dt: float) -> None:
        robot = run.named.robot_position
        self.pilot.station = (float(robot[0] + self.offset[0]), float(robot[1] + self.offset[1]), 0.0, self.heading)
        self.pilot.station_velocity = run.named.robot_velocity
        self.pilot.update(run, t, dt)


class VehiclePilot:
    """Speed, heading and depth autopilot of a vehicle (gains: ``vehicles.Autopilot``), and the
    allocation of the wrench it asks for to the thrusters.

    ``setpoints``: rows of (time s, surge speed over ground m/s, heading rad, depth m), each held
    until the next. At PILOT_HZ: a surge force from the speed error (PI), a yaw moment from the
    heading error (PID, on the yaw rate), a world-vertical force from the depth error (PID, on
    the vertical speed), roll and pitch moments towards level (PD), each error clipped to
    ``PILOT_BANDS``; the wrench is met as closely as the thrusters' limits allow, moments first
    (``vehicles.allocation.allocate``: where a thruster saturates, the moments as closely as the
    limits allow, then the forces with those moments held), each thruster's command being the
    thrust wanted (N), which its actuator lags and clips."""

    def __init__(self, setpoints: np.ndarray, gains, thrusters, actuators: np.ndarray, route=None,
                 start=(0.0, 0.0), lookahead: float = 5.0, acceptance_radius: float = 2.0, fins=(),
                 fin_actuators=(), propeller=None, propeller_actuator=None, manoeuvre: Manoeuvre | None = None,
                 surface: bool = False, body=None, los_integral_gain: float = 0.0, interpolate: bool = False,
                 pitch_schedule=None):
        self.setpoints = setpoints
        self.body = body  # the vehicle flown (a vehicle.BoundVehicle); None: the run's robot
        self.route = None if route is None else np.asarray(route, dtype=float)  # rows x, y, depth, speed
        self.lookahead, self.acceptance_radius = float(lookahead), float(acceptance_radius)
        self.los_integral_gain = float(los_integral_gain)  # kappa of integral LOS (0: plain LOS)
        self.interpolate = bool(interpolate)  # setpoints ramped linearly between rows, not held
        # rows (time s, pitch rad, positive nose down), linear between them: flown instead of depth
        self.pitch_schedule = None if pitch_schedule is None else np.asarray(pitch_schedule, dtype=float)
        self._y_int = 0.0  # integral LOS's integral of the cross-track error (m)
        self._leg = 0  # the route's waypoint being steered to
        self._from = np.asarray(start, dtype=float)[:2].copy()  # where the leg starts (m)
        self.station = None  # (x, y, depth, heading) held once the last waypoint is reached
        self.station_velocity = np.zeros(2)  # m/s, world x, y: the station's own (a vessel following)
        self.gains = gains
        self.B = thrust_matrix(thrusters)
        self.lo = np.array([-t.max_reverse for t in thrusters])
        self.hi = np.array([t.max_forward for t in thrusters])
        self.actuators = actuators
        self._i = np.zeros(3)  # integrals of the speed (m), heading (rad s) and depth (m s) errors
        # the most each integral term may ask for: what all the thrusters give along surge, in
        # yaw and along z together (an unreachable speed does not wind the integral up forever)
        most = np.abs(self.B) @ np.maximum(self.hi, -self.lo) if self.B.shape[1] else np.zeros(6)
        ki = np.array([gains.speed_ki, gains.heading_ki, gains.depth_ki])
        self._i_max = np.where(ki > 0, most[[0, 5, 2]] / np.where(ki > 0, ki, 1.0), 0.0)
        self._ki = ki
        self._band = np.array(PILOT_BANDS)
        self._since = 1.0 / PILOT_HZ  # the first call commands
        self.wrench = np.zeros(6)  # the wrench last asked for (N, N m; body frame)
        self._w = np.r_[1.0, 1.0, 1.0, MOMENT_WEIGHT, MOMENT_WEIGHT, MOMENT_WEIGHT]
        if gains.depth_by_pitch:  # a torpedo asks for surge force, pitch and yaw moments only
            self._w = np.r_[1.0, 0.0, 0.0, 0.0, MOMENT_WEIGHT, MOMENT_WEIGHT]
        if surface:  # a surface vessel: heave, roll and pitch are the hydrostatics' (a thrust's pitch
            # moment is no reason to thrust less)
            self._w = np.r_[1.0, 1.0, 0.0, 0.0, 0.0, MOMENT_WEIGHT]
        self._WB = self._w[:, None] * self.B
        self._pinv = np.linalg.pinv(self._WB) if self.B.shape[1] else None  # the unbounded solution
        # fins and a propeller: their columns depend on the speed through the water (``_effectors``)
        self.fins, self.fin_actuators = tuple(fins), np.asarray(fin_actuators, dtype=int)
        self.propeller, self.propeller_actuator = propeller, propeller_actuator
        self._steered = bool(self.fins) or propeller is not None
        self.manoeuvre = manoeuvre
        self._rudders = np.array([f.yaw_per_angle != 0.0 for f in self.fins], dtype=bool)
        if self._steered:
            self._fin_cols = np.array([[*f.lift_direction, *np.cross(f.position, f.lift_direction)]
                                       for f in self.fins]).reshape(-1, 6)
            self._fin_gain = np.array([0.5 * f.area * f.cl_delta for f in self.fins])
            self._fin_max = np.array([f.max_angle for f in self.fins])
            if propeller is not None:
                r = propeller.position
                self._prop_col = np.array([1.0, 0.0, 0.0, 0.0, r[2], -r[1]])
        self._max_pitch = math.radians(gains.max_pitch_deg)
        self._i_pitch = 0.0  # integral of the pitch error (rad s), a vehicle that dives by pitching
        if gains.depth_by_pitch:  # the depth error that asks for the largest pitch, the largest integral
            self._band[2] = gains.max_pitch_deg / gains.depth_pitch_kp if gains.depth_pitch_kp > 0 else math.inf
            self._i_max[2] = gains.max_pitch_deg / gains.depth_pitch_ki if gains.depth_pitch_ki > 0 else 0.0

    def setpoint(self, t: float) -> tuple[float, float, float]:
        """(speed m/s, heading rad, depth m) at ``t`` (s): the row in force, or (``interpolate``)
        ramped linearly between rows (the heading the short way round)."""
        sp = self.setpoints
        k = int(np.searchsorted(sp[:, 0], t, side="right")) - 1
        if not self.interpolate or k + 1 >= len(sp):
            return tuple(float(x) for x in sp[k, 1:])
        f = (t - sp[k, 0]) / (sp[k + 1, 0] - sp[k, 0])
        turn = heading_error(float(sp[k + 1, 2]), float(sp[k, 2]))
        return (float(sp[k, 1] + f * (sp[k + 1, 1] - sp[k, 1])), float(sp[k, 2] + f * turn),
                float(sp[k, 3] + f * (sp[k + 1, 3] - sp[k, 3])))

    def guide(self, p: np.ndarray, heading: float, h: float = 0.0, speed: float = 0.0) -> tuple[float, float, float]:
        """Line-of-sight guidance along the route (Fossen 2021, Sec. 12.3: lookahead-based
        steering): (speed m/s, heading rad, depth m) for the vehicle at ``p`` (m, world); the
        heading aims ``lookahead`` metres down the leg from the vehicle's foot on it. With
        ``los_integral_gain`` kappa > 0, integral LOS (Fossen 2021, Sec. 12.3.3; Borhaug, Pavlov
        and Pettersen 2008): the aim is moved by kappa y_int, where y_int integrates
        U Delta e / (Delta^2 + (e + kappa y_int)^2) over the step ``h`` (s) at the vehicle's
        ``speed`` U (m/s), e the cross-track error: a steady current's offset is taken out. A
        waypoint within ``acceptance_radius`` (horizontally) is passed (and the integral
        restarts); at the last one the vehicle holds station (``station``)."""
        wp = self.route
        while self.station is None and math.hypot(*(wp[self._leg, :2] - p[:2])) < self.acceptance_radius:
            if self._leg == len(wp) - 1:
                self.station = (float(wp[-1, 0]), float(wp[-1, 1]), float(wp[-1, 2]), heading)
            else:
                self._from = wp[self._leg, :2].copy()
                self._leg += 1
                self._y_int = 0.0
        if self.station is not None:
            return 0.0, self.station[3], self.station[2]
        a, b = self._from, wp[self._leg, :2]
        path = math.atan2(b[1] - a[1], b[0] - a[0])
        cross = -(p[0] - a[0]) * math.sin(path) + (p[1] - a[1]) * math.cos(path)  # left of the leg: > 0
        if self.los_integral_gain > 0.0:
            k, delta = self.los_integral_gain, self.lookahead
            self._y_int += h * speed * delta * cross / (delta ** 2 + (cross + k * self._y_int) ** 2)
            cross = cross + k * self._y_int
        return float(wp[self._leg, 3]), path - math.atan(cross / self.lookahead), float(wp[self._leg, 2])

    def update(self, run, t: float, dt: float) -> None:
        self._since += dt
        if self._since < 1.0 / PILOT_HZ - 1e-9:
            return
        h, self._since = self._since, 0.0
        g = self.gains
        vehicle = self.body if self.body is not None else run.vehicle
        nu, R = vehicle.velocity(run.sim.data)
        p = run.sim.data.xpos[vehicle.id]
        yaw = math.atan2(R[1, 0], R[0, 0])
        if self.route is None:
            speed, heading, depth = self.setpoint(t)
        else:
            speed, heading, depth = self.guide(p, yaw, h, math.hypot(*(R @ nu[:3])[:2]))
        e = np.array([speed - nu[0], heading_error(heading, math.atan2(R[1, 0], R[0, 0])),
                      -depth - float(p[2])])
        band = self._band
        if self._steered:  # what the fins can give depends on the speed: so do the integrals' caps
            eff = self._effectors(run, vehicle, nu, R)
            most = np.abs(eff[0]) @ np.maximum(eff[2], -eff[1])
            ki = self._ki[:2]
            self._i_max[:2] = np.where(ki > 0, most[[0, 5]] / np.where(ki > 0, ki, 1.0), 0.0)
        self._i = np.clip(self._i + np.where(np.abs(e) < band, e, 0.0) * h, -self._i_max, self._i_max)
        e = np.clip(e, -band, band)
        w = float((R @ nu[:3])[2])
        X = g.speed_kp * e[0] + g.speed_ki * self._i[0]
        N = g.heading_kp * e[1] - g.heading_kd * nu[5] + g.heading_ki * self._i[1]
        roll, pitch = roll_pitch(R)
        K = -g.roll_kp * roll - g.roll_kd * nu[3]
        if g.depth_by_pitch:  # rise or dive by pitching (pitch > 0: nose down)
            f = np.zeros(3)
            if self.pitch_schedule is not None:  # a pitch profile instead of a depth
                ps = self.pitch_schedule
                pitch_wanted = float(np.interp(t, ps[:, 0], ps[:, 1]))
            else:
                pitch_wanted = -math.radians(g.depth_pitch_kp * e[2] + g.depth_pitch_ki * self._i[2])
                pitch_wanted = max(-self._max_pitch, min(self._max_pitch, pitch_wanted))
            err = pitch_wanted - pitch
            if g.pitch_ki > 0.0 and abs(err) < PILOT_BANDS[1]:  # capped at the fins' pitch moment now
                cap = (np.abs(eff[0][4]) @ np.maximum(eff[2], -eff[1])) / g.pitch_ki if self._steered else 0.0
                self._i_pitch = max(-cap, min(cap, self._i_pitch + err * h))
            M = g.pitch_kp * err - g.pitch_kd * nu[4] + g.pitch_ki * self._i_pitch
        else:
            Z = g.depth_kp * e[2] - g.depth_kd * w + g.depth_ki * self._i[2]
            f = R.T @ np.array([0.0, 0.0, Z])
            M = -g.pitch_kp * pitch - g.pitch_kd * nu[4]
        self.wrench = np.array([X + f[0], f[1], f[2], K, M, N])
        if self.station is not None:  # hold the station: a horizontal PD on the position error and
            # on the velocity relative to the station's own (0 for a fixed one)
            ex, ey = self.station[0] - float(p[0]), self.station[1] - float(p[1])
            c, s = math.cos(yaw), math.sin(yaw)
            vx, vy = self.station_velocity
            self.wrench[0] = f[0] + g.station_kp * (c * ex + s * ey) - g.station_kd * (nu[0] - (c * vx + s * vy))
            self.wrench[1] = f[1] + g.station_kp * (-s * ex + c * ey) - g.station_kd * (nu[1] - (-s * vx + c * vy))
        if self._steered:
            self._allocate(run.sim.data, *eff)
            if self.manoeuvre is not None:
                self._manoeuvre(run, t, yaw)
        elif self.B.shape[1]:  # the least-thrust answer where within the limits, else the moments first
            # (method: lsq_linear's default, which thrusters alone have always been solved with)
            run.sim.data.ctrl[self.actuators] = allocate(self.B, self.lo, self.hi, self.wrench, self._w, self._pinv,
                                                         method="trf")

    def _effectors(self, run, vehicle, nu: np.ndarray, R: np.ndarray):
        """(B 6 x n, lower and upper limits, surge speed through the water m/s, rho kg/m^3): the
        thrusters', fins' (per rad) and propeller's (per N of thrust) wrench per unit of command
        at the present speed through the water, and their limits."""
        z = np.array([min(float(run.sim.data.xpos[vehicle.id][2]), 0.0)])
        water = vehicle.water
        rho = float(water.rho(z)[0])
        v = nu[:3] - R.T @ water.velocity(z)[0]  # through the water, body frame
        cols, lo, hi = [self.B], [self.lo], [self.hi]
        if self.fins:
            U2 = np.array([float(v @ v) - float(f.span @ v) ** 2 for f in self.fins])
            cols.append((self._fin_cols * (rho * U2 * self._fin_gain)[:, None]).T)
            lo.append(-self._fin_max)
            hi.append(self._fin_max)
        u_r = float(v[0])
        if self.propeller is not None:
            p = self.propeller
            cols.append(self._prop_col[:, None])
            lo.append([min(p.thrust(-p.max_rpm, u_r, rho)[0], 0.0)])
            hi.append([max(p.thrust(p.max_rpm, u_r, rho)[0], 0.0)])
        return np.hstack(cols), np.concatenate(lo), np.concatenate(hi), u_r, rho

    def _allocate(self, data, B, lo, hi, u_r: float, rho: float) -> None:
        """Allocate ``wrench`` to thrusters, fins (angle, rad) and a propeller (thrust, turned
        into a shaft speed) with the columns of ``_effectors``: as for thrusters alone, the
        least-squares answer of least effort where it is within the limits, else the moments
        first (``vehicles.allocation.allocate``)."""
        x = allocate(B, lo, hi, self.wrench, self._w)
        n = self.B.shape[1]
        if n:
            data.ctrl[self.actuators] = x[:n]
        if self.fins:
            data.ctrl[self.fin_actuators] = x[n:n + len(self.fins)]
        if self.propeller is not None:
            data.ctrl[self.propeller_actuator] = self.propeller.rpm_for(float(x[-1]), u_r, rho)

    def _manoeuvre(self, run, t: float, yaw: float) -> None:
        """The manoeuvre's rudder angle and held shaft speed, over what the allocation gave."""
        mv, data = self.manoeuvre, run.sim.data
        angle = mv.angle(t, yaw)
        if angle is None:
            return
        data.ctrl[self.fin_actuators[self._rudders]] = angle
        if self.propeller is not None:
            if mv.rpm is None:
                mv.rpm = float(data.act[run.sim.model.actuator_actadr[self.propeller_actuator]])
            data.ctrl[self.propeller_actuator] = mv.rpm

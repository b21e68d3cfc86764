"""Named readouts of a running scenario: what the CLI records, the plots and the renderer draw
and the environments observe, each read the same way from MuJoCo's state.

``run.named`` (a ``ScenarioRun``'s) is a ``Readouts``: ``run.named.ship_tension``,
``run.named.tow_force_body``, ``run.named.robot_heading`` ... (as dm_control's
``physics.named``). Each is computed from the state of the last step when it is read; arrays
are fresh copies. ``record()`` gives one row of ``RECORD_FIELDS``, the columns of
``timeseries.csv``.

Units SI; world frame (z up, surface z = 0) unless the name says ``body`` (the robot's frame:
x forward, y left, z up); angles in radians here, degrees in the record.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mjtether.cable import tangle

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
    # (added later: at the end, so that every earlier column keeps its place)
    ("cable_moment_body_x", "N m", "cable_moment in the robot's body frame (x forward)"),
    ("cable_moment_body_y", "N m", "... body y (left)"),
    ("cable_moment_body_z", "N m", "... body z (up)"),
    ("cable_clearance", "m", "tangle monitor: the cable's smallest clearance from a vehicle's hull (a capsule of its "
     "drawn length and largest half-breadth), thrusters, fins and propeller, the robot's or the vessel's, leaving "
     "out the cable within a hull length of its own tow point (negative: through the hull; that hull length when "
     "no cable is left to check); only in runs with a vehicle"),
    ("cable_self_clearance", "m", "tangle monitor: the cable's smallest distance from itself, between elements "
     "with at least 5 nominal element lengths of cable between them, up to 5 nominal element lengths (or "
     "tangle.self_clearance_m if larger): farther is recorded as that"),
    ("cable_plan_crossings", "", "tangle monitor: how many pairs of such elements cross in plan view"),
    ("cable_wrap", "deg", "tangle monitor: the angle the cable sweeps round the vehicle in plan view within two "
     "hull lengths (or two elements) of it (360: one full turn); only in runs with a vehicle"),
    ("max_compression", "N", "the largest push of any element's constraint since the previous sample, over every "
     "time step (>= 0): a cable carries tension only, so a push is the model's error, which the tension columns "
     "(never negative) leave out; lines.npz's linetether_compression has every element's"),
    ("peak_tension", "N", "the largest tension of any deployed element since the previous sample, over every time "
     "step (a snap's peak falls between samples); lines.npz's linetether_peak_tension has every element's"),
    ("snap_count", "", "snap loads so far: slack-to-taut events of any element (mjtether.cable.snap; "
     "summary.json's snap_loads lists them)"),
    ("wave_elevation", "m", "the sea surface's height at the ship's position (0 on a flat sea)"),
    ("fairlead_z", "m", "height of the fairlead (its heave in a sea state: the ship's motion)"),
    ("heave_compensation", "m", "line paid out by the winch's heave compensator (0 without one): the fairlead's "
     "heave less this is the residual motion the line sees"),
]


def roll_pitch(R: np.ndarray) -> tuple[float, float]:
    """Roll and pitch (rad) of a body with rotation matrix ``R`` (body to world, z-y-x Euler
    angles: heading, then pitch about the body's y, then roll about its x)."""
    return math.atan2(R[2, 1], R[2, 2]), math.asin(max(-1.0, min(1.0, -R[2, 0])))


TANGLE_FIELDS = ("cable_clearance", "cable_self_clearance", "cable_plan_crossings", "cable_wrap")
"""The tangle monitor's columns (``Readouts.tangle``): none without a tether."""
VEHICLE_FIELDS = ("cable_clearance", "cable_wrap")
"""The tangle monitor's columns about a vehicle: written only in a run with one (a vehicle robot
or a vessel carrying the winch)."""

TETHER_FIELDS = ("ship_tension", "ship_force_x", "ship_force_y", "ship_force_z", "tow_tension", "tow_force_x",
                 "tow_force_y", "tow_force_z", "tow_force_body_x", "tow_force_body_y", "tow_force_body_z",
                 "cable_moment_x", "cable_moment_y", "cable_moment_z", "cable_moment_body_x", "cable_moment_body_y",
                 "cable_moment_body_z", "deployed_length", "payout_rate",
                 "tether_lowest_z", "length_on_seabed", "slack_elements", *TANGLE_FIELDS, "max_compression",
                 "peak_tension", "snap_count", "heave_compensation")
"""The record's columns that describe the tether: a run without one (``tether.attached = false``)
writes the others only."""




def _hull(body: int, vs, at_end: bool) -> tuple:
    """A vehicle (``vehicles.VehicleSpec``) for the tangle monitor: its hull as a capsule along
    its body x of its drawn length and largest half-breadth (``size``), its thrusters', fins'
    and propeller's positions, and the arc (its length) of cable by its tow point left out."""
    a, b, c = (float(v) for v in vs.size)
    r = max(b, c)
    half = max(a - r, 0.0)
    pts = [t.position for t in vs.thrusters] + [f.position for f in vs.fins]
    if vs.propeller is not None:
        pts.append(vs.propeller.position)
    return (body, np.array([-half, 0.0, 0.0]), np.array([half, 0.0, 0.0]), r,
            np.asarray(pts, dtype=float).reshape(-1, 3), 2.0 * a, at_end)


class NoTether:
    """What a run without a tether reads where a tether would be (the ``BoundTether`` readouts
    ``Readouts`` uses): nothing deployed, a single node at the ship's fairlead, no forces."""

    first = 0
    deployed_length = 0.0
    l0 = 1.0
    rest_lengths = np.zeros(0)

    def __init__(self, model, data):
        self._fairlead = model.site("ship/fairlead").id

    def end_force(self, data, end: str) -> np.ndarray:
        return np.zeros(3)

    def end_tension(self, data, end: str) -> float:
        return 0.0

    def nodes(self, data) -> np.ndarray:
        return data.site_xpos[self._fairlead][None, :].copy()

    all_nodes = nodes

    def tension(self, data) -> np.ndarray:
        return np.zeros(0)

    element_tension = element_length = element_compression = tension

    def take_peak_compression(self, data=None) -> np.ndarray:
        return np.zeros(0)

    def slack_count(self, data) -> int:
        return 0

    snaps = None


class Readouts:
    """The named readouts of ``run`` (a ``runner.ScenarioRun``), read from its simulation's
    current state."""

    def __init__(self, run):
        self._run = run
        self._sim = run.sim
        self._bt = run.bt if run.bt is not None else NoTether(run.sim.model, run.sim.data)
        m = run.sim.model
        self.ship_mocap = int(m.body("ship").mocapid[0])
        """Mocap index of the ship's body (-1 for a vessel, ``ship.vessel``: a body of its own)."""
        self._ship_body = m.body("ship").id
        # a robot with a body of its own: the walker (its torso) or a vehicle (its hull)
        end = run.scene.robot_end
        self._bodied = end.body is not None
        self.torso = m.body(end.body).id if self._bodied else None
        """Body id of the robot: the walker's torso or the vehicle's hull (None for an anchor)."""
        self.tow_site = m.site(end.site).id if self._bodied else None
        """Site id of the robot's tow point (None for an anchor)."""
        self._vel6 = np.zeros(6)
        # the tangle monitor's vehicles: (body id, hull end a, hull end b, radius, points (body frame),
        # excluded arc m, cable tied at its last node?)
        self.hulls = []
        if run.scene.vehicle is not None:  # a vehicle robot's hull (``robot_ends.Vehicle``)
            self.hulls.append(_hull(m.body(end.body).id, run.scene.vehicle, True))
        if run.scene.vessel is not None:
            self.hulls.append(_hull(self._ship_body, run.scene.vessel, False))
        self.last_tangle = None
        """The latest ``tangle()``: what the record and the monitor's events read."""
        self._peak = (-1, np.zeros(0))  # (simulation revision, N): see peak_compression
        self._peak_tension = (-1, np.zeros(0))  # (simulation revision, N): see peak_tension
        self._fairlead = m.site("ship/fairlead").id

    # ------------------------------------------------------------------ the tether's ends

    @property
    def time(self) -> float:
        """Simulated time (s)."""
        return float(self._sim.data.time)

    @property
    def ship_force(self) -> np.ndarray:
        """Force of the tether on the ship's fairlead (N, world)."""
        return self._bt.end_force(self._sim.data, "start")

    @property
    def ship_tension(self) -> float:
        """Tension at the ship (N): the magnitude of ``ship_force``."""
        return self._bt.end_tension(self._sim.data, "start")

    @property
    def tow_force(self) -> np.ndarray:
        """Force of the tether on the robot's tow point (N, world)."""
        return self._bt.end_force(self._sim.data, "end")

    @property
    def tow_tension(self) -> float:
        """Tension at the robot's tow point (N)."""
        return self._bt.end_tension(self._sim.data, "end")

    @property
    def tow_force_body(self) -> np.ndarray:
        """``tow_force`` in the robot's body frame (N; an anchor's frame is the world's)."""
        return self.robot_rotation.T @ self.tow_force

    @property
    def cable_moment_body(self) -> np.ndarray:
        """``cable_moment`` in the robot's body frame (N m)."""
        return self.robot_rotation.T @ self.cable_moment

    @property
    def cable_moment(self) -> np.ndarray:
        """Moment of the tether's force about the robot's centre of mass (N m, world): M_c =
        r_c x T_c (Khan et al. 2023, Eq. 38); zero for an anchor, which has none of its own."""
        if not self._bodied:
            return np.zeros(3)
        d = self._sim.data
        return np.cross(self.robot_position - d.subtree_com[self.torso], self.tow_force)

    # ------------------------------------------------------------------ winch and ship

    @property
    def deployed_length(self) -> float:
        """Unstretched deployed length (m)."""
        return self._bt.deployed_length

    @property
    def payout_rate(self) -> float:
        """The winch's payout rate (m/s; negative: reel-in)."""
        return self._run.winch.current_rate

    @property
    def ship_position(self) -> np.ndarray:
        """Position of the ship's body (m, world): the prescribed ship's mocap body (the fairlead's,
        less its heave) or a vessel's origin (on its design waterline)."""
        d = self._sim.data
        return (d.mocap_pos[self.ship_mocap] if self.ship_mocap >= 0 else d.xpos[self._ship_body]).copy()

    # ------------------------------------------------------------------ the robot

    @property
    def robot_position(self) -> np.ndarray:
        """The robot's tow point (m, world)."""
        if not self._bodied:
            return np.array(self._run.robot_position, dtype=float)
        return self._sim.data.site_xpos[self.tow_site].copy()

    def robot_state(self):
        """(tow point (m, world), heading (rad), horizontal speed (m/s), body rotation matrix),
        read together."""
        d = self._sim.data
        if not self._bodied:
            return self._run.robot_position, 0.0, 0.0, np.eye(3)
        R = d.xmat[self.torso].reshape(3, 3)
        vel = np.zeros(6)  # (angular, linear), world frame, at the torso frame's origin
        mujoco.mj_objectVelocity(self._sim.model, d, mujoco.mjtObj.mjOBJ_BODY, self.torso, vel, 0)
        return d.site_xpos[self.tow_site].copy(), math.atan2(R[1, 0], R[0, 0]), float(np.hypot(*vel[3:5])), R

    @property
    def robot_rotation(self) -> np.ndarray:
        """The robot's orientation, body to world (3x3; the identity for an anchor)."""
        if not self._bodied:
            return np.eye(3)
        return self._sim.data.xmat[self.torso].reshape(3, 3).copy()

    @property
    def robot_heading(self) -> float:
        """Heading of the robot's body x axis (rad, from +x towards +y; 0 for an anchor)."""
        if not self._bodied:
            return 0.0
        R = self._sim.data.xmat[self.torso].reshape(3, 3)
        return math.atan2(R[1, 0], R[0, 0])

    @property
    def robot_roll_pitch(self) -> tuple[float, float]:
        """Roll and pitch of the robot (rad; see ``roll_pitch``)."""
        return roll_pitch(self.robot_rotation)

    @property
    def robot_velocity(self) -> np.ndarray:
        """Horizontal velocity (m/s, world x and y) of the robot's torso frame (0 for an anchor)."""
        if not self._bodied:
            return np.zeros(2)
        vel = np.zeros(6)  # (angular, linear), world frame, at the torso frame's origin
        mujoco.mj_objectVelocity(self._sim.model, self._sim.data, mujoco.mjtObj.mjOBJ_BODY, self.torso, vel, 0)
        return vel[3:5].copy()

    @property
    def robot_speed(self) -> float:
        """Horizontal speed of the robot (m/s)."""
        return float(np.hypot(*self.robot_velocity))

    @property
    def torso_position(self) -> np.ndarray:
        """Position of the walker's torso frame (m, world)."""
        return self._sim.data.xpos[self.torso].copy()

    @property
    def actuator_power(self) -> float:
        """Mechanical power of the walker's actuators, |force x velocity| summed (W)."""
        d = self._sim.data
        return float(np.abs(d.actuator_force * d.actuator_velocity).sum())

    @property
    def yaw_rate(self) -> float:
        """The walker's angular velocity about world z (rad/s): its free joint's last dof."""
        m = self._sim.model
        return float(self._sim.data.qvel[m.body_dofadr[self.torso] + 5])

    def progress_rate(self) -> float:
        """The robot's velocity (m/s) along the cable's direction at the robot, away from the
        ship: the horizontal direction from the cable's node one nominal element back (or the
        ship, if it is straight above) to the tow point."""
        if not self._bodied:
            return 0.0
        d = self._sim.data
        bt = self._bt
        x = d.flexvert_xpos[bt.vertadr + bt.n - 1:bt.vertadr + bt.n + 1]  # the last two nodes
        ex, ey = float(x[1, 0] - x[0, 0]), float(x[1, 1] - x[0, 1])
        if math.hypot(ex, ey) < 1e-3 * bt.l0:
            ship = self.ship_position
            ex, ey = float(x[1, 0] - ship[0]), float(x[1, 1] - ship[1])
        vel = self._vel6
        mujoco.mj_objectVelocity(self._sim.model, d, mujoco.mjtObj.mjOBJ_SITE, self.tow_site, vel, 0)
        return float(vel[3] * ex + vel[4] * ey) / max(math.hypot(ex, ey), 1e-9)

    # ------------------------------------------------------------------ the tether

    @property
    def tether_nodes(self) -> np.ndarray:
        """The deployed nodes (m, world), shape (N+1, 3), the first at the ship."""
        return self._bt.nodes(self._sim.data)

    @property
    def tether_tension(self) -> np.ndarray:
        """Tension of the deployed elements (N, never negative), the first at the ship."""
        return self._bt.tension(self._sim.data)

    @property
    def element_nodes(self) -> np.ndarray:
        """Every node allocated (m, world), numbered from the drum's core; those on the drum at
        the fairlead."""
        return self._bt.all_nodes(self._sim.data)

    @property
    def element_tension(self) -> np.ndarray:
        """Tension of every element allocated (N); 0 for slack ones and those on the drum."""
        return self._bt.element_tension(self._sim.data)

    @property
    def element_length(self) -> np.ndarray:
        """Stretched length of every element allocated (m); 0 for those on the drum."""
        return self._bt.element_length(self._sim.data)

    @property
    def element_compression(self) -> np.ndarray:
        """Push of every element allocated (N, >= 0; ``BoundTether.element_compression``)."""
        return self._bt.element_compression(self._sim.data)

    @property
    def peak_compression(self) -> np.ndarray:
        """The largest push of every element allocated since the previous sample (N, >= 0),
        over every time step (``BoundTether.take_peak_compression``): reading it at a new state
        of the simulation ends the interval; read again at the same state, the same values."""
        rev = self._sim.revision
        if self._peak[0] != rev:
            self._peak = (rev, self._bt.take_peak_compression(self._sim.data))
        return self._peak[1].copy()

    @property
    def peak_tension(self) -> np.ndarray:
        """The largest tension of every element allocated since the previous sample (N, >= 0),
        over every time step (the snap detector's, ``BoundTether.snaps``; the tension now
        where it has none): read at a new state of the simulation it ends the interval; read
        again at the same state, the same values."""
        rev = self._sim.revision
        if self._peak_tension[0] != rev:
            det = self._bt.snaps
            now = self._bt.element_tension(self._sim.data)
            self._peak_tension = (rev, now if det is None else np.maximum(det.take_interval_max(), now))
        return self._peak_tension[1].copy()

    @property
    def snaps(self) -> list[dict]:
        """The snap loads found so far (``cable.snap.SnapDetector.events``: time_s, element,
        peak_tension_N, slack_duration_s; elements numbered from the drum's core)."""
        det = self._bt.snaps
        return [] if det is None else det.events

    @property
    def slack_elements(self) -> int:
        """Deployed elements carrying no tension."""
        return self._bt.slack_count(self._sim.data)

    def length_on_seabed(self, x: np.ndarray | None = None) -> float:
        """Unstretched tether length (m) lying on the seabed: the deployed elements with both
        nodes within one diameter of it (``x``: the deployed nodes, if already read)."""
        run = self._run
        x = self._bt.nodes(self._sim.data) if x is None else x
        on = x[:, 2] < run.seabed_z(x[:, 0], x[:, 1]) + run.contact_diameter
        return float(self._bt.rest_lengths[self._bt.first:][on[1:] & on[:-1]].sum())

    def touchdown_arc_length(self) -> float | None:
        """Unstretched arc length (m, from the ship) to the first deployed element lying on the
        seabed (as ``length_on_seabed`` counts them), or None if none does."""
        run = self._run
        x = self._bt.nodes(self._sim.data)
        on = x[:, 2] < run.seabed_z(x[:, 0], x[:, 1]) + run.contact_diameter
        lying = on[1:] & on[:-1]
        if not lying.any():
            return None
        return float(self._bt.rest_lengths[self._bt.first:][:int(np.argmax(lying))].sum())

    # ------------------------------------------------------------------ the water

    @property
    def fairlead_position(self) -> np.ndarray:
        """The ship's fairlead (m, world): where the tether leaves the ship, on its motion."""
        return self._sim.data.site_xpos[self._fairlead].copy()

    @property
    def wave_elevation(self) -> float:
        """The sea surface's height (m) at the ship's position now (0 on a flat sea)."""
        waves = self._run.water.waves
        if waves is None:
            return 0.0
        x, y = self.ship_position[:2]
        return float(waves.elevation(float(x), float(y), float(self._sim.data.time)))

    @property
    def heave_compensation(self) -> float:
        """Line (m) the winch's heave compensator has paid out (0 without one)."""
        drive = getattr(self._run, "winch_drive", None)
        c = None if drive is None else drive.compensator
        return 0.0 if c is None else float(c.length)

    def current_at(self, z) -> np.ndarray:
        """Current velocity (m/s, world) at heights ``z`` (m), shape ``z.shape + (3,)``."""
        return self._run.water.velocity(np.asarray(z, dtype=float))

    # ------------------------------------------------------------------ the tangle monitor

    def tangle(self, x: np.ndarray | None = None) -> dict:
        """The tangle monitor (``mjtether.cable.tangle``) on the deployed cable ``x`` (its nodes; read
        now by default): ``clearance`` (m) and ``clearance_at`` (the cable's closest point, m,
        world) from the nearest vehicle, ``self_clearance`` (m) and ``self_clearance_at``,
        ``plan_crossings`` and ``wrap`` (rad). Where there is nothing to check (all the cable
        within the monitor's blind arc: a hull length from a tow point, 5 nominal elements for
        the cable itself; or nothing within the self-clearance's reach), the clearance is +inf
        and its place the ship's fairlead."""
        d = self._sim.data
        x = self._bt.nodes(d) if x is None else x
        out = {"clearance": math.inf, "clearance_at": x[0].copy(), "wrap": 0.0}
        for body, a, b, r, pts, exclude, at_end in self.hulls:
            R, p = d.xmat[body].reshape(3, 3), d.xpos[body]
            c, where = tangle.vehicle_clearance(x, p + R @ a, p + R @ b, r, p + pts @ R.T, exclude, at_end)
            if c < out["clearance"]:
                out["clearance"], out["clearance_at"] = c, where
            out["wrap"] = max(out["wrap"], tangle.wrap_angle(x, p, max(2.0 * exclude, 2.0 * self._bt.l0)))
        blind = 5.0 * self._bt.l0
        c, where, crossings = tangle.self_clearance(x, blind, max(blind, self._run.sc.tangle.self_clearance_m))
        out["self_clearance"], out["self_clearance_at"], out["plan_crossings"] = c, where, crossings
        self.last_tangle = out
        return out

    def tangle_record(self, x: np.ndarray | None = None) -> list:
        """The record's tangle columns (``TANGLE_FIELDS``): where the monitor has nothing to
        check, its blind arc (the shortest hull length) in place of +inf; the cable's clearance
        from itself up to its reach (5 nominal elements, or the scenario's threshold if larger)."""
        t = self.tangle(x)
        blind = min((h[5] for h in self.hulls), default=0.0)
        c = t["clearance"] if math.isfinite(t["clearance"]) else blind
        reach = max(5.0 * self._bt.l0, self._run.sc.tangle.self_clearance_m)
        sc = t["self_clearance"] if math.isfinite(t["self_clearance"]) else reach
        return [c, sc, float(t["plan_crossings"]), math.degrees(t["wrap"])]

    # ------------------------------------------------------------------ the record

    def record(self) -> list:
        """One row of ``RECORD_FIELDS``."""
        d = self._sim.data
        bt = self._bt
        fs = bt.end_force(d, "start")
        fe = bt.end_force(d, "end")
        x = bt.nodes(d)
        on_bottom = self.length_on_seabed(x)
        ship = self.ship_position
        tow, yaw, speed, R = self.robot_state()
        if self._bodied:  # Khan et al. Eq. 38 about the robot's centre of mass
            moment = np.cross(tow - d.subtree_com[self.torso], fe)
        else:
            moment = np.zeros(3)  # an anchor has no centre of mass of its own
        roll, pitch = roll_pitch(R)
        return [d.time, float(np.linalg.norm(fs)), *fs, float(np.linalg.norm(fe)), *fe, *(R.T @ fe), *moment,
                bt.deployed_length, self._run.winch.current_rate, ship[0], ship[1], *tow, math.degrees(yaw),
                math.degrees(roll), math.degrees(pitch), speed, float(x[:, 2].min()), on_bottom,
                bt.slack_count(d), *(R.T @ moment), *self.tangle_record(x),
                float(self.peak_compression.max(initial=0.0)), float(self.peak_tension.max(initial=0.0)),
                0 if bt.snaps is None else len(bt.snaps.events), self.wave_elevation,
                float(d.site_xpos[self._fairlead][2]), self.heave_compensation]

"""Run a scenario: build its scene, start it, step its controllers and physics, and record.

A ``ScenarioRun`` is made of small parts a reader can follow from TOML to CSV:

* ``scene``: the typed configuration as an ``MjSpec`` (water, seabed, ship, the robot end) and
  the library's objects (water column, tether or line make-up, winch, ship kinematics);
* ``robot_ends``: the robot end as a part (walker, anchor or vehicle): its bodies, its tow point
  at the start, the tether's end on it, its hold while the cable settles, its gait or pilot;
* ``start``: the walker's standing pose, the tether's quasi-static steady state (or a settling
  start), the pre-roll that loads the seabed contacts before t = 0;
* ``controllers``: the gait, the ship and the winch, each updated before every physics step;
* ``readouts``: the named readouts (``run.named``) that the record (``RECORD_FIELDS``), the
  plots, the renderer and the environments read.

``run()`` steps a scenario to its end and returns the records.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from mjtether.cable import builder, softening, stability
from mjtether.cable.softening import EAWarning  # noqa: F401 - where it was defined before (runner.EAWarning)
from mjtether.scenario import Scenario, start
from mjtether.simulation import Simulation

from .controllers import GaitDrive, Manoeuvre, PathDrive, Ship, VehiclePilot, VesselFollow, WinchDrive  # noqa: F401 - Ship: the run's ship kinematics
from . import weather
from .sea import compensator_from
from .readouts import RECORD_FIELDS, Readouts, roll_pitch  # noqa: F401 - the record's columns
from .robot_ends import ROBOT_ENDS, manoeuvre_from  # noqa: F401 - the robot ends; where manoeuvre_from was
from .scene import (  # noqa: F401 - where they were found before
    VEHICLE,
    build_scene,
    heading_quat,
    makeup_from,
    tether_from,
    water_from,
    winch_from,
)


STATE_FIELDS = ("qpos", "mocap_pos", "mocap_quat")
"""``ScenarioRun.state``'s arrays, by the names ``run``'s history and ``tether.npz`` give them."""


class RunFailed(RuntimeError):
    """The run stopped: divergence, or the tether's rated load was exceeded; or it could not
    start (``reason``: why there is no steady state to start from, else None)."""

    def __init__(self, message: str, reason: str | None = None):
        super().__init__(message)
        self.reason = reason


class ScenarioRun:
    """A compiled scenario, ready to step: ``step()`` advances one time step (the controllers,
    then the physics); ``named`` holds its readouts; ``record()`` returns one row of
    ``RECORD_FIELDS``.

    ``replay``: the scene built only, to show states saved by a run (``mjtether.io.replay``):
    nothing is stepped or solved (no walker stand, no steady state, no pre-roll); the tether
    starts in ``start.fallback_nodes``'s shape, and the state is the caller's to set."""

    def __init__(self, sc: Scenario, replay: bool = False):
        self.sc = sc
        self.scene = scene = build_scene(sc)
        self.water, self.tether_spec, self.makeup = scene.water, scene.tether_spec, scene.makeup
        self.line, self.winch, self.ship, self.walker = scene.line, scene.winch, scene.ship, scene.walker
        dt = sc.simulation.timestep
        spec = scene.spec
        self.robot_end = end = scene.robot_end  # the walker, the anchor or the vehicle (``robot_ends``)
        self.is_vehicle, self.gait_drive, self.pilot, self.vehicle = end.is_vehicle, end.gait_drive, None, None
        # the tether's steady state is solved to the robot's tow point at the start: the walker's
        # standing (it stands on the seabed first, alone, and the run starts in that pose)
        robot = end.tow_point(scene, dt, replay)
        self.stand_pose, self.stand_ctrl = end.stand_pose, end.stand_ctrl
        self.robot_position = robot
        self.tethered = sc.tether.attached
        top = scene.fairlead_start()
        empty = self.tethered and sc.winch.start_empty
        if replay:
            self.initial, self.initial_note = None, "replayed from saved states"
        elif empty:
            start.check_at_fairlead(top, robot, sc.robot.position)
            self.initial, self.initial_note = None, "nothing deployed: the vehicle starts at the fairlead"
        elif self.tethered:
            self.initial, self.initial_note = start.steady_start(scene, top, robot, dt)
        else:
            self.initial, self.initial_note = None, "no tether: the vehicle runs alone, level and at rest"
        # the quasi-static steady state and its note (why there is none), before a settling start replaces them
        self.steady_state, self.steady_note = self.initial, self.initial_note
        how = sc.simulation.start
        if not self.tethered or empty or replay:
            settle = False
        elif how == "settle" or (how == "auto" and self.initial is None):
            settle, self.initial = True, None
            self.initial_note = f"settled with the robot {end.held}" + (
                "" if how == "settle" else f" (no steady state: {self.initial_note})")
        elif self.initial is None:
            settle_hint = "" if self.initial_note.startswith("tether.length") else (
                "; set simulation.start = \"settle\" to let the cable fall into place while the robot is held")
            raise RunFailed(f"no consistent start: {self.initial_note}{settle_hint}", reason=self.initial_note)
        else:
            settle = False
        # a steady state solved on a level seabed, lying above a sloped or gridded one, falls onto it
        drape = self.tethered and not empty and not settle and not replay and \
            start.floats_over_seabed(scene, self.initial.nodes)
        if drape:
            self.initial_note += (" on a level seabed at the tow point's depth, then settled onto the seabed with "
                                  "the robot held")
        if settle or drape:  # held in place while the cable settles (the walker's weld)
            end.hold(spec)
        self.tm = None
        if self.tethered:
            if empty:  # every node at the fairlead; set_length(0) below stows them on the drum
                nodes = np.tile(top, (self.line.segments + 1, 1))
            else:
                nodes = start.fallback_nodes(scene, top, robot) if settle or replay else self.initial.nodes
            self.tm = builder.add_tether(spec, self.line, builder.SitePoint("ship/fairlead"), end.tether_end(),
                                         water=self.water, nodes=nodes, seabed_friction=sc.tether.seabed_friction,
                                         seabed_stiffness=sc.water.seabed_stiffness or None,
                                         seabed_damping=sc.water.seabed_damping,
                                         max_length=self.winch.max_length if self.makeup.pays_out else None,
                                         end_at=end.end_at(robot),
                                         added_mass=sc.tether.added_mass,
                                         start_at=top)  # (the fairlead's place: no compile to find it)
        self.sim = Simulation(spec, self.water, tethers=[self.tm] if self.tethered else [], bodies=scene.bodies,
                              warn_EA=False)  # (it warns naming tether.EA: _check_EA)
        self._ship_tension = (-1, 0.0)  # (simulation revision, N): see ship_end_tension
        self.ship_pilot = None
        try:
            if scene.vessel is not None:  # the vessel: level at its start heading, on its autopilot
                self.ship_pilot = self._vessel_pilot(scene)
            end.start(self)  # a vehicle level at its start heading, at rest, and its pilot; the gait bound
            self.pilot, self.vehicle = end.pilot, end.vehicle
            if self.initial is not None and not drape:  # the steady state's seabed friction, carried into the run
                self.sim.tether().preload_friction(self.sim.data, self.initial.tension)
            self.bt = self.sim.tether() if self.tethered else None
            with warnings.catch_warnings():
                if replay:  # (the run warned already)
                    warnings.simplefilter("ignore", EAWarning)
                self.effective_EA = self._check_EA() if self.tethered else None
            if empty:
                self.bt.set_length(0.0, rate=0.0)
                self.winch.length = 0.0
                self.sim.forward()
            self.named = Readouts(self)
            self.torso, self.tow_site = self.named.torso, self.named.tow_site
            # the order they act in at each step: the gait or autopilot, then the ship, then the winch
            self.winch_drive = winch = WinchDrive(self.winch, compensator_from(sc), self.ship) \
                if self.tethered else None
            ship = self.ship if self.ship_pilot is None else self.ship_pilot
            self.controllers = [c for c in (*end.controllers, ship, winch) if c is not None]
            weather.attach(self)  # the wind on a vessel and a Gauss-Markov current, stepped first (none: nothing)
            # (alone, or on an empty drum, a vehicle starts as placed: there are no contacts to load)
            if self.tethered and not empty and not replay:
                start.preroll(self, settle or drape, until_still=drape,
                              substeps=start.FALLBACK_SUBSTEPS if settle else 1)
            if self.bt is not None:  # the first sample's pushes are those at t = 0, not the pre-roll's
                self.bt.clear_peak_compression()
                if not replay:  # snap loads from here, each element slack below 1 % of its tension now
                    self.bt.start_snaps()
        except BaseException:
            self.sim.close()  # a run that cannot start leaves nothing registered
            raise
        self.rated_load = sc.tether.rated_load

    def _check_EA(self):
        """The element furthest below the EA asked for (``softening.softening``: {"asked_N",
        "effective_N", "ratio"}, ratio 1: as asked), with a warning, once, where the time step makes
        the cable softer (``builder``: the solver cannot slow its axial mode enough), naming the
        effective EA and the step that would keep it (``stability.ea_timestep``); None for an
        inextensible tether."""
        asked = self.bt.drum.EA[self.bt.drum.first:]  # N, each deployed element's (inf: inextensible)
        elastic = np.isfinite(asked)
        report = softening.softening(asked[elastic], self.bt.effective_EA[elastic]) if elastic.any() else None
        if report is not None and report["ratio"] < softening.SOFT:
            if self.makeup.is_uniform:
                keep = (f"; simulation.timestep = {stability.ea_timestep(self.makeup.tether, self.water):.3g} s or "
                        "less keeps it")
            else:
                keep = f"; a step {report['ratio'] ** 0.5:.3g} times this one keeps it"
            softening.warn("tether.EA", report, self.sc.simulation.timestep, keep, stacklevel=4)
        return report

    def _vessel_pilot(self, scene):
        """Turn the vessel to ``ship.heading_deg`` and give it its autopilot: station on
        ``ship.position`` (fixed), ``ship.waypoints`` at ``ship.speed`` by line-of-sight guidance,
        then station on the last (waypoints), or a station ``ship.offset`` from the robot, moving
        with it (follow: a ``VesselFollow``)."""
        m, s = self.sim.model, self.sc.ship
        adr = m.joint("ship/ball").qposadr[0]
        heading = math.radians(s.heading_deg)
        self.sim.data.qpos[adr:adr + 4] = heading_quat(heading)
        self.sim.forward()
        body = next(b for b in self.sim.bodies if getattr(b, "name", None) == "ship")
        vs = scene.vessel
        acts = np.array([m.actuator(f"ship/{t.name}").id for t in vs.thrusters], dtype=int)
        route = None if s.mode != "waypoints" else [[x, y, 0.0, s.speed] for x, y in s.waypoints]
        pilot = VehiclePilot(np.array([[0.0, 0.0, heading, 0.0]]), vs.autopilot, vs.thrusters, acts, route=route,
                             start=s.position, lookahead=self.sc.robot.lookahead,
                             acceptance_radius=self.sc.robot.acceptance_radius, surface=True, body=body)
        if route is None:
            pilot.station = (float(s.position[0]), float(s.position[1]), 0.0, heading)
        if s.mode == "follow":  # the station moves with the robot, ship.offset from it
            return VesselFollow(pilot, s.offset, heading)
        return pilot

    @property
    def contact_diameter(self) -> float:
        """Diameter (m) of the cable's seabed contact (``Scene.contact_diameter``)."""
        return self.scene.contact_diameter

    def seabed_z(self, x, y):
        """Height (m) of the (possibly sloped) seabed at ``x``, ``y`` (m)."""
        return self.scene.seabed_z(x, y)

    # ------------------------------------------------------------------ commands

    def set_command(self, speed: float, turn_rate: float) -> None:
        """Command the walker directly (m/s, rad/s), overriding the schedule from now on."""
        self.gait_drive.set_command(speed, turn_rate)

    def release_pilot(self) -> None:
        """Hand a vehicle's actuators to the caller (e.g. a Gymnasium agent): its autopilot stops
        commanding them, and whatever is written to ``sim.data.ctrl`` is flown."""
        if self.pilot is None:
            raise RuntimeError("release_pilot: the robot is not a vehicle")
        if self.pilot in self.controllers:
            self.controllers.remove(self.pilot)

    @property
    def heading_ref(self) -> float | None:
        """The walker's commanded heading (rad): its turn rate integrated (None for an anchor)."""
        return None if self.gait_drive is None else self.gait_drive.heading_ref

    # ------------------------------------------------------------------ stepping

    def step(self) -> None:
        """One time step: every controller, then the physics; raises ``RunFailed`` if the
        ship-end tension exceeds the tether's rated load."""
        sim, dt = self.sim, self.sim.timestep
        t = sim.time
        for c in self.controllers:
            c.update(self, t, dt)
        sim.step()
        if self.bt is None:
            return
        tension = self.ship_end_tension()
        if tension > self.rated_load:
            raise RunFailed(f"ship-end tension {tension:.0f} N exceeded the "
                            f"tether's rated load {self.rated_load:g} N at t = {sim.time:.2f} s")

    def advance(self, steps: int) -> None:
        """``steps`` time steps (``step`` each), or, where every controller holds still at every
        step (``idle``: a ship holding station on a flat sea, a fixed winch, nothing else) and no
        rated load is checked, the controllers once and the physics in one call (compiled blocks,
        ``cable.stepping``): the same bits, as their updates would write the same values."""
        if self.blocks and self.rated_load == math.inf and all(getattr(c, "idle", False) for c in self.controllers):
            sim = self.sim
            t = sim.time
            for c in self.controllers:
                c.update(self, t, sim.timestep)
            sim.step(steps)
            return
        for _ in range(steps):
            self.step()

    blocks = True
    """Let ``advance`` step in blocks where it can (False: one ``step`` at a time always)."""

    def ship_end_tension(self) -> float:
        """The ship-end tension (N) now: read once per state of the simulation (``step``'s
        rated-load check reads it after the physics, the winch's law again before the next)."""
        rev = self.sim.revision
        if self._ship_tension[0] != rev:
            self._ship_tension = (rev, self.bt.end_tension(self.sim.data, "start"))
        return self._ship_tension[1]

    # ------------------------------------------------------------------ readouts

    def robot_state(self):
        """(tow point position, yaw (rad), horizontal speed (m/s), body rotation matrix)."""
        return self.named.robot_state()

    def record(self) -> list:
        """One row of ``RECORD_FIELDS``."""
        return self.named.record()

    def length_on_seabed(self, x: np.ndarray | None = None) -> float:
        """Unstretched tether length (m) lying on the seabed (see ``Readouts.length_on_seabed``)."""
        return self.named.length_on_seabed(x)

    def element_record(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(every node (n+1, 3) m, element tension (n,) N, element length (n,) m, each element's
        largest push since the previous sample (n,) N (``Readouts.peak_compression``), each
        element's largest tension since the previous sample (n,) N (``Readouts.peak_tension``)),
        numbered from the drum's core; nodes on the drum at the fairlead, their elements 0."""
        n = self.named
        return n.element_nodes, n.element_tension, n.element_length, n.peak_compression, n.peak_tension

    def state(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The MuJoCo state that places every body (``STATE_FIELDS``): ``qpos`` (nq,), ``mocap_pos``
        (nmocap, 3) m and ``mocap_quat`` (nmocap, 4), copies; what ``mjtether.io.replay`` sets again."""
        d = self.sim.data
        return d.qpos.copy(), d.mocap_pos.copy(), d.mocap_quat.copy()

    def close(self) -> None:
        self.sim.close()


def __getattr__(name):
    """``run`` and the monitors a run checks at its samples live in ``recording`` (the run loop);
    ``runner.run`` and ``from mjtether.scenario.runner import run`` still find them."""
    if name in ("run", "TangleMonitor", "SurfaceWatch"):
        from . import recording
        return getattr(recording, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

"""Build a network in MuJoCo and run it: every line a tether of ``mjtether.cable``, every free
point and free body a rigid body with its hydrodynamics, every held point a world site.

Each line is added with its end B as the tether's start and end A as its end (MoorDyn's ends:
A usually the anchor, B the fairlead). A free point is a body with a free joint carrying the
point's mass, buoyancy (its volume, over its waterline band where it pierces the surface:
``config.waterline_height``), drag (CdA on each of its axes) and added mass (Ca rho V), and
the lumped masses of its lines' end nodes (the sum over the line ends there, with their real
weight): each of those nodes keeps half its mass (``cable.ends.NODE_SHARE``) and its loads, so that a
free line end moves with the line's own inertia (a 10-segment line of 240 kg sliding on the
seabed as 240 kg, not as the 292 kg the drum's conditioning armature at its ends and a point as
heavy as its end node made it), and the point's connects are as well conditioned as the
line's (a massless point given its own 1 g instead moved MoorPy's case8.dat bridle 42 % off
MoorDyn-C). A line's force on a point is its connect's with the moved weight added back
(MoorDyn's: the end node's weight with the line's pull). Coupled and fixed bodies are held at their pose; a
free body starts at the pose where its weight, buoyancy and lines balance (``statics.equilibrium``
with ``bodies=True``; its given pose where that is not found, or with ``simulation.start =
"as_written"``) and settles; a pinned body starts turned to its balance about its pin and turns
on a ball joint there (its added mass there as the diagonal of the rigid-body transform to
the pin, ``rigidbody.BoundBodyHydro``). A vehicle is its
vehicle file's MuJoCo body (``vehicles.build_vehicle``), flown by the scenario's autopilot
(``VehiclePilot``) holding its station; a walker is the scenario's hexapod standing on the seabed,
walking on the scenario's gait drive (``walkers``); a line paying out has its drum at end B, whose deployed
length grows at its payout speed up to its max_length (``BoundTether.set_length``). Lines rest
on the seabed with their axis on it, as MoorDyn's nodes do: each diameter touches its own copy
of the seabed, lowered by its radius (``_add_seabeds``). With seabed friction every line starts
with it mobilised as the statics' catenary has it (``preload_friction``), and the first row's
line forces are those the first step finds (``first_forces``).

The time step is the largest that every line allows (``cable.stability.max_timestep`` at the
steady-state tension, and the seabed contact's limit), at most ``MAX_TIMESTEP``, halved where a run
at it diverges (``simulate``); a MoorDyn file's ``dtM`` is for MoorDyn's explicit integrator and
is not used.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import mujoco
import numpy as np

from mjtether.cable import builder, snap, softening, stability
from mjtether.cable import ends as line_ends
from mjtether.files.results_folder import line_arrays, write_folder
from mjtether.physics import water as wm
from mjtether.physics.rigidbody import RigidBodyHydro, add_body_hydro
from mjtether.scenario.controllers import VehiclePilot
from mjtether.simulation import Simulation, SimulationDiverged, drive
from mjtether.vehicles.files import build_vehicle

from . import cost, statics
from . import walkers as walker_parts
from .config import Network, to_dict, waterline_height

MAX_TIMESTEP = 0.005
"""Longest step taken (s): bodies, vehicles and free points have no stability limit of their own in
``timestep_for`` yet. (At 10 ms, before the seabed contact's damping was capped at b dt = 1, the
three lines of MoorDyn's lines.txt did not settle, tension noise of 25 %, though each line's
stability limits allowed it; at 5 ms they settle as at 2 ms, 0.01 %.)"""


def water_of(net: Network) -> wm.WaterColumn:
    """The network's water column (its current's headings from degrees to radians): a
    ``[water.current]`` made into its ``physics.water`` profile by the scenario's own code
    (``scenario.scene.current_from``), or the ``current_depths`` table; its sea, ``[waves]`` or
    ``water.wave_components`` (``Network.wave_field``: the scenario's ``sea.wave_field``)."""
    current = None
    if net.current is not None:
        from mjtether.scenario.scene import current_from
        current = current_from(net.current, net.depth)
    elif net.current_depths:
        current = wm.TabulatedCurrent(net.current_depths, net.current_speeds,
                                      [math.radians(h) for h in net.current_headings_deg])
    return wm.WaterColumn(depth=net.depth, density=wm.ConstantDensity(net.rho), gravity=net.gravity,
                          waves=net.wave_field(), **({"current": current} if current is not None else {}))


def _quat(rpy_deg) -> list:
    q = np.zeros(4)
    mujoco.mju_euler2Quat(q, np.radians(rpy_deg), "xyz")
    return list(q)


def body_frame(net: Network, name: str):
    """World position (m) and rotation matrix of a body (or vehicle) at its pose in the network,
    or of a walker's torso where it stands (``walkers.torso_frame``)."""
    if name in net.walkers:
        return walker_parts.torso_frame(net, name, water_of(net))
    b = net.bodies.get(name)
    pos, rpy = (b.position, b.rpy_deg) if b is not None else (net.vehicles[name].position,
                                                                (0.0, 0.0, net.vehicles[name].heading_deg))
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, np.array(_quat(rpy)))
    return np.array(pos, float), R.reshape(3, 3)


def start_positions(net: Network) -> dict:
    """World position (m) of every point where the network starts, before the statics."""
    out = {}
    for name, p in net.points.items():
        if p.kind == "body":
            x, R = body_frame(net, p.body)
            out[name] = x + R @ np.array(p.position)
        else:
            out[name] = np.array(p.position, float)
    return out


def timestep_for(net: Network, states: dict, water: wm.WaterColumn) -> float:
    """The largest step (s) at which every line is stable and keeps its EA at its steady tension
    (``stability.max_timestep(keep_EA=True)``, as a scenario's line: ``scenario.stable_step``) and
    the seabed contact is stable, at most ``MAX_TIMESTEP`` where free points, moving bodies or
    vehicles are in it (they have no stability limit of their own yet) and the scenario's
    ``stable_step.MAX_TIMESTEP`` where every point is held."""
    from mjtether.scenario.stable_step import MAX_TIMESTEP as HELD_MAX
    moving = net.vehicles or net.walkers or any(p.kind == "free" for p in net.points.values()) \
        or any(b.kind in MOVING for b in net.bodies.values())
    dts = [MAX_TIMESTEP if moving else HELD_MAX]
    for ln in net.lines:
        lt = net.line_types[ln.type]
        tspec = lt.tether(ln.length, ln.segments)
        st = states[ln.name]
        tension = max(np.linalg.norm(st.force_a), np.linalg.norm(st.force_b))
        dts.append(stability.max_timestep(tspec, water, tension=tension, keep_EA=True))  # (the largest current's drag)
        if net.seabed_stiffness > 0:
            dts.append(0.9 * builder.seabed_contact(tspec, net.rho, net.seabed_stiffness, net.seabed_damping)[2])
    dt = min(dts)
    scale = 10.0 ** (math.floor(math.log10(dt)) - 1)
    return math.floor(dt / scale) * scale  # (2 figures, rounded down)


def line_softening(r: "NetworkRun") -> dict:
    """{line: ``softening.softening`` of its deployed elements} (None for no softening report),
    with an ``EAWarning`` for each line that runs softer than its EA at the run's step."""
    out = {}
    for ln in r.net.lines:
        bt = r.sim.tethers[ln.name]
        rep = softening.softening(r.net.line_types[ln.type].EA, bt.effective_EA)
        keep = (f"; a step {rep['ratio'] ** 0.5:.3g} times this one keeps it" if rep is not None else "")
        softening.warn(f"line {ln.name!r} EA", rep, r.timestep, keep, stacklevel=4)
        out[ln.name] = rep
    return out


@dataclass
class NetworkRun:
    """A network built and ready to step (``sim``), with its start (``note``: how it was found)."""

    net: Network
    sim: Simulation
    point_bodies: dict
    note: str
    timestep: float
    pilots: dict = None  # vehicle name -> its VehiclePilot
    vehicle_bodies: dict = None  # vehicle name -> its BoundVehicle
    walkers: dict = field(default_factory=dict)  # walker name -> its ``walkers.WalkerGait``
    _scratch: mujoco.MjData | None = field(default=None, repr=False)  # (see poses_now)
    history: dict = field(default_factory=dict)  # line name -> its ``record``s, one per sample
    effective_EA: dict = field(default_factory=dict)  # line name -> ``softening.softening`` at the step
    states: list = field(default_factory=list)  # ``qpos`` at each sample's time (see ``record``)
    video: dict | None = None  # the video's file, frames, fps, camera and tension scale, where one was made
    end_inertia: dict = field(default_factory=dict)  # line -> {side: kg}: see ``end_inertia``

    def advance(self, steps: int) -> None:
        """Step ``steps`` times; with vehicles, walkers or winches, their controls act before each step."""
        if not self.pilots and not self.walkers and not any(ln.payout_speed > 0 for ln in self.net.lines):
            self.sim.step(steps)
            return
        dt = self.timestep
        for _ in range(steps):
            t = self.sim.time
            for pilot in self.pilots.values():
                pilot.update(self, t, dt)
            for gait in self.walkers.values():
                gait.update(self, t, dt)
            for ln in self.net.lines:
                if ln.payout_speed > 0:
                    length = ln.length + ln.payout_speed * (t + dt)
                    bt = self.sim.tethers[ln.name]
                    bt.set_length(min(length, ln.max_length), rate=ln.payout_speed if length < ln.max_length else 0.0)
                    if bt.tm.end_mass_to:  # (the drum resets the masses when it releases a node)
                        line_ends.move_end_masses(bt, self.end_inertia[ln.name])
            self.sim.step()

    def deployed_length(self, name: str) -> float:
        """Unstretched length (m) of line ``name`` out of its drum."""
        return float(self.sim.tethers[name].deployed_length)

    def line_forces(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """Forces of line ``name`` on its ends A and B (N, world)."""
        bt = self.sim.tethers[name]
        d = self.sim.data  # (with the weight of the end node's mass its point carries: ``cable.ends``)
        return (bt.end_force(d, "end") + line_ends.moved_weight(bt, "end"),
                bt.end_force(d, "start") + line_ends.moved_weight(bt, "start"))

    def line_nodes(self, name: str) -> np.ndarray:
        """Node positions (m, world) of line ``name`` from end A to end B."""
        return self.sim.tethers[name].nodes(self.sim.data)[::-1].copy()

    def record(self) -> None:
        """Keep every line's nodes (m, world; shape (n+1, 3)), element tensions and pushes (N, >=
        0; shape (n,)), all from end A to end B, in ``history`` (at the state the last step
        began from, as the end forces of ``sample``). A line paying out keeps its full capacity:
        its nodes still on the drum are given at end B, its elements there carry 0."""
        d = self.sim.data
        for ln in self.net.lines:
            bt = self.sim.tethers[ln.name]
            h = self.history.setdefault(ln.name, {"nodes": [], "tension": [], "compression": [], "peak_tension": []})
            h["nodes"].append(bt.all_nodes(d)[::-1])
            tension = bt.element_tension(d)
            h["tension"].append(tension[::-1])
            h["compression"].append(bt.take_peak_compression(d)[::-1])  # (the largest since the last sample)
            h["peak_tension"].append(np.maximum(bt.snaps.take_interval_max(), tension)[::-1])  # (the same)
        self.states.append(d.qpos.copy())  # (the bodies' and points' poses at sim.time: poses_now)

    def point_position(self, name: str) -> np.ndarray:
        return self.sim.data.xpos[self.point_bodies[name]].copy()

    def poses_now(self) -> mujoco.MjData:
        """The bodies' poses at ``sim.time`` (``xpos``, ``xmat``), in a scratch MjData: after a
        step MuJoCo's own kinematics still describe the state the step began from, and are left
        so (the pilots read them between steps)."""
        if self._scratch is None:
            self._scratch = mujoco.MjData(self.sim.model)
        self._scratch.qpos[:] = self.sim.data.qpos
        mujoco.mj_kinematics(self.sim.model, self._scratch)
        return self._scratch


MOVING = ("free", "pinned")
"""The kinds of body that move (on a free joint; on a ball joint at the pin)."""


def moved_end_masses(net: Network) -> dict:
    """{free point: {(line, side): kg}}: the masses of the line end nodes at each free point that
    its body carries (``cable.ends.moved_mass``; side ``"end"`` is the line's end A, ``"start"``
    its end B). Every line end at a free point moves but end B of a line paying out, which
    its drum's payout weighs; such a point weighs its own mass only."""
    out = {name: {} for name, p in net.points.items() if p.kind == "free"}
    for ln in net.lines:
        tether = net.line_types[ln.type].tether(ln.length, ln.segments)
        for side, pid in (("start", ln.b), ("end", ln.a)):
            if pid in out and not (side == "start" and ln.payout_speed > 0):
                out[pid][(ln.name, side)] = line_ends.moved_mass(tether, side)
    return out


def end_inertia(net: Network, moved: dict) -> dict:
    """{line: {side: kg}}: each moved line end's share of its point's inertia (the point's mass,
    its lines' moved masses and its added mass, split among them as their moved masses), which
    its end element is tuned for (``cable.ends.move_end_masses``)."""
    out = {ln.name: {} for ln in net.lines}
    for name, ends_at in moved.items():
        p, total = net.points[name], sum(ends_at.values())
        inertia = p.mass + total + p.ca * net.rho * p.volume
        for (line, side), m in ends_at.items():
            out[line][side] = inertia * m / total
    return out


def build(net: Network) -> NetworkRun:
    """The network in MuJoCo at its steady state (``statics.equilibrium``), or with every point
    where it is given (``net.start == "as_written"``)."""
    water = water_of(net)
    if net.start == "as_written":
        positions, note, poses = start_positions(net), "started as written, at rest", {}
    else:  # (the free and pinned bodies too: their poses where their loads balance)
        positions, note, poses = statics.equilibrium(net, start_positions(net), bodies=True)
    states = {ln.name: statics.line_ends(net, ln, positions[ln.a], positions[ln.b]) for ln in net.lines}
    dt = net.timestep if net.timestep is not None else timestep_for(net, states, water)
    cost.check(net, dt)
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.gravity = [0.0, 0.0, -net.gravity]
    bits = _add_seabeds(spec, net, water)
    hydro = []
    for name, b in net.bodies.items():
        pose = poses.get(name)
        if pose is None:
            pos, quat = list(b.position), _quat(b.rpy_deg)
        else:
            quat = np.zeros(4)
            mujoco.mju_mat2Quat(quat, np.asarray(pose.rotation, float).ravel())
            pos, quat = list(pose.position), list(quat)
        body = spec.worldbody.add_body(name=f"body/{name}", pos=pos, quat=quat)
        if b.kind in MOVING:
            if b.kind == "free":
                body.add_freejoint()
            else:
                body.add_joint(name=f"body/{name}/pin", type=mujoco.mjtJoint.mjJNT_BALL, pos=list(b.pin))
            body.explicitinertial = True  # (else MuJoCo infers the inertia from geoms, and there are none)
            body.mass, body.ipos, body.inertia = b.mass, list(b.cg), list(b.inertia)
            hydro.append(add_body_hydro(spec, f"body/{name}", RigidBodyHydro(
                volume=b.volume, drag_cd=(1.0, 1.0, 1.0), drag_area=b.cd_area,
                added_mass=tuple(c * net.rho * b.volume for c in b.ca), height=waterline_height(b.volume, b.height))))
    for name, v in net.vehicles.items():  # (turned to its heading by its ball joint, below)
        hydro.append(build_vehicle(spec, v.spec, f"body/{name}", pos=v.position))
    for name in net.walkers:  # (its legs put in their standing pose, below)
        hydro.append(walker_parts.attach(spec, net, name, water))
    moved = moved_end_masses(net)
    unmoved = {}  # free point -> the lumped masses of the line ends there that do not move (see moved_end_masses)
    for ln in net.lines:
        if ln.payout_speed > 0 and ln.b in moved:
            unmoved.setdefault(ln.b, []).append(line_ends.lumped_end_mass(
                net.line_types[ln.type].tether(ln.length, ln.segments), "start"))
    for name, p in net.points.items():
        if p.kind != "free":
            continue
        real = p.mass + sum(moved[name].values())  # (a point only at the drum end of lines paying out: as
        mass = max(real, max(unmoved.get(name, [1e-3])))  # heavy as their end nodes, its extra weight compensated)
        r = 0.1
        body = spec.worldbody.add_body(name=f"point/{name}", pos=list(positions[name]))
        body.add_freejoint()
        body.explicitinertial = True  # (the mass at the point: a sphere of radius r)
        body.mass, body.ipos, body.inertia = mass, [0.0, 0.0, 0.0], [0.4 * mass * r * r] * 3
        if mass > real:
            body.gravcomp = (mass - real) / mass
        body.add_site(name=f"point/{name}", size=[r, r, r])
        hydro.append(add_body_hydro(spec, f"point/{name}", RigidBodyHydro(
            volume=p.volume, drag_cd=(1.0, 1.0, 1.0), drag_area=(p.cd_area,) * 3,
            added_mass=(p.ca * net.rho * p.volume,) * 3, height=waterline_height(p.volume, p.height))))
    tms = {}
    for ln in net.lines:
        lt = net.line_types[ln.type]
        ends = [_support(net, positions, pid) for pid in (ln.b, ln.a)]
        nodes = _on_grid(net, states[ln.name].nodes[::-1])
        tms[ln.name] = builder.add_tether(
            spec, lt.tether(ln.length, ln.segments), ends[0], ends[1], water=water, nodes=nodes, name=ln.name,
            seabed_friction=net.seabed_friction, seabed_stiffness=net.seabed_stiffness or None,
            seabed_damping=net.seabed_damping, start_at=positions[ln.b], end_at=positions[ln.a],
            contact_bit=bits[net.line_types[ln.type].diameter],
            max_length=ln.max_length if ln.payout_speed > 0 else None,
            end_mass_to=tuple(side for side, pid in (("start", ln.b), ("end", ln.a))
                              if (ln.name, side) in moved.get(pid, {})))
    sim = Simulation(spec, water, tethers=list(tms.values()), bodies=hydro, warn_EA=False)  # (line_softening warns)
    shares = end_inertia(net, moved)
    for ln in net.lines:
        if tms[ln.name].end_mass_to:
            line_ends.move_end_masses(sim.tethers[ln.name], shares[ln.name])
    vehicle_bodies, pilots = {}, {}
    for name, v in net.vehicles.items():  # (after the Simulation: the pilot flies its bound body)
        vs = v.spec
        bound = next(b for b in sim.bodies if getattr(b, "name", None) == f"body/{name}")
        acts = np.array([sim.model.actuator(f"body/{name}/{t.name}").id for t in vs.thrusters], dtype=int)
        heading = math.radians(v.heading_deg)
        adr = sim.model.joint(f"body/{name}/ball").qposadr[0]  # (its slides stay along the world axes)
        sim.data.qpos[adr:adr + 4] = _quat((0.0, 0.0, v.heading_deg))
        pilot = VehiclePilot(np.array([[0.0, 0.0, heading, v.station[2]]]), vs.autopilot, vs.thrusters, acts,
                             start=v.position, body=bound)
        pilot.station = (v.station[0], v.station[1], v.station[2], heading)
        vehicle_bodies[name], pilots[name] = bound, pilot
    point_bodies = {}
    for name, p in net.points.items():
        if p.kind == "free":
            bid = sim.model.body(f"point/{name}").id
            point_bodies[name] = bid
            sim.data.xfrc_applied[bid, :3] = p.force
    if net.seabed_friction > 0:
        preload_friction(sim, net, positions)
    sim.forward()
    gaits = walker_parts.start(sim, net, water)
    r = NetworkRun(net, sim, point_bodies, note, dt, pilots, vehicle_bodies, walkers=gaits, end_inertia=shares)
    r.effective_EA = line_softening(r)
    return r


def preload_friction(sim: Simulation, net: Network, positions: dict) -> None:
    """Start every line's seabed friction from its steady state, as a scenario starts its tether
    (``BoundTether.preload_friction``): the stick points of its laid nodes are placed so that
    friction holds them as they lie, under each element's tension in the statics
    (``steady_tension``). Without it a laid line starts with no friction mobilised, as a line
    just laid and never pulled."""
    for ln in net.lines:
        bt = sim.tethers[ln.name]
        bt.preload_friction(sim.data, steady_tension(net, ln, positions[ln.a], positions[ln.b])[::-1])


def steady_tension(net: Network, ln, pa, pb) -> np.ndarray:
    """The tension (N) of each element of line ``ln``, from end A to end B, in its steady state
    with its ends at ``pa`` and ``pb`` (m, world; ``statics.line_ends``): the elastic catenary's
    with seabed friction at each element's middle, where the catenary gave its shape, else EA
    times the strain of its chord. (Not the chords' strain of a catenary: a chord is shorter than
    its arc, by 1e-5 on a 5 m element of a chain with w / H = 3e-3 1/m, which a stiff chain's
    strain of 5e-4 feels as a tension 2 % short.)"""
    lt, state = net.line_types[ln.type], statics.line_ends(net, ln, pa, pb)
    x, rest = state.nodes, ln.length / ln.segments
    T = lt.EA * np.maximum(np.linalg.norm(np.diff(x, axis=0), axis=1) / rest - 1.0, 0.0)
    if state.catenary:  # (as line_ends found it: from the low end up)
        pa, pb = np.asarray(pa, float), np.asarray(pb, float)
        lo, hi = (pa, pb) if pa[2] <= pb[2] else (pb, pa)
        on_bottom = lo[2] <= net.seabed_height(lo[0], lo[1]) + 1e-3 * ln.length
        c = statics._catenary(lo, hi, ln.length, lt.wet_weight(net.rho, net.gravity), lt.EA, net.seabed_friction,
                              on_bottom)
        if c is not None:
            T = c.tension((np.arange(ln.segments) + 0.5) * rest)
            T = T if pa[2] <= pb[2] else T[::-1]
    return T


def _add_seabeds(spec: mujoco.MjSpec, net: Network, water: wm.WaterColumn) -> dict:
    """The seabed (a plane, or the network's grid as a height field), on which bodies and vehicles
    rest, and for each line diameter d a copy of it lowered by d/2 that only lines of that
    diameter touch, so that they rest with their axis on the seabed, as MoorDyn's nodes do (see
    ``builder.add_tether``'s ``contact_bit``). Returns {d: the contact bit of its copy}."""
    def seabed(**kw):
        if net.grid is not None:
            return builder.add_seabed_grid(spec, net.grid, friction=net.seabed_friction, **kw)
        return builder.add_seabed(spec, water, friction=net.seabed_friction, **kw)

    seabed()
    diameters = sorted({net.line_types[ln.type].diameter for ln in net.lines})
    if len(diameters) > 29:  # (a contact bit each, above the robots' and the default tether's)
        raise ValueError(f"a network's lines come in at most 29 diameters; this one has {len(diameters)}")
    bits = {}
    for i, d in enumerate(diameters):
        bits[d] = 4 << i
        seabed(name=f"seabed/d{i}", lower=d / 2, bits=(0, bits[d]), rgba=(0.0, 0.0, 0.0, 0.0))
    return bits


def _on_grid(net: Network, nodes: np.ndarray) -> np.ndarray:
    """``nodes`` (m, world), those below a bathymetry grid lifted onto it (axis on it, as lines
    rest): the statics lay a line on a level seabed at its low end's depth, which put a slope's
    uphill nodes inside it (a line laid down 10 deg was thrown out and folded)."""
    if net.grid is None:
        return nodes
    out = np.array(nodes, float)
    out[:, 2] = np.maximum(out[:, 2], [net.grid.height(x, y) for x, y in out[:, :2]])
    return out


def _support(net: Network, positions: dict, pid: str):
    p = net.points[pid]
    if p.kind == "free":
        return builder.SitePoint(f"point/{pid}")
    if p.kind == "body":
        if p.body in net.walkers:
            return walker_parts.support(p.body, p.position)
        return builder.BodyPoint(f"body/{p.body}", p.position)
    return builder.FixedPoint(positions[pid])


SETTLE_RATE = 1.0
"""Damping (1/s, per unit of each degree of freedom's mass) while a network settles."""
SETTLED_SPEED = 1e-3
"""A settling network has settled when no degree of freedom moves faster than this (m/s, rad/s)."""


def settle(r: NetworkRun, duration: float) -> None:
    """Let the network fall into place for up to ``duration`` (s) with every degree of freedom
    damped at ``SETTLE_RATE`` (MuJoCo's joint damping, integrated implicitly), as MoorDyn's
    dynamic relaxation does before its run, stopping once it has settled (every speed below
    ``SETTLED_SPEED``, checked each second, as MoorDyn checks its threshIC); then take the
    damping off, stop every motion and start the clock at 0."""
    m, d = r.sim.model, r.sim.data
    saved = m.dof_damping.copy()
    m.dof_damping[:] = saved + SETTLE_RATE / np.maximum(m.dof_invweight0, 1e-12)
    every = max(1, round(1.0 / r.timestep))
    total, done = max(1, round(duration / r.timestep)), 0
    try:
        while done < total:
            k = min(every, total - done)
            r.sim.step(k)
            done += k
            if float(np.abs(d.qvel).max()) < SETTLED_SPEED:
                break
    finally:
        m.dof_damping[:] = saved
    d.qvel[:] = 0.0
    d.time = 0.0
    r.note += f"; settled for {done * r.timestep:g} s with damping"
    r.sim.forward()


def columns(net: Network) -> list[str]:
    """The time series' columns: per line, the tension (N) and its horizontal and vertical parts
    at ends A and B and its stretched length (m); per free point and free or pinned body, its
    position (m);
    per vehicle, its position (m) and heading (deg); per walker, its torso's position (m) and
    heading (deg: ``walkers.columns``); per line paying out, its deployed length (m)."""
    cols = ["time_s"]
    for ln in net.lines:
        for end in ("A", "B"):
            cols += [f"line{ln.name}_{end}_tension_N", f"line{ln.name}_{end}_horizontal_N",
                     f"line{ln.name}_{end}_vertical_N"]
        cols.append(f"line{ln.name}_length_m")
    for name, p in net.points.items():
        if p.kind == "free":
            cols += [f"point{name}_{k}_m" for k in "xyz"]
    for name, b in net.bodies.items():
        if b.kind in MOVING:
            cols += [f"body{name}_{k}_m" for k in "xyz"]
    for name in net.vehicles:
        cols += [f"vehicle{name}_{k}_m" for k in "xyz"] + [f"vehicle{name}_heading_deg"]
    cols += walker_parts.columns(net)
    cols += [f"line{ln.name}_deployed_m" for ln in net.lines if ln.payout_speed > 0]
    return cols


def sample(r: NetworkRun) -> list[float]:
    """One row of ``columns``. The line forces and lengths are the last step's (found at the
    state that step began from); the positions of points, bodies and vehicles are at
    ``sim.time`` (``NetworkRun.poses_now``)."""
    row = [r.sim.time]
    for ln in r.net.lines:
        for f in r.line_forces(ln.name):
            row += [float(np.linalg.norm(f)), float(math.hypot(f[0], f[1])), float(abs(f[2]))]
        row.append(r.sim.tethers[ln.name].stretched_length(r.sim.data))
    now = r.poses_now()
    for bid in r.point_bodies.values():
        row += list(now.xpos[bid])
    for name, b in r.net.bodies.items():
        if b.kind in MOVING:
            row += list(now.xpos[r.sim.model.body(f"body/{name}").id])
    for name, body in r.vehicle_bodies.items():
        R = now.xmat[body.id].reshape(3, 3)
        row += list(now.xpos[body.id]) + [math.degrees(math.atan2(R[1, 0], R[0, 0]))]
    row += walker_parts.sample(r.net, r.sim.model, now)
    row += [r.deployed_length(ln.name) for ln in r.net.lines if ln.payout_speed > 0]
    return row


class NetworkResult(NamedTuple):
    """What ``simulate`` and ``run_to`` return (``r, rows = simulate(net)`` still unpacks it)."""

    run: NetworkRun
    rows: np.ndarray


def simulate(net: Network, progress=None, video=None) -> NetworkResult:
    """Run ``net`` for its duration; returns ``NetworkResult(run, rows)``: the run (at its final
    state; ``r.sim.close()`` when done) and the time series (rows of ``columns``, one per output
    interval from the start and one at the end, ``simulation.drive``). ``video(r)``, where
    given, makes a recorder (``due(t)``, ``capture()``, ``finish()``, ``abort()``: as
    ``mjtether.io.render.VideoRecorder``) that takes a frame at the first step on or after each
    frame's time, is finished with the run and aborted if it fails (``r.video`` says what it
    wrote). Raises
    SimulationDiverged. Where mjtether chose the step (no ``simulation.timestep``) and the run
    diverges, it runs again from its start at half the step, up to ``RETRIES`` times, and its
    note says so: the step limits hold near the steady state, and a start far from it (a line
    written 40 % longer than its ends allow, released at rest) snaps its nodes to speeds at
    which the explicit drag needs a finer step."""
    halved, why = 0, []
    while True:
        r = build(net)
        try:
            table = _run(r, progress, video)
        except SimulationDiverged as exc:
            if net.timestep is not None or halved == RETRIES:
                raise
            why.append(f"{r.timestep:g} s ({exc})")
            net = dataclasses.replace(net, timestep=r.timestep / 2)
            halved += 1
            continue
        if why:
            r.note += f"; run at {r.timestep:g} s: the run diverged at " + ", then at ".join(why)
        return NetworkResult(r, table)


def first_forces(r: NetworkRun) -> None:
    """The constraint forces at the start (the first sample's line forces) as the first step
    finds them: ``mj_forward`` with the slack elements switched as a step switches them (an
    element whose equality pushed goes slack, and the forces are found again, up to
    ``simulation.SLACK_REDOS`` times), not with the elements that started taut but push, whose
    forces the first step throws away. (These are the model's forces at its start: where the
    start is not the model's own equilibrium, a line left unsettled whose nodes are the
    continuous catenary's, the first rows show the swing that follows.)"""
    from mjtether.simulation import SLACK_REDOS
    r.sim.forward()
    for _ in range(SLACK_REDOS):
        changed = False
        for bt in r.sim.tethers.values():
            changed |= bt.update_slack()
        if not changed:
            break
        r.sim.forward()


RETRIES = 3
"""Times a network run at mjtether's own step is run again at half the step after it diverges."""


def _run(r: NetworkRun, progress=None, video=None) -> np.ndarray:
    """``simulate``'s run of the built ``r`` (``simulation.drive``, every system's run loop): its
    rows; ``r.sim`` closed (and the video aborted) if it fails."""
    net = r.net
    rec = None
    try:
        if net.settle > 0 and net.start == "steady":
            settle(r, net.settle)
        every = max(1, round(net.output_interval / r.timestep))
        total = max(1, round(net.duration / r.timestep))
        for bt in r.sim.tethers.values():  # (the settling's pushes are not the run's; its snaps from here)
            bt.clear_peak_compression()
            bt.start_snaps()
        first_forces(r)
        rec = video(r) if video is not None else None

        def on_sample():
            row = sample(r)
            r.record()
            return row

        table = drive(r.advance, total, every, on_sample, clock=lambda: r.sim.time, video=rec, progress=progress,
                      names=columns(net)).rows
        if rec is not None:
            path = rec.finish()
            r.video = {"file": Path(path).name, "frames": rec.frames, "fps": rec.s.fps, "camera": rec.s.camera,
                       "tension_scale_N": rec.scale}
    except BaseException:
        if rec is not None:
            rec.abort()
        r.sim.close()
        raise
    return table


def write(r: NetworkRun, rows: np.ndarray, folder, *, source=None, wall_time: float = 0.0,
          plots: bool = True) -> None:
    """The results of a run into ``folder`` (a staging folder, ``outdir.Staging``, committed when
    written; or a plain empty folder) by the writer every system shares
    (``files.results_folder.write_folder``): ``timeseries.csv`` (``columns``), ``lines.npz``,
    ``summary.json`` and, with ``plots``, ``tension.png`` and ``profile.png``
    (``network.plots``). ``lines.npz`` holds ``time_s`` (the samples' times, s)
    and, per line NAME, from end A to end B: ``lineNAME`` (its final deployed nodes, m),
    ``lineNAME_nodes`` (samples, n+1, 3; m), ``lineNAME_tension``, ``lineNAME_compression`` and
    ``lineNAME_peak_tension`` (samples, n; N, >= 0: each element's pull, the largest push its
    constraint made since the previous sample, which a cable cannot and the tension leaves out,
    and its largest pull since then; see ``NetworkRun.record``); ``summary.json`` each line's
    snap loads (``snap_loads``, ``cable.snap.snap_report``)."""
    net = r.net
    cols = columns(net)
    arrays = {"time_s": rows[:, 0]}
    for ln in net.lines:
        arrays.update(line_arrays(ln.name, r.line_nodes(ln.name), r.history.get(ln.name, {})))
    if r.states:  # (the bodies' and points' poses: a replay sets them; see ``NetworkRun.record``)
        arrays["qpos"] = np.array(r.states)
    final = dict(zip(cols, rows[-1]))
    summary = {
        "source": None if source is None else str(source),
        "kind": "network",
        "simulated_s": float(rows[-1, 0]),
        "timestep_s": r.timestep,
        "wall_time_s": round(wall_time, 3),
        "start": r.note,
        "notes": list(net.notes),
        "lines": {ln.name: {"type": ln.type, "A": ln.a, "B": ln.b, "length_m": ln.length, "segments": ln.segments,
                            "final_A_tension_N": final[f"line{ln.name}_A_tension_N"],
                            "final_B_tension_N": final[f"line{ln.name}_B_tension_N"],
                            "peak_tension_N": float(rows[:, [cols.index(f"line{ln.name}_{e}_tension_N")
                                                             for e in "AB"]].max()),
                            "effective_EA": r.effective_EA.get(ln.name),
                            "snap_count": len(r.sim.tethers[ln.name].snaps.events)}
                  for ln in net.lines},
        "snap_loads": {ln.name: snap.snap_report(r.sim.tethers[ln.name]) for ln in net.lines},
        "network": to_dict(net),
    }
    if r.video is not None:
        summary["video"] = r.video
    from . import plots as network_plots
    write_folder(folder, cols, rows, arrays, summary,
                 plots=(lambda into: network_plots.write(into, r, rows, cols)) if plots else None)


def run_to(net: Network, out, *, overwrite: bool = False, source=None, progress=None,
           plots: bool = True, video=None) -> NetworkResult:
    """Simulate ``net`` and write its results folder ``out`` whole or not at all; returns the run
    (its simulation closed) and the time series. ``video(r, folder)``, where given, makes the
    recorder of ``simulate`` writing into the results folder ``folder`` (staged with the rest)."""
    from mjtether.files.outdir import Staging, check_target
    target = check_target(out, overwrite=overwrite, protect=[source] if source else ())
    t0 = time.perf_counter()
    with Staging(target, overwrite=overwrite) as stage:
        r, rows = simulate(net, progress=progress,
                           video=None if video is None else (lambda run_: video(run_, stage.path)))
        try:
            write(r, rows, stage, source=source, wall_time=time.perf_counter() - t0, plots=plots)
        finally:
            r.sim.close()
    return NetworkResult(r, rows)

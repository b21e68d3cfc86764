"""Seabed walkers in a network: the scenario's hexapod (``mjtether.walker``) standing on the
network's seabed and walking on the scenario's gait drive (``scenario.controllers.GaitDrive``:
its tripod gait, speed ramp and heading hold, at its control rate).

A walker starts as a scenario's does: the scenario's walker part (``scenario.robot_ends.Walker``,
its ``stand``: ``scenario.start.stand_walker``) lets it stand alone on
the seabed (stepping in place in still water for ``start.STAND_S``) and puts that pose at its
position and heading, at rest; the network's statics hold its points there (``torso_frame``)
and its lines start from them. It is attached under the prefix ``walker/NAME/`` (its torso the
body ``walker/NAME/torso``, its tow point the site ``walker/NAME/tow_point``), carrying the
scenario walker's rigid-body hydrodynamics (``walker.HYDRO``). Units SI, world frame z up;
headings in radians here (degrees in the network file).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mjtether.cable import builder
from mjtether.physics import water as wm
from mjtether.physics.rigidbody import add_body_hydro
from mjtether.scenario.controllers import GaitDrive
from mjtether.scenario.robot_ends import Ground, Walker
from mjtether.scenario.scene import WALKER_PATCH
from mjtether.scenario.sections import Robot
from mjtether.walker import HYDRO, Tripod, walker_spec

STAND_TIMESTEP = 0.005
"""Step (s) a walker stands at (``stand``) where the network gives no ``simulation.timestep``:
the network's longest step with anything moving in it (``run.MAX_TIMESTEP``), the scenario's
default. The pose is found before the run's step is (the statics need it first)."""


def prefix(name: str) -> str:
    """The prefix of walker ``name``'s bodies, joints, actuators and sites."""
    return f"walker/{name}/"


def part(w):
    """Network walker ``w`` as the scenario's robot-end part (``scenario.robot_ends.Walker``): a
    ``[robot]`` section of type walker at its position and heading, on its gait period and
    schedule (deg/s, as ``robot.commands``)."""
    commands = w.commands if w.commands is not None else ((0.0, w.speed, 0.0),)
    return Walker(Robot(type="walker", start=w.position, heading_deg=w.heading_deg, gait_period=w.gait_period,
                        commands=commands))


def ground(net, w, water: wm.WaterColumn) -> Ground:
    """The seabed and water network walker ``w`` stands on: the network's seabed (its bathymetry
    grid's plane fitted around the walker, or level), friction and ``water``."""
    grid = net.grid
    slope, slope_heading = (0.0, 0.0) if grid is None else grid.plane_at(*w.position, WALKER_PATCH)
    return Ground(water, slope, slope_heading, net.seabed_friction, net.seabed_height, grid, net.bathymetry)


def stand(net, name: str, water: wm.WaterColumn, gait: Tripod | None = None):
    """Walker ``name``'s standing pose (``robot_ends.Walker.stand``, at ``STAND_TIMESTEP``
    or the network's step): ({(body, index in body): (qpos, qvel)}, {actuator: control}, tow point
    m), its bodies and actuators named as the scenario's (``walker/...``); ``gait`` (default: a
    new one) is left at the phase it stood in. Stands on a level seabed are made once and kept."""
    w = net.walkers[name]
    dt = net.timestep if net.timestep is not None else STAND_TIMESTEP
    return part(w).stand(ground(net, w, water), gait if gait is not None else Tripod(period=w.gait_period), dt)


def torso_frame(net, name: str, water: wm.WaterColumn) -> tuple[np.ndarray, np.ndarray]:
    """World position (m) and rotation matrix of walker ``name``'s torso where it stands."""
    q = stand(net, name, water)[0][("walker/torso", 0)][0]
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, q[3:7])
    return np.array(q[:3], float), R.reshape(3, 3)


def attach(spec: mujoco.MjSpec, net, name: str, water: wm.WaterColumn):
    """Attach walker ``name`` (``prefix``) to ``spec``, its torso where it stands (its legs are
    set in ``start``); returns its rigid-body hydrodynamics (as ``scene.place_walker``)."""
    q = stand(net, name, water)[0][("walker/torso", 0)][0]
    torso = walker_spec().body("torso")
    torso.pos, torso.quat = list(q[:3]), list(q[3:7])
    spec.worldbody.add_frame().attach_body(torso, prefix(name), "")
    return add_body_hydro(spec, f"{prefix(name)}torso", HYDRO)


class WalkerGait(GaitDrive):
    """The scenario's gait drive for a walker attached under ``prefix`` (``GaitDrive.bind``
    binds the one named ``walker/``)."""

    def bind(self, model, data, torso: int, prefix: str = "walker/") -> None:
        self.gait.bind(model, prefix=prefix)
        self._torso, self._data = torso, data
        self._xmat, self._ctrl = data.xmat, data.ctrl


def start(sim, net, water: wm.WaterColumn) -> dict:
    """Put every walker in its standing pose (joints at rest, servos at their standing targets,
    as ``scenario.start.preroll`` does) and give it its gait drive; returns {name: ``WalkerGait``}."""
    m, d = sim.model, sim.data
    gaits = {}
    for name, w in net.walkers.items():
        pre = prefix(name)
        drive = WalkerGait(np.array(w.schedule, dtype=float), w.gait_period, math.radians(w.heading_deg))
        pose, ctrl, _ = stand(net, name, water, drive.gait)
        for (body, k), (q, v) in pose.items():
            j = m.body_jntadr[m.body(pre + body.removeprefix("walker/")).id] + k
            d.qpos[m.jnt_qposadr[j]:m.jnt_qposadr[j] + len(q)] = q
            d.qvel[m.jnt_dofadr[j]:m.jnt_dofadr[j] + len(v)] = v
        for act, u in ctrl.items():
            d.ctrl[m.actuator(pre + act.removeprefix("walker/")).id] = u
        drive.bind(m, d, m.body(f"{pre}torso").id, prefix=pre)
        gaits[name] = drive
    return gaits


def support(name: str, position) -> builder.BodyPoint:
    """A line's end on walker ``name`` at ``position`` (m, its torso's frame)."""
    return builder.BodyPoint(f"{prefix(name)}torso", position)


def columns(net) -> list[str]:
    """Per walker: its torso's position (m, world) and heading (deg from +x towards +y)."""
    return [c for name in net.walkers for c in [f"walker{name}_{k}_m" for k in "xyz"] + [f"walker{name}_heading_deg"]]


def sample(net, model, now) -> list[float]:
    """``columns``' values from the poses ``now`` (an MjData whose kinematics are current)."""
    row = []
    for name in net.walkers:
        body = model.body(f"{prefix(name)}torso").id
        R = now.xmat[body].reshape(3, 3)
        row += list(now.xpos[body]) + [math.degrees(math.atan2(R[1, 0], R[0, 0]))]
    return row

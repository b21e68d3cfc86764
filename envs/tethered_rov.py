"""``mjtether/TetheredROV-v0``: hold an ROV on station (or fly it along waypoints) at depth in a
current while its umbilical pulls.

A BlueROV2 Heavy (``assets/vehicles/bluerov2_heavy.toml``; ``vehicle`` may name another shipped
vehicle with thrusters) hangs on ``tether_length`` m of umbilical from a ship holding station at
the origin, in water ``depth`` m deep with an exponential current drawn as in the other
environments (surface speed up to ``current_max_kn``, decay depth 10-40 m, any heading). At each
reset a target is drawn ``start_distance`` m from the ship (bearing within 0.5 rad of +x), at a
depth of 15-30 m, with a target heading anywhere; the vehicle starts level, at rest, within
``start_offset`` m of it, facing the target heading give or take 0.5 rad, the umbilical in its
quasi-static shape. ``task="waypoints"``: two more targets follow, 5-10 m apart at the same depth,
each passed within ``acceptance_radius`` m; the last is held. The agent commands the thrusters
directly.

Action (``Box(-1, 1, (n,))``, n thrusters, 8 for the BlueROV2 Heavy): each thruster's thrust as a
fraction of its forward (action > 0) or reverse (action < 0) maximum, N; each thruster lags its
command with its time constant.

Observation (``Box``, float32, physical units, 19 + n values, clipped to the bounds):

=======  ======================================================  ========================
 0-2     target position in the vehicle's frame (x ahead, y left, z up, m)  [-200, 200]
 3-4     sin, cos of the heading error (target heading - heading)  [-1, 1]
 5-7     the vehicle's velocity in its frame (m/s)                  [-5, 5]
 8-10    its angular velocity in its frame (rad/s)                  [-5, 5]
 11-12   roll and pitch (rad; pitch > 0 nose down)                  [-pi, pi]
 13-15   umbilical force on the tow point in the vehicle's frame (N)  [-2 rated_load, 2 rated_load]
 16-17   current (x, y) at the vehicle's depth in its frame (m/s)   [-5, 5]
 18      depth (m)                                                  [0, depth]
 19-     each thruster's delivered thrust as a fraction of its maximum  [-1, 1]
=======  ======================================================  ========================

Reward per step::

    r = - w_position * |target - p| / position_ref          (distance from the target)
        - w_heading  * (1 - cos(heading error))               (off the target heading)
        - w_effort   * mean(action^2)                          (thrust asked for)
        + waypoint_bonus on passing a waypoint (``task="waypoints"``)
        - failure_penalty on termination

The episode terminates when the umbilical's ship-end tension exceeds the rated load, the
vehicle is more than ``max_error`` m from its target, or it reaches the surface; it is
truncated by ``max_episode_steps`` (600: 60 s at the default 0.1 s per step). ``info`` holds the
reward terms, the target, the distance to it, the waypoint reached, the tensions, the
vehicle's position and the tangle monitor's readings (``cable_clearance`` from the vehicle,
``cable_self_clearance`` and ``cable_plan_crossings``, m and a count; +inf where there is nothing
to check); ``is_success`` when it is within ``acceptance_radius`` of the last target.

Baseline: ``baselines.StationKeepingPID`` (mjtether's autopilot with the vehicle file's gains).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from gymnasium import spaces

from mjtether.io.render import Marker
from mjtether.physics import actuation
from mjtether.scenario.config import Section, param
from mjtether.scenario.readouts import roll_pitch
from mjtether.vehicles.files import load_vehicle

from .base import TetherEnv, _finite_action, kwargs_table

TARGET_RGBA = (0.1, 0.95, 0.2, 0.55)
"""Colour of the target marker in rendered frames (translucent green)."""


@dataclass(frozen=True)
class TetheredROVConfig(Section):
    """``TetheredROV-v0``'s keyword arguments: the site and umbilical, the task, the reward."""

    vehicle: str = param("bluerov2_heavy", doc="a shipped vehicle with thrusters (mjtether.vehicles.files.shipped())")
    task: str = param("station", doc="station (hold the target) or waypoints (three targets in turn)",
                      choices=("station", "waypoints"))
    depth: float = param(50.0, 35.0, 2000.0, "m", "depth of the seabed")
    tether_length: float = param(60.0, 10.0, 2000.0, "m", "umbilical length")
    segments: int = param(20, 4, 400, "", "umbilical elements")
    diameter: float = param(0.0076, 1e-3, 0.1, "m", "umbilical diameter")
    cable_density: float = param(1150.0, 500.0, 20000.0, "kg/m^3", "umbilical bulk density")
    EA: float = param(2.0e5, 1e3, 1e12, "N", "umbilical axial stiffness")
    rated_load: float = param(1500.0, 10.0, 1e8, "N", "rated load; the episode ends above it")
    current_max_kn: float = param(0.6, 0.0, 4.0, "kn", "largest surface current drawn")
    start_distance: float = param(15.0, 0.0, 1000.0, "m", "horizontal distance of the (first) target from the ship")
    start_offset: float = param(2.0, 0.0, 20.0, "m", "largest distance of the start from the target")
    acceptance_radius: float = param(1.0, 0.05, 20.0, "m", "a target is reached within this distance")
    max_error: float = param(20.0, 1.0, 1000.0, "m", "the episode ends this far from the target")
    position_ref: float = param(1.0, 0.01, 1e3, "m", "the reward's distance scale")
    w_position: float = param(1.0, 0.0, 1e3, "", "weight of the distance from the target")
    w_heading: float = param(0.5, 0.0, 1e3, "", "weight of the heading error")
    w_effort: float = param(0.05, 0.0, 1e3, "", "weight of the thrust asked for")
    waypoint_bonus: float = param(10.0, 0.0, 1e6, "", "bonus on passing a waypoint")
    failure_penalty: float = param(50.0, 0.0, 1e6, "", "penalty on termination")
    timestep: float = param(0.005, 1e-4, 0.01, "s", "MuJoCo time step")
    frame_skip: int = param(20, 1, 1000, "", "MuJoCo steps per environment step")
    width: int = param(480, 16, 4096, "px", "rendered frame width")
    height: int = param(360, 16, 4096, "px", "rendered frame height")

    def _check(self):
        if self.vehicle not in _with_thrusters():
            self._bad("vehicle", f"must be a shipped vehicle with thrusters: {', '.join(_with_thrusters())}")
        reach = math.hypot(self.start_distance + self.start_offset, 30.0 + self.start_offset)
        if reach >= self.tether_length:
            self._bad("tether_length", f"must reach the farthest start, {reach:.0f} m from the fairlead "
                      "(start_distance + start_offset, 30 m + start_offset deep)")


def _with_thrusters() -> list[str]:
    from mjtether.vehicles.files import shipped

    return [n for n in shipped() if load_vehicle(n).thrusters]


class TetheredROVEnv(TetherEnv):
    """See the module docstring."""

    Config = TetheredROVConfig

    def __init__(self, **kwargs):
        camera = kwargs.get("camera_name")
        if camera is not None and camera not in ("track", "side", "top"):
            raise ValueError(f"camera_name must be one of the renderer's views 'track', 'side', 'top' (the ROV's "
                             f"model has no cameras); got {camera!r}")
        if kwargs.get("camera_id") not in (None, -1):
            raise ValueError(f"camera_id must be -1 (the default view): the ROV's model has no cameras; got "
                             f"{kwargs['camera_id']!r}")
        if (kwargs.get("default_camera_config") or {}).get("camera") == "walker":
            raise ValueError("default_camera_config['camera'] must be 'track', 'side' or 'top' (there is no walker)")
        super().__init__(**kwargs)
        vs = load_vehicle(self.vehicle)
        self.thrusters = vs.thrusters
        n = len(self.thrusters)
        self._max_fwd = np.array([t.max_forward for t in self.thrusters])
        self._max_rev = np.array([t.max_reverse for t in self.thrusters])
        F2 = 2.0 * self.rated_load
        lo = [-200.0] * 3 + [-1.0, -1.0] + [-5.0] * 6 + [-math.pi] * 2 + [-F2] * 3 + [-5.0] * 2 + [0.0] + [-1.0] * n
        hi = [200.0] * 3 + [1.0, 1.0] + [5.0] * 6 + [math.pi] * 2 + [F2] * 3 + [5.0] * 2 + [self.depth] + [1.0] * n
        self.observation_space = spaces.Box(np.array(lo, np.float32), np.array(hi, np.float32), dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (n,), dtype=np.float32)
        self.targets = np.zeros((1, 4))  # rows: x, y, depth (m), heading (rad)
        self.leg = 0

    # ---------------------------------------------------------------- episode set-up

    def _scenario(self, rng: np.random.Generator) -> dict:
        bearing = float(rng.uniform(-0.5, 0.5))
        depth = float(rng.uniform(15.0, 30.0))
        p = self.start_distance * np.array([math.cos(bearing), math.sin(bearing)])
        rows = [[*p, depth, float(rng.uniform(-math.pi, math.pi))]]
        if self.task == "waypoints":
            for _ in range(2):
                step = float(rng.uniform(5.0, 10.0))
                turn = rows[-1][3] + float(rng.uniform(-1.0, 1.0))
                rows.append([rows[-1][0] + step * math.cos(turn), rows[-1][1] + step * math.sin(turn), depth,
                             float(rng.uniform(-math.pi, math.pi))])
        self.targets, self.leg = np.array(rows), 0
        r, a = self.start_offset * math.sqrt(float(rng.uniform())), float(rng.uniform(-math.pi, math.pi))
        start = [p[0] + r * math.cos(a), p[1] + r * math.sin(a), -depth + float(rng.uniform(-1.0, 1.0)) * 0.5 * r]
        heading = rows[0][3] + float(rng.uniform(-0.5, 0.5))
        return {
            "simulation": {"timestep": self.timestep, "duration": 1e4, "output_interval": 1.0, "start": "auto",
                           "max_wall_hours": 1000.0, "max_output_gb": 1000.0},
            "water": {"depth": self.depth,
                      "current": {"type": "exponential", "surface_speed": float(rng.uniform(0.0, self.current_max)),
                                  "decay_depth": float(rng.uniform(10.0, 40.0)),
                                  "heading_deg": math.degrees(rng.uniform(-math.pi, math.pi))}},
            "tether": {"length": self.tether_length, "segments": self.segments, "diameter": self.diameter,
                       "density": self.cable_density, "EA": self.EA, "rated_load": self.rated_load},
            "ship": {"mode": "fixed", "position": [0.0, 0.0]},
            "winch": {"mode": "fixed"},
            # the autopilot holds the start while the umbilical's contacts load (the pre-roll); the
            # agent then has the thrusters
            "robot": {"type": "vehicle", "vehicle": self.vehicle, "position": start,
                      "heading_deg": math.degrees(heading), "setpoints": [[0.0, 0.0, math.degrees(heading), depth]]},
        }

    # ---------------------------------------------------------------- gymnasium API

    def reset(self, *, seed=None, options=None):
        self._start_episode(seed)
        self.runner.release_pilot()
        self._acts = np.array([self.runner.sim.model.actuator(f"vehicle/{t.name}").id for t in self.thrusters])
        self._human_frame()
        return self._get_obs(), self._info({})

    def step(self, action):
        if self.runner is None:
            raise RuntimeError("call reset() before step()")
        a = _finite_action(action, len(self.thrusters))
        self.runner.sim.data.ctrl[self._acts] = np.where(a >= 0.0, a * self._max_fwd, a * self._max_rev)
        self._advance()
        err = self._target_error()
        dist = float(np.linalg.norm(err[:3]))
        passed = False
        if self.task == "waypoints" and dist <= self.acceptance_radius and self.leg < len(self.targets) - 1:
            self.leg, passed = self.leg + 1, True
            err = self._target_error()
            dist = float(np.linalg.norm(err[:3]))
        surfaced = float(self.runner.named.robot_position[2]) >= 0.0
        terminated = bool(self.broke or dist > self.max_error or surfaced)
        terms = {
            "reward_position": -self.w_position * dist / self.position_ref,
            "reward_heading": -self.w_heading * (1.0 - math.cos(err[3])),
            "reward_effort": -self.w_effort * float(np.mean(a * a)),
            "reward_waypoint": self.waypoint_bonus if passed else 0.0,
            "reward_failure": -self.failure_penalty if terminated else 0.0,
        }
        self._human_frame()
        return self._get_obs(), float(sum(terms.values())), terminated, False, self._info(terms)

    # ---------------------------------------------------------------- readouts

    def _vehicle_state(self):
        """(origin (3,) m, R body to world, nu (6,) body frame)."""
        r = self.runner
        nu, R = r.vehicle.velocity(r.sim.data)
        return r.sim.data.xpos[r.vehicle.id].copy(), R, nu

    def _target_error(self) -> np.ndarray:
        """(target - origin in the world frame (3,), m; heading error, rad)."""
        from mjtether.scenario.controllers import heading_error

        p, R, _ = self._vehicle_state()
        x, y, depth, heading = self.targets[self.leg]
        return np.array([x - p[0], y - p[1], -depth - p[2], heading_error(heading, math.atan2(R[1, 0], R[0, 0]))])

    def _get_obs(self) -> np.ndarray:
        r = self.runner
        n = r.named
        p, R, nu = self._vehicle_state()
        err = self._target_error()
        roll, pitch = roll_pitch(R)
        current = R.T @ n.current_at(np.array([min(p[2], 0.0)]))[0]
        act = r.sim.data.act[actuation.delivered(r.sim.model, self._acts)]
        delivered = np.where(act >= 0.0, act / self._max_fwd, act / np.maximum(self._max_rev, 1e-9))
        obs = np.array([*(R.T @ err[:3]), math.sin(err[3]), math.cos(err[3]), *nu, roll, pitch,
                        *n.tow_force_body, *current[:2], -p[2], *delivered], dtype=np.float32)
        return np.clip(obs, self.observation_space.low, self.observation_space.high)

    def _info(self, terms: dict) -> dict:
        n = self.runner.named
        err = self._target_error()
        dist = float(np.linalg.norm(err[:3]))
        tg = n.tangle()
        return {**terms, "target": self.targets[self.leg].copy(), "target_distance": dist, "waypoint": self.leg,
                "is_success": bool(self.leg == len(self.targets) - 1 and dist <= self.acceptance_radius),
                "ship_tension": n.ship_tension, "tow_tension": n.tow_tension, "deployed_length": n.deployed_length,
                "position": self._vehicle_state()[0], "rated_load_exceeded": self.broke, "time": n.time,
                "cable_clearance": tg["clearance"], "cable_self_clearance": tg["self_clearance"],
                "cable_plan_crossings": tg["plan_crossings"]}

    # ---------------------------------------------------------------- rendering

    def render_markers(self) -> list[Marker]:
        """The current target as a translucent green sphere ``acceptance_radius`` wide (a scene
        geom only)."""
        import mujoco

        x, y, depth, _ = self.targets[self.leg]
        r = self.acceptance_radius
        return [Marker(pos=(float(x), float(y), -float(depth)), size=(r, r, r), rgba=TARGET_RGBA,
                       gtype=mujoco.mjtGeom.mjGEOM_SPHERE)]


TetheredROVEnv.__doc__ += kwargs_table(TetheredROVConfig)

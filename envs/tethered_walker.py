"""``mjtether/TetheredWalker-v0``: walk the tethered hexapod to a goal on the seabed.

The walker starts ``start_distance`` m from a ship holding station, facing away from it (with
up to 0.5 rad of random yaw), on a seabed ``depth`` m down, in an exponential current drawn as
in ``TetherWinch-v0``. A goal is drawn 15 to 30 m away, within 90 degrees of straight ahead. The
agent commands the gait and the winch.

Action (``Box(-1, 1, (3,))``): forward speed as a fraction of ``max_speed`` (m/s), turn rate as a
fraction of ``max_turn_rate`` (rad/s), payout rate as a fraction of ``max_rate`` (m/s).

Observation (``Box``, float32, physical units, 19 values, clipped to the bounds):

=====  ===============================================  =========================
 0-1   goal position in the walker's frame (x ahead, y left, m)   [-1e3, 1e3]
 2     distance to the goal (m)                          [0, 1e3]
 3-4   the walker's velocity in its frame (m/s)          [-3, 3]
 5     its yaw rate (rad/s)                              [-3, 3]
 6-8   tether force on the tow point in the walker's frame (N)    [-2 rated_load, 2 rated_load]
 9     deployed length (m)                               [0, max_length]
 10    ship-end tension (N)                              [0, 2 rated_load]
 11    tether length on the seabed (m)                   [0, max_length]
 12    the drum's payout rate now (m/s)                  [-max_rate, max_rate]
 13-18 current (x, y) at 5 %, 25 % and 75 % of the depth, in the walker's frame (m/s) [-5, 5]
=====  ===============================================  =========================

Reward per step::

    r = w_progress * (d_prev - d) / (max_speed dt)       (progress towards the goal, 1 at full speed)
        - w_force  * |F_tow| / force_ref                 (tow force)
        - w_energy * sum_j |tau_j qdot_j| dt / energy_ref (leg actuators' mechanical work)
        + goal_bonus on reaching the goal (within goal_radius m)
        - failure_penalty on breaking the tether or running out of it

The episode terminates at the goal, above the rated load, or at a length limit; it is truncated
by ``max_episode_steps`` (900: 90 s). ``info`` holds the reward terms, the distance to the goal,
the tensions, the positions and ``is_success``.

Rendered frames (``render_mode="rgb_array"`` or ``"human"``) show the goal as a translucent
green column ``goal_radius`` wide on the seabed, drawn into the scene only (not a model geom: the
physics is the same with and without rendering).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from gymnasium import spaces

from mjtether.io.render import Marker
from mjtether.scenario.config import param
from mjtether.scenario.runner import RunFailed

from .base import TetherEnv, TetherEnvConfig, _finite_action, kwargs_table

GOAL_RGBA = (0.1, 0.95, 0.2, 0.55)
"""Colour of the goal marker in rendered frames (translucent green)."""
GOAL_MARKER_HEIGHT = 2.0
"""Height (m) of the goal marker, a column standing on the seabed."""


@dataclass(frozen=True)
class TetheredWalkerConfig(TetherEnvConfig):
    """``TetheredWalker-v0``'s keyword arguments: the site and tether, the walker's limits, the reward."""

    max_speed: float = param(0.5, 0.05, 1.0, "m/s", "forward speed at action 1")
    max_turn_rate: float = param(0.2, 0.01, 0.5, "rad/s", "turn rate at action 1")
    goal_radius: float = param(1.0, 0.1, 100.0, "m", "the goal is reached within this distance")
    force_ref: float = param(500.0, 1.0, 1e8, "N", "the reward's tow-force scale")
    energy_ref: float = param(500.0, 1.0, 1e8, "J", "the reward's energy scale")
    w_progress: float = param(1.0, 0.0, 1e3, "", "weight of progress towards the goal")
    w_force: float = param(0.2, 0.0, 1e3, "", "weight of the tow force")
    w_energy: float = param(0.05, 0.0, 1e3, "", "weight of the leg actuators' work")
    goal_bonus: float = param(50.0, 0.0, 1e6, "", "bonus on reaching the goal")
    failure_penalty: float = param(50.0, 0.0, 1e6, "", "penalty on breaking the tether or running out of it")


class TetheredWalkerEnv(TetherEnv):
    """See the module docstring."""

    Config = TetheredWalkerConfig

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        F2, L = 2.0 * self.rated_load, self.max_length
        lo = [-1e3, -1e3, 0.0, -3.0, -3.0, -3.0, -F2, -F2, -F2, 0.0, 0.0, 0.0, -self.max_rate] + [-5.0] * 6
        hi = [1e3, 1e3, 1e3, 3.0, 3.0, 3.0, F2, F2, F2, L, F2, L, self.max_rate] + [5.0] * 6
        self.observation_space = spaces.Box(np.array(lo, np.float32), np.array(hi, np.float32), dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (3,), dtype=np.float32)
        self.goal = np.zeros(2)

    def _robot_section(self, rng):
        heading = float(rng.uniform(-0.5, 0.5))
        start = np.array([math.cos(heading), math.sin(heading)]) * self.start_distance
        d, bearing = rng.uniform(15.0, 30.0), heading + rng.uniform(-math.pi / 2, math.pi / 2)
        self.goal = start + d * np.array([math.cos(bearing), math.sin(bearing)])
        return {"type": "walker", "start": start.tolist(), "heading_deg": math.degrees(heading),
                "commands": [[0.0, 0.0, 0.0]]}

    # ---------------------------------------------------------------- gymnasium API

    def reset(self, *, seed=None, options=None):
        self._start_episode(seed)
        self.runner.set_command(0.0, 0.0)
        self._prev_distance = self._goal_distance()
        self._human_frame()
        return self._get_obs(), self._info({})

    def step(self, action):
        if self.runner is None:
            raise RuntimeError("call reset() before step()")
        a = _finite_action(action, 3)
        r = self.runner
        r.set_command(a[0] * self.max_speed, a[1] * self.max_turn_rate)
        r.winch.command(a[2] * self.max_rate)
        work = 0.0  # mechanical work of the leg actuators over the step (J)
        for _ in range(self.frame_skip):
            try:
                r.step()
            except RunFailed:
                self.broke = True
                break
            work += r.named.actuator_power * self.timestep
        dist = self._goal_distance()
        F = r.named.tow_force
        success = dist <= self.goal_radius
        failed = self.broke or self.at_length_limit()
        terms = {
            "reward_progress": self.w_progress * (self._prev_distance - dist) / (self.max_speed * self.dt),
            "reward_force": -self.w_force * float(np.linalg.norm(F)) / self.force_ref,
            "reward_energy": -self.w_energy * work / self.energy_ref,
            "reward_goal": self.goal_bonus if success else 0.0,
            "reward_failure": -self.failure_penalty if failed else 0.0,
        }
        self._prev_distance = dist
        self._human_frame()
        return self._get_obs(), float(sum(terms.values())), bool(success or failed), False, self._info(terms)

    # ---------------------------------------------------------------- rendering

    def goal_marker(self) -> Marker:
        """The goal as drawn: a translucent green column, ``goal_radius`` wide and
        ``GOAL_MARKER_HEIGHT`` m tall, standing on the seabed at the goal (a scene geom only)."""
        gx, gy = (float(c) for c in self.goal)
        z = float(self.runner.seabed_z(gx, gy)) if self.runner is not None else -self.depth
        h = GOAL_MARKER_HEIGHT / 2
        return Marker(pos=(gx, gy, z + h), size=(self.goal_radius, self.goal_radius, h), rgba=GOAL_RGBA)

    def render_markers(self) -> list[Marker]:
        return [self.goal_marker()]

    # ---------------------------------------------------------------- observation

    def _goal_distance(self) -> float:
        """Horizontal distance (m) from the walker's torso to the goal."""
        return float(np.hypot(*(self.goal - self.runner.named.torso_position[:2])))

    def _get_obs(self) -> np.ndarray:
        n = self.runner.named
        yaw = n.robot_heading
        cy, sy = math.cos(yaw), math.sin(yaw)

        def to_body(vx, vy):
            return cy * vx + sy * vy, -sy * vx + cy * vy

        g = to_body(*(self.goal - n.torso_position[:2]))
        vb = to_body(*n.robot_velocity)
        cur = self.currents().reshape(-1, 2)
        cur_b = [c for u in cur for c in to_body(*u)]
        obs = np.array([*g, float(np.hypot(*g)), *vb, n.yaw_rate, *n.tow_force_body, n.deployed_length,
                        n.ship_tension, self.length_on_seabed(), n.payout_rate, *cur_b], dtype=np.float32)
        return np.clip(obs, self.observation_space.low, self.observation_space.high)

    def _info(self, terms: dict) -> dict:
        n = self.runner.named
        return {**terms, "goal": self.goal.copy(), "goal_distance": self._goal_distance(),
                "is_success": self._goal_distance() <= self.goal_radius, "ship_tension": n.ship_tension,
                "tow_tension": n.tow_tension, "deployed_length": n.deployed_length,
                "position": n.torso_position, "rated_load_exceeded": self.broke, "time": n.time}


TetheredWalkerEnv.__doc__ += kwargs_table(TetheredWalkerConfig)

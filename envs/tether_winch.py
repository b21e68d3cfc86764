"""``mjtether/TetherWinch-v0``: pay out and reel in the tether behind a walker on a scripted route.

The hexapod walker sets off from ``start_distance`` m ahead of a ship holding station, on a
seabed ``depth`` m down, and follows a route drawn at each reset: three legs of equal duration
over ``route_duration`` s, each at a speed in [0.15, 0.45] m/s, half of them turning at up to
0.06 rad/s. The current is exponential in depth, with a surface speed up to ``current_max_kn``,
a decay depth in [10, 40] m and any heading. The agent commands the winch.

Action (``Box(-1, 1, (1,))``): the payout rate as a fraction of ``max_rate`` (m/s; negative reels
in). The drum follows it at up to 0.2 m/s^2.

Observation (``Box``, float32, physical units, 16 values, clipped to the bounds):

====  ==================================================  =========================
 0    deployed length (m)                                 [0, max_length]
 1    ship-end tension (N)                                [0, 2 rated_load]
 2    tow-point tension (N)                               [0, 2 rated_load]
 3    horizontal distance of the tow point from the ship  [0, 1e4] m
 4-5  sin, cos of its bearing from the ship (from +x)     [-1, 1]
 6    the walker's horizontal speed (m/s)                 [0, 3]
 7    its range rate, d(distance)/dt (m/s)                [-3, 3]
 8-13 current (x, y) at 5 %, 25 % and 75 % of the depth   [-5, 5] m/s
 14   tether length lying on the seabed (m)               [0, max_length]
 15   the drum's payout rate now (m/s)                    [-max_rate, max_rate]
====  ==================================================  =========================

Reward per step (dimensionless, per ``dt`` = frame_skip x timestep s)::

    r = - w_tension  * T_tow / T_ref                      (keep the tow tension low ...)
        - w_steady   * |T_tow - T_tow,prev| / T_ref        (... and steady)
        - w_slack    * max(0, L_seabed - slack_allowance) / slack_allowance   (no excess on the bottom)
        - failure_penalty  on termination

with T_ref = ``tension_ref`` N. The episode terminates when the ship-end tension exceeds the
rated load or the deployed length reaches ``min_length`` or ``max_length``; it is truncated by
``max_episode_steps`` (600: 60 s at the default 0.1 s per step).

``info`` holds the reward terms (``reward_tension``, ``reward_steady``, ``reward_slack``,
``reward_failure``), the tensions, the deployed length, the tow point's position and the
walker's speed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from gymnasium import spaces

from mjtether.scenario.config import param

from .base import TetherEnv, TetherEnvConfig, _finite_action, kwargs_table


@dataclass(frozen=True)
class TetherWinchConfig(TetherEnvConfig):
    """``TetherWinch-v0``'s keyword arguments: the site and tether, the route, the reward."""

    route_duration: float = param(60.0, 1.0, 1e5, "s", "duration of the three-leg route")
    tension_ref: float = param(500.0, 1.0, 1e8, "N", "T_ref, the reward's tension scale")
    slack_allowance: float = param(10.0, 0.1, 1e4, "m", "tether on the seabed before w_slack applies")
    w_tension: float = param(1.0, 0.0, 1e3, "", "weight of the tow tension")
    w_steady: float = param(0.5, 0.0, 1e3, "", "weight of the change in tow tension")
    w_slack: float = param(0.5, 0.0, 1e3, "", "weight of excess cable on the seabed")
    failure_penalty: float = param(50.0, 0.0, 1e6, "", "penalty on termination")


class TetherWinchEnv(TetherEnv):
    """See the module docstring."""

    Config = TetherWinchConfig

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        T2 = 2.0 * self.rated_load
        lo = [0.0, 0.0, 0.0, 0.0, -1.0, -1.0, 0.0, -3.0] + [-5.0] * 6 + [0.0, -self.max_rate]
        hi = [self.max_length, T2, T2, 1e4, 1.0, 1.0, 3.0, 3.0] + [5.0] * 6 + [self.max_length, self.max_rate]
        self.observation_space = spaces.Box(np.array(lo, np.float32), np.array(hi, np.float32), dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (1,), dtype=np.float32)

    def _robot_section(self, rng):
        legs = 3
        t = np.arange(legs) * self.route_duration / legs
        speed = rng.uniform(0.15, 0.45, legs)
        turn = np.where(rng.uniform(size=legs) < 0.5, 0.0, rng.uniform(-0.06, 0.06, legs))
        heading = float(rng.uniform(-0.5, 0.5))
        start = [self.start_distance * math.cos(heading), self.start_distance * math.sin(heading)]
        return {"type": "walker", "start": start, "heading_deg": math.degrees(heading),
                "commands": [[float(a), float(b), math.degrees(c)] for a, b, c in zip(t, speed, turn)]}

    # ---------------------------------------------------------------- gymnasium API

    def reset(self, *, seed=None, options=None):
        self._start_episode(seed)
        tow, _, _ = self.robot_kinematics()
        self._prev_distance = float(np.hypot(tow[0], tow[1]))
        self._human_frame()
        ro = self._readouts()
        return self._get_obs(ro), self._info({}, ro)

    def step(self, action):
        if self.runner is None:
            raise RuntimeError("call reset() before step()")
        a = float(_finite_action(action, 1)[0])
        self.runner.winch.command(a * self.max_rate)
        self._advance()
        ro = self._readouts()
        obs = self._get_obs(ro)
        tow = ro["tow_tension"]
        terms = {
            "reward_tension": -self.w_tension * tow / self.tension_ref,
            "reward_steady": -self.w_steady * abs(tow - self._prev_tow) / self.tension_ref,
            "reward_slack": -self.w_slack * max(0.0, ro["length_on_seabed"] - self.slack_allowance)
            / self.slack_allowance,
        }
        terminated = bool(self.broke or self.at_length_limit())
        terms["reward_failure"] = -self.failure_penalty if terminated else 0.0
        self._prev_tow = tow
        reward = float(sum(terms.values()))
        self._human_frame()
        return obs, reward, terminated, False, self._info(terms, ro)

    # ---------------------------------------------------------------- observation

    def _readouts(self) -> dict:
        """What the observation, the reward and ``info`` read, once per step (N, m, m/s, world)."""
        n = self.runner.named
        tow, _, v = self.robot_kinematics()
        return {"ship_tension": n.ship_tension, "tow_tension": n.tow_tension, "length_on_seabed": self.length_on_seabed(),
                "tow_point": tow, "velocity": v}

    def _get_obs(self, ro: dict) -> np.ndarray:
        n = self.runner.named
        tow, v = ro["tow_point"], ro["velocity"]
        dist = float(np.hypot(tow[0], tow[1]))
        bearing = math.atan2(tow[1], tow[0])
        radial = float(v @ (tow[:2] / max(dist, 1e-9)))
        obs = np.array([n.deployed_length, ro["ship_tension"], ro["tow_tension"], dist,
                        math.sin(bearing), math.cos(bearing), float(np.hypot(*v)), radial,
                        *self.currents(), ro["length_on_seabed"], n.payout_rate], dtype=np.float32)
        return np.clip(obs, self.observation_space.low, self.observation_space.high)

    def _info(self, terms: dict, ro: dict) -> dict:
        n = self.runner.named
        return {**terms, "ship_tension": ro["ship_tension"], "tow_tension": ro["tow_tension"],
                "deployed_length": n.deployed_length, "tow_point": ro["tow_point"],
                "robot_speed": float(np.hypot(*ro["velocity"])), "length_on_seabed": ro["length_on_seabed"],
                "rated_load_exceeded": self.broke, "time": n.time}


TetherWinchEnv.__doc__ += kwargs_table(TetherWinchConfig)

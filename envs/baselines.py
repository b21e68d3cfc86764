"""Hand-written controllers to compare learned policies against. Each is called with the
environment (for its state) and returns an action in the environment's normalised action space.
"""

from __future__ import annotations

import math

import numpy as np


class FollowPayout:
    """Khan et al. (2023), Eq. 30: pay out at the walker's speed, V_po = v_r (``TetherWinch-v0``)."""

    def __call__(self, env) -> np.ndarray:
        e = env.unwrapped
        _, _, v = e.robot_kinematics()
        return np.array([np.clip(float(np.hypot(*v)) / e.max_rate, -1.0, 1.0)], dtype=np.float32)


class SteerToGoal:
    """``TetheredWalker-v0``: turn towards the goal (proportional on the bearing error, gain
    ``k_turn`` per rad), walk at ``speed`` of the top speed, slowing within 3 m, and pay out
    at the walker's speed (Eq. 30)."""

    def __init__(self, speed: float = 0.8, k_turn: float = 2.0):
        self.speed, self.k_turn = speed, k_turn

    def __call__(self, env) -> np.ndarray:
        e = env.unwrapped
        d = e.runner.sim.data
        R = d.xmat[e.runner.torso].reshape(3, 3)
        yaw = math.atan2(R[1, 0], R[0, 0])
        to_goal = e.goal - d.xpos[e.runner.torso][:2]
        err = (math.atan2(to_goal[1], to_goal[0]) - yaw + math.pi) % (2 * math.pi) - math.pi
        dist = float(np.hypot(*to_goal))
        speed = self.speed * min(1.0, dist / 3.0) * max(0.0, math.cos(err))
        _, _, v = e.robot_kinematics()
        return np.array([speed, np.clip(self.k_turn * err, -1.0, 1.0),
                         np.clip(float(np.hypot(*v)) / e.max_rate, -1.0, 1.0)], dtype=np.float32)


class SlantRangePayout:
    """``TetherWinch-v0``, a stronger reference than Eq. 30: pay out at the rate the straight
    line from the ship to the tow point lengthens, d/dt sqrt(r^2 + h^2) = v_r r / sqrt(r^2 + h^2)
    (v_r: the walker's range rate, r: its horizontal distance, h: the tow point's depth), so that
    a steep tether is not over-paid."""

    def __call__(self, env) -> np.ndarray:
        e = env.unwrapped
        tow, _, v = e.robot_kinematics()
        r = float(np.hypot(tow[0], tow[1]))
        radial = float(v @ (tow[:2] / max(r, 1e-9)))
        rate = radial * r / math.hypot(r, tow[2])
        return np.array([np.clip(rate / e.max_rate, -1.0, 1.0)], dtype=np.float32)

"""Thrust allocation: the wrench an autopilot asks for (body frame, N and N m about the origin)
shared among a vehicle's effectors (thrusters, fins, a propeller: the columns of B, each the
wrench of one unit of its command) within their limits, the moments before the forces.

``allocate`` answers in one of three ways:

* where the weighted least-squares answer of least effort, pinv(W B) W tau, is within every
  effector's limits (the usual case), that answer: it meets the wrench as closely as the
  effectors can, unbounded or not;
* where it is not (some effector saturates): the moments (the rows 3 to 5 that have a weight)
  as closely as the limits allow, by bounded least squares on those rows alone (the closest
  reachable moments are one point, however many commands give them); then the one weighted
  bounded least-squares problem over every row (scipy's ``lsq_linear``): where its answer gives
  those moments (to ``MET``), it stands: of the answers that give them, none gives the forces
  more closely (it minimises the forces' residual plus the moments', and the latter is the least
  there is). A pure surge demand, or a torpedo whose propeller gives no moment and whose fins no
  surge, ends here;
* else the forces, as closely as the limits allow with those moments held: bounded least
  squares on every row, the moments' rows aimed at what the first pass reached and weighted
  ``HOLD`` times more (an equality constraint's penalty form; the first pass reached them, so
  this one can too), and the commands themselves weighted ``LEAST`` (the least effort among
  answers that give the same wrench).

One weighted least squares over all rows, as before (moments weighted 10 per metre), is no
priority: the BlueROV2 Heavy asked for 3 m/s asks 563 N of surge of the 129 N its four
horizontal thrusters give, and against that surge error the weighted problem gave the yaw loop
none of its 6.6 N m. It did not turn to a new heading, and the hull's Munk moment (its sway added
mass above its surge one; with it left out, the vehicle kept its heading, unturned) spun it at
15 deg/s, where the quadratic yaw damping takes the moment (it has no linear yaw damping). Held
first, the yaw moment costs the surge 0.7 N per N of thrust the yaw takes, and the heading holds
(``tests/vehicles/test_bluerov2_heading.py``).

Units SI; body frame x forward, y left, z up; rows of a wrench (X, Y, Z, K, M, N).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import lsq_linear

HOLD = 1.0e3
"""How much more the second pass weighs the moments the first pass reached than the forces: the
moments' residual there is of order 1/HOLD^2 of the forces' (measured 1.7e-5 N m of yaw against
the BlueROV2's 434 N of unmet surge)."""
MET = 1.0e-6
"""A moment within MET of the most the effectors can give of it (N m) of the closest reachable one
is that one (1e-6: 4e-5 N m of the BlueROV2's 39 N m of yaw, what a heading error of 4
micro-radians asks)."""
LEAST = 1.0e-3
"""The weight of the commands themselves in the second pass (per unit of command, against the
weighted wrench): it picks the least-effort answer among those that give the same wrench (the
BlueROV2's four vertical thrusters have one combination that gives none) and moves the wrench by
about LEAST^2 of the commands (5e-5 N at 50 N)."""


def allocate(B: np.ndarray, lo: np.ndarray, hi: np.ndarray, wrench: np.ndarray, weights: np.ndarray,
             pinv: np.ndarray | None = None, method: str = "bvls") -> np.ndarray:
    """The commands (n,) that give ``wrench`` (6,) through the effectors' columns ``B`` (6 x n)
    within [``lo``, ``hi``] (n,), the rows weighted by ``weights`` (6,; 0: a row left to itself):
    the least-effort least-squares answer where it is within the limits, else the moments first
    (see the module docstring). ``pinv``: pinv(W B) where the caller keeps it (B fixed);
    ``method``: scipy's ``lsq_linear`` method for the one weighted bounded problem tried first."""
    WB = weights[:, None] * B
    target = weights * wrench
    x = (np.linalg.pinv(WB) if pinv is None else pinv) @ target
    if np.all(x >= lo) and np.all(x <= hi):
        return x
    x = lsq_linear(WB, target, bounds=(lo, hi), method=method).x
    moments = np.flatnonzero(weights[3:] > 0.0) + 3
    if len(moments) == 0:
        return x
    first = lsq_linear(WB[moments], target[moments], bounds=(lo, hi), method="bvls").x
    held = target.copy()
    held[moments] = WB[moments] @ first  # the moments as close as the effectors can give them (weighted)
    capacity = weights[moments] * (np.abs(B[moments]) @ np.maximum(hi, -lo))  # the most of each (weighted)
    if np.all(np.abs(WB[moments] @ x - held[moments]) <= MET * capacity):
        return x  # it gives those moments: no answer that gives them gives the forces more closely
    scale = np.ones(6)
    scale[moments] = HOLD
    n = B.shape[1]  # (and the commands themselves, weighted LEAST: of the answers that give that wrench,
    # the least effort, not whichever the solver meets first)
    A = np.vstack([scale[:, None] * WB, LEAST * np.eye(n)])
    return lsq_linear(A, np.r_[scale * held, np.zeros(n)], bounds=(lo, hi), method="bvls").x

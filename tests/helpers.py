"""Helpers that tests in several folders share (``tests/`` is on ``sys.path`` through the
rootdir's ``conftest.py``): a small anchor scenario, and the walker's pose errors."""

import math

import mujoco
import numpy as np

from mjtether.cable import builder

SMALL = """
[simulation]
duration = {duration}
timestep = 0.005
output_interval = 0.5
[water]
depth = 100.0
[water.current]
type = "exponential"
surface_speed = 0.8
decay_depth = 20.0
[tether]
length = 120.0
segments = 30
diameter = 0.03
density = 2500.0
EA = 5.0e6
[robot]
type = "anchor"
position = [60.0, 0.0, -80.0]
"""


def small(duration=10.0, extra=""):
    return SMALL.format(duration=duration) + extra


def pose_errors(run) -> tuple[float, float]:
    """(tilt of the walker's up axis from the seabed's normal, heading error from the commanded
    heading (the scenario's heading plus the commanded turn rate integrated)), degrees."""
    _, yaw, _, R = run.robot_state()
    rot = np.zeros(9)
    if run.scene.grid is not None:  # a bathymetry grid: the plane fitted to it under the walker
        from mjtether.scenario.scene import WALKER_PATCH
        x, y = run.sim.data.xpos[run.torso][:2]
        slope, heading = run.scene.grid.plane_at(x, y, WALKER_PATCH)
        mujoco.mju_quat2Mat(rot, np.array(builder.slope_quat(slope, heading)))
    else:
        mujoco.mju_quat2Mat(rot, run.sim.model.geom("seabed").quat)
    normal = rot[[2, 5, 8]]
    tilt = math.degrees(math.acos(min(1.0, float(R[:, 2] @ normal))))
    heading = math.degrees((yaw - run.heading_ref + math.pi) % (2 * math.pi) - math.pi)
    return tilt, abs(heading)


def raw_element_forces(bt, data) -> np.ndarray:
    """MuJoCo's own constraint force on each element's equality row (``efc_force``), shape
    (n,), read without mjtether's readouts (which clip at zero): negative pulls the element's
    nodes together (tension), positive pushes them apart; 0 where the equality is switched off
    (slack, or on the drum)."""
    eq = int(mujoco.mjtConstraint.mjCNSTR_EQUALITY)
    n = data.nefc
    rows = np.nonzero((data.efc_type[:n] == eq) & (data.efc_id[:n] >= bt.eq0) & (data.efc_id[:n] < bt.eq0 + bt.n))[0]
    f = np.zeros(bt.n)
    f[data.efc_id[rows] - bt.eq0] = data.efc_force[rows]
    return f

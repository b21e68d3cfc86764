"""A surface vessel carrying the winch (``ship.vessel``): the test vessel of
``tests/data/test_usv.toml`` holds station over an anchored cable, and its sinkage and trim are
what its hydrostatics and the cable's pull at the fairlead make them; it flies waypoints with the
cable in tow."""

import math
from pathlib import Path

import numpy as np
import pytest

from mjtether.scenario.runner import RECORD_FIELDS, ScenarioRun, run
from mjtether.scenario import load_scenario

USV = Path(__file__).resolve().parents[1] / "data" / "test_usv.toml"
COL = {name: k for k, (name, _, _) in enumerate(RECORD_FIELDS)}

SCENARIO = f"""
[simulation]
duration = {{duration}}
timestep = 0.005
output_interval = 1.0
[water]
depth = 60.0
[water.density]
type = "constant"
rho = 1025.0
[water.current]
type = "constant"
speed = 0.0
[tether]
length = 90.0
segments = 30
diameter = 0.02
density = 3000.0
EA = 1.0e6
[winch]
mode = "fixed"
[ship]
vessel = "{USV.as_posix()}"
mode = "{{mode}}"
position = [0.0, 0.0]
waypoints = [[30.0, 0.0], [30.0, 30.0]]
speed = 0.5
[robot]
type = "anchor"
position = [-40.0, 0.0, -60.0]
"""


def test_vessel_sinks_and_trims_as_its_hydrostatics_say():
    """On station in still water, a heavy cable hanging from the fairlead at the stern
    (x_f = -1 m): the vessel sinks by F_z / (rho g A_wp) and trims by the moment x_f F_z about
    its centre of gravity over rho g V GM_L (small angles; the cable's horizontal pull at the
    waterline adds no moment about the origin's height), F_z the cable's downward pull on the
    fairlead. Tolerances: 2 % (the sinkage moves the fairlead, and the cable's pull with it,
    by far less)."""
    sc = load_scenario(text=SCENARIO.format(duration=30.0, mode="fixed"))
    r = ScenarioRun(sc)
    try:
        for _ in range(int(30.0 / 0.005)):
            r.step()
        d = r.sim.data
        ship = r.sim.model.body("ship").id
        z = float(d.xpos[ship][2])
        R = d.xmat[ship].reshape(3, 3)
        pitch = math.asin(-R[2, 0])  # > 0 nose down
        F = r.named.ship_force  # the cable's force on the vessel (N, world)
    finally:
        r.close()
    rho, g, A, V, GM_L, x_f = 1025.0, sc.water.gravity, 0.8, 0.08, 2.5, -1.0
    assert F[2] < -50.0  # the cable pulls down
    assert z == pytest.approx(F[2] / (rho * g * A), rel=0.02)
    # the cable's pull F_z (< 0) at the stern (x_f < 0): a moment -x_f F_z about y (z up, y left),
    # bow up, pitch < 0 (positive nose down)
    moment = -x_f * F[2]
    assert pitch < 0.0
    assert pitch == pytest.approx(moment / (rho * g * V * GM_L), rel=0.02)


def test_vessel_flies_its_waypoints_with_the_cable():
    """Line-of-sight guidance along ship.waypoints at 0.5 m/s: the vessel passes the first
    (within robot.acceptance_radius, 2 m) and heads for the second; it stays afloat."""
    sc = load_scenario(text=SCENARIO.format(duration=90.0, mode="waypoints"),
                       overrides=["robot.position=[10.0, 0.0, -60.0]"])
    rows, _, info = run(sc, keep_nodes=False)
    x, y = rows[:, COL["ship_x"]], rows[:, COL["ship_y"]]
    passed = np.flatnonzero(np.hypot(x - 30.0, y) < 2.0)
    assert len(passed) and y[-1] > 5.0
    assert np.all(np.abs(y[:passed[0]]) < 0.5)  # on the first leg
    assert info["initial_state"].startswith("quasi-static steady state")


def test_a_vessel_must_float_and_have_thrusters():
    from mjtether.scenario.config import ConfigError

    with pytest.raises(ConfigError, match=r"ship.vessel = .*bluerov2_heavy is not a surface vessel"):
        load_scenario(text=SCENARIO.format(duration=10.0, mode="fixed").replace(USV.as_posix(), "bluerov2_heavy"))
    with pytest.raises(ConfigError, match=r"ship.heave_amplitude .*is for the prescribed ship"):
        load_scenario(text=SCENARIO.format(duration=10.0, mode="fixed") + "\n", overrides=["ship.heave_amplitude=1.0"])


FOLLOW = f"""
[simulation]
duration = 80.0
timestep = 0.005
output_interval = 1.0
[water]
depth = 60.0
[tether]
length = 40.0
segments = 20
diameter = 0.0076
density = 1150.0
EA = 2.0e5
[winch]
mode = "fixed"
[ship]
vessel = "{USV.as_posix()}"
mode = "follow"
position = [0.0, 0.0]
offset = [-15.0, 0.0]
[robot]
type = "vehicle"
vehicle = "bluerov2_heavy"
position = [15.0, 0.0, -20.0]
setpoints = [[0.0, 0.0, 0.0, 20.0], [10.0, 0.4, 0.0, 20.0]]
"""


def test_vessel_follows_the_robot():
    """``ship.mode = "follow"`` with a vessel: its autopilot holds a station 15 m behind the
    BlueROV2's tow point, moving with the ROV at 0.4 m/s. Over the last 20 s of 80 s the vessel
    is within 0.5 m of that station (its PD acts on the position and on the velocity relative to
    the station's: it lags by what it takes to make its drag at 0.4 m/s, d_u u + d_uu u^2 = 8.8 N,
    and the cable's pull over its station gain of 60 N/m, about 0.2 m; measured 0.22 m) and moves
    at the ROV's speed, to 2 %."""
    rows, _, _ = run(load_scenario(text=FOLLOW))
    late = rows[rows[:, COL["time"]] >= 60.0]
    gap = np.hypot(late[:, COL["ship_x"]] - (late[:, COL["robot_x"]] - 15.0), late[:, COL["ship_y"]] - late[:, COL["robot_y"]])
    assert gap.max() < 0.5
    t, x = late[:, COL["time"]], late[:, COL["ship_x"]]
    speed = (x[-1] - x[0]) / (t[-1] - t[0])
    assert speed == pytest.approx(late[:, COL["robot_speed"]].mean(), rel=0.02)

"""A vehicle at the tether's end in a scenario: its autopilot reaches its setpoints with the
umbilical pulling, its state is read through the named readouts, and bad vehicle input is named.

The vehicle is the test ROV of ``tests/data/test_rov.toml`` (made-up numbers) on 40 m of
slightly heavy cable from a ship holding station."""

import math
from pathlib import Path

import numpy as np
import pytest

from mjtether.scenario.config import ConfigError
from mjtether.scenario.runner import ScenarioRun, run
from mjtether.scenario import load_scenario
from mjtether.vehicles.files import load_vehicle, thrust_matrix

ROV = Path(__file__).resolve().parents[1] / "data" / "test_rov.toml"

SCENARIO = f"""
[simulation]
duration = 40.0
timestep = 0.005
output_interval = 1.0
[water]
depth = 60.0
[tether]
length = 40.0
segments = 20
diameter = 0.008
density = 1100.0
EA = 1.0e6
[winch]
mode = "fixed"
[robot]
type = "vehicle"
vehicle = "{ROV.as_posix()}"
position = [10.0, 0.0, -15.0]
setpoints = [[0.0, 0.0, 0.0, 15.0], [10.0, 0.3, 30.0, 20.0]]
"""


def test_autopilot_reaches_its_setpoints_on_the_tether():
    """After 10 s holding 15 m, the setpoint becomes 0.3 m/s at 30 degrees and 20 m: 30 s later
    the vehicle is within 0.25 m of the depth, 1 degree of the heading and 0.02 m/s of the speed
    (the loops' steady error; a tighter tolerance would test the gains, not the model), level to
    2 degrees, and the tether pulls on it (its tow tension > 0)."""
    sc = load_scenario(text=SCENARIO)
    r = ScenarioRun(sc)
    try:
        assert r.initial is not None  # started from the quasi-static steady state to its tow point
        for _ in range(int(round(40.0 / r.sim.timestep))):
            r.step()
        n = r.named
        depth = -float(r.sim.data.xpos[n.torso][2])
        roll, pitch = n.robot_roll_pitch
        assert abs(depth - 20.0) < 0.25, depth
        assert abs(math.degrees(n.robot_heading) - 30.0) < 1.0, math.degrees(n.robot_heading)
        assert abs(n.robot_speed - 0.3) < 0.02, n.robot_speed
        assert max(abs(roll), abs(pitch)) < math.radians(2.0), (roll, pitch)
        assert n.tow_tension > 0.0
        # the cable's pull, turned into the body frame, is what the readout gives
        np.testing.assert_allclose(n.robot_rotation @ n.tow_force_body, n.tow_force, rtol=1e-12, atol=1e-12)
    finally:
        r.close()


def test_vehicle_run_records_its_state():
    rows, history, info = run(load_scenario(text=SCENARIO, overrides=["simulation.duration=5.0"]))
    assert np.all(np.isfinite(rows)) and len(rows) == 6
    assert info["initial_state"].startswith("quasi-static")


def test_thrust_matrix_by_hand():
    """The test ROV's front-left thruster pushes forward-right at 45 degrees from (0.15, 0.1, 0):
    its column is [d; r x d] with d = (1, -1, 0) / sqrt 2 and r x d = (0, 0, -0.15 - 0.1) / sqrt 2."""
    B = thrust_matrix(load_vehicle(ROV).thrusters)
    assert B.shape == (6, 6)
    h = 1 / math.sqrt(2)
    np.testing.assert_allclose(B[:, 0], [h, -h, 0.0, 0.0, 0.0, -0.25 * h], atol=1e-12)


@pytest.mark.parametrize("extra, message", [
    ('vehicle = "no_such_vehicle"', "robot.vehicle = 'no_such_vehicle': vehicle 'no_such_vehicle': not a shipped"),
    ("setpoints = [[0.0, 0.3, 0.0, -5.0]]", "robot.setpoints = .*depths .* >= 0 m"),
    ("setpoints = [[1.0, 0.3, 0.0, 5.0]]", "robot.setpoints = .*must start at 0"),
])
def test_bad_vehicle_input_is_named(extra, message):
    text = SCENARIO.replace('setpoints = [[0.0, 0.0, 0.0, 15.0], [10.0, 0.3, 30.0, 20.0]]', "")
    if extra.startswith("vehicle"):
        text = text.replace(f'vehicle = "{ROV.as_posix()}"', extra)
    else:
        text += extra + "\n"
    with pytest.raises(ConfigError, match=message):
        load_scenario(text=text)


def test_bad_vehicle_file_is_named(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(ROV.read_text().replace("mass = 11.0", "mas = 11.0"))
    with pytest.raises(ValueError, match="bad.toml: unknown key vehicle.mas"):
        load_vehicle(bad)


def test_bluerov2_top_speed_with_its_thrusters_saturated():
    """The shipped BlueROV2 Heavy asked for 3 m/s (more than it can do) at 20 m, alone in still
    water: its four horizontal T200s saturate (two forward at 51.4 N, two reversed at 39.9 N, at
    45 degrees: X = 0.7071 (2 51.4 + 2 39.9) = 129.1 N) while the vertical ones hold depth and
    trim, and it settles where its surge damping takes all of X: 13.7 u + 141 u^2 = 129.1 N,
    u = 0.910 m/s (von Benzon et al. 2022's damping; their own 85 N of thrust gives 0.73 m/s,
    their Table 4 0.72 m/s). Tolerance 1 %: the depth and pitch loops' small forces."""
    from types import SimpleNamespace

    import mujoco

    import mjtether as mt
    from mjtether.scenario.controllers import VehiclePilot
    from mjtether.vehicles.files import build_vehicle

    vs = load_vehicle("bluerov2_heavy")
    water = mt.WaterColumn(depth=100.0)
    spec = mujoco.MjSpec()
    spec.option.timestep = 0.005
    vm = build_vehicle(spec, vs, "vehicle", pos=(0.0, 0.0, -20.0))
    with mt.Simulation(spec, water, bodies=[vm]) as sim:
        acts = np.array([sim.model.actuator(f"vehicle/{t.name}").id for t in vs.thrusters])
        pilot = VehiclePilot(np.array([[0.0, 3.0, 0.0, 20.0]]), vs.autopilot, vs.thrusters, acts)
        run_like = SimpleNamespace(vehicle=sim.bodies[0], sim=sim)
        speeds = []
        for k in range(int(round(30.0 / 0.005))):
            pilot.update(run_like, sim.time, 0.005)
            sim.step()
            if sim.time > 25.0:
                speeds.append(sim.bodies[0].velocity(sim.data)[0][0])
    X = 0.70711 * (2 * 51.4 + 2 * 39.9)
    expected = (-13.7 + math.sqrt(13.7**2 + 4 * 141.0 * X)) / (2 * 141.0)
    assert float(np.mean(speeds)) == pytest.approx(expected, rel=0.01)


def test_vehicle_settling_start_flies_its_first_setpoint():
    """start = "settle": the cable falls from a guessed shape while the vehicle holds its first
    setpoint on its autopilot (it is not welded in place); the run then goes on as usual."""
    r = ScenarioRun(load_scenario(text=SCENARIO, overrides=['simulation.start="settle"']))
    try:
        assert r.initial is None and r.initial_note == "settled with the robot on its autopilot"
        depth = -float(r.sim.data.xpos[r.named.torso][2])
        assert abs(depth - 15.0) < 0.5 and r.sim.time == 0.0
        r.step()
    finally:
        r.close()


ROUTE = """
[simulation]
duration = 100.0
timestep = 0.005
[water]
depth = 80.0
[tether]
length = 80.0
segments = 30
diameter = 0.0076
density = 1150.0
EA = 2.0e5
[winch]
mode = "fixed"
[robot]
type = "vehicle"
vehicle = "bluerov2_heavy"
position = [10.0, 1.0, -20.0]
waypoints = [[30.0, 0.0, 20.0, 0.5], [30.0, 20.0, 25.0, 0.5]]
"""


def test_line_of_sight_route_then_station_keeping():
    """The BlueROV2 starts 1 m off the first leg (from its start towards (30, 0)), follows the
    route by line-of-sight guidance in still water and holds station at the last waypoint with
    the umbilical pulling: on the first leg, from x = 18 m on, it is within 0.1 m of the leg's line
    (plain LOS converges to the line without a current); over the last 20 s it stays within 0.2 m
    of (30, 20) horizontally and 0.1 m of 25 m depth."""
    r = ScenarioRun(load_scenario(text=ROUTE))
    try:
        leg_a, leg_b = np.array([10.0, 1.0]), np.array([30.0, 0.0])
        d = (leg_b - leg_a) / np.linalg.norm(leg_b - leg_a)
        worst_leg, held = 0.0, []
        for _ in range(int(round(100.0 / r.sim.timestep))):
            r.step()
            p = r.sim.data.xpos[r.named.torso]
            if r.pilot._leg == 0 and p[0] > 18.0:
                off = p[:2] - leg_a
                worst_leg = max(worst_leg, abs(off[0] * d[1] - off[1] * d[0]))
            if r.sim.time > 80.0:
                held.append(p.copy())
        assert r.pilot.station is not None
        held = np.array(held)
        assert worst_leg < 0.1, worst_leg
        assert np.max(np.hypot(held[:, 0] - 30.0, held[:, 1] - 20.0)) < 0.2
        assert np.max(np.abs(held[:, 2] + 25.0)) < 0.1
    finally:
        r.close()


def test_a_vehicle_starting_at_a_heading_starts_on_its_cable():
    """A vehicle placed at a start heading of 120 deg: the cable's quasi-static start is solved
    to its tow point turned with it (the tow point is behind the origin), and at t = 0 the
    cable's last node is there (within 1 mm: the soft connect after the pre-roll)."""
    text = SCENARIO.replace('position = [10.0, 0.0, -15.0]', 'position = [10.0, 0.0, -15.0]\nheading_deg = 120.0')
    sc = load_scenario(text=text.replace("[0.0, 0.0, 0.0, 15.0], ", "[0.0, 0.0, 120.0, 15.0], "))
    r = ScenarioRun(sc)
    try:
        assert r.initial is not None
        tow = r.named.robot_position
        vs = load_vehicle(ROV)
        yaw = math.radians(120.0)
        R = np.array([[math.cos(yaw), -math.sin(yaw), 0.0], [math.sin(yaw), math.cos(yaw), 0.0], [0.0, 0.0, 1.0]])
        assert np.allclose(r.initial.nodes[-1], np.array([10.0, 0.0, -15.0]) + R @ np.asarray(vs.tow_point), atol=1e-9)
        assert np.linalg.norm(r.named.tether_nodes[-1] - tow) < 1e-3
        assert math.degrees(r.named.robot_heading) == pytest.approx(120.0, abs=0.5)
    finally:
        r.close()


CROSS_CURRENT = ROUTE.replace("[tether]", """[water.current]
type = "constant"
speed = 0.15
heading_deg = 90.0
[tether]""").replace("position = [10.0, 1.0, -20.0]\nwaypoints = [[30.0, 0.0, 20.0, 0.5], [30.0, 20.0, 25.0, 0.5]]",
                     "position = [5.0, 0.0, -20.0]\nwaypoints = [[70.0, 0.0, 20.0, 0.5], [70.0, 20.0, 20.0, 0.5]]")


@pytest.mark.parametrize("kappa", [0.0, 1.0], ids=["plain", "integral"])
def test_integral_line_of_sight_takes_out_the_current_offset(kappa):
    """A 65 m leg along x at 0.5 m/s in a 0.15 m/s cross current (+y). Plain LOS holds the leg
    only where the heading it asks for crabs into the current: the vehicle sits off the line by
    lookahead x tan(crab angle) = 5 m x 0.15 / sqrt(0.5^2 - 0.15^2) = 1.6 m downstream (a
    kinematic answer, the speed through the water kept at 0.5 m/s; between 1.4 and 1.9 m here);
    integral LOS (kappa = 1) holds it within 0.15 m from x = 40 m on."""
    sc = load_scenario(text=CROSS_CURRENT, overrides=["simulation.duration=130.0",
                                                      f"robot.los_integral_gain={kappa}"])
    r = ScenarioRun(sc)
    offsets = []
    try:
        while r.sim.time < 130.0 - 1e-9 and r.pilot._leg == 0:
            r.step()
            p = r.sim.data.xpos[r.named.torso]
            if 40.0 <= p[0] <= 65.0:
                offsets.append(float(p[1]))
    finally:
        r.close()
    offsets = np.array(offsets)
    assert len(offsets) > 1000
    if kappa == 0.0:
        assert np.all((offsets > 1.4) & (offsets < 1.9)), (offsets.min(), offsets.max())
    else:
        assert np.max(np.abs(offsets)) < 0.15, np.max(np.abs(offsets))

"""The free drum (tension zero at the drum, as in the AUV-and-cable model of paying out from a
drum: T = 0 at the drum end) working from zero deployed length."""

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest
from conftest import new_spec

import mjtether as mt


def test_sinker_pulls_cable_off_a_free_drum_from_zero_length():
    """A 50 kg sphere (0.3 m across) hangs at the fairlead with nothing deployed, the drum free
    (it pays out at tension / 200 N s/m). Released, the sphere sinks and pulls cable off the
    drum. Over the last 10 s of a 60 s run (means; the free drum and the cable's axial mode ring):
    * the deployed length equals the sphere's depth within 0.5 m (the cable hangs straight);
    * the deployed elements number deployed length / 2 m nominal, to one (the drum element);
    * the sphere is at terminal speed: the cable's pull on it balances its weight less its
      buoyancy and drag (1/2 rho Cd A v^2 at its measured speed), within 2 %;
    * the cable is in balance: the pull at the top is the pull at the bottom plus the cable's
      submerged weight less the tangential drag on it as it sinks at that speed, within 2 %."""
    dt = 0.005
    water = mt.WaterColumn(depth=300.0)
    tether = mt.TetherSpec(length=2.0, segments=1, diameter=0.02, density=1300.0, EA=1e6)
    r, m_s, cd = 0.15, 50.0, 1.0
    spec = new_spec(dt)
    body = spec.worldbody.add_body(name="sinker", pos=[0, 0, 0])
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[r, 0, 0], mass=m_s, contype=0, conaffinity=0)
    volume, area = 4 / 3 * math.pi * r**3, math.pi * r**2
    hydro = mt.add_body_hydro(spec, "sinker", mt.RigidBodyHydro(volume=volume, drag_cd=cd, drag_area=area))
    tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, 0]), mt.BodyPoint("sinker"), water=water,
                       nodes=np.zeros((2, 3)), max_length=100.0)
    winch = mt.Winch(length=0.0, mode="free", drum_damping=200.0, max_length=100.0, max_rate=5.0, max_accel=5.0)
    tail = []
    with mt.Simulation(spec, water, [tm], [hydro]) as sim:
        bt = sim.tether()
        bt.set_length(0.0)
        sim.forward()
        assert bt.deployed_length == 0.0 and bt.N == 1
        sid = sim.model.body("sinker").id
        for k in range(int(round(60.0 / dt))):
            T = bt.end_tension(sim.data, "start")
            bt.set_length(winch.advance(dt, sim.time, T), rate=winch.current_rate)
            sim.step()
            if sim.time > 50.0:
                d = sim.data
                tail.append((bt.deployed_length, -d.xpos[sid][2], bt.N, -d.cvel[sid][5],
                             bt.end_force(d, "start")[2], bt.end_force(d, "end")[2]))
    L, depth, n_el, v, top, bottom = np.array(tail).T
    assert np.abs(L - depth).max() < 0.5
    assert np.all(np.abs(n_el - L / 2.0) <= 1.0)
    rho, g = 1025.0, 9.81
    v_mean = v.mean()
    pull = m_s * g - rho * volume * g - 0.5 * rho * cd * area * v_mean**2
    assert bottom.mean() == pytest.approx(pull, rel=0.02)
    w = tether.wet_weight_per_length(rho)
    drag = 0.5 * rho * tether.cd_tangential * math.pi * tether.diameter * v_mean**2
    assert -top.mean() == pytest.approx(bottom.mean() + (w - drag) * L.mean(), rel=0.02)


FIBRE = """
[simulation]
duration = 120.0
timestep = 0.005
output_interval = 1.0
[water]
depth = 100.0
[tether]
length = 20.0
segments = 4
diameter = 0.001
density = 1025.0
cd_normal = 1.2
cd_tangential = 0.01
EA = 0.0
[winch]
mode = "free"
start_empty = true
max_length = 150.0
max_rate = 3.0
drum_damping = 0.5
[ship]
fairlead_z = -20.0
[robot]
type = "vehicle"
vehicle = "remus100"
position = [{x}, 0.0, -20.0]
heading_deg = 0.0
setpoints = [[0.0, 1.0, 0.0, 20.0]]
"""


def test_a_vehicle_pulls_fibre_off_a_free_drum_from_nothing():
    """``winch.start_empty``: a REMUS 100 starts with its tow point at the fairlead and nothing
    deployed, and runs ahead at 1 m/s pulling a neutrally buoyant 1 mm fibre off a free drum (the
    001 paper's straight run). The fibre lies straight behind it and slides along itself at the
    payout speed, so over the last 20 s of 120 s (means): the deployed length is the distance
    run, within 0.5 m; and the pull at the tow point less the pull at the drum is the tangential
    drag of the whole deployed length, 1/2 rho C_dt pi d L v^2, within 1 % (exact for a straight
    line sliding along itself; the depth loop's small wander would add normal drag: measured
    1e-6). A start with the tow point away from the fairlead is refused with the position that
    would do."""
    from mjtether.scenario.config import ConfigError
    from mjtether.scenario.runner import ScenarioRun
    from mjtether.scenario import load_scenario

    run = ScenarioRun(load_scenario(text=FIBRE.format(x=0.8)))
    try:
        assert run.named.deployed_length == 0.0 and run.initial_note.startswith("nothing deployed")
        x0 = run.named.robot_position[0]
        tail = []
        for _ in range(int(round(120.0 / 0.005))):
            run.step()
            if run.named.time > 100.0:
                n = run.named
                tail.append((n.deployed_length, n.robot_position[0] - x0, n.tow_tension - n.ship_tension,
                             n.payout_rate))
    finally:
        run.close()
    L, run_x, dT, v = np.array(tail).T
    assert np.abs(L - run_x).max() < 0.5
    drag = 0.5 * 1025.0 * 0.01 * math.pi * 0.001 * L * v ** 2
    assert dT.mean() == pytest.approx(drag.mean(), rel=0.01)
    with pytest.raises(ConfigError, match=r"robot.position = \[0.8, 0.0, -20.0\]"):
        ScenarioRun(load_scenario(text=FIBRE.format(x=3.0)))


def test_a_free_drum_is_not_held_back_by_an_acceleration_limit(tmp_path):
    """The REMUS 100 of examples/remus_fibre_payout.toml flown off a free drum from nothing
    deployed (drum damping c = 2 N s/m): with no ``winch.max_accel`` given, the drum takes only
    its damping, so the tension at the drum follows c times the payout rate. In 2 s means over
    the first 10 s within 1 N (measured 0.06 N at worst; single steps chatter up to 27 N while the
    first 3 m leave the drum). With the 0.2 m/s^2 limit that used to be the default, the drum
    held the vehicle back with 71 N for seconds where c v was 1.1 N."""
    from mjtether import cli
    example = Path(__file__).resolve().parents[2] / "examples" / "remus_fibre_payout.toml"
    out = tmp_path / "res"
    assert cli.main(["run", str(example), "--set", "winch.start_empty=true", "--set", "ship.fairlead_z=-20",
                     "--set", "robot.position=[0.8, 0.0, -20.0]", "--set", "simulation.duration=10",
                     "--set", "simulation.output_interval=0.005", "--out", str(out), "--no-plots"]) == 0
    rows = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    t = rows["time_s"]
    for lo in (0.0, 2.0, 4.0, 6.0, 8.0):
        w = (t > lo) & (t <= lo + 2.0)
        drum = rows["ship_tension_N"][w].mean()
        assert abs(drum - 2.0 * rows["payout_rate_mpers"][w].mean()) <= 1.0, (lo, drum)

"""A submerged vehicle at the free surface: it keeps the part of its buoyancy, added-mass and
damping forces and hull loads that is under the water, and its thrusters, fins and propeller
give nothing in the air; a positively buoyant vehicle floats, it never flies (issue 30: a
BlueROV2 released at 1 m depth used to be 9.6 m above the water after 200 s)."""

import mujoco
import numpy as np
import pytest

from mjtether import cli
from mjtether.physics import water as wm
from mjtether.simulation import Simulation
from mjtether.vehicles.files import build_vehicle, load_vehicle
from conftest import new_spec


def _spec(water) -> mujoco.MjSpec:
    """A 5 ms implicit-fast model under the water's own gravity."""
    spec = new_spec(0.005)
    spec.option.gravity = [0.0, 0.0, -water.gravity]
    return spec


def test_a_buoyant_rov_floats_with_archimedes_share_of_it_under_water():
    """The BlueROV2 Heavy (13.5 kg, 0.0134 m^3: 2.3 N buoyant in sea water) released at rest 1 m
    down, thrusters off: it rises and floats. Its centre never goes above the surface, and after
    120 s it is within its own height (0.378 m) of it, at rest, with the part of it under water
    that carries its weight: B_wet = m g, Archimedes, within 0.5 % (the rest: its slow heave)."""
    vs = load_vehicle("bluerov2_heavy")
    water = wm.WaterColumn(depth=50.0)
    spec = _spec(water)
    vm = build_vehicle(spec, vs, "rov", pos=(0.0, 0.0, -1.0))
    with Simulation(spec, water, bodies=[vm]) as sim:
        bv, d = sim.bodies[0], sim.data
        highest = -np.inf
        for _ in range(int(round(120.0 / 0.005))):
            sim.step()
            highest = max(highest, float(d.xpos[bv.id][2]))
        z, wet = float(d.xpos[bv.id][2]), bv.wet_fraction(d)
        speed = float(np.linalg.norm(d.qvel[:3]))
    assert highest <= 0.0, highest
    assert -2 * vs.size[2] <= z <= 0.0 and speed < 1e-3, (z, speed)
    assert wet * 1025.0 * vs.hydro.volume == pytest.approx(vs.mass, rel=5e-3)


def test_a_vehicle_breaking_the_surface_is_logged_and_may_stop_the_run(tmp_path):
    """A BlueROV2 asked to hold 0 m depth breaks the surface: the run logs it with its time
    (summary.json run.surface_events) and, with robot.stop_at_surface, ends there with its results
    written up to then."""
    import json

    text = ('[simulation]\nduration = 60.0\n[tether]\nattached = false\n[robot]\ntype = "vehicle"\n'
            'vehicle = "bluerov2_heavy"\nposition = [0.0, 0.0, -5.0]\nsetpoints = [[0.0, 0.0, 0.0, 0.0]]\n')
    (tmp_path / "up.toml").write_text(text)
    for stop, out in (("false", tmp_path / "a"), ("true", tmp_path / "b")):
        assert cli.main(["run", str(tmp_path / "up.toml"), "--set", f"robot.stop_at_surface={stop}", "--out", str(out),
                         "--no-plots"]) == 0
        run = json.loads((out / "summary.json").read_text())["run"]
        events = run["surface_events"]
        assert events and events[0]["kind"] == "breach" and 0.0 < events[0]["time_s"] < 60.0
        rows = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
        assert rows["robot_z_m"].max() <= 0.5  # (floats: never flies)
        if stop == "true":
            assert "robot.stop_at_surface" in run["stopped"] and rows["time_s"][-1] < 60.0
        else:
            assert rows["time_s"][-1] == pytest.approx(60.0)


@pytest.mark.slow
def test_the_hong_uuv_pitching_up_at_0_6_m_s_breaches_and_is_reported(tmp_path):
    """examples/hong2020_platform.toml with the UUV at 0.6 m/s (no depth loop) for 300 s: the
    cable's pull pitches it up until it reaches the surface (at 85.7 s, measured). It used to
    keep its full buoyancy, drag and thrust in the air and fly to z = +3.0 m; now the run logs
    the breach and the vehicle stays at the surface for the rest of the run (its tow point below
    z = 0 at every sample)."""
    import json
    from pathlib import Path

    example = Path(__file__).resolve().parents[2] / "examples" / "hong2020_platform.toml"
    out = tmp_path / "res"
    assert cli.main(["run", str(example), "--set", "simulation.duration=300", "--set",
                     "robot.setpoints=[[0.0, 0.6, 0.0, 3.0]]", "--out", str(out), "--no-plots"]) == 0
    events = json.loads((out / "summary.json").read_text())["run"]["surface_events"]
    assert len(events) >= 1 and 60.0 < events[0]["time_s"] < 120.0, events
    rows = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    assert rows["robot_z_m"].max() < 0.0


def test_every_shipped_vehicle_states_its_water_and_a_neutral_one_stays_put_in_it():
    """Every shipped vehicle file says the water it is trimmed for; the REMUS 100, neutral in
    Fossen's 1026 kg/m^3 (``hydro.volume = "neutral"``: its mass over that density), left at rest
    20 m down in that water moves less than 1 mm in 60 s (its volume rounded to 7 figures had it
    rise 2.7 mm)."""
    from mjtether.vehicles.files import shipped

    for name in shipped():
        assert load_vehicle(name).water_density is not None, name
    vs = load_vehicle("remus100")
    water = wm.WaterColumn(depth=100.0, density=wm.ConstantDensity(vs.water_density))
    assert vs.mass == pytest.approx(vs.water_density * vs.hydro.volume, rel=1e-15)
    spec = _spec(water)
    vm = build_vehicle(spec, vs, "auv", pos=(0.0, 0.0, -20.0))
    with Simulation(spec, water, bodies=[vm]) as sim:
        start = sim.data.xpos[sim.bodies[0].id].copy()
        sim.run(60.0)
        moved = float(np.linalg.norm(sim.data.xpos[sim.bodies[0].id] - start))
    assert moved < 1e-3, moved

"""The walker as a part of a network (``[walkers.NAME]``): the scenario's hexapod standing on the
seabed and walking on the scenario's gait drive, and the two shipped networks that use it
(examples/networks/walker_clump_bridle.toml, ship_cage_walker.toml). Checked against what does
not come from the network's run: the walker's own MJCF, a scenario run of the same walker on
the same tether, the kinematics of a speed ramped at the gait's acceleration, and the weights in
water of the clump, the lines and the cage (Archimedes) and the clump's drag (Morison)."""

import math
from pathlib import Path

import numpy as np
import pytest

from mjtether import cli
from mjtether.io import moordyn
from mjtether.network import NetworkError, from_dict, to_dict
from mjtether.network import run as nr
from mjtether.network.config import WALKER_TOW_POINT
from mjtether.scenario import load_scenario
from mjtether.scenario.readouts import RECORD_FIELDS
from mjtether.scenario.runner import run as run_scenario
from mjtether.walker import walker_spec

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "networks"
G, RHO = 9.80665, 1025.0
WALK_ACCEL = 0.2  # m/s^2: the gait drive's speed ramp (scenario.controllers.WALK_ACCEL)
TETHER = {"diameter": 0.03, "mass_per_length": 1.5, "EA": 1e7}


def walker_net(speed: float, duration: float = 10.0, **walker) -> dict:
    """A ship's coupled point at the surface and a walker 20 m off on a 30 m deep seabed, on a 45 m
    tether: the network of ``scenario_of``."""
    return {"water": {"depth": 30.0, "seabed_stiffness": 0.0},
            "simulation": {"duration": duration, "timestep": 0.005, "output_interval": 0.5},
            "line_types": {"t": TETHER},
            "walkers": {"w": {"position": [20.0, 0.0], "speed": speed, **walker}},
            "points": {"ship": {"kind": "coupled", "position": [0.0, 0.0, 0.0]},
                       "tow": {"kind": "body", "body": "w"}},
            "lines": [{"name": "tether", "type": "t", "a": "tow", "b": "ship", "length": 45.0, "segments": 20}]}


def scenario_of(speed: float, duration: float = 10.0):
    return load_scenario(data={"water": {"depth": 30.0},
                               "simulation": {"duration": duration, "timestep": 0.005, "output_interval": 0.5},
                               "tether": {"length": 45.0, "segments": 20, **TETHER}, "ship": {"fairlead_z": 0.0},
                               "robot": {"type": "walker", "start": [20.0, 0.0], "commands": [[0.0, speed, 0.0]]}})


def network_track(speed: float) -> np.ndarray:
    """(time s, torso x, y m, heading deg) of the network's walker."""
    net = from_dict(walker_net(speed))
    r, rows = nr.simulate(net)
    r.sim.close()
    cols = nr.columns(net)
    return rows[:, [0] + [cols.index(f"walkerw_{k}") for k in ("x_m", "y_m", "heading_deg")]]


def test_the_tow_point_a_walker_point_defaults_to_is_the_walkers_own():
    """A ``body`` point on a walker given no position is at ``WALKER_TOW_POINT``: the site
    ``tow_point`` of assets/walker/walker.xml, in its torso's frame."""
    site = walker_spec().site("tow_point")
    assert np.allclose(WALKER_TOW_POINT, site.pos, atol=1e-12)
    assert from_dict(walker_net(0.0)).points["tow"].position == pytest.approx(tuple(site.pos))


def test_a_network_walker_walks_as_the_scenarios_walker():
    """Commanded at 0.3 m/s for 10 s, the network's walker covers what the scenario's walker covers
    on the same tether in the same water (within 3 %, measured 0.3 %: the scenario's ship and
    pre-roll are not the network's), and about what a speed ramped up at WALK_ACCEL gives,
    v (t - v / 2a) = 2.775 m (within 5 %: the tripod's feet are not rigid; the scenario's walker
    makes 2 % more), keeping its heading (0.5 deg) and line (0.1 m)."""
    v, T = 0.3, 10.0
    track = network_track(v)
    walked = track[-1, 1] - track[0, 1]
    rows, _, _ = run_scenario(scenario_of(v))
    names = [f[0] for f in RECORD_FIELDS]
    scenario_walked = rows[-1, names.index("robot_x")] - rows[0, names.index("robot_x")]
    assert walked == pytest.approx(scenario_walked, rel=0.03)
    assert walked == pytest.approx(v * (T - v / (2 * WALK_ACCEL)), rel=0.05)
    assert np.abs(track[:, 3]).max() < 0.5 and np.abs(track[:, 2]).max() < 0.1


def test_a_walker_at_speed_0_stands_where_it_was_put():
    """At speed 0 the walker steps in place on its position, facing its heading: within 5 cm
    and 0.5 deg over 10 s (a tether of 45 m pulling it with tens of newtons); its torso about
    WALKER_STAND_HEIGHT (0.9 m) over the seabed (within 5 cm: its feet sink into MuJoCo's soft
    contact)."""
    net = from_dict(walker_net(0.0, heading_deg=30.0))
    r, rows = nr.simulate(net)
    cols = nr.columns(net)
    r.sim.close()
    xy = rows[:, [cols.index("walkerw_x_m"), cols.index("walkerw_y_m")]]
    assert np.hypot(*(xy - [20.0, 0.0]).T).max() < 0.05
    assert np.abs(rows[:, cols.index("walkerw_heading_deg")] - 30.0).max() < 0.5
    assert rows[:, cols.index("walkerw_z_m")] + 30.0 == pytest.approx(np.full(len(rows), 0.9), abs=0.05)


def test_the_statics_hold_a_walkers_points_where_it_stands():
    """The line starts at the walker's tow point as MuJoCo places the site on the stood walker
    (its pose, not the network's arithmetic: within 1 um), and it stays there at the first step
    (within 1 mm)."""
    net = from_dict(walker_net(0.0, duration=0.01))
    r = nr.build(net)
    site = r.sim.data.site_xpos[r.sim.model.site("walker/w/tow_point").id].copy()
    assert np.allclose(r.line_nodes("tether")[0], site, atol=1e-6)
    assert np.allclose(nr.start_positions(net)["tow"], site, atol=1e-6)
    r.advance(1)
    assert np.allclose(r.poses_now().site_xpos[r.sim.model.site("walker/w/tow_point").id], site, atol=1e-3)
    r.sim.close()


@pytest.mark.parametrize("change, says", [
    ({"sped": 0.3}, r"walkers\.w: unknown key\(s\) sped; allowed: commands, gait_period, heading_deg, position, speed"),
    ({"speed": 1.5}, r"walker 'w': speed = 1\.5: must be in \[-1\.00, 1\.00\] m/s"),
    ({"heading_deg": 400.0}, r"walker 'w': heading_deg = 400.*\[-360, 360\] deg"),
    ({"position": [1.0, 2.0, 3.0]}, r"walker 'w': position"),
    ({"gait_period": 0.1}, r"walker 'w': gait_period = 0\.1.*\[0\.4, 5\]"),
    ({"commands": [[1.0, 0.2, 0.0]]}, r"walker 'w': commands.*start at 0"),
    ({"commands": [[0.0, 0.2, 0.0]], "speed": 0.1}, r"walker 'w': give speed or commands, not both"),
    ({"position": [1e7, 0.0]}, r"walker 'w': position"),
])
def test_a_bad_walker_key_is_refused_naming_it(change, says):
    data = walker_net(0.0)
    data["walkers"]["w"].update(change)
    with pytest.raises(NetworkError, match=says):
        from_dict(data, name="w.toml")


def test_a_walker_is_refused_where_it_cannot_stand_or_is_named_twice():
    data = walker_net(0.0)
    data["water"]["depth"] = 0.5
    with pytest.raises(NetworkError, match=r"walker 'w'.*seabed there is at z = -0\.50 m"):
        from_dict(data)
    data = walker_net(0.0)
    data["bodies"] = {"w": {"kind": "fixed", "position": [0.0, 0.0, -5.0]}}
    with pytest.raises(NetworkError, match=r"walkers: w also named as a body"):
        from_dict(data)
    data = walker_net(0.0)
    data["points"]["tow"].update(body="crab", position=[0.0, 0.0, 0.0])
    with pytest.raises(NetworkError, match=r"body 'crab' is not a body, vehicle or walker \(w\)"):
        from_dict(data)


# ------------------------------------------------------------------ the examples

def run_example(tmp_path_factory, name: str, *sets):
    out = tmp_path_factory.mktemp(name) / "res"
    args = ["run", str(EXAMPLES / f"{name}.toml"), "--out", str(out), "--no-plots"]
    for s in sets:
        args += ["--set", s]
    assert cli.main(args) == 0
    return np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)


@pytest.fixture(scope="module")
def clump(tmp_path_factory):
    return run_example(tmp_path_factory, "walker_clump_bridle", "simulation.duration=30")


@pytest.fixture(scope="module")
def cage(tmp_path_factory):
    return run_example(tmp_path_factory, "ship_cage_walker", "simulation.duration=60")


def wet(mass_per_length: float, diameter: float) -> float:
    """Weight in water per metre (N/m)."""
    return (mass_per_length - RHO * math.pi * diameter ** 2 / 4) * G


def test_the_clumps_pendant_carries_its_weight_in_water(clump):
    """At rest in the current under the ship, the pendant pulls the clump with its weight in
    water, (150 - 1025 * 0.0191) g = 1279 N, and holds it against its drag in the current there,
    1/2 rho CdA u^2 with u = 0.3 ((60 + z) / 60)^(1/7) (0.2 m^2, 5.7 N): the magnitude within
    0.1 % (measured 0.04 %: the clump rings on its stiff pendant), the horizontal part's mean
    within 5 % once it has swung into the current (t >= 5 s; measured 1.2 %; each sample within
    20 %, measured 17 %: it still swings on its 4 m pendant, about 4 s a swing, and the pendant's
    own drag is in it; the swing grew from 12 % when the line ends' mass moved into the free
    points, which carried it without its weight before)."""
    t = clump["time_s"]
    late = t >= 1.0  # (the first sample's line forces are those before the first step)
    W = (150.0 - RHO * 0.0191) * G
    u = 0.3 * ((60.0 + clump["pointclump_z_m"][late]) / 60.0) ** (1 / 7)
    drag = 0.5 * RHO * 0.2 * u ** 2
    assert np.allclose(clump["linependant_A_tension_N"][late], np.hypot(W, drag), rtol=1e-3)
    swung = t[late] >= 5.0
    horizontal = clump["linependant_A_horizontal_N"][late][swung]
    assert horizontal.mean() == pytest.approx(drag[swung].mean(), rel=0.05)
    assert np.allclose(horizontal, drag[swung], rtol=0.2)


def test_the_ship_carries_the_lead_the_pendant_and_the_clump(clump):
    """The ship's vertical force is the lead's and the pendant's weight in water (w L), the
    clump's, and the tail's vertical pull at the ring (the run's own, a newton or so): within
    0.2 % (measured 0.01 %)."""
    late = clump["time_s"] >= 1.0
    W = (150.0 - RHO * 0.0191) * G
    want = wet(3.2, 0.035) * 45.0 + wet(1.6, 0.02) * 4.0 + W + clump["linetail_B_vertical_N"][late]
    assert np.allclose(clump["linelead_B_vertical_N"][late], want, rtol=2e-3)


def test_the_clump_walker_walks_away_on_its_slack_tail(clump):
    """The walker covers v (t - v / 2a) at 0.1 m/s (within 5 %, as the walker above) along +x,
    its tail slack (under 60 N at the walker after the first second)."""
    t = clump["time_s"]
    walked = clump["walkercrab_x_m"][-1] - clump["walkercrab_x_m"][0]
    assert walked == pytest.approx(0.1 * (t[-1] - 0.1 / (2 * WALK_ACCEL)), rel=0.05)
    assert clump["linetail_A_tension_N"][t >= 1.0].max() < 60.0


def test_the_cage_hangs_on_the_umbilical_while_the_walker_walks_out(cage):
    """The ship carries the umbilical's and the cage's weights in water and the excursion's vertical
    pull (0.2 %, measured 0.01 %); the cage's winch pays out at 0.15 m/s from 25 m (the deployed
    length within 6 cm of 25 + 0.15 t); the walker walks away from the cage at 0.1 m/s (within 5 %)
    on a slack excursion tether (under 50 N at the walker after the first second)."""
    t = cage["time_s"]
    late = t >= 1.0
    want = wet(3.2, 0.035) * 100.0 + (800.0 - RHO * 0.3) * G + cage["lineexcursion_B_vertical_N"][late]
    assert np.allclose(cage["lineumbilical_B_vertical_N"][late], want, rtol=2e-3)
    assert np.allclose(cage["lineexcursion_deployed_m"], np.minimum(25.0 + 0.15 * t, 40.0), atol=0.06)
    walked = cage["walkercrab_x_m"][-1] - cage["walkercrab_x_m"][0]
    assert walked == pytest.approx(0.1 * (t[-1] - 0.1 / (2 * WALK_ACCEL)), rel=0.05)
    assert cage["lineexcursion_A_tension_N"][late].max() < 50.0


@pytest.mark.parametrize("name", ["walker_clump_bridle", "ship_cage_walker"])
def test_the_walker_examples_survive_the_round_trip(name):
    net = moordyn.load_any(EXAMPLES / f"{name}.toml")
    assert net.walkers and net.current is not None
    assert from_dict(to_dict(net), name=net.name) == net

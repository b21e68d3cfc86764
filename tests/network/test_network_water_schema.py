"""One water schema: a network's TOML takes the current and density as a scenario writes them
(``[water.current]`` of any type, ``[water.density]`` of type constant) besides its own
``current_depths`` table and ``rho``. Checked against the profiles' formulas written out here,
against the scenario's own water column for the same table, and run against run."""

import math

import numpy as np
import pytest

from mjtether.network import NetworkError, from_dict, to_dict
from mjtether.network import run as nr
from mjtether.scenario import load_scenario
from mjtether.scenario.scene import water_from

DEPTH = 80.0
DEPTHS = np.array([0.0, 5.0, 17.5, 40.0, 63.0, 80.0])  # m below the surface, where the current is compared


def tree(water: dict, duration: float = 4.0) -> dict:
    """A hanging line with a clump in the current, from a ship's coupled point."""
    return {"water": {"depth": DEPTH, **water}, "simulation": {"duration": duration},
            "line_types": {"rope": {"diameter": 0.03, "mass_per_length": 2.0, "EA": 1e7}},
            "points": {"ship": {"kind": "coupled", "position": [0.0, 0.0, 0.0]},
                       "clump": {"kind": "free", "position": [0.0, 0.0, -40.0], "mass": 50.0, "volume": 0.01,
                                 "cd_area": 0.3}},
            "lines": [{"name": "hang", "type": "rope", "a": "clump", "b": "ship", "length": 40.0, "segments": 10}]}


def velocity(net, depths=DEPTHS) -> np.ndarray:
    return nr.water_of(net).current(-np.asarray(depths))


def towards(speed, heading_deg) -> np.ndarray:
    """Velocities (m/s, world) of ``speed`` (per depth) towards ``heading_deg``."""
    h = math.radians(heading_deg)
    return np.stack([speed * math.cos(h), speed * math.sin(h), np.zeros_like(speed)], axis=-1)


d = DEPTHS
FORMULAS = [  # ([water.current], its velocity at DEPTHS from the profile's formula)
    ({"type": "constant", "speed": 0.4, "heading_deg": 30.0}, towards(np.full(d.shape, 0.4), 30.0)),
    ({"type": "linear", "surface_speed": 0.8, "bottom_speed": 0.2, "bottom_depth": 50.0, "heading_deg": -45.0},
     towards(0.8 + (0.2 - 0.8) * np.minimum(d / 50.0, 1.0), -45.0)),  # (constant below bottom_depth)
    ({"type": "exponential", "surface_speed": 1.2, "decay_depth": 15.0, "heading_deg": 90.0},
     towards(1.2 * np.exp(-d / 15.0), 90.0)),
    ({"type": "power", "surface_speed": 0.6, "exponent": 1 / 7, "heading_deg": 180.0},
     towards(0.6 * ((DEPTH - d) / DEPTH) ** (1 / 7), 180.0)),  # (zero at the seabed, the network's depth)
    ({"type": "table", "depths": [0.0, 30.0, 80.0], "speeds": [0.5, 0.3, 0.1], "headings_deg": [0.0, 90.0, 90.0]},
     # (east and north parts interpolated in depth)
     np.stack([np.interp(d, [0, 30, 80], [0.5, 0.0, 0.0]), np.interp(d, [0, 30, 80], [0.0, 0.3, 0.1]),
               np.zeros_like(d)], axis=-1)),
]


@pytest.mark.parametrize("current, want", FORMULAS, ids=[c["type"] for c, _ in FORMULAS])
def test_a_scenario_current_gives_its_profile_and_the_scenarios_own(current, want):
    """Each type of ``[water.current]`` gives the velocity its formula gives at six depths, and the
    one the same table gives in a scenario of that depth: within 1e-12 m/s (rounding)."""
    net = from_dict(tree({"current": current}))
    assert np.allclose(velocity(net), want, rtol=0, atol=1e-12)
    sc = load_scenario(data={"water": {"depth": DEPTH, "current": current}})
    assert np.allclose(water_from(sc).current(-DEPTHS), want, rtol=0, atol=1e-12)


def test_the_two_spellings_of_a_current_table_run_alike():
    """The same table written as ``[water.current]`` (type table) and as the network's
    ``current_depths``/``current_speeds``/``current_headings_deg`` gives the same velocity at six
    depths (against the interpolation written here, 1e-12 m/s) and the same run, row for row."""
    table = {"depths": [0.0, 30.0, 80.0], "speeds": [0.5, 0.3, 0.1], "headings_deg": [0.0, 90.0, 90.0]}
    scenario_way = from_dict(tree({"current": {"type": "table", **table}}))
    network_way = from_dict(tree({"current_depths": table["depths"], "current_speeds": table["speeds"],
                                  "current_headings_deg": table["headings_deg"]}))
    want = FORMULAS[-1][1]
    assert np.allclose(velocity(scenario_way), want, atol=1e-12) and np.allclose(velocity(network_way), want,
                                                                                 atol=1e-12)
    rows = []
    for net in (scenario_way, network_way):
        r, table_ = nr.simulate(net)
        r.sim.close()
        rows.append(table_)
    assert rows[0].shape == rows[1].shape and np.array_equal(rows[0], rows[1])
    cols = nr.columns(network_way)
    assert abs(rows[0][-1, cols.index("pointclump_x_m")]) > 0.01  # (the current did push the clump)


def test_a_scenario_density_is_the_networks_rho():
    """``[water.density]`` of type constant is ``water.rho``: the same network."""
    assert from_dict(tree({"density": {"type": "constant", "rho": 1010.0}})) == from_dict(tree({"rho": 1010.0}))
    assert from_dict(tree({"density": {"rho": 1010.0}})).rho == 1010.0


@pytest.mark.parametrize("water, says", [
    ({"current": {"type": "constant", "speed": 11.0}}, r"water\.current\.speed.*\[0, 10\]"),
    ({"current": {"type": "constant", "sped": 1.0}}, r"water\.current\.sped.*speed"),
    ({"current": {"type": "swirl"}}, r"water\.current\.type"),
    ({"current": {"type": "table", "depths": [0.0, 10.0], "speeds": [0.1]}}, r"water\.current\.speeds"),
    ({"current": {"type": "constant", "speed": 0.2}, "current_depths": [0.0], "current_speeds": [0.1],
      "current_headings_deg": [0.0]}, r"not both"),
    ({"current": 0.3}, r"water\.current must be a table"),
    ({"density": {"type": "linear"}}, r"water\.density\.type.*constant"),
    ({"density": {"rho": 1010.0}, "rho": 1000.0}, r"not both"),
    ({"density": {"rho": 1300.0}}, r"water\.density\.rho.*\[900, 1100\]"),
])
def test_a_bad_water_table_is_refused_naming_its_key(water, says):
    with pytest.raises(NetworkError, match=says):
        from_dict(tree(water), name="w.toml")


def test_a_scenario_current_survives_the_round_trip():
    """``to_dict`` keeps ``[water.current]`` as a table (``from_dict(to_dict(net)) == net``), and
    takes knots as a scenario does (1 kn = 1852/3600 m/s)."""
    net = from_dict(tree({"current": {"type": "power", "surface_speed_kn": 1.0, "exponent": 0.2}}))
    assert net.current.surface_speed == pytest.approx(1852 / 3600, rel=1e-15)
    assert from_dict(to_dict(net)) == net
    assert to_dict(net)["water"]["current"]["type"] == "power"

"""examples/networks/rov_cage_excursion.toml, a tethered-robot network: a ship holds a cage 100 m
down on an umbilical; the cage's winch pays an excursion tether out to a BlueROV2 Heavy that
flies out to hold station 30 m away, in a current. Checked against what does not come from the
run: the weights in water of the umbilical and the cage (closed form), the cable's own node
geometry against the winch's deployed length, and the station the ROV was given."""

import math
from pathlib import Path

import numpy as np
import pytest

from mjtether import cli
from mjtether.io import moordyn

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "networks" / "rov_cage_excursion.toml"


@pytest.fixture(scope="module")
def rows(tmp_path_factory):
    out = tmp_path_factory.mktemp("rov") / "res"
    assert cli.main(["run", str(EXAMPLE), "--set", "simulation.duration=200", "--out", str(out), "--no-plots"]) == 0
    return np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)


def test_the_ship_carries_the_umbilical_and_the_cage_in_water(rows):
    """Once the ROV holds station on a slack excursion tether (t >= 160 s), the ship's vertical
    force is the umbilical's wet weight w L plus the cage's (m - rho V) g plus the excursion
    tether's vertical pull on the cage (the run's own output, a few newtons): within 0.2 %
    (measured 0.02 %; the rest is the umbilical's stretch under the current's drag)."""
    g, rho = 9.80665, 1025.0
    w_umb = (3.2 - rho * math.pi * 0.035 ** 2 / 4) * g * 100.0
    cage = (800.0 - rho * 0.3) * g
    late = rows["time_s"] >= 160.0
    want = w_umb + cage + rows["lineexcursion_B_vertical_N"][late]
    assert np.abs(rows["lineumbilical_B_vertical_N"][late] - want).max() <= 2e-3 * want.min()


def test_the_cage_winch_pays_the_excursion_tether_out(rows):
    """The deployed length grows at 0.1 m/s from 15 m to 40 m; the tether the nodes draw (their
    polyline, stretched) is that long within 1 % while the ROV pulls it taut (t < 120 s)."""
    t = rows["time_s"]
    assert np.allclose(rows["lineexcursion_deployed_m"], np.minimum(15.0 + 0.1 * t, 40.0), atol=0.06)
    taut = t < 120.0
    assert np.allclose(rows["lineexcursion_length_m"][taut], rows["lineexcursion_deployed_m"][taut], rtol=0.01)


def test_the_rov_flies_out_and_holds_its_station(rows):
    """The BlueROV2 starts 12 m from the cage, is held back by the short tether (it pulls it with
    about its surge thrust), and once the tether is long enough holds its station (-30, 0) at
    100 m depth within 1 m and 0.2 m (t >= 160 s)."""
    t = rows["time_s"]
    early = (t > 10.0) & (t < 100.0)
    assert rows["lineexcursion_A_tension_N"][early].min() > 50.0  # (pulling against the short tether)
    late = t >= 160.0
    off = np.hypot(rows["vehiclerov_x_m"][late] + 30.0, rows["vehiclerov_y_m"][late])
    assert off.max() <= 1.0 and np.abs(rows["vehiclerov_z_m"][late] + 100.0).max() <= 0.2


def test_a_network_with_a_vehicle_or_a_winch_is_not_written_as_moordyn():
    net = moordyn.load_any(EXAMPLE)
    with pytest.raises(ValueError, match="vehicles flown by an autopilot"):
        moordyn.write_network(net)

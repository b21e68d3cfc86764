"""The seabed from a bathymetry grid (``water.bathymetry``): a uniform slope given as a grid
against the same slope given as ``water.seabed_slope_deg`` (the plane mjtether had before, its
own contact and friction); the shipped uneven example from the CLI; bad grids refused naming
the key."""

import math

import numpy as np
import pytest

from mjtether import cli
from mjtether.scenario import ScenarioError, load_scenario

ANCHOR = """
[simulation]
duration = 10.0
timestep = 0.00625
[water]
depth = 120.0
{seabed}
[water.current]
type = "exponential"
surface_speed_kn = 1.0
decay_depth = 15.0
[tether]
length = 200.0
segments = 80
diameter = 0.025
density = 2500.0
EA = 5.0e6
seabed_friction = 0.5
[ship]
mode = "fixed"
position = [0.0, 0.0]
[robot]
type = "anchor"
position = [100.0, 0.0, -102.367]
"""
SLOPE_DEG = 10.0


def _slope_grid(path, spacing=2.0):
    x = np.arange(-20.0, 150.0 + 1e-9, spacing)
    y = np.arange(-40.0, 40.0 + 1e-9, spacing)
    X, _ = np.meshgrid(x, y)
    np.savetxt(path, 120.0 - math.tan(math.radians(SLOPE_DEG)) * X, delimiter=",", fmt="%.9f")


def _run(tmp_path, name, seabed):
    (tmp_path / f"{name}.toml").write_text(ANCHOR.format(seabed=seabed))
    out = tmp_path / name
    assert cli.main(["run", str(tmp_path / f"{name}.toml"), "--out", str(out), "--no-plots"]) == 0
    return np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)


def test_a_uniform_slope_given_as_a_grid_gives_the_slope_s_tensions(tmp_path):
    """200 m of umbilical from a ship to an anchor on a 10 deg slope, 77 m of it laid with
    friction 0.5, in a current: once as ``seabed_slope_deg = 10``, once as a 2 m depth grid of
    the same plane (a MuJoCo height field, the friction along each node's tangent plane). Both
    start from the same steady state and settle onto the slope; the tensions over the last 5 s
    within 0.5 % of the fairlead tension (measured: fairlead 1e-7, anchor 0.04 % of it, 0.19 %
    of the anchor's own 168 N; the height field's contacts fall per triangle of the grid, the
    plane's per node, and share the anchor node's weight between anchor and seabed a little
    differently)."""
    _slope_grid(tmp_path / "slope.csv")
    plane = _run(tmp_path, "plane", f"seabed_slope_deg = {SLOPE_DEG}")
    grid = _run(tmp_path, "grid", 'bathymetry = "slope.csv"\nbathymetry_spacing_m = 2.0\n'
                                  "bathymetry_origin_m = [-20.0, -40.0]")
    late = plane["time_s"] >= 5.0
    fair = plane["ship_tension_N"][late].mean()
    for key in ("ship_tension_N", "tow_tension_N"):
        assert abs(grid[key][late].mean() - plane[key][late].mean()) <= 0.005 * fair, key
    assert plane["length_on_seabed_m"][late].mean() > 50.0  # (the friction case: a long laid part)


def test_the_uneven_seabed_example_runs_from_the_cli(tmp_path):
    """examples/walker_bathymetry.toml: the walker stands on the grid (its torso 0.8 to 1.3 m over
    the ground under it) and climbs."""
    from pathlib import Path

    from mjtether.physics import bathymetry
    example = Path(__file__).resolve().parents[2] / "examples" / "walker_bathymetry.toml"
    out = tmp_path / "res"
    assert cli.main(["run", str(example), "--set", "simulation.duration=10", "--out", str(out), "--no-plots"]) == 0
    rows = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    grid = bathymetry.load(example.with_name("seabed_patch.csv"), 1.0, (-10.0, -30.0))
    above = rows["robot_z_m"] - grid.height(rows["robot_x_m"], rows["robot_y_m"])
    assert 0.8 <= above.min() and above.max() <= 1.3, (above.min(), above.max())
    assert rows["robot_x_m"][-1] - rows["robot_x_m"][0] > 1.0


@pytest.mark.parametrize("water, key, words", [
    ('bathymetry = "nowhere.csv"', "water.bathymetry", "no such file"),
    ('bathymetry = "grid.csv"', "water.bathymetry", "needs water.bathymetry_spacing_m"),
    ('bathymetry = "grid.csv"\nbathymetry_spacing_m = 2.0\nseabed_slope_deg = 5.0', "water.seabed_slope_deg",
     "must be 0 with a bathymetry grid"),
    ('bathymetry = "grid.csv"\nbathymetry_spacing_m = 2.0\nbathymetry_origin_m = [500.0, 0.0]', "robot.position",
     "outside the bathymetry grid"),
])
def test_a_bad_bathymetry_is_refused_naming_the_key(tmp_path, water, key, words):
    np.savetxt(tmp_path / "grid.csv", np.full((41, 86), 110.0), delimiter=",")
    (tmp_path / "s.toml").write_text(ANCHOR.format(seabed=water))
    with pytest.raises(ScenarioError) as err:
        load_scenario(tmp_path / "s.toml")
    assert err.value.key == key and words in str(err.value), str(err.value)

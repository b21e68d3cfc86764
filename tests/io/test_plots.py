"""Result plots (mjtether.io.results): titles, SI units, and a side view that draws the seabed, the
water surface, the ship and the robot where the scenario and the run put them."""

import math
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.text import Text  # noqa: E402

from mjtether.io import lines_npz, results  # noqa: E402
from mjtether.scenario.runner import RECORD_FIELDS, run  # noqa: E402
from mjtether.scenario import load_scenario  # noqa: E402

DEPTH = 100.0
SLOPE_DEG = 5.0

SLOPED = f"""
[simulation]
duration = 1.0
output_interval = 0.5
[robot]
type = "anchor"
position = [40.0, 0.0, -96.0]
[water]
depth = {DEPTH}
seabed_slope_deg = {SLOPE_DEG}
seabed_slope_heading_deg = 0.0
[tether]
length = 108.0
segments = 10
"""

UNIT = re.compile(r"\((m|s|N|kN|m/s|N m|kg|Pa|deg|\N{DEGREE SIGN})\)\s*$")


@pytest.fixture(scope="module")
def sloped_run():
    sc = load_scenario(text=SLOPED)
    rows, history, info = run(sc)
    return sc, rows, history, info


@pytest.fixture(scope="module")
def figures(sloped_run):
    sc, rows, history, _ = sloped_run
    figs = {"tension": results.tension_figure(rows),
            "line_tension": results.line_tension_figure(lines_npz.tether_arrays(rows[:, 0], history), sc),
            "profile": results.profile_figure(rows, history["nodes"], sc),
            "track": results.track_figure(rows, sc)}
    yield figs
    for f in figs.values():
        plt.close(f)


def by_gid(fig, gid):
    found = [a for a in fig.findobj(lambda o: o.get_gid() == gid)]
    assert len(found) == 1, f"{gid}: {len(found)} artists"
    return found[0]


def col(rows, name):
    return rows[:, [n for n, _, _ in RECORD_FIELDS].index(name)]


def test_every_figure_and_axes_titled_every_label_with_si_unit(figures):
    for name, fig in figures.items():
        assert fig.get_suptitle().strip(), name
        for ax in fig.axes:
            assert ax.get_title().strip(), name
            for label in (ax.get_xlabel(), ax.get_ylabel()):
                assert UNIT.search(label), f"{name}: {label!r} has no SI unit in parentheses"


def test_no_radians_anywhere(figures):
    for name, fig in figures.items():
        texts = [t.get_text() for t in fig.findobj(Text)]
        assert texts
        for t in texts:
            assert "rad" not in t.lower(), f"{name}: {t!r}"


def test_side_view_seabed_has_the_scenario_slope(figures, sloped_run):
    sc = sloped_run[0]
    x, z = (np.asarray(v, dtype=float) for v in by_gid(figures["profile"], "seabed").get_data())
    assert len(x) > 2
    slope, intercept = np.polyfit(x, z, 1)
    # heading 0: the seabed rises along +x at tan(5 deg), through z = -depth at x = 0
    assert slope == pytest.approx(math.tan(math.radians(SLOPE_DEG)), abs=1e-6)
    assert intercept == pytest.approx(-DEPTH, abs=1e-6)
    assert np.max(np.abs(z - (slope * x + intercept))) < 1e-9  # a straight line, not a flat one
    # it covers the cable's x range
    nodes = sloped_run[2]["nodes"]
    assert x.min() <= nodes[..., 0].min() and x.max() >= nodes[..., 0].max()
    assert sc.water.seabed_slope_deg == SLOPE_DEG


def test_ship_and_robot_markers_at_the_cable_ends(figures, sloped_run):
    nodes = sloped_run[2]["nodes"]
    ship = np.asarray(by_gid(figures["profile"], "ship").get_data(), dtype=float).ravel()
    robot = np.asarray(by_gid(figures["profile"], "robot").get_data(), dtype=float).ravel()
    assert np.max(np.abs(ship - nodes[-1, 0, [0, 2]])) < 1e-9
    assert np.max(np.abs(robot - nodes[-1, -1, [0, 2]])) < 1e-9
    # the ship is at the surface (fairlead_z = 0), the robot at its anchor near (40, -96.5)
    assert ship[1] == pytest.approx(0.0, abs=1e-6)
    assert robot[0] == pytest.approx(40.0, abs=0.5)


def test_side_view_legend_and_surface(figures):
    side = figures["profile"].axes[0]
    legend = [t.get_text() for t in side.get_legend().get_texts()]
    for word in ("seabed", "water surface", "ship", "robot"):
        assert any(word in t for t in legend), (word, legend)
    surface = by_gid(figures["profile"], "surface")
    assert np.allclose(surface.get_ydata(), 0.0)


def test_tracks_start_markers_and_upslope_arrow(figures, sloped_run):
    rows = sloped_run[1]
    for name in ("profile", "track"):
        fig = figures[name]
        for who in ("ship", "robot"):
            start = np.asarray(by_gid(fig, f"{who}_start").get_data(), dtype=float).ravel()
            assert np.allclose(start, [col(rows, f"{who}_x")[0], col(rows, f"{who}_y")[0]], atol=1e-12)
            x, y = by_gid(fig, f"{who}_track").get_data()
            assert len(x) == len(rows)
        arrow = by_gid(fig, "upslope")
        assert "upslope" in arrow.get_text()
        # the arrow runs from its label to its tip: along +x (heading 0), in points
        dx, dy = -np.asarray(arrow.xyann, dtype=float)
        assert math.degrees(math.atan2(dy, dx)) == pytest.approx(0.0, abs=1e-9)


def test_tension_curves_kept(figures, sloped_run):
    rows = sloped_run[1]
    top, bottom = figures["tension"].axes
    labels = [line.get_label() for line in top.get_lines()]
    assert labels == ["ship end", "tow point"]
    assert np.array_equal(top.get_lines()[0].get_ydata(), col(rows, "ship_tension"))
    assert np.array_equal(top.get_lines()[1].get_ydata(), col(rows, "tow_tension"))
    assert np.array_equal(bottom.get_lines()[0].get_ydata(), col(rows, "deployed_length"))


def synthetic(heading_deg, slope_deg=8.0, depth=150.0):
    """A scenario (not run) and hand-made rows and nodes: a straight cable from the ship at
    (0, 10, 0) to (60, 25, z) m, a level seabed or one rising towards ``heading_deg``."""
    sc = load_scenario(text=f"""
[robot]
type = "anchor"
position = [60.0, 25.0, -100.0]
[ship]
position = [0.0, 10.0]
[water]
depth = {depth}
seabed_slope_deg = {slope_deg}
seabed_slope_heading_deg = {heading_deg}
""")
    n = 3
    rows = np.zeros((n, len(RECORD_FIELDS)))
    names = [f for f, _, _ in RECORD_FIELDS]
    rows[:, names.index("time")] = [0.0, 1.0, 2.0]
    rows[:, names.index("ship_y")] = 10.0
    rows[:, names.index("robot_x")] = [60.0, 61.0, 62.0]
    rows[:, names.index("robot_y")] = 25.0
    s = np.linspace(0.0, 1.0, 9)[:, None]
    cable = (1 - s) * [0.0, 10.0, 0.0] + s * [60.0, 25.0, -100.0]
    nodes = np.repeat(cable[None], n, axis=0)
    return sc, rows, nodes


@pytest.mark.parametrize("heading_deg", [30.0, 90.0, -135.0])
def test_side_view_seabed_section_at_the_robot_y(heading_deg):
    slope_deg, depth = 8.0, 150.0
    sc, rows, nodes = synthetic(heading_deg, slope_deg, depth)
    fig = results.profile_figure(rows, nodes, sc)
    try:
        x, z = (np.asarray(v, dtype=float) for v in by_gid(fig, "seabed").get_data())
        k, c = np.polyfit(x, z, 1)
        t, h = math.tan(math.radians(slope_deg)), math.radians(heading_deg)
        # z = -depth + tan(slope) (x cos h + y sin h), at the robot's y = 25 m
        assert k == pytest.approx(t * math.cos(h), abs=1e-6)
        assert c == pytest.approx(-depth + t * math.sin(h) * 25.0, abs=1e-6)
        arrow = by_gid(fig, "upslope")
        dx, dy = -np.asarray(arrow.xyann, dtype=float)
        assert math.atan2(dy, dx) == pytest.approx(math.atan2(math.sin(h), math.cos(h)), abs=1e-9)
    finally:
        plt.close(fig)


def test_level_seabed_flat_and_no_upslope_arrow():
    sc, rows, nodes = synthetic(0.0, slope_deg=0.0, depth=150.0)
    for fig in (results.profile_figure(rows, nodes, sc), results.track_figure(rows, sc)):
        try:
            assert not fig.findobj(lambda o: o.get_gid() == "upslope")
            if fig.findobj(lambda o: o.get_gid() == "seabed"):
                _, z = by_gid(fig, "seabed").get_data()
                assert np.allclose(z, -150.0, atol=1e-12)
        finally:
            plt.close(fig)


def test_profile_with_first_sample_only(sloped_run):
    """``runner.run(keep_nodes=False)`` keeps the nodes of the first sample only."""
    sc, rows, history, _ = sloped_run
    fig = results.profile_figure(rows, history["nodes"][:1], sc)
    try:
        ship = np.asarray(by_gid(fig, "ship").get_data(), dtype=float).ravel()
        assert np.max(np.abs(ship - history["nodes"][0, 0, [0, 2]])) < 1e-9
    finally:
        plt.close(fig)


@pytest.mark.parametrize("plots", [True, False])
def test_write_folder_has_the_three_pngs(tmp_path, sloped_run, plots):
    """With a tether: tension.png, line_tension.png and profile.png (no track.png: the profile's
    top view draws the same tracks); with ``plots=False`` none."""
    sc, rows, history, info = sloped_run
    before = set(plt.get_fignums())
    out = results.write(tmp_path / "out", sc, rows, history, info, plots=plots)
    pngs = {"tension.png", "line_tension.png", "profile.png"}
    present = {p.name for p in out.iterdir() if p.suffix == ".png"}
    if plots:
        assert present == pngs
        for name in pngs:
            assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    else:
        assert present == set()
    assert set(plt.get_fignums()) == before  # write closed every figure it opened

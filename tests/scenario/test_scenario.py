"""Scenario files, the runner and `mjtether run` / `mjtether solve`."""

import functools
import json
from pathlib import Path

import numpy as np
import pytest

from mjtether import cli
from mjtether.io import results
from mjtether.quasistatic import khan2023, steady_state
from mjtether.scenario.runner import ScenarioRun, run, tether_from, water_from
from mjtether.io.reference import scenarios_md
from mjtether.scenario import ScenarioError, load_scenario

from helpers import small



# ------------------------------------------------------------------ bad scenario files

BAD = {
    "unknown key": ("[tether]\nlenght = 100.0\n", "unknown key tether.lenght"),
    "negative depth": ("[water]\ndepth = -5.0\n", "water.depth = -5.0: must be a number in [0.1, 12000] m"),
    "zero segments": ("[tether]\nsegments = 0\n", "tether.segments = 0: must be an integer in [4, 5000]"),
    "unsorted current table": ('[water.current]\ntype = "table"\ndepths = [0.0, 50.0, 20.0]\n'
                               'speeds = [1.0, 0.5, 0.2]\n', "water.current.depths = [0.0, 50.0, 20.0]: must be strictly increasing"),
    "robot below the seabed": ("[water]\ndepth = 50.0\n", "is below the seabed"),
    "wrong type": ('[simulation]\nduration = "long"\n', "simulation.duration = 'long': must be a number"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_bad_scenario_files_exit_nonzero_with_one_clear_error(case, tmp_path, capsys):
    body, message = BAD[case]
    text = body + ("" if "[robot]" in body else '[robot]\ntype = "anchor"\nposition = [10.0, 0.0, -80.0]\n')
    f = tmp_path / "bad.toml"
    f.write_text(text)
    out = tmp_path / "res"
    assert cli.main(["run", str(f), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(f) in err[0] and message in err[0], err
    assert not out.exists()


def test_knots_are_converted_and_unknown_sections_refused():
    sc = load_scenario(text='[water.current]\ntype = "constant"\nspeed_kn = 2.0\n[robot]\ntype = "anchor"\n'
                            'position = [1.0, 0, -10.0]')
    assert sc.water.current.speed == pytest.approx(2 * 0.514444)
    with pytest.raises(ScenarioError, match="unknown key boat"):
        load_scenario(text="[boat]\nx = 1\n")
    with pytest.raises(ScenarioError, match="given twice"):
        load_scenario(text="[water.current]\nspeed = 1.0\nspeed_kn = 2.0\n[robot]\ntype = 'anchor'\n"
                           "position = [1.0, 0, -10.0]")


def test_scenario_reference_is_current():
    """docs/scenarios.md is generated from the typed scenario (python scripts/make_scenario_docs.py):
    the file in the repository must be exactly what the code generates now."""
    with open("docs/scenarios.md") as fh:
        assert fh.read() == scenarios_md(), "docs/scenarios.md is stale: run python scripts/make_scenario_docs.py"


# ------------------------------------------------------------------ physics through the runner

def test_static_scenario_settles_to_the_quasi_static_answer():
    """Both ends fixed in a depth-varying current (0.8 m/s at the surface, decaying over 20 m,
    along +x). The run is not left at its own start: its cable is put into the steady state for
    the current reversed (a mirror-image bow, ship-end force 20 % of the tension away from the
    answer and nodes 1.7 m off, more than the node tolerance) and let go. After 30 s the run's end
    forces are within 2 % of an independent steady_state solve for the real current, and its
    nodes within 1 % of the length (the tolerances of the dynamic cross-checks in
    test_quasistatic; measured: 0.06 % and 0.04 m)."""
    sc = load_scenario(text=small(30.0))
    water, tether = water_from(sc), tether_from(sc)
    ss = steady_state(tether, water, [0, 0, 0], [60.0, 0.0, -80.0])
    reversed_current = water_from(load_scenario(text=small(30.0), overrides=["water.current.heading_deg=180.0"]))
    wrong = steady_state(tether, reversed_current, [0, 0, 0], [60.0, 0.0, -80.0])
    assert np.linalg.norm(wrong.top_force - ss.top_force) > 0.1 * ss.top_tension  # a start far from the answer
    assert np.abs(wrong.nodes - ss.nodes).max() > 0.01 * tether.length
    r = ScenarioRun(sc)
    try:
        r.bt.set_state(r.sim.data, nodes=wrong.nodes, velocity=np.zeros_like(wrong.nodes))
        r.sim.forward()
        for _ in range(round(30.0 / r.sim.timestep)):
            r.step()
        f_ship, f_tow = r.named.ship_force, r.named.tow_force
        nodes = r.bt.nodes(r.sim.data)
    finally:
        r.close()
    assert np.linalg.norm(f_ship - ss.top_force) <= 0.02 * ss.top_tension
    assert np.linalg.norm(f_tow - ss.bottom_force) <= 0.02 * ss.tow_tension
    assert np.abs(nodes - ss.nodes).max() <= 0.01 * tether.length


SHIP_AWAY = """
[ship]
mode = "waypoints"
waypoints = [[-40.0, 0.0]]
speed = 0.5
"""


def test_tension_rises_as_the_ship_moves_away_with_a_fixed_length():
    """The ship moves 20 m away at 0.5 m/s: the ship-end tension rises (21 % here) to the
    quasi-static tension at the ship's final position, within 2 % (the ship is still moving)."""
    sc = load_scenario(text=small(40.0, SHIP_AWAY))
    rows, _, _ = run(sc)
    t = rows[:, 1]
    assert np.all(np.diff(t[4:]) > -0.01 * t[0])  # rising, up to noise
    final = steady_state(tether_from(sc), water_from(sc), [rows[-1, 17], rows[-1, 18], 0.0], [60.0, 0.0, -80.0])
    assert final.top_tension > 1.15 * t[0]
    assert t[-1] == pytest.approx(final.top_tension, rel=0.02)


def test_tension_band_mode_holds_the_band():
    """The same manoeuvre with the winch regulating the ship-end tension into [1.05, 1.25] times
    its initial value: after the first 5 s every sample is inside the band (2 % slack for the
    regulator's ramp and the cable's response)."""
    t0 = run(load_scenario(text=small(0.5)))[0][0, 1]
    lo, hi = 1.05 * t0, 1.25 * t0
    winch = f'\n[winch]\nmode = "tension"\nband = [{lo}, {hi}]\nmax_rate = 1.0\nmax_length = 300.0\n'
    rows, _, _ = run(load_scenario(text=small(40.0, SHIP_AWAY + winch)))
    t = rows[rows[:, 0] >= 5.0, 1]
    assert t.min() >= 0.98 * lo and t.max() <= 1.02 * hi
    # it reels in (a little) to bring the tension up into the band, then pays out as the ship
    # moves away
    assert rows[:, 15].min() < 120.0 and rows[-1, 15] > rows[:, 15].min() + 1.0 and rows[-1, 16] > 0


# ------------------------------------------------------------------ the command line

def test_run_writes_a_complete_results_folder(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text(small(2.0))
    out = tmp_path / "res"
    assert cli.main(["run", str(f), "--out", str(out)]) == 0
    names = {p.name for p in out.iterdir()}
    assert {"timeseries.csv", "lines.npz", "summary.json", "tension.png", "profile.png", "line_tension.png"} <= names
    header = (out / "timeseries.csv").read_text().splitlines()[0].split(",")
    # a walker run: the tangle monitor's columns about a vehicle are left out, the cable's own kept
    assert header == results.column_names(vehicle=False)
    assert "cable_self_clearance_m" in header and "cable_clearance_m" not in header
    data = np.genfromtxt(out / "timeseries.csv", delimiter=",", skip_header=1)
    assert data.shape == (5, len(header)) and np.all(np.isfinite(data))
    npz = np.load(out / "lines.npz")
    assert npz["linetether_nodes"].shape == (5, 31, 3)
    s = json.loads((out / "summary.json").read_text())
    assert s["scenario"]["tether"]["segments"] == 30 and s["run"]["realtime_factor"] > 0
    assert all((out / p).stat().st_size > 1000 for p in ("tension.png", "profile.png", "line_tension.png"))


def test_failed_run_writes_nothing(tmp_path, capsys):
    """Above the rated load the run stops, exits 1 and leaves no results folder."""
    f = tmp_path / "s.toml"
    f.write_text(small(5.0).replace("EA = 5.0e6", "EA = 5.0e6\nrated_load = 100.0"))
    out = tmp_path / "res"
    assert cli.main(["run", str(f), "--out", str(out)]) == 1
    assert "rated load" in capsys.readouterr().err
    assert not out.exists() and not list(tmp_path.glob(".res*"))


def test_solve_prints_the_steady_state(tmp_path, capsys):
    """``mjtether solve`` on the small scenario in still water prints the tensions of the elastic
    catenary, solved here with SciPy from the scenario's numbers (120 m of 30 mm cable, 2500
    kg/m^3, EA = 5 MN, from the ship to an anchor 60 m off and 80 m down; the whole line hangs
    clear of the seabed): ship end and tow end to 0.5 % (the solver's 30-element lumped line
    differs from the continuum by O(1/N^2), about 0.1 %; measured 0.01 %)."""
    import math
    import re

    from scipy.optimize import fsolve

    f = tmp_path / "s.toml"
    f.write_text(small().replace('[water.current]\ntype = "exponential"\nsurface_speed = 0.8\ndecay_depth = 20.0\n', ""))
    assert "current" not in f.read_text()
    assert cli.main(["solve", str(f)]) == 0
    text = capsys.readouterr().out
    printed = [float(x) for x in re.findall(r"\(tension ([0-9.]+) N\)", text)]
    assert len(printed) == 2, text
    L, EA, w = 120.0, 5.0e6, (2500.0 - 1025.0) * math.pi * 0.03**2 / 4 * 9.81
    X, Z = 60.0, 80.0  # the anchor, from the ship

    def ends(p):  # H and the vertical force V at the ship; the elastic catenary's span and drop
        H, V = p
        Va = V - w * L
        return [H / w * (math.asinh(V / H) - math.asinh(Va / H)) + H * L / EA - X,
                H / w * (math.hypot(1.0, V / H) - math.hypot(1.0, Va / H)) + (V * L - w * L * L / 2) / EA - Z]

    H, V = fsolve(ends, [0.25 * w * L, 0.8 * w * L], xtol=1e-13)
    assert V - w * L < 0.0  # the tow end pulls down too: no seabed contact at the anchor
    assert printed[0] == pytest.approx(math.hypot(H, V), rel=0.005)
    assert printed[1] == pytest.approx(math.hypot(H, V - w * L), rel=0.005)


def test_solve_prints_the_paper_method_for_a_walker(tmp_path, capsys):
    """For a walker the paper's method is run at its first commanded speed, to its depth."""
    f = tmp_path / "w.toml"
    f.write_text(WALK.format(length=122.0, winch="follow"))
    assert cli.main(["solve", str(f)]) == 0
    text = capsys.readouterr().out
    sc = load_scenario(f)
    r = ScenarioRun(sc)
    try:
        t = r.tether_spec
        k = khan2023(diameter=t.diameter, cable_density=2500.0, water=r.water, robot_speed=0.5,
                     depth=-r.robot_position[2], segments=40, cd_normal=t.cd_normal, cd_axial=t.cd_tangential,
                     gravity=9.81, variant="consistent")
    finally:
        r.close()
    assert f"consistent length to reach it {k.length:.1f} m" in text and "printed" in text


# ------------------------------------------------------------------ the walker on a tether

WALK = """
[simulation]
duration = 40.0
output_interval = 0.5
[water]
depth = 100.0
[tether]
length = {length}
segments = 40
diameter = 0.025
density = 2500.0
EA = 5.0e6
[winch]
mode = "{winch}"
max_length = 400.0
[robot]
type = "walker"
start = [60.0, 0.0]
commands = [[0.0, 0.5, 0.0]]
"""


@functools.lru_cache(maxsize=None)
def _walk(winch: str, extra: str = "") -> np.ndarray:
    text = WALK.format(length=122.0, winch=winch).replace('max_length = 400.0', 'max_length = 400.0' + extra)
    return run(load_scenario(text=text))[0]


def test_slow_payout_slows_the_walker_and_the_tow_force_opposes_it():
    """The walker sets off at 0.5 m/s with the winch paying out at its speed (Eq. 30), and
    again with the winch fixed and only 5 m of slack: the tether then pulls back on the tow
    point (negative body-x force, growing) and the walker covers measurably less ground."""
    out = {winch: _walk(winch) for winch in ("follow", "fixed")}
    dist = {k: r[-1, 19] - r[0, 19] for k, r in out.items()}
    assert dist["fixed"] < 0.9 * dist["follow"]
    assert dist["follow"] == pytest.approx(0.5 * 40.0, rel=0.1)
    tow_x = {k: r[:, 9] for k, r in out.items()}  # tow force, body x (forward)
    assert tow_x["fixed"][-10:].mean() < 2.0 * tow_x["follow"][-10:].mean() < 0.0
    tow = out["fixed"][:, 5]
    assert tow[-1] > 3.0 * tow[4]  # tow-point tension rises as the walker moves away


def test_tension_band_mode_holds_the_band_behind_the_walker():
    """The same walk with the winch regulating the ship-end tension into [0.9, 1.4] times its
    initial value. With the length fixed the tension leaves the band (by more than 50 %); with
    regulation every sample after the first 5 s (the regulator's filter and integral settling) is
    inside it, with 2 % slack. The band is wide because each stride of the walker sends a ripple
    of about +-130 N (one standard deviation) up the cable, which no winch can follow."""
    fixed = _walk("fixed")
    t0 = fixed[0, 1]
    lo, hi = 0.9 * t0, 1.4 * t0
    assert fixed[:, 1].max() > 1.5 * hi
    rows = _walk("tension", f'\nband = [{lo}, {hi}]\nmax_rate = 1.0')
    t = rows[rows[:, 0] >= 5.0, 1]
    assert t.min() >= 0.98 * lo and t.max() <= 1.02 * hi
    # it holds the band by paying out behind the walker (10 m in 40 s seen)
    assert rows[-1, 15] > rows[0, 15] + 5.0 and rows[-1, 16] > 0.2


def test_a_line_type_of_the_library_sets_the_tether():
    """`tether.line_type` fills the cable's properties from mjtether/cable/linetypes.toml (and the
    rated load from its MBL); giving a property as well, with another value, is refused."""
    from mjtether.cable.makeup import load_line_types

    lt = load_line_types()["steel_armoured_umbilical_17mm"]
    sc = load_scenario(text=small(1.0).replace("diameter = 0.03\ndensity = 2500.0\nEA = 5.0e6\n",
                                               'line_type = "steel_armoured_umbilical_17mm"\n'))
    t = tether_from(sc)
    assert (t.diameter, t.mu, t.EA, t.EI, t.cd_normal) == (lt.diameter, lt.mass_per_length, lt.EA, lt.EI, lt.cd_normal)
    assert sc.tether.rated_load == lt.mbl
    with pytest.raises(ScenarioError, match="tether.diameter = 0.03: tether.line_type = 'steel_armoured_umbilical_17mm'"):
        load_scenario(text=small(1.0).replace("EA = 5.0e6\n", 'EA = 5.0e6\nline_type = "steel_armoured_umbilical_17mm"\n'))


EXAMPLE_FILES = sorted((Path(__file__).resolve().parents[2] / "examples").glob("*.toml"))


@pytest.mark.parametrize("path", EXAMPLE_FILES, ids=lambda p: p.stem)
def test_solve_answers_every_shipped_example(path, capsys):
    """`mjtether solve` on each shipped example exits 0 with an answer: the steady state, or what
    there is instead (no tether; nothing deployed at the start); a vehicle is called a vehicle."""
    assert cli.main(["solve", str(path)]) == 0
    out = capsys.readouterr().out
    sc = load_scenario(path)
    if not sc.tether.attached:
        assert out.startswith("no tether")
    elif sc.winch.start_empty:
        assert out.startswith("nothing deployed")
    else:
        assert out.startswith("steady state of")
    if sc.robot.type == "vehicle":
        assert "robot is a vehicle" in out or not sc.tether.attached or sc.winch.start_empty

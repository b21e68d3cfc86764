"""Line make-ups in scenario files: ``[[tether.sections]]``, ``[[tether.point_loads]]`` and
``[[tether.floats]]`` load into a checked scenario, run from the make-up's steady state, and hold
it. The reference answer is the quasi-static solver's, solved here from ``mjtether.cable.makeup``
objects built by hand from the example's numbers (not through the scenario code under test);
the solver itself is checked against catenaries and MoorPy in ``test_steady_sections``.
"""

import re
from pathlib import Path

import numpy as np
import pytest
from helpers import raw_element_forces

import mjtether as mt
from mjtether.cable.makeup import DistributedBuoyancy, LineMakeup, PointLoad, Section
from mjtether.quasistatic import steady_state
from mjtether.scenario.runner import RECORD_FIELDS, ScenarioRun, run
from mjtether.scenario import ScenarioError, load_scenario, to_toml

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "lazy_wave_umbilical.toml"
COL = {name: k for k, (name, _, _) in enumerate(RECORD_FIELDS)}
UMB = "steel_armoured_umbilical_17mm"


def _by_hand(heading_deg: float = 90.0):
    """The example's line, water and ends, written out again from its numbers (the current
    0.3 m/s towards ``heading_deg``)."""
    umb = lambda L, n: Section.from_line_type(UMB, L, n)  # noqa: E731
    line = LineMakeup([umb(120.0, 24), umb(60.0, 12), umb(120.0, 24)],
                      [DistributedBuoyancy(120.0, 180.0, 5.607e-3, mass_per_length=2.8035, cd_area_per_length=0.1),
                       PointLoad(240.0, mass=200.0, volume=0.02, cd_area=0.3)])
    r = float(line.element_diameter[-1]) / 2
    # the dynamic cable's axis rests one radius above the seabed: solve to that plane
    water = mt.WaterColumn(depth=100.0 - r, current=mt.ConstantCurrent(0.3, heading=np.radians(heading_deg)))
    top, bottom = np.array([0.0, 0.0, -2.0]), np.array([200.0, 0.0, -100.0 + r])
    return line, water, top, bottom


def test_example_loads_as_the_make_up_it_describes():
    sc = load_scenario(EXAMPLE)
    t = sc.tether
    assert t.is_makeup and t.length == 300.0 and t.segments == 60  # the sections' sums
    assert [s.length for s in t.sections] == [120.0, 60.0, 120.0]
    assert t.sections[0].EA == 1.88e7  # from the line-type library
    assert t.rated_load == 176800.0  # the sections' smallest MBL, none given
    assert t.point_loads[0].mass == 200.0 and t.floats[0].start == 120.0
    assert load_scenario(text=to_toml(sc)) == sc  # written out and read back


@pytest.mark.parametrize("heading_deg, anchor_tol", [(90.0, 0.02), (180.0, 0.01)])
def test_lazy_wave_scenario_starts_from_and_holds_its_steady_state(heading_deg, anchor_tol):
    """10 s at 5 ms from the steady state, in the example's 0.3 m/s current across the line
    (90 deg) and against it (180 deg). The ship-end force within 2 % of the quasi-static answer
    (the issue's tolerance; the dynamic model carries the same loads on a finite-stiffness
    cable: measured 0.013 % and 0.005 %). The anchor's horizontal pull within 2 % across the
    current (measured 0.17 %; its direction differs by 2.6 deg: the frictionless laid part bows
    in the cross flow, which the straight-laid statics does not) and 1 % along it (measured 0.3 %:
    the laid part's tangential drag, 1.2 N, which the statics leaves out; before the clump's drag
    at the touchdown was carried into the laid line, 4.2 %). The clump on the seabed. And at every
    step of the same 10 s, run again step by step, every deployed element pulls by MuJoCo's own
    constraint force on its row (``efc_force`` < 0: none slack over the float's hump, none
    pushing; the readouts clip at zero and could not show it; measured: the weakest pull at any
    step 337 N across the current and 160 N against it), and the readout's tension is that pull."""
    sc = load_scenario(EXAMPLE, overrides=["simulation.duration=10.0", f"water.current.heading_deg={heading_deg}"])
    line, water, top, bottom = _by_hand(heading_deg)
    ss = steady_state(line, water, top, bottom, seabed=True)
    rows, hist, info = run(sc, keep_nodes=True)
    assert info["initial_state"].startswith("quasi-static steady state")
    late = rows[:, COL["time"]] >= 5.0
    fs = rows[late][:, [COL["ship_force_x"], COL["ship_force_y"], COL["ship_force_z"]]].mean(axis=0)
    fe = rows[late][:, [COL["tow_force_x"], COL["tow_force_y"], COL["tow_force_z"]]].mean(axis=0)
    assert np.linalg.norm(fs - ss.top_force) <= 0.02 * np.linalg.norm(ss.top_force), (fs, ss.top_force)
    assert np.hypot(*fe[:2]) == pytest.approx(np.hypot(*ss.bottom_force[:2]), rel=anchor_tol)
    clump = hist["nodes"][-1, 48]  # node at 240 m: 24 + 12 + 12 elements of 5 m
    assert clump[2] <= -100.0 + 2 * float(line.element_diameter[-1])
    r = ScenarioRun(sc)
    try:
        weakest = np.inf
        for _ in range(round(10.0 / r.sim.timestep)):
            r.step()
            f = raw_element_forces(r.bt, r.sim.data)
            np.testing.assert_array_equal(r.bt.element_tension(r.sim.data), np.maximum(-f, 0.0))
            weakest = min(weakest, float(-f[r.bt.first:].max()))
    finally:
        r.close()
    assert weakest > 0.0, f"an element's row did not pull: {weakest:.4g} N"


@pytest.mark.parametrize("text, key, words", [
    ('[[tether.sections]]\nline_type = "fathom_rov_tether"\nlength = 250.0\nsegments = 20\n[winch]\nmode = "follow"',
     "winch.mode", "payout of a make-up is not supported"),
    ('[[tether.sections]]\nlength = 100.0\nsegments = 20\ndiameter = 0.02\nmass_per_length = 1.0\n'
     '[[tether.sections]]\nlength = 100.0\nsegment = 20\n', "tether.sections[1].segment", "did you mean segments"),
    ('[[tether.sections]]\nline_type = "fathom_rov_tether"\ndiameter = 0.05\nlength = 100.0\n',
     "tether.sections[0].diameter", "give one or the other"),
    ('[[tether.sections]]\nlength = 100.0\nsegments = 20\n', "tether.sections[0].diameter", "or give a line_type"),
    ('[tether]\nlength = 200.0\n[[tether.sections]]\nline_type = "fathom_rov_tether"\nlength = 100.0\n',
     "tether.length", "sections add up to 100"),
    ('[tether]\nline_type = "fathom_rov_tether"\n[[tether.sections]]\nline_type = "fathom_rov_tether"\n',
     "tether.line_type", "give each section its line_type"),
    ('[[tether.point_loads]]\narc_length = 400.0\nmass = 10.0\n[winch]\nmode = "fixed"',
     "tether.point_loads[0].arc_length", "must be in [0, 300]"),
    ('[[tether.floats]]\nstart = 50.0\nend = 40.0\n', "tether.floats[0].end", "must be > start"),
    ('[tether]\nsections = 3\n', "tether.sections", "list of [[tether.sections]] tables"),
])
def test_bad_make_up_keys_are_refused_by_name(text, key, words):
    with pytest.raises(ScenarioError) as err:
        load_scenario(text=text)
    assert err.value.key == key and words in str(err.value), str(err.value)


def test_point_loads_on_a_uniform_tether_make_a_one_section_make_up():
    sc = load_scenario(text='[tether]\nlength = 300.0\nsegments = 30\nEA = 1e7\n[winch]\nmode = "fixed"\n'
                            '[[tether.point_loads]]\narc_length = 150.0\nmass = 50.0\n'
                            '[robot]\ntype = "anchor"\nposition = [200.0, 0.0, -150.0]\n[water]\ndepth = 200.0')
    r = ScenarioRun(sc)
    try:
        mk = r.makeup
        assert len(mk.sections) == 1 and mk.sections[0].length == 300.0 and mk.sections[0].EA == 1e7
        assert mk.node_mass[15] - mk.node_mass[14] == pytest.approx(50.0)  # the clump on node 15 (150 m)
    finally:
        r.close()


def test_truncated_make_up_keeps_element_lengths_and_refuses_cut_loads():
    line, *_ = _by_hand()
    short = line.truncated(290.0)
    assert short.length == pytest.approx(290.0) and short.segments == 58  # 10 m off the last section
    assert np.allclose(short.element_length, 5.0)
    with pytest.raises(ValueError, match="clump|point load"):
        line.truncated(230.0)  # the clump at 240 m would be cut off


def test_set_and_sweep_reach_one_table_of_an_array_by_its_index(tmp_path):
    """``--set tether.floats[0].start=110`` (and a sweep's ``--vary``) changes that table's key;
    an index past the last table, a misspelt list or a bad index is refused by name."""
    from mjtether.sweep import SweepError, _resolve

    sc = load_scenario(EXAMPLE, overrides=["tether.floats[0].start=110.0", "tether.sections[1].segments=14"])
    assert sc.tether.floats[0].start == 110.0 and sc.tether.sections[1].segments == 14 and sc.tether.segments == 62
    for bad, words in (("tether.floats[3].start=1", "has 1 [[tether.floats]] table(s)"),
                       ("tether.flots[0].start=1", "did you mean floats?"),
                       ("tether.floats[x].start=1", "an index is a whole number in brackets"),
                       ("tether.floats[0].strat=1", "did you mean start?")):
        with pytest.raises(ScenarioError, match=re.escape(words)):
            load_scenario(EXAMPLE, overrides=[bad])
    path, param = _resolve("tether.floats[0].start", "--vary")
    assert path == "tether.floats[0].start" and param.unit == "m"
    with pytest.raises(SweepError, match="did you mean floats"):
        _resolve("tether.flots[0].start", "--vary")

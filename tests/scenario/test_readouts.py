"""The named readouts (``run.named``) are what the record, the plots, the video and the
environments read: the record's columns must be the readouts of the same names, and the body-frame
and moment readouts must be the world-frame ones turned and crossed (checked with MuJoCo's own
arrays, not the readouts' code). Tolerance: 1e-12 relative (the same numbers, one rounding)."""

import math

import mujoco
import numpy as np
import pytest

from mjtether.scenario.readouts import RECORD_FIELDS
from mjtether.scenario.runner import ScenarioRun
from mjtether.scenario import load_scenario

COLUMNS = [name for name, _, _ in RECORD_FIELDS]


@pytest.fixture(scope="module")
def walking():
    """The default walker scenario, 2 s after its start."""
    run = ScenarioRun(load_scenario())
    for _ in range(int(round(2.0 / run.sim.timestep))):
        run.step()
    yield run
    run.close()


def col(row, name):
    return row[COLUMNS.index(name)]


def test_record_columns_are_the_named_readouts(walking):
    n, row = walking.named, walking.record()
    assert len(row) == len(COLUMNS)
    assert col(row, "time") == n.time
    assert col(row, "ship_tension") == pytest.approx(n.ship_tension, rel=1e-12)
    assert col(row, "tow_tension") == pytest.approx(n.tow_tension, rel=1e-12)
    for k, axis in enumerate("xyz"):
        assert col(row, f"ship_force_{axis}") == n.ship_force[k]
        assert col(row, f"tow_force_{axis}") == n.tow_force[k]
        assert col(row, f"tow_force_body_{axis}") == pytest.approx(n.tow_force_body[k], rel=1e-12, abs=1e-9)
        assert col(row, f"cable_moment_{axis}") == pytest.approx(n.cable_moment[k], rel=1e-12, abs=1e-9)
        assert col(row, f"cable_moment_body_{axis}") == pytest.approx(n.cable_moment_body[k], rel=1e-12, abs=1e-9)
    R = n.robot_rotation  # the body-frame readouts are the world ones turned into the robot's frame
    np.testing.assert_allclose(R @ n.cable_moment_body, n.cable_moment, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(R @ n.tow_force_body, n.tow_force, rtol=1e-12, atol=1e-9)
    assert col(row, "deployed_length") == n.deployed_length
    assert col(row, "payout_rate") == n.payout_rate
    assert col(row, "robot_heading") == pytest.approx(math.degrees(n.robot_heading), rel=1e-12)
    roll, pitch = n.robot_roll_pitch
    assert col(row, "robot_roll") == pytest.approx(math.degrees(roll), rel=1e-12, abs=1e-12)
    assert col(row, "robot_pitch") == pytest.approx(math.degrees(pitch), rel=1e-12, abs=1e-12)
    assert col(row, "robot_speed") == pytest.approx(n.robot_speed, rel=1e-12)
    np.testing.assert_array_equal([col(row, f"robot_{a}") for a in "xyz"], n.robot_position)
    assert col(row, "tether_lowest_z") == n.tether_nodes[:, 2].min()
    assert col(row, "length_on_seabed") == n.length_on_seabed()
    assert col(row, "slack_elements") == n.slack_elements


def test_body_frame_and_moment_readouts_against_mujoco(walking):
    """tow_force_body is the world force in the torso's frame (MuJoCo's xmat), the cable moment
    is (tow point - subtree centre of mass) x force, and the tow point is MuJoCo's site."""
    n, d, m = walking.named, walking.sim.data, walking.sim.model
    torso = m.body("walker/torso").id
    R = d.xmat[torso].reshape(3, 3)
    np.testing.assert_allclose(R @ n.tow_force_body, n.tow_force, rtol=1e-12, atol=1e-9)
    tow = d.site_xpos[m.site("walker/tow_point").id]
    np.testing.assert_array_equal(n.robot_position, tow)
    np.testing.assert_allclose(n.cable_moment, np.cross(tow - d.subtree_com[torso], n.tow_force), rtol=1e-12)
    assert n.robot_heading == pytest.approx(math.atan2(R[1, 0], R[0, 0]), rel=1e-12)


def _raw_connect_force(m, d, name) -> np.ndarray:
    """MuJoCo's constraint force (N, world) on the rows of equality ``name`` (a connect: three)."""
    eq_id = m.equality(name).id
    rows = [r for r in range(d.nefc) if d.efc_type[r] == mujoco.mjtConstraint.mjCNSTR_EQUALITY and d.efc_id[r] == eq_id]
    assert len(rows) == 3, rows
    return d.efc_force[rows].copy()


def test_anchor_readouts():
    """An anchor has no body: its frame is the world's, its moment zero, its speed zero. Its
    force is checked against an answer worked out here: 150 m of the default tether (20 mm,
    1050 kg/m^3 in 1025 kg/m^3 still water: w = 0.0770 N/m, W = wL = 11.56 N) hanging from the
    ship to an anchor 100 m off and 100 m down, clear of the seabed, one step after its start at
    rest. Nothing but the two supports holds the cable up, and nothing pushes it sideways, so
    the forces on them read from MuJoCo's own rows (``tether/drum0``, the ship's node, and
    ``tether/end_connect``, the anchor's) add up to W straight down, to 0.2 % of W (the start is
    the quasi-static solver's answer, not the lumped model's exact rest: measured 0.07 % of W
    sideways, 0.006 % vertically). The named readouts are those rows' forces."""
    sc = load_scenario(overrides=['robot.type="anchor"', "robot.position=[100.0, 0.0, -100.0]",
                                  "tether.length=150.0", 'winch.mode="fixed"'])
    run = ScenarioRun(sc)
    try:
        run.step()
        n, m, d = run.named, run.sim.model, run.sim.data
        np.testing.assert_array_equal(n.robot_rotation, np.eye(3))
        np.testing.assert_array_equal(n.tow_force_body, n.tow_force)
        np.testing.assert_array_equal(n.cable_moment, np.zeros(3))
        assert n.robot_speed == 0.0 and n.progress_rate() == 0.0
        ship, anchor = _raw_connect_force(m, d, "tether/drum0"), _raw_connect_force(m, d, "tether/end_connect")
        t = sc.tether
        W = (t.density - sc.water.density.rho) * math.pi * t.diameter ** 2 / 4 * sc.water.gravity * t.length
        assert np.linalg.norm(ship + anchor - [0.0, 0.0, -W]) <= 2e-3 * W, (ship + anchor, W)
        np.testing.assert_array_equal(n.tow_force, anchor)
        np.testing.assert_array_equal(n.ship_force, ship)
        assert n.tow_tension == pytest.approx(np.linalg.norm(anchor), rel=1e-12)
    finally:
        run.close()

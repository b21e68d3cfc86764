"""The fibre-paying AUV cases (``scripts/reproduce_001.py``, ``examples/auv_fibre_*.toml``)
against answers that do not come from mjtether: the tangential drag of a straight fibre sliding
out through still water, and the paper's claim for its anti-twining manoeuvre."""

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

from mjtether.scenario.readouts import RECORD_FIELDS
from mjtether.scenario.runner import run
from mjtether.scenario import load_scenario

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("reproduce_001", ROOT / "scripts" / "reproduce_001.py")
rep = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(rep)
COL = {name: k for k, (name, _, _) in enumerate(RECORD_FIELDS)}


@pytest.mark.slow
def test_straight_run_tension_is_the_sliding_fibres_drag(capsys):
    """``reproduce_001.py --json --quick`` (25 m elements, 0.01 s steps; CI's setting): the tow
    tension at 200, 500 and 1000 m deployed is 1/2 rho C_dt pi d L v^2 plus the drum's pull
    c v, worked out here from the example's inputs, within 2 % (the drum and the axial mode ring;
    measured 0.2 %), so T(1000)/T(500) is that line's, about 1.94."""
    assert rep.main(["--json", "--quick"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["length_m"] == [200.0, 500.0, 1000.0]
    sc = load_scenario(ROOT / "examples" / "auv_fibre_straight.toml")
    t = sc.tether
    want = [0.5 * 1025.0 * t.cd_tangential * np.pi * t.diameter * L + sc.winch.drum_damping for L in out["length_m"]]
    np.testing.assert_allclose(out["tension_N"], want, rtol=0.02)
    assert out["ratio_1000_500"] == pytest.approx(want[2] / want[1], rel=0.02)


def _closest(name: str) -> float:
    rows, _, _ = run(load_scenario(ROOT / "examples" / f"{name}.toml"), keep_nodes=False)
    rows = np.asarray(rows)
    return float(rows[rows[:, COL["time"]] >= 15.0, COL["cable_clearance"]].min())


@pytest.mark.slow
def test_the_anti_twining_turn_keeps_the_vehicle_off_its_fibre():
    """The paper's claim: circling in a current, the vehicle comes back over its fibre unless it
    first turns to port. Without the turn it runs through the fibre (clearance below 0: the hull
    and the cable do not collide in mjtether); with a 30 deg port turn first it stays more than
    0.5 m clear (measured: -0.09 m and 0.72 m; docs/auv_fibre_reproduction.md shows that larger
    turns do not help)."""
    plain, anti = _closest("auv_fibre_circle"), _closest("auv_fibre_circle_antitwining")
    assert plain < 0.0
    assert anti > 0.5

"""Hong et al.'s (2020) USV drifting in wind and current (``scripts/hong2020_drift.py``, their
Case 2): the drift section of ``docs/hong2020_reproduction.md`` is the script's JSON as written
(every number on it), and the drifts that have an answer outside the code hold it."""

import contextlib
import importlib.util
import io
import json
import math
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("hong2020_drift", ROOT / "scripts" / "hong2020_drift.py")
drift = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(drift)


@pytest.fixture(scope="module")
def out():
    """``hong2020_drift.py --json``'s output (its five runs: about 9 s)."""
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert drift.main(["--json"]) == 0
    return json.loads(buf.getvalue())


def test_the_page_holds_the_scripts_json(out):
    """The page's drift section is ``section`` of ``--json``'s output, character for character:
    regenerate it with ``python scripts/hong2020_drift.py`` when the physics moves."""
    page = (ROOT / "docs" / "hong2020_reproduction.md").read_text()
    assert drift.kept_section(page) == drift.section(out)


def test_a_uniform_current_only_carries_the_usv(out):
    """Galilean invariance (the hull's loads on its velocity through the water): in 0.5 m/s towards
    45 deg the turning circle's centre drifts at the current's velocity, to 0.1 % and 0.05 deg, and
    the turn about it is the still-water one, to 0.1 % in radius and period. (Measured: 1e-8.)"""
    c = out["cases"]
    cur, still = c["current_45"], c["still"]
    assert cur["drift_speed_mps"] == pytest.approx(0.5, rel=1e-3)
    assert cur["drift_direction_deg"] == pytest.approx(45.0, abs=0.05)
    assert cur["radius_m"] == pytest.approx(still["radius_m"], rel=1e-3)
    assert cur["period_s"] == pytest.approx(still["period_s"], rel=1e-3)
    assert still["drift_speed_mps"] < 1e-6  # (still water: no drift)


def test_the_wind_drifts_are_one_turned_by_the_winds_turn(out):
    """The two winds differ only by a 90 deg turn of the wind: the USV starts heading 0 and then
    turns through every heading alike, so over whole turns the drift turns with the wind, its speed
    the same, to 2 % and 1 deg (whole turns sample the headings alike only to within the start's
    offset, a part of a turn in 3)."""
    w0, w90 = out["cases"]["wind_0"], out["cases"]["wind_90"]
    assert w90["drift_speed_mps"] == pytest.approx(w0["drift_speed_mps"], rel=0.02)
    assert w90["drift_direction_deg"] - w0["drift_direction_deg"] == pytest.approx(90.0, abs=1.0)
    assert math.hypot(*w0["drift_mps"]) > 1e-3  # (it does drift)

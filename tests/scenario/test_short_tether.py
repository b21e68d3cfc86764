"""A tether shorter than the straight distance (the span) between the ship's fairlead and the
robot's tow point is refused before anything is simulated, naming tether.length, the span and the
minimum length, alone and in a sweep.

Before, an elastic tether was let stretch up to 10 % to reach: the default walker with 205 m of
tether for its 214 m span started near 220 kN (EA 5e6 N times 4.5 %) and failed 0.06 s in as
"simulation diverged ... reduce the time step", in a run and as a sweep's case. The spans below are
computed here from the scenario's geometry (Pythagoras), not taken from the code's check.
"""

import math
import re

import pytest

from mjtether.cli import main
from mjtether.scenario import ScenarioError, load_scenario
from mjtether.scenario.runner import ScenarioRun
from mjtether.cable.tether import MAX_REACH_STRAIN

ANCHOR = """\
[simulation]
duration = 1.0
output_interval = 0.5
[water]
depth = 100.0
[tether]
length = {length}
segments = 10
diameter = 0.03
density = 2500.0
EA = 5.0e6
[robot]
type = "anchor"
position = [40.0, 0.0, -90.0]
"""
ANCHOR_SPAN = math.hypot(40.0, 90.0)  # m: fairlead at (0, 0, 0), anchor at (40, 0, -90)
WALKER_SPAN = math.hypot(80.0, 199.0)  # m: default walker, tow point about 1 m over the 200 m seabed at x = 80 m


def _numbers(msg):
    return [float(x) for x in re.findall(r"(\d+(?:\.\d+)?) m\b", msg)]


def test_an_elastic_tether_shorter_than_its_span_is_refused_on_loading():
    """95 m of elastic tether for the anchor's 98.5 m span: refused naming the key, the span and
    the minimum (the span, stretched by at most MAX_REACH_STRAIN: an anchor has no tow-point offset)."""
    with pytest.raises(ScenarioError) as e:
        load_scenario(text=ANCHOR.format(length=95.0))
    msg = str(e.value)
    assert e.value.key == "tether.length" and "tether.length = 95 m: too short for its ends" in msg
    assert f"{ANCHOR_SPAN:.1f} m apart" in msg and f"give tether.length >= {ANCHOR_SPAN / (1 + MAX_REACH_STRAIN):.1f} m" in msg
    load_scenario(text=ANCHOR.format(length=ANCHOR_SPAN))  # as long as the span: accepted


def test_the_walker_case_of_the_issue_is_refused_alone_before_simulating(tmp_path, capsys):
    """The default walker with 205 m for its 214.5 m span: ``run`` stops with the key, the span and the
    minimum in one line (the span less the 2 m allowed for the tow point's offset, over 1.001), writes nothing, and
    says nothing of the time step."""
    out = tmp_path / "res"
    assert main(["run", "default_walker", "--set", "tether.length=205", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "tether.length = 205 m: too short for its ends" in err and "time step" not in err
    span, minimum = _numbers(err.split("apart")[0])[-1], _numbers(err.split(">=")[1])[0]
    assert abs(span - WALKER_SPAN) < 0.5 and abs(minimum - (WALKER_SPAN - 2.0) / (1 + MAX_REACH_STRAIN)) < 0.5
    assert err.count("\n") == 1 and not out.exists()


def test_within_the_tow_point_allowance_the_start_refuses_at_the_tow_point_itself():
    """213 m passes the file's check (the span less 2 m) but not the start's, which measures to the
    standing walker's tow point: refused (naming tether.length and a span within 0.5 m of 214.5 m)
    before the run is built, not left to start stretched."""
    sc = load_scenario("default_walker", overrides=["tether.length=213"])
    with pytest.raises(ScenarioError) as e:
        ScenarioRun(sc)
    msg = str(e.value)
    assert e.value.key == "tether.length" and "tether.length = 213 m: too short for its ends" in msg
    span = _numbers(msg.split("apart")[0])[-1]
    assert abs(span - WALKER_SPAN) < 0.5 and f"give tether.length >= {span / (1 + MAX_REACH_STRAIN):.2f} m (the minimum)" in msg


def test_a_two_case_sweep_with_a_short_tether_is_refused_before_any_case_runs(tmp_path, capsys):
    (tmp_path / "s.toml").write_text(ANCHOR.format(length=120.0))
    out = tmp_path / "sw"
    assert main(["sweep", str(tmp_path / "s.toml"), "--vary", "tether.length=90,120", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "tether.length = 90" in err and f"{ANCHOR_SPAN:.1f} m apart" in err
    assert f">= {ANCHOR_SPAN / (1 + MAX_REACH_STRAIN):.1f} m" in err and "diverged" not in err and not out.exists()


def test_a_sweep_case_short_at_the_tow_point_fails_with_the_reason_and_the_other_runs(tmp_path):
    """The issue's sweep: 2 walker cases, one 213 m long (short of the 214.2 m to its tow point), one
    300 m: the first is recorded as failed naming tether.length (not as diverged), the second runs."""
    import csv
    out = tmp_path / "sw"
    assert main(["sweep", "default_walker", "--set", "simulation.duration=0.5", "--set", "tether.segments=20",
                 "--vary", "tether.length=213,300", "--out", str(out)]) == 0
    with open(out / "cases.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["status"] for r in rows] == ["failed", "ok"]
    assert "tether.length = 213 m: too short for its ends" in rows[0]["error"]
    assert "diverged" not in rows[0]["error"] and rows[0]["diverged_at_s"] == ""

"""A vehicle without a tether (``tether.attached = false``) from the CLI, and the standard
manoeuvres (``robot.manoeuvre``) that set its rudder."""

import csv
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from mjtether.scenario import ConfigError, load_scenario

ALONE = """
[simulation]
duration = {duration}
timestep = 0.005
output_interval = 0.5
[water]
depth = 100.0
[tether]
attached = false
[robot]
type = "vehicle"
vehicle = "remus100"
position = [0.0, 0.0, -20.0]
setpoints = [[0.0, 1.5, 0.0, 20.0]]
manoeuvre = "{manoeuvre}"
manoeuvre_start_s = 10.0
rudder_deg = 15.0
zigzag_heading_deg = 20.0
spiral_rudders_deg = [15.0, -5.0, 0.0]
spiral_step_s = 10.0
"""


def test_a_vehicle_alone_from_the_cli(tmp_path):
    """``mjtether run`` of a vehicle without a tether: the CSV has the ship's and robot's columns
    and none of the tether's, only track.png is plotted, lines.npz holds no line (the states only, for a replay), the summary
    reports no tensions; the vehicle flies its setpoint (1.5 m/s within 2 %, 20 m depth within
    0.2 m after 30 s)."""
    scenario = tmp_path / "alone.toml"
    scenario.write_text(ALONE.format(duration=30.0, manoeuvre="none"))
    out = tmp_path / "out"
    done = subprocess.run([sys.executable, "-m", "mjtether.cli", "run", str(scenario), "--out", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "no tether" in done.stdout
    assert sorted(p.name for p in out.iterdir()) == ["lines.npz", "mjtether-manifest.json", "summary.json",
                                                      "timeseries.csv", "track.png"]
    with np.load(out / "lines.npz") as z:
        assert sorted(z.files) == ["mocap_pos", "mocap_quat", "qpos", "time_s"]
    with open(out / "timeseries.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert not [c for c in rows[0] if "tension" in c or "force" in c or "deployed" in c or "slack" in c]
    last = rows[-1]
    assert float(last["robot_speed_mpers"]) == pytest.approx(1.5, rel=0.02)
    assert float(last["robot_z_m"]) == pytest.approx(-20.0, abs=0.2)
    s = json.loads((out / "summary.json").read_text())
    assert list(s["final"]) == ["time_s"] and "peak" not in s and s["run"]["tethered"] is False


def test_only_a_vehicle_runs_without_a_tether():
    with pytest.raises(ConfigError, match=r"tether.attached = false: only a vehicle can run without a tether"):
        load_scenario(text="[tether]\nattached = false\n")


def _fly(manoeuvre, duration):
    """Step the scenario; (t s, heading rad, rudder command rad, shaft command rpm) per step."""
    from mjtether.scenario.runner import ScenarioRun

    r = ScenarioRun(load_scenario(text=ALONE.format(duration=duration, manoeuvre=manoeuvre)))
    try:
        m, d = r.sim.model, r.sim.data
        rudder, prop = m.actuator("vehicle/rudder").id, m.actuator("vehicle/propeller").id
        out = []
        while r.sim.time < duration - 1e-9:
            r.step()
            out.append([r.sim.time, r.named.robot_heading, d.ctrl[rudder], d.ctrl[prop]])
    finally:
        r.close()
    return np.array(out)


def test_zigzag_reverses_the_rudder_at_the_heading_change():
    """A 15/20 zig-zag (ITTC): from 10 s the rudder goes to +15 deg (the REMUS 100 turns to
    starboard, its heading falling), and is reversed each time the heading has changed by 20 deg
    from the start the way the rudder turns it; each reversal comes within one autopilot period
    (0.05 s) of the heading crossing, and the heading overshoots the 20 deg (the vehicle's
    inertia); the shaft is held at its speed at 10 s."""
    a = _fly("zigzag", 60.0)
    t, heading, rudder, rpm = a.T
    on = t > 10.0 + 0.05
    psi0 = heading[np.searchsorted(t, 10.0)]
    change = np.degrees(np.unwrap(heading) - psi0)
    assert np.all(np.abs(np.abs(rudder[on]) - math.radians(15.0)) < 1e-12)
    flips = np.flatnonzero(np.diff(np.sign(rudder)) != 0)
    flips = flips[t[flips] > 10.0]
    assert len(flips) >= 3
    since = int(np.searchsorted(t, 10.0))
    for k in flips:
        side = -np.sign(rudder[k])  # a positive rudder lowers the heading
        crossed = since + np.flatnonzero((side * change[since:k + 1]) >= 20.0)
        assert len(crossed) and t[k + 1] - t[crossed[0]] <= 0.05 + 1e-9, f"reversal at {t[k + 1]:.2f} s"
        since = k + 1
    assert change.min() < -20.5 and change.max() > 20.5
    assert np.ptp(rpm[on]) == 0.0 and rpm[on][0] > 0.0


def test_spiral_holds_each_rudder_angle_for_its_step():
    a = _fly("spiral", 45.0)
    t, _, rudder, _ = a.T
    for lo, want in ((10.0, 15.0), (20.0, -5.0), (30.0, 0.0), (40.0, 0.0)):
        window = (t > lo + 0.1) & (t < lo + 9.9)
        assert np.allclose(rudder[window], math.radians(want), atol=1e-12)


PROFILE = """
[simulation]
duration = 40.0
timestep = 0.005
output_interval = 0.5
[water]
depth = 200.0
[tether]
attached = false
[robot]
type = "vehicle"
vehicle = "remus100"
position = [0.0, 0.0, -20.0]
setpoint_interpolation = "linear"
setpoints = [[0.0, 2.0, 0.0, 20.0], [10.0, 2.0, 0.0, 20.0], [40.0, 2.0, -60.0, 20.0]]
pitch_schedule = [[0.0, 0.0], [10.0, 0.0], [20.0, 20.0], [40.0, 20.0]]
"""


def test_pitch_and_heading_profiles_are_flown():
    """The REMUS 100 at 2 m/s given a pitch profile theta(t) (level, then 2 deg/s down to
    20 deg nose down, held; the 001 paper's kind of schedule) and a heading ramp psi(t) (0 to
    -60 deg over 30 s, robot.setpoint_interpolation = "linear"): from 6 s after the pitch ramp
    ends the pitch is within 0.5 deg of 20 deg (the pitch loop's integral takes out the
    restoring moment); the heading lags the ramp (a PID's lag behind a ramp, which its integral
    slowly takes out: 4.6 deg at 20 s, 0.8 deg at 40 s) by under 2.5 deg over the last 10 s."""
    from mjtether.scenario.runner import RECORD_FIELDS, run

    rows, _, _ = run(load_scenario(text=PROFILE), keep_nodes=False)
    col = {n: i for i, (n, _, _) in enumerate(RECORD_FIELDS)}
    t = rows[:, 0]
    late = t >= 26.0
    assert np.max(np.abs(rows[late, col["robot_pitch"]] - 20.0)) < 0.5
    ramp = t >= 30.0
    want = -60.0 * (t[ramp] - 10.0) / 30.0
    assert np.max(np.abs(rows[ramp, col["robot_heading"]] - want)) < 2.5


def test_a_pitch_schedule_needs_a_vehicle_that_dives_by_pitching():
    with pytest.raises(ConfigError, match="robot.pitch_schedule = .*bluerov2_heavy does not dive by pitching"):
        load_scenario(text=PROFILE.replace('"remus100"', '"bluerov2_heavy"'))

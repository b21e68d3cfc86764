"""Hong et al. (2020)'s USV drifting in wind and current (their Sec. 4.2, Case 2, Fig. 14): the
USV alone turning on its two stern thrusters (29.2 kgf port, 14.6 kgf starboard, open loop) in
still water, in a wind of 1 m/s at 0 deg, in a wind of 1 m/s at 90 deg, and in a current of
0.5 m/s at 45 deg; plus the same current as a first-order Gauss-Markov process about that mean
(parameters assumed: the paper gives none).

The inputs, none fitted to the paper's figures:

* the USV: ``assets/vehicles/hong2020_usv.toml`` (their Table 4 and measured thrusters; the
  hydrodynamics a reading, Fossen's Otter Froude-scaled: ``docs/vehicles.md``); the paper's
  29.2 kgf is above its own measured maximum, 29.12 kgf, to which the thruster clips it;
* which thruster pushes harder is not stated: the port one, as Eq. 6 lists it first (so the USV
  turns to starboard; the other reading mirrors every drift about the start heading);
* the wind load: Eqs. 7-9 with the middle of Eq. 9's ranges and the USV's projected areas
  read as 0.5 m of mean height above its waterline (``vehicles.wind.HONG2020_USV``);
* angles in the paper's frame, read as Fossen's: x ahead at the start, y to starboard, angles
  from x towards y (clockwise seen from above); a wind or current "at" an angle moves towards
  it (Fossen's beta in u = V cos(beta - psi), the form of their Eq. 10). mjtether's world is z
  up, so the runs use y' = -y and angles negated; every number here is turned back.

Each case runs ``DURATION`` s at ``TIMESTEP`` s; after the first turn (``SETTLE`` s) the track
is averaged over whole turns (the period from the mean yaw rate): each average is the turning
circle's centre at the window's middle time, whatever the radius, and the line through the
centres gives the drift velocity. ``--json`` prints the results; without it the script writes its
section of ``docs/hong2020_reproduction.md`` (between the markers, the rest of the page kept).

    python scripts/hong2020_drift.py [--json] [--out docs/hong2020_reproduction.md]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tomllib
from pathlib import Path

import numpy as np

from mjtether.scenario import Scenario, build, weather
from mjtether.scenario.runner import ScenarioRun

KGF = 9.80665  # N
PORT_KGF, STARBOARD_KGF = 29.2, 14.6  # their Sec. 4.1 turning thrusts
DURATION, TIMESTEP, SETTLE = 160.0, 0.01, 40.0  # s (measured: at 0.005 s the wind's and the steady
# current's drifts move by under 0.3 % and 0.04 deg)
GM = {"mu": 0.1, "sigma": 0.05 * math.sqrt(2 * 0.1), "v_min": 0.0, "v_max": 1.0, "seed": 0}
"""The Gauss-Markov current's assumed parameters: a correlation time of 10 s and a stationary
standard deviation of 0.05 m/s (sigma = 0.05 sqrt(2 mu)), held in [0, 1] m/s; direction steady."""

BASE = """
[simulation]
duration = {duration}
timestep = {timestep}
output_interval = 0.5
[water]
depth = 50.0
[tether]
attached = false
[robot]
type = "vehicle"
vehicle = "hong2020_usv"
position = [0.0, 0.0, 0.0]
setpoints = [[0.0, 0.0, 0.0, 0.0]]
"""

CASES = [  # (key, label, paper's disturbance (kind, speed m/s, angle deg in the paper's frame) or None, extra TOML)
    ("still", "no disturbance", None, ""),
    ("wind_0", "wind 1 m/s at 0 deg", ("wind", 1.0, 0.0), "[wind]\nspeed = 1.0\ndirection_deg = 0.0\n"),
    ("wind_90", "wind 1 m/s at 90 deg", ("wind", 1.0, 90.0), "[wind]\nspeed = 1.0\ndirection_deg = -90.0\n"),
    ("current_45", "current 0.5 m/s at 45 deg", ("current", 0.5, 45.0),
     "[water.current]\nspeed = 0.5\nheading_deg = -45.0\n"),
    ("current_45_gm", "current 0.5 m/s at 45 deg, Gauss-Markov", ("current", 0.5, 45.0),
     "[water.current]\nspeed = 0.5\nheading_deg = -45.0\n[water.current.gauss_markov]\n"
     + "".join(f"{k} = {v!r}\n" for k, v in GM.items())),
]

BEGIN = "<!-- scripts/hong2020_drift.py: begin -->"
END = "<!-- scripts/hong2020_drift.py: end -->"


def scenario(extra: str = "", duration: float = DURATION, timestep: float = TIMESTEP) -> Scenario:
    return build(Scenario, tomllib.loads(BASE.format(duration=duration, timestep=timestep) + extra))


def run_case(extra: str = "", duration: float = DURATION, timestep: float = TIMESTEP) -> dict:
    """One case: the USV turning open loop; its track (columns: t s, x m, y m, yaw rad, and the
    water's own displacement from the start, the current at the surface integrated step by step,
    x m, y m; paper's frame) and the last wind load (N, N, N m, paper's frame)."""
    run = ScenarioRun(scenario(extra, duration, timestep))
    try:
        w = weather.attach(run)
        run.release_pilot()
        m, d = run.sim.model, run.sim.data
        d.ctrl[m.actuator("vehicle/port").id] = PORT_KGF * KGF
        d.ctrl[m.actuator("vehicle/starboard").id] = STARBOARD_KGF * KGF
        body = run.vehicle.id
        n = int(round(duration / timestep))
        track, water = np.empty((n + 1, 6)), np.zeros(2)
        for k in range(n + 1):
            R = d.xmat[body].reshape(3, 3)
            track[k] = d.time, d.xpos[body][0], -d.xpos[body][1], -math.atan2(R[1, 0], R[0, 0]), *water
            if k == n:
                break
            run.step()  # (its current: the one the step read, before the next update)
            u = run.water.velocity(np.zeros(1))[0]
            water += (u[0] * timestep, -u[1] * timestep)
        load = [0.0, 0.0, 0.0] if w is None or not w.vessels else [float(w.vessels[0].load[0]),
                                                                    -float(w.vessels[0].load[1]),
                                                                    -float(w.vessels[0].load[2])]
    finally:
        run.close()
    return {"track": track, "wind_load": load}


def _line(mids: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """The velocity (m/s, (2,)) of the line fitted through ``centres`` (m, (k, 2)) at ``mids`` (s)."""
    return np.array([np.polyfit(mids, centres[:, i], 1)[0] for i in (0, 1)])


def drift(track: np.ndarray, settle: float = SETTLE) -> dict:
    """The turn and its drift from a track (``run_case``'s): the yaw rate (deg/s, > 0 to
    starboard), the period (s), the circle's radius about the drifting centre (m), the speed over
    the ground (m/s) and the drift: velocity (m/s), speed, direction (deg, paper's frame), from
    the centres of whole turns after ``settle`` s; and the water's drift: its displacement's
    averages over the same turns, fitted the same way (what a hull carried by the current alone
    would drift)."""
    keep = track[:, 0] >= settle
    t, x, y, yaw, wx, wy = track[keep].T
    yaw = np.unwrap(yaw)
    rate = (yaw[-1] - yaw[0]) / (t[-1] - t[0])  # rad/s
    period = 2 * math.pi / abs(rate)
    dt = t[1] - t[0]
    per = int(round(period / dt))
    turns = (len(t) - 1) // per
    if turns < 2:
        raise ValueError(f"the run holds {turns} whole turn(s) after {settle:g} s; it needs 2")
    windows = [slice(j * per, (j + 1) * per) for j in range(turns)]
    mids = np.array([t[s].mean() for s in windows])
    centres = np.array([[x[s].mean(), y[s].mean()] for s in windows])
    vel = _line(mids, centres)
    water = _line(mids, np.array([[wx[s].mean(), wy[s].mean()] for s in windows]))
    fit = np.array([np.polyval(np.polyfit(mids, centres[:, i], 1), t) for i in (0, 1)]).T
    radius = float(np.mean(np.hypot(x - fit[:, 0], y - fit[:, 1])))
    speed = float(np.mean(np.hypot(np.diff(x), np.diff(y)) / dt))
    v = float(np.hypot(*vel))
    return {"yaw_rate_deg_s": math.degrees(rate), "period_s": float(period), "turns": turns, "radius_m": radius,
            "ground_speed_mps": speed, "drift_mps": [float(c) for c in vel], "drift_speed_mps": v,
            "drift_direction_deg": math.degrees(math.atan2(vel[1], vel[0])), "drift_per_turn_m": v * float(period),
            "water_drift_mps": [float(c) for c in water], "water_drift_speed_mps": float(np.hypot(*water))}


def results(duration: float = DURATION, timestep: float = TIMESTEP) -> dict:
    """Every case's turn and drift (``drift``), with its disturbance and, where there is one, the
    angle from the disturbance's direction to the drift's (deg, > 0 clockwise); and the numbers
    the page compares them with: Eq. 7's head-on load at 1 m/s (N), the USV file's linear surge
    and sway damping (N s/m), and the resistance the paper's straight run implies (its 2 x 29.2
    kgf at about 0.8 m/s, N)."""
    from mjtether.vehicles.files import load_vehicle
    from mjtether.vehicles.wind import HONG2020_USV, wind_load
    damping = load_vehicle("hong2020_usv").hydro.linear_damping
    out = {"duration_s": duration, "timestep_s": timestep, "settle_s": SETTLE, "port_kgf": PORT_KGF,
           "starboard_kgf": STARBOARD_KGF, "gauss_markov": GM,
           "head_on_wind_load_1mps_N": float(-wind_load(HONG2020_USV, 1.0, 0.0)[0]),
           "surge_damping_N_s_m": float(damping[0, 0]), "sway_damping_N_s_m": float(damping[1, 1]),
           "paper_straight_resistance_N": 2 * PORT_KGF * KGF, "cases": {}}
    for key, label, dist, extra in CASES:
        r = run_case(extra, duration, timestep)
        row = {"label": label, **drift(r["track"]), "last_wind_load": r["wind_load"]}
        if dist is not None:
            kind, speed, angle = dist
            row.update(kind=kind, speed_mps=speed, direction_deg=angle,
                       drift_off_disturbance_deg=(row["drift_direction_deg"] - angle + 180.0) % 360.0 - 180.0)
        out["cases"][key] = row
    gm = out["cases"]["current_45_gm"]
    out["gm_drift_over_water_drift"] = gm["drift_speed_mps"] / gm["water_drift_speed_mps"]
    return out


def _signed(x: float) -> str:
    """One decimal with its sign, a rounded zero as +0.0."""
    return f"{round(x, 1) + 0.0:+.1f}"


def section(out: dict) -> str:
    """The page's drift section (between ``BEGIN`` and ``END``) from ``results()``."""
    c = out["cases"]
    still = c["still"]
    rows = ["| case | turn radius (m) | speed over ground (m/s) | period (s) | drift (m/s) | drift direction (deg) "
            "| drift off the disturbance's direction (deg) | drift per turn (m) |", "|---|---|---|---|---|---|---|---|"]
    for key, *_ in CASES:
        r = c[key]
        off = _signed(r["drift_off_disturbance_deg"]) if "kind" in r else "-"
        way = f"{r['drift_direction_deg']:.1f}" if r["drift_speed_mps"] >= 5e-5 else "-"
        rows.append(f"| {r['label']} | {r['radius_m']:.2f} | {r['ground_speed_mps']:.3f} | {r['period_s']:.2f} "
                    f"| {r['drift_speed_mps']:.4f} | {way} | {off} "
                    f"| {r['drift_per_turn_m']:.3f} |")
    w0, w90, cur, gm = c["wind_0"], c["wind_90"], c["current_45"], c["current_45_gm"]
    g = out["gauss_markov"]
    offs = (w0["drift_off_disturbance_deg"], w90["drift_off_disturbance_deg"])
    oblique = ("The wind's drift is oblique, as the paper says of its runs (\"drifts in an oblique direction "
               "rather than the same direction as the incident disturbance\"): " if min(map(abs, offs)) > 5.0 else
               "The wind's drift is nearly along the wind, where the paper says its runs drift \"in an oblique "
               "direction rather than the same direction as the incident disturbance\": ")
    straight = abs(cur["drift_off_disturbance_deg"]) < 0.5
    lines = [
        BEGIN,
        "## The USV drifting in wind and current (their Case 2, Fig. 14)",
        "",
        "Generated by `python scripts/hong2020_drift.py`; do not edit by hand.",
        "",
        f"The USV alone (`hong2020_usv`) turns open loop on {out['port_kgf']:g} kgf port and "
        f"{out['starboard_kgf']:g} kgf starboard (their Sec. 4.1; the thruster clips the first to its "
        "measured 29.12 kgf; which side pushes harder is not stated: port, as their Eq. 6 lists it first), for "
        f"{out['duration_s']:g} s at {out['timestep_s']:g} s steps. Wind: their Eqs. 7-9 on the relative wind, "
        "the middle of Eq. 9's ranges, the projected areas read as 0.5 m of mean height above the waterline "
        "(`[wind]`, `vehicles.wind.HONG2020_USV`); current: uniform (`[water.current]`), and once as a "
        "first-order Gauss-Markov process about the same mean (`[water.current.gauss_markov]`, assumed: "
        f"mu = {g['mu']:g} 1/s, a stationary standard deviation of 0.05 m/s, held in [{g['v_min']:g}, "
        f"{g['v_max']:g}] m/s, seed {g['seed']}; the paper gives none). Frame: the paper's, x ahead at "
        "the start, y to starboard, angles from x towards y; a wind or current at an angle moves towards it "
        f"(Fossen's convention). After the first {out['settle_s']:g} s the track is averaged over whole turns: "
        "the centres of the turning circle, whose line is the drift. Nothing is fitted to the paper's figure, "
        "whose drifts the text does not give in numbers.",
        "",
        *rows,
        "",
        f"The current carries the USV with it: it drifts at {cur['drift_speed_mps']:.4f} m/s towards "
        f"{cur['drift_direction_deg']:.1f}° in a current of 0.5 m/s towards 45°, and its turn through the water "
        f"is the still-water one (radius {cur['radius_m']:.2f} m against {still['radius_m']:.2f} m, about the "
        "drifting centre). That is Galilean invariance: the hull's loads are on its velocity through the water, "
        "as in their Eq. 31 (the relative velocity v_r). The Gauss-Markov current drifts it by what the water "
        f"did over the same turns: {gm['drift_speed_mps']:.4f} m/s against the water's own "
        f"{gm['water_drift_speed_mps']:.4f} m/s (ratio {out['gm_drift_over_water_drift']:.4f}).",
        "",
        f"A 1 m/s wind moves it little: {w0['drift_speed_mps'] * 1000:.2f} mm/s ({w0['drift_per_turn_m'] * 100:.1f} cm "
        f"a turn) in the wind at 0°, {w90['drift_speed_mps'] * 1000:.2f} mm/s in the wind at 90°. Eq. 7 head-on at "
        f"1 m/s on this 3 m USV is {out['head_on_wind_load_1mps_N']:.2f} N, against a hull that resists "
        f"{out['surge_damping_N_s_m']:.0f} N per m/s of surge and {out['sway_damping_N_s_m']:.0f} N per m/s of "
        "sway; most of the air load in a run is the USV's own speed through the air, which turns with it. "
        + oblique + f"{_signed(offs[0])}° and {_signed(offs[1])}° off the wind's direction (clockwise positive). "
        + ("The current's drift is not oblique here: a uniform current only carries the hull." if straight else
           f"The current's drift is {_signed(cur['drift_off_disturbance_deg'])}° off its direction."),
        "",
        "Against the paper: it shows the drifts only in its figure, its USV coefficients are unpublished, and "
        "its still-water turn (radius about 1.75 m at about 0.8 m/s) is not this file's "
        f"({still['radius_m']:.2f} m at {still['ground_speed_mps']:.2f} m/s; `docs/vehicles.md` argues why). "
        "The current's drift does not depend on the hull (it is the current's); the wind's is the wind load "
        "over the hull's resistance, and the paper's hull, which by its own straight run resists "
        f"{out['paper_straight_resistance_N']:.0f} N at about 0.8 m/s, would drift less under the same load. "
        "Nothing here is tuned towards the figure.",
        END,
    ]
    return "\n".join(lines) + "\n"


def write_section(path: Path, out: dict) -> None:
    """Put ``section(out)`` in ``path`` between the markers (appended if they are not there), the
    rest of the page as it was."""
    old = path.read_text() if path.exists() else ""
    new = section(out)
    i, j = old.find(BEGIN), old.find(END)
    if i >= 0 and j > i:
        text = old[:i] + new + old[j + len(END):].lstrip("\n")
    else:
        text = old.rstrip("\n") + ("\n\n" if old else "") + new
    tmp = path.with_suffix(".tmp")
    tmp.write_text(text)
    tmp.replace(path)


def kept_section(text: str) -> str:
    """The drift section of a page's ``text`` ("" if none): what a script regenerating the rest
    of the page appends again."""
    i, j = text.find(BEGIN), text.find(END)
    return text[i:j + len(END)] + "\n" if i >= 0 and j > i else ""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", action="store_true", help="print the results as JSON (nothing written)")
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs" / "hong2020_reproduction.md"))
    a = ap.parse_args(argv)
    out = results()
    if a.json:
        print(json.dumps(out, indent=1))
        return 0
    for key, *_ in CASES:
        r = out["cases"][key]
        print(f"{r['label']:42s} radius {r['radius_m']:6.2f} m, drift {r['drift_speed_mps']:.4f} m/s "
              f"towards {r['drift_direction_deg']:6.1f} deg")
    write_section(Path(a.out), out)
    print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Reproduce the tethered-AUV study that pulls an optical fibre off a ship's drum at zero tension
(the Australian Maritime College's Mullaya AUV; finite-difference cable after Ablow and
Schechter 1983): the tow-point tension of a straight run at 1 m/s at 200, 500 and 1000 m
deployed (its Table III), in calm water and in its currents, and its manoeuvres (pitching down,
zig-zag, a circle with and without its anti-twining manoeuvre, a downward spiral), each the
example scenario ``examples/auv_fibre_*.toml``.

As in the paper the vehicle moves "at equilibrium conditions": its motion is prescribed
(``robot.path``: 1 m/s through the water, heading and pitch), the fibre is paid out from
nothing by a free drum, and the output is the cable's pull at the tow point. The fibre's
parameters (the paper's Table II) did not survive in our copy, nor could the study it takes them
from (Feng and Allen 2004, Ocean Engineering 31, 1019-1035, the Subzero II vehicle) be read:
they are assumed (in the example files; ``docs/auv_fibre_reproduction.md`` says why).

    python scripts/reproduce_001.py            # every case (minutes): docs/reproductions/auv_fibre.json, then the page
    python scripts/reproduce_001.py --render   # no simulation: the page from the committed JSON
    python scripts/reproduce_001.py --json [--quick]

Every number of the page sits in a marker, ``<!--repro:auv_fibre.KEY:FORMAT-->text<!--/repro-->``
(the syntax of ``scripts/make_bench_docs.py``'s ``bench`` markers, read from
``docs/reproductions/`` instead of ``docs/bench/``), which ``tests/papers/test_reproduction_docs.py``
checks against the JSON. The JSON is ``{"result": ..., "measured": {date, command, commit, wall
time, machine, versions}}``, as benchmark JSON is. ``--json`` prints the result (the straight
run's ``length_m``, ``tension_N``, ... at the top level); ``--quick`` uses 25 m elements and steps
of 0.01 s (for CI), runs the straight case only and writes nothing.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from mjtether.scenario.readouts import RECORD_FIELDS
from mjtether.scenario.runner import run
from mjtether.scenario import load_scenario

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import make_bench_docs as mbd  # noqa: E402  (the marker syntax, the JSON lookup, the machine block)

NAME = "auv_fibre"  # docs/reproductions/auv_fibre.json
REPRO_DIR = ROOT / "docs" / "reproductions"
DOC = ROOT / "docs" / "auv_fibre_reproduction.md"
EXAMPLES = ROOT / "examples"
COL = {name: k for k, (name, _, _) in enumerate(RECORD_FIELDS)}
LENGTHS = (200.0, 500.0, 1000.0)  # m, Table III
PAPER_T1000 = 51.055  # N, the only entry of Table III that survived
QUICK = ("tether.length=100.0", "simulation.timestep=0.01")  # 25 m elements

CURRENTS = (  # label, speed (m/s), heading (deg): the paper's straight-running currents
    ("calm", 0.0, 0.0),
    ("downstream 0.35 m/s", 0.35, 0.0),
    ("upstream 0.35 m/s", 0.35, 180.0),
    ("cross 0.1 m/s", 0.1, -90.0),
)
MANOEUVRES = (  # label, example, overrides
    ("pitching down, calm", "auv_fibre_pitch_down", ()),
    ("pitching down, 0.5 m/s downstream", "auv_fibre_pitch_down", ("water.current.speed=0.5",)),
    ("zig-zag, calm", "auv_fibre_zigzag", ()),
    ("circle, 0.1 m/s current", "auv_fibre_circle", ()),
    ("circle with the anti-twining turn", "auv_fibre_circle_antitwining", ()),
    ("spiral, 0.05 m/s along +y", "auv_fibre_spiral", ()),
    ("spiral, 0.05 m/s along -y", "auv_fibre_spiral", ("water.current.heading_deg=-90.0",)),
)


def scenario(name: str, overrides=()):
    return load_scenario(EXAMPLES / f"{name}.toml", overrides=overrides)


def rows_of(sc) -> np.ndarray:
    rows, _, _ = run(sc, keep_nodes=False)
    return np.asarray(rows)


def tension_at_lengths(rows: np.ndarray, lengths=LENGTHS, window: float = 10.0) -> list[float]:
    """The tow-point tension (N) when the deployed length passes each of ``lengths`` (m): the
    mean over the samples within +-``window``/2 m of it (the free drum and the cable's axial
    mode ring a little)."""
    L, T = rows[:, COL["deployed_length"]], rows[:, COL["tow_tension"]]
    out = []
    for x in lengths:
        near = np.abs(L - x) <= window / 2
        if not near.any():
            raise RuntimeError(f"the run did not deploy {x:g} m (it reached {L.max():.0f} m)")
        out.append(float(T[near].mean()))
    return out


def straight(quick: bool) -> dict:
    """The calm straight run: tensions at 200, 500 and 1000 m, their ratio, and the tangential
    drag of the deployed fibre sliding out at 1 m/s, 1/2 rho C_dt pi d L v^2, beside them."""
    sc = scenario("auv_fibre_straight", QUICK if quick else ())
    rows = rows_of(sc)
    T = tension_at_lengths(rows)
    t = sc.tether
    drag = [0.5 * 1025.0 * t.cd_tangential * math.pi * t.diameter * L * 1.0 ** 2 + sc.winch.drum_damping * 1.0
            for L in LENGTHS]
    return {"length_m": list(LENGTHS), "tension_N": T, "ratio_1000_500": T[2] / T[1],
            "tangential_drag_N": drag, "paper_tension_1000_N": PAPER_T1000,
            "implied_cdt_d_m": 2 * PAPER_T1000 / (1025.0 * math.pi * 1000.0)}


def currents() -> list[dict]:
    """The straight run for 500 s in each of the paper's currents: tension and deployed length."""
    out = []
    for label, speed, heading in CURRENTS:
        sc = scenario("auv_fibre_straight", (f"water.current.speed={speed}", f"water.current.heading_deg={heading}",
                                             "simulation.duration=500.0"))
        rows = rows_of(sc)
        last = rows[-1]
        out.append({"case": label, "tension_N": float(last[COL["tow_tension"]]),
                    "deployed_m": float(last[COL["deployed_length"]]),
                    "robot_y_m": float(last[COL["robot_y"]])})
    return out


def manoeuvres() -> list[dict]:
    """Each manoeuvre's example: largest and final tow tension, deployed length, and the tangle
    monitor's worst moments (after the first 15 s, while the cable is shorter than the monitor's
    blind arcs)."""
    out = []
    for label, name, overrides in MANOEUVRES:
        rows = rows_of(scenario(name, overrides))
        out.append({"case": label, "example": name, **_tangle_summary(rows)})
    return out


def _tangle_summary(rows: np.ndarray) -> dict:
    T = rows[:, COL["tow_tension"]]
    late = rows[:, COL["time"]] >= MONITOR_FROM
    c, sc = rows[late, COL["cable_clearance"]], rows[late, COL["cable_self_clearance"]]
    k = int(np.argmin(c))
    return {"max_tension_N": float(T.max()), "final_tension_N": float(T[-1]),
            "deployed_m": float(rows[-1, COL["deployed_length"]]), "min_clearance_m": float(c[k]),
            "min_clearance_time_s": float(rows[late][k, COL["time"]]), "min_self_clearance_m": float(sc.min()),
            "plan_crossings": int(rows[:, COL["cable_plan_crossings"]].max())}


MONITOR_FROM = 15.0  # s: the tangle monitor's numbers are read from then on
ANGLES = (30.0, 45.0, 60.0, 90.0)  # deg: port turns before the circle (the paper gives none)


def antitwining_angles() -> list[dict]:
    """The anti-twining circle with port turns of ``ANGLES`` (3 deg/s, then the 360 deg
    starboard circle at 3 deg/s and 60 s ahead): the smallest clearance from the vehicle."""
    out = []
    for a in ANGLES:
        tp = 10.0 + a / 3.0
        path = f"[[0.0, 0.0, 0.0, 0.0], [10.0, 1.0, 0.0, 0.0], [{tp}, 1.0, {a}, 0.0], [{tp + 120.0}, 1.0, {a - 360.0}, 0.0]]"
        rows = rows_of(scenario("auv_fibre_circle_antitwining", (f"robot.path={path}",
                                                                 f"simulation.duration={tp + 180.0}")))
        out.append({"port_turn_deg": a, **_tangle_summary(rows)})
    return out


def inputs() -> dict:
    """The straight example's inputs that the page quotes (SI but the diameter, in mm)."""
    sc = scenario("auv_fibre_straight")
    t, w = sc.tether, sc.winch
    return {"speed_m_s": float(sc.robot.path[-1][1]), "diameter_mm": t.diameter * 1000, "density_kg_m3": t.density,
            "cd_normal": t.cd_normal, "cd_tangential": t.cd_tangential, "EA_N": t.EA,
            "drum_damping_N_s_m": w.drum_damping, "element_m": t.length / t.segments,
            "self_clearance_reach_m": 5 * t.length / t.segments, "monitor_from_s": MONITOR_FROM,
            "antitwining_turn_deg": float(scenario("auv_fibre_circle_antitwining").robot.path[2][2])}


def results(quick: bool) -> dict:
    """Everything the page shows: the straight run's keys at the top level (what ``--json
    --quick`` prints), and with ``quick`` false the currents, manoeuvres and port turns."""
    s = straight(quick)
    if quick:
        return s
    s = {**s, "inputs": inputs(), "currents": currents(), "manoeuvres": manoeuvres(),
         "port_turns": antitwining_angles()}
    s["implied_cdt_at_our_d"] = s["implied_cdt_d_m"] / (s["inputs"]["diameter_mm"] / 1000)
    s["implied_d_at_our_cdt_mm"] = s["implied_cdt_d_m"] / s["inputs"]["cd_tangential"] * 1000
    return s


def measured(command: str, wall_s: float) -> dict:
    """Where and when the numbers were made: make_bench_docs.py's ``measured`` block."""
    return mbd.measured_block(command, wall_s)


def write_json(result: dict, meas: dict, repro_dir: Path = REPRO_DIR) -> Path:
    repro_dir.mkdir(parents=True, exist_ok=True)
    out = repro_dir / f"{NAME}.json"
    out.write_text(json.dumps({"result": result, "measured": meas}, indent=1) + "\n")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", action="store_true", help="print the result as JSON")
    ap.add_argument("--quick", action="store_true", help="25 m elements, 0.01 s steps, the straight run only; "
                    "writes nothing")
    ap.add_argument("--render", action="store_true", help="no simulation: write the page from the committed JSON")
    ap.add_argument("--out", default=str(DOC))
    a = ap.parse_args(argv)
    if a.render:
        Path(a.out).write_text(render())
        print(f"wrote {a.out} from {mbd._rel(REPRO_DIR / f'{NAME}.json')}")
        return 0
    t0 = time.perf_counter()
    s = results(a.quick)
    wall = time.perf_counter() - t0
    if a.json:
        print(json.dumps(s, indent=1))
    else:
        _print_summary(s)
    if a.quick:
        return 0
    cmd = "python scripts/reproduce_001.py" + (" --json" if a.json else "")
    out = write_json(s, measured(cmd, wall))
    Path(a.out).write_text(render())
    print(f"wrote {mbd._rel(out)} ({wall:.0f} s) and {a.out}", file=sys.stderr if a.json else sys.stdout)
    return 0


def _print_summary(s: dict) -> None:
    print("straight, calm: tension at " + ", ".join(f"{L:g} m {T:.2f} N" for L, T in zip(LENGTHS, s["tension_N"]))
          + f"; T(1000)/T(500) = {s['ratio_1000_500']:.3f}; the paper: {PAPER_T1000} N at 1000 m")
    for c in s.get("currents", ()):
        print(f"straight 500 s, {c['case']}: {c['tension_N']:.2f} N with {c['deployed_m']:.0f} m out")
    for m in s.get("manoeuvres", ()):
        print(f"{m['case']}: tension up to {m['max_tension_N']:.2f} N, {m['final_tension_N']:.2f} N at the end "
              f"with {m['deployed_m']:.0f} m out; closest to the vehicle {m['min_clearance_m']:.2f} m")
    for g in s.get("port_turns", ()):
        print(f"anti-twining with a {g['port_turn_deg']:g} deg port turn: closest {g['min_clearance_m']:.2f} m")


def marker(key: str, fmt: str = "", repro_dir: Path = REPRO_DIR) -> str:
    """``key`` of the result (``@key``: of the measured block) as a marker holding its text."""
    ref = f"{NAME}{'' if key.startswith('@') else '.'}{key}" + (f":{fmt}" if fmt else "")
    return f"<!--repro:{ref}-->{mbd.value_of(ref, repro_dir)}<!--/repro-->"


def render(repro_dir: Path = REPRO_DIR) -> str:
    """``docs/auv_fibre_reproduction.md`` from ``docs/reproductions/auv_fibre.json``: every number
    a marker (no simulation)."""
    res = json.loads((repro_dir / f"{NAME}.json").read_text())["result"]

    def m(key, fmt=""):
        return marker(key, fmt, repro_dir)

    examples = [x["example"] for x in res["manoeuvres"]]
    plain = f"manoeuvres.{examples.index('auv_fibre_circle')}"
    k_anti = examples.index("auv_fibre_circle_antitwining")
    anti = f"manoeuvres.{k_anti}"
    verdict = "holds" if res["manoeuvres"][k_anti]["min_clearance_m"] > 0 else "fails here"
    speed = m("inputs.speed_m_s", "g")
    lines = [
        "# Reproducing the tethered AUV that pays out optical fibre",
        "",
        "Generated by `python scripts/reproduce_001.py` from `docs/reproductions/auv_fibre.json` "
        f"(made on {m('@date')} at {m('@commit')} in {m('@wall_s', '.0f')} s on a "
        f"{m('@machine.cpu_count')}-core machine); do not edit by hand.",
        "",
        "The study: a tethered-AUV model from the Australian Maritime College (its Mullaya AUV; a",
        "finite-difference cable after Ablow and Schechter, 1983, Ocean Engineering 10(6)), in which",
        "an AUV pulls an optical fibre off a drum on its ship at zero tension, the fibre inelastic,",
        "light, thin and neutrally buoyant, from nothing deployed. Its authors and year could not be",
        "recovered from the copy we worked from; its text and tables are what is quoted here. Each case",
        "is an example scenario (`examples/auv_fibre_*.toml`: `mjtether run` gives its plots,",
        "`mjtether render` its video).",
        "",
        "## Inputs and their sources",
        "",
        "| input | value | source |",
        "|---|---|---|",
        f"| vehicle motion | prescribed: {speed} m/s through the water, heading and pitch as given (`robot.path`) "
        "| the paper: \"the AUV is moving at equilibrium conditions\" |",
        "| vehicle | the REMUS 100's hull and tail tow point (Fossen's model) | the Mullaya AUV's Table I did "
        "not survive; with the motion prescribed only the tow point's place and the hull (for the tangle "
        "monitor) enter |",
        f"| fibre diameter | {m('inputs.diameter_mm', 'g')} mm | assumed (a tight-buffered fibre of that class) |",
        f"| fibre density | {m('inputs.density_kg_m3', 'g')} kg/m³ (neutral) | the paper: neutrally buoyant |",
        f"| normal drag coefficient | {m('inputs.cd_normal', 'g')} (on d l) | assumed: a circular cylinder at "
        "Re ~ 1000 |",
        f"| tangential drag coefficient | {m('inputs.cd_tangential', 'g')} (on π d l) | assumed |",
        f"| EA | {m('inputs.EA_N', 'g')} N | the paper: inelastic; 0.01 % stretch at 5 N (a hard constraint, "
        "EA = 0, rings on a prescribed tow point) |",
        f"| drum | free, {m('inputs.drum_damping_N_s_m', 'g')} N s/m, from empty | the paper: "
        "T = 0 at the drum, nothing deployed at the start |",
        f"| elements | {m('inputs.element_m', 'g')} m paid out | mjtether's choice |",
        "",
        "The paper's Table II (cable and fluid) did not survive in our copy. It takes them from Feng and",
        "Allen (2004), \"Evaluation of the effects of the communication cable on the dynamics of an",
        "underwater flight vehicle\", Ocean Engineering 31, 1019-1035 (the Subzero II vehicle), whose",
        "parameter table we could not read either. So the fibre's diameter and drag coefficients are",
        "assumed, and only the product that sets the tension matters (below).",
        "",
        "## Straight running at 1 m/s (Table III)",
        "",
        "| deployed (m) | mjtether tow tension (N) | 1/2 ρ C_dt π d L v² + drum (N) | the paper (N) |",
        "|---|---|---|---|",
    ]
    for k, L in enumerate(res["length_m"]):
        paper = m("paper_tension_1000_N", "g") if L == 1000.0 else "lost"
        lines.append(f"| {m(f'length_m.{k}', 'g')} | {m(f'tension_N.{k}', '.2f')} | "
                     f"{m(f'tangential_drag_N.{k}', '.2f')} | {paper} |")
    lines += [
        "",
        f"T(1000)/T(500) = {m('ratio_1000_500', '.3f')}. With a free drum the fibre leaves the drum at the",
        "vehicle's speed and lies straight behind it, so all of it slides along itself through the water",
        f"at {speed} m/s: the tension at the tow point is the tangential drag of the whole deployed length,",
        "growing linearly with it, plus the drum's own small pull; hence a ratio of 2 less the drum's",
        f"share. Only the product C_dt d sets the slope: the paper's {m('paper_tension_1000_N', 'g')} N at 1000 m "
        "(the one entry",
        f"of Table III that survived) means C_dt d = {m('implied_cdt_d_m', '.3g')} m, e.g. C_dt = "
        f"{m('implied_cdt_at_our_d', '.3f')} on our {m('inputs.diameter_mm', 'g')} mm fibre, or our "
        f"{m('inputs.cd_tangential', 'g')} on a {m('implied_d_at_our_cdt_mm', '.1f')} mm cable. Our assumed "
        f"fibre gives {m('tension_N.2', '.2f')} N; the difference is the fibre, not the physics.",
        "",
        "## Straight running in the paper's currents (500 s)",
        "",
        "| current | tow tension (N) | deployed (m) | sideways drift of the vehicle (m) |",
        "|---|---|---|---|",
    ]
    for k in range(len(res["currents"])):
        c = f"currents.{k}"
        lines.append(f"| {m(c + '.case')} | {m(c + '.tension_N', '.2f')} | {m(c + '.deployed_m', '.0f')} "
                     f"| {m(c + '.robot_y_m', '.1f')} |")
    lines += [
        "",
        "A current along the track carries the vehicle and the fibre alike: the fibre still slides",
        f"through the water at {speed} m/s, so its tension per metre is unchanged and only the deployed",
        "length differs (more with the current, less against it). The paper calls the current that",
        "raises the tension \"upstream\" and explains it by the vehicle's \"absolute velocity increased by",
        "the current\": that is the current along the track, our \"downstream\". A cross current carries",
        "the vehicle and the fibre sideways together; only near the fixed drum does the fibre cross the",
        "flow, and the tension at the tow point is that of calm water, as the paper finds (\"similar to",
        "the one in calm water\").",
        "",
        "## Manoeuvres",
        "",
        "| case | largest tow tension (N) | at the end (N) | deployed (m) | closest to the vehicle (m) "
        "| closest to itself (m) | plan crossings |",
        "|---|---|---|---|---|---|---|",
    ]
    for k in range(len(res["manoeuvres"])):
        c = f"manoeuvres.{k}"
        lines.append(f"| {m(c + '.case')} | {m(c + '.max_tension_N', '.2f')} | {m(c + '.final_tension_N', '.2f')} "
                     f"| {m(c + '.deployed_m', '.0f')} | {m(c + '.min_clearance_m', '.2f')} "
                     f"| {m(c + '.min_self_clearance_m', '.2f')} | {m(c + '.plan_crossings')} |")
    lines += [
        "",
        f"(Clearances from {m('inputs.monitor_from_s', 'g')} s on, from the tangle monitor: `cable_clearance_m`, "
        "`cable_self_clearance_m`,",
        "`cable_plan_crossings` in `timeseries.csv`. A negative clearance is the cable through the hull,",
        "which mjtether does not stop: it has no contact between cable and vehicle. The cable's",
        f"clearance from itself is looked for up to five elements, {m('inputs.self_clearance_reach_m', 'g')} m: "
        "farther shows as that.)",
        "",
        "## The circle and the anti-twining manoeuvre",
        "",
        "Without the manoeuvre the vehicle's smallest clearance from its fibre is "
        f"{m(plain + '.min_clearance_m', '.2f')} m "
        f"(at {m(plain + '.min_clearance_time_s', '.0f')} s, as it comes back over the drum; below 0: through it); "
        f"with a {m('inputs.antitwining_turn_deg', 'g')}° port turn first, "
        f"{m(anti + '.min_clearance_m', '.2f')} m (the paper's claim "
        f"{verdict}). "
        "The paper gives no angle, "
        "and the result depends on it:",
        "",
        "| port turn (deg) | closest to the vehicle (m) | at (s) |",
        "|---|---|---|",
    ]
    for k in range(len(res["port_turns"])):
        g = f"port_turns.{k}"
        lines.append(f"| {m(g + '.port_turn_deg', 'g')} | {m(g + '.min_clearance_m', '.2f')} "
                     f"| {m(g + '.min_clearance_time_s', '.0f')} |")
    lines += [
        "",
        "Why: a neutrally buoyant fibre moves with the water, as the vehicle does, so in a uniform",
        "current their relative geometry is that of still water except at the drum, which stays put",
        "over the ground while the water passes it. The fibre from the drum to the start of the circle",
        "is what the returning vehicle can meet; a port turn first moves the circle off that line, but a",
        "larger one brings the closing part of the circle back across the earlier fibre. The",
        "heading profiles here are assumed (the paper's Figs. 10-13 did not survive); the tangle",
        "monitor reports the clearances for any other.",
        "",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())

"""Reproduce the water-tank test of Hong, Park, Lee, Park and Kim (2020), "Dynamics Modeling and
Motion Simulation of USV/UUV with Linked Underwater Cable", J. Mar. Sci. Eng. 8(5), 485: its
Table 2 cable, one end fixed, the UUV's weight at the other, in a current of 0 to 1 m/s, and its
Table 3 (tension and lay-back angle, their simulation and their experiment).

For each current this prints the steady tension at the fixed end (top) and at the UUV (bottom)
in kgf, and the lay-back angle from the vertical at the top, of the chord (top to UUV) and at the
UUV, beside the paper's two columns, settles the same case in MuJoCo (``mujoco_case``) for a
third column, and writes ``docs/hong2020_reproduction.md``. ``--json`` prints the quasi-static
results as JSON (add ``--dynamic`` for MuJoCo's); ``--quick`` prints the table only.

The inputs (nothing is fitted to Table 3):

* the cable of Table 2: 3 m, d = 0.025 m, 3121 kg/m^3, C_d = 2.5 on the diameter, 20 nodes, with
  the paper's own drag law, its Eq. 20-21 (``tether.drag_law = "loading_functions"``: the one C_d
  scaled by loading functions of the flow's angle to the cable, a tangential term included); the "effective modulus of elasticity
  7.5 x 10^6 GPa" is read as EA = 7.5e6 N (as a modulus, 7.5e15 Pa, it is no material; as EA it
  is a 25 mm armoured cable's order of magnitude); at these loads the cable stretches by 2e-5,
  so the reading does not show; the cable damping (100 N s) does not enter a steady state;
* the UUV of Table 4: 12 kgf in water ("12 kg (in water)"); its drag, which the paper does not
  give, that of a torpedo of its 0.25 x 0.25 m section lying along the current: C_d 0.42 on its
  frontal area (Allen et al. 2000's value for the REMUS hull, as Fossen uses it);
* fresh water of 1000 kg/m^3 (a water tank; the paper gives no density), uniform current over
  the 3 m.

``static_case(current, drag_law="morison", rho=1025.0)`` gives the earlier reading (the
cross-flow principle with no tangential drag, in sea water) for comparison.

Readings argued in ``docs/hong2020_reproduction.md``: the tension meter at the UUV end (the
paper's own simulation reports "the force acting on the last node", 11.39 kgf in still water,
the UUV's weight, not the 15.1 kgf at the fixed end), and the lay-back angle of the chord (a
camera's view of the whole cable).

    python scripts/reproduce_hong2020.py [--json [--dynamic]] [--quick] [--out docs/hong2020_reproduction.md]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

import mjtether as mt
from mjtether.quasistatic.steady import steady_state

KGF = 9.80665  # N
RHO, G = 1000.0, 9.81  # fresh water in the tank
DRAG_LAW = "loading_functions"  # the paper's Eq. 20-21
CURRENTS = (0.0, 0.3, 0.5, 0.7, 1.0)  # m/s, Table 3

LENGTH, DIAMETER, DENSITY, CD_NORMAL, NODES, EA = 3.0, 0.025, 3121.0, 2.5, 20, 7.5e6
UUV_WEIGHT = 12.0 * KGF  # N, in water
UUV_CD, UUV_AREA = 0.42, 0.25 * 0.25 * math.pi / 4  # on its frontal area (m^2)

# Table 3 of the paper: (simulation, experiment)
PAPER_TENSION_KGF = {"simulation": [11.39, 13.13, 13.91, 14.20, 16.53],
                     "experiment": [13.06, 13.10, 13.15, 14.05, 17.99]}
PAPER_LAYBACK_DEG = {"simulation": [0.0, 2.25, 6.62, 9.29, 14.78],
                     "experiment": [0.23, 2.43, 8.78, 11.85, 16.14]}


def tether(drag_law: str = DRAG_LAW) -> mt.TetherSpec:
    """The cable of Table 2 (20 nodes: 19 elements), no tangential C_dt of its own (the paper
    gives one C_d; its loading functions carry the tangential drag)."""
    return mt.TetherSpec(length=LENGTH, segments=NODES - 1, diameter=DIAMETER, density=DENSITY,
                         cd_normal=CD_NORMAL, cd_tangential=0.0, EA=EA, drag_law=drag_law)


def water(current: float, rho: float = RHO) -> mt.WaterColumn:
    return mt.WaterColumn(depth=10.0, density=mt.ConstantDensity(rho), gravity=G,
                          current=mt.ConstantCurrent(current))


def uuv_drag(current: float, rho: float = RHO) -> float:
    """The UUV's drag along the current (N)."""
    return 0.5 * rho * current * current * UUV_CD * UUV_AREA


def _angle(v) -> float:
    """Angle of a vector from the vertical in the x-z plane (deg)."""
    return math.degrees(math.atan2(abs(v[0]), abs(v[2])))


def static_case(current: float, drag_law: str = DRAG_LAW, rho: float = RHO) -> dict:
    """The steady state by the quasi-static solver, marched up from the UUV (the cable holds it
    against its weight and its drag): tensions (kgf) and angles (deg)."""
    ss = steady_state(tether(drag_law), water(current, rho), None, [0.0, 0.0, -5.0],
                      bottom_force=[-uuv_drag(current, rho), 0.0, UUV_WEIGHT], seabed=False)
    X = ss.nodes
    return {"tension_top_kgf": ss.top_tension / KGF, "tension_bottom_kgf": ss.tow_tension / KGF,
            "layback_top_deg": _angle(X[1] - X[0]), "layback_chord_deg": _angle(X[-1] - X[0]),
            "layback_bottom_deg": _angle(X[-1] - X[-2]), "height_m": float(X[0, 2] - X[-1, 2]),
            "nodes": X}


def mujoco_case(current: float, duration: float = 40.0, dt: float = 0.002) -> dict:
    """The same case settled in MuJoCo: the cable from a fixed point to a 12 kg body (no
    displaced volume: 12 kgf in water) with the UUV's drag along x, released hanging straight
    down; after ``duration`` s, the tensions at both ends (kgf) and the chord angle (deg)."""
    import mujoco

    top = np.array([0.0, 0.0, -1.0])
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, -G]
    body = spec.worldbody.add_body(name="uuv", pos=list(top - [0.0, 0.0, LENGTH]))
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.1, 0, 0], mass=UUV_WEIGHT / G,
                  contype=0, conaffinity=0)
    w = water(current)
    hydro = mt.add_body_hydro(spec, "uuv", mt.RigidBodyHydro(
        volume=0.0, drag_cd=(UUV_CD, 0.0, 0.0), drag_area=(UUV_AREA, 0.0, 0.0), angular_drag=(1.0, 1.0, 1.0)))
    tm = mt.add_tether(spec, tether(), mt.FixedPoint(top), mt.BodyPoint("uuv"), water=w)
    with mt.Simulation(spec, w, [tm], [hydro]) as sim:
        sim.run(duration)
        t = sim.tether()
        f_top = np.linalg.norm(t.end_force(sim.data, "start"))
        f_bot = np.linalg.norm(t.end_force(sim.data, "end"))
        p = sim.data.xpos[sim.model.body("uuv").id]
    return {"tension_top_kgf": f_top / KGF, "tension_bottom_kgf": f_bot / KGF,
            "layback_chord_deg": _angle(p - top)}


PLATFORM = Path(__file__).resolve().parents[1] / "examples" / "hong2020_platform.toml"
PLATFORM_CASES = (  # label, USV speed, UUV speed (m/s), current (m/s), its heading (deg; the track is 0)
    ("Case 5: stationary", 0.0, 0.0, 0.0, 0.0),
    ("Case 6: both at 0.5 m/s", 0.5, 0.5, 0.0, 0.0),
    ("Case 6 in a 0.3 m/s cross current", 0.5, 0.5, 0.3, 90.0),
    ("Case 7: USV 0.5 m/s, UUV 0.3 m/s", 0.5, 0.3, 0.0, 0.0),
    ("both at 0.6 m/s", 0.6, 0.6, 0.0, 0.0),
)
FAST = "both at 0.6 m/s"  # the row that shows the UUV's pitch instability


def platform_case(usv_speed: float, uuv_speed: float, current: float, heading: float,
                  max_duration: float = 300.0, window: float = 10.0) -> dict:
    """``examples/hong2020_platform.toml`` with the given speeds and current (heading in deg),
    run until settled: every ``window`` s the state is compared with the one a window before, and
    the run stops once the UUV's depth has moved under 1 mm, its roll and pitch under 0.05 deg and
    every cable force component under 0.1 N (``settled_s``: that time), or at ``max_duration``
    (``settled_s`` None: the row is a transient). Returns the cable's force on the USV (N, world:
    x along the track, y to port, z up) and on the UUV (N, its body frame), the UUV's depth (m),
    its roll and pitch (deg, pitch > 0 nose down), its speed (m/s) and the surface events."""
    from mjtether.scenario import load_scenario
    from mjtether.scenario.runner import ScenarioRun, SurfaceWatch

    sc = load_scenario(PLATFORM, overrides=(f"simulation.duration={max_duration}", f"ship.speed={usv_speed}",
                                             f"robot.setpoints=[[0.0, {uuv_speed}, 0.0, 3.0]]",
                                             f"water.current.speed={current}",
                                             f"water.current.heading_deg={heading}"))
    run = ScenarioRun(sc)
    surface = SurfaceWatch(run.vehicle, stop=False)  # (checked at every step)

    def state() -> dict:
        n = run.named
        roll, pitch = n.robot_roll_pitch
        return {"usv_force_N": n.ship_force.tolist(), "uuv_force_body_N": n.tow_force_body.tolist(),
                "uuv_depth_m": float(-n.robot_position[2]), "uuv_roll_deg": math.degrees(roll),
                "uuv_pitch_deg": math.degrees(pitch), "uuv_speed_mps": float(n.robot_speed)}

    try:
        per_window = int(round(window / sc.simulation.timestep))
        last, settled, t = None, None, 0.0
        while t < max_duration - 1e-9 and settled is None:
            for _ in range(per_window):
                run.step()
                surface.check(run)
            t += window
            now = state()
            if last is not None and (
                    abs(now["uuv_depth_m"] - last["uuv_depth_m"]) < 1e-3
                    and abs(now["uuv_roll_deg"] - last["uuv_roll_deg"]) < 0.05
                    and abs(now["uuv_pitch_deg"] - last["uuv_pitch_deg"]) < 0.05
                    and np.max(np.abs(np.subtract(now["usv_force_N"] + now["uuv_force_body_N"],
                                                  last["usv_force_N"] + last["uuv_force_body_N"]))) < 0.1):
                settled = t
            last = now
        return {**now, "settled_s": settled, "time_s": t,
                "surface_events": surface.events}
    finally:
        run.close()


def table(dynamic: bool = False) -> dict:
    rows = [static_case(u) for u in CURRENTS]
    out = {"current_mps": list(CURRENTS),
           "tension_kgf": [r["tension_bottom_kgf"] for r in rows],
           "layback_deg": [r["layback_chord_deg"] for r in rows]}
    for key in ("tension_top_kgf", "tension_bottom_kgf", "layback_top_deg", "layback_chord_deg",
                "layback_bottom_deg"):
        out[key] = [r[key] for r in rows]
    out["paper_simulation_tension_kgf"] = PAPER_TENSION_KGF["simulation"]
    out["paper_experiment_tension_kgf"] = PAPER_TENSION_KGF["experiment"]
    out["paper_simulation_layback_deg"] = PAPER_LAYBACK_DEG["simulation"]
    out["paper_experiment_layback_deg"] = PAPER_LAYBACK_DEG["experiment"]
    e = np.array(out["layback_deg"]) - PAPER_LAYBACK_DEG["experiment"]
    out["layback_worst_deg"] = float(np.abs(e).max())
    out["layback_rms_deg"] = float(np.sqrt(np.mean(e ** 2)))
    out["tension_worst_0_to_0p5_kgf"] = float(max(abs(a - b) for a, b, u in zip(
        out["tension_kgf"], PAPER_TENSION_KGF["experiment"], CURRENTS) if u <= 0.5))
    # the earlier reading, for comparison: the cross-flow principle (no tangential drag) in sea water
    e = np.array([static_case(u, "morison", 1025.0)["layback_chord_deg"] for u in CURRENTS]) - PAPER_LAYBACK_DEG["experiment"]
    out["morison_sea_layback_worst_deg"] = float(np.abs(e).max())
    out["morison_sea_layback_rms_deg"] = float(np.sqrt(np.mean(e ** 2)))
    # what the loading functions' tangential drag adds to the tension's rise up the cable (kgf)
    w = (DENSITY - RHO) * G * math.pi / 4 * DIAMETER ** 2
    out["tangential_rise_kgf"] = [r["tension_top_kgf"] - r["tension_bottom_kgf"] - w * r["height_m"] / KGF for r in rows]
    if dynamic:
        dyn = [mujoco_case(u) for u in CURRENTS]
        for key in ("tension_top_kgf", "tension_bottom_kgf", "layback_chord_deg"):
            out[f"mujoco_{key}"] = [d[key] for d in dyn]
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", action="store_true", help="print the results as JSON (nothing written)")
    ap.add_argument("--dynamic", action="store_true", help="with --json: also settle each case in MuJoCo")
    ap.add_argument("--quick", action="store_true", help="the quasi-static table only; nothing written")
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs" / "hong2020_reproduction.md"))
    a = ap.parse_args(argv)
    if a.json:
        print(json.dumps(table(a.dynamic), indent=1))
        return 0
    out = table(dynamic=not a.quick)
    platform = [] if a.quick else [(label, platform_case(*args)) for label, *args in PLATFORM_CASES]
    print("current  tension (kgf): top  bottom | paper sim  exp   lay-back (deg): top  chord  bottom | paper sim  exp")
    for k, u in enumerate(CURRENTS):
        print(f"{u:5.1f}     {out['tension_top_kgf'][k]:12.2f} {out['tension_bottom_kgf'][k]:7.2f} | "
              f"{PAPER_TENSION_KGF['simulation'][k]:9.2f} {PAPER_TENSION_KGF['experiment'][k]:5.2f}   "
              f"{out['layback_top_deg'][k]:15.2f} {out['layback_chord_deg'][k]:6.2f} "
              f"{out['layback_bottom_deg'][k]:7.2f} | {PAPER_LAYBACK_DEG['simulation'][k]:9.2f} "
              f"{PAPER_LAYBACK_DEG['experiment'][k]:5.2f}")
    print(f"lay-back (chord) against the experiment: worst {out['layback_worst_deg']:.2f} deg, "
          f"RMS {out['layback_rms_deg']:.2f} deg; tension at 0-0.5 m/s: worst {out['tension_worst_0_to_0p5_kgf']:.2f} kgf")
    for label, r in platform:
        print(f"{label}: cable on the USV {np.round(r['usv_force_N'], 1)} N, on the UUV (body) "
              f"{np.round(r['uuv_force_body_N'], 1)} N; UUV at {r['uuv_depth_m']:.2f} m, roll {r['uuv_roll_deg']:.1f} deg, "
              f"pitch {r['uuv_pitch_deg']:.1f} deg, {r['uuv_speed_mps']:.2f} m/s")
    if not a.quick:
        write_report(Path(a.out), out, platform)
        print(f"wrote {a.out}")
    return 0


def _f(x: float) -> str:
    """One decimal, without a minus on a rounded zero."""
    return f"{round(x, 1) + 0.0:.1f}"


DRIFT_MARK = "<!-- scripts/hong2020_drift.py: begin -->"
"""Where ``scripts/hong2020_drift.py``'s section of the page begins (this script keeps it)."""


def write_report(path: Path, out: dict, platform=()) -> None:
    """``docs/hong2020_reproduction.md`` from ``table(dynamic=True)``'s and ``platform_case``'s
    results."""
    exp_t, exp_a = PAPER_TENSION_KGF["experiment"], PAPER_LAYBACK_DEG["experiment"]
    sim_t, sim_a = PAPER_TENSION_KGF["simulation"], PAPER_LAYBACK_DEG["simulation"]
    k7, k10 = CURRENTS.index(0.7), CURRENTS.index(1.0)
    k5 = CURRENTS.index(0.5)
    low = max(abs(out["layback_chord_deg"][k] - exp_a[k]) for k in range(k7 + 1))
    tan_ratio = math.tan(math.radians(exp_a[k10])) / math.tan(math.radians(exp_a[k5]))
    lines = [
        "# Reproducing Hong et al. (2020): the cable in the water tank",
        "",
        "Generated by `python scripts/reproduce_hong2020.py`; do not edit by hand.",
        "",
        "Hong, Park, Lee, Park and Kim (2020), \"Dynamics Modeling and Motion Simulation of USV/UUV with",
        "Linked Underwater Cable\", J. Mar. Sci. Eng. 8(5), 485: a 3 m cable fixed at one end holds the",
        "UUV's weight at the other in a current of 0 to 1 m/s; their Table 3 gives the tension and the",
        "lay-back angle, simulated and measured.",
        "",
        "## Inputs and their sources",
        "",
        "| input | value | source |",
        "|---|---|---|",
        f"| cable length, diameter | {LENGTH:g} m, {DIAMETER:g} m | Table 2 |",
        f"| cable density | {DENSITY:g} kg/m³ | Table 2 |",
        f"| normal drag coefficient | {CD_NORMAL:g} (on the diameter) | Table 2 |",
        "| drag law | the paper's Eq. 20-21 (`tether.drag_law = \"loading_functions\"`): C_d on d l scaled by "
        "f_p(η) across and f_p3(η) along the cable, η the flow's angle to it | Eq. 20-21 |",
        f"| nodes | {NODES} ({NODES - 1} elements) | Table 2 |",
        f"| EA | {EA:g} N | Table 2's \"effective modulus of elasticity 7.5 × 10⁶ GPa\" read as EA: as a "
        "modulus (7.5e15 Pa) it is no material; the cable then stretches by 2e-5, so the reading does not show |",
        "| cable damping 100 N s | not used | does not enter a steady state |",
        "| UUV in water | 12 kgf | Table 4, \"12 kg (in water)\" |",
        f"| UUV drag | C_d {UUV_CD:g} on its {UUV_AREA:.4f} m² frontal area, lying along the current | not given; "
        "a torpedo hull's axial drag (Allen et al. 2000, the REMUS 100, as Fossen 2021 uses it) |",
        f"| water | fresh, {RHO:g} kg/m³; g = {G:g} m/s²; current uniform over the depth | a water tank; "
        "no density given |",
        "",
        "## Table 3 side by side",
        "",
        "Tensions in kgf, angles in degrees from the vertical. Ours: the quasi-static solver",
        "(`steady_state`, marched up from the UUV) and, in brackets, MuJoCo settled for 40 s.",
        "",
        "| current (m/s) | tension at UUV | tension at fixed end | paper sim. | paper exp. "
        "| angle at top | chord angle | angle at UUV | paper sim. | paper exp. |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for k, u in enumerate(CURRENTS):
        dyn = (f" ({out['mujoco_tension_bottom_kgf'][k]:.2f})", f" ({out['mujoco_tension_top_kgf'][k]:.2f})",
               f" ({out['mujoco_layback_chord_deg'][k]:.2f})") if "mujoco_tension_top_kgf" in out else ("", "", "")
        lines.append(f"| {u:.1f} | {out['tension_bottom_kgf'][k]:.2f}{dyn[0]} | {out['tension_top_kgf'][k]:.2f}{dyn[1]} "
                     f"| {sim_t[k]:.2f} | {exp_t[k]:.2f} | {out['layback_top_deg'][k]:.2f} "
                     f"| {out['layback_chord_deg'][k]:.2f}{dyn[2]} | {out['layback_bottom_deg'][k]:.2f} "
                     f"| {sim_a[k]:.2f} | {exp_a[k]:.2f} |")
    lines += [
        "",
        f"Against the experiment, reading the tension at the UUV and the chord's angle: tension within "
        f"{out['tension_worst_0_to_0p5_kgf']:.2f} kgf from 0 to 0.5 m/s; lay-back angle "
        f"{out['layback_worst_deg']:.2f}° at worst (at 1.0 m/s) and {out['layback_rms_deg']:.2f}° RMS over the five "
        "currents. The paper's own simulation differs from its experiment by up to 1.67 kgf and 2.56°; we "
        "aimed at that tension difference and at 5° worst, 3° RMS for the angle: "
        + ("both are met." if out["layback_worst_deg"] <= 5.0 and out["layback_rms_deg"] <= 3.0 else
           "the tension meets it, the angle does not (below).")
        + f" The earlier reading, the cross-flow principle with no tangential drag in sea water of 1025 kg/m³, "
        f"gave {out['morison_sea_layback_worst_deg']:.2f}° worst and {out['morison_sea_layback_rms_deg']:.2f}° RMS.",
        "",
        "## The readings",
        "",
        "* **Where the tension is measured.** The paper puts its tension meter \"at the end of the cable\"",
        "  and its simulation reports \"the force acting on the last node\", 11.39 kgf in still water: the",
        f"  UUV's 12 kgf, not the {out['tension_top_kgf'][0]:.2f} kgf the fixed end carries (the UUV and the "
        f"cable's {out['tension_top_kgf'][0] - out['tension_bottom_kgf'][0]:.2f} kgf). So the",
        "  UUV end. The experiment's 13.06 kgf in still water is 1.06 kgf above the UUV's weight (a meter",
        "  or shackle in the water, or a UUV a little heavier than its nominal 12 kg, would do it).",
        "* **Which angle.** A camera sees the whole cable; the lay-back angle of a nearly straight cable is",
        "  that of its chord, from the fixed end to the UUV. The angles at the ends are in the table too.",
        "",
        "## What the stated inputs cannot give",
        "",
        "A cable whose drag is normal to it changes its tension only by its own weight: T_top = T_bottom",
        "+ w h (w its submerged weight per metre, h the height between its ends), and at the UUV",
        "T_bottom = √(W² + D²) with W = 12 kgf and the UUV's small drag D (`tests/papers/test_hong2020.py` checks",
        "both). The paper's tangential loading function adds "
        f"{max(out['tangential_rise_kgf']):.2f} kgf to that rise at most (at 1.0 m/s). "
        "The tension anywhere on the cable therefore lies between about 12.0 and 15.1 kgf at every",
        "current. The experiment is inside that band up to 0.7 m/s "
        f"({exp_t[k7]:.2f} kgf at 0.7 m/s: {exp_t[k7] - out['tension_bottom_kgf'][k7]:+.2f} kgf on our UUV-end "
        f"value, {exp_t[k7] - out['tension_top_kgf'][k7]:+.2f} kgf on the fixed end's) but not at 1.0 m/s: "
        f"{exp_t[k10]:.2f} kgf is {exp_t[k10] - out['tension_bottom_kgf'][k10]:+.2f} kgf above our UUV-end tension "
        f"and {exp_t[k10] - out['tension_top_kgf'][k10]:+.2f} kgf above the largest tension on the cable. No steady",
        "state of these inputs reaches it. What could: an unsteady load (at 1 m/s the 25 mm cable sheds",
        "vortices at about 8 Hz, St = 0.2, and the hanging UUV may swing or kite), a meter reading peaks",
        "rather than means, or more drag on the UUV than a streamlined body has (a UUV turned across the",
        "flow: about 0.45 m² of side area). None is stated; none is assumed here.",
        "",
        f"The measured angle grows more slowly than quadratic drag allows: from 0.5 to 1.0 m/s the dynamic",
        f"pressure grows fourfold but tan(angle) only {tan_ratio:.2f}-fold. For a cable and a body whose weights",
        "do not change, tan(angle) grows with U² at small angles, so no fixed drag coefficient matches both",
        f"ends of the range: with the stated C_d = 2.5 and the paper's loading functions the chord is within "
        f"{low:.1f}° of the measurement from 0 to 0.7 m/s and {out['layback_chord_deg'][k10] - exp_a[k10]:+.1f}° "
        "off at 1.0 m/s. (A circular",
        "cylinder at these Reynolds numbers, 7,000 to 25,000, has C_d about 1.2, half the stated value;",
        "with it every angle would be low, 1.0 m/s's included. It is not used: nothing here is fitted.)",
        "",
        "The paper's own simulation column is not a steady state of its stated inputs either: it starts",
        "below the UUV's weight (11.39 kgf) and rises 1.74 kgf by 0.3 m/s, where the drag on this cable and",
        "body changes the tension at either end by under 0.1 kgf.",
        "",
        "Which numbers to trust: for these inputs, ours (the quasi-static march and MuJoCo's settled",
        "state agree to 0.1 % and 0.02°; the march agrees with a continuous cable of the same law,",
        "integrated by SciPy in the test, to 1e-4 in tension and 0.01° in angle). For the real cable at",
        "1 m/s, the measurement: it holds something the stated inputs leave out.",
        "",
        "## The full platform",
        "",
        "`examples/hong2020_platform.toml`: the paper's USV tows its UUV through 3 m of the Table 2",
        "cable, the UUV hanging 3 m below the USV's stern (their Cases 5-7), each on its own thrusters.",
        "The vehicles are readings of the paper (its hydrodynamic coefficients are unpublished; see",
        "`docs/vehicles.md`). The run records the cable's force on both vehicles (`ship_force_*`,",
        "`tow_force_body_*` in `timeseries.csv`) and the UUV's depth and attitude. Each case runs until",
        "settled (every 10 s its state is compared with the one 10 s before: the UUV's depth within 1 mm,",
        "its roll and pitch within 0.05°, every cable force within 0.1 N; the time is in the last column);",
        "a case still changing at 300 s is marked as a transient, with its state then. The cable is the",
        "tank's, with the paper's drag law; the water is sea water (1025 kg/m³, the platform's; the UUV",
        "file is trimmed for it).",
        "",
        "| case | cable on the USV (N: along track, to port, up) | cable on the UUV (N, its body: forward, "
        "to port, up) "
        "| UUV depth (m) | UUV roll, pitch (deg, pitch > 0 nose down) | UUV speed (m/s) | settled by |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, r in platform:
        f, b = r["usv_force_N"], r["uuv_force_body_N"]
        when = (f"{r['settled_s']:.0f} s" if r["settled_s"] is not None else
                f"**transient**: still changing at {r['time_s']:.0f} s")
        if r["surface_events"]:
            when += f"; broke the surface at {r['surface_events'][0]['time_s']:.0f} s"
        lines.append(f"| {label} | {_f(f[0])}, {_f(f[1])}, {_f(f[2])} | {_f(b[0])}, {_f(b[1])}, {_f(b[2])} "
                     f"| {r['uuv_depth_m']:.2f} | {_f(r['uuv_roll_deg'])}, {_f(r['uuv_pitch_deg'])} "
                     f"| {r['uuv_speed_mps']:.2f} | {when} |")
    rows = dict(platform)
    lines += [
        "",
        "As in the paper's Case 5, at rest the cable holds the UUV's weight in water and nothing else",
        "(12 kgf = 117.7 N; the paper's text says \"12 N\", its tank test and Table 4 12 kgf). Running",
        "together at the same speed the cable pulls the USV back by the cable's own drag and the UUV",
        "trims nose up; a cross current sets the cable and the UUV's pull sideways; a slower UUV (Case",
        "7) is towed along at the USV's speed and pulled up by the cable, nose down.",
    ]
    fast = rows.get(FAST)
    if fast is not None:
        if fast["surface_events"]:
            what = (f"it holds its depth for a while, then pitches up and climbs, and breaks the surface at "
                    f"{fast['surface_events'][0]['time_s']:.0f} s; a run logs that in `summary.json` under "
                    "`run.surface_events`, and `robot.stop_at_surface` ends it there")
        elif fast["settled_s"] is None:
            what = f"it is still pitching at {fast['time_s']:.0f} s ({_f(fast['uuv_pitch_deg'])}°)"
        else:
            what = f"it settles at {_f(fast['uuv_pitch_deg'])}° pitch"
        lines += [
            "The paper's Case 6 speed is not stated; 0.5 m/s is used because this finless UUV is unstable in",
            f"pitch at 0.6 m/s: {what}. Its Munk moment, (Z_wdot - X_udot) u w, outgrows the restoring",
            "moment of its weight (BG = 0.0196 m) and of the cable's pull at its tying point. The paper's",
            "model, with REMUS coefficients that carry fins, shows no such instability.",
        ]
    lines.append("")
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    old = path.read_text() if path.exists() else ""
    drift = old.find(DRIFT_MARK)  # (the drift case's section, scripts/hong2020_drift.py's, is kept)
    tmp.write_text("\n".join(lines) + ("\n" + old[drift:] if drift >= 0 else ""))
    tmp.replace(path)


if __name__ == "__main__":
    sys.exit(main())

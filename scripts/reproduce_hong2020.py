"""Reproduce the water-tank test of Hong, Park, Lee, Park and Kim (2020), "Dynamics Modeling and
Motion Simulation of USV/UUV with Linked Underwater Cable", J. Mar. Sci. Eng. 8(5), 485: its
Table 2 cable, one end fixed, the UUV's weight at the other, in a current of 0 to 1 m/s, and its
Table 3 (tension and lay-back angle, their simulation and their experiment).

For each current this prints the steady tension at the fixed end (top) and at the UUV (bottom)
in kgf, and the lay-back angle from the vertical at the top, of the chord (top to UUV) and at the
UUV, beside the paper's two columns. ``--json`` prints them as JSON; ``--dynamic`` also settles
the same case in MuJoCo (``mujoco_case``) and prints its tensions and chord angle.

The inputs (nothing is fitted to Table 3):

* the cable of Table 2: 3 m, d = 0.025 m, 3121 kg/m^3, C_d = 2.5 on the diameter (normal flow;
  the paper gives no tangential coefficient: 0), 20 nodes; the "effective modulus of elasticity
  7.5 x 10^6 GPa" is read as EA = 7.5e6 N (as a modulus, 7.5e15 Pa, it is no material; as EA it
  is a 25 mm armoured cable's order of magnitude); at these loads the cable stretches by 2e-5,
  so the reading does not show; the cable damping (100 N s) does not enter a steady state;
* the UUV of Table 4: 12 kgf in water ("12 kg (in water)"); its drag, which the paper does not
  give, that of a torpedo of its 0.25 x 0.25 m section lying along the current: C_d 0.42 on its
  frontal area (Allen et al. 2000's value for the REMUS hull, as Fossen uses it);
* sea water of 1025 kg/m^3 (the paper gives none), uniform current over the 3 m.

Readings argued in ``docs/hong2020_reproduction.md``: the tension meter at the UUV end (the
paper's own simulation reports "the force acting on the last node", 11.39 kgf in still water,
the UUV's weight, not the 15.1 kgf at the fixed end), and the lay-back angle of the chord (a
camera's view of the whole cable).

    python scripts/reproduce_hong2020.py [--json] [--dynamic]
"""

from __future__ import annotations

import argparse
import json
import math
import sys

import numpy as np

import mjtether as mt
from mjtether.quasistatic.steady import steady_state

KGF = 9.80665  # N
RHO, G = 1025.0, 9.81
CURRENTS = (0.0, 0.3, 0.5, 0.7, 1.0)  # m/s, Table 3

LENGTH, DIAMETER, DENSITY, CD_NORMAL, NODES, EA = 3.0, 0.025, 3121.0, 2.5, 20, 7.5e6
UUV_WEIGHT = 12.0 * KGF  # N, in water
UUV_CD, UUV_AREA = 0.42, 0.25 * 0.25 * math.pi / 4  # on its frontal area (m^2)

# Table 3 of the paper: (simulation, experiment)
PAPER_TENSION_KGF = {"simulation": [11.39, 13.13, 13.91, 14.20, 16.53],
                     "experiment": [13.06, 13.10, 13.15, 14.05, 17.99]}
PAPER_LAYBACK_DEG = {"simulation": [0.0, 2.25, 6.62, 9.29, 14.78],
                     "experiment": [0.23, 2.43, 8.78, 11.85, 16.14]}


def tether(cd_tangential: float = 0.0) -> mt.TetherSpec:
    """The cable of Table 2 (20 nodes: 19 elements)."""
    return mt.TetherSpec(length=LENGTH, segments=NODES - 1, diameter=DIAMETER, density=DENSITY,
                         cd_normal=CD_NORMAL, cd_tangential=cd_tangential, EA=EA)


def water(current: float) -> mt.WaterColumn:
    return mt.WaterColumn(depth=10.0, density=mt.ConstantDensity(RHO), gravity=G,
                          current=mt.ConstantCurrent(current))


def uuv_drag(current: float) -> float:
    """The UUV's drag along the current (N)."""
    return 0.5 * RHO * current * current * UUV_CD * UUV_AREA


def _angle(v) -> float:
    """Angle of a vector from the vertical in the x-z plane (deg)."""
    return math.degrees(math.atan2(abs(v[0]), abs(v[2])))


def static_case(current: float, cd_tangential: float = 0.0) -> dict:
    """The steady state by the quasi-static solver, marched up from the UUV (the cable holds it
    against its weight and its drag): tensions (kgf) and angles (deg)."""
    ss = steady_state(tether(cd_tangential), water(current), None, [0.0, 0.0, -5.0],
                      bottom_force=[-uuv_drag(current), 0.0, UUV_WEIGHT], seabed=False)
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
    if dynamic:
        dyn = [mujoco_case(u) for u in CURRENTS]
        for key in ("tension_top_kgf", "tension_bottom_kgf", "layback_chord_deg"):
            out[f"mujoco_{key}"] = [d[key] for d in dyn]
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", action="store_true", help="print the results as JSON")
    ap.add_argument("--dynamic", action="store_true", help="also settle each case in MuJoCo (about a minute)")
    a = ap.parse_args(argv)
    out = table(a.dynamic)
    if a.json:
        print(json.dumps(out, indent=1))
        return 0
    print("current  tension (kgf): top  bottom | paper sim  exp   lay-back (deg): top  chord  bottom | paper sim  exp")
    for k, u in enumerate(CURRENTS):
        print(f"{u:5.1f}     {out['tension_top_kgf'][k]:12.2f} {out['tension_bottom_kgf'][k]:7.2f} | "
              f"{PAPER_TENSION_KGF['simulation'][k]:9.2f} {PAPER_TENSION_KGF['experiment'][k]:5.2f}   "
              f"{out['layback_top_deg'][k]:15.2f} {out['layback_chord_deg'][k]:6.2f} "
              f"{out['layback_bottom_deg'][k]:7.2f} | {PAPER_LAYBACK_DEG['simulation'][k]:9.2f} "
              f"{PAPER_LAYBACK_DEG['experiment'][k]:5.2f}")
    if a.dynamic:
        for k, u in enumerate(CURRENTS):
            print(f"MuJoCo {u:3.1f} m/s: top {out['mujoco_tension_top_kgf'][k]:.2f} kgf, bottom "
                  f"{out['mujoco_tension_bottom_kgf'][k]:.2f} kgf, chord {out['mujoco_layback_chord_deg'][k]:.2f} deg")
    print(f"lay-back (chord) against the experiment: worst {out['layback_worst_deg']:.2f} deg, "
          f"RMS {out['layback_rms_deg']:.2f} deg; tension at 0-0.5 m/s: worst {out['tension_worst_0_to_0p5_kgf']:.2f} kgf")
    return 0


if __name__ == "__main__":
    sys.exit(main())

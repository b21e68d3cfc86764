"""Reproduce Tables 2-8 of Khan et al. (2023) with the paper's method and with a consistent model.

For every table row this prints, and writes to ``docs/khan2023_reproduction.md``, the paper's
deployed length and tow-point tension beside

* ``khan2023(variant="printed")``: Eqs. 22-23 as printed;
* ``khan2023(variant="consistent")``: Eqs. 22-23 re-derived from Eq. 21;
* ``steady_state``: the physically consistent towed steady state of the same cable in the
  same water (see ``TOWED_CASE`` below),

with percent errors, then the timings of one ``khan2023`` pass and one ``steady_state`` solve at
N = 200. Nothing here is tuned to the paper's numbers.

    python scripts/reproduce_khan2023.py [--out docs/khan2023_reproduction.md] [--quick]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

import mjtether as mt
from mjtether.quasistatic import khan2023, steady_state

KN = mt.KNOT
DECAY = 55.0 / math.log(100.0)  # m: the exponential current is 1 % of its surface value at 55 m

TOWED_CASE = """\
**The `steady_state` column.** A walker that walks away from a ship holding station does not
reach a steady state (its cable grows longer and its shape changes), so the paper's "steady
state" has no exact physical counterpart. The closest steady one is towing: ship and walker move
together at v_r into the head current, so the whole cable moves at v_r (Eq. 5 instead makes the
cable's speed grow linearly from 0 at the ship to v_r at the walker). For the paper's deployed
length L (the row's length), the ship is at the surface, the cable leaves it at 30 degrees below
the horizontal (the paper's assumed theta_1), and the walker's tow point is on the seabed at the
row's depth; the ship's lead, the tensions and the vertical pull on the walker follow.
`steady_state` is marched from the ship (one point plus the end force) with the top tension found
by root-finding so that the end reaches the depth; drag is Morison on the relative velocity with
C_dn = 1.0 on d l and C_dt = 0.015 on pi d l, the paper's values. (Asking instead for the cable
to meet the seabed tangentially at the walker has no solution at 0 kn: the drag-dominated cable
then reaches only about 220 m.)"""


# table, label, paper length (m), paper tension (N), case parameters
def rows():
    base = dict(vs=5.0, vr=2.0, d=0.020, rho_c=1025.0, density="linear", depth=500.0, length=None)

    def r(table, label, L, T, **kw):
        return table, label, L, T, {**base, **kw}

    out = [r("2", f"surface current {v:g} kn", L, T, vs=v)
           for v, L, T in ((0, 2050, 858), (1, 2070, 877), (3, 2140, 886), (5, 2260, 928))]
    out += [r("3", "constant density 1025, cable 1050", 2250, 1025, rho_c=1050.0, density="constant"),
            r("3", "linear density 1025-980, cable 1050", 1700, 1040, rho_c=1050.0)]
    out += [r("4", f"walker speed {v:g} kn", L, T, vr=v) for v, L, T in ((1, 1720, 415), (2, 2260, 928))]
    out += [r("5", f"diameter {d:g} mm", L, T, d=d / 1000) for d, L, T in ((25, 2100, 1178), (20, 2300, 942),
                                                                         (18, 2380, 835))]
    out += [r("6", f"length {L:g} m (given)", L, T, length=float(L))
            for L, T in zip(range(2300, 2481, 20), (942, 958, 975, 990, 1004, 1020, 1034, 1050, 1064, 1078))]
    out += [r("7", f"cable density {rc:g}", L, T, rho_c=float(rc)) for rc, L, T in ((1025, 2300, 942),
                                                                                   (1050, 1700, 1046))]
    out += [r("8", f"water depth {D:g} m", L, T, depth=float(D))
            for D, L, T in ((550, 2600, 1182), (500, 2300, 942), (200, 2100, 501), (180, 1960, 400),
                            (150, 1750, 295))]
    return out


def water(p, heading=0.0):
    dens = mt.LinearDensity(1025.0, 980.0, 500.0) if p["density"] == "linear" else mt.ConstantDensity(1025.0)
    return mt.WaterColumn(depth=p["depth"], density=dens, gravity=9.8,
                          current=mt.ExponentialCurrent(p["vs"] * KN, decay_depth=DECAY, heading=heading))


def run_khan(p, variant):
    kw = dict(diameter=p["d"], cable_density=p["rho_c"], water=water(p), robot_speed=p["vr"] * KN,
              variant=variant)
    try:
        if p["length"] is not None:
            r = khan2023(length=p["length"], **kw)
        else:
            r = khan2023(depth=p["depth"], **kw)
    except (ValueError, RuntimeError) as e:
        return None, None, str(e)
    note = f"depth reached {r.depth:.0f} m" if p["length"] is not None else ""
    return r.length, r.tow_tension, note


def run_towed(p, L, N=200):
    """The towed steady state of TOWED_CASE: (tow tension N, note)."""
    D = p["depth"]
    w = water(p, heading=math.pi)  # head current: flowing towards -x, the walker moves towards +x
    tet = mt.TetherSpec(length=L, segments=N, diameter=p["d"], density=p["rho_c"], cd_normal=1.0,
                        cd_tangential=0.015)
    v = np.array([p["vr"] * KN, 0.0, 0.0])
    a = math.radians(30.0)

    def solve(log_t):
        T = math.exp(log_t)
        return steady_state(tet, w, [0, 0, 0], top_force=[T * math.cos(a), 0, -T * math.sin(a)],
                            tow_velocity=v, seabed=False)

    lo, hi = math.log(1.0), math.log(1e3)
    while solve(hi).nodes[-1, 2] > -D:
        hi += math.log(4.0)
        if hi > math.log(1e8):
            return None, f"does not reach {D:g} m"
    log_t = brentq(lambda x: solve(x).nodes[-1, 2] + D, lo, hi, xtol=1e-10)
    ss = solve(log_t)
    return ss.tow_tension, (f"ship {ss.nodes[-1, 0]:.0f} m behind, top tension {ss.top_tension:.0f} N, "
                            f"cable lifts the walker by {ss.bottom_force[2]:.0f} N")


def pct(model, paper):
    return None if model is None else 100.0 * (model - paper) / paper


def fmt(x, nd=0):
    return "n/a" if x is None else f"{x:,.{nd}f}"


def fmt_pct(x):
    return "n/a" if x is None else f"{x:+.0f} %"


PERF = ("Timings (`python scripts/bench_quasistatic.py`, `docs/bench/bench_quasistatic.json`, measured on "
        "<!--bench:bench_quasistatic@date--><!--/bench--> on a shared "
        "<!--bench:bench_quasistatic@machine.cpu_count--><!--/bench-->-core machine): one khan2023 pass at "
        "N = 200: <!--bench:bench_quasistatic.khan2023_pass_ms_N200:.1f--><!--/bench--> ms; one steady_state "
        "solve at N = 200 (3-D, turning current): "
        "<!--bench:bench_quasistatic.steady_state_ms_N200_3d_turning_current:.0f--><!--/bench--> ms.")
"""The timings line of the report: markers that ``scripts/make_bench_docs.py`` fills from the
benchmark's committed JSON (this script measures nothing)."""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs" / "khan2023_reproduction.md"))
    ap.add_argument("--quick", action="store_true", help="only the first row of each table")
    args = ap.parse_args(argv)

    table = []
    seen = set()
    for tab, label, L, T, p in rows():
        if args.quick and tab in seen:
            continue
        seen.add(tab)
        Lp, Tp, np_ = run_khan(p, "printed")
        Lc, Tc, nc = run_khan(p, "consistent")
        Ts, ns = run_towed(p, L)
        line = dict(tab=tab, label=label, L=L, T=T, Lp=Lp, Tp=Tp, Lc=Lc, Tc=Tc, Ts=Ts,
                    notes="; ".join(x for x in (f"printed: {np_}" if np_ else "", f"consistent: {nc}" if nc else "",
                                                f"steady: {ns}") if x))
        table.append(line)
        print(f"Table {tab} | {label:38s} | paper {L:5.0f} m {T:6.0f} N | printed {fmt(Lp):>7} m {fmt(Tp):>7} N"
              f" | consistent {fmt(Lc):>7} m {fmt(Tc):>7} N | steady {fmt(Ts):>7} N | {ns}", flush=True)

    def med(key_model, key_paper):
        vals = [abs(pct(r[key_model], r[key_paper])) for r in table if r[key_model] is not None]
        return (statistics.median(vals), max(vals), len(vals)) if vals else (math.nan, math.nan, 0)

    depth_rows = [r for r in table if r["tab"] != "6"]
    stats = {}
    for name, kl, kt in (("printed", "Lp", "Tp"), ("consistent", "Lc", "Tc"), ("steady_state", None, "Ts")):
        s = {"T": med(kt, "T")}
        if kl:
            vals = [abs(pct(r[kl], r["L"])) for r in depth_rows if r[kl] is not None]
            s["L"] = (statistics.median(vals), max(vals), len(vals)) if vals else (math.nan, math.nan, 0)
        stats[name] = s
    within10 = {name: sum(1 for r in table if r[k] is not None and abs(pct(r[k], r["T"])) <= 10)
                for name, k in (("printed", "Tp"), ("consistent", "Tc"), ("steady_state", "Ts"))}
    summary = (f"Summary: over {len(table)} rows the median |error| in tow tension is "
               f"{stats['printed']['T'][0]:.0f} % (printed), {stats['consistent']['T'][0]:.0f} % (consistent), "
               f"{stats['steady_state']['T'][0]:.0f} % (towed steady state); in deployed length "
               f"{stats['printed']['L'][0]:.0f} % (printed) and {stats['consistent']['L'][0]:.0f} % (consistent). "
               f"Rows with the tension within 10 %: {within10['printed']} printed, {within10['consistent']} "
               f"consistent, {within10['steady_state']} steady state.")
    print(summary)
    if not args.quick:
        write_report(Path(args.out), table, summary, PERF)
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from make_bench_docs import rewrite

        rewrite([Path(args.out)])  # the timings, from docs/bench/bench_quasistatic.json
        print(f"wrote {args.out}")
    return 0


def write_report(path: Path, table, summary, perf):
    lines = [
        "# Reproducing Khan et al. (2023), Tables 2-8",
        "",
        "Generated by `python scripts/reproduce_khan2023.py`; do not edit by hand.",
        "",
        summary,
        "",
        perf,
        "",
        "Lengths are the deployed length needed for the cable's end to reach the seabed depth",
        "(Table 6 gives the length; the tension there is at that length). Tensions are at the tow point.",
        "Errors are (model - paper) / paper.",
        "",
        "| Table | case | paper L (m) | paper T (N) | printed L | printed T | consistent L | consistent T "
        "| steady T | notes |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in table:
        lines.append(
            f"| {r['tab']} | {r['label']} | {r['L']:,.0f} | {r['T']:,.0f} "
            f"| {fmt(r['Lp'])} ({fmt_pct(pct(r['Lp'], r['L']))}) | {fmt(r['Tp'])} ({fmt_pct(pct(r['Tp'], r['T']))}) "
            f"| {fmt(r['Lc'])} ({fmt_pct(pct(r['Lc'], r['L']))}) | {fmt(r['Tc'])} ({fmt_pct(pct(r['Tc'], r['T']))}) "
            f"| {fmt(r['Ts'])} ({fmt_pct(pct(r['Ts'], r['T']))}) | {r['notes']} |")
    lines += ["", "## How each column was computed", "", CASE_NOTES, "", TOWED_CASE, "", INCONSISTENCIES, ""]
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text("\n".join(lines))
    tmp.replace(path)


CASE_NOTES = """\
Common inputs (Table 1 unless the row says otherwise): d = 0.02 m, cable density 1025 kg/m^3,
C_dn = 1.0, C_da = 0.015, g = 9.8 m/s^2, N = 200, walker speed 2 kn, surface current 5 kn with an
exponential profile, water density linear from 1025 kg/m^3 at the surface to 980 kg/m^3 at 500 m
(continued with the same gradient below 500 m), seabed 500 m.

Readings of the paper this reproduction had to choose (also in `mjtether/quasistatic/khan2023.py`):

* exponential current u = u_s exp(-depth / 11.94 m): the paper gives no decay depth, only
  "almost zero at 50-60 m"; this leaves 1 % at 55 m;
* water density 980 kg/m^3 at 500 m (Secs. 4.4 and Table 3), not the 990 of Sec. 3.6;
* the current is head-on and adds to the walker's speed (Eq. 4, V = v_c + v_r), and the element
  speed grows linearly from 0 at the ship to v_r at the walker (Eq. 5), taken at element centres;
* element 1 has T_1 = W_s (Eqs. 35-36, the whole cable's specific weight, made consistent with
  the computed profile) and theta_1 = 30 degrees (Sec. 3.12);
* "length deployed" is the L at which Eq. 29's depth equals the seabed depth."""

INCONSISTENCIES = """\
## What the paper's equations and tables do not agree on

* **Eqs. 22-23 do not follow from Eq. 21.** Eliminating T_i from Eq. 21 gives
  D_2 V^2 tan(theta) sin(theta) + C_1 tan(theta) + C_2 - W_s = 0 and
  T_i = (D_1 V^2 cos^3 + D_2 V^2 sin^3 + C_1) / cos(theta); the paper prints D_1 in the first and
  swaps sin^3 and cos^3 in the second. `tests/quasistatic/test_quasistatic.py` checks that the consistent
  variant satisfies Eq. 21 and the printed one does not.
* **The weight acts upwards in Eq. 18.** With the paper's geometry (Eqs. 26-29: the cable
  descends for theta > 0), Eq. 18's vertical row adds W_s,i to the vertical tension going down,
  so with no drag both variants give an inverted catenary, steeper at the bottom, as a buoyant
  cable would hang (tested). A heavy cable's vertical tension falls going down.
* **Eq. 18 rotates the drag twice.** Its drag terms are D_1 V^2 cos^3, D_2 V^2 sin^3, ...: the
  element frame components D_a = D_1 V^2 cos^2, D_n = D_2 V^2 sin^2 multiplied once more by the
  direction cosines. A Morison balance has the normal drag ~ V_n |V_n| acting along the normal,
  which is what `steady_state` uses.
* **Eq. 5 is not a steady state.** The cable's speed varies linearly from 0 to v_r along its
  length, so the cable stretches or moves relative to itself; no rigid steady motion has that
  velocity field.
* **One case, two answers.** The default case (5 kn current, 2 kn walker, 20 mm, 1025 kg/m^3,
  500 m) is Table 2 row 4 and Table 4 row 2 with 2260 m and 928 N, but Table 5 row 2, Table 6
  row 1, Table 7 row 1 and Table 8 row 2 give 2300 m and 942 N.
* Table 3 row 2 (linear density, cable 1050 kg/m^3) gives 1700 m and 1040 N; Table 7 row 2, the
  same case, 1700 m and 1046 N.
* Sec. 3.6 gives 990 kg/m^3 at 500 m, Sec. 4.4 980 kg/m^3.
* Table 8's caption says "TC Density"; the table is about water depth. Table 1 calls C_da the
  "cross" drag coefficient; it is the axial one (Eq. 12).
* Sec. 4.7 reports a "time step of 20 s" for a method with no time in it; the 180 m of payout in
  3 min matches Eq. 32 at 2 kn (185 m).

## Why the towed steady state is so different

In the towed state every element moves at v_r, while Eq. 5 gives the upper half of the cable less
than half of it; and Morison drag on the relative velocity, ~ 1/2 rho C_dn d V^2 = 10.9 N/m at
2 kn across the cable, is far larger than the wet weight of a 20 mm cable of density
1025 kg/m^3 in water of 1025-980 kg/m^3 (at most 0.14 N/m). The cable streams almost
horizontally from the ship to the walker (1.6-2.5 km ahead of the ship in every row), the
tension is carried by drag, not weight, and the cable even lifts the walker (by 76 N to
1.6 kN). With the top angle held at 30 degrees a longer cable reaches the seabed with less top
tension, so in Table 6 the towed tension falls slowly as L grows, the opposite of the paper's
trend.

The consistent variant finds deployed lengths close to the paper's (median 5 %) but tensions
about a third lower; the printed variant finds half the length and three times the tension.
Neither agreement nor disagreement validates the paper: both variants share Eq. 18's doubled
drag rotation, its upward weight and Eq. 5's velocity field."""


if __name__ == "__main__":
    sys.exit(main())

"""Reproduce Tables 2-8 of Khan et al. (2023) with the paper's method and with a consistent model.

For every table row this prints, and writes to ``docs/khan2023_reproduction.md``, the paper's
deployed length and tow-point tension beside

* ``khan2023(variant="printed")``: Eqs. 22-23 as printed;
* ``khan2023(variant="consistent")``: Eqs. 22-23 re-derived from Eq. 21;
* ``steady_state``: the physically consistent towed steady state of the same cable in the
  same water (see ``TOWED_CASE`` below),

with percent errors, then the timings of one ``khan2023`` pass and one ``steady_state`` solve at
N = 200 (from the benchmark's JSON, ``docs/bench/bench_quasistatic.json``). Nothing here is tuned
to the paper's numbers.

    python scripts/reproduce_khan2023.py            # every row: docs/reproductions/khan2023.json, then the page
    python scripts/reproduce_khan2023.py --render   # no computation: the page from the committed JSON
    python scripts/reproduce_khan2023.py --json [--quick]   # print the result; --quick: one row a table, writes nothing

Every number the script computes sits in the page in a marker,
``<!--repro:khan2023.KEY:FORMAT-->text<!--/repro-->`` (the syntax of ``scripts/make_bench_docs.py``'s
``bench`` markers, read from ``docs/reproductions/``), which ``tests/papers/test_reproduction_docs.py``
checks against the JSON, ``{"result": ..., "measured": {date, command, commit, wall time, machine,
versions}}`` as benchmark JSON is.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

import mjtether as mt
from mjtether.quasistatic import khan2023, steady_state

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import make_bench_docs as mbd  # noqa: E402  (the marker syntax, the JSON lookup, the machine block)

NAME = "khan2023"  # docs/reproductions/khan2023.json
REPRO_DIR = ROOT / "docs" / "reproductions"
DOC = ROOT / "docs" / "khan2023_reproduction.md"
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
    """khan2023 on row ``p``: (deployed length m, tow tension N, depth reached m or None, error text)."""
    kw = dict(diameter=p["d"], cable_density=p["rho_c"], water=water(p), robot_speed=p["vr"] * KN,
              variant=variant)
    try:
        if p["length"] is not None:
            r = khan2023(length=p["length"], **kw)
        else:
            r = khan2023(depth=p["depth"], **kw)
    except (ValueError, RuntimeError) as e:
        return None, None, None, str(e)
    return r.length, r.tow_tension, (r.depth if p["length"] is not None else None), ""


def run_towed(p, L, N=200):
    """The towed steady state of TOWED_CASE: a dict of the tow tension (N), the ship's lead (m),
    the top tension (N) and the cable's lift on the walker (N), or of an error text."""
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
            return {"steady_T_N": None, "steady_error": f"does not reach {D:g} m"}
    log_t = brentq(lambda x: solve(x).nodes[-1, 2] + D, lo, hi, xtol=1e-10)
    ss = solve(log_t)
    return {"steady_T_N": float(ss.tow_tension), "steady_ship_behind_m": float(ss.nodes[-1, 0]),
            "steady_top_tension_N": float(ss.top_tension), "steady_lift_N": float(ss.bottom_force[2])}


def pct(model, paper):
    return None if model is None else 100.0 * (model - paper) / paper


def table_row(tab, label, L, T, p) -> dict:
    """One table row: the paper's numbers, each model's and their errors in % (None: no answer)."""
    row = {"table": tab, "case": label, "paper_L_m": float(L), "paper_T_N": float(T)}
    for variant in ("printed", "consistent"):
        Lv, Tv, depth, err = run_khan(p, variant)
        row.update({f"{variant}_L_m": Lv, f"{variant}_T_N": Tv, f"{variant}_L_pct": pct(Lv, L),
                    f"{variant}_T_pct": pct(Tv, T), f"{variant}_depth_m": depth, f"{variant}_error": err})
    row.update(run_towed(p, L))
    row["steady_T_pct"] = pct(row["steady_T_N"], T)
    return row


def summarise(table: list[dict]) -> dict:
    """Median and largest |error| (%) of each model's tension over all rows and of its length over
    the rows where the length is found (all but Table 6), and the rows within 10 % in tension."""
    def stats(key, rows):
        vals = [abs(r[key]) for r in rows if r[key] is not None]
        return {"median": statistics.median(vals) if vals else None, "max": max(vals) if vals else None,
                "rows": len(vals)}

    depth_rows = [r for r in table if r["table"] != "6"]
    out = {"rows": len(table)}
    for name in ("printed", "consistent", "steady"):
        out[f"{name}_T_pct"] = stats(f"{name}_T_pct", table)
        out[f"{name}_within_10pct"] = sum(1 for r in table if r[f"{name}_T_pct"] is not None
                                          and abs(r[f"{name}_T_pct"]) <= 10)
    for name in ("printed", "consistent"):
        out[f"{name}_L_pct"] = stats(f"{name}_L_pct", depth_rows)
    for key in ("steady_ship_behind_m", "steady_lift_N"):
        vals = [r[key] for r in table if r.get(key) is not None]
        out[key] = {"min": min(vals), "max": max(vals)}
    return out


def inputs() -> dict:
    """Derived numbers the page's prose quotes, from the common case (Table 1)."""
    p = rows()[0][4]
    area = math.pi * p["d"] ** 2 / 4
    return {"drag_N_per_m_at_walker_speed": 0.5 * 1025.0 * 1.0 * p["d"] * (p["vr"] * KN) ** 2,
            "largest_wet_weight_N_per_m": (p["rho_c"] - 980.0) * 9.8 * area,
            "walker_speed_kn": p["vr"], "diameter_mm": p["d"] * 1000, "cable_density_kg_m3": p["rho_c"]}


def measured(command: str, wall_s: float) -> dict:
    """Where and when the numbers were made: make_bench_docs.py's ``measured`` block."""
    return mbd.measured_block(command, wall_s)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(DOC))
    ap.add_argument("--quick", action="store_true", help="only the first row of each table; writes nothing")
    ap.add_argument("--json", action="store_true", help="print the result as JSON")
    ap.add_argument("--render", action="store_true", help="no computation: write the page from the committed JSON")
    args = ap.parse_args(argv)
    if args.render:
        Path(args.out).write_text(render())
        print(f"wrote {args.out} from docs/reproductions/{NAME}.json")
        return 0

    t0 = time.perf_counter()
    table, seen = [], set()
    for tab, label, L, T, p in rows():
        if args.quick and tab in seen:
            continue
        seen.add(tab)
        r = table_row(tab, label, L, T, p)
        table.append(r)
        if not args.json:
            print(f"Table {tab} | {label:38s} | paper {L:5.0f} m {T:6.0f} N | printed {fmt(r['printed_L_m'])} m "
                  f"{fmt(r['printed_T_N'])} N | consistent {fmt(r['consistent_L_m'])} m {fmt(r['consistent_T_N'])} N "
                  f"| steady {fmt(r['steady_T_N'])} N", flush=True)
    result = {"rows": table, "summary": summarise(table), "inputs": inputs()}
    wall = time.perf_counter() - t0
    if args.json:
        print(json.dumps(result, indent=1))
    if args.quick:
        return 0
    REPRO_DIR.mkdir(parents=True, exist_ok=True)
    cmd = "python scripts/reproduce_khan2023.py" + (" --json" if args.json else "")
    (REPRO_DIR / f"{NAME}.json").write_text(json.dumps({"result": result, "measured": measured(cmd, wall)},
                                                       indent=1) + "\n")
    Path(args.out).write_text(render())
    print(f"wrote docs/reproductions/{NAME}.json ({wall:.0f} s) and {args.out}",
          file=sys.stderr if args.json else sys.stdout)
    return 0


def fmt(x, nd=0):
    return "n/a" if x is None else f"{x:,.{nd}f}"


def marker(key: str, fmt: str = "", repro_dir: Path = REPRO_DIR) -> str:
    """``key`` of the result (``@key``: of the measured block) as a marker holding its text; a
    missing answer (null) is ``n/a``, outside a marker."""
    ref = f"{NAME}{'' if key.startswith('@') else '.'}{key}" + (f":{fmt}" if fmt else "")
    try:
        return f"<!--repro:{ref}-->{mbd.value_of(ref, repro_dir)}<!--/repro-->"
    except ValueError:
        obj = json.loads((repro_dir / f"{NAME}.json").read_text())["result"]
        for part in key.split("."):
            obj = obj[int(part)] if isinstance(obj, list) else obj[part]
        if obj is None:
            return "n/a"
        raise


PERF = ("Timings (`python scripts/bench_quasistatic.py`, `docs/bench/bench_quasistatic.json`, measured on "
        "<!--bench:bench_quasistatic@date--><!--/bench--> on a shared "
        "<!--bench:bench_quasistatic@machine.cpu_count--><!--/bench-->-core machine): one khan2023 pass down "
        "the cable at N = 200: <!--bench:bench_quasistatic.khan2023_pass_ms_N200:.1f--><!--/bench--> ms; a whole "
        "`khan2023(...)` call, many passes: given the length (2260 m) "
        "<!--bench:bench_quasistatic.khan2023_call_ms_N200_length2260:.0f--><!--/bench--> ms, given a depth "
        "(500 m, as the tables are) <!--bench:bench_quasistatic.khan2023_call_s_N200_depth500:.1f--><!--/bench--> s; "
        "one steady_state solve at N = 200 (3-D, turning current): "
        "<!--bench:bench_quasistatic.steady_state_ms_N200_3d_turning_current:.0f--><!--/bench--> ms.")
"""The timings line of the page: markers filled from the benchmark's committed JSON
(``docs/bench/bench_quasistatic.json``, which ``scripts/make_bench_docs.py`` checks); this script
times nothing but its own run (the ``measured`` block)."""


def _fill_bench(text: str) -> str:
    return mbd.MARKER.sub(lambda x: f"<!--bench:{x['ref']}-->{mbd.value_of(x['ref'])}<!--/bench-->", text)


def render(repro_dir: Path = REPRO_DIR) -> str:
    """``docs/khan2023_reproduction.md`` from ``docs/reproductions/khan2023.json``: every number
    the script computes a marker (no computation)."""
    res = json.loads((repro_dir / f"{NAME}.json").read_text())["result"]

    def m(key, fmt=""):
        return marker(key, fmt, repro_dir)

    def cell(k, model, q, unit_fmt=",.0f"):
        base = f"rows.{k}.{model}_{q}"
        val = m(base + ("_m" if q == "L" else "_N"), unit_fmt)
        return val if val == "n/a" else f"{val} ({m(base + '_pct', '+.0f')} %)"

    s = "summary"
    summary = (f"Summary: over {m(s + '.rows')} rows the median |error| in tow tension is "
               f"{m(s + '.printed_T_pct.median', '.0f')} % (printed), {m(s + '.consistent_T_pct.median', '.0f')} % "
               f"(consistent), {m(s + '.steady_T_pct.median', '.0f')} % (towed steady state); in deployed length "
               f"{m(s + '.printed_L_pct.median', '.0f')} % (printed) and {m(s + '.consistent_L_pct.median', '.0f')} % "
               f"(consistent). Rows with the tension within 10 %: {m(s + '.printed_within_10pct')} printed, "
               f"{m(s + '.consistent_within_10pct')} consistent, {m(s + '.steady_within_10pct')} steady state.")
    lines = [
        "# Reproducing Khan et al. (2023), Tables 2-8",
        "",
        "Generated by `python scripts/reproduce_khan2023.py` from `docs/reproductions/khan2023.json` "
        f"(made on {m('@date')} at {m('@commit')} in {m('@wall_s', '.0f')} s on a "
        f"{m('@machine.cpu_count')}-core machine); do not edit by hand.",
        "",
        summary,
        "",
        _fill_bench(PERF),
        "",
        "Lengths are the deployed length needed for the cable's end to reach the seabed depth",
        "(Table 6 gives the length; the tension there is at that length). Tensions are at the tow point.",
        "Errors are (model - paper) / paper.",
        "",
        "| Table | case | paper L (m) | paper T (N) | printed L | printed T | consistent L | consistent T "
        "| steady T | notes |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for k, r in enumerate(res["rows"]):
        notes = []
        for variant in ("printed", "consistent"):
            if r[f"{variant}_error"]:
                notes.append(f"{variant}: no answer")
            elif r[f"{variant}_depth_m"] is not None:
                notes.append(f"{variant}: depth reached {m(f'rows.{k}.{variant}_depth_m', '.0f')} m")
        if r["steady_T_N"] is None:
            notes.append(f"steady: {r['steady_error']}")
        else:
            notes.append(f"steady: ship {m(f'rows.{k}.steady_ship_behind_m', '.0f')} m behind, top tension "
                         f"{m(f'rows.{k}.steady_top_tension_N', '.0f')} N, cable lifts the walker by "
                         f"{m(f'rows.{k}.steady_lift_N', '.0f')} N")
        lines.append(
            f"| {m(f'rows.{k}.table')} | {m(f'rows.{k}.case')} | {m(f'rows.{k}.paper_L_m', ',.0f')} "
            f"| {m(f'rows.{k}.paper_T_N', ',.0f')} | {cell(k, 'printed', 'L')} | {cell(k, 'printed', 'T')} "
            f"| {cell(k, 'consistent', 'L')} | {cell(k, 'consistent', 'T')} | {cell(k, 'steady', 'T')} "
            f"| {'; '.join(notes)} |")
    i = "inputs"
    why = WHY.format(
        drag=m(i + ".drag_N_per_m_at_walker_speed", ".1f"), vr=m(i + ".walker_speed_kn", "g"),
        d=m(i + ".diameter_mm", "g"), rho=m(i + ".cable_density_kg_m3", "g"),
        wet=m(i + ".largest_wet_weight_N_per_m", ".2f"),
        lead_lo=m(s + ".steady_ship_behind_m.min", ".0f"), lead_hi=m(s + ".steady_ship_behind_m.max", ".0f"),
        lift_lo=m(s + ".steady_lift_N.min", ".0f"), lift_hi=m(s + ".steady_lift_N.max", ".0f"),
        cons_L=m(s + ".consistent_L_pct.median", ".0f"))
    lines += ["", "## How each column was computed", "", CASE_NOTES, "", TOWED_CASE, "", INCONSISTENCIES, "",
              why, ""]
    return "\n".join(lines)


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
  3 min matches Eq. 32 at 2 kn (185 m)."""

WHY = """\
## Why the towed steady state is so different

In the towed state every element moves at v_r, while Eq. 5 gives the upper half of the cable less
than half of it; and Morison drag on the relative velocity, ~ 1/2 rho C_dn d V^2 = {drag} N/m at
{vr} kn across the cable, is far larger than the wet weight of a {d} mm cable of density
{rho} kg/m^3 in water of 1025-980 kg/m^3 (at most {wet} N/m). The cable streams almost
horizontally from the ship to the walker ({lead_lo} m to {lead_hi} m ahead of the ship in every row),
the tension is carried by drag, not weight, and the cable even lifts the walker (by {lift_lo} N to
{lift_hi} N). With the top angle held at 30 degrees a longer cable reaches the seabed with less top
tension, so in Table 6 the towed tension falls slowly as L grows, the opposite of the paper's
trend.

The consistent variant finds deployed lengths close to the paper's (median {cons_L} %) but tensions
about a third lower; the printed variant finds half the length and three times the tension.
Neither agreement nor disagreement validates the paper: both variants share Eq. 18's doubled
drag rotation, its upward weight and Eq. 5's velocity field."""
"""The last section of the page; the fields are markers (``render``)."""

if __name__ == "__main__":
    sys.exit(main())

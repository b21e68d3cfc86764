"""Benchmark: the quasi-static solvers at N = 200 elements.

* one ``khan2023`` pass down the cable (Sec. 3.12 of the paper), the paper's default case
  (2260 m, 5 kn exponential current, 2 kn walker);
* whole ``khan2023(...)`` calls in that water, best of 3: given the length (2260 m; the
  method's passes until the tow point's conditions are met) and given a depth (500 m; the length
  that reaches it, found by root finding over such solves, as Tables 2-8 and the Python API
  guide call it): a call costs many passes;
* one full ``steady_state`` solve between two fixed ends (the shooting problem, Newton from the
  coarse-to-fine cascade), best of 3, for three cases: a 3-D one (300 m of cable in a current
  that turns by 90 degrees with depth), an in-plane current, and a heavy line resting on the
  seabed.

    python scripts/bench_quasistatic.py [--json]
"""

from __future__ import annotations

import argparse
import json
import math
import time

import mjtether as mt
from mjtether.quasistatic import khan2023, steady_state
from mjtether.quasistatic.khan2023 import time_one_sweep

CASES = {
    "3d_turning_current": (mt.TetherSpec(length=300.0, segments=200, diameter=0.02, density=1500.0, EA=5e6),
                           mt.WaterColumn(depth=300.0, current=mt.TabulatedCurrent(
                               [0, 50, 200], [1.0, 0.5, 0.1], [math.pi / 2, math.pi / 4, 0.0])),
                           [0, 0, 0], [150, 0, -200]),
    "in_plane_current": (mt.TetherSpec(length=60.0, segments=200, diameter=0.03, density=2000.0, EA=2e6),
                         mt.WaterColumn(depth=100.0, current=mt.ConstantCurrent(0.5)), [0, 0, 0], [40, 0, -30]),
    "seabed_catenary": (mt.TetherSpec(length=500.0, segments=200, diameter=0.1, mass_per_length=89.6, EA=5e8),
                        mt.WaterColumn(depth=200.0), [400, 0, 0], [0, 0, -200]),
}


def _khan_water() -> mt.WaterColumn:
    return mt.WaterColumn(depth=600.0, density=mt.LinearDensity(1025.0, 980.0, 500.0), gravity=9.8,
                          current=mt.ExponentialCurrent(5 * mt.KNOT, decay_depth=55 / math.log(100)))


def khan_pass_ms() -> float:
    return 1e3 * time_one_sweep(_khan_water(), 2 * mt.KNOT, 2260.0, segments=200)


def khan_call_s(repeat: int = 3, **kw) -> float:
    """Best wall time (s) of a whole ``khan2023`` call (printed variant, N = 200)."""
    water, best = _khan_water(), math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        khan2023(water=water, robot_speed=2 * mt.KNOT, segments=200, **kw)
        best = min(best, time.perf_counter() - t0)
    return best


def steady_ms(case: str, repeat: int = 3) -> float:
    tether, water, top, bottom = CASES[case]
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        steady_state(tether, water, top, bottom)
        best = min(best, time.perf_counter() - t0)
    return 1e3 * best


def measure() -> dict:
    out = {"khan2023_pass_ms_N200": round(khan_pass_ms(), 2),
           "khan2023_call_ms_N200_length2260": round(1e3 * khan_call_s(length=2260.0), 1),
           "khan2023_call_s_N200_depth500": round(khan_call_s(depth=500.0), 3)}
    for case in CASES:
        out[f"steady_state_ms_N200_{case}"] = round(steady_ms(case), 1)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    out = measure()
    if args.json:
        print(json.dumps(out))
        return
    print(f"khan2023, one pass, N = 200: {out['khan2023_pass_ms_N200']:.1f} ms")
    print(f"khan2023(...), N = 200, length 2260 m: {out['khan2023_call_ms_N200_length2260']:.0f} ms")
    print(f"khan2023(...), N = 200, depth 500 m: {out['khan2023_call_s_N200_depth500']:.2f} s")
    for case in CASES:
        print(f"steady_state, N = 200, {case}: {out[f'steady_state_ms_N200_{case}']:.0f} ms")


if __name__ == "__main__":
    main()

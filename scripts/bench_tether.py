"""Benchmark: cost per step of the tether against its number of segments.

A 1000 m tether (d = 0.02 m, 1050 kg/m^3) from (0, 0, 0) to a fixed point at (600, 0, -700)
in a 2.5 m/s exponential current (decay depth 15 m) and a linear density profile (1025 to
980 kg/m^3 over 500 m), simulated for 60 s from rest on the still-water catenary shape.

Reports the cost per step and the real-time factor for each N, the cost ratio of N=400 to
N=100, MuJoCo's own step of the N=200 model without the hydrodynamics (what MuJoCo alone costs
here) and the whole step over it, the kernels used (``MJTETHER_KERNELS``), and the cost of a drum: a 200-element tether with 10 % and with 100 % of it deployed (the
rest parked on the drum). Stability is checked two ways: the drag rate lambda (see
``mjtether.cable.stability``) gives lambda dt < 1, and with ``--check`` the N=200 run is repeated
at half the step: the ship-end tension after 60 s must agree within 1 %.

    python scripts/bench_tether.py [--json] [--check] [--timestep 0.005]
"""

from __future__ import annotations

import argparse
import json
import time

import mujoco
import numpy as np

import mjtether as mt

SEGMENTS = [25, 50, 100, 200, 400]


def make(N: int, dt: float):
    water = mt.WaterColumn(depth=1000.0, density=mt.LinearDensity(1025.0, 980.0, 500.0),
                           current=mt.ExponentialCurrent(2.5, decay_depth=15.0))
    tether = mt.TetherSpec(length=1000.0, segments=N, diameter=0.02, density=1050.0)
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, 0]), mt.FixedPoint([600, 0, -700]), water=water)
    return mt.Simulation(spec, water, [tm]), tether, water


def run(N: int, dt: float, duration: float = 60.0, bare: bool = False):
    """Cost per step (us) of ``duration`` s from rest; with ``bare``, also that of MuJoCo's own
    step of the same model in the same state, without the hydrodynamics (the callback
    suspended) and without the tension-only switching: what MuJoCo alone costs; and that of the
    same steps taken by the Python loop (``Simulation.compiled_steps = False``) over the compiled
    one (``cable.stepping``)."""
    sim, tether, water = make(N, dt)
    with sim:
        sim.step(10)  # warm up
        n = int(round(duration / dt)) - 10
        t0 = time.perf_counter()
        sim.step(n)
        wall = time.perf_counter() - t0
        top = float(np.linalg.norm(sim.tether().end_force(sim.data, "start")))
        us_bare = ratio = python_loop = None
        if bare:  # alternate 200 whole steps and 200 bare ones from the same state, 5 times each
            m, d = sim.model, sim.data
            state = sim.save_state()
            whole, own, loop = [], [], []
            for _ in range(5):
                sim.restore_state(state)
                t0 = time.perf_counter()
                sim.step(200)
                whole.append(time.perf_counter() - t0)
                sim.restore_state(state)
                sim.compiled_steps = False
                t0 = time.perf_counter()
                sim.step(200)
                loop.append(time.perf_counter() - t0)
                sim.compiled_steps = True
                sim.restore_state(state)
                with mt.dispatch.suspended():
                    t0 = time.perf_counter()
                    for _ in range(200):
                        mujoco.mj_step(m, d)
                    own.append(time.perf_counter() - t0)
            us_bare = float(np.median(own)) / 200 * 1e6
            ratio = float(np.median(whole)) / float(np.median(own))
            python_loop = float(np.median(loop)) / float(np.median(whole))
    us = wall / n * 1e6
    return dict(us=us, rtf=dt / (us * 1e-6), top=top, us_bare=us_bare, over_bare=ratio, python_loop=python_loop,
                lam_dt=mt.stability.drag_rate(tether, water) * dt)


def run_deployed(fraction: float, dt: float, duration: float = 20.0, capacity: int = 200):
    """Cost per step (us) of a drum holding a 1000 m, 200-element tether with ``fraction`` of it
    deployed straight down (the rest parked on the drum), in the same water."""
    water = mt.WaterColumn(depth=1000.0, density=mt.LinearDensity(1025.0, 980.0, 500.0),
                           current=mt.ExponentialCurrent(2.5, decay_depth=15.0))
    n = max(1, int(round(fraction * capacity)))
    L = 1000.0 * n / capacity
    tether = mt.TetherSpec(length=L, segments=n, diameter=0.02, density=1050.0)
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    nodes = np.outer(np.linspace(0.0, L, n + 1), [0.0, 0.0, -1.0])
    tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, 0]), mt.FreeEnd(), water=water, nodes=nodes,
                       max_length=1000.0)
    with mt.Simulation(spec, water, [tm]) as sim:
        sim.step(10)
        steps = int(round(duration / dt))
        t0 = time.perf_counter()
        sim.step(steps)
        return (time.perf_counter() - t0) / steps * 1e6


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--check", action="store_true", help="repeat N=200 at half the step")
    ap.add_argument("--timestep", type=float, default=0.005, help="time step (s)")
    args = ap.parse_args(argv)
    dt = args.timestep
    res = {N: run(N, dt, bare=N in (25, 200)) for N in SEGMENTS}
    out = {"N": SEGMENTS, "us_per_step": [round(res[N]["us"], 1) for N in SEGMENTS],
           "timestep": [dt] * len(SEGMENTS), "realtime_factor": [round(res[N]["rtf"], 2) for N in SEGMENTS],
           "ship_tension_N": [round(res[N]["top"], 2) for N in SEGMENTS],
           "drag_rate_x_dt": round(res[200]["lam_dt"], 3),
           "cost_ratio_400_100": round(res[400]["us"] / res[100]["us"], 2),
           # MuJoCo's own step of the N=200 model (no hydrodynamics, no slack switching), and
           # the whole step over it (medians of 5 alternating rounds from the same state)
           "bare_mj_step_us_N200": round(res[200]["us_bare"], 1),
           "cost_over_bare_N200": round(res[200]["over_bare"], 2),
           # the same steps in the Python step loop over the compiled one (``cable.stepping``)
           "python_loop_over_compiled_N25": round(res[25]["python_loop"], 2),
           "python_loop_over_compiled_N200": round(res[200]["python_loop"], 2),
           "kernels": mt.compiled.backend(), "callback": "native" if mt.native.available() else "python"}
    # cable parked on a drum must cost little: 10 % and 100 % of a 200-element tether deployed
    out["drum_us_per_step_10pct"] = round(run_deployed(0.1, dt), 1)
    out["drum_us_per_step_100pct"] = round(run_deployed(1.0, dt), 1)
    if args.check:
        half = run(200, dt / 2)
        out["check_N200_half_step_tension_rel_diff"] = round(abs(half["top"] / res[200]["top"] - 1), 5)
    if args.json:
        print(json.dumps(out))
        return
    print(f"time step {dt} s; drag rate x dt = {out['drag_rate_x_dt']} (stable below 2, no overshoot below 1)")
    print(f"{'N':>5} {'us/step':>10} {'x real time':>12} {'ship tension (N)':>17}")
    for i, N in enumerate(SEGMENTS):
        print(f"{N:>5} {out['us_per_step'][i]:>10.1f} {out['realtime_factor'][i]:>12.1f} {out['ship_tension_N'][i]:>17.1f}")
    print(f"cost(400) / cost(100) = {out['cost_ratio_400_100']}; "
          f"N=200 real-time factor {out['realtime_factor'][3]}")
    print(f"N=200: MuJoCo's own step {out['bare_mj_step_us_N200']} us; the whole step costs "
          f"{out['cost_over_bare_N200']}x that ({out['kernels']} kernels)")
    print(f"drum of 200 elements: {out['drum_us_per_step_10pct']} us/step with 10 % deployed, "
          f"{out['drum_us_per_step_100pct']} us/step with all of it")
    if args.check:
        print(f"N=200 at dt/2: ship tension differs by {100 * out['check_N200_half_step_tension_rel_diff']:.3f} %")


if __name__ == "__main__":
    main()

"""Benchmark: batched rollouts of a tether model on MuJoCo's threads, with its hydrodynamics.

A 1000 m tether (d = 0.02 m, 1050 kg/m^3, N segments) from (0, 0, 0) to a fixed point at
(600, 0, -700) in a 0.5 m/s exponential current (decay depth 15 m) over a linear density
profile, started from its steady state in still water (every element taut, as a rollout needs:
it does not switch slack elements), time step 5 ms.

Reports, for N = 200:

* ``agreement``: the largest difference, over every step and coordinate, between a rollout
  (``mjtether.rollouts.rollout``) and ``Simulation.step`` from the same state, relative to the
  largest coordinate (the goal is 1e-10);
* ``us_per_step_simulation``, ``us_per_step_rollout_1_thread``, ``us_per_step_rollout_2_threads``
  (wall time per step of one trajectory; a batch of ``--batch`` rollouts on 2 threads shares the
  wall time), ``us_per_step_bare`` (MuJoCo's own step of the model, no callback);
* ``speedup_2_threads``: one thread's wall time for the batch over two threads' (the goal is 1.8
  on 2 cores), median of ``--repeat`` alternating rounds; ``speedup_2_threads_bare``: the same for
  MuJoCo alone (the callback removed, so the cable runs in vacuum: timing only), measured in the
  same rounds: how far the machine lets two threads scale at all.

    python scripts/bench_rollout.py [--json] [--segments 200] [--steps 400] [--batch 8]
"""

from __future__ import annotations

import argparse
import copy
import json
import time

import mujoco
import numpy as np
from mujoco import rollout

import mjtether as mt
from mjtether import rollouts
from mjtether.quasistatic import steady_state


def make(N: int, dt: float) -> mt.Simulation:
    water = mt.WaterColumn(depth=1000.0, density=mt.LinearDensity(1025.0, 980.0, 500.0),
                           current=mt.ExponentialCurrent(0.5, decay_depth=15.0))
    tether = mt.TetherSpec(length=1000.0, segments=N, diameter=0.02, density=1050.0)
    top, end = [0.0, 0.0, 0.0], [600.0, 0.0, -700.0]
    ss = steady_state(tether, mt.WaterColumn(depth=1000.0, density=water.density), top, end, seabed=False)
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    tm = mt.add_tether(spec, tether, mt.FixedPoint(top), mt.FixedPoint(end), water=water, nodes=ss.nodes)
    return mt.Simulation(spec, water, [tm])


def bare_rollout(sim: mt.Simulation, batch: np.ndarray, steps: int, nthread: int) -> float:
    """Wall time (s) of the batch rolled out by MuJoCo alone (no passive callback) on ``nthread``."""
    datas = [copy.copy(sim.data) for _ in range(nthread)]
    with mt.dispatch.suspended():
        t0 = time.perf_counter()
        if nthread == 1:
            rollout.rollout(sim.model, datas[0], batch, nstep=steps)
        else:
            with rollout.Rollout(nthread=nthread) as r:
                r.rollout(sim.model, datas, batch, nstep=steps)
        return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--segments", type=int, default=200)
    ap.add_argument("--steps", type=int, default=400, help="steps per rollout")
    ap.add_argument("--batch", type=int, default=8, help="rollouts in the threaded batch")
    ap.add_argument("--repeat", type=int, default=3, help="alternating rounds of 1 and 2 threads")
    args = ap.parse_args(argv)
    dt, steps = 0.005, args.steps
    with make(args.segments, dt) as sim:
        if not sim.native:
            raise SystemExit("bench_rollout: the native callback is not available (numba is missing, or "
                             "MJTETHER_KERNELS=numpy): rollouts would run in vacuum")
        s0 = rollouts.initial_state(sim)
        saved = sim.save_state()
        nq = sim.model.nq
        # the Simulation's own trajectory, step by step
        want = np.empty((steps, nq))
        t0 = time.perf_counter()
        for i in range(steps):
            sim.step()
            want[i] = sim.data.qpos
        us_sim = (time.perf_counter() - t0) / steps * 1e6
        sim.restore_state(saved)
        # one rollout, then the batch on 1 and 2 threads, alternating
        t0 = time.perf_counter()
        one, _ = rollouts.rollout(sim, s0[None], nstep=steps)
        us_one = (time.perf_counter() - t0) / steps * 1e6
        batch = np.repeat(s0[None], args.batch, axis=0)
        walls = {1: [], 2: [], "bare 1": [], "bare 2": []}
        worst = float(np.max(np.abs(one[0, :, 1:1 + nq] - want)))
        for _ in range(args.repeat):
            for nthread in (1, 2):
                t0 = time.perf_counter()
                out, _ = rollouts.rollout(sim, batch, nstep=steps, nthread=nthread)
                walls[nthread].append(time.perf_counter() - t0)
                worst = max(worst, float(np.max(np.abs(out[:, :, 1:1 + nq] - want[None]))))
                walls[f"bare {nthread}"].append(bare_rollout(sim, batch, steps, nthread))
        # MuJoCo alone, from the same state
        mujoco.mj_setState(sim.model, sim.data, s0, rollouts.STATE)
        with mt.dispatch.suspended():
            t0 = time.perf_counter()
            mujoco.mj_step(sim.model, sim.data, steps)
            us_bare = (time.perf_counter() - t0) / steps * 1e6
        scale = float(np.max(np.abs(want)))
    w1, w2 = float(np.median(walls[1])), float(np.median(walls[2]))
    out = {"segments": args.segments, "timestep": dt, "steps": steps, "batch": args.batch,
           "agreement": float(f"{worst / scale:.3g}"),
           "us_per_step_simulation": round(us_sim, 1), "us_per_step_rollout_1_thread": round(us_one, 1),
           "us_per_step_rollout_2_threads": round(w2 / (args.batch * steps) * 1e6, 1),
           "us_per_step_bare": round(us_bare, 1),
           "speedup_2_threads": round(w1 / w2, 2),
           "speedup_2_threads_bare": round(float(np.median(walls["bare 1"]) / np.median(walls["bare 2"])), 2)}
    if args.json:
        print(json.dumps(out))
    else:
        for k, v in out.items():
            print(f"{k:32s} {v}")


if __name__ == "__main__":
    main()

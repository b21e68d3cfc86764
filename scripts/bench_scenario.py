"""Benchmark: real-time factor of a scenario run (default: the built-in walker scenario, N = 100
with seabed contact), on one core, without writing results. The wall time counts everything a
run does: building the model, the quasi-static start, the pre-roll, stepping and recording.

    python scripts/bench_scenario.py [SCENARIO.toml] [--duration 60] [--segments N] [--check] [--json]
    python scripts/bench_scenario.py --vehicles [--json]

``--vehicles`` runs the vehicle cases (``VEHICLE_CASES``) instead: the REMUS 100 torpedo AUV on a
200-segment tether, the BlueROV2 Heavy on a 200-segment umbilical, and the REMUS 100 alone; and
times the REMUS 100's passive wrench with the compiled and the NumPy kernels.

It also times the run's step against MuJoCo's own step of the same states (``_mujoco_share``;
the goal: MuJoCo's step at least 0.9 of the run's).

``--check`` runs the scenario again with the time step divided by ``--refine`` (default 2) and
reports how far the answers a user reads move: the mean ship-end and
tow-point tensions after the first 10 s, the tow tension's standard deviation (the gait's
ripple), and the robot's final position.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from mjtether.cli import DEFAULT_SCENARIO
from mjtether.scenario.runner import RECORD_FIELDS, run
from mjtether.scenario import load_scenario

COL = {name: k for k, (name, _, _) in enumerate(RECORD_FIELDS)}


def _run(path: str, duration: float, timestep: float | None = None, segments: int | None = None):
    sets = [f"simulation.duration={duration!r}"] + ([f"simulation.timestep={timestep!r}"] if timestep else []) \
        + ([f"tether.segments={segments}"] if segments else [])
    sc = load_scenario(path, overrides=sets)
    rows, _, info = run(sc, keep_nodes=False)
    return sc, rows, info


ROOT = Path(__file__).resolve().parents[1]
VEHICLE_CASES = {
    # name: (example, overrides); 60 s each
    "torpedo_auv_200_segments": ("examples/remus_fibre_payout.toml",
                                 ["winch.mode=\"fixed\"", "tether.length=200.0", "tether.segments=200",
                                  "winch.max_length=200.0", "robot.position=[180.0, 0.0, -20.0]"]),
    "rov_200_segments": ("examples/rov_umbilical.toml", ["tether.segments=200"]),
    "torpedo_auv_alone": ("examples/remus_turning_circle.toml", []),
}


def _vehicles(duration: float) -> dict:
    out = {}
    for name, (path, sets) in VEHICLE_CASES.items():
        sc = load_scenario(ROOT / path, overrides=[f"simulation.duration={duration!r}", *sets])
        _, _, info = run(sc, keep_nodes=False)
        out[name] = {"scenario": path, "overrides": sets, "segments": sc.tether.segments if sc.tether.attached else 0,
                     "timestep": sc.simulation.timestep, "simulated_s": info["simulated_s"],
                     "wall_s": round(info["wall_time_s"], 2), "realtime_factor": round(info["realtime_factor"], 2)}
    return out


def _vehicle_wrench_us(kernels: str, calls: int = 5000) -> float:
    """Cost (us per call) of the REMUS 100's passive wrench (``BoundVehicle.wrench``: hull, fins,
    propeller, added-mass terms, buoyancy) with the ``kernels`` given, median of 5 rounds."""
    import os
    import time

    import mujoco

    from mjtether.physics import compiled
    from mjtether.simulation import Simulation
    from mjtether.vehicles.files import build_vehicle, load_vehicle
    from mjtether.physics.water import ExponentialCurrent, WaterColumn

    was = os.environ.get(compiled.KERNELS_ENV)
    os.environ[compiled.KERNELS_ENV] = kernels
    try:
        spec = mujoco.MjSpec()
        vm = build_vehicle(spec, load_vehicle("remus100"), "auv", pos=(0.0, 0.0, -20.0))
        water = WaterColumn(depth=100.0, current=ExponentialCurrent(0.5, decay_depth=20.0))
        with Simulation(spec, water, bodies=[vm]) as sim:
            bv, d = sim.bodies[0], sim.data
            d.qvel[:] = [1.5, 0.1, -0.05, 0.02, 0.03, 0.1]
            d.act[:] = [0.1, -0.05, 1200.0]
            rounds = []
            for _ in range(5):
                t0 = time.perf_counter()
                for _ in range(calls):
                    bv.wrench(sim.model, d)
                rounds.append((time.perf_counter() - t0) / calls * 1e6)
    finally:
        if was is None:
            os.environ.pop(compiled.KERNELS_ENV, None)
        else:
            os.environ[compiled.KERNELS_ENV] = was
    return round(float(np.median(rounds)), 1)


def _mujoco_share(path: str, steps: int = 3000, warm: int = 400) -> dict:
    """The run's step against MuJoCo's own step of its model: ``steps`` steps of the scenario's
    ``ScenarioRun`` (controllers, the tether's switching and redo, the checks), each timed alone,
    after ``warm`` steps; then MuJoCo's ``mj_step`` (with the loads' callback) from each of the
    same states, timed alone. Returns the two means (us), their ratio (MuJoCo's over the run's;
    1: the run costs nothing beyond one MuJoCo step), MuJoCo's steps per step (the tension-only
    switching redoes some: ``Simulation.redone_steps``) and the share of the run's time they
    take (1: nothing but MuJoCo's steps)."""
    import time

    import mujoco

    from mjtether.scenario.runner import ScenarioRun

    r = ScenarioRun(load_scenario(path))
    try:
        for _ in range(warm):
            r.step()
        m, d = r.sim.model, r.sim.data
        spec = mujoco.mjtState.mjSTATE_INTEGRATION
        states = np.empty((steps, mujoco.mj_stateSize(m, spec)))
        run_s, redone = 0.0, r.sim.redone_steps
        for k in range(steps):
            mujoco.mj_getState(m, d, states[k], spec)
            t0 = time.perf_counter()
            r.step()
            run_s += time.perf_counter() - t0
        per_step = 1.0 + (r.sim.redone_steps - redone) / steps  # MuJoCo's steps per step, redone ones too
        own_s = 0.0
        for k in range(steps):
            mujoco.mj_setState(m, d, states[k], spec)
            t0 = time.perf_counter()
            mujoco.mj_step(m, d)
            own_s += time.perf_counter() - t0
    finally:
        r.close()
    return {"run_step_us": round(run_s / steps * 1e6, 1), "mujoco_step_us": round(own_s / steps * 1e6, 1),
            "mujoco_step_share": round(own_s / run_s, 3), "mujoco_steps_per_step": round(per_step, 3),
            "mujoco_steps_share": round(own_s * per_step / run_s, 3)}


def _answers(rows: np.ndarray) -> dict:
    late = rows[:, 0] >= min(10.0, rows[-1, 0] / 2)
    return {"ship_tension_mean": float(rows[late, COL["ship_tension"]].mean()),
            "tow_tension_mean": float(rows[late, COL["tow_tension"]].mean()),
            "tow_tension_std": float(rows[late, COL["tow_tension"]].std()),
            "robot_final": rows[-1, [COL["robot_x"], COL["robot_y"], COL["robot_z"]]]}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenario", nargs="?", default=str(DEFAULT_SCENARIO))
    ap.add_argument("--duration", type=float, default=60.0, help="simulated seconds (default 60)")
    ap.add_argument("--check", action="store_true", help="rerun at a finer time step and compare")
    ap.add_argument("--refine", type=float, default=2, help="time-step divisor of --check (default 2)")
    ap.add_argument("--segments", type=int, default=None,
                    help="tether segments instead of the scenario's (e.g. 200 for examples/rov_umbilical.toml)")
    ap.add_argument("--vehicles", action="store_true", help="run the vehicle cases (VEHICLE_CASES) instead")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    if args.vehicles:
        out = {"vehicles": _vehicles(args.duration),
               "vehicle_wrench_us": {k: _vehicle_wrench_us(k) for k in ("numba", "numpy")}}
        if args.json:
            print(json.dumps(out))
            return
        for name, v in out["vehicles"].items():
            print(f"{name}: {v['scenario']} {' '.join(v['overrides'])}: N = {v['segments']}, {v['simulated_s']:.0f} s in "
                  f"{v['wall_s']} s, {v['realtime_factor']}x real time")
        w = out["vehicle_wrench_us"]
        print(f"REMUS 100 passive wrench: {w['numba']} us compiled, {w['numpy']} us NumPy")
        return
    sc, rows, info = _run(args.scenario, args.duration, segments=args.segments)
    dt = sc.simulation.timestep
    out = {"scenario": args.scenario, "segments": sc.tether.segments, "timestep": dt,
           "simulated_s": info["simulated_s"], "wall_s": round(info["wall_time_s"], 2),
           "realtime_factor": round(info["realtime_factor"], 2)}
    out.update(_mujoco_share(args.scenario))
    if args.check:
        _, fine, _ = _run(args.scenario, args.duration, dt / args.refine, segments=args.segments)
        a, b = _answers(rows), _answers(fine)
        out["check"] = {
            "fine_timestep": dt / args.refine,
            "ship_tension_mean_rel": round(a["ship_tension_mean"] / b["ship_tension_mean"] - 1, 5),
            "tow_tension_mean_rel": round(a["tow_tension_mean"] / b["tow_tension_mean"] - 1, 4),
            "tow_tension_mean_N": [round(a["tow_tension_mean"], 1), round(b["tow_tension_mean"], 1)],
            "tow_tension_std_N": [round(a["tow_tension_std"], 1), round(b["tow_tension_std"], 1)],
            "robot_final_distance_m": round(float(np.linalg.norm(a["robot_final"] - b["robot_final"])), 3)}
    if args.json:
        print(json.dumps(out))
        return
    print(f"{out['scenario']}: N = {out['segments']}, dt = {dt:g} s, {out['simulated_s']:.0f} s in "
          f"{out['wall_s']} s, {out['realtime_factor']}x real time")
    print(f"a step: {out['run_step_us']} us, of which MuJoCo's own step of the same states "
          f"{out['mujoco_step_us']} us ({100 * out['mujoco_step_share']:.0f} %); {out['mujoco_steps_per_step']} "
          f"MuJoCo steps per step (the slack switching's redos), {100 * out['mujoco_steps_share']:.0f} % of the time")
    if args.check:
        c = out["check"]
        print(f"against dt = {c['fine_timestep']:g} s: mean ship tension {100 * c['ship_tension_mean_rel']:+.3f} %, "
              f"mean tow tension {100 * c['tow_tension_mean_rel']:+.2f} % ({c['tow_tension_mean_N'][0]} vs "
              f"{c['tow_tension_mean_N'][1]} N; gait ripple std {c['tow_tension_std_N'][0]} vs "
              f"{c['tow_tension_std_N'][1]} N), robot's final position {c['robot_final_distance_m']} m apart")


if __name__ == "__main__":
    main()

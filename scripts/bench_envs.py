"""Benchmark: environment steps per second and reset time of every mjtether environment.

``mjtether/TetherWinch-v0`` (30-segment tether, the legged walker) with random actions: one
environment on one core, and an async vector of two; resets are included (each builds the
episode's model and quasi-static start). An environment step is ``frame_skip`` physics steps
(default 10 x 10 ms = 0.1 s of simulated time); ``physics_steps_per_s`` is the same throughput
counted in MuJoCo steps.

For each environment (``envs``, with its default settings): ``steps_per_s`` with random
actions (resets excluded), ``reset_ms`` (mean of ``--resets`` seeded resets after ``WARM_UP``
others, the best of ``ROUNDS``; ``reset_in_mujoco_steps``: that in bare ``mj_step``s of the
episode's model, a ratio that holds from machine to machine), and
``mujoco_bound_steps_per_s``: the environment steps per second MuJoCo alone would allow, from
its own ``mj_step`` of the episode's model with the tether's and bodies' forces (the native
callback) and nothing else: no controller, winch, slack switching or readout. The gap between
the two is the environment's Python; the bound is where MuJoCo sets the limit.

A native batch (``gym.make_vec`` stepping many models by ``mujoco.rollout`` threads) is not
offered: every environment runs a controller in Python between physics steps (the walker's
gait, the ROV's thruster allocation, the winch), which a rollout cannot call.

    python scripts/bench_envs.py [--steps 3000] [--frame-skip 10] [--resets 10] [--json]
"""

from __future__ import annotations

import argparse
import json
import time

import gymnasium as gym
import mujoco
import numpy as np

import mjtether.envs  # noqa: F401 - registers the environments

ENV_ID = "mjtether/TetherWinch-v0"
ENV_IDS = ("mjtether/TetherWinch-v0", "mjtether/TetheredWalker-v0", "mjtether/TetheredROV-v0")
WARM_UP = 20
"""Resets (other seeds) before the timed ones: a training run resets thousands of times, and its
first few fill the caches every later reset reads (the walker's stand on each seabed, the
cable's parts for each element layout: ``TetherWinch-v0``'s spread of lengths gives about seven
layouts). Before 2026-11-27 one reset warmed up, so the first reset of each layout was timed too."""
ROUNDS = 5
"""Rounds of the timed resets (the same seeds each round): ``reset_ms`` is the lowest round's
mean, as ``timeit`` takes the best of its repeats. Other jobs on a shared machine only add time,
and here they swing a round's mean by up to 1.5x; every round is kept in ``reset_ms_rounds``
(before 2026-11-27: one round)."""


def profile(env_id: str, steps: int, resets: int) -> dict:
    """Steps per second (resets excluded), mean reset time and MuJoCo's bound of ``env_id``."""
    env = gym.make(env_id)
    env.action_space.seed(0)
    for seed in range(1000, 1000 + WARM_UP):  # (caches: see WARM_UP)
        env.reset(seed=seed)
    rounds = []  # the mean reset of each round over the same seeds
    for _ in range(ROUNDS):
        t_reset = []
        for seed in range(1, resets + 1):
            t0 = time.perf_counter()
            env.reset(seed=seed)
            t_reset.append(time.perf_counter() - t0)
        rounds.append(float(np.mean(t_reset)))
    wall, done = 0.0, 0
    while done < steps:
        t0 = time.perf_counter()
        _, _, term, trunc, _ = env.step(env.action_space.sample())
        wall += time.perf_counter() - t0
        done += 1
        if term or trunc:
            env.reset()
    u = env.unwrapped
    sim, frame_skip = u.runner.sim, u.frame_skip
    state = sim.save_state()
    n = max(200, steps)
    t0 = time.perf_counter()
    mujoco.mj_step(sim.model, sim.data, n)  # (the native callback applies the loads)
    bare = (time.perf_counter() - t0) / n
    sim.restore_state(state)
    env.close()
    return {"steps_per_s": round(done / wall, 1), "reset_ms": round(1e3 * min(rounds), 1),
            "reset_ms_rounds": [round(1e3 * r, 1) for r in rounds],
            "reset_in_mujoco_steps": round(min(rounds) / bare),
            "mujoco_bound_steps_per_s": round(1.0 / (bare * frame_skip), 1), "frame_skip": frame_skip}


def single(steps: int, frame_skip: int) -> float:
    env = gym.make(ENV_ID, frame_skip=frame_skip)
    env.action_space.seed(0)
    env.reset(seed=0)
    t0 = time.perf_counter()
    for _ in range(steps):
        _, _, term, trunc, _ = env.step(env.action_space.sample())
        if term or trunc:
            env.reset()
    rate = steps / (time.perf_counter() - t0)
    env.close()
    return rate


def vector(steps: int, frame_skip: int, n: int = 2) -> float:
    venv = gym.make_vec(ENV_ID, num_envs=n, vectorization_mode="async", frame_skip=frame_skip)
    venv.action_space.seed(0)
    venv.reset(seed=list(range(n)))
    t0 = time.perf_counter()
    for _ in range(steps // n):
        venv.step(venv.action_space.sample())  # (autoreset inside)
    rate = (steps // n) * n / (time.perf_counter() - t0)
    venv.close()
    return rate


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--frame-skip", type=int, default=10)
    ap.add_argument("--resets", type=int, default=10)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    s = single(args.steps, args.frame_skip)
    v = vector(args.steps, args.frame_skip)
    envs = {e.split("/")[1]: profile(e, args.steps // 3, args.resets) for e in ENV_IDS}
    out = {"env": ENV_ID, "segments": 30, "frame_skip": args.frame_skip, "timestep": 0.01,
           "steps_per_s_single": round(s, 1), "steps_per_s_async2": round(v, 1),
           "physics_steps_per_s_single": round(s * args.frame_skip, 1),
           "simulated_s_per_wall_s_single": round(s * args.frame_skip * 0.01, 2), "envs": envs}
    if args.json:
        print(json.dumps(out))
    else:
        print(f"{ENV_ID}, N = 30, frame_skip {args.frame_skip}: {out['steps_per_s_single']} steps/s on one core "
              f"({out['physics_steps_per_s_single']} MuJoCo steps/s, {out['simulated_s_per_wall_s_single']}x real "
              f"time); async vector of 2: {out['steps_per_s_async2']} steps/s")
        for name, r in envs.items():
            print(f"{name} (frame_skip {r['frame_skip']}): {r['steps_per_s']} steps/s, reset {r['reset_ms']} ms; "
                  f"MuJoCo alone would allow {r['mujoco_bound_steps_per_s']} steps/s")


if __name__ == "__main__":
    main()

"""Benchmark: environment steps per second of ``mjtether/TetherWinch-v0`` (30-segment tether,
the legged walker) with random actions: one environment on one core, and an async vector of two.
Resets are included (each builds the episode's model and quasi-static start).

    python scripts/bench_envs.py [--steps 3000] [--frame-skip 10] [--json]

An environment step is ``frame_skip`` physics steps (default 10 x 10 ms = 0.1 s of simulated
time); ``physics_steps_per_s`` is the same throughput counted in MuJoCo steps.
"""

from __future__ import annotations

import argparse
import json
import time

import gymnasium as gym

import mjtether.envs  # noqa: F401 - registers the environments

ENV_ID = "mjtether/TetherWinch-v0"


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
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    s = single(args.steps, args.frame_skip)
    v = vector(args.steps, args.frame_skip)
    out = {"env": ENV_ID, "segments": 30, "frame_skip": args.frame_skip, "timestep": 0.01,
           "steps_per_s_single": round(s, 1), "steps_per_s_async2": round(v, 1),
           "physics_steps_per_s_single": round(s * args.frame_skip, 1),
           "simulated_s_per_wall_s_single": round(s * args.frame_skip * 0.01, 2)}
    if args.json:
        print(json.dumps(out))
    else:
        print(f"{ENV_ID}, N = 30, frame_skip {args.frame_skip}: {out['steps_per_s_single']} steps/s on one core "
              f"({out['physics_steps_per_s_single']} MuJoCo steps/s, {out['simulated_s_per_wall_s_single']}x real "
              f"time); async vector of 2: {out['steps_per_s_async2']} steps/s")


if __name__ == "__main__":
    main()

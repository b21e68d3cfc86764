"""The environments start every episode with the walker standing, and only a real tension ends
an episode at the rated load."""

import gymnasium as gym
import numpy as np
import pytest
from helpers import pose_errors

import mjtether.envs  # noqa: F401 - registers the environments


@pytest.mark.slow
@pytest.mark.parametrize("env_id, resets", [("mjtether/TetherWinch-v0", 100), ("mjtether/TetheredWalker-v0", 30)])
def test_randomised_resets_start_upright(env_id, resets):
    """Randomised resets (the issue's 100 of TetherWinch-v0, seeds 0-99, and 30 more of
    TetheredWalker-v0, which builds the same start around a different goal): at every step
    (0.1 s) of the first 5 s, with the winch stopped, the walker is within 2 deg of upright and
    of its commanded heading (the issue's requirement; measured at most 0.5 deg and 0.9 deg).
    Every one starts from the quasi-static steady state, none from the settling fallback (seed
    93 of TetherWinch-v0 settled for want of one until ``start.REFINE_START`` tried 2N and 3N
    elements)."""
    env = gym.make(env_id).unwrapped
    worst, settled = [], []
    try:
        for seed in range(resets):
            env.reset(seed=seed)
            if not env.runner.initial_note.startswith("quasi-static steady state"):
                settled.append((seed, env.runner.initial_note))
            errors = [pose_errors(env.runner)]
            for _ in range(50):
                env.step(np.zeros(env.action_space.shape, dtype=np.float32))
                errors.append(pose_errors(env.runner))
            worst.append(np.max(errors, axis=0))
    finally:
        env.close()
    worst = np.array(worst)
    assert worst[:, 0].max() <= 2.0 and worst[:, 1].max() <= 2.0, worst.max(axis=0)
    assert not settled, settled


@pytest.mark.slow
def test_full_payout_episodes_end_only_on_real_tension():
    """20 TetherWinch-v0 episodes (seeds 0-19) of 30 s paying out at the full rate: the cable
    lands on the seabed as it goes, and no real tension comes near the 3 kN rated load (the
    ship-end tension peaks at 1.7 kN in the first three seeds). Before tension-only elements,
    compression spikes at touchdown, reported as tension, ended 65 % of such episodes at the
    rated load; now none ends there, and every element tension is finite and >= 0 at every step."""
    env = gym.make("mjtether/TetherWinch-v0", max_episode_steps=300)
    broke, peak = 0, 0.0
    try:
        for seed in range(20):
            env.reset(seed=seed)
            done = False
            while not done:
                _, _, terminated, truncated, info = env.step(np.ones(1, dtype=np.float32))
                done = terminated or truncated
                bt, d = env.unwrapped.runner.bt, env.unwrapped.runner.sim.data
                tension = bt.element_tension(d)
                assert np.all(np.isfinite(tension)) and tension.min() >= 0.0
                broke += info["rated_load_exceeded"]
                peak = max(peak, info["ship_tension"])
    finally:
        env.close()
    assert broke == 0, peak

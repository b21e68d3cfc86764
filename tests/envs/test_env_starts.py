"""The environments start every episode with the walker standing, and only a real tension ends
an episode at the rated load."""

import gymnasium as gym
import numpy as np
import pytest
from helpers import pose_errors, raw_element_forces

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
    lands on the seabed as it goes, and no real tension comes near the 3 kN rated load. Before
    tension-only elements, compression spikes at touchdown, reported as tension, ended 65 % of
    such episodes at the rated load; now none ends there. Checked at every environment step
    (0.1 s) on MuJoCo's own constraint forces (``efc_force`` of each element's equality row, not
    the readouts, which clip at zero): every one finite, no element pulls with the rated load or
    more (the criterion the episode applies to the ship end, applied to every element; measured:
    at most 1.28 kN, down the cable; the ship end at most 0.93 kN), and the readout's element
    tension is that pull, max(-efc_force, 0), exactly."""
    env = gym.make("mjtether/TetherWinch-v0", max_episode_steps=300)
    broke, peak, worst = 0, 0.0, 0.0
    try:
        rated = env.unwrapped.rated_load
        for seed in range(20):
            env.reset(seed=seed)
            done = False
            while not done:
                _, _, terminated, truncated, info = env.step(np.ones(1, dtype=np.float32))
                done = terminated or truncated
                bt, d = env.unwrapped.runner.bt, env.unwrapped.runner.sim.data
                f = raw_element_forces(bt, d)
                assert np.all(np.isfinite(f))
                np.testing.assert_array_equal(bt.element_tension(d), np.maximum(-f, 0.0))
                worst = max(worst, float(-f.min()))
                broke += info["rated_load_exceeded"]
                peak = max(peak, info["ship_tension"])
    finally:
        env.close()
    assert broke == 0, peak
    assert worst < rated, (worst, rated)

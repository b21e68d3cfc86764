"""The Gymnasium environments: API conformance, determinism, vector environments, robustness,
baselines and the PPO training script's smoke run."""

import importlib.util
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import mjtether.envs  # noqa: F401 - registers the environments
from mjtether.envs import FollowPayout, SteerToGoal, TetheredWalkerEnv, TetherWinchEnv

IDS = ["mjtether/TetherWinch-v0", "mjtether/TetheredWalker-v0", "mjtether/TetheredROV-v0"]
ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("env_id", IDS)
def test_check_env_passes(env_id):
    env = gym.make(env_id).unwrapped
    try:
        check_env(env, skip_render_check=True)
    finally:
        env.close()


@pytest.mark.parametrize("env_id", IDS)
def test_registration_and_spaces(env_id):
    spec = gym.spec(env_id)
    assert spec.max_episode_steps in (600, 900)
    env = gym.make(env_id)
    try:
        obs, info = env.reset(seed=3)
        assert env.observation_space.contains(obs) and np.all(np.isfinite(obs))
        assert {"ship_tension", "tow_tension", "deployed_length"} <= set(info)
        _, _, _, _, info = env.step(env.action_space.sample())
        assert any(k.startswith("reward_") for k in info)
    finally:
        env.close()


def _rollout(env, seed, n=15):
    obs, _ = env.reset(seed=seed)
    env.action_space.seed(seed)
    out = [obs]
    for _ in range(n):
        obs, r, term, trunc, _ = env.step(env.action_space.sample())
        out.append(np.r_[obs.astype(float), r])  # (a Python float would be cast to float32)
        if term or trunc:
            break
    return out


@pytest.mark.parametrize("env_id", IDS)
def test_reset_with_a_seed_is_deterministic(env_id):
    """Two environments reset with the same seed and given the same actions agree bitwise; a
    different seed draws a different episode (current, route or goal)."""
    a, b = gym.make(env_id), gym.make(env_id)
    try:
        ra, rb = _rollout(a, 7), _rollout(b, 7)
        assert all(np.array_equal(x, y) for x, y in zip(ra, rb))
        assert not np.array_equal(_rollout(b, 8, n=0)[0], ra[0])
    finally:
        a.close()
        b.close()


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_vector_envs_match_single_envs(mode):
    """Two TetherWinch-v0 copies in a vector environment (sync: two models in one process,
    sharing MuJoCo's passive-force callback; async: subprocesses) give the same observations and
    rewards as single environments with the same seeds and actions."""
    seeds, n = [11, 12], 5
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, (n, 2, 1)).astype(np.float32)
    venv = gym.make_vec(IDS[0], num_envs=2, vectorization_mode=mode)
    try:
        obs, _ = venv.reset(seed=seeds)
        vec = [obs]
        for k in range(n):
            obs, r, _, _, _ = venv.step(actions[k])
            vec.append(np.c_[obs.astype(float), r])
    finally:
        venv.close()
    for i, s in enumerate(seeds):
        env = gym.make(IDS[0])
        try:
            obs, _ = env.reset(seed=s)
            single = [obs]
            for k in range(n):
                obs, r, _, _, _ = env.step(actions[k, i])
                single.append(np.r_[obs.astype(float), r])
        finally:
            env.close()
        assert np.array_equal(vec[0][i], single[0])
        assert all(np.array_equal(vec[k][i], single[k]) for k in range(1, n + 1))


@pytest.mark.slow
@pytest.mark.parametrize("cls", [TetherWinchEnv, TetheredWalkerEnv])
def test_ten_thousand_random_steps(cls):
    """10 000 random actions, resetting on termination or truncation: no exception and every
    observation finite and inside the observation space."""
    env = gym.wrappers.TimeLimit(cls(), 600 if cls is TetherWinchEnv else 900)
    env.action_space.seed(0)
    try:
        obs, _ = env.reset(seed=0)
        episodes = 1
        for _ in range(10_000):
            obs, r, term, trunc, _ = env.step(env.action_space.sample())
            assert np.all(np.isfinite(obs)) and np.isfinite(r) and env.observation_space.contains(obs)
            if term or trunc:
                obs, _ = env.reset()
                episodes += 1
        assert episodes >= 2
    finally:
        env.close()


def test_baselines_do_their_job():
    """The payout rule pays out at the walker's speed (Khan et al.'s Eq. 30): over 6 s of
    TetherWinch-v0 (seed 1, after 3 s of the rule), the cable paid out equals the distance the
    walker's torso covered, summed from MuJoCo's own body positions (``xpos``) after every
    environment step (0.1 s), to 5 % (the rule holds the torso's velocity of the start of each
    0.1 s step while the gait makes the speed vary within a stride, and the 0.1 s chords cut the
    gait's sway a little short; measured: 1.6 %). Steering to the goal reaches it."""
    env = gym.make(IDS[0])
    try:
        env.reset(seed=1)
        for _ in range(30):
            env.step(FollowPayout()(env))
        run = env.unwrapped.runner
        d = run.sim.data
        length0, p, path = run.bt.deployed_length, d.xpos[run.torso][:2].copy(), 0.0
        for _ in range(60):
            env.step(FollowPayout()(env))
            q = d.xpos[run.torso][:2].copy()
            path, p = path + float(np.hypot(*(q - p))), q
        paid = run.bt.deployed_length - length0
        assert path > 1.0  # the walker walked (1.5 m)
        assert paid == pytest.approx(path, rel=0.05)
    finally:
        env.close()
    env = gym.make(IDS[1])
    try:
        env.reset(seed=2)
        done, info = False, {}
        while not done:
            _, _, term, trunc, info = env.step(SteerToGoal()(env))
            done = term or trunc
        assert info["is_success"]
    finally:
        env.close()


def test_rgb_array_rendering():
    env = gym.make(IDS[0], render_mode="rgb_array", width=160, height=120)
    try:
        env.reset(seed=0)
        frame = env.render()
        assert frame.shape == (120, 160, 3) and frame.std() > 5
    finally:
        env.close()


def test_depth_array_reads_the_distance_to_the_seabed():
    """``render_mode="depth_array"`` from the top view, which looks straight down: the seabed is a
    plane facing the camera, so every pixel that sees it reads the camera's height above it (the
    depth is along the viewing axis). That height comes from the camera's position, which MuJoCo
    reports in the scene, and the seabed's, -depth; most pixels see the seabed, so the median is
    that height within 0.5 % (the view is tilted 0.1 deg off vertical; the depth buffer's
    resolution at that range is a few cm). The walker and tether, nearer, read less."""
    env = gym.make(IDS[0], render_mode="depth_array", width=160, height=120,
                   default_camera_config={"camera": "top"})
    try:
        env.reset(seed=0)
        depth = env.render()
        base = env.unwrapped
        cam = base._renderer.scene.camera
        z_cam = 0.5 * (cam[0].pos[2] + cam[1].pos[2])
        height = z_cam + base.depth
        assert depth.shape == (120, 160) and depth.dtype == np.float32 and np.all(np.isfinite(depth))
        assert float(np.median(depth)) == pytest.approx(height, rel=0.005)
        assert depth.min() < 0.99 * height  # something (the walker, the tether) stands above the seabed
    finally:
        env.close()


def test_bad_constructor_arguments_are_refused():
    with pytest.raises(ValueError, match=r"frame_skip = 0: must be an integer in \[1, 1000\]"):
        TetherWinchEnv(frame_skip=0)
    with pytest.raises(ValueError, match=r"max_length = 50.0: must be >= tether_length \(130 m\)"):
        TetherWinchEnv(max_length=50.0)


@pytest.mark.skipif(importlib.util.find_spec("stable_baselines3") is None,
                    reason="Stable-Baselines3 is the optional [learning] extra")
def test_ppo_training_script_smoke(tmp_path):
    """A few hundred steps of training, then both controllers on one evaluation seed (run as
    the script is run: in its own process)."""
    import subprocess
    import sys

    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "train_ppo.py"), "--timesteps", "256",
                        "--eval-seeds", "1", "--envs", "1", "--out", str(tmp_path)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    assert "| PPO policy" in r.stdout and "Eq. 30" in r.stdout
    assert {"policy.zip", "vecnormalize.pkl", "learning_curve.png", "evaluation.json"} <= {
        p.name for p in tmp_path.iterdir()}

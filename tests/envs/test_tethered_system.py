"""``mjtether/TetheredSystem-v0``: a vehicle of a system file (a network) flown by the agent;
Gymnasium conformance, the named observation, the reward terms, the physics of the default
system with the thrusters off, seeding and restoring, divergence, bad arguments, a MoorDyn file's
lines."""

import dataclasses
import math
import pickle
from pathlib import Path

import gymnasium as gym
import mujoco
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import mjtether.envs  # noqa: F401 - registers the environments
from mjtether.envs import TetheredSystemEnv
from mjtether.io.moordyn import load_any
from mjtether.network import Vehicle

ID = "mjtether/TetheredSystem-v0"
ROOT = Path(__file__).resolve().parents[2]
SYSTEM = ROOT / "examples" / "networks" / "rov_cage_excursion.toml"
MOORDYN = ROOT / "tests" / "data" / "moordyn" / "example" / "lines.txt"
G = 9.80665  # the network's default gravity (MoorDyn-C's), m/s^2
RHO = 1025.0  # the network's default water density, kg/m^3


@pytest.fixture(scope="module")
def env():
    e = gym.make(ID)
    yield e
    e.close()


def test_check_env_passes_and_it_is_registered():
    e = gym.make(ID, system=str(SYSTEM))
    try:
        assert gym.spec(ID).max_episode_steps == 600
        check_env(e.unwrapped, skip_render_check=True)
    finally:
        e.close()


def test_observation_names_every_element_and_every_line(env):
    """One name per element, all different; each line of the file has its end A and end B
    tension, read from the file itself (not from the environment)."""
    e = env.unwrapped
    obs, _ = env.reset(seed=0)
    names = e.observation_names
    assert isinstance(names, tuple) and all(isinstance(n, str) for n in names)
    assert len(names) == obs.shape[0] == e.observation_space.shape[0] and len(set(names)) == len(names)
    lines = [ln.name for ln in load_any(str(SYSTEM)).lines]
    assert lines == ["umbilical", "excursion"]
    for ln in lines:
        for end in "AB":
            assert f"line {ln} {end} tension kN" in names


def test_reward_terms_sum_to_the_reward_and_are_what_they_say():
    """Under random thrust: the four terms sum to the reward (to 1e-12, float rounding), and the
    distance and tension terms are recomputed here from the model's own state: the vehicle's
    origin by MuJoCo's kinematics of qpos in a fresh MjData, each line's tension as the norm of
    its end forces, rated 50 N (so that the term is active; 1e-9 relative: the same arithmetic)."""
    e = gym.make(ID, rated_tension=50.0, w_tension=0.5, w_distance=2.0, distance_ref=4.0)
    try:
        env = e.unwrapped
        e.reset(seed=4)
        e.action_space.seed(4)
        scratch = mujoco.MjData(env.runner.sim.model)
        seen_tension = False
        for _ in range(20):
            a = e.action_space.sample()
            _, r, term, trunc, info = e.step(a)
            terms = {k: v for k, v in info.items() if k.startswith("reward_")}
            assert set(terms) == {"reward_distance", "reward_control", "reward_tension", "reward_failure"}
            assert r == pytest.approx(sum(terms.values()), abs=1e-12)
            run = env.runner
            scratch.qpos[:] = run.sim.data.qpos
            mujoco.mj_kinematics(run.sim.model, scratch)
            p = scratch.xpos[run.sim.model.body("body/rov").id]
            assert terms["reward_distance"] == pytest.approx(-2.0 * np.linalg.norm(p - info["station"]) / 4.0, rel=1e-9)
            over = sum(max(max(np.linalg.norm(f) for f in run.line_forces(ln)) / 50.0 - 1.0, 0.0)
                       for ln in ("umbilical", "excursion"))
            assert terms["reward_tension"] == pytest.approx(-0.5 * over, rel=1e-9)
            assert terms["reward_control"] == pytest.approx(-0.05 * np.mean(np.asarray(a, float) ** 2), rel=1e-6)
            seen_tension |= over > 0
            assert not (term or trunc)
        assert seen_tension
    finally:
        e.close()


def test_thrusters_off_the_vehicle_drifts_with_the_current_and_the_cage_hangs(env):
    """20 s with zero action. (1) The tension elements of the observation are the run's own end
    forces' norms in kN (float32: 1e-6 relative). (2) The ROV drifts downstream (+x) at the
    current's speed at its depth, interpolated here from the file's table (0.3, 0.2, 0.15, 0.1 m/s
    at 0, 50, 100, 150 m): within 5 % (it is still slowing into the drift, and its slack tether
    pulls a little), across-stream under 1 mm/s. (3) Archimedes: the cage (800 kg, 0.3 m^3)
    hangs on the umbilical, whose end A carries its weight less its buoyancy, (m - rho V) g, and
    end B that plus the umbilical's wet weight (3.2 kg/m less rho pi d^2/4, 100 m): within 1 %
    (the cage's and the umbilical's drag, ~20 N across, and what is left of the drop's
    oscillation)."""
    e = env.unwrapped
    obs, _ = env.reset(seed=0)
    for _ in range(200):
        obs, _, term, trunc, info = env.step(np.zeros(env.action_space.shape))
        assert not (term or trunc)
    names = e.observation_names
    run = e.runner
    for ln in ("umbilical", "excursion"):
        fa, fb = run.line_forces(ln)
        assert obs[names.index(f"line {ln} A tension kN")] == pytest.approx(np.linalg.norm(fa) / 1000.0, rel=1e-6)
        assert obs[names.index(f"line {ln} B tension kN")] == pytest.approx(np.linalg.norm(fb) / 1000.0, rel=1e-6)
    depth = -info["position"][2]
    current = np.interp(depth, [0.0, 50.0, 100.0, 150.0], [0.3, 0.2, 0.15, 0.1])
    assert obs[names.index("rov vx m/s")] == pytest.approx(current, rel=0.05)
    assert abs(obs[names.index("rov vy m/s")]) < 1e-3
    cage_wet = (800.0 - RHO * 0.3) * G
    umbilical_wet = (3.2 - RHO * math.pi * 0.035 ** 2 / 4) * G * 100.0
    assert 1000.0 * obs[names.index("line umbilical A tension kN")] == pytest.approx(cage_wet, rel=0.01)
    assert 1000.0 * obs[names.index("line umbilical B tension kN")] == pytest.approx(cage_wet + umbilical_wet, rel=0.01)


def test_seeded_reset_repeats_and_restores_the_start_exactly():
    """The same seed gives the same first observation twice (after an episode in between), a
    different seed another station; and after a reset the run steps exactly (bit for bit) as a
    freshly built environment's does: the restore of the steady start is exact."""
    e = gym.make(ID, station_noise=5.0)
    fresh = gym.make(ID, station_noise=5.0)
    try:
        first, info = e.reset(seed=7)
        assert np.linalg.norm(info["station"] - np.array([-30.0, 0.0, -100.0])) <= 5.0
        e.action_space.seed(0)
        for _ in range(15):
            e.step(e.action_space.sample())
        again, _ = e.reset(seed=7)
        assert np.array_equal(first, again)
        other, _ = e.reset(seed=8)
        assert not np.array_equal(first, other)
        e.reset(seed=7)
        fresh.reset(seed=7)
        a = np.linspace(-1.0, 1.0, e.action_space.shape[0])
        for _ in range(10):
            o1, r1, *_ = e.step(a)
            o2, r2, *_ = fresh.step(a)
            assert np.array_equal(o1, o2) and r1 == r2
    finally:
        e.close()
        fresh.close()


def test_a_divergence_ends_the_episode_without_nan(env):
    """A tether node kicked to 1e4 m/s (past the simulation's node-speed limit) ends the episode
    with the divergence's message in info; the observation stays finite; reset starts again."""
    e = env.unwrapped
    env.reset(seed=0)
    env.step(np.zeros(env.action_space.shape))
    bt = e.runner.sim.tethers["excursion"]
    e.runner.sim.data.qvel[bt._dof0 + 3 * bt.n] = 1e4
    obs, r, term, trunc, info = env.step(np.zeros(env.action_space.shape))
    assert term and not trunc
    assert "diverged" in info["diverged"] and np.all(np.isfinite(obs)) and math.isfinite(r)
    with pytest.raises(RuntimeError, match="diverged"):
        env.step(np.zeros(env.action_space.shape))
    obs, info = env.reset(seed=0)
    assert info["diverged"] is None and np.all(np.isfinite(obs))
    assert not env.step(np.zeros(env.action_space.shape))[2]


def test_bad_system_or_vehicle_is_refused_naming_it(tmp_path):
    missing = tmp_path / "no_such_system.toml"
    with pytest.raises(ValueError, match="no_such_system.toml"):
        TetheredSystemEnv(system=str(missing))
    with pytest.raises(ValueError, match=r"vehicle = 'auv' is not a vehicle of .*; its vehicles: rov"):
        TetheredSystemEnv(vehicle="auv")
    with pytest.raises(ValueError, match="lines.txt.* has no vehicle"):
        TetheredSystemEnv(system=str(MOORDYN))
    with pytest.raises(ValueError, match="single-tether scenario"):
        TetheredSystemEnv(system=str(ROOT / "examples" / "default_walker.toml"))
    with pytest.raises(ValueError, match=r"station = \[1.0, 2.0, -3.0\]: its depth"):
        TetheredSystemEnv(station=(1.0, 2.0, -3.0))
    with pytest.raises(ValueError, match="unknown keyword argument 'frameskip'"):
        TetheredSystemEnv(frameskip=3)


def test_a_moordyn_files_lines_with_a_vehicle():
    """A MoorDyn file holds no vehicle (mjtether's MoorDyn reader has none, its writer refuses
    them): MoorDyn's example lines.txt (three catenary lines, 120 degrees apart) with a BlueROV2
    added in Python is a system the environment flies. Each line is named; their tensions are
    the run's end forces; and the spread's symmetry, not the code, says the three lines' tensions
    at each end are equal (within 0.1 %: fairlead 1 sits 5.2 m out, 2 and 3 5.197 m)."""
    net = load_any(str(MOORDYN))
    net = dataclasses.replace(net, vehicles={"rov": Vehicle("rov", "bluerov2_heavy", (20.0, 0.0, -30.0), 0.0)})
    e = TetheredSystemEnv(system=net)
    try:
        obs, _ = e.reset(seed=0)
        for _ in range(5):
            obs, _, term, _, _ = e.step(np.zeros(8))
            assert not term
        names = e.observation_names
        tens = {}
        for ln in ("1", "2", "3"):
            for end, f in zip("AB", e.runner.line_forces(ln)):
                tens[ln, end] = obs[names.index(f"line {ln} {end} tension kN")]
                assert tens[ln, end] == pytest.approx(np.linalg.norm(f) / 1000.0, rel=1e-6)
        for end in "AB":
            assert tens["2", end] == pytest.approx(tens["1", end], rel=1e-3)
            assert tens["3", end] == pytest.approx(tens["1", end], rel=1e-3)
    finally:
        e.close()


def test_rgb_array_frame_and_pickling():
    e = gym.make(ID, render_mode="rgb_array", width=96, height=72)
    try:
        e.reset(seed=1)
        e.step(np.zeros(e.action_space.shape))
        frame = e.render()
        assert frame.shape == (72, 96, 3) and frame.dtype == np.uint8 and frame.std() > 1.0
        copy = pickle.loads(pickle.dumps(e.unwrapped))
        try:
            assert np.array_equal(copy.reset(seed=3)[0], e.reset(seed=3)[0])
        finally:
            copy.close()
    finally:
        e.close()

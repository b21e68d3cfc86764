"""The hexapod walker on a flat seabed, underwater, without a tether: speed tracking and turning
against the commanded kinematics (the independent answer: distance = speed x time, and a circle
of radius v / w)."""

import math

import mujoco
import numpy as np
import pytest

import mjtether as mt
from mjtether.walker import ASSETS, HYDRO, MASS, Tripod, leg_ik

DEPTH = 50.0


def _walk(speed, turn_rate, duration, sample_every=100, period=1.2):
    spec = mujoco.MjSpec.from_file(str(ASSETS / "scene.xml"))
    spec.geom("seabed").pos = [0, 0, -DEPTH]
    spec.body("torso").pos = [0, 0, -DEPTH + 0.9]
    water = mt.WaterColumn(depth=DEPTH)
    bm = mt.add_body_hydro(spec, "torso", HYDRO)
    with mt.Simulation(spec, water, bodies=[bm]) as sim:
        m, d = sim.model, sim.data
        gait = Tripod(period=period).bind(m)
        torso, dt = m.body("torso").id, m.opt.timestep
        for _ in range(int(1.0 / dt)):  # settle on the seabed, stepping in place
            d.ctrl[gait.actuators] = gait.targets(dt, 0.0, 0.0)
            sim.step()
        track = [d.xpos[torso].copy()]
        for k in range(int(round(duration / dt))):
            d.ctrl[gait.actuators] = gait.targets(dt, speed, turn_rate)
            sim.step()
            if (k + 1) % sample_every == 0:
                track.append(d.xpos[torso].copy())
        return np.array(track), float(np.sum(m.body_mass))


def test_leg_ik_round_trip():
    """The IK angles put the foot back where asked (forward kinematics written independently)."""
    for p in ([0.65, 0.0, -0.8], [0.8, 0.2, -0.7], [0.5, -0.3, -0.6]):
        q0, q1, q2 = leg_ik(p)
        r = 0.15 + 0.5 * math.cos(q1) - 0.8 * math.sin(q1 + q2)
        z = -0.5 * math.sin(q1) - 0.8 * math.cos(q1 + q2)
        np.testing.assert_allclose([r * math.cos(q0), r * math.sin(q0), z], p, atol=1e-9)
    with pytest.raises(ValueError, match="out of reach"):
        leg_ik([3.0, 0.0, 0.0])


@pytest.mark.parametrize("speed", [0.1, 0.3, 0.5])
def test_walker_tracks_the_commanded_speed(speed):
    """Average forward speed over 30 s within 10 % of the command (the issue's target; 0.102,
    0.305 and 0.499 m/s seen)."""
    track, mass = _walk(speed, 0.0, 30.0)
    assert mass == pytest.approx(MASS)
    mean = np.linalg.norm(track[-1, :2] - track[0, :2]) / 30.0
    assert mean == pytest.approx(speed, rel=0.10)
    assert abs(track[-1, 2] - track[0, 2]) < 0.05  # it walks, it does not sink or climb


def test_walker_reaches_two_knots_with_a_quick_gait():
    """The paper's robot walks at 2 kn (1.029 m/s). With a 0.8 s gait cycle and a 1.2 m/s command
    the walker averages more than that over 30 s (1.11 m/s seen); the open-loop gait drifts a
    little sideways at that pace (2.8 m in 33 m seen), so only the forward speed is checked."""
    track, _ = _walk(1.2, 0.0, 30.0, period=0.8)
    assert (track[-1, 0] - track[0, 0]) / 30.0 > 2 * 0.514444


def test_walker_walks_a_10_m_circle():
    """0.3 m/s at 0.03 rad/s for one full turn: the fitted circle has a 10 m radius within 5 %
    (10.43 m seen: the feet slip a little when turning) and the track stays on it (1 % spread)."""
    v, w = 0.3, 0.03
    track, _ = _walk(v, w, 2 * math.pi / w)
    P = track[:, :2]
    c = np.linalg.lstsq(np.c_[2 * P, np.ones(len(P))], (P**2).sum(1), rcond=None)[0]
    radius = math.sqrt(c[2] + c[0] ** 2 + c[1] ** 2)
    assert radius == pytest.approx(v / w, rel=0.05)
    assert np.std(np.linalg.norm(P - c[:2], axis=1)) < 0.01 * radius


def test_compiled_gait_matches_the_python_gait(monkeypatch):
    """``walker.tripod_targets`` against ``Tripod.targets``' Python loop through ``leg_ik``
    (the round trip above checks that one): 300 random phases, speeds and turn rates, the
    stride limit reached, to 1e-12 rad; a foot out of reach raises the same error."""
    from mjtether.physics import compiled

    pytest.importorskip("numba")
    m = mujoco.MjModel.from_xml_path(str(ASSETS / "scene.xml"))
    fast = Tripod().bind(m)
    monkeypatch.setenv(compiled.KERNELS_ENV, "numpy")
    slow = Tripod().bind(m)
    assert fast._fast and not slow._fast
    rng = np.random.default_rng(5)
    for _ in range(300):
        dt, v, w = rng.uniform(0.0, 0.7), rng.uniform(-0.8, 0.8), rng.uniform(-0.6, 0.6)
        np.testing.assert_allclose(fast.targets(dt, v, w), slow.targets(dt, v, w), rtol=0, atol=1e-12)
    for gait in (fast, slow):
        gait.step_height = 5.0
        with pytest.raises(ValueError, match="out of reach"):
            for _ in range(20):
                gait.targets(0.1, 0.0, 0.0)

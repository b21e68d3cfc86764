"""Hong et al.'s (2020) wind load (their Eqs. 7-9, Fossen's coefficients) on the surface vessels
of a run (``[wind]``, ``scenario.weather``): the load a run applies against Eq. 7 written out
here, in Fossen's own frame (x forward, y starboard, z down, angles clockwise), from the relative
wind of the vessel's state (its velocity over the ground at its origin, in its horizontal axes:
Eq. 7 is a 3-DOF load); and the wind's bad input named."""

import math

import numpy as np
import pytest

from mjtether.scenario import ConfigError, load_scenario, weather
from mjtether.scenario.runner import ScenarioRun

KGF = 9.80665

ALONE = """
[simulation]
duration = 50.0
timestep = 0.01
output_interval = 0.5
[water]
depth = 50.0
[tether]
attached = false
[robot]
type = "vehicle"
vehicle = "hong2020_usv"
position = [0.0, 0.0, 0.0]
setpoints = [[0.0, 0.0, 0.0, 0.0]]
[wind]
speed = 6.0
direction_deg = 30.0
"""

SHIP = """
[simulation]
duration = 20.0
timestep = 0.005
output_interval = 0.5
[water]
depth = 20.0
[tether]
length = 25.0
segments = 10
diameter = 0.02
density = 3000.0
EA = 1.0e6
[winch]
mode = "fixed"
[ship]
vessel = "otter"
mode = "fixed"
position = [0.0, 0.0]
heading_deg = 40.0
[robot]
type = "anchor"
position = [-10.0, 0.0, -20.0]
[wind]
speed = 8.0
direction_deg = -100.0
cx = 0.6
"""


def fossen_eq7(V_w, beta_w, psi, u, v, A_T, A_L, L, cx, cy, cn, rho=1.225):
    """Eqs. 7-8 in Fossen's frame: the wind of speed ``V_w`` towards ``beta_w`` (rad, clockwise,
    NED), a craft of heading ``psi`` moving at (u, v) (m/s, body x forward, y starboard). Returns
    (X, Y, N): N, N, N m, body frame (y starboard, N positive bow to starboard)."""
    u_w, v_w = V_w * math.cos(beta_w - psi), V_w * math.sin(beta_w - psi)
    u_rw, v_rw = u - u_w, v - v_w
    V_r2 = u_rw ** 2 + v_rw ** 2
    gamma = -math.atan2(v_rw, u_rw)
    q = 0.5 * rho * V_r2
    return (q * -cx * math.cos(gamma) * A_T, q * cy * math.sin(gamma) * A_L, q * cn * math.sin(2 * gamma) * A_L * L)


def _check_steps(run, label, windage, speed, direction_deg, steps, before=None):
    """Step ``run``; before each step note the vessel's state, after it compare the applied load
    (``xfrc_applied``: moved back from the centre of mass to the origin) with ``fossen_eq7``.
    Returns the largest relative difference and the relative wind angles seen (rad)."""
    w = weather.attach(run)
    vessel = next(v for v in w.vessels if v.label == label)
    d, i = run.sim.data, vessel.body.id
    worst, gammas = 0.0, []
    for _ in range(steps):
        if before is not None:
            before(run)
        R = d.xmat[i].reshape(3, 3).copy()
        v_world = d.qvel[vessel.body._v].copy()  # the origin's velocity (world, z up)
        lever = d.xpos[i] - d.xipos[i]  # the origin from the centre of mass (m, world)
        run.step()
        psi = math.atan2(R[1, 0], R[0, 0])
        # to Fossen's NED frame: y and every angle change sign
        psi_n, beta_n = -psi, -math.radians(direction_deg)
        c, s_ = math.cos(psi), math.sin(psi)  # the vessel's horizontal axes (its heading; Eq. 7 is 3-DOF)
        vb = np.array([c * v_world[0] + s_ * v_world[1], -s_ * v_world[0] + c * v_world[1]])  # x fwd, y port
        X, Y, N = fossen_eq7(speed, beta_n, psi_n, vb[0], -vb[1], windage.frontal_area, windage.lateral_area,
                             windage.length, windage.cx, windage.cy, windage.cn)
        # back to the world frame, z up: the body force (X, -Y), the moment -N
        want_f = np.array([[c, -s_], [s_, c]]) @ np.array([X, -Y])
        f = d.xfrc_applied[i, :3]
        m = d.xfrc_applied[i, 3:] - np.cross(lever, f)  # about the origin
        scale = math.hypot(X, Y)
        worst = max(worst, np.max(np.abs(f[:2] - want_f)) / scale,
                    abs(m[2] - (-N)) / max(abs(N), scale * windage.length), abs(f[2]) / scale,
                    np.max(np.abs(m[:2])) / scale)
        u_rw = vb[0] - speed * math.cos(beta_n - psi_n)
        v_rw = -vb[1] - speed * math.sin(beta_n - psi_n)
        gammas.append(-math.atan2(v_rw, u_rw))
    return worst, np.array(gammas)


def test_the_wind_on_a_turning_usv_is_eq7_at_its_relative_wind():
    """The Hong USV alone turning open loop (29.2 / 14.6 kgf) in a 6 m/s wind: at every step the
    load applied is Eq. 7 of the relative wind (the wind minus the vessel's velocity), computed
    here in Fossen's frame from the state before the step, to 1e-9 of its size (rounding only),
    over relative wind angles all round the compass; no vertical force and, about the origin, no
    roll or pitch moment."""
    from mjtether.vehicles.wind import HONG2020_USV
    run = ScenarioRun(load_scenario(text=ALONE))
    try:
        run.release_pilot()
        m, d = run.sim.model, run.sim.data
        d.ctrl[m.actuator("vehicle/port").id] = 29.2 * KGF
        d.ctrl[m.actuator("vehicle/starboard").id] = 14.6 * KGF
        worst, gammas = _check_steps(run, "robot", HONG2020_USV, 6.0, 30.0, 4000)
    finally:
        run.close()
    assert worst < 1e-9
    span = np.ptp(np.unwrap(gammas))
    assert span > 2 * math.pi  # (a whole turn, 40 s: the relative wind all round)


def test_the_wind_on_the_ships_vessel_takes_the_otter_windage_and_the_keys_given():
    """``ship.vessel = "otter"`` on station with a tether to an anchor, in an 8 m/s wind and with
    ``wind.cx = 0.6``: the load is Eq. 7 with the Otter's windage and c_x = 0.6, to 1e-9."""
    from mjtether.vehicles.wind import OTTER
    run = ScenarioRun(load_scenario(text=SHIP))
    try:
        windage = type(OTTER)(OTTER.frontal_area, OTTER.lateral_area, OTTER.length, cx=0.6)
        worst, _ = _check_steps(run, "ship", windage, 8.0, -100.0, 400)
    finally:
        run.close()
    assert worst < 1e-9


@pytest.mark.parametrize("extra, key, words", [
    ("[wind]\nspeed = 2.0\n", "wind.speed", "acts on a surface vessel"),
    ("[wind]\nspeed = 2.0\nfrontal_area = 1.0\n", "wind.lateral_area", "together"),
    ("[wind]\ncn = 0.3\n", "wind.cn", r"\[0.05, 0.2\]"),
    ("[wind]\nspeed = -1.0\n", "wind.speed", r"\[0, 60\] m/s"),
])
def test_bad_wind_is_named(extra, key, words):
    """Wind with no vessel to act on, areas given in part, a coefficient outside Eq. 9's range and
    a negative speed are each refused naming the key (at load, or when the run is built)."""
    text = SHIP.split("[wind]")[0].replace('vessel = "otter"\n', "") + extra  # (a prescribed ship: no vessel)
    with pytest.raises(ConfigError, match=words) as err:
        run = ScenarioRun(load_scenario(text=text))
        try:
            weather.attach(run)
        finally:
            run.close()
    assert err.value.key == key

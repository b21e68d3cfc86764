"""Thrusters (``mjtether.vehicles.thruster``): the thrust curve by hand from Hong et al. (2020)'s numbers,
and the MuJoCo actuator against the first-order response it is meant to have (exact for
MuJoCo's ``filterexact``: 1e-12), its asymmetric saturation, and the force and moment it puts on
the hull (r x F by hand)."""

import math

import mujoco
import numpy as np
import pytest

from mjtether.vehicles.thruster import KGF, ThrustCurve, Thruster, add_thruster

# Hong et al. (2020), Sec. 2.4.1: dead zone about 1.6-3.2 V, 29.12 kgf forward, 13.83 kgf reverse;
# the control range (0-5 V here) is an assumption: their Figure 4 did not survive
USV = ThrustCurve(v_min=0.0, dead_low=1.6, dead_high=3.2, v_max=5.0, max_forward=29.12 * KGF,
                  max_reverse=13.83 * KGF)


def test_thrust_curve_by_hand():
    np.testing.assert_array_equal(USV.thrust([1.6, 2.4, 3.2]), 0.0)  # the dead zone
    assert USV.thrust(5.0) == pytest.approx(29.12 * KGF, rel=1e-12)
    assert USV.thrust(0.0) == pytest.approx(-13.83 * KGF, rel=1e-12)
    assert USV.thrust(4.1) == pytest.approx(0.5 * 29.12 * KGF, rel=1e-12)  # halfway up the forward ramp
    assert USV.thrust(0.8) == pytest.approx(-0.5 * 13.83 * KGF, rel=1e-12)
    assert USV.thrust(9.0) == USV.thrust(5.0)  # clipped to the curve's range


def test_bad_thrust_curve_and_thruster_are_named():
    with pytest.raises(ValueError, match="v_min < dead_low <= dead_high < v_max"):
        ThrustCurve(0.0, 3.2, 1.6, 5.0, 100.0, 50.0)
    with pytest.raises(ValueError, match="port.direction must not be zero"):
        Thruster("port", (0, 0, 0), (0, 0, 0), 100.0, 50.0)
    with pytest.raises(ValueError, match="port.time_constant must be > 0 s"):
        Thruster("port", (0, 0, 0), (1, 0, 0), 100.0, 50.0, time_constant=0.0)


def _hull(thruster, dt=0.002):
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, 0.0]
    b = spec.worldbody.add_body(name="hull")
    b.add_freejoint()
    b.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.2, 0.0, 0.0], mass=50.0)
    name = add_thruster(spec, "hull", thruster)
    m = spec.compile()
    return m, mujoco.MjData(m), m.actuator(name).id


def test_thruster_responds_to_first_order_and_saturates_asymmetrically():
    """A 100 N command to a thruster of 80 N forward, 30 N reverse and tau = 0.25 s: the thrust
    delivered n steps later is 80 (1 - exp(-n dt / tau)); then -100 N: it falls towards -30 N."""
    th = Thruster("stern", (-0.5, 0.2, 0.0), (1.0, 0.0, 0.0), max_forward=80.0, max_reverse=30.0,
                  time_constant=0.25)
    m, d, a = _hull(th)
    dt = m.opt.timestep
    d.ctrl[a] = 100.0
    for n in range(1, 500):
        mujoco.mj_step(m, d)
        assert d.act[a] == pytest.approx(80.0 * (1.0 - math.exp(-n * dt / 0.25)), rel=1e-12)
    d.ctrl[a] = -100.0
    for _ in range(3000):
        mujoco.mj_step(m, d)
    assert d.act[a] == pytest.approx(-30.0, rel=1e-9)


@pytest.mark.parametrize("direction", [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.6, 0.0, -0.8)])
def test_thrust_force_and_moment_on_the_hull(direction):
    """At rest (identity orientation), the actuator's generalized force on the free joint is the
    thrust F along ``direction`` and the moment r x F about the hull's origin (r the thruster's
    position): 1e-12."""
    r = np.array([-0.5, 0.2, 0.1])
    th = Thruster("t", tuple(r), direction, max_forward=50.0, max_reverse=50.0, time_constant=1e-3)
    m, d, a = _hull(th)
    d.ctrl[a] = 40.0
    for _ in range(50):  # 100 time constants: the thrust has arrived
        mujoco.mj_step(m, d)
    d.qpos[:] = [0, 0, 0, 1, 0, 0, 0]  # back at rest, where r and F are given
    d.qvel[:] = 0.0
    mujoco.mj_forward(m, d)
    F = 40.0 * np.asarray(direction) / np.linalg.norm(direction)
    np.testing.assert_allclose(d.qfrc_actuator[:3], F, rtol=1e-12, atol=1e-12 * 40)
    np.testing.assert_allclose(d.qfrc_actuator[3:], np.cross(r, F), rtol=1e-12, atol=1e-12 * 40)

"""The suspended weight of Li et al. (004_1344bf68f719ac97.txt): a 200 t body on a 50 m tether.

Paper parameters: m = 200 t, m_f = 0.5 m, m_a = 0.5 m_f, C_d = 1.05, S = 20 m^2, l = 50 m,
which give eps = 2.153 and omega = 0.280 rad/s. As the paper assumes, the tether's own
weight and drag are negligible: it is neutrally buoyant, drag-free and 0.04 % of the mass.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.signal import find_peaks

import mujoco
import mjtether as mt
from conftest import new_spec

PAPER = mt.SuspendedWeight(m=200e3, m_f=100e3, m_a=50e3, cd=1.05, S=20.0, l=50.0)
TOP = np.array([0.0, 0.0, -10.0])


def swing(u_c: float, phi0: float, duration: float, dt: float = 0.005):
    """Simulate and return times (s) and the swing angle (rad) from the vertical."""
    water = mt.WaterColumn(depth=500.0, current=mt.ConstantCurrent(u_c))
    spec = new_spec(dt)
    pos = TOP + PAPER.l * np.array([np.sin(phi0), 0.0, -np.cos(phi0)])
    body = spec.worldbody.add_body(name="weight", pos=pos)
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[1.5, 0, 0], mass=PAPER.m,
                  contype=0, conaffinity=0)
    hydro = mt.add_body_hydro(spec, "weight", mt.RigidBodyHydro(
        volume=PAPER.m_f / 1025.0, drag_cd=PAPER.cd, drag_area=PAPER.S, added_mass=PAPER.m_a, height=3.0))
    tether = mt.TetherSpec(length=PAPER.l, segments=5, diameter=0.05, density=1025.0,
                           cd_normal=0.0, cd_tangential=0.0, ca_normal=0.0)
    tm = mt.add_tether(spec, tether, mt.FixedPoint(TOP), mt.BodyPoint("weight"), water=water)
    t, phi = [], []
    with mt.Simulation(spec, water, [tm], [hydro]) as sim:
        bid = sim.model.body("weight").id

        def rec(s):
            p = s.data.xpos[bid] - TOP
            t.append(s.time)
            phi.append(np.arctan2(p[0], -p[2]))
        sim.run(duration, rec, every=0.02)
        # the tether holds the weight: force on the body is up and equals its wet weight
        f_end = sim.tether().end_force(sim.data, "end")
    return np.array(t), np.array(phi), f_end


def test_paper_parameters():
    assert PAPER.eps == pytest.approx(2.153, abs=1e-3)
    assert PAPER.omega == pytest.approx(0.280, abs=1e-3)


def test_period_and_decay_in_still_water():
    phi0 = np.radians(5.0)  # the paper's initial condition
    t, phi, f_end = swing(0.0, phi0, 6 * PAPER.period)
    up = t[1:][(phi[:-1] < 0) & (phi[1:] >= 0)]
    period = np.mean(np.diff(up))
    # 2 %: the tolerance (measured 0.1 %: the 5 deg amplitude adds 0.05 %)
    assert period == pytest.approx(PAPER.period, rel=0.02)

    # amplitude decay. Independent reference 1: Eq. 2 integrated numerically (scipy, rtol 1e-10)
    # with sin(phi) kept, i.e. the paper's model without the small-angle and averaging steps.
    w2, eps = PAPER.omega**2, PAPER.eps
    ode = solve_ivp(lambda _, y: [y[1], -w2 * np.sin(y[0]) - eps * abs(y[1]) * y[1]],
                    (0, t[-1]), [phi0, 0.0], t_eval=t, rtol=1e-10, atol=1e-12)
    pk, _ = find_peaks(phi)
    pk_ref, _ = find_peaks(ode.y[0])
    n = min(len(pk), len(pk_ref))
    assert n >= 5
    # the full 3-D simulation against the same physics: peaks within 1 % (measured 0.3 %)
    np.testing.assert_allclose(phi[pk[:n]], ode.y[0][pk_ref[:n]], rtol=0.01)
    # Reference 2: Eq. 17 (method of averaging). Its first-order error against the ODE bounds
    # any model's agreement with it: 0.23 % at most over these six swings (eps*a ~ 0.2 is
    # small). With the 0.3 % between simulation and ODE, 1 % is the tolerance we can justify.
    eq17 = PAPER.still_water_amplitude(t[pk[:n]], phi0)
    np.testing.assert_allclose(ode.y[0][pk_ref[:n]], eq17, rtol=0.005)
    np.testing.assert_allclose(phi[pk[:n]], eq17, rtol=0.01)
    # the tether holds the swinging weight: the pull on it is its wet weight, within the 2 %
    # that the swing's centripetal term (m v^2 / l < 0.1 %) and cos(phi) leave
    assert np.linalg.norm(f_end) == pytest.approx(PAPER.wet_weight, rel=0.02)
    assert f_end[2] > 0


@pytest.mark.parametrize("u_c", [0.5, 1.0, 1.5])
def test_balance_angle_in_current(u_c):
    # released at rest on the vertical; the swing decays as exp(-u_c eps t / l) (Eq. 23), so
    # after 250 s less than 1 % of it is left at 0.5 m/s; average over the last two periods
    t, phi, _ = swing(u_c, 0.0, 250.0)
    last = t > t[-1] - 2 * PAPER.period
    A = PAPER.balance_angle(u_c)
    # 3 %: the tolerance; the exact balance tan(phi) = D / (G - F) differs from
    # Eq. 8 by 0.02 % at 1.5 m/s
    assert np.mean(phi[last]) == pytest.approx(A, rel=0.03)

"""Issue 43's clump test: a clump weight on a vertical line whose top heaves with a regular wave
(RAO 1 in heave), drag off, against the linear single-degree-of-freedom answer written here."""

import math

import mujoco
import numpy as np

from mjtether import BodyPoint, RigidBodyHydro, Simulation, TetherSpec, add_body_hydro, add_tether
from mjtether.cable.builder import AXIAL_OMEGA_DT
from mjtether.physics import waves
from mjtether.physics.water import ConstantDensity, WaterColumn

RHO, G, DEPTH = 1025.0, 9.81, 200.0
L, N, D, DENSITY, EA, ZETA = 50.0, 20, 0.02, 1600.0, 378e3, 1.0  # the line: m, -, m, kg/m^3, N, -
M, R = 1000.0, 0.3  # the clump: kg, m (a sphere)
A, DT = 0.15, 0.005  # m, the top's heave amplitude; s, the time step


def _amplitude(t, y, w):
    """Least-squares complex amplitude c1 - i c2 of y(t) = c0 + c1 cos(w t) + c2 sin(w t)."""
    B = np.column_stack([np.ones_like(t), np.cos(w * t), np.sin(w * t)])
    c = np.linalg.lstsq(B, y, rcond=None)[0]
    return complex(c[1], -c[2])


def test_a_clump_under_a_heaving_top_against_the_sdof_answer():
    """A 1000 kg sphere (r 0.3 m, C_a 0.5: added mass 0.5 rho V) on 50 m of line (EA 378 kN, so
    k = EA / L = 7560 N/m; 0.5 kg/m, no drag, no added mass) hanging from a top that heaves with a regular wave
    (its elevation there, eta = A sin(w t), A 0.15 m), at w = 0.9 of the clump's natural frequency
    (T 2.62 s). The water is left flat (the native callback: 1.3 s against 9 s with the waves'
    kinematics on every element and the clump, which changed X by 1e-5: the clump is 52 m down,
    exp(-k z) ~ 1e-13, and the line's Froude-Krylov load is a few N). The SDOF answer: (M + m_a + mu
    L / 3) x'' + c (x' - y') + k (x - y) = 0, so X / A = (k + i c w) / (k - (M + m_a + mu L / 3) w^2
    + i c w) (the line's mass lumped by a third, as a spring's: 0.8 % of the moving mass). The
    line's axial damping c is how mjtether damps an element (``cable.builder.axial_params``): the
    damping ratio zeta (1, the default) of its axial mode at the frequency the solver is given,
    w_cap = AXIAL_OMEGA_DT / dt (each element's own, near 500 rad/s, is above it, and below the
    softening limit 100 w_cap), i.e. an element damper 2 zeta K_e / w_cap; in series, c = 2 zeta k /
    w_cap = 189 N s/m, 3.3 % of the SDOF's critical damping: the answer is 4 % below the undamped
    one, so the test resolves the damping. Left out: the soft constraint's own inertia, a stiffness
    k (1 - w^2 / w_cap^2) (w / w_cap = 0.03 here: 0.5 % on X; measured +0.7 % on X, +0.75 % on the
    top tension). The top tension's amplitude from the momentum of what hangs: w^2 |(M + m_a) X + mu
    L (X + A) / 2| (the line moving as the straight-line interpolation of its ends). Both within 2 %
    over the last two periods of 38 (the start's transient, time constant 11 s, is down to 1e-4)."""
    w_n = math.sqrt((EA / L) / (M + 0.5 * RHO * 4 / 3 * math.pi * R ** 3 + DENSITY * math.pi * D ** 2 / 4 * L / 3))
    w = 0.9 * w_n
    period = 2 * math.pi / w
    field = waves.WaveField(waves.regular(2 * A, period, 0.0, DEPTH, G, phase=math.pi / 2), DEPTH, G)
    water = WaterColumn(depth=DEPTH, density=ConstantDensity(RHO), gravity=G)
    tether = TetherSpec(length=L, segments=N, diameter=D, density=DENSITY, EA=EA, cd_normal=0.0, cd_tangential=0.0,
                        ca_normal=0.0, axial_damping_ratio=ZETA)
    V = 4 / 3 * math.pi * R ** 3
    m_a, mu = 0.5 * RHO * V, DENSITY * math.pi * D ** 2 / 4
    k = EA / L
    weight = (M - RHO * V) * G + (mu - RHO * math.pi * D ** 2 / 4) * G * L / 2
    spec = mujoco.MjSpec()
    spec.option.gravity = [0.0, 0.0, -G]
    spec.option.timestep = DT
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.worldbody.add_body(name="top", mocap=True, pos=[0.0, 0.0, 0.0])
    clump = spec.worldbody.add_body(name="clump", pos=[0.0, 0.0, -L - weight / k - R])
    clump.add_freejoint()
    clump.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[R, 0, 0], mass=M, contype=0, conaffinity=0)
    hydro = add_body_hydro(spec, "clump", RigidBodyHydro(volume=V, drag_cd=0.0, drag_area=math.pi * R * R,
                                                         added_mass=m_a, height=2 * R))
    tm = add_tether(spec, tether, BodyPoint("top"), BodyPoint("clump", (0.0, 0.0, R)), water=water)
    ts, zs, tops = [], [], []
    with Simulation(spec, water, [tm], [hydro]) as sim:
        tt, d = sim.tether(), sim.data
        zadr = sim.model.jnt_qposadr[sim.model.body("clump").jntadr[0]] + 2
        for _ in range(int(round(38 * period / DT))):
            d.mocap_pos[0, 2] = field.elevation(0.0, 0.0, d.time + DT)  # (the heave at the step's end)
            sim.step(1)
            ts.append(d.time)
            zs.append(d.qpos[zadr])
            tops.append(np.linalg.norm(tt.end_force(d, "start")))
    ts, zs, tops = np.array(ts), np.array(zs), np.array(tops)
    last = ts > ts[-1] - 2 * period
    c = 2 * ZETA * k * DT / AXIAL_OMEGA_DT
    X = A * (k + 1j * c * w) / (k - (M + m_a + mu * L / 3) * w * w + 1j * c * w)
    top = w * w * abs((M + m_a) * X + mu * L * (X + A) / 2)
    got_x = abs(_amplitude(ts[last], zs[last], w))
    got_top = abs(_amplitude(ts[last], tops[last], w))
    assert abs(got_x - abs(X)) <= 0.02 * abs(X), (got_x, abs(X))
    assert abs(got_top - top) <= 0.02 * top, (got_top, top)
    assert tops[last].min() > 0.3 * weight, tops[last].min()  # (taut throughout: the linear answer holds)

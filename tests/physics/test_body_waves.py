"""Morison's equation in waves on rigid bodies and vehicles (``rigidbody.BoundBodyHydro``,
``vehicles.vehicle.BoundVehicle``): their loads in a regular wave against the closed-form time
history written out here from linear (Airy) theory, and a floating vessel riding a long swell
against the single-degree-of-freedom heave answer."""

import math

import mujoco
import numpy as np
import pytest

from mjtether import Simulation, add_body_hydro
from mjtether.physics import compiled, waves
from mjtether.physics.rigidbody import RigidBodyHydro
from mjtether.physics.water import ConstantCurrent, ConstantDensity, WaterColumn
from mjtether.vehicles.files import build_vehicle, load_vehicle
from mjtether.vehicles.vehicle import VehicleHydro, add_vehicle

RHO, G, DEPTH = 1025.0, 9.81, 60.0
H, T = 3.0, 8.0  # m, s
U_C = 0.4  # m/s, the current along +x


def dispersion(w, depth=DEPTH):
    """k (rad/m) of omega^2 = g k tanh(k h), by bisection."""
    lo, hi = 1e-6, 10.0
    for _ in range(200):
        k = 0.5 * (lo + hi)
        lo, hi = (k, hi) if w * w > G * k * math.tanh(k * depth) else (lo, k)
    return k


def airy(x, z, t, height=H, period=T):
    """(eta, velocity (3,), local acceleration (3,)) of a regular wave travelling along +x, from
    the textbook form (Dean & Dalrymple 1991, Ch. 4), Wheeler-stretched (z' = h (z - eta) / (h +
    eta); zero above the surface)."""
    w = 2 * math.pi / period
    k = dispersion(w)
    th = k * x - w * t
    a = height / 2
    eta = a * math.cos(th)
    if z > eta:
        return eta, np.zeros(3), np.zeros(3)
    zs = DEPTH * (z - eta) / (DEPTH + eta)
    ch, sh = math.cosh(k * (zs + DEPTH)) / math.sinh(k * DEPTH), math.sinh(k * (zs + DEPTH)) / math.sinh(k * DEPTH)
    return (eta, np.array([a * w * ch * math.cos(th), 0.0, a * w * sh * math.sin(th)]),
            np.array([a * w * w * ch * math.sin(th), 0.0, -a * w * w * sh * math.cos(th)]))


def sea(height=H, period=T, current=U_C):
    field = waves.WaveField(waves.regular(height, period, 0.0, DEPTH, G), DEPTH, G)
    return WaterColumn(depth=DEPTH, density=ConstantDensity(RHO), current=ConstantCurrent(current), gravity=G,
                       waves=field)


def _turn(yaw, pitch):
    """Body-to-world rotation: yaw about z, then pitch about the body's y (rad)."""
    cz, sz, cy, sy = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
    return np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]]) @ \
        np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])


@pytest.mark.parametrize("depth, turned", [(6.0, False), (6.0, True), (0.3, False)])
def test_a_welded_body_in_a_regular_wave(depth, turned):
    """A welded (jointless) cylinder-like body, 0.8 m^3, its centre ``depth`` m down (6 m: always
    under; 0.3 m: it pierces the surface, 1 m tall, in a 3 m wave), upright or turned 40 deg in
    yaw and 25 deg in pitch, in a regular wave H 3 m, T 8 s in 60 m over a current of 0.4 m/s.
    Its force over a period against the closed form at its centre: drag per body axis 1/2 rho
    C_d S |u_k| u_k on u = current + particle velocity (the law ``RigidBodyHydro`` states), the
    inertia rho V a + R diag(m_a) R^T a (Froude-Krylov plus added mass, C_m = 1 + C_a), buoyancy
    rho g V, all times the wet fraction clip(1/2 - (z - eta) / height, 0, 1) under the
    instantaneous surface eta. Within 1 % of the wave load's amplitude (the force less the
    still-water buoyancy): the code and the closed form differ only in round-off."""
    V, cd, area, ma, height = 0.8, (1.2, 0.9, 0.6), (0.9, 1.1, 0.7), (400.0, 700.0, 900.0), 1.0
    R = _turn(math.radians(40), math.radians(25)) if turned else np.eye(3)
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, R.ravel())
    spec = mujoco.MjSpec()
    spec.option.gravity = [0.0, 0.0, -G]
    centre = np.array([5.0, 0.0, -depth])
    body = spec.worldbody.add_body(name="b", pos=list(centre), quat=list(quat))
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.5, 0, 0], contype=0, conaffinity=0)
    hydro = add_body_hydro(spec, "b", RigidBodyHydro(volume=V, drag_cd=cd, drag_area=area, added_mass=ma,
                                                     height=height))
    with Simulation(spec, sea(), bodies=[hydro]) as sim:
        bb = sim.bodies[0]
        assert sim.native  # (a run's loads come from native's twin: tests/physics/test_native_waves.py checks it
        # against the Python loads read here)
        got, want, wave_load = [], [], []
        for t in np.linspace(0.0, T, 41):
            sim.data.time = t
            f, tq, p = bb.loads(sim.model, sim.data)
            assert np.allclose(p, centre, atol=1e-12) and np.abs(tq).max() < 1e-9
            eta, u, a = airy(centre[0], centre[2], t)
            frac = min(max(0.5 - (centre[2] - eta) / height, 0.0), 1.0)
            ub = R.T @ (u + (U_C, 0.0, 0.0))
            drag = R @ (0.5 * RHO * frac * np.array(cd) * np.array(area) * np.abs(ub) * ub)
            inertia = frac * (RHO * V * a + R @ np.diag(ma) @ R.T @ a)
            buoy = np.array([0.0, 0.0, RHO * G * V * frac])
            got.append(f)
            want.append(drag + inertia + buoy)
            wave_load.append(drag + inertia + buoy - (0.0, 0.0, RHO * G * V * min(max(0.5 + depth / height, 0), 1)))
    got, want = np.array(got), np.array(want)
    assert np.abs(got - want).max() <= 0.01 * np.abs(wave_load).max()
    if depth < 1.0:  # (the surface crossed it: fully dry and fully wet within the period)
        assert got[:, 2].min() < 1e-9 and got[:, 2].max() > RHO * G * V


@pytest.mark.parametrize("kernels", ["numba", "numpy"])
def test_a_submerged_vehicle_held_in_a_regular_wave(kernels, monkeypatch):
    """A submerged vehicle held still 6 m down (diagonal added mass and linear and quadratic
    damping, centre of buoyancy 0.05 m above its origin) in the same wave and current: its
    wrench (body frame = world, about the origin) over a period against the closed form with
    nu_r = -(current + particle velocity) at its centre of buoyancy: D_L u + D_Q |u| u, the
    Munk moment (M_A nu_r) x nu_r (Fossen's -C_A(nu_r) nu_r at rest), rho V a + M_A a, the
    buoyancy rho g V, and the moments of the Froude-Krylov force and the buoyancy about the
    origin. Within 1 % of the wave load's amplitude, on the compiled kernel and on NumPy."""
    if kernels == "numba" and compiled.numba is None:
        pytest.skip("numba is not installed")
    monkeypatch.setenv(compiled.KERNELS_ENV, kernels)
    V, r_b = 0.05, np.array([0.0, 0.0, 0.05])
    MA, DL, DQ = np.array([10.0, 40.0, 45.0, 1.0, 2.0, 2.0]), np.array([20.0, 50.0, 60.0, 3, 3, 3]), \
        np.array([30.0, 90.0, 100.0, 1, 1, 1])
    spec = mujoco.MjSpec()
    spec.option.gravity = [0.0, 0.0, -G]
    origin = np.array([5.0, 0.0, -6.0])
    vm = add_vehicle(spec, "auv", mass=RHO * V, inertia=(1.0, 2.0, 2.0), pos=origin, size=(0.5, 0.15, 0.15),
                     hydro=VehicleHydro(volume=V, centre_of_buoyancy=tuple(r_b), added_mass=MA, linear_damping=DL,
                                        quadratic_damping=DQ))
    with Simulation(spec, sea(), bodies=[vm]) as sim:
        bv = sim.bodies[0]
        assert not sim.native and (bv._codes is not None) == (kernels == "numba")
        got, want, wave_load = [], [], []
        for t in np.linspace(0.0, T, 41):
            sim.data.time = t
            tau = bv.wrench(sim.model, sim.data)
            _, u, a = airy(origin[0], origin[2] + r_b[2], t)
            u = u + (U_C, 0.0, 0.0)
            nu_r = -u
            f = DL[:3] * u + DQ[:3] * np.abs(u) * u + RHO * V * a + MA[:3] * a
            m = np.cross(MA[:3] * nu_r, nu_r) + np.cross(r_b, RHO * V * a + (0.0, 0.0, RHO * G * V))
            got.append(tau)
            want.append(np.r_[f + (0.0, 0.0, RHO * G * V), m])
            wave_load.append(np.r_[f, m - np.cross(r_b, (0.0, 0.0, RHO * G * V))])
    got, want = np.array(got), np.array(want)
    assert np.abs(got - want).max() <= 0.01 * np.abs(wave_load).max()


def _fit(t, y, w):
    """Least-squares amplitude of y(t) = c + a cos(w t) + b sin(w t)."""
    A = np.column_stack([np.ones_like(t), np.cos(w * t), np.sin(w * t)])
    c = np.linalg.lstsq(A, y, rcond=None)[0]
    return math.hypot(c[1], c[2])


@pytest.mark.parametrize("kernels", ["numba", "numpy"])
def test_the_otter_rides_a_long_swell(kernels, monkeypatch):
    """The Otter USV (Fossen's, shipped), free and unpowered, in a regular swell H 0.6 m, T 10 s
    in 60 m: it heaves through its own hydrostatics under the instantaneous surface. Its heave
    amplitude over the last two periods against the single-degree-of-freedom answer written
    here: (m + A33) z'' + D33 z' + rho g A_wp z = rho g A_wp eta + (rho V + A33) a + D33 w, the
    particle motion at half its mean draft d = V / A_wp under the surface, i.e. z / eta = (k_h -
    (rho V + A33) w^2 e + i w D33 e) / (k_h - (m + A33) w^2 + i w D33), e = sinh(k (h - d/2)) /
    sinh(k h) (Airy's vertical profile), k_h = rho g A_wp. Within 1 %: the answer is near 1 here
    (a long swell, w 0.63 rad/s against its heave frequency 7.5 rad/s; a vessel that ignored the
    waves would not heave at all). Its start (at rest on its design waterline) decays with a time
    constant 2 (m + A33) / D33 = 0.45 s, gone before the fit's window (the last two periods). On the
    compiled kernel and on NumPy."""
    if kernels == "numba" and compiled.numba is None:
        pytest.skip("numba is not installed")
    monkeypatch.setenv(compiled.KERNELS_ENV, kernels)
    vs = load_vehicle("otter")
    h = vs.hydro
    spec = mujoco.MjSpec()
    spec.option.gravity = [0.0, 0.0, -G]
    spec.option.timestep = 0.005
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    vm = build_vehicle(spec, vs, "otter")
    Hs, Ts = 0.6, 10.0
    with Simulation(spec, sea(Hs, Ts, current=0.0), bodies=[vm]) as sim:
        zadr = sim.model.joint("otter/z").qposadr[0]
        ts, zs = [], []
        while sim.data.time < 3 * Ts:
            sim.step(10)
            ts.append(sim.data.time)
            zs.append(sim.data.qpos[zadr])
    ts, zs = np.array(ts), np.array(zs)
    last = ts > Ts
    w = 2 * math.pi / Ts
    k = dispersion(w)
    m, A33, D33 = vs.mass, h.added_mass[2, 2], h.linear_damping[2, 2]
    kh = RHO * G * h.surface.waterplane_area
    e = math.sinh(k * (DEPTH - 0.5 * h.volume / h.surface.waterplane_area)) / math.sinh(k * DEPTH)
    rao = abs((kh - (RHO * h.volume + A33) * w * w * e + 1j * w * D33 * e) / (kh - (m + A33) * w * w + 1j * w * D33))
    got = _fit(ts[last], zs[last], w) / (Hs / 2)
    assert abs(got - rao) <= 0.01 * rao, (got, rao)

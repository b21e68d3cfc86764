"""A free-swimming vehicle (``mjtether.vehicles.vehicle``) against an independent integration of Fossen's
equations, written out here again (not imported from ``mjtether.vehicles.fossen``) and integrated by
scipy's ``solve_ivp`` (RK45, rtol 1e-10) with quaternion kinematics:

    (M_RB + M_A) nu' = tau - C_RB(nu) nu - C_A(nu_r) nu_r - D(nu_r) nu_r - g(eta) - M_A [omega x nu_c; 0]

(the last term: M_A nu_r' for a current uniform and steady in the world, whose body components
turn as nu_c' = -omega x nu_c). MuJoCo integrates the rigid body itself, with the added mass in
its mass matrix and the rest as passive forces. The control is a prescribed body-frame wrench
standing in for thrust, rudder and sternplanes: steps of surge force, yaw and pitch moment.

Tolerance: 1 % (the issue's), of the largest value of each state group over the run: the
position (of the distance covered), the body linear and angular velocities, and the orientation
(the angle between the two, of the largest rotation from the start). MuJoCo's step is 5 ms; its
first-order time integration leaves an error of order dt on the trajectory.
"""

import math

import mujoco
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mjtether as mt
from mjtether.vehicles.vehicle import VehicleHydro, add_vehicle

RHO, G = 1025.0, 9.81


def S(a):
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def coriolis(M, nu):
    """Fossen (2021) Thm 3.2 for a symmetric 6x6 M: C = [[0, -S(M11 v + M12 w)], [-S(.), -S(M21 v + M22 w)]]."""
    a = M[:3, :3] @ nu[:3] + M[:3, 3:] @ nu[3:]
    b = M[3:, :3] @ nu[:3] + M[3:, 3:] @ nu[3:]
    return np.block([[np.zeros((3, 3)), -S(a)], [-S(a), -S(b)]])


def quat_to_R(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


# a torpedo-shaped test vehicle the size of a REMUS 100 (a 1.6 m x 0.19 m prolate spheroid, 31 kg,
# its centre of gravity 2 cm below its centre of buoyancy); coefficients of a plausible size, not
# the REMUS's (those come with the vehicle files)
TORPEDO = dict(
    mass=31.0, inertia=(0.112, 3.99, 3.99), r_g=np.array([0.0, 0.0, -0.02]), volume=31.0 / RHO,
    r_b=np.zeros(3), added_mass=np.array([1.0, 29.0, 29.0, 0.01, 1.6, 1.6]),
    linear=np.array([2.0, 10.0, 10.0, 0.5, 5.0, 5.0]), quadratic=np.array([5.0, 60.0, 60.0, 0.1, 10.0, 10.0]))
# a light ROV whose added mass exceeds its own (heave 2.2x, surge and sway 1.0-1.4x)
LIGHT_ROV = dict(
    mass=11.0, inertia=(0.16, 0.16, 0.16), r_g=np.array([0.0, 0.0, -0.05]), volume=11.2 / RHO,
    r_b=np.zeros(3), added_mass=np.array([11.0, 15.0, 24.0, 0.1, 0.1, 0.12]),
    linear=np.array([4.0, 6.0, 5.0, 0.1, 0.2, 0.3]), quadratic=np.array([18.0, 22.0, 40.0, 1.0, 1.0, 1.5]))
CURRENT = np.array([0.3 * math.cos(math.radians(30)), 0.3 * math.sin(math.radians(30)), 0.0])


def control(t):
    """Body-frame wrench (N, N m): surge force throughout, a yaw moment from 10 to 30 s, a pitch
    moment from 30 to 45 s."""
    tau = np.zeros(6)
    tau[0] = 10.0
    if 10.0 <= t < 30.0:
        tau[5] = 1.0
    if 30.0 <= t < 45.0:
        tau[4] = 0.5
    return tau


def reference(p, duration):
    """solve_ivp of Fossen's equations: times, positions, quaternions, nu."""
    m, rg = p["mass"], p["r_g"]
    Ig = np.diag(p["inertia"])
    M_RB = np.block([[m * np.eye(3), -m * S(rg)], [m * S(rg), Ig - m * S(rg) @ S(rg)]])
    M_A = np.diag(p["added_mass"])
    Minv = np.linalg.inv(M_RB + M_A)
    W, B = m * G, RHO * G * p["volume"]

    def f(t, y):
        q, nu = y[3:7], y[7:]
        R = quat_to_R(q)
        nu_c = np.r_[R.T @ CURRENT, 0.0, 0.0, 0.0]
        nu_r = nu - nu_c
        fg, fb = R.T @ [0.0, 0.0, -W], R.T @ [0.0, 0.0, B]
        g = -np.r_[fg + fb, np.cross(rg, fg) + np.cross(p["r_b"], fb)]
        D = p["linear"] * nu_r + p["quadratic"] * np.abs(nu_r) * nu_r
        dnu_c = np.r_[np.cross(nu[3:], nu_c[:3]), 0.0, 0.0, 0.0]  # -(nu_c)' = omega x nu_c
        nudot = Minv @ (control(t) - coriolis(M_RB, nu) @ nu - coriolis(M_A, nu_r) @ nu_r - D - g - M_A @ dnu_c)
        w, x, yq, z = q
        wx, wy, wz = nu[3:]
        qdot = 0.5 * np.array([-x * wx - yq * wy - z * wz, w * wx + yq * wz - z * wy,
                               w * wy - x * wz + z * wx, w * wz + x * wy - yq * wx])
        return np.r_[R @ nu[:3], qdot, nudot]

    y0 = np.r_[0.0, 0.0, -50.0, 1.0, 0.0, 0.0, 0.0, np.zeros(6)]
    ts = np.arange(0.0, duration + 1e-9, 0.5)
    sol = solve_ivp(f, (0.0, duration), y0, t_eval=ts, rtol=1e-10, atol=1e-10, method="RK45")
    assert sol.success
    return ts, sol.y[:3].T, sol.y[3:7].T, sol.y[7:].T


def mujoco_run(p, duration, dt=0.005):
    water = mt.WaterColumn(depth=200.0, density=mt.ConstantDensity(RHO), current=mt.ConstantCurrent(
        float(np.linalg.norm(CURRENT)), math.radians(30)), gravity=G)
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, -G]
    hydro = VehicleHydro(volume=p["volume"], centre_of_buoyancy=p["r_b"], added_mass=p["added_mass"],
                         linear_damping=p["linear"], quadratic_damping=p["quadratic"])
    vm = add_vehicle(spec, "auv", mass=p["mass"], inertia=p["inertia"], hydro=hydro, centre_of_gravity=p["r_g"],
                     pos=(0.0, 0.0, -50.0))
    out = {"t": [], "p": [], "q": [], "nu": []}
    with mt.Simulation(spec, water, bodies=[vm]) as sim:
        d = sim.data
        bv = sim.bodies[0]
        every = int(round(0.5 / dt))
        for k in range(int(round(duration / dt)) + 1):
            if k % every == 0:
                nu, _ = bv.velocity(d)
                out["t"].append(d.time)
                out["p"].append(d.xpos[bv.id].copy())
                out["q"].append(d.xquat[bv.id].copy())
                out["nu"].append(nu)
            tau = control(d.time)
            R = d.xmat[bv.id].reshape(3, 3)
            d.qfrc_applied[bv._v] = R @ tau[:3]
            d.qfrc_applied[bv._w] = tau[3:]
            sim.step()
    return {k: np.array(v) for k, v in out.items()}


def rotation_angle(q1, q2):
    dots = np.abs(np.sum(q1 * q2, axis=1)).clip(0.0, 1.0)
    return 2 * np.arccos(dots)


@pytest.mark.parametrize("params", [TORPEDO, LIGHT_ROV], ids=["torpedo", "light_rov"])
def test_vehicle_matches_an_independent_integration(params):
    duration = 60.0
    ts, p_ref, q_ref, nu_ref = reference(params, duration)
    mj = mujoco_run(params, duration)
    n = min(len(ts), len(mj["t"]))
    assert np.allclose(mj["t"][:n], ts[:n])
    path = np.max(np.linalg.norm(p_ref - p_ref[0], axis=1))
    errs = {
        "position": np.max(np.linalg.norm(mj["p"][:n] - p_ref[:n], axis=1)) / path,
        "linear velocity": np.max(np.abs(mj["nu"][:n, :3] - nu_ref[:n, :3])) / np.max(np.abs(nu_ref[:, :3])),
        "angular velocity": np.max(np.abs(mj["nu"][:n, 3:] - nu_ref[:n, 3:])) / np.max(np.abs(nu_ref[:, 3:])),
        "orientation": np.max(rotation_angle(mj["q"][:n], q_ref[:n]))
        / np.max(rotation_angle(q_ref, np.tile(q_ref[0], (len(q_ref), 1)))),
    }
    bad = {k: f"{v:.3%}" for k, v in errs.items() if not v <= 0.01}
    assert not bad, f"off by more than 1 %: {bad} (all: { {k: f'{v:.3%}' for k, v in errs.items()} })"


def test_coriolis_matrix_does_no_work():
    """Fossen (2021) Thm 3.2: C(nu) of a symmetric positive definite M is skew-symmetric, so
    nu . C(nu) nu = 0 (the Coriolis-centripetal forces do no work), for mjtether.vehicles.fossen.m2c;
    1e-12 of |nu| |C nu| (rounding)."""
    from mjtether.vehicles.fossen import m2c

    rng = np.random.default_rng(1)
    for _ in range(20):
        A = rng.normal(size=(6, 6))
        M = A @ A.T + 6 * np.eye(6)
        nu = rng.normal(size=6)
        C = m2c(M, nu)
        np.testing.assert_allclose(C, -C.T, atol=1e-12 * np.abs(C).max())
        assert abs(nu @ C @ nu) <= 1e-12 * np.linalg.norm(nu) * np.linalg.norm(C @ nu)
        np.testing.assert_allclose(C @ nu, coriolis(M, nu) @ nu, rtol=1e-12, atol=1e-12 * np.abs(C @ nu).max())


@pytest.mark.parametrize("kwargs, message", [
    (dict(volume=-1.0), "hydro.volume"),
    (dict(volume=0.03, added_mass=np.arange(36.0).reshape(6, 6)), "hydro.added_mass must be symmetric"),
    (dict(volume=0.03, added_mass=[1, 1, 1, -5, 1, 1]), "hydro.added_mass must be positive semi-definite"),
    (dict(volume=0.03, added_mass=[1, 2, 3]), "hydro.added_mass must be 6 numbers"),
    (dict(volume=0.03, quadratic_damping=[1, 1, 1, 1, 1, -1]), "hydro.quadratic_damping must be 6 numbers >= 0"),
])
def test_bad_vehicle_hydro_is_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        VehicleHydro(**kwargs)


@pytest.mark.parametrize("inertia", [(1.0, 0.0, 1.0), (1.0, float("nan"), 1.0), (1.0, 1.0)])
def test_bad_vehicle_inertia_is_named(inertia):
    with pytest.raises(ValueError, match=r"auv.inertia must be 3 principal moments > 0"):
        add_vehicle(mujoco.MjSpec(), "auv", mass=31.0, inertia=inertia, hydro=VehicleHydro(volume=0.03))


def _decay_period(params, axis: int, angle_deg: float = 5.0, dt=0.002, duration=None):
    """Free decay in still water, no damping, neutrally buoyant (a vehicle that rises or sinks
    couples its heave into roll and pitch through the Munk moment), from ``angle_deg`` of roll
    (axis 0) or pitch (1): the period (s) from the upward zero crossings of the angle."""
    p = dict(params, linear=np.zeros(6), quadratic=np.zeros(6), volume=params["mass"] / RHO)
    water = mt.WaterColumn(depth=200.0, density=mt.ConstantDensity(RHO), gravity=G)
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, -G]
    hydro = VehicleHydro(volume=p["volume"], centre_of_buoyancy=p["r_b"], added_mass=p["added_mass"])
    vm = add_vehicle(spec, "auv", mass=p["mass"], inertia=p["inertia"], hydro=hydro, centre_of_gravity=p["r_g"],
                     pos=(0.0, 0.0, -50.0))
    with mt.Simulation(spec, water, bodies=[vm]) as sim:
        m, d = sim.model, sim.data
        adr = m.joint("auv/ball").qposadr[0]
        half = math.radians(angle_deg) / 2
        d.qpos[adr:adr + 4] = [math.cos(half), *(math.sin(half) * np.eye(3)[axis])]
        sim.forward()
        t, a = [], []
        for _ in range(int(round(duration / dt))):
            sim.step()
            R = d.xmat[sim.bodies[0].id].reshape(3, 3)
            t.append(d.time)
            a.append(math.atan2(R[2, 1], R[2, 2]) if axis == 0 else -math.asin(R[2, 0]))
    t, a = np.array(t), np.array(a)
    up = np.flatnonzero((a[:-1] < 0) & (a[1:] >= 0))
    tc = t[up] - a[up] * (t[up + 1] - t[up]) / (a[up + 1] - a[up])  # interpolated crossings
    assert len(tc) >= 3
    return float(np.mean(np.diff(tc)))


@pytest.mark.parametrize("params", [TORPEDO, LIGHT_ROV], ids=["torpedo", "light_rov"])
@pytest.mark.parametrize("axis", [0, 1], ids=["roll", "pitch"])
def test_roll_and_pitch_free_decay_period(params, axis):
    """Undamped roll (pitch) about the body x (y) axis with the centre of gravity a distance BG
    below the centre of buoyancy: T = 2 pi sqrt(I / (W BG)) with I the rigid body's inertia
    about its centre of gravity plus the added inertia K_p' (M_q'), plus what the coupled sway
    (surge) adds: the centre of gravity swings through m z_g^2 of inertia about the origin, of
    which the hull's sway (surge) added mass Y_v' (X_u') holds back the part Y_v' / (m + Y_v')
    (momentum along the free horizontal axis is conserved). Tolerance 2 % (the issue's); the
    5 degree amplitude shifts a pendulum's period by 0.05 %."""
    m, zg = params["mass"], params["r_g"][2]
    BG = params["r_b"][2] - zg
    added = params["added_mass"]
    sway = added[1] if axis == 0 else added[0]
    I = params["inertia"][axis] + added[3 + axis] + m * zg**2 * sway / (m + sway)
    T = 2 * math.pi * math.sqrt(I / (m * G * BG))
    measured = _decay_period(params, axis, duration=4.5 * T)
    assert measured == pytest.approx(T, rel=0.02), f"period {measured:.4f} s, expected {T:.4f} s"

"""The shipped REMUS 100 (``assets/vehicles/remus100.toml``, Fossen's model) against answers that
do not come from mjtether's code:

* an independent integration of the same equations, written out here again from Fossen (2021,
  Sec. 8.4.2) and his Python Vehicle Simulator's ``remus100.py`` (not imported from
  ``mjtether``): hull lift and axial drag, cross-flow drag by strips, fins, the Wageningen
  propeller, the faded linear damping, C_A with Fossen's eight entries left out, the servo and
  shaft lags; scipy's ``solve_ivp`` (RK45, rtol 1e-9) with quaternion kinematics;
* the straight-running speed at 1525 rpm from the force balance thrust = drag, solved here with
  scipy's ``brentq``, and against the speed Fossen states for it and the one his code reaches.

Body frame x forward, y left, z up (Fossen's y and z flip sign).
"""

import math

import mujoco
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import mjtether as mt
from mjtether.vehicles.files import build_vehicle, load_vehicle

RHO, G = 1026.0, 9.81
# the REMUS 100's numbers as Fossen's remus100.py has them (the test's own copy)
L, DIAM = 1.6, 0.19
A, B_ = L / 2, DIAM / 2
MASS = 4 / 3 * math.pi * RHO * A * B_**2
IX, IYZ = 2 / 5 * MASS * B_**2, 1 / 5 * MASS * (A**2 + B_**2)
R_G = np.array([0.0, 0.0, -0.02])
S_REF = 0.7 * L * DIAM
CD0 = 0.42 * math.pi * B_**2 / S_REF
MA = np.array([0.83891, 29.43764, 29.43764, 0.03360, 3.42621, 3.42621])
D_LIN = np.array([1.59341, 3.02335, 3.02335, 0.58852, 10.78727, 7.45398])
ZEROED = [(4, 0), (0, 4), (4, 2), (2, 4), (5, 0), (0, 5), (5, 1), (1, 5)]
CD_2D = 1.1977
A_FIN, CL_R, CL_S, X_FIN = 0.0133, 0.5, 0.7, -0.8
D_PROP, KT0, KTMAX, KQ0, KQMAX, JMAX = 0.14, 0.4566, 0.1798, 0.0700, 0.0312, 0.6632
T_DED, WAKE = 0.1, 0.056
T_FIN, T_SHAFT = 0.1, 1.0
CURRENT = np.array([0.3 * math.cos(math.radians(30)), 0.3 * math.sin(math.radians(30)), 0.0])


def S(a):
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def coriolis(M, nu):
    a = M[:3, :3] @ nu[:3] + M[:3, 3:] @ nu[3:]
    b = M[3:, :3] @ nu[:3] + M[3:, 3:] @ nu[3:]
    return np.block([[np.zeros((3, 3)), -S(a)], [-S(a), -S(b)]])


def quat_to_R(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def thrust(rpm, u_r):
    """(thrust on the hull N, torque rolling it N m) of Fossen's REMUS propeller."""
    n = rpm / 60.0
    va = (1 - WAKE) * u_r
    if n > 0:
        T = RHO * D_PROP**4 * (KT0 * n * n + (KTMAX - KT0) / JMAX * (va / D_PROP) * n)
        Q = RHO * D_PROP**5 * (KQ0 * n * n + (KQMAX - KQ0) / JMAX * (va / D_PROP) * n)
    else:
        T, Q = RHO * D_PROP**4 * KT0 * n * abs(n), RHO * D_PROP**5 * KQ0 * n * abs(n)
    return (1 - T_DED) * T, 0.1 * Q


def commands(t):
    """(shaft rpm, rudder rad, stern planes rad): full speed throughout, rudder +5 deg from 10 to
    40 s, stern planes -5 deg from 20 to 30 s."""
    rudder = math.radians(5.0) if 10.0 <= t < 40.0 else 0.0
    stern = math.radians(-5.0) if 20.0 <= t < 30.0 else 0.0
    return 1525.0, rudder, stern


def hydro_forces(nu_r, d_r, d_s, rpm):
    """Everything but inertia, Coriolis and restoring: hull, cross-flow, fins, propeller, linear
    damping (body frame, N and N m)."""
    u, v, w, p, q, r = nu_r
    U = math.sqrt(u * u + v * v + w * w)
    tau = -(D_LIN * np.array([math.exp(-3 * U), math.exp(-3 * U), 1, 1, 1, 1])) * nu_r
    # hull lift and drag in the vertical plane (Fossen's forceLiftDrag), mirrored when the water
    # comes from astern (the vehicle starts at rest in the current: u_r < 0 at first)
    alpha = math.atan2(w, abs(u))
    AR = DIAM**2 / S_REF
    CL = math.pi * AR / (1 + math.sqrt(1 + (AR / 2) ** 2)) * alpha
    CD = CD0 + CL**2 / (math.pi * 0.7 * AR)
    FD, FL = 0.5 * RHO * U * U * S_REF * CD, 0.5 * RHO * U * U * S_REF * CL
    s = 1.0 if u >= 0 else -1.0
    tau[0] += s * (-math.cos(alpha) * FD + math.sin(alpha) * FL)
    tau[2] += -math.sin(alpha) * FD - math.cos(alpha) * FL
    # cross-flow drag, 20 strips along the hull, drag along each strip's cross-flow
    dx = L / 20
    for x in (np.arange(20) + 0.5) * dx - L / 2:
        vy, vz = v + x * r, w - x * q
        k = -0.5 * RHO * DIAM * CD_2D * dx * math.hypot(vy, vz)
        tau[1] += k * vy
        tau[2] += k * vz
        tau[4] += -x * k * vz
        tau[5] += x * k * vy
    # fins: rudder (lift +y for +delta), stern planes (lift +z), both at x = -0.8 m
    qh, qv = 0.5 * RHO * (u * u + v * v) * A_FIN, 0.5 * RHO * (u * u + w * w) * A_FIN
    Y, Z = qh * CL_R * d_r, qv * CL_S * d_s
    tau[0] += -qh * CL_R * d_r**2 - qv * CL_S * d_s**2
    tau[1] += Y
    tau[2] += Z
    tau[4] += -X_FIN * Z
    tau[5] += X_FIN * Y
    Xp, Kp = thrust(rpm, u)
    tau[0] += Xp
    tau[3] += Kp
    return tau


def reference(duration):
    M_RB = np.block([[MASS * np.eye(3), -MASS * S(R_G)],
                     [MASS * S(R_G), np.diag([IX, IYZ, IYZ]) - MASS * S(R_G) @ S(R_G)]])
    M_A = np.diag(MA)
    Minv = np.linalg.inv(M_RB + M_A)
    W = MASS * G
    Bf = RHO * G * 0.0302431

    def f(t, y):
        q, nu, d_r, d_s, rpm = y[3:7], y[7:13], y[13], y[14], y[15]
        R = quat_to_R(q)
        nu_c = np.r_[R.T @ CURRENT, 0.0, 0.0, 0.0]
        nu_r = nu - nu_c
        C_A = coriolis(M_A, nu_r)
        for i, j in ZEROED:
            C_A[i, j] = 0.0
        fg, fb = R.T @ [0.0, 0.0, -W], R.T @ [0.0, 0.0, Bf]
        g = -np.r_[fg + fb, np.cross(R_G, fg)]
        dnu_c = np.r_[np.cross(nu[3:], nu_c[:3]), 0.0, 0.0, 0.0]
        nudot = Minv @ (hydro_forces(nu_r, d_r, d_s, rpm) - coriolis(M_RB, nu) @ nu - C_A @ nu_r - g - M_A @ dnu_c)
        w, x, yq, z = q
        wx, wy, wz = nu[3:]
        qdot = 0.5 * np.array([-x * wx - yq * wy - z * wz, w * wx + yq * wz - z * wy,
                               w * wy - x * wz + z * wx, w * wz + x * wy - yq * wx])
        rpm_c, dr_c, ds_c = commands(t)
        return np.r_[R @ nu[:3], qdot, nudot, (dr_c - d_r) / T_FIN, (ds_c - d_s) / T_FIN, (rpm_c - rpm) / T_SHAFT]

    y0 = np.r_[0.0, 0.0, -50.0, 1.0, 0.0, 0.0, 0.0, np.zeros(6), 0.0, 0.0, 0.0]
    ts = np.arange(0.0, duration + 1e-9, 0.5)
    # the commands step at 10, 20, 30 and 40 s: integrate piecewise so the steps are met exactly
    edges = [0.0, 10.0, 20.0, 30.0, 40.0, duration]
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        t_eval = ts[(ts >= a - 1e-9) & (ts < b - 1e-9)] if b < duration else ts[ts >= a - 1e-9]
        sol = solve_ivp(f, (a, b), y0, t_eval=t_eval, rtol=1e-9, atol=1e-9, method="RK45",
                        first_step=1e-3)
        assert sol.success
        out.append(sol.y)
        y0 = solve_ivp(f, (a, b), y0, rtol=1e-9, atol=1e-9, method="RK45", first_step=1e-3).y[:, -1]
    y = np.hstack(out)
    return ts, y[:3].T, y[3:7].T, y[7:13].T


def remus_sim(dt=0.005, current=CURRENT):
    water = mt.WaterColumn(depth=500.0, density=mt.ConstantDensity(RHO), current=mt.ConstantCurrent(
        float(np.linalg.norm(current)), math.atan2(current[1], current[0])), gravity=G)
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, -G]
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    vm = build_vehicle(spec, load_vehicle("remus100"), "auv", pos=(0.0, 0.0, -50.0))
    return mt.Simulation(spec, water, bodies=[vm])


def mujoco_run(duration, dt=0.005):
    out = {"t": [], "p": [], "q": [], "nu": []}
    with remus_sim(dt) as sim:
        m, d = sim.model, sim.data
        bv = sim.bodies[0]
        ids = [m.actuator(f"auv/{n}").id for n in ("propeller", "rudder", "stern_planes")]
        every = int(round(0.5 / dt))
        for k in range(int(round(duration / dt)) + 1):
            if k % every == 0:
                nu, _ = bv.velocity(d)
                out["t"].append(d.time)
                out["p"].append(d.xpos[bv.id].copy())
                out["q"].append(d.xquat[bv.id].copy())
                out["nu"].append(nu)
            d.ctrl[ids] = commands(d.time + 1e-9)
            sim.step()
    return {k: np.array(v) for k, v in out.items()}


def rotation_angle(q1, q2):
    return 2 * np.arccos(np.abs(np.sum(q1 * q2, axis=1)).clip(0.0, 1.0))


def test_remus_matches_an_independent_integration():
    """60 s of full propeller, a rudder step and a stern-plane step in a 0.3 m/s current. Tolerance
    1 % (the issue's), of the largest value of each state group over the run: position (of the
    distance covered), body linear and angular velocities, orientation (the angle between the
    two, of the largest rotation from the start). MuJoCo's first-order step (5 ms) and its exact
    first-order lag of the servo and shaft, updated once a step, leave errors of order dt."""
    duration = 60.0
    ts, p_ref, q_ref, nu_ref = reference(duration)
    mj = mujoco_run(duration)
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


def straight_speed_balance(rpm):
    """The speed (m/s) at which the propeller's thrust meets the hull's axial drag and the faded
    linear surge damping, straight and level in still water."""
    def residual(u):
        return thrust(rpm, u)[0] - 0.5 * RHO * u * u * S_REF * CD0 - D_LIN[0] * math.exp(-3 * u) * u
    return brentq(residual, 0.01, 10.0, xtol=1e-12)


@pytest.fixture(scope="module")
def straight_run():
    """The REMUS 100 at 1525 rpm for 60 s from rest in still water: (speed over the last 5 s
    m/s, its spread m/s)."""
    with remus_sim(current=np.zeros(3)) as sim:
        m, d = sim.model, sim.data
        d.ctrl[m.actuator("auv/propeller").id] = 1525.0
        u = []
        for k in range(12000):
            sim.step()
            if k >= 11000:
                u.append(sim.bodies[0].velocity(d)[0][0])
    return float(np.mean(u)), float(np.ptp(u))


def test_remus_straight_speed_meets_the_force_balance(straight_run):
    """Steady straight speed at 1525 rpm against thrust = drag (brentq, 1e-12): the run has
    settled (its time constant, (m + X_u') / (d drag / du), is about 1 s: 60 s is 60 of them)
    within 1e-4 m/s, so 1e-3 relative leaves room only for the level trim's small pitch."""
    u, spread = straight_run
    assert spread < 1e-4
    assert u == pytest.approx(straight_speed_balance(1525.0), rel=1e-3)


def test_remus_straight_speed_against_fossen(straight_run):
    """Fossen states 2.5 m/s at 1525 rpm (remus100.py's docstring and its J_max comment); his
    own code, run unmodified (forward Euler, h = 0.02 s, 200 s), settles at 2.554 m/s. Against
    his code: 0.2 % (his Euler step and the 0.1 % gap between his speed over ground and our speed
    through the water vanish in still water; what is left is rounding of the transcribed
    coefficients); against his stated figure: 3 %, the 2.2 % by which his own code exceeds it
    and the statement's two significant figures."""
    u, _ = straight_run
    assert u == pytest.approx(2.554, rel=2e-3)
    assert u == pytest.approx(2.5, rel=0.03)


TOWING = """
[simulation]
duration = 60.0
timestep = 0.005
[water]
depth = 200.0
gravity = 9.81
[water.density]
type = "constant"
rho = 1026.0
[tether]
length = 100.0
segments = 50
diameter = 0.006
density = 1200.0
EA = 1.0e5
rated_load = 2000.0
[winch]
mode = "fixed"
[ship]
mode = "follow"
offset = [-80.0, 0.0]
speed = 5.0
[robot]
type = "vehicle"
vehicle = "remus100"
position = [80.0, 0.0, -30.0]
setpoints = [[0.0, 2.0, 0.0, 30.0]]
manoeuvre = "turning_circle"
rudder_deg = 0.0
manoeuvre_start_s = 20.0
"""


def test_tethered_remus_is_slowed_by_what_its_tow_force_predicts():
    """The REMUS 100 on 100 m of cable, the ship following 80 m behind it: the speed loop runs
    until 20 s, then the shaft is held at its speed (full, 1525 rpm) and the rudder at 0. Over
    the last 10 s the surge forces on the hull, written out in this file (Fossen's equations
    at the measured mean state, fin angles and shaft speed), must balance the cable's recorded
    tow-point force (body x); and the speed at which they balance, solved here (brentq), must
    be the one the vehicle runs at. Tolerances: the balance within 1 % of the tow force and the
    predicted speed within 1 % of the slow-down from the free-running speed: the cable is
    still settling (the vehicle accelerates by ~4e-3 m/s^2, 0.2 % of the tow force times the
    vehicle's surge mass)."""
    from mjtether.scenario.runner import ScenarioRun
    from mjtether.scenario import load_scenario

    r = ScenarioRun(load_scenario(text=TOWING))
    try:
        m, d = r.sim.model, r.sim.data
        acts = [m.actuator_actadr[m.actuator(f"vehicle/{n}").id] for n in ("propeller", "rudder", "stern_planes")]
        rows = []
        while r.sim.time < 60.0 - 1e-9:
            r.step()
            if r.sim.time > 50.0:
                rows.append([*r.vehicle.velocity(d)[0], *d.act[acts], *r.named.tow_force_body])
    finally:
        r.close()
    mean = np.mean(rows, axis=0)
    nu, (rpm, d_r, d_s), tow = mean[:6], mean[6:9], mean[9:12]
    assert rpm == pytest.approx(1525.0)
    X = hydro_forces(nu, d_r, d_s, rpm)[0]
    assert tow[0] < -20.0  # the cable holds the vehicle back
    assert abs(X + tow[0]) <= 0.01 * abs(tow[0]), f"surge forces {X:.2f} N against the tow force {tow[0]:.2f} N"

    def residual(u):
        v = nu.copy()
        v[0] = u
        return hydro_forces(v, d_r, d_s, rpm)[0] + tow[0]

    predicted = brentq(residual, 0.1, 5.0, xtol=1e-12)
    free = straight_speed_balance(rpm)
    slowed = free - nu[0]
    assert slowed > 0.5  # m/s: the cable costs the vehicle a good part of its speed
    assert abs(predicted - nu[0]) <= 0.01 * slowed, (
        f"runs at {nu[0]:.4f} m/s, the tow force predicts {predicted:.4f} m/s (free: {free:.4f} m/s)")


def pvs_crossflow(nu_r, rho):
    """Fossen's Python Vehicle Simulator's cross-flow drag (gnc.py ``crossFlowDrag``), written
    out here: 21 points from tail to nose, each weighted dx = L / 20, sway and yaw only."""
    dx = L / 20
    Y = N = 0.0
    for i in range(21):
        x = -L / 2 + dx * i
        vy = nu_r[1] + x * nu_r[5]
        Y -= 0.5 * RHO * DIAM * CD_2D * abs(vy) * vy * dx
        N -= 0.5 * RHO * DIAM * CD_2D * x * abs(vy) * vy * dx
    return np.array([0.0, Y, 0.0, 0.0, 0.0, N])


def turning_circle(rpm, rudder_deg, fossen_crossflow, duration=100.0, dt=0.005):
    """(steady turning diameter 2 U / (d heading / dt) m, horizontal speed U m/s) of the REMUS
    100 alone, from rest at ``rpm`` with ``rudder_deg`` from t = 0, in still water, measured over
    the last 20 s."""
    import dataclasses

    from mjtether.vehicles.vehicle import Hull

    vs = load_vehicle("remus100")
    if fossen_crossflow:
        lift_and_axial_drag = dataclasses.replace(vs.hydro.hull, crossflow_cd=0.0)

        class FossenHull(Hull):
            def wrench(self, nu_r, rho):
                return lift_and_axial_drag.wrench(nu_r, rho) + pvs_crossflow(nu_r, rho)

        fields = {f.name: getattr(vs.hydro.hull, f.name) for f in dataclasses.fields(Hull)}
        vs = dataclasses.replace(vs, hydro=dataclasses.replace(vs.hydro, hull=FossenHull(**fields)))
    water = mt.WaterColumn(depth=500.0, density=mt.ConstantDensity(RHO), gravity=G)
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, -G]
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    vm = build_vehicle(spec, vs, "auv", pos=(0.0, 0.0, -100.0))
    with mt.Simulation(spec, water, bodies=[vm]) as sim:
        m, d = sim.model, sim.data
        d.ctrl[m.actuator("auv/propeller").id] = rpm
        d.ctrl[m.actuator("auv/rudder").id] = math.radians(rudder_deg)
        t, yaw, U = [], [], []
        body = sim.bodies[0].id
        for _ in range(int(round(duration / dt))):
            sim.step()
            if d.time >= duration - 20.0:
                R = d.xmat[body].reshape(3, 3)
                t.append(d.time)
                yaw.append(math.atan2(R[1, 0], R[0, 0]))
                U.append(math.hypot(*d.qvel[sim.bodies[0]._v][:2]))
    rate = np.polyfit(t, np.unwrap(yaw), 1)[0]
    return 2 * np.mean(U) / abs(rate), float(np.mean(U)), rate


# Fossen's Python Vehicle Simulator (github.com/cybergalactic/PythonVehicleSimulator, c717e07,
# 2025), remus100.py run unmodified in still water (forward Euler, h = 0.02 s; the same to 5
# digits at h = 0.005 s): steady turning diameter (m, a circle fitted to the last two turns) and
# speed (m/s) for (rpm, rudder deg). A positive rudder turns it to starboard.
PVS_TURNING = {(1525.0, 5.0): (80.73, 2.544), (1525.0, 10.0): (49.10, 2.528), (1525.0, 15.0): (36.92, 2.507),
               (1000.0, 10.0): (54.49, 1.659)}


@pytest.mark.parametrize("rpm, rudder", list(PVS_TURNING), ids=[f"{r:.0f}rpm-{d:.0f}deg" for r, d in PVS_TURNING])
def test_remus_turning_circles_match_fossens_code(rpm, rudder):
    """With Fossen's own cross-flow sum (``pvs_crossflow``) in place of mjtether's, the turning
    circles of his code: diameter and speed within 0.5 % (his forward-Euler step and our 5 ms
    MuJoCo step each move them by less than 0.05 %; the tolerance leaves room for the
    transcribed coefficients' rounding). The vehicle turns to starboard (heading decreasing, z
    up). mjtether's own cross-flow sum (the midpoint rule of the strip integral, also in heave
    and pitch) makes the circles 6-8 % tighter: docs/vehicles.md sets the two side by side.
    (A hull of a class of its own runs through the NumPy kernels, not the compiled one, which
    has mjtether's sum built in.)"""
    diameter, U, rate = turning_circle(rpm, rudder, fossen_crossflow=True)
    want_d, want_U = PVS_TURNING[(rpm, rudder)]
    assert rate < 0.0
    assert diameter == pytest.approx(want_d, rel=5e-3)
    assert U == pytest.approx(want_U, rel=5e-3)

"""The BlueROV2 Heavy with the thrust model of von Benzon, Sørensen, Uth, Jouffroy, Liniger and
Pedersen (2022), "An Open-Source Benchmark Simulator: Control of a BlueROV2 Underwater Robot",
J. Mar. Sci. Eng. 10(12), 1898 (``assets/vehicles/bluerov2_heavy_benchmark.toml``), against
answers worked out here from their numbers, typed in below, not read from mjtether:

- their Table A1: mass 13.5 kg, volume 0.0134 m^3 (identified in a fresh-water pool,
  1000 kg/m^3), added mass X_u' 6.36 kg and Z_w' 18.68 kg, damping X_u 13.7 N s/m,
  X_|u|u 141 N s^2/m^2, Z_w 33 N s/m, Z_|w|w 190 N s^2/m^2;
- their simulator's thrust model: each thruster clipped to +-30 N, then passed through
  K(s) = (6136 s + 108700) / (s^3 + 89 s^2 + 9258 s + 108700) (their Eq. 19; the benchmark's
  Simulink block, as published with it), whose step response scipy gives here;
- the thruster layout: four horizontal thrusters at 45 degrees to the surge axis, four vertical.

The steady full-surge and full-heave speeds are the roots of thrust = damping, solved here in
closed form. The vehicle runs through mjtether's normal API (MuJoCo, 5 ms steps) in their pool's
water (1000 kg/m^3, g = 9.81 m/s^2, as the vehicle file says it was identified in)."""

import math
from types import SimpleNamespace

import mujoco
import numpy as np
import pytest
from scipy import signal
from scipy.integrate import solve_ivp

import mjtether as mt
from mjtether.physics import actuation
from mjtether.scenario.controllers import VehiclePilot
from mjtether.vehicles.files import build_vehicle, load_vehicle

# von Benzon et al. (2022), Table A1, and their simulator's thrust model
MASS, VOLUME, RHO, G = 13.5, 0.0134, 1000.0, 9.81
X_UDOT, Z_WDOT = 6.36, 18.68
X_U, X_UU, Z_W, Z_WW = 13.7, 141.0, 33.0, 190.0
F_MAX = 30.0  # N, each thruster, either way
K_NUM, K_DEN = [6136.0, 108700.0], [1.0, 89.0, 9258.0, 108700.0]  # Eq. 19
NET_UP = RHO * VOLUME * G - MASS * G  # N: -0.98 N, 1 N heavy in their pool
X_FULL = 4 * F_MAX * math.cos(math.pi / 4)  # 84.85 N: four horizontal thrusters at 45 degrees
Z_FULL = 4 * F_MAX  # 120 N: four vertical thrusters
DT = 0.005


def _root(force, lin, quad):
    """The speed v > 0 at which lin v + quad v^2 = force."""
    return (-lin + math.sqrt(lin * lin + 4.0 * quad * force)) / (2.0 * quad)


def _fly(seconds, *, thrust=None, setpoint=None, dt=DT):
    """The benchmark vehicle 50 m down in their pool's water, from rest: each step its thrusters
    are commanded ``thrust`` (N, one per thruster) or its autopilot flies ``setpoint``
    (heading, speed, ..., depth). Returns the times (s), body velocities nu (n x 6), positions
    (n x 3) and delivered thrusts (n x 8)."""
    vs = load_vehicle("bluerov2_heavy_benchmark")
    water = mt.WaterColumn(depth=100.0, density=mt.ConstantDensity(RHO))
    assert water.gravity == G
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    vm = build_vehicle(spec, vs, "vehicle", pos=(0.0, 0.0, -50.0))
    t, nu, pos, act = [], [], [], []
    with mt.Simulation(spec, water, bodies=[vm]) as sim:
        acts = np.array([sim.model.actuator(f"vehicle/{th.name}").id for th in vs.thrusters])
        delivered = actuation.delivered(sim.model, acts)  # each thruster's last activation
        body = sim.bodies[0]
        if setpoint is not None:
            pilot = VehiclePilot(np.array([setpoint]), vs.autopilot, vs.thrusters, acts)
            run_like = SimpleNamespace(vehicle=body, sim=sim)
        for _ in range(int(round(seconds / dt))):
            if setpoint is not None:
                pilot.update(run_like, sim.time, dt)
            else:
                sim.data.ctrl[acts] = thrust
            sim.step()
            t.append(sim.time)
            nu.append(body.velocity(sim.data)[0])
            pos.append(sim.data.xpos[body.id].copy())
            act.append(sim.data.act[delivered].copy())
    return np.array(t), np.array(nu), np.array(pos), np.array(act)


def _full_heave(sign):
    """Every vertical thruster asked for 100 N along +-z (more than it has: its +-30 N limit
    clips it), the horizontal ones nothing."""
    vs = load_vehicle("bluerov2_heavy_benchmark")
    return np.array([100.0 * sign * np.sign(th.direction[2]) if abs(th.direction[2]) > 0.5 else 0.0
                     for th in vs.thrusters])


@pytest.fixture(scope="module")
def surge_run():
    """The autopilot asked for 3 m/s (more than the vehicle can do) at 50 m for 12 s."""
    return _fly(12.0, setpoint=[0.0, 3.0, 0.0, 50.0])


def test_the_file_carries_the_benchmark_thrust_model_and_bluerov2_heavy_otherwise():
    """Every thruster gives +-30 N through their K(s), coefficient for coefficient; the rest of
    the vehicle (hull, hydrodynamics, thruster geometry, autopilot) is ``bluerov2_heavy``'s,
    exactly."""
    bench, t200 = load_vehicle("bluerov2_heavy_benchmark"), load_vehicle("bluerov2_heavy")
    assert len(bench.thrusters) == 8
    for th in bench.thrusters:
        assert (th.max_forward, th.max_reverse) == (F_MAX, F_MAX), th
        assert th.response == (tuple(K_NUM), tuple(K_DEN)) and th.time_constant is None, th
    for a, b in zip(bench.thrusters, t200.thrusters):
        assert (a.name, a.position, a.direction) == (b.name, b.position, b.direction)
    assert (bench.mass, bench.inertia, bench.centre_of_gravity, bench.tow_point, bench.water_density) == \
        (t200.mass, t200.inertia, t200.centre_of_gravity, t200.tow_point, t200.water_density)
    assert repr(bench.hydro) == repr(t200.hydro)
    assert bench.autopilot == t200.autopilot


def test_full_surge_speed_from_the_force_balance(surge_run):
    """Asked for 3 m/s, the autopilot saturates the four horizontal thrusters (+-30 N at 45
    degrees: X = 4 x 30 cos 45 = 84.85 N) while the vertical ones hold depth and trim the pitch
    moment of the horizontal ones 8.5 cm below the centre of gravity; the speed settles where
    surge damping takes all of X: 13.7 u + 141 u^2 = 84.85 N, u = 0.72869 m/s. Measured over the
    last 2 s: 0.72869 (7e-7 relative). Tolerance 0.1 %: the surge lag (m + X_u') / (X_u + 2 X_|u|u
    u) = 0.09 s has died out 100 times over, and the trim forces are vertical; what is left is the
    pitch trim's small tilt of the thrust (cos of micro-radians) and the loops' residuals."""
    t, nu, _, act = surge_run
    last = t > t[-1] - 2.0
    expected = _root(X_FULL, X_U, X_UU)
    assert expected == pytest.approx(0.72869, abs=1e-5)  # the closed form, as quoted in the docs
    horizontal = np.abs(act[-1, :4])
    np.testing.assert_allclose(horizontal, F_MAX, rtol=1e-9)  # saturated
    assert float(np.mean(nu[last, 0])) == pytest.approx(expected, rel=1e-3)
    assert float(np.max(np.abs(nu[last, 3:]))) < 1e-3  # level and straight


@pytest.mark.parametrize("sign", [1.0, -1.0], ids=["up", "down"])
def test_full_heave_speeds_from_the_force_balance(sign):
    """Four vertical thrusters at +-30 N give Z = 120 N; with their pool's net buoyancy
    (1000 x 0.0134 x 9.81 - 13.5 x 9.81 = -0.98 N) the vehicle settles at 33 w + 190 w^2 =
    120 - 0.98 N going up (0.70937 m/s) and 120 + 0.98 N going down (0.71583 m/s). Measured after
    8 s: both to 4e-14. Tolerance 0.1 %: the heave lag (m + Z_w') / (Z_w + 2 Z_|w|w w) = 0.11 s
    has died out 70 times over; nothing else acts in heave (the vertical thrusters push through
    the centre of gravity's height and the centre of buoyancy is straight above it)."""
    t, nu, _, act = _fly(8.0, thrust=_full_heave(sign))
    expected = _root(Z_FULL + sign * NET_UP, Z_W, Z_WW)
    np.testing.assert_allclose(np.abs(act[-1, 4:]), F_MAX, rtol=1e-9)
    assert float(sign * nu[-1, 2]) == pytest.approx(expected, rel=1e-3)
    assert float(np.max(np.abs(nu[-1, [0, 1, 3, 4, 5]]))) < 1e-6


@pytest.mark.parametrize("dt", [0.001, 0.005])
def test_thruster_step_is_the_step_response_of_eq_19(dt):
    """A full-heave step from rest (each vertical thruster asked for 100 N, clipped to 30 N):
    the thrust each delivers at every step is 30 N times K(s)'s step response (scipy's
    ``signal.step``, which integrates the state space exactly for a step) at that time. MuJoCo
    steps the thruster's three states exactly for a command held over the step, so nothing but
    rounding separates them: tolerance 1e-9 of 30 N (measured 1e-11 at both steps). K(s) starts
    with zero slope, reaches 0.999 at 40 ms, dips to 0.853 at 73 ms and is within 5 % from
    about 0.12 s; a single lag could share only its mean delay (0.0287 s) and missed it by up to
    0.28 of the step."""
    t, _, _, act = _fly(1.0, thrust=_full_heave(1.0), dt=dt)
    _, y = signal.step((K_NUM, K_DEN), T=np.r_[0.0, t])
    expected = np.repeat(F_MAX * y[1:, None], 4, axis=1)  # the four vertical thrusters
    np.testing.assert_allclose(np.abs(act[:, 4:]), expected, rtol=0.0, atol=1e-9 * F_MAX)


def _their_heave(seconds):
    """Their heave equation with their thrust through K(s), integrated here (scipy's solve_ivp,
    rtol 1e-10): (m + Z_w') w' = K(s)[120 N] + (B - W) - (33 + 190 |w|) w, from rest."""
    m_z = MASS + Z_WDOT
    A, B, C, D = signal.tf2ss(K_NUM, K_DEN)

    def rhs(_, x):
        w = x[3]
        thrust = float(C[0] @ x[:3] + D[0, 0] * Z_FULL)
        return np.r_[A @ x[:3] + B[:, 0] * Z_FULL, (thrust + NET_UP - (Z_W + Z_WW * abs(w)) * w) / m_z, w]

    return solve_ivp(rhs, (0.0, seconds), np.zeros(5), rtol=1e-10, atol=1e-12, dense_output=True, max_step=1e-3)


@pytest.mark.parametrize("dt", [0.001, 0.005])
def test_heave_from_rest_against_their_heave_equation_with_eq_19(dt):
    """Full heave up from rest for 3 s, against their heave equation with K(s) (``_their_heave``).
    MuJoCo holds each step's forces over the step (the thrust, the damping and the buoyancy
    of the state the step starts from), so the two differ by a first-order error in the step:
    tolerances of one step's change of velocity at the largest acceleration, dt x 120 N /
    32.18 kg (2.6 % of top speed at 5 ms, 0.53 % at 1 ms), and of one step's travel at top speed
    (3.5 mm at 5 ms). Measured: the velocity within 1.24 % of top speed at 5 ms and 0.25 % at
    1 ms (first order: 5x for 5x), the height 2.4 mm and 0.5 mm short of their 2.0098 m. With
    the single lag this file used to have, the velocity was 4.6 % off at 5 ms, and the test
    failed at 1 ms. Once both have reached top speed they agree to 1e-3 of it."""
    t, nu, pos, _ = _fly(3.0, thrust=_full_heave(1.0), dt=dt)
    ref = _their_heave(3.0)
    w_top = _root(Z_FULL + NET_UP, Z_W, Z_WW)
    np.testing.assert_allclose(nu[:, 2], ref.sol(t)[3], rtol=0.0, atol=dt * Z_FULL / (MASS + Z_WDOT))
    assert float(pos[-1, 2] + 50.0) == pytest.approx(float(ref.sol(3.0)[4]), abs=dt * w_top)
    gap = np.abs(nu[:, 2] - ref.sol(t)[3])
    assert float(gap[t > 1.0].max()) < 1e-3 * w_top  # steady: the same top speed


@pytest.mark.xfail(strict=True, reason="their Table A1 damping and 85 N balance at 0.729 m/s, not 0.72 (see docstring)")
def test_top_surge_speed_against_their_table_4_figure(surge_run):
    """Their Table 4, as read for ``bluerov2_heavy.toml`` (the paper could not be re-read for
    this test): 0.72 m/s at 85 N. A two-figure 0.72 stands for [0.715, 0.725). mjtether's
    benchmark vehicle runs at 0.7287 m/s (test above), and so does the force balance of their
    own Table A1 damping at their 84.85 N (13.7 u + 141 u^2 = 84.85 gives 0.72869; 0.72 would
    need 83.0 N, 2.2 % less). The gap is between their two published numbers, not in mjtether:
    whether the 0.72 is a pool measurement (which the fitted damping need not pass through) or
    rounded down from their simulation could not be checked here. Strict xfail: it fails the
    day this matches, so that the docs are corrected."""
    t, nu, _, _ = surge_run
    u = float(np.mean(nu[t > t[-1] - 2.0, 0]))
    assert 0.715 <= u < 0.725, u

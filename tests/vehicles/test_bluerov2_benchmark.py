"""The BlueROV2 Heavy with the thrust model of von Benzon, Sørensen, Uth, Jouffroy, Liniger and
Pedersen (2022), "An Open-Source Benchmark Simulator: Control of a BlueROV2 Underwater Robot",
J. Mar. Sci. Eng. 10(12), 1898 (``assets/vehicles/bluerov2_heavy_benchmark.toml``), against
answers worked out here from their numbers, typed in below, not read from mjtether:

- their Table A1: mass 13.5 kg, volume 0.0134 m^3 (identified in a fresh-water pool,
  1000 kg/m^3), added mass X_u' 6.36 kg and Z_w' 18.68 kg, damping X_u 13.7 N s/m,
  X_|u|u 141 N s^2/m^2, Z_w 33 N s/m, Z_|w|w 190 N s^2/m^2;
- their simulator's thrust model: each thruster clipped to +-30 N, then lagged by
  K(s) = (6136 s + 108700) / (s^3 + 89 s^2 + 9258 s + 108700) (their Eq. 19; the benchmark's
  Simulink block, as published with it);
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
            act.append(sim.data.act[acts].copy())
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
    """Every thruster gives +-30 N and lags by K(s)'s mean delay -K'(0) (the first moment of its
    impulse response, (9258 - 6136) / 108700 = 0.028721 s), to the file's three figures (half a
    unit in the last: 0.17 %); the rest of the vehicle (hull, hydrodynamics, thruster geometry,
    autopilot) is ``bluerov2_heavy``'s, exactly."""
    bench, t200 = load_vehicle("bluerov2_heavy_benchmark"), load_vehicle("bluerov2_heavy")
    mean_delay = K_DEN[2] / K_DEN[3] - K_NUM[0] / K_NUM[1]
    assert len(bench.thrusters) == 8
    for th in bench.thrusters:
        assert (th.max_forward, th.max_reverse) == (F_MAX, F_MAX), th
        assert th.time_constant == pytest.approx(mean_delay, abs=0.5e-4), th
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
    8 s: both to 1e-14. Tolerance 0.1 %: the heave lag (m + Z_w') / (Z_w + 2 Z_|w|w w) = 0.11 s
    has died out 70 times over; nothing else acts in heave (the vertical thrusters push through
    the centre of gravity's height and the centre of buoyancy is straight above it)."""
    t, nu, _, act = _fly(8.0, thrust=_full_heave(sign))
    expected = _root(Z_FULL + sign * NET_UP, Z_W, Z_WW)
    np.testing.assert_allclose(np.abs(act[-1, 4:]), F_MAX, rtol=1e-9)
    assert float(sign * nu[-1, 2]) == pytest.approx(expected, rel=1e-3)
    assert float(np.max(np.abs(nu[-1, [0, 1, 3, 4, 5]]))) < 1e-6


def test_thruster_step_has_the_mean_delay_of_eq_19():
    """A full-heave step from rest (1 ms steps): each vertical thruster's delivered thrust F(t)
    reaches 30 N with the mean delay of their K(s), int_0^inf (1 - F/30) dt = -K'(0) =
    0.028721 s, the one number a single lag can share with K(s) that fixes the thrust impulse
    (and so the distance) lost after a step. Tolerance 0.2 %: the file gives the time constant to
    three figures (0.0287 s, 0.07 % from -K'(0)) and the trapezoid rule on 1 ms steps overstates
    a lag's mean delay by dt^2 / (12 tau^2) = 0.01 %.

    K(s) itself is not a single lag (poles -13.16 and -37.92 +- 82.60i 1/s): its step starts with
    zero slope, reaches 0.999 at 40 ms, dips to 0.853 at 73 ms, and is within 5 % from 0.12 s. The
    gap to the lag is measured here and stated, not hidden: at most 0.28 of the step (at 34 ms;
    the bounds below only pin where and how large it is), and both are within 1 % of 30 N after
    0.4 s."""
    t, _, _, act = _fly(1.0, thrust=_full_heave(1.0), dt=0.001)
    tt = np.r_[0.0, t]
    F = np.r_[0.0, np.abs(act[:, 4:]).mean(axis=1)]
    deficit = 1.0 - F / F_MAX
    mean_delay = float(np.sum(0.5 * (deficit[1:] + deficit[:-1]) * np.diff(tt)))
    k_mean_delay = K_DEN[2] / K_DEN[3] - K_NUM[0] / K_NUM[1]
    assert k_mean_delay == pytest.approx(0.028721, abs=1e-6)
    assert mean_delay == pytest.approx(k_mean_delay, rel=2e-3)
    # the gap to K(s)'s own step, measured (documented in the vehicle file and docs/vehicles.md)
    _, y = signal.step((K_NUM, K_DEN), T=tt)
    gap = np.abs(F / F_MAX - y)
    assert 0.2 < float(gap.max()) < 0.35 and 0.02 < float(tt[gap.argmax()]) < 0.05
    late = tt > 0.4
    assert np.all(np.abs(y[late] - 1.0) < 0.01) and np.all(np.abs(F[late] / F_MAX - 1.0) < 0.01)


def test_heave_from_rest_against_their_heave_equation_with_eq_19():
    """Full heave up from rest for 3 s, against their heave equation integrated here
    (scipy's solve_ivp, rtol 1e-10) with their thrust through K(s):
    (m + Z_w') w' = K(s)[120 N] + (B - W) - (33 + 190 |w|) w. The distance risen agrees to one
    step's travel at top speed and half again (1.5 x 5 ms x 0.709 m/s = 5.3 mm: MuJoCo applies
    the thrust of the step before; the lag's shared mean delay leaves no other distance
    between them). Measured: 3.5 mm short of their 2.0098 m. Their velocity runs ahead of
    mjtether's while K(s) leads the lag (measured: at most 0.032 m/s, 4.6 % of top speed, at
    0.06 s); against the same equation with the file's single lag in place of K(s) mjtether
    agrees to one step's change of velocity (dt x the largest acceleration, 120 N / 32.18 kg)."""
    t, nu, pos, _ = _fly(3.0, thrust=_full_heave(1.0))
    risen = pos[:, 2] + 50.0
    m_z = MASS + Z_WDOT
    A, B, C, D = signal.tf2ss(K_NUM, K_DEN)

    def theirs(_, x):
        w = x[3]
        thrust = float(C[0] @ x[:3] + D[0, 0] * Z_FULL)
        return np.r_[A @ x[:3] + B[:, 0] * Z_FULL, (thrust + NET_UP - (Z_W + Z_WW * abs(w)) * w) / m_z, w]

    tau = load_vehicle("bluerov2_heavy_benchmark").thrusters[4].time_constant

    def lagged(_, x):
        thrust, w = x[0], x[1]
        return [(Z_FULL - thrust) / tau, (thrust + NET_UP - (Z_W + Z_WW * abs(w)) * w) / m_z, w]

    ref = solve_ivp(theirs, (0.0, 3.0), np.zeros(5), rtol=1e-10, atol=1e-12, dense_output=True, max_step=1e-3)
    lag = solve_ivp(lagged, (0.0, 3.0), np.zeros(3), rtol=1e-10, atol=1e-12, dense_output=True, max_step=1e-3)
    w_top = _root(Z_FULL + NET_UP, Z_W, Z_WW)
    assert float(risen[-1]) == pytest.approx(float(ref.sol(3.0)[4]), abs=1.5 * DT * w_top)
    np.testing.assert_allclose(nu[:, 2], lag.sol(t)[1], atol=DT * Z_FULL / m_z)
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

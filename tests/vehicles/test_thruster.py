"""Thrusters (``mjtether.vehicles.thruster``): the thrust curve by hand from Hong et al. (2020)'s numbers,
and the MuJoCo actuator against the first-order response it is meant to have (exact for
MuJoCo's ``filterexact``: 1e-12), its asymmetric saturation, and the force and moment it puts on
the hull (r x F by hand)."""

import math

import mujoco
import numpy as np
import pytest

from mjtether.physics import dispatch
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
    m = dispatch.compile_spec(spec)  # (frees the callback slots while compiling: a Python act_dyn fails a compile)
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


# --------------------------------------------------------------------------- a transfer-function response

# a second-order thruster response, omega^2 / (s^2 + 2 zeta omega s + omega^2), omega 20 1/s, zeta 0.3:
# its step response in closed form (an underdamped oscillator from rest), worked out here
OMEGA, ZETA = 20.0, 0.3
SECOND = ((OMEGA ** 2,), (1.0, 2.0 * ZETA * OMEGA, OMEGA ** 2))


def _second_order_step(t):
    wd = OMEGA * math.sqrt(1.0 - ZETA ** 2)
    return 1.0 - np.exp(-ZETA * OMEGA * t) * (np.cos(wd * t) + ZETA / math.sqrt(1.0 - ZETA ** 2) * np.sin(wd * t))


def _step_through(m, d, a, command, steps):
    """The thrust delivered after each of ``steps`` steps at ``command`` (the actuator's last
    activation)."""
    out = []
    d.ctrl[a] = command
    for _ in range(steps):
        mujoco.mj_step(m, d)
        out.append(d.act[m.actuator_actadr[a] + m.actuator_actnum[a] - 1])
    return np.array(out)


def test_a_response_thruster_delivers_the_closed_form_step_response_and_saturates():
    """A 100 N command to a thruster of 80 N forward through SECOND: the thrust delivered at each
    step is 80 N times the oscillator's step response, 1 - exp(-zeta w t) (cos w_d t + zeta /
    sqrt(1 - zeta^2) sin w_d t), in closed form: 1e-9 of 80 N (the discretisation is exact for a
    command held over the step; rounding is left). The actuator's force on the hull is that
    thrust (the last activation, the one MuJoCo's gain multiplies). Then -100 N: it settles at
    the 30 N reverse limit."""
    th = Thruster("stern", (-0.5, 0.0, 0.0), (1.0, 0.0, 0.0), 80.0, 30.0,
                  response={"numerator": SECOND[0], "denominator": SECOND[1]})  # (as a vehicle file's table)
    m, d, a = _hull(th)
    assert m.actuator_actnum[a] == 2 and m.actuator_dyntype[a] == mujoco.mjtDyn.mjDYN_USER
    y = _step_through(m, d, a, 100.0, 500)
    t = m.opt.timestep * np.arange(1, 501)
    np.testing.assert_allclose(y, 80.0 * _second_order_step(t), rtol=0.0, atol=80e-9)
    assert d.actuator_force[a] == pytest.approx(y[-2], rel=1e-12)  # (computed at the last step's start)
    y = _step_through(m, d, a, -100.0, 3000)
    assert y[-1] == pytest.approx(-30.0, rel=1e-9)


def test_the_python_and_the_compiled_callbacks_agree():
    """The Python ``mjcb_act_dyn`` (used where numba cannot run) and the compiled one give the same
    thrust to 1e-12 on von Benzon et al.'s (2022) K(s) under a changing command."""
    from mjtether.physics import actuation, native
    if not native.available():
        pytest.skip("the compiled callback needs numba")
    th = Thruster("t", (0, 0, 0), (1, 0, 0), 30.0, 30.0,
                  response=((6136.0, 108700.0), (1.0, 89.0, 9258.0, 108700.0)))
    runs = []
    for cb in (native.act_dyn_callback(), actuation._act_dyn):
        m, d, a = _hull(th, dt=0.005)
        mujoco.set_mjcb_act_dyn(cb)
        try:
            runs.append(np.concatenate([_step_through(m, d, a, c, 40) for c in (12.0, -50.0, 7.0)]))
        finally:
            actuation.install()
    np.testing.assert_allclose(runs[0], runs[1], rtol=0.0, atol=1e-12 * 30.0)
    assert np.ptp(runs[0]) > 30.0  # it moved


@pytest.mark.filterwarnings("ignore:Nan, Inf or huge value in QACC")
def test_a_response_thruster_at_another_step_is_nan_and_set_response_fixes_it():
    """The discretisation is for one time step: stepped at another, the thrust becomes NaN (the
    run's divergence check then stops it) instead of a wrong response; ``set_response``
    re-discretises it for the model's step, and the response is the closed form again."""
    from mjtether.physics import actuation
    th = Thruster("t", (0, 0, 0), (1, 0, 0), 80.0, 80.0, response=SECOND)
    m, d, a = _hull(th, dt=0.002)
    m.opt.timestep = 0.004
    assert np.all(np.isnan(_step_through(m, d, a, 10.0, 2)))
    actuation.set_response(m, a, *th.response)
    mujoco.mj_resetData(m, d)
    y = _step_through(m, d, a, 10.0, 100)
    np.testing.assert_allclose(y, 10.0 * _second_order_step(0.004 * np.arange(1, 101)), rtol=0.0, atol=1e-8)


def test_a_rollout_on_worker_threads_gives_the_same_response():
    """``mujoco.rollout`` steps on threads that never enter Python; the compiled callback gives
    them the same thrust as ``mj_step`` on this thread: 1e-12."""
    from mjtether.physics import native
    if not native.available():
        pytest.skip("the compiled callback needs numba")
    from mujoco import rollout
    m, d, a = _hull(Thruster("t", (0, 0, 0), (1, 0, 0), 80.0, 80.0, response=SECOND))
    y = _step_through(m, d, a, 50.0, 60)
    mujoco.mj_resetData(m, d)
    state = np.zeros((2, mujoco.mj_stateSize(m, mujoco.mjtState.mjSTATE_FULLPHYSICS)))
    mujoco.mj_getState(m, d, state[0], mujoco.mjtState.mjSTATE_FULLPHYSICS)
    state[1] = state[0]
    ctrl = np.full((2, 60, m.nu), 50.0)
    out, _ = rollout.rollout([m, m], [mujoco.MjData(m), mujoco.MjData(m)], state, ctrl)
    act = out[:, :, 1 + m.nq + m.nv:1 + m.nq + m.nv + m.na]
    np.testing.assert_allclose(act[:, :, -1], np.broadcast_to(y, (2, 60)), rtol=0.0, atol=1e-12 * 80.0)


@pytest.mark.parametrize("response, message", [
    ((1.0,), "numerator and denominator"),
    (((1.0,), (1.0, 2.0, 3.0, 4.0, 5.0)), "order must be 1 to 3, got 4"),
    (((1.0, 1.0), (1.0, 1.0)), "strictly proper"),
    (((2.0,), (1.0, 4.0)), "gain at rest K\\(0\\) .* must be 1 .*got 0.5"),
    (((1.0,), (1.0, -1.0, -2.0)), "negative real part"),
    (((1.0,), (1.0, float("nan"))), "finite"),
    ({"numerator": [1.0], "denominator": [1.0, 1.0], "gain": 2.0}, "a table of numerator and denominator"),
])
def test_bad_responses_are_named(response, message):
    with pytest.raises(ValueError, match=f"port.response.*{message}"):
        Thruster("port", (0, 0, 0), (1, 0, 0), 100.0, 50.0, response=response)


def test_time_constant_and_response_together_are_refused():
    with pytest.raises(ValueError, match="port: give time_constant .* or response .*, not both"):
        Thruster("port", (0, 0, 0), (1, 0, 0), 100.0, 50.0, time_constant=0.1, response=SECOND)


def test_a_compile_leaves_another_codes_act_dyn_callback_alone():
    """Until mjtether builds a response thruster, the process's ``mjcb_act_dyn`` is not its own:
    compiling through ``dispatch`` (as every Simulation does) keeps a callback other code set.
    Run in a fresh process, where mjtether has installed none."""
    import subprocess
    import sys
    import textwrap

    code = textwrap.dedent("""
        import mujoco
        from mjtether.physics import dispatch
        theirs = lambda m, d, i: 0.0
        mujoco.set_mjcb_act_dyn(theirs)
        dispatch.compile_spec(mujoco.MjSpec.from_string("<mujoco><worldbody/></mujoco>"))
        assert mujoco.get_mjcb_act_dyn() is theirs, mujoco.get_mjcb_act_dyn()
    """)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]

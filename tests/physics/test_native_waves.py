"""The native passive callback (``mjtether.physics.native``) in waves: tethers and rigid bodies.

The reference is the Python path: the providers' own loads (``cable.loads.CableLoads``' sea at
the Gauss points and the nodes by ``WaveField.state``, its point loads' NumPy arithmetic,
``BoundBodyHydro.wave_loads`` in NumPy), run by the Python callback with the native one off,
and, further from the code under test, the NumPy reference kernels throughout (``hydro``,
``WaveField.reference_state``). The native callback evaluates the same sea (``waves.state_kernel``)
at the same points at the ``mjData``'s time and adds the same loads in compiled code: against
the Python path 1e-12 of the largest generalised force (the rounding of a different order of
additions, 1e-16 relative, with room for nothing else), and over 300 steps the same trajectory
to 1e-12 of the largest coordinate; against the NumPy kernels 1e-11 of the largest force (the
compiled sea agrees with the NumPy one to 1e-12 of its largest value: ``test_wave_kernel``).
"""

import math
import pathlib

import mujoco
import numpy as np
import pytest

import mjtether as mt
from conftest import new_spec
from mjtether import rollouts
from mjtether.physics import compiled, native, waves
from mjtether.quasistatic import steady_state
from mjtether.scenario import load_scenario
from mjtether.scenario.runner import ScenarioRun

pytestmark = pytest.mark.skipif(compiled.numba is None, reason="numba is not installed")

ROOT = pathlib.Path(__file__).resolve().parents[2]
SEAS = {
    # a JONSWAP sea (Hs 3 m, Tp 9 s, 100 components) on the walker, its body in the sea too,
    # from its full sea at once (no build-up); and the same with its build-up ramp
    "jonswap": ("examples/walker_sea_state.toml", ["waves.ramp_periods=0.0"]),
    "jonswap_ramp": ("examples/walker_sea_state.toml", []),
    # a regular 2 m, 8 s wave on the lazy-wave make-up (floats, a clump: point loads) near the surface
    "regular": ("examples/lazy_wave_umbilical.toml", ['waves.type="regular"', "waves.height=2.0", "waves.period=8.0",
                                                      "waves.ramp_periods=0.0"]),
}
STEPS = 300


def _run(name: str) -> ScenarioRun:
    path, more = SEAS[name]
    return ScenarioRun(load_scenario(ROOT / path, overrides=["simulation.duration=5.0", *more]))


def _python_forces(sim, numpy: bool = False):
    """``qfrc_passive`` at the simulation's state from the Python providers (the native callback
    off; ``numpy``: with the NumPy kernels and the NumPy sea); the stick points left as they were."""
    m, d = sim.model, sim.data
    stick = d.userdata.copy()
    kept = [(t, t._fast) for t in sim.tethers.values()], [(b, b._codes) for b in sim.bodies]
    field = (sim.tether().water if sim.tethers else sim.bodies[0].water).waves
    if numpy:
        for t in sim.tethers.values():
            t._fast = None
        for b in sim.bodies:
            b._codes = None
        field.compiled = False
    mujoco.set_mjcb_passive(None)
    try:
        mujoco.mj_forward(m, d)
        for p in sim._providers:
            p.apply(m, d)
        return d.qfrc_passive.copy()
    finally:
        mt.dispatch._install()
        d.userdata[:] = stick
        for obj, fast in kept[0]:
            obj._fast = fast
        for obj, codes in kept[1]:
            obj._codes = codes
        if field is not None:
            field.compiled = True


def _native_forces(sim):
    d = sim.data
    stick = d.userdata.copy()
    mujoco.mj_forward(sim.model, d)
    d.userdata[:] = stick
    return d.qfrc_passive.copy()


@pytest.mark.parametrize("name", list(SEAS))
def test_native_wave_loads_match_the_python_path(name):
    """Every 50th of 300 steps: the native callback's generalised passive forces against the
    Python path's (1e-12 of the largest) and the NumPy kernels' (1e-11) at the same state; the
    waves really load the line there (their part is over 0.1 % of the largest force)."""
    run = _run(name)
    try:
        sim = run.sim
        assert sim.native  # (every provider native, in waves)
        assert sim.tether().water.waves is not None
        for step in range(STEPS):
            run.step()
            if step % 50 != 49:
                continue
            got = _native_forces(sim)
            want = _python_forces(sim)
            scale = np.max(np.abs(want))
            assert np.max(np.abs(got - want)) <= 1e-12 * scale, f"{np.max(np.abs(got - want)) / scale:.3g}"
            ref = _python_forces(sim, numpy=True)
            assert np.max(np.abs(got - ref)) <= 1e-11 * scale, f"{np.max(np.abs(got - ref)) / scale:.3g}"
        water = sim.tether().water
        field = water.waves
        object.__setattr__(water, "waves", None)  # (the flat sea's forces at the same state: the waves' share)
        try:
            flat = _python_forces(sim)
        finally:
            object.__setattr__(water, "waves", field)
        assert np.max(np.abs(flat - want)) > 1e-3 * scale
    finally:
        run.close()


@pytest.mark.parametrize("name", ["jonswap", "regular"])
def test_native_run_in_waves_is_the_python_run(name, monkeypatch):
    """300 steps natively and with the Python callback (``native.available`` made False): the
    same trajectory, 1e-12 of the largest coordinate."""
    run = _run(name)
    try:
        assert run.sim.native
        for _ in range(STEPS):
            run.step()
        got = run.sim.data.qpos.copy()
    finally:
        run.close()
    monkeypatch.setattr(native, "available", lambda: False)
    run = _run(name)
    try:
        assert not run.sim.native
        for _ in range(STEPS):
            run.step()
        want = run.sim.data.qpos.copy()
    finally:
        run.close()
    assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want))


def _hanging(water):
    """A 150 m cable hanging from the surface between fixed points 80 m apart and 100 m down in
    ``water``, started from its steady state in still water."""
    tether = mt.TetherSpec(length=150.0, segments=30, diameter=0.03, density=1100.0)
    top, end = [0.0, 0.0, 0.0], [80.0, 0.0, -100.0]
    ss = steady_state(tether, mt.WaterColumn(depth=300.0), top, end, seabed=False)
    spec = new_spec(0.005)
    tm = mt.add_tether(spec, tether, mt.FixedPoint(top), mt.FixedPoint(end), water=water, nodes=ss.nodes)
    return mt.Simulation(spec, water, [tm])


def test_a_rollout_in_a_regular_wave_is_the_simulations_run():
    """400 steps (2 s) of the hanging cable in a 3 m, 6 s regular wave: a rollout on MuJoCo's
    threads (which read the wave's time from each ``mjData``) against ``Simulation.step``, 1e-10
    of the largest coordinate (as ``test_native``'s rollouts); the same cable in still water
    ends decimetres away (the check can fail)."""
    field = waves.WaveField(waves.regular(3.0, 6.0, depth=300.0), depth=300.0)
    with _hanging(mt.WaterColumn(depth=300.0, waves=field)) as sim:
        assert sim.native
        s0 = rollouts.initial_state(sim)
        sim.step(400)
        want = sim.data.qpos.copy()
        out, _ = rollouts.rollout(sim, np.repeat(s0[None], 2, axis=0), nstep=400, nthread=2)
        for got in out[:, -1]:
            assert np.max(np.abs(got[1:1 + sim.model.nq] - want)) <= 1e-10 * np.max(np.abs(want))
    with _hanging(mt.WaterColumn(depth=300.0)) as still:
        still.step(400)
        assert np.max(np.abs(still.data.qpos - want)) > 0.05


def test_a_turned_body_on_slide_joints_in_waves():
    """A 0.8 m^3 body turned 40 deg in yaw and 25 in pitch on three slide joints (its added mass
    R diag(m_a) R^T, not a free joint's), its centre 0.3 m down in a 3 m, 8 s wave (it pierces
    the surface) in a 0.4 m/s current, moving: the native callback's force on its joints against
    the Python path's (``BoundBodyHydro.wave_loads``) at 21 instants of a period, 1e-12 of the
    largest; the wave moves the force by over 10 % of it (the check can fail)."""
    field = waves.WaveField(waves.regular(3.0, 8.0, 0.0, 60.0), 60.0)
    water = mt.WaterColumn(depth=60.0, current=mt.ConstantCurrent(0.4), waves=field)
    cz, sz, cy, sy = math.cos(0.7), math.sin(0.7), math.cos(0.44), math.sin(0.44)
    R = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]]) @ np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0],
                                                                               [-sy, 0.0, cy]])
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, R.ravel())
    spec = new_spec(0.005)
    body = spec.worldbody.add_body(name="b", pos=[5.0, 0.0, -0.3], quat=list(quat))
    for axis in np.eye(3) @ R:  # (slide joints along the world's axes, in the body frame)
        body.add_joint(type=mujoco.mjtJoint.mjJNT_SLIDE, axis=list(axis))
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.5, 0, 0], mass=900.0, contype=0, conaffinity=0)
    hydro = mt.add_body_hydro(spec, "b", mt.RigidBodyHydro(volume=0.8, drag_cd=(1.2, 0.9, 0.6), drag_area=(0.9, 1.1, 0.7),
                                                           added_mass=(400.0, 700.0, 900.0), height=1.0))
    with mt.Simulation(spec, water, bodies=[hydro]) as sim:
        assert sim.native and not sim.bodies[0]._free
        sim.data.qvel[:] = (0.3, -0.2, 0.5)
        forces = []
        for t in np.linspace(0.0, 8.0, 21):
            sim.data.time = t
            got, want = _native_forces(sim), _python_forces(sim)
            scale = np.max(np.abs(want))
            assert np.max(np.abs(got - want)) <= 1e-12 * scale, f"{np.max(np.abs(got - want)) / scale:.3g}"
            forces.append(want)
    forces = np.array(forces)
    assert np.max(np.ptp(forces, axis=0)) > 0.1 * np.max(np.abs(forces))

"""Two simulations in one process never see each other's forces."""

import numpy as np
import pytest

import mjtether as mt
from conftest import new_spec


def _make(speed: float):
    water = mt.WaterColumn(depth=300.0, current=mt.ExponentialCurrent(speed, decay_depth=20.0))
    tether = mt.TetherSpec(length=150.0, segments=20, diameter=0.03, density=1100.0)
    spec = new_spec(0.005)
    tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, 0]), mt.FixedPoint([80, 0, -100]), water=water)
    return mt.Simulation(spec, water, [tm])


def _run_alone(speed, steps):
    with _make(speed) as sim:
        sim.step(steps)
        return sim.data.qpos.copy(), sim.tether().tension(sim.data)


def test_alternate_stepping_equals_alone():
    steps = 400
    qa, ta = _run_alone(2.0, steps)
    qb, tb = _run_alone(0.3, steps)
    a, b = _make(2.0), _make(0.3)
    try:
        for _ in range(steps):
            a.step()
            b.step()
        # bitwise: the same model stepped the same way gives the same numbers
        np.testing.assert_array_equal(a.data.qpos, qa)
        np.testing.assert_array_equal(b.data.qpos, qb)
        np.testing.assert_array_equal(a.tether().tension(a.data), ta)
        np.testing.assert_array_equal(b.tether().tension(b.data), tb)
        assert not np.allclose(qa, qb)  # the two cases really differ
    finally:
        a.close()
        b.close()


def test_close_removes_forces():
    sim = _make(2.0)
    sim.close()
    assert mt.dispatch.active_count() == 0
    # stepping the raw model now gives MuJoCo's own dynamics only (no drag, no buoyancy)
    import mujoco
    mujoco.mj_step(sim.model, sim.data)
    assert np.all(sim.data.qfrc_passive == 0.0)


def test_a_provider_failing_on_the_first_state_leaves_nothing_registered(monkeypatch):
    """A Python force provider (the NumPy kernels: compiled ones raise nothing) that raises while
    the simulation is being made (its first mj_forward) raises from the constructor, and the
    half-made simulation is unregistered (there is no object to close)."""
    import mujoco

    import mjtether.vehicles.vehicle
    from mjtether.vehicles.files import build_vehicle, load_vehicle

    spec = mujoco.MjSpec()
    vm = build_vehicle(spec, load_vehicle("remus100"), "auv", pos=(0.0, 0.0, -10.0))

    def fails(self, model, data):
        raise ArithmeticError("a provider failed")

    monkeypatch.setattr(mjtether.vehicles.vehicle.BoundVehicle, "apply", fails)
    monkeypatch.setenv(mt.compiled.KERNELS_ENV, "numpy")
    before = mt.dispatch.active_count()
    with pytest.raises(ArithmeticError, match="a provider failed"):
        mt.Simulation(spec, mt.WaterColumn(depth=100.0), bodies=[vm])
    assert mt.dispatch.active_count() == before


def _state(sim):
    import mujoco

    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    s = np.zeros(mujoco.mj_stateSize(sim.model, spec))
    mujoco.mj_getState(sim.model, sim.data, s, spec)
    return s


def test_a_rollout_of_a_python_forced_model_is_refused_not_run_in_vacuum(monkeypatch):
    """With the NumPy kernels (Python providers), ``mujoco.rollout`` steps its own ``MjData``,
    which no Simulation owns and whose worker threads cannot call Python: its cable would have no
    drag, weight or buoyancy. On the main thread it fails with the reason; on worker threads
    (where an exception would abort the process) its states come back NaN with a RuntimeWarning
    saying why. The simulation itself steps on unharmed, and a model that is not mjtether's rolls
    out as before. (With the compiled kernels the loads apply there: ``test_native``.)"""
    import mujoco
    from mujoco import rollout

    monkeypatch.setenv(mt.compiled.KERNELS_ENV, "numpy")
    plain = mujoco.MjModel.from_xml_string("<mujoco><worldbody><body><freejoint/><geom size='0.1'/></body>"
                                           "</worldbody></mujoco>")  # (compiled before the simulation)
    with _make(0.5) as sim:
        s0 = _state(sim)
        with pytest.raises(Exception, match="no mjtether Simulation owns"):
            rollout.rollout(sim.model, mujoco.MjData(sim.model), s0[None], nstep=5)
        with pytest.warns(RuntimeWarning, match="no mjtether Simulation owns"):
            with rollout.Rollout(nthread=2) as r:
                states, _ = r.rollout([sim.model] * 2, [mujoco.MjData(sim.model) for _ in range(2)],
                                      np.repeat(s0[None], 2, axis=0), nstep=5)
        assert np.isnan(states[:, -1, 1:]).all(axis=-1).all()
        sim.step(10)
        assert np.all(np.isfinite(sim.data.qpos))
        d = mujoco.MjData(plain)
        ps = np.zeros(mujoco.mj_stateSize(plain, mujoco.mjtState.mjSTATE_FULLPHYSICS))
        mujoco.mj_getState(plain, d, ps, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        out, _ = rollout.rollout(plain, d, ps[None], nstep=5)
        assert np.all(np.isfinite(out))

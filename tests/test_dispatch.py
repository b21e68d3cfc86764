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
    """A force provider that raises while the simulation is being made (its first mj_forward)
    raises from the constructor, and the half-made simulation is unregistered (there is no
    object to close)."""
    import mujoco

    import mjtether.vehicle
    from mjtether.vehicles import build_vehicle, load_vehicle

    spec = mujoco.MjSpec()
    vm = build_vehicle(spec, load_vehicle("remus100"), "auv", pos=(0.0, 0.0, -10.0))

    def fails(self, model, data):
        raise ArithmeticError("a provider failed")

    monkeypatch.setattr(mjtether.vehicle.BoundVehicle, "apply", fails)
    before = mt.dispatch.active_count()
    with pytest.raises(ArithmeticError, match="a provider failed"):
        mt.Simulation(spec, mt.WaterColumn(depth=100.0), bodies=[vm])
    assert mt.dispatch.active_count() == before

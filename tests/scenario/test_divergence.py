"""A simulation that blows up is stopped and reported, never carried on with NaN."""

import numpy as np
import pytest

import mjtether as mt
from conftest import new_spec


def test_too_large_step_is_reported():
    # a light line in a 5 m/s current: lambda = 225 1/s, so a 50 ms step (lambda dt = 11)
    # is far beyond the explicit-drag limit (lambda dt < 2)
    water = mt.WaterColumn(depth=300.0, current=mt.ConstantCurrent(5.0))
    tether = mt.TetherSpec(length=100.0, segments=20, diameter=0.01, density=1030.0, EA=1e5)
    assert mt.stability.drag_rate(tether, water) * 0.05 > 2
    spec = new_spec(0.05)
    tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, 0]), mt.FreeEnd(), water=water)
    with mt.Simulation(spec, water, [tm]) as sim:
        with pytest.raises(mt.SimulationDiverged, match="diverged at t ="):
            sim.run(60.0)
        assert sim.time < 60.0


def test_stable_step_from_the_limit_runs_clean():
    water = mt.WaterColumn(depth=300.0, current=mt.ConstantCurrent(5.0))
    tether = mt.TetherSpec(length=100.0, segments=20, diameter=0.01, density=1030.0, EA=1e5)
    dt = mt.stability.max_timestep(tether, water)
    spec = new_spec(dt)
    tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, 0]), mt.FreeEnd(), water=water)
    with mt.Simulation(spec, water, [tm]) as sim:
        sim.run(30.0)
        assert np.all(np.isfinite(sim.tether().nodes(sim.data)))
        # streamed out behind the fixed point by the current
        assert sim.tether().nodes(sim.data)[-1, 0] > 50.0


def test_divergence_is_reported_when_and_where_it_happened():
    """The same diverging run stepped in one call of 60 s and one step at a time: both report the
    same time (the step it went, not the start of the call) and name the tether node or element
    and the quantity that went first (no reference needed: the two must agree, and the time
    must lie inside the run)."""
    water = mt.WaterColumn(depth=300.0, current=mt.ConstantCurrent(5.0))
    tether = mt.TetherSpec(length=100.0, segments=20, diameter=0.01, density=1030.0, EA=1e5)
    messages = []
    for batched in (True, False):
        spec = new_spec(0.05)
        tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, 0]), mt.FreeEnd(), water=water)
        with mt.Simulation(spec, water, [tm]) as sim:
            with pytest.raises(mt.SimulationDiverged) as err:
                if batched:
                    sim.step(1200)
                else:
                    for _ in range(1200):
                        sim.step()
            messages.append(str(err.value))
    times = [float(m.split("t = ")[1].split(" s")[0]) for m in messages]
    assert times[0] == times[1] and 0.0 < times[0] < 60.0, messages
    assert all(("tether node" in m or "tether element" in m or "MuJoCo" in m) for m in messages), messages
    assert messages[0] == messages[1]

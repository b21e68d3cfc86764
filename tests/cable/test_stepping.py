"""The compiled step loop (``mjtether.cable.stepping``) against the Python loop it replaces.

The reference is ``Simulation._advance``'s Python loop: it calls MuJoCo's ``mj_step`` through
the bindings and the same compiled slack, peak and snap kernels one step at a time. The compiled
block makes the same calls in the same order, so the two must agree bit for bit (tolerance 0):
any difference in the switching, a redo taken or missed, a snap recorded at another step, shows
as a changed bit at once. The cases make that switching happen: a line whose top is jerked
slack and taut (hundreds of snaps and redone steps), and MoorDyn's three-line network.
"""

import math

import mujoco
import numpy as np
import pytest
from conftest import new_spec

import mjtether as mt
from mjtether.io import moordyn
from mjtether.network import run as network_run
from mjtether.cable import stepping
from mjtether.physics import compiled, dispatch
from mjtether.simulation import Simulation, SimulationDiverged

pytestmark = pytest.mark.skipif(compiled.numba is None, reason="numba is not installed")

WATER = mt.WaterColumn(depth=100.0)
MOORDYN = "tests/data/moordyn/tests/Mooring/lines.txt"


def jerked_line(compiled_steps: bool, dt: float = 0.002, memory: int | None = None) -> Simulation:
    """A 10 m line of 10 elements, heavier than water, between a fixed point and a mocap top
    9 m away at the same depth, with its snap detector started."""
    spec = new_spec(dt)
    if memory is not None:
        spec.memory = memory
    spec.worldbody.add_body(name="top", pos=[9.0, 0.0, -10.0], mocap=True)
    tm = mt.add_tether(spec, mt.TetherSpec(length=10.0, segments=10, diameter=0.02, density=1300.0),
                       mt.FixedPoint([0.0, 0.0, -10.0]), mt.BodyPoint("top"), water=WATER)
    sim = Simulation(spec, WATER, tethers=[tm])
    sim.compiled_steps = compiled_steps
    sim.tether().start_snaps()
    return sim


def jerk(sim: Simulation, blocks: int = 600, steps: int = 10, amplitude: float = 0.6) -> dict:
    """Swing the top ``amplitude`` (m) either way at 1.5 s (the line goes slack and snaps taut each swing),
    ``steps`` steps at a time; the state and readouts at the end."""
    top = sim.data.mocap_pos
    for _ in range(blocks):
        top[0, 0] = 9.0 + amplitude * math.sin(2 * math.pi * sim.time / 1.5)
        sim.step(steps)
    bt = sim.tether()
    return {"qpos": sim.data.qpos.copy(), "qvel": sim.data.qvel.copy(), "eq_active": sim.data.eq_active.copy(),
            "peak_push": bt.take_peak_compression(), "events": bt.snaps.events,
            "min_tension": bt.snaps.min_tension_N.copy(), "max_tension": bt.snaps.max_tension_N.copy(),
            "time": sim.time, "redone": sim.redone_steps}


def test_a_jerked_line_gives_the_python_loops_bits():
    """600 blocks of 10 steps (12 s) of a line snapping slack and taut: state, eq_active, peak
    pushes and every snap event as the Python loop gives them, bit for bit; the compiled loop ran
    (``usable``), and the case switches (hundreds of snaps, so the redo and the early return on a
    snap are both exercised)."""
    ref = jerked_line(False)
    fast = jerked_line(True)
    try:
        assert not stepping.usable(ref) and stepping.usable(fast)
        a, b = jerk(ref), jerk(fast)
        assert ref._stepper.calls == 0 and fast._stepper.calls >= 600
    finally:
        ref.close()
        fast.close()
    assert len(a["events"]) > 100 and a["redone"] > 100
    assert a["events"] == b["events"]
    for key in ("qpos", "qvel", "eq_active", "peak_push", "min_tension", "max_tension"):
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    assert a["time"] == b["time"] and a["redone"] == b["redone"]


def test_one_step_at_a_time_and_blocks_agree():
    """The same run stepped one step per call and 25 steps per call (the top moved every 25
    steps in both): the same bits, so a block and its steps are one computation."""
    one, many = jerked_line(True), jerked_line(True)
    try:
        for sim, steps in ((one, 1), (many, 25)):
            top = sim.data.mocap_pos
            for _ in range(200):
                top[0, 0] = 9.0 + 0.6 * math.sin(2 * math.pi * sim.time / 1.5)
                for _ in range(25 // steps):
                    sim.step(steps)
        np.testing.assert_array_equal(one.data.qpos, many.data.qpos)
        assert one.tether().snaps.events == many.tether().snaps.events
    finally:
        one.close()
        many.close()


def test_moordyn_three_lines_give_the_python_loops_bits(monkeypatch):
    """MoorDyn's ``lines.txt`` (three lines, a free body) run by the network runner, whose blocks
    between output samples are single ``Simulation.step`` calls: its whole time series as the
    Python loop gives it."""
    net = moordyn.read(MOORDYN)
    fast = network_run.simulate(net)
    fast.run.sim.close()
    monkeypatch.setattr(Simulation, "compiled_steps", False)
    ref = network_run.simulate(net)
    ref.run.sim.close()
    assert ref.run.sim._stepper.calls == 0 and fast.run.sim._stepper.calls > 10
    assert ref.rows.shape == fast.rows.shape and len(ref.rows) > 10
    np.testing.assert_array_equal(ref.rows, fast.rows)


def test_divergence_is_found_and_named_as_by_the_python_loop():
    """A step five times the one above (0.01 s) and a swing twice as wide: both loops raise SimulationDiverged with
    the same message (the same step found, the same node named), and restore_state's search
    from the block's start finds it in the compiled loop too."""
    messages = []
    for compiled_steps in (False, True):
        sim = jerked_line(compiled_steps, dt=0.01)
        try:
            with pytest.raises(SimulationDiverged) as err:
                jerk(sim, blocks=100, steps=10, amplitude=1.2)
            messages.append(str(err.value))
        finally:
            sim.close()
    assert messages[0] == messages[1]


def test_the_python_loop_steps_where_a_python_callback_is_installed():
    """While a simulation with Python loads is live (a provider registered in Python here), no
    compiled block steps: an exception in a Python callback could not come back through it."""
    sim = jerked_line(True)
    other = mujoco.MjData(sim.model)
    try:
        assert stepping.usable(sim)
        dispatch.register(other, lambda m, d: None)
        assert not dispatch.native_only() and not stepping.usable(sim)
        sim.step(5)  # (the Python loop, with the Python callback dispatching the native block)
    finally:
        dispatch.unregister(other)
        assert stepping.usable(sim)
        sim.close()


def test_the_python_loop_steps_where_the_arena_is_more_than_half_used():
    """A model given just 1.5 times the memory its steps use: the compiled loop is not used
    (a MuJoCo error inside it would end the process); with 3 times, it is."""
    probe = jerked_line(True)
    probe.step(10)
    used = int(probe.data.maxuse_arena) + int(probe.data.maxuse_stack)
    probe.close()
    for factor, expected in ((1.5, False), (3.0, True)):
        sim = jerked_line(True, memory=int(factor * used))
        try:
            sim.step(10)
            assert stepping.usable(sim) is expected, factor
        finally:
            sim.close()


def test_the_struct_offsets_read_mujocos_own_nefc_and_efc_force():
    """The words the compiled loop reads in mjData (``stepping.offsets``) hold what the bindings
    give for ``nefc`` and ``efc_force``, along a run whose constraint rows come and go (below
    the most it had, ``maxuse_efc``, which a wrong offset could read instead)."""
    import ctypes
    efc, nefc = stepping.offsets()
    sim = jerked_line(True)
    seen = set()
    try:
        top = sim.data.mocap_pos
        for _ in range(300):
            top[0, 0] = 9.0 + 0.6 * math.sin(2 * math.pi * sim.time / 1.5)
            sim.step(10)
            d = sim.data
            assert ctypes.c_int32.from_address(d._address + nefc).value == d.nefc
            assert ctypes.c_int64.from_address(d._address + 8 * efc).value == d.efc_force.ctypes.data
            seen.add(d.nefc)
        assert min(seen) < sim.data.maxuse_efc
    finally:
        sim.close()

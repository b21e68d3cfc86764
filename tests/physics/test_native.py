"""The native passive-force callback (``mjtether.physics.native``) and rollouts on MuJoCo's threads.

The reference is the NumPy kernels (``hydro``, ``seabed``, ``BoundVehicle.wrench``'s NumPy
path), which state the physics and are tested against hand-computed loads elsewhere. The
native callback adds the same loads in compiled code: 1e-12 of the largest generalised force,
the rounding of a different order of additions (1e-16 relative) with room for nothing else.

A rollout (``mujoco.rollout`` on worker threads, through ``mjtether.rollouts``) must give the
trajectory ``Simulation.run`` gives for the same start, to 1e-10 of the largest coordinate:
both step the same model with the same forces, so they agree to rounding, and any missing or
extra force (a cable in vacuum) shows at once as centimetres.
"""

import mujoco
import numpy as np
import pytest
from mujoco import rollout

import mjtether as mt
from conftest import new_spec
from mjtether.physics import compiled, native
from mjtether import rollouts
from mjtether.quasistatic import steady_state
from mjtether.scenario.runner import ScenarioRun
from mjtether.scenario import load_scenario

pytestmark = pytest.mark.skipif(compiled.numba is None, reason="numba is not installed")

EXAMPLES = {
    "walker": None,  # the built-in scenario, paying out at 0.5 m/s: seabed friction, current, hydro
    "lazy_wave": "examples/lazy_wave_umbilical.toml",  # a make-up: floats, a clump, point loads
    "rov": "examples/rov_umbilical.toml",  # a vehicle on a tether
    "otter_rov": "examples/otter_rov_launch.toml",  # a surface vessel and an ROV
    "remus_payout": "examples/remus_fibre_payout.toml",  # a vehicle paying out fibre
}


def _reference(sim):
    """``qfrc_passive`` at the simulation's state with every provider's NumPy kernel (the Python
    providers, the native callback switched off); the stick points are left as they were."""
    m, d = sim.model, sim.data
    for t in sim.tethers.values():
        t._fast = None
    for b in sim.bodies:
        b._codes = None
    mujoco.set_mjcb_passive(None)
    try:
        mujoco.mj_forward(m, d)  # MuJoCo's own passive forces
        for p in sim._providers:
            p.apply(m, d)
        return d.qfrc_passive.copy()
    finally:
        mt.dispatch._install()


@pytest.mark.parametrize("name", list(EXAMPLES))
def test_native_loads_match_the_numpy_kernels(name):
    """Each example after 0.5 s (a winch paying out, nodes on the seabed with their stick points,
    vehicles under way): the generalised passive forces of the native callback against the
    NumPy kernels at the same state, to 1e-12 of the largest."""
    import pathlib

    root = pathlib.Path(__file__).resolve().parents[2]
    path = EXAMPLES[name]
    more = ["winch.mode=constant", "winch.rate=0.5"] if name == "walker" else []
    sc = load_scenario(None if path is None else root / path, overrides=["simulation.duration=0.5", *more])
    run = ScenarioRun(sc)
    try:
        assert run.sim.native
        for _ in range(int(round(0.5 / run.sim.timestep))):
            run.step()
        d = run.sim.data
        stick = d.userdata.copy()
        mujoco.mj_forward(run.sim.model, d)
        got = d.qfrc_passive.copy()
        d.userdata[:] = stick
        want = _reference(run.sim)
        scale = np.max(np.abs(want))
        assert np.max(np.abs(got - want)) <= 1e-12 * scale, f"{np.max(np.abs(got - want)) / scale:.3g}"
        if name == "walker":  # (the case really pays out and touches down)
            t = run.sim.tether()
            assert t.payout_rate > 0 and np.isfinite(d.userdata).any()
            # the friction's stick springs follow the model's time step (a settling pre-roll
            # takes a quarter of it): the same at a changed step
            run.sim.model.opt.timestep /= 4
            d.userdata[:] = stick
            mujoco.mj_forward(run.sim.model, d)
            got = d.qfrc_passive.copy()
            d.userdata[:] = stick
            want = _reference(run.sim)
            assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want))
    finally:
        run.close()


def _taut(speed=0.5, segments=40):
    """A 150 m cable between fixed points, 80 m apart and 100 m down, in an exponential current of
    ``speed`` at the surface, started from its steady state in still water (every element taut)."""
    water = mt.WaterColumn(depth=300.0, current=mt.ExponentialCurrent(speed, decay_depth=20.0))
    tether = mt.TetherSpec(length=150.0, segments=segments, diameter=0.03, density=1100.0)
    top, end = [0.0, 0.0, 0.0], [80.0, 0.0, -100.0]
    ss = steady_state(tether, mt.WaterColumn(depth=300.0), top, end, seabed=False)
    spec = new_spec(0.005)
    tm = mt.add_tether(spec, tether, mt.FixedPoint(top), mt.FixedPoint(end), water=water, nodes=ss.nodes)
    return mt.Simulation(spec, water, [tm])


def test_a_rollout_is_the_simulations_run():
    """400 steps (2 s) of the taut cable pushed by a 0.5 m/s current: one rollout, and four on two
    threads, against ``Simulation.step`` from the same state."""
    with _taut(speed=0.5) as sim:
        s0 = rollouts.initial_state(sim)
        sim.step(400)
        assert sim.tether().slack_count(sim.data) == 0  # (a rollout does not switch slack elements)
        want = sim.data.qpos.copy()
        moved = np.max(np.abs(want - s0[1:1 + sim.model.nq]))
        assert moved > 0.3  # the current really moves the cable
        one, _ = rollouts.rollout(sim, s0[None], nstep=400)
        many, _ = rollouts.rollout(sim, np.repeat(s0[None], 4, axis=0), nstep=400, nthread=2)
        for got in (one[0, -1], *many[:, -1]):
            assert np.max(np.abs(got[1:1 + sim.model.nq] - want)) <= 1e-10 * np.max(np.abs(want))


def test_a_rollout_in_vacuum_would_be_far_off():
    """The check above can fail: the same rollout with the callback removed (no drag, weight or
    buoyancy) ends decimetres away."""
    with _taut(speed=0.5) as sim:
        s0 = rollouts.initial_state(sim)
        sim.step(400)
        want = sim.data.qpos.copy()
        mujoco.set_mjcb_passive(None)
        try:
            out, _ = rollout.rollout(sim.model, mujoco.MjData(sim.model), s0[None], nstep=400)
        finally:
            mt.dispatch._install()
        assert np.max(np.abs(out[0, -1, 1:1 + sim.model.nq] - want)) > 0.3


def _rov_run() -> ScenarioRun:
    """The ROV example, seabed friction off (its stick points are state a rollout does not carry)."""
    import pathlib

    root = pathlib.Path(__file__).resolve().parents[2]
    return ScenarioRun(load_scenario(root / "examples/rov_umbilical.toml",
                                     overrides=["simulation.duration=1", "tether.seabed_friction=0"]))


def test_vehicle_rollouts_on_two_threads_match_the_simulation():
    """The ROV example's vehicle (whose callback turns its added-mass tendons in the model): four
    rollouts on two threads, each on its own registered copy of the model, under recorded
    thruster commands, against ``Simulation.step`` under the same commands."""
    run = _rov_run()
    try:
        sim = run.sim
        for _ in range(20):
            run.step()  # under way
        s0, saved = rollouts.initial_state(sim), sim.save_state()
        steps = 100
        ctrl = np.empty((steps, sim.model.nu))
        for i in range(steps):  # the commands of the run's own pilot, then stepped as a rollout would
            run.step()
            ctrl[i] = sim.data.ctrl
        sim.restore_state(saved)
        for t in sim.tethers.values():  # (a fixed deployed length: what a rollout keeps)
            t.drum.payout_rate = 0.0
            t._sync_native()
        registered = len(native._blocks)
        for i in range(steps):
            sim.data.ctrl[:] = ctrl[i]
            sim.step()
        assert all(t.slack_count(sim.data) == 0 for t in sim.tethers.values())
        want = sim.data.qpos.copy()
        out, _ = rollouts.rollout(sim, np.repeat(s0[None], 4, axis=0), ctrl[None], nthread=2)
        for got in out[:, -1]:
            assert np.max(np.abs(got[1:1 + sim.model.nq] - want)) <= 1e-10 * np.max(np.abs(want))
        assert len(native._blocks) == registered  # the copies are unregistered
    finally:
        run.close()


def test_a_shared_vehicle_model_is_refused_not_mixed_up():
    """A vehicle's loads turn its added-mass tendons in the model from the state being stepped:
    a plain ``mujoco.rollout`` of the simulation's own model (another MjData, on one thread or
    two) would give each rollout the others' mass matrix. It is refused: its states come back
    NaN; the simulation steps on unharmed and ``rollouts.rollout`` (a copy per rollout) works."""
    import copy

    run = _rov_run()
    try:
        sim = run.sim
        s0 = rollouts.initial_state(sim)
        for nthread in (1, 2):
            datas = [copy.copy(sim.data) for _ in range(nthread)]
            with rollout.Rollout(nthread=nthread) as r:
                out, _ = r.rollout(sim.model, datas, np.repeat(s0[None], 4, axis=0), nstep=5)
            assert np.isnan(out[:, -1, 1:1 + sim.model.nq]).all()
        run.step()
        assert np.all(np.isfinite(sim.data.qpos))
        out, _ = rollouts.rollout(sim, np.repeat(rollouts.initial_state(sim)[None], 2, axis=0), nstep=5, nthread=2)
        assert np.all(np.isfinite(out))
    finally:
        run.close()


def test_rollouts_refuse_what_they_cannot_carry(monkeypatch):
    """The NumPy kernels (Python, which rollout threads cannot call) and seabed friction (stick
    points in userdata, which a rollout's state leaves out) are refused with the reason; so are
    bad arguments (thread count, a start of the wrong size, NaN or text) and a closed simulation."""
    monkeypatch.setenv(compiled.KERNELS_ENV, "numpy")
    with _taut(segments=10) as sim:
        assert not sim.native
        with pytest.raises(ValueError, match="run in Python"):
            rollouts.rollout(sim, rollouts.initial_state(sim)[None], nstep=2)
    monkeypatch.delenv(compiled.KERNELS_ENV)
    run = ScenarioRun(load_scenario(overrides=["simulation.duration=1"]))
    try:
        with pytest.raises(ValueError, match="seabed friction"):
            rollouts.rollout(run.sim, rollouts.initial_state(run.sim)[None], nstep=2)
        with pytest.raises(ValueError, match="nthread must be an integer from 1 to 256"):
            rollouts.rollout(run.sim, rollouts.initial_state(run.sim)[None], nstep=2, nthread=0)
    finally:
        run.close()
    with _taut(segments=10) as sim:
        s0 = rollouts.initial_state(sim)
        for bad, what in ((s0[None, :5], "got shape \\(1, 5\\)"), (np.full((1, len(s0)), np.nan), "with NaN or inf"),
                          ("abc", "must be numbers")):
            with pytest.raises(ValueError, match=f"initial_state .*{what}"):
                rollouts.rollout(sim, bad, nstep=2)
    with pytest.raises(ValueError, match="the simulation is closed"):
        rollouts.rollout(sim, s0[None], nstep=2)


def test_a_pushing_rollout_element_is_reported():
    """A cable 0.5 % longer than the straight line it starts on (taut, as within 1 %): its elements
    push at once, which a Simulation switches off and a rollout cannot; it warns, naming them."""
    water = mt.WaterColumn(depth=300.0)
    tether = mt.TetherSpec(length=100.5, segments=10, diameter=0.03, density=1100.0)
    spec = new_spec(0.005)
    tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, -10]), mt.FixedPoint([100, 0, -10]), water=water,
                       nodes=np.linspace([0, 0, -10], [100, 0, -10], 11))
    with mt.Simulation(spec, water, [tm]) as sim:
        s0 = rollouts.initial_state(sim)
        assert sim.data.eq_active[sim.tether()._eqs].all()
        with pytest.warns(RuntimeWarning, match=r"element \d+ \(0 at the ship\) was taut, and shorter than its "
                                                r"rest length: it pushed, at step 1 of rollout 0"):
            rollouts.rollout(sim, s0[None], nstep=5)


def test_a_mujoco_whose_structs_cannot_be_read_falls_back_to_python(monkeypatch):
    """Where the callback cannot find MuJoCo's struct fields (a future MuJoCo), a simulation
    warns once and runs its loads in Python (the compiled kernels, called from Python), and
    rollouts are refused."""
    def unreadable():
        raise RuntimeError("mjtether.physics.native: the fields ['qvel'] were not found in MjData")

    monkeypatch.setattr(native, "_state", {})
    monkeypatch.setattr(native, "_offsets", unreadable)
    with pytest.warns(RuntimeWarning, match="the hydrodynamic loads run in Python instead"):
        sim = _taut(segments=10)
    with sim:
        assert not sim.native and sim.tethers["tether"]._fast is not None  # (compiled kernels, from Python)
        sim.step(20)
        assert np.all(np.isfinite(sim.data.qpos))
        with pytest.raises(ValueError, match="run in Python"):
            rollouts.rollout(sim, rollouts.initial_state(sim)[None], nstep=2)


def test_a_model_that_is_not_mjtethers_is_left_alone():
    """With the native callback installed, a plain model steps with MuJoCo's forces only."""
    plain = mujoco.MjModel.from_xml_string("<mujoco><worldbody><body><freejoint/><geom size='0.1'/></body>"
                                           "</worldbody></mujoco>")
    with _taut(segments=10):
        d = mujoco.MjData(plain)
        mujoco.mj_step(plain, d, 10)
        assert np.all(d.qfrc_passive == 0.0)
        assert d.qvel[2] == pytest.approx(-9.81 * 10 * plain.opt.timestep, rel=1e-12)

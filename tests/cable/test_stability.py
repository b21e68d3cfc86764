"""``stability.max_timestep`` is a true bound within 2x of the largest stable step: a run at
exactly its answer stays clean, and a run at twice its answer blows up, on a static catenary,
a line held across a current, a tether to a walking robot and a tether paid out by a winch.

The largest stable steps measured for these and other cases are tabulated in the docstring of
``mjtether.cable.stability``; the tests do not use them. Every run at the answer uses
``max_timestep`` as a user would: the tether and the water, and (for the winch) ``payout``,
never the tension.
"""

import copy
import math

import numpy as np
import pytest
from conftest import new_spec

import mjtether as mt
from mjtether.quasistatic import initial_state, steady_state
from mjtether.scenario.runner import ScenarioRun, tether_from, water_from
from mjtether.scenario import load_scenario

KICK = 0.05
"""Random node velocities (m/s, seeded) added at the start of the fixed-end runs: a start at the
exact steady state has nothing for an instability to grow from in a short run."""


def _span(tether, water, top, bottom, dt, duration):
    """Run ``tether`` between fixed points from its steady state (plus ``KICK``) for
    ``duration`` s at ``dt``; returns (ship-end tensions every 0.5 s, steady top tension)."""
    ss = initial_state(tether, water, top, bottom, timestep=dt, seabed=False)
    spec = new_spec(dt)
    tm = mt.add_tether(spec, tether, mt.FixedPoint(top), mt.FixedPoint(bottom), water=water, nodes=ss.nodes)
    with mt.Simulation(spec, water, [tm]) as sim:
        bt = sim.tether()
        v = KICK * np.random.default_rng(0).standard_normal((bt.N + 1, 3))
        v[[0, -1]] = 0.0
        bt.set_state(sim.data, velocity=v)
        sim.forward()
        tensions = []
        sim.run(duration, callback=lambda s: tensions.append(bt.end_tension(s.data, "start")), every=0.5)
    return np.array(tensions), ss.top_tension


# ------------------------------------------------------------------ static catenary

STATIC_WATER = mt.WaterColumn(depth=300.0)
STATIC_TETHER = mt.TetherSpec(length=100.0, segments=20, diameter=0.03, density=2500.0, EA=5e6)
_A = math.radians(50.0)
STATIC_ENDS = ([0.0, 0.0, 0.0], [80.0 * math.cos(_A), 0.0, -80.0 * math.sin(_A)])


def test_static_catenary_runs_clean_at_the_answer():
    """100 m of 30 mm cable hanging 80 m at 50 deg in still water: the string limit of 5 m
    elements at the estimated tension (its wet weight, 1023 N; 862 N at the top in fact). For a
    minute at the answer the top tension stays within 1 % of the steady state over the second
    half (0.01 % seen: the kick dies out; an unstable zig-zag grows without bound)."""
    dt = mt.stability.max_timestep(STATIC_TETHER, STATIC_WATER)
    assert 0.1 < dt < 0.3
    t, steady = _span(STATIC_TETHER, STATIC_WATER, *STATIC_ENDS, dt, 60.0)
    assert np.abs(t[len(t) // 2:] / steady - 1.0).max() < 0.01


def test_static_catenary_blows_up_at_twice_the_answer():
    dt = 2 * mt.stability.max_timestep(STATIC_TETHER, STATIC_WATER)
    with pytest.raises(mt.SimulationDiverged):
        _span(STATIC_TETHER, STATIC_WATER, *STATIC_ENDS, dt, 60.0)


# ------------------------------------------------------------------ across a current

CURRENT_WATER = mt.WaterColumn(depth=300.0, current=mt.ConstantCurrent(2.0))
CURRENT_TETHER = mt.TetherSpec(length=100.0, segments=20, diameter=0.01, density=1030.0)  # inextensible
CURRENT_ENDS = ([0.0, 0.0, -50.0], [0.0, 80.0, -50.0])  # level, across the current


def test_line_across_a_current_runs_clean_at_the_answer():
    """A light 10 mm line spanning 80 m across a 2 m/s current: the drag limit (lambda = 152
    1/s). For 30 s at the answer the top tension stays within 1 % of the steady state over the
    second half (0.3 % seen)."""
    dt = mt.stability.max_timestep(CURRENT_TETHER, CURRENT_WATER)
    assert dt * mt.stability.drag_rate(CURRENT_TETHER, CURRENT_WATER) == pytest.approx(1.6)
    t, steady = _span(CURRENT_TETHER, CURRENT_WATER, *CURRENT_ENDS, dt, 30.0)
    assert np.abs(t[len(t) // 2:] / steady - 1.0).max() < 0.01


def test_line_across_a_current_blows_up_at_twice_the_answer():
    dt = 2 * mt.stability.max_timestep(CURRENT_TETHER, CURRENT_WATER)
    with pytest.raises(mt.SimulationDiverged):
        _span(CURRENT_TETHER, CURRENT_WATER, *CURRENT_ENDS, dt, 30.0)


# ------------------------------------------------------------------ walking end

WALKER = {
    "simulation": {"duration": 10.0, "timestep": 0.005, "output_interval": 0.5},
    "water": {"depth": 50.0, "current": {"type": "constant", "speed": 1.0, "heading_deg": 90.0}},
    "tether": {"length": 80.0, "segments": 32, "diameter": 0.005, "density": 1500.0, "EA": 1e5},
    "ship": {"mode": "fixed", "position": [0.0, 0.0]},
    "winch": {"mode": "fixed"},
    "robot": {"type": "walker", "start": [50.0, 0.0], "commands": [[0.0, 0.3, 0.0]]},
}
"""The walker sets off at 0.3 m/s from 50 m downrange of the ship, across a 1 m/s current, on
80 m of light 5 mm line held across the flow: the tether's drag limit (lambda = 124 1/s) is
below the walker's own (``stability.WALKER_MAX_TIMESTEP``), so the step is the tether's."""


def _walk(dt, duration=10.0):
    """Run ``WALKER`` at ``dt``; returns (walker's distance along x, mean ship-end tension over
    each half second)."""
    sc = load_scenario(data=copy.deepcopy(WALKER), overrides=[f"simulation.timestep={dt!r}"])
    run = ScenarioRun(sc)
    try:
        x0 = run.robot_state()[0][0]
        times, tensions = [], []
        for _ in range(int(round(duration / dt))):
            run.step()
            times.append(run.sim.time)
            tensions.append(run.bt.end_tension(run.sim.data, "start"))
        half = np.minimum((np.array(times) / 0.5 - 1e-9).astype(int), int(round(duration / 0.5)) - 1)
        means = np.bincount(half, weights=tensions) / np.bincount(half)
        return run.robot_state()[0][0] - x0, means
    finally:
        run.close()


def _walker_timestep():
    sc = load_scenario(data=copy.deepcopy(WALKER))
    return mt.stability.max_timestep(tether_from(sc), water_from(sc), walker=True)


def test_walking_end_runs_clean_at_the_answer():
    """10 s at the answer against a reference at a quarter of it: the walker covers the same
    distance within 5 % (2.7 m of the 3 m commanded: the drive ramps the speed up),
    and the ship-end tension, averaged over each half second while the walker pulls the line
    taut (40 to 170 N), stays within 10 % of the reference's (the gait's jerks differ from step
    to step)."""
    dt = _walker_timestep()
    assert 0.005 < dt < mt.stability.WALKER_MAX_TIMESTEP
    dx, t = _walk(dt)
    ref_dx, ref_t = _walk(dt / 4)
    assert dx == pytest.approx(ref_dx, rel=0.05) and ref_dx > 2.4
    assert np.abs(t / ref_t - 1.0).max() < 0.10


def test_walking_end_blows_up_at_twice_the_answer():
    """The tether goes (a node mid-cable, in the first seconds), not the walker: alone, the
    walker still walks at this step (6 % fast at 0.025 s, see ``mjtether.cable.stability``)."""
    with pytest.raises(mt.SimulationDiverged, match="tether node"):
        _walk(2 * _walker_timestep())


# ------------------------------------------------------------------ payout

PAYOUT_WATER = mt.WaterColumn(depth=200.0, current=mt.ExponentialCurrent(1.0, decay_depth=20.0))
PAYOUT_TETHER = mt.TetherSpec(length=100.0, segments=40, diameter=0.03, density=2000.0, EA=5e6)
PAYOUT_BOTTOM = np.array([60.0, 0.0, -70.0])


def _payout(dt):
    """Pay out from 100 to 130 m at 1 m/s (as test_winch), then hold for the rest of a minute;
    returns the ship-end tension after every step."""
    start = steady_state(PAYOUT_TETHER, PAYOUT_WATER, [0, 0, 0], PAYOUT_BOTTOM)
    spec = new_spec(dt)
    tm = mt.add_tether(spec, PAYOUT_TETHER, mt.FixedPoint([0, 0, 0]), mt.FixedPoint(PAYOUT_BOTTOM),
                       water=PAYOUT_WATER, nodes=start.nodes, max_length=130.0)
    winch = mt.Winch(length=100.0, mode="constant", rate=1.0, max_length=130.0)
    with mt.Simulation(spec, PAYOUT_WATER, [tm]) as sim:
        bt = sim.tether()
        t = [bt.end_tension(sim.data, "start")]
        for _ in range(int(round(60.0 / dt))):
            bt.set_length(winch.advance(dt, sim.time, 0.0), rate=winch.current_rate)
            sim.step()
            t.append(bt.end_tension(sim.data, "start"))
        assert bt.deployed_length == pytest.approx(130.0)
    return np.array(t)


def test_payout_runs_clean_at_the_answer():
    """12 nodes released from the drum at the answer (the drum element's limit: it is 0.2 l0
    long just after a release): the tension never changes by more than 10 % from one step to
    the next (a release rings it: measured 7.4 % at most; 4.4 % at 5 ms, test_winch) and
    ends within 2 % of the steady state of 130 m, the bounds test_winch uses at 5 ms."""
    dt = mt.stability.max_timestep(PAYOUT_TETHER, PAYOUT_WATER, payout="out")
    assert dt < mt.stability.max_timestep(PAYOUT_TETHER, PAYOUT_WATER)
    t = _payout(dt)
    assert np.abs(np.diff(t) / t[:-1]).max() < 0.10
    end = steady_state(mt.TetherSpec(length=130.0, segments=40, diameter=0.03, density=2000.0, EA=5e6),
                       PAYOUT_WATER, [0, 0, 0], PAYOUT_BOTTOM)
    assert t[-1] == pytest.approx(end.top_tension, rel=0.02)


def test_payout_blows_up_at_twice_the_answer():
    with pytest.raises(mt.SimulationDiverged):
        _payout(2 * mt.stability.max_timestep(PAYOUT_TETHER, PAYOUT_WATER, payout="out"))


# ------------------------------------------------------------------ the estimate itself


def _chain_omega(lengths, m, T, EI=0.0):
    """Highest transverse natural frequency (rad/s) of a chain of elements ``lengths`` (m) held
    at both ends, under tension ``T`` (N), with mass ``m`` per metre lumped half to each node of
    an element and bending stiffness ``EI`` (N m^2) on the nodes' discrete curvature: the
    generalized eigenproblem K v = omega^2 M v, built and solved here with NumPy/SciPy."""
    from scipy.linalg import eigh

    lengths = np.asarray(lengths, float)
    n = len(lengths) - 1  # interior nodes
    mass = m * (lengths[:-1] + lengths[1:]) / 2
    D1 = np.zeros((len(lengths), n))  # element slope from the nodes' lateral displacements
    for e in range(len(lengths)):
        if e < n:
            D1[e, e] += 1.0 / lengths[e]
        if e > 0:
            D1[e, e - 1] -= 1.0 / lengths[e]
    K = T * D1.T @ np.diag(lengths) @ D1  # the string: T/l per element
    if EI:
        D2 = np.diff(D1, axis=0) / ((lengths[:-1, None] + lengths[1:, None]) / 2)  # curvature at each node
        K += EI * D2.T @ np.diag((lengths[:-1] + lengths[1:]) / 2) @ D2
    return math.sqrt(eigh(K, np.diag(mass), eigvals_only=True)[-1])


def _euler_drag_diverges(dt, lam_u, speed, steps=200):
    """Forward Euler (as MuJoCo applies the passive drag) on a node held at rest across a
    current U by a constant force (the tension) that balances its drag: per metre,
    m dv/dt = 1/2 rho C d (|U - v| (U - v) - U^2), written with lam_u = rho C d / m, from a
    disturbance v = 1 % of U. True if the disturbance grows."""
    v = 0.01 * speed
    for _ in range(steps):
        v += dt * 0.5 * lam_u * (abs(speed - v) * (speed - v) - speed * speed)
    return not abs(v) < 0.01 * speed


def test_answer_is_a_true_bound_within_2x_of_the_linear_chains_limit():
    """What the formula is for, checked without it: a semi-implicit (symplectic) Euler step,
    MuJoCo's for the explicit string and bending forces, is stable for omega dt < 2 on the
    highest mode of the chain, and forward Euler on a node held across a current for lambda dt
    < 2. The answer must lie at or below those limits (a true bound) and above half of them
    (within 2x): 0.5 < answer / limit <= 1, the module's claim (``SAFETY`` = 0.8 puts it at
    0.8, the zig-zag's frequency for 40 elements being within 0.1 % of its N -> inf value).
    The limits are computed here from the inputs alone: omega from the eigenproblem of the
    lumped chain (string, with bending, and with a drum element 0.2 l0 long next to the
    fairlead, as just after a release), the drag rate by running forward Euler on the
    quadratic drag and bisecting for the step at which a 1 % disturbance grows. Measured:
    answer / limit = 0.799 (string with bending), 0.799 (bending-dominated, EI = 2000 N m^2),
    0.855 (drum element; the code lumps its mass a little differently) and 0.800 (drag)."""
    st = mt.stability
    rho = 1025.0
    tether = mt.TetherSpec(length=100.0, segments=40, diameter=0.03, density=2500.0, EA=5e6, EI=100.0)
    still = mt.WaterColumn(depth=300.0)
    m = tether.mu + tether.ca_normal * rho * tether.area  # transverse mass per metre (with added mass)
    l0 = tether.segment_length
    T = 1000.0
    ratios = {}
    limit = 2.0 / _chain_omega([l0] * 40, m, T, tether.EI)
    ratios["string + bending"] = st.max_timestep(tether, still, tension=T) / limit
    stiff = mt.TetherSpec(length=100.0, segments=40, diameter=0.03, density=2500.0, EA=5e6, EI=2000.0)
    limit = 2.0 / _chain_omega([l0] * 40, m, T, stiff.EI)
    ratios["bending-dominated"] = st.max_timestep(stiff, still, tension=T) / limit
    lengths = [0.2 * l0] + [l0] * 39  # the drum element after a release (SPLIT = 1.2)
    limit = 2.0 / _chain_omega(lengths, m, T, tether.EI)
    ratios["drum element, paying out"] = st.max_timestep(tether, still, tension=T, payout="out") / limit
    # drag: a light line in a 3 m/s current (no tension, no bending: drag is the only limit)
    fast = mt.WaterColumn(depth=300.0, current=mt.ConstantCurrent(3.0))
    flexible = mt.TetherSpec(length=100.0, segments=20, diameter=0.03, density=2500.0)
    lam_u = rho * flexible.cd_normal * flexible.diameter / m
    lo, hi = 1e-4, 1.0  # bisect the forward-Euler step at which a disturbance grows
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if _euler_drag_diverges(mid, lam_u, 3.0) else (mid, hi)
    ratios["drag across 3 m/s"] = st.max_timestep(flexible, fast, tension=0.0) / lo
    bad = {k: round(r, 4) for k, r in ratios.items() if not 0.5 < r <= 1.0}
    assert not bad, f"answer / limit outside (0.5, 1]: {bad} (all: {ratios})"
    # nothing limits a weightless line in still water; a bad payout is refused by name
    neutral = mt.TetherSpec(length=100.0, diameter=0.03, density=1025.0)
    assert st.max_timestep(neutral, still) == math.inf
    with pytest.raises(ValueError, match="payout"):
        st.max_timestep(tether, still, payout="sideways")

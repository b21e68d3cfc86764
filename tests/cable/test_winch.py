"""The winch: its control logic, and paying out a dynamic tether without tension spikes."""

import numpy as np
import pytest
from conftest import new_spec

import mjtether as mt
from mjtether.quasistatic import steady_state


def run_winch(w, seconds, dt=0.01, tension=0.0, speed=0.0):
    for k in range(int(round(seconds / dt))):
        w.advance(dt, k * dt, tension, speed)
    return w.length


def test_winch_modes():
    w = mt.Winch(length=100.0, mode="constant", rate=0.5, max_length=200.0)
    # accelerates at max_accel (0.2 m/s^2) to 0.5 m/s: 0.625 m in the 2.5 s ramp, then 0.5 m/s
    assert run_winch(w, 12.5) == pytest.approx(100.0 + 0.625 + 0.5 * 10.0, abs=0.01)  # dt = 0.01 s steps
    w = mt.Winch(length=100.0, mode="follow", max_length=200.0, max_accel=100.0)
    assert run_winch(w, 10.0, speed=0.3) == pytest.approx(103.0, abs=0.01)
    w = mt.Winch(length=100.0, mode="fixed")
    assert run_winch(w, 10.0, tension=1e6) == 100.0
    # tension band: pays out above, reels in below, proportionally to the tension's distance
    # from the band's centre (before any integral action)
    w = mt.Winch(length=100.0, mode="tension", band=(100.0, 200.0), max_rate=1.0, max_length=200.0, min_length=50.0)
    assert w.payout_rate(0, 250.0, 0) == 1.0 and w.payout_rate(0, 50.0, 0) == -1.0
    assert w.payout_rate(0, 150.0, 0) == 0.0
    assert w.payout_rate(0, 195.0, 0) == pytest.approx(0.9)
    w = mt.Winch(length=100.0, mode="external", max_rate=1.0)
    w.command(5.0)
    assert w.payout_rate(0, 0, 0) == 1.0
    w = mt.Winch(length=100.0, mode="free", drum_damping=100.0)
    assert w.payout_rate(0, 50.0, 0) == pytest.approx(0.5) and w.payout_rate(0, -5.0, 0) == 0.0


def test_winch_stops_smoothly_at_its_limits():
    """Braking for max_length: the length ends exactly at the limit, the rate at zero."""
    w = mt.Winch(length=100.0, mode="constant", rate=1.0, max_length=110.0)
    rates = []
    for k in range(3000):
        w.advance(0.01, k * 0.01, 0.0)
        rates.append(w.current_rate)
    assert w.length == pytest.approx(110.0, abs=1e-9) and rates[-1] == 0.0
    assert np.abs(np.diff(rates)).max() <= 0.2 * 0.01 + 1e-12  # never more than max_accel


def test_winch_bad_input():
    with pytest.raises(ValueError, match="winch.mode"):
        mt.Winch(length=10.0, mode="spin")
    with pytest.raises(ValueError, match="winch.length must be in"):
        mt.Winch(length=10.0, min_length=20.0, max_length=30.0)
    with pytest.raises(ValueError, match="winch.band"):
        mt.Winch(length=10.0, mode="tension", band=(5.0, 1.0))
    with pytest.raises(ValueError, match="winch.rate"):
        mt.Winch(length=10.0, rate=5.0, max_rate=1.0)


def test_payout_has_no_tension_spikes_and_ends_at_the_steady_state():
    """Paying out 30 m at 1 m/s (the drum accelerating at 0.2 m/s^2) between fixed ends in a
    current, the cable leaving the drum at the ship. Sampled every 0.05 s, the ship-end tension
    never changes by more than 10 % from one sample to the next. Two effects set that bound, both
    measured: each node released from the drum rings the tension by up to +-4.4 %, and when the
    drum stops accelerating (t = 5 s) the tension steps up by 35 N (8 %), which is the cable's
    axial inertia: (mass + added mass) x acceleration = (141 + 72) kg x 0.2 m/s^2 = 43 N. (The
    tension falls by a third while the cable sinks through the water, which is drag.) After 30 s
    at the new length it is within 2 % of the steady state of 130 m. Every element in the water
    but the drum element keeps the nominal 2.5 m, and the deployed cable's mass is mass per length
    x deployed length (to 1e-12: it is bookkeeping) at every sample."""
    dt = 0.005
    water = mt.WaterColumn(depth=200.0, current=mt.ExponentialCurrent(1.0, decay_depth=20.0))
    bottom = np.array([60.0, 0.0, -70.0])
    tether = mt.TetherSpec(length=100.0, segments=40, diameter=0.03, density=2000.0, EA=5e6)
    start = steady_state(tether, water, [0, 0, 0], bottom)
    spec = new_spec(dt)
    tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, 0]), mt.FixedPoint(bottom), water=water,
                       nodes=start.nodes, max_length=130.0)
    winch = mt.Winch(length=100.0, mode="constant", rate=1.0, max_length=130.0)
    samples = []
    with mt.Simulation(spec, water, [tm]) as sim:
        bt = sim.tether()
        samples.append(bt.end_tension(sim.data, "start"))
        for k in range(int(round(60.0 / dt))):
            bt.set_length(winch.advance(dt, sim.time, 0.0), rate=winch.current_rate)
            sim.step()
            if (k + 1) % 10 == 0:
                samples.append(bt.end_tension(sim.data, "start"))
                mass = sim.model.body_mass[bt._bids[bt.first:]].sum()
                assert mass == pytest.approx(tether.mu * bt.deployed_length, rel=1e-12)
                rest = bt.rest_lengths[bt.first:]
                assert np.all(rest[1:] == 2.5) and 0.1 * 2.5 <= rest[0] <= 1.2 * 2.5
        assert bt.deployed_length == pytest.approx(130.0)
        assert bt.N == 52  # 40 elements, and 12 of 2.5 m released from the drum
    t = np.array(samples)
    assert np.abs(np.diff(t) / t[:-1]).max() < 0.10
    end = steady_state(mt.TetherSpec(length=130.0, segments=40, diameter=0.03, density=2000.0, EA=5e6),
                       water, [0, 0, 0], bottom)
    assert t[-1] == pytest.approx(end.top_tension, rel=0.02)


def test_saved_state_restores_payout_exactly():
    """Paying out 2 m/s through several node releases: a state saved before them, restored, and
    stepped again with the same lengths gives bitwise the same nodes, element tensions and
    payout layout (MuJoCo's state and the drum's together; no reference: it must repeat)."""
    dt = 0.005
    water = mt.WaterColumn(depth=100.0)
    tether = mt.TetherSpec(length=20.0, segments=10, diameter=0.02, density=2000.0, EA=1e6)
    spec = new_spec(dt)
    nodes = np.outer(np.linspace(0.0, 20.0, 11), [0.0, 0.0, -1.0])
    tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, 0]), mt.FreeEnd(), water=water, nodes=nodes,
                       max_length=40.0)

    def advance(sim, L, steps):
        out = []
        for _ in range(steps):
            L += 2.0 * dt
            sim.tether().set_length(L, rate=2.0)
            sim.step()
            out.append((sim.tether().all_nodes(sim.data).copy(), sim.tether().element_tension(sim.data).copy(),
                        sim.tether().payout_state()))
        return out

    with mt.Simulation(spec, water, [tm]) as sim:
        advance(sim, 20.0, 100)
        saved, L = sim.save_state(), sim.tether().deployed_length
        first = advance(sim, L, 600)
        assert first[-1][2][0] < first[0][2][0]  # nodes were released from the drum on the way
        sim.restore_state(saved)
        again = advance(sim, L, 600)
    for (x1, t1, p1), (x2, t2, p2) in zip(first, again):
        assert np.array_equal(x1, x2) and np.array_equal(t1, t2) and p1 == p2

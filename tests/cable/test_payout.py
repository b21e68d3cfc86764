"""Paying a cable out vertically from a drum in still water: the top tension against the
closed-form balance of weight and tangential drag, the element count and the deployed mass."""

import math

import numpy as np
import pytest
from conftest import new_spec
from helpers import raw_element_forces

import mjtether as mt

RHO, G = 1025.0, 9.81  # WaterColumn's default density and gravity
V = 0.5  # payout speed (m/s)
L0, L1 = 10.0, 100.0  # deployed length at the start and at the end (m): a 10x growth
TOP = np.array([0.0, 0.0, -0.5])  # fairlead just under the surface: the whole cable is wet


def test_vertical_payout_tension_is_weight_less_tangential_drag():
    """A cable (d = 20 mm, 1300 kg/m^3, C_dt = 0.03) hangs from a fixed fairlead with a free
    lower end in 500 m of still water and is paid out at V = 0.5 m/s from 10 m (5 elements of
    2 m) to 100 m. Every deployed node but the held fairlead node starts sinking at V, so the
    whole cable moves steadily down along its own axis from the start.

    Expected top tension (derived here, not by the code): every metre of a cable sinking
    steadily at V along its axis carries its wet weight w = (mu - rho A) g down and the
    tangential Morison drag f_t = 1/2 rho C_dt pi d V^2 *up* (drag opposes the motion, which is
    down), and nothing accelerates, so the tension at the top is T = (w - f_t) L for L deployed.
    Here w = 0.848 N/m and f_t = 0.242 N/m (29 % of w), so the drag term is far above the
    tolerance.

    Checked at every step after the first second (so node releases are seen too):
    * |T_top / ((w - f_t) L) - 1| <= 2 %: the requirement (the lumped model resolves the weight
      exactly; 2 % leaves room for the discretisation of the drag near the fairlead);
    and every 0.5 s:
    * the element count follows the length: every deployed element but the drum element is l0
      long and the drum element's rest length stays in [0.1, 1.2] l0 (``set_length``: a node is
      released from the drum above 1.2 l0, taken back below 0.1 l0), so the count N satisfies
      0.1 l0 <= L - (N - 1) l0 <= 1.2 l0, i.e. L/l0 - 0.2 <= N <= L/l0 + 0.9 -- within one
      element of L / l0;
    * every deployed element pulls, read from MuJoCo's own constraint force on its equality row
      (``efc_force`` < 0, not the readouts, which clip at zero), and that pull lies between the
      closed-form tensions (w - f_t) (L - s) of the continuous cable at the element's two ends
      (s the unstretched arc length from the fairlead: a segment of a hanging cable carries
      more than the cable below its lower end and less than the cable below its upper end),
      give or take 2 % of (w - f_t) L, the budget of the top check (measured: every pull inside
      its bracket, the nearest 0.03 % of (w - f_t) L from an edge);
    * the deployed mass (sum of the deployed node bodies' masses) is mu L to 1e-9 relative: it is
      bookkeeping, exact up to rounding.
    """
    dt = 0.02
    water = mt.WaterColumn(depth=500.0)
    tether = mt.TetherSpec(length=L0, segments=5, diameter=0.02, density=1300.0, cd_tangential=0.03)
    w = tether.wet_weight_per_length(RHO, G)
    f_t = 0.5 * RHO * tether.cd_tangential * math.pi * tether.diameter * V * V
    assert f_t > 0.25 * w  # the drag is a sizeable part of the answer
    spec = new_spec(dt)
    tm = mt.add_tether(spec, tether, mt.FixedPoint(TOP), mt.FreeEnd(), water=water, max_length=L1)
    worst = (0.0, None)
    with mt.Simulation(spec, water, [tm]) as sim:
        bt = sim.tether()
        l0 = bt.l0
        velocity = np.zeros((bt.N + 1, 3))
        velocity[1:, 2] = -V  # the fairlead node is held; the rest sinks with the payout
        bt.set_state(sim.data, velocity=velocity)
        sim.forward()
        every = int(round(0.5 / dt))
        for k in range(int(round((L1 - L0) / V / dt))):
            bt.set_length(min(L0 + V * (k + 1) * dt, L1), rate=V)
            sim.step()
            L = bt.deployed_length
            if sim.time > 1.0 + 1e-9:  # the tension at every step, node releases included
                err = bt.end_tension(sim.data, "start") / ((w - f_t) * L) - 1.0
                if abs(err) > abs(worst[0]):
                    worst = (err, L)
            if (k + 1) % every:
                continue
            pull = -raw_element_forces(bt, sim.data)[bt.first:]  # MuJoCo's, unclipped
            assert np.all(pull > 0.0), f"element not pulling at L = {L:.2f} m: {pull.min():.4g} N"
            below = np.cumsum(bt.rest_lengths[::-1])[::-1][bt.first:]  # cable below each element's top
            lo, hi = (w - f_t) * (below - bt.rest_lengths[bt.first:]), (w - f_t) * below
            out = float(np.maximum(lo - pull, pull - hi).max()) / ((w - f_t) * L)
            assert out <= 0.02, f"an element's pull is {100 * out:.2f} % of (w - f_t) L outside its bracket at L = {L:.2f} m"
            assert bt.slack_count(sim.data) == 0, f"slack element at L = {L:.2f} m"
            N = bt.N
            assert 0.1 * l0 - 1e-9 <= L - (N - 1) * l0 <= 1.2 * l0 + 1e-9, (L, N)
            assert abs(N - L / l0) < 1.0
            mass = sim.model.body_mass[bt._bids[bt.first:]].sum()
            assert mass == pytest.approx(tether.mu * L, rel=1e-9)
        assert bt.deployed_length == pytest.approx(L1)
    assert abs(worst[0]) <= 0.02, (f"top tension off (w - f_t) L by {100 * worst[0]:+.2f} % at L = {worst[1]:.2f} m "
                                   f"(w = {w:.4f} N/m, f_t = {f_t:.4f} N/m)")



@pytest.mark.parametrize("added_mass, stiffness", [("isotropic", None), ("normal", 5e4)])
def test_a_tether_from_kept_parts_is_the_model_built_afresh(added_mass, stiffness):
    """``add_tether`` keeps its cable's parts (bodies, joints, flex, tendons, equalities) per
    layout and copies them for the next tether of that layout, as an environment's resets do
    (another length, so other masses, element lengths and node positions, and another end).
    Built after the parts served another tether, the model must be byte for byte the model
    built with nothing kept (MuJoCo's own serialisation, ``mj_saveModel``: positions, masses,
    names, everything): a kept part that carried a value over would show here."""
    import mujoco

    from mjtether.cable import builder
    from mjtether.physics import dispatch

    water = mt.WaterColumn(depth=100.0)

    def build(length, end):
        spec = new_spec(0.01)
        builder.add_seabed(spec, water, friction=0.5)
        tether = mt.TetherSpec(length=length, segments=12, diameter=0.03, density=1500.0)
        builder.add_tether(spec, tether, mt.FixedPoint((0.0, 0.0, -1.0)), mt.FixedPoint(end), water=water,
                           seabed_friction=0.3, seabed_stiffness=stiffness, max_length=2.5 * length,
                           added_mass=added_mass)
        model = dispatch.compile_spec(spec)
        buf = np.zeros(mujoco.mj_sizeModel(model), np.uint8)
        mujoco.mj_saveModel(model, None, buf)
        return buf.tobytes()

    builder.cable_parts.cache_clear()
    fresh = build(120.0, (60.0, 10.0, -100.0))
    builder.cable_parts.cache_clear()
    build(121.0, (40.0, -20.0, -100.0))  # the parts are made for this one ...
    assert builder.cable_parts.cache_info().currsize == 1
    assert build(120.0, (60.0, 10.0, -100.0)) == fresh  # ... and serve this (12 of 31 elements deployed)
    assert builder.cable_parts.cache_info().currsize == 1

"""The tether resting on the seabed: against the analytic catenary with seabed contact, and on a
sloped seabed."""

import math

import numpy as np
import pytest
from conftest import new_spec

import mjtether as mt
from mjtether.cable.builder import add_seabed, seabed_height
from mjtether.quasistatic import catenary


@pytest.mark.parametrize("friction", [0.0, 0.5])
def test_tether_lies_on_the_seabed_like_the_catenary(friction):
    """A 50 m chain (130 N/m submerged) from a fairlead at the surface to an anchor on a 20 m
    deep seabed, dropped from the catenary shape of a line 40 % lighter (so it starts slack and
    falls into place). Settled (40 s, mean of 5 s): the fairlead force is within 1 % of the
    elastic catenary with seabed contact, and as many nodes lie on the seabed as the catenary's
    laid length says (to one node). Friction cannot change this state (the laid part carries no
    tension gradient after falling slack), so cb = 0 is the answer for both. The cable's axis
    lies one radius above the seabed plane; the anchor is placed there."""
    dt = 0.005
    water = mt.WaterColumn(depth=20.0)
    d = 0.05
    tether = mt.TetherSpec(length=50.0, segments=50, diameter=d, density=7800.0, EA=1e7)
    w = tether.wet_weight_per_length(1025.0)
    anchor, fairlead = np.array([0.0, 0.0, -20.0 + d / 2]), np.array([40.0, 0.0, 0.0])
    answer = catenary(anchor, fairlead, 50.0, w, EA=1e7, cb=0.0)
    start = catenary(anchor, fairlead, 50.0, 0.6 * w).points(np.linspace(0, 50, 51))[::-1]
    spec = new_spec(dt)
    add_seabed(spec, water, friction=0.9)
    tm = mt.add_tether(spec, tether, mt.FixedPoint(fairlead), mt.FixedPoint(anchor), water=water, nodes=start,
                       seabed_friction=friction)
    with mt.Simulation(spec, water, [tm]) as sim:
        bt = sim.tether()
        sim.run(40.0)
        f = []
        for _ in range(100):
            sim.step(10)
            f.append(bt.end_force(sim.data, "start"))
        x = bt.nodes(sim.data)
    f = np.mean(f, axis=0)
    assert np.linalg.norm(f - answer.fairlead_force) <= 0.01 * np.linalg.norm(answer.fairlead_force)
    on_bottom = np.sum(x[:, 2] < anchor[2] + 0.01) - 1  # elements fully on the seabed
    assert abs(on_bottom - answer.laid_length) <= 1.0
    assert x[:, 2].min() > -20.0  # never through the seabed


def test_tether_on_a_frictionless_slope_hangs_from_its_upper_end():
    """A 20 m steel line laid straight down a frictionless 10 deg slope that rises towards
    heading 30 deg, held at its upper end, free at the lower. The slope carries the weight's
    normal component, so the holding force along the slope is exactly w L sin(alpha), pointing
    down the slope (w: wet weight per metre). After 10 s (mean of 2 s) it is within 1 %; the
    cable rests one radius above the slope (to 2 mm), and the slope's height is seabed_height."""
    alpha, heading = math.radians(10.0), math.radians(30.0)
    water = mt.WaterColumn(depth=50.0)
    d = 0.04
    tether = mt.TetherSpec(length=20.0, segments=40, diameter=d, density=7800.0, EA=1e8)
    up = np.array([math.cos(heading), math.sin(heading), 0.0])
    down_slope = -np.array([math.cos(alpha) * up[0], math.cos(alpha) * up[1], math.sin(alpha)])
    normal = np.array([-math.sin(alpha) * up[0], -math.sin(alpha) * up[1], math.cos(alpha)])
    top = np.array([*(5.0 * up[:2]), 0.0])
    top[2] = seabed_height(water, top[0], top[1], alpha, heading)
    top = top + d / 2 * normal  # the cable's axis
    nodes = top + np.linspace(0.0, 20.0, 41)[:, None] * down_slope
    spec = new_spec(0.005)
    add_seabed(spec, water, friction=0.0, slope=alpha, slope_heading=heading)
    tm = mt.add_tether(spec, tether, mt.FixedPoint(top), mt.FreeEnd(), water=water, nodes=nodes,
                       seabed_friction=0.0)
    with mt.Simulation(spec, water, [tm]) as sim:
        bt = sim.tether()
        sim.run(10.0)
        f = []
        for _ in range(40):
            sim.step(10)
            f.append(bt.end_force(sim.data, "start"))
        x = bt.nodes(sim.data)
    along = float(np.mean(f, axis=0) @ down_slope)
    expected = tether.wet_weight_per_length(1025.0) * 20.0 * math.sin(alpha)
    assert along == pytest.approx(expected, rel=0.01)
    clearance = x[:, 2] - seabed_height(water, x[:, 0], x[:, 1], alpha, heading)
    assert np.abs(clearance * math.cos(alpha) - d / 2).max() < 0.002


def test_moordyns_seabed_is_refused_too_stiff_for_the_step_and_never_throws_the_cable_back():
    """MoorDyn's usual seabed (kBot 3e6 Pa/m, cBot 3e5 Pa s/m) under a light line (30 mm, 3000
    kg/m^3): per kg of cable (2.84 kg/m with its added mass) k = 3.17e4 1/s^2 and b = 3.17e3
    1/s, about nine times the critical damping 2 sqrt(k): a landing node does not bounce. At 5
    ms the builder refuses it, naming the step at which k dt^2 = 0.1 (rounded down: 1.77 ms).
    At that step, the line, held at one end 1 m above the seabed and let fall flat onto it (no
    drag: it lands at up to 3.1 m/s), is never thrown back faster than k dt^2 = 0.099 of its
    fastest landing (measured 0.097 of it). The bound: MuJoCo takes the contact's reference
    acceleration -b v - k x at the start of a step, and with b capped at 1/dt a node's speed
    after its first step in the contact is -k dt x0, x0 its depth when the contact found it,
    less than its landing speed V times dt; after that the damping takes each step's speed
    away again. Before the cap b dt could be 8, and a node landing at 1 m/s left at 36 m/s."""
    depth, d, length = 30.0, 0.03, 20.0
    water = mt.WaterColumn(depth=depth)
    tether = mt.TetherSpec(length=length, segments=20, diameter=d, density=3000.0, EA=1e8, cd_normal=0.0,
                           cd_tangential=0.0)
    top = np.array([0.0, 0.0, -depth + d / 2 + 1.0])
    nodes = top + np.outer(np.linspace(0.0, length, 21), [1.0, 0.0, 0.0])

    def build(dt):
        spec = new_spec(dt)
        add_seabed(spec, water, friction=0.5)
        tm = mt.add_tether(spec, tether, mt.FixedPoint(top), mt.FreeEnd(), water=water, nodes=nodes,
                           seabed_friction=0.0, seabed_stiffness=3e6, seabed_damping=3e5)
        return spec, tm

    with pytest.raises(ValueError, match=r"water.seabed_stiffness = 3e\+06 Pa/m .* needs a time step of at most "
                                         r"0.00177 s, not 0.005 s") as info:
        build(0.005)
    dt_max = float(str(info.value).split("at most ")[1].split(" s")[0])
    spec, tm = build(dt_max)
    landing = np.zeros(21)
    leaving = np.zeros(21)
    with mt.Simulation(spec, water, [tm]) as sim:
        bt = sim.tether()
        x0 = bt.nodes(sim.data)
        for _ in range(int(round(6.0 / dt_max))):
            before = bt.nodes(sim.data)
            sim.step()
            x = bt.nodes(sim.data)
            vz = (x[:, 2] - before[:, 2]) / dt_max
            down = x[:, 2] < -depth + d / 2 + 0.01  # (on the seabed, within a cm)
            landing = np.where(down & (landing == 0.0), -vz, landing)
            leaving = np.where(down, np.maximum(leaving, vz), leaving)
    assert landing.max() > 1.0 and np.all(x[1:, 2] < x0[1:, 2] - 0.9)  # (it fell and lies there)
    k = 3e6 * d / (3000.0 * math.pi * d * d / 4 + 1025.0 * math.pi * d * d / 4)  # 1/s^2 per kg, Ca 1
    assert leaving.max() <= k * dt_max ** 2 * landing.max(), (leaving.max(), landing.max())

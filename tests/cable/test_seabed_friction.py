"""Seabed friction of laid cable (``mjtether.cable.seabed``): Coulomb friction with a stick point.

The kernel against Coulomb's law by hand, then the dynamic tether: a laid cable pulled along the
seabed below its friction limit does not creep, and dragged at a steady speed it pulls back with
mu times its submerged weight (plus its tangential drag). MoorPy's laid line with friction is in
``test_moorpy_case``.
"""

import math

import numpy as np
import pytest
from conftest import new_spec

import mjtether as mt
from mjtether.cable.builder import add_seabed
from mjtether.cable.seabed import seabed_friction

UP = np.array([0.0, 0.0, 1.0])


def _kernel(x, stick, v=None, mu=0.5, N=100.0, k=1e4, c=0.0):
    n = len(x)
    return seabed_friction(np.asarray(x, float), np.zeros((n, 3)) if v is None else np.asarray(v, float),
                           np.asarray(stick, float), point=np.zeros(3), normal=UP, radius=0.01,
                           normal_force=np.full(n, N), mu=mu, stiffness=np.full(n, k), damping=np.full(n, c))


def test_kernel_sticks_below_the_limit_and_slides_at_it():
    """By hand, mu N = 50 N, k = 1e4 N/m. A node 3 mm from its stick point is pulled back with
    30 N and the stick point stays; one 8 mm away would need 80 N: it gets 50 N, towards the stick
    point, which is dragged to 5 mm behind it. A node off the seabed (2 cm up) gets nothing and
    loses its stick point; a node that lands (NaN stick point) sticks where it is, with no force."""
    x = [[0.003, 0.0, 0.01], [0.0, 0.008, 0.01], [0.0, 0.0, 0.03], [1.0, 2.0, 0.01]]
    stick = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [np.nan] * 3]
    f, s = _kernel(x, stick)
    np.testing.assert_allclose(f[0], [-30.0, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(s[0], [0.0, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(f[1], [0.0, -50.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(s[1], [0.0, 0.003, 0.0], atol=1e-12)
    assert np.all(f[2] == 0.0) and np.all(np.isnan(s[2]))
    np.testing.assert_allclose(f[3], 0.0, atol=1e-12)
    np.testing.assert_allclose(s[3], [1.0, 2.0, 0.0], atol=1e-12)


def test_kernel_damping_never_exceeds_coulomb():
    """A node sliding at 1 m/s with a damper of 1e3 N s/m: the damper alone would give 1000 N;
    the friction is capped at mu N = 50 N, against the motion."""
    f, _ = _kernel([[0.0, 0.0, 0.01]], [[0.0, 0.0, 0.0]], v=[[1.0, 0.0, 0.0]], c=1e3)
    np.testing.assert_allclose(f[0], [-50.0, 0.0, 0.0], atol=1e-9)


D, RHO_C, L, N_EL, DEPTH = 0.05, 4000.0, 40.0, 20, 50.0


def _laid_line(dt: float, cb: float):
    """A 40 m line of 5 cm, 4000 kg/m^3 cable laid straight along +x on a 50 m deep seabed, its
    start on a mocap body (the puller), its end free; returns (spec, tether spec, water)."""
    water = mt.WaterColumn(depth=DEPTH)
    tether = mt.TetherSpec(length=L, segments=N_EL, diameter=D, density=RHO_C, EA=1e7)
    spec = new_spec(dt)
    add_seabed(spec, water, friction=0.9)
    z = -DEPTH + D / 2
    puller = spec.worldbody.add_body(name="puller", mocap=True, pos=[L, 0.0, z])
    puller.add_site(name="puller/eye")
    nodes = np.c_[np.linspace(L, 0.0, N_EL + 1), np.zeros(N_EL + 1), np.full(N_EL + 1, z)]
    tm = mt.add_tether(spec, tether, mt.SitePoint("puller/eye"), mt.FreeEnd(), water=water, nodes=nodes,
                       seabed_friction=cb)
    return spec, tm, tether, water


def test_a_laid_line_pulled_below_its_friction_limit_does_not_creep():
    """The puller holds the line's end 5 cm further along +x than where it lay (taking up the
    slack of the laid line, 0.01 % strain): the line's tension then needs friction near the
    puller, and the total it can give, mu w L = 0.5 x 54.5 N/m x 40 m = 1090 N, is far above
    the pull. Over 20 s the far end moves by less than 1 mm (measured: 2e-10 m; on a frictionless
    seabed it slides 16 m)."""
    spec, tm, tether, water = _laid_line(0.005, 0.5)
    with mt.Simulation(spec, water, [tm]) as sim:
        bt = sim.tether()
        m, d = sim.model, sim.data
        d.mocap_pos[m.body("puller").mocapid[0], 0] += 0.05
        sim.run(1.0)
        far0 = bt.nodes(d)[-1].copy()
        pull0 = bt.end_tension(d, "start")
        sim.run(20.0)
        moved = float(np.linalg.norm(bt.nodes(d)[-1] - far0))
        pull = bt.end_tension(d, "start")
    w = tether.wet_weight_per_length(water.rho([0.0])[0], water.gravity)
    assert pull0 > 10.0 and pull < 0.5 * 0.5 * w * L  # a real pull, well below the limit
    assert moved < 1e-3, moved


def test_a_laid_line_dragged_along_pulls_back_with_mu_times_its_weight():
    """The puller drags the line along +x at 0.1 m/s for 20 s: after the first metres, the
    tension at the puller is the kinetic friction mu w L plus the tangential drag of the line,
    1/2 rho C_dt pi d L v^2, within 2 % (the line's ends and the soft normal contact; measured
    1146.35 N against 1146.34 N)."""
    cb, speed = 0.5, 0.1
    spec, tm, tether, water = _laid_line(0.005, cb)
    with mt.Simulation(spec, water, [tm]) as sim:
        bt = sim.tether()
        m, d = sim.model, sim.data
        mid = m.body("puller").mocapid[0]
        tensions = []

        def pull(s):
            d.mocap_pos[mid, 0] += speed * s.timestep
        for _ in range(int(round(20.0 / sim.timestep))):
            pull(sim)
            sim.step()
            if sim.time > 10.0:
                tensions.append(bt.end_tension(d, "start"))
    rho = water.rho([0.0])[0]
    w = tether.wet_weight_per_length(rho, water.gravity)
    drag = 0.5 * rho * tether.cd_tangential * math.pi * D * L * speed**2
    assert np.mean(tensions) == pytest.approx(cb * w * L + drag, rel=0.02)

"""A heavy cable between two fixed points in still water settles on the analytic catenary."""

import numpy as np

import mjtether as mt
from conftest import new_spec


def test_static_catenary_matches_analytic():
    L, N = 120.0, 50
    tether = mt.TetherSpec(length=L, segments=N, diameter=0.02, density=7800.0)
    water = mt.WaterColumn(depth=200.0)
    p0, p1 = np.array([0.0, 0.0, -10.0]), np.array([100.0, 0.0, -30.0])
    ref = mt.catenary(p0, p1, L, tether.wet_weight_per_length(1025.0))

    # start away from the answer: the catenary-shaped curve pushed 2 m sideways
    nodes = mt.sagged_polyline(p0, p1, L, N)
    nodes[:, 1] += 2.0 * np.sin(np.linspace(0.0, np.pi, N + 1))
    spec = new_spec(0.004)
    tm = mt.add_tether(spec, tether, mt.FixedPoint(p0), mt.FixedPoint(p1), water=water, nodes=nodes)
    with mt.Simulation(spec, water, [tm]) as sim:
        sim.run(60.0)
        # the cable still sways slightly (quadratic drag damps small motions slowly): average
        # the end forces over the last 20 s, sampled every 0.1 s
        fa, fb, xs = [], [], []
        def sample(s):
            fa.append(s.tether().end_force(s.data, "start"))
            fb.append(s.tether().end_force(s.data, "end"))
            xs.append(s.tether().nodes(s.data))
        sim.run(20.0, sample, every=0.1)
    fa_ref, fb_ref = ref.end_forces()
    fa, fb, x = np.mean(fa, axis=0), np.mean(fb, axis=0), np.mean(xs, axis=0)
    # 1 %: the tolerance; a lumped model at N = 50 is within ~0.1 % of the continuum
    np.testing.assert_allclose(np.linalg.norm(fa), np.linalg.norm(fa_ref), rtol=0.01)
    np.testing.assert_allclose(np.linalg.norm(fb), np.linalg.norm(fb_ref), rtol=0.01)
    np.testing.assert_allclose(fa, fa_ref, atol=0.01 * np.linalg.norm(fa_ref))
    np.testing.assert_allclose(fb, fb_ref, atol=0.01 * np.linalg.norm(fb_ref))
    # nodes at their arc length on the catenary within 0.5 % of the 100 m span
    err = np.linalg.norm(x - ref.points(np.linspace(0.0, L, N + 1)), axis=1)
    assert err.max() < 0.005 * ref.span, err.max()

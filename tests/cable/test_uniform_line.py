"""A bound uniform tether is a one-section line make-up (``CableLayout.line``): its per-element
arrays are the tether's own numbers, over the elements waiting on the drum too, and an
inextensible line is never reported as softened.

Tolerances: none (exact equality) where the arrays must be the scalars the uniform tether had
(the same IEEE operations give the same bits: EI / l0 and L / N computed here independently);
the mass check is to 1e-12 relative (a sum of N + 1 lumped masses against mu L in closed form)."""

import warnings

import numpy as np
from conftest import new_spec

import mjtether as mt
from mjtether.cable.loads import compiled_arrays
from mjtether.cable.makeup import LineMakeup, Section
from mjtether.cable.softening import EAWarning


def _bound(tether, max_length=None, nodes=None):
    spec = new_spec(0.005)
    tm = mt.add_tether(spec, tether, mt.FixedPoint((0.0, 0.0, 0.0)), mt.FixedPoint((30.0, 0.0, -40.0)),
                       water=mt.WaterColumn(depth=100.0), max_length=max_length, nodes=nodes)
    return spec, tm


def test_a_uniform_tether_with_a_drum_is_one_section_over_every_element():
    t = mt.TetherSpec(length=60.0, segments=12, diameter=0.03, mass_per_length=1.7, EA=2e6, EI=40.0,
                      cd_normal=1.1, cd_tangential=0.01)
    spec, tm = _bound(t, max_length=90.0)
    water = mt.WaterColumn(depth=100.0)
    with mt.Simulation(spec, water, [tm]) as sim:
        bt = sim.tether()
        L = bt.layout
        assert isinstance(L.line, LineMakeup) and L.line.is_uniform and L.pays_out
        assert tm.first > 0  # nodes wait on the drum
        l0 = 60.0 / 12
        assert np.all(L.nominal == l0) and L.nominal.shape == (bt.n,)
        c = compiled_arrays(L)
        assert np.all(c["diameter"] == 0.03) and np.all(c["cd_normal"] == 1.1)
        assert np.all(c["area"] == np.pi * 0.03**2 / 4.0) and np.all(c["cd_area_float"] == 0.0)
        assert np.all(c["bend"] == 40.0 / l0) and c["bend"].shape == (bt.n - 1,)
        assert np.all(bt.drum.EA == 2e6)
        # the deployed cable weighs mu L (the nodes on the drum are parked, not counted)
        deployed = sim.model.body_mass[L.bids[bt.first:]].sum()
        assert abs(deployed - 1.7 * 60.0) <= 1e-12 * 1.7 * 60.0


def test_an_inextensible_make_up_is_not_reported_softened():
    """Sections without EA are inextensible: there is no EA to fall short of (the bound tether
    gave them an asked EA of inf, and every element came out "softened" to 0 % of it)."""
    line = LineMakeup((Section(30.0, 6, 0.03, 1.7), Section(30.0, 6, 0.05, 2.5)))
    ss = mt.quasistatic.steady_state(line, mt.WaterColumn(depth=100.0), (0.0, 0.0, 0.0), (30.0, 0.0, -40.0),
                                     seabed=False, EA=1e9)
    spec, tm = _bound(line, nodes=ss.nodes)
    with warnings.catch_warnings():
        warnings.simplefilter("error", EAWarning)
        with mt.Simulation(spec, mt.WaterColumn(depth=100.0), [tm]) as sim:
            assert np.all(np.isinf(sim.tether().drum.EA))

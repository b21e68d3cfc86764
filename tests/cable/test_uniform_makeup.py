"""A uniform tether is a one-section line make-up: ``LineMakeup.uniform`` carries what the
dynamic model needs (axial damping ratio, added-mass mode, drag law), ``add_tether`` builds it
as the ``TetherSpec`` (payout allowed, the same model to the bit), and bad make-ups are refused
naming the field.

Tolerances: none where the same numbers must come out (the same IEEE operations); the deployed
mass to 1e-12 relative (a sum of N + 1 lumped masses against mu L)."""

import math

import numpy as np
import pytest
from conftest import new_spec

import mjtether as mt
from mjtether.cable import ends
from mjtether.cable.makeup import LineMakeup, PointLoad, Section

TOP, BOTTOM = (0.0, 0.0, 0.0), (30.0, 0.0, -40.0)


def _tether(**kw):
    props = dict(length=60.0, segments=12, diameter=0.03, density=1400.0, EA=2e6, EI=40.0, cd_normal=1.1,
                 cd_tangential=0.01, ca_normal=0.8, axial_damping_ratio=3.0, added_mass="normal")
    props.update(kw)
    return mt.TetherSpec(**props)


def test_the_one_section_make_up_gives_back_its_tether():
    """Every number of the TetherSpec comes back from its make-up (``tether``), equal to the bit, the
    mass per metre rho_c pi d^2 / 4 (computed here, to 1e-15: another order of the same product)
    included; the dynamic model's properties are carried."""
    t = _tether(drag_law="loading_functions")
    line = LineMakeup.uniform(t)
    assert line.is_uniform and line.pays_out
    back = line.tether
    assert back.mu == pytest.approx(1400.0 * math.pi * 0.03**2 / 4.0, rel=1e-15)
    for name in ("mu", "length", "segments", "diameter", "EA", "EI", "cd_normal", "cd_tangential", "ca_normal",
                 "axial_damping_ratio", "added_mass", "drag_law", "area", "segment_length"):
        assert getattr(back, name) == getattr(t, name), name
    assert LineMakeup.of(t) == line and LineMakeup.of(line) is line


def test_a_uniform_make_up_builds_the_tetherspec_model_and_pays_out():
    """Built from its make-up, a uniform tether with a drum (max_length 90 m) and no start shape
    is the model built from the TetherSpec: masses, armature, element solver parameters, equal to
    the bit (its damping ratio 3 and normal added mass carried); the drum holds
    ceil(90 / 5 - 0.5) + 1 = 19 elements, and the deployed cable weighs mu L."""
    t = _tether()
    water = mt.WaterColumn(depth=100.0)
    models = []
    for line in (t, LineMakeup.uniform(t)):
        spec = new_spec(0.005)
        tm = mt.add_tether(spec, line, mt.FixedPoint(TOP), mt.FixedPoint(BOTTOM), water=water, max_length=90.0)
        assert tm.n == 19 and tm.first == 7 and tm.added_mass == "normal" and tm.line.pays_out
        sim = mt.Simulation(spec, water, [tm])
        models.append((sim, tm))
    try:
        (a, ta), (b, tb) = models
        assert tb.spec.axial_damping_ratio == 3.0 and tb.makeup is None
        for name in ("body_mass", "dof_armature", "eq_solref", "eq_solimp", "tendon_invweight0", "wrap_prm"):
            np.testing.assert_array_equal(getattr(b.model, name), getattr(a.model, name), err_msg=name)
        L = b.tether().layout
        deployed = b.model.body_mass[L.bids[tb.first:]].sum()
        assert abs(deployed - t.mu * 60.0) <= 1e-12 * t.mu * 60.0
    finally:
        for sim, _ in models:
            sim.close()


def test_end_lumps_are_half_an_element_and_a_point_load():
    """An end node lumps half its element, mu L / (2 N) (closed form), whatever the form of the
    line; a clump on the end node adds its mass."""
    t = _tether()
    half = 0.5 * t.mu * 60.0 / 12
    assert ends.lumped_end_mass(t, "end") == pytest.approx(half, rel=1e-15)
    assert ends.lumped_end_mass(LineMakeup.uniform(t), "start") == pytest.approx(half, rel=1e-15)
    clumped = LineMakeup(LineMakeup.uniform(t).sections, [PointLoad(60.0, mass=7.0)])
    assert ends.lumped_end_mass(clumped, "end") == pytest.approx(half + 7.0, rel=1e-15)


def test_bad_make_ups_name_the_field_and_the_range():
    sec = (Section(30.0, 6, 0.03, 1.7), Section(30.0, 6, 0.05, 2.5))
    with pytest.raises(ValueError, match=r"line_makeup.axial_damping_ratio must be in \[0.3, 10.0\]"):
        LineMakeup(sec, axial_damping_ratio=0.1)
    with pytest.raises(ValueError, match="line_makeup.added_mass must be one of isotropic, normal"):
        LineMakeup(sec, added_mass="axial")
    with pytest.raises(ValueError, match="line_makeup.drag_law = 'loading_functions' is for a uniform line"):
        LineMakeup(sec, drag_law="loading_functions")
    with pytest.raises(ValueError, match="line_makeup: 2 section"):
        LineMakeup(sec).tether
    with pytest.raises(ValueError, match="tether must be a TetherSpec or a LineMakeup, got str"):
        mt.add_tether(new_spec(0.005), "cable", mt.FixedPoint(TOP), mt.FixedPoint(BOTTOM))
    with pytest.raises(ValueError, match="payout of a line make-up is not supported yet"):
        mt.add_tether(new_spec(0.005), LineMakeup(sec), mt.FixedPoint(TOP), mt.FixedPoint(BOTTOM),
                      nodes=np.linspace(TOP, BOTTOM, 13) * [1, 1, 1], max_length=90.0)

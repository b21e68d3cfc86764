"""Line make-ups (mjtether.cable.makeup): input checks, the discretisation of sections, point loads
(lever rule) and float sections, and the line-type library."""

import math

import numpy as np
import pytest

import mjtether as mt
from mjtether.cable.makeup import DistributedBuoyancy, LineMakeup, PointLoad, Section, load_line_types

RHO, G = 1025.0, 9.81


def _sec(length=10.0, segments=5, **kw):
    return Section(length, segments, kw.pop("diameter", 0.02), kw.pop("mass_per_length", 0.5), **kw)


# ---------------------------------------------------------------------------- input checks

@pytest.mark.parametrize("kw, field", [
    (dict(length=0.0), "section.length"),
    (dict(length=float("nan")), "section.length"),
    (dict(segments=0), "section.segments"),
    (dict(segments=2.0), "section.segments"),
    (dict(diameter=-0.1), "section.diameter"),
    (dict(mass_per_length=0.0), "section.mass_per_length"),
    (dict(EA=0.0), "section.EA"),
    (dict(EI=-1.0), "section.EI"),
    (dict(cd_normal=11.0), "section.cd_normal"),
    (dict(cd_tangential=-0.1), "section.cd_tangential"),
    (dict(ca_normal="1"), "section.ca_normal"),
    (dict(name=3), "section.name"),
    (dict(mbl=0.0), "section.mbl"),
])
def test_section_rejects_bad_input_naming_the_field(kw, field):
    with pytest.raises(ValueError, match=field.replace(".", r"\.")):
        _sec(**kw)


@pytest.mark.parametrize("make, field", [
    (lambda: PointLoad(-1.0), "point_load.arc_length"),
    (lambda: PointLoad(1.0, mass=-1.0), "point_load.mass"),
    (lambda: PointLoad(1.0, volume=float("inf")), "point_load.volume"),
    (lambda: PointLoad(1.0, cd_area=-1.0), "point_load.cd_area"),
    (lambda: PointLoad(1.0, ca=20.0), "point_load.ca"),
    (lambda: DistributedBuoyancy(5.0, 5.0, 0.01), "distributed_buoyancy.end"),
    (lambda: DistributedBuoyancy(0.0, 5.0, -0.01), "distributed_buoyancy.volume_per_length"),
    (lambda: DistributedBuoyancy(0.0, 5.0, 0.01, mass_per_length=-1), "distributed_buoyancy.mass_per_length"),
    (lambda: LineMakeup([]), "line_makeup.sections"),
    (lambda: LineMakeup([mt.TetherSpec(length=10.0)]), r"line_makeup.sections\[0\]"),
    (lambda: LineMakeup([_sec()], [PointLoad(10.5)]), r"line_makeup.loads\[0\].arc_length"),
    (lambda: LineMakeup([_sec()], [DistributedBuoyancy(2.0, 11.0, 0.01)]), r"line_makeup.loads\[0\].end"),
    (lambda: LineMakeup([_sec()], ["buoy"]), r"line_makeup.loads\[0\]"),
    (lambda: LineMakeup([_sec(segments=3000), _sec(segments=3000)]), "line_makeup"),
])
def test_loads_and_makeup_reject_bad_input(make, field):
    with pytest.raises(ValueError, match=field):
        make()


# ---------------------------------------------------------------------------- discretisation

def test_sections_keep_their_own_element_length_and_joints_are_nodes():
    line = LineMakeup([_sec(10.0, 4, EA=1e5), _sec(3.0, 3, diameter=0.05, mass_per_length=2.0), _sec(7.0, 2)])
    assert line.segments == 9 and line.length == 20.0
    np.testing.assert_array_equal(line.element_length, [2.5] * 4 + [1.0] * 3 + [3.5] * 2)
    np.testing.assert_array_equal(line.section_nodes, [0, 4, 7, 9])
    np.testing.assert_array_equal(line.node_arc_length[line.section_nodes], [0.0, 10.0, 13.0, 20.0])
    np.testing.assert_allclose(np.diff(line.node_arc_length), line.element_length, rtol=1e-14)
    np.testing.assert_array_equal(line.element_diameter, [0.02] * 4 + [0.05] * 3 + [0.02] * 2)
    np.testing.assert_array_equal(line.element_mass_per_length, [0.5] * 4 + [2.0] * 3 + [0.5] * 2)
    assert np.all(line.element_EA[:4] == 1e5) and np.all(np.isinf(line.element_EA[4:]))
    # wet weight (mu - rho pi d^2 / 4) g, by hand for the middle section
    assert line.element_wet_weight(RHO, G)[5] == pytest.approx((2.0 - RHO * math.pi * 0.05**2 / 4) * G, rel=1e-14)
    assert not line.is_uniform and not line.has_point_loads


def test_point_load_lever_rule_keeps_total_and_moment():
    """A load inside an element is split between its two nodes in the ratio of the distances
    (lever rule): total and first moment unchanged; one on a node goes wholly to it."""
    line = LineMakeup([_sec(10.0, 4), _sec(6.0, 3)],
                      [PointLoad(3.125, mass=8.0, volume=0.2, cd_area=0.4, ca=0.5),  # 1/4 into element 1
                       PointLoad(10.0, mass=5.0),  # on the joint (node 4)
                       PointLoad(16.0, volume=1.0, ca=1.0)])  # on the bottom node
    s = line.node_arc_length
    np.testing.assert_allclose(line.node_mass[[1, 2]], [6.0, 2.0], rtol=1e-14)
    np.testing.assert_allclose(line.node_volume[[1, 2]], [0.15, 0.05], rtol=1e-14)
    np.testing.assert_allclose(line.node_cd_area[[1, 2]], [0.3, 0.1], rtol=1e-14)
    assert line.node_mass[4] == 5.0 and line.node_volume[-1] == 1.0
    assert line.node_mass.sum() == pytest.approx(13.0, rel=1e-14)
    assert (line.node_mass * s).sum() == pytest.approx(8.0 * 3.125 + 5.0 * 10.0, rel=1e-14)
    # added mass: ca * volume per node; the volume-weighted ca
    np.testing.assert_allclose(line.node_added_volume[[1, 2, 7]], [0.075, 0.025, 1.0], rtol=1e-14)
    np.testing.assert_allclose(line.node_ca[[0, 1, 2, 7]], [0.0, 0.5, 0.5, 1.0], rtol=1e-14)
    assert line.node_wet_weight(RHO, G)[7] == pytest.approx(-RHO * G, rel=1e-14)


def test_distributed_buoyancy_is_the_per_element_overlap():
    """A float section adds its volume, mass and drag area per metre to every element it covers,
    in proportion to the overlap: the totals over the line are the float section's."""
    line = LineMakeup([_sec(10.0, 10)], [DistributedBuoyancy(2.5, 6.0, 0.01, mass_per_length=4.0,
                                                             cd_area_per_length=0.3, ca=0.8)])
    l = line.element_length
    area0 = math.pi * 0.02**2 / 4
    extra_v = (line.element_area - area0) * l
    np.testing.assert_allclose(extra_v[[1, 2, 3, 5, 6]], [0.0, 0.005, 0.01, 0.01, 0.0], atol=1e-15)
    assert extra_v.sum() == pytest.approx(0.01 * 3.5, rel=1e-12)
    assert ((line.element_mass_per_length - 0.5) * l).sum() == pytest.approx(4.0 * 3.5, rel=1e-12)
    assert (line.element_float_cd_area * l).sum() == pytest.approx(0.3 * 3.5, rel=1e-12)
    assert (line.element_float_added_volume * l).sum() == pytest.approx(0.8 * 0.01 * 3.5, rel=1e-12)


def test_uniform_and_reversed():
    t = mt.TetherSpec(length=120.0, segments=30, diameter=0.03, density=1400.0, EA=3e6, EI=2.0, cd_normal=1.1,
                      cd_tangential=0.01, ca_normal=0.9)
    line = LineMakeup.uniform(t)
    assert line.is_uniform and line.segments == 30 and line.length == 120.0
    (s,) = line.sections
    assert (s.diameter, s.mass_per_length, s.EA, s.EI, s.cd_normal, s.cd_tangential, s.ca_normal) == \
        (t.diameter, t.mu, t.EA, t.EI, t.cd_normal, t.cd_tangential, t.ca_normal)
    assert np.all(line.element_length == t.segment_length)
    two = LineMakeup([_sec(10.0, 4), _sec(6.0, 3, diameter=0.05)],
                     [PointLoad(3.0, mass=1.0), DistributedBuoyancy(11.0, 15.0, 0.002)])
    rev = two.reversed()
    assert [x.length for x in rev.sections] == [6.0, 10.0]
    assert rev.loads[0].arc_length == 13.0 and (rev.loads[1].start, rev.loads[1].end) == (1.0, 5.0)
    np.testing.assert_allclose(rev.element_area, two.element_area[::-1], rtol=1e-14)
    np.testing.assert_allclose(rev.node_mass, two.node_mass[::-1], rtol=1e-14, atol=1e-15)
    assert rev.reversed() == two


# ---------------------------------------------------------------------------- line types

def test_line_type_library():
    types = load_line_types()
    assert {"fathom_rov_tether", "fibre_optic_microtether", "steel_armoured_umbilical_17mm", "polyester_rope_24mm",
            "studless_chain_120mm"} <= set(types)
    for t in types.values():
        assert len(t.source) > 40, t.name
        assert t.mbl > 0 and t.diameter > 0
    # the kinds the library claims: a light tether near neutral in sea water, a neutral fibre tether
    # (within 1e-4 kg/m of neutral), sinking armoured umbilical, chain and rope
    assert abs(types["fathom_rov_tether"].wet_weight_per_length(RHO, G)) < 0.05
    assert abs(types["fibre_optic_microtether"].wet_weight_per_length(RHO, G)) < 1e-4 * G
    for sinking in ("steel_armoured_umbilical_17mm", "polyester_rope_24mm", "studless_chain_120mm"):
        assert types[sinking].wet_weight_per_length(RHO, G) > 0


def test_chain_line_type_is_moorpys_120_mm_chain():
    """MoorPy's getLineProps(120, 'chain') (MoorProps_default.yaml, MoorPy 1.3.0) gives d_vol 0.216 m,
    m 288 kg/m, EA 1 232 572 089.6 N, MBL 13 639 789.32 N and w 2456.820077 N/m in 1025 kg/m^3 (printed
    by MoorPy itself): the library entry reproduces them to 1e-12."""
    c = load_line_types()["studless_chain_120mm"]
    assert (c.diameter, c.mass_per_length) == (0.216, 288.0)
    assert c.EA == pytest.approx(1232572089.6, rel=1e-12)
    assert c.mbl == pytest.approx(13639789.32, rel=1e-12)
    assert c.wet_weight_per_length(RHO, G) == pytest.approx(2456.820077481978, rel=1e-12)


def test_section_from_line_type():
    s = Section.from_line_type("polyester_rope_24mm", 300.0, 60, cd_normal=1.5)
    t = load_line_types()["polyester_rope_24mm"]
    assert (s.length, s.segments, s.name, s.mbl, s.EA, s.cd_normal) == (300.0, 60, "polyester_rope_24mm", t.mbl, t.EA, 1.5)
    with pytest.raises(ValueError, match="unknown line type 'kevlar'"):
        Section.from_line_type("kevlar", 10.0, 2)
    with pytest.raises(ValueError, match="unknown override"):
        Section.from_line_type("polyester_rope_24mm", 10.0, 2, colour="red")
    with pytest.raises(ValueError, match="section.length"):
        Section.from_line_type("polyester_rope_24mm", -1.0, 2)


def test_load_line_types_checks_a_file(tmp_path):
    p = tmp_path / "types.toml"
    p.write_text('[thin]\ndiameter = 0.01\nmass_per_length = 0.1\nEA = 1e5\nEI = 0.0\ncd_normal = 1.2\n'
                 'cd_tangential = 0.008\nca_normal = 1.0\nmbl = 1000.0\nsource = "made up for a test"\n')
    assert load_line_types(p)["thin"].EA == 1e5
    p.write_text(p.read_text().replace("diameter = 0.01", "diameter = -0.01"))
    with pytest.raises(ValueError, match=r"\[thin\].*section.diameter"):
        load_line_types(p)
    p.write_text('[thin]\ndiameter = 0.01\n')
    with pytest.raises(ValueError, match="lacks"):
        load_line_types(p)

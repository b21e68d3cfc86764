"""The network's statics from a slack start (``statics.equilibrium``): light ropes, which have no
stiffness while slack, and a clump on a vertical wire, against closed forms written here."""

import math

import numpy as np

from mjtether.network import from_dict, run, statics

RHO, G = 1025.0, 9.80665


def _water():
    return {"depth": 200.0, "rho": RHO, "gravity": G, "seabed_stiffness": 0.0}


def _equilibrium(net):
    pos, note = statics.equilibrium(net, run.start_positions(net))
    assert note.startswith("elastic catenaries with"), note
    return pos


def test_a_clump_on_a_v_bridle_of_slack_light_ropes_finds_its_place():
    """A 500 kg clump (0.05 m^3) on two light ropes of 50 m (1 mm, 1e-3 kg/m, EA 1e10 N) from
    held points 60 m apart at z = -20, written at (1, 0, -50), where both ropes are slack
    (their ends 43.1 m and 41.7 m apart): it hangs at (0, 0, -60), each rope
    carrying W / (2 cos theta), cos theta = 40 / 50, W its wet weight (m - rho V) g. Before, the
    search stalled with 4.4 kN left. Tolerance 1e-4 of T and 1e-3 m: the ropes' own weight
    (0.1 N in all) and stretch (2e-7 of their length) move it by under 1e-5."""
    mass, vol = 500.0, 0.05
    net = from_dict({"water": _water(),
                     "line_types": {"rope": {"diameter": 0.001, "mass_per_length": 1e-3, "EA": 1e10}},
                     "points": {"a": {"kind": "fixed", "position": [-30.0, 0.0, -20.0]},
                                "b": {"kind": "fixed", "position": [30.0, 0.0, -20.0]},
                                "clump": {"kind": "free", "position": [1.0, 0.0, -50.0], "mass": mass, "volume": vol}},
                     "lines": [{"name": "left", "type": "rope", "a": "clump", "b": "a", "length": 50.0, "segments": 10},
                               {"name": "right", "type": "rope", "a": "clump", "b": "b", "length": 50.0,
                                "segments": 10}]})
    for ln in net.lines:  # (the start is slack)
        assert np.linalg.norm(np.subtract(net.points[ln.b].position, [1.0, 0.0, -50.0])) < ln.length
    T = (mass - RHO * vol) * G / (2 * 0.8)
    pos = _equilibrium(net)
    np.testing.assert_allclose(pos["clump"], [0.0, 0.0, -60.0], atol=1e-3)
    for ln in net.lines:
        st = statics.line_ends(net, ln, pos[ln.a], pos[ln.b])
        assert abs(np.linalg.norm(st.force_a) - T) < 1e-4 * T


def _hanging(mass, start, EA=1e7):
    return from_dict({"water": _water(),
                      "line_types": {"wire": {"diameter": 0.02, "mass_per_length": 2.0, "EA": EA}},
                      "points": {"top": {"kind": "coupled", "position": [0.0, 0.0, -2.0]},
                                 "clump": {"kind": "free", "position": start, "mass": mass, "volume": 0.01}},
                      "lines": [{"name": "wire", "type": "wire", "a": "clump", "b": "top", "length": 30.0,
                                 "segments": 10}]})


def test_a_clump_on_a_vertical_wire_hangs_its_length_and_stretch_below_the_top():
    """A 300 kg clump (0.01 m^3) on a 30 m wire (2 kg/m, 20 mm, EA 1e7 N) from a point at
    z = -2, written where the wire is just straight (the sweep's case, that missed by 0.07 N),
    slack, or aside: the foot carries T = (m - rho V) g, the top T + w L, and the clump hangs
    L + (T + w L / 2) L / EA below the top (the mean tension's stretch), on its vertical.
    Tolerance 1e-6 of T and 1e-6 m (the statics' own: 1e-6 of the load, 3 mN, on EA / L)."""
    L, EA, w = 30.0, 1e7, (2.0 - RHO * math.pi * 0.02 ** 2 / 4) * G
    for mass in (100.0, 300.0, 1000.0):
        T = (mass - RHO * 0.01) * G
        z = -2.0 - L - (T + w * L / 2) * L / EA
        for start in ([0.0, 0.0, -32.0], [0.0, 0.0, -25.0], [0.5, 0.0, -31.0]):
            net = _hanging(mass, start)
            pos = _equilibrium(net)
            assert abs(pos["clump"][2] - z) < 1e-6, (mass, start)
            assert math.hypot(*pos["clump"][:2]) < 1e-4 * L, (mass, start)  # (its swing: T / L, 100 N/m)
            st = statics.line_ends(net, net.lines[0], pos["clump"], pos["top"])
            assert abs(np.linalg.norm(st.force_a) - T) < 1e-6 * T
            assert abs(np.linalg.norm(st.force_b) - (T + w * L)) < 1e-6 * T


def test_a_vertical_line_folds_when_slack_and_hangs_straight_when_taut():
    """``statics.vertical`` on a 30 m wire (w from 2 kg/m, 20 mm; EA 1e7 N), ends c apart on one
    vertical: slack, it folds, each end carrying the weight of its side of the fold, the sides
    l1 - l2 = c / (1 + w L / 2 EA) (each side's stretch w l^2 / 2 EA); taut, the foot carries
    EA (c / L - 1) - w L / 2; the two meet at c = L (1 + w L / 2 EA) (the foot's tension 0).
    Exact to rounding: 1e-9 N; 1e-4 N across the meeting point, 1e-12 of c either side of it
    (EA 1e-12 = 1e-5 N)."""
    L, EA, w = 30.0, 1e7, (2.0 - RHO * math.pi * 0.02 ** 2 / 4) * G
    lo = np.zeros(3)
    c = 12.0
    l1 = 0.5 * (L + c / (1 + w * L / (2 * EA)))
    f_lo, f_hi = statics.vertical(lo, [0.0, 0.0, c], L, w, EA)
    assert abs(f_lo[2] + w * (L - l1)) < 1e-9 and abs(f_hi[2] + w * l1) < 1e-9
    # (the drop from the top to the fold, less that from the foot, is c)
    assert abs((l1 + w * l1 ** 2 / (2 * EA)) - ((L - l1) + w * (L - l1) ** 2 / (2 * EA)) - c) < 1e-9
    c = 30.5
    f_lo, f_hi = statics.vertical(lo, [0.0, 0.0, c], L, w, EA)
    assert abs(f_lo[2] - (EA * (c / L - 1) - w * L / 2)) < 1e-9 and abs(f_hi[2] + f_lo[2] + w * L) < 1e-9
    edge = L * (1 + w * L / (2 * EA))
    below, above = (statics.vertical(lo, [0.0, 0.0, edge * (1 + s)], L, w, EA) for s in (-1e-12, 1e-12))
    assert abs(below[0][2]) < 1e-4 and abs(above[0][2]) < 1e-4 and abs(below[1][2] + w * L) < 1e-4

"""A buoyant line lying on the surface floats at its draft (Archimedes), a float's waterplane
holding it there, where buoyancy by the axis alone would switch on and off as the axis crossed
z = 0 and leave it chattering there (MoorDyn's tripod.txt float, tests/io/test_moordyn_files.py)."""

import math

import numpy as np
import pytest
import scipy.optimize

from mjtether.network import from_dict, run


@pytest.mark.parametrize("offset", [0.01, -0.01])
def test_a_level_float_line_rests_at_its_draft(offset):
    """A 10 m line 0.5 m wide at 0.4 of the water's density, its ends free, released level with
    its axis 1 cm above or below its draft: the draft, where the wet part of its cross-section is
    0.4 of the whole (the circular segment: (pi - acos c + c sqrt(1 - c^2)) / pi = 0.4 with the
    axis c r under the water; c = -0.158, the axis 39.4 mm above the surface). It heaves about
    there (nothing radiates waves to damp it, and drag at Cd 10 damps a heave of millimetres
    slowly), so its mean height over the last 20 s of 40 s is compared: within 0.5 mm, what
    is left of the decaying heave in that mean (measured 0.26 mm from above, 0.27 mm from below).
    By the axis alone it would fall onto z = 0 and chatter there, 39 mm off."""
    rho, d, ratio = 1025.0, 0.5, 0.4
    area = math.pi * d * d / 4
    c = scipy.optimize.brentq(lambda c: (math.pi - math.acos(c) + c * math.sqrt(1 - c * c)) / math.pi - ratio, -1, 1)
    axis = -c * d / 2
    assert axis == pytest.approx(0.0394, abs=1e-4)
    z0 = axis + offset
    data = {"water": {"depth": 50.0, "rho": rho}, "simulation": {"duration": 40.0},
            "line_types": {"f": {"diameter": d, "mass_per_length": ratio * rho * area, "EA": 1e7,
                                 "cd_normal": 10.0}},
            "points": {"a": {"kind": "free", "position": [0.0, 0.0, z0], "mass": 0.0, "volume": 0.0},
                       "b": {"kind": "free", "position": [10.0, 0.0, z0], "mass": 0.0, "volume": 0.0}},
            "lines": [{"name": "1", "type": "f", "a": "a", "b": "b", "length": 10.0, "segments": 10}]}
    r, rows = run.simulate(from_dict(data))
    r.sim.close()
    cols = run.columns(r.net)
    late = rows[:, 0] >= 20.0
    for end in "ab":
        z = rows[late, cols.index(f"point{end}_z_m")]
        assert np.mean(z) == pytest.approx(axis, abs=5e-4), np.mean(z)


def _moordyn_c_wet_fraction(tmp_path, axis_z: float, d: float, length: float, mu: float, rho: float) -> float:
    """The submerged part of a level line (both ends fixed, axis at ``axis_z``, three segments)
    by MoorDyn-C's own node weights, ``GetLineNodeWeight``: sum W_z = -g (m L - rho V)."""
    moordyn = pytest.importorskip("moordyn")
    path = tmp_path / f"float{axis_z:+g}.txt"
    path.write_text(f"""MoorDyn input: a level float line
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
float      {d}     {mu}       2.2e9      -0.5        0          0.0    0.0    0.0     0.0
---------------------- POINTS --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     0       0       {axis_z}   0      0       0      0
2     Fixed     {length}    0       {axis_z}   0      0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     float      1        2         {length}      3      -
---------------------- OPTIONS -----------------------------------------
1E-5          dtM
{rho}        WtrDnsty
100           WtrDpth
0             TmaxIC
------------------------- need this line --------------------------------------
""")
    s = moordyn.Create(str(path))
    try:
        moordyn.Init(s, np.zeros(0), np.zeros(0))
        moordyn.Step(s, np.zeros(0), np.zeros(0), 0.0, 1e-5)
        line = moordyn.GetLine(s, 1)
        nodes = [moordyn.GetLineNodePos(line, i)[2] for i in range(moordyn.GetLineN(line) + 1)]
        assert np.sign(nodes).tolist() == [np.sign(axis_z)] * 4  # (every node on its side of the surface)
        wz = sum(moordyn.GetLineNodeWeight(line, i)[2] for i in range(moordyn.GetLineN(line) + 1))
    finally:
        moordyn.Close(s)
    return (wz / 9.80665 + mu * length) / (rho * math.pi * d * d / 4 * length)


@pytest.mark.parametrize("axis_z", [-0.01, 0.01])
def test_moordyn_c_buoys_a_float_by_its_nodes_and_mjtether_by_its_wet_part(tmp_path, axis_z):
    """Why tripod.txt is not compared with MoorDyn-C. Its float (0.82 m wide, 0.63 m long, 133.3
    kg/m) is a line lying on the surface. MoorDyn-C buoys a line segment by where its two nodes
    are (Line.cpp, calcSubSeg): all of it when both are under the surface, none when both are
    above. With the float level and its axis 1 cm under or over the surface, MoorDyn-C's own node
    weights give it all or none of its buoyancy, where the cylinder cut by the surface has 51.6 %
    or 48.4 % of it under water (the circular segment, 1 - (a - sin a) / (2 pi), a = 2 acos(-z/r)
    with z the axis height): 3.3 kN of buoyancy switches on and off as the float's axis crosses the
    surface, so MoorDyn-C's float has no waterplane stiffness and never settles there.
    mjtether's wet fraction (``hydro.wet_fraction``, the mean of each cross-section's circular
    segment along the axis) is the cylinder's, within 1e-9 for a level element."""
    from mjtether.physics import hydro

    d, length, mu, rho = 0.82, 0.63, 133.3333333, 1025.0
    r = d / 2
    a = 2 * math.acos(-axis_z / r)  # (the dry segment's angle: the surface is -axis_z above the axis)
    wet = 1 - (a - math.sin(a)) / (2 * math.pi)
    assert wet == pytest.approx(0.516 if axis_z < 0 else 0.484, abs=1e-3)
    theirs = _moordyn_c_wet_fraction(tmp_path, axis_z, d, length, mu, rho)
    assert theirs == pytest.approx(1.0 if axis_z < 0 else 0.0, abs=1e-9)
    ours, _ = hydro.wet_fraction(np.array([axis_z]), np.array([axis_z]), r)
    assert float(ours[0]) == pytest.approx(wet, abs=1e-9)

"""Free and pinned bodies in the network's statics (``statics.equilibrium(..., bodies=True)``):
Archimedes on a buoy held down by one line, the tilt of a body with an offset centre of
gravity on a bridle, a pinned body turned by a rope, each against an answer written here, and a
moored buoy against MoorPy (an independent implementation; skipped where it is not installed)."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from mjtether.network import from_dict, run, statics
from mjtether.network.solve import solve

RHO, G = 1025.0, 9.80665
NEUTRAL = RHO * math.pi * 0.001 ** 2 / 4  # kg/m: a 1 mm rope that weighs nothing in the water


def _water():
    return {"depth": 200.0, "rho": RHO, "gravity": G, "seabed_stiffness": 0.0}


def _solve(net):
    pos, note, poses = statics.equilibrium(net, run.start_positions(net), bodies=True)
    assert note.startswith("elastic catenaries with"), note
    return pos, poses


def test_a_buoy_held_down_by_one_line_carries_its_net_buoyancy():
    """A 500 kg, 1.2 m^3 buoy on a 40 m wire (2 kg/m, 20 mm, EA 1e7 N) to an anchor at z = -150,
    tied 0.5 m below its origin, written 3 m aside, 5 m low and turned (10, -5, 30) deg: its
    line's top tension is (rho V - m) g, the anchor's that less the wire's wet weight w L
    (Archimedes), the buoy's origin L + (T_top - w L / 2) L / EA + 0.5 m above the anchor, upright.
    Tolerance 1e-6 of the tension (the statics' own is 1e-6 of the load, 7 mN), 1e-6 m in height
    (7 mN on the wire's EA / L), 1e-4 m aside (7 mN on its swing's stiffness T / L, 176 N/m) and
    1e-6 rad (7 mN m on the 3.5 kN m/rad of T at 0.5 m)."""
    m, V, L, EA, d, mpl = 500.0, 1.2, 40.0, 1e7, 0.02, 2.0
    net = from_dict({"water": _water(),
                     "line_types": {"wire": {"diameter": d, "mass_per_length": mpl, "EA": EA}},
                     "bodies": {"buoy": {"kind": "free", "position": [3.0, 0.0, -115.0], "rpy_deg": [10.0, -5.0, 30.0],
                                         "mass": m, "volume": V, "inertia": [100.0] * 3}},
                     "points": {"anchor": {"kind": "fixed", "position": [0.0, 0.0, -150.0]},
                                "eye": {"kind": "body", "body": "buoy", "position": [0.0, 0.0, -0.5]}},
                     "lines": [{"name": "hold", "type": "wire", "a": "anchor", "b": "eye", "length": L,
                                "segments": 10}]})
    w = (mpl - RHO * math.pi * d * d / 4) * G
    top = (RHO * V - m) * G
    pos, poses = _solve(net)
    st = statics.line_ends(net, net.lines[0], pos["anchor"], pos["eye"])
    assert abs(np.linalg.norm(st.force_b) - top) < 1e-6 * top
    assert abs(np.linalg.norm(st.force_a) - (top - w * L)) < 1e-6 * top
    z = -150.0 + L + (top - w * L / 2) * L / EA + 0.5
    np.testing.assert_allclose(poses["buoy"].position[:2], [0.0, 0.0], atol=1e-4)
    assert abs(poses["buoy"].position[2] - z) < 1e-6
    assert np.linalg.norm(poses["buoy"].rotation[:, 2] - [0.0, 0.0, 1.0]) < 1e-6


def test_a_body_with_an_offset_cg_on_a_bridle_tilts_its_cg_under_the_hang_point():
    """A 400 kg, 0.1 m^3 body hung from one fixed point by two light ropes of 5 m to body points
    (+-2, 0, 0) m; its centre of gravity 0.3 m along x, its buoyancy at its origin; written
    0.5 m aside with both ropes slack. The ropes (EA 1e9 N: strain 1e-6; neutrally buoyant) and
    body are a rigid triangle turning about the hang point, h = sqrt(5^2 - 2^2) above the origin
    in the body frame: in balance the resultant of weight and buoyancy, at x_e = m e / (m - rho V)
    in the body frame, is under it: the body's x axis turned atan(x_e / h) down (a roll about
    that axis, through both ropes' points, the weight and the buoyancy, is neutral, and not
    checked). Tolerance 1e-5 rad: the ropes' stretch (20 um, differing by under 10 um between
    them over their 4 m spread) moves it by under 3e-6 (measured 7e-7)."""
    m, V, e, a, L = 400.0, 0.1, 0.3, 2.0, 5.0
    net = from_dict({"water": _water(),
                     "line_types": {"rope": {"diameter": 0.001, "mass_per_length": NEUTRAL, "EA": 1e9}},
                     "bodies": {"box": {"kind": "free", "position": [0.5, 0.0, -24.0], "mass": m, "volume": V,
                                        "cg": [e, 0.0, 0.0], "inertia": [50.0] * 3}},
                     "points": {"hook": {"kind": "fixed", "position": [0.0, 0.0, -20.0]},
                                "left": {"kind": "body", "body": "box", "position": [-a, 0.0, 0.0]},
                                "right": {"kind": "body", "body": "box", "position": [a, 0.0, 0.0]}},
                     "lines": [{"name": "l", "type": "rope", "a": "left", "b": "hook", "length": L, "segments": 5},
                               {"name": "r", "type": "rope", "a": "right", "b": "hook", "length": L, "segments": 5}]})
    h = math.sqrt(L * L - a * a)
    tilt = math.atan(m * e / (m - RHO * V) / h)
    _, poses = _solve(net)
    R = poses["box"].rotation
    assert abs(math.asin(-R[2, 0]) - tilt) < 1e-5  # (body x turned down by it; a roll about it is free)
    below = poses["box"].position + R @ [m * e / (m - RHO * V), 0.0, 0.0]
    np.testing.assert_allclose(below[:2], [0.0, 0.0], atol=1e-5)


def test_a_pinned_body_turns_until_the_rope_s_moment_meets_its_weight_s():
    """A pinned body (100 kg, 0.02 m^3) whose origin hangs 2 m below its pin at z = -20, pulled
    sideways by a neutrally buoyant rope (28 m, EA 1e5 N) from its point 3 m below the pin to a fixed point
    at (0, 30, -23): its roll theta is where the moment about the pin of the rope's pull
    EA (c / L - 1) balances that of its wet weight at 2 sin(theta), solved here with brentq.
    Tolerance 1e-6 rad (the statics' force tolerance, 1e-6 of the load)."""
    m, V, EA, L = 100.0, 0.02, 1e5, 28.0
    pin, far = np.array([0.0, 0.0, -20.0]), np.array([0.0, 30.0, -23.0])
    net = from_dict({"water": _water(),
                     "line_types": {"rope": {"diameter": 0.001, "mass_per_length": NEUTRAL, "EA": EA}},
                     "bodies": {"bob": {"kind": "pinned", "position": [0.0, 0.0, -22.0], "pin": [0.0, 0.0, 2.0],
                                        "mass": m, "volume": V, "inertia": [5.0] * 3}},
                     "points": {"eye": {"kind": "body", "body": "bob", "position": [0.0, 0.0, -1.0]},
                                "post": {"kind": "fixed", "position": list(far)}},
                     "lines": [{"name": "pull", "type": "rope", "a": "eye", "b": "post", "length": L, "segments": 5}]})
    W = (m - RHO * V) * G

    def moment(th):  # about the pin, along x (a roll th turns body -z towards +y)
        p = pin + 3.0 * np.array([0.0, math.sin(th), -math.cos(th)])
        c = np.linalg.norm(far - p)
        f = EA * (c / L - 1.0) * (far - p) / c
        return np.cross(p - pin, f)[0] + np.cross(2.0 * np.array([0.0, math.sin(th), -math.cos(th)]),
                                                  [0.0, 0.0, -W])[0]

    theta = brentq(moment, 0.0, 1.5)
    pos, poses = _solve(net)
    R = poses["bob"].rotation
    assert abs(math.atan2(R[2, 1], R[2, 2]) - theta) < 1e-6
    np.testing.assert_allclose(poses["bob"].position + R @ [0.0, 0.0, 2.0], pin, atol=1e-9)


def test_a_floating_body_sinks_to_its_archimedes_draft_over_its_waterline_band():
    """A free 600 kg, 1 m^3 body with a 1 m waterline band (``height``), no lines, written 3 m
    down and tilted: it floats with m / (rho V) of its band under water, its origin (the band's
    middle, where the buoyancy acts, as in the dynamics) at z = h (1/2 - m / (rho V)); upright,
    its centre of gravity 0.1 m below its origin. Tolerance 1e-6 m (the force tolerance on the
    band's stiffness rho g V / h)."""
    m, V, h = 600.0, 1.0, 1.0
    net = from_dict({"water": _water(),
                     "bodies": {"float": {"kind": "free", "position": [0.0, 0.0, -3.0], "rpy_deg": [5.0, 0.0, 0.0],
                                          "mass": m, "volume": V, "height": h, "cg": [0.0, 0.0, -0.1],
                                          "inertia": [50.0] * 3}},
                     "points": {}, "lines": []})
    _, poses = _solve(net)
    assert abs(poses["float"].position[2] - h * (0.5 - m / (RHO * V))) < 1e-6
    assert np.linalg.norm(poses["float"].rotation[:, 2] - [0.0, 0.0, 1.0]) < 1e-6


def test_solve_balances_the_shipped_moored_buoy_and_gives_its_pose():
    """examples/networks/moored_buoy_body.toml: written 30 m down, its ropes would pull 2.38 MN;
    balanced, the three ropes carry the buoy's net buoyancy, (rho V - m) g, between them: the
    sum of their pulls' vertical parts within 1e-6 of it, the yaw, roll and pitch near zero
    (the ropes' points are 120 degrees apart, to 4 digits), and nothing named as held."""
    from mjtether.io.moordyn import load_any

    net = load_any("examples/networks/moored_buoy_body.toml")
    sol = solve(net)
    assert sol.balanced, sol.note
    b = net.bodies["buoy"]
    up = (RHO * b.volume - b.mass) * G
    pull = sum(sol.lines[n].force_b[2] for n in ("1", "2", "3"))
    assert abs(-pull - up) < 1e-6 * up
    assert max(abs(a) for a in sol.poses["buoy"].rpy_deg) < 1e-2
    assert not any("buoy" in s for s in sol.unbalanced)


def test_a_free_body_matches_moorpy():
    """The same moored buoy in MoorPy (``System.solveEquilibrium``: its own catenary and 6-DOF
    body solve): the buoy's position within 1 mm and each rope's top tension within 1e-4 (MoorPy's
    own tolerances, 1e-4 m and its catenary's 1e-6 of the tension, bound the difference)."""
    mp = pytest.importorskip("moorpy")
    from mjtether.io.moordyn import load_any

    net = load_any("examples/networks/moored_buoy_body.toml")
    sol = solve(net)
    lt = net.line_types["rope"]
    b = net.bodies["buoy"]
    ms = mp.System(depth=net.depth, rho=net.rho, g=net.gravity)
    ms.lineTypes["rope"] = {"name": "rope", "material": "rope", "d_vol": lt.diameter, "d_nom": lt.diameter,
                            "input_d": lt.diameter, "m": lt.mass_per_length, "EA": lt.EA, "MBL": 0.0, "cost": 0.0,
                            "w": lt.wet_weight(net.rho, net.gravity)}
    body = ms.addBody(0, np.array([*b.position, 0, 0, 0]), m=b.mass, v=b.volume, rCG=np.array(b.cg))
    for k, ln in enumerate(net.lines, start=1):
        anchor = ms.addPoint(1, np.array(net.points[ln.a].position))
        eye = ms.addPoint(1, np.array(net.points[ln.b].position))
        body.attachPoint(eye.number, np.array(net.points[ln.b].position))
        ms.addLine(ln.length, "rope", pointA=anchor.number, pointB=eye.number)
    ms.initialize()
    ms.solveEquilibrium(tol=1e-6)
    np.testing.assert_allclose(body.r6[:3], sol.poses["buoy"].position, atol=1e-3)
    for k, ln in enumerate(net.lines):
        top = np.linalg.norm(ms.lineList[k].fB)
        assert abs(top - sol.lines[ln.name].tension_b) < 1e-4 * top

"""``steady_state`` for non-uniform line make-ups (mjtether.cable.makeup), each against an answer that
does not come from the solver: MoorPy's own numbers, hand statics, the analytic catenary per
section, a node-by-node force balance computed here, and the uniform ``TetherSpec`` path."""

import math

import numpy as np
import pytest
from scipy.optimize import root

import mjtether as mt
from mjtether.cable.makeup import DistributedBuoyancy, LineMakeup, PointLoad, Section, load_line_types
from mjtether.quasistatic import catenary, steady_state

RHO, G = 1025.0, 9.81  # WaterColumn's defaults
UMB = "steel_armoured_umbilical_17mm"


def _wet(line_type: str) -> float:
    """Wet weight per metre (N/m) of a library line type, by hand."""
    t = load_line_types()[line_type]
    return (t.mass_per_length - RHO * math.pi * t.diameter**2 / 4) * G


# ---------------------------------------------------------------------------- uniform == TetherSpec

UNIFORM_CASES = {
    # suspended between two points in a turning current, crossing nothing
    "suspended": (mt.TetherSpec(length=300, segments=60, diameter=0.03, mass_per_length=1.5, EA=2e6),
                  mt.WaterColumn(depth=250.0, current=mt.ExponentialCurrent(1.0, decay_depth=40)),
                  [0, 0, -5], [150, 20, -200], dict(seabed=False)),
    # MoorPy's catenary case (tests/quasistatic/test_moorpy_case.py): straight-laid with friction
    "laid": (mt.TetherSpec(length=500, segments=100, diameter=0.1, mass_per_length=800 / G + RHO * math.pi * 0.01 / 4,
                           EA=7.51e12),
             mt.WaterColumn(depth=250.0), [400, 0, -50], [0, 0, -250], dict(seabed_friction=0.1)),
    # a slack cable in a current (the slack solver, allowed for a one-section make-up)
    "slack": (mt.TetherSpec(length=300, segments=60, diameter=0.03, mass_per_length=1.5, EA=2e6),
              mt.WaterColumn(depth=100.0, current=mt.ConstantCurrent(0.8)), [0, 0, 0], [50, 0, -100], {}),
}


@pytest.mark.parametrize("case", sorted(UNIFORM_CASES))
def test_uniform_makeup_gives_the_tetherspec_answer(case):
    """A one-section make-up of a TetherSpec runs the make-up code (per-element arrays, the general
    laid-part profile) and must give the TetherSpec's answer to 1e-9 relative: the same equations,
    so only rounding (measured ~1e-15) may differ."""
    tether, water, top, bottom, kw = UNIFORM_CASES[case]
    a = steady_state(tether, water, top, bottom, **kw)
    b = steady_state(LineMakeup.uniform(tether), water, top, bottom, **kw)
    scale = np.abs(a.nodes).max()
    np.testing.assert_allclose(b.nodes, a.nodes, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(b.tension, a.tension, rtol=0, atol=1e-9 * a.tension.max())
    np.testing.assert_allclose(b.top_force, a.top_force, rtol=0, atol=1e-9 * a.top_tension)
    np.testing.assert_allclose(b.bottom_force, a.bottom_force, rtol=0, atol=1e-9 * a.top_tension)
    for name in ("touchdown", "laid_length", "slack_length"):
        va, vb = getattr(a, name), getattr(b, name)
        assert (va is None and vb is None) or vb == pytest.approx(va, rel=1e-9, abs=1e-9 * tether.length), name


# ---------------------------------------------------------------------------- MoorPy test_basicU

# NREL/MoorPy tests/test_system.py::test_basicU: 100 m depth, line type getLineProps(120, 'chain'),
# anchors on the seabed at x = -200 and +200 m, floats (m = 0, v = 50 m^3) joined by lines of
# 120 / 250 / 120 m (ms1 splits the 250 m line at a free midpoint); the test asserts the two systems
# put the floats within 1 mm of each other. Their positions, as MoorPy 1.3.0 prints them
# (solveEquilibrium3(tol=0.0001)), and the msU line results:
MOORPY_FLOATS = {"msU": [(-102.5001973909, -43.1995291393), (102.5004858704, -43.1991808623)],
                 "ms1": [(-102.500253746, -43.1994658258), (102.5003819037, -43.1991775271)]}
MOORPY_H = 156696.9126570013  # horizontal tension (N), line 0 of msU
MOORPY_LAID_END, MOORPY_LAID_MID = 17.68045977833799, 45.36050925718044  # LBot of lines 0 and 1 of msU (m)
FLOAT_V = 50.0


def _half_u(n_per_m: float = 1.0):
    """By symmetry (both floats alike, anchors at +-200 m) half of the U: anchor -> 120 m -> float
    -> 125 m -> the middle of the U on the seabed at x = 0, where the other half pulls with the
    same horizontal tension. Both ends lie on the seabed: the line lifts off near the anchor and
    touches down again before the middle, as in MoorPy."""
    chain = lambda L: Section.from_line_type("studless_chain_120mm", L, int(round(L * n_per_m)))
    line = LineMakeup([chain(120.0), chain(125.0)], [PointLoad(120.0, volume=FLOAT_V, name="float")])
    ss = steady_state(line, mt.WaterColumn(depth=100.0), [-200.0, 0.0, -100.0], [0.0, 0.0, -100.0], seabed=True)
    return line, ss


def _continuum_float():
    """The float's equilibrium from the analytic catenary of each span (no discretisation): the
    horizontal tensions of the two spans equal, their vertical tensions at the float sum to its
    buoyancy."""
    w, EA = _wet("studless_chain_120mm"), load_line_types()["studless_chain_120mm"].EA
    anchor, middle = np.array([-200.0, 0, -100]), np.array([0.0, 0, -100])

    def spans(p):
        f = np.array([p[0], 0.0, p[1]])
        return (catenary(anchor, f, 120.0, w, EA=EA, seabed=True), catenary(middle, f, 125.0, w, EA=EA, seabed=True))

    def balance(p):
        c1, c2 = spans(p)
        return [(c1.H - c2.H) / (FLOAT_V * RHO * G), (c1.VF + c2.VF - FLOAT_V * RHO * G) / (FLOAT_V * RHO * G)]

    sol = root(balance, [-102.5, -43.2], tol=1e-14)
    assert sol.success and max(map(abs, sol.fun)) < 1e-12
    return sol.x, spans(sol.x)


def test_moorpy_basic_u_float_positions():
    """The floats of the U within 1 mm of MoorPy's (MoorPy's own tolerance between its two
    versions, whose answers differ by 0.3 mm; measured here: <= 0.7 mm, of which ~0.5 mm is the
    1-m lumped discretisation, below). The second float is the mirror image of the first.
    Horizontal tension to 1e-4 (MoorPy's solver tolerance; measured 7e-6), laid lengths to 1 cm."""
    line, ss = _half_u()
    j = line.section_nodes[1]
    x, z = ss.nodes[j, 0], ss.nodes[j, 2]
    for version, floats in MOORPY_FLOATS.items():
        for sign, (xm, zm) in zip((1.0, -1.0), floats):
            assert abs(sign * x - xm) < 1e-3 and abs(z - zm) < 1e-3, (version, x, z, xm, zm)
    assert ss.top_force[0] == pytest.approx(MOORPY_H, rel=1e-4)
    assert ss.top_force[1] == 0.0 and ss.top_force[2] == 0.0  # the anchor is pulled along the seabed
    assert ss.bottom_force == pytest.approx(-ss.top_force, rel=1e-12)  # frictionless seabed
    assert ss.top_laid_length == pytest.approx(MOORPY_LAID_END, abs=0.01)
    assert 2 * ss.laid_length == pytest.approx(MOORPY_LAID_MID, abs=0.02)
    assert np.all(ss.nodes[:, 2] >= -100.0 - 1e-9) and ss.nodes[-1] == pytest.approx([0, 0, -100], abs=1e-5)


def test_moorpy_basic_u_against_the_catenary_of_each_span():
    """The float's equilibrium from the analytic catenary of each span, solved here: the lumped
    line converges to it as 1/N^2 (the lumped-mass discretisation): within 1 mm at 1 m elements
    (measured 0.5 mm) and about 4 times closer at 0.5 m (ratio within [3, 5])."""
    (xc, zc), (c1, c2) = _continuum_float()
    errors = []
    for n_per_m in (0.5, 1.0):
        line, ss = _half_u(n_per_m)
        f = ss.nodes[line.section_nodes[1]]
        errors.append(math.hypot(f[0] - xc, f[2] - zc))
        if n_per_m == 1.0:
            assert errors[-1] < 1e-3
            assert ss.top_force[0] == pytest.approx(c1.H, rel=1e-4)
            assert ss.top_laid_length == pytest.approx(c1.laid_length, abs=0.01)
            assert ss.laid_length == pytest.approx(c2.laid_length, abs=0.01)
    assert 3.0 < errors[0] / errors[1] < 5.0, errors
    # and the continuum answer is MoorPy's, to its solver tolerance
    for xm, zm in MOORPY_FLOATS["msU"][:1] + MOORPY_FLOATS["ms1"][:1]:
        assert abs(xc - xm) < 5e-4 and abs(zc - zm) < 5e-4


def test_full_u_with_mid_span_touchdown_is_refused():
    """The whole U (three sections, two floats at the joints) touches down between its ends,
    which is not modelled: a clear ValueError, not a wrong answer."""
    chain = lambda L, n: Section.from_line_type("studless_chain_120mm", L, n)
    line = LineMakeup([chain(120.0, 24), chain(250.0, 50), chain(120.0, 24)],
                      [PointLoad(120.0, volume=FLOAT_V), PointLoad(370.0, volume=FLOAT_V)])
    with pytest.raises(ValueError, match="rest on the seabed between its two ends"):
        steady_state(line, mt.WaterColumn(depth=100.0), [-200, 0, -100], [200, 0, -100], seabed=True)


# ---------------------------------------------------------------------------- a free buoy

def test_free_buoy_on_a_vertical_line():
    """A buoy (0.5 m^3, 100 kg) on 50 m of polyester rope from an anchor: hand statics give the
    tension T(s) = B - w s below the buoy (B its net buoyancy, w the rope's wet weight) and the
    stretch (B L - w L^2 / 2) / EA. With the top end held at the buoy's hand-computed position the
    solver must find no force there (the buoy is in equilibrium): |top force| < 1e-9 B (Newton's
    tolerance 1e-10 of the length times the rope's stiffness EA/L gives 1e-6 N = 3e-10 B), and the
    first element's tension B - w l / 2 to 1e-9 (the lumped stretch sum is exact)."""
    rope = Section.from_line_type("polyester_rope_24mm", 50.0, 50)
    line = LineMakeup([rope], [PointLoad(0.0, mass=100.0, volume=0.5, cd_area=0.3)])
    B, w, L, EA = (RHO * 0.5 - 100.0) * G, _wet("polyester_rope_24mm"), 50.0, rope.EA
    z_buoy = -100.0 + L + (B * L - w * L * L / 2) / EA
    ss = steady_state(line, mt.WaterColumn(depth=100.0), [0, 0, z_buoy], [0, 0, -100], seabed=True, tol=1e-10)
    assert np.linalg.norm(ss.top_force) < 1e-9 * B
    assert ss.tension[0] == pytest.approx(B - w * 0.5, rel=1e-9)
    assert ss.tension[-1] == pytest.approx(B - w * 49.5, rel=1e-9)
    assert ss.bottom_force == pytest.approx([0, 0, B - w * L], rel=1e-9, abs=1e-9 * B)
    assert ss.touchdown is None


def test_buoy_in_a_current_on_a_weightless_line():
    """A small buoy (10 l, 2 kg, CdA 0.05 m^2) in a uniform 0.6 m/s current on 50 m of neutrally
    buoyant, drag-free fibre tether: the line is straight along the buoy's net force (D, 0, B),
    D = 1/2 rho CdA U^2, with tension sqrt(D^2 + B^2) and stretch L T / EA. At that hand-computed
    buoy position the top force must vanish (< 1e-9 T) and every element carry T (1e-9)."""
    U, d = 0.6, 0.00075
    fibre = Section.from_line_type("fibre_optic_microtether", 50.0, 25, mass_per_length=RHO * math.pi * d * d / 4,
                                   cd_normal=0.0, cd_tangential=0.0)
    line = LineMakeup([fibre], [PointLoad(0.0, mass=2.0, volume=0.01, cd_area=0.05)])
    B, D = (RHO * 0.01 - 2.0) * G, 0.5 * RHO * 0.05 * U * U
    T = math.hypot(B, D)
    buoy = np.array([0.0, 0.0, -100.0]) + 50.0 * (1 + T / fibre.EA) * np.array([D, 0.0, B]) / T
    water = mt.WaterColumn(depth=100.0, current=mt.ConstantCurrent(U))
    ss = steady_state(line, water, buoy, [0, 0, -100], seabed=True, tol=1e-10)
    assert np.linalg.norm(ss.top_force) < 1e-9 * T
    np.testing.assert_allclose(ss.tension, T, rtol=1e-9)


# ---------------------------------------------------------------------------- lazy wave

FLOAT_VPL = 5.607e-3  # float volume per metre (m^3/m): net -20 N/m on the umbilical with 500 kg/m^3 foam


def _lazy_wave(current=None, cd_area_per_length=0.1):
    """A lazy wave in 100 m of water: 300 m of armoured umbilical (1 m elements) from the ship at
    2 m depth to a robot on the seabed 200 m away, with floats on 120-180 m (a sag bend, a buoyant
    hog bend, then a touchdown with the rest laid, frictionless)."""
    umb = lambda L: Section.from_line_type(UMB, L, int(L))
    line = LineMakeup([umb(120.0), umb(60.0), umb(120.0)],
                      [DistributedBuoyancy(120.0, 180.0, FLOAT_VPL, mass_per_length=500 * FLOAT_VPL,
                                           cd_area_per_length=cd_area_per_length)])
    water = mt.WaterColumn(depth=100.0, current=current or mt.ConstantCurrent())
    top, bottom = np.array([0.0, 0.0, -2.0]), np.array([200.0, 0.0, -100.0])
    return line, water, top, bottom, steady_state(line, water, top, bottom, seabed=True, tol=1e-10)


def _node_balance(line, ss, water, float_cd_area):
    """Force balance of the suspended nodes, computed here from the solver's nodes and element
    tensions: E_k = T_k t_k and each element's own load (wet weight, Morison drag at its centre,
    from the section data by hand), half to each node. Returns (imbalance of nodes 1..k-2, top
    force minus E_0 - f_0 / 2), k the touchdown element (the node next to it may be held on the
    seabed, so it is left out)."""
    t_ = load_line_types()[UMB]
    s = line.node_arc_length
    l = np.diff(s)
    floats = (s[:-1] >= 120.0 - 1e-9) & (s[1:] <= 180.0 + 1e-9)
    x, T = ss.nodes, ss.tension
    dx = np.diff(x, axis=0)
    t = dx / np.linalg.norm(dx, axis=1)[:, None]
    E = T[:, None] * t
    u = water.velocity(0.5 * (x[:-1, 2] + x[1:, 2]))
    ut = (u * t).sum(axis=1)
    un = u - ut[:, None] * t
    un_abs = np.linalg.norm(un, axis=1)
    f = (0.5 * RHO * l * (t_.cd_normal * t_.diameter + np.where(floats, float_cd_area, 0.0)) * un_abs)[:, None] * un
    f += (0.5 * RHO * math.pi * t_.diameter * t_.cd_tangential * l * np.abs(ut) * ut)[:, None] * t
    area = math.pi * t_.diameter**2 / 4 + np.where(floats, FLOAT_VPL, 0.0)
    mu = t_.mass_per_length + np.where(floats, 500 * FLOAT_VPL, 0.0)
    f[:, 2] += (RHO * area - mu) * G * l
    k = int(np.searchsorted(s, ss.touchdown, side="right") - 1)
    imbalance = E[1:k - 1] - E[:k - 2] + 0.5 * (f[:k - 2] + f[1:k - 1])
    return imbalance, ss.top_force - (E[0] + 0.5 * f[0]), k


def test_lazy_wave_node_by_node_and_per_section_catenaries():
    """Without current: (1) every suspended node's forces sum to < 1e-6 of the top tension
    (measured 1e-14: the march is exact when the loads do not depend on the element's direction);
    (2) the horizontal tension is the same in every suspended element and the laid part (no
    horizontal load anywhere), to 1e-9 (leaving out the two elements at the node before the
    touchdown, which the solver holds on the seabed where the discrete line dips under it by a
    few mm); (3) each section is a plain catenary between the solver's
    own joints - the hog bend one of negative wet weight (reflected in z) - with the same
    horizontal tension and end vertical tensions to (l/a)^2 = 1.6e-3, the order of the lumped
    discretisation (a = H / w = 25 m, l = 1 m; measured 1e-5 to 2e-4), and the laid length to 1 cm."""
    line, water, top, bottom, ss = _lazy_wave()
    imbalance, top_miss, k = _node_balance(line, ss, water, 0.1)
    Ttop = ss.top_tension
    assert np.abs(imbalance).max() < 1e-6 * Ttop
    assert np.abs(top_miss).max() < 1e-6 * Ttop
    # the shape is a lazy wave: a sag bend, a hog bend, then a touchdown after the floats
    j = line.section_nodes
    z = ss.nodes[:, 2]
    assert z[:j[1]].min() < z[j[1]] - 10 and z[j[1]:j[2]].max() > z[j[2]] + 10 and z[j[1]:j[2]].max() < -2.0
    assert z[:j[1]].min() > -100.0 + 10 and ss.touchdown > 180.0 and ss.laid_length > 10.0
    # (2) horizontal tension
    dx = np.diff(ss.nodes, axis=0)
    H = ss.top_force[0]
    Hk = ss.tension[:k - 1] * np.hypot(dx[:k - 1, 0], dx[:k - 1, 1]) / np.linalg.norm(dx[:k - 1], axis=1)
    np.testing.assert_allclose(Hk, H, rtol=1e-9)
    np.testing.assert_allclose(ss.tension[k + 1:], H, rtol=1e-9)  # laid, frictionless
    assert ss.bottom_force == pytest.approx([-H, 0, 0], rel=1e-9, abs=1e-9 * H)
    assert np.all(ss.nodes[k + 1:, 2] == -100.0)
    # (3) section by section
    w1, EA = _wet(UMB), load_line_types()[UMB].EA
    w2 = w1 + (500 * FLOAT_VPL - RHO * FLOAT_VPL) * G
    assert w2 < 0
    tol = (1.0 / (H / w1)) ** 2
    sag = catenary(ss.nodes[j[1]], top, 120.0, w1, EA=EA, seabed=False)
    assert sag.H == pytest.approx(H, rel=tol) and sag.VF == pytest.approx(-ss.top_force[2], rel=tol)
    a, b = ss.nodes[j[1]] * [1, 1, -1], ss.nodes[j[2]] * [1, 1, -1]  # hog bend, reflected: sinking
    assert b[2] > a[2]
    hog = catenary(a, b, 60.0, -w2, EA=EA, seabed=False)
    assert hog.H == pytest.approx(H, rel=tol)
    lower = catenary(bottom, ss.nodes[j[2]], 120.0, w1, EA=EA, seabed=True)
    assert lower.H == pytest.approx(H, rel=tol)
    assert lower.laid_length == pytest.approx(ss.laid_length, abs=0.01)
    # the vertical tension at the second joint seen from both sections: the hog bend's (reflected)
    # vertical tension at its fairlead, and the lower catenary's, as the solver's element there
    V_joint = -(ss.tension[j[2]] * dx[j[2], 2] / np.linalg.norm(dx[j[2]]) - 0.5 * w1 * 1.0)
    assert hog.VF == pytest.approx(V_joint, rel=tol) and lower.VF == pytest.approx(V_joint, rel=tol)


def test_lazy_wave_node_balance_in_a_cross_current():
    """With a 0.2 m/s current at 1 rad to the line's plane (drag on the line and on the floats'
    extra drag area), the same node-by-node balance, by hand, holds to 1e-4 of the top tension:
    the march takes two fixed-point sweeps per element for its direction (the existing design
    for all tethers), which leaves ~1e-5 (measured 1.5e-5; 3e-14 with six sweeps)."""
    line, water, *_, ss = _lazy_wave(mt.ConstantCurrent(0.2, heading=1.0))
    imbalance, top_miss, _ = _node_balance(line, ss, water, 0.1)
    assert np.abs(imbalance).max() < 1e-4 * ss.top_tension
    assert np.abs(top_miss).max() < 1e-4 * ss.top_tension
    assert abs(ss.top_force[1]) > 10.0  # the current does push the line sideways


# ---------------------------------------------------------------------------- a clump weight

def test_clump_weight_holds_the_touchdown():
    """A 300 kg steel clump 150 m down 250 m of umbilical holds the touchdown point: for a range of
    robot positions the line touches down exactly at the clump, the suspended part is a plain
    catenary from the clump (on the seabed) to the ship - H and the top's vertical tension to
    (l/a)^2 = 2e-4 (a = 66 m; measured 3e-5) - the line pulls the clump up by less than its wet weight
    (the seabed carries the rest), and the 100 m laid beyond loses cb w per metre to friction, so
    the robot feels H - cb w 100 (to 1e-9)."""
    umb = lambda L: Section.from_line_type(UMB, L, int(L))
    m, V = 300.0, 300.0 / 7850.0
    line = LineMakeup([umb(150.0), umb(100.0)], [PointLoad(150.0, mass=m, volume=V, cd_area=0.2)])
    top, cb, w = np.array([0.0, 0.0, -2.0]), 0.5, _wet(UMB)
    ss = steady_state(line, mt.WaterColumn(depth=100.0), top, [206.0, 0.0, -100.0], seabed=True,
                      seabed_friction=cb, tol=1e-10)
    assert ss.touchdown == pytest.approx(150.0, abs=1e-9)
    clump = ss.nodes[150]
    assert clump[2] == pytest.approx(-100.0, abs=1e-6)
    H = ss.top_force[0]
    c = catenary(clump, top, 150.0, w, EA=load_line_types()[UMB].EA, seabed=False)
    tol = (1.0 / (H / w)) ** 2
    assert c.H == pytest.approx(H, rel=tol) and c.VF == pytest.approx(-ss.top_force[2], rel=tol)
    assert 0.0 < c.anchor_tension[1] < (m - RHO * V) * G
    assert -ss.bottom_force[0] == pytest.approx(H - cb * w * 100.0, rel=1e-9)


# ---------------------------------------------------------------------------- marches and refusals

def test_marching_a_makeup_down_then_up_returns_to_the_top():
    """One march down from the top with a given top force, then one up from where it ended with
    the force found there (the reversed make-up): back to the top node and force, to 1e-9. (No
    current: with one, the two marches' two-sweep fixed points for the element direction differ
    by ~1e-4.)"""
    line = LineMakeup([Section.from_line_type(UMB, 80.0, 40), Section.from_line_type("polyester_rope_24mm", 60.0, 30)],
                      [PointLoad(80.0, volume=0.05, mass=10.0, cd_area=0.1), PointLoad(110.3, mass=40.0),
                       DistributedBuoyancy(20.0, 50.0, 0.002, cd_area_per_length=0.05)])
    water = mt.WaterColumn(depth=300.0)
    down = steady_state(line, water, [0, 0, -1.0], top_force=[-300.0, 50.0, -900.0], seabed=False)
    up = steady_state(line, water, None, bottom=down.nodes[-1], bottom_force=down.bottom_force, seabed=False)
    np.testing.assert_allclose(up.nodes, down.nodes, rtol=0, atol=1e-9 * 140.0)
    np.testing.assert_allclose(up.top_force, down.top_force, rtol=0, atol=1e-9 * down.top_tension)
    np.testing.assert_allclose(up.tension, down.tension, rtol=1e-9)


def test_a_slack_makeup_is_refused_clearly():
    """A make-up too long to lie taut between its touchdown and the robot (slack on the seabed)
    is modelled for uniform lines only: NotImplementedError saying so (or, where the march meets
    the seabed first, the mid-span ValueError), never a wrong answer."""
    umb = lambda L: Section.from_line_type(UMB, L, int(L))
    line = LineMakeup([umb(150.0), umb(100.0)], [PointLoad(150.0, mass=300.0, volume=300.0 / 7850.0)])
    with pytest.raises((NotImplementedError, ValueError), match="slack|between its two ends"):
        steady_state(line, mt.WaterColumn(depth=100.0), [0, 0, -2.0], [140.0, 0, -100.0], seabed=True)
    with pytest.raises(ValueError, match="TetherSpec or a LineMakeup"):
        steady_state("umbilical", mt.WaterColumn(depth=100.0), [0, 0, 0], [10, 0, -100])

"""Slack tethers on the seabed (``steady_state`` with more cable than the straight-laid shape
takes): the free hang with zero tension at the touchdown and zero-tension cable laid in a chosen
layout, against answers that do not come from the solver: MoorPy's fully slack profile, the
straight hang of a cable in a uniform current at its critical angle, Morison's drag summed over
the returned nodes, and plane geometry of the layouts."""

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.optimize import brentq

import mjtether as mt
from mjtether.quasistatic import catenary, steady_state

W = 800.0  # submerged weight (N/m) in 1025 kg/m^3, g = 9.81
D = 0.1
TOP, BOTTOM = np.array([0.0, 0.0, 0.0]), np.array([150.0, 0.0, -200.0])
DEPTH = 200.0


def _line(length=600.0, N=120, EA=1e10, **kw):
    mu = W / 9.81 + 1025.0 * math.pi * D * D / 4
    return mt.TetherSpec(length=length, segments=N, diameter=D, mass_per_length=mu, EA=EA, **kw)


def _water(current=None):
    return mt.WaterColumn(depth=DEPTH, gravity=9.81, current=current or mt.ConstantCurrent())


def _vertical_hang(EA):
    """MoorPy's fully slack profile (``Catenary.catenary``, ProfileType 4): HF = 0 and
    VF = W * LHanging, LHanging = sqrt(2 ZF EA/W + (EA/W)^2) - EA/W, the unstretched length that
    hangs vertically to the seabed; the rest, L - LHanging, lies on it."""
    a = EA / W
    return math.sqrt(2 * DEPTH * a + a * a) - a


def _critical_hang(tether, speed, EA, w=W):
    """A cable (submerged weight ``w``, N/m) with zero tension at its lower end, in a uniform
    current of ``speed`` along +y, hangs straight, at the angle phi from the vertical where its
    weight and its Morison drag per metre add up along it. Returns (load per metre (N/m, world,
    on the cable), phi, unstretched hanging length s from drop = cos(phi) (s + |f| s^2 / (2 EA)))."""
    rho, d = 1025.0, tether.diameter
    qn = 0.5 * rho * tether.cd_normal * d
    qt = 0.5 * rho * tether.cd_tangential * math.pi * d
    u = np.array([0.0, speed, 0.0])

    def load(phi):
        t = np.array([0.0, math.sin(phi), -math.cos(phi)])  # down the cable
        ut = u @ t
        un = u - ut * t
        return qn * np.linalg.norm(un) * un + qt * abs(ut) * ut * t + np.array([0.0, 0.0, -w])

    phi = brentq(lambda p: math.sin(p) * load(p)[2] + math.cos(p) * load(p)[1], 0.0, 1.5)
    f = load(phi)
    k = np.linalg.norm(f) / (2 * EA)
    s = (math.sqrt(1 + 4 * k * DEPTH / math.cos(phi)) - 1) / (2 * k)
    return f, phi, s


# ---------------------------------------------------------------- no current: MoorPy's slack line

@pytest.mark.parametrize("cb", [0.5, 0.0])
def test_no_current_is_moorpy_fully_slack_line(cb):
    """600 m from (0,0,0) to (150,0,-200) in 200 m of water is longer than drop + span (350 m):
    MoorPy hangs LHanging vertically and lays the rest. The discrete vertical hang is exact (the
    element stretch uses the mid-element tension, exact for a linear tension), so only the
    solver's tolerance (1e-7 L = 6e-5 m of height, 3e-7 relative) remains: 1e-6 allowed.
    Friction plays no part (no tension on the seabed): cb = 0 gives the same."""
    EA = 1e10
    tether = _line(EA=EA)
    ss = steady_state(tether, _water(), TOP, BOTTOM, seabed_friction=cb)
    LH = _vertical_hang(EA)
    assert abs(ss.top_force[0]) + abs(ss.top_force[1]) <= 1e-9 * W * LH  # no horizontal load at all
    assert ss.top_force[2] == pytest.approx(-W * LH, rel=1e-6)
    assert ss.touchdown == pytest.approx(LH, rel=1e-6)
    assert ss.laid_length == pytest.approx(600.0 - LH, rel=1e-6)
    assert ss.slack_length == ss.laid_length
    np.testing.assert_array_equal(ss.bottom_force, 0.0)
    x, l = ss.nodes, tether.segment_length
    assert x[:, 2].min() >= -DEPTH - 1e-6
    np.testing.assert_allclose(x[-1], BOTTOM, rtol=0, atol=1e-6 * 600.0)
    # the hang is vertical under the top; its elements are stretched by T / EA exactly
    k = int(ss.touchdown // l)  # the touchdown element
    np.testing.assert_allclose(x[:k + 1, :2], 0.0, atol=1e-9)
    seg = np.linalg.norm(np.diff(x, axis=0), axis=1)
    np.testing.assert_allclose(seg[:k], l * (1 + ss.tension[:k] / EA), rtol=1e-9)
    # laid: on the seabed, no tension, unstretched; zero-tension links are at most l apart and
    # exactly l except where the default straight layout folds back on itself (one element)
    np.testing.assert_array_equal(x[k + 1:, 2], -DEPTH)
    np.testing.assert_array_equal(ss.tension[k + 1:], 0.0)
    laid = seg[k + 1:]
    assert laid.max() <= l * (1 + 1e-12)
    assert np.sum(np.abs(laid - l) > 1e-9 * l) <= 1
    # the touchdown element: node k hangs above the touchdown point P = (0, 0, -200), node k+1
    # lies on the seabed; together the two pieces are one element long
    P = np.array([0.0, 0.0, -DEPTH])
    assert np.linalg.norm(x[k] - P) + np.linalg.norm(x[k + 1] - P) == pytest.approx(l, rel=1e-6)


# ---------------------------------------------------------------- with a current

@pytest.mark.parametrize("cb", [0.5, 0.0])
def test_uniform_current_hangs_straight_at_the_critical_angle(cb):
    """0.5 m/s along +y: the hang is the straight critical-angle hang (``_critical_hang``, from
    Morison's formula and a 1-D root); the discrete hang is exactly straight, so again only the
    solver's tolerance remains: 1e-6. The top takes the whole drag; the laid cable carries no
    tension, so a frictionless seabed holds it as well (the same answer for cb = 0)."""
    EA = 1e10
    tether = _line(EA=EA)
    ss = steady_state(tether, _water(mt.ConstantCurrent(0.5, math.pi / 2)), TOP, BOTTOM, seabed_friction=cb)
    f, phi, s = _critical_hang(tether, 0.5, EA)
    np.testing.assert_allclose(ss.top_force, f * s, rtol=0, atol=1e-6 * np.linalg.norm(f * s))
    assert ss.touchdown == pytest.approx(s, rel=1e-6)
    assert 0.01 < phi < 0.03  # a heavy cable: about 1 degree
    # the hanging nodes lie on the straight line from the top at phi
    k = int(ss.touchdown // tether.segment_length)
    t = np.array([0.0, math.sin(phi), -math.cos(phi)])
    rel = ss.nodes[:k + 1] - TOP
    np.testing.assert_allclose(rel - np.outer(rel @ t, t), 0.0, atol=1e-6)
    np.testing.assert_array_equal(ss.tension[k + 1:], 0.0)
    np.testing.assert_array_equal(ss.bottom_force, 0.0)
    assert ss.touchdown + ss.laid_length == pytest.approx(600.0, rel=1e-12)
    assert ss.slack_length == ss.laid_length


def _morison(nodes, tether, water):
    """Weight and Morison drag (N, world) on the polyline ``nodes``, element by element at the
    element centres: 1/2 rho Cdn d l |u_n| u_n + 1/2 rho Cdt pi d l |u_t| u_t - w l z."""
    e = np.diff(nodes, axis=0)
    t = e / np.linalg.norm(e, axis=1)[:, None]
    zc = 0.5 * (nodes[1:, 2] + nodes[:-1, 2])
    u = water.velocity(zc)
    rho = water.rho(zc)
    ut = np.sum(u * t, axis=1)
    un = u - ut[:, None] * t
    q = 0.5 * rho * D * tether.segment_length
    f = (q * tether.cd_normal * np.linalg.norm(un, axis=1))[:, None] * un
    f += (q * tether.cd_tangential * math.pi * np.abs(ut) * ut)[:, None] * t
    f[:, 2] -= W * tether.segment_length
    return f


@pytest.mark.parametrize("cb", [0.5, 0.0])
def test_exponential_current_top_takes_the_drag(cb):
    """A surface current of 1.5 m/s decaying over 40 m, across the span: the hang is curved
    (no closed form). Its horizontal top force is the drag on the hanging elements summed from
    the returned nodes with Morison's formula (the touchdown element counted by its hanging
    fraction, along the element above it), within 1 % (the brief's tolerance; the part element's
    direction is the only approximation, a fraction of one element's drag of 40). No tension on
    the seabed, the lengths add up to L, and cb changes nothing."""
    tether = _line()
    water = _water(mt.ExponentialCurrent(1.5, decay_depth=40.0, heading=math.pi / 2))
    ss = steady_state(tether, water, TOP, BOTTOM, seabed_friction=cb)
    l = tether.segment_length
    k = int(ss.touchdown // l)
    phi = ss.touchdown / l - k
    f = _morison(ss.nodes[:k + 1], tether, water)
    total = f.sum(axis=0) + phi * f[-1]
    assert np.linalg.norm(ss.top_force[:2] - total[:2]) <= 0.01 * np.linalg.norm(total[:2])
    assert ss.top_force[2] == pytest.approx(total[2], rel=0.01)
    assert ss.top_force[1] > 100.0  # a real drag, pulling the top downstream
    np.testing.assert_array_equal(ss.tension[k + 1:], 0.0)
    np.testing.assert_array_equal(ss.bottom_force, 0.0)
    assert ss.touchdown + ss.laid_length == pytest.approx(600.0, rel=1e-12)
    assert ss.slack_length == ss.laid_length
    assert np.all(ss.nodes[:, 2] >= -DEPTH - 1e-6)
    np.testing.assert_allclose(ss.nodes[-1], BOTTOM, atol=1e-6 * 600.0)


def test_slack_or_straight_laid_rule():
    """Slack exactly when the free hang leaves at least |R - P| of cable for the seabed. A light
    line (30 mm, 3000 kg/m^3) in 1 m/s hangs at 44 degrees (``_critical_hang``, x and y swapped):
    with the current along +x, P lies 194 m downstream, past R, so L* = s + |R - P| = 322 m,
    and a 330 m line, shorter than drop + span (350 m), is slack; with the current along -x,
    L* = 622 m: a 625 m line is slack, a 572 m one, longer than drop + span, is straight-laid,
    pulled taut to R (cb = 0: the bottom feels the laid tension). The touchdown of the slack
    ones is the critical hang's to 1e-5 (the hang is exactly straight; solver tolerance), and so
    is the top force, less what the cable above the surface at the top does not carry."""
    light = mt.TetherSpec(length=400.0, segments=80, diameter=0.03, density=3000.0, EA=1e9)
    f, phi, s = _critical_hang(light, 1.0, 1e9, w=(3000.0 - 1025.0) * light.area * 9.81)
    reach = s * math.sin(phi)  # horizontal sweep of the hang (its stretch, ~1e-6, is far below the margins)
    assert 190.0 < reach < 200.0
    cases = [(0.0, reach, 8.0, True), (math.pi, -reach, 3.0, True), (math.pi, -reach, -50.0, False)]
    for heading, P, margin, slack in cases:
        L = s + abs(BOTTOM[0] - P) + margin
        ss = steady_state(replace(light, length=L), _water(mt.ConstantCurrent(1.0, heading)), TOP, BOTTOM,
                          seabed_friction=0.0)
        assert (ss.slack_length > 0) == slack, (heading, L)
        assert (np.linalg.norm(ss.bottom_force) == 0) == slack, (heading, L)
        if slack:
            assert ss.touchdown == pytest.approx(s, rel=1e-5)
            want = s * np.array([math.cos(heading) * f[1], 0.0, f[2]])  # the current along +-x
            # less the buoyancy and drag (f + its weight in air) of the cable above the surface at
            # the top, its axis starting at z = 0: a hoof of the cylinder, (2/3) r^3 tan(phi), as a
            # length of it (3 mm; 2e-5 of the top force)
            dry = 2 * (light.diameter / 2) * math.tan(phi) / (3 * math.pi)
            want -= dry * np.array([math.cos(heading) * f[1], 0.0, f[2] + 3000.0 * light.area * 9.81])
            np.testing.assert_allclose(ss.top_force, want, rtol=0, atol=1e-5 * np.linalg.norm(want))
        else:
            assert ss.bottom_force[0] < 0  # pulled back towards the top
    assert s + abs(BOTTOM[0] - reach) + 8.0 < 350.0 < s + abs(BOTTOM[0] + reach) - 50.0


# ---------------------------------------------------------------- layouts

def _kasa_circle(p):
    """Least-squares circle through horizontal points p (n, 2): centre, radii."""
    A = np.c_[2 * p, np.ones(len(p))]
    sol = np.linalg.lstsq(A, (p * p).sum(axis=1), rcond=None)[0]
    c = sol[:2]
    return c, np.linalg.norm(p - c, axis=1)


def _layout_chord(layout, b, angle):
    """End of a layout of unit length from the origin along b (plane geometry, by hand)."""
    n = np.array([-b[1], b[0]])
    if layout == "straight":
        return b
    if layout == "arc":
        return (math.sin(angle) * b + (1 - math.cos(angle)) * n) / angle
    half = angle / 2  # two arcs of length 1/2 and radius 1/angle
    r = 1 / angle
    m = r * (math.sin(half) * b + (1 - math.cos(half)) * n)
    b2 = math.cos(half) * b + math.sin(half) * n
    n2 = np.array([-b2[1], b2[0]])
    return m + r * (math.sin(half) * b2 - (1 - math.cos(half)) * n2)


@pytest.mark.parametrize("layout", ["straight", "arc", "s"])
def test_layouts(layout):
    """No current, so P = (0, 0, -200) under the top. The slack leaves R along b = (0, 1) for
    L_s, where L_s + |R + L_s c - P| = L - LHanging (solved here by bisection), then a straight
    piece joins it to P. Checked to 1e-6 m: straight layout nodes on the ray from R along b at
    their material distance; arc nodes on one circle (a least-squares fit) of radius L_s / theta
    with its centre to the left of b; "s" nodes on two such circles of radius L_s / theta, left
    then right; the joining piece on the segment P-Q0 at its material distance from P."""
    EA, angle = 1e10, 2.0
    tether = _line(EA=EA)
    b = np.array([0.0, 1.0])
    ss = steady_state(tether, _water(), TOP, BOTTOM, layout=layout, layout_direction=(0.0, 2.0, 5.0),
                      layout_angle=angle)
    LH = _vertical_hang(EA)
    LB = 600.0 - LH
    c = _layout_chord(layout, b, angle)
    R, P = BOTTOM[:2], np.zeros(2)
    Ls = brentq(lambda x: x + np.linalg.norm(R + x * c - P) - LB, 0.0, LB, xtol=1e-12)
    Q0 = R + Ls * c
    l = tether.segment_length
    v = 600.0 - np.arange(121) * l  # material distance from R
    on = v <= Ls - 1e-9
    xy = ss.nodes[on, :2]
    assert on.sum() > 20
    if layout == "straight":
        np.testing.assert_allclose(xy, R + np.outer(v[on], b), atol=1e-6)
    elif layout == "arc":
        centre, r = _kasa_circle(xy)
        np.testing.assert_allclose(r, Ls / angle, atol=1e-6)
        d = centre - R
        assert b[0] * d[1] - b[1] * d[0] > 0  # turning left
    else:
        first, second = v[on] <= Ls / 2 + 1e-9, v[on] >= Ls / 2 - 1e-9
        centre1, r1 = _kasa_circle(xy[first])
        centre2, r2 = _kasa_circle(xy[second])
        np.testing.assert_allclose(np.r_[r1, r2], Ls / angle, atol=1e-6)
        d = centre1 - R
        assert b[0] * d[1] - b[1] * d[0] > 0  # the first arc turns left
        # the second turns the other way: its centre is across the common tangent, 2 r away
        assert np.linalg.norm(centre2 - centre1) == pytest.approx(2 * Ls / angle, abs=1e-6)
    # the joining piece: laid nodes beyond the layout lie on the segment P-Q0
    k = int(ss.touchdown // l)
    join = ~on & (np.arange(121) > k)
    assert join.sum() > 5
    rel = ss.nodes[join, :2] - P
    u = (Q0 - P) / np.linalg.norm(Q0 - P)
    np.testing.assert_allclose(rel - np.outer(rel @ u, u), 0.0, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(rel, axis=1), 600.0 - v[join] - LH, atol=1e-6)  # unstretched
    np.testing.assert_array_equal(ss.nodes[k + 1:, 2], -DEPTH)


def test_layout_does_not_change_the_hang():
    """With a current too, the hang and the top force are the same for every layout and
    direction (bit for bit: the hang is solved before the layout is laid)."""
    water = _water(mt.ExponentialCurrent(1.0, decay_depth=50.0, heading=0.3))
    tether = _line(N=60)
    states = [steady_state(tether, water, TOP, BOTTOM, seabed_friction=0.3, layout=lay, layout_direction=d)
              for lay in ("straight", "arc", "s") for d in (None, (1.0, -1.0))]
    k = int(states[0].touchdown // tether.segment_length)
    for ss in states[1:]:
        np.testing.assert_array_equal(ss.top_force, states[0].top_force)
        np.testing.assert_array_equal(ss.nodes[:k + 1], states[0].nodes[:k + 1])
        assert ss.touchdown == states[0].touchdown


# ---------------------------------------------------------------- bad input, and the old answer

def test_layout_bad_input():
    tether, water = _line(N=20), _water()
    with pytest.raises(ValueError, match=r"steady_state\.layout must be one of 'straight', 'arc', 's'"):
        steady_state(tether, water, TOP, BOTTOM, layout="coil")
    for bad in [(0, 0, 0), (0.0, 0.0, 1.0), (np.nan, 1.0), (1.0,), "east"]:
        with pytest.raises(ValueError, match=r"steady_state\.layout_direction"):
            steady_state(tether, water, TOP, BOTTOM, layout_direction=bad)
    for bad in [0.0, -1.0, 2 * math.pi, math.inf, "wide"]:
        with pytest.raises(ValueError, match=r"steady_state\.layout_angle"):
            steady_state(tether, water, TOP, BOTTOM, layout="arc", layout_angle=bad)


@pytest.mark.parametrize("cb", [0.0, 0.5])
def test_not_too_long_is_the_straight_laid_catenary(cb):
    """400 m from (0,0,0) to (350,0,-200): the free hang (200 m) leaves 200 m, less than the 350 m
    to R, so the cable is straight-laid as before, whatever the layout arguments: the analytic
    elastic catenary's fairlead force within 0.5 % (the lumped discretisation is O(1/N^2), 0.1 %
    at N = 100 in test_quasistatic), and its zero-tension length max(L_B - H / (cb w), 0)."""
    tether = _line(length=400.0, N=120, EA=5e8)
    bottom = np.array([350.0, 0.0, -200.0])
    a = steady_state(tether, _water(), TOP, bottom, seabed_friction=cb)
    b = steady_state(tether, _water(), TOP, bottom, seabed_friction=cb, layout="arc", layout_direction=(1, 1),
                     layout_angle=1.0)
    np.testing.assert_array_equal(a.nodes, b.nodes)
    np.testing.assert_array_equal(a.top_force, b.top_force)
    c = catenary(bottom, TOP, 400.0, W, EA=5e8, cb=cb)
    assert np.linalg.norm(a.top_force - c.fairlead_force) <= 5e-3 * np.linalg.norm(c.fairlead_force)
    assert a.laid_length == pytest.approx(c.laid_length, rel=5e-3)
    want = max(c.laid_length - c.H / (cb * W), 0.0) if cb > 0 else 0.0
    assert a.slack_length == pytest.approx(want, abs=5e-3 * 400.0)
    if cb == 0:
        assert np.linalg.norm(a.bottom_force) > 0.1 * c.H

"""Quasi-static solvers against independent answers: MoorPy's published catenary cases, the
analytic catenary, the dynamic MuJoCo tether, and the catenary limit of Khan et al.'s method."""

import math

import numpy as np
import pytest
from conftest import new_spec

import mjtether as mt
from mjtether.quasistatic import catenary, initial_state, khan2023, steady_state

# ---------------------------------------------------------------- analytic catenary vs MoorPy

# NREL/MoorPy tests/test_catenary.py: inputs (XF, ZF, L, EA, w, CB) and the published
# (fAH, fAV, fBH, fBV, LBot). A negative CB there means the seabed is below the anchor: no contact.
MOORPY = [
    ((400, 200, 500.0, 7.51e12, 800.0, 5.0), (0.0, 0.0, -96643.43501616362, -237751.75997440016, 202.81030003199982)),
    ((400, 200, 500.0, 7.51e12, 800.0, 0.0), (96643.42815934008, 0.0, -96643.42815934008, -237751.75535996316,
                                              202.81030580004602)),
    ((400, 200, 500.0, 7.51e12, 800.0, 0.1), (80418.60434855078, 0.0, -96643.42877136687, -237751.75577183915,
                                              202.81030528520108)),
    ((400, 200, 500.0, 7.51e12, 200.0, -372.7), (43694.580989249596, -22365.599350216216, -43694.580989249596,
                                                 -77634.40064978378, 0.0)),
    ((89.9, 59.2, 130.0, 7.51e8, 881.05, -372.7), (31373.229006023103, -26650.341270116318, -31373.229006023103,
                                                   -87886.15872988368, 0.0)),
]


@pytest.mark.parametrize("case", range(len(MOORPY)))
def test_catenary_matches_moorpy(case):
    """MoorPy solves to a tolerance of 1e-6 on its equations; we agree to 1e-6 of the largest force."""
    (XF, ZF, L, EA, w, CB), want = MOORPY[case]
    c = catenary([0, 0, 0], [XF, 0, ZF], L, w, EA=EA, cb=max(CB, 0.0), seabed=CB >= 0)
    got = (c.anchor_force[0], c.anchor_force[2], c.fairlead_force[0], c.fairlead_force[2], c.laid_length)
    scale = max(abs(x) for x in want[:4])
    np.testing.assert_allclose(got[:4], want[:4], rtol=0, atol=1e-6 * scale)
    assert got[4] == pytest.approx(want[4], abs=1e-6 * L)
    # the profile closes on the fairlead
    np.testing.assert_allclose(c.points([L])[0], [XF, 0, ZF], atol=1e-6 * L)


# ---------------------------------------------------------------- steady_state vs catenary

def _heavy_line(N, EA):
    d = 0.1
    mu = 800.0 / 9.81 + 1025.0 * math.pi * d * d / 4  # 800 N/m submerged in 1025 kg/m^3
    return mt.TetherSpec(length=500.0, segments=N, diameter=d, mass_per_length=mu, EA=EA)


@pytest.mark.parametrize("cb", [0.0, 0.5])
def test_steady_state_with_seabed_equals_catenary(cb):
    """No current: the discrete steady state on a seabed is the elastic catenary with friction.
    N = 100 elements; the lumped discretisation is O(1/N^2), 0.1 % here; 0.5 % allowed."""
    tether = _heavy_line(100, EA=5e8)
    water = mt.WaterColumn(depth=200.0, gravity=9.81)
    ss = steady_state(tether, water, top=[400, 0, 0], bottom=[0, 0, -200], seabed_friction=cb)
    c = catenary([0, 0, -200], [400, 0, 0], 500.0, 800.0, EA=5e8, cb=cb)
    for got, want in ((ss.top_force, c.fairlead_force), (ss.bottom_force, c.anchor_force)):
        assert np.linalg.norm(got - want) <= 5e-3 * np.linalg.norm(c.fairlead_force)
    assert ss.laid_length == pytest.approx(c.laid_length, rel=5e-3)
    s = np.arange(101) * 5.0
    np.testing.assert_allclose(ss.nodes[::-1], c.points(s), atol=5e-3 * 500)


def test_steady_state_suspended_equals_catenary():
    """Both ends suspended in still water, 3-D orientation: end forces within 0.5 %."""
    tether = mt.TetherSpec(length=120.0, segments=60, diameter=0.03, density=3000.0, EA=1e7)
    water = mt.WaterColumn(depth=300.0)
    top, bottom = np.array([5.0, -3.0, 0.0]), np.array([60.0, 50.0, -60.0])
    ss = steady_state(tether, water, top, bottom)
    w = tether.wet_weight_per_length(1025.0)
    c = catenary(bottom, top, 120.0, w, EA=1e7, seabed=False)
    scale = np.linalg.norm(c.fairlead_force)
    assert np.linalg.norm(ss.top_force - c.fairlead_force) <= 5e-3 * scale
    assert np.linalg.norm(ss.bottom_force - c.anchor_force) <= 5e-3 * scale
    assert ss.touchdown is None and ss.laid_length == 0.0


def test_one_end_and_its_force_reproduce_the_two_point_solution():
    """Marching down from the top force, or up from the bottom force, of a solved two-point
    problem lands on the other end: the same discrete equations solved from either side.
    5 mm allowed on 60 m: each element's balance is solved by two fixed-point sweeps, whose
    remainder differs with the direction of marching (2 mm seen upwards, 1e-5 of the length)."""
    water, v = CASES["cross current"]
    two = steady_state(TETHER, water, TOP, BOTTOM, tow_velocity=v)
    down = steady_state(TETHER, water, TOP, top_force=two.top_force, tow_velocity=v)
    up = steady_state(TETHER, water, None, BOTTOM, bottom_force=two.bottom_force, tow_velocity=v)
    for ss in (down, up):
        assert np.abs(ss.nodes - two.nodes).max() < 5e-3
        assert np.linalg.norm(ss.top_force - two.top_force) < 1e-3 * two.top_tension
        assert np.linalg.norm(ss.bottom_force - two.bottom_force) < 1e-3 * two.top_tension


# ---------------------------------------------------------------- dynamic tether vs steady_state

DT = 0.005
TETHER = mt.TetherSpec(length=60.0, segments=30, diameter=0.03, density=2000.0, EA=2e6)
TOP, BOTTOM = np.array([0.0, 0.0, 0.0]), np.array([40.0, 0.0, -30.0])
CASES = {
    # (a) uniform current in the plane of the ends
    "in-plane current": (mt.WaterColumn(depth=100.0, current=mt.ConstantCurrent(0.5, 0.0)), np.zeros(3)),
    # (b) a current across the plane of the ends, 1.0 m/s at the surface to 0.2 m/s at 30 m
    "cross current": (mt.WaterColumn(depth=100.0, density=mt.LinearDensity(1025.0, 1020.0, 100.0),
                                     current=mt.TabulatedCurrent([0.0, 30.0], [1.0, 0.2], [np.pi / 2] * 2)),
                      np.zeros(3)),
    # (c) both ends towed at 0.5 m/s in still water, at an angle to the plane of the ends
    "towed": (mt.WaterColumn(depth=100.0), np.array([0.4, 0.3, 0.0])),
}


def _simulate(water, v_tow, duration, nodes=None, velocity=None, tether=TETHER, record_every=1):
    """Run the dynamic tether between two mocap supports (a ship and a robot) moved at
    ``v_tow`` before every step. Returns the history, one entry per ``record_every`` steps, of
    (start force, end force, nodes relative to the start support's path).

    A mocap body has no velocity, so the soft ``connect`` (``solref`` time constant 2 dt,
    critical damping) trails a moving support by 4 dt v_tow; the supports start 3 dt v_tow ahead
    of the cable (plus the dt v_tow of the first update), where the steady towed state has them.
    """
    spec = new_spec(DT)
    lead = 3 * DT * np.asarray(v_tow)
    for body, p in (("ship", TOP), ("robot", BOTTOM)):
        spec.worldbody.add_body(name=body, mocap=True, pos=p + lead)
    if nodes is not None:
        nodes = nodes + lead  # add_tether wants the end nodes on the supports; moved back below
    tm = mt.add_tether(spec, tether, mt.BodyPoint("ship"), mt.BodyPoint("robot"), water=water, nodes=nodes)
    hist = []
    with mt.Simulation(spec, water, tethers=[tm]) as sim:
        bt = sim.tether()
        if nodes is not None:
            bt.set_state(sim.data, nodes=nodes - lead, velocity=velocity)
        sim.forward()
        for k in range(int(round(duration / DT))):
            sim.data.mocap_pos[:] += v_tow * DT
            sim.step()
            if (k + 1) % record_every == 0:
                rel = bt.nodes(sim.data) - (sim.data.mocap_pos[0] - lead - TOP)
                hist.append((bt.end_force(sim.data, "start"), bt.end_force(sim.data, "end"), rel))
    return hist


@pytest.mark.parametrize("case", list(CASES))
def test_dynamic_tether_settles_to_steady_state(case):
    """Started from the default sagged shape, the MuJoCo tether settles (100 s, mean of the last
    10 s) to the steady state: end forces within 2 %, nodes within 1 % of the length.
    (The slowest case, the in-plane current, decays with a time constant of about 20 s.)"""
    water, v = CASES[case]
    ss = steady_state(TETHER, water, TOP, BOTTOM, tow_velocity=v)
    hist = _simulate(water, v, 100.0, record_every=20)
    tail = hist[-int(10.0 / (20 * DT)):]
    f_start = np.mean([h[0] for h in tail], axis=0)
    f_end = np.mean([h[1] for h in tail], axis=0)
    nodes = np.mean([h[2] for h in tail], axis=0)
    assert np.linalg.norm(f_start - ss.top_force) <= 0.02 * np.linalg.norm(ss.top_force)
    assert np.linalg.norm(f_end - ss.bottom_force) <= 0.02 * np.linalg.norm(ss.bottom_force)
    assert np.abs(nodes - ss.nodes).max() <= 0.01 * TETHER.length
    if case == "cross current":  # a genuinely 3-D shape
        assert np.abs(ss.nodes[:, 1]).max() > 0.1 * TETHER.length, "the shape is not 3-D"


@pytest.mark.parametrize("case,inextensible", [("cross current", True), ("towed", False)])
def test_initial_state_has_no_transient(case, inextensible):
    """Started from ``initial_state`` (positions and, towed, velocities), the end tensions stay
    within 2 % of their steady values over the first 10 s (every step)."""
    water, v = CASES[case]
    tether = mt.TetherSpec(length=60.0, segments=30, diameter=0.03, density=2000.0,
                           EA=None if inextensible else 2e6)
    ss = initial_state(tether, water, TOP, BOTTOM, timestep=DT, tow_velocity=v)
    hist = _simulate(water, v, 10.0, nodes=ss.nodes, velocity=ss.velocity, tether=tether)
    for i, want in ((0, ss.top_tension), (1, ss.tow_tension)):
        t = np.array([np.linalg.norm(h[i]) for h in hist])
        assert np.abs(t / want - 1).max() < 0.02, (i, np.abs(t / want - 1).max())


# ---------------------------------------------------------------- strong surface current

SURFACE = dict(length=150.0, diameter=0.025, density=2500.0, EA=5e6)
SURFACE_BOTTOM = np.array([80.0, 0.0, -100.0])  # on the seabed of 100 m of water


def test_steady_state_in_a_strong_surface_current():
    """A 150 m tether (d = 25 mm, 2500 kg/m^3) from a fairlead at the surface to a point on the
    seabed 100 m down and 80 m away, in an exponential surface current of 0.5, 1 or 2 m/s
    decaying over 10, 20 or 40 m, with 10, 20, 40 or 80 elements: 36 cases. Started from the
    catenary's top force alone, 14 of them stalled with the bottom end 122 m off: the current's
    drag puts three times that horizontal force on the top, and a shot whose first element's
    far end rises out of the water lands some 200 m from one whose end stays in (the shot map
    jumps between them). Started with the top's share of the drag added (``_drag_share``), 35
    converge (the 36th, 40 elements at 2 m/s over 40 m, stalls 1.9 m off); required: 35.

    Then one that used to stall (80 elements, 2 m/s over 20 m) against the dynamic model,
    started from its steady state (``initial_state``) on a frictionless seabed: both end
    tensions, averaged over the last 2 s of 5 s, within 1 % of the steady state's (measured
    -0.15 % and +0.3 %; the first steps ring by 12 % at the bottom end while the seabed contact
    takes up the laid cable's weight, which is why a run pre-rolls)."""
    top = np.zeros(3)
    converged = []
    for N in (10, 20, 40, 80):
        for U in (0.5, 1.0, 2.0):
            for decay in (10.0, 20.0, 40.0):
                water = mt.WaterColumn(depth=100.0, current=mt.ExponentialCurrent(U, decay_depth=decay))
                try:
                    steady_state(mt.TetherSpec(segments=N, **SURFACE), water, top, SURFACE_BOTTOM, seabed=True)
                except RuntimeError:
                    continue
                converged.append((N, U, decay))
    assert len(converged) >= 35, f"{36 - len(converged)} of 36 did not converge"
    assert (80, 2.0, 20.0) in converged

    dt, d = 0.005, SURFACE["diameter"]
    tether = mt.TetherSpec(segments=80, **SURFACE)
    current = mt.ExponentialCurrent(2.0, decay_depth=20.0)
    water = mt.WaterColumn(depth=100.0, current=current)
    bottom = SURFACE_BOTTOM + [0.0, 0.0, d / 2]  # the cable's axis one radius up
    ss = initial_state(tether, mt.WaterColumn(depth=100.0 - d / 2, current=current), top, bottom, timestep=dt,
                       seabed=True)
    assert ss.laid_length > 0.0  # (the case has a laid part: the seabed matters)
    spec = new_spec(dt)
    mt.builder.add_seabed(spec, water, friction=0.0)
    tm = mt.add_tether(spec, tether, mt.FixedPoint(top), mt.FixedPoint(bottom), water=water, nodes=ss.nodes,
                       seabed_friction=0.0)
    tensions = []
    with mt.Simulation(spec, water, [tm]) as sim:
        bt = sim.tether()
        for _ in range(int(round(5.0 / dt))):
            sim.step()
            if sim.time > 3.0:
                tensions.append([bt.end_tension(sim.data, "start"), bt.end_tension(sim.data, "end")])
    settled = np.mean(tensions, axis=0) / [ss.top_tension, ss.tow_tension] - 1.0
    assert np.abs(settled).max() < 0.01, f"end tensions settled {np.round(100 * settled, 2)} % from the steady state"


# ---------------------------------------------------------------- Khan et al. (2023)

def _still(depth=600.0):
    return mt.WaterColumn(depth=depth, density=mt.LinearDensity(1025.0, 980.0, 500.0), gravity=9.8)


@pytest.mark.parametrize("variant", ["printed", "consistent"])
def test_khan_without_drag_is_an_inverted_catenary(variant):
    """With no current and no walker speed both variants reduce to C_1 tan(theta) + C_2 = W_s:
    constant horizontal tension, and a vertical tension that *grows* by W_s,i going down, i.e.
    the weight acts upwards (the sign of W_s in the paper's Eq. 18). The profile is then the
    mirror image of the analytic hanging catenary through the mirrored ends (0.5 % of L; the
    recursion puts each element's weight at one end, an O(l) offset)."""
    water = mt.WaterColumn(depth=600.0, density=mt.ConstantDensity(1000.0), gravity=9.8)
    r = khan2023(water=water, robot_speed=0.0, length=300.0, cable_density=1200.0, variant=variant)
    H = r.tension * np.cos(r.theta)
    np.testing.assert_allclose(H, H[0], rtol=1e-9)
    assert np.all(np.diff(r.theta) > 0)  # steeper going down: the opposite of a hanging cable
    w = math.pi * 0.02**2 / 4 * 9.8 * 200.0
    c = mt.catenary([0, 0, 0], [r.X[-1], 0.0, -r.Z[-1]], 300.0, w)
    mirrored = np.c_[r.X, np.zeros(201), -r.Z]
    np.testing.assert_allclose(mirrored, c.points(np.linspace(0, 300.0, 201)), atol=5e-3 * 300.0)


def test_khan_consistent_variant_satisfies_eq21():
    """The re-derived Eqs. 22-23 solve the paper's Eq. 21 (both rows) element by element;
    the printed ones do not."""
    water = mt.WaterColumn(depth=600.0, density=mt.LinearDensity(1025.0, 980.0, 500.0),
                           current=mt.ExponentialCurrent(5 * mt.KNOT, decay_depth=55 / math.log(100)), gravity=9.8)
    res = {}
    for variant in ("printed", "consistent"):
        r = khan2023(water=water, robot_speed=2 * mt.KNOT, length=1500.0, variant=variant)
        N, l, d = 200, 1500.0 / 200, 0.02
        zc = 0.5 * (r.Z[1:] + r.Z[:-1])
        rho0 = water.rho(zc)
        V2 = (2 * mt.KNOT * (np.arange(N) + 0.5) / N + water.current.speed_at(zc)) ** 2
        D1 = 0.5 * 0.015 * rho0 * math.pi * d * l * V2
        D2 = 0.5 * 1.0 * rho0 * d * l * V2
        Ws = math.pi * d * d / 4 * l * 9.8 * (1025.0 - rho0)
        s, c = np.sin(r.theta), np.cos(r.theta)
        T, C1, C2 = r.tension, r.tension * c, -r.tension * s
        row1 = -T[1:] * c[1:] + D1[1:] * c[1:] ** 3 + D2[1:] * s[1:] ** 3 + C1[:-1]
        row2 = T[1:] * s[1:] - D1[1:] * c[1:] ** 2 * s[1:] + D2[1:] * s[1:] ** 2 * c[1:] + C2[:-1] - Ws[1:]
        res[variant] = max(np.abs(row1).max(), np.abs(row2).max()) / T.max()
    # 1e-3: each element's mid-depth (for rho_0 and V) comes from one predictor-corrector step,
    # not iterated to convergence; that leaves residuals of about 1e-4 of the largest tension
    assert res["consistent"] < 1e-3
    assert res["printed"] > 1e-2


def test_khan_finds_the_length_to_reach_the_seabed():
    r = khan2023(water=_still(), robot_speed=1.0, depth=300.0, variant="consistent")
    assert r.depth == pytest.approx(300.0, abs=1e-3)
    assert r.length > 300.0


# ---------------------------------------------------------------- bad input

def test_quasistatic_bad_input():
    water = mt.WaterColumn(depth=100.0)
    with pytest.raises(ValueError, match="variant"):
        khan2023(water=water, robot_speed=1.0, length=100.0, variant="paper")
    with pytest.raises(ValueError, match="exactly one of length"):
        khan2023(water=water, robot_speed=1.0)
    with pytest.raises(ValueError, match="give top and bottom"):
        steady_state(TETHER, water, TOP)
    with pytest.raises(ValueError, match="below the seabed"):
        steady_state(TETHER, water, TOP, [10, 0, -150])
    with pytest.raises(ValueError, match="cannot span"):
        steady_state(mt.TetherSpec(length=10.0, segments=5), water, TOP, [20, 0, 0])
    with pytest.raises(ValueError, match="tow_velocity"):
        steady_state(TETHER, water, TOP, BOTTOM, tow_velocity=[1, 2])
    with pytest.raises(ValueError, match="catenary.cb"):
        catenary([0, 0, 0], [10, 0, 5], 20.0, 10.0, cb=-1)

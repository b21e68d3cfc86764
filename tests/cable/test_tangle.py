"""The tangle monitor (``mjtether.cable.tangle``, ``Readouts.tangle``, the ``[tangle]`` thresholds)
against answers worked out here: brute-force distances between densely sampled segments,
closed-form geometry (a hairpin's legs, a figure crossing itself, a cable wound round a post),
and, in a run, the first moment the prescribed hull comes within the threshold of the recorded
cable, found by sampling both."""

import math

import numpy as np
import pytest

from mjtether.cable import tangle
from mjtether.scenario.runner import run
from mjtether.scenario import load_scenario

RNG = np.random.default_rng(7)


def test_segment_distance_is_the_brute_force_minimum():
    """Random, parallel and degenerate segment pairs: the distance is never above the minimum
    over 401 x 401 sample points of the two, and within what that sampling can miss (its spacing
    squared over the segments' scale: 1e-3)."""
    u = np.linspace(0.0, 1.0, 401)
    for k in range(200):
        p0, p1, q0, q1 = RNG.normal(size=(4, 3))
        if k % 5 == 0:
            q1 = q0 + 0.7 * (p1 - p0)  # parallel
        if k % 7 == 0:
            p1 = p0.copy()  # a point
        d, cp, cq = tangle.segment_distance(p0, p1, q0, q1)
        P, Q = p0 + u[:, None] * (p1 - p0), q0 + u[:, None] * (q1 - q0)
        brute = np.min(np.linalg.norm(P[:, None] - Q[None], axis=-1))
        assert d <= brute + 1e-12 and brute - d < 1e-3
        assert np.linalg.norm(cp - cq) == pytest.approx(d, abs=1e-12)


def test_vehicle_clearance_is_the_nearest_of_every_element():
    """Random cables round a random capsule with points: the clearance is the minimum over every
    element of its distance to the capsule's axis less its radius, and to each point (the
    monitor looks only at the elements that can be nearest: it must find that minimum)."""
    for _ in range(200):
        n = int(RNG.integers(5, 80))
        nodes = np.cumsum(RNG.normal(size=(n + 1, 3)), axis=0)
        a, b, pts = RNG.normal(size=3) * 3, RNG.normal(size=3) * 3, RNG.normal(size=(4, 3)) * 2
        c, _ = tangle.vehicle_clearance(nodes, a, b, 0.2, pts, 0.0)
        d, _, _ = tangle.segment_distance(nodes[:-1], nodes[1:], a, b)
        dp, _, _ = tangle.segment_distance(nodes[:-1][:, None], nodes[1:][:, None], pts[None], pts[None])
        assert c == pytest.approx(min(d.min() - 0.2, dp.min()), abs=1e-12)


def _hairpin(gap: float, leg: float = 50.0) -> np.ndarray:
    a = np.linspace(0.0, leg, 51)
    turn = np.linspace(-math.pi / 2, math.pi / 2, 31)[1:-1]
    return np.r_[np.c_[a[::-1], np.zeros_like(a), np.zeros_like(a)],
                 np.c_[gap / 2 * np.cos(turn), gap / 2 + gap / 2 * np.sin(turn), np.zeros_like(turn)],
                 np.c_[a, np.full_like(a, gap), np.zeros_like(a)]]


def test_self_clearance_of_a_hairpin_and_of_a_crossing():
    """A hairpin with legs 3 m apart: its clearance from itself is 3 m (pairs with at least 10 m
    of cable between them), with no crossing, and +inf when looked for only up to 2.5 m; an S
    whose end passes 2 m under its start crosses itself once in plan view, 2 m apart."""
    c, _, n = tangle.self_clearance(_hairpin(3.0), 10.0)
    assert c == pytest.approx(3.0, abs=1e-9) and n == 0
    assert tangle.self_clearance(_hairpin(3.0), 10.0, reach=2.5)[0] == math.inf
    s = np.array([[0.0, 0.0, 0.0], [20.0, 0.0, 0.0], [20.0, 20.0, -1.0], [10.0, 20.0, -2.0], [10.0, -10.0, -2.0]])
    c, at, n = tangle.self_clearance(s, 10.0)
    assert n == 1 and c == pytest.approx(2.0, abs=1e-9)
    assert at == pytest.approx([10.0, 0.0, -1.0], abs=1e-9)


def test_wrap_angle_of_a_cable_wound_round_a_post():
    """One and a half turns round a post within the radius: 3 pi; a straight cable past it: the
    angle it subtends there (2 atan(5/1) for nodes from -5 to 5 m at 1 m off)."""
    a = np.linspace(0.0, 3 * math.pi, 200)
    helix = np.c_[1.5 * np.cos(a), 1.5 * np.sin(a), -0.1 * a]
    assert tangle.wrap_angle(helix, [0.0, 0.0, 0.0], 2.0) == pytest.approx(3 * math.pi, rel=1e-9)
    line = np.c_[np.linspace(-5.0, 5.0, 101), np.ones(101), np.zeros(101)]
    assert tangle.wrap_angle(line, [0.0, 0.0, 0.0], 10.0) == pytest.approx(2 * math.atan(5.0), rel=1e-9)


@pytest.mark.parametrize("noise", [1e-17, -1e-17, 0.0])
def test_a_cable_hanging_straight_under_a_vehicle_winds_nothing(noise):
    """A catenary in the x-z plane through the hull's centre in plan view: 0, whatever sign the
    rounding gives its nodes' y (a +-pi sweep each side had made 0, 180 or 360 deg by CPU)."""
    x = np.linspace(-3.0, 3.0, 41)
    y = noise * np.sign(x) * np.abs(x)  # (the sign of each half's offset from rounding)
    cable = np.c_[x, y, 0.1 * x * x - 5.0]
    assert tangle.wrap_angle(cable, [0.0, 0.0, -4.0], 3.58) == 0.0
    cable[:, 1] += 0.05  # 5 cm to one side of the centre: the angle it subtends, 2 atan(3 / 0.05)
    assert tangle.wrap_angle(cable, [0.0, 0.0, -4.0], 3.58) == pytest.approx(2 * math.atan(3.0 / 0.05), rel=1e-9)


CROSSING = """
[simulation]
duration = 82.0
timestep = 0.005
output_interval = 0.1
[water]
depth = 200.0
[tether]
length = 20.0
segments = 8
diameter = 0.001
density = 1025.0
cd_normal = 1.2
cd_tangential = 0.01
EA = 5.0e4
[winch]
mode = "free"
start_empty = true
max_length = 150.0
max_rate = 3.0
max_accel = 1.0
drum_damping = 0.5
[ship]
fairlead_z = -50.0
[robot]
type = "vehicle"
vehicle = "remus100"
position = [0.8, 0.0, -50.0]
heading_deg = 0.0
path = [[0.0, 0.0, 0.0, 0.0], [10.0, 1.0, 0.0, 0.0], [30.0, 1.0, 0.0, 0.0], [50.0, 1.0, 180.0, 0.0],
        [65.0, 1.0, 180.0, 0.0], [75.0, 1.0, 270.0, 0.0]]
[tangle]
clearance_m = 1.0
"""


def test_a_scripted_crossing_is_logged_when_and_where_it_happens():
    """A REMUS 100 (its hull a capsule 1.6 m long, 0.095 m in radius) lays fibre along x, turns
    back and runs south across it. The event (threshold 1 m) is logged at the first recorded
    sample where the hull, placed by integrating the prescribed path here (1e-4 s steps), comes
    within 1 m of the recorded cable, each sampled at 5 cm (the cable within 1.6 m of arc of
    the tow point left out), and at the cable's point nearest the hull then, within 0.1 m."""
    sc = load_scenario(text=CROSSING)
    rows, hist, info = run(sc)
    events = info["tangle_events"]
    assert len(events) == 1 and events[0]["kind"] == "vehicle"
    r = np.array(sc.robot.path)
    dt = 1e-4
    t = np.arange(0.0, 82.0 + dt, dt)
    U = np.interp(t, r[:, 0], r[:, 1])
    h = np.radians(np.interp(t, r[:, 0], r[:, 2]))
    x, y = 0.8 + np.cumsum(U * np.cos(h)) * dt, np.cumsum(U * np.sin(h)) * dt
    first = None
    for k, tk in enumerate(rows[:, 0]):
        if tk < 60.0:
            continue
        i = int(round(tk / dt))
        axis = np.c_[x[i] + np.linspace(-0.705, 0.705, 30) * math.cos(h[i]),
                     y[i] + np.linspace(-0.705, 0.705, 30) * math.sin(h[i]), np.full(30, -50.0)]
        nodes = hist["nodes"][k]
        s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(nodes, axis=0), axis=1))]
        pts = np.concatenate([np.linspace(a, b, max(2, int(np.linalg.norm(b - a) / 0.05) + 1))
                              for a, b, sa in zip(nodes[:-1], nodes[1:], s[:-1]) if s[-1] - sa >= 1.6 + 5.0])
        d = np.linalg.norm(pts[:, None] - axis[None], axis=-1) - 0.095
        if d.min() < 1.0:
            first = (tk, pts[np.unravel_index(np.argmin(d), d.shape)[0]])
            break
    assert first is not None
    assert events[0]["time_s"] == pytest.approx(first[0], abs=1e-9)
    assert np.linalg.norm(np.array(events[0]["place_m"]) - first[1]) < 0.1


def test_the_vehicle_clearance_starts_at_the_hull_not_at_the_first_node():
    """A 1.6 m hull (capsule on x from 0 to 1.6 m, radius 0.1 m, tow point at its tail, x = 0) and a
    cable whose first element, 5 m long, runs from the tow point to (4, 0.5, 0): past 1.6 m of arc
    (the hull's length, left out) it runs alongside the hull. By hand: at arc 1.6 m the cable is at
    (1.5876, 0.1985, 0), 0.1985 m from the hull's axis, so 0.0985 m from its surface, the nearest
    point of the rest of the element (it only moves away). The whole first element used to be left
    out (clearance +inf)."""
    from mjtether.cable import tangle as tg
    nodes = np.array([[0.0, 0.0, 0.0], [4.0, 0.5, 0.0], [8.0, 1.0, 0.0]])[::-1]  # (tied at the last node)
    c, where = tg.vehicle_clearance(nodes, [0.0, 0.0, 0.0], [1.6, 0.0, 0.0], 0.1, exclude=1.6, from_end=True)
    u = np.array([4.0, 0.5, 0.0]) / np.hypot(4.0, 0.5)
    p = 1.6 * u
    assert c == pytest.approx(p[1] - 0.1, abs=1e-9)
    assert np.allclose(where, p, atol=1e-9)


def _cables(rng):
    """Cables of every shape the monitor meets, (name, nodes): straight, coiled, looping
    (random walks in 3-D), lying on itself on a flat seabed (a random walk in plan, z = 0, with
    segments that touch and overlap), a hairpin whose legs touch, a figure of eight crossing
    itself in plan at different depths, and lattice walks (integer nodes: exact ties)."""
    for k in range(60):
        n = int(rng.integers(3, 160))
        u = np.linspace(0.0, 1.0, n + 1)
        a = u * rng.uniform(1.0, 8.0) * 2 * math.pi
        yield "straight", np.c_[50 * u, 3 * u, -10 * u] + rng.normal(scale=0.01, size=(n + 1, 3))
        yield "coiled", np.c_[2 * np.cos(a), 2 * np.sin(a), -rng.uniform(0.0, 3.0) * u]
        yield "looping", np.cumsum(rng.normal(size=(n + 1, 3)), axis=0)
        yield "on itself", np.cumsum(rng.normal(size=(n + 1, 3)) * [1.0, 1.0, 0.0], axis=0)
        yield "eight", np.c_[5 * np.sin(a), 5 * np.sin(a) * np.cos(a), -u - 2 * np.cos(a)]
        yield "lattice", np.cumsum(rng.integers(-1, 2, size=(n + 1, 3)) * [1, 1, 0], axis=0).astype(float)
    yield "hairpin", _hairpin(0.0)
    yield "hairpin", _hairpin(3.0)


def _brute_self(nodes, min_arc, reach):
    """The self-clearance and the plan crossings worked out here over every pair of elements:
    distances from ``segment_distance`` (checked above against sampling), crossings by the
    sign of the plan cross products (a proper crossing: each segment's ends on either side of
    the other's line)."""
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(nodes, axis=0), axis=1))]
    i, j = np.triu_indices(len(nodes) - 1, 1)
    far = s[j] - s[i + 1] >= min_arc
    i, j = i[far], j[far]
    d, _, _ = tangle.segment_distance(nodes[i], nodes[i + 1], nodes[j], nodes[j + 1])
    best = d.min() if len(d) and d.min() <= reach else math.inf

    def side(p, q, r):
        return np.sign((q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0]))

    a, b, c, e = nodes[i], nodes[i + 1], nodes[j], nodes[j + 1]
    crossings = int(np.count_nonzero((side(a, b, c) * side(a, b, e) < 0) & (side(c, e, a) * side(c, e, b) < 0)))
    return best, crossings


def _einsum_sums_as_the_twins() -> bool:
    """Whether this NumPy's einsum sums three products as the twins do, (x + z) + y (then the
    twins give the reference's numbers bit for bit)."""
    x, y = np.random.default_rng(1).normal(size=(2, 1000, 3))
    return np.array_equal(np.einsum("...i,...i", x, y), (x[:, 0] * y[:, 0] + x[:, 2] * y[:, 2]) + x[:, 1] * y[:, 1])


def _a_self_witness(nodes, at, best, min_arc):
    """Whether ``at`` is midway between two elements ``best`` apart (within 1e-9 m), with at
    least ``min_arc`` of arc between them: within best / 2 of both."""
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(nodes, axis=0), axis=1))]
    d, _, _ = tangle.segment_distance(at, at, nodes[:-1], nodes[1:])
    near = np.flatnonzero(d <= best / 2 + 1e-9)
    return any(s[j] - s[i + 1] >= min_arc for i in near for j in near if j > i)


def test_the_compiled_twins_give_the_reference_numbers():
    """The compiled self- and vehicle clearances (``compiled=True``) against the NumPy and scipy
    reference (``compiled=False``) on 362 cables of every shape (``_cables``), each with three
    (min_arc, reach) and three exclusions. Where this NumPy's einsum sums as the twins do (it
    does here: the golden runs need it), every number is the same bit for bit. Elsewhere: the
    same plan crossings exactly, the distances to 1e-12 m (rounding), the vehicle's nearest
    cable point to 1e-9 m, and the self-clearance's place (which a near tie between two pairs,
    as between a coil's turns, may move from one to the other) checked as a witness: midway
    between two elements that far apart (to 1e-9 m) with min_arc between them. On the random
    3-D walks (general position: no two elements within 1e-9 in plan by chance) the twin also
    matches the brute force over every pair worked out here (``_brute_self``): the distance to
    1e-12 m, the proper crossings exactly. The compiled cables are sized as runs have them (3
    to 160 elements) plus the two hairpins."""
    rng = np.random.default_rng(45)
    exact = _einsum_sums_as_the_twins()
    for name, x in _cables(rng):
        for min_arc, reach in ((2.0, 2.0), (5.0, 10.0), (0.5, 0.5)):
            ref = tangle.self_clearance(x, min_arc, reach, compiled=False)
            fast = tangle.self_clearance(x, min_arc, reach, compiled=True)
            assert fast[2] == ref[2], (name, min_arc)
            if exact:
                assert fast[0] == ref[0] and np.array_equal(fast[1], ref[1]), (name, min_arc, ref, fast)
            elif math.isfinite(ref[0]):
                assert abs(fast[0] - ref[0]) <= 1e-12 and _a_self_witness(x, fast[1], fast[0], min_arc), (name, min_arc)
            else:
                assert fast[0] == math.inf and np.array_equal(fast[1], x[0])
            if name == "looping":
                best, crossings = _brute_self(x, min_arc, reach)
                assert fast[2] == crossings and (fast[0] == best == math.inf or abs(fast[0] - best) <= 1e-12)
        c = x.mean(axis=0)
        a, b, pts = c + rng.normal(size=3) * 3, c + rng.normal(size=3) * 3, c + rng.normal(size=(4, 3)) * 2
        for exclude, from_end, p in ((0.0, True, pts), (1.5, True, ()), (3.0, False, pts)):
            ref = tangle.vehicle_clearance(x, a, b, 0.2, p, exclude, from_end, compiled=False)
            fast = tangle.vehicle_clearance(x, a, b, 0.2, p, exclude, from_end, compiled=True)
            if exact:
                assert fast[0] == ref[0] and np.array_equal(fast[1], ref[1]), (name, exclude, ref, fast)
            else:
                assert fast[0] == ref[0] or abs(fast[0] - ref[0]) <= 1e-12, (name, exclude)
                assert np.allclose(fast[1], ref[1], rtol=0.0, atol=1e-9), (name, exclude)


def test_the_twins_answer_the_hand_worked_cases():
    """The compiled self-clearance on the closed-form cases above: the hairpin's legs 3 m
    apart (no crossing; nothing within 2.5 m), the S crossing itself once 2 m below, at
    (10, 0, -1), and a cable lying straight back over itself in plan 1 m below: clearance
    1 m, and as crossings every pair of its legs' elements that meet or overlap in plan with
    3 m of arc between them. Its legs are elements 0-9 (x from i to i + 1) and 12-21 (x from
    21 - j to 22 - j), the turn two vertical elements of 0.5 m at x = 10, so the arc between
    elements i and j of the two legs is j - i - 2 m, and they meet in plan where
    |i - (21 - j)| <= 1: 25 pairs (the turn's elements meet no element 3 m of arc away)."""
    c, _, n = tangle.self_clearance(_hairpin(3.0), 10.0, compiled=True)
    assert c == pytest.approx(3.0, abs=1e-9) and n == 0
    assert tangle.self_clearance(_hairpin(3.0), 10.0, reach=2.5, compiled=True)[0] == math.inf
    s = np.array([[0.0, 0.0, 0.0], [20.0, 0.0, 0.0], [20.0, 20.0, -1.0], [10.0, 20.0, -2.0], [10.0, -10.0, -2.0]])
    c, at, n = tangle.self_clearance(s, 10.0, compiled=True)
    assert n == 1 and c == pytest.approx(2.0, abs=1e-9)
    assert at == pytest.approx([10.0, 0.0, -1.0], abs=1e-9)
    x = np.r_[np.c_[np.arange(11.0), np.zeros(11), np.zeros(11)],
              np.c_[10.0, 0.0, -0.5], np.c_[np.arange(10.0, -1.0, -1.0), np.zeros(11), np.full(11, -1.0)]]
    c, _, n = tangle.self_clearance(x, 3.0, compiled=True)
    legs = [(i, j) for i in range(10) for j in range(12, 22) if abs(i - (21 - j)) <= 1 and j - i - 2 >= 3]
    assert c == pytest.approx(1.0, abs=1e-12) and n == len(legs) == 25
    assert tangle.self_clearance(x, 3.0, compiled=False)[2] == 25


def test_the_monitor_runs_at_the_samples_only(monkeypatch):
    """In a run the tangle monitor (self-clearance, and vehicle clearance for a vehicle) is
    worked out once per recorded row, not per step: 2 s at 5 ms steps recorded every 0.1 s
    is 400 steps and 21 rows, and so 21 evaluations of each."""
    from mjtether.scenario import readouts

    calls = {"self": 0, "vehicle": 0}

    def counted(name, f):
        def wrapper(*args, **kwargs):
            calls[name] += 1
            return f(*args, **kwargs)
        return wrapper

    monkeypatch.setattr(readouts.tangle, "self_clearance", counted("self", tangle.self_clearance))
    monkeypatch.setattr(readouts.tangle, "vehicle_clearance", counted("vehicle", tangle.vehicle_clearance))
    sc = load_scenario(text=CROSSING, overrides=["simulation.duration=2.0"])
    rows, _, _ = run(sc)
    assert len(rows) == 21 and calls == {"self": 21, "vehicle": 21}


@pytest.mark.parametrize("compiled", [False, True])
def test_a_vehicle_point_is_measured_from_the_nearest_point_of_the_cable(compiled):
    """A 10 m element along x and a thruster 1 m off its middle, at (5, 1, 0), the hull 50 m
    away: the clearance is 1 m (by hand), at (5, 0, 0)."""
    nodes = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]])
    c, where = tangle.vehicle_clearance(nodes, [0.0, 50.0, 0.0], [1.0, 50.0, 0.0], 0.1, [[5.0, 1.0, 0.0]],
                                        compiled=compiled)
    assert c == pytest.approx(1.0, abs=1e-12) and np.allclose(where, [5.0, 0.0, 0.0], atol=1e-12)

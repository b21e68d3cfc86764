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

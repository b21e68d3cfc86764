"""The tangle monitor's geometry (pure NumPy, no MuJoCo): how close a cable comes to a vehicle
and to itself, how often it crosses itself in plan view, and how far it wraps round a vehicle.

The cable is its polyline of nodes (m, world, (n+1, 3)); a vehicle is a capsule (its hull: the
segment between two points and a radius) and a set of points (its thrusters, fins, propeller).
Units SI; angles in radians.
"""

from __future__ import annotations

import math

import numpy as np


def segment_distance(p0, p1, q0, q1):
    """Shortest distances between segments p0-p1 and q0-q1 (arrays broadcast over leading
    axes, last axis 3), and the closest points on each: (distance, point on p, point on q)."""
    p0, p1, q0, q1 = (np.asarray(a, dtype=float) for a in (p0, p1, q0, q1))
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a = np.einsum("...i,...i", d1, d1)
    e = np.einsum("...i,...i", d2, d2)
    f = np.einsum("...i,...i", d2, r)
    c = np.einsum("...i,...i", d1, r)
    b = np.einsum("...i,...i", d1, d2)
    eps = 1e-18
    denom = a * e - b * b
    # s on p (clamped), then t on q for that s, then s again for the clamped t (Ericson 2005, 5.1.9)
    s = np.where(denom > eps * np.maximum(a * e, eps), np.clip((b * f - c * e) / np.where(denom > 0, denom, 1.0),
                                                               0.0, 1.0), 0.0)
    s = np.where(a <= eps, 0.0, s)
    t = np.where(e <= eps, 0.0, (b * s + f) / np.where(e > eps, e, 1.0))
    t_c = np.clip(t, 0.0, 1.0)
    s = np.where(a <= eps, 0.0, np.where(t != t_c, np.clip((b * t_c - c) / np.where(a > eps, a, 1.0), 0.0, 1.0), s))
    t = t_c
    cp = p0 + s[..., None] * d1
    cq = q0 + t[..., None] * d2
    return np.linalg.norm(cp - cq, axis=-1), cp, cq


def arc_lengths(nodes: np.ndarray) -> np.ndarray:
    """Arc length (m) at each node from the first."""
    return np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(nodes, axis=0), axis=1))]


def vehicle_clearance(nodes: np.ndarray, hull_a, hull_b, radius: float, points=(), exclude: float = 0.0,
                      from_end: bool = True) -> tuple[float, np.ndarray]:
    """Smallest clearance (m) between the cable ``nodes`` and a vehicle: its hull, the capsule
    ``hull_a``-``hull_b`` of ``radius``, and its ``points`` (thrusters, fins, propeller), leaving
    out the cable within ``exclude`` m of arc from the end it is tied to (the last node with
    ``from_end``, else the first; an element that reaches beyond it counts from there on).
    Returns (clearance, the cable's closest point); clearance is negative where the cable passes
    through the hull, +inf with no cable left to check."""
    s = arc_lengths(nodes)
    s = s[-1] - s if from_end else s
    keep = np.maximum(s[:-1], s[1:]) > exclude  # elements reaching beyond the exclusion
    if not keep.any():
        return math.inf, nodes[-1 if from_end else 0].copy()
    p0, p1 = nodes[:-1][keep].copy(), nodes[1:][keep].copy()
    s0, s1 = s[:-1][keep], s[1:][keep]
    # an element partly within the exclusion: only its part beyond it (the hull's length of arc
    # from the tow point), not the whole element, is left out
    for q, sq, other, so in ((p0, s0, p1, s1), (p1, s1, p0, s0)):
        cut = sq < exclude
        if cut.any():
            f = ((exclude - sq[cut]) / (so[cut] - sq[cut]))[:, None]
            q[cut] = q[cut] + f * (other[cut] - q[cut])
    a, b = np.asarray(hull_a, dtype=float), np.asarray(hull_b, dtype=float)
    # only elements that can be the nearest: midpoints within the nearest midpoint's distance
    # plus an element and the vehicle's extent (its points included)
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    centre = 0.5 * (a + b)
    extent = max(0.5 * float(np.linalg.norm(b - a)) + radius,
                 float(np.max(np.linalg.norm(pts - centre, axis=1))) if len(pts) else 0.0)
    mid = np.linalg.norm(0.5 * (p0 + p1) - centre, axis=1)
    near = mid <= mid.min() + float(np.max(np.linalg.norm(p1 - p0, axis=1))) + 2.0 * extent
    p0, p1 = p0[near], p1[near]
    d, cp, _ = segment_distance(p0, p1, a, b)
    d = d - radius
    k = int(np.argmin(d))
    best, where = float(d[k]), cp[k]
    if len(pts):
        dp, cpp, _ = segment_distance(p0[:, None, :], p1[:, None, :], pts[None, :, :], pts[None, :, :])
        i, j = np.unravel_index(int(np.argmin(dp)), dp.shape)
        if dp[i, j] < best:
            best, where = float(dp[i, j]), cpp[i, j]
    return best, np.asarray(where, dtype=float).copy()


def self_clearance(nodes: np.ndarray, min_arc: float, reach: float | None = None) -> tuple[float, np.ndarray, int]:
    """The cable's clearance from itself: the smallest distance (m) between two of its elements
    with at least ``min_arc`` m of cable between them (nearer ones are neighbours, not a loop),
    looked for up to ``reach`` m (default ``min_arc``), the place (midway between the closest
    points) and the number of such pairs that cross in plan view (their x-y projections
    intersect). +inf (and the first node) when no such pair is within ``reach``. Candidate pairs
    come from a k-d tree of the elements' midpoints (scipy), so a long cable costs about as much
    per element as a short one."""
    from scipy.spatial import cKDTree

    reach = min_arc if reach is None else reach
    n = len(nodes) - 1
    if n < 2:
        return math.inf, nodes[0].copy(), 0
    s = arc_lengths(nodes)
    mids = 0.5 * (nodes[:-1] + nodes[1:])
    span = float(np.max(np.diff(s)))  # the longest element: two can touch with midpoints this far apart

    def far_pairs(points, r):
        ij = cKDTree(points).query_pairs(r, output_type="ndarray")
        if len(ij) == 0:
            return ij
        i, j = ij.min(axis=1), ij.max(axis=1)
        keep = (s[j] - s[i + 1]) >= min_arc
        return np.c_[i[keep], j[keep]]

    best, at = math.inf, nodes[0].copy()
    ij = far_pairs(mids, reach + span)
    if len(ij):
        i, j = ij[:, 0], ij[:, 1]
        d, cp, cq = segment_distance(nodes[i], nodes[i + 1], nodes[j], nodes[j + 1])
        k = int(np.argmin(d))
        if d[k] <= reach:
            best, at = float(d[k]), 0.5 * (cp[k] + cq[k])
    crossings = 0
    ij = far_pairs(mids[:, :2], span)
    if len(ij):
        i, j = ij[:, 0], ij[:, 1]
        flat = np.array([1.0, 1.0, 0.0])
        dxy, _, _ = segment_distance(nodes[i] * flat, nodes[i + 1] * flat, nodes[j] * flat, nodes[j + 1] * flat)
        crossings = int(np.count_nonzero(dxy <= 1e-9))
    return best, at, crossings


def wrap_angle(nodes: np.ndarray, centre, radius: float) -> float:
    """How far the cable winds round a vehicle in plan view (rad, >= 0): the angle its nodes
    within ``radius`` (m, horizontally) of ``centre`` sweep about it, summed over consecutive
    nodes that are both that close (one full turn of cable round the hull: 2 pi)."""
    c = np.asarray(centre, dtype=float)
    rel = nodes[:, :2] - c[:2]
    near = np.hypot(rel[:, 0], rel[:, 1]) <= radius
    ang = np.arctan2(rel[:, 1], rel[:, 0])
    both = near[:-1] & near[1:]
    if not both.any():
        return 0.0
    step = (np.diff(ang) + math.pi) % (2 * math.pi) - math.pi
    return float(abs(step[both].sum()))

"""The tangle monitor's geometry (no MuJoCo): how close a cable comes to a vehicle and to itself,
how often it crosses itself in plan view, and how far it wraps round a vehicle.

The cable is its polyline of nodes (m, world, (n+1, 3)); a vehicle is a capsule (its hull: the
segment between two points and a radius) and a set of points (its thrusters, fins, propeller).
Units SI; angles in radians.

The NumPy code is the reference. ``vehicle_clearance`` and ``self_clearance`` also have compiled
twins (``_vehicle_kernel``, ``_self_kernel``; numba, through ``physics.compiled.jit``), which run
where the compiled kernels run (``compiled.backend()``) or when asked (``compiled=True``). They
do the same arithmetic in the same order (NumPy's einsum sums three terms as (x + z) + y, and so
do they), so they give the reference's numbers bit for bit where NumPy sums so (checked in
``tests/cable/test_tangle.py``), to rounding anywhere. The self-clearance's twin visits the pairs
of elements in (i, j) order instead of taking a k-d tree's candidates, measuring only those that
can be nearest and skipping along the cable past those that cannot (consecutive midpoints are
at most the longest element apart); ties go to the first pair in (i, j) order in both. The
monitor runs once per recorded sample (``Readouts.tangle_record``), not per step. Measured
(``scripts/bench_tangle.py``, a 100 m cable of 100 elements): the self-clearance 120-580 us in
NumPy and scipy, 15-50 us compiled; MoorDyn's 20-segment chain records a sample in 84 us
instead of 270 us.
"""

from __future__ import annotations

import math

import numpy as np

from mjtether.physics import compiled as _compiled
from mjtether.physics.compiled import jit


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
    s = np.where((e <= eps) & (a > eps), np.clip(-c / np.where(a > eps, a, 1.0), 0.0, 1.0), s)  # (q a point)
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


def _use_compiled(compiled: bool | None) -> bool:
    return _compiled.backend() == "numba" if compiled is None else bool(compiled)


def vehicle_clearance(nodes: np.ndarray, hull_a, hull_b, radius: float, points=(), exclude: float = 0.0,
                      from_end: bool = True, compiled: bool | None = None) -> tuple[float, np.ndarray]:
    """Smallest clearance (m) between the cable ``nodes`` and a vehicle: its hull, the capsule
    ``hull_a``-``hull_b`` of ``radius``, and its ``points`` (thrusters, fins, propeller), leaving
    out the cable within ``exclude`` m of arc from the end it is tied to (the last node with
    ``from_end``, else the first; an element that reaches beyond it counts from there on).
    Returns (clearance, the cable's closest point); clearance is negative where the cable passes
    through the hull, +inf with no cable left to check. ``compiled``: run the compiled twin
    (True), the NumPy reference (False), or whichever the compiled kernels say (None)."""
    if _use_compiled(compiled):
        f = np.ascontiguousarray
        best, where = _vehicle_kernel(f(nodes, dtype=float), f(hull_a, dtype=float), f(hull_b, dtype=float),
                                      float(radius), f(np.asarray(points, dtype=float).reshape(-1, 3)),
                                      float(exclude), bool(from_end))
        return best, where
    return _vehicle_clearance_numpy(np.asarray(nodes, dtype=float), hull_a, hull_b, radius, points, exclude,
                                    from_end)


def _vehicle_clearance_numpy(nodes, hull_a, hull_b, radius, points, exclude, from_end):
    """``vehicle_clearance`` in NumPy (the reference)."""
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


def self_clearance(nodes: np.ndarray, min_arc: float, reach: float | None = None,
                   compiled: bool | None = None) -> tuple[float, np.ndarray, int]:
    """The cable's clearance from itself: the smallest distance (m) between two of its elements
    with at least ``min_arc`` m of cable between them (nearer ones are neighbours, not a loop),
    looked for up to ``reach`` m (default ``min_arc``), the place (midway between the closest
    points; of two pairs equally close, the first in element order) and the number of such pairs
    that cross in plan view (their x-y projections intersect). +inf (and the first node) when no
    such pair is within ``reach``. ``compiled``: run the compiled twin (True), the NumPy
    reference (False), or whichever the compiled kernels say (None)."""
    reach = min_arc if reach is None else reach
    nodes = np.asarray(nodes, dtype=float)
    if len(nodes) - 1 < 2:
        return math.inf, nodes[0].copy(), 0
    if _use_compiled(compiled):
        best, at, crossings = _self_kernel(np.ascontiguousarray(nodes), float(min_arc), float(reach))
        return best, at, int(crossings)
    return _self_clearance_numpy(nodes, min_arc, reach)


def _self_clearance_numpy(nodes, min_arc, reach):
    """``self_clearance`` in NumPy (the reference): candidate pairs from a k-d tree of the
    elements' midpoints (scipy), so a long cable costs about as much per element as a short one."""
    from scipy.spatial import cKDTree

    s = arc_lengths(nodes)
    mids = 0.5 * (nodes[:-1] + nodes[1:])
    span = float(np.max(np.diff(s)))  # the longest element: two can touch with midpoints this far apart

    def far_pairs(points, r):
        ij = cKDTree(points).query_pairs(r, output_type="ndarray")
        if len(ij) == 0:
            return ij
        i, j = ij.min(axis=1), ij.max(axis=1)
        keep = (s[j] - s[i + 1]) >= min_arc
        i, j = i[keep], j[keep]
        order = np.lexsort((j, i))  # (element order: the tree's own order is arbitrary, and decides ties)
        return np.c_[i[order], j[order]]

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
    nodes that are both that close (one full turn of cable round the hull: 2 pi). An element
    whose plan view passes over the centre (within 1e-9 of ``radius``: a cable hanging straight
    under the vehicle) winds nothing: its sweep of +-pi would take its sign from rounding."""
    c = np.asarray(centre, dtype=float)
    rel = nodes[:, :2] - c[:2]
    near = np.hypot(rel[:, 0], rel[:, 1]) <= radius
    ang = np.arctan2(rel[:, 1], rel[:, 0])
    a, b = rel[:-1], rel[1:]
    over = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) <= 1e-9 * radius * np.hypot(*(b - a).T)
    both = near[:-1] & near[1:] & ~over
    if not both.any():
        return 0.0
    step = (np.diff(ang) + math.pi) % (2 * math.pi) - math.pi
    return float(abs(step[both].sum()))


# --------------------------------------------------------------------------- compiled twins


@jit
def _dot(ax, ay, az, bx, by, bz):
    """``np.einsum("...i,...i")`` of two 3-vectors, summed in the order NumPy's einsum sums
    three terms (two lanes, the third term into the first: (x + z) + y), so that the twins
    give its numbers bit for bit (anywhere else they agree to rounding)."""
    return (ax * bx + az * bz) + ay * by


@jit
def _closest(p0x, p0y, p0z, p1x, p1y, p1z, q0x, q0y, q0z, q1x, q1y, q1z):
    """``segment_distance`` of one pair, the same operations in the same order: (distance,
    closest point on p (x, y, z), closest point on q (x, y, z))."""
    d1x, d1y, d1z = p1x - p0x, p1y - p0y, p1z - p0z
    d2x, d2y, d2z = q1x - q0x, q1y - q0y, q1z - q0z
    rx, ry, rz = p0x - q0x, p0y - q0y, p0z - q0z
    a = _dot(d1x, d1y, d1z, d1x, d1y, d1z)
    e = _dot(d2x, d2y, d2z, d2x, d2y, d2z)
    f = _dot(d2x, d2y, d2z, rx, ry, rz)
    c = _dot(d1x, d1y, d1z, rx, ry, rz)
    b = _dot(d1x, d1y, d1z, d2x, d2y, d2z)
    eps = 1e-18
    denom = a * e - b * b
    s = min(max((b * f - c * e) / denom, 0.0), 1.0) if denom > eps * max(a * e, eps) else 0.0
    if a <= eps:
        s = 0.0
    if e <= eps and a > eps:  # (q a point)
        s = min(max(-c / a, 0.0), 1.0)
    t = 0.0 if e <= eps else (b * s + f) / e
    t_c = min(max(t, 0.0), 1.0)
    if a <= eps:
        s = 0.0
    elif t != t_c:
        s = min(max((b * t_c - c) / a, 0.0), 1.0)
    cpx, cpy, cpz = p0x + s * d1x, p0y + s * d1y, p0z + s * d1z
    cqx, cqy, cqz = q0x + t_c * d2x, q0y + t_c * d2y, q0z + t_c * d2z
    dx, dy, dz = cpx - cqx, cpy - cqy, cpz - cqz
    return math.sqrt(dx * dx + dy * dy + dz * dz), cpx, cpy, cpz, cqx, cqy, cqz


@jit
def _pair(x, i, j, flat):
    """``_closest`` of elements i and j of the cable ``x`` (nodes (n+1, 3)); in plan view (z
    taken as 0) with ``flat``."""
    z = 0.0 if flat else 1.0
    return _closest(x[i, 0], x[i, 1], x[i, 2] * z, x[i + 1, 0], x[i + 1, 1], x[i + 1, 2] * z,
                    x[j, 0], x[j, 1], x[j, 2] * z, x[j + 1, 0], x[j + 1, 1], x[j + 1, 2] * z)


@jit
def _arcs(nodes):
    """``arc_lengths``."""
    s = np.zeros(nodes.shape[0])
    for k in range(nodes.shape[0] - 1):
        dx, dy, dz = nodes[k + 1, 0] - nodes[k, 0], nodes[k + 1, 1] - nodes[k, 1], nodes[k + 1, 2] - nodes[k, 2]
        s[k + 1] = s[k] + math.sqrt(dx * dx + dy * dy + dz * dz)
    return s


@jit
def _vehicle_kernel(nodes, a, b, radius, pts, exclude, from_end):
    """``vehicle_clearance`` compiled: every element beyond the exclusion against the hull, then
    against each point, the first nearest of each kept, as the reference's ``argmin`` keeps it."""
    n = nodes.shape[0] - 1
    s = _arcs(nodes)
    if from_end:
        s = s[-1] - s
    p0, p1 = np.empty(3), np.empty(3)
    hull, hull_at = math.inf, nodes[n if from_end else 0].copy()
    point, point_at = math.inf, hull_at.copy()
    kept = False
    for k in range(n):
        s0, s1 = s[k], s[k + 1]
        if not max(s0, s1) > exclude:
            continue
        kept = True
        for m in range(3):
            p0[m], p1[m] = nodes[k, m], nodes[k + 1, m]
        if s0 < exclude:  # (only its part beyond the exclusion)
            f = (exclude - s0) / (s1 - s0)
            for m in range(3):
                p0[m] = p0[m] + f * (p1[m] - p0[m])
        elif s1 < exclude:
            f = (exclude - s1) / (s0 - s1)
            for m in range(3):
                p1[m] = p1[m] + f * (p0[m] - p1[m])
        d, cx, cy, cz, _, _, _ = _closest(p0[0], p0[1], p0[2], p1[0], p1[1], p1[2], a[0], a[1], a[2], b[0], b[1], b[2])
        if d - radius < hull:
            hull = d - radius
            hull_at[0], hull_at[1], hull_at[2] = cx, cy, cz
        for j in range(pts.shape[0]):
            q = pts[j]
            d, cx, cy, cz, _, _, _ = _closest(p0[0], p0[1], p0[2], p1[0], p1[1], p1[2], q[0], q[1], q[2],
                                              q[0], q[1], q[2])
            if d < point:
                point = d
                point_at[0], point_at[1], point_at[2] = cx, cy, cz
    if not kept:
        return math.inf, hull_at
    if point < hull:
        return point, point_at
    return hull, hull_at


@jit
def _self_kernel(nodes, min_arc, reach):
    """``self_clearance`` compiled: (clearance, place, plan crossings). Each element i against
    the elements j > i at least ``min_arc`` of arc on whose midpoints are within the reference's
    k-d tree radius (its candidates), in (i, j) order, measuring only the pairs that can matter:
    two elements are no nearer than their midpoints' distance D less half their lengths (in
    plan: plan lengths), so a pair is passed over when that bound is above the distance to beat
    (the best so far, at most ``reach``; 1e-9 for a crossing), and since consecutive midpoints
    are at most the longest element (``most``) apart, so are the next (bound - beat) / most
    elements along. The bound is relaxed by 1e-9 of the distances and 1e-12 of the coordinates,
    far above their rounding."""
    n = nodes.shape[0] - 1
    s = _arcs(nodes)
    length, plan = np.empty(n), np.empty(n)
    span, scale = 0.0, 0.0
    for k in range(n):
        length[k] = s[k + 1] - s[k]
        span = max(span, length[k])
        plan[k] = math.hypot(nodes[k + 1, 0] - nodes[k, 0], nodes[k + 1, 1] - nodes[k, 1])
    for k in range(n + 1):
        scale = max(scale, abs(nodes[k, 0]), abs(nodes[k, 1]), abs(nodes[k, 2]))
    mids = 0.5 * (nodes[:-1] + nodes[1:])
    best, at = math.inf, nodes[0].copy()
    crossings = 0
    for flat in (False, True):
        r = span if flat else reach + span
        r2 = r * r
        z = 0.0 if flat else 1.0
        le = plan if flat else length
        most = 0.0
        for k in range(n):
            most = max(most, le[k])
        first = 0
        for i in range(n):
            first = max(first, i + 1)
            while first < n and s[first] - s[i + 1] < min_arc:
                first += 1
            j = first
            while j < n:
                dx, dy, dz = mids[i, 0] - mids[j, 0], mids[i, 1] - mids[j, 1], (mids[i, 2] - mids[j, 2]) * z
                D2 = dx * dx + dy * dy + dz * dz
                D = math.sqrt(D2)
                beat = 1e-9 if flat else min(best, reach)
                tol = 1e-9 * (1.0 + r + D) + 1e-12 * scale
                over = D - 0.5 * (le[i] + most) - beat  # (the bound of this pair and the next, less beat)
                if over > tol:
                    j += max(1, int(over / most * (1.0 - 1e-9))) if most > 0.0 else 1
                    continue
                if D2 > r2 or D - 0.5 * (le[i] + le[j]) - beat > tol:  # (not a candidate; too far)
                    j += 1
                    continue
                d, cpx, cpy, cpz, cqx, cqy, cqz = _pair(nodes, i, j, flat)
                if flat:
                    if d <= 1e-9:
                        crossings += 1
                elif d < best:
                    best = d
                    at[0], at[1], at[2] = 0.5 * (cpx + cqx), 0.5 * (cpy + cqy), 0.5 * (cpz + cqz)
                j += 1
    if not best <= reach:
        return math.inf, nodes[0].copy(), crossings
    return best, at, crossings

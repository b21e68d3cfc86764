"""The steady state of a network, as MoorPy solves it: each line an elastic catenary between its
ends, the free points where the line forces, their weight, buoyancy and applied force balance.

``line_ends`` gives the forces a line exerts on its two ends (N, world frame) and its shape;
``equilibrium`` moves the free points until the force on each is zero (scipy's ``root``); bodies,
free ones too, stay at their given pose (a free body then settles in the dynamics).
Where the catenary has no answer (a line that is weightless or buoyant in water, or hangs
vertically) the line is a straight elastic bar carrying half its wet weight at each end:
exact for a weightless line, and a start the dynamics settle from otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import root

from mjtether.analytic import sagged_polyline
from mjtether.quasistatic.catenary import catenary

from .config import Network


@dataclass(frozen=True)
class LineState:
    """A line's steady state: the forces on its ends A and B (N, world) and its N + 1 nodes
    from A to B (m, world); ``catenary``: whether the elastic catenary gave them."""

    force_a: np.ndarray
    force_b: np.ndarray
    nodes: np.ndarray
    catenary: bool


def line_ends(net: Network, line, pa, pb) -> LineState:
    """The steady state of ``line`` with its ends at ``pa`` and ``pb`` (m, world)."""
    lt = net.line_types[line.type]
    pa, pb = np.asarray(pa, float), np.asarray(pb, float)
    w = lt.wet_weight(net.rho, net.gravity)
    L, N = line.length, line.segments
    s = np.linspace(0.0, L, N + 1)
    low_is_a = pa[2] <= pb[2]
    lo, hi = (pa, pb) if low_is_a else (pb, pa)
    span = math.hypot(*(hi - lo)[:2])
    if w > 1e-9 * lt.EA / L and span > 1e-6 * L:
        on_bottom = lo[2] <= net.seabed_height(lo[0], lo[1]) + 1e-3 * L  # (a level seabed at its low end)
        try:
            c = catenary(lo, hi, L, w, EA=lt.EA, cb=net.seabed_friction, seabed=on_bottom)
        except (RuntimeError, ValueError):
            c = None
        if c is not None:
            f_lo, f_hi = c.anchor_force, c.fairlead_force
            pts = c.points(s)
            if low_is_a:
                return LineState(f_lo, f_hi, pts, True)
            return LineState(f_hi, f_lo, pts[::-1].copy(), True)
    d = pb - pa
    chord = float(np.linalg.norm(d))
    u = d / chord if chord > 0 else np.array([0.0, 0.0, -1.0])
    T = lt.EA * max(chord / L - 1.0, 0.0)
    half = np.array([0.0, 0.0, -0.5 * w * L])
    nodes = sagged_polyline(pa, pb, L, N, sag_down=w >= 0) if chord > 0 else pa + np.outer(s, u)
    return LineState(T * u + half, -T * u + half, nodes, False)


def point_load(net: Network, p) -> np.ndarray:
    """Weight, buoyancy and applied force on a free point (N, world)."""
    return np.array(p.force, float) + np.array([0.0, 0.0, (net.rho * p.volume - p.mass) * net.gravity])


def equilibrium(net: Network, positions: dict) -> tuple[dict, str]:
    """The free points' positions where the forces on them balance, starting from ``positions``
    ({point: world position, m} for every point, body points included); returns (positions, a
    note: how they were found, or why not)."""
    free = [name for name, p in net.points.items() if p.kind == "free"]
    if not free:
        return dict(positions), "every point held: each line's elastic catenary"
    scale = max(ln.length for ln in net.lines)

    def forces(x):
        pos = dict(positions)
        for k, name in enumerate(free):
            pos[name] = x[3 * k:3 * k + 3] * scale
        net_force = {name: point_load(net, net.points[name]) for name in free}
        for ln in net.lines:
            st = line_ends(net, ln, pos[ln.a], pos[ln.b])
            if ln.a in net_force:
                net_force[ln.a] = net_force[ln.a] + st.force_a
            if ln.b in net_force:
                net_force[ln.b] = net_force[ln.b] + st.force_b
        return pos, net_force

    ref = max(1.0, max(abs(point_load(net, net.points[n])[2]) for n in free),
              max(net.line_types[ln.type].wet_weight(net.rho, net.gravity) * ln.length for ln in net.lines))

    def residual(x):
        _, f = forces(x)
        return np.concatenate([f[n] for n in free]) / ref

    x0 = np.concatenate([np.asarray(positions[n], float) for n in free]) / scale
    sol = root(residual, x0, method="hybr", options={"xtol": 1e-12})
    worst = float(np.max(np.abs(sol.fun))) * ref if sol.fun.size else 0.0
    if worst > 1e-6 * ref:  # (a slack line has no stiffness to start from: try with the lines drawn taut)
        x1 = np.concatenate([_taut(net, n, positions) for n in free]) / scale
        sol1 = root(residual, x1, method="hybr", options={"xtol": 1e-12})
        worst1 = float(np.max(np.abs(sol1.fun))) * ref
        if worst1 < worst:
            sol, worst = sol1, worst1
    if not np.all(np.isfinite(sol.x)) or worst > 1e-6 * ref:
        where = free[int(np.argmax(np.abs(sol.fun))) // 3] if np.all(np.isfinite(sol.fun)) else None
        left = f"{worst:.3g} N left on point {where}" if where is not None else "no finite answer"
        if where is not None and np.all(np.isfinite(sol.x)):
            p = forces(sol.x)[0][where]
            if p[2] <= net.seabed_height(p[0], p[1]) + 1e-3 * scale:
                left += "; the statics give a free point no seabed to rest on"
        return dict(positions), (f"the free points' equilibrium was not found ({left}): starting from the file's "
                                 "positions")
    pos, _ = forces(sol.x)
    below = [n for n in free if pos[n][2] < net.seabed_height(pos[n][0], pos[n][1]) - 1e-6]
    if below:
        return dict(positions), (f"the equilibrium puts point(s) {', '.join(below)} below the seabed: starting "
                                 "from the file's positions")
    return pos, f"elastic catenaries with {len(free)} free point(s) in equilibrium (largest force left {worst:.2g} N)"


def _taut(net: Network, name: str, positions: dict) -> np.ndarray:
    """A start for free point ``name``: as far from each held point it is tied to, along the line
    from it, as the line is long (the mean over its lines; where it is now if tied to none)."""
    guesses = []
    for ln, end in net.attached(name):
        other = ln.b if end == "a" else ln.a
        if net.points[other].kind == "free":
            continue
        d = np.asarray(positions[name], float) - positions[other]
        n = np.linalg.norm(d)
        guesses.append(positions[other] + (d / n if n > 0 else np.array([0.0, 0.0, -1.0])) * ln.length)
    return np.mean(guesses, axis=0) if guesses else np.asarray(positions[name], float)

"""The steady state of a network, as MoorPy solves it: each line an elastic catenary between its
ends, the free points and the free and pinned bodies where the line forces, their weight,
buoyancy and applied force balance.

``line_ends`` gives the forces a line exerts on its two ends (N, world frame) and its shape;
``equilibrium`` moves the free points until the force on each is zero (scipy's ``root``) and,
with ``bodies=True``, the free bodies' 6 degrees of freedom and the pinned bodies' 3 rotations
too, until the force and the moment on each free body (about its origin) and the moment on each
pinned body (about its pin, which stays where the written pose puts it) are zero. A body's
weight acts at its centre of gravity ``cg``, its buoyancy at its origin (a network's body has no
centre of buoyancy of its own: the dynamics, ``run.build``, put it there too), over its
waterline band where it pierces the surface (``buoyancy``, the dynamics' rule); the lines' end
forces act at the body's points. Coupled and fixed bodies stay at their pose, vehicles where
they start and walkers where they stand (``run.body_frame``: a walker does not move in the
statics; its points are held at its standing pose, as a held point's). A free point's buoyancy
is still its whole volume's, wherever it is (the dynamics give it the waterline rule: a float
on the surface is balanced in the statics above it, fully buoyant, and falls to it in a run).

Where the catenary has no answer (a line that is weightless or buoyant in water) the line is a
straight elastic bar carrying half its wet weight at each end: exact for a weightless line, and
a start the dynamics settle from otherwise. A sinking line whose ends are on one vertical
(``vertical``) hangs straight when taut and folds when slack, in closed form; one near the
vertical, where the catenary's own start misses, is solved again from the straight bar's forces.

The search is scipy's ``root`` (Powell's hybrid method) on a Jacobian of small forward steps
(``STEP``: a stiff line is taut only micrometres past its length). Where it fails: Newton's
method with a fresh Jacobian each step (``_newton``: a stiff line near the vertical, whose stretch
is 1e7 times stiffer than its swing); from where every line with a moving end is just taut
(``_Balance.taut_start``, a small least squares: a slack weightless rope has no stiffness to
search on); and last from there with the lines' EA cut and raised back step by step
(``_continuation``: stiff light ropes on a body), with a trust-region least squares at each EA
where both fail (``_least_squares``: a body on a bridle, whose roll about the bridle's axis no
load sees, so that the Jacobian is singular along it). Measured on a clump or buoy on one line
(5 line types, 3 masses, 5 starts each, above and below: 150 cases): 56 missed before, 11
now (a 1e11 N rod, and buoys that cannot lift their line); a network that cannot balance
(MoorDyn's tripod.txt, a float line through the surface) now takes 8 s to say so where first
measured (22-24 s on a 2-core Intel Xeon), 1.6 s before.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares, root
from scipy.spatial.transform import Rotation

from mjtether.analytic import sagged_polyline
from mjtether.quasistatic.catenary import ElasticCatenary, _residual, catenary

from .config import Network, waterline_height

MOVING = ("free", "pinned")
"""The kinds of body the statics move (``equilibrium(..., bodies=True)``)."""
TURN_DAMPING = 1e-6
"""Newton's steps are damped in the bodies' turns by this share of the Jacobian's largest term
(Levenberg-Marquardt on those unknowns only): a turn its loads barely set (a buoy on one line,
about the line) leaves the Jacobian near singular, and the undamped step there is a wild one.
The balance found is not moved by it (the damping acts on the step, not on the residual)."""
MAX_TURN = 0.2
"""The largest turn (rad) of a body in one Newton step."""
STEP = 1e-9
"""The finite-difference step of the Jacobian, on each unknown (at least 1): a stiff line stretched
a micrometre in balance has its slack kink closer than ``root``'s own step, 1.5e-8."""
TOLERANCE = 1e-6
"""The largest force left on a free point or body, on the network's reference force (its
largest point or body load, or line weight, at least 1 N); a moment on that times its lever."""


@dataclass(frozen=True)
class LineState:
    """A line's steady state: the forces on its ends A and B (N, world) and its N + 1 nodes
    from A to B (m, world); ``catenary``: whether the elastic catenary gave them."""

    force_a: np.ndarray
    force_b: np.ndarray
    nodes: np.ndarray
    catenary: bool


@dataclass(frozen=True)
class BodyPose:
    """A body's pose: its origin (m, world) and rotation (body to world)."""

    position: np.ndarray
    rotation: np.ndarray

    @property
    def rpy_deg(self) -> tuple:
        """Roll, pitch, yaw (degrees) in a body's ``rpy_deg`` convention (``rotation``)."""
        return tuple(float(a) for a in Rotation.from_matrix(self.rotation).as_euler("XYZ", degrees=True))


def rotation(rpy_deg) -> np.ndarray:
    """Body-to-world rotation of a body's roll, pitch, yaw (degrees), turned about its x, then its
    new y, then its new z: R = Rx Ry Rz, MuJoCo's ``"xyz"`` sequence (``run._quat``)."""
    return Rotation.from_euler("XYZ", rpy_deg, degrees=True).as_matrix()


def buoyancy(net: Network, volume: float, height: float | None, z: float) -> float:
    """Upward buoyancy (N) of ``volume`` (m^3) centred at height ``z`` (m, world): rho g V below
    z = -h/2, none above +h/2, linear between (h the waterline band, ``config.waterline_height``),
    as the dynamics apply it (``physics.hydro.rigid_body_loads``)."""
    h = waterline_height(volume, height)
    return net.rho * net.gravity * volume * min(max(0.5 - z / h, 0.0), 1.0)


def vertical(lo, hi, L: float, w: float, EA: float) -> tuple[np.ndarray, np.ndarray]:
    """Forces (N, world) on the low end ``lo`` and the high end ``hi`` of a sinking line (w > 0
    N/m) whose ends are on one vertical, ``c`` apart: taut (c >= L (1 + w L / 2 EA), so that the
    low end's tension EA (c / L - 1) - w L / 2 is not negative), a straight hanging bar;
    else folded below, l1 hanging from the high end, l2 = L - l1 from the low one, each section's
    weight on its end: l1 - l2 = c / (1 + w L / 2 EA) (each hanging section's stretch is
    w l^2 / 2 EA)."""
    c = float(hi[2] - lo[2])
    k = 1.0 + w * L / (2.0 * EA)
    if c >= L * k:
        T = EA * (c / L - 1.0)
        return np.array([0.0, 0.0, T - 0.5 * w * L]), np.array([0.0, 0.0, -T - 0.5 * w * L])
    l1 = 0.5 * (L + c / k)
    return np.array([0.0, 0.0, -w * (L - l1)]), np.array([0.0, 0.0, -w * l1])


def _catenary(lo, hi, L, w, EA, cb, on_bottom):
    """The elastic catenary from ``lo`` up to ``hi``, or None: the catenary's own solve, else
    again from the straight bar's end forces (a taut line near the vertical, where Jonkman's start,
    for a slack line, misses) and from a vertical fold's (a slack one)."""
    try:
        return catenary(lo, hi, L, w, EA=EA, cb=cb, seabed=on_bottom)
    except (RuntimeError, ValueError):
        pass
    d = hi - lo
    XF, ZF = math.hypot(d[0], d[1]), float(d[2])
    chord = math.hypot(XF, ZF)
    T = EA * max(chord / L - 1.0, 0.0)
    starts = [(T * XF / chord, T * ZF / chord + 0.5 * w * L)] if T > 0 else []
    starts.append((1e-3 * w * L, 0.5 * w * (L + ZF)))

    def fun(p):
        try:
            rx, rz = _residual(math.exp(float(p[0])), float(p[1]) * w * L, XF, ZF, L, w, EA, cb, on_bottom)
        except (OverflowError, ZeroDivisionError, ValueError):
            return [1e10, 1e10]
        return [rx / L, rz / L]

    for H0, V0 in starts:
        sol = root(fun, [math.log(max(H0, 1e-9 * w * L)), V0 / (w * L)], method="hybr", options={"xtol": 1e-13})
        if np.all(np.isfinite(sol.fun)) and max(abs(r) for r in sol.fun) <= 1e-9:
            H, VF = math.exp(sol.x[0]), sol.x[1] * w * L
            return ElasticCatenary(lo, hi, L, w, EA, cb, H, VF, max(L - VF / w, 0.0) if on_bottom else 0.0)
    return None


def line_ends(net: Network, line, pa, pb, EA: float | None = None) -> LineState:
    """The steady state of ``line`` with its ends at ``pa`` and ``pb`` (m, world); ``EA`` (N) in
    place of its type's (a softened line, in ``equilibrium``'s continuation)."""
    lt = net.line_types[line.type]
    if EA is not None:
        lt = dataclasses.replace(lt, EA=EA)
    pa, pb = np.asarray(pa, float), np.asarray(pb, float)
    w = lt.wet_weight(net.rho, net.gravity)
    L, N = line.length, line.segments
    s = np.linspace(0.0, L, N + 1)
    low_is_a = pa[2] <= pb[2]
    lo, hi = (pa, pb) if low_is_a else (pb, pa)
    span = math.hypot(*(hi - lo)[:2])
    d = pb - pa
    chord = float(np.linalg.norm(d))
    nodes = sagged_polyline(pa, pb, L, N, sag_down=w >= 0) if chord > 0 else pa + np.outer(s, [0.0, 0.0, -1.0])
    if w > 1e-9 * lt.EA / L and span > 1e-6 * L:
        on_bottom = lo[2] <= net.seabed_height(lo[0], lo[1]) + 1e-3 * L  # (a level seabed at its low end)
        c = _catenary(lo, hi, L, w, lt.EA, net.seabed_friction, on_bottom)
        if c is not None:
            f_lo, f_hi = c.anchor_force, c.fairlead_force
            pts = c.points(s)
            if low_is_a:
                return LineState(f_lo, f_hi, pts, True)
            return LineState(f_hi, f_lo, pts[::-1].copy(), True)
    elif w > 1e-9 * lt.EA / L:
        f_lo, f_hi = vertical(lo, hi, L, w, lt.EA)
        return LineState(f_lo, f_hi, nodes, False) if low_is_a else LineState(f_hi, f_lo, nodes, False)
    u = d / chord if chord > 0 else np.array([0.0, 0.0, -1.0])
    T = lt.EA * max(chord / L - 1.0, 0.0)
    half = np.array([0.0, 0.0, -0.5 * w * L])
    return LineState(T * u + half, -T * u + half, nodes, False)


def point_load(net: Network, p) -> np.ndarray:
    """Weight, buoyancy (fully submerged: see the module docstring) and applied force on a free
    point (N, world)."""
    return np.array(p.force, float) + np.array([0.0, 0.0, (net.rho * p.volume - p.mass) * net.gravity])


class _Balance:
    """The statics' unknowns (free points' positions over ``scale``; a free body's position over
    ``scale`` and rotation vector, rad, from its written pose; a pinned body's rotation vector)
    and the loads left on them, on ``ref``."""

    def __init__(self, net: Network, positions: dict, bodies: bool):
        self.net, self.start = net, positions
        self.free = [name for name, p in net.points.items() if p.kind == "free"]
        self.bodies = [name for name, b in net.bodies.items() if bodies and b.kind in MOVING]
        self.scale = max([ln.length for ln in net.lines] or [1.0])
        self.on = {n: [(p.name, np.array(p.position, float)) for p in net.points.values() if p.body == n]
                   for n in self.bodies}
        self.r0 = {n: rotation(net.bodies[n].rpy_deg) for n in self.bodies}
        self.pin = {n: np.array(b.position) + self.r0[n] @ np.array(b.pin) for n, b in net.bodies.items()
                    if n in self.bodies}
        self.lever = {n: max([float(np.linalg.norm(q - net.bodies[n].pin)) for _, q in self.on[n]]
                             + [float(np.linalg.norm(np.subtract(net.bodies[n].cg, net.bodies[n].pin))), 0.1])
                      for n in self.bodies}
        g = net.gravity
        self.ref = max([1.0] + [abs(point_load(net, net.points[n])[2]) for n in self.free]
                       + [abs(net.rho * b.volume - b.mass) * g for n, b in net.bodies.items() if n in self.bodies]
                       + [abs(net.line_types[ln.type].wet_weight(net.rho, g)) * ln.length for ln in net.lines])
        self.ea_cap = math.inf  # (the lines' EA at most this, N: ``_continuation``)
        self.labels = [f"point {n}" for n in self.free for _ in range(3)]
        self.turns = [0.0] * len(self.labels)  # (1 on a body's rotation vector)
        for n in self.bodies:
            self.labels += [f"body {n}"] * (6 if net.bodies[n].kind == "free" else 3)
            self.turns += [0.0] * (3 if net.bodies[n].kind == "free" else 0) + [1.0] * 3

    def x0(self) -> np.ndarray:
        parts = [np.asarray(self.start[n], float) / self.scale for n in self.free]
        for n in self.bodies:
            b = self.net.bodies[n]
            parts += [np.array(b.position) / self.scale] if b.kind == "free" else []
            parts.append(np.zeros(3))
        return np.concatenate(parts) if parts else np.zeros(0)

    def state(self, x) -> tuple[dict, dict]:
        """Every point's position (m, world) and each moving body's ``BodyPose`` at ``x``."""
        pos, poses, k = dict(self.start), {}, 0
        for n in self.free:
            pos[n], k = x[k:k + 3] * self.scale, k + 3
        for n in self.bodies:
            b = self.net.bodies[n]
            if b.kind == "free":
                xb, k = x[k:k + 3] * self.scale, k + 3
            R, k = Rotation.from_rotvec(x[k:k + 3]).as_matrix() @ self.r0[n], k + 3
            if b.kind == "pinned":
                xb = self.pin[n] - R @ np.array(b.pin)
            poses[n] = BodyPose(xb, R)
            for name, q in self.on[n]:
                pos[name] = xb + R @ q
        return pos, poses

    def residual(self, x) -> np.ndarray:
        """The forces on the free points and bodies, moments on the bodies, on ``ref`` (and lever)."""
        net, g = self.net, self.net.gravity
        pos, poses = self.state(x)
        force = {n: point_load(net, net.points[n]) for n in self.free}
        held = {name: np.zeros(3) for n in self.bodies for name, _ in self.on[n]}
        for ln in net.lines:
            EA = net.line_types[ln.type].EA
            st = line_ends(net, ln, pos[ln.a], pos[ln.b], None if EA <= self.ea_cap else self.ea_cap)
            for end, f in ((ln.a, st.force_a), (ln.b, st.force_b)):
                for table in (force, held):
                    if end in table:
                        table[end] = table[end] + f
        out = [force[n] / self.ref for n in self.free]
        for n in self.bodies:
            b, p = net.bodies[n], poses[n]
            loads = [(p.position + p.rotation @ np.array(b.cg), np.array([0.0, 0.0, -b.mass * g])),
                     (p.position, np.array([0.0, 0.0, buoyancy(net, b.volume, b.height, p.position[2])]))]
            loads += [(pos[name], held[name]) for name, _ in self.on[n]]
            about = p.position if b.kind == "free" else self.pin[n]
            moment = sum(np.cross(r - about, f) for r, f in loads)
            if b.kind == "free":
                out.append(sum(f for _, f in loads) / self.ref)
            out.append(moment / (self.ref * self.lever[n]))
        return np.concatenate(out) if out else np.zeros(0)

    def taut_start(self, x0) -> np.ndarray:
        """Near ``x0``, where each line with a moving end is just taut (stretched by the strain of
        ``ref``, between 1e-9 and 1 %), so that it has stiffness to search on: a least squares
        on those lines' stretch, each unknown held near ``x0`` by a weight of 1e-3. A buoyant free
        body that no line holds starts at its draft instead (below it, its buoyancy does not
        change with depth: nothing to search on)."""
        movers = set(self.free) | {name for n in self.bodies for name, _ in self.on[n]}
        lines = [ln for ln in self.net.lines if ln.a in movers or ln.b in movers]
        strain = [min(max(self.ref / self.net.line_types[ln.type].EA, 1e-9), 1e-2) for ln in lines]

        def misfit(x):
            pos, _ = self.state(x)
            gaps = [(np.linalg.norm(pos[ln.b] - pos[ln.a]) / ln.length - 1.0 - e) for ln, e in zip(lines, strain)]
            return np.concatenate([gaps, 1e-3 * (x - x0)])

        x = least_squares(misfit, x0, xtol=1e-12, ftol=1e-12).x
        k = 3 * len(self.free)
        for n in self.bodies:
            b, tied = self.net.bodies[n], {name for name, _ in self.on[n]}
            held = any(ln.a in tied or ln.b in tied for ln in self.net.lines)
            if b.kind == "free" and not held and self.net.rho * b.volume > b.mass:
                h = waterline_height(b.volume, b.height)
                x[k + 2] = h * (0.5 - b.mass / (self.net.rho * b.volume)) / self.scale
            k += 6 if b.kind == "free" else 3
        return x


def _attempt(bal: _Balance, x):
    """``root`` (Powell's hybrid method) from ``x``: its answer and the largest residual left."""
    sol = root(bal.residual, x, jac=lambda y: _jacobian(bal, y), method="hybr", options={"xtol": 1e-12})
    return sol.x, _worst(sol.fun, sol.x)


def _least_squares(bal: _Balance, x):
    """A trust-region least squares (scipy's ``least_squares``, "trf") from ``x``: its answer and
    the largest residual left. The last resort at each EA of ``_continuation``, taken where it
    balances: a motion the loads do not see (a body on a bridle rolling about the line through
    its rope points, its weight and its buoyancy) makes the Jacobian singular; hybr's updated
    Jacobian drifts along it (to a roll of -48 rad, measured) and Newton's steps from the taut
    start slacken the ropes, where the trust region's steps stay short."""
    sol = least_squares(bal.residual, x, jac=lambda y: _jacobian(bal, y), method="trf", xtol=1e-15, ftol=1e-15,
                        gtol=1e-15, max_nfev=LEAST_SQUARES_EVALS)
    return sol.x, _worst(sol.fun, sol.x)


LEAST_SQUARES_EVALS = 200
"""The most residual evaluations ``_least_squares`` takes (each step takes a Jacobian too: one
residual per unknown)."""


def _jacobian(bal: _Balance, x, r=None) -> np.ndarray:
    """The residual's forward-difference Jacobian at ``x``, each unknown stepped by ``STEP``."""
    r = bal.residual(x) if r is None else r
    h = STEP * np.maximum(np.abs(x), 1.0)
    return np.column_stack([(bal.residual(x + h[j] * np.eye(x.size)[j]) - r) / h[j] for j in range(x.size)])


def _worst(r, x) -> float:
    return float(np.max(np.abs(r))) if r.size and np.all(np.isfinite(r)) and np.all(np.isfinite(x)) else math.inf


STALL = 8
"""Newton's method stops where its shortest step has not fallen by 10 % over this many steps."""


def _clipped(bal: _Balance, dx) -> np.ndarray:
    """Newton step ``dx`` with each body's turn cut to ``MAX_TURN``."""
    dx = np.array(dx, float)
    for k in np.flatnonzero(bal.turns)[::3]:
        dx[k:k + 3] *= min(1.0, MAX_TURN / max(float(np.linalg.norm(dx[k:k + 3])), 1e-300))
    return dx


def _newton(bal: _Balance, x, steps: int = 100):
    """Newton's method from ``x`` with the Jacobian taken afresh at each step (least squares where
    it is singular: a body free to turn about a vertical line), each step halved until the next
    one, with that Jacobian, is shorter (Deuflhard's natural monotonicity test). A stiff line near
    the vertical stretches 1e7 times stiffer than it swings: its swing's step overshoots along
    the chord, so the force left grows while the step that remains falls; ``root``'s updated
    Jacobian stalls there."""
    r, sizes = bal.residual(x), []
    for _ in range(steps):
        if _worst(r, x) <= TOLERANCE or (len(sizes) > STALL and min(sizes[-STALL:]) > 0.9 * min(sizes[:-STALL])):
            break
        J = _jacobian(bal, x, r)
        pinv = np.linalg.pinv(J + TURN_DAMPING * np.abs(J).max() * np.diag(bal.turns), rcond=1e-12)
        dx = _clipped(bal, -pinv @ r)
        sizes.append(float(np.linalg.norm(dx)))
        if sizes[-1] < 1e-9 * max(1.0, float(np.linalg.norm(x))) and len(sizes) > 1 and sizes[-2] < 1e-6:
            break  # (at a least-squares point, no root near: the steps vanish and the force stays)
        for _ in range(30):
            r1 = bal.residual(x + dx)
            if _worst(r1, x + dx) < math.inf and np.linalg.norm(_clipped(bal, -pinv @ r1)) < sizes[-1]:
                break
            dx = 0.5 * dx
        else:
            break
        x, r = x + dx, r1
    return x, _worst(r, x)


def _continuation(bal: _Balance, x):
    """From ``x``, with every line's EA cut to what stretches it 1 % at ``ref`` (its taut range
    wide and its stiffness near its swing's), then to 10 times that, and on to its own EA, each
    balance the start of the next (Newton where ``root`` stalls): for stiff light ropes, which
    are taut only within micrometres of their length, so that a swing's step slackens them."""
    top = max(bal.net.line_types[ln.type].EA for ln in bal.net.lines) if bal.net.lines else 0.0
    cap, worst = 100.0 * bal.ref, math.inf
    while True:
        bal.ea_cap = cap if cap < top else math.inf
        x1, worst = _attempt(bal, x)
        if worst > TOLERANCE:
            x1, worst = min((x1, worst), _newton(bal, x1), key=lambda t: t[1])
        if worst > TOLERANCE:  # (a neutral motion: the least squares' trust region, from this EA's start,
            x2, left = _least_squares(bal, x)  # taken only where it balances: elsewhere its answer, which
            if left <= TOLERANCE:  # may rest a point on the seabed, would be no better a start)
                x1, worst = x2, left
        if worst > TOLERANCE and bal.ea_cap < math.inf and not math.isfinite(worst):
            break
        x = x1
        if bal.ea_cap == math.inf:
            break
        cap *= 10.0
    bal.ea_cap = math.inf
    return x, worst


def equilibrium(net: Network, positions: dict, bodies: bool = False):
    """The free points' positions where the forces on them balance, starting from ``positions``
    ({point: world position, m} for every point, body points included); returns (positions, a
    note: how they were found, or why not). With ``bodies=True`` the free and pinned bodies are
    balanced too (else held at their written pose) and it returns (positions, note, poses):
    {body: ``BodyPose``} for every body (at its written pose where held or not found)."""
    bal = _Balance(net, positions, bodies)
    poses = {n: BodyPose(np.array(b.position, float), rotation(b.rpy_deg)) for n, b in net.bodies.items()}

    def done(pos, note, solved=None):
        return (pos, note, {**poses, **(solved or {})}) if bodies else (pos, note)

    if not bal.free and not bal.bodies:
        return done(dict(positions), "every point held: each line's elastic catenary")
    x0 = bal.x0()
    x, worst = _attempt(bal, x0)
    if worst > TOLERANCE:  # (again by Newton; then from the lines drawn taut, as a slack one has no stiffness)
        x, worst = min((x, worst), _newton(bal, x0), key=lambda t: t[1])
    if worst > TOLERANCE:
        x1, left = _attempt(bal, bal.taut_start(x0))
        if left < worst:  # (a new basin: Newton from there too)
            x, worst = min((x1, left), _newton(bal, x1), key=lambda t: t[1])
    if worst > TOLERANCE:  # (stiff ropes: softened, then stiffened back to their own EA)
        x, worst = min((x, worst), _continuation(bal, bal.taut_start(x0)), key=lambda t: t[1])
    what = " and ".join(part for part in (f"{len(bal.free)} free point(s)" if bal.free else "",
                                          f"{len(bal.bodies)} body(ies)" if bal.bodies else "") if part)
    if worst > TOLERANCE:
        where = bal.labels[int(np.argmax(np.abs(bal.residual(x))))] if math.isfinite(worst) else None
        left = f"{worst * bal.ref:.3g} N left on {where}" if where is not None else "no finite answer"
        if where is not None and where.startswith("point "):
            p = bal.state(x)[0][where[6:]]
            if p[2] <= net.seabed_height(p[0], p[1]) + 1e-3 * bal.scale:
                left += "; the statics give a free point no seabed to rest on"
        return done(dict(positions), f"the free points' equilibrium was not found ({left}): starting from "
                                     "the file's positions" + (" and poses" if bal.bodies else ""))
    pos, solved = bal.state(x)
    below = [n for n in bal.free if pos[n][2] < net.seabed_height(pos[n][0], pos[n][1]) - 1e-6]
    below += [f"body {n}" for n, p in solved.items() if p.position[2] < net.seabed_height(*p.position[:2]) - 1e-6]
    if below:
        return done(dict(positions), f"the equilibrium puts point(s) {', '.join(below)} below the seabed: starting "
                                     "from the file's positions")
    return done(pos, f"elastic catenaries with {what} in equilibrium (largest force left {worst * bal.ref:.2g} N)",
                solved)

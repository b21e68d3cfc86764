"""A physically consistent 3-D steady state of the tether, by shooting.

The same discretisation as the dynamic model (``mjtether.builder``): N elements of material
length l = L / N between nodes 0 (ship) .. N (robot); every element carries its wet weight
(mu - rho(z_c) A) g l and Morison drag on the relative velocity u(z_c) - v_tow at its centre
z_c (``mjtether.hydro``), and the lumped-mass node balance is

    E_{k+1} - E_k + (f_k + f_{k+1}) / 2 = 0,

with E_k = T_k t_k the tension vector of element k and f_k its external load. Writing
P_k = E_k + f_k / 2 (the force the cable below node k exerts on everything above it; P_0 is
the force of the cable on the ship) gives the marching recursion

    E_k = P_k - f_k(t_k) / 2,   t_k = E_k / |E_k|,   P_{k+1} = P_k - f_k,
    x_{k+1} = x_k + l (1 + T_k / EA) t_k,

solved for t_k by fixed-point iteration. ``steady_state`` marches from the ship with the
unknown ship force P_0 and finds it by Newton's method (finite-difference Jacobian) so that the
last node lands on the robot end. With the robot end on the seabed, the cable may rest on the
bottom: marching stops where the vertical tension reaches zero (the touchdown point, which must
lie on the seabed), and the rest of the cable lies straight on the seabed in the direction of
the horizontal tension there, its tension falling by cb w per metre (the seabed model of
MoorPy and of the analytic ``catenary``). Current drag on the laid part is neglected.

Slack cable. The straight-laid solution needs a tension H > 0 at the touchdown P: the cable
runs taut from P to the bottom end R. It exists only while the cable is short enough; without
current never once L > drop + horizontal span (a hanging catenary has s - x <= drop). A longer
cable on the seabed is *slack*: the suspended part hangs freely, its tension falling to zero
at P (horizontal as well as vertical), and the L_B = L - s_P of cable on the seabed carries no
tension at all:

* the suspended part is fixed by the top alone. With a current its lowest part is swept
  downstream and meets the seabed at the angle at which its weight and drag are in line with it
  (a kink there, which zero tension allows); in a uniform current the whole hang is straight at
  that angle. The top force is the total weight and drag of the hang: the top takes all the
  drag, the seabed none. The current depends on depth only, so the hang has the same shape
  wherever P is: it is marched up from zero force at the seabed, its length s_P solved for (a
  1-D secant search) so that it reaches the top's height, and then moved under the top. (Shot
  down from the top, the miss is singular at the solution: a slightly wrong top force leaves a
  small tension at the bottom, which the current turns a long way.) Near zero tension the
  element's direction is iterated to convergence with relaxation, as the plain two-sweep
  fixed point of the downward march can cycle there;
* a zero-tension cable needs no friction to stay where it lies, so this holds on a frictionless
  seabed too (``seabed_friction`` plays no part), and any shape on the seabed is an
  equilibrium. The shape is chosen by ``layout``: the slack leaves R along the horizontal unit
  vector b (``layout_direction``, "back along the robot's track"; by default towards the top)
  for a length L_s as a straight line ("straight"), a circular arc turning left
  (counter-clockwise seen from above) by ``layout_angle`` ("arc"), or two arcs of L_s / 2
  turning by +layout_angle/2 then -layout_angle/2 ("s"), and ends at Q0 = R + L_s c (c a fixed
  horizontal vector of the layout, |c| <= 1); a straight zero-tension piece of length
  L_B - L_s joins P to Q0, so L_s solves L_s + |Q0 - P| = L_B (the smallest root of a quadratic;
  one in [0, L_B] exists as |R - P| <= L_B). For the default straight layout that piece runs
  from P away from R and the slack comes back over it (a hairpin) when L_B > |R - P|;
* laid nodes lie on the seabed, unstretched, at their material distances along that path.

Why zero tension. A taut laid part (tension falling by cb w per metre from some H > 0 to zero,
then slack) is a static equilibrium too, for a whole range of H, with the seabed taking part of
the drag; statics does not single one out, each is on the point of slipping along its taut
part, and none exists on a frictionless seabed. The zero-tension one needs no friction, is the
continuation of the no-current solution (the cable hangs vertically, H = 0) and continues the
straight-laid solution, whose H falls to zero as L grows to s_P + |R - P|.

Which solution, with the bottom end on the seabed: the slack one whenever it exists (the free
hang reaches the seabed within L and leaves L - s_P >= |R - P|, horizontally), else the
straight-laid one (with H > 0). The two meet at L = s_P + |R - P|, where H reaches zero. A
current that sweeps P away from R can make the straight-laid one the answer for
L > drop + span too, and one that sweeps P towards R the slack one for L < drop + span.

A uniform tow velocity v_tow of the whole cable (both ends moving together, the towed steady
state) is the same as an extra current -v_tow.

Frames: world, z up, water surface z = 0, seabed z = -water.depth. SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from .. import _checks
from ..hydro import wet_fraction
from ..tether import TetherSpec
from ..water import WaterColumn
from .catenary import catenary


MIN_COARSE_SEGMENTS = 5
"""Fewest elements of the coarse solves that start Newton's method for finer tethers."""

LAYOUTS = ("straight", "arc", "s")
"""Shapes of slack cable laid on the seabed from the bottom end (see the module docstring)."""


@dataclass(frozen=True)
class SteadyState:
    """A steady tether configuration.

    Attributes:
        nodes: node positions (m, world), shape (N+1, 3), node 0 at the ship (top) end.
        tension: tension of each element (N), shape (N,).
        top_force, bottom_force: force of the cable on the top / bottom end (N, world).
        touchdown: unstretched arc length from the top at which the cable meets the seabed (m),
            or ``None`` if it hangs free.
        laid_length: unstretched length lying on the seabed (m).
        velocity: velocity of every node (m/s, world): the tow velocity.
        residual: distance (m) between the last node and the requested bottom end (for a
            slack cable, whose last node is on it, the height miss of the hang at the top).
        jacobian: derivative of that miss with respect to the top force (m/N), 3x3, for
            two-point solves; finer solves start from it.
        slack_length: unstretched length of the laid cable that carries no tension (m): all of
            ``laid_length`` for a slack cable (see the module docstring); on a straight-laid
            one the part beyond u0 = H / (cb w) from the touchdown; else 0.
    """

    nodes: np.ndarray
    tension: np.ndarray
    top_force: np.ndarray
    bottom_force: np.ndarray
    touchdown: float | None
    laid_length: float
    velocity: np.ndarray
    residual: float
    jacobian: np.ndarray | None = field(default=None, repr=False)
    slack_length: float = 0.0

    @property
    def tow_tension(self) -> float:
        """Tension at the bottom (robot) end |bottom_force| (N)."""
        return float(np.linalg.norm(self.bottom_force))

    @property
    def top_tension(self) -> float:
        """Tension at the top (ship) end |top_force| (N)."""
        return float(np.linalg.norm(self.top_force))


class _Cable:
    """Constants of the march for one tether in one water column."""

    def __init__(self, tether: TetherSpec, water: WaterColumn, tow_velocity, EA):
        self.N = tether.segments
        self.l = tether.segment_length
        self.L = tether.length
        self.EA = math.inf if EA is None else float(EA)
        self.d = tether.diameter
        self.A = tether.area
        self.mu = tether.mu
        self.cdn = tether.cd_normal
        self.cdt_pi = math.pi * tether.cd_tangential
        self.g = water.gravity
        self.water = water
        self.v_tow = np.asarray(tow_velocity, dtype=float)

    def loads(self, x0, t, l_s):
        """External load (N) on elements starting at ``x0`` (K, 3) with tangents ``t`` (K, 3)
        and stretched lengths ``l_s`` (K,)."""
        z0 = x0[:, 2]
        z1 = z0 + l_s * t[:, 2]
        if z0.max() <= 0.0 and z1.max() <= 0.0:  # fully wet, the usual case
            zc = 0.5 * (z0 + z1)
            l_wet = self.l
        else:
            zc = np.minimum(0.5 * (z0 + z1), 0.0)
            l_wet = self.l * wet_fraction(z0, z1)[0]
        rho = self.water.rho(zc)
        u = self.water.velocity(zc) - self.v_tow
        ut = (u * t).sum(axis=1)
        un = u - ut[:, None] * t
        q = 0.5 * self.d * l_wet * rho
        f = (q * self.cdn * np.sqrt((un * un).sum(axis=1)))[:, None] * un
        f += (q * self.cdt_pi * np.abs(ut) * ut)[:, None] * t
        f[:, 2] += (rho * self.A * l_wet - self.mu * self.l) * self.g
        return f

    def march(self, x0, P0, stop_on_touchdown=False, iterations=2):
        """March the N elements from node positions ``x0`` with forces ``P0`` (K, 3).

        Returns (nodes (K, n+1, 3), tension (K, n), P (K, n+1, 3)). With
        ``stop_on_touchdown`` the march of each shot also records the first element where the
        vertical component of P becomes >= 0 (returned as the fourth item, -1 if never).
        """
        n = self.N
        K = x0.shape[0]
        X = np.empty((K, n + 1, 3))
        P = np.empty((K, n + 1, 3))
        T = np.empty((K, n))
        X[:, 0], P[:, 0] = x0, P0
        td = np.full(K, -1)
        f = np.zeros((K, 3))
        f[:, 2] = -self.mu * self.l * self.g
        for k in range(n):
            p = P[:, k]
            for _ in range(iterations):
                E = p - 0.5 * f
                Tk = np.sqrt((E * E).sum(axis=1))
                t = E / np.maximum(Tk, 1e-300)[:, None]
                l_s = self.l * (1.0 + Tk / self.EA)
                f = self.loads(X[:, k], t, l_s)
            T[:, k] = Tk
            X[:, k + 1] = X[:, k] + l_s[:, None] * t
            P[:, k + 1] = p - f
            if stop_on_touchdown:
                new = (td < 0) & (P[:, k + 1, 2] >= 0.0)
                td[new] = k
        if stop_on_touchdown:
            return X, T, P, td
        return X, T, P


def _lay(cable: _Cable, X, T, P, k, seabed_z, cb):
    """Cut one march at the touchdown inside element ``k`` and lay the rest on the seabed.

    Returns (nodes, tension, bottom force, touchdown arc length, laid length, length of it at
    zero tension)."""
    pz0, pz1 = P[k, 2], P[k + 1, 2]
    phi = float(np.clip(-pz0 / (pz1 - pz0), 0.0, 1.0)) if pz1 != pz0 else 1.0
    x_td = X[k] + phi * (X[k + 1] - X[k])
    s_td = (k + phi) * cable.l
    p_td = P[k] + phi * (P[k + 1] - P[k])
    H = math.hypot(p_td[0], p_td[1])
    e = np.array([p_td[0], p_td[1], 0.0]) / max(H, 1e-300)
    LB = max(cable.L - s_td, 0.0)
    w = (cable.mu - float(cable.water.rho(np.array([seabed_z]))[0]) * cable.A) * cable.g

    def tension_at(u):  # u: unstretched distance from the touchdown along the seabed
        return np.maximum(H - cb * max(w, 0.0) * u, 0.0)

    def stretched(u):  # stretched distance from the touchdown
        u = np.asarray(u, dtype=float)
        if cable.EA == math.inf:
            return u
        if cb <= 0 or w <= 0:
            return u * (1 + H / cable.EA)
        u0 = min(H / (cb * w), 1e300)  # tension reaches zero here
        uc = np.minimum(u, u0)
        return u + (H * uc - cb * w * uc * uc / 2) / cable.EA

    N = cable.N
    s_nodes = np.arange(N + 1) * cable.l
    nodes = X.copy()
    on = s_nodes > s_td
    x_lay = x_td.copy()
    x_lay[2] = seabed_z  # (x_td is on the seabed once the touchdown residual vanishes)
    nodes[on] = x_lay + np.outer(stretched(s_nodes[on] - s_td), e)
    tension = T.copy()
    s_mid = (np.arange(N) + 0.5) * cable.l
    lay_el = s_mid > s_td
    tension[lay_el] = tension_at(s_mid[lay_el] - s_td)
    end = x_lay + stretched(LB) * e
    nodes[-1] = end
    # the node before the touchdown can sit a little below the seabed (the discrete cable crosses
    # it inside the touchdown element); hold it on the seabed
    nodes[:, 2] = np.maximum(nodes[:, 2], seabed_z)
    bottom_force = -float(tension_at(LB)) * e
    slack = max(LB - H / (cb * w), 0.0) if cb > 0 and w > 0 else 0.0
    return nodes, tension, bottom_force, s_td, LB, slack


def steady_state(tether: TetherSpec, water: WaterColumn, top, bottom=None, *, top_force=None,
                 bottom_force=None, tow_velocity=(0.0, 0.0, 0.0), seabed: bool = True,
                 seabed_friction: float = 0.0, EA="tether", tol: float = 1e-7,
                 max_iterations: int = 60, guess=None, layout: str = "straight", layout_direction=None,
                 layout_angle: float = math.pi / 2) -> SteadyState:
    """Steady shape and tensions of ``tether`` in ``water`` (see the module docstring).

    Give the ends as either
      * ``top`` and ``bottom`` (both fixed points, m): the shooting problem; or
      * ``top`` and ``top_force`` (force of the cable on the top end, N): one march down; or
      * ``bottom`` and ``bottom_force`` (force of the cable on the bottom end): one march up
        (pass ``top=None``).

    Args:
        tow_velocity: uniform velocity of the whole cable (m/s, world), e.g. a ship and a robot
            moving together; drag acts on u(z) - tow_velocity.
        seabed: with ``True`` and the bottom end on the seabed (within 1 mm), the cable may
            rest on the bottom; with ``False`` the seabed is ignored.
        seabed_friction: Coulomb coefficient cb of the laid cable (>= 0).
        EA: axial stiffness (N); by default the tether's own (``None`` = inextensible).
        tol: required distance of the last node from ``bottom``, relative to the length.
        guess: optional starting force of the cable on the top end (N).
        layout: shape of slack cable on the seabed: "straight", "arc" or "s" (module
            docstring); used only when the cable is slack.
        layout_direction: horizontal direction (world, 2 or 3 numbers; z is ignored; any
            length) in which slack cable leaves the bottom end, back along the robot's track;
            ``None``: from the bottom end towards the top end.
        layout_angle: total turn of the slack cable (rad, in (0, 2 pi)), left (counter-clockwise
            seen from above) for "arc", +/- half of it for "s".

    Raises ``ValueError`` on bad input or when the cable would rest on the seabed between two
    suspended parts (mid-span touchdown is not modelled), ``RuntimeError`` if Newton fails.
    """
    if not isinstance(tether, TetherSpec):
        raise ValueError(f"tether must be a TetherSpec, got {type(tether).__name__}")
    if not isinstance(water, WaterColumn):
        raise ValueError(f"water must be a WaterColumn, got {type(water).__name__}")
    v_tow = _checks.vector3("steady_state.tow_velocity", tow_velocity)
    cb = _checks.non_negative("steady_state.seabed_friction", seabed_friction)
    _checks.positive("steady_state.tol", tol)
    if EA == "tether":
        EA = tether.EA
    elif EA is not None:
        EA = _checks.positive("steady_state.EA", EA, "N")
    if not isinstance(layout, str) or layout not in LAYOUTS:
        raise ValueError(f"steady_state.layout must be one of {', '.join(map(repr, LAYOUTS))}, got {layout!r}")
    layout_b = None
    if layout_direction is not None:
        try:
            b = np.asarray(layout_direction, dtype=float).ravel()
        except (TypeError, ValueError):
            b = np.full(1, np.nan)
        h = math.hypot(b[0], b[1]) if b.shape in ((2,), (3,)) and np.all(np.isfinite(b)) else 0.0
        if not (h > 0.0 and math.isfinite(h)):
            raise ValueError("steady_state.layout_direction must be 2 or 3 finite numbers with a non-zero "
                             f"horizontal part, got {layout_direction!r}")
        layout_b = np.array([b[0] / h, b[1] / h, 0.0])
    layout_angle = _checks.finite("steady_state.layout_angle", layout_angle)
    if not 0.0 < layout_angle < 2 * math.pi:
        raise ValueError(f"steady_state.layout_angle must be in (0, 2 pi) rad, got {layout_angle!r}")
    cable = _Cable(tether, water, v_tow, EA)
    vel = np.tile(v_tow, (tether.segments + 1, 1))
    seabed_z = water.seabed_z
    given = [name for name, v in (("top", top), ("bottom", bottom), ("top_force", top_force),
                                  ("bottom_force", bottom_force)) if v is not None]

    if sorted(given) == ["top", "top_force"] or sorted(given) == ["bottom", "bottom_force"]:
        upward = top is None
        x0 = _checks.vector3("steady_state.bottom" if upward else "steady_state.top", bottom if upward else top)
        F = _checks.vector3("steady_state.bottom_force" if upward else "steady_state.top_force",
                            bottom_force if upward else top_force)
        X, T, P = cable.march(x0[None], F[None])
        X, T, P = X[0], T[0], P[0]
        if upward:
            X, T = X[::-1], T[::-1]
            top_f, bot_f = -P[-1], F
        else:
            top_f, bot_f = F, -P[-1]
        if seabed and X[:, 2].min() < seabed_z - 1e-3:
            raise ValueError("steady_state: the marched cable passes below the seabed; give both ends "
                             "(the touchdown is then solved for) or pass seabed=False")
        return SteadyState(X, T, top_f, bot_f, None, 0.0, vel, 0.0)

    if sorted(given) != ["bottom", "top"]:
        raise ValueError("steady_state: give top and bottom, top and top_force, or bottom and bottom_force; "
                         f"got {', '.join(given) or 'nothing'}")
    top = _checks.vector3("steady_state.top", top)
    bottom = _checks.vector3("steady_state.bottom", bottom)
    for name, p in (("top", top), ("bottom", bottom)):
        if seabed and p[2] < seabed_z - 1e-3:
            raise ValueError(f"steady_state.{name} is below the seabed (z = {seabed_z} m), got z = {p[2]}")
    chord = float(np.linalg.norm(bottom - top))
    if EA is None and chord >= tether.length:
        raise ValueError(f"steady_state: an inextensible tether of length {tether.length} m cannot span "
                         f"{chord:.6g} m between its ends")
    contact = bool(seabed) and abs(bottom[2] - seabed_z) <= 1e-3
    problem = dict(top=top, bottom=bottom, contact=contact, seabed_z=seabed_z, cb=cb, seabed=bool(seabed))
    guess = None if guess is None else _checks.vector3("steady_state.guess", guess)
    if contact:  # slack if it can be (module docstring), else straight-laid
        ss = _slack_state(cable, top, bottom, seabed_z, (layout, layout_b, layout_angle), tol, max_iterations, vel)
        if ss is not None:
            return ss
    return _straight_state(tether, water, v_tow, EA, problem, guess, tol, max_iterations, vel)


def _cascade(tether: TetherSpec, water: WaterColumn, v_tow, EA, pb: dict, guess, tol: float,
             max_iterations: int, first_guess):
    """Newton on the top force for problem ``pb``, started from ``guess`` or, for fine tethers,
    from the solve of a coarse one (the top force converges as 1/N^2, so a coarse solve gives an
    excellent starting force and Jacobian: a cascade, e.g. 200 -> 25 -> 5 elements), else from
    ``first_guess(cable)``. Returns (cable, F, J, the converged march, residual)."""
    cable = _Cable(tether, water, v_tow, EA)
    J = None
    if guess is not None:
        F = guess
    elif tether.segments >= 4 * MIN_COARSE_SEGMENTS:
        coarse = replace(tether, segments=max(tether.segments // 8, MIN_COARSE_SEGMENTS))
        try:
            _, F, J, *_ = _cascade(coarse, water, v_tow, EA, pb, None, max(tol, 1e-5), max_iterations, first_guess)
        except RuntimeError:  # too coarse to resolve the shape: start from scratch at this N
            F = first_guess(cable)
    else:
        F = first_guess(cable)
    return (cable, *_solve_top_force(cable, pb, F, J, tol, max_iterations))


def _straight_state(tether, water, v_tow, EA, pb, guess, tol, max_iterations, vel) -> SteadyState:
    """The two-point solve with any laid part straight (see the module docstring)."""
    seabed_z, contact = pb["seabed_z"], pb["contact"]
    cable, F, J, shot, r = _cascade(tether, water, v_tow, EA, pb, guess, tol, max_iterations,
                                    lambda c: _first_guess(c, pb["top"], pb["bottom"], contact, pb["cb"]))
    X, T, P, td = shot
    if contact and td >= 0:
        nodes, tension, bot_f, s_td, LB, slack = _lay(cable, X, T, P, td, seabed_z, pb["cb"])
        return SteadyState(nodes, tension, F, bot_f, s_td, LB, vel, float(np.linalg.norm(r)), J, slack)
    if pb["seabed"] and X[:, 2].min() < seabed_z - 1e-3:
        raise ValueError("steady_state: the cable would rest on the seabed between its two ends, which is "
                         "not modelled; raise the bottom end onto the seabed or pass seabed=False")
    return SteadyState(X, T, F, -P[-1], None, 0.0, vel, float(np.linalg.norm(r)), J)


def _layout_offsets(layout: str, b: np.ndarray, angle: float, Ls: float, v) -> np.ndarray:
    """Horizontal offsets (m, world), shape (len(v), 3), from the bottom end of the points at
    unstretched distances ``v`` (m, 0 <= v <= Ls) along a slack layout of length ``Ls`` (m)
    that leaves the bottom end along the horizontal unit vector ``b`` (module docstring).
    Linear in (Ls, v) together: the end is Ls times the layout's chord vector per metre."""
    v = np.clip(np.atleast_1d(np.asarray(v, dtype=float)), 0.0, Ls)
    if layout == "straight" or Ls <= 0.0:
        return np.outer(v, b)

    def arc(t, n, rho, phi):  # an arc of radius rho from tangent t turning towards n by phi
        return rho * (np.outer(np.sin(phi), t) + np.outer(1.0 - np.cos(phi), n))

    n = np.array([-b[1], b[0], 0.0])  # z x b: to the left of b
    rho = Ls / angle  # "arc": angle over Ls; "s": angle/2 over Ls/2 each
    if layout == "arc":
        return arc(b, n, rho, v / rho)
    half, a = 0.5 * Ls, 0.5 * angle
    b2 = math.cos(a) * b + math.sin(a) * n  # the tangent at the inflection
    n2 = np.array([-b2[1], b2[0], 0.0])
    return arc(b, n, rho, np.minimum(v, half) / rho) + arc(b2, -n2, rho, np.maximum(v - half, 0.0) / rho)


def _hang_up(cable: _Cable, s_td: float, seabed_z: float, stop_z: float = math.inf, max_iterations: int = 200):
    """March a free hang up from zero force at a touchdown at (0, 0, seabed_z), for an unstretched
    hanging length ``s_td`` (m): first the hanging fraction phi of the touchdown element, then
    whole elements, so that the nodes lie at the material points of the top-down numbering
    (s_td = (k + phi) l). Going up across element j, P_j = P_(j+1) + f_j and the element carries
    E_j = P_(j+1) + f_j / 2 (scaled by phi for the part element); its direction t_j solves
    t = E(t) / |E(t)| by a fixed-point iteration, relaxed whenever it stops contracting: near zero
    tension the load turns the element as much as the tension does, and the plain iteration
    can cycle. Stops above ``stop_z``.

    Returns (nodes from the touchdown up (n, 3), tension of each element from the bottom up,
    P at the last node (the force of the cable on the top, N), phi)."""
    l = cable.l
    k = int(math.floor(s_td / l * (1 + 1e-12)))
    phi = s_td / l - k
    fracs = ([phi] if phi > 1e-12 else []) + [1.0] * k
    x, p = np.array([0.0, 0.0, seabed_z]), np.zeros(3)
    t = np.array([0.0, 0.0, -1.0])  # down the cable, from the upper node to the lower one
    xs, Ts = [x], []
    T = 0.0
    for frac in fracs:
        alpha, miss_old = 1.0, math.inf
        for _ in range(max_iterations):
            l_s = frac * l * (1.0 + T / cable.EA)
            f = cable.loads((x - l_s * t)[None], t[None], np.array([l_s]))[0]
            E = p + 0.5 * frac * f
            T = math.sqrt(E @ E)
            g = E / max(T, 1e-300)
            miss = math.sqrt((g - t) @ (g - t))
            if miss <= 1e-10:
                break
            if miss > 0.5 * miss_old:  # not contracting: relax
                alpha = max(0.5 * alpha, 1.0 / 64)
            miss_old = miss
            t = t + alpha * (g - t)
            t /= math.sqrt(t @ t)
        t = g
        x = x - frac * l * (1.0 + T / cable.EA) * t
        p = p + frac * f
        xs.append(x)
        Ts.append(T)
        if x[2] > stop_z:
            break
    return np.array(xs), np.array(Ts), p, phi


def _slack_state(cable: _Cable, top, bottom, seabed_z, layout_args, tol: float, max_iterations: int,
                 vel) -> SteadyState | None:
    """The slack cable (module docstring): a free hang with zero tension at the touchdown, the
    rest laid at zero tension in the layout; ``None`` if there is none: the cable does not
    sink (at the seabed), hangs freely without reaching the seabed, or leaves too little on the
    seabed to reach the bottom end (it is then straight-laid, with tension).

    The hang is marched up from the touchdown (``_hang_up``): the current depends on depth
    only, so the hang's shape is the same wherever the touchdown is, and only its length s_td
    is solved for (secant method on the height it reaches), then the hang is moved under the
    top. Raises ``RuntimeError`` if that fails."""
    layout, b, angle = layout_args
    w = (cable.mu - float(cable.water.rho(np.array([seabed_z]))[0]) * cable.A) * cable.g
    drop = top[2] - seabed_z
    if w <= 0 or drop <= 0:
        return None
    L, l = cable.L, cable.l
    R = np.array([bottom[0], bottom[1], seabed_z])

    def laid_room(s, x_top):  # cable left on the seabed minus the distance from the touchdown to R
        d = R - (top - x_top)
        return L - s - math.hypot(d[0], d[1])

    # the whole length in whole elements: where it passes the top's height estimates s_td
    xs, *_ = _hang_up(cable, L, seabed_z, stop_z=top[2])
    z = xs[:, 2]
    if z[-1] < top[2]:
        return None  # hanging freely, it would not reach the seabed
    j = int(np.argmax(z >= top[2]))
    a = (top[2] - z[j - 1]) / (z[j] - z[j - 1])
    s = (j - 1 + a) * l
    if laid_room(s, xs[j - 1] + a * (xs[j] - xs[j - 1])) < -2 * l:
        return None  # clearly too short to lie slack
    slope = (z[j] - z[j - 1]) / l  # d(height reached) / d(s_td): then secants
    s_prev = g_prev = None
    for _ in range(max_iterations):
        xs, Ts, F, phi = _hang_up(cable, s, seabed_z)
        g = xs[-1, 2] - top[2]
        if abs(g) <= tol * L:
            break
        if s_prev is not None and s != s_prev and (g - g_prev) / (s - s_prev) > 0:
            slope = (g - g_prev) / (s - s_prev)
        s_prev, g_prev = s, g
        s_new = min(max(s - g / slope, 0.5 * s), L)
        if s_new == s:
            return None  # it needs more than the whole cable
        s = s_new
    else:
        raise RuntimeError(f"steady_state: the free hang of a slack cable did not converge (height miss {g:.3g} m)")
    if laid_room(s, xs[-1]) < 0.0:
        return None
    shift = np.array([top[0] - xs[-1, 0], top[1] - xs[-1, 1], 0.0])
    hang = xs[::-1] + shift  # nodes 0 .. k, then the touchdown
    hang[0] = top
    x_td = hang[-1]
    k = len(xs) - 1 - (1 if phi > 1e-12 else 0)  # node index at the top of the touchdown element
    LB = L - s
    d = R - x_td
    if b is None:  # from the bottom end towards the top (or the touchdown, or +x)
        for v in (top - R, x_td - R, np.array([1.0, 0.0, 0.0])):
            if math.hypot(v[0], v[1]) > 1e-9 * L:
                b = np.array([v[0], v[1], 0.0]) / math.hypot(v[0], v[1])
                break
    # L_s + |d + L_s c| = LB  <=>  A L_s^2 - 2 B L_s + C = 0, smallest root (module docstring)
    c = _layout_offsets(layout, b, angle, 1.0, [1.0])[0]
    A, B, C = 1.0 - c @ c, d @ c + LB, LB * LB - d @ d
    Ls = min(max(C / max(B + math.sqrt(max(B * B - A * C, 0.0)), 1e-300), 0.0), LB)
    Q0 = R + Ls * c
    Lc = LB - Ls  # the straight piece from the touchdown to Q0
    join = (Q0 - x_td) / max(Lc, 1e-300)
    N = cable.N
    u = np.arange(k + 1, N + 1) * l - s  # unstretched distance of the laid nodes from the touchdown
    nodes = np.empty((N + 1, 3))
    nodes[:k + 1] = hang[:k + 1]
    nodes[k + 1:] = np.where((u <= Lc)[:, None], x_td + np.outer(u, join),
                             R + _layout_offsets(layout, b, angle, Ls, LB - u))
    nodes[-1] = R
    nodes[k + 1:, 2] = seabed_z
    tension = np.zeros(N)
    tension[:k] = Ts[::-1][:k] if phi <= 1e-12 else Ts[1:][::-1]
    if phi > 0.5:  # the touchdown element is mostly hanging
        tension[k] = Ts[0]
    return SteadyState(nodes, tension, F, np.zeros(3), s, LB, vel, abs(float(g)), None, LB)


def _shoot(cable: _Cable, pb: dict, F: np.ndarray):
    """Residuals (m), shape (K, 3), of the shots with top forces ``F`` (K, 3), and the marches."""
    K = F.shape[0]
    X, T, P, td = cable.march(np.tile(pb["top"], (K, 1)), F, stop_on_touchdown=True)
    r = np.empty((K, 3))
    for j in range(K):
        k = td[j]
        if pb["contact"] and k >= 0:
            nodes, *_ = _lay(cable, X[j], T[j], P[j], k, pb["seabed_z"], pb["cb"])
            phi = np.clip(-P[j, k, 2] / (P[j, k + 1, 2] - P[j, k, 2]), 0.0, 1.0)
            r[j] = nodes[-1] - pb["bottom"]
            r[j, 2] = X[j, k, 2] + phi * (X[j, k + 1, 2] - X[j, k, 2]) - pb["seabed_z"]  # touchdown height
        else:
            r[j] = X[j, -1] - pb["bottom"]
    return r, (X, T, P, td)


def _force_scale(cable: _Cable, top, bottom) -> float:
    """A force (N) of the order of the tether's loads: weight or drag on its whole length."""
    zs = np.linspace(min(top[2], 0.0), min(bottom[2], 0.0), 8)
    rho = float(cable.water.rho(zs[4:5])[0])
    w = abs(cable.mu - rho * cable.A) * cable.g
    u = float(np.max(np.linalg.norm(cable.water.velocity(zs) - cable.v_tow, axis=1)))
    return max(w, 0.5 * rho * cable.cdn * cable.d * u * u, 1e-3) * cable.L


def _first_guess(cable: _Cable, top, bottom, contact: bool = False, cb: float = 0.0) -> np.ndarray:
    """The analytic catenary's top force (no current, mean density), when it applies; else half
    the weight down plus the force scale along the chord."""
    d = bottom - top
    w = (cable.mu - float(cable.water.rho(np.array([0.5 * (top[2] + bottom[2])]))[0]) * cable.A) * cable.g
    if w > 0 and top[2] >= bottom[2] and np.hypot(d[0], d[1]) > 1e-6 * cable.L:
        try:
            c = catenary(bottom, top, cable.L, w, EA=None if cable.EA == math.inf else cable.EA, cb=cb,
                         seabed=contact)
            return c.fairlead_force
        except (ValueError, RuntimeError):
            pass
    return 0.5 * abs(w) * cable.L * np.array([0.0, 0.0, -1.0]) + d / max(np.linalg.norm(d), 1e-9) * 0.5 * \
        _force_scale(cable, top, bottom)


def _solve_top_force(cable: _Cable, pb: dict, F, J, tol: float, max_iterations: int):
    """Newton's method on the top force with a backtracking line search. With a starting
    Jacobian ``J`` (from a coarser solve) it first tries chord steps, which need one march each.
    Returns (F, J, the converged march, residual)."""
    scale = _force_scale(cable, pb["top"], pb["bottom"])
    L = cable.L

    def with_jacobian(F):
        h = 1e-6 * max(np.linalg.norm(F), scale * 1e-3)
        rs, (X, T, P, td) = _shoot(cable, pb, np.vstack([F, F + h * np.eye(3)]))
        return rs[0], (rs[1:] - rs[0]).T / h, (X[0], T[0], P[0], int(td[0]))

    def single(F):
        rs, (X, T, P, td) = _shoot(cable, pb, F[None])
        return rs[0], (X[0], T[0], P[0], int(td[0]))

    if J is None:
        r, J, shot = with_jacobian(F)
        fresh = True
    else:
        r, shot = single(F)
        fresh = False
    for it in range(max_iterations):
        if np.linalg.norm(r) <= tol * L:
            return F, J, shot, r
        try:
            step = -np.linalg.solve(J, r)
        except np.linalg.LinAlgError:
            step = -np.linalg.lstsq(J, r, rcond=None)[0]
        lim = 0.5 * max(np.linalg.norm(F), scale)  # no step larger than half the force scale
        if np.linalg.norm(step) > lim:
            step *= lim / np.linalg.norm(step)
        if not fresh:  # chord step with the inherited Jacobian: keep it while it converges fast
            r_new, shot_new = single(F + step)
            if np.all(np.isfinite(r_new)) and np.linalg.norm(r_new) < 0.25 * np.linalg.norm(r):
                F, r, shot = F + step, r_new, shot_new
                continue
            r, J, shot = with_jacobian(F)
            fresh = True
            continue
        r_new, J_new, shot_new = with_jacobian(F + step)
        if np.all(np.isfinite(r_new)) and np.linalg.norm(r_new) < np.linalg.norm(r):
            F, r, J, shot = F + step, r_new, J_new, shot_new
            continue
        a = 0.5
        while True:
            r_new, _ = single(F + a * step)
            if np.all(np.isfinite(r_new)) and np.linalg.norm(r_new) < np.linalg.norm(r) * (1 - 1e-4 * a):
                break
            a *= 0.5
            if a < 1e-4:
                raise RuntimeError(f"steady_state: Newton stalled at |residual| = {np.linalg.norm(r):.3g} m "
                                   f"after {it} iterations")
        F = F + a * step
        r, J, shot = with_jacobian(F)
    raise RuntimeError(f"steady_state: no convergence in {max_iterations} iterations "
                       f"(|residual| = {np.linalg.norm(r):.3g} m)")

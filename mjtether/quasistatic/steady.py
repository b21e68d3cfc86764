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

Line make-ups. ``tether`` may be a ``mjtether.makeup.LineMakeup`` instead of a ``TetherSpec``:
sections of different line types joined end to end (each with its own element length, diameter,
mass, EA and drag coefficients), float sections (extra volume, mass and normal drag area per
metre on the elements they cover) and point loads (clump weights, buoyancy modules) lumped on the
nodes by the lever rule. The march uses each element's own properties, and node k + 1 adds its
point load g = (rho V - m) g z_hat (buoyancy only under water) + 1/2 rho CdA |u| u (u the relative
velocity at the node): P_k+1 = P_k - f_k - g_k+1 (added mass plays no part in statics). A point
load on node 0 is counted in the top force. What is supported for a make-up:

* two fixed ends, suspended (``seabed=False``, or clear of the seabed);
* the bottom end on the seabed with a straight-laid part: the touchdown is the first element
  after the last buoyant part (a buoyant element or a net buoyant point load, which cannot lie on
  the seabed) where P_z turns from negative to >= 0, inside the element or on a node whose point
  load (a clump holding the touchdown) turns it (the seabed carries that load's weight; its
  drag goes on into the laid part); the laid part's tension falls by cb w per metre
  with each element's own w and by cb W at each laid clump of wet weight W, never below zero
  (the rest lies unstretched, at zero tension);
* the top end on the seabed too (within 1 mm), e.g. one half of a symmetric U between two
  anchors: the line may lie on the seabed from the top and lift off. The shooting parameter is
  then F: with F_z >= 0 the line leaves the top with force F; with F_z < 0 it lies on the seabed
  for the length whose wet weight is -F_z and lifts off with horizontal force (F_x, F_y), its
  tension falling by friction towards the top (``top_laid_length``; the reported top force is the
  anchor's, horizontal). The shot is continuous in F, so Newton works as before;
* single marches from either end (``top_force`` or ``bottom_force``).

Refused: a line resting on the seabed between two suspended parts (ValueError, as for a
TetherSpec), and a slack make-up (too long to lie taut between its touchdown and the bottom end):
the zero-tension hang above is solved only for uniform lines (a one-section make-up without loads
is solved like a TetherSpec, slack included); for others, when no taut solution is found with the
bottom end on the seabed, ``NotImplementedError`` says so.

Frames: world, z up, water surface z = 0, seabed z = -water.depth. SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.integrate import trapezoid

from .. import _checks, compiled
from ..hydro import morison_drag, wet_fraction
from ..makeup import LineMakeup
from ..tether import TetherSpec
from ..water import WaterColumn
from .catenary import catenary


MIN_COARSE_SEGMENTS = 12
"""Fewest elements of the coarse solves that start Newton's method for finer tethers. (5 gave a
coarse model too poor in a current sheared over a few elements' length: its Newton steps cost
more than they saved, 165 of the 176 marches of a 200-element tether in a 0.5 m/s exponential
current, 5 ms against 1.6 ms with 12; the converged states are the same to the tolerance.)"""

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
        top_laid_length: unstretched length lying on the seabed at the top end (m): a
            ``LineMakeup`` whose top end is on the seabed (the lift-off point is there); else 0.
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
    top_laid_length: float = 0.0

    @property
    def tow_tension(self) -> float:
        """Tension at the bottom (robot) end |bottom_force| (N)."""
        return float(np.linalg.norm(self.bottom_force))

    @property
    def top_tension(self) -> float:
        """Tension at the top (ship) end |top_force| (N)."""
        return float(np.linalg.norm(self.top_force))


class _Cable:
    """Constants of the march for one tether (a ``TetherSpec`` or a ``LineMakeup``) in one water
    column: per-element arrays (``l_e``, ``d_e``, ...) and, for a uniform line, the same as
    scalars (``l``, ``d``, ...; ``None`` for a non-uniform make-up)."""

    def __init__(self, tether, water: WaterColumn, tow_velocity, EA):
        self.g = water.gravity
        self.water = water
        self._wet_at = {}  # seabed height (m): wet weight per metre there (N/m), see seabed_wet_weight
        self.v_tow = np.asarray(tow_velocity, dtype=float)
        self.float_cda = None  # normal drag area of distributed floats per metre, per element
        self.node_loads = None  # (mass, volume, cd_area) per node, where any
        self.k_min = 0  # first element that may hold the touchdown
        if isinstance(tether, TetherSpec):
            self.makeup = None
            self.N = N = tether.segments
            self.l = tether.segment_length
            self.L = tether.length
            self.EA = math.inf if EA is None else float(EA)
            self.d = tether.diameter
            self.A = tether.area
            self.mu = tether.mu
            self.cdn = tether.cd_normal
            self.cdt_pi = math.pi * tether.cd_tangential
            self.l_e, self.EA_e, self.d_e = np.full(N, self.l), np.full(N, self.EA), np.full(N, self.d)
            self.A_e, self.mu_e = np.full(N, self.A), np.full(N, self.mu)
            self.cdn_e, self.cdt_pi_e = np.full(N, self.cdn), np.full(N, self.cdt_pi)
            self.s_node = np.arange(N + 1) * self.l
            self.fast = self._compiled()
            return
        line: LineMakeup = tether
        self.makeup = line
        self.N = N = line.segments
        self.L = line.length
        self.l_e = line.element_length
        if EA == "tether":
            self.EA_e = line.element_EA
        else:
            self.EA_e = np.full(N, math.inf if EA is None else float(EA))
        self.d_e = line.element_diameter
        self.A_e = line.element_area
        self.mu_e = line.element_mass_per_length
        self.cdn_e = line.element_cd_normal
        self.cdt_pi_e = math.pi * line.element_cd_tangential
        self.s_node = line.node_arc_length
        if np.any(line.element_float_cd_area > 0):
            self.float_cda = line.element_float_cd_area
        if line.has_point_loads:
            self.node_loads = (line.node_mass, line.node_volume, line.node_cd_area)
        if line.is_uniform:  # the scalars of the uniform path (the slack state uses them)
            self.l, self.EA, self.d, self.A = float(self.l_e[0]), float(self.EA_e[0]), float(self.d_e[0]), float(self.A_e[0])
            self.mu, self.cdn, self.cdt_pi = float(self.mu_e[0]), float(self.cdn_e[0]), float(self.cdt_pi_e[0])
        else:
            self.l = self.EA = self.d = self.A = self.mu = self.cdn = self.cdt_pi = None
        # buoyant parts cannot lie on the seabed: the touchdown comes after the last of them
        self.w_sb = self.seabed_weight(self.mu_e, self.A_e)
        buoyant = [e + 1 for e in np.flatnonzero(self.w_sb < 0.0)]
        if self.node_loads is not None:
            self.W_sb = self.seabed_weight(self.node_loads[0], self.node_loads[1])
            buoyant += list(np.flatnonzero(self.W_sb < 0.0))
        else:
            self.W_sb = np.zeros(N + 1)
        self.k_min = int(max(buoyant, default=0))
        self.fast = self._compiled()

    def _compiled(self):
        """The arguments of ``compiled.steady_march`` after the shots (the same march, compiled),
        or None where it does not apply (the NumPy kernels, a water profile it does not know)."""
        codes = compiled.profile_codes(self.water) if compiled.backend() == "numba" else None
        if codes is None:
            return None
        f = lambda a: np.ascontiguousarray(np.broadcast_to(a, (self.N,)), dtype=float)  # noqa: E731
        return (f(self.l_e), f(self.EA_e), f(self.d_e), f(self.A_e), f(self.mu_e), f(self.cdn_e), f(self.cdt_pi_e),
                f(0.0 if self.float_cda is None else self.float_cda), *codes, self.v_tow.astype(float), float(self.g))

    def seabed_wet_weight(self, seabed_z: float) -> float:
        """Submerged weight per metre (N/m) of the uniform line on a seabed at ``seabed_z`` (m)."""
        w = self._wet_at.get(seabed_z)
        if w is None:
            w = self._wet_at[seabed_z] = (self.mu - float(self.water.rho(np.array([seabed_z]))[0]) * self.A) * self.g
        return w

    def seabed_weight(self, mass, volume):
        """Submerged weight (N or N/m) of ``mass`` and ``volume`` at the seabed's density."""
        rho = float(self.water.rho(np.array([self.water.seabed_z]))[0])
        return (np.asarray(mass) - rho * np.asarray(volume)) * self.g

    def loads(self, x0, t, l_s, k=0):
        """External load (N) on elements ``k`` starting at ``x0`` (K, 3) with tangents ``t`` (K, 3)
        and stretched lengths ``l_s`` (K,)."""
        l, d, A, mu = self.l_e[k], self.d_e[k], self.A_e[k], self.mu_e[k]
        z0 = x0[:, 2]
        z1 = z0 + l_s * t[:, 2]
        if z0.max() <= 0.0 and z1.max() <= 0.0:  # fully wet, the usual case
            zc = 0.5 * (z0 + z1)
            l_wet = l
        else:
            zc = np.minimum(0.5 * (z0 + z1), 0.0)
            l_wet = l * wet_fraction(z0, z1)[0]
        rho = self.water.rho(zc)
        u = self.water.velocity(zc) - self.v_tow
        floats = self.float_cda[k] if self.float_cda is not None and self.float_cda[k] > 0.0 else None
        f = morison_drag(t, u, rho, l_wet, d, self.cdn_e[k], self.cdt_pi_e[k], floats)
        f[:, 2] += (rho * A * l_wet - mu * l) * self.g
        return f

    def node_load(self, x, j):
        """Point load (N) on node ``j`` at positions ``x`` (K, 3): weight, buoyancy (under water
        only) and drag 1/2 rho CdA |u| u on the relative velocity; ``None`` if the node has none."""
        if self.node_loads is None:
            return None
        m, V, cda = (a[j] for a in self.node_loads)
        if m == 0.0 and V == 0.0 and cda == 0.0:
            return None
        z = x[:, 2]
        zc = np.minimum(z, 0.0)
        wet = (z <= 0.0).astype(float)
        rho = self.water.rho(zc)
        g = np.zeros((x.shape[0], 3))
        g[:, 2] = (rho * V * wet - m) * self.g
        if cda > 0.0:
            u = self.water.velocity(zc) - self.v_tow
            g += (0.5 * rho * cda * wet * np.sqrt((u * u).sum(axis=1)))[:, None] * u
        return g

    def march(self, x0, P0, stop_on_touchdown=False, iterations=2, start=0, first_frac=1.0, allow_first=True,
              own_load=True):
        """March the N elements from node positions ``x0`` with forces ``P0`` (K, 3).

        Returns (nodes (K, n+1, 3), tension (K, n), P (K, n+1, 3)); P excludes the point load on
        its own node (``P0`` includes node 0's: it is the top force). With
        ``stop_on_touchdown`` the march of each shot also records the first element k (from
        ``k_min`` on) where the vertical component of P becomes >= 0 (P_k,z < 0 <= P_k+1,z, or
        just P_k+1,z >= 0 at k = k_min with ``allow_first``), returned as the fourth item, -1 if
        never. Make-ups only: a march may start at node ``start`` (``x0`` is then the point where
        it starts, ``P0`` the force there, already net of any point load there when not
        ``own_load``) with a first element of fraction ``first_frac``; the fifth item is the
        point loads on the nodes (K, n+1, 3).
        """
        n = self.N
        K = x0.shape[0]
        X = np.empty((K, n + 1, 3))
        P = np.empty((K, n + 1, 3))
        T = np.empty((K, n))
        if self.fast is not None and start == 0 and first_frac == 1.0 and self.node_loads is None:
            td = np.empty(K, dtype=np.int64)
            compiled.steady_march(np.ascontiguousarray(x0, dtype=float), np.ascontiguousarray(P0, dtype=float),
                                  *self.fast, iterations, stop_on_touchdown, max(self.k_min, start), allow_first,
                                  X, T, P, td)
            if self.makeup is not None:
                return X, T, P, td, np.zeros((K, n + 1, 3))
            return (X, T, P, td) if stop_on_touchdown else (X, T, P)
        X[:, start], P[:, start] = x0, P0
        G = np.zeros((K, n + 1, 3)) if self.makeup is not None else None
        if start == 0 and own_load:
            g0 = self.node_load(X[:, 0], 0)
            if g0 is not None:
                G[:, 0] = g0
                P[:, 0] = P0 - g0
        td = np.full(K, -1)
        k_min = max(self.k_min, start)
        f = np.zeros((K, 3))
        f[:, 2] = -self.mu_e[start] * self.l_e[start] * self.g
        for k in range(start, n):
            p = P[:, k]
            l, EA = self.l_e[k], self.EA_e[k]
            if k == start and first_frac != 1.0:
                frac = first_frac
                for _ in range(iterations):
                    E = p - 0.5 * frac * f
                    Tk = np.sqrt((E * E).sum(axis=1))
                    t = E / np.maximum(Tk, 1e-300)[:, None]
                    l_s = frac * l * (1.0 + Tk / EA)
                    f = self.loads(X[:, k], t, l_s, k)
                f = frac * f
            else:
                for _ in range(iterations):
                    E = p - 0.5 * f
                    Tk = np.sqrt((E * E).sum(axis=1))
                    t = E / np.maximum(Tk, 1e-300)[:, None]
                    l_s = l * (1.0 + Tk / EA)
                    f = self.loads(X[:, k], t, l_s, k)
            T[:, k] = Tk
            X[:, k + 1] = X[:, k] + l_s[:, None] * t
            g = self.node_load(X[:, k + 1], k + 1)
            if g is None:
                P[:, k + 1] = p - f
            else:
                G[:, k + 1] = g
                P[:, k + 1] = p - f - g
            if stop_on_touchdown and k >= k_min:
                new = (td < 0) & (P[:, k + 1, 2] >= 0.0)
                if not (k == k_min and allow_first):
                    new &= P[:, k, 2] < 0.0
                td[new] = k
        if self.makeup is not None:
            return X, T, P, td, G
        if stop_on_touchdown:
            return X, T, P, td
        return X, T, P


def _touchdown_fraction(P, k: int) -> float:
    """Where in element ``k`` of a march the vertical force ``P[:, 2]`` (N) crosses zero: the
    touchdown, as a fraction of the element (0 at node k, 1 at node k+1)."""
    pz0, pz1 = float(P[k, 2]), float(P[k + 1, 2])
    return min(max(-pz0 / (pz1 - pz0), 0.0), 1.0) if pz1 != pz0 else 1.0


def _lay(cable: _Cable, X, T, P, k, seabed_z, cb, end_only: bool = False):
    """Cut one march at the touchdown inside element ``k`` and lay the rest on the seabed.

    Returns (nodes, tension, bottom force, touchdown arc length, laid length, length of it at
    zero tension); with ``end_only``, just the laid end (the last node, m: what a shot needs)."""
    phi = _touchdown_fraction(P, k)
    x_td = X[k] + phi * (X[k + 1] - X[k])
    s_td = (k + phi) * cable.l
    px, py = (float(P[k, i]) + phi * (float(P[k + 1, i]) - float(P[k, i])) for i in range(2))
    H = math.hypot(px, py)
    e = np.array([px, py, 0.0]) / max(H, 1e-300)
    LB = max(cable.L - s_td, 0.0)
    w = cable.seabed_wet_weight(seabed_z)

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

    if end_only:
        x_lay = x_td.copy()
        x_lay[2] = seabed_z
        return x_lay + float(stretched(LB)) * e
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


def _laid_profile(cable: _Cable, s0: float, direction: int, length: float, H: float, cb: float):
    """A straight laid stretch of a make-up: from arc length ``s0`` (tension ``H`` there) for
    ``length`` (m, unstretched) towards larger (``direction`` +1) or smaller (-1) arc lengths,
    its tension falling by cb w per metre (w: each element's wet weight at the seabed, >= 0) and
    by cb W at each laid node with a point load of wet weight W > 0, never below zero.

    Returns (idx, S, S_end, tension_at, T_end, slack): the nodes strictly inside the stretch (in
    the order met), their stretched distances (m) from ``s0``, the stretched length of the whole
    stretch, a function giving the tension (N) at unstretched distances from ``s0``, the tension
    at the far end, and the unstretched length at zero tension."""
    s, N = cable.s_node, cable.N
    eps = 1e-12 * max(cable.L, 1.0)
    if direction > 0:
        idx = np.flatnonzero((s > s0 + eps) & (s < s0 + length - eps))
        u_in = s[idx] - s0
    else:
        idx = np.flatnonzero((s < s0 - eps) & (s > s0 - length + eps))[::-1]
        u_in = s0 - s[idx]
    b = np.concatenate([[0.0], u_in, [max(length, 0.0)]])
    n_p = len(b) - 1
    mids = s0 + direction * 0.5 * (b[:-1] + b[1:])
    e = np.clip(np.searchsorted(s, mids, side="right") - 1, 0, N - 1)
    c = cb * np.maximum(cable.w_sb[e], 0.0)
    EA = cable.EA_e[e]
    drops = cb * np.maximum(cable.W_sb[idx], 0.0)
    T0 = np.empty(n_p)
    S = np.zeros(n_p + 1)
    T, slack = float(H), 0.0
    for i in range(n_p):
        if i > 0:
            T = max(T - drops[i - 1], 0.0)
        T0[i] = T
        D = b[i + 1] - b[i]
        if c[i] > 0.0:
            uc = min(D, T / c[i])
            integral = T * uc - c[i] * uc * uc / 2
            slack += D - uc
            T = max(T - c[i] * D, 0.0)
        else:
            integral = T * D
            slack += D if T <= 0.0 else 0.0
        S[i + 1] = S[i] + D + integral / EA[i]

    def tension_at(u):
        u = np.asarray(u, dtype=float)
        i = np.clip(np.searchsorted(b, u, side="right") - 1, 0, n_p - 1)
        return np.maximum(T0[i] - c[i] * (u - b[i]), 0.0)

    return idx, S[1:-1], float(S[-1]), tension_at, T, slack


def _lay_makeup(cable: _Cable, X, T, P, G, k, seabed_z, cb):
    """``_lay`` for a make-up: cut the march at the touchdown inside element ``k`` (or on node
    k + 1, where a point load takes P_z over zero) and lay the rest straight on the seabed.

    Returns (nodes, tension, bottom force, touchdown arc length, laid length, length of it at zero
    tension, height of the touchdown point)."""
    f = P[k] - P[k + 1] - G[k + 1]  # element k's load
    phi = float(np.clip(P[k, 2] / f[2], 0.0, 1.0)) if f[2] != 0.0 else 1.0
    x_td = X[k] + phi * (X[k + 1] - X[k])
    s_td = float(cable.s_node[k] + phi * cable.l_e[k])
    p_td = P[k] - phi * f
    if phi >= 1.0:  # touchdown on node k + 1: the seabed carries its point load's vertical part, and
        # the horizontal part (a clump's drag) goes on into the laid line
        p_td = p_td - np.array([G[k + 1][0], G[k + 1][1], 0.0])
    H = math.hypot(p_td[0], p_td[1])
    e = np.array([p_td[0], p_td[1], 0.0]) / max(H, 1e-300)
    LB = max(cable.L - s_td, 0.0)
    idx, S, S_end, tension_at, T_end, slack = _laid_profile(cable, s_td, +1, LB, H, cb)
    nodes = X.copy()
    x_lay = x_td.copy()
    x_lay[2] = seabed_z
    nodes[idx] = x_lay + np.outer(S, e)
    nodes[-1] = x_lay + S_end * e
    tension = T.copy()
    s_mid = cable.s_node[:-1] + 0.5 * cable.l_e
    lay_el = s_mid > s_td
    tension[lay_el] = tension_at(s_mid[lay_el] - s_td)
    # as in _lay: the node before the touchdown can sit a little below the seabed; hold it there
    nodes[:, 2] = np.maximum(nodes[:, 2], seabed_z)
    return nodes, tension, -T_end * e, s_td, LB, slack, float(x_td[2])


def _liftoff(cable: _Cable, F, top, cb: float):
    """The laid start of a make-up whose top end is on the seabed, from the shooting parameter
    ``F`` (3,): with F_z >= 0 the line leaves the top end with force F (``None`` is returned);
    with F_z < 0 a length s_lo lies on the seabed from the top, the one whose wet weight is -F_z
    (point loads included; a partly lifted one at the lift-off node), and the line lifts off
    there with horizontal force (F_x, F_y): this keeps the shot continuous in F.

    Returns a dict: start (node the march starts from), frac (fraction of its first element
    still to march), x (lift-off point), p (force there), s_lo, e (horizontal direction), and
    the laid part's nodes, positions and tension."""
    D = -float(F[2])
    if not D > 0.0:
        return None
    s, N = cable.s_node, cable.N
    start, frac, Pz = N - 1, 1.0, 0.0
    for e_ in range(N):
        w, l = cable.w_sb[e_], cable.l_e[e_]
        if w <= 0.0:  # a buoyant or neutral element does not lie on the seabed
            start = e_
            break
        if D < w * l * (1.0 - 1e-12):
            start, frac = e_, 1.0 - D / (w * l)
            break
        D = max(D - w * l, 0.0)
        if e_ + 1 >= N:
            break
        W = cable.W_sb[e_ + 1]
        if W < 0.0 or D <= W:  # lift-off at node e_ + 1 (a point load there partly lifted)
            start, Pz = e_ + 1, (max(W - D, 0.0) if W >= 0.0 else 0.0)
            break
        D -= W
    s_lo = float(s[start] + (1.0 - frac) * cable.l_e[start])
    H = math.hypot(F[0], F[1])
    e = np.array([F[0], F[1], 0.0]) / H if H > 0.0 else np.array([1.0, 0.0, 0.0])
    profile = _laid_profile(cable, s_lo, -1, s_lo, H, cb)
    return dict(start=start, frac=frac, s_lo=s_lo, e=e, H=H, p=np.array([F[0], F[1], Pz]),
                x=top + profile[2] * e, profile=profile)


def _lay_top(cable: _Cable, lift: dict, top, X, T, P):
    """Fill the laid top part of one make-up march in place: its nodes, tensions and forces.
    Returns the force on the top end (N)."""
    s_lo, e, start = lift["s_lo"], lift["e"], lift["start"]
    idx, S, S_end, tension_at, T_end, _ = lift["profile"]
    x_lo = lift["x"]
    X[idx] = x_lo - np.outer(S, e)
    X[0] = top
    s_mid = cable.s_node[:-1] + 0.5 * cable.l_e
    lay_el = s_mid < s_lo
    T[lay_el] = tension_at(s_lo - s_mid[lay_el])
    P[:start] = lift["p"]
    return T_end * e


def _shoot_makeup(cable: _Cable, pb: dict, F: np.ndarray):
    """``_shoot`` for a make-up: residuals (K, 3) and, per shot, a dict of the finished state."""
    K = F.shape[0]
    top, cb = pb["top"], pb["cb"]
    marches = []
    if pb.get("top_contact"):
        for j in range(K):
            lift = _liftoff(cable, F[j], top, cb)
            if lift is None:
                X, T, P, td, G = cable.march(top[None], F[j][None], stop_on_touchdown=True, allow_first=False)
                marches.append((X[0], T[0], P[0], int(td[0]), G[0], None, F[j].copy()))
                continue
            X, T, P, td, G = cable.march(lift["x"][None], lift["p"][None], stop_on_touchdown=True,
                                         start=lift["start"], first_frac=lift["frac"], allow_first=False,
                                         own_load=False)
            X, T, P = X[0], T[0], P[0]
            top_f = _lay_top(cable, lift, top, X, T, P)
            marches.append((X, T, P, int(td[0]), G[0], lift, top_f))
    else:
        X, T, P, td, G = cable.march(np.tile(top, (K, 1)), F, stop_on_touchdown=True)
        marches = [(X[j], T[j], P[j], int(td[j]), G[j], None, F[j].copy()) for j in range(K)]
    r = np.empty((K, 3))
    shots = []
    for j, (X, T, P, k, G, lift, top_f) in enumerate(marches):
        shot = dict(X=X, T=T, P=P, td=k, lift=lift, top_force=top_f, nodes=X, tension=T,
                    bottom_force=-P[-1], s_td=None, LB=0.0, slack=0.0)
        if pb["contact"] and k >= 0:
            nodes, tension, bot_f, s_td, LB, slack, z_td = _lay_makeup(cable, X, T, P, G, k, pb["seabed_z"], cb)
            shot.update(nodes=nodes, tension=tension, bottom_force=bot_f, s_td=s_td, LB=LB, slack=slack)
            r[j] = nodes[-1] - pb["bottom"]
            r[j, 2] = z_td - pb["seabed_z"]  # touchdown height
        else:
            r[j] = X[-1] - pb["bottom"]
        shots.append(shot)
    return r, shots


def _makeup_state(cable: _Cable, pb: dict, F, J, shot: dict, r, vel) -> SteadyState:
    """The ``SteadyState`` of a converged make-up shot, after checking that the suspended part
    does not pass below the seabed (by more than 1 mm, or 2 % of the longest element next to a
    touchdown or lift-off, where the discrete line may dip a little under the continuous one)."""
    seabed_z = pb["seabed_z"]
    lift = shot["lift"]
    first = lift["start"] + 1 if lift is not None else 0
    td = shot["td"] if pb["contact"] and shot["td"] >= 0 else -1
    last = td if td >= 0 else cable.N
    z = shot["X"][first:last + 1, 2]
    allow = np.full(z.shape, 1e-3)
    near = 0.02 * float(np.max(cable.l_e))
    if td >= 0 and len(z):
        allow[-2:] = max(1e-3, near)
    if lift is not None and len(z):
        allow[:2] = max(1e-3, near)
    if pb["seabed"] and len(z) and np.any(z < seabed_z - allow):
        raise ValueError("steady_state: the cable would rest on the seabed between its two ends, which is "
                         "not modelled; raise the bottom end onto the seabed or pass seabed=False")
    return SteadyState(shot["nodes"], shot["tension"], shot["top_force"], shot["bottom_force"], shot["s_td"],
                       shot["LB"], vel, float(np.linalg.norm(r)), J, shot["slack"],
                       lift["s_lo"] if lift is not None else 0.0)


def _coarse(tether):
    """A coarser version of ``tether`` (about 1/8 of its elements) for the cascade."""
    n = max(tether.segments // 8, MIN_COARSE_SEGMENTS)
    if isinstance(tether, TetherSpec):
        return replace(tether, segments=n)
    sections = tuple(replace(s, segments=max(1, round(s.segments * n / tether.segments))) for s in tether.sections)
    return LineMakeup(sections, tether.loads)


def steady_state(tether: TetherSpec | LineMakeup, water: WaterColumn, top, bottom=None, *, top_force=None,
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
        guess: optional starting force of the cable on the top end (N) (for a make-up whose top
            end is on the seabed: the shooting parameter F of the module docstring).
        layout: shape of slack cable on the seabed: "straight", "arc" or "s" (module
            docstring); used only when the cable is slack.
        layout_direction: horizontal direction (world, 2 or 3 numbers; z is ignored; any
            length) in which slack cable leaves the bottom end, back along the robot's track;
            ``None``: from the bottom end towards the top end.
        layout_angle: total turn of the slack cable (rad, in (0, 2 pi)), left (counter-clockwise
            seen from above) for "arc", +/- half of it for "s".

    ``tether`` is a uniform ``TetherSpec`` or a ``LineMakeup`` (sections, point loads, float
    sections; see "Line make-ups" in the module docstring). For a make-up, ``EA`` = "tether"
    takes each section's own EA, a number or ``None`` replaces them all.

    Raises ``ValueError`` on bad input or when the cable would rest on the seabed between two
    suspended parts (mid-span touchdown is not modelled), ``RuntimeError`` if Newton fails,
    ``NotImplementedError`` for a non-uniform make-up that finds no taut solution with its bottom
    end on the seabed (it may be slack there, which is modelled for uniform lines only).
    """
    makeup = tether if isinstance(tether, LineMakeup) else None
    if makeup is None and not isinstance(tether, TetherSpec):
        raise ValueError(f"tether must be a TetherSpec or a LineMakeup, got {type(tether).__name__}")
    if not isinstance(water, WaterColumn):
        raise ValueError(f"water must be a WaterColumn, got {type(water).__name__}")
    v_tow = _checks.vector3("steady_state.tow_velocity", tow_velocity)
    cb = _checks.non_negative("steady_state.seabed_friction", seabed_friction)
    _checks.positive("steady_state.tol", tol)
    if EA == "tether":
        EA = tether.EA if makeup is None else "tether"
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
        if makeup is None:
            X, T, P = cable.march(x0[None], F[None])
        else:  # a make-up marched up is the reversed make-up marched down
            c = _Cable(makeup.reversed(), water, v_tow, EA) if upward else cable
            X, T, P, *_ = c.march(x0[None], F[None])
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
    if makeup is not None:
        problem["top_contact"] = bool(seabed) and abs(top[2] - seabed_z) <= 1e-3
    guess = None if guess is None else _checks.vector3("steady_state.guess", guess)
    uniform = makeup is None or makeup.is_uniform
    if contact and uniform:  # slack if it can be (module docstring), else straight-laid
        ss = _slack_state(cable, top, bottom, seabed_z, (layout, layout_b, layout_angle), tol, max_iterations, vel)
        if ss is not None:
            return ss
    if uniform or not contact:
        return _straight_state(tether, water, v_tow, EA, problem, guess, tol, max_iterations, vel)
    try:
        return _straight_state(tether, water, v_tow, EA, problem, guess, tol, max_iterations, vel)
    except RuntimeError as exc:
        raise NotImplementedError(
            "steady_state: no taut (straight-laid) steady state found for this line make-up with its bottom "
            f"end on the seabed ({exc}). The line may be slack there (too long to lie taut between the "
            "touchdown and the bottom end), which is modelled for uniform lines only; shorten the line, move "
            "the bottom end away, or give a starting top force (guess=...)") from exc


def _cascade(tether, water: WaterColumn, v_tow, EA, pb: dict, guess, tol: float,
             max_iterations: int, first_guess):
    """Newton on the top force for problem ``pb``, started from ``guess`` or, for fine tethers,
    from the solve of a coarse one (the top force converges as 1/N^2, so a coarse solve gives an
    excellent starting force and Jacobian: a cascade, e.g. 200 -> 25 elements), else from
    ``first_guess(cable)``. Returns (cable, F, J, the converged march, residual)."""
    cable = _Cable(tether, water, v_tow, EA)
    J = None
    if guess is not None:
        F = guess
    elif tether.segments >= 4 * MIN_COARSE_SEGMENTS:
        coarse = _coarse(tether)
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
                                    lambda c: _first_guess(c, pb["top"], pb["bottom"], contact, pb["cb"],
                                                           pb.get("top_contact", False)))
    if cable.makeup is not None:
        return _makeup_state(cable, pb, F, J, shot, r, vel)
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
    if cable.fast is not None:
        k = int(math.floor(s_td / l * (1 + 1e-12)))
        xs, Ts, p = np.empty((k + 2, 3)), np.empty(k + 1), np.empty(3)
        _, _, d, A, mu, cdn, cdt_pi, fcda, *water = cable.fast
        count, phi = compiled.hang_up(s_td, seabed_z, stop_z, max_iterations, l, cable.EA, float(d[0]), float(A[0]),
                                      float(mu[0]), float(cdn[0]), float(cdt_pi[0]), float(fcda[0]), *water, xs, Ts, p)
        return xs[:count], Ts[:count - 1], p, phi
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
    if cable.makeup is not None:
        return _shoot_makeup(cable, pb, F)
    K = F.shape[0]
    X, T, P, td = cable.march(np.tile(pb["top"], (K, 1)), F, stop_on_touchdown=True)
    r = np.empty((K, 3))
    if cable.fast is not None:  # the same residuals, compiled (compiled.shot_residuals)
        contact, seabed_z = pb["contact"], pb["seabed_z"]
        compiled.shot_residuals(X, P, td, pb["bottom"], contact, seabed_z, pb["cb"],
                                cable.seabed_wet_weight(seabed_z) if contact else 0.0, cable.L, cable.l, cable.EA, r)
    else:
        _residuals(cable, pb, X, T, P, td, r)
    return r, (X, T, P, td)


def _residuals(cable: _Cable, pb: dict, X, T, P, td, r) -> None:
    """The shots' residuals (m) into ``r`` (K, 3): the last node's miss of the bottom end, or
    for a shot that touches down with the bottom end on the seabed, the laid end's miss (``_lay``)
    with the touchdown's height above the seabed as the third component."""
    for j in range(X.shape[0]):
        k = td[j]
        if pb["contact"] and k >= 0:
            end = _lay(cable, X[j], T[j], P[j], k, pb["seabed_z"], pb["cb"], end_only=True)
            phi = _touchdown_fraction(P[j], k)
            r[j] = end - pb["bottom"]
            r[j, 2] = X[j, k, 2] + phi * (X[j, k + 1, 2] - X[j, k, 2]) - pb["seabed_z"]  # touchdown height
        else:
            r[j] = X[j, -1] - pb["bottom"]


def _force_scale(cable: _Cable, top, bottom) -> float:
    """A force (N) of the order of the tether's loads: weight or drag on its whole length."""
    zs = np.linspace(min(top[2], 0.0), min(bottom[2], 0.0), 8)
    if cable.makeup is not None:
        rho = float(cable.water.rho(zs[4:5])[0])
        u = float(np.max(np.linalg.norm(cable.water.velocity(zs) - cable.v_tow, axis=1)))
        w = float(np.max(np.abs(cable.mu_e - rho * cable.A_e))) * cable.g
        drag = float(np.max(cable.cdn_e * cable.d_e))
        if cable.node_loads is not None:
            m, V, cda = cable.node_loads
            w += float(np.sum(np.abs(m - rho * V))) * cable.g / cable.L
            drag += float(np.sum(cda)) / cable.L
        return max(w, 0.5 * rho * drag * u * u, 1e-3) * cable.L
    rho = float(cable.water.rho(zs[4:5])[0])
    w = abs(cable.mu - rho * cable.A) * cable.g
    u = float(np.max(np.linalg.norm(cable.water.velocity(zs) - cable.v_tow, axis=1)))
    return max(w, 0.5 * rho * cable.cdn * cable.d * u * u, 1e-3) * cable.L


def _first_guess(cable: _Cable, top, bottom, contact: bool = False, cb: float = 0.0,
                 top_contact: bool = False) -> np.ndarray:
    """The analytic catenary's top force (no current, mean density), when it applies, else half
    the weight down plus the force scale along the chord; with the top's share of the current's
    drag added (``_drag_share``)."""
    drag = _drag_share(cable, top, bottom)
    if cable.makeup is not None:
        return _first_guess_makeup(cable, top, bottom, contact, cb, top_contact) + drag
    d = bottom - top
    w = (cable.mu - float(cable.water.rho(np.array([0.5 * (top[2] + bottom[2])]))[0]) * cable.A) * cable.g
    if w > 0 and top[2] >= bottom[2] and np.hypot(d[0], d[1]) > 1e-6 * cable.L:
        try:
            c = catenary(bottom, top, cable.L, w, EA=None if cable.EA == math.inf else cable.EA, cb=cb,
                         seabed=contact)
            return c.fairlead_force + drag
        except (ValueError, RuntimeError):
            pass
    return 0.5 * abs(w) * cable.L * np.array([0.0, 0.0, -1.0]) + d / max(np.linalg.norm(d), 1e-9) * 0.5 * \
        _force_scale(cable, top, bottom) + drag


def _drag_share(cable: _Cable, top, bottom, samples: int = 64) -> np.ndarray:
    """The top's share (N) of the current's normal drag on a vertical line from the top's depth
    to the bottom's: drag per metre 1/2 rho C_dn d |u| u (u the current less the tow velocity,
    horizontal), shared between the ends by the lever rule. A first guess only: with a strong
    surface current the top holds several times the still-water catenary's horizontal force,
    and a shot from the catenary's force alone can land on the wrong side of the map's jump
    where the first element's far end leaves the water (``_solve_top_force``)."""
    z_t, z_b = min(float(top[2]), 0.0), min(float(bottom[2]), 0.0)
    if z_t - z_b <= 1e-9:
        return np.zeros(3)
    z = np.linspace(z_b, z_t, samples)
    u = np.asarray(cable.water.velocity(z), float) - cable.v_tow
    u[:, 2] = 0.0
    cd_d = float(np.sum(cable.cdn_e * cable.d_e * cable.l_e) / np.sum(cable.l_e))
    q = 0.5 * np.asarray(cable.water.rho(z), float)[:, None] * cd_d * np.linalg.norm(u, axis=1)[:, None] * u
    share = ((z - z_b) / (z_t - z_b))[:, None] * q
    return trapezoid(share, z, axis=0)


def _first_guess_makeup(cable: _Cable, top, bottom, contact: bool, cb: float, top_contact: bool) -> np.ndarray:
    """``_first_guess`` for a make-up: the catenary of its mean wet weight (point loads
    included) and series stiffness; with the top end on the seabed, half the mean weight on the
    seabed there (the shooting parameter of ``_liftoff``) and the force scale along the chord."""
    d = bottom - top
    rho = float(cable.water.rho(np.array([0.5 * (top[2] + bottom[2])]))[0])
    W = float(np.sum((cable.mu_e - rho * cable.A_e) * cable.l_e)) * cable.g
    if cable.node_loads is not None:
        W += float(np.sum(cable.node_loads[0] - rho * cable.node_loads[1])) * cable.g
    w = W / cable.L
    compliance = float(np.sum(cable.l_e / cable.EA_e))
    EA = cable.L / compliance if compliance > 0.0 else None
    if not top_contact and w > 0 and top[2] >= bottom[2] and np.hypot(d[0], d[1]) > 1e-6 * cable.L:
        try:
            return catenary(bottom, top, cable.L, w, EA=EA, cb=cb, seabed=contact).fairlead_force
        except (ValueError, RuntimeError):
            pass
    return 0.5 * abs(w) * cable.L * np.array([0.0, 0.0, -1.0]) + d / max(np.linalg.norm(d), 1e-9) * 0.5 * \
        _force_scale(cable, top, bottom)


def _first_shot(shots):
    """The first shot of a ``_shoot``: (X, T, P, td) for a TetherSpec, the state dict for a make-up."""
    if isinstance(shots, list):
        return shots[0]
    X, T, P, td = shots
    return X[0], T[0], P[0], int(td[0])


def _solve_top_force(cable: _Cable, pb: dict, F, J, tol: float, max_iterations: int):
    """Newton's method on the top force with a backtracking line search. With a starting
    Jacobian ``J`` (from a coarser solve) it first tries chord steps, which need one march each.
    Returns (F, J, the converged march, residual)."""
    scale = _force_scale(cable, pb["top"], pb["bottom"])
    L = cable.L

    def with_jacobian(F):
        h = 1e-6 * max(np.linalg.norm(F), scale * 1e-3)
        rs, shots = _shoot(cable, pb, np.vstack([F, F + h * np.eye(3)]))
        return rs[0], (rs[1:] - rs[0]).T / h, _first_shot(shots)

    def single(F):
        rs, shots = _shoot(cable, pb, F[None])
        return rs[0], _first_shot(shots)

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

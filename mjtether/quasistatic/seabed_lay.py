"""Cable on the seabed for the steady-state solver (``steady``): the touchdown, the laid part,
the lift-off and the slack cable's hang.

* a shot that touches down: where in the element it does (``_touchdown_fraction``), and the rest
  laid straight on the seabed beyond it, its tension falling by friction (``_lay``; for a
  make-up ``_lay_makeup`` with the laid profile of ``_laid_profile``);
* a make-up whose top end is on the seabed: the laid part from the top and the lift-off point
  (``_liftoff``, ``_lay_top``);
* the slack cable: its free hang marched up from the touchdown (``_hang_up``; compiled twin
  ``kernels.hang_up``), and the rest laid at zero tension in a layout (``_layout_offsets``,
  ``_slack_state``).

The method is in the docstring of ``steady``. Frames: world, z up, water surface z = 0, seabed
z = -water.depth. SI units.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from . import kernels
from .line import _Cable

if TYPE_CHECKING:  # (steady imports this module: ``_slack_state`` imports SteadyState when it runs)
    from .steady import SteadyState


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
        count, phi = kernels.hang_up(s_td, seabed_z, stop_z, max_iterations, l, cable.EA, float(d[0]), float(A[0]),
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
    from .steady import SteadyState  # (here: steady imports this module)

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

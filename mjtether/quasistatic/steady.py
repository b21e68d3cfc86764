"""A physically consistent 3-D steady state of the tether, by shooting.

The same discretisation as the dynamic model (``mjtether.cable.builder``): N elements of material
length l = L / N between nodes 0 (ship) .. N (robot); every element carries its wet weight
(mu - rho(z_c) A) g l and Morison drag on the relative velocity u(z_c) - v_tow at its centre
z_c (``mjtether.physics.hydro``), and the lumped-mass node balance is

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

Line make-ups. ``tether`` may be a ``mjtether.cable.makeup.LineMakeup`` instead of a ``TetherSpec``:
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
from scipy.optimize import root

from mjtether import _checks
from mjtether.cable.makeup import LineMakeup
from mjtether.cable.tether import TetherSpec
from mjtether.physics.water import WaterColumn

from . import kernels, seabed_lay
from .catenary import catenary
from .line import _Cable
from .seabed_lay import _lay, _lay_makeup, _lay_top, _liftoff, _slack_state, _touchdown_fraction

# The line (``line``) and the seabed lay (``seabed_lay``) have modules of their own; the
# helpers the tests reach through this module stay here, the same objects:
_hang_up = seabed_lay._hang_up


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
    return replace(tether, sections=sections)


def _solver_line(tether) -> TetherSpec | LineMakeup:
    """What the solver marches for ``tether`` (a ``TetherSpec`` or a ``LineMakeup``): a uniform
    line as its ``TetherSpec`` (the scalar path: the closed-form first guess, the slack state,
    the drag continuation), any other make-up as it is (the piecewise march)."""
    line = LineMakeup.of(tether, "steady_state.tether")
    if not line.is_uniform:
        return line
    return tether if isinstance(tether, TetherSpec) else line.tether


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
    sections; see "Line make-ups" in the module docstring; a uniform one, one section without
    loads, is solved as its ``TetherSpec``). For a make-up, ``EA`` = "tether" takes each
    section's own EA, a number or ``None`` replaces them all.

    Raises ``ValueError`` on bad input or when the cable would rest on the seabed between two
    suspended parts (mid-span touchdown is not modelled), ``RuntimeError`` if Newton fails,
    ``NotImplementedError`` for a non-uniform make-up that finds no taut solution with its bottom
    end on the seabed (it may be slack there, which is modelled for uniform lines only).
    """
    tether = _solver_line(tether)
    uniform = isinstance(tether, TetherSpec)
    if not isinstance(water, WaterColumn):
        raise ValueError(f"water must be a WaterColumn, got {type(water).__name__}")
    v_tow = _checks.vector3("steady_state.tow_velocity", tow_velocity)
    cb = _checks.non_negative("steady_state.seabed_friction", seabed_friction)
    _checks.positive("steady_state.tol", tol)
    if EA == "tether":
        EA = tether.EA if uniform else "tether"
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
        if uniform:
            X, T, P = cable.march(x0[None], F[None])
        else:  # a make-up marched up is the reversed make-up marched down
            c = _Cable(tether.reversed(), water, v_tow, EA) if upward else cable
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
    if not uniform:
        problem["top_contact"] = bool(seabed) and abs(top[2] - seabed_z) <= 1e-3
    guess = None if guess is None else _checks.vector3("steady_state.guess", guess)
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


CONTINUATION = (0.0, 0.25, 0.5, 0.7, 0.85, 0.95)
"""The flow speeds, as fractions of the real one, through which ``_drag_continuation`` walks."""


def _drag_continuation(tether: TetherSpec, water: WaterColumn, v_tow, EA, pb: dict, tol: float,
                       max_iterations: int, first_guess):
    """A starting top force (N) for a line whose solve from ``first_guess`` stalls (a strong
    surface current: the start sits in a basin Newton and Levenberg-Marquardt cannot leave):
    the solves with the flow slowed to each fraction a of ``CONTINUATION`` in turn, each started
    from the one before (drag scales as a^2, so the coefficients do: a still line's drag is
    that of a^2 C_d in the whole flow), from the line without drag, which always solves."""
    F = None
    for a in CONTINUATION:
        slow = replace(tether, cd_normal=a * a * tether.cd_normal, cd_tangential=a * a * tether.cd_tangential)
        _, F, *_ = _cascade(slow, water, v_tow, EA, pb, F, tol, max_iterations, first_guess)
    return F


def _straight_state(tether, water, v_tow, EA, pb, guess, tol, max_iterations, vel) -> SteadyState:
    """The two-point solve with any laid part straight (see the module docstring)."""
    seabed_z, contact = pb["seabed_z"], pb["contact"]

    def first_guess(c):
        return _first_guess(c, pb["top"], pb["bottom"], contact, pb["cb"], pb.get("top_contact", False))

    try:
        cable, F, J, shot, r = _cascade(tether, water, v_tow, EA, pb, guess, tol, max_iterations, first_guess)
    except RuntimeError:
        if guess is not None or not isinstance(tether, TetherSpec) or tether.cd_normal + tether.cd_tangential == 0:
            raise
        F = _drag_continuation(tether, water, v_tow, EA, pb, tol, max_iterations, first_guess)
        cable, F, J, shot, r = _cascade(tether, water, v_tow, EA, pb, F, tol, max_iterations, first_guess)
    if not cable.uniform:
        return _makeup_state(cable, pb, F, J, shot, r, vel)
    X, T, P, td = shot
    if contact and td >= 0:
        nodes, tension, bot_f, s_td, LB, slack = _lay(cable, X, T, P, td, seabed_z, pb["cb"])
        return SteadyState(nodes, tension, F, bot_f, s_td, LB, vel, float(np.linalg.norm(r)), J, slack)
    if pb["seabed"] and X[:, 2].min() < seabed_z - 1e-3:
        raise ValueError("steady_state: the cable would rest on the seabed between its two ends, which is "
                         "not modelled; raise the bottom end onto the seabed or pass seabed=False")
    return SteadyState(X, T, F, -P[-1], None, 0.0, vel, float(np.linalg.norm(r)), J)


def _shoot(cable: _Cable, pb: dict, F: np.ndarray):
    """Residuals (m), shape (K, 3), of the shots with top forces ``F`` (K, 3), and the marches."""
    if not cable.uniform:
        return _shoot_makeup(cable, pb, F)
    K = F.shape[0]
    X, T, P, td = cable.march(np.tile(pb["top"], (K, 1)), F, stop_on_touchdown=True)
    r = np.empty((K, 3))
    if cable.fast is not None:  # the same residuals, compiled (kernels.shot_residuals)
        contact, seabed_z = pb["contact"], pb["seabed_z"]
        kernels.shot_residuals(X, P, td, pb["bottom"], contact, seabed_z, pb["cb"],
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
    if not cable.uniform:
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
    if not cable.uniform:
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
    """Newton's method on the top force with a backtracking line search (``_newton``); where it
    stalls, Levenberg-Marquardt (scipy's ``root``, method "lm") from the same start, whose
    damped steps reach solutions Newton's full steps overshoot: docs/python_api.md's 800 m line in a
    3 kn surface current, whose start Newton could not leave, converges so to the state the
    dynamic model settles towards. Returns (F, J, the converged march, residual)."""
    try:
        return _newton(cable, pb, F, J, tol, max_iterations)
    except RuntimeError as exc:
        start, stalled = np.asarray(F, dtype=float), exc

    def residual(f):
        rs, _ = _shoot(cable, pb, np.asarray(f, dtype=float)[None])
        return np.where(np.isfinite(rs[0]), rs[0], 1e6 * cable.L)

    sol = root(residual, start, method="lm", options={"xtol": 1e-12, "maxiter": 100 * max_iterations})
    if not np.all(np.isfinite(sol.x)) or np.linalg.norm(residual(sol.x)) > tol * cable.L:
        raise stalled
    return _newton(cable, pb, sol.x, None, tol, max_iterations)  # (its Jacobian and march, at the answer)


def _newton(cable: _Cable, pb: dict, F, J, tol: float, max_iterations: int):
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

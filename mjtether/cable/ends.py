"""Line ends whose node's mass the support's body carries (``builder.add_tether``'s
``end_mass_to``).

A tether's end node is held to its support by a stiff ``connect``. Where the support is a body
that moves with the line end (a network's free point: a ring, a buoy, a massless free end),
the node's lumped mass (half its element's, with any point load's) is better carried by that
body: the drum otherwise gives an end node armature up to an interior node's inertia (for the
conditioning of its constraints, see ``builder``) and the body must be as heavy again, so the
end moves with about twice its inertia; a near-massless body instead (1 g) leaves its connects
badly conditioned (MuJoCo sizes a connect's softness on its bodies' inverse masses at compile
time: MoorPy's case8.dat bridle came out 42 % off MoorDyn-C). With ``end_mass_to``, the node
keeps ``NODE_SHARE`` of its lumped mass and its own added mass, and the support body, whose
builder must give it the rest (``lumped_end_mass``, with its real weight), carries the rest:
inertia and weight are both the line's. The node keeps its loads (buoyancy, drag, added mass,
seabed contact and friction): they pass through the connect. The node's weight that moved is
no longer in the connect's force: ``moved_weight`` is what to add back to read the line's force
on its support (MoorDyn's convention: the end node's weight with the line's pull).

The masses are set once the tether is bound (``move_end_masses``); the drum resets them when it
releases or takes back a node, so a tether paying out has its ends moved again after each
``set_length``. The start end of a tether with a drum is not moved (its fairlead node's share
changes with payout). Units SI, world frame.
"""

from __future__ import annotations

import math

import numpy as np

SIDES = ("start", "end")
NODE_SHARE = 0.5
"""The share of its lumped mass (and weight) an end node keeps when its support's body carries
the rest (the two together are the line's: neither inertia nor weight is counted twice). Half:
an end node keeping 0.1 % bounced off the cell edges of a bathymetry grid, its seabed contact
holding up the point's weight through the connect (MoorDyn's seafloor.txt: a 19.5 mm hop, 10 %
still 10 mm; at half, under 1 mm, as before the move), while the MoorDyn-C comparisons of the
networks and the sliding line's Coulomb test hold at half as at 0.1 %."""


def parse_end_mass_to(value, start, end, *, drum: bool) -> tuple:
    """``add_tether``'s ``end_mass_to`` (None, ``"start"``, ``"end"`` or both) as a tuple of
    sides, checked against the ``start`` and ``end`` anchors (a body each must carry the mass: a
    ``BodyPoint`` or a ``SitePoint``) and whether the start has a ``drum`` (then it cannot); an
    empty tuple is none."""
    from .builder import BodyPoint, SitePoint
    if value is None:
        return ()
    try:
        sides = (value,) if isinstance(value, str) else tuple(value)
    except TypeError:
        sides = (value,)
    if any(s not in SIDES for s in sides):
        raise ValueError(f"end_mass_to must be 'start', 'end' or ('start', 'end'), got {value!r}")
    for side, anchor in zip(SIDES, (start, end)):
        if side in sides and not isinstance(anchor, (BodyPoint, SitePoint)):
            raise ValueError(f"end_mass_to: the {side} end is a {type(anchor).__name__}, which has no body to carry "
                             "its node's mass (a BodyPoint or a SitePoint has)")
    if "start" in sides and drum:
        raise ValueError("end_mass_to: the start end pays out from its drum (max_length > length), and its fairlead "
                         "node's mass changes with the payout; only the end's can move")
    return tuple(s for s in SIDES if s in sides)


def lumped_end_mass(tether, side: str) -> float:
    """The lumped mass (kg) of the ``side`` end node of ``tether`` (a ``LineMakeup``, or a
    ``TetherSpec``: its one section), not paying out at that end: half its element's, with its
    point load there."""
    from .makeup import LineMakeup
    if side not in SIDES:
        raise ValueError(f"side must be 'start' or 'end', got {side!r}")
    line = LineMakeup.of(tether)
    k = 0 if side == "start" else -1
    return float(0.5 * line.element_mass_per_length[k] * line.element_length[k] + line.node_mass[k])


def moved_mass(tether, side: str) -> float:
    """The mass (kg) the support body of ``side`` carries for the node: all of ``lumped_end_mass``
    but the node's ``NODE_SHARE``."""
    return (1.0 - NODE_SHARE) * lumped_end_mass(tether, side)


def moved_weight(bt, side: str) -> np.ndarray:
    """The weight (N, world) of the node's mass that bound tether ``bt``'s ``side`` support body
    carries (zero where it does not): add it to ``bt.end_force`` for the line's force on its
    support, the node's weight in."""
    if side not in bt.tm.end_mass_to:
        return np.zeros(3)
    return moved_mass(bt.tm.line, side) * np.asarray(bt.model.opt.gravity, float)


def move_end_masses(bt, inertia: dict) -> None:
    """Move the masses of bound tether ``bt``'s ``tm.end_mass_to`` end nodes into their supports:
    each node keeps ``NODE_SHARE`` of its mass and its added mass, and no armature for
    conditioning; ``inertia`` {side: kg} is the node's share of its support body's inertia (its
    mass with its added mass), which the node's end element is tuned for and its seabed stick
    spring is sized on (``builder.axial_scalar``). Idempotent: run again after the drum resets
    the masses."""
    from .builder import axial_scalar
    L, dr = bt.layout, bt.drum
    m, tm = L.model, bt.tm
    for side in tm.end_mass_to:
        i = L.n if side == "end" else dr.first
        j = i - 1 if side == "end" else i  # its element
        lumped = lumped_end_mass(tm.line, side)
        now = float(m.body_mass[L.bids[i]])
        if not (math.isclose(now, lumped, rel_tol=1e-9) or math.isclose(now, NODE_SHARE * lumped, rel_tol=1e-9)):
            raise RuntimeError(f"tether {tm.name!r}: its {side} node weighs {now:g} kg, not its lumped {lumped:g} kg")
        normal = 0.5 * float(dr.added_per_m[j]) * float(dr.rest[j])  # (its half of its element's added mass)
        iso = float(dr.node_added[i]) + (normal if L.normal_ten is None else 0.0)  # (its point load's: 0 if none)
        iso = max(iso, 1e-9 * dr.i_ref)
        m.body_mass[L.bids[i]] = NODE_SHARE * lumped
        m.dof_armature[L.dof0 + 3 * i:L.dof0 + 3 * i + 3] = iso
        dr.inertia[i] = NODE_SHARE * lumped + iso + float(inertia[side])
        inv = 1.0 / float(dr.inertia[j]) + 1.0 / float(dr.inertia[j + 1])
        EA = float(dr.EA[j])  # (inf: inextensible)
        S, B, d = axial_scalar(None if math.isinf(EA) else EA, float(dr.rest[j]), inv,
                               m.opt.timestep, L.spec.axial_damping_ratio)
        e = L.eq0 + j
        m.tendon_invweight0[L.tadr + j] = inv
        m.eq_solref[e] = (-S, -B)
        m.eq_solimp[e, 0] = m.eq_solimp[e, 1] = d
        dr.lead[j] = B / S
        dr.K[j] = S / ((1.0 - d) * inv)
        dr.set_rest(j, j + 1)

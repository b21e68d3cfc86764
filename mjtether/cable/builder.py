"""Add a tether to a ``mujoco.MjSpec``.

Construction (measured, MuJoCo 4.0.0, one core of this machine, 1000 m tether, Newton
solver, implicitfast, 5 ms step, no hydrodynamics; ``scripts/bench_constructions.py``):

=============================================  =========  =========  =========
construction                                   N = 100    N = 200    N = 400
=============================================  =========  =========  =========
capsule bodies, free joints, ``connect``        275 us     544 us    1082 us
ball-joint sub-chains of 5, ``connect``         227 us     456 us     942 us
1-D flex, node bodies with 3 slide joints       124 us     245 us     482 us
=============================================  =========  =========  =========

All three are O(N) (a single ball-joint tree is O(N^3): 2.2 ms at N = 100). We keep the
lumped-mass chain of the 1-D flex: a diagonal mass matrix, one constraint row per element,
and the discretisation that MoorDyn and Hong et al. (2020) use. Each node is a body with
three world slide joints carrying the lumped mass (half of each adjacent element); the flex
gives every element a capsule of the cable's diameter for rendering and seabed contact.

**Tension only.** Each element is a spatial tendon between the sites of its two nodes, held
at its rest length by a soft tendon equality that ``BoundTether.update_slack`` switches off
(``eq_active``) while the element is slack: after a step, an element whose equality pushed goes
slack, and a slack one stretched past its rest length is taut again; the step is then redone
with that set (``Simulation``), so that elements do not push or overshoot for a step. A slack
element carries nothing, as cable (and MoorDyn's and OrcaFlex's segments) do. The flex's own
edge equality, used before, pushes as well as pulls: compression spikes appeared as tension
wherever payout laid cable down. MuJoCo's one-sided tendon limits (``solreflimit``), the
obvious alternative, chatter at the stiffness a long step allows: a limit row slowed to the
step (impedance near 1) lets a node feel its full load in a step when it is slack and only
(1 - impedance) of it when taut, so it bounces in and out of the limit (a still, hanging
50 m line at 5 ms: tension noise of 50 % against 1e-8 with the equalities). Bending stiffness
``EI`` is a separate passive force (``hydro.bending_forces``), not part of the element force.

Elongation is physical. In static equilibrium MuJoCo's soft constraint stretches by
r = R f / (k imp), with R = (1 - d)/d * A (A = ``efc_diagA``, which for a tendon equality is
``tendon_invweight0``: we set it to the element's true inverse mass along its axis,
1/m_i + 1/m_(i+1)), and k imp = S / d for a negative ``solref = (-S, -B)`` and constant
impedance d. So an element of stiffness K = EA / l needs S = K (1 - d) A. The impedance d sets
how fast the axial mode rings: d -> 0 is a plain spring at the physical frequency
omega_ax = sqrt(K A); d -> 1 slows it. We keep the physical frequency when the time step
resolves it (omega_ax dt <= AXIAL_OMEGA_DT = 0.4) and otherwise slow the axial mode to 0.4 / dt,
which keeps the static stretch T l / EA exact and the step stable. Where even d = 0.9999
(MuJoCo's largest impedance) cannot slow it enough, the element is made as stiff as that step
allows and no stiffer: its effective EA is lower than asked (``BoundTether.effective_EA``); ``EA=None``
(inextensible) always takes that limit (strain < 1e-3 at working tension).

**Payout at the drum.** A compiled model cannot grow, so ``add_tether`` allocates nodes for
``max_length``: the cable is numbered from the drum's core (node 0) to the robot end (node n),
and only nodes ``first`` .. n are deployed. Node ``first`` sits at the fairlead, held there by
its own ``connect`` equality (one per node, switched through ``eq_active``); the element next
to it, the drum element, takes all payout and reel-in; every other deployed element keeps the
nominal length l0 = L / N. Paying out past 1.2 l0 releases the next node from the drum (the
drum element splits into one of l0 and a new drum element of the rest); reeling in below
0.1 l0 takes a node back (the drum element merges with its neighbour; see
``cable.drum.SPLIT``). Nodes on the drum are parked: no equality, no hydrodynamic force,
gravity compensated, at rest. ``BoundTether.set_length`` does this at run time.

Ends: every end is a node body, joined to its support (a world site for a fixed point, a site
on the ship or robot) by a stiff ``connect`` equality whose force is the force of the tether on
that support. The end nodes get armature up to an interior node's inertia (it sits at a
support and weighs nothing) so that their constraints are as well conditioned as the rest.
On a height-field seabed, a node held at a ``FixedPoint`` is the world's vertex of the flex (its
body still carries the node): MuJoCo collides a height field with the elements, skipping those
with a vertex on its body, so the seabed does not push a node the anchor holds, as on a plane,
where it collides vertices and a held one tangent to it takes nothing. (Tangent to the prisms at a
grid node, MuJoCo found penetrations of 1e-4 m, some sideways, and the held node, which cannot
move out, passed their 40-70 kN to the anchor: up to 29 % of a chain's 140 kN. The node's flex
vertex is then not its body: read node bodies from the ``TetherModel``, not ``flex_vertbodyid``.)

Added mass: the normal added mass C_a rho A l of each element is lumped on its nodes. By default
(``added_mass="isotropic"``) it is armature of the three slide joints, which MuJoCo integrates
implicitly: isotropic, so the nodes also carry it along the cable, where a slender cylinder has
none. With ``added_mass="normal"`` it acts normal to the cable only: each node has two fixed tendons
whose joint coefficients are two unit vectors normal to the cable there, and whose armature is
the node's added mass, so MuJoCo's mass matrix holds m I + m_a (I - t t^T), integrated
implicitly. ``BoundTether`` turns the two directions with the cable after every force
computation (they lag the shape by one step). An isotropic armature (all three slide joints)
would add m_a to the axial inertia too: on the flexible jumper of Lowe and Langley (2006),
whose fairlead moves 10 m at 27 s, that overstated the tension swing by half
(``scripts/reproduce_lowe_langley2006.py``: 0.1-0.2 kN RMS from the paper with "normal").
"normal" is not the default yet: with it, the slack switching lets a pushed element push (0.16
W in ``test_pushed_elements_carry_no_force``) and a touchdown spike (1.49 T0 in
``test_lowering_onto_the_seabed_has_no_tension_spike``).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from mjtether import _checks
from mjtether.analytic import sagged_polyline
from mjtether.physics import dispatch
from mjtether.physics.water import WaterColumn

from . import ends
from .makeup import LineMakeup
from .tether import ADDED_MASS, TetherSpec

MIN_IMP, MAX_IMP = 1e-4, 0.9999  # MuJoCo's mjMINIMP, mjMAXIMP
AXIAL_OMEGA_DT = 0.4
"""Largest omega * dt given to the axial mode. MuJoCo applies the constraint's damping
explicitly; with critical damping the highest mode of a chain is stable only for omega dt <
sqrt(6) - 2 = 0.449, and tensions came out 4-45 % off for elements whose physical frequency sat
at 0.45-0.53 / dt under the former cap of 0.5 (tests/cable/test_axial_band.py)."""


# ------------------------------------------------------------------------------ anchors


@dataclass(frozen=True)
class FixedPoint:
    """A tether end fixed in the world at ``position`` (m)."""

    position: tuple

    def __post_init__(self):
        object.__setattr__(self, "position", tuple(_checks.vector3("FixedPoint.position", self.position)))


@dataclass(frozen=True)
class BodyPoint:
    """A tether end on a body (a mocap ship, a robot) at ``offset`` (m, body frame)."""

    body: str
    offset: tuple = (0.0, 0.0, 0.0)

    def __post_init__(self):
        object.__setattr__(self, "offset", tuple(_checks.vector3("BodyPoint.offset", self.offset)))


@dataclass(frozen=True)
class SitePoint:
    """A tether end at a named site, e.g. a robot's tow point."""

    site: str


@dataclass(frozen=True)
class FreeEnd:
    """A free tether end (it only carries half an element's mass)."""


Anchor = FixedPoint | BodyPoint | SitePoint | FreeEnd


# ----------------------------------------------------------------- axial constraint tuning


@dataclass(frozen=True)
class AxialParams:
    """MuJoCo parameters of the element length limits (see module docstring); scalars, or
    arrays with one value per element.

    Attributes:
        S, B: ``solreflimit = (-S, -B)`` (1/s^2, 1/s).
        d: constant impedance (``solimplimit = (d, d, 0.001, 0.5, 2)``).
        stiffness: static element stiffness K = EA_eff / l (N/m).
        omega: axial-mode frequency given to the solver (rad/s).
        omega_physical: sqrt(K_EA A) of the element as asked (rad/s); inf when inextensible.
    """

    S: np.ndarray
    B: np.ndarray
    d: np.ndarray
    stiffness: np.ndarray
    omega: np.ndarray
    omega_physical: np.ndarray

    @property
    def solref(self):
        return np.stack([-np.asarray(self.S, float), -np.asarray(self.B, float)], axis=-1)

    @property
    def solimp(self):
        d = np.asarray(self.d, float)
        return np.stack([d, d, np.full_like(d, 0.001), np.full_like(d, 0.5), np.full_like(d, 2.0)], axis=-1)

    def effective_EA(self, segment_length) -> np.ndarray:
        """Axial stiffness (N) the solver realises in statics for elements of ``segment_length``."""
        return np.asarray(self.stiffness) * segment_length


def axial_params(EA: float | None, segment_length, inv_mass, timestep: float,
                 damping_ratio: float = 1.0) -> AxialParams:
    """Limit-constraint parameters so that elements of rest length ``segment_length`` (m) whose
    nodes have the inverse mass ``inv_mass`` along the element (1/m_i + 1/m_(i+1), 1/kg; also
    the ``tendon_invweight0`` MuJoCo is given) stretch by T l / EA, stably at ``timestep`` (s).
    Arguments broadcast (one value per element)."""
    l = np.asarray(segment_length, dtype=float)
    a = np.asarray(inv_mass, dtype=float)
    omega_cap = AXIAL_OMEGA_DT / timestep
    with np.errstate(divide="ignore", invalid="ignore"):
        K = np.full(np.broadcast(l, a).shape, np.inf) if EA is None else EA / np.maximum(l, 1e-12)
        omega_phys = np.sqrt(K * a)
        x = np.clip((omega_cap / omega_phys) ** 2, 1.0 - MAX_IMP, 1.0 - MIN_IMP)  # x = 1 - d
        d = 1.0 - x
        # the physical frequency where d can give it, else the cap (the element is then softer)
        S = np.minimum(K * x * a, omega_cap**2)
        stiffness = S / (x * a)
    omega = np.sqrt(S)
    B = np.atleast_1d(2.0 * damping_ratio * omega) if np.ndim(omega) else 2.0 * damping_ratio * omega
    return AxialParams(S=S, B=B, d=d, stiffness=stiffness, omega=omega, omega_physical=omega_phys)


def axial_scalar(EA: float | None, segment_length: float, inv_mass: float, timestep: float,
                 damping_ratio: float = 1.0) -> tuple[float, float, float]:
    """``axial_params`` for one element, in scalar arithmetic: (S, B, d)."""
    omega_cap = AXIAL_OMEGA_DT / timestep
    K = math.inf if EA is None else EA / max(segment_length, 1e-12)
    omega_phys2 = K * inv_mass
    x = min(max(omega_cap**2 / omega_phys2, 1.0 - MAX_IMP), 1.0 - MIN_IMP)
    S = min(K * x * inv_mass, omega_cap**2)
    return S, 2.0 * damping_ratio * math.sqrt(S), 1.0 - x


# ------------------------------------------------------------------------------ seabed

ROBOT_CONTACT_BIT = 1
"""contype/conaffinity bit of robots' geoms (feet, hull) and of the seabed."""
TETHER_CONTACT_BIT = 2
"""contype bit of the tether; only the seabed has it in its conaffinity."""


def seabed_height(water: WaterColumn, x, y, slope: float = 0.0, slope_heading: float = 0.0):
    """Height z (m) of the seabed at horizontal positions ``x``, ``y`` (m, world): ``-water.depth``
    at the origin, rising at ``slope`` (rad) towards ``slope_heading`` (rad, from +x to +y)."""
    along = np.asarray(x, dtype=float) * math.cos(slope_heading) + np.asarray(y, dtype=float) * math.sin(slope_heading)
    return water.seabed_z + math.tan(slope) * along


def slope_quat(slope: float, slope_heading: float) -> list:
    """The quaternion (w, x, y, z) that turns +z onto the normal of a seabed rising at ``slope``
    (rad) towards ``slope_heading`` (rad from +x towards +y)."""
    # rotate +z onto the normal (-sin a cos h, -sin a sin h, cos a): by a about (sin h, -cos h, 0)
    c, s_ = math.cos(slope / 2), math.sin(slope / 2)
    return [c, s_ * math.sin(slope_heading), -s_ * math.cos(slope_heading), 0.0]


def add_seabed(spec: mujoco.MjSpec, water: WaterColumn, *, friction: float = 0.6, size: float = 0.0,
               rgba=(0.45, 0.4, 0.3, 1.0), name: str = "seabed", slope: float = 0.0,
               slope_heading: float = 0.0, point=None, lower: float = 0.0,
               bits: tuple[int, int] = (ROBOT_CONTACT_BIT, ROBOT_CONTACT_BIT | TETHER_CONTACT_BIT)
               ) -> mujoco.MjsGeom:
    """The seabed: a plane through z = -water.depth at the origin (or through ``point``, m),
    tilted by ``slope`` (rad, in [0, 45 deg)) so that it rises towards ``slope_heading`` (see
    ``seabed_height``). Robots (contype bit 1) and tethers built with ``seabed_friction`` (bit 2)
    rest on it. ``size`` is the half-width drawn (0: infinite). ``lower`` (m) moves the plane
    that far along its normal into the ground, and ``bits`` are its (contype, conaffinity): a
    copy that only one tether touches (see ``add_tether``'s ``contact_bit``)."""
    if not isinstance(water, WaterColumn):
        raise ValueError(f"water must be a WaterColumn, got {type(water).__name__}")
    _checks.non_negative("seabed.friction", friction)
    _checks.in_range("seabed.slope", slope, 0.0, math.radians(45.0) - 1e-9, "rad")
    _checks.finite("seabed.slope_heading", slope_heading)
    _checks.non_negative("seabed.lower", lower, "m")
    pos = np.array([0.0, 0.0, water.seabed_z] if point is None else [float(v) for v in point])
    quat = slope_quat(slope, slope_heading)
    if lower:
        R = np.zeros(9)
        mujoco.mju_quat2Mat(R, np.array(quat))
        pos = pos - lower * R.reshape(3, 3)[:, 2]
    return spec.worldbody.add_geom(
        name=name, type=mujoco.mjtGeom.mjGEOM_PLANE, pos=pos.tolist(), quat=quat,
        size=[size, size, 1.0], friction=[float(friction), 0.005, 0.0001], rgba=list(rgba),
        contype=bits[0], conaffinity=bits[1], condim=3)


def add_seabed_grid(spec: mujoco.MjSpec, bathymetry, *, friction: float = 0.6, rgba=(0.45, 0.4, 0.3, 1.0),
                    name: str = "seabed", base: float = 1.0, lower: float = 0.0,
                    bits: tuple[int, int] = (ROBOT_CONTACT_BIT, ROBOT_CONTACT_BIT | TETHER_CONTACT_BIT)
                    ) -> mujoco.MjsGeom:
    """The seabed as a MuJoCo height field over ``bathymetry`` (``physics.bathymetry.Bathymetry``):
    its grid nodes are the field's (rows along y, columns along x), a solid ``base`` m thick
    under its lowest point. Robots and tethers rest on it as on ``add_seabed``'s plane; outside
    the grid there is no seabed. ``lower`` (m) moves it down and ``bits`` are its (contype,
    conaffinity), as for ``add_seabed``."""
    _checks.non_negative("seabed.friction", friction)
    _checks.non_negative("seabed.lower", lower, "m")
    b = bathymetry
    zmin, zrange = float(b.z.min()), max(float(np.ptp(b.z)), 1e-6)
    x0, x1, y0, y1 = b.bounds
    spec.add_hfield(name=name, size=[(x1 - x0) / 2, (y1 - y0) / 2, zrange, base], nrow=len(b.y), ncol=len(b.x),
                    userdata=((b.z - zmin) / zrange).ravel().tolist())
    return spec.worldbody.add_geom(
        name=name, type=mujoco.mjtGeom.mjGEOM_HFIELD, hfieldname=name,
        pos=[(x0 + x1) / 2, (y0 + y1) / 2, zmin - lower], friction=[float(friction), 0.005, 0.0001],
        rgba=list(rgba), contype=bits[0], conaffinity=bits[1], condim=3)


def grid_of(model: mujoco.MjModel, geom: int):
    """The ``Bathymetry`` of height-field geom ``geom`` of a compiled model (the inverse of
    ``add_seabed_grid``)."""
    from mjtether.physics.bathymetry import Bathymetry
    h = int(model.geom_dataid[geom])
    nrow, ncol = int(model.hfield_nrow[h]), int(model.hfield_ncol[h])
    rx, ry, zrange, _ = model.hfield_size[h]
    adr = int(model.hfield_adr[h])
    cx, cy, z0 = model.geom_pos[geom]
    z = z0 + zrange * model.hfield_data[adr:adr + nrow * ncol].reshape(nrow, ncol)
    return Bathymetry(np.linspace(cx - rx, cx + rx, ncol), np.linspace(cy - ry, cy + ry, nrow), z)


# ------------------------------------------------------------------------------ builder


@dataclass
class TetherModel:
    """What ``add_tether`` put in the spec: names, masses and parameters.

    Nodes are numbered from the drum's core (0) to the robot end (``n``); element j joins nodes
    j and j+1 and is the same piece of cable for the whole run. Nodes ``first`` .. n are
    deployed at the start (``first`` at the fairlead); 0 .. first-1 wait on the drum.
    """

    name: str
    spec: TetherSpec
    start: Anchor
    end: Anchor
    node_bodies: list
    n: int  # elements allocated, drum included
    first: int  # the node at the fairlead at the start
    nominal_length: float  # l0 = L / N (m)
    initial_nodes: np.ndarray  # (n+1, 3), parked nodes at the start anchor
    connects: dict = field(default_factory=dict)  # "end" -> equality name; "start": one per node
    max_length: float = 0.0
    seabed_friction: float | None = None  # Coulomb coefficient on the seabed; None: no contact
    line: LineMakeup | None = None  # the line: its sections and point loads (a uniform tether: its one section)
    userdata_adr: int = -1  # where the nodes' stick points (3 per node) start in MuJoCo's userdata
    added_mass: str = "isotropic"  # or "normal": see add_tether
    end_mass_to: tuple = ()  # the ends whose node's mass its support's body carries (see add_tether)

    makeup = property(lambda self: None if self.line.is_uniform else self.line,
                      doc="The line where it is not uniform, else None (older callers; new code reads ``line``).")

    @property
    def flex(self) -> str:
        return f"{self.name}"

    def element_tendon(self, j: int) -> str:
        return f"{self.name}/element{j}"

    def drum_connect(self, i: int) -> str:
        return f"{self.name}/drum{i}"

    def normal_tendon(self, i: int, k: int) -> str:
        """The fixed tendon that carries node ``i``'s normal added mass along its ``k``-th (0, 1)
        normal direction (see ``add_tether``)."""
        return f"{self.name}/node{i}/normal{k}"


def anchor_position(spec: mujoco.MjSpec, anchor: Anchor) -> np.ndarray | None:
    """World position (m) of ``anchor`` in the uncompiled ``spec`` (None for a free end)."""
    if isinstance(anchor, FixedPoint):
        return np.asarray(anchor.position, float)
    if isinstance(anchor, FreeEnd):
        return None
    model = dispatch.compile_spec(spec.copy())
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    if isinstance(anchor, BodyPoint):
        bid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, anchor.body)
        if bid < 0:
            raise ValueError(f"BodyPoint.body: no body named {anchor.body!r} in the spec")
        return data.xpos[bid] + data.xmat[bid].reshape(3, 3) @ np.asarray(anchor.offset)
    sid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, anchor.site)
    if sid < 0:
        raise ValueError(f"SitePoint.site: no site named {anchor.site!r} in the spec")
    return data.site_xpos[sid].copy()


def _reference_spec(makeup: LineMakeup) -> TetherSpec:
    """The TetherSpec of a line make-up: a uniform line's own (``LineMakeup.tether``); for
    another, a uniform one of its length and element count, for what the builder sizes once (the
    flex's radius: the widest section's; the initial masses, which ``BoundTether`` sets per
    element and node), with the make-up's axial damping ratio and added-mass mode."""
    if makeup.is_uniform:
        return makeup.tether
    d = makeup.element_diameter
    mu = makeup.element_mass_per_length
    return TetherSpec(length=makeup.length, segments=makeup.segments, diameter=float(d.max()),
                      mass_per_length=float(np.average(mu, weights=makeup.element_length)),
                      axial_damping_ratio=makeup.axial_damping_ratio, added_mass=makeup.added_mass)


CONTACT_B_DT = 1.0
"""Largest b dt of a seabed contact given as MoorDyn's kBot, cBot (k, b per kg of cable,
``solref = (-k, -b)``). MuJoCo takes a contact's reference acceleration -b v - k r at the start
of the step, so over a step a landing node's speed v becomes (1 - b dt) v - k dt r: beyond
b dt = 1 the contact throws the node back out faster than it came, gaining energy beyond 2
(measured, a ball landing at 1 m/s on such a contact at implicitfast: out at 2.9 m/s at b dt =
1.5, 36 m/s at 6.9, which MoorDyn's default cBot made of a neutral 0.1 m line at 1.8 ms). A
damping beyond this is taken as CONTACT_B_DT / dt: a landing node stops in the step it lands.
(MoorDyn's default kBot and cBot are over-critical on the usual cables, b / (2 sqrt(k)) = 2.1 on
a 390 kg/m chain and 10 on a neutral 0.1 m line: they stop it too, in MoorDyn's own small
steps.)"""
CONTACT_K_DT2 = 0.1
"""Largest k dt^2 of that contact (see CONTACT_B_DT): at b dt = 1 a landing node leaves again at
most at k dt^2 of its landing speed V (its speed after its first step in the contact is -k dt x0,
x0 < V dt its depth when the contact found it; the damping then takes each step's speed away),
so a tenth at most (measured on a ball: 0.01, 0.05, 0.10, 0.26, 1.02 of V at k dt^2 = 0.01,
0.05, 0.1, 0.25, 1)."""


def seabed_contact(tether: TetherSpec, rho: float, stiffness: float, damping: float) -> tuple[float, float, float]:
    """MoorDyn's seabed contact, kBot ``stiffness`` (Pa/m) and cBot ``damping`` (Pa s/m) on the
    cable's projected area d l, per kg of an element with its added mass in water of density
    ``rho``: (k 1/s^2, b 1/s, the longest step MuJoCo's contact takes with them, s: that of k;
    b is capped at CONTACT_B_DT / dt by ``contact_damping``)."""
    per_kg = tether.diameter / (tether.mu + tether.ca_normal * rho * tether.area)  # (d l) / (m l)
    k, b = stiffness * per_kg, max(damping * per_kg, 1e-9)
    return k, b, math.sqrt(CONTACT_K_DT2 / k)


def seabed_timestep(tether, rho: float, stiffness: float) -> float:
    """The longest step (s) MuJoCo's contact takes with MoorDyn's kBot ``stiffness`` (Pa/m) under
    ``tether`` (a TetherSpec or a LineMakeup: its widest section, its mean mass) in water of
    density ``rho`` (kg/m^3): k dt^2 = CONTACT_K_DT2, to 3 figures, rounded down (the step
    shown works)."""
    if isinstance(tether, LineMakeup):
        tether = _reference_spec(tether)
    dt_max = seabed_contact(tether, rho, stiffness, 0.0)[2]
    scale = 10.0 ** (math.floor(math.log10(dt_max)) - 2)
    return math.floor(dt_max / scale) * scale


def contact_damping(b: float, dt: float) -> float:
    """The contact damping (1/s per kg) a step of ``dt`` s takes: ``b``, at most CONTACT_B_DT / dt."""
    return min(b, CONTACT_B_DT / dt)


def drum_capacity(tether: TetherSpec, max_length: float | None) -> int:
    """Elements to allocate so that the drum can pay out to ``max_length`` (m) with every
    element but the drum element at the nominal length and the drum element at most 1.5 of it."""
    if max_length is None or max_length <= tether.length:
        return tether.segments
    l0 = tether.segment_length
    return max(tether.segments, int(math.ceil(max_length / l0 - 0.5)) + 1)


_FLEX = "cable"
"""The flex's name in ``cable_parts`` (renamed to the tether's own name once attached)."""
PARTS_KEPT = 64
"""Cable layouts ``cable_parts`` keeps (the least recently used is dropped beyond)."""


@functools.lru_cache(maxsize=PARTS_KEPT)
def cable_parts(n: int, first: int, diameter: float, rgba: tuple, solref: tuple | None,
                added_mass: str, contact_bit: int = TETHER_CONTACT_BIT) -> mujoco.MjSpec:
    """A spec holding a tether's own parts, named without its prefix (see ``add_tether``): n + 1
    node bodies with three world slide joints and a site each (at the origin, mass unset), the
    1-D flex through them (``diameter`` m, its seabed contact ``solref``, None for none, with
    the geoms whose conaffinity has ``contact_bit``), element
    j's tendon and equality (active for j >= ``first``), and for ``added_mass="normal"`` two
    fixed tendons per node. Kept per layout (do not change the returned spec: copy it)."""
    parts = mujoco.MjSpec()
    body_names = [f"node{i}" for i in range(n + 1)]
    for i, bname in enumerate(body_names):
        b = parts.worldbody.add_body(name=bname)
        b.explicitinertial = True
        b.gravcomp = 1.0 if i < first else 0.0
        for axis, ax in zip("xyz", np.eye(3)):
            b.add_joint(name=f"{bname}/{axis}", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=ax)
        b.add_site(name=bname, size=[diameter] * 3)

    flex = parts.add_flex(name=_FLEX, dim=1, radius=diameter / 2, rgba=list(rgba))
    flex.vertbody = body_names
    flex.vert = [0.0] * (3 * (n + 1))
    flex.elem = [k for i in range(n) for k in (i, i + 1)]
    flex.selfcollide = mujoco.mjtFlexSelf.mjFLEXSELF_NONE
    if solref is None:  # no contact at all
        flex.contype = 0
        flex.conaffinity = 0
    else:  # touches only geoms with its bit in their conaffinity (see add_seabed)
        flex.contype = contact_bit
        flex.conaffinity = 0
        # the contact carries the normal force only; friction is mjtether.cable.seabed's stick-point
        # Coulomb model (MuJoCo's soft friction creeps under a steady load), applied by
        # BoundTether with its stick points in MuJoCo's userdata
        flex.priority = 1  # the tether's settings, not the seabed geom's, set the contact
        flex.condim = 1
        flex.margin = 0.0
        flex.solref = list(solref)
        flex.solimp = [0.99, 0.999, 0.001, 0.5, 2.0]

    # element j: a tendon between its nodes' sites held at its rest length by an equality that
    # BoundTether switches off while the element is slack (tension only); the solver parameters
    # and rest lengths are set per element by BoundTether once masses are known
    for j in range(n):
        t = parts.add_tendon(name=f"element{j}")
        t.wrap_site(body_names[j])
        t.wrap_site(body_names[j + 1])
        t.rgba = [0.0, 0.0, 0.0, 0.0]
    for j in range(n):
        e = parts.add_equality(name=f"element{j}", type=mujoco.mjtEq.mjEQ_TENDON, name1=f"element{j}")
        e.active = j >= first
    # normal added mass: two fixed tendons per node, along two directions normal to the cable,
    # whose armature BoundTether sets to the node's added mass and whose joint coefficients it
    # turns with the cable (a slender cylinder has no added mass along its axis)
    for i in range(n + 1 if added_mass == "normal" else 0):
        for k in range(2):
            t = parts.add_tendon(name=f"{body_names[i]}/normal{k}")
            for axis, c in zip("xyz", np.eye(3)[k]):
                t.wrap_joint(f"{body_names[i]}/{axis}", float(c))
    return parts


def add_tether(
    spec: mujoco.MjSpec,
    tether: TetherSpec | LineMakeup,
    start: Anchor,
    end: Anchor,
    *,
    water: WaterColumn | None = None,
    nodes=None,
    name: str = "tether",
    rgba=(0.95, 0.6, 0.1, 1.0),
    seabed_friction: float | None = None,
    seabed_stiffness: float | None = None,
    seabed_damping: float = 0.0,
    max_length: float | None = None,
    end_at=None,
    added_mass: str | None = None,
    start_at=None,
    contact_bit: int = TETHER_CONTACT_BIT,
    end_mass_to=None,
) -> TetherModel:
    """Add ``tether`` to ``spec`` between ``start`` (the ship end, where its drum is) and ``end``.

    Args:
        tether: a ``TetherSpec``, or a ``LineMakeup`` (a uniform one is built as its ``tether``).
        spec: the model to add to; its ``option.timestep`` must already be set.
        water: sets the density of the added mass (default: 1025 kg/m^3 everywhere).
        nodes: initial positions (m) of the N+1 deployed nodes, shape (N+1, 3), the first at
            ``start``; default: a catenary-shaped curve of the tether's length between the ends
            (straight down from ``start`` for a free end).
        seabed_friction: ``None`` (default) for a tether that touches nothing; a Coulomb
            coefficient (>= 0) to let it rest and slide on the seabed of ``add_seabed`` (and on
            nothing else: robots' legs never snag it).
        seabed_stiffness, seabed_damping: the seabed's normal contact as MoorDyn gives it, a
            pressure per metre of penetration (Pa/m, kBot) and per m/s of penetration speed
            (Pa s/m, cBot) on the cable's projected area d l, mapped onto the contact's
            ``solref = (-k, -b)`` per unit of an element's mass (with its added mass), b at
            most 1/dt (``CONTACT_B_DT``: more would throw landing nodes back out);
            ``None`` (default): MuJoCo's soft contact with a time constant of two steps.
        max_length: the longest deployed length (m) a winch may pay out to; cable beyond
            ``tether.length`` waits on the drum at ``start`` (see the module docstring); a
            uniform line only (``LineMakeup.pays_out``: a make-up's length is fixed).
            Reel-in needs no allowance.
        end_at: where the end support will be when the simulation starts (m, world), if not
            where ``spec`` puts it (e.g. a robot whose joints are set to a standing pose after
            compiling); the last node is placed there.
        added_mass: ``"isotropic"`` or ``"normal"`` (see ``TetherSpec.added_mass`` and the module
            docstring); default: the line's (``LineMakeup.added_mass``: a TetherSpec's own,
            ``"isotropic"`` for a make-up that does not say).
        start_at: as ``end_at``, for the start support (a vessel turned after compiling).
        contact_bit: the contype of the cable's contact, which touches the geoms with that bit
            in their conaffinity (default: the seabed of ``add_seabed``). A cable rests with its
            surface on what it touches, its axis one radius above it; to rest it on its axis, as
            MoorDyn's nodes do, give it a copy of the seabed lowered by its radius, with a bit of
            its own (``add_seabed``'s ``lower`` and ``bits``). (Not by a contact capsule of no
            radius: on a height field, where its cells' prisms meet, such a capsule finds the
            nearest way out sideways, through the neighbouring prism's wall, and sinks.)
        end_mass_to: ``"start"``, ``"end"`` or both (a tuple): the ends whose node's mass the
            support's body carries instead (``cable.ends``: the node keeps its loads); default none.

    The cable's own parts are made once per layout (``cable_parts``: element count, drum
    capacity, diameter, contact, added mass) and copied into ``spec`` under the prefix
    ``name/``, then placed and weighed: an environment's resets, whose tethers differ in length
    and position only, do not rebuild them.
    """
    if not isinstance(spec, mujoco.MjSpec):
        raise ValueError(f"spec must be a mujoco.MjSpec (the model to add the tether to, e.g. mujoco.MjSpec() or "
                         f"mujoco.MjSpec.from_file(path)), got {type(spec).__name__} {spec!r:.40}")
    if seabed_friction is not None:
        _checks.non_negative("seabed_friction", seabed_friction)
    line = LineMakeup.of(tether)  # (a uniform tether: its one section; see mjtether.cable.makeup)
    if not isinstance(tether, TetherSpec):
        tether = _reference_spec(line)
    if not line.pays_out:  # sections and point loads: a fixed length, not evenly spaced nodes
        if max_length is not None and max_length > line.length * (1 + 1e-9):
            raise ValueError("max_length: payout of a line make-up is not supported yet (its length is fixed; "
                             "a uniform line, one section without loads, pays out)")
        if nodes is None:
            raise ValueError("nodes: give the start shape of a line make-up (e.g. steady_state(makeup, ...).nodes)")
    if added_mass is None:
        added_mass = line.added_mass
    if added_mass not in ADDED_MASS:
        raise ValueError(f"added_mass must be one of {', '.join(ADDED_MASS)}, got {added_mass!r}")
    for label, a in (("start", start), ("end", end)):
        if not isinstance(a, (FixedPoint, BodyPoint, SitePoint, FreeEnd)):
            raise ValueError(f"{label} must be FixedPoint, BodyPoint, SitePoint or FreeEnd, got {a!r}")
    if max_length is not None:
        _checks.in_range("max_length", max_length, 0.0, 1e6, "m")
        if isinstance(start, FreeEnd) and max_length > tether.length:
            raise ValueError("max_length: a tether with a free start end has no drum to pay out from")
    dt = _checks.positive("spec.option.timestep", spec.option.timestep, "s")
    N, L, l0 = tether.segments, tether.length, tether.segment_length
    n = drum_capacity(tether, max_length)
    first = n - N

    p0 = anchor_position(spec, start) if start_at is None else _checks.vector3("start_at", start_at)
    p1 = anchor_position(spec, end) if end_at is None else _checks.vector3("end_at", end_at)
    if nodes is None and p0 is None:
        raise ValueError("nodes: give the initial node positions when the start end is free")
    if nodes is None:
        if p1 is None:
            nodes = p0 + np.outer(np.linspace(0.0, L, N + 1), [0.0, 0.0, -1.0])
        else:
            nodes = sagged_polyline(p0, p1, L, N)
    nodes = np.array(nodes, dtype=float)
    if nodes.shape != (N + 1, 3) or not np.all(np.isfinite(nodes)):
        raise ValueError(f"nodes must be a finite array of shape ({N + 1}, 3) (m)")
    if p1 is not None and np.linalg.norm(nodes[-1] - p1) > 1e-6 * max(L, 1.0):
        raise ValueError("nodes[-1] must coincide with the end anchor")
    if p0 is not None and np.linalg.norm(nodes[0] - p0) > 1e-6 * max(L, 1.0):
        raise ValueError("nodes[0] must coincide with the start anchor")
    all_nodes = np.vstack([np.repeat(nodes[:1], first, axis=0), nodes])

    # the flex's seabed contact: None (touches nothing), or its solref
    if seabed_friction is None:
        solref = None
    elif seabed_stiffness is None:  # MuJoCo's soft contact, a time constant of two steps
        solref = (2 * dt, 1.0)
    else:  # MoorDyn's kBot, cBot (Pa/m, Pa s/m) on d l, per kg of an element (added mass in)
        _checks.positive("seabed_stiffness", seabed_stiffness, "Pa/m")
        _checks.non_negative("seabed_damping", seabed_damping, "Pa s/m")
        rho = 1025.0 if water is None else float(water.rho([water.seabed_z])[0])
        k, b, _ = seabed_contact(tether, rho, seabed_stiffness, seabed_damping)
        dt_max = seabed_timestep(tether, rho, seabed_stiffness)
        if dt > dt_max * (1 + 1e-12):
            raise ValueError(
                f"water.seabed_stiffness = {seabed_stiffness:g} Pa/m on this cable (d {tether.diameter:g} m, "
                f"{tether.mu:g} kg/m) needs a time step of at most {dt_max:.3g} s, not {dt:g} s: per kg of "
                f"cable it is {k:.3g} 1/s^2, and MuJoCo's contact throws a landing node back out beyond k dt^2 = "
                f"{CONTACT_K_DT2:g}; take a shorter step or a softer seabed")
        solref = (-k, -contact_damping(b, dt))

    # the cable's own bodies, joints, flex, tendons and equalities: a copy of the parts for this
    # layout (kept: an environment's resets differ in positions and masses only), placed and
    # weighed, attached under the name prefix; masses of the deployed cable (nodes on the drum
    # get an interior node's: they are parked)
    parts = cable_parts(n, first, float(tether.diameter), tuple(float(c) for c in rgba), solref, added_mass,
                        contact_bit).copy()
    m_el = tether.mu * l0
    inertia = [1e-6 * m_el * l0 * l0 + 1e-12] * 3
    for b, x in zip(parts.bodies[1:], all_nodes):  # (bodies[0] is the world)
        b.pos = x
        b.mass = m_el
        b.inertia = inertia
    spec.attach(parts, frame=spec.worldbody.add_frame(), prefix=f"{name}/")
    spec.flex(f"{name}/{_FLEX}").name = name
    body_names = [f"{name}/node{i}" for i in range(n + 1)]

    tm = TetherModel(name=name, spec=tether, start=start, end=end, node_bodies=body_names, n=n, first=first,
                     nominal_length=l0, initial_nodes=all_nodes,
                     max_length=float(max(L, max_length or 0.0)), seabed_friction=seabed_friction,
                     line=line, added_mass=added_mass)
    tm.end_mass_to = ends.parse_end_mass_to(end_mass_to, start, end, drum=n > N)
    if seabed_friction is not None:  # the nodes' stick points on the seabed (see mjtether.cable.seabed)
        tm.userdata_adr = spec.nuserdata
        spec.nuserdata += 3 * (n + 1)

    def connect(name_, site1, site2, active):
        c = spec.add_equality(name=name_, type=mujoco.mjtEq.mjEQ_CONNECT, objtype=mujoco.mjtObj.mjOBJ_SITE,
                              name1=site1, name2=site2)
        c.solref = [2 * dt, 1.0]
        c.solimp = [MAX_IMP, MAX_IMP, 0.001, 0.5, 2.0]
        c.active = active
        return c.name

    for label, anchor in (("start", start), ("end", end)):
        if isinstance(anchor, FreeEnd):
            continue
        site = f"{name}/{label}_attach"
        if isinstance(anchor, FixedPoint):
            spec.worldbody.add_site(name=site, pos=list(anchor.position), size=[tether.diameter] * 3)
        elif isinstance(anchor, BodyPoint):
            spec.body(anchor.body).add_site(name=site, pos=list(anchor.offset), size=[tether.diameter] * 3)
        else:
            site = anchor.site
        if label == "end":
            tm.connects["end"] = connect(f"{name}/end_connect", site, body_names[n], True)
        else:  # one per node that can sit at the fairlead; the deployed first one is active
            tm.connects["start"] = [connect(tm.drum_connect(i), site, body_names[i], i == first) for i in range(n)]
    held = [(i, a) for i, a in ((0, start), (n, end)) if isinstance(a, FixedPoint)]  # (node 0: held or parked there)
    if held and solref is not None and any(g.type == mujoco.mjtGeom.mjGEOM_HFIELD and g.conaffinity & contact_bit
                                           for g in spec.worldbody.geoms):  # (see the module docstring)
        flex, vert = spec.flex(name), np.zeros((n + 1, 3))
        bodies = list(flex.vertbody)
        for i, a in held:
            bodies[i], vert[i] = "world", a.position
        flex.vertbody, flex.vert = bodies, vert.ravel().tolist()
    return tm

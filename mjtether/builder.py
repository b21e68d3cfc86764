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
**1-D flex**: 2.2 times cheaper than free capsules, one constraint row per element instead of
three, a diagonal mass matrix, and it is the lumped-mass discretisation that MoorDyn and
Hong et al. (003_25e034c98571ae2e.txt) use. Each element is a capsule of the cable's
diameter (the flex radius) for rendering and contact; each node is a body with three world
slide joints carrying the lumped mass (half of each adjacent element).

Elongation is physical. The flex's edge-length equality is a soft constraint; in static
equilibrium MuJoCo's soft constraint stretches by r = R f / (k imp), with R = (1 - d)/d * A_hat
(A_hat = ``efc_diagA``, 2/m for an edge between free nodes of mass m; measured after
compiling, since MuJoCo derives it from ``body_invweight0``) and
k imp = S / d for a negative ``solref = (-S, -B)`` and constant impedance d. So an element
of stiffness EA / l needs S = (EA / l) (1 - d) A_hat. The impedance d then sets how fast the
axial mode rings: d -> 0 is a plain explicit spring at the physical frequency
omega_ax = sqrt(2 EA / (m l)); d -> 1 slows it. We take the physical frequency when the time
step resolves it (omega_ax dt <= 0.5) and otherwise slow the axial mode to 0.5 / dt, which
keeps the static stretch T l / EA exact and the step stable. ``EA=None`` (inextensible)
uses d = 0.9999, the stiffest MuJoCo allows at that step: strain < 1e-3 at working tension
(reported by ``TetherModel.effective_EA``).

Ends: every end is a node body of half an element's mass, joined to its support (a world
site for a fixed point, a site on the ship or robot) by a stiff ``connect`` equality whose
force is the force of the tether on that support. Keeping the end nodes free makes every
element's constraint row alike, so one ``solref`` gives every element the same EA / l.

Added mass: the normal added mass C_a rho A l of each element is lumped on its nodes as
armature of the three slide joints, which MuJoCo integrates implicitly. Armature is
isotropic, so the nodes also carry it along the cable, where a slender cylinder has none; we
tried removing that part with a force lagged by one step and it made the axial tension
noisy (5 % swings in a static catenary), so the isotropic form stays. It changes axial
(surge) inertia only, not statics or the transverse dynamics that drag and tension set.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from . import _checks, dispatch
from .analytic import sagged_polyline
from .tether import TetherSpec
from .water import WaterColumn

MIN_IMP, MAX_IMP = 1e-4, 0.9999  # MuJoCo's mjMINIMP, mjMAXIMP
AXIAL_OMEGA_DT = 0.5  # largest omega * dt given to the axial mode


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
    """MuJoCo parameters of the edge-length constraint (see module docstring)."""

    solref: tuple
    solimp: tuple
    stiffness: float  # static element stiffness K = EA_eff / l (N/m)
    omega: float  # axial-mode frequency given to the solver (rad/s)
    omega_physical: float  # sqrt(2 EA / (m l)) (rad/s); inf when inextensible

    def effective_EA(self, segment_length: float) -> float:
        return self.stiffness * segment_length


def axial_params(EA: float | None, segment_length: float, node_mass: float, timestep: float,
                 damping_ratio: float = 1.0, diag_a: float | None = None) -> AxialParams:
    """Solver parameters so that an element of length ``segment_length`` (m) between nodes of
    ``node_mass`` (kg) stretches by T l / EA, stably at ``timestep`` (s).

    ``diag_a`` is MuJoCo's ``efc_diagA`` for one element row (1/kg); by default 2 / m, the
    value MuJoCo 4 computes for an edge between two free nodes. ``Simulation`` measures it
    after compiling and retunes the constraint with the measured value.
    """
    a_true = 2.0 / node_mass  # relative inverse mass of the two nodes along the edge
    a_hat = a_true if diag_a is None else diag_a
    omega_cap = AXIAL_OMEGA_DT / timestep
    if EA is None:
        d = MAX_IMP
        x = 1.0 - d
        c = a_true / (d * a_true + x * a_hat)
        S = omega_cap**2 / c
        K = S / (x * a_hat)
        omega_phys = math.inf
    else:
        K = EA / segment_length
        omega_phys = math.sqrt(K * a_true)
        q = min(1.0, (omega_cap / omega_phys) ** 2)
        # omega^2 = omega_phys^2 x / (r (1 - x) + x) with r = a_true / a_hat; solve for x
        r = a_true / a_hat
        x = r * q / (1.0 + q * (r - 1.0))
        d = min(max(1.0 - x, MIN_IMP), MAX_IMP)
        x = 1.0 - d
        S = K * x * a_hat
        c = a_true / (d * a_true + x * a_hat)
    omega = math.sqrt(c * S)
    B = 2.0 * damping_ratio * omega / c
    return AxialParams(solref=(-S, -B), solimp=(d, d, 0.001, 0.5, 2.0), stiffness=K,
                       omega=omega, omega_physical=omega_phys)


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


def add_seabed(spec: mujoco.MjSpec, water: WaterColumn, *, friction: float = 0.6, size: float = 0.0,
               rgba=(0.45, 0.4, 0.3, 1.0), name: str = "seabed", slope: float = 0.0,
               slope_heading: float = 0.0) -> mujoco.MjsGeom:
    """The seabed: a plane through z = -water.depth at the origin, tilted by ``slope`` (rad, in
    [0, 45 deg)) so that it rises towards ``slope_heading`` (see ``seabed_height``). Robots
    (contype bit 1) and tethers built with ``seabed_friction`` (bit 2) rest on it. ``size`` is
    the half-width drawn (0: infinite)."""
    if not isinstance(water, WaterColumn):
        raise ValueError(f"water must be a WaterColumn, got {type(water).__name__}")
    _checks.non_negative("seabed.friction", friction)
    _checks.in_range("seabed.slope", slope, 0.0, math.radians(45.0) - 1e-9, "rad")
    _checks.finite("seabed.slope_heading", slope_heading)
    # rotate +z onto the normal (-sin a cos h, -sin a sin h, cos a): by a about (sin h, -cos h, 0)
    c, s_ = math.cos(slope / 2), math.sin(slope / 2)
    quat = [c, s_ * math.sin(slope_heading), -s_ * math.cos(slope_heading), 0.0]
    return spec.worldbody.add_geom(
        name=name, type=mujoco.mjtGeom.mjGEOM_PLANE, pos=[0.0, 0.0, water.seabed_z], quat=quat,
        size=[size, size, 1.0], friction=[float(friction), 0.005, 0.0001], rgba=list(rgba),
        contype=ROBOT_CONTACT_BIT, conaffinity=ROBOT_CONTACT_BIT | TETHER_CONTACT_BIT, condim=3)


# ------------------------------------------------------------------------------ builder


@dataclass
class TetherModel:
    """What ``add_tether`` put in the spec: names, masses and parameters.

    Node i (0..N) is a flex vertex carried by the body ``node_bodies[i]``.
    """

    name: str
    spec: TetherSpec
    start: Anchor
    end: Anchor
    node_bodies: list
    node_mass: np.ndarray  # kg, per node
    added_mass: np.ndarray  # kg, per node (isotropic armature)
    axial: AxialParams
    initial_nodes: np.ndarray
    connects: dict = field(default_factory=dict)  # "start"/"end" -> equality name

    @property
    def flex(self) -> str:
        return f"{self.name}"

    @property
    def edge_equality(self) -> str:
        return f"{self.name}/stretch"

    @property
    def effective_EA(self) -> float:
        """Axial stiffness the solver realises in statics (N): EA, or the inextensible limit."""
        return self.axial.effective_EA(self.spec.segment_length)


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


def add_tether(
    spec: mujoco.MjSpec,
    tether: TetherSpec,
    start: Anchor,
    end: Anchor,
    *,
    water: WaterColumn | None = None,
    nodes=None,
    name: str = "tether",
    rgba=(0.95, 0.6, 0.1, 1.0),
    seabed_friction: float | None = None,
) -> TetherModel:
    """Add ``tether`` to ``spec`` between ``start`` (node 0, the ship end) and ``end``.

    Args:
        spec: the model to add to; its ``option.timestep`` must already be set.
        water: sets the density of the added mass (default: 1025 kg/m^3 everywhere).
        nodes: initial node positions (N+1, 3) in m; default: a catenary-shaped curve of the
            tether's length between the ends (straight down from ``start`` for a free end).
        seabed_friction: ``None`` (default) for a tether that touches nothing; a Coulomb
            coefficient (>= 0) to let it rest and slide on the seabed of ``add_seabed`` (and on
            nothing else: robots' legs never snag it).
    """
    if seabed_friction is not None:
        _checks.non_negative("seabed_friction", seabed_friction)
    if not isinstance(tether, TetherSpec):
        raise ValueError(f"tether must be a TetherSpec, got {type(tether).__name__}")
    for label, a in (("start", start), ("end", end)):
        if not isinstance(a, (FixedPoint, BodyPoint, SitePoint, FreeEnd)):
            raise ValueError(f"{label} must be FixedPoint, BodyPoint, SitePoint or FreeEnd, got {a!r}")
    dt = _checks.positive("spec.option.timestep", spec.option.timestep, "s")
    N, L, l = tether.segments, tether.length, tether.segment_length

    p0 = anchor_position(spec, start)
    p1 = anchor_position(spec, end)
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

    rho = (water.rho if water is not None else (lambda z: np.full(np.shape(z), 1025.0)))(nodes[:, 2])
    m_el = tether.mu * l
    node_mass = np.full(N + 1, m_el)
    node_mass[[0, -1]] = 0.5 * m_el
    added = tether.ca_normal * rho * tether.area * l
    # End nodes carry half an element's mass and added mass; armature of the other half makes
    # their inertia equal to an interior node's, so that MuJoCo's constraint scaling (the
    # diagonal of J M^-1 J^T) and hence the stiffness EA / l are the same for every element.
    # The extra inertia sits at a support (or at a free tip) and weighs nothing.
    armature = added + np.r_[0.5 * (m_el + added[0]), np.zeros(N - 1), 0.5 * (m_el + added[-1])]
    added[[0, -1]] *= 0.5
    body_names = []
    for i in range(N + 1):
        bname = f"{name}/node{i}"
        b = spec.worldbody.add_body(name=bname, pos=nodes[i])
        b.explicitinertial = True
        b.mass = node_mass[i]
        b.inertia = [1e-6 * node_mass[i] * l * l + 1e-12] * 3
        for axis, ax in zip("xyz", np.eye(3)):
            b.add_joint(name=f"{bname}/{axis}", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=ax,
                        armature=float(armature[i]))
        if i in (0, N):
            b.add_site(name=f"{name}/{'start' if i == 0 else 'end'}", size=[tether.diameter] * 3)
        body_names.append(bname)

    flex = spec.add_flex(name=name, dim=1, radius=tether.diameter / 2, rgba=list(rgba))
    flex.vertbody = body_names
    flex.vert = [0.0] * (3 * (N + 1))
    flex.elem = [k for i in range(N) for k in (i, i + 1)]
    flex.selfcollide = mujoco.mjtFlexSelf.mjFLEXSELF_NONE
    if seabed_friction is None:  # no contact at all
        flex.contype = 0
        flex.conaffinity = 0
    else:  # touches only geoms with the seabed bit in their conaffinity (see add_seabed)
        flex.contype = TETHER_CONTACT_BIT
        flex.conaffinity = 0
        flex.priority = 1  # the tether's friction, not the seabed geom's, sets the contact
        flex.condim = 3 if seabed_friction > 0 else 1  # (zero friction in a cone is degenerate)
        flex.friction = [float(seabed_friction), 0.005, 0.0001]
        flex.margin = 0.0
        flex.solref = [2 * dt, 1.0]
        flex.solimp = [0.99, 0.999, 0.001, 0.5, 2.0]

    axial = axial_params(tether.EA, l, m_el + added[N // 2], dt, tether.axial_damping_ratio)
    eq = spec.add_equality(name=f"{name}/stretch", type=mujoco.mjtEq.mjEQ_FLEX, name1=name)
    eq.solref = list(axial.solref)
    eq.solimp = list(axial.solimp)

    tm = TetherModel(name=name, spec=tether, start=start, end=end, node_bodies=body_names,
                     node_mass=node_mass, added_mass=added, axial=axial, initial_nodes=nodes)
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
        c = spec.add_equality(name=f"{name}/{label}_connect", type=mujoco.mjtEq.mjEQ_CONNECT,
                              objtype=mujoco.mjtObj.mjOBJ_SITE, name1=site, name2=f"{name}/{label}")
        c.solref = [2 * dt, 1.0]
        c.solimp = [MAX_IMP, MAX_IMP, 0.001, 0.5, 2.0]
        tm.connects[label] = c.name
    return tm

"""Seabed friction of a bound tether: the seabed it rests on (a plane, or a height field whose
local tangent plane under each node is taken), its nodes' stick points (in MuJoCo's
``userdata``), and the Coulomb friction of ``seabed.seabed_friction`` on the deployed nodes, or
its compiled twin. Units SI, world frame.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mjtether.physics import compiled

from .builder import TETHER_CONTACT_BIT, grid_of
from .drum import Drum
from .layout import CableLayout
from .seabed import CONTACT_TOLERANCE, STICK_DAMPING, STICK_STIFFNESS, seabed_friction


class SeabedContact:
    """The seabed friction of a bound tether. ``seabed``: (a point on the seabed plane, its unit
    normal, the cable's submerged weight per metre there (N/m) times the cosine of its slope),
    or None for a tether without seabed friction (MuJoCo's contact is then all). On a height
    field (``grid``, a ``Bathymetry``), the point and normal are None and are each node's own,
    under it, at each call, and the weight is not yet times the cosine."""

    def __init__(self, layout: CableLayout, drum: Drum):
        self.layout, self.drum = layout, drum
        self.grid = None
        self.seabed = self._find_seabed()

    def _find_seabed(self):
        """The seabed plane the tether rests on, for its friction (``mjtether.cable.seabed``):
        (a point on it, its unit normal, the cable's submerged weight per metre there (N/m)
        times the cosine of its slope), or None for a tether without seabed contact. The stick
        points live in ``data.userdata``, NaN (off the seabed) at the start."""
        L = self.layout
        model, tm, water = L.model, L.tm, self.drum.water
        if not tm.seabed_friction or tm.userdata_adr < 0:  # (no friction: MuJoCo's contact is all)
            return None
        flex = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_FLEX, tm.name)
        bit = int(model.flex_contype[flex]) if flex >= 0 else TETHER_CONTACT_BIT  # (its seabed: see add_tether)
        seabed = (model.geom_conaffinity & bit != 0) & (model.geom_bodyid == 0)
        planes = np.flatnonzero(seabed & ((model.geom_type == int(mujoco.mjtGeom.mjGEOM_PLANE))
                                          | (model.geom_type == int(mujoco.mjtGeom.mjGEOM_HFIELD)))).tolist()
        if not planes:
            return None
        if len(planes) > 1:
            raise ValueError("a tether with seabed_friction rests on one seabed (a plane or a height field); the "
                             f"model has {len(planes)} (geoms {planes})")
        g = planes[0]
        if model.geom_type[g] == int(mujoco.mjtGeom.mjGEOM_HFIELD):
            self.grid = grid_of(model, g)
            point, normal = None, np.array([0.0, 0.0, 1.0])  # (each node's own, in kernel)
            rho = float(water.rho([float(self.grid.z.mean())])[0])
        else:
            R = np.zeros(9)
            mujoco.mju_quat2Mat(R, model.geom_quat[g])
            normal = R.reshape(3, 3)[:, 2].copy()
            point = model.geom_pos[g].copy()
            rho = float(water.rho([point[2]])[0])
        # each node's wet weight: half its elements' and its point load's (a line that pays out
        # takes its one weight per metre on the elements' rest lengths as they change: ``kernel``)
        mk = L.line
        ww = mk.element_wet_weight(rho, water.gravity) * mk.element_length
        self.node_wet = (np.r_[0.0, ww] * 0.5 + np.r_[ww, 0.0] * 0.5 + mk.node_wet_weight(rho, water.gravity)) * normal[2]
        w = L.spec.wet_weight_per_length(rho, water.gravity) * normal[2]
        self.stick = slice(tm.userdata_adr, tm.userdata_adr + 3 * (L.n + 1))
        L.data.userdata[self.stick] = np.nan
        return point, normal, w

    def friction(self, data: mujoco.MjData, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Seabed friction on the deployed nodes at ``x`` (m) moving at ``v`` (m/s), N, updating
        their stick points."""
        k = self.drum.first
        stick = data.userdata[self.stick].reshape(-1, 3)
        f, stick[k:] = self.kernel(x, v, stick[k:])
        stick[:k] = np.nan  # nodes on the drum
        return f

    def planes(self, x):
        """The seabed's plane under nodes ``x`` (n, 3) m: (a point on it, its unit normal), each
        (3,) for a plane or (n, 3) for a height field (its tangent plane under each node)."""
        point, normal, _ = self.seabed
        if self.grid is None:
            return point, normal
        feet = x.copy()
        feet[:, 2], normal = self.grid.height_and_normal(x[:, 0], x[:, 1])
        return feet, normal

    def kernel(self, x, v, stick, preload=None):
        """``seabed.seabed_friction`` for the deployed nodes; with ``preload`` (N per node), the
        stick points are first placed so that the springs pull with it (up to mu N)."""
        L, dr = self.layout, self.drum
        _, _, w = self.seabed
        point, normal = self.planes(x)
        k = dr.first
        if not L.pays_out:  # (a buoyant node does not press on the seabed)
            normal_force = np.maximum(self.node_wet[k:], 0.0)
        elif w <= 0.0:  # a buoyant cable does not press on the seabed
            return np.zeros_like(x), np.full_like(x, np.nan)
        else:  # each node's half of its elements
            half = (0.5 * w) * dr.deployed_rest
            normal_force = np.empty(len(half) + 1)
            normal_force[:-1] = half
            normal_force[-1] = 0.0
            normal_force[1:] += half
        mass = dr.inertia[k:]  # body mass + armature (added mass)
        dt = L.model.opt.timestep
        stiffness = (STICK_STIFFNESS / dt ** 2) * mass
        damping = (2.0 * STICK_DAMPING * math.sqrt(STICK_STIFFNESS) / dt) * mass  # 2 zeta sqrt(k m)
        if self.grid is not None:  # the weight's part pressing on the local slope
            normal_force = normal_force * normal[:, 2]
        if preload is not None:
            foot = x - np.sum((x - point) * normal, axis=-1)[:, None] * normal
            stick = foot + preload / stiffness[:, None]
        if L.fast is not None and self.grid is None:
            m = len(x)
            force, new = L.fast["friction"][:m], L.fast["stick"][:m]
            compiled.seabed_friction(x, v, stick, point, normal, L.spec.diameter / 2, normal_force,
                                     float(L.tm.seabed_friction), stiffness, damping, CONTACT_TOLERANCE, force,
                                     new)
            return force, new
        return seabed_friction(x, v, stick, point=point, normal=normal, radius=L.spec.diameter / 2,
                               normal_force=normal_force, mu=L.tm.seabed_friction, stiffness=stiffness,
                               damping=damping)

    def preload(self, data: mujoco.MjData, tension, hydro) -> None:
        """Start the seabed friction from a steady state: set the stick points of the laid nodes
        so that friction holds them as they are, with element ``tension`` (N, the deployed
        elements', e.g. ``SteadyState.tension``), current and weight (each node's share up to
        mu N); ``hydro(x, v)`` gives the hydrodynamic loads (``loads.CableLoads.hydro``). Uses the
        positions and velocities in ``data`` (qpos, qvel)."""
        if self.seabed is None:
            return
        L = self.layout
        k, n, m = self.drum.first, L.n, L.model
        T = np.asarray(tension, dtype=float)
        if T.shape != (n - k,) or not np.all(np.isfinite(T)):
            raise ValueError(f"tension must be {n - k} finite element tensions (N), got shape {T.shape}")
        x = L.x(k)
        v = L.v(k)
        e = x[1:] - x[:-1]
        t = e / np.maximum(np.linalg.norm(e, axis=1), 1e-12)[:, None]
        total = hydro(x, v)
        total[:-1] += T[:, None] * t
        total[1:] -= T[:, None] * t
        total += m.body_mass[L.bids[k:], None] * m.opt.gravity
        _, normal = self.planes(x)
        # what friction must hold, in the seabed's plane
        need = -(total - np.sum(total * normal, axis=-1)[:, None] * normal)
        need[[0, -1]] = 0.0  # the ends are held by their supports
        stick = data.userdata[self.stick].reshape(-1, 3)
        stick[:] = np.nan
        f, stick[k:] = self.kernel(x, v, stick[k:], preload=need)

"""A MuJoCo simulation with tethers and hydrodynamic bodies: compile, step, read out, close.

``Simulation`` compiles an ``MjSpec`` that ``add_tether`` and ``add_body_hydro`` prepared,
registers its force providers with the process-wide passive callback
(``mjtether.dispatch``), steps with divergence detection, and removes its providers on
``close()`` (or at the end of a ``with`` block).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from . import compiled, dispatch, native
from .builder import AXIAL_OMEGA_DT, MAX_IMP, MIN_IMP, TETHER_CONTACT_BIT, TetherModel, axial_params, axial_scalar
from .hydro import bending_forces, element_geometry, tether_loads
from .rigidbody import BodyHydroModel, BoundBodyHydro, make_not_simple
from .vehicle import BoundVehicle, VehicleModel
from .seabed import CONTACT_TOLERANCE, STICK_DAMPING, STICK_STIFFNESS, seabed_friction
from .water import WaterColumn


_EQUALITY = int(mujoco.mjtConstraint.mjCNSTR_EQUALITY)  # an int: comparing arrays with the enum is slow
_BADQPOS, _BADQVEL, _BADQACC = (int(w) for w in (mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL,
                                                  mujoco.mjtWarning.mjWARN_BADQACC))
_EX, _EZ = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
MAX_NODE_SPEED = 1000.0
"""Tether node speed (m/s) taken as divergence: no cable in water moves at 1 km/s."""
MAX_STRAIN = 1.0
"""Stretch of an element, over the nominal element length, taken as divergence: a cable
stretched to twice its length has failed."""
FAIRLEAD_SHARE = 0.05
"""Part of the drum element, in units of l0, lumped on the fairlead node (see ``_update``)."""
_STATE = mujoco.mjtState.mjSTATE_INTEGRATION
SLACK_FORCE = 0.1
"""A push or overshoot worth more than this part of an element's weight in water, and more than
SLACK_TENSION of the highest element tension at that step, has its step redone with the element
switched (see ``BoundTether.update_slack``)."""
SLACK_TENSION = 0.1
"""See SLACK_FORCE: a push or overshoot below either is
switched a step late, which costs less than redoing the step (measured on the built-in walker
scenario, where the gait jerks the cable near the tow point taut and slack: 1.055 MuJoCo steps
per step, against 1.25 with the weight threshold alone)."""
SLACK_REDOS = 1
"""Times a step is redone with elements switched both ways; one more redo may then switch off
elements still pushing while shorter than their rest length. (3 redos gave 1.6 MuJoCo steps
per step on the built-in walker scenario and no fewer pushes in the tests.)"""
START_SLACK = 0.01
"""An element shorter than its rest length by more than this fraction starts slack."""
SPLIT, MERGE = 1.2, 0.1
"""The drum element (next to the fairlead) releases a node from the drum when its rest length
passes SPLIT x the nominal element length l0, and takes one back below MERGE x l0. The node that
moves is then only (SPLIT - 1) or MERGE x l0 from the fairlead: the chord it is placed on is
that short, so it starts close to where the sagging cable would have it (a node placed at a
third of a 1.5 l0 drum element rang the ship tension by +-5 %), and the band between them keeps
a winch that dithers from releasing and taking back the same node."""


class SimulationDiverged(RuntimeError):
    """The state became non-finite or MuJoCo reported a bad acceleration."""


class BoundTether:
    """A ``TetherModel`` bound to a compiled model: indices, force provider, payout, readouts.

    Nodes and elements are numbered as in ``builder``: from the drum's core (0) to the robot end
    (``n``); only nodes ``first`` .. n are deployed, ``first`` at the fairlead. Readouts named
    after the deployed cable (``nodes``, ``tension``) return the deployed part only, its first
    row at the ship; ``element_*`` readouts return all ``n`` elements, 0 for those on the drum.
    Readouts refer to the state of the last ``mj_forward``/``mj_step``. Forces are those the
    tether exerts on its ends (N, world frame).
    """

    def __init__(self, tm: TetherModel, model: mujoco.MjModel, data: mujoco.MjData, water: WaterColumn):
        self.tm = tm
        self.spec = s = tm.spec
        self.water = water
        self.model, self.data = model, data
        self.n = n = tm.n
        self.l0 = tm.nominal_length
        self.max_length = tm.max_length
        fid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_FLEX, tm.name)
        self.vertadr = int(model.flex_vertadr[fid])
        self.tadr = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TENDON, tm.element_tendon(0))
        self._ten = slice(self.tadr, self.tadr + n)
        # the normal added mass's tendons (two per node, see builder) and their joint coefficients
        self._normal_ten = self._normal_prm = None  # (isotropic added mass: none)
        if tm.added_mass == "normal":
            nadr = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TENDON, tm.normal_tendon(0, 0))
            if nadr < 0 or not np.all(model.tendon_num[nadr:nadr + 2 * (n + 1)] == 3) or \
                    not np.all(np.diff(model.tendon_adr[nadr:nadr + 2 * (n + 1)]) == 3):
                raise RuntimeError("tether normal added-mass tendons missing or not contiguous")
            self._normal_ten = slice(nadr, nadr + 2 * (n + 1))
            w0 = int(model.tendon_adr[nadr])
            self._normal_prm = model.wrap_prm[w0:w0 + 6 * (n + 1)].reshape(n + 1, 2, 3)  # a view
        self._row_cache: dict[int, slice] = {}
        self.eq0 = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, tm.element_tendon(0))
        self._eqs = slice(self.eq0, self.eq0 + n)
        # constraint rows of each equality defined before the elements' (see _element_rows)
        rows_of = {int(mujoco.mjtEq.mjEQ_CONNECT): 3, int(mujoco.mjtEq.mjEQ_WELD): 6, int(mujoco.mjtEq.mjEQ_JOINT): 1,
                   int(mujoco.mjtEq.mjEQ_TENDON): 1}
        before = model.eq_type[:self.eq0]
        if any(int(t) not in rows_of for t in before):
            raise ValueError("a tether must be added before any flex equality of the spec")
        self._rows_before = np.array([rows_of[int(t)] for t in before], dtype=np.int64)
        start = tm.connects.get("start")
        self.drum_eq = None if start is None else np.array(
            [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, c) for c in start])
        self.end_eq = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, tm.connects["end"]) \
            if "end" in tm.connects else None
        self._bids = np.array([mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, b) for b in tm.node_bodies])
        dofs = (model.body_dofadr[self._bids][:, None] + np.arange(3)).ravel()
        if not np.all(np.diff(dofs) == 1):
            raise RuntimeError("tether node dofs must be contiguous")
        self._dof0 = int(dofs[0])
        qadr = (model.jnt_qposadr[model.body_jntadr[self._bids]][:, None] + np.arange(3)).ravel()
        if not np.all(np.diff(qadr) == 1):
            raise RuntimeError("tether node qpos must be contiguous")
        self._q0 = int(qadr[0])
        self._body0 = tm.initial_nodes.ravel().copy()  # node body positions at qpos = 0
        make_not_simple(model, self._bids)  # masses and armature change with the deployed length
        self.first = tm.first
        self.drum_rest = self.l0
        self.payout_rate = 0.0  # m/s, of the last set_length
        self._eq_snapshot = None  # Simulation's copy of eq_active at the last force computation (use_snapshot)
        self._snap_views = None  # its slices before and at the elements (_element_rows)
        # views of the per-step arrays (mjData's and mjModel's arrays never move)
        self._eq_view, self._length_view = data.eq_active[self._eqs], data.ten_length[self._ten]
        self._drum_arrays = (model.body_mass, model.dof_armature, model.tendon_invweight0, model.tendon_armature,
                             model.eq_solref, model.eq_solimp, model.eq_data, model.tendon_length0)
        self._mu = s.mu
        self._ca_A = s.ca_normal * s.area
        self.makeup = mk = tm.makeup
        if mk is not None:  # a line make-up: per-element properties and point loads, no payout
            self.drum_rest = float(mk.element_length[0])
            self._mu = mk.element_mass_per_length  # kg/m, per element (floats in)
            self._ca_A = mk.element_ca_normal * np.pi * mk.element_diameter**2 / 4 + mk.element_float_added_volume
            self._EA = np.where(np.isfinite(mk.element_EA), mk.element_EA, np.inf)
        # pushes and overshoots below this (N) switch elements without redoing the step
        w0 = s.wet_weight_per_length(float(water.rho([0.0])[0])) if mk is None else \
            float(np.mean(np.abs(mk.element_wet_weight(float(water.rho([0.0])[0]), water.gravity))))
        self._f_min = max(SLACK_FORCE * abs(w0) * self.l0, 1e-6)
        self._seabed = self._find_seabed(model, tm)
        self._fast = self._compiled_kernels() if compiled.backend() == "numba" else None
        # updated in place, as the native callback reads them (native_table)
        self._rest, self._inertia = np.zeros(n), np.zeros(n + 1)
        self._native_state = np.zeros(3)  # first, its share of the drum element, payout rate
        self._relayout()

    def _compiled_kernels(self):
        """Per-element properties and work arrays for the compiled kernels (``compiled``): each
        element's diameter, C_dn, C_dt, displaced area per metre and floats' drag area per metre,
        each joint's EI / l (None without bending), the water profiles' codes (None: evaluated in
        NumPy), and buffers for the loads."""
        s, mk, n = self.spec, self.makeup, self.n
        if mk is None:
            full = lambda value: np.full(n, float(value))  # noqa: E731
            c = dict(diameter=full(s.diameter), cd_normal=full(s.cd_normal), cd_tangential=full(s.cd_tangential),
                     area=full(np.pi * s.diameter**2 / 4.0), cd_area_float=full(0.0),
                     bend=np.full(max(n - 1, 0), s.EI / self.l0) if s.EI > 0 else None)
        else:
            EI, rest = mk.element_EI, np.asarray(mk.element_length, dtype=float)
            c = dict(diameter=mk.element_diameter, cd_normal=mk.element_cd_normal,
                     cd_tangential=mk.element_cd_tangential, area=mk.element_area,
                     cd_area_float=mk.element_float_cd_area,
                     bend=(0.5 * (EI[1:] + EI[:-1])) / (0.5 * (rest[1:] + rest[:-1])) if np.any(EI > 0) else None)
            c = {k: (v if v is None else np.ascontiguousarray(v, dtype=float)) for k, v in c.items()}
        c.update(water=compiled.profile_codes(self.water), rho=np.empty(n), u=np.empty((n, 3)),
                 f=np.empty((n + 1, 3)), friction=np.empty((n + 1, 3)), stick=np.empty((n + 1, 3)))
        return c

    # ----------------------------------------------------------------- layout of the cable

    def _x(self, i0: int = 0, i1: int | None = None) -> np.ndarray:
        """Positions (m) of nodes i0..i1-1 from qpos (valid before mj_forward)."""
        i1 = self.n + 1 if i1 is None else i1
        return (self.data.qpos[self._q0 + 3 * i0:self._q0 + 3 * i1] + self._body0[3 * i0:3 * i1]).reshape(-1, 3)

    def _v(self, i0: int = 0, i1: int | None = None) -> np.ndarray:
        i1 = self.n + 1 if i1 is None else i1
        return self.data.qvel[self._dof0 + 3 * i0:self._dof0 + 3 * i1].reshape(-1, 3)

    def _place(self, i: int, x, v) -> None:
        self.data.qpos[self._q0 + 3 * i:self._q0 + 3 * i + 3] = np.asarray(x) - self._body0[3 * i:3 * i + 3]
        self.data.qvel[self._dof0 + 3 * i:self._dof0 + 3 * i + 3] = v

    @property
    def fairlead_share(self) -> float:
        """Length (m) of the drum element whose mass and loads the fairlead node carries:
        FAIRLEAD_SHARE l0, or half the drum element if it is shorter than twice that."""
        if self.drum_eq is None or self.makeup is not None:
            return 0.5 * self.drum_rest  # a free start end or a make-up: an ordinary element
        return min(FAIRLEAD_SHARE * self.l0, 0.5 * self.drum_rest)

    @property
    def rest_lengths(self) -> np.ndarray:
        """Unstretched length of every element (m), shape (n,); 0 for elements on the drum."""
        if self.makeup is not None:
            return np.array(self.makeup.element_length, dtype=float)
        r = np.zeros(self.n)
        r[self.first] = self.drum_rest
        r[self.first + 1:] = self.l0
        return r

    def _relayout(self) -> None:
        """Masses, armature, element limits and tuning, equalities and gravity compensation for
        the current ``first`` and ``drum_rest`` (every node and element)."""
        m, d, k, n = self.model, self.data, self.first, self.n
        m.body_gravcomp[self._bids] = (np.arange(n + 1) < k).astype(float)
        if self.drum_eq is not None:
            d.eq_active[self.drum_eq] = 0
            d.eq_active[self.drum_eq[k]] = 1
        x = self._x()
        z = x[:, 2]
        zc = np.minimum(0.5 * (z[1:] + z[:-1]), 0.0)
        self._added_per_m = self._ca_A * np.asarray(self.water.rho(zc), float)  # kg/m, per element
        if self.makeup is not None:  # the point loads' added mass, at the start's depths
            self._node_added = self.makeup.node_added_volume * np.asarray(self.water.rho(np.minimum(z, 0.0)), float)
        self._update()
        self._orient_added_mass(x[k:])
        # elements about as long as their rest length or longer start taut, clearly slack ones
        # slack (an element started taut that pushes is switched off at the first step)
        length = np.linalg.norm(np.diff(x, axis=0), axis=1)
        d.eq_active[self._eqs] = (np.arange(n) >= k) & (length >= self._rest * (1 - START_SLACK))

    def _update(self) -> None:
        """Masses, armature and element solver parameters of every node and element for the
        current rest lengths (``_update_drum`` does an ordinary payout step's share of this)."""
        m, k, n, l0 = self.model, self.first, self.n, self.l0
        rest = self.rest_lengths
        idx = np.arange(n + 1)
        r_left = np.r_[0.0, rest]  # the element on each side of each node (0 past the ends)
        r_right = np.r_[rest, 0.0]
        ap = self._added_per_m
        a_left = np.r_[0.0, ap]
        a_right = np.r_[ap, 0.0]
        # the drum element's part at the fairlead is a constant FAIRLEAD_SHARE l0 (at most half of
        # it): everything paid out adds to the first free node, so the free cable's mass grows
        # continuously and nothing jumps when a node is released or taken back
        c = self.fairlead_share
        left = np.where(idx == k + 1, 1.0 - c / max(rest[k], 1e-300), 0.5)
        right = np.where(idx == k, c / max(rest[k], 1e-300), 0.5)
        added = left * a_left * r_left + right * a_right * r_right
        parked = idx < k
        end = (idx == k) | (idx == n)  # at a support: inertia up to an interior node's
        if self.makeup is None:
            mass = self._mu * (left * r_left + right * r_right)
            i_ref = self._i_ref = (self._mu + np.median(ap)) * l0  # an interior node's (normal) inertia
            mass = np.where(parked, self._mu * l0, mass)
            iso = np.zeros(n + 1)
        else:  # per-element mass per length, and the point loads' masses and (isotropic) added masses
            mu = self._mu
            mass = left * np.r_[0.0, mu] * r_left + right * np.r_[mu, 0.0] * r_right + self.makeup.node_mass
            iso = self._node_added.copy()
            i_ref = self._i_ref = float(np.median(mass + added + iso))
        # the line's added mass acts normal to it (the normal tendons); the isotropic armature
        # holds the point loads' added mass, a parked node's inertia and a support's conditioning
        normal = np.where(parked, 0.0, added)
        iso = np.where(parked, i_ref - mass, iso)
        iso = np.where(end & ~parked, np.maximum(i_ref - mass - normal, iso), iso)
        if self._normal_ten is None:  # isotropic added mass: all of it on the slide joints
            iso = iso + normal
        iso = np.maximum(iso, 1e-9 * i_ref)
        m.body_mass[self._bids] = mass
        m.dof_armature[self._dof0:self._dof0 + 3 * (n + 1)] = np.repeat(iso, 3)
        if self._normal_ten is not None:
            m.tendon_armature[self._normal_ten] = np.repeat(normal, 2)
        self._inertia[:] = mass + iso  # along the cable (what its axial mode moves)
        # elements: inverse mass along the element, solver parameters, rest lengths
        js = np.arange(n)
        inv = 1.0 / self._inertia[:-1] + 1.0 / self._inertia[1:]
        p = axial_params(self.spec.EA if self.makeup is None else self._EA, np.where(js >= k, rest, l0), inv,
                         m.opt.timestep, self.spec.axial_damping_ratio)
        m.tendon_invweight0[self._ten] = inv
        m.eq_solref[self._eqs] = p.solref
        m.eq_solimp[self._eqs] = p.solimp
        self._lead = p.B / p.S  # s: see _set_rest
        self._K = np.array(p.stiffness, dtype=float)  # N/m, static stiffness of each element
        self._rest[:] = rest
        self._deployed_rest = self._rest[k:]
        self._set_rest(0, n)
        self.axial = p
        self._sync_native()

    def _sync_native(self) -> None:
        """The payout state as the native callback reads it (``native_table``'s state row)."""
        st = self._native_state
        st[0] = self.first
        st[1] = 0.5 if self.makeup is not None else self.fairlead_share / max(self.drum_rest, 1e-300)
        st[2] = self.payout_rate if self.drum_eq is not None else 0.0

    def native_table(self):
        """This tether's arrays for the native callback (``native``, slots ``T_*``), or None where
        its loads need Python (the NumPy kernels, or a water profile the compiled kernels do not
        know). The arrays are this object's own, updated in place as the cable pays out."""
        c = self._fast
        if c is None or c["water"] is None:
            return None
        dkind, dp, ckind, cp = c["water"]
        mk, n = self.makeup, self.n
        empty = np.zeros(0)
        mode, real = 0, np.zeros(13)
        real[0] = self.water.gravity
        if self._seabed is not None:
            point, normal, w = self._seabed
            mode = 2 if mk is not None else (3 if w <= 0.0 else 1)
            # (over dt^2 and dt at each step: a pre-roll changes the time step)
            real[1:7] = (STICK_STIFFNESS, 2.0 * STICK_DAMPING * math.sqrt(STICK_STIFFNESS), w,
                         float(self.tm.seabed_friction), self.spec.diameter / 2, CONTACT_TOLERANCE)
            real[7:10], real[10:13] = point, normal
        wrap = -1 if self._normal_prm is None else int(self.model.tendon_adr[self._normal_ten.start])
        points = mk is not None and mk.has_point_loads
        ints = np.array([n, self.vertadr, self._dof0, mode, self._stick.start if mode else 0,
                         c["bend"] is not None, dkind, ckind, points, wrap], dtype=np.int64)
        node = (lambda a: np.ascontiguousarray(a, dtype=float)) if mk is not None else (lambda a: empty)  # noqa: E731
        return [ints, real, self._native_state, self._rest, self._inertia, c["diameter"], c["cd_normal"],
                c["cd_tangential"], c["area"], c["cd_area_float"], empty if c["bend"] is None else c["bend"], dp, cp,
                node(getattr(self, "_node_wet", empty)) if mode == 2 else empty,
                node(mk.node_volume) if points else empty, node(mk.node_cd_area) if points else empty]

    def _update_drum(self) -> None:
        """``_update`` for an ordinary payout step (only the drum element's rest length changed):
        the same bookkeeping for the fairlead node, the first free node and the two elements at
        them, in scalar arithmetic (this runs at every step of a paying-out winch); with the
        compiled kernels, ``compiled.drum_update``."""
        m, k, n, l0, mu = self.model, self.first, self.n, self.l0, self._mu
        if self._fast is not None:
            EA = self.spec.EA
            compiled.drum_update(k, n, l0, mu, self.drum_rest, self.fairlead_share, self._added_per_m, self._i_ref,
                                 self._dof0, self.tadr, self.eq0,
                                 -1 if self._normal_ten is None else self._normal_ten.start,
                                 math.inf if EA is None else float(EA), m.opt.timestep, self.spec.axial_damping_ratio,
                                 AXIAL_OMEGA_DT, MIN_IMP, MAX_IMP, self.payout_rate, self._bids, self._rest,
                                 self._inertia, self._lead, self._K, *self._drum_arrays)
            return
        body_mass, armature, invweight = m.body_mass, m.dof_armature, m.tendon_invweight0
        ten_armature, nten = m.tendon_armature, (None if self._normal_ten is None else self._normal_ten.start)
        eq_solref, eq_solimp = m.eq_solref, m.eq_solimp
        s = self.drum_rest
        self._rest[k] = s  # (_deployed_rest is a view of it)
        c = self.fairlead_share
        ap = self._added_per_m
        i_ref = self._i_ref
        inertia = self._inertia
        right = l0 if k + 1 < n else 0.0
        for i, mass, add in ((k, mu * c, float(ap[k]) * c),
                             (k + 1, mu * ((s - c) + 0.5 * right),
                              float(ap[k]) * (s - c) + (0.5 * float(ap[k + 1]) * right if k + 1 < n else 0.0))):
            iso = max(i_ref - mass - add, 0.0) if i == k or i == n else 0.0
            if nten is None:  # isotropic added mass
                iso += add
            else:
                ten_armature[nten + 2 * i:nten + 2 * i + 2] = add
            iso = max(iso, 1e-9 * i_ref)
            body_mass[self._bids[i]] = mass
            dof = self._dof0 + 3 * i
            armature[dof:dof + 3] = iso
            inertia[i] = mass + iso
        dt, zeta, EA = m.opt.timestep, self.spec.axial_damping_ratio, self.spec.EA
        for j in range(k, min(k + 2, n)):
            inv = 1.0 / float(inertia[j]) + 1.0 / float(inertia[j + 1])
            S, B, d = axial_scalar(EA, float(self._rest[j]), inv, dt, zeta)
            invweight[self.tadr + j] = inv
            e = self.eq0 + j
            eq_solref[e] = (-S, -B)
            eq_solimp[e, 0] = eq_solimp[e, 1] = d
            self._lead[j] = B / S
            self._K[j] = S / ((1.0 - d) * inv)
        m.eq_data[self.eq0 + k, 0] = (s + self._lead[k] * self.payout_rate - m.tendon_length0[self.tadr + k])

    def _set_rest(self, lo: int, hi: int) -> None:
        """The equality of element j holds its length at rest_j + lead_j * (payout rate if j is
        the drum element): MuJoCo damps the rate of the element's length, and the lead turns
        that into its strain rate for the drum element, whose rest length grows at the payout
        rate (B l' + S (l - rest - (B / S) rest') = B (l' - rest') + S (l - rest))."""
        js = np.arange(lo, hi)
        target = self._rest[js] + np.where(js == self.first, self._lead[js] * self.payout_rate, 0.0)
        self.model.eq_data[self.eq0 + js, 0] = target - self.model.tendon_length0[self.tadr + js]

    def update_slack(self, taut: bool = True) -> bool:
        """Switch elements between taut and slack after a step: an element whose equality pushed
        (compression) goes slack; a slack one longer than its rest
        length is taut again (with ``taut`` False, only elements shorter than their rest length go
        slack, and none is switched on: the last pass of a step redone). Returns whether a push or
        an overshoot was worth more than ``SLACK_FORCE`` of an element's weight in water and
        ``SLACK_TENSION`` of the highest tension
        (``Simulation`` then redoes the step with the new set, so that no element pushes and none
        overshoots its rest length for a step; smaller ones, a laid cable's noise, just switch). (MuJoCo's one-sided limit constraints chatter at the stiffness a long time
        step allows, so tension only is made this way, from two-sided equalities.)"""
        d, k = self.data, self.first
        if self._fast is not None:  # the same switching, compiled (compiled.slack_switch)
            rows = self._element_rows(d)
            return compiled.slack_switch(self._eq_view, d.efc_force[rows], self._length_view, self._rest,
                                         self._K, k, self._f_min, SLACK_TENSION, taut,
                                         rows.stop - rows.start >= self.n - k)[1]
        act = d.eq_active[self._eqs].copy()
        rows = self._element_rows(d)
        f = d.efc_force[rows]
        changed = redo = False
        # a push or overshoot is worth a redo above a tenth of an element's weight, or above
        # SLACK_TENSION of the highest tension in the cable now
        f_min = max(self._f_min, -SLACK_TENSION * f.min()) if len(f) else self._f_min
        if len(f) and f.max() > 0.0:  # efc_force > 0 pushes the nodes apart
            pushing = f > 0.0
            push = np.flatnonzero(act)[pushing]
            if not taut:  # the last time round: only elements shorter than their rest length
                keep = d.ten_length[self.tadr + push] < self._rest[push]
                push, pushing = push[keep], f[pushing][keep]
            else:
                pushing = f[pushing]
            if len(push):  # (shorter than its rest length or not: a cable's damping cannot push)
                act[push] = 0
                changed = True
                redo = pushing.max() > f_min
        if taut and rows.stop - rows.start < self.n - k:
            slack = np.flatnonzero(act[k:] == 0) + k
            over = d.ten_length[self.tadr + slack] - self._rest[slack]
            caught = over > 0.0
            if caught.any():
                act[slack[caught]] = 1
                changed = True
                redo = redo or float((over[caught] * self._K[slack[caught]]).max()) > f_min
        if changed:
            d.eq_active[self._eqs] = act
        return redo

    def _element_rows(self, data) -> slice:
        """Constraint rows of the active element equalities: one each, in element order, after
        the rows of the active equalities defined before them (MuJoCo orders equality rows by
        equality)."""
        if self._eq_snapshot is None:  # (efc_active)
            before, elements = data.eq_active[:self.eq0], data.eq_active[self._eqs]
        else:
            before, elements = self._snap_views
        r0 = int(self._rows_before @ before) if self.eq0 else 0
        return slice(r0, r0 + int(np.count_nonzero(elements)))

    def use_snapshot(self, snap: np.ndarray) -> None:
        """Read ``eq_active`` as it was at the last force computation from ``snap``, a copy
        that the simulation keeps up to date in place (see ``efc_active``)."""
        self._eq_snapshot = snap
        self._snap_views = (snap[:self.eq0], snap[self._eqs])

    def efc_active(self, data) -> np.ndarray:
        """``eq_active`` as it was when MuJoCo last computed the constraint forces (the slack
        switching changes it after a step, for the next one)."""
        snap = self._eq_snapshot
        return data.eq_active if snap is None else snap

    def payout_state(self) -> tuple[int, float]:
        """(first deployed node, drum element rest length in m): with MuJoCo's state (qpos,
        qvel, eq_active) this is everything needed to restore the payout exactly."""
        return self.first, self.drum_rest

    def restore_payout(self, state) -> None:
        """Restore a ``payout_state()`` (set MuJoCo's own state first, then call this)."""
        first, drum = state
        self.first, self.drum_rest = int(first), float(drum)
        self._relayout()

    def set_length(self, length: float, rate: float | None = None) -> None:
        """Change the deployed (unstretched) length to ``length`` (m) at the drum, as a winch does.

        The drum element (next to the fairlead) takes the change; past SPLIT x l0 it releases the
        next node from the drum (placed on the drum element's chord so that the split pieces keep
        their stretch, with the interpolated velocity); below MERGE x l0 its neighbour's node is
        taken back (moved to the fairlead, the drum element taking both pieces). Every other
        deployed element keeps the nominal length l0, and the mass of the deployed cable is
        mass per length x ``length``. Only the drum nodes' masses and the drum elements' solver
        parameters change at an ordinary step. ``rate`` is the payout rate (m/s; by default the
        change over one time step): the drum element's damping acts on its strain rate, its
        length's rate less this.
        """
        L = float(length)
        if not (np.isfinite(L) and L >= 0):
            raise ValueError(f"length must be a finite number >= 0 m, got {length!r}")
        if self.makeup is not None:
            if abs(L - self.makeup.length) > 1e-9 * self.makeup.length:
                raise ValueError(f"length: a line make-up's length is fixed at {self.makeup.length:g} m "
                                 "(payout of a make-up is not supported yet)")
            return
        n, l0 = self.n, self.l0
        k = self.first
        s = L - (n - k - 1) * l0
        if s == self.drum_rest:
            if self.payout_rate:
                self.payout_rate = 0.0
                self._set_rest(k, k + 1)
                self._sync_native()
            return  # (a fixed winch calls this every step)
        self.payout_rate = (L - self.deployed_length) / self.model.opt.timestep if rate is None else float(rate)
        if self.drum_eq is None:
            raise ValueError("set_length: this tether has a free start end and no drum")
        if L > self.max_length * (1 + 1e-9) + 1e-9:
            raise ValueError(f"length {L:g} m exceeds the tether's max_length {self.max_length:g} m "
                             "(give add_tether(max_length=...) the winch's max_length)")
        changed = False
        while s > SPLIT * l0 and k > 0:  # release node k-1 from the drum
            xf, vf = self._x(k, k + 1)[0], self._v(k, k + 1)[0].copy()
            xn, vn = self._x(k + 1, k + 2)[0], self._v(k + 1, k + 2)[0].copy()
            f = (s - l0) / s
            # the released node moves with the cable in the water (paid out at the drum's speed)
            self._place(k, xf + f * (xn - xf), vn)
            self._place(k - 1, xf, vf)
            k -= 1
            s -= l0
            changed = True
        while s < MERGE * l0 and k < n - 1:  # take node k+1 back onto the drum
            xf, vf = self._x(k, k + 1)[0], self._v(k, k + 1)[0].copy()
            self._place(k + 1, xf, vf)
            self._place(k, xf, np.zeros(3))
            k += 1
            s += l0
            changed = True
        self.first, self.drum_rest = k, max(s, 0.0)
        if changed:
            self._relayout()
        else:
            self._update_drum()
            self._sync_native()

    # ----------------------------------------------------------------- forces

    def _find_seabed(self, model: mujoco.MjModel, tm: TetherModel):
        """The seabed plane the tether rests on, for its friction (``mjtether.seabed``): (a point
        on it, its unit normal, the cable's submerged weight per metre there (N/m) times the
        cosine of its slope), or None for a tether without seabed contact. The stick points live
        in ``data.userdata``, NaN (off the seabed) at the start."""
        if not tm.seabed_friction or tm.userdata_adr < 0:  # (no friction: MuJoCo's contact is all)
            return None
        planes = np.flatnonzero((model.geom_type == int(mujoco.mjtGeom.mjGEOM_PLANE))
                                & (model.geom_conaffinity & TETHER_CONTACT_BIT != 0) & (model.geom_bodyid == 0)).tolist()
        if not planes:
            return None
        if len(planes) > 1:
            raise ValueError("a tether with seabed_friction rests on one seabed plane; the model has "
                             f"{len(planes)} (geoms {planes})")
        g = planes[0]
        R = np.zeros(9)
        mujoco.mju_quat2Mat(R, model.geom_quat[g])
        normal = R.reshape(3, 3)[:, 2].copy()
        point = model.geom_pos[g].copy()
        rho = float(self.water.rho([point[2]])[0])
        if self.makeup is not None:  # each node's wet weight: half its elements' and its point load's
            ww = self.makeup.element_wet_weight(rho, self.water.gravity) * self.makeup.element_length
            self._node_wet = (np.r_[0.0, ww] * 0.5 + np.r_[ww, 0.0] * 0.5 + self.makeup.node_wet_weight(
                rho, self.water.gravity)) * normal[2]
        w = self.spec.wet_weight_per_length(rho, self.water.gravity) * normal[2]
        self._stick = slice(tm.userdata_adr, tm.userdata_adr + 3 * (self.n + 1))
        self.data.userdata[self._stick] = np.nan
        return point, normal, w

    def _friction(self, data: mujoco.MjData, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Seabed friction on the deployed nodes (N), updating their stick points."""
        k = self.first
        stick = data.userdata[self._stick].reshape(-1, 3)
        f, stick[k:] = self._friction_kernel(x, v, stick[k:])
        stick[:k] = np.nan  # nodes on the drum
        return f

    def _friction_kernel(self, x, v, stick, preload=None):
        """``seabed.seabed_friction`` for the deployed nodes; with ``preload`` (N per node), the
        stick points are first placed so that the springs pull with it (up to mu N)."""
        point, normal, w = self._seabed
        k = self.first
        if self.makeup is not None:  # (a buoyant node does not press on the seabed)
            normal_force = np.maximum(self._node_wet[k:], 0.0)
        elif w <= 0.0:  # a buoyant cable does not press on the seabed
            return np.zeros_like(x), np.full_like(x, np.nan)
        else:  # each node's half of its elements
            half = (0.5 * w) * self._deployed_rest
            normal_force = np.empty(len(half) + 1)
            normal_force[:-1] = half
            normal_force[-1] = 0.0
            normal_force[1:] += half
        mass = self._inertia[k:]  # body mass + armature (added mass)
        dt = self.model.opt.timestep
        stiffness = (STICK_STIFFNESS / dt ** 2) * mass
        damping = (2.0 * STICK_DAMPING * math.sqrt(STICK_STIFFNESS) / dt) * mass  # 2 zeta sqrt(k m)
        if preload is not None:
            foot = x - ((x - point) @ normal)[:, None] * normal
            stick = foot + preload / stiffness[:, None]
        if self._fast is not None:
            m = len(x)
            force, new = self._fast["friction"][:m], self._fast["stick"][:m]
            compiled.seabed_friction(x, v, stick, point, normal, self.spec.diameter / 2, normal_force,
                                     float(self.tm.seabed_friction), stiffness, damping, CONTACT_TOLERANCE, force,
                                     new)
            return force, new
        return seabed_friction(x, v, stick, point=point, normal=normal, radius=self.spec.diameter / 2,
                               normal_force=normal_force, mu=self.tm.seabed_friction, stiffness=stiffness,
                               damping=damping)

    def loads(self, data: mujoco.MjData) -> np.ndarray:
        """Hydrodynamic (+ bending, + seabed friction) loads on the deployed nodes (N, shape
        (n-first+1, 3)); updates the seabed stick points."""
        return self._loads(data).copy()

    def _loads(self, data: mujoco.MjData) -> np.ndarray:
        """``loads``, in a buffer of the compiled kernels that the next call overwrites."""
        k = self.first
        x = data.flexvert_xpos[self.vertadr + k:self.vertadr + self.n + 1]
        v = data.qvel[self._dof0 + 3 * k:self._dof0 + 3 * (self.n + 1)].reshape(-1, 3)
        f = self._hydro(x, v)
        if self._seabed is not None:
            f += self._friction(data, x, v)
        return f

    def _hydro(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Hydrodynamic (+ bending) loads (N) on deployed nodes at ``x`` (m) moving at ``v`` (m/s)."""
        s = self.spec
        if self.payout_rate and self.drum_eq is not None:
            # the cable at the fairlead moves out of the drum at the payout rate, along the drum
            # element: its drag acts on that material velocity, not on the fairlead node's
            e = x[1] - x[0]
            v = v.copy()
            v[0] += self.payout_rate / max(math.sqrt(e @ e), 1e-9) * e
        if self._fast is not None:
            return self._compiled_hydro(x, v)
        mk = self.makeup
        if mk is not None:
            return self._makeup_hydro(x, v)
        f = tether_loads(x, v, segment_length=self._deployed_rest, diameter=s.diameter,
                         cd_normal=s.cd_normal, cd_tangential=s.cd_tangential,
                         rho_fn=self.water.rho, current_fn=self.water.velocity,
                         gravity=self.water.gravity,
                         first_share=self.fairlead_share / max(self.drum_rest, 1e-300))
        if s.EI > 0:
            f += bending_forces(x, s.EI, self.l0)
        return f

    def _compiled_hydro(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """``_hydro`` (and ``_makeup_hydro``) with the compiled kernels: the same loads, into a
        buffer that the next call overwrites."""
        c, k, m = self._fast, self.first, len(x) - 1
        rho, u, f = c["rho"][:m], c["u"][:m], c["f"][:m + 1]
        if c["water"] is None:  # a profile the compiled kernels do not know: its own NumPy code
            zc = np.minimum(0.5 * (x[1:, 2] + x[:-1, 2]), 0.0)
            rho[:] = self.water.rho(zc)
            u[:] = self.water.velocity(zc)
        else:
            compiled.element_water(x, *c["water"], rho, u)
        mk = self.makeup
        share = 0.5 if mk is not None else self.fairlead_share / max(self.drum_rest, 1e-300)
        compiled.tether_loads(x, v, self._deployed_rest, c["diameter"][k:], c["cd_normal"][k:],
                              c["cd_tangential"][k:], c["area"][k:], c["cd_area_float"][k:], rho, u,
                              self.water.gravity, share, f)
        if c["bend"] is not None:
            compiled.add_bending_forces(x, c["bend"][k:], f)
        if mk is not None and mk.has_point_loads:
            self._point_loads(x, v, f)
        return f

    def _point_loads(self, x: np.ndarray, v: np.ndarray, f: np.ndarray) -> None:
        """Add each point load's buoyancy (under water) and drag 1/2 rho CdA |u - v| (u - v) at its
        node (its weight is in the node's mass) to ``f`` (N)."""
        mk = self.makeup
        z = np.minimum(x[:, 2], 0.0)
        wet = x[:, 2] <= 0.0
        rho = np.asarray(self.water.rho(z), float)
        f[:, 2] += rho * mk.node_volume * self.water.gravity * wet
        cda = mk.node_cd_area
        if np.any(cda > 0):
            u = self.water.velocity(z) - v
            f += (0.5 * rho * cda * wet * np.sqrt(np.einsum("ij,ij->i", u, u)))[:, None] * u

    def _makeup_hydro(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """``_hydro`` of a line make-up: each element with its own diameter, coefficients and
        floats; each point load's buoyancy (under water) and drag 1/2 rho CdA |u - v| (u - v) at
        its node (its weight is in the node's mass); bending with each joint's mean EI."""
        mk = self.makeup
        float_cda = mk.element_float_cd_area
        f = tether_loads(x, v, segment_length=self._deployed_rest, diameter=mk.element_diameter,
                         cd_normal=mk.element_cd_normal, cd_tangential=mk.element_cd_tangential,
                         rho_fn=self.water.rho, current_fn=self.water.velocity, gravity=self.water.gravity,
                         area=mk.element_area, float_cd_area=float_cda if np.any(float_cda > 0) else None)
        if mk.has_point_loads:
            self._point_loads(x, v, f)
        EI = mk.element_EI
        if np.any(EI > 0):
            rest = self._deployed_rest
            f += bending_forces(x, 0.5 * (EI[1:] + EI[:-1]), 0.5 * (rest[1:] + rest[:-1]))
        return f

    def preload_friction(self, data: mujoco.MjData, tension) -> None:
        """Start the seabed friction from a steady state: set the stick points of the laid nodes
        so that friction holds them as they are, with element ``tension`` (N, the deployed
        elements', e.g. ``SteadyState.tension``), current and weight (each node's share up to
        mu N). Without it a laid line starts with no friction mobilised, as a cable just laid
        and never pulled; a steady state with friction (MoorPy's, ``steady_state``) assumes it
        fully mobilised, as after the pull that brought the line there. Uses the positions and
        velocities in ``data`` (qpos, qvel)."""
        if self._seabed is None:
            return
        k, n, m = self.first, self.n, self.model
        T = np.asarray(tension, dtype=float)
        if T.shape != (n - k,) or not np.all(np.isfinite(T)):
            raise ValueError(f"tension must be {n - k} finite element tensions (N), got shape {T.shape}")
        x = self._x(k)
        v = self._v(k)
        e = x[1:] - x[:-1]
        t = e / np.maximum(np.linalg.norm(e, axis=1), 1e-12)[:, None]
        total = self._hydro(x, v)
        total[:-1] += T[:, None] * t
        total[1:] -= T[:, None] * t
        total += m.body_mass[self._bids[k:], None] * m.opt.gravity
        point, normal, _ = self._seabed
        need = -(total - (total @ normal)[:, None] * normal)  # what friction must hold, in the seabed's plane
        need[[0, -1]] = 0.0  # the ends are held by their supports
        stick = data.userdata[self._stick].reshape(-1, 3)
        stick[:] = np.nan
        f, stick[k:] = self._friction_kernel(x, v, stick[k:], preload=need)

    def apply(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        f = self._loads(data)
        data.qfrc_passive[self._dof0 + 3 * self.first:self._dof0 + 3 * (self.n + 1)] += f.ravel()
        if self._normal_prm is not None:
            self._orient_added_mass(data.flexvert_xpos[self.vertadr + self.first:self.vertadr + self.n + 1])

    def _orient_added_mass(self, x: np.ndarray) -> None:
        """Turn the deployed nodes' normal added-mass tendons normal to the cable at ``x`` (the
        deployed nodes, m): at each node two unit vectors normal to its tangent (the mean of its
        elements' directions). MuJoCo uses them from the next mass matrix on."""
        if self._normal_prm is None or len(x) < 2:
            return
        e = x[1:] - x[:-1]
        e /= np.maximum(np.sqrt(np.einsum("ij,ij->i", e, e)), 1e-300)[:, None]
        t = np.empty_like(x)
        t[0], t[-1] = e[0], e[-1]
        np.add(e[:-1], e[1:], out=t[1:-1])
        norm = np.sqrt(np.einsum("ij,ij->i", t, t))
        # a node without a direction (an element of zero length, a cable folded back on itself)
        # keeps its last one
        ok = norm > 1e-6
        t = t[ok] / norm[ok, None]
        # first normal: horizontal (z x t), or along x x t where the cable is near vertical
        a = np.where((np.abs(t[:, 2]) < 0.9)[:, None], _EZ, _EX)
        n1 = np.cross(a, t)
        n1 /= np.sqrt(np.einsum("ij,ij->i", n1, n1))[:, None]
        prm = self._normal_prm[self.first:]
        if ok.all():
            prm[:, 0] = n1
            prm[:, 1] = np.cross(t, n1)
        else:
            prm[ok, 0] = n1
            prm[ok, 1] = np.cross(t, n1)

    def set_state(self, data: mujoco.MjData, nodes=None, velocity=None) -> None:
        """Set the deployed nodes' positions (m) and/or velocities (m/s), world frame, shape
        (deployed elements + 1, 3), e.g. from a ``quasistatic.steady_state``; call
        ``Simulation.forward()`` afterwards."""
        k, n = self.first, self.n
        for label, arr in (("nodes", nodes), ("velocity", velocity)):
            if arr is None:
                continue
            a = np.asarray(arr, dtype=float)
            if a.shape != (n - k + 1, 3) or not np.all(np.isfinite(a)):
                raise ValueError(f"{label} must be a finite array of shape ({n - k + 1}, 3)")
            if label == "nodes":
                data.qpos[self._q0 + 3 * k:self._q0 + 3 * (n + 1)] = a.ravel() - self._body0[3 * k:]
            else:
                data.qvel[self._dof0 + 3 * k:self._dof0 + 3 * (n + 1)] = a.ravel()

    # ----------------------------------------------------------------- readouts

    @property
    def N(self) -> int:
        """Number of deployed elements (the drum element included)."""
        return self.n - self.first

    @property
    def segment_length(self) -> float:
        """Nominal element length l0 = initial length / segments (m)."""
        return self.l0

    @property
    def effective_EA(self) -> np.ndarray:
        """Axial stiffness (N) each deployed element has in statics: EA, or less where the time
        step cannot resolve it (see ``builder``; always so for an inextensible tether)."""
        k = self.first
        return self._K[k:] * self._rest[k:]

    def drum_element(self) -> tuple[float, float]:
        """The element at the drum: (its axial stiffness in the dynamics, N/m: EA / rest length,
        or less where the time step cannot resolve it; the rate its stretched length grows at,
        m/s, from its nodes' velocities). A free drum pays out against them (``winch``)."""
        k = self.first
        x, v = self._x(k, k + 2), self._v(k, k + 2)
        e = x[1] - x[0]
        L = math.sqrt(float(e @ e))
        return float(self._K[k]), (float((v[1] - v[0]) @ e) / L if L > 0.0 else 0.0)

    @property
    def deployed_length(self) -> float:
        """Unstretched deployed length (m)."""
        if self.makeup is not None:
            return float(self.makeup.length)
        return self.drum_rest + (self.n - self.first - 1) * self.l0

    def nodes(self, data: mujoco.MjData) -> np.ndarray:
        """Deployed node positions (m, world frame), shape (N+1, 3), the first at the ship."""
        return data.flexvert_xpos[self.vertadr + self.first:self.vertadr + self.n + 1].copy()

    def all_nodes(self, data: mujoco.MjData) -> np.ndarray:
        """Every node (m, world), shape (n+1, 3), numbered from the drum's core; nodes on the
        drum are given at the fairlead."""
        x = data.flexvert_xpos[self.vertadr:self.vertadr + self.n + 1].copy()
        x[:self.first] = x[self.first]
        return x

    def _rows(self, data: mujoco.MjData, eq_id: int) -> slice:
        """The constraint rows of equality ``eq_id``: a contiguous block that MuJoCo places
        among the equality rows at the top of efc_*; cached, and checked at its ends."""
        r = self._row_cache.get(eq_id)
        t, i, n = data.efc_type, data.efc_id, data.nefc
        if self._fast is not None:  # the same check and search, compiled (compiled.equality_rows)
            start, stop = compiled.equality_rows(t, i, n, eq_id, -1 if r is None else r.start,
                                                 -1 if r is None else r.stop, _EQUALITY)
            if r is None or (start, stop) != (r.start, r.stop):
                r = self._row_cache[eq_id] = slice(start, stop)
            return r
        if r is None or not (r.stop <= n and t[r.start] == _EQUALITY and i[r.start] == eq_id
                             and t[r.stop - 1] == _EQUALITY and i[r.stop - 1] == eq_id
                             and (r.start == 0 or t[r.start - 1] != _EQUALITY or i[r.start - 1] != eq_id)
                             and (r.stop == n or t[r.stop] != _EQUALITY or i[r.stop] != eq_id)):
            rows = np.nonzero((t[:n] == _EQUALITY) & (i[:n] == eq_id))[0]
            r = slice(int(rows[0]), int(rows[-1]) + 1) if len(rows) else slice(0, 0)
            self._row_cache[eq_id] = r
        return r

    def element_tension(self, data: mujoco.MjData) -> np.ndarray:
        """Axial tension of every element (N), shape (n,): never negative (elements carry
        tension only); 0 for slack elements and those on the drum."""
        rows = self._element_rows(data)
        out = np.zeros(self.n)
        if rows.stop > data.nefc:
            raise RuntimeError("tether tension is available after mj_forward/mj_step")
        out[np.flatnonzero(self.efc_active(data)[self._eqs])] = np.maximum(-data.efc_force[rows], 0.0)
        out[:self.first] = 0.0
        return out

    def tension(self, data: mujoco.MjData) -> np.ndarray:
        """Axial tension of the deployed elements (N), shape (N,), the first at the ship."""
        return self.element_tension(data)[self.first:]

    def element_length(self, data: mujoco.MjData) -> np.ndarray:
        """Stretched length of every element (m), shape (n,); 0 for elements on the drum."""
        out = data.ten_length[self._ten].copy()
        out[:self.first] = 0.0
        return out

    def slack_count(self, data: mujoco.MjData) -> int:
        """Deployed elements carrying no tension."""
        return int(np.count_nonzero(self.tension(data) <= 0.0))

    def stretched_length(self, data: mujoco.MjData) -> float:
        """Sum of the deployed elements' lengths (m)."""
        return float(element_geometry(self.nodes(data))[1].sum())

    def end_force(self, data: mujoco.MjData, which: str = "start") -> np.ndarray:
        """Force of the tether on its ``"start"`` (ship) or ``"end"`` (robot) support (N, world):
        the force of the ``connect`` constraint that holds the end node to the support."""
        if which not in ("start", "end"):
            raise ValueError(f"which must be 'start' or 'end', got {which!r}")
        eq = self.end_eq if which == "end" else (None if self.drum_eq is None else self.drum_eq[self.first])
        if eq is None:  # a free end
            return np.zeros(3)
        return data.efc_force[self._rows(data, int(eq))].copy()

    def end_tension(self, data: mujoco.MjData, which: str = "start") -> float:
        """Magnitude of ``end_force`` (N)."""
        f = self.end_force(data, which)
        return math.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) if len(f) == 3 else 0.0


class Simulation:
    """Compile ``spec`` and simulate it with tether and body hydrodynamics in ``water``.

    >>> # sim = Simulation(spec, water, tethers=[tm]); sim.step(1000); sim.close()
    """

    def __init__(self, spec: mujoco.MjSpec, water: WaterColumn, tethers=(), bodies=()):
        if not isinstance(water, WaterColumn):
            raise ValueError(f"water must be a WaterColumn, got {type(water).__name__}")
        self.water = water
        self.model = dispatch.compile_spec(spec)
        # buoyancy uses water.gravity, weight MuJoCo's option.gravity: they must be the same
        g_model = np.array(self.model.opt.gravity, dtype=float)
        disabled = bool(self.model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY)
        g_eff = np.zeros(3) if disabled else g_model
        if np.linalg.norm(g_eff - (0.0, 0.0, -water.gravity)) > 1e-9 * max(water.gravity, np.linalg.norm(g_eff)):
            shown = ", ".join(f"{c:.12g}" for c in g_model)
            raise ValueError(
                f"WaterColumn.gravity = {water.gravity:.12g} m/s^2 differs from the model's option.gravity "
                f"({shown}){' (disabled by option.disableflags: 0 in effect)' if disabled else ''}: buoyancy "
                "and weight would not balance; set one to the other")
        self.data = mujoco.MjData(self.model)
        self.tethers = {}
        for tm in tethers:
            if not isinstance(tm, TetherModel):
                raise ValueError("tethers must be TetherModel objects returned by add_tether")
            self.tethers[tm.name] = BoundTether(tm, self.model, self.data, water)
        self.bodies = []
        for bm in bodies:
            if isinstance(bm, VehicleModel):
                self.bodies.append(BoundVehicle(bm, self.model, water))
            elif isinstance(bm, BodyHydroModel):
                self.bodies.append(BoundBodyHydro(bm, self.model, water))
            else:
                raise ValueError("bodies must be BodyHydroModel or VehicleModel objects returned by add_body_hydro "
                                 "or add_vehicle")
        self._providers = [*self.tethers.values(), *self.bodies]
        self._buf = np.empty(mujoco.mj_stateSize(self.model, _STATE))
        self._eq_snapshot = self.data.eq_active.copy()
        for t in self.tethers.values():
            t.use_snapshot(self._eq_snapshot)
        # views of mjData's arrays that the per-step code reads (they never move)
        self._eq_active, self._qpos, self._qvel = self.data.eq_active, self.data.qpos, self.data.qvel
        self._tether_list = tuple(self.tethers.values())
        self._closed = False
        self._warnings = self.data.warning.number  # MuJoCo's warning counts (a live view)
        self._bad_acc0 = 0
        self._t_step = 0.0  # s, the time at the end of the step being taken
        self.revision = 0  # counts steps, forward() and restore_state(): what was read at one revision holds
        self._worst = []  # what was furthest out after the last step (see check)
        with dispatch.suspended():  # (the first call reads MuJoCo's structs from two small models)
            ok = native.available()
        tables = [p.native_table() for p in self._providers] if ok else [None]
        block = None
        if all(t is not None for t in tables):
            kinds = [native.TETHER] * len(self.tethers) + [native.VEHICLE if isinstance(b, BoundVehicle) else native.BODY
                                                           for b in self.bodies]
            writes = any(t._normal_prm is not None for t in self.tethers.values()) or \
                any(isinstance(b, BoundVehicle) for b in self.bodies)
            block = native.Block(list(zip(kinds, tables)), writes_model=writes)
        self.native = block is not None  # MuJoCo applies the loads itself, on any thread (``native``)
        dispatch.register(self.data, self._passive, self.model, block=block)
        try:
            mujoco.mj_forward(self.model, self.data)
            dispatch.raise_pending(self.data)
        except BaseException:  # a provider failed on the first state: leave nothing registered
            self.close()
            raise

    def _passive(self, m, d):
        for p in self._providers:
            p.apply(m, d)

    @property
    def time(self) -> float:
        return float(self.data.time)

    @property
    def timestep(self) -> float:
        return float(self.model.opt.timestep)

    def tether(self, name: str = "tether") -> BoundTether:
        return self.tethers[name]

    def forward(self) -> None:
        """Recompute forces and readouts for the current state without stepping."""
        self.revision += 1
        mujoco.mj_forward(self.model, self.data)
        self._eq_snapshot[:] = self.data.eq_active
        dispatch.raise_pending(self.data)

    def step(self, nstep: int = 1) -> None:
        """Advance ``nstep`` steps; raise ``SimulationDiverged`` if the state blows up, naming
        the time and what went first (see ``check``)."""
        if self._closed:
            raise RuntimeError("simulation is closed")
        saved = self.save_state() if nstep > 1 else None
        self._advance(nstep)
        dispatch.raise_pending(self.data)
        try:
            self.check()
        except SimulationDiverged:
            if saved is None:
                raise
            # find the step where it went, one step at a time from the saved state
            self.restore_state(saved)
            for _ in range(nstep):
                self._advance(1)
                dispatch.raise_pending(self.data)
                self.check()
            raise

    def _advance(self, nstep: int) -> None:
        """``nstep`` MuJoCo steps, switching slack tether elements after each."""
        self.revision += 1
        if not self.tethers:
            self._t_step = self.data.time + self.model.opt.timestep
            mujoco.mj_step(self.model, self.data, nstep)
            return
        tethers = self._tether_list
        m, d, buf, spec = self.model, self.data, self._buf, _STATE
        snap, eq_active = self._eq_snapshot, self._eq_active
        dt = m.opt.timestep
        for _ in range(nstep):
            self._t_step = d.time + dt
            mujoco.mj_getState(m, d, buf, spec)
            mujoco.mj_step(m, d)
            snap[:] = eq_active
            changed = False
            for t in tethers:
                changed |= t.update_slack()
            redo = 0
            while changed:  # redo the step with the elements taut now (see update_slack)
                redo += 1
                active = d.eq_active.copy()
                mujoco.mj_setState(m, d, buf, spec)
                d.eq_active[:] = active
                mujoco.mj_step(m, d)
                snap[:] = d.eq_active
                if redo > SLACK_REDOS:
                    break
                changed = False
                for t in tethers:  # the last time round, only switch off elements that pushed
                    changed |= t.update_slack(taut=redo < SLACK_REDOS)

    def save_state(self):
        """Everything needed to continue exactly from here (MuJoCo's integration state and the
        payout state of every tether); see ``restore_state``."""
        spec = mujoco.mjtState.mjSTATE_INTEGRATION
        buf = np.empty(mujoco.mj_stateSize(self.model, spec))
        mujoco.mj_getState(self.model, self.data, buf, spec)
        return buf, {k: t.payout_state() for k, t in self.tethers.items()}

    def restore_state(self, state) -> None:
        """Return to a ``save_state()``; readouts are valid after ``forward()`` or a step."""
        buf, payout = state
        self.revision += 1
        mujoco.mj_setState(self.model, self.data, buf, mujoco.mjtState.mjSTATE_INTEGRATION)
        for k, t in self.tethers.items():
            t.restore_payout(payout[k])
        w = self.data.warning  # (MuJoCo's warning counts are not part of its state)
        self._bad_acc0 = w[_BADQPOS].number + w[_BADQVEL].number + w[_BADQACC].number

    def run(self, duration: float, callback=None, every: float | None = None) -> None:
        """Simulate ``duration`` seconds; call ``callback(sim)`` every ``every`` seconds."""
        dt = self.timestep
        n = int(round(duration / dt))
        k = max(1, int(round((every or duration) / dt))) if callback else n
        done = 0
        while done < n:
            m = min(k, n - done)
            self.step(m)
            done += m
            if callback:
                callback(self)

    def check(self) -> None:
        """Raise ``SimulationDiverged`` if the state has gone bad: MuJoCo's own check (a
        position, velocity or acceleration non-finite or above 1e10, after which it resets the
        state), a tether node faster than ``MAX_NODE_SPEED`` or an element stretched by more
        than ``MAX_STRAIN``. The message names the time, the tether element or MuJoCo degree of
        freedom, and the quantity."""
        d = self.data
        count = self._warnings  # (a view of the counts: cheaper than the list's items)
        bad = int(count[_BADQPOS]) + int(count[_BADQVEL]) + int(count[_BADQACC])
        if bad > self._bad_acc0 or not math.isfinite(self._qvel[0] + self._qpos[0]):
            w = d.warning
            self._bad_acc0 = bad
            what = []
            for code, q in ((_BADQPOS, "position"), (_BADQVEL, "velocity"), (_BADQACC, "acceleration")):
                if w[code].number:
                    what.append(f"{q} of {self._dof_name(int(w[code].lastinfo))}")
            # MuJoCo has reset the state (time too): report the step it went in, and what was
            # already furthest out in the last good state
            self._diverged(self._t_step, "MuJoCo found a non-finite or huge " + " and ".join(what)
                           + (f"; a step earlier {self._furthest()}" if self._worst else ""))
        worst = []
        qvel, ten_length = self._qvel, d.ten_length
        for name, t in self.tethers.items():
            k = t.first
            v = qvel[t._dof0 + 3 * k:t._dof0 + 3 * (t.n + 1)]
            if t._fast is not None:  # (compiled.tether_extremes: the same search)
                i, vmax, j, stretch = compiled.tether_extremes(v, ten_length[t.tadr + k:t.tadr + t.n], t._deployed_rest)
            else:
                i = int(np.argmax(np.abs(v)))
                vmax = abs(float(v[i]))
            if not vmax <= MAX_NODE_SPEED:  # (NaN too)
                self._diverged(d.time, f"{name} node {i // 3} (of {t.N + 1} deployed, 0 at the ship) moves at "
                                       f"{vmax:.3g} m/s")
            if t.spec.EA is not None:
                # stretch over the nominal element length (the drum element may be short)
                if t._fast is None:
                    s = ten_length[t.tadr + k:t.tadr + t.n] - t._deployed_rest
                    j = int(np.argmax(s))
                    stretch = float(s[j])
                strain = stretch / t.l0
                if strain > MAX_STRAIN:
                    self._diverged(d.time, f"{name} element {j} (0 at the ship) is stretched by "
                                           f"{100 * strain:.0f} % (EA {t.spec.EA:g} N)")
                worst.append((name, i // 3, vmax, j, strain))
            else:
                worst.append((name, i // 3, vmax, None, None))
        self._worst = worst  # formatted only if the next step fails (see _furthest)

    def _furthest(self) -> str:
        """What was furthest out after the last good step: each tether's fastest node and most
        stretched element."""
        out = []
        for name, i, vmax, j, strain in self._worst:
            out.append(f"{name} node {i} (0 at the ship) moved fastest, at {vmax:.3g} m/s")
            if j is not None:
                out.append(f"element {j} was the most stretched, by {100 * strain:.2g} %")
        return ", ".join(out)

    def _dof_name(self, dof: int) -> str:
        m = self.model
        if not 0 <= dof < m.nv:
            return "the state"
        body = int(m.dof_bodyid[dof])
        for name, t in self.tethers.items():
            hits = np.nonzero(t._bids == body)[0]
            if len(hits):
                return f"{name} node {int(hits[0]) - t.first} (0 at the ship)"
        return f"body {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, body) or body}"

    def _diverged(self, t: float, what: str) -> None:
        raise SimulationDiverged(
            f"simulation diverged at t = {t:.4f} s (time step {self.timestep:g} s): {what}; "
            "reduce the time step (see mjtether.stability.max_timestep)")

    def close(self) -> None:
        """Remove this simulation's force providers from the passive callback."""
        if not self._closed:
            dispatch.unregister(self.data)
            self._closed = True

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass

"""The drum of a bound tether: payout, the release and take-back of nodes, and the masses and
axial element parameters that follow from the deployed length.

A compiled model cannot grow, so every node the winch can pay out is in it from the start. The
nodes still on the drum are parked at the fairlead (gravity-compensated, no equality); only
nodes ``first`` .. n are deployed, ``first`` at the fairlead. The drum element (``first``, next
to the fairlead) takes every change of length: past SPLIT x l0 it releases the next node from
the drum, below MERGE x l0 it takes one back. Units SI, world frame.
"""

from __future__ import annotations

import math

import numpy as np

from mjtether.physics.water import WaterColumn

from . import kernels
from .builder import AXIAL_OMEGA_DT, MAX_IMP, MIN_IMP, FixedPoint, axial_params, axial_scalar
from .layout import CableLayout
from .loads import orient_added_mass

FAIRLEAD_SHARE = 0.05
"""The least part of the drum element, in units of l0, lumped on the fairlead node: its share
while a node is released or taken back (``fairlead_share``)."""
START_SLACK = 0.01
MAX_SET_STRAIN = 0.1
"""``set_length`` refuses a tether between two fixed points shorter than their distance over
1 + this (elastic) or than their distance (inextensible): it could only reach them torn."""
"""An element shorter than its rest length by more than this fraction starts slack."""
SPLIT, MERGE = 1.2, 0.1
"""The drum element (next to the fairlead) releases a node from the drum when its rest length
passes SPLIT x the nominal element length l0, and takes one back below MERGE x l0. The node that
moves is then only (SPLIT - 1) or MERGE x l0 from the fairlead: the chord it is placed on is
that short, so it starts close to where the sagging cable would have it (a node placed at a
third of a 1.5 l0 drum element rang the ship tension by +-5 %), and the band between them keeps
a winch that dithers from releasing and taking back the same node."""


def fairlead_share(drum_rest: float, l0: float) -> float:
    """Length (m) of the drum element (rest length ``drum_rest``, m) whose mass and loads the
    fairlead node carries, for elements of nominal length ``l0`` (m).

    Half of it when the drum element is a whole element (drum_rest = l0: a line that has not paid
    out, lumped half and half at its ends as at every other element, so the top converges with N
    like the rest of the line). Across a release (drum_rest SPLIT l0 -> (SPLIT - 1) l0) and a
    take-back (MERGE l0 -> (1 + MERGE) l0) the share must not jump, or the free cable's mass and
    loads would: so it is a function of drum_rest / l0 modulo 1, FAIRLEAD_SHARE l0 through the
    band where nodes move (phase MERGE .. SPLIT - 1), rising linearly to l0 / 2 at phase 1 and
    falling linearly back over phase 0 .. MERGE; never more than half the drum element."""
    phase = (drum_rest / l0) % 1.0
    lo, hi = MERGE, SPLIT - 1.0
    if phase <= lo:
        g = 0.5 - (0.5 - FAIRLEAD_SHARE) * phase / lo
    elif phase <= hi:
        g = FAIRLEAD_SHARE
    else:
        g = FAIRLEAD_SHARE + (0.5 - FAIRLEAD_SHARE) * (phase - hi) / (1.0 - hi)
    return min(g * l0, 0.5 * drum_rest)


class Drum:
    """Payout state of a bound tether and the model parameters it sets.

    State: ``first`` (the deployed node at the fairlead), ``drum_rest`` (the drum element's rest
    length, m), ``payout_rate`` (m/s, of the last ``set_length``). Per node: ``inertia`` (body
    mass plus armature along the cable, kg); per element: ``rest`` (rest length, m; 0 on the
    drum), ``K`` (static axial stiffness, N/m), ``lead`` (s, see ``set_rest``), and ``axial`` (the
    last ``builder.axial_params``). ``native_state`` is the payout as the native callback reads it.
    """

    def __init__(self, layout: CableLayout, water: WaterColumn):
        L = self.layout = layout
        s, n = L.spec, L.n
        self.water = water
        self.first = L.tm.first
        self.drum_rest = L.l0
        self.payout_rate = 0.0  # m/s, of the last set_length
        m = L.model
        self._model_arrays = (m.body_mass, m.dof_armature, m.tendon_invweight0, m.tendon_armature,
                              m.eq_solref, m.eq_solimp, m.eq_data, m.tendon_length0)
        mk = L.line
        self.drum_rest = float(L.nominal[self.first])
        self.EA = L.element(mk.element_EA)  # N, per element (inf: inextensible)
        if L.pays_out:  # one mass per length (kg/m) and added mass per metre (kg/m per kg/m^3)
            self.mu = s.mu
            self.ca_A = s.ca_normal * s.area
        else:  # per element (floats in); (the same numbers in another order for a uniform line: see
            # update, whose lumping follows)
            self.mu = mk.element_mass_per_length
            self.ca_A = mk.element_ca_normal * np.pi * mk.element_diameter**2 / 4 + mk.element_float_added_volume
        # updated in place, as the native callback reads them (loads.native_table)
        self.rest, self.inertia = np.zeros(n), np.zeros(n + 1)
        self.native_state = np.zeros(3)  # first, its share of the drum element, payout rate

    # ----------------------------------------------------------------- lengths

    @property
    def fairlead_share(self) -> float:
        """Length (m) of the drum element whose mass and loads the fairlead node carries
        (``fairlead_share``: half of it unless the drum is releasing or taking back a node)."""
        L = self.layout
        if L.drum_eq is None:
            return 0.5 * self.drum_rest  # a free start end: an ordinary element
        # (a line that does not pay out has its drum element at its nominal length: half of it)
        return fairlead_share(self.drum_rest, float(L.nominal[self.first]))

    @property
    def rest_lengths(self) -> np.ndarray:
        """Unstretched length of every element (m), shape (n,); 0 for elements on the drum."""
        r = self.layout.nominal.copy()
        r[:self.first] = 0.0
        r[self.first] = self.drum_rest
        return r

    @property
    def deployed_length(self) -> float:
        """Unstretched deployed length (m)."""
        L = self.layout
        if not L.pays_out:  # (its length is fixed: the sections' exact sum)
            return float(L.line.length)
        return self.drum_rest + (L.n - self.first - 1) * L.l0

    @property
    def effective_EA(self) -> np.ndarray:
        """Axial stiffness (N) each deployed element has in statics: EA, or less where the time
        step cannot resolve it (see ``builder``; always so for an inextensible tether)."""
        k = self.first
        return self.K[k:] * self.rest[k:]

    def drum_element(self) -> tuple[float, float]:
        """The element at the drum: (its axial stiffness in the dynamics, N/m: EA / rest length,
        or less where the time step cannot resolve it; the rate its stretched length grows at,
        m/s, from its nodes' velocities). A free drum pays out against them (``winch``)."""
        k = self.first
        x, v = self.layout.x(k, k + 2), self.layout.v(k, k + 2)
        e = x[1] - x[0]
        length = math.sqrt(float(e @ e))
        return float(self.K[k]), (float((v[1] - v[0]) @ e) / length if length > 0.0 else 0.0)

    # ----------------------------------------------------------------- model parameters

    def relayout(self) -> None:
        """Masses, armature, element limits and tuning, equalities and gravity compensation for
        the current ``first`` and ``drum_rest`` (every node and element)."""
        L = self.layout
        m, d, k, n = L.model, L.data, self.first, L.n
        m.body_gravcomp[L.bids] = (np.arange(n + 1) < k).astype(float)
        if L.drum_eq is not None:
            d.eq_active[L.drum_eq] = 0
            d.eq_active[L.drum_eq[k]] = 1
        x = L.x()
        z = x[:, 2]
        zc = np.minimum(0.5 * (z[1:] + z[:-1]), 0.0)
        self.added_per_m = self.ca_A * np.asarray(self.water.rho(zc), float)  # kg/m, per element
        # the point loads' added mass, at the start's depths
        self.node_added = L.node(L.line.node_added_volume) * np.asarray(self.water.rho(np.minimum(z, 0.0)), float)
        self.update()
        orient_added_mass(L.normal_prm, k, x[k:])
        # elements about as long as their rest length or longer start taut, clearly slack ones
        # slack (an element started taut that pushes is switched off at the first step)
        length = np.linalg.norm(np.diff(x, axis=0), axis=1)
        d.eq_active[L.eqs] = (np.arange(n) >= k) & (length >= self.rest * (1 - START_SLACK))

    def update(self) -> None:
        """Masses, armature and element solver parameters of every node and element for the
        current rest lengths (``update_drum`` does an ordinary payout step's share of this)."""
        L = self.layout
        m, k, n, l0 = L.model, self.first, L.n, L.l0
        rest = self.rest_lengths
        idx = np.arange(n + 1)
        r_left = np.r_[0.0, rest]  # the element on each side of each node (0 past the ends)
        r_right = np.r_[rest, 0.0]
        ap = self.added_per_m
        a_left = np.r_[0.0, ap]
        a_right = np.r_[ap, 0.0]
        # the drum element's part at the fairlead (``fairlead_share``): half of a whole element,
        # FAIRLEAD_SHARE l0 around a release or take-back, so that nothing jumps then
        c = self.fairlead_share
        left = np.where(idx == k + 1, 1.0 - c / max(rest[k], 1e-300), 0.5)
        right = np.where(idx == k, c / max(rest[k], 1e-300), 0.5)
        added = left * a_left * r_left + right * a_right * r_right
        parked = idx < k
        end = (idx == k) | (idx == n)  # at a support: inertia up to an interior node's
        # the point loads' masses and (isotropic) added masses: none on a uniform tether
        iso = self.node_added.copy()
        if L.pays_out:  # one mass per length: as update_drum lumps it, step by step
            mass = self.mu * (left * r_left + right * r_right)
            i_ref = self.i_ref = (self.mu + np.median(ap)) * l0  # an interior node's (normal) inertia
            mass = np.where(parked, self.mu * l0, mass)
        else:  # per-element mass per length
            mu = self.mu
            mass = left * np.r_[0.0, mu] * r_left + right * np.r_[mu, 0.0] * r_right + L.line.node_mass
            i_ref = self.i_ref = float(np.median(mass + added + iso))
        # the line's added mass acts normal to it (the normal tendons); the isotropic armature
        # holds the point loads' added mass, a parked node's inertia and a support's conditioning
        normal = np.where(parked, 0.0, added)
        iso = np.where(parked, i_ref - mass, iso)
        iso = np.where(end & ~parked, np.maximum(i_ref - mass - normal, iso), iso)
        if L.normal_ten is None:  # isotropic added mass: all of it on the slide joints
            iso = iso + normal
        iso = np.maximum(iso, 1e-9 * i_ref)
        m.body_mass[L.bids] = mass
        m.dof_armature[L.dof0:L.dof0 + 3 * (n + 1)] = np.repeat(iso, 3)
        if L.normal_ten is not None:
            m.tendon_armature[L.normal_ten] = np.repeat(normal, 2)
        self.inertia[:] = mass + iso  # along the cable (what its axial mode moves)
        # elements: inverse mass along the element, solver parameters, rest lengths
        js = np.arange(n)
        inv = 1.0 / self.inertia[:-1] + 1.0 / self.inertia[1:]
        p = axial_params(self.EA, np.where(js >= k, rest, l0), inv,
                         m.opt.timestep, L.spec.axial_damping_ratio)
        m.tendon_invweight0[L.ten] = inv
        m.eq_solref[L.eqs] = p.solref
        m.eq_solimp[L.eqs] = p.solimp
        self.lead = p.B / p.S  # s: see set_rest
        self.K = np.array(p.stiffness, dtype=float)  # N/m, static stiffness of each element
        self.rest[:] = rest
        self.deployed_rest = self.rest[k:]
        self.set_rest(0, n)
        self.axial = p
        self.sync_native()

    def sync_native(self) -> None:
        """The payout state as the native callback reads it (``loads.native_table``'s state row)."""
        st = self.native_state
        st[0] = self.first
        st[1] = self.fairlead_share / max(self.drum_rest, 1e-300)
        st[2] = self.payout_rate if self.layout.drum_eq is not None else 0.0

    def update_drum(self) -> None:
        """``update`` for an ordinary payout step (only the drum element's rest length changed):
        the same bookkeeping for the fairlead node, the first free node and the two elements at
        them, in scalar arithmetic (this runs at every step of a paying-out winch); with the
        compiled kernels, ``kernels.drum_update``."""
        L = self.layout
        m, k, n, l0, mu = L.model, self.first, L.n, L.l0, self.mu
        if L.fast is not None:
            EA = L.spec.EA
            kernels.drum_update(k, n, l0, mu, self.drum_rest, self.fairlead_share, self.added_per_m, self.i_ref,
                                L.dof0, L.tadr, L.eq0, -1 if L.normal_ten is None else L.normal_ten.start,
                                math.inf if EA is None else float(EA), m.opt.timestep, L.spec.axial_damping_ratio,
                                AXIAL_OMEGA_DT, MIN_IMP, MAX_IMP, self.payout_rate, L.bids, self.rest,
                                self.inertia, self.lead, self.K, *self._model_arrays)
            return
        body_mass, armature, invweight = m.body_mass, m.dof_armature, m.tendon_invweight0
        ten_armature, nten = m.tendon_armature, (None if L.normal_ten is None else L.normal_ten.start)
        eq_solref, eq_solimp = m.eq_solref, m.eq_solimp
        s = self.drum_rest
        self.rest[k] = s  # (deployed_rest is a view of it)
        c = self.fairlead_share
        ap = self.added_per_m
        i_ref = self.i_ref
        inertia = self.inertia
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
            body_mass[L.bids[i]] = mass
            dof = L.dof0 + 3 * i
            armature[dof:dof + 3] = iso
            inertia[i] = mass + iso
        dt, zeta, EA = m.opt.timestep, L.spec.axial_damping_ratio, L.spec.EA
        for j in range(k, min(k + 2, n)):
            inv = 1.0 / float(inertia[j]) + 1.0 / float(inertia[j + 1])
            S, B, d = axial_scalar(EA, float(self.rest[j]), inv, dt, zeta)
            invweight[L.tadr + j] = inv
            e = L.eq0 + j
            eq_solref[e] = (-S, -B)
            eq_solimp[e, 0] = eq_solimp[e, 1] = d
            self.lead[j] = B / S
            self.K[j] = S / ((1.0 - d) * inv)
        m.eq_data[L.eq0 + k, 0] = (s + self.lead[k] * self.payout_rate - m.tendon_length0[L.tadr + k])

    def set_rest(self, lo: int, hi: int) -> None:
        """The equality of element j holds its length at rest_j + lead_j * (payout rate if j is
        the drum element): MuJoCo damps the rate of the element's length, and the lead turns
        that into its strain rate for the drum element, whose rest length grows at the payout
        rate (B l' + S (l - rest - (B / S) rest') = B (l' - rest') + S (l - rest))."""
        L = self.layout
        js = np.arange(lo, hi)
        target = self.rest[js] + np.where(js == self.first, self.lead[js] * self.payout_rate, 0.0)
        L.model.eq_data[L.eq0 + js, 0] = target - L.model.tendon_length0[L.tadr + js]

    # ----------------------------------------------------------------- payout

    def payout_state(self) -> tuple[int, float, float]:
        """(first deployed node, drum element rest length in m, payout rate in m/s): with MuJoCo's
        state (qpos, qvel, eq_active) this is everything needed to restore the payout exactly."""
        return self.first, self.drum_rest, self.payout_rate

    def restore_payout(self, state) -> None:
        """Restore a ``payout_state()`` (set MuJoCo's own state first, then call this; a state of
        two items, from before the rate was kept, leaves the rate as it is)."""
        first, drum, *rate = state
        if rate:
            self.payout_rate = float(rate[0])
        self.first, self.drum_rest = int(first), float(drum)
        self.relayout()

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
        L = self.layout
        length_m = float(length)
        if not (np.isfinite(length_m) and length_m >= 0):
            raise ValueError(f"length must be a finite number >= 0 m, got {length!r}")
        if not L.pays_out:
            if abs(length_m - L.line.length) > 1e-9 * L.line.length:
                raise ValueError(f"length: a line make-up's length is fixed at {L.line.length:g} m "
                                 "(payout of a make-up is not supported yet)")
            return
        n, l0 = L.n, L.l0
        k = self.first
        s = length_m - (n - k - 1) * l0
        if s == self.drum_rest:
            if self.payout_rate:
                self.payout_rate = 0.0
                self.set_rest(k, k + 1)
                self.sync_native()
            return  # (a fixed winch calls this every step)
        self.payout_rate = (length_m - self.deployed_length) / L.model.opt.timestep if rate is None else float(rate)
        if L.drum_eq is None:
            raise ValueError("set_length: this tether has a free start end and no drum")
        tm = L.tm
        if isinstance(tm.start, FixedPoint) and isinstance(tm.end, FixedPoint):
            span = float(np.linalg.norm(np.subtract(tm.end.position, tm.start.position)))
            elastic = L.spec.EA is not None
            least = span / (1.0 + MAX_SET_STRAIN) if elastic else span
            if length_m < least:
                raise ValueError(f"set_length length = {length!r} m: the tether's fixed ends are {span:.4g} m apart; "
                                 f"give length >= {least:.4g} m (" + ("elastic, stretched at most "
                                 f"{100 * MAX_SET_STRAIN:.0f} %)" if elastic else "inextensible)"))
        if length_m > L.max_length * (1 + 1e-9) + 1e-9:
            raise ValueError(f"length {length_m:g} m exceeds the tether's max_length {L.max_length:g} m "
                             "(give add_tether(max_length=...) the winch's max_length)")
        changed = False
        while s > SPLIT * l0 and k > 0:  # release node k-1 from the drum
            xf, vf = L.x(k, k + 1)[0], L.v(k, k + 1)[0].copy()
            xn, vn = L.x(k + 1, k + 2)[0], L.v(k + 1, k + 2)[0].copy()
            f = (s - l0) / s
            # the released node moves with the cable in the water (paid out at the drum's speed)
            L.place(k, xf + f * (xn - xf), vn)
            L.place(k - 1, xf, vf)
            k -= 1
            s -= l0
            changed = True
        while s < MERGE * l0 and k < n - 1:  # take node k+1 back onto the drum
            xf, vf = L.x(k, k + 1)[0], L.v(k, k + 1)[0].copy()
            L.place(k + 1, xf, vf)
            L.place(k, xf, np.zeros(3))
            k += 1
            s += l0
            changed = True
        self.first, self.drum_rest = k, max(s, 0.0)
        if changed:
            self.relayout()
        else:
            self.update_drum()
            self.sync_native()

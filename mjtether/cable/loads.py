"""The loads on a bound tether's deployed nodes: Morison drag, buoyancy, bending and point loads
(``physics.hydro``'s NumPy kernels or their compiled twins), seabed friction (``friction``), the
orientation of the normal added mass, and the arrays the native callback reads instead.

Units SI, world frame; loads in N on the deployed nodes, the first at the fairlead.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mjtether.physics import compiled
from mjtether.physics.hydro import bending_forces, gauss_heights, tether_loads

from .layout import CableLayout
from .seabed import CONTACT_TOLERANCE, STICK_DAMPING, STICK_STIFFNESS

_EX, _EZ = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])


def compiled_arrays(layout: CableLayout) -> dict:
    """Per-element properties and work arrays for the compiled kernels (``compiled``): each
    element's diameter, C_dn, C_dt, displaced area per metre and floats' drag area per metre,
    each joint's EI / l (None without bending), the water profiles' codes (None: evaluated in
    NumPy), and buffers for the loads."""
    L, mk, n = layout, layout.line, layout.n
    c = dict(diameter=L.element(mk.element_diameter), cd_normal=L.element(mk.element_cd_normal),
             cd_tangential=L.element(mk.element_cd_tangential), area=L.element(mk.element_area),
             cd_area_float=L.element(mk.element_float_cd_area), bend=joint_stiffness(L))
    c.update(water=compiled.profile_codes(layout.water), rho=np.empty(2 * n), u=np.empty((2 * n, 3)),
             f=np.empty((n + 1, 3)), friction=np.empty((n + 1, 3)), stick=np.empty((n + 1, 3)))
    return c


def joint_stiffness(layout: CableLayout) -> np.ndarray | None:
    """Each joint's bending stiffness over length, EI / l (N m), shape (n - 1,): the mean of its two
    elements' EI over the mean of their nominal lengths (a uniform line's EI / l0, exactly); None
    without bending."""
    EI, rest = layout.element(layout.line.element_EI), layout.nominal
    if not np.any(EI > 0):
        return None
    return (0.5 * (EI[1:] + EI[:-1])) / (0.5 * (rest[1:] + rest[:-1]))


def orient_added_mass(normal_prm, first: int, x: np.ndarray) -> None:
    """Turn the deployed nodes' normal added-mass tendons (``normal_prm``, the layout's view of
    their joint coefficients; None: isotropic added mass, nothing to do) normal to the cable at
    ``x`` (the deployed nodes, m): at each node two unit vectors normal to its tangent (the mean
    of its elements' directions). MuJoCo uses them from the next mass matrix on."""
    if normal_prm is None or len(x) < 2:
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
    prm = normal_prm[first:]
    if ok.all():
        prm[:, 0] = n1
        prm[:, 1] = np.cross(t, n1)
    else:
        prm[ok, 0] = n1
        prm[ok, 1] = np.cross(t, n1)


class CableLoads:
    """The passive loads of a bound tether, given its ``drum`` (payout state) and its seabed
    ``contact`` (``friction.SeabedContact``)."""

    def __init__(self, layout: CableLayout, drum, contact):
        self.layout, self.drum, self.contact = layout, drum, contact
        self.bend = joint_stiffness(layout)  # EI / l of each joint (N m), None without bending

    def buffer(self, data: mujoco.MjData) -> np.ndarray:
        """Hydrodynamic (+ bending, + seabed friction) loads on the deployed nodes (N, shape
        (n-first+1, 3)), updating the seabed stick points; in a buffer of the compiled kernels
        that the next call overwrites."""
        L, k = self.layout, self.drum.first
        x = data.flexvert_xpos[L.vertadr + k:L.vertadr + L.n + 1]
        v = data.qvel[L.dof0 + 3 * k:L.dof0 + 3 * (L.n + 1)].reshape(-1, 3)
        f = self.hydro(x, v)
        if self.contact.seabed is not None:
            f += self.contact.friction(data, x, v)
        return f

    def apply(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Add the loads to ``data.qfrc_passive`` and turn the normal added mass with the cable
        (the force provider's call, from the passive callback)."""
        L, k = self.layout, self.drum.first
        f = self.buffer(data)
        data.qfrc_passive[L.dof0 + 3 * k:L.dof0 + 3 * (L.n + 1)] += f.ravel()
        if L.normal_prm is not None:
            orient_added_mass(L.normal_prm, k, data.flexvert_xpos[L.vertadr + k:L.vertadr + L.n + 1])

    def hydro(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Hydrodynamic (+ bending) loads (N) on deployed nodes at ``x`` (m) moving at ``v`` (m/s)."""
        L, dr = self.layout, self.drum
        s = L.spec
        if dr.payout_rate and L.drum_eq is not None:
            # the cable at the fairlead moves out of the drum at the payout rate, along the drum
            # element: its drag acts on that material velocity, not on the fairlead node's
            e = x[1] - x[0]
            v = v.copy()
            v[0] += dr.payout_rate / max(math.sqrt(e @ e), 1e-9) * e
        if L.fast is not None:
            return self._compiled_hydro(x, v)
        mk, k = L.line, dr.first
        plain = not mk.has_floats  # (the displaced area is pi d^2 / 4, no floats' drag)
        f = tether_loads(x, v, segment_length=dr.deployed_rest, diameter=L.element(mk.element_diameter)[k:],
                         cd_normal=L.element(mk.element_cd_normal)[k:],
                         cd_tangential=L.element(mk.element_cd_tangential)[k:], rho_fn=L.water.rho,
                         current_fn=L.water.velocity, gravity=L.water.gravity,
                         area=None if plain else L.element(mk.element_area)[k:],
                         float_cd_area=None if plain else L.element(mk.element_float_cd_area)[k:],
                         drag_law=s.drag_law,
                         first_share=dr.fairlead_share / max(dr.drum_rest, 1e-300))
        if mk.has_point_loads:
            self._point_loads(x, v, f)
        if self.bend is not None:
            f += bending_forces(x, self.bend[k:], 1.0)
        return f

    def _compiled_hydro(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """``hydro`` with the compiled kernels: the same loads, into a
        buffer that the next call overwrites."""
        L, dr = self.layout, self.drum
        c, k, m = L.fast, dr.first, len(x) - 1
        rho, u, f = c["rho"][:2 * m], c["u"][:2 * m], c["f"][:m + 1]
        if c["water"] is None:  # a profile the compiled kernels do not know: its own NumPy code
            zg = np.minimum(gauss_heights(x[:, 2]), 0.0).T.ravel()  # (element i's two at 2i, 2i + 1)
            rho[:] = L.water.rho(zg)
            u[:] = L.water.velocity(zg)
        else:
            compiled.element_water(x, *c["water"], rho, u)
        mk = L.line
        share = dr.fairlead_share / max(dr.drum_rest, 1e-300)
        compiled.tether_loads(x, v, dr.deployed_rest, c["diameter"][k:], c["cd_normal"][k:],
                              c["cd_tangential"][k:], c["area"][k:], c["cd_area_float"][k:], rho, u,
                              L.water.gravity, share, f)
        if c["bend"] is not None:
            compiled.add_bending_forces(x, c["bend"][k:], f)
        if mk.has_point_loads:
            self._point_loads(x, v, f)
        return f

    def _point_loads(self, x: np.ndarray, v: np.ndarray, f: np.ndarray) -> None:
        """Add each point load's buoyancy (under water) and drag 1/2 rho CdA |u - v| (u - v) at its
        node (its weight is in the node's mass) to ``f`` (N)."""
        L = self.layout
        mk = L.line
        z = np.minimum(x[:, 2], 0.0)
        wet = x[:, 2] <= 0.0
        rho = np.asarray(L.water.rho(z), float)
        f[:, 2] += rho * mk.node_volume * L.water.gravity * wet
        cda = mk.node_cd_area
        if np.any(cda > 0):
            u = L.water.velocity(z) - v
            f += (0.5 * rho * cda * wet * np.sqrt(np.einsum("ij,ij->i", u, u)))[:, None] * u

    def native_table(self):
        """This tether's arrays for the native callback (``native``, slots ``T_*``), or None where
        its loads need Python (the NumPy kernels, a water profile the compiled kernels do not
        know, or friction on a height field). The arrays are the drum's own, updated in place as the cable pays out."""
        L, dr, contact = self.layout, self.drum, self.contact
        c = L.fast
        if c is None or c["water"] is None or contact.grid is not None:  # (a height field's friction: NumPy)
            return None
        dkind, dp, ckind, cp = c["water"]
        mk, n = L.line, L.n
        empty = np.zeros(0)
        mode, real = 0, np.zeros(13)
        real[0] = L.water.gravity
        if contact.seabed is not None:
            point, normal, w = contact.seabed
            mode = 2 if not L.pays_out else (3 if w <= 0.0 else 1)  # (the nodes' own weights: see friction)
            # (over dt^2 and dt at each step: a pre-roll changes the time step)
            real[1:7] = (STICK_STIFFNESS, 2.0 * STICK_DAMPING * math.sqrt(STICK_STIFFNESS), w,
                         float(L.tm.seabed_friction), L.spec.diameter / 2, CONTACT_TOLERANCE)
            real[7:10], real[10:13] = point, normal
        wrap = -1 if L.normal_prm is None else int(L.model.tendon_adr[L.normal_ten.start])
        points = mk.has_point_loads
        ints = np.array([n, L.vertadr, L.dof0, mode, contact.stick.start if mode else 0,
                         c["bend"] is not None, dkind, ckind, points, wrap], dtype=np.int64)
        node = lambda a: np.ascontiguousarray(a, dtype=float)  # noqa: E731
        return [ints, real, dr.native_state, dr.rest, dr.inertia, c["diameter"], c["cd_normal"],
                c["cd_tangential"], c["area"], c["cd_area_float"], empty if c["bend"] is None else c["bend"], dp, cp,
                node(getattr(contact, "node_wet", empty)) if mode == 2 else empty,
                node(mk.node_volume) if points else empty, node(mk.node_cd_area) if points else empty]

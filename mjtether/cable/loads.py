"""The loads on a bound tether's deployed nodes: Morison drag, buoyancy, bending and point loads
(``physics.hydro``'s NumPy kernels or their compiled twins), seabed friction (``friction``), the
orientation of the normal added mass, and the arrays the native callback reads instead.

Units SI, world frame; loads in N on the deployed nodes, the first at the fairlead.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import mujoco
import numpy as np

from mjtether.physics import compiled
from mjtether.physics.hydro import (GAUSS_POINTS, bending_forces, gauss_heights, gauss_points, tether_loads,
                                    wave_inertia)

from .layout import CableLayout
from .seabed import CONTACT_TOLERANCE, STICK_DAMPING, STICK_STIFFNESS

_EX, _EZ = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])


class SeaAtLine(NamedTuple):
    """The waves along a line at one instant (``CableLoads.sea``)."""

    surface: np.ndarray  # (m,) m: the water surface's height over each element's centre
    velocity: np.ndarray  # (2, m, 3) m/s: the particle velocity at each element's Gauss points
    acceleration: np.ndarray  # (2, m, 3) m/s^2: the particles' local acceleration there


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
             f=np.empty((n + 1, 3)), friction=np.empty((n + 1, 3)), stick=np.empty((n + 1, 3)),
             still=np.zeros(n))  # (the mean water line over every element: no waves)
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


_GAUSS_S = np.array(GAUSS_POINTS)[:, None]  # (2, 1): an element's Gauss points, as fractions of it


def _wave_added_mass(layout: CableLayout) -> tuple[np.ndarray, np.ndarray]:
    """The added mass's area per metre (m^2) of each element normal to it and along it, as the
    model carries it (C_a pi d^2 / 4 plus the floats' C_a V per metre; along it the same where
    the added mass is isotropic, else 0): what the waves' inertia load takes (``hydro.wave_inertia``)."""
    mk = layout.line
    d = layout.element(mk.element_diameter)
    added = layout.element(mk.element_ca_normal) * np.pi * d ** 2 / 4 + layout.element(mk.element_float_added_volume)
    # (isotropic: the armature on all axes)
    return added, (added if layout.normal_prm is None else np.zeros_like(added))


class CableLoads:
    """The passive loads of a bound tether, given its ``drum`` (payout state) and its seabed
    ``contact`` (``friction.SeabedContact``)."""

    def __init__(self, layout: CableLayout, drum, contact):
        self.layout, self.drum, self.contact = layout, drum, contact
        self.bend = joint_stiffness(layout)  # EI / l of each joint (N m), None without bending
        self._added = _wave_added_mass(layout)  # (the waves' inertia load's, ``_wave_inertia``)

    def buffer(self, data: mujoco.MjData) -> np.ndarray:
        """Hydrodynamic (+ bending, + seabed friction) loads on the deployed nodes (N, shape
        (n-first+1, 3)), updating the seabed stick points; in a buffer of the compiled kernels
        that the next call overwrites."""
        L, k = self.layout, self.drum.first
        x = data.flexvert_xpos[L.vertadr + k:L.vertadr + L.n + 1]
        v = data.qvel[L.dof0 + 3 * k:L.dof0 + 3 * (L.n + 1)].reshape(-1, 3)
        f = self.hydro(x, v, data.time)
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

    def hydro(self, x: np.ndarray, v: np.ndarray, t: float = 0.0) -> np.ndarray:
        """Hydrodynamic (+ bending) loads (N) on deployed nodes at ``x`` (m) moving at ``v`` (m/s)
        at time ``t`` (s; the waves' phase, where there are waves: ``wave_loads``)."""
        L, dr = self.layout, self.drum
        s = L.spec
        if dr.payout_rate and L.drum_eq is not None:
            # the cable at the fairlead moves out of the drum at the payout rate, along the drum
            # element: its drag acts on that material velocity, not on the fairlead node's
            e = x[1] - x[0]
            v = v.copy()
            v[0] += dr.payout_rate / max(math.sqrt(e @ e), 1e-9) * e
        sea = self.sea(x, t)
        if L.fast is not None:
            return self._compiled_hydro(x, v, sea, t)
        mk, k = L.line, dr.first
        plain = not mk.has_floats  # (the displaced area is pi d^2 / 4, no floats' drag)
        f = tether_loads(x, v, segment_length=dr.deployed_rest, diameter=L.element(mk.element_diameter)[k:],
                         cd_normal=L.element(mk.element_cd_normal)[k:],
                         cd_tangential=L.element(mk.element_cd_tangential)[k:], rho_fn=L.water.rho,
                         current_fn=L.water.velocity, gravity=L.water.gravity,
                         area=None if plain else L.element(mk.element_area)[k:],
                         float_cd_area=None if plain else L.element(mk.element_float_cd_area)[k:],
                         drag_law=s.drag_law,
                         first_share=dr.fairlead_share / max(dr.drum_rest, 1e-300),
                         surface=None if sea is None else sea.surface, wave_velocity=None if sea is None else sea.velocity)
        self._wave_inertia(x, sea, f)
        if mk.has_point_loads:
            self._point_loads(x, v, f, t)
        if self.bend is not None:
            f += bending_forces(x, self.bend[k:], 1.0)
        return f

    def sea(self, x: np.ndarray, t: float):
        """The waves at the deployed nodes ``x`` (m) at time ``t`` (s), or None without waves: a
        ``SeaAtLine`` of the surface's height over each element (m, (m,): the mean of its two
        Gauss points', its centre's to second order in the element's length over the wave
        length), the particle velocity and local acceleration at each element's Gauss points
        (m/s, m/s^2, (2, m, 3)): one evaluation of the sea per step."""
        waves = self.layout.water.waves
        if waves is None:
            return None
        if self.layout.fast is None:
            gp = gauss_points(x)
            eta, vel, acc = waves.state(gp.reshape(-1, 3), t)
            return SeaAtLine(eta.reshape(2, -1).mean(axis=0), vel.reshape(gp.shape), acc.reshape(gp.shape))
        # the compiled kernels' order: element i's two Gauss points at 2i and 2i + 1 (the same
        # points, the arrays (2, m, 3) views of it)
        m = len(x) - 1
        gp = x[:-1, None, :] + _GAUSS_S * (x[1:] - x[:-1])[:, None, :]
        eta, vel, acc = waves.state(gp.reshape(-1, 3), t)
        return SeaAtLine(0.5 * (eta[0::2] + eta[1::2]), vel.reshape(m, 2, 3).transpose(1, 0, 2),
                         acc.reshape(m, 2, 3).transpose(1, 0, 2))

    def _wave_inertia(self, x: np.ndarray, sea, f: np.ndarray) -> None:
        """Add the waves' inertia loads (``hydro.wave_inertia``: Froude-Krylov plus the added
        mass the model carries, normal only or isotropic as ``TetherSpec.added_mass``) to ``f``."""
        if sea is None:
            return
        L, k = self.layout, self.drum.first
        mk = L.line
        added, axial = (a[k:] for a in self._added)
        zg = np.minimum(gauss_heights(x[:, 2]), 0.0)
        f += wave_inertia(x, self.drum.deployed_rest, L.element(mk.element_area)[k:],
                          L.element(mk.element_diameter)[k:], sea.surface, np.asarray(L.water.rho(zg), dtype=float),
                          sea.acceleration, added, axial)

    def _compiled_hydro(self, x: np.ndarray, v: np.ndarray, sea=None, t: float = 0.0) -> np.ndarray:
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
        if sea is not None:  # (element i's two Gauss points at 2i, 2i + 1)
            u += sea.velocity.transpose(1, 0, 2).reshape(2 * m, 3)
        mk = L.line
        share = dr.fairlead_share / max(dr.drum_rest, 1e-300)
        compiled.tether_loads(x, v, dr.deployed_rest, c["diameter"][k:], c["cd_normal"][k:],
                              c["cd_tangential"][k:], c["area"][k:], c["cd_area_float"][k:], rho, u,
                              L.water.gravity, share, f, c["still"][:m] if sea is None else sea.surface)
        if sea is not None:  # (``_wave_inertia``; the density at the Gauss points is the drag's)
            added, axial = self._added
            compiled.add_wave_inertia(x, dr.deployed_rest, c["area"][k:], c["diameter"][k:], sea.surface, rho,
                                      sea.acceleration.transpose(1, 0, 2).reshape(2 * m, 3), added[k:], axial[k:], f)
        if c["bend"] is not None:
            compiled.add_bending_forces(x, c["bend"][k:], f)
        if mk.has_point_loads:
            self._point_loads(x, v, f, t)
        return f

    def _point_loads(self, x: np.ndarray, v: np.ndarray, f: np.ndarray, t: float = 0.0) -> None:
        """Add each point load's buoyancy (under water) and drag 1/2 rho CdA |u - v| (u - v) at its
        node (its weight is in the node's mass) to ``f`` (N); with waves, under the instantaneous
        surface, on the current plus the particle velocity, and with the inertia load rho (V +
        C_a V) a of the fluid's acceleration a (Froude-Krylov plus its added mass)."""
        L = self.layout
        mk = L.line
        waves = L.water.waves
        z = np.minimum(x[:, 2], 0.0)
        rho = np.asarray(L.water.rho(z), float)
        if waves is None:
            wet = x[:, 2] <= 0.0
        else:
            wet = x[:, 2] <= waves.elevation(x[:, 0], x[:, 1], t)
            wave_u, wave_a = waves.kinematics(x, t)
            f += (rho * wet * (mk.node_volume + mk.node_added_volume))[:, None] * wave_a
        f[:, 2] += rho * mk.node_volume * L.water.gravity * wet
        cda = mk.node_cd_area
        if np.any(cda > 0):
            u = L.water.velocity(z) - v if waves is None else L.water.velocity(z) + wave_u - v
            f += (0.5 * rho * cda * wet * np.sqrt(np.einsum("ij,ij->i", u, u)))[:, None] * u

    def native_table(self):
        """This tether's arrays for the native callback (``native``, slots ``T_*``), or None where
        its loads need Python (the NumPy kernels, a water profile the compiled kernels do not
        know, or friction on a height field). The arrays are the drum's own, updated in place as the cable pays out;
        with waves, the sea's components (``WaveField``'s table) and the added mass their inertia load takes."""
        L, dr, contact = self.layout, self.drum, self.contact
        c, waves = L.fast, L.water.waves
        if c is None or c["water"] is None or contact.grid is not None:
            return None  # (a height field's friction: the Python callback)
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
                         c["bend"] is not None, dkind, ckind, points, wrap, waves is not None], dtype=np.int64)
        node = lambda a: np.ascontiguousarray(a, dtype=float)  # noqa: E731
        sea = [empty] * 5 if waves is None else [
            waves._table.ravel(), np.array([waves.depth, waves.ramp_s, waves.stretching == "wheeler"], dtype=float),
            node(self._added[0]), node(self._added[1]), node(mk.node_added_volume) if points else empty]
        return [ints, real, dr.native_state, dr.rest, dr.inertia, c["diameter"], c["cd_normal"],
                c["cd_tangential"], c["area"], c["cd_area_float"], empty if c["bend"] is None else c["bend"], dp, cp,
                node(getattr(contact, "node_wet", empty)) if mode == 2 else empty,
                node(mk.node_volume) if points else empty, node(mk.node_cd_area) if points else empty, *sea]

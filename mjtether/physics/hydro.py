"""Hydrodynamic force kernels: pure NumPy, no MuJoCo.

Tether (lumped-mass discretisation, nodes 0..N, element i joins nodes i and i+1), after the
design conventions and Morison's equation. For element i of unstretched length l, diameter d,
unit tangent t and relative velocity v_rel = u(z_g) - v_g at each of its two Gauss points
(``GAUSS_POINTS``, each standing for half its length; ``morison_drag``, the one drag kernel of
the dynamic tether and the quasi-static solver):

* normal drag      F_n = 1/2 rho C_dn d l_wet |v_n| v_n,
* tangential drag  F_t = 1/2 rho C_dt pi d l_wet |v_t| v_t,
* buoyancy         F_b = rho(z) g A l_wet, upwards, acting at the centre of the wetted part,

where l_wet is the submerged part of the element (the cable may cross the surface z = 0): its
cylinder's volume under the surface over A (``wet_fraction``), so that a float lying on the
surface floats at its draft.
``loading_function_drag`` is the other drag law a tether may take (``TetherSpec.drag_law``):
Hong et al.'s (2020, J. Mar. Sci. Eng. 8, 485) Eq. 20-21, one C_d scaled by loading functions of
the angle between the cable and the flow.
Element loads go to its two nodes by the lever rule: its drag from its Gauss points (a consistent
load: the nodes' deflections then converge at second order also in a current sheared over a few
elements, where splitting the drag half and half, as the mass is, leaves 0.6 % at N = 50), its
buoyancy from the centre of its wet part.
The added mass C_a rho A l is carried by the MuJoCo mass matrix (see ``builder``), not here.

Rigid bodies: buoyancy rho g V at the centre of buoyancy, quadratic drag per body axis
F_k = 1/2 rho C_k S_k |v_k| v_k on the relative velocity, angular drag M_k = -c_k |w_k| w_k.

All inputs and outputs are SI, world frame unless stated.
"""

from __future__ import annotations

import math

import numpy as np


def element_geometry(x: np.ndarray):
    """Element vectors, lengths (m) and unit tangents of a node polyline ``x`` (N+1, 3)."""
    e = x[1:] - x[:-1]
    length = np.sqrt(np.einsum("ij,ij->i", e, e))
    t = e / np.maximum(length, 1e-12)[:, None]
    return e, length, t


def _disk_wet(c):
    """F(c) = (pi - acos c + c sqrt(1 - c^2)) / pi, the wet fraction of a disk whose centre is
    c h under the surface (h its vertical half-height; 0 for c <= -1, 1 for c >= 1), and its
    integrals over c, G and H: dG/dc = F, dH/dc = c F (the wet fraction of the cross-sections of
    a cylinder cut by the surface, and its first moment, integrated along the axis)."""
    cc = np.clip(c, -1.0, 1.0)
    s = np.sqrt(1.0 - cc * cc)
    a, b = np.arccos(cc), np.arcsin(cc)
    F = (np.pi - a + cc * s) / np.pi
    G = (np.pi * cc - cc * a + s - s ** 3 / 3.0) / np.pi + np.maximum(c - 1.0, 0.0)
    H = (np.pi * cc * cc / 2.0 - cc * cc * a / 2.0 - (b - cc * s) / 4.0
         + (cc * (2.0 * cc * cc - 1.0) * s + b) / 8.0) / np.pi + (np.maximum(c, 1.0) ** 2 - 1.0) / 2.0
    return F, G, H


def section_half_height(diameter, t: np.ndarray) -> np.ndarray:
    """Half the vertical extent (m) of the cross-sections of cylinders of ``diameter`` (m, scalar
    or per element) along unit tangents ``t`` (K, 3): r sqrt(1 - t_z^2)."""
    return 0.5 * np.asarray(diameter) * np.sqrt(np.maximum(1.0 - t[:, 2] ** 2, 0.0))


def wet_fraction(z0: np.ndarray, z1: np.ndarray, half_height=0.0):
    """Submerged fraction of straight elements with axis end heights z0, z1 (m), and the position
    (0 at node i, 1 at node i+1) of the centre of the wetted part.

    ``half_height`` (m, scalar or per element): half the vertical extent of an element's cross
    section (``section_half_height``). Each cross
    section square to the axis is wet by its circular segment under z = 0 and the element's
    fraction is their mean along the axis, which is the cylinder's wet volume cut by the surface
    exactly (end caps aside): a float lying on the surface is buoyed by the part of it that is
    under water, so it rests at its draft rather than chattering about a step. 0: by the axis
    alone (the wet length of a line crossing the surface)."""
    h = np.broadcast_to(np.asarray(half_height, dtype=float), np.shape(z0))
    if (z0 + h).max() <= 0.0 and (z1 + h).max() <= 0.0:  # the usual case: the whole line is under water
        return np.ones_like(z0), np.full_like(z0, 0.5)
    lo = np.minimum(z0, z1)
    hi = np.maximum(z0, z1)
    span = hi - lo
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.where(span > 1e-12, np.clip(-lo / np.where(span > 1e-12, span, 1.0), 0.0, 1.0),
                        (lo <= 0.0).astype(float))
    # centre of the wet part, measured from the lower end, then mapped to node i -> node i+1
    c_low = 0.5 * frac
    centre = np.where(z0 <= z1, c_low, 1.0 - c_low)
    # the cross-sections' circular segments, where an element of some width meets the surface
    cut = (h > 1e-9) & ((z0 + h > 0.0) | (z1 + h > 0.0)) & ((z0 - h < 0.0) | (z1 - h < 0.0))
    frac = np.where((h > 1e-9) & ~cut, (z0 + h <= 0.0).astype(float), frac)
    centre = np.where((h > 1e-9) & ~cut, 0.5, centre)
    for i in np.flatnonzero(cut):
        frac[i], centre[i] = _cut_element(-z0[i] / h[i], -z1[i] / h[i])
    return frac, centre


def _cut_element(c0: float, c1: float):
    """(wet fraction, centre of the wet part) of an element whose cross-sections' centres run from
    c0 h to c1 h under the surface: the mean of F along it and its centroid, from the integrals
    of ``_disk_wet``; for a nearly level element (|c1 - c0| < 1e-4, where their difference
    would lose digits) from F at the middle and its slope (error below 3e-7)."""
    dc = c1 - c0
    if abs(dc) < 1e-4:
        cm = 0.5 * (c0 + c1)
        F = float(_disk_wet(cm)[0])
        slope = 2.0 * math.sqrt(max(1.0 - cm * cm, 0.0)) / math.pi  # dF/dc
        return F, (min(max(0.5 + dc * slope / (12.0 * F), 0.0), 1.0) if F > 0.0 else 0.5)
    _, G0, H0 = (float(a) for a in _disk_wet(c0))
    _, G1, H1 = (float(a) for a in _disk_wet(c1))
    G = G1 - G0
    if G == 0.0:
        return 0.0, 0.5
    return min(max(G / dc, 0.0), 1.0), min(max(((H1 - H0) - c0 * G) / (dc * G), 0.0), 1.0)


def morison_drag(t: np.ndarray, u: np.ndarray, rho, l_wet, diameter, cd_normal, cd_tangential_pi,
                 float_cd_area=None) -> np.ndarray:
    """Morison drag (N, world) on straight cable elements, shape (K, 3): normal
    1/2 rho C_dn d l_wet |u_n| u_n plus tangential 1/2 rho C_dt pi d l_wet |u_t| u_t, plus, with
    ``float_cd_area`` (m^2 per metre of cable: floats on it), 1/2 rho C_dA l_wet |u_n| u_n.

    Args:
        t: unit tangents (K, 3); u: flow relative to the element (current less its velocity),
            m/s (K, 3).
        rho: water density (kg/m^3), l_wet: wetted length (m), diameter (m), cd_normal and
            cd_tangential_pi (C_dt times pi): scalars or one per element (K,).
    """
    ut = (u * t).sum(axis=1)
    un = u - ut[:, None] * t
    q = 0.5 * diameter * l_wet * rho
    un_mag = np.sqrt((un * un).sum(axis=1))
    f = (q * cd_normal * un_mag)[:, None] * un
    f += (q * cd_tangential_pi * np.abs(ut) * ut)[:, None] * t
    if float_cd_area is not None:  # the floats' own normal drag
        f += (0.5 * float_cd_area * l_wet * rho * un_mag)[:, None] * un
    return f


DRAG_LAWS = ("morison", "loading_functions")
"""A tether's drag laws: ``morison`` (normal C_dn on d l, tangential C_dt on pi d l, each on its
own velocity component: the cross-flow principle) and ``loading_functions`` (Hong et al. 2020,
Eq. 20-21: one C_d on d l, scaled by loading functions of the flow's angle to the cable)."""


def loading_functions(eta):
    """Hong et al. (2020, J. Mar. Sci. Eng. 8, 485), Eq. 21: the normal and tangential loading
    functions f_p, f_p3 of the angle eta (rad, 0..pi/2) between the cable and the relative flow.
    f_p runs from 0 (flow along the cable) to 1 (flow across it). The tangential fit f_p3 (0.0201
    along the cable) crosses zero at 89.9 deg and ends at -6.9e-5 at 90 deg; it is held at zero
    there (a tangential force along the flow would be no drag)."""
    e = np.asarray(eta, float)
    fp = 0.5 - 0.1 * np.cos(e) + 0.1 * np.sin(e) - 0.4 * np.cos(2 * e) - 0.11 * np.sin(2 * e)
    ft = 0.01 * (2.008 + e * (-0.3858 + e * (1.9159 + e * (-4.1615 + e * (3.5064 - 1.1873 * e)))))
    return fp, np.maximum(ft, 0.0)


def loading_function_drag(t: np.ndarray, u: np.ndarray, rho, l_wet, diameter, cd) -> np.ndarray:
    """Drag (N, world) on straight cable elements by Hong et al.'s (2020) Eq. 20, shape (K, 3):
    normal 1/2 rho C_d d l_wet f_p(eta) |u|^2 along the flow's normal part, tangential
    1/2 rho C_d d l_wet f_p3(eta) |u|^2 along the flow's tangential part (``loading_functions``),
    eta the angle between the cable and the relative flow u. Both act on |u|^2, the whole flow's
    dynamic pressure (where ``morison_drag`` takes each component's own).

    Args:
        t: unit tangents (K, 3); u: flow relative to the element (current less its velocity), m/s
            (K, 3); rho (kg/m^3), l_wet (m), diameter (m), cd (on d l): scalars or one per element.
    """
    ut = (u * t).sum(axis=1)
    un = u - ut[:, None] * t
    un_mag = np.sqrt((un * un).sum(axis=1))
    u2 = un_mag * un_mag + ut * ut
    eta = np.arctan2(un_mag, np.abs(ut))
    fp, ft = loading_functions(eta)
    q = 0.5 * rho * cd * diameter * l_wet * u2
    with np.errstate(invalid="ignore", divide="ignore"):
        n_dir = np.where(un_mag[:, None] > 1e-12, un / np.where(un_mag > 1e-12, un_mag, 1.0)[:, None], 0.0)
    return (q * fp)[:, None] * n_dir + (q * ft * np.sign(ut))[:, None] * t


def element_drag(drag_law: str, t, u, rho, l_wet, diameter, cd_normal, cd_tangential_pi, float_cd_area=None):
    """Drag (N, world) on straight cable elements by ``drag_law`` (``DRAG_LAWS``):
    ``morison_drag``, or ``loading_function_drag`` with ``cd_normal`` as its one C_d (the
    tangential coefficient and the floats' drag area unused)."""
    if drag_law == "loading_functions":
        return loading_function_drag(t, u, rho, l_wet, diameter, cd_normal)
    return morison_drag(t, u, rho, l_wet, diameter, cd_normal, cd_tangential_pi, float_cd_area)


GAUSS = 0.5 / math.sqrt(3.0)
GAUSS_POINTS = (0.5 - GAUSS, 0.5 + GAUSS)
"""Where along an element (0 at node i, 1 at node i+1) its drag is taken: the two-point Gauss
rule, exact for loads that vary along it as a cubic (a current sheared over a few elements'
length: the midpoint rule missed l^2 (2/d)^2 / 24 of a drag decaying as exp(2 z / d))."""


def gauss_heights(z: np.ndarray) -> np.ndarray:
    """Heights (m), shape (2, n), of the Gauss points of the elements between nodes at heights
    ``z`` (n+1,)."""
    return np.stack([z[:-1] + s * (z[1:] - z[:-1]) for s in GAUSS_POINTS])


def tether_loads(
    x: np.ndarray,
    v: np.ndarray,
    *,
    segment_length: float,
    diameter: float,
    cd_normal: float,
    cd_tangential: float,
    rho_fn,
    current_fn,
    gravity: float = 9.81,
    first_share: float = 0.5,
    area=None,
    float_cd_area=None,
    drag_law: str = "morison",
    surface=None,
    wave_velocity=None,
) -> np.ndarray:
    """Hydrodynamic loads on the nodes of a tether (N, world frame), shape ``(N+1, 3)``.

    Args:
        x, v: node positions (m) and velocities (m/s), shape ``(N+1, 3)``.
        segment_length: unstretched element length l (m), or one per element; loads scale with
            the material length, not the stretched one.
        rho_fn(z) -> rho (kg/m^3), current_fn(z) -> u (m/s, shape z.shape + (3,)).
        first_share: the part of the first element's load that goes to node 0 (the rest to
            node 1), as its mass does (the drum element at a fairlead, ``cable.drum.Drum.update``);
            0.5: by the lever rule, as every other element. While it is not 0.5 (paying out),
            element 1 splits its drag half and half, as its mass is split, so that a node
            released from the drum takes its drag as it takes its mass.
        diameter, cd_normal, cd_tangential: scalars, or one per element (a line make-up).
        area: displaced volume per metre of each element (m^2) if not pi d^2 / 4 (floats on it).
        float_cd_area: extra normal drag area per metre of each element (m^2/m: floats), or None.
        drag_law: ``"morison"`` or ``"loading_functions"`` (``DRAG_LAWS``; the latter takes
            ``cd_normal`` as its one C_d and ignores ``cd_tangential`` and floats).
        surface: the water surface's height over each element (m, (n,)), where waves move it:
            the wet fraction and the buoyancy follow it (None: the mean water line, z = 0).
        wave_velocity: the waves' particle velocity at each element's Gauss points (m/s, shape
            (2, n, 3)), added to the current (None: no waves). Density and current are taken at
            the still-water height, clamped at z = 0 (constant into a crest).
    """
    _, _, t = element_geometry(x)
    z0, z1 = (x[:-1, 2], x[1:, 2]) if surface is None else (x[:-1, 2] - surface, x[1:, 2] - surface)
    frac, centre = wet_fraction(z0, z1, section_half_height(diameter, t))
    zg = np.minimum(gauss_heights(x[:, 2]), 0.0)
    rho = rho_fn(zg)  # (2, n): at each element's two Gauss points
    near = far = 0.0  # each element's drag on node i and on node i + 1: the lever rule from its Gauss points
    for g, s in enumerate(GAUSS_POINTS):
        u = current_fn(zg[g]) if wave_velocity is None else current_fn(zg[g]) + wave_velocity[g]
        vrel = u - ((1.0 - s) * v[:-1] + s * v[1:])
        drag = element_drag(drag_law, t, vrel, rho[g], 0.5 * segment_length * frac, diameter, cd_normal,
                            np.pi * np.asarray(cd_tangential), float_cd_area)
        near, far = near + (1.0 - s) * drag, far + s * drag
    rho_mean = rho.mean(axis=0)
    if area is None:
        fb = (gravity * np.pi * diameter**2 / 4.0 * segment_length) * rho_mean * frac
    else:
        fb = (gravity * area * segment_length) * rho_mean * frac
    f = np.empty_like(x)
    f[:-1] = near
    f[-1] = 0.0
    f[1:] += far
    f[:-1, 2] += (1.0 - centre) * fb
    f[1:, 2] += centre * fb
    if first_share != 0.5:  # paying out: element 0's load, first_share of it on node 0 and the rest on node 1;
        # element 1's half and half, as the drum element's mass and its own are lumped
        shift = near[0] - first_share * (near[0] + far[0])
        shift[2] += (1.0 - centre[0] - first_share) * fb[0]
        f[0] -= shift
        f[1] += shift
        if len(x) > 2:
            shift = near[1] - 0.5 * (near[1] + far[1])
            f[1] -= shift
            f[2] += shift
    return f


def gauss_points(x: np.ndarray) -> np.ndarray:
    """Positions (m), shape (2, n, 3), of the Gauss points of the elements of the node polyline
    ``x`` (n+1, 3)."""
    return np.stack([x[:-1] + s * (x[1:] - x[:-1]) for s in GAUSS_POINTS])


def wave_inertia(x: np.ndarray, rest, area, diameter, surface: np.ndarray, rho: np.ndarray,
                 acceleration: np.ndarray, added_normal, added_axial) -> np.ndarray:
    """The waves' inertia loads on the nodes (N, world, shape (n+1, 3)): Morison's inertia term
    with C_m = 1 + C_a, i.e. the Froude-Krylov force rho A l a on the displaced volume plus the
    added mass's share rho A_a l a, split into the fluid acceleration's normal and axial parts:
    rho l_wet (A a + A_an a_n + A_at a_t) at each Gauss point for half the element, shared to its
    nodes by the lever rule (as the drag). ``rest`` l (m), ``area`` the displaced area per metre
    A (m^2), ``diameter`` (m), ``added_normal`` / ``added_axial`` the added mass's area per metre
    normal to and along the element (m^2: C_a pi d^2 / 4, plus floats' C_a V per metre; what
    the model's added mass holds, so that the load and the inertia agree), one per element (n,);
    ``surface`` the water surface's height over each element (m), ``rho`` (2, n) the density and
    ``acceleration`` (2, n, 3) the fluid's local acceleration (m/s^2) at the Gauss points."""
    _, _, t = element_geometry(x)
    frac, _ = wet_fraction(x[:-1, 2] - surface, x[1:, 2] - surface, section_half_height(diameter, t))
    f = np.zeros_like(x)
    for g, s in enumerate(GAUSS_POINTS):
        a = acceleration[g]
        axial = np.einsum("ij,ij->i", a, t)[:, None] * t
        m = (0.5 * rho[g] * np.asarray(rest) * frac)[:, None]  # kg per m^2 of area
        load = m * (np.asarray(area)[:, None] * a + np.asarray(added_normal)[:, None] * (a - axial)
                    + np.asarray(added_axial)[:, None] * axial)
        f[:-1] += (1.0 - s) * load
        f[1:] += s * load
    return f


def bending_forces(x: np.ndarray, EI: float, segment_length: float) -> np.ndarray:
    """Node forces (N) from the discrete bending energy sum_i (EI / l) (1 - t_{i-1} . t_i).

    For small angles this is EI theta^2 / (2 l), the energy of a beam of curvature theta / l
    over a length l.
    """
    f = np.zeros_like(x)
    if np.all(np.asarray(EI) <= 0.0) or len(x) < 3:
        return f
    _, length, t = element_geometry(x)
    k = EI / segment_length
    if np.ndim(k):  # one per joint (a line make-up): as a column
        k = np.asarray(k)[:, None]
    a, b = t[:-1], t[1:]
    la, lb = length[:-1, None], length[1:, None]
    cos = np.einsum("ij,ij->i", a, b)[:, None]
    # dE/de_a = -k (b - (a.b) a) / |e_a| ; dE/de_b = -k (a - (a.b) b) / |e_b|
    ga = -k * (b - cos * a) / la
    gb = -k * (a - cos * b) / lb
    # e_j = x_{j+1} - x_j: force = -dE/dx
    f[:-2] += ga
    f[1:-1] -= ga
    f[1:-1] += gb
    f[2:] -= gb
    return f


def rigid_body_loads(
    R: np.ndarray,
    p_cob: np.ndarray,
    v_cob: np.ndarray,
    omega: np.ndarray,
    *,
    volume: float,
    height: float,
    drag_cd: np.ndarray,
    drag_area: np.ndarray,
    angular_drag: np.ndarray,
    rho_fn,
    current_fn,
    gravity: float = 9.81,
):
    """Force (N) at the centre of buoyancy and torque (N m), world frame, on one rigid body.

    Args:
        R: body orientation (3x3, body to world).
        p_cob, v_cob: world position (m) and velocity (m/s) of the centre of buoyancy.
        omega: angular velocity (rad/s, world frame).
        volume: displaced volume V (m^3) when fully submerged.
        height: vertical extent (m) over which the body crosses the surface (partial
            submersion is linear in the height of the centre of buoyancy over that band).
        drag_cd, drag_area: C_d and projected area S (m^2) per body axis x, y, z.
        angular_drag: c_k (N m s^2) per body axis, M_k = -c_k |w_k| w_k.
    """
    z = min(float(p_cob[2]), 0.0)
    frac = min(max(0.5 - p_cob[2] / height, 0.0), 1.0) if height > 0 else float(p_cob[2] <= 0)
    zz = np.array([z])
    rho = float(rho_fn(zz)[0])
    u = current_fn(zz)[0]
    vrel_b = (u - v_cob) @ R  # R^T (u - v)
    f_b = (0.5 * rho * frac) * drag_cd * drag_area * np.abs(vrel_b) * vrel_b
    force = R @ f_b
    force[2] += rho * gravity * volume * frac
    w_b = omega @ R
    torque = R @ (-frac * angular_drag * np.abs(w_b) * w_b)
    return force, torque

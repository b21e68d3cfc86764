"""Compiled twins (numba) of the per-step force kernels, and which kernels a run uses.

The NumPy kernels (``hydro.tether_loads``, ``hydro.bending_forces``, ``cable.seabed.seabed_friction``,
the profiles of ``water``, the rigid-body and vehicle loads) are the reference: they state the
physics, and the tests check that these compiled loops give the same numbers to 1e-12 relative
(``tests/physics/test_compiled.py``; the native callback that calls the force kernels inside
MuJoCo: ``native``, ``tests/physics/test_native.py``). The other compiled twins live beside the
code they twin, built with ``jit`` from here: the steady march (``quasistatic.kernels``), the
cable's per-step bookkeeping (``cable.kernels``) and the walker's gait (``walker.tripod_targets``).
The loops exist for speed only: on a 200-element cable a NumPy kernel spends about 100 us per
step in the overhead of some sixty small array operations, as much as MuJoCo's own step.

The water profiles are compiled by kind (constant, linear, exponential, power-law and tabulated
current; constant, linear and tabulated density: the classes of ``water``, not subclasses of
them); a profile of any other class is evaluated by its own NumPy code and passed in.

Which kernels run: the environment variable ``MJTETHER_KERNELS`` = ``numba`` (the default,
where numba imports) or ``numpy`` (the reference; also what runs where numba is missing).
numba caches the machine code beside this file (or in its user cache when the package folder is
read-only), keyed on the source of every kernel of the package (``jitcache``: a change to any
kernel recompiles them all, so a cached kernel never runs code that is no longer there), so only
the first run after an install or an update pays the compile time.

Units SI, world frame, as in the NumPy kernels.
"""

from __future__ import annotations

import math
import os

import numpy as np

from mjtether.physics import jitcache
from mjtether.physics import water as _water
from mjtether.physics.hydro import GAUSS  # (an element's Gauss points lie at 1/2 -+ GAUSS of its length)

try:  # numba is a dependency; the NumPy kernels still run where it cannot be imported
    import numba
except ImportError:  # pragma: no cover - exercised only without numba
    numba = None

KERNELS_ENV = "MJTETHER_KERNELS"


def backend() -> str:
    """The kernels a simulation created now uses: "numba" or "numpy" (see the module doc)."""
    want = os.environ.get(KERNELS_ENV, "numba").strip().lower() or "numba"
    if want not in ("numba", "numpy"):
        raise ValueError(f"{KERNELS_ENV} must be 'numba' or 'numpy', got {want!r}")
    return "numba" if want == "numba" and numba is not None else "numpy"


def jit(fn=None, *, fma: bool = False):
    """numba's ``njit`` as every kernel of the package is compiled (cached, no GIL, NumPy's
    error model), or ``fn`` itself where numba is missing. ``fma``: let LLVM fuse a multiply and
    the add that takes its product into one fused multiply-add, rounded once instead of twice
    (numba's ``fastmath={"contract"}`` alone: no reassociation, no change to NaN, infinity or
    signed-zero handling); for the polynomial-heavy sea kernels, where it cuts a third of the time
    and moves the answers by rounding (measured 2e-14 of the largest value against the NumPy
    reference, ``waves.state_kernel``). ``@jit`` and ``@jit(fma=True)`` both work."""
    if fn is None:
        return lambda f: jit(f, fma=fma)
    if numba is None:
        return fn
    return numba.njit(cache=jitcache.CACHE, nogil=True, error_model="numpy",
                      fastmath={"contract"} if fma else False)(fn)


# --------------------------------------------------------------------------- water profiles

DENSITY_CONSTANT, DENSITY_LINEAR, DENSITY_TABLE = 0, 1, 2
CURRENT_CONSTANT, CURRENT_LINEAR, CURRENT_EXPONENTIAL, CURRENT_POWER, CURRENT_TABLE = 0, 1, 2, 3, 4


def profile_codes(water) -> tuple[int, np.ndarray, int, np.ndarray] | None:
    """(density kind, its parameters, current kind, its parameters) of ``water`` for the compiled
    kernels, or None if a profile is of a class they do not know (it is then evaluated in NumPy)."""
    d, c = water.density, water.current
    if type(d) is _water.ConstantDensity:
        dk, dp = DENSITY_CONSTANT, [d.rho]
    elif type(d) is _water.LinearDensity:
        dk, dp = DENSITY_LINEAR, [d.rho_surface, (d.rho_ref - d.rho_surface) / d.depth_ref]
    elif type(d) is _water.TabulatedDensity:
        dk, dp = DENSITY_TABLE, np.r_[d.depths, d.rho]
    else:
        return None
    if type(c) is _water.ConstantCurrent:
        ck, cp = CURRENT_CONSTANT, [c.speed, c.heading]
    elif type(c) is _water.LinearCurrent:
        ck, cp = CURRENT_LINEAR, [c.surface_speed, c.bottom_speed, c.depth_ref, c.heading]
    elif type(c) is _water.ExponentialCurrent:
        ck, cp = CURRENT_EXPONENTIAL, [c.surface_speed, c.decay_depth, c.heading]
    elif type(c) is _water.PowerLawCurrent:
        ck, cp = CURRENT_POWER, [c.surface_speed, c.seabed_depth, c.exponent, c.heading]
    elif type(c) is _water.TabulatedCurrent:
        ck, cp = CURRENT_TABLE, np.r_[c.depths, c._ux, c._uy]
    else:
        return None
    return dk, np.asarray(dp, dtype=float), ck, np.asarray(cp, dtype=float)


@jit
def _interp(x, xp, fp):
    """``np.interp(x, xp, fp)`` for one number ``x`` (``xp`` increasing), by the same formula
    (slope (x - xp_j) + fp_j; NaN gives NaN), without the allocation of numba's ``np.interp``."""
    n = xp.shape[0]
    if x < xp[0]:
        return fp[0]
    if x >= xp[n - 1]:
        return fp[n - 1]
    lo, hi = 0, n - 1  # xp[lo] <= x < xp[hi]
    while hi - lo > 1:
        mid = (lo + hi) >> 1
        if xp[mid] <= x:
            lo = mid
        else:
            hi = mid
    slope = (fp[lo + 1] - fp[lo]) / (xp[lo + 1] - xp[lo])
    return slope * (x - xp[lo]) + fp[lo]


@jit
def _density(kind, p, depth):
    """Density (kg/m^3) at ``depth`` (m, >= 0): ``water``'s profiles."""
    if kind == 0:
        return p[0]
    if kind == 1:
        return p[0] + p[1] * depth
    n = p.shape[0] // 2
    return _interp(depth, p[:n], p[n:])


@jit
def _speed(kind, p, depth):
    """Current speed (m/s) at ``depth`` (m, >= 0) of the profiles of one heading: ``water``'s
    constant (0), linear (1), exponential (2) and power-law (3) profiles."""
    if kind == 0:
        return p[0]
    if kind == 1:
        return p[0] + (p[1] - p[0]) * min(depth / p[2], 1.0)
    if kind == 2:
        return p[0] * math.exp(-depth / p[1])
    return p[0] * min(max((p[1] - depth) / p[1], 0.0), 1.0) ** p[2]


@jit
def _disk_wet(c):
    """``hydro._disk_wet`` of one c: (F, G, H)."""
    cc = min(max(c, -1.0), 1.0)
    s = math.sqrt(1.0 - cc * cc)
    a, b = math.acos(cc), math.asin(cc)
    F = (math.pi - a + cc * s) / math.pi
    G = (math.pi * cc - cc * a + s - s * s * s / 3.0) / math.pi + max(c - 1.0, 0.0)
    H = ((math.pi * cc * cc / 2.0 - cc * cc * a / 2.0 - (b - cc * s) / 4.0
          + (cc * (2.0 * cc * cc - 1.0) * s + b) / 8.0) / math.pi + (max(c, 1.0) ** 2 - 1.0) / 2.0)
    return F, G, H


@jit
def _wet_fraction(z0, z1, h):
    """``hydro.wet_fraction`` of one element with axis end heights ``z0``, ``z1`` (m) and its
    cross-section's vertical half-height ``h`` (m; 0: by the axis alone): (its submerged
    fraction, the centre of its wet part, 0 at node i to 1 at node i+1)."""
    if z0 + h <= 0.0 and z1 + h <= 0.0:
        return 1.0, 0.5
    if h > 1e-9:
        if z0 - h >= 0.0 and z1 - h >= 0.0:
            return 0.0, 0.5
        c0, c1 = -z0 / h, -z1 / h
        dc = c1 - c0
        if abs(dc) < 1e-4:  # (hydro._cut_element)
            cm = 0.5 * (c0 + c1)
            F = _disk_wet(cm)[0]
            if F <= 0.0:
                return 0.0, 0.5
            slope = 2.0 * math.sqrt(max(1.0 - cm * cm, 0.0)) / math.pi
            return F, min(max(0.5 + dc * slope / (12.0 * F), 0.0), 1.0)
        F0, G0, H0 = _disk_wet(c0)
        F1, G1, H1 = _disk_wet(c1)
        G = G1 - G0
        if G == 0.0:
            return 0.0, 0.5
        return min(max(G / dc, 0.0), 1.0), min(max(((H1 - H0) - c0 * G) / (dc * G), 0.0), 1.0)
    lo, hi = min(z0, z1), max(z0, z1)
    span = hi - lo
    if span > 1e-12:
        frac = min(max(-lo / span, 0.0), 1.0)
    else:
        frac = 1.0 if lo <= 0.0 else 0.0
    return frac, (0.5 * frac if z0 <= z1 else 1.0 - 0.5 * frac)


@jit
def _current(ckind, cp, depth):
    """Horizontal current (u_x, u_y), m/s, at ``depth`` (m, >= 0): ``water``'s profiles (the
    tabulated one by components, the others as a speed along their heading)."""
    if ckind == 4:
        m = cp.shape[0] // 3
        return _interp(depth, cp[:m], cp[m:2 * m]), _interp(depth, cp[:m], cp[2 * m:])
    speed = _speed(ckind, cp, depth)
    return speed * math.cos(cp[cp.shape[0] - 1]), speed * math.sin(cp[cp.shape[0] - 1])


@jit
def element_water(x, dkind, dp, ckind, cp, rho, u):
    """Density ``rho`` (2n,) and current ``u`` (2n, 3) at the two Gauss points of each element
    of the node polyline ``x`` (n+1, 3) (element i's at 2i and 2i + 1, ``GAUSS``), at or below the
    surface (as ``hydro.tether_loads`` takes them)."""
    n = x.shape[0] - 1
    if ckind == 4:
        m = cp.shape[0] // 3
    else:  # one heading: its direction once, the last two parameters
        cos, sin = math.cos(cp[cp.shape[0] - 1]), math.sin(cp[cp.shape[0] - 1])
    for i in range(n):
        for g in range(2):
            s = 0.5 - GAUSS if g == 0 else 0.5 + GAUSS
            k = 2 * i + g
            depth = max(-min(x[i, 2] + s * (x[i + 1, 2] - x[i, 2]), 0.0), 0.0)
            rho[k] = _density(dkind, dp, depth)
            if ckind == 4:
                u[k, 0] = _interp(depth, cp[:m], cp[m:2 * m])
                u[k, 1] = _interp(depth, cp[:m], cp[2 * m:])
            else:
                speed = _speed(ckind, cp, depth)
                u[k, 0] = speed * cos
                u[k, 1] = speed * sin
            u[k, 2] = 0.0


# --------------------------------------------------------------------------- tether


@jit
def tether_loads(x, v, rest, diameter, cd_normal, cd_tangential, area, cd_area_float, rho, u, gravity,
                 first_share, f, surface):
    """``hydro.tether_loads`` into ``f`` (n+1, 3), N: every element property given per element
    (n,): rest length l (m), diameter d (m), C_dn, C_dt, displaced area per metre (m^2) and the
    floats' extra normal drag area per metre (m^2/m); ``rho`` (2n,) and ``u`` (2n, 3) at the
    elements' Gauss points (``element_water``, the waves' particle velocity added where there are
    waves); ``surface`` (n,): the water surface's height over each element (m; zeros: the mean
    water line)."""
    n = x.shape[0] - 1
    near = np.zeros((n, 3))  # (each element's drag on node i, and on node i + 1: the lever rule)
    far = np.zeros((n, 3))
    fb = np.empty(n)
    centre = np.empty(n)
    t = np.empty(3)
    vrel = np.empty(3)
    for i in range(n):
        for j in range(3):
            t[j] = x[i + 1, j] - x[i, j]
        length = math.sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
        inv = 1.0 / max(length, 1e-12)
        for j in range(3):
            t[j] *= inv
        # the submerged fraction and the centre of the wet part (hydro.wet_fraction)
        h = 0.5 * diameter[i] * math.sqrt(max(1.0 - t[2] * t[2], 0.0))
        frac, centre[i] = _wet_fraction(x[i, 2] - surface[i], x[i + 1, 2] - surface[i], h)
        for g in range(2):  # (the drag at its two Gauss points, each for half its length)
            s = 0.5 - GAUSS if g == 0 else 0.5 + GAUSS
            k = 2 * i + g
            for j in range(3):
                vrel[j] = u[k, j] - ((1.0 - s) * v[i, j] + s * v[i + 1, j])
            vt_mag = vrel[0] * t[0] + vrel[1] * t[1] + vrel[2] * t[2]
            vn0 = vrel[0] - vt_mag * t[0]
            vn1 = vrel[1] - vt_mag * t[1]
            vn2 = vrel[2] - vt_mag * t[2]
            vn_mag = math.sqrt(vn0 * vn0 + vn1 * vn1 + vn2 * vn2)
            q = (0.25 * rest[i] * diameter[i]) * rho[k] * frac
            kn = q * (cd_normal[i] + cd_area_float[i] / diameter[i]) * vn_mag
            kt = q * math.pi * cd_tangential[i] * abs(vt_mag)
            d0 = vn0 * kn + vt_mag * t[0] * kt
            d1 = vn1 * kn + vt_mag * t[1] * kt
            d2 = vn2 * kn + vt_mag * t[2] * kt
            near[i, 0] += (1.0 - s) * d0
            near[i, 1] += (1.0 - s) * d1
            near[i, 2] += (1.0 - s) * d2
            far[i, 0] += s * d0
            far[i, 1] += s * d1
            far[i, 2] += s * d2
        fb[i] = (gravity * area[i] * rest[i]) * (0.5 * (rho[2 * i] + rho[2 * i + 1])) * frac
    for j in range(3):
        f[n, j] = 0.0
    for i in range(n):
        for j in range(3):
            f[i, j] = near[i, j]
    for i in range(n):
        for j in range(3):
            f[i + 1, j] += far[i, j]
    for i in range(n):
        f[i, 2] += (1.0 - centre[i]) * fb[i]
    for i in range(n):
        f[i + 1, 2] += centre[i] * fb[i]
    if first_share != 0.5 and n > 0:  # paying out: element 0's load, first_share of it on node 0, the rest on
        # node 1; element 1's half and half (hydro.tether_loads)
        for j in range(3):
            s = near[0, j] - first_share * (near[0, j] + far[0, j])
            if j == 2:
                s += (1.0 - centre[0] - first_share) * fb[0]
            f[0, j] -= s
            f[1, j] += s
        if n > 1:
            for j in range(3):
                s = near[1, j] - 0.5 * (near[1, j] + far[1, j])
                f[1, j] -= s
                f[2, j] += s


@jit
def add_bending_forces(x, k, f):
    """``hydro.bending_forces`` added into ``f`` (n+1, 3), N, with ``k`` (n-1,) = EI / l of each
    joint (N m)."""
    n = x.shape[0] - 1
    if n < 2:
        return
    t = np.empty((n, 3))
    length = np.empty(n)
    for i in range(n):
        e0, e1, e2 = x[i + 1, 0] - x[i, 0], x[i + 1, 1] - x[i, 1], x[i + 1, 2] - x[i, 2]
        length[i] = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        inv = 1.0 / max(length[i], 1e-12)
        t[i, 0], t[i, 1], t[i, 2] = e0 * inv, e1 * inv, e2 * inv
    for i in range(n - 1):  # the joint at node i+1, between elements i (a) and i+1 (b)
        cos = t[i, 0] * t[i + 1, 0] + t[i, 1] * t[i + 1, 1] + t[i, 2] * t[i + 1, 2]
        for j in range(3):
            ga = -k[i] * (t[i + 1, j] - cos * t[i, j]) / length[i]
            gb = -k[i] * (t[i, j] - cos * t[i + 1, j]) / length[i + 1]
            f[i, j] += ga
            f[i + 1, j] += gb - ga
            f[i + 2, j] -= gb


@jit
def add_wave_inertia(x, rest, area, diameter, surface, rho, acceleration, added_normal, added_axial, f):
    """``hydro.wave_inertia`` added into ``f`` (n+1, 3), N: the waves' Froude-Krylov plus
    added-mass load, per element (n,) its rest length (m), displaced area per metre (m^2),
    diameter (m), the surface's height over it (m) and the added mass's area per metre normal to
    and along it (m^2); ``rho`` (2n,) and the fluid's local ``acceleration`` (2n, 3), m/s^2, at
    the Gauss points (element i's at 2i and 2i + 1, as ``element_water``)."""
    n = x.shape[0] - 1
    t = np.empty(3)
    for i in range(n):
        for j in range(3):
            t[j] = x[i + 1, j] - x[i, j]
        inv = 1.0 / max(math.sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]), 1e-12)
        for j in range(3):
            t[j] *= inv
        h = 0.5 * diameter[i] * math.sqrt(max(1.0 - t[2] * t[2], 0.0))
        frac = _wet_fraction(x[i, 2] - surface[i], x[i + 1, 2] - surface[i], h)[0]
        for g in range(2):
            s = 0.5 - GAUSS if g == 0 else 0.5 + GAUSS
            k = 2 * i + g
            at = acceleration[k, 0] * t[0] + acceleration[k, 1] * t[1] + acceleration[k, 2] * t[2]
            mass = 0.5 * rho[k] * rest[i] * frac  # kg per m^2 of area
            for j in range(3):
                axial = at * t[j]
                load = mass * (area[i] * acceleration[k, j] + added_normal[i] * (acceleration[k, j] - axial)
                               + added_axial[i] * axial)
                f[i, j] += (1.0 - s) * load
                f[i + 1, j] += s * load


# --------------------------------------------------------------------------- seabed friction


@jit
def seabed_friction(x, v, stick, point, normal, radius, normal_force, mu, stiffness, damping, tolerance, force,
                    new):
    """``seabed.seabed_friction`` into ``force`` (n, 3), N, and the new stick points ``new``
    (n, 3), NaN off the seabed; ``tolerance`` is ``seabed.CONTACT_TOLERANCE``."""
    n = x.shape[0]
    xt = np.empty(3)
    s = np.empty(3)
    fv = np.empty(3)
    for i in range(n):
        height = (x[i, 0] - point[0]) * normal[0] + (x[i, 1] - point[1]) * normal[1] \
            + (x[i, 2] - point[2]) * normal[2]
        if not (height <= (1.0 + 2.0 * tolerance) * radius and normal_force[i] > 0.0):
            for j in range(3):
                force[i, j] = 0.0
                new[i, j] = np.nan
            continue
        vn = v[i, 0] * normal[0] + v[i, 1] * normal[1] + v[i, 2] * normal[2]
        fresh = math.isnan(stick[i, 0]) or math.isnan(stick[i, 1]) or math.isnan(stick[i, 2])
        for j in range(3):
            xt[j] = x[i, j] - height * normal[j]  # the node's foot on the seabed
            s[j] = xt[j] if fresh else stick[i, j]  # a node that lands sticks where it lands
            fv[j] = stiffness[i] * (s[j] - xt[j])
        limit = mu * normal_force[i]
        scale = min(1.0, limit / max(math.sqrt(fv[0] * fv[0] + fv[1] * fv[1] + fv[2] * fv[2]), 1e-300))
        for j in range(3):  # beyond the limit the stick point is dragged along: the spring stays at mu N
            new[i, j] = xt[j] + (s[j] - xt[j]) * scale
            fv[j] = fv[j] * scale - damping[i] * (v[i, j] - vn * normal[j])
        scale = min(1.0, limit / max(math.sqrt(fv[0] * fv[0] + fv[1] * fv[1] + fv[2] * fv[2]), 1e-300))
        for j in range(3):
            force[i, j] = fv[j] * scale


# --------------------------------------------------------------------------- rigid bodies


@jit
def rigid_body_loads(R, p_cob, v_cob, omega, volume, height, drag_cd, drag_area, angular_drag, dkind, dp, ckind, cp,
                     gravity, force, torque):
    """``hydro.rigid_body_loads`` into ``force`` (3,), N, at the centre of buoyancy and ``torque``
    (3,), N m, world frame; the water profiles as codes (``profile_codes``): the still sea of
    ``rigid_body_wave_loads`` (no surface, particle velocity or acceleration: the same numbers
    bit for bit, x + 0 being x)."""
    still = np.zeros(3)
    rigid_body_wave_loads(R, p_cob, v_cob, omega, volume, height, drag_cd, drag_area, angular_drag, True, still,
                          dkind, dp, ckind, cp, gravity, 0.0, still, still, force, torque)


@jit
def rigid_body_wave_loads(R, p_cob, v_cob, omega, volume, height, drag_cd, drag_area, angular_drag, free, ma, dkind,
                          dp, ckind, cp, gravity, eta, uw, aw, force, torque):
    """``rigidbody.BoundBodyHydro.wave_loads`` into ``force`` (3,), N, at the centre of buoyancy and
    ``torque`` (3,), N m, world frame: the sea there given as the surface ``eta`` (m) over it, the
    particle velocity ``uw`` (m/s) and local acceleration ``aw`` (m/s^2); the added mass the model
    carries from the body's ``ma`` (3,), kg, as ``BoundBodyHydro.added_mass_world`` (``free``: a free joint's)."""
    added = np.zeros((3, 3))
    for i in range(3):
        if free:
            added[i, i] = 0.5 * (ma[0] + ma[1]) if i < 2 else ma[2]
        else:  # R diag(ma) R^T
            for j in range(3):
                added[i, j] = R[i, 0] * ma[0] * R[j, 0] + R[i, 1] * ma[1] * R[j, 1] + R[i, 2] * ma[2] * R[j, 2]
    depth = max(-min(p_cob[2], 0.0), 0.0)
    rise = p_cob[2] - eta  # the centre of buoyancy's height over the surface (m)
    if height > 0:
        frac = min(max(0.5 - rise / height, 0.0), 1.0)
    else:
        frac = 1.0 if rise <= 0 else 0.0
    rho = _density(dkind, dp, depth)
    u = np.empty(3)
    u[0], u[1] = _current(ckind, cp, depth)
    u[2] = 0.0
    fb, tb = np.empty(3), np.empty(3)
    for k in range(3):  # body axes: R^T (u + uw - v) and R^T omega
        vk = ((u[0] + uw[0]) - v_cob[0]) * R[0, k] + ((u[1] + uw[1]) - v_cob[1]) * R[1, k] + (
            (u[2] + uw[2]) - v_cob[2]) * R[2, k]
        wk = omega[0] * R[0, k] + omega[1] * R[1, k] + omega[2] * R[2, k]
        fb[k] = (0.5 * rho * frac) * drag_cd[k] * drag_area[k] * abs(vk) * vk
        tb[k] = -frac * angular_drag[k] * abs(wk) * wk
    for j in range(3):
        inertia = rho * volume * aw[j] + (added[j, 0] * aw[0] + added[j, 1] * aw[1] + added[j, 2] * aw[2])
        force[j] = R[j, 0] * fb[0] + R[j, 1] * fb[1] + R[j, 2] * fb[2] + frac * inertia
        torque[j] = R[j, 0] * tb[0] + R[j, 1] * tb[1] + R[j, 2] * tb[2]
    force[2] += rho * gravity * volume * frac


# --------------------------------------------------------------------------- vehicles


def vehicle_arrays(hydro, fins, propeller, r_g):
    """The parameters of ``vehicle_wrench`` from a ``VehicleHydro``, its fins, propeller and
    centre of gravity ``r_g`` (body frame): (zeroed-C_A mask (6, 6), hull (9,: present, L, D,
    axial Cd, cross-flow Cd, reference area, Oswald factor, strips, cross-flow sum: 0 the
    midpoint rule, 1 Fossen's), fins (k, 10), propeller (13,), surface (14,))."""
    keep = np.ones((6, 6))
    for i, j in hydro.coriolis_zeroed:
        keep[i, j] = 0.0
    h = hydro.hull
    hull = np.zeros(9) if h is None else np.array(
        [1.0, h.length, h.diameter, h.axial_cd, h.crossflow_cd, h.reference_area, h.oswald, h.strips,
         1.0 if h.crossflow == "fossen" else 0.0], dtype=float)
    fin = np.array([[*f.position, *f.lift_direction, f.area, f.cl_delta,
                     -1.0 if f.stall_angle is None else f.stall_angle, f.post_stall_lift] for f in fins],
                   dtype=float).reshape(-1, 10)
    p = propeller
    prop = np.zeros(13) if p is None else np.array(
        [1.0, *p.position, p.diameter, p.kt0, p.kt_max, p.ja_max, p.kq0, p.kq_max, p.thrust_deduction,
         p.wake_fraction, p.torque_scale], dtype=float)
    sf = hydro.surface
    surface = np.zeros(14) if sf is None else np.array(
        [1.0, sf.waterplane_area, sf.gm_t, sf.gm_l, sf.max_volume, *r_g, *sf.centre_of_flotation, sf.length,
         sf.draft, sf.crossflow_cd, sf.strips], dtype=float)
    return keep, hull, fin, prop, surface


@jit
def vehicle_wrench(nu, R, z, dkind, dp, ckind, cp, gravity, MA, keep, DL, fade, DQ, Mlin, volume, r_b, hull, fins,
                   deltas, prop, rpm, surface, z_origin, size, thr, thr_force, tau):
    """``vehicle.BoundVehicle``'s explicit wrench (body frame, N and N m about the origin) into
    ``tau`` (6,): -C_A(nu_r) nu_r (``keep``: 0 where an entry is left out), -D(nu_r) nu_r (rows of
    D_L faded by exp(-fade U_r)), M_A (omega x nu_r), the buoyancy at r_b, the hull's lift and
    drag, the fins' and the propeller's (``vehicle_arrays``), or a surface vessel's hydrostatics
    at its origin's height ``z_origin`` (m) in place of the buoyancy; the water at height ``z``
    (m, <= 0) as codes (``profile_codes``). A submerged vehicle at the surface (``wet_fraction``
    of its hull of semi-axes ``size``, m) keeps that fraction of its buoyancy, added-mass and
    damping forces and hull loads; a fin, the propeller or a thruster (rows of ``thr``: body
    position, direction; its thrust now ``thr_force``, N, which MuJoCo applies) above the water
    gives nothing (the thruster's is taken back). The NumPy reference: ``BoundVehicle.wrench``."""
    depth = max(-z, 0.0)
    rho = _density(dkind, dp, depth)
    u = np.zeros(3)
    u[0], u[1] = _current(ckind, cp, depth)
    nr = np.empty(6)
    for k in range(3):
        nr[k] = nu[k] - (R[0, k] * u[0] + R[1, k] * u[1] + R[2, k] * u[2])
        nr[3 + k] = nu[3 + k]
    # C_A(nu_r) of the symmetric part of M_A (fossen.m2c), entries left out where keep = 0
    h = np.zeros(6)
    for i in range(6):
        for j in range(6):
            h[i] += 0.5 * (MA[i, j] + MA[j, i]) * nr[j]
    C = np.zeros((6, 6))
    for (r0, c0, a) in ((0, 3, 0), (3, 0, 0), (3, 3, 3)):  # -S(h1), -S(h1), -S(h2)
        C[r0 + 0, c0 + 1] = h[a + 2]
        C[r0 + 0, c0 + 2] = -h[a + 1]
        C[r0 + 1, c0 + 0] = -h[a + 2]
        C[r0 + 1, c0 + 2] = h[a + 0]
        C[r0 + 2, c0 + 0] = h[a + 1]
        C[r0 + 2, c0 + 1] = -h[a + 0]
    U = math.sqrt(nr[0] * nr[0] + nr[1] * nr[1] + nr[2] * nr[2])
    for i in range(6):
        s = 0.0
        f = math.exp(-fade[i] * U)
        for j in range(6):
            s += C[i, j] * keep[i, j] * nr[j] + f * DL[i, j] * nr[j]
        tau[i] = -s - DQ[i] * abs(nr[i]) * nr[i]
    # M_A (omega x nu_r) on the linear block
    c0 = nu[4] * nr[2] - nu[5] * nr[1]
    c1 = nu[5] * nr[0] - nu[3] * nr[2]
    c2 = nu[3] * nr[1] - nu[4] * nr[0]
    for i in range(3):
        tau[i] += Mlin[i, 0] * c0 + Mlin[i, 1] * c1 + Mlin[i, 2] * c2
    wet = 1.0
    if surface[0] == 0.0:  # a submerged vehicle: what of it is under the water
        wet = wet_fraction(R, z_origin, r_b, size)
        for i in range(6):
            tau[i] *= wet
    if surface[0] > 0.0:  # fossen.surface_restoring: buoyancy through the centre of gravity, its
        # change at the centre of flotation, righting moments; Surface.crossflow
        xf, yf = surface[8], surface[9]
        Vs = min(max(volume - surface[1] * (z_origin + R[2, 0] * xf + R[2, 1] * yf), 0.0), surface[4])
        B = rho * gravity * Vs
        fb0, fb1, fb2 = R[2, 0] * B, R[2, 1] * B, R[2, 2] * B
        dB = rho * gravity * (Vs - volume)
        db0, db1, db2 = R[2, 0] * dB, R[2, 1] * dB, R[2, 2] * dB
        gx, gy, gz = surface[5], surface[6], surface[7]
        ax, ay = xf - gx, yf - gy
        k = rho * gravity * min(Vs, volume)
        roll = math.atan2(R[2, 1], R[2, 2])
        pitch = math.asin(max(-1.0, min(1.0, -R[2, 0])))
        tau[0] += fb0
        tau[1] += fb1
        tau[2] += fb2
        tau[3] += gy * fb2 - gz * fb1 - k * surface[2] * math.sin(roll) + ay * db2
        tau[4] += gz * fb0 - gx * fb2 - k * surface[3] * math.sin(pitch) - ax * db2
        tau[5] += gx * fb1 - gy * fb0 + ax * db1 - ay * db0
        if surface[12] > 0.0:
            L, T, strips = surface[10], surface[11], int(surface[13])
            dx = L / strips
            for i in range(strips):
                x = (i + 0.5) * dx - 0.5 * L
                vy = nr[1] + x * nr[5]
                kk = -0.5 * rho * T * surface[12] * dx * abs(vy)
                tau[1] += kk * vy
                tau[5] += x * kk * vy
    else:  # buoyancy at r_b (the weight is MuJoCo's), of the part under the water
        B = rho * gravity * volume * wet
        fb0, fb1, fb2 = R[2, 0] * B, R[2, 1] * B, R[2, 2] * B
        tau[0] += fb0
        tau[1] += fb1
        tau[2] += fb2
        tau[3] += r_b[1] * fb2 - r_b[2] * fb1
        tau[4] += r_b[2] * fb0 - r_b[0] * fb2
        tau[5] += r_b[0] * fb1 - r_b[1] * fb0
    if hull[0] > 0.0:  # fossen.lift_drag and fossen.crossflow_drag (or crossflow_drag_fossen)
        L, D, cd2d, area, oswald, strips = hull[1], hull[2], hull[4], hull[5], hull[6], int(hull[7])
        cd0 = hull[3] * math.pi * D * D / 4.0 / area
        hx = math.hypot(nr[0], nr[2])
        if hx > 0.0:
            alpha = math.atan2(nr[2], abs(nr[0]))
            AR = D * D / area
            CL = math.pi * AR / (1.0 + math.sqrt(1.0 + (AR / 2.0) ** 2)) * alpha
            CD = cd0 + CL * CL / (math.pi * oswald * AR)
            q = 0.5 * rho * U * U * area * wet
            lift, drag = q * CL, q * CD
            sgn = 1.0 if nr[0] >= 0.0 else -1.0
            tau[0] += -drag * nr[0] / hx + lift * sgn * math.sin(alpha)
            tau[2] += -drag * nr[2] / hx - lift * math.cos(alpha)
        dx = L / strips
        if hull[8] > 0.0:  # Fossen's sum: strips + 1 points from tail to nose, sway and yaw
            for k in range(strips + 1):
                x = k * dx - 0.5 * L
                vy = nr[1] + x * nr[5]
                kk = -0.5 * rho * D * cd2d * dx * abs(vy) * wet
                tau[1] += kk * vy
                tau[5] += x * kk * vy
        else:  # the midpoint rule of the strip integral, along each strip's cross-flow
            for k in range(strips):
                x = (k + 0.5) * dx - 0.5 * L
                vy = nr[1] + x * nr[5]
                vz = nr[2] - x * nr[4]
                kk = -0.5 * rho * D * cd2d * dx * math.hypot(vy, vz) * wet
                tau[1] += kk * vy
                tau[2] += kk * vz
                tau[4] -= x * kk * vz
                tau[5] += x * kk * vy
    for k in range(fins.shape[0]):  # fins.fin_wrench
        px, py, pz = fins[k, 0], fins[k, 1], fins[k, 2]
        lx, ly, lz = fins[k, 3], fins[k, 4], fins[k, 5]
        sdot = -lz * nr[1] + ly * nr[2]  # the span (0, -lz, ly) . v
        U2 = nr[0] * nr[0] + nr[1] * nr[1] + nr[2] * nr[2] - sdot * sdot
        q = 0.5 * rho * U2 * fins[k, 6]
        if surface[0] == 0.0 and z_origin + R[2, 0] * px + R[2, 1] * py + R[2, 2] * pz > 0.0:
            q = 0.0  # (a fin in the air)
        d = deltas[k]
        stall = fins[k, 8]
        if stall < 0.0 or abs(d) <= stall:
            cl = fins[k, 7] * d
        else:
            cl = math.copysign(fins[k, 7] * stall * fins[k, 9], d)
        fx = q * cl * lx - math.copysign(q * fins[k, 7] * d * d, nr[0])
        fy = q * cl * ly
        fz = q * cl * lz
        tau[0] += fx
        tau[1] += fy
        tau[2] += fz
        tau[3] += py * fz - pz * fy
        tau[4] += pz * fx - px * fz
        tau[5] += px * fy - py * fx
    if prop[0] > 0.0:  # propeller.Propeller.thrust
        n = rpm / 60.0
        D = prop[4]
        if n > 0.0:
            j = (1.0 - prop[11]) * nr[0] / D * abs(n) / prop[7]
            T = rho * D ** 4 * (prop[5] * n * n + (prop[6] - prop[5]) * j)
            Q = rho * D ** 5 * (prop[8] * n * n + (prop[9] - prop[8]) * j)
        else:
            T = rho * D ** 4 * prop[5] * abs(n) * n
            Q = rho * D ** 5 * prop[8] * abs(n) * n
        thrust = (1.0 - prop[10]) * T
        if surface[0] == 0.0 and z_origin + R[2, 0] * prop[1] + R[2, 1] * prop[2] + R[2, 2] * prop[3] > 0.0:
            thrust, Q = 0.0, 0.0  # (a propeller in the air)
        tau[0] += thrust
        tau[3] += prop[12] * Q
        tau[4] += prop[3] * thrust
        tau[5] -= prop[2] * thrust
    if surface[0] == 0.0:
        for k in range(thr.shape[0]):  # a thruster in the air: MuJoCo's thrust taken back
            px, py, pz = thr[k, 0], thr[k, 1], thr[k, 2]
            if z_origin + R[2, 0] * px + R[2, 1] * py + R[2, 2] * pz > 0.0:
                fx, fy, fz = thr_force[k] * thr[k, 3], thr_force[k] * thr[k, 4], thr_force[k] * thr[k, 5]
                tau[0] -= fx
                tau[1] -= fy
                tau[2] -= fz
                tau[3] -= py * fz - pz * fy
                tau[4] -= pz * fx - px * fz
                tau[5] -= px * fy - py * fx


@jit
def wet_fraction(R, z_origin, r_b, size):
    """The fraction (0 to 1) of a submerged vehicle's hull under the water: its centre of
    buoyancy (``r_b``, body frame) at height z_b and its vertical extent h = 2 sqrt(sum_k
    (R_zk a_k)^2) (the ellipsoid of semi-axes ``size``, m, turned by ``R``), taken linear in
    between: clip(1/2 - z_b / h, 0, 1)."""
    zb = z_origin + R[2, 0] * r_b[0] + R[2, 1] * r_b[1] + R[2, 2] * r_b[2]
    h = 2.0 * math.sqrt((R[2, 0] * size[0]) ** 2 + (R[2, 1] * size[1]) ** 2 + (R[2, 2] * size[2]) ** 2)
    if h <= 0.0:
        return 1.0 if zb <= 0.0 else 0.0
    return min(max(0.5 - zb / h, 0.0), 1.0)

"""Compiled twins (numba) of the per-step force kernels, the steady march and the per-step
bookkeeping, and which kernels a run uses.

The NumPy kernels (``hydro.tether_loads``, ``hydro.bending_forces``, ``seabed.seabed_friction``,
the profiles of ``water``, ``quasistatic.steady``'s march and hang, ``walker.leg_ik`` and
``simulation.BoundTether.update_slack``) are the reference: they state the physics, and the
tests check that these compiled loops give the same numbers to 1e-12 relative
(``tests/test_compiled.py``, ``tests/test_walker.py``; the native callback that calls the force
kernels inside MuJoCo: ``native``, ``tests/test_native.py``).
The loops exist for speed only: on a 200-element cable a NumPy kernel spends about 100 us per
step in the overhead of some sixty small array operations, as much as MuJoCo's own step.

The water profiles are compiled by kind (constant, linear, exponential, power-law and tabulated
current; constant, linear and tabulated density: the classes of ``water``, not subclasses of
them); a profile of any other class is evaluated by its own NumPy code and passed in.

Which kernels run: the environment variable ``MJTETHER_KERNELS`` = ``numba`` (the default,
where numba imports) or ``numpy`` (the reference; also what runs where numba is missing).
numba caches the machine code beside this file (or in its user cache when the package folder is
read-only), so only the first run on a machine pays the compile time (a few seconds).

Units SI, world frame, as in the NumPy kernels.
"""

from __future__ import annotations

import math
import os

import numpy as np

from . import water as _water

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


def _jit(fn):
    return fn if numba is None else numba.njit(cache=True, nogil=True, error_model="numpy")(fn)


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


@_jit
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


@_jit
def _density(kind, p, depth):
    """Density (kg/m^3) at ``depth`` (m, >= 0): ``water``'s profiles."""
    if kind == 0:
        return p[0]
    if kind == 1:
        return p[0] + p[1] * depth
    n = p.shape[0] // 2
    return _interp(depth, p[:n], p[n:])


@_jit
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


@_jit
def _wet_fraction(z0, z1):
    """``hydro.wet_fraction`` of one element with end heights ``z0``, ``z1`` (m): its submerged
    fraction."""
    lo, hi = min(z0, z1), max(z0, z1)
    span = hi - lo
    if span > 1e-12:
        return min(max(-lo / span, 0.0), 1.0)
    return 1.0 if lo <= 0.0 else 0.0


@_jit
def _current(ckind, cp, depth):
    """Horizontal current (u_x, u_y), m/s, at ``depth`` (m, >= 0): ``water``'s profiles (the
    tabulated one by components, the others as a speed along their heading)."""
    if ckind == 4:
        m = cp.shape[0] // 3
        return _interp(depth, cp[:m], cp[m:2 * m]), _interp(depth, cp[:m], cp[2 * m:])
    speed = _speed(ckind, cp, depth)
    return speed * math.cos(cp[cp.shape[0] - 1]), speed * math.sin(cp[cp.shape[0] - 1])


@_jit
def element_water(x, dkind, dp, ckind, cp, rho, u):
    """Density ``rho`` (n,) and current ``u`` (n, 3) at the centres of the elements of the node
    polyline ``x`` (n+1, 3), at or below the surface (as ``hydro.tether_loads`` takes them)."""
    n = x.shape[0] - 1
    if ckind == 4:
        m = cp.shape[0] // 3
    else:  # one heading: its direction once, the last two parameters
        cos, sin = math.cos(cp[cp.shape[0] - 1]), math.sin(cp[cp.shape[0] - 1])
    for i in range(n):
        depth = max(-min(0.5 * (x[i + 1, 2] + x[i, 2]), 0.0), 0.0)
        rho[i] = _density(dkind, dp, depth)
        if ckind == 4:
            u[i, 0] = _interp(depth, cp[:m], cp[m:2 * m])
            u[i, 1] = _interp(depth, cp[:m], cp[2 * m:])
        else:
            speed = _speed(ckind, cp, depth)
            u[i, 0] = speed * cos
            u[i, 1] = speed * sin
        u[i, 2] = 0.0


# --------------------------------------------------------------------------- tether


@_jit
def tether_loads(x, v, rest, diameter, cd_normal, cd_tangential, area, cd_area_float, rho, u, gravity,
                 first_share, f):
    """``hydro.tether_loads`` into ``f`` (n+1, 3), N: every element property given per element
    (n,): rest length l (m), diameter d (m), C_dn, C_dt, displaced area per metre (m^2) and the
    floats' extra normal drag area per metre (m^2/m); ``rho`` (n,) and ``u`` (n, 3) at the
    elements' centres (``element_water``)."""
    n = x.shape[0] - 1
    half = np.empty((n, 3))
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
        z0, z1 = x[i, 2], x[i + 1, 2]
        frac = _wet_fraction(z0, z1)
        c_low = 0.5 * frac
        centre[i] = c_low if z0 <= z1 else 1.0 - c_low
        for j in range(3):
            vrel[j] = u[i, j] - 0.5 * (v[i + 1, j] + v[i, j])
        vt_mag = vrel[0] * t[0] + vrel[1] * t[1] + vrel[2] * t[2]
        vn0 = vrel[0] - vt_mag * t[0]
        vn1 = vrel[1] - vt_mag * t[1]
        vn2 = vrel[2] - vt_mag * t[2]
        vn_mag = math.sqrt(vn0 * vn0 + vn1 * vn1 + vn2 * vn2)
        q = (0.25 * rest[i] * diameter[i]) * rho[i] * frac
        kn = q * (cd_normal[i] + cd_area_float[i] / diameter[i]) * vn_mag
        kt = q * math.pi * cd_tangential[i] * abs(vt_mag)
        half[i, 0] = vn0 * kn + vt_mag * t[0] * kt
        half[i, 1] = vn1 * kn + vt_mag * t[1] * kt
        half[i, 2] = vn2 * kn + vt_mag * t[2] * kt
        fb[i] = (gravity * area[i] * rest[i]) * rho[i] * frac
    for j in range(3):
        f[n, j] = 0.0
    for i in range(n):
        for j in range(3):
            f[i, j] = half[i, j]
    for i in range(n):
        for j in range(3):
            f[i + 1, j] += half[i, j]
    for i in range(n):
        f[i, 2] += (1.0 - centre[i]) * fb[i]
    for i in range(n):
        f[i + 1, 2] += centre[i] * fb[i]
    if first_share != 0.5 and n > 0:  # part of element 0's load from node 0 to node 1
        for j in range(3):
            s = (1.0 - 2.0 * first_share) * half[0, j]
            if j == 2:
                s += (1.0 - centre[0] - first_share) * fb[0]
            f[0, j] -= s
            f[1, j] += s


@_jit
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


# --------------------------------------------------------------------------- seabed friction


@_jit
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


@_jit
def rigid_body_loads(R, p_cob, v_cob, omega, volume, height, drag_cd, drag_area, angular_drag, dkind, dp, ckind, cp,
                     gravity, force, torque):
    """``hydro.rigid_body_loads`` into ``force`` (3,), N, at the centre of buoyancy and ``torque``
    (3,), N m, world frame; the water profiles as codes (``profile_codes``)."""
    zcob = p_cob[2]
    depth = max(-min(zcob, 0.0), 0.0)
    if height > 0:
        frac = min(max(0.5 - zcob / height, 0.0), 1.0)
    else:
        frac = 1.0 if zcob <= 0 else 0.0
    rho = _density(dkind, dp, depth)
    u = np.empty(3)
    u[0], u[1] = _current(ckind, cp, depth)
    u[2] = 0.0
    fb = np.empty(3)
    tb = np.empty(3)
    for k in range(3):  # body axes: R^T (u - v) and R^T omega
        vk = (u[0] - v_cob[0]) * R[0, k] + (u[1] - v_cob[1]) * R[1, k] + (u[2] - v_cob[2]) * R[2, k]
        wk = omega[0] * R[0, k] + omega[1] * R[1, k] + omega[2] * R[2, k]
        fb[k] = (0.5 * rho * frac) * drag_cd[k] * drag_area[k] * abs(vk) * vk
        tb[k] = -frac * angular_drag[k] * abs(wk) * wk
    for j in range(3):
        force[j] = R[j, 0] * fb[0] + R[j, 1] * fb[1] + R[j, 2] * fb[2]
        torque[j] = R[j, 0] * tb[0] + R[j, 1] * tb[1] + R[j, 2] * tb[2]
    force[2] += rho * gravity * volume * frac


# --------------------------------------------------------------------------- vehicles


def vehicle_arrays(hydro, fins, propeller, r_g):
    """The parameters of ``vehicle_wrench`` from a ``VehicleHydro``, its fins, propeller and
    centre of gravity ``r_g`` (body frame): (zeroed-C_A mask (6, 6), hull (8,), fins (k, 10),
    propeller (13,), surface (14,))."""
    keep = np.ones((6, 6))
    for i, j in hydro.coriolis_zeroed:
        keep[i, j] = 0.0
    h = hydro.hull
    hull = np.zeros(8) if h is None else np.array(
        [1.0, h.length, h.diameter, h.axial_cd, h.crossflow_cd, h.reference_area, h.oswald, h.strips], dtype=float)
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


@_jit
def vehicle_wrench(nu, R, z, dkind, dp, ckind, cp, gravity, MA, keep, DL, fade, DQ, Mlin, volume, r_b, hull, fins,
                   deltas, prop, rpm, surface, z_origin, tau):
    """``vehicle.BoundVehicle``'s explicit wrench (body frame, N and N m about the origin) into
    ``tau`` (6,): -C_A(nu_r) nu_r (``keep``: 0 where an entry is left out), -D(nu_r) nu_r (rows of
    D_L faded by exp(-fade U_r)), M_A (omega x nu_r), the buoyancy at r_b, the hull's lift and
    drag, the fins' and the propeller's (``vehicle_arrays``), or a surface vessel's hydrostatics
    at its origin's height ``z_origin`` (m) in place of the buoyancy; the water at height ``z``
    (m, <= 0) as codes (``profile_codes``). The NumPy reference: ``BoundVehicle.wrench``."""
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
    else:  # buoyancy at r_b (the weight is MuJoCo's)
        B = rho * gravity * volume
        fb0, fb1, fb2 = R[2, 0] * B, R[2, 1] * B, R[2, 2] * B
        tau[0] += fb0
        tau[1] += fb1
        tau[2] += fb2
        tau[3] += r_b[1] * fb2 - r_b[2] * fb1
        tau[4] += r_b[2] * fb0 - r_b[0] * fb2
        tau[5] += r_b[0] * fb1 - r_b[1] * fb0
    if hull[0] > 0.0:  # fossen.lift_drag and fossen.crossflow_drag
        L, D, cd2d, area, oswald, strips = hull[1], hull[2], hull[4], hull[5], hull[6], int(hull[7])
        cd0 = hull[3] * math.pi * D * D / 4.0 / area
        hx = math.hypot(nr[0], nr[2])
        if hx > 0.0:
            alpha = math.atan2(nr[2], abs(nr[0]))
            AR = D * D / area
            CL = math.pi * AR / (1.0 + math.sqrt(1.0 + (AR / 2.0) ** 2)) * alpha
            CD = cd0 + CL * CL / (math.pi * oswald * AR)
            q = 0.5 * rho * U * U * area
            lift, drag = q * CL, q * CD
            sgn = 1.0 if nr[0] >= 0.0 else -1.0
            tau[0] += -drag * nr[0] / hx + lift * sgn * math.sin(alpha)
            tau[2] += -drag * nr[2] / hx - lift * math.cos(alpha)
        dx = L / strips
        for k in range(strips):
            x = (k + 0.5) * dx - 0.5 * L
            vy = nr[1] + x * nr[5]
            vz = nr[2] - x * nr[4]
            kk = -0.5 * rho * D * cd2d * dx * math.hypot(vy, vz)
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
        tau[0] += thrust
        tau[3] += prop[12] * Q
        tau[4] += prop[3] * thrust
        tau[5] -= prop[2] * thrust


# --------------------------------------------------------------------------- the steady march


@_jit
def _element_load(z0, t, l_s, l, d, A, mu, cdn, cdt_pi, float_cda, dkind, dp, ckind, cp, v_tow, g, f):
    """``quasistatic.steady._Cable.loads`` of one element into ``f`` (3,), N: from height ``z0``
    (m) along the unit tangent ``t`` for the stretched length ``l_s`` (m); its wet length, the
    water at its centre, Morison drag on the current less ``v_tow``, buoyancy less weight."""
    z1 = z0 + l_s * t[2]
    if z0 <= 0.0 and z1 <= 0.0:
        zc = 0.5 * (z0 + z1)
        l_wet = l
    else:
        zc = min(0.5 * (z0 + z1), 0.0)
        l_wet = l * _wet_fraction(z0, z1)
    depth = max(-min(zc, 0.0), 0.0)
    rho = _density(dkind, dp, depth)
    u0, u1 = _current(ckind, cp, depth)
    u0, u1, u2 = u0 - v_tow[0], u1 - v_tow[1], 0.0 - v_tow[2]
    ut = u0 * t[0] + u1 * t[1] + u2 * t[2]
    n0, n1, n2 = u0 - ut * t[0], u1 - ut * t[1], u2 - ut * t[2]
    q = 0.5 * d * l_wet * rho
    un_mag = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    kn = q * cdn * un_mag
    kt = q * cdt_pi * abs(ut) * ut
    f[0] = kn * n0 + kt * t[0]
    f[1] = kn * n1 + kt * t[1]
    f[2] = kn * n2 + kt * t[2]
    if float_cda > 0.0:
        kf = 0.5 * float_cda * l_wet * rho * un_mag
        f[0] += kf * n0
        f[1] += kf * n1
        f[2] += kf * n2
    f[2] += (rho * A * l_wet - mu * l) * g


@_jit
def hang_up(s_td, seabed_z, stop_z, max_iterations, l, EA, d, A, mu, cdn, cdt_pi, float_cda, dkind, dp, ckind, cp,
            v_tow, g, xs, Ts, p):
    """``quasistatic.steady._hang_up`` of a uniform line (element properties as scalars, the
    water as codes): the nodes from the touchdown up into ``xs`` (k + 2, 3), the tensions into
    ``Ts`` (k + 1,), the force at the last node into ``p`` (3,); returns (nodes written, phi)."""
    k = int(math.floor(s_td / l * (1 + 1e-12)))
    phi = s_td / l - k
    first = 0 if phi > 1e-12 else 1  # (a hanging part of the touchdown element, if any)
    x = np.array([0.0, 0.0, seabed_z])
    t = np.array([0.0, 0.0, -1.0])
    f, E, gg = np.empty(3), np.empty(3), np.empty(3)
    p[0] = p[1] = p[2] = 0.0
    xs[0] = x
    count = 1
    T = 0.0
    for i in range(first, k + 1):
        frac = phi if i == 0 else 1.0
        alpha, miss_old = 1.0, math.inf
        for _ in range(max_iterations):
            l_s = frac * l * (1.0 + T / EA)
            _element_load(x[2] - l_s * t[2], t, l_s, l, d, A, mu, cdn, cdt_pi, float_cda, dkind, dp, ckind, cp,
                          v_tow, g, f)
            for j in range(3):
                E[j] = p[j] + 0.5 * frac * f[j]
            T = math.sqrt(E[0] * E[0] + E[1] * E[1] + E[2] * E[2])
            for j in range(3):
                gg[j] = E[j] / max(T, 1e-300)
            miss = math.sqrt((gg[0] - t[0]) ** 2 + (gg[1] - t[1]) ** 2 + (gg[2] - t[2]) ** 2)
            if miss <= 1e-10:
                break
            if miss > 0.5 * miss_old:  # not contracting: relax
                alpha = max(0.5 * alpha, 1.0 / 64)
            miss_old = miss
            for j in range(3):
                t[j] = t[j] + alpha * (gg[j] - t[j])
            norm = math.sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
            for j in range(3):
                t[j] /= norm
        for j in range(3):
            t[j] = gg[j]
        s = frac * l * (1.0 + T / EA)
        for j in range(3):
            x[j] = x[j] - s * t[j]
            p[j] = p[j] + frac * f[j]
        xs[count] = x
        Ts[count - 1] = T
        count += 1
        if x[2] > stop_z:
            break
    return count, phi


@_jit
def steady_march(x0, P0, l_e, EA_e, d_e, A_e, mu_e, cdn_e, cdt_pi_e, float_cda, dkind, dp, ckind, cp, v_tow, g,
                 iterations, stop_on_touchdown, k_min, allow_first, X, T, P, td):
    """``quasistatic.steady._Cable.march`` of a line without point loads from node 0: the
    elements marched from ``x0`` (K, 3) with top forces ``P0`` (K, 3) into nodes ``X`` (K, n+1,
    3), tensions ``T`` (K, n) and forces ``P`` (K, n+1, 3) (N, m), and with
    ``stop_on_touchdown`` the touchdown element of each shot into ``td`` (K,), -1 if none.
    Per element (n,): unstretched length (m), EA (N, inf: inextensible), diameter (m),
    displaced area (m^2), mass per length (kg/m), C_dn, pi C_dt, floats' normal drag area per
    metre (m^2/m); the water as codes (``profile_codes``); ``v_tow`` the tow velocity (m/s)."""
    K, n = x0.shape[0], l_e.shape[0]
    f = np.empty(3)
    E = np.empty(3)
    t = np.empty(3)
    for s in range(K):
        for j in range(3):
            X[s, 0, j] = x0[s, j]
            P[s, 0, j] = P0[s, j]
        td[s] = -1
        f[0], f[1], f[2] = 0.0, 0.0, -mu_e[0] * l_e[0] * g
        for k in range(n):
            l, EA, d = l_e[k], EA_e[k], d_e[k]
            Tk, l_s = 0.0, 0.0
            for _ in range(iterations):
                for j in range(3):
                    E[j] = P[s, k, j] - 0.5 * f[j]
                Tk = math.sqrt(E[0] * E[0] + E[1] * E[1] + E[2] * E[2])
                inv = max(Tk, 1e-300)
                for j in range(3):
                    t[j] = E[j] / inv
                l_s = l * (1.0 + Tk / EA)
                _element_load(X[s, k, 2], t, l_s, l, d, A_e[k], mu_e[k], cdn_e[k], cdt_pi_e[k], float_cda[k], dkind,
                              dp, ckind, cp, v_tow, g, f)
            T[s, k] = Tk
            for j in range(3):
                X[s, k + 1, j] = X[s, k, j] + l_s * t[j]
                P[s, k + 1, j] = P[s, k, j] - f[j]
            if stop_on_touchdown and k >= k_min and td[s] < 0 and P[s, k + 1, 2] >= 0.0:
                if (k == k_min and allow_first) or P[s, k, 2] < 0.0:
                    td[s] = k


@_jit
def shot_residuals(X, P, td, bottom, contact, seabed_z, cb, w, L, l, EA, r):
    """``quasistatic.steady._shoot``'s residuals (m) of K marches of a uniform line into ``r``
    (K, 3): the last node's miss of ``bottom``, or with ``contact`` and a touchdown in element
    ``td[s]``, the laid end's miss (``_lay`` with ``end_only``: the rest of the unstretched
    length ``L`` (m) laid straight from the touchdown along the horizontal force there, stretched
    under the tension that seabed friction ``cb`` takes off it at ``w`` N/m) with, as the third
    component, the touchdown's height above ``seabed_z``. Nodes ``X`` (K, n+1, 3), forces ``P``
    (K, n+1, 3), element length ``l`` (m), ``EA`` (N, inf: inextensible)."""
    for s in range(X.shape[0]):
        k = td[s]
        if not (contact and k >= 0):
            for j in range(3):
                r[s, j] = X[s, X.shape[1] - 1, j] - bottom[j]
            continue
        pz0, pz1 = P[s, k, 2], P[s, k + 1, 2]
        phi = min(max(-pz0 / (pz1 - pz0), 0.0), 1.0) if pz1 != pz0 else 1.0
        px = P[s, k, 0] + phi * (P[s, k + 1, 0] - P[s, k, 0])
        py = P[s, k, 1] + phi * (P[s, k + 1, 1] - P[s, k, 1])
        H = math.hypot(px, py)
        LB = max(L - (k + phi) * l, 0.0)
        if EA == math.inf:
            stretch = LB
        elif cb <= 0 or w <= 0:
            stretch = LB * (1 + H / EA)
        else:
            uc = min(LB, min(H / (cb * w), 1e300))
            stretch = LB + (H * uc - cb * w * uc * uc / 2) / EA
        Hm = max(H, 1e-300)
        r[s, 0] = X[s, k, 0] + phi * (X[s, k + 1, 0] - X[s, k, 0]) + stretch * (px / Hm) - bottom[0]
        r[s, 1] = X[s, k, 1] + phi * (X[s, k + 1, 1] - X[s, k, 1]) + stretch * (py / Hm) - bottom[1]
        r[s, 2] = X[s, k, 2] + phi * (X[s, k + 1, 2] - X[s, k, 2]) - seabed_z


# --------------------------------------------------------------------------- the walker's gait


@_jit
def tripod_targets(phase, legs, speed, turn_rate, half, max_stride, step_height, coxa, femur, tibia, out):
    """``walker.Tripod.targets`` after its phase update: the 18 joint targets (rad) into ``out``
    for ``phase`` (0-1), each leg's row of ``legs`` (hip x, y, z, cos and sin of its yaw, neutral
    foot x, y, z, phase offset; m), the commanded ``speed`` (m/s) and ``turn_rate`` (rad/s), half
    the gait period (s), the stride limit and step height (m) and the link lengths (m) of
    ``walker.leg_ik``. Returns the index of the first leg whose foot is out of reach, or -1."""
    for i in range(legs.shape[0]):
        hx, hy, hz, c, s, nx, ny, nz, offset = (legs[i, 0], legs[i, 1], legs[i, 2], legs[i, 3], legs[i, 4],
                                                  legs[i, 5], legs[i, 6], legs[i, 7], legs[i, 8])
        ph = (phase + offset) % 1.0
        dx, dy = (speed - turn_rate * ny) * half, turn_rate * nx * half
        n = math.hypot(dx, dy)
        if n > max_stride:
            dx, dy = dx * max_stride / n, dy * max_stride / n
        if ph < 0.5:  # stance
            a, lift = 0.5 - 2 * ph, 0.0
        else:  # swing
            sig = 2 * ph - 1
            a, lift = sig - 0.5, step_height * math.sin(math.pi * sig)
        fx, fy, fz = nx + a * dx - hx, ny + a * dy - hy, nz + lift - hz
        x, y, z = c * fx + s * fy, -s * fx + c * fy, fz  # R^T (foot - hip): walker.leg_ik from here
        q0 = math.atan2(y, x)
        r = math.hypot(x, y) - coxa
        D = math.hypot(r, z)
        if not abs(femur - tibia) < D < femur + tibia:
            return i
        gamma = math.acos((femur ** 2 + D * D - tibia ** 2) / (2 * femur * D))
        a1 = math.atan2(z, r) + gamma
        a2 = math.atan2(z - femur * math.sin(a1), r - femur * math.cos(a1))
        q1 = -a1
        phi = math.atan2(-math.cos(a2), -math.sin(a2))
        out[3 * i], out[3 * i + 1], out[3 * i + 2] = q0, q1, phi - q1
    return -1


# --------------------------------------------------------------------------- per-step bookkeeping


@_jit
def equality_rows(efc_type, efc_id, nefc, eq_id, start, stop, equality):
    """``simulation.BoundTether._rows``: the rows (start, stop) of equality ``eq_id`` among the
    first ``nefc`` constraint rows (type ``equality``), a contiguous block; the block
    [``start``, ``stop``) given is checked at its ends and kept if it is still that equality's
    whole block, else found again by a search ((0, 0) if it has none)."""
    if 0 <= start < stop <= nefc and efc_type[start] == equality and efc_id[start] == eq_id \
            and efc_type[stop - 1] == equality and efc_id[stop - 1] == eq_id \
            and (start == 0 or efc_type[start - 1] != equality or efc_id[start - 1] != eq_id) \
            and (stop == nefc or efc_type[stop] != equality or efc_id[stop] != eq_id):
        return start, stop
    first, last = -1, -1
    for r in range(nefc):
        if efc_type[r] == equality and efc_id[r] == eq_id:
            if first < 0:
                first = r
            last = r
    return (first, last + 1) if first >= 0 else (0, 0)


@_jit
def slack_switch(act, f, ten_length, rest, K, first, f_min, slack_tension, taut, all_rows):
    """``simulation.BoundTether.update_slack`` after its row lookup: ``act`` (n,) the elements'
    ``eq_active`` (switched in place), ``f`` the active elements' constraint forces in element
    order (N, > 0 pushes), ``ten_length``, ``rest`` (m) and ``K`` (N/m) per element; ``all_rows``:
    every deployed element had a row. Returns (changed, redo)."""
    n = act.shape[0]
    nf = f.shape[0]
    if nf:
        lowest = f[0]
        for r in range(1, nf):
            lowest = min(lowest, f[r])
        f_min = max(f_min, -slack_tension * lowest)
    changed = redo = False
    if nf:
        off = np.zeros(n, dtype=np.bool_)
        push_max, pushed = -math.inf, False
        r = 0
        for e in range(n):  # an element whose equality pushed goes slack (the last pass: only short ones)
            if act[e]:
                if f[r] > 0.0 and (taut or ten_length[e] < rest[e]):
                    off[e] = True
                    pushed = True
                    push_max = max(push_max, f[r])
                r += 1
        if pushed:
            for e in range(n):
                if off[e]:
                    act[e] = 0
            changed = True
            redo = push_max > f_min
    if taut and not all_rows:  # a slack element longer than its rest length is taut again
        over_max, caught = -math.inf, False
        for e in range(first, n):
            if act[e] == 0:
                over = ten_length[e] - rest[e]
                if over > 0.0:
                    act[e] = 1
                    caught = True
                    over_max = max(over_max, over * K[e])
        if caught:
            changed = True
            redo = redo or over_max > f_min
    return changed, redo


@_jit
def tether_extremes(v, stretch_from, rest):
    """``simulation.Simulation.check``'s search over one tether: (index of the largest |v| (the
    first NaN if any), that |v|, index of the largest ``stretch_from - rest``, that stretch)."""
    i, vmax = 0, -1.0
    for a in range(v.shape[0]):
        x = abs(v[a])
        if math.isnan(x):
            i, vmax = a, x
            break
        if x > vmax:
            i, vmax = a, x
    j, smax = 0, -math.inf
    for b in range(rest.shape[0]):
        s = stretch_from[b] - rest[b]
        if math.isnan(s):
            j, smax = b, s
            break
        if s > smax:
            j, smax = b, s
    return i, vmax, j, smax


@_jit
def axial_scalar(EA, segment_length, inv_mass, timestep, damping_ratio, omega_dt, min_imp, max_imp):
    """``builder.axial_scalar`` (EA = inf: inextensible): (S, B, d)."""
    omega_cap = omega_dt / timestep
    K = EA / max(segment_length, 1e-12)
    x = min(max(omega_cap * omega_cap / (K * inv_mass), 1.0 - max_imp), 1.0 - min_imp)
    S = min(K * x * inv_mass, omega_cap * omega_cap)
    return S, 2.0 * damping_ratio * math.sqrt(S), 1.0 - x


@_jit
def drum_update(k, n, l0, mu, s, c, ap, i_ref, dof0, tadr, eq0, nten, EA, dt, zeta, omega_dt, min_imp, max_imp,
                payout_rate, bids, rest, inertia, lead, K, body_mass, armature, invweight, ten_armature, eq_solref,
                eq_solimp, eq_data, tendon_length0):
    """``simulation.BoundTether._update_drum``: an ordinary payout step's bookkeeping of the
    fairlead node ``k``, the first free node and the elements at them, written into the model's
    arrays (``body_mass``, ``dof_armature``, ``tendon_invweight0``, ``tendon_armature`` from
    ``nten`` on (-1: isotropic added mass), ``eq_solref``, ``eq_solimp``, ``eq_data``) and the
    tether's own (``rest``, ``inertia``, ``lead``, ``K``). ``s`` the drum element's rest length
    and ``c`` the fairlead's share of it (m), ``ap`` added mass per metre per element (kg/m)."""
    rest[k] = s
    right = l0 if k + 1 < n else 0.0
    for which in range(2):
        if which == 0:
            i, mass, add = k, mu * c, ap[k] * c
        else:
            i = k + 1
            mass = mu * ((s - c) + 0.5 * right)
            add = ap[k] * (s - c) + (0.5 * ap[k + 1] * right if k + 1 < n else 0.0)
        iso = max(i_ref - mass - add, 0.0) if (i == k or i == n) else 0.0
        if nten < 0:
            iso += add
        else:
            ten_armature[nten + 2 * i] = add
            ten_armature[nten + 2 * i + 1] = add
        iso = max(iso, 1e-9 * i_ref)
        body_mass[bids[i]] = mass
        dof = dof0 + 3 * i
        armature[dof] = armature[dof + 1] = armature[dof + 2] = iso
        inertia[i] = mass + iso
    for j in range(k, min(k + 2, n)):
        inv = 1.0 / inertia[j] + 1.0 / inertia[j + 1]
        S, B, d = axial_scalar(EA, rest[j], inv, dt, zeta, omega_dt, min_imp, max_imp)
        invweight[tadr + j] = inv
        e = eq0 + j
        eq_solref[e, 0] = -S
        eq_solref[e, 1] = -B
        eq_solimp[e, 0] = eq_solimp[e, 1] = d
        lead[j] = B / S
        K[j] = S / ((1.0 - d) * inv)
    eq_data[eq0 + k, 0] = s + lead[k] * payout_rate - tendon_length0[tadr + k]


"""Marine-craft manoeuvring terms in Fossen's vector form (pure NumPy, no MuJoCo).

T. I. Fossen, *Handbook of Marine Craft Hydrodynamics and Motion Control*, 2nd ed., Wiley 2021:

    M_RB nu' + C_RB(nu) nu + M_A nu_r' + C_A(nu_r) nu_r + D(nu_r) nu_r + g(eta) = tau

with nu = [u, v, w, p, q, r] the body-fixed linear velocity of the body origin (CO) and the
angular velocity, nu_r = nu - nu_c the velocity relative to the current, M_A the (symmetric)
added-mass matrix, C_A its Coriolis-centripetal matrix (which holds the Munk moment), D the
damping and g the restoring forces.

Frames: body x forward, y left, z up (MuJoCo's; Fossen writes x forward, y starboard, z down:
the diagonal terms are the same, the signs of y and z offsets and of products of inertia flip);
world z up. Units SI.
"""

from __future__ import annotations

import math

import numpy as np


def cross(a, b) -> np.ndarray:
    """a x b of two 3-vectors (numpy.cross costs 20 us for this)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def skew(a) -> np.ndarray:
    """S(a), the 3x3 matrix with S(a) b = a x b."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def m2c(M: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """Coriolis-centripetal matrix C(nu) of the 6x6 inertia matrix ``M`` (its symmetric part),
    parametrised as in Fossen (2021), Thm. 3.2 / Eq. 6.43: with the momenta
    h1 = M11 nu1 + M12 nu2 and h2 = M21 nu1 + M22 nu2, C = [[0, -S(h1)], [-S(h1), -S(h2)]]."""
    M = 0.5 * (M + M.T)
    h1 = M[:3, :3] @ nu[:3] + M[:3, 3:] @ nu[3:]
    h2 = M[3:, :3] @ nu[:3] + M[3:, 3:] @ nu[3:]
    C = np.zeros((6, 6))
    C[:3, 3:] = -skew(h1)
    C[3:, :3] = -skew(h1)
    C[3:, 3:] = -skew(h2)
    return C


def damping_force(nu_r: np.ndarray, linear: np.ndarray, quadratic: np.ndarray) -> np.ndarray:
    """D(nu_r) nu_r (N, N m, body frame): ``linear`` (6x6) D_L nu_r plus ``quadratic`` (6,)
    D_Q,k |nu_r,k| nu_r,k per axis."""
    return linear @ nu_r + quadratic * np.abs(nu_r) * nu_r


def restoring_force(R: np.ndarray, weight: float, buoyancy: float, r_g: np.ndarray, r_b: np.ndarray) -> np.ndarray:
    """g(eta) (Fossen 2021, Eq. 4.6, world z up): minus the body-frame wrench about the origin of
    the weight W (N) at ``r_g`` and the buoyancy B (N) at ``r_b``; ``R`` body to world."""
    f_g = R.T @ np.array([0.0, 0.0, -weight])
    f_b = R.T @ np.array([0.0, 0.0, buoyancy])
    return -np.concatenate([f_g + f_b, cross(r_g, f_g) + cross(r_b, f_b)])


def crossflow_drag(nu_r: np.ndarray, rho: float, length: float, diameter: float, cd: float,
                   strips: int = 20) -> np.ndarray:
    """Cross-flow drag of a slender hull by strip theory (Fossen 2021, Sec. 6.7.2): the hull's
    length (m) in ``strips`` equal strips about the origin (x from -L/2 to L/2), each of
    diameter D (m) in the flow across it with the 2-D drag coefficient ``cd``; the flow across
    a strip at x is (v_r + x r, w_r - x q) (body frame, m/s), and its drag acts along that flow.
    Returns the body-frame wrench (N, N m) about the origin: sway, heave, pitch and yaw."""
    dx = length / strips
    x = (np.arange(strips) + 0.5) * dx - 0.5 * length
    vy = nu_r[1] + x * nu_r[5]
    vz = nu_r[2] - x * nu_r[4]
    k = -0.5 * rho * diameter * cd * dx * np.hypot(vy, vz)
    Y, Z = k * vy, k * vz
    return np.array([0.0, Y.sum(), Z.sum(), 0.0, -(x * Z).sum(), (x * Y).sum()])


def crossflow_drag_fossen(nu_r: np.ndarray, rho: float, length: float, diameter: float, cd: float,
                          strips: int = 20) -> np.ndarray:
    """Cross-flow drag summed as Fossen sums it for his REMUS 100 (Fossen 2021, Sec. 6.7.2, and
    the ``crossFlowDrag`` of his Python Vehicle Simulator): ``strips`` + 1 points from tail to
    nose, x_i = -L/2 + i L / ``strips`` (m, body frame, about the origin), each weighted
    dx = L / ``strips`` (the end points in full: the sum counts a hull (strips + 1) / strips as
    long as it is), each of diameter D (m) with the 2-D drag coefficient ``cd``, in sway and yaw
    only: the flow across the hull at x is v_r + x r (m/s; heave and pitch are left out), and
    its drag -1/2 rho D cd |v_r + x r| (v_r + x r) dx (N). Returns the body-frame wrench (N, N m)
    about the origin: sway and yaw. Fossen's code takes strips = 20: 21 points."""
    dx = length / strips
    x = np.arange(strips + 1) * dx - 0.5 * length
    vy = nu_r[1] + x * nu_r[5]
    Y = -0.5 * rho * diameter * cd * dx * np.abs(vy) * vy
    return np.array([0.0, Y.sum(), 0.0, 0.0, 0.0, (x * Y).sum()])


def lift_drag(nu_r: np.ndarray, rho: float, area: float, cd0: float, span: float,
              oswald: float = 0.7) -> np.ndarray:
    """Lift and drag of a hull in its vertical plane (Fossen 2021, Sec. 8.4.2; his
    ``forceLiftDrag``): angle of attack alpha = atan2(w_r, |u_r|), lift coefficient
    CL = CL_alpha alpha with CL_alpha = pi AR / (1 + sqrt(1 + (AR / 2)^2)) and AR = span^2 / area,
    drag coefficient CD = cd0 + CL^2 / (pi e AR), both on the reference ``area`` (m^2) at the
    dynamic pressure of the whole relative speed |(u_r, v_r, w_r)| (as Fossen writes it). The
    drag acts against the flow in the x-z plane, the lift across it, opposing w_r; running
    astern mirrors it (Fossen's form is for u_r > 0). Returns the body-frame wrench (surge and
    heave, N; no moment), z up."""
    u, w = float(nu_r[0]), float(nu_r[2])
    h = math.hypot(u, w)
    if h == 0.0:
        return np.zeros(6)
    alpha = math.atan2(w, abs(u))
    AR = span ** 2 / area
    CL = math.pi * AR / (1.0 + math.sqrt(1.0 + (AR / 2.0) ** 2)) * alpha
    CD = cd0 + CL ** 2 / (math.pi * oswald * AR)
    q = 0.5 * rho * (u * u + float(nu_r[1]) ** 2 + w * w) * area
    lift, drag = q * CL, q * CD
    return np.array([-drag * u / h + lift * math.copysign(1.0, u) * math.sin(alpha), 0.0,
                     -drag * w / h - lift * math.cos(alpha), 0.0, 0.0, 0.0])


def surface_restoring(R: np.ndarray, z: float, rho: float, gravity: float, volume: float, waterplane_area: float,
                      gm_t: float, gm_l: float, max_volume: float, r_g, r_f=(0.0, 0.0)) -> np.ndarray:
    """Hydrostatics of a surface vessel (Fossen 2021, Sec. 4.2: linear restoring about the
    floating equilibrium, G = H(r_f)^T diag(0, 0, rho g A_wp, rho g V GM_T, rho g V GM_L, 0) H(r_f)
    with the heave spring at the centre of flotation r_f), made to hold at any heave: the
    submerged volume V_s = V - A_wp z_f, z_f the height (m) above the design waterline of the
    waterplane's point under the centre of flotation (``r_f`` = (x, y) in the body frame, on the
    waterline z = 0; ``z`` is the body origin's height), within [0, ``max_volume``]. The buoyancy
    rho g V acts upwards through the centre of gravity ``r_g`` (body frame), its change
    rho g (V_s - V) at the centre of flotation's x and y (at r_g's height: in the linear theory
    it does not enter), and the righting moments -rho g V_s' GM_T sin(phi) about x and
    -rho g V_s' GM_L sin(theta) about y (V_s' = min(V_s, V); theta > 0 nose down). Valid while
    the vessel floats. Returns the body-frame wrench (N, N m) about the origin; the weight is
    MuJoCo's."""
    xf, yf = float(r_f[0]), float(r_f[1])
    z_f = z + R[2, 0] * xf + R[2, 1] * yf
    Vs = min(max(volume - waterplane_area * z_f, 0.0), max_volume)
    f = R.T @ np.array([0.0, 0.0, rho * gravity * Vs])
    df = R.T @ np.array([0.0, 0.0, rho * gravity * (Vs - volume)])
    k = rho * gravity * min(Vs, volume)
    roll = math.atan2(R[2, 1], R[2, 2])
    pitch = math.asin(max(-1.0, min(1.0, -R[2, 0])))
    m = cross(r_g, f) + cross((xf - r_g[0], yf - r_g[1], 0.0), df)
    return np.array([f[0], f[1], f[2], m[0] - k * gm_t * math.sin(roll), m[1] - k * gm_l * math.sin(pitch), m[2]])

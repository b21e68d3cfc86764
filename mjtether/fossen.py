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

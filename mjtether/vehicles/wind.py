"""The wind load on a surface vessel as Hong et al. (2020) take it from Fossen (pure NumPy; a
run applies it to its surface vessels from ``[wind]``: ``scenario.weather``).

Hong, Park, Lee, Park and Kim (2020, J. Mar. Sci. Eng. 8, 485), Sec. 2.4.2, Eqs. 7-9:

    X_wind = 1/2 C_X(gamma_R) rho_a V_R^2 A_T
    Y_wind = 1/2 C_Y(gamma_R) rho_a V_R^2 A_L                                   (7)
    N_wind = 1/2 C_N(gamma_R) rho_a V_R^2 A_L L

    C_X = -c_x cos(gamma_R),  C_Y = c_y sin(gamma_R),  C_N = c_n sin(2 gamma_R)   (8)

    c_x in (0.5, 0.9),  c_y in (0.7, 0.95),  c_n in (0.05, 0.2)                 (9)

with A_T the frontal and A_L the lateral projected area above water, L the length overall and
rho_a the air density (the text calls it rho_w). These are Fossen's (Handbook of Marine Craft
Hydrodynamics and Motion Control, Wiley 2011, Sec. 8.1) "general" coefficients for ships with
xz-plane symmetry. (The extracted text writes the angle gamma_R in Eq. 7 and psi_R in Eq. 8,
and the yaw coefficient c_z in Eqs. 8-9: taken as one angle and as Fossen's c_n.)

Fossen's frame and angle (x forward, y starboard, z down; the ones Hong's Sec. 2.1 sets):
with the vessel's velocity (u, v) and the wind's (u_w, v_w) in body axes, u_rw = u - u_w,
v_rw = v - v_w, V_R = |(u_rw, v_rw)| and gamma_R = -atan2(v_rw, u_rw): 0 for a head wind,
+-pi for a following one, -pi/2 for a wind from starboard. Here (body x forward, y to port,
z up, as the vehicles in MuJoCo) the same angle is atan2(v_r, u_r) of the vessel's velocity
through the air (u_r, v_r): the bearing off the bow, positive to port, that the relative wind
comes from. Forces come back in this frame: the surge force is Fossen's, the sway force and yaw
moment change sign (y to port, z up). So a head wind pushes the vessel astern, a wind from
starboard pushes it to port, and, c_n > 0, a wind on either bow turns the bow away from it.

World frame: z up, heading psi from +x towards +y; a wind's velocity is the way the air moves
(Fossen's beta_w, the water column's convention for a current). Units SI: m/s, rad, m, m^2,
kg/m^3; forces N, moments N m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mjtether import _checks

AIR_DENSITY = 1.225
"""Air density (kg/m^3): the ISA sea-level value (15 C)."""

CX_RANGE, CY_RANGE, CN_RANGE = (0.5, 0.9), (0.7, 0.95), (0.05, 0.2)
"""Hong et al.'s Eq. 9 (Fossen 2011, Sec. 8.1): the ranges of c_x, c_y, c_n."""


@dataclass(frozen=True)
class Windage:
    """What a surface vessel shows the wind: ``frontal_area`` A_T and ``lateral_area`` A_L (m^2,
    projected above the waterline), ``length`` L overall (m), Fossen's coefficients ``cx``,
    ``cy``, ``cn`` (within Eq. 9's ranges), ``air_density`` (kg/m^3)."""

    frontal_area: float
    lateral_area: float
    length: float
    cx: float = 0.7
    cy: float = 0.825
    cn: float = 0.125
    air_density: float = AIR_DENSITY

    def __post_init__(self):
        _checks.positive("windage.frontal_area", self.frontal_area, "m^2")
        _checks.positive("windage.lateral_area", self.lateral_area, "m^2")
        _checks.positive("windage.length", self.length, "m")
        _checks.in_range("windage.cx", self.cx, *CX_RANGE, "(Hong et al. 2020, Eq. 9)")
        _checks.in_range("windage.cy", self.cy, *CY_RANGE, "(Hong et al. 2020, Eq. 9)")
        _checks.in_range("windage.cn", self.cn, *CN_RANGE, "(Hong et al. 2020, Eq. 9)")
        _checks.positive("windage.air_density", self.air_density, "kg/m^3")


HONG2020_USV = Windage(frontal_area=1.82 * 0.5, lateral_area=3.0 * 0.5, length=3.0)
"""Hong et al.'s (2020) USV, a reading: their Table 4 gives its length (3 m) and breadth
(1.82 m) but no projected areas, and Eq. 9 only the coefficients' ranges. Assumed here: a mean
height of 0.5 m above the waterline over its length and breadth (A_T = 1.82 x 0.5 = 0.91 m^2,
A_L = 3 x 0.5 = 1.5 m^2, L = 3 m), and the middle of each of Eq. 9's ranges (c_x = 0.7,
c_y = 0.825, c_n = 0.125)."""


OTTER = Windage(frontal_area=1.08 * 0.5 / 1.5, lateral_area=2.0 * 0.5 / 1.5, length=2.0)
"""Fossen's Otter USV (2 m long, 1.08 m beam; ``assets/vehicles/otter.toml``), a reading: the
``HONG2020_USV`` reading's 0.5 m mean height above the waterline scaled down by the 1.5 that
makes the Otter of the Hong USV file (A_T = 0.36 m^2, A_L = 0.667 m^2, L = 2 m), and the middle
of Eq. 9's ranges. Fossen's otter.py carries no wind load."""

WINDAGE = {"hong2020_usv": HONG2020_USV, "otter": OTTER}
"""The shipped surface vessels' windage, by their vehicle names (``vehicles.files.shipped()``)."""


def _planar(name: str, value) -> np.ndarray:
    """Finite horizontal vectors (..., 2) from (..., 2) or (..., 3) (z dropped)."""
    v = np.asarray(value, dtype=float)
    if v.ndim < 1 or v.shape[-1] not in (2, 3) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be finite (x, y) or (x, y, z) velocities in m/s, got shape {v.shape}")
    return v[..., :2]


def _finite_array(name: str, value, unit: str) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite ({unit})")
    return a


def fossen_coefficients(gamma, cx: float, cy: float, cn: float) -> np.ndarray:
    """Eq. 8 at Fossen's relative wind angle ``gamma`` (rad): (C_X, C_Y, C_N), shape
    gamma.shape + (3,), in Fossen's frame (y starboard, yaw positive bow to starboard)."""
    g = _finite_array("gamma", gamma, "rad")
    return np.stack([-cx * np.cos(g), cy * np.sin(g), cn * np.sin(2.0 * g)], axis=-1)


def relative_wind(wind, velocity, heading):
    """(V_R m/s, gamma_R rad) of a vessel of world ``velocity`` (m/s) and ``heading`` (rad) in a
    ``wind`` of world velocity (m/s): the speed of the vessel through the air and the bearing
    off its bow, positive to port, that the relative wind comes from (module docstring)."""
    w, v = _planar("wind", wind), _planar("velocity", velocity)
    psi = _finite_array("heading", heading, "rad")
    d = v - w
    c, s = np.cos(psi), np.sin(psi)
    u_r = c * d[..., 0] + s * d[..., 1]
    v_r = -s * d[..., 0] + c * d[..., 1]
    return np.hypot(u_r, v_r), np.arctan2(v_r, u_r)


def wind_load(windage: Windage, speed, gamma) -> np.ndarray:
    """Eqs. 7-8: (X, Y, N) (N, N, N m), shape gamma.shape + (3,), body frame x forward, y to
    port, z up, at relative wind ``speed`` V_R (m/s, >= 0) from bearing ``gamma`` (rad,
    ``relative_wind``'s; Fossen's gamma_R)."""
    V = _finite_array("speed", speed, "m/s")
    if np.any(V < 0.0):
        raise ValueError(f"speed must be >= 0 m/s (the relative wind's magnitude), got {V.min()}")
    q = 0.5 * windage.air_density * V ** 2
    C = fossen_coefficients(gamma, windage.cx, windage.cy, windage.cn)
    A_L = windage.lateral_area
    fossen = np.stack([q * C[..., 0] * windage.frontal_area, q * C[..., 1] * A_L,
                       q * C[..., 2] * A_L * windage.length], axis=-1)
    return fossen * np.array([1.0, -1.0, -1.0])  # (y starboard, z down) -> (y port, z up)


def wind_load_world(windage: Windage, wind, velocity, heading) -> np.ndarray:
    """The wind load (F_x N, F_y N, M_z N m), world frame z up, on a vessel of world
    ``velocity`` (m/s) and ``heading`` (rad) in a ``wind`` of world velocity (m/s)."""
    V, gamma = relative_wind(wind, velocity, heading)
    X, Y, N = np.moveaxis(wind_load(windage, V, gamma), -1, 0)
    psi = np.asarray(heading, dtype=float)
    c, s = np.cos(psi), np.sin(psi)
    return np.stack([c * X - s * Y, s * X + c * Y, N], axis=-1)


def wind_velocity(speed: float, direction: float) -> np.ndarray:
    """A wind's world velocity (m/s, shape (3,)) from its ``speed`` (m/s, >= 0) and the
    ``direction`` it blows towards (rad, from +x towards +y)."""
    V = _checks.non_negative("wind.speed", speed, "m/s")
    a = _checks.finite("wind.direction", direction)
    return np.array([V * math.cos(a), V * math.sin(a), 0.0])

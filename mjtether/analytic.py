"""Closed-form answers used to start runs and to check them.

* The inextensible catenary between two points (Irvine, *Cable Structures*, 1981, ch. 1).
* The suspended weight of Li et al. (004_1344bf68f719ac97.txt): a heavy body on a light tether
  oscillating with quadratic damping, solved by the method of averaging.

Frames: world, z up. Forces are those the cable exerts on its supports (N, world frame).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from mjtether import _checks


@dataclass(frozen=True)
class Catenary:
    """An inextensible catenary hanging under a uniform load ``w`` (N/m, > 0 downwards).

    In the vertical plane through both ends, with x the horizontal distance from end A and
    y the height above A, the curve is y = a cosh((x - x0)/a) - a cosh(x0/a), a = H / w.
    """

    p0: np.ndarray
    p1: np.ndarray
    length: float
    w: float
    a: float
    x0: float

    @property
    def span(self) -> float:
        return float(np.hypot(*(self.p1 - self.p0)[:2]))

    @property
    def horizontal_tension(self) -> float:
        """H = w a (N), constant along the cable."""
        return self.w * self.a

    def _frame(self):
        d = self.p1 - self.p0
        h = np.hypot(d[0], d[1])
        ex = np.array([d[0] / h, d[1] / h, 0.0]) if h > 0 else np.array([1.0, 0.0, 0.0])
        return ex

    def points(self, s) -> np.ndarray:
        """World positions at arc lengths ``s`` from end A (m), shape ``(len(s), 3)``."""
        s = np.asarray(s, dtype=float)
        a, x0 = self.a, self.x0
        x = x0 + a * np.arcsinh(s / a + np.sinh(-x0 / a))
        y = a * (np.cosh((x - x0) / a) - np.cosh(x0 / a))
        return self.p0 + np.outer(x, self._frame()) + np.outer(y, [0.0, 0.0, 1.0])

    def tension(self, s) -> np.ndarray:
        """Tension magnitude at arc lengths ``s`` (N): T = w a cosh((x - x0)/a)."""
        s = np.asarray(s, dtype=float)
        u = s / self.a + np.sinh(-self.x0 / self.a)  # sinh((x - x0)/a)
        return self.w * self.a * np.sqrt(1.0 + u * u)

    def end_forces(self) -> tuple[np.ndarray, np.ndarray]:
        """Forces of the cable on support A and on support B (N, world frame)."""
        ex = self._frame()
        H = self.horizontal_tension
        vA = self.w * self.a * math.sinh(-self.x0 / self.a)  # = -V at A (slope negative)
        vB = self.w * self.a * math.sinh((self.span - self.x0) / self.a)
        fA = H * ex + np.array([0, 0, vA])  # cable pulls A towards B and down
        fB = -H * ex - np.array([0, 0, vB])
        return fA, fB


def catenary(p0, p1, length: float, w: float) -> Catenary:
    """Solve the inextensible catenary of ``length`` (m) between ``p0`` and ``p1`` under ``w`` N/m.

    ``w`` is the submerged weight per metre (> 0 sinks). Raises ``ValueError`` if the length
    does not exceed the straight distance, or if the ends are on one vertical.
    """
    p0 = _checks.vector3("catenary.p0", p0)
    p1 = _checks.vector3("catenary.p1", p1)
    length = _checks.positive("catenary.length", length, "m")
    w = _checks.positive("catenary.w", w, "N/m")
    d = p1 - p0
    h = float(np.hypot(d[0], d[1]))
    v = float(d[2])
    if h < 1e-9:
        raise ValueError("catenary: the two ends are on one vertical; the span must be > 0 m")
    chord = math.hypot(h, v)
    if length <= chord * (1 + 1e-12):
        raise ValueError(f"catenary.length must exceed the distance between the ends ({chord:.6g} m)")
    target = math.sqrt(length**2 - v**2)
    # with b = h / (2a): sinh(b) / b = target / h > 1, increasing in b
    r = target / h
    g = lambda b: (b + math.log1p(-math.exp(-2 * b)) - math.log(2 * b)) - math.log(r)  # noqa: E731
    hi = 1.0
    while g(hi) < 0:
        hi *= 2
    b = brentq(g, 1e-9, hi, xtol=1e-15, rtol=1e-15, maxiter=500)
    a = h / (2 * b)
    x0 = h / 2 - a * math.atanh(v / length)
    return Catenary(p0, p1, length, w, a, x0)


def sagged_polyline(p0, p1, length: float, n: int, sag_down: bool = True) -> np.ndarray:
    """``n + 1`` points at equal arc length along a catenary-shaped curve of ``length`` from
    ``p0`` to ``p1``; a straight line if the chord is as long as the length (or longer).

    Used as a neutral initial shape; ``sag_down=False`` gives the mirror image (arching up),
    the shape a buoyant line takes.
    """
    p0 = np.asarray(p0, float)
    p1 = np.asarray(p1, float)
    s = np.linspace(0.0, length, n + 1)
    chord = float(np.linalg.norm(p1 - p0))
    d = p1 - p0
    if chord >= length * (1 - 1e-9):
        return p0 + np.outer(s / length, d)
    if np.hypot(d[0], d[1]) < 1e-6 * length:  # ends on a vertical: fold the slack sideways
        return _folded_vertical(p0, p1, length, n)
    if sag_down:
        return catenary(p0, p1, length, 1.0).points(s)
    mirrored = catenary(p0 * [1, 1, -1], p1 * [1, 1, -1], length, 1.0).points(s)
    return mirrored * [1, 1, -1]


def _folded_vertical(p0, p1, length, n):
    s = np.linspace(0.0, length, n + 1)
    # a symmetric V in the x-z plane with the right length
    half = length / 2
    dz = (p1[2] - p0[2]) / 2
    off = math.sqrt(max(half**2 - dz**2, 0.0))
    mid = (p0 + p1) / 2 + np.array([off, 0.0, 0.0])
    out = np.empty((n + 1, 3))
    for i, si in enumerate(s):
        if si <= half:
            out[i] = p0 + (mid - p0) * si / half
        else:
            out[i] = mid + (p1 - mid) * (si - half) / half
    return out


# --------------------------------------------------------------- Li et al., suspended weight


@dataclass(frozen=True)
class SuspendedWeight:
    """The pendulum of Li et al.: mass ``m`` (kg), displaced water mass ``m_f`` (kg), added mass
    ``m_a`` (kg), drag coefficient ``cd`` on area ``S`` (m^2), tether length ``l`` (m), water
    density ``rho`` (kg/m^3). Their Eq. 3 defines eps and omega."""

    m: float
    m_f: float
    m_a: float
    cd: float
    S: float
    l: float
    rho: float = 1025.0
    g: float = 9.81

    @property
    def wet_weight(self) -> float:
        """G - F (N)."""
        return (self.m - self.m_f) * self.g

    @property
    def eps(self) -> float:
        """Damping parameter eps = Cd rho S l / (2 (m + m_a)) (Eq. 3)."""
        return self.cd * self.rho * self.S * self.l / (2 * (self.m + self.m_a))

    @property
    def omega(self) -> float:
        """omega = sqrt((G - F) / ((m + m_a) l)) (rad/s, Eq. 3)."""
        return math.sqrt(self.wet_weight / ((self.m + self.m_a) * self.l))

    @property
    def period(self) -> float:
        """T = 2 pi sqrt((m + m_a) l / (G - F)) (s)."""
        return 2 * math.pi / self.omega

    def balance_angle(self, u_c: float) -> float:
        """Eq. 8: A = Cd rho S u_c^2 / (2 (G - F)) (rad)."""
        return self.cd * self.rho * self.S * u_c**2 / (2 * self.wet_weight)

    def still_water_amplitude(self, t, phi0: float):
        """Eq. 17 with C1 of Eq. 19: amplitude a(t) of the swing released from rest at
        ``phi0`` (rad) in still water: a = (4 eps omega t / (3 pi) + C1)^-1."""
        c1 = math.sqrt(9 * math.pi**2 - 16 * self.eps**2 * phi0**2) / (3 * math.pi * phi0)
        return 1.0 / (4 * self.eps * self.omega * np.asarray(t, float) / (3 * math.pi) + c1)

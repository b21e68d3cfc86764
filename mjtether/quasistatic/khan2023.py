"""The 2-D quasi-static finite-segment method of Khan et al. (2023), J. Mar. Sci. Eng. 11:1539
(``../shared/seeds/000_facb350256c48569.txt``, Secs. 3.5-3.13, Eqs. 5-37).

The tether runs from the ship (node 1, at X = Z = 0) to the seabed walker (node N+1); element i
has length l = L / N (Eq. 7) and angle theta_i below the horizontal, so that (Eqs. 26-27)

    X_{i+1} = X_i + l cos(theta_i),   Z_{i+1} = Z_i - l sin(theta_i).

Each element carries its specific weight W_s,i = (pi d^2 / 4) l g (rho_c - rho_0) (Eq. 11),
axial drag D_1 V_i^2 cos^2 with D_1 = 1/2 C_da rho_0 pi d l (Eq. 13) and normal drag
D_2 V_i^2 sin^2 with D_2 = 1/2 C_dn rho_0 d l (Eq. 15), with rho_0 and the relative speed
V_i = v_{i,r} + v_c(z) (Eq. 5) taken at the element's mid-depth. Eq. 21 balances element i,
with C_1 = T_{i-1} cos(theta_{i-1}) and C_2 = -T_{i-1} sin(theta_{i-1}) (Eqs. 19-20)::

    -T_i cos + D_1 V^2 cos^3 + D_2 V^2 sin^3 + C_1 = 0
     T_i sin - D_1 V^2 cos^2 sin + D_2 V^2 sin^2 cos + C_2 - W_s,i = 0

Eliminating T_i (multiply the first by tan and add) gives, exactly,

    D_2 V^2 tan(theta) sin(theta) + C_1 tan(theta) + C_2 - W_s,i = 0          ("consistent" 22)
    T_i = (D_1 V^2 cos^3 + D_2 V^2 sin^3 + C_1) / cos(theta)                    ("consistent" 23)

whereas the paper prints D_1 in place of D_2 in Eq. 22 and swaps sin^3 and cos^3 in Eq. 23::

    D_1 V^2 tan(theta) sin(theta) + C_1 tan(theta) + C_2 - W_s,i = 0          ("printed" 22)
    T_i = (D_1 V^2 sin^3 + D_2 V^2 cos^3 + C_1) / cos(theta)                    ("printed" 23)

Neither is a correct Morison balance (Eq. 18 already applies the element rotation twice to
the drag), which is why ``steady_state`` exists; this module reproduces the paper's method.

Readings this module had to choose (the text is ambiguous; each is stated in the report):

* **Element velocity** (Eq. 5): the walker's speed varies linearly from 0 at node 1 to v_r at
  node N+1; an element takes the value at its centre, v_r (i - 1/2) / N. The current is added
  to it (Eq. 4, V = v_c + v_r): a head current, against the walker's motion.
* **Exponential current**: the paper gives no decay depth, only "almost zero at 50-60 m"
  (Sec. 3.5). Passed in through ``water.current`` (``ExponentialCurrent``); the reproduction
  uses a decay depth of 55 m / ln(100) = 11.94 m (1 % of the surface value at 55 m).
* **Linear density**: 1025 kg/m^3 at the surface to 980 kg/m^3 at 500 m (Sec. 4.4, Table 3;
  Sec. 3.6 says 990). The reproduction uses 980, the value of the results section.
* **Upper boundary condition** (Eqs. 35-36 and Sec. 3.12): element 1 has the tension
  T_1 = W_s = sum_i W_s,i, the total specific weight of the deployed cable, and the assumed
  angle theta_1 = 30 degrees; Eqs. 22-23 give elements 2..N. W_s depends on the depths of all
  elements, so it is solved for (a scalar root) to be consistent with the computed profile
  (Sec. 3.14, "iterative update of the environment parameters").
* **Mid-depth of an element**: found with the previous element's angle, then once more with the
  element's own angle (one predictor-corrector step per element).
* **"Length deployed"** (Tables 2-8): the length L for which the computed depth (Eq. 29)
  equals the seabed depth, found by root-finding on L (the continuation in L of Sec. 3.12);
  the tension reported is that of element N, at the tow point (Eq. 37).

Units SI; X forward (towards the walker), Z up (negative below the surface).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from mjtether import _checks
from mjtether.physics.water import WaterColumn

THETA1 = math.radians(30.0)
"""Assumed angle of element 1 at the ship (Sec. 3.12)."""


@dataclass(frozen=True)
class KhanResult:
    """One solution of the Khan et al. method.

    Attributes:
        X, Z: node coordinates (m), shape (N+1,), node 1 (index 0) at the ship.
        tension: element tensions T_i (N), shape (N,).
        theta: element angles below the horizontal (rad), shape (N,).
        length: deployed length L (m).
        variant: "printed" or "consistent".
    """

    X: np.ndarray
    Z: np.ndarray
    tension: np.ndarray
    theta: np.ndarray
    length: float
    variant: str

    @property
    def range(self) -> float:
        """Horizontal distance from the ship to the tow point (m), Eq. 28."""
        return float(self.X[-1])

    @property
    def depth(self) -> float:
        """Depth reached by the cable's end (m), Eq. 29."""
        return float(-self.Z[-1])

    @property
    def tow_tension(self) -> float:
        """Tension at the tow point, T_N (N), Eq. 37."""
        return float(self.tension[-1])


def _solve_theta(a: float, c1: float, c: float) -> float:
    """Root of h(theta) = a sin^2 + c1 sin + c cos in (-pi/2, pi/2), the form of Eq. 22
    multiplied by cos(theta); a, c1 >= 0. Safeguarded Newton iteration."""
    if c < 0.0:
        lo, hi = 0.0, 0.5 * math.pi
    else:
        lo, hi = -0.5 * math.pi, 0.0
        if a - c1 >= 0.0:  # h(-pi/2) = a - c1 has the sign of h(0): no root
            raise ValueError("khan2023: Eq. 22 has no root in (-pi/2, pi/2) for an element; the cable is too "
                             "buoyant for the paper's method")
    th = 0.5 * (lo + hi)
    for _ in range(60):
        s, co = math.sin(th), math.cos(th)
        h = a * s * s + c1 * s + c * co
        if h > 0.0:
            hi = th
        else:
            lo = th
        dh = 2 * a * s * co + c1 * co - c * s
        nxt = th - h / dh if dh != 0.0 else 0.5 * (lo + hi)
        if not lo < nxt < hi:
            nxt = 0.5 * (lo + hi)
        if abs(nxt - th) < 1e-13:
            return nxt
        th = nxt
    return th


class _Khan:
    def __init__(self, diameter, cable_density, water, robot_speed, cd_normal, cd_axial, gravity, variant):
        self.d = diameter
        self.rho_c = cable_density
        self.water = water
        self.vr = robot_speed
        self.cdn = cd_normal
        self.cda = cd_axial
        self.g = gravity
        self.variant = variant

    def env(self, z: float):
        """(rho_0, current speed) at height z."""
        zz = np.array([min(z, 0.0)])
        return float(self.water.rho(zz)[0]), float(self.water.current.speed_at(zz)[0])

    def sweep(self, L: float, N: int, Ws_total: float):
        """One pass down the cable (Sec. 3.12). Returns X, Z, T, theta and the sum of W_s,i."""
        l = L / N
        area = math.pi * self.d**2 / 4.0
        X = np.zeros(N + 1)
        Z = np.zeros(N + 1)
        T = np.zeros(N)
        th = np.zeros(N)
        consistent = self.variant == "consistent"
        T[0], th[0] = Ws_total, THETA1  # Eq. 35 and the assumed first angle
        X[1], Z[1] = l * math.cos(THETA1), -l * math.sin(THETA1)
        rho0, _ = self.env(-0.5 * l * math.sin(THETA1))
        ws_sum = area * l * self.g * (self.rho_c - rho0)
        T_prev, th_prev = T[0], th[0]
        for i in range(1, N):
            c1 = T_prev * math.cos(th_prev)
            c2 = -T_prev * math.sin(th_prev)
            v_rel_robot = self.vr * (i + 0.5) / N
            guess = th_prev
            for _ in range(2):  # predictor with the previous angle, corrector with this one
                rho0, vc = self.env(Z[i] - 0.5 * l * math.sin(guess))
                V2 = (v_rel_robot + vc) ** 2
                D1 = 0.5 * self.cda * rho0 * math.pi * self.d * l
                D2 = 0.5 * self.cdn * rho0 * self.d * l
                Ws = area * l * self.g * (self.rho_c - rho0)
                guess = _solve_theta((D2 if consistent else D1) * V2, c1, c2 - Ws)
            t = guess
            s, c = math.sin(t), math.cos(t)
            if consistent:
                T[i] = (D1 * V2 * c**3 + D2 * V2 * s**3 + c1) / c
            else:
                T[i] = (D1 * V2 * s**3 + D2 * V2 * c**3 + c1) / c
            th[i] = t
            X[i + 1] = X[i] + l * c
            Z[i + 1] = Z[i] - l * s
            ws_sum += Ws
            T_prev, th_prev = T[i], t
        return X, Z, T, th, ws_sum

    def solve(self, L: float, N: int) -> KhanResult:
        # W_s (Eq. 36) consistent with the profile it produces: a scalar root
        def gap(ws):
            return self.sweep(L, N, ws)[4] - ws

        hi = max(abs(self.rho_c - 1025.0), 1.0) * math.pi * self.d**2 / 4 * L * self.g
        for _ in range(60):
            if gap(hi) < 0:
                break
            hi *= 2.0
        else:
            raise RuntimeError("khan2023: no boundary tension W_s (Eq. 36) consistent with the profile")
        lo = 1e-9 * hi
        if gap(lo) <= 0:
            raise RuntimeError("khan2023: the cable is buoyant (W_s <= 0); the paper's method needs a heavy cable")
        Ws = brentq(gap, lo, hi, xtol=1e-12, rtol=1e-10)
        X, Z, T, th, _ = self.sweep(L, N, Ws)
        return KhanResult(X, Z, T, th, L, self.variant)


def khan2023(*, diameter: float = 0.02, cable_density: float = 1025.0, water: WaterColumn,
             robot_speed: float, length: float | None = None, depth: float | None = None,
             segments: int = 200, cd_normal: float = 1.0, cd_axial: float = 0.015,
             gravity: float = 9.8, variant: str = "printed", max_length: float = 20000.0) -> KhanResult:
    """Run the Khan et al. (2023) quasi-static method (see the module docstring).

    Give either ``length`` (m): the profile of that deployed length; or ``depth`` (m, > 0): the
    deployed length whose end reaches that depth (Tables 2-8), found between ``depth`` and
    ``max_length``. Defaults are the paper's Table 1 (d = 0.02 m, rho_c = 1025 kg/m^3,
    C_dn = 1.0, C_da = 0.015, g = 9.8 m/s^2, N = 200). ``robot_speed`` in m/s; the water
    column supplies rho_0(z) and the current speed v_c(z) (its heading is ignored: the method
    is 2-D, the current is head-on).
    """
    if variant not in ("printed", "consistent"):
        raise ValueError(f"khan2023.variant must be 'printed' or 'consistent', got {variant!r}")
    if not isinstance(water, WaterColumn):
        raise ValueError(f"khan2023.water must be a WaterColumn, got {type(water).__name__}")
    k = _Khan(_checks.positive("khan2023.diameter", diameter, "m"),
              _checks.in_range("khan2023.cable_density", cable_density, 1.0, 20000.0, "kg/m^3"),
              water, _checks.non_negative("khan2023.robot_speed", robot_speed, "m/s"),
              _checks.non_negative("khan2023.cd_normal", cd_normal),
              _checks.non_negative("khan2023.cd_axial", cd_axial),
              _checks.positive("khan2023.gravity", gravity, "m/s^2"), variant)
    N = _checks.positive_int("khan2023.segments", segments, 1)
    if (length is None) == (depth is None):
        raise ValueError("khan2023: give exactly one of length (m) or depth (m)")
    if length is not None:
        return k.solve(_checks.positive("khan2023.length", length, "m"), N)
    D = _checks.positive("khan2023.depth", depth, "m")
    Lmax = _checks.positive("khan2023.max_length", max_length, "m")
    f = lambda L: k.solve(L, N).depth - D  # noqa: E731
    lo = D * (1 + 1e-9)
    if f(Lmax) < 0:
        raise ValueError(f"khan2023: {Lmax:g} m of cable does not reach {D:g} m depth; raise max_length")
    L = brentq(f, lo, Lmax, xtol=1e-6, rtol=1e-10)
    return k.solve(L, N)


def time_one_sweep(water: WaterColumn, robot_speed: float, length: float, segments: int = 200,
                   repeat: int = 20, **kw) -> float:
    """Wall time (s) of one pass down the cable (Sec. 3.12), best of ``repeat``."""
    k = _Khan(kw.get("diameter", 0.02), kw.get("cable_density", 1025.0), water, robot_speed,
              kw.get("cd_normal", 1.0), kw.get("cd_axial", 0.015), kw.get("gravity", 9.8),
              kw.get("variant", "printed"))
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        k.sweep(length, segments, 100.0)
        best = min(best, time.perf_counter() - t0)
    return best

"""The analytic elastic catenary with seabed contact and friction.

The classic closed form used by mooring codes (Jonkman 2007, *Dynamics Modeling and Loads
Analysis of an Offshore Floating Wind Turbine*, NREL/TP-500-41958, Sec. 4.2; MAP++; MoorPy's
``Catenary.catenary``). A line of unstretched length L, submerged weight w per metre and
axial stiffness EA hangs between an anchor A and a fairlead B that is XF horizontally and
ZF vertically (up) from A. With H the horizontal tension and VF the vertical tension at B:

fully suspended::

    XF = H/w [asinh(VF/H) - asinh((VF - wL)/H)] + H L / EA
    ZF = H/w [sqrt(1 + (VF/H)^2) - sqrt(1 + ((VF - wL)/H)^2)] + (VF L - w L^2 / 2) / EA

part of the line on the seabed (anchor on the seabed, L_B = L - VF / w > 0 m lying on it,
Coulomb friction coefficient CB)::

    XF = L_B + H/w asinh(VF/H) + H L / EA
         + CB w / (2 EA) [-L_B^2 + (L_B - H/(CB w)) max(L_B - H/(CB w), 0)]
    ZF = H/w [sqrt(1 + (VF/H)^2) - 1] + VF^2 / (2 EA w)

On the seabed the tension falls from H at the touchdown point by CB w per metre towards the
anchor and never below zero, so the anchor feels max(H - CB w L_B, 0), horizontally.

Frames: world, z up. Forces are those the line exerts on its ends (N, world frame).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import root

from mjtether import _checks


@dataclass(frozen=True)
class ElasticCatenary:
    """A solved elastic catenary (see the module docstring for the equations).

    Attributes:
        anchor, fairlead: world positions of the ends A (lower) and B (upper) (m).
        length: unstretched length L (m); w: submerged weight (N/m); EA (N); cb: friction.
        H: horizontal tension at the fairlead (N); VF: vertical tension at the fairlead (N).
        laid_length: unstretched length lying on the seabed, L_B (m); 0 if fully suspended.
    """

    anchor: np.ndarray
    fairlead: np.ndarray
    length: float
    w: float
    EA: float
    cb: float
    H: float
    VF: float
    laid_length: float

    @property
    def _ex(self) -> np.ndarray:
        d = self.fairlead - self.anchor
        h = math.hypot(d[0], d[1])
        return np.array([d[0] / h, d[1] / h, 0.0])

    @property
    def anchor_tension(self) -> tuple[float, float]:
        """(horizontal, vertical) tension at the anchor (N); vertical > 0 means the line
        leaves the anchor upwards."""
        if self.laid_length > 0.0:
            return max(self.H - self.cb * self.w * self.laid_length, 0.0), 0.0
        return self.H, self.VF - self.w * self.length

    @property
    def fairlead_force(self) -> np.ndarray:
        """Force of the line on the fairlead B (N, world): towards the anchor and down."""
        return -self.H * self._ex - np.array([0.0, 0.0, self.VF])

    @property
    def anchor_force(self) -> np.ndarray:
        """Force of the line on the anchor A (N, world)."""
        ha, va = self.anchor_tension
        return ha * self._ex + np.array([0.0, 0.0, va])

    def tension(self, s) -> np.ndarray:
        """Tension magnitude (N) at unstretched arc length ``s`` from the anchor (m)."""
        s = np.asarray(s, dtype=float)
        H, w, LB = self.H, self.w, self.laid_length
        V = self.VF - w * self.length + w * s if LB <= 0 else w * np.maximum(s - LB, 0.0)
        hang = np.sqrt(H * H + V * V)
        if LB <= 0:
            return hang
        bottom = np.maximum(H - self.cb * w * (LB - s), 0.0)
        return np.where(s <= LB, bottom, hang)

    def points(self, s) -> np.ndarray:
        """World positions (m) at unstretched arc lengths ``s`` from the anchor, shape (n, 3)."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        H, w, EA, LB = self.H, self.w, self.EA, self.laid_length
        if LB <= 0:
            Va = self.VF - w * self.length
            V = Va + w * s
            x = H / w * (np.arcsinh(V / H) - math.asinh(Va / H)) + H * s / EA
            z = H / w * (np.sqrt(1 + (V / H) ** 2) - math.sqrt(1 + (Va / H) ** 2)) + (Va * s + w * s * s / 2) / EA
        else:
            x = np.empty_like(s)
            z = np.zeros_like(s)
            on = s <= LB
            x[on] = s[on] + self._bottom_stretch(s[on])
            u = s[~on] - LB
            x[~on] = (LB + self._bottom_stretch(np.array(LB)) + H / w * np.arcsinh(w * u / H) + H * u / EA)
            z[~on] = H / w * (np.sqrt(1 + (w * u / H) ** 2) - 1) + w * u * u / (2 * EA)
        return self.anchor + np.outer(x, self._ex) + np.outer(z, [0.0, 0.0, 1.0])

    def _bottom_stretch(self, s):
        """Elastic stretch (m) of the laid line between the anchor and arc length ``s``."""
        H, w, EA, LB = self.H, self.w, self.EA, self.laid_length
        if self.cb <= 0:
            return H * s / EA
        s0 = max(LB - H / (self.cb * w), 0.0)  # tension is zero between the anchor and s0
        s = np.asarray(s, dtype=float)
        sc = np.maximum(s, s0)
        return ((H - self.cb * w * LB) * (sc - s0) + self.cb * w * (sc * sc - s0 * s0) / 2) / EA


def _residual(H, VF, XF, ZF, L, w, EA, cb, contact):
    LB = L - VF / w
    if contact and LB > 0:
        x = LB + H / w * math.asinh(VF / H) + H * L / EA
        if cb > 0:
            lam = LB - H / (cb * w)
            x += cb * w / (2 * EA) * (-LB * LB + lam * max(lam, 0.0))
        z = H / w * (math.sqrt(1 + (VF / H) ** 2) - 1) + VF * VF / (2 * EA * w)
    else:
        Va = VF - w * L
        x = H / w * (math.asinh(VF / H) - math.asinh(Va / H)) + H * L / EA
        z = H / w * (math.sqrt(1 + (VF / H) ** 2) - math.sqrt(1 + (Va / H) ** 2)) + (VF * L - w * L * L / 2) / EA
    return x - XF, z - ZF


def catenary(anchor, fairlead, length: float, w: float, *, EA: float | None = None,
             cb: float = 0.0, seabed: bool = True) -> ElasticCatenary:
    """Solve the elastic catenary from ``anchor`` (lower end) to ``fairlead`` (upper end).

    Args:
        anchor, fairlead: world positions (m); the fairlead must not be lower than the anchor
            and the two must not be on one vertical.
        length: unstretched length L (m).
        w: submerged weight per metre (N/m, > 0).
        EA: axial stiffness (N); ``None`` for an inextensible line.
        cb: seabed friction coefficient CB (>= 0).
        seabed: whether the anchor lies on a horizontal seabed that the line can rest on;
            ``False`` lets the line hang freely (below the anchor if it must).
    """
    anchor = _checks.vector3("catenary.anchor", anchor)
    fairlead = _checks.vector3("catenary.fairlead", fairlead)
    L = _checks.positive("catenary.length", length, "m")
    w = _checks.positive("catenary.w", w, "N/m")
    EA = math.inf if EA is None else _checks.positive("catenary.EA", EA, "N")
    cb = _checks.non_negative("catenary.cb", cb)
    d = fairlead - anchor
    XF, ZF = math.hypot(d[0], d[1]), float(d[2])
    if XF < 1e-9:
        raise ValueError("catenary: anchor and fairlead are on one vertical; the span must be > 0 m")
    if ZF < 0:
        raise ValueError("catenary.fairlead must not be lower than the anchor (swap the ends)")
    if EA == math.inf and math.hypot(XF, ZF) >= L:
        raise ValueError(f"catenary.length must exceed the distance between the ends ({math.hypot(XF, ZF):.6g} m) "
                         "for an inextensible line")
    # Jonkman's starting guess
    chord = math.hypot(XF, ZF)
    lam = 0.2 if chord >= L else math.sqrt(3 * ((L * L - ZF * ZF) / (XF * XF) - 1))
    H0 = max(abs(w * XF / (2 * lam)), 1e-6 * w * L)
    V0 = w / 2 * (ZF / math.tanh(lam) + L)

    def fun(p):
        try:
            H, VF = math.exp(float(p[0])), float(p[1]) * w * L
            rx, rz = _residual(H, VF, XF, ZF, L, w, EA, cb, seabed)
        except (OverflowError, ZeroDivisionError):  # (a trial far out: H or V/H past a float)
            return [1e10, 1e10]
        return [rx / L, rz / L]

    sol = root(fun, [math.log(H0), V0 / (w * L)], method="hybr", options={"xtol": 1e-13})
    if not sol.success or max(abs(r) for r in sol.fun) > 1e-9:
        raise RuntimeError(f"catenary did not converge: {sol.message}")
    H, VF = math.exp(sol.x[0]), sol.x[1] * w * L
    LB = max(L - VF / w, 0.0) if seabed else 0.0
    return ElasticCatenary(anchor, fairlead, L, w, EA, cb, H, VF, LB)

"""Control fins (rudders, stern planes) of a torpedo vehicle: their lift and drag, and the MuJoCo
actuator that holds each fin's angle.

A fin at ``position`` on the hull, deflected by delta, gives lift along ``lift_direction`` (the
force a positive delta makes; across the hull's axis) and drag against the hull's axis, as in
Fossen (2021, Sec. 8.4.2; his REMUS 100 model):

    L = 1/2 rho U^2 A CL(delta),    D = 1/2 rho U^2 A CL_delta delta^2,

with U the flow speed across the fin's span (for a rudder, whose span is vertical,
sqrt(u_r^2 + v_r^2)), CL(delta) = CL_delta delta up to the stall angle and ``post_stall_lift``
of that peak beyond it. As in Fossen's model the angle of attack is the deflection: the flow
turned by the hull's own sway and yaw at the fin is not added.

The fin's actuator (``{body}/{name}``) takes the commanded angle (rad), clipped to
+-``max_angle``, and lags it with ``time_constant`` (its ``filterexact`` activation is the
angle); it makes no force itself: ``vehicle.BoundVehicle`` applies the fin's lift and drag.

Units SI (angles rad inside; the vehicle file gives degrees); body frame x forward, y left, z up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from mjtether import _checks


@dataclass(frozen=True)
class Fin:
    """A control fin (or a pair acting together): ``position`` (m, body), ``lift_direction``
    (body unit vector, across x), planform ``area`` A (m^2), lift slope ``cl_delta`` (1/rad),
    largest deflection ``max_angle`` (rad), ``time_constant`` of its servo (s); ``stall_angle``
    (rad, None: no stall within ``max_angle``) beyond which the lift falls to ``post_stall_lift``
    of its peak."""

    name: str
    position: tuple
    lift_direction: tuple
    area: float
    cl_delta: float
    max_angle: float
    time_constant: float = 0.1
    stall_angle: float | None = None
    post_stall_lift: float = 0.5

    def __post_init__(self):
        _checks.text("fin.name", self.name)
        object.__setattr__(self, "position", tuple(_checks.vector3(f"{self.name}.position", self.position)))
        d = np.asarray(_checks.vector3(f"{self.name}.lift_direction", self.lift_direction))
        n = float(np.linalg.norm(d))
        if n < 1e-9 or abs(d[0]) > 1e-6 * n:
            raise ValueError(f"{self.name}.lift_direction must be a nonzero vector across the hull's axis "
                             f"(x component 0), got {self.lift_direction!r}")
        object.__setattr__(self, "lift_direction", tuple(d / n))
        _checks.positive(f"{self.name}.area", self.area, "m^2")
        _checks.positive(f"{self.name}.cl_delta", self.cl_delta, "1/rad")
        if not (0.0 < self.max_angle <= math.pi / 2):
            raise ValueError(f"{self.name}.max_angle must be in (0, 90] deg, got {math.degrees(self.max_angle):g} deg")
        _checks.positive(f"{self.name}.time_constant", self.time_constant, "s")
        if self.stall_angle is not None and not (0.0 < self.stall_angle <= math.pi / 2):
            raise ValueError(f"{self.name}.stall_angle must be in (0, 90] deg, got "
                             f"{math.degrees(self.stall_angle):g} deg")
        if not (0.0 <= self.post_stall_lift <= 1.0):
            raise ValueError(f"{self.name}.post_stall_lift must be in [0, 1], got {self.post_stall_lift!r}")

    @property
    def span(self) -> np.ndarray:
        """The fin's span direction (body unit vector): x cross the lift direction."""
        ell = np.asarray(self.lift_direction)
        return np.array([0.0, -ell[2], ell[1]])

    @property
    def yaw_per_angle(self) -> float:
        """The yaw moment's share of the lift (m): (r x lift direction)_z; nonzero for a rudder."""
        r, ell = self.position, self.lift_direction
        return float(r[0] * ell[1] - r[1] * ell[0])


def lift_coefficient(delta: float, fin: Fin) -> float:
    """CL at deflection ``delta`` (rad): linear, then ``post_stall_lift`` of the peak past stall."""
    if fin.stall_angle is None or abs(delta) <= fin.stall_angle:
        return fin.cl_delta * delta
    return math.copysign(fin.cl_delta * fin.stall_angle * fin.post_stall_lift, delta)


def fin_wrench(nu_r: np.ndarray, delta: float, fin: Fin, rho: float) -> np.ndarray:
    """The fin's lift and drag as a body-frame wrench (N, N m) about the origin, at relative
    velocity ``nu_r`` (body frame) and deflection ``delta`` (rad)."""
    v = nu_r[:3]
    s = fin.span
    U2 = float(v @ v) - float(s @ v) ** 2
    q = 0.5 * rho * U2 * fin.area
    f = q * lift_coefficient(delta, fin) * np.asarray(fin.lift_direction)
    f[0] -= math.copysign(q * fin.cl_delta * delta * delta, v[0])  # against the hull's way
    r = fin.position
    return np.array([f[0], f[1], f[2], r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]])


def add_fin(spec: mujoco.MjSpec, body: str, fin: Fin) -> str:
    """Add ``fin`` to the body named ``body``: a site ``{body}/{fin.name}`` and an actuator of the
    same name whose control is the commanded angle (rad) and whose activation is the angle (no
    force of its own). Returns the actuator's name."""
    b = spec.body(body)
    if b is None:
        raise ValueError(f"add_fin: no body named {body!r} in the spec")
    name = f"{body}/{fin.name}"
    b.add_site(name=name, pos=list(fin.position), size=[0.015, 0.0, 0.0])
    a = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_SITE)
    a.dyntype = mujoco.mjtDyn.mjDYN_FILTEREXACT
    a.dynprm[0] = fin.time_constant
    a.gaintype = mujoco.mjtGain.mjGAIN_FIXED
    a.gainprm[0] = 0.0
    a.biastype = mujoco.mjtBias.mjBIAS_NONE
    a.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
    a.ctrlrange = [-fin.max_angle, fin.max_angle]
    return name

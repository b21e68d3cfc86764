"""The hexapod seabed walker: model loading, hydrodynamics and a tripod gait.

The MJCF is ``assets/walker/walker.xml`` (``scene.xml`` stands it on a seabed), installed as the
package data ``mjtether.assets`` (see pyproject.toml) and found through ``importlib.resources``
so that it works from a wheel as well as from the source tree. ``Tripod``
turns a commanded forward speed v (m/s, body x) and turn rate w (rad/s, about z) into the 18
joint targets of the position actuators: legs {lf, rm, lr} and {rf, lm, rr} alternate between
stance, where each foot moves in the body frame at -(v x + w z x p) so that the body moves at
(v, w) if the feet do not slip, and swing, where the foot returns along the same line lifted by
``step_height`` on a half sine. Feet positions go through the analytic inverse kinematics of
each 3-joint leg (coxa yaw, femur and tibia pitch). Units SI; body frame x forward, z up.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from mjtether.files.packagedata import asset_dir
from mjtether.physics import compiled
from mjtether.physics.rigidbody import RigidBodyHydro


def _assets() -> Path:
    """The folder of the walker's MJCF files (``packagedata.asset_dir``)."""
    return asset_dir("walker", "walker.xml")


ASSETS = _assets()
LEGS = ("lf", "lm", "lr", "rf", "rm", "rr")
TRIPOD_A = ("lf", "rm", "lr")
COXA, FEMUR, TIBIA = 0.15, 0.5, 0.8  # link lengths (m); the foot sphere centre ends the tibia
MASS = 650.0  # kg in air

HYDRO = RigidBodyHydro(
    # hull and legs displace 0.38 m^3: 3.82 kN of buoyancy in 1025 kg/m^3 against 6.38 kN of
    # weight, 2.56 kN submerged weight (39 % of the weight in air)
    volume=0.38, centre_of_buoyancy=(0.0, 0.0, 0.1),
    drag_cd=(1.0, 1.0, 1.2), drag_area=(1.0 * 0.4 + 0.6, 1.6 * 0.4 + 0.6, 1.6 * 1.0 + 0.4),
    added_mass=(160.0, 330.0, 900.0), added_inertia=(60.0, 120.0, 150.0), angular_drag=(300.0, 600.0, 600.0),
    height=1.1)
"""Rigid-body hydrodynamics of the walker, on the torso (legs lumped in)."""


@functools.cache
def _parsed_walker() -> mujoco.MjSpec:
    return mujoco.MjSpec.from_file(str(ASSETS / "walker.xml"))


def walker_spec() -> mujoco.MjSpec:
    """The walker alone (its torso body is ``torso``, its tow point site ``tow_point``): a
    copy of ``assets/walker.xml`` parsed once (a copy takes a tenth of a parse)."""
    return _parsed_walker().copy()


def leg_ik(p) -> tuple[float, float, float]:
    """Joint angles (coxa, femur, tibia) in rad that put the foot centre at ``p`` (m, leg frame:
    x out of the hip, z up). Knee up; raises ValueError if out of reach."""
    x, y, z = (float(c) for c in p)
    q0 = math.atan2(y, x)
    r = math.hypot(x, y) - COXA
    D = math.hypot(r, z)
    if not abs(FEMUR - TIBIA) < D < FEMUR + TIBIA:
        raise ValueError(f"leg_ik: foot target {[x, y, z]} is out of reach")
    gamma = math.acos((FEMUR**2 + D * D - TIBIA**2) / (2 * FEMUR * D))
    a1 = math.atan2(z, r) + gamma
    a2 = math.atan2(z - FEMUR * math.sin(a1), r - FEMUR * math.cos(a1))
    q1 = -a1
    phi = math.atan2(-math.cos(a2), -math.sin(a2))
    return q0, q1, phi - q1


@dataclass
class Tripod:
    """Tripod gait (see the module docstring).

    Attributes:
        period: gait cycle (s); each tripod is in stance for half of it.
        step_height: foot lift in swing (m).
        max_stride: longest stance stroke (m); faster commands are clipped to max_stride / (period / 2).
    """

    period: float = 1.2
    step_height: float = 0.15
    max_stride: float = 0.6

    def __post_init__(self):
        self.phase = 0.0
        self._legs = None

    @property
    def top_speed(self) -> float:
        return self.max_stride / (self.period / 2)

    def bind(self, model: mujoco.MjModel, prefix: str = "") -> "Tripod":
        """Read hip poses and actuator indices from a compiled model."""
        legs, acts = [], []
        for leg in LEGS:
            b = model.body(f"{prefix}leg_{leg}")
            yaw = 2 * math.atan2(b.quat[3], b.quat[0])
            hx, hy, hz = (float(c) for c in b.pos)
            c, s = math.cos(yaw), math.sin(yaw)
            reach = COXA + FEMUR  # neutral foot: straight out of the hip, TIBIA below it
            legs.append((hx, hy, hz, c, s, hx + c * reach, hy + s * reach, hz - TIBIA,
                         0.0 if leg in TRIPOD_A else 0.5))
            acts += [model.actuator(f"{prefix}{leg}_{j}").id for j in ("coxa", "femur", "tibia")]
        self._legs = legs
        self._leg_table = np.array(legs, dtype=float)  # (for the compiled gait)
        self._out = np.empty(3 * len(legs))
        self._fast = compiled.backend() == "numba"
        self.actuators = np.array(acts)
        return self

    def targets(self, dt: float, speed: float, turn_rate: float):
        """Advance the phase by ``dt`` (s) and return the 18 target angles (rad) of
        ``self.actuators`` (leg by leg in ``LEGS`` order: coxa, femur, tibia). Scalar code:
        six legs are too few for NumPy to pay off, and this runs at the control rate; with the
        compiled kernels, ``tripod_targets``, in an array that the next call overwrites.
        A foot out of reach raises ValueError (``leg_ik``)."""
        if self._legs is None:
            raise RuntimeError("Tripod.bind(model) first")
        self.phase = (self.phase + dt / self.period) % 1.0
        half = self.period / 2
        if self._fast:  # the same arithmetic, compiled (tests/scenario/test_walker.py)
            bad = tripod_targets(self.phase, self._leg_table, float(speed), float(turn_rate), half,
                               self.max_stride, self.step_height, COXA, FEMUR, TIBIA, self._out)
            if bad < 0:
                return self._out
        out = []
        for hx, hy, hz, c, s, nx, ny, nz, offset in self._legs:
            ph = (self.phase + offset) % 1.0
            # stance stroke over half a cycle: the body's velocity at the foot, clipped
            dx, dy = (speed - turn_rate * ny) * half, turn_rate * nx * half
            n = math.hypot(dx, dy)
            if n > self.max_stride:
                dx, dy = dx * self.max_stride / n, dy * self.max_stride / n
            if ph < 0.5:  # stance
                a, lift = 0.5 - 2 * ph, 0.0
            else:  # swing
                sig = 2 * ph - 1
                a, lift = sig - 0.5, self.step_height * math.sin(math.pi * sig)
            fx, fy, fz = nx + a * dx - hx, ny + a * dy - hy, nz + lift - hz
            out += leg_ik((c * fx + s * fy, -s * fx + c * fy, fz))  # R^T (foot - hip)
        return out


@compiled.jit
def tripod_targets(phase, legs, speed, turn_rate, half, max_stride, step_height, coxa, femur, tibia, out):
    """``Tripod.targets`` after its phase update: the 18 joint targets (rad) into ``out``
    for ``phase`` (0-1), each leg's row of ``legs`` (hip x, y, z, cos and sin of its yaw, neutral
    foot x, y, z, phase offset; m), the commanded ``speed`` (m/s) and ``turn_rate`` (rad/s), half
    the gait period (s), the stride limit and step height (m) and the link lengths (m) of
    ``leg_ik``. Returns the index of the first leg whose foot is out of reach, or -1."""
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
        x, y, z = c * fx + s * fy, -s * fx + c * fy, fz  # R^T (foot - hip): leg_ik from here
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

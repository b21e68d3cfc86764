"""A free-swimming vehicle in MuJoCo: a rigid body whose hydrodynamics follow Fossen's
manoeuvring equations (``fossen``), with the added mass in MuJoCo's mass matrix.

The body has three slide joints along the world axes (its origin, CO) and a ball joint (its
orientation, no singularity), so MuJoCo integrates M_RB nu' + C_RB(nu) nu and the weight at the
centre of gravity itself. The added mass is split:

* into MuJoCo's mass matrix (stable whatever its size, as for a light ROV whose added mass
  exceeds its own): the linear block of M_A through three fixed tendons over the slide joints,
  each along one of the block's principal axes turned with the body (coefficients updated at
  every step; MuJoCo uses them from the next step's mass matrix on), with that axis's added
  mass as tendon armature; the diagonal of the angular block as the ball joint's armature
  (MuJoCo's ball velocity is in the body frame);
* explicit, from the last step's acceleration: what remains (the angular block's products and
  the linear-angular coupling; zero for the bodies of revolution and box-like ROVs shipped).

Explicitly, as passive forces each step: C_A(nu_r) nu_r (the Munk moment), D(nu_r) nu_r, the
buoyancy rho(z) g V at the centre of buoyancy, and the term M_A (omega x nu_r) that turns the
tendons' world-frame inertia into Fossen's body-frame M_A nu_r' (for a current uniform and
steady in the world: nu_c' = -omega x nu_c in the body). The current is the water column's at the
body origin's depth; its change with depth along the vehicle's path (w du/dz) is neglected in
nu_c'. The vehicle is taken fully submerged.

Units SI; world z up; body x forward, y left, z up.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np

from . import _checks
from .fossen import cross, damping_force, m2c, restoring_force
from .rigidbody import make_not_simple


def _matrix6(name: str, value) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if a.shape == (6,):
        a = np.diag(a)
    if a.shape != (6, 6) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be 6 numbers (a diagonal) or a 6x6 matrix, got shape {a.shape}")
    return a


@dataclass(frozen=True)
class VehicleHydro:
    """A vehicle's hydrodynamic parameters (Fossen's form; body frame x forward, y left, z up).

    Attributes:
        volume: displaced volume V (m^3); buoyancy rho g V acts at ``centre_of_buoyancy``.
        centre_of_buoyancy: r_b (m, body frame).
        added_mass: M_A, 6x6 or its diagonal (kg, kg m, kg m^2), symmetric, positive definite.
        linear_damping: D_L, 6x6 or its diagonal (N s/m, N m s/rad ...).
        quadratic_damping: D_Q per axis, 6 numbers (N s^2/m^2, N m s^2/rad^2).
    """

    volume: float
    centre_of_buoyancy: tuple = (0.0, 0.0, 0.0)
    added_mass: np.ndarray = field(default_factory=lambda: np.zeros(6))
    linear_damping: np.ndarray = field(default_factory=lambda: np.zeros(6))
    quadratic_damping: np.ndarray = field(default_factory=lambda: np.zeros(6))

    def __post_init__(self):
        _checks.non_negative("hydro.volume", self.volume, "m^3")
        object.__setattr__(self, "centre_of_buoyancy", tuple(_checks.vector3("hydro.centre_of_buoyancy",
                                                                              self.centre_of_buoyancy)))
        MA = _matrix6("hydro.added_mass", self.added_mass)
        if np.max(np.abs(MA - MA.T)) > 1e-9 * max(np.max(np.abs(MA)), 1.0):
            raise ValueError("hydro.added_mass must be symmetric")
        if np.min(np.linalg.eigvalsh(MA)) < -1e-9 * max(np.max(np.abs(MA)), 1.0):
            raise ValueError("hydro.added_mass must be positive semi-definite")
        object.__setattr__(self, "added_mass", MA)
        object.__setattr__(self, "linear_damping", _matrix6("hydro.linear_damping", self.linear_damping))
        q = np.asarray(self.quadratic_damping, dtype=float)
        if q.shape != (6,) or not np.all(np.isfinite(q)) or np.any(q < 0):
            raise ValueError("hydro.quadratic_damping must be 6 numbers >= 0")
        object.__setattr__(self, "quadratic_damping", q)


@dataclass
class VehicleModel:
    """What ``add_vehicle`` put in the spec; pass it to ``Simulation(bodies=...)``."""

    name: str
    hydro: VehicleHydro


def add_vehicle(spec: mujoco.MjSpec, name: str, *, mass: float, inertia, hydro: VehicleHydro,
                centre_of_gravity=(0.0, 0.0, 0.0), pos=(0.0, 0.0, 0.0), size=(0.5, 0.1, 0.1),
                rgba=(0.95, 0.75, 0.1, 1.0)) -> VehicleModel:
    """Add a vehicle body ``name`` at ``pos`` (m, world) to ``spec``: mass (kg) and principal
    ``inertia`` (3 numbers, kg m^2, about the centre of gravity ``centre_of_gravity``, body
    axes); an ellipsoid of semi-axes ``size`` (m) is drawn (it has no mass and no contacts).
    Sites: ``{name}/origin``. Set the orientation through the ball joint's qpos (w, x, y, z)."""
    _checks.positive(f"{name}.mass", mass, "kg")
    I = np.asarray(inertia, dtype=float)
    if I.shape != (3,) or not np.all(np.isfinite(I)) or np.any(I <= 0):
        raise ValueError(f"{name}.inertia must be 3 principal moments > 0 (kg m^2), got {inertia!r}")
    if not isinstance(hydro, VehicleHydro):
        raise ValueError("hydro must be a VehicleHydro")
    body = spec.worldbody.add_body(name=name, pos=list(pos))
    body.explicitinertial = True
    body.mass = float(mass)
    body.ipos = list(_checks.vector3(f"{name}.centre_of_gravity", centre_of_gravity))
    body.inertia = list(I)
    for k, axis in enumerate("xyz"):
        j = body.add_joint(name=f"{name}/{axis}", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=list(np.eye(3)[k]))
        j.armature = 0.0
    body.add_joint(name=f"{name}/ball", type=mujoco.mjtJoint.mjJNT_BALL)
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_ELLIPSOID, size=list(size), contype=0, conaffinity=0, mass=0.0,
                  rgba=list(rgba))
    body.add_site(name=f"{name}/origin")
    for k in range(3):  # the linear added mass along its principal axes (BoundVehicle turns them)
        t = spec.add_tendon(name=f"{name}/added_mass{k}")
        for j, axis in enumerate("xyz"):
            t.wrap_joint(f"{name}/{axis}", float(j == k))
    return VehicleModel(name, hydro)


class BoundVehicle:
    """A ``VehicleModel`` bound to a compiled model: its mass-matrix share of the added mass and
    its passive forces (see the module docstring)."""

    def __init__(self, vm: VehicleModel, model: mujoco.MjModel, water):
        self.name, self.hydro, self.water = vm.name, vm.hydro, water
        self.id = model.body(vm.name).id
        slide = model.joint(f"{vm.name}/x")
        ball = model.joint(f"{vm.name}/ball")
        self._v = slice(int(slide.dofadr[0]), int(slide.dofadr[0]) + 3)
        self._w = slice(int(ball.dofadr[0]), int(ball.dofadr[0]) + 3)
        t0 = model.tendon(f"{vm.name}/added_mass0").id
        self._ten = slice(t0, t0 + 3)
        w0 = int(model.tendon_adr[t0])
        self._prm = model.wrap_prm[w0:w0 + 9].reshape(3, 3)  # a view: tendon k's coefficients on x, y, z
        MA = vm.hydro.added_mass
        lam, E = np.linalg.eigh(MA[:3, :3])
        self._axes = E  # body-frame principal axes of the linear block (columns)
        model.tendon_armature[self._ten] = np.maximum(lam, 0.0)
        model.dof_armature[self._w] = np.diag(MA[3:, 3:])
        implicit = np.zeros((6, 6))
        implicit[:3, :3] = MA[:3, :3]
        implicit[3:, 3:] = np.diag(np.diag(MA[3:, 3:]))
        self._explicit = MA - implicit
        self._has_explicit = bool(np.any(self._explicit != 0.0))
        self._M_lin = MA[:3, :3].copy()
        self._r_b = np.asarray(vm.hydro.centre_of_buoyancy, dtype=float)
        make_not_simple(model, self.id)
        self._orient(np.eye(3))

    def _orient(self, R: np.ndarray) -> None:
        """Turn the added-mass tendons along the linear block's principal axes at orientation R."""
        self._prm[:] = (R @ self._axes).T

    def velocity(self, data) -> tuple[np.ndarray, np.ndarray]:
        """(nu (6,), body frame: linear velocity of the origin and angular velocity; R body to
        world)."""
        R = data.xmat[self.id].reshape(3, 3)
        return np.concatenate([R.T @ data.qvel[self._v], data.qvel[self._w]]), R

    def wrench(self, model, data) -> np.ndarray:
        """The hydrodynamic wrench (body frame, about the origin) MuJoCo does not make itself."""
        nu, R = self.velocity(data)
        z = np.array([min(float(data.xpos[self.id][2]), 0.0)])
        nu_c = np.zeros(6)
        nu_c[:3] = R.T @ self.water.velocity(z)[0]
        nu_r = nu - nu_c
        h = self.hydro
        MA = h.added_mass
        tau = -(m2c(MA, nu_r) @ nu_r) - damping_force(nu_r, h.linear_damping, h.quadratic_damping)
        tau[:3] += self._M_lin @ cross(nu[3:], nu_r[:3])
        B = float(self.water.rho(z)[0]) * self.water.gravity * h.volume
        tau -= restoring_force(R, 0.0, B, np.zeros(3), self._r_b)  # the buoyancy (MuJoCo weighs it)
        if self._has_explicit:  # the rest of M_A nu', from the last step's acceleration
            a = np.concatenate([R.T @ data.qacc[self._v] - cross(nu[3:], nu[:3]), data.qacc[self._w]])
            tau -= self._explicit @ a
        return tau

    def apply(self, model, data) -> None:
        tau = self.wrench(model, data)
        R = data.xmat[self.id].reshape(3, 3)
        data.qfrc_passive[self._v] += R @ tau[:3]
        data.qfrc_passive[self._w] += tau[3:]
        self._orient(R)

"""Hydrodynamics of rigid bodies (a robot, a suspended weight, a vehicle).

``RigidBodyHydro`` describes one body; ``add_body_hydro`` records it for a body of a
``mujoco.MjSpec``. At run time the simulation applies buoyancy at the centre of buoyancy,
quadratic drag per body axis on the relative velocity (current minus body), and angular
drag, through the same passive-force callback as the tether (``mjtether.physics.dispatch``).

Added mass goes into the mass matrix as armature of the body's free joint, where MuJoCo
integrates it implicitly: the rotational part exactly (free-joint angular dofs are in the
body frame), the translational part per world axis (x and y take the mean of the body's
x and y added masses, z the body's z added mass; exact for a body that stays upright).
Bodies without a free joint get buoyancy and drag only.

Waves (``WaterColumn.waves``): the sea is evaluated once per step at the centre of buoyancy
(where the loads act; the body is taken small against the wave length). The drag acts on the
current plus the particle velocity there, less the body's velocity; the wet fraction follows the
instantaneous surface (the centre of buoyancy's height over the elevation above it, over
``height``); and Morison's inertia term rho (V + V_a) a, Froude-Krylov plus the added mass (C_m =
1 + C_a), acts on the particles' local acceleration a, times the wet fraction. The added mass in
it is what the model carries: a free body's armature per world axis (x and y the mean of its x and
y added masses, z its z), so that a neutrally buoyant free body moves with the water; a body
without a free joint (welded, pinned) takes its body-axis added masses turned to the world,
R diag(m_a) R^T. ``wave_loads`` states them (the sea from ``WaveField.state``); the native
callback runs their compiled twin (``compiled.rigid_body_wave_loads``); without waves nothing
changes.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from mjtether import _checks
from mjtether.physics import compiled

from .hydro import rigid_body_loads


def _triple(name, value, check):
    v = np.broadcast_to(np.asarray(value, dtype=float), (3,)).copy()
    for k, c in zip("xyz", v):
        check(f"{name}[{k}]", c)
    return tuple(float(c) for c in v)


@dataclass(frozen=True)
class RigidBodyHydro:
    """Hydrodynamic description of one body; vectors are per body axis x, y, z.

    Attributes:
        volume: displaced volume when fully submerged (m^3).
        centre_of_buoyancy: body-frame position (m).
        drag_cd: drag coefficients C_d.
        drag_area: projected areas S (m^2) normal to each axis.
        added_mass: added mass along each axis (kg).
        added_inertia: added rotational inertia about each axis (kg m^2).
        angular_drag: c (N m s^2) in M = -c |w| w about each axis.
        height: vertical extent (m) over which the body pierces the surface.
    """

    volume: float
    centre_of_buoyancy: tuple = (0.0, 0.0, 0.0)
    drag_cd: tuple = (1.0, 1.0, 1.0)
    drag_area: tuple = (0.0, 0.0, 0.0)
    added_mass: tuple = (0.0, 0.0, 0.0)
    added_inertia: tuple = (0.0, 0.0, 0.0)
    angular_drag: tuple = (0.0, 0.0, 0.0)
    height: float = 1.0

    def __post_init__(self):
        nn = _checks.non_negative
        _checks.non_negative("hydro.volume", self.volume, "m^3")
        object.__setattr__(self, "centre_of_buoyancy",
                           tuple(_checks.vector3("hydro.centre_of_buoyancy", self.centre_of_buoyancy)))
        for f in ("drag_cd", "drag_area", "added_mass", "added_inertia", "angular_drag"):
            object.__setattr__(self, f, _triple(f"hydro.{f}", getattr(self, f), nn))
        _checks.positive("hydro.height", self.height, "m")


@dataclass
class BodyHydroModel:
    body: str
    hydro: RigidBodyHydro


def add_body_hydro(spec: mujoco.MjSpec, body: str, hydro: RigidBodyHydro) -> BodyHydroModel:
    """Record ``hydro`` for the body named ``body`` of ``spec``; pass the result to
    ``Simulation(bodies=...)``."""
    if spec.body(body) is None:
        raise ValueError(f"add_body_hydro: no body named {body!r} in the spec")
    if not isinstance(hydro, RigidBodyHydro):
        raise ValueError("hydro must be a RigidBodyHydro")
    return BodyHydroModel(body, hydro)


def make_not_simple(model: mujoco.MjModel, body_ids) -> None:
    """MuJoCo computes the mass matrix of "simple" bodies from values cached at compile time,
    which ignore mass and armature set afterwards; take the bodies off that fast path."""
    model.body_simple[np.atleast_1d(body_ids)] = 0
    simple = model.body_simple[model.dof_bodyid] != 0
    count = 0
    for k in range(model.nv - 1, -1, -1):
        count = count + 1 if simple[k] else 0
        model.dof_simplenum[k] = count


class BoundBodyHydro:
    """A ``BodyHydroModel`` bound to a compiled model: indices, armature, force provider."""

    def __init__(self, bm: BodyHydroModel, model: mujoco.MjModel, water):
        self.name = bm.body
        self.hydro = h = bm.hydro
        self.water = water
        self.id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, bm.body)
        self._cob = np.asarray(h.centre_of_buoyancy, dtype=float)
        self._cd = np.asarray(h.drag_cd, dtype=float)
        self._area = np.asarray(h.drag_area, dtype=float)
        self._ang = np.asarray(h.angular_drag, dtype=float)
        jnt = model.body_jntadr[self.id]
        if jnt >= 0 and model.jnt_type[jnt] == mujoco.mjtJoint.mjJNT_FREE:
            dof = model.jnt_dofadr[jnt]
            ma = h.added_mass
            model.dof_armature[dof:dof + 3] += [0.5 * (ma[0] + ma[1])] * 2 + [ma[2]]
            model.dof_armature[dof + 3:dof + 6] += h.added_inertia
            make_not_simple(model, self.id)
        elif jnt >= 0 and model.jnt_type[jnt] == mujoco.mjtJoint.mjJNT_BALL:
            # turning about the pin at r from the body's origin (body frame) moves the origin at
            # w x r: the added mass's kinetic energy adds ma_j r_k^2 + ma_k r_j^2 about axis i
            # (the diagonal of S(r)^T M_A S(r); the cross terms are left out)
            r, ma = -model.jnt_pos[jnt], np.asarray(h.added_mass)
            dof = model.jnt_dofadr[jnt]
            model.dof_armature[dof:dof + 3] += np.asarray(h.added_inertia) + [
                ma[1] * r[2] ** 2 + ma[2] * r[1] ** 2, ma[0] * r[2] ** 2 + ma[2] * r[0] ** 2,
                ma[0] * r[1] ** 2 + ma[1] * r[0] ** 2]
            make_not_simple(model, self.id)
        self._free = jnt >= 0 and model.jnt_type[jnt] == mujoco.mjtJoint.mjJNT_FREE
        self._vel = np.zeros(6)
        # the compiled kernel (``compiled``), where it runs and knows the water's profiles
        self._codes = compiled.profile_codes(water) if compiled.backend() == "numba" else None
        self._force, self._torque = np.zeros(3), np.zeros(3)

    def native_table(self):
        """This body's arrays for the native callback (``native``, slots ``B_*``), or None where its
        loads need Python (the NumPy kernels, or a water profile the compiled kernels do not know); with
        waves, the sea's components (``WaveField``'s table) and the added mass ``wave_loads`` takes."""
        if self._codes is None:
            return None
        dkind, dp, ckind, cp = self._codes
        h, waves = self.hydro, self.water.waves
        sea = [] if waves is None else [
            waves._table.ravel(), np.array([waves.depth, waves.ramp_s, waves.stretching == "wheeler"], dtype=float),
            np.array([self._free, *h.added_mass], dtype=float)]
        return [np.array([self.id, dkind, ckind, waves is not None], dtype=np.int64),
                np.array([h.volume, h.height, self.water.gravity, *self._cob], dtype=float),
                self._cd, self._area, self._ang, dp, cp, *sea]

    def loads(self, model, data):
        """Force (N) at the centre of buoyancy, torque (N m) and that point, world frame."""
        R = data.xmat[self.id].reshape(3, 3)
        p = data.xpos[self.id] + R @ self._cob
        mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, self.id, self._vel, 0)
        w, v0 = self._vel[:3], self._vel[3:]
        rx, ry, rz = p - data.xpos[self.id]  # v at the centre of buoyancy = v0 + w x r
        v = v0 + (w[1] * rz - w[2] * ry, w[2] * rx - w[0] * rz, w[0] * ry - w[1] * rx)
        if self.water.waves is not None:
            f, tq = self.wave_loads(R, p, v, w, float(data.time))
            return f, tq, p
        if self._codes is not None:
            compiled.rigid_body_loads(R, p, v, w, self.hydro.volume, self.hydro.height,
                                      self._cd, self._area, self._ang, *self._codes, self.water.gravity,
                                      self._force, self._torque)
            return self._force.copy(), self._torque.copy(), p
        f, tq = rigid_body_loads(R, p, v, w, volume=self.hydro.volume, height=self.hydro.height,
                                 drag_cd=self._cd, drag_area=self._area, angular_drag=self._ang,
                                 rho_fn=self.water.rho, current_fn=self.water.velocity,
                                 gravity=self.water.gravity)
        return f, tq, p

    def added_mass_world(self, R: np.ndarray) -> np.ndarray:
        """The added mass (kg, 3x3, world axes) the model carries at orientation ``R``: a free
        body's armature per world axis, else R diag(m_a) R^T (see the module docstring)."""
        ma = np.asarray(self.hydro.added_mass, dtype=float)
        if self._free:
            return np.diag([0.5 * (ma[0] + ma[1])] * 2 + [ma[2]])
        return (R * ma) @ R.T

    def wave_loads(self, R, p, v, w, t: float):
        """Force (N) at the centre of buoyancy ``p`` (m, world) moving at ``v`` (m/s) and torque
        (N m), world frame, in the water column's waves at time ``t`` (s): buoyancy under the
        instantaneous surface, drag on current + particle velocity - ``v``, angular drag on ``w``
        (rad/s, world), and the inertia load rho (V + V_a) a (see the module docstring)."""
        h, water = self.hydro, self.water
        eta, uw, aw = water.waves.state(p[None, :], t)
        zz = np.array([min(float(p[2]), 0.0)])
        rho = float(water.rho(zz)[0])
        rise = float(p[2] - eta[0])  # the centre of buoyancy's height over the surface (m)
        frac = min(max(0.5 - rise / h.height, 0.0), 1.0) if h.height > 0 else float(rise <= 0)
        vrel_b = (water.velocity(zz)[0] + uw[0] - v) @ R  # body axes
        force = R @ ((0.5 * rho * frac) * self._cd * self._area * np.abs(vrel_b) * vrel_b)
        force += frac * (rho * h.volume * aw[0] + self.added_mass_world(R) @ aw[0])
        force[2] += rho * water.gravity * h.volume * frac
        w_b = w @ R
        return force, R @ (-frac * self._ang * np.abs(w_b) * w_b)

    def apply(self, model, data):
        f, tq, p = self.loads(model, data)
        mujoco.mj_applyFT(model, data, f, tq, p, self.id, data.qfrc_passive)

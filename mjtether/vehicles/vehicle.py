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
buoyancy rho(z) g V at the centre of buoyancy, a torpedo's hull lift, axial and cross-flow drag
(``Hull``; ``fossen.lift_drag``, ``fossen.crossflow_drag`` or ``fossen.crossflow_drag_fossen``),
its fins' lift and drag (``fins``) and its propeller's thrust (``propeller``), and the term
M_A (omega x nu_r) that turns the tendons' world-frame inertia into Fossen's body-frame
M_A nu_r' (for a current uniform and steady in the world: nu_c' = -omega x nu_c in the body).
The current is the water column's at the body origin's depth; its change with depth along
the vehicle's path (w du/dz) is neglected in nu_c'. At the surface a submerged vehicle keeps
the fraction of its hull under the water (``compiled.wet_fraction``: its centre of buoyancy's
height over its drawn ellipsoid's vertical extent) of its buoyancy, added-mass and damping
forces and hull loads, and a fin, its propeller or a thruster in the air gives nothing: a
positively buoyant vehicle floats, it does not fly.
(The added mass in MuJoCo's mass matrix stays whole.)

Waves (``WaterColumn.waves``): the sea is evaluated once per step at the centre of buoyancy
(the vehicle taken small against the wave length; for a surface vessel, at the centre of
buoyancy's x, y, half its mean draft V / A_wp under the instantaneous surface there, so that the
point stays in the water as the vessel rides the waves). The particle velocity there joins the
current in nu_c (drag, lift, fins, propeller, the Munk moment: everything on nu_r); the surface is
the instantaneous one (the wet fraction, a fin, propeller or thruster in the air, and a surface
vessel's hydrostatics all take the origin's height over the elevation there, so a floating vessel
heaves on its own hydrostatics); and Morison's inertia term acts on the particles' local
acceleration a (body axes): the Froude-Krylov force rho V a at the centre of buoyancy plus the
added mass's M_A[:, :3] a (the rest of Fossen's M_A nu_r'; C_m = 1 + C_a), times the wet
fraction. A surface vessel's waterline takes the elevation at one point, not the wave's slope:
the waves do not roll or pitch it through its hydrostatics (only through the FK moment about its
origin). The compiled kernel takes the waves as a shift of nu (only nu - nu_c and the angular
rates enter it) and of the origin's height (only its height over the surface enters the wet
fraction and the hydrostatics); the native callback knows no waves (a run with waves uses the
Python callback). Without waves nothing changes.

Units SI; world z up; body x forward, y left, z up.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np

from mjtether import _checks
from mjtether.physics import actuation, compiled
from mjtether.physics.rigidbody import make_not_simple

from .fins import fin_wrench
from .fossen import (cross, crossflow_drag, crossflow_drag_fossen, damping_force, lift_drag, m2c, restoring_force,
                     surface_restoring)
from .propeller import Propeller


def _matrix6(name: str, value) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if a.shape == (6,):
        a = np.diag(a)
    if a.shape != (6, 6) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be 6 numbers (a diagonal) or a 6x6 matrix, got shape {a.shape}")
    return a


class TrimDensityWarning(UserWarning):
    """A vehicle built in water of another density than the one its file says it is trimmed for
    (``vehicle.water_density``): its buoyancy differs from its trim by (rho_w - rho_trim) g V, and a
    vehicle neutral there sinks or rises here (the REMUS 100, neutral in 1026 kg/m^3, sinks 2.6 m in
    60 s in 1025 kg/m^3)."""


CROSSFLOW_SUMS = ("midpoint", "fossen")
"""How a ``Hull`` sums its cross-flow drag (``Hull.crossflow``)."""


@dataclass(frozen=True)
class Hull:
    """A slender hull of revolution's lift and drag (Fossen 2021, Sec. 8.4.2): ``length`` L and
    ``diameter`` D (m); axial drag coefficient ``axial_cd`` on the frontal area pi D^2 / 4;
    the 2-D ``crossflow_cd`` of its section, summed over ``strips`` strips; lift on the
    ``reference_area`` (m^2; Fossen: 0.7 L D) with span D and Oswald factor ``oswald``.

    ``crossflow`` picks the cross-flow sum: "midpoint" (the default; ``fossen.crossflow_drag``)
    takes the midpoint rule of the strip integral over the hull, in sway and heave along each
    strip's cross-flow (sway, heave, pitch and yaw loads); "fossen"
    (``fossen.crossflow_drag_fossen``) sums it as Fossen (2021) publishes it for his REMUS 100:
    ``strips`` + 1 points from tail to nose each weighted L / ``strips``, in sway and yaw only."""

    length: float
    diameter: float
    axial_cd: float
    crossflow_cd: float
    reference_area: float
    oswald: float = 0.7
    strips: int = 20
    crossflow: str = "midpoint"

    def __post_init__(self):
        for key, unit in (("length", "m"), ("diameter", "m"), ("reference_area", "m^2"), ("oswald", "")):
            _checks.positive(f"hull.{key}", getattr(self, key), unit)
        for key in ("axial_cd", "crossflow_cd"):
            _checks.non_negative(f"hull.{key}", getattr(self, key))
        _checks.positive_int("hull.strips", self.strips)
        if not isinstance(self.crossflow, str) or self.crossflow not in CROSSFLOW_SUMS:
            raise ValueError(f"hull.crossflow must be one of {', '.join(map(repr, CROSSFLOW_SUMS))}, "
                             f"got {self.crossflow!r}")

    def wrench(self, nu_r: np.ndarray, rho: float) -> np.ndarray:
        """Lift, axial and cross-flow drag (body frame, N, N m about the origin)."""
        cd0 = self.axial_cd * np.pi * self.diameter ** 2 / 4.0 / self.reference_area
        crossflow = crossflow_drag_fossen if self.crossflow == "fossen" else crossflow_drag
        return (lift_drag(nu_r, rho, self.reference_area, cd0, self.diameter, self.oswald)
                + crossflow(nu_r, rho, self.length, self.diameter, self.crossflow_cd, self.strips))


@dataclass(frozen=True)
class Surface:
    """A surface vessel's hydrostatics (``fossen.surface_restoring``) and cross-flow drag: its
    ``waterplane_area`` A_wp (m^2), transverse and longitudinal metacentric heights ``gm_t`` and
    ``gm_l`` (m, above the centre of gravity), the volume it displaces fully submerged,
    ``max_volume`` (m^3), and its ``centre_of_flotation`` (x, y: m, body frame; the centroid of
    the waterplane, where a change of draft acts). The body origin is on the design waterline,
    where it displaces ``VehicleHydro.volume``.

    Cross-flow drag in sway and yaw (Fossen 2021, Sec. 6.7.2, as for surface craft): ``strips``
    strips along the ``length`` (m, about the origin), each of height ``draft`` (m) with the 2-D
    drag coefficient ``crossflow_cd`` (0: none) in the flow across it (``fossen.crossflow_drag``
    with the heave flow left out)."""

    waterplane_area: float
    gm_t: float
    gm_l: float
    max_volume: float
    centre_of_flotation: tuple = (0.0, 0.0)
    length: float = 0.0
    draft: float = 0.0
    crossflow_cd: float = 0.0
    strips: int = 20

    def __post_init__(self):
        for key, unit in (("waterplane_area", "m^2"), ("gm_t", "m"), ("gm_l", "m"), ("max_volume", "m^3")):
            _checks.positive(f"surface.{key}", getattr(self, key), unit)
        cf = np.asarray(self.centre_of_flotation, dtype=float)
        if cf.shape != (2,) or not np.all(np.isfinite(cf)):
            raise ValueError(f"surface.centre_of_flotation must be 2 numbers (x, y; m), got {self.centre_of_flotation!r}")
        object.__setattr__(self, "centre_of_flotation", (float(cf[0]), float(cf[1])))
        for key, unit in (("length", "m"), ("draft", "m"), ("crossflow_cd", "")):
            _checks.non_negative(f"surface.{key}", getattr(self, key), unit)
        _checks.positive_int("surface.strips", self.strips)
        if self.crossflow_cd > 0.0 and (self.length <= 0.0 or self.draft <= 0.0):
            raise ValueError("surface.crossflow_cd > 0 needs surface.length > 0 and surface.draft > 0 (m)")

    def crossflow(self, nu_r: np.ndarray, rho: float) -> np.ndarray:
        """Cross-flow drag in sway and yaw (body frame, N, N m about the origin)."""
        if self.crossflow_cd == 0.0:
            return np.zeros(6)
        flat = np.array([nu_r[0], nu_r[1], 0.0, nu_r[3], 0.0, nu_r[5]])
        return crossflow_drag(flat, rho, self.length, self.draft, self.crossflow_cd, self.strips)


@dataclass(frozen=True)
class VehicleHydro:
    """A vehicle's hydrodynamic parameters (Fossen's form; body frame x forward, y left, z up).

    Attributes:
        volume: displaced volume V (m^3); buoyancy rho g V acts at ``centre_of_buoyancy``.
        centre_of_buoyancy: r_b (m, body frame).
        added_mass: M_A, 6x6 or its diagonal (kg, kg m, kg m^2), symmetric, positive definite.
        linear_damping: D_L, 6x6 or its diagonal (N s/m, N m s/rad ...).
        quadratic_damping: D_Q per axis, 6 numbers (N s^2/m^2, N m s^2/rad^2).
        linear_damping_fade: per axis (s/m): D_L's row k is scaled by exp(-fade_k U_r), U_r the
            relative speed (Fossen's REMUS 100 fades surge and sway linear damping so).
        coriolis_zeroed: (row, column) entries of C_A(nu_r) left out (0-based, Fossen's axis
            order u v w p q r), as Fossen's REMUS 100 model drops the Munk moments.
        hull: a torpedo's hull lift and drag (None: none).
        surface: a surface vessel's hydrostatics (None: a submerged vehicle, buoyant by
            rho g ``volume`` at ``centre_of_buoyancy``).
    """

    volume: float
    centre_of_buoyancy: tuple = (0.0, 0.0, 0.0)
    added_mass: np.ndarray = field(default_factory=lambda: np.zeros(6))
    linear_damping: np.ndarray = field(default_factory=lambda: np.zeros(6))
    quadratic_damping: np.ndarray = field(default_factory=lambda: np.zeros(6))
    linear_damping_fade: np.ndarray = field(default_factory=lambda: np.zeros(6))
    coriolis_zeroed: tuple = ()
    hull: Hull | None = None
    surface: Surface | None = None

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
        f = np.asarray(self.linear_damping_fade, dtype=float)
        if f.shape != (6,) or not np.all(np.isfinite(f)) or np.any(f < 0):
            raise ValueError("hydro.linear_damping_fade must be 6 numbers >= 0 (s/m)")
        object.__setattr__(self, "linear_damping_fade", f)
        pairs = tuple((int(i), int(j)) for i, j in self.coriolis_zeroed)
        if any(not (0 <= i < 6 and 0 <= j < 6) for i, j in pairs):
            raise ValueError(f"hydro.coriolis_zeroed must be (row, column) pairs in 0..5, got {self.coriolis_zeroed!r}")
        object.__setattr__(self, "coriolis_zeroed", pairs)
        if self.hull is not None and not isinstance(self.hull, Hull):
            raise ValueError("hydro.hull must be a Hull")
        if self.surface is not None:
            if not isinstance(self.surface, Surface):
                raise ValueError("hydro.surface must be a Surface")
            if self.surface.max_volume < self.volume:
                raise ValueError(f"surface.max_volume ({self.surface.max_volume:g} m^3) must be at least hydro.volume "
                                 f"({self.volume:g} m^3), what the vessel displaces floating")


@dataclass
class VehicleModel:
    """What ``add_vehicle`` put in the spec; pass it to ``Simulation(bodies=...)``."""

    name: str
    hydro: VehicleHydro
    fins: tuple = ()  # fins.Fin, their actuators named {name}/{fin.name}
    propeller: Propeller | None = None  # its actuator named {name}/{propeller.name}
    size: tuple = (0.5, 0.1, 0.1)  # m, the drawn ellipsoid's semi-axes: the hull's extent at the surface
    thrusters: tuple = ()  # thruster.Thruster, their actuators named {name}/{thruster.name}
    trim_density: float | None = None  # kg/m^3: the water it is trimmed for (None: none stated; no warning)
    file: str = ""  # the vehicle file it was read from ("": built in code)


def add_vehicle(spec: mujoco.MjSpec, name: str, *, mass: float, inertia, hydro: VehicleHydro,
                centre_of_gravity=(0.0, 0.0, 0.0), pos=(0.0, 0.0, 0.0), size=(0.5, 0.1, 0.1),
                rgba=(0.95, 0.75, 0.1, 1.0)) -> VehicleModel:
    """Add a vehicle body ``name`` at ``pos`` (m, world) to ``spec``: mass (kg) and ``inertia``
    (kg m^2, about the centre of gravity ``centre_of_gravity``, body axes): 3 principal moments,
    or the matrix's 6 entries Ixx, Iyy, Izz, Ixy, Ixz, Iyz (MuJoCo's ``fullinertia``); an
    ellipsoid of semi-axes ``size`` (m) is drawn (it has no mass and no contacts). Sites:
    ``{name}/origin``. Set the orientation through the ball joint's qpos (w, x, y, z)."""
    _checks.positive(f"{name}.mass", mass, "kg")
    I = np.asarray(inertia, dtype=float)
    if I.shape == (6,):
        full = np.array([[I[0], I[3], I[4]], [I[3], I[1], I[5]], [I[4], I[5], I[2]]])
        ok = np.all(np.isfinite(I)) and np.min(np.linalg.eigvalsh(full)) > 0
    else:
        ok = I.shape == (3,) and np.all(np.isfinite(I)) and np.all(I > 0)
    if not ok:
        raise ValueError(f"{name}.inertia must be 3 principal moments > 0 or the 6 entries (Ixx, Iyy, Izz, Ixy, "
                         f"Ixz, Iyz) of a positive definite matrix (kg m^2), got {inertia!r}")
    if not isinstance(hydro, VehicleHydro):
        raise ValueError("hydro must be a VehicleHydro")
    body = spec.worldbody.add_body(name=name, pos=list(pos))
    body.explicitinertial = True
    body.mass = float(mass)
    body.ipos = list(_checks.vector3(f"{name}.centre_of_gravity", centre_of_gravity))
    if I.shape == (6,):
        body.fullinertia = list(I)
    else:
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
    return VehicleModel(name, hydro, size=tuple(float(v) for v in size))


class BoundVehicle:
    """A ``VehicleModel`` bound to a compiled model: its mass-matrix share of the added mass and
    its passive forces (see the module docstring)."""

    def __init__(self, vm: VehicleModel, model: mujoco.MjModel, water):
        self.name, self.hydro, self.water = vm.name, vm.hydro, water
        self.id = model.body(vm.name).id
        self._model = model
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
        self._r_g = model.body_ipos[self.id].copy()  # the centre of gravity (body frame)
        self._zeroed = tuple(np.array(ij, dtype=int) for ij in zip(*vm.hydro.coriolis_zeroed)) or None
        self._fade = vm.hydro.linear_damping_fade if np.any(vm.hydro.linear_damping_fade) else None
        self.fins, self.propeller = tuple(vm.fins), vm.propeller
        self._size = np.asarray(vm.size, dtype=float)
        self._thr = np.array([[*t.position, *t.direction] for t in vm.thrusters], dtype=float).reshape(-1, 6)
        thr_ids = [model.actuator(f"{vm.name}/{t.name}").id for t in vm.thrusters]
        for t, a in zip(vm.thrusters, thr_ids):  # a transfer-function response, for this model's step
            if t.response is not None:
                actuation.set_response(model, a, *t.response)
        self._thr_act = np.asarray(actuation.delivered(model, np.array(thr_ids, dtype=int)), dtype=np.int64)
        # the fins' angles and the shaft speed are their actuators' activations
        self._fin_act = np.array([actuation.delivered(model, model.actuator(f"{vm.name}/{f.name}").id)
                                  for f in self.fins], dtype=int)
        self._prop_act = (None if vm.propeller is None else
                          int(actuation.delivered(model, model.actuator(f"{vm.name}/{vm.propeller.name}").id)))
        # the compiled kernel (``compiled.vehicle_wrench``), where it runs and knows the water's
        # profiles and the hull (a subclass of Hull with a wrench of its own runs in NumPy)
        known_hull = vm.hydro.hull is None or type(vm.hydro.hull) is Hull
        self._codes = compiled.profile_codes(water) if compiled.backend() == "numba" and known_hull else None
        if self._codes is not None:
            self._arrays = compiled.vehicle_arrays(vm.hydro, self.fins, self.propeller, model.body_ipos[self.id])
            self._deltas = np.zeros(len(self.fins))
            self._tau = np.zeros(6)
        make_not_simple(model, self.id)
        self._orient(np.eye(3))
        if vm.trim_density is not None:
            self._warn_trim(vm, float(model.body_pos[self.id][2]))

    def _warn_trim(self, vm: VehicleModel, z: float) -> None:
        """Warn (``TrimDensityWarning``) where the water's density at the vehicle's starting height
        ``z`` (m, world; 0 above the surface) is not the one it is trimmed for: its buoyancy differs
        from its trim by (rho_w - rho_trim) g V (N; the displaced volume V, whole)."""
        rho = float(self.water.rho(np.array([min(z, 0.0)]))[0])
        if abs(rho - vm.trim_density) <= 1e-9 * vm.trim_density:  # (the same water, to rounding)
            return
        change = (rho - vm.trim_density) * self.water.gravity * self.hydro.volume
        who = f"vehicle file {Path(vm.file).name} (body {vm.name!r})" if vm.file else f"vehicle {vm.name!r}"
        warnings.warn(f"{who} is trimmed for water of {vm.trim_density:g} kg/m^3, but the water at its depth "
                      f"({-min(z, 0.0):g} m) is {rho:.6g} kg/m^3: its buoyancy differs from its trim by "
                      f"{change:+.6g} N (what is neutral there {'rises' if change > 0 else 'sinks'} here); give the "
                      f"water a density of {vm.trim_density:g} kg/m^3 to fly it as trimmed", TrimDensityWarning,
                      stacklevel=3)

    def native_table(self):
        """This vehicle's arrays for the native callback (``native``, slots ``V_*``), or None where
        its wrench needs Python (the NumPy kernels, a water profile or hull class the compiled
        kernel does not know, or the waves)."""
        if self._codes is None or self.water.waves is not None:
            return None
        dkind, dp, ckind, cp = self._codes
        h = self.hydro
        keep, hull, fins, prop, surface = self._arrays
        f = lambda a: np.ascontiguousarray(a, dtype=float).ravel()  # noqa: E731
        w0 = int(self._model.tendon_adr[self._ten.start])
        ints = np.array([self.id, self._v.start, self._w.start, dkind, ckind,
                         -1 if self._prop_act is None else self._prop_act, w0, self._has_explicit], dtype=np.int64)
        return [ints, np.array([self.water.gravity, h.volume], dtype=float), f(h.added_mass), f(keep),
                f(h.linear_damping), f(h.linear_damping_fade), f(h.quadratic_damping), f(self._M_lin), f(self._r_b),
                f(hull), f(fins), f(prop), f(surface), dp, cp, np.asarray(self._fin_act, dtype=np.int64), f(self._axes),
                f(self._explicit), f(self._size), f(self._thr), np.asarray(self._thr_act, dtype=np.int64)]

    def _orient(self, R: np.ndarray) -> None:
        """Turn the added-mass tendons along the linear block's principal axes at orientation R."""
        self._prm[:] = (R @ self._axes).T

    def wet_fraction(self, data) -> float:
        """The fraction of its hull under the water now (``compiled.wet_fraction``; 1 for a
        surface vessel, whose hydrostatics are its own)."""
        if self.hydro.surface is not None:
            return 1.0
        return float(compiled.wet_fraction(data.xmat[self.id].reshape(3, 3), float(data.xpos[self.id][2]), self._r_b,
                                           self._size))

    def sea(self, data, R: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """The waves at the centre of buoyancy now: (the surface's elevation, m; the particle
        velocity, m/s, and local acceleration, m/s^2, world); (0.0, None, None) without waves."""
        waves = self.water.waves
        if waves is None:
            return 0.0, None, None
        p = data.xpos[self.id] + R @ self._r_b
        t = float(data.time)
        if self.hydro.surface is not None:  # (half its mean draft under the surface, see the module docstring)
            eta = float(waves.elevation(p[0], p[1], t))
            p = np.array([p[0], p[1], eta - 0.5 * self.hydro.volume / self.hydro.surface.waterplane_area])
        eta, u, a = waves.state(p[None, :], t)
        return float(eta[0]), u[0], a[0]

    def wave_inertia(self, R: np.ndarray, a_w: np.ndarray, rho: float, wet: float) -> np.ndarray:
        """Morison's inertia wrench (body frame, N and N m about the origin) of the fluid's local
        acceleration ``a_w`` (m/s^2, world) in water of density ``rho`` (kg/m^3), times the wet
        fraction ``wet``: rho V a at the centre of buoyancy plus M_A[:, :3] a."""
        a = R.T @ a_w
        fk = rho * self.hydro.volume * a
        return wet * (np.r_[fk, np.cross(self._r_b, fk)] + self.hydro.added_mass[:, :3] @ a)

    def velocity(self, data) -> tuple[np.ndarray, np.ndarray]:
        """(nu (6,), body frame: linear velocity of the origin and angular velocity; R body to
        world)."""
        R = data.xmat[self.id].reshape(3, 3)
        return np.concatenate([R.T @ data.qvel[self._v], data.qvel[self._w]]), R

    def wrench(self, model, data) -> np.ndarray:
        """The hydrodynamic wrench (body frame, about the origin) MuJoCo does not make itself."""
        if self._codes is not None:
            return self._compiled_wrench(data)
        nu, R = self.velocity(data)
        z = np.array([min(float(data.xpos[self.id][2]), 0.0)])
        eta, u_w, a_w = self.sea(data, R)
        u = self.water.velocity(z)[0]
        nu_c = np.zeros(6)
        nu_c[:3] = R.T @ (u if a_w is None else u + u_w)
        nu_r = nu - nu_c
        h = self.hydro
        MA = h.added_mass
        CA = m2c(MA, nu_r)
        if self._zeroed is not None:
            CA[self._zeroed] = 0.0
        DL = h.linear_damping
        if self._fade is not None:
            DL = np.exp(-self._fade * math.sqrt(float(nu_r[:3] @ nu_r[:3])))[:, None] * DL
        tau = -(CA @ nu_r) - damping_force(nu_r, DL, h.quadratic_damping)
        tau[:3] += self._M_lin @ cross(nu[3:], nu_r[:3])
        rho = float(self.water.rho(z)[0])
        z0 = float(data.xpos[self.id][2]) - eta  # (the origin's height over the surface)
        wet = 1.0 if h.surface is not None else compiled.wet_fraction(R, z0, self._r_b, self._size)
        tau *= wet
        dry = (lambda p: h.surface is None and z0 + float(R[2] @ np.asarray(p, dtype=float)) > 0.0)  # noqa: E731
        if h.hull is not None:
            tau += wet * h.hull.wrench(nu_r, rho)
        for fin, adr in zip(self.fins, self._fin_act):
            if not dry(fin.position):
                tau += fin_wrench(nu_r, float(data.act[adr]), fin, rho)
        if self.propeller is not None and not dry(self.propeller.position):
            p = self.propeller
            thrust, torque = p.thrust(float(data.act[self._prop_act]), float(nu_r[0]), rho)
            r = p.position
            tau += (thrust, 0.0, 0.0, torque, r[2] * thrust, -r[1] * thrust)
        for row, adr in zip(self._thr, self._thr_act):  # a thruster in the air: MuJoCo's thrust taken back
            if dry(row[:3]):
                f = float(data.act[adr]) * row[3:]
                tau -= np.r_[f, np.cross(row[:3], f)]
        if h.surface is not None:  # floating: hydrostatics about the design waterline
            sf = h.surface
            tau += surface_restoring(R, z0, rho, self.water.gravity, h.volume,
                                     sf.waterplane_area, sf.gm_t, sf.gm_l, sf.max_volume, self._r_g,
                                     sf.centre_of_flotation)
            tau += sf.crossflow(nu_r, rho)
        else:
            B = rho * self.water.gravity * h.volume * wet
            tau -= restoring_force(R, 0.0, B, np.zeros(3), self._r_b)  # the buoyancy (MuJoCo weighs it)
        if a_w is not None:
            tau += self.wave_inertia(R, a_w, rho, wet)
        if self._has_explicit:  # the rest of M_A nu', from the last step's acceleration
            a = np.concatenate([R.T @ data.qacc[self._v] - cross(nu[3:], nu[:3]), data.qacc[self._w]])
            tau -= self._explicit @ a
        return tau

    def _compiled_wrench(self, data) -> np.ndarray:
        """``wrench`` by ``compiled.vehicle_wrench`` (the same forces, to rounding)."""
        nu, R = self.velocity(data)
        h = self.hydro
        self._deltas[:] = data.act[self._fin_act]
        rpm = 0.0 if self._prop_act is None else float(data.act[self._prop_act])
        keep, hull, fins, prop, surface = self._arrays
        tau = self._tau
        z = float(data.xpos[self.id][2])
        eta, u_w, a_w = self.sea(data, R)
        shifted = nu
        if a_w is not None:  # nu - nu_w: the kernel sees nu_r = nu - nu_c - nu_w (see the module docstring)
            shifted = nu.copy()
            shifted[:3] -= R.T @ u_w
        compiled.vehicle_wrench(shifted, R, min(z, 0.0), *self._codes, self.water.gravity, h.added_mass, keep,
                                h.linear_damping, h.linear_damping_fade, h.quadratic_damping, self._M_lin, h.volume,
                                self._r_b, hull, fins, self._deltas, prop, rpm, surface, z - eta, self._size, self._thr,
                                data.act[self._thr_act] if len(self._thr_act) else np.zeros(0), tau)
        tau = tau.copy()
        if a_w is not None:
            rho = float(self.water.rho(np.array([min(z, 0.0)]))[0])
            wet = 1.0 if h.surface is not None else compiled.wet_fraction(R, z - eta, self._r_b, self._size)
            tau += self.wave_inertia(R, a_w, rho, wet)
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

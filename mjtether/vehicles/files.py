"""Vehicle parameter files: a vehicle's rigid body, hydrodynamics, thrusters, tow point and
autopilot gains in one TOML file, every number with its source. The shipped ones live in
``assets/vehicles`` (installed as ``mjtether.assets.vehicles``); ``load_vehicle`` takes a shipped
name or a path.

The file's tables (units SI; body frame x forward, y left, z up; see ``vehicle`` and ``thruster``)::

    [vehicle]      name, mass, inertia (3 principal moments, or 6: Ixx, Iyy, Izz, Ixy, Ixz, Iyz
                   of the matrix about the centre of gravity), centre_of_gravity, size (drawn
                   ellipsoid semi-axes), tow_point, water_density (kg/m^3: the water it is
                   trimmed for, or identified in), sources (a table: parameter -> where it comes from)
    [hydro]        volume (m^3, or "neutral": mass / water_density, exactly), centre_of_buoyancy,
                   added_mass, linear_damping, quadratic_damping, linear_damping_fade, coriolis_zeroed
    [hull]         length, diameter, axial_cd, crossflow_cd, reference_area, oswald, strips,
                   crossflow ("midpoint", the default: the midpoint rule of the strip integral,
                   sway and heave; "fossen": Fossen's sum of strips + 1 points, sway and yaw)
                   (a torpedo's hull lift and drag, ``vehicle.Hull``)
    [surface]      waterplane_area, gm_t, gm_l, max_volume, centre_of_flotation, length, draft,
                   crossflow_cd, strips (a surface vessel's hydrostatics and cross-flow drag,
                   ``vehicle.Surface``; its origin on the design waterline)
    [[thrusters]]  name, position, direction, max_forward, max_reverse, time_constant or response
                   (a table {numerator, denominator}: the thrust's transfer function, ``thruster.Thruster``)
    [[fins]]       name, position, lift_direction, area, cl_delta, max_angle_deg, time_constant,
                   stall_angle_deg, post_stall_lift (``fins.Fin``)
    [propeller]    name, position, diameter, kt0, kt_max, ja_max, kq0, kq_max, thrust_deduction,
                   wake_fraction, max_rpm, time_constant, torque_scale (``propeller.Propeller``)
    [autopilot]    speed_kp, speed_ki, heading_kp, heading_kd, heading_ki, depth_kp, depth_kd, depth_ki,
                   roll_kp, roll_kd, pitch_kp, pitch_kd, station_kp, station_kd,
                   depth_by_pitch, depth_pitch_kp, depth_pitch_ki, max_pitch_deg, pitch_ki
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np
import tomllib

from mjtether.io.packagedata import asset_dir

from .fins import Fin, add_fin
from .propeller import Propeller, add_propeller
from .thruster import Thruster, add_thruster
from .vehicle import Hull, Surface, VehicleHydro, VehicleModel, add_vehicle

KEYS = {
    "vehicle": {"name", "mass", "inertia", "centre_of_gravity", "size", "tow_point", "water_density", "sources"},
    "hydro": {"volume", "centre_of_buoyancy", "added_mass", "linear_damping", "quadratic_damping",
              "linear_damping_fade", "coriolis_zeroed"},
    "hull": {"length", "diameter", "axial_cd", "crossflow_cd", "reference_area", "oswald", "strips", "crossflow"},
    "surface": {"waterplane_area", "gm_t", "gm_l", "max_volume", "centre_of_flotation", "length", "draft",
                "crossflow_cd", "strips"},
    "thrusters": {"name", "position", "direction", "max_forward", "max_reverse", "time_constant", "response"},
    "fins": {"name", "position", "lift_direction", "area", "cl_delta", "max_angle_deg", "time_constant",
             "stall_angle_deg", "post_stall_lift"},
    "propeller": {"name", "position", "diameter", "kt0", "kt_max", "ja_max", "kq0", "kq_max", "thrust_deduction",
                  "wake_fraction", "max_rpm", "time_constant", "torque_scale"},
    "autopilot": {"speed_kp", "speed_ki", "heading_kp", "heading_kd", "heading_ki", "depth_kp", "depth_kd",
                  "depth_ki", "roll_kp", "roll_kd", "pitch_kp", "pitch_kd", "station_kp", "station_kd",
                  "depth_by_pitch", "depth_pitch_kp", "depth_pitch_ki", "max_pitch_deg", "pitch_ki"},
}
LISTS = ("thrusters", "fins")
"""The tables that may repeat ([[thrusters]], [[fins]])."""


@dataclass(frozen=True)
class Autopilot:
    """Gains of the speed, heading and depth loops (``controllers.VehiclePilot``): surge force
    X = kp e_u + ki int(e_u) (N per m/s, N per m); yaw moment N = kp e_psi - kd r + ki int(e_psi)
    (N m per rad, N m s, N m per rad s); vertical force (world) Z = kp e_z - kd w + ki int(e_z)
    (N per m, N s/m, N per m s); for a vehicle whose thrusters can (an ROV), level attitude:
    K = -kp phi - kd p, M = -kp theta - kd q (N m per rad, N m s; 0: left to its restoring);
    station keeping (an ROV): horizontal force kp e - kd v on the position error in the body frame
    (N per m, N s/m). A vehicle that cannot push itself up or down (a torpedo:
    ``depth_by_pitch``) holds depth by pitching: the pitch it asks for is
    depth_pitch_kp e_z + depth_pitch_ki int(e_z) (deg per m, deg per m s), within
    +-``max_pitch_deg``, held by the pitch loop M = pitch_kp (theta_d - theta) - pitch_kd q
    + pitch_ki int(theta_d - theta) (N m per rad s; the integral takes out what the restoring
    moment and the hull's lift ask for at a steady pitch)."""

    speed_kp: float = 0.0
    speed_ki: float = 0.0
    heading_kp: float = 0.0
    heading_kd: float = 0.0
    heading_ki: float = 0.0
    depth_kp: float = 0.0
    depth_kd: float = 0.0
    depth_ki: float = 0.0
    roll_kp: float = 0.0
    roll_kd: float = 0.0
    pitch_kp: float = 0.0
    pitch_kd: float = 0.0
    station_kp: float = 0.0
    station_kd: float = 0.0
    depth_by_pitch: bool = False
    depth_pitch_kp: float = 0.0
    depth_pitch_ki: float = 0.0
    max_pitch_deg: float = 20.0
    pitch_ki: float = 0.0


@dataclass(frozen=True)
class VehicleSpec:
    """A vehicle file's contents (see the module docstring)."""

    name: str
    mass: float
    inertia: tuple
    centre_of_gravity: tuple
    size: tuple
    tow_point: tuple
    hydro: VehicleHydro
    thrusters: tuple = ()
    fins: tuple = ()
    propeller: Propeller | None = None
    autopilot: Autopilot = field(default_factory=Autopilot)
    sources: dict = field(default_factory=dict)
    path: str = ""
    water_density: float | None = None  # kg/m^3: the water the vehicle is trimmed for (None: not stated)

    @property
    def weight(self) -> float:
        """In air (N), at standard gravity."""
        return self.mass * 9.80665


def shipped() -> list[str]:
    """Names of the vehicles shipped in ``assets/vehicles``."""
    return sorted(p.stem for p in asset_dir("vehicles", "README.md").glob("*.toml"))


def load_vehicle(name_or_path) -> VehicleSpec:
    """A shipped vehicle by name (``shipped()``) or a vehicle file by path; errors name the
    file and the key."""
    p = Path(str(name_or_path))
    if p.suffix != ".toml":
        if str(name_or_path) not in shipped():
            raise ValueError(f"vehicle {name_or_path!r}: not a shipped vehicle ({', '.join(shipped())}) "
                             "nor a .toml file")
        p = asset_dir("vehicles", "README.md") / f"{name_or_path}.toml"
    if not p.is_file():
        raise ValueError(f"vehicle file {p}: no such file")
    try:
        tree = tomllib.loads(p.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"vehicle file {p}: {exc}") from None
    where = p.name
    for table, keys in KEYS.items():
        items = tree.get(table, [] if table in LISTS else {})
        for k, item in enumerate(items if table in LISTS else [items]):
            label = f"{table}[{k}]" if table in LISTS else table
            unknown = sorted(set(item) - keys)
            if unknown:
                raise ValueError(f"{where}: unknown key {label}.{unknown[0]}; allowed: {', '.join(sorted(keys))}")
    unknown = sorted(set(tree) - set(KEYS))
    if unknown:
        raise ValueError(f"{where}: unknown table [{unknown[0]}]; allowed: {', '.join(KEYS)}")
    v, h = tree.get("vehicle", {}), tree.get("hydro", {})
    for table, item, key in (("vehicle", v, "mass"), ("vehicle", v, "inertia"), ("hydro", h, "volume")):
        if key not in item:
            raise ValueError(f"{where}: {table}.{key} is required")
    rho = v.get("water_density")
    if rho is not None and not (isinstance(rho, (int, float)) and 900.0 <= rho <= 1100.0):
        raise ValueError(f"{where}: vehicle.water_density must be in [900, 1100] kg/m^3, got {rho!r}")
    if h["volume"] == "neutral":  # neutrally buoyant in the water it is trimmed for, exactly
        if rho is None or not (isinstance(v["mass"], (int, float)) and v["mass"] > 0):
            raise ValueError(f"{where}: hydro.volume = \"neutral\" needs vehicle.mass (kg) and vehicle.water_density "
                             "(kg/m^3)")
        h = {**h, "volume": float(v["mass"]) / float(rho)}
    try:
        hull = Hull(**tree["hull"]) if "hull" in tree else None
        surface = Surface(**tree["surface"]) if "surface" in tree else None
        hydro = VehicleHydro(volume=h["volume"], centre_of_buoyancy=h.get("centre_of_buoyancy", (0.0, 0.0, 0.0)),
                             added_mass=h.get("added_mass", np.zeros(6)),
                             linear_damping=h.get("linear_damping", np.zeros(6)),
                             quadratic_damping=h.get("quadratic_damping", np.zeros(6)),
                             linear_damping_fade=h.get("linear_damping_fade", np.zeros(6)),
                             coriolis_zeroed=tuple(h.get("coriolis_zeroed", ())), hull=hull, surface=surface)
        thrusters = tuple(Thruster(**t) for t in tree.get("thrusters", []))
        fins = tuple(_fin(f) for f in tree.get("fins", []))
        propeller = Propeller(**tree["propeller"]) if "propeller" in tree else None
        autopilot = Autopilot(**tree.get("autopilot", {}))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{where}: {exc}") from None
    if not (isinstance(v["mass"], (int, float)) and v["mass"] > 0):
        raise ValueError(f"{where}: vehicle.mass must be > 0 kg, got {v['mass']!r}")
    return VehicleSpec(name=str(v.get("name", p.stem)), mass=float(v["mass"]), inertia=tuple(v["inertia"]),
                       centre_of_gravity=tuple(v.get("centre_of_gravity", (0.0, 0.0, 0.0))),
                       size=tuple(v.get("size", (0.5, 0.2, 0.2))), tow_point=tuple(v.get("tow_point", (0.0, 0.0, 0.0))),
                       hydro=hydro, thrusters=thrusters, fins=fins, propeller=propeller, autopilot=autopilot,
                       sources=dict(v.get("sources", {})),
                       path=str(p), water_density=None if rho is None else float(rho))


def _fin(table: dict) -> Fin:
    """A [[fins]] table (angles in degrees) as a ``Fin`` (radians)."""
    t = dict(table)
    for key in ("max_angle_deg", "stall_angle_deg"):
        if key in t:
            t[key[:-4]] = math.radians(float(t.pop(key)))
    if "max_angle" not in t:
        raise ValueError(f"fins {t.get('name', '?')}: max_angle_deg is required")
    return Fin(**t)


def build_vehicle(spec: mujoco.MjSpec, vs: VehicleSpec, name: str = "vehicle", pos=(0.0, 0.0, 0.0)) -> VehicleModel:
    """Add ``vs`` to ``spec`` as body ``name`` at ``pos`` (m, world): its body, thrusters, fins
    and propeller (actuators ``{name}/{part}``) and tow point site ``{name}/tow_point``."""
    vm = add_vehicle(spec, name, mass=vs.mass, inertia=vs.inertia, hydro=vs.hydro,
                     centre_of_gravity=vs.centre_of_gravity, pos=pos, size=vs.size)
    spec.body(name).add_site(name=f"{name}/tow_point", pos=list(vs.tow_point), size=[0.02, 0.0, 0.0])
    for th in vs.thrusters:
        add_thruster(spec, name, th)
    for fin in vs.fins:
        add_fin(spec, name, fin)
    if vs.propeller is not None:
        add_propeller(spec, name, vs.propeller)
    vm.fins, vm.propeller, vm.thrusters = vs.fins, vs.propeller, tuple(vs.thrusters)
    return vm


def thrust_matrix(thrusters) -> np.ndarray:
    """The thrust configuration matrix (6 x n): thruster k's unit thrust as a body-frame wrench
    about the origin, [d_k; r_k x d_k]."""
    return np.array([[*t.direction, *np.cross(t.position, t.direction)] for t in thrusters]).T.reshape(6, -1)


"""Vehicle parameter files: a vehicle's rigid body, hydrodynamics, thrusters, tow point and
autopilot gains in one TOML file, every number with its source. The shipped ones live in
``assets/vehicles`` (installed as ``mjtether.assets.vehicles``); ``load_vehicle`` takes a shipped
name or a path.

The file's tables (units SI; body frame x forward, y left, z up; see ``vehicle`` and ``thruster``)::

    [vehicle]      name, mass, inertia (3 principal moments, or 6: Ixx, Iyy, Izz, Ixy, Ixz, Iyz
                   of the matrix about the centre of gravity), centre_of_gravity, size (drawn
                   ellipsoid semi-axes), tow_point, water_density (kg/m^3: the water it is
                   trimmed for, or identified in), trimmed (true, the default: trimmed for
                   water_density, and built in water of another density it warns,
                   ``vehicle.TrimDensityWarning``; false: water_density is only where it was
                   identified), sources (a table: parameter -> where it comes from)
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
import os
from dataclasses import dataclass, field, fields
from pathlib import Path

import mujoco
import numpy as np
import tomllib

from mjtether import _checks
from mjtether.files.packagedata import asset_dir

from .fins import Fin, add_fin
from .propeller import Propeller, add_propeller
from .thruster import Thruster, add_thruster
from .vehicle import Hull, Surface, VehicleHydro, VehicleModel, add_vehicle

KEYS = {
    "vehicle": {"name", "mass", "inertia", "centre_of_gravity", "size", "tow_point", "water_density", "trimmed",
                "sources"},
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

MAX_MASS = 1.0e9
"""The heaviest vehicle or vessel a file may describe (kg): a large ship, a million tonnes."""
MAX_SIZE = 1.0e3
"""The largest extent (m) of a vehicle's points (centre of gravity, tow point) and drawn size."""
MAX_NUMBER = 1.0e15
"""The largest magnitude of any number in a vehicle file (SI): a million-tonne ship's yaw inertia
is some 1e13 kg m^2. 1e300, which the classes' own checks (> 0, >= 0) let through, is refused."""
MAX_GAIN = 1.0e9
"""The largest autopilot gain (SI, each in its own unit; the shipped files' largest is 1340 N m per
rad)."""


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

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "depth_by_pitch":
                if not isinstance(value, (bool, np.bool_)):
                    raise ValueError(f"autopilot.depth_by_pitch = {value!r}: must be true or false")
            else:  # (each gain in its own unit: the class docstring)
                lo, hi, unit, above = RANGES["autopilot", f.name]
                object.__setattr__(self, f.name, _checks.number(f"autopilot.{f.name}", value, lo, hi, unit,
                                                                above=above))


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
    trimmed: bool = True  # trimmed for water_density (False: only identified in it; no TrimDensityWarning)

    @property
    def weight(self) -> float:
        """In air (N), at standard gravity."""
        return self.mass * 9.80665


def shipped() -> list[str]:
    """Names of the vehicles shipped in ``assets/vehicles``."""
    return sorted(p.stem for p in asset_dir("vehicles", "README.md").glob("*.toml"))


RANGES = {  # (table, key): (lo, hi, unit, lo excluded); any other number is within +-MAX_NUMBER
    ("vehicle", "mass"): (0.0, MAX_MASS, "kg", True),
    ("vehicle", "inertia"): (-MAX_NUMBER, MAX_NUMBER, "kg m^2", False),
    ("vehicle", "centre_of_gravity"): (-MAX_SIZE, MAX_SIZE, "m", False),
    ("vehicle", "size"): (0.0, MAX_SIZE, "m", True),
    ("vehicle", "tow_point"): (-MAX_SIZE, MAX_SIZE, "m", False),
    ("vehicle", "water_density"): (900.0, 1100.0, "kg/m^3", False),
    ("autopilot", "max_pitch_deg"): (0.0, 90.0, "deg", True),
    **{("autopilot", k): (0.0, MAX_GAIN, "", False) for k in KEYS["autopilot"] - {"depth_by_pitch", "max_pitch_deg"}},
}
"""The allowed values of a vehicle file's numbers, where its classes do not say (they check the rest)."""
COUNTS = {("vehicle", "inertia"): (3, 6), ("vehicle", "centre_of_gravity"): (3,), ("vehicle", "size"): (3,),
          ("vehicle", "tow_point"): (3,)}
"""How many numbers a list of the [vehicle] table holds."""
_LISTS_OF_NUMBERS = {"inertia", "centre_of_gravity", "size", "tow_point", "centre_of_buoyancy", "added_mass",
                     "linear_damping", "quadratic_damping", "linear_damping_fade", "centre_of_flotation", "position",
                     "direction", "lift_direction"}
"""Keys whose values are lists of numbers (the others' are one number, but for ``_NOT_NUMBERS``)."""
_NOT_NUMBERS = {"name", "sources", "crossflow", "depth_by_pitch", "trimmed", "response", "coriolis_zeroed"}
"""Keys whose values are not numbers or lists of numbers (checked by ``_numbers_in`` or their class)."""


def load_vehicle(name_or_path) -> VehicleSpec:
    """A shipped vehicle by name (``shipped()``) or a vehicle file by path; errors name the
    file, the key and what is allowed (never the file's contents)."""
    if not isinstance(name_or_path, (str, os.PathLike)):
        raise ValueError(f"vehicle = {name_or_path!r}: must be text: a shipped vehicle ({', '.join(shipped())}) "
                         "or a vehicle file (.toml)")
    p = Path(name_or_path)
    if p.suffix != ".toml":
        if str(name_or_path) not in shipped():
            raise ValueError(f"vehicle {str(name_or_path)!r}: not a shipped vehicle ({', '.join(shipped())}) "
                             "nor a .toml file")
        p = asset_dir("vehicles", "README.md") / f"{name_or_path}.toml"
    try:
        tree = tomllib.loads(_checks.read_text(f"vehicle file {p}", p))
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"vehicle file {p}: not valid TOML: {exc}") from None
    where = p.name
    for table, keys in KEYS.items():
        items = tree.get(table, [] if table in LISTS else {})
        if not (isinstance(items, list) and all(isinstance(i, dict) for i in items) if table in LISTS
                else isinstance(items, dict)):
            shape = f"[[{table}]] tables" if table in LISTS else f"a table [{table}]"
            raise ValueError(f"{where}: {table} must be {shape}")
        for k, item in enumerate(items if table in LISTS else [items]):
            label = f"{table}[{k}]" if table in LISTS else table
            unknown = sorted(set(item) - keys)
            if unknown:
                raise ValueError(f"{where}: unknown key {label}.{unknown[0]}; allowed: {', '.join(sorted(keys))}")
            try:
                _numbers_in(table, label, item)
            except ValueError as exc:
                raise ValueError(f"{where}: {exc}") from None
    unknown = sorted(set(tree) - set(KEYS))
    if unknown:
        raise ValueError(f"{where}: unknown table [{unknown[0]}]; allowed: {', '.join(KEYS)}")
    v, h = tree.get("vehicle", {}), tree.get("hydro", {})
    for table, item, key in (("vehicle", v, "mass"), ("vehicle", v, "inertia"), ("hydro", h, "volume")):
        if key not in item:
            raise ValueError(f"{where}: {table}.{key} is required")
    if not isinstance(v.get("sources", {}), dict):
        raise ValueError(f"{where}: vehicle.sources must be a table [vehicle.sources] of parameter = \"source\"")
    rho = v.get("water_density")
    if h["volume"] == "neutral":  # neutrally buoyant in the water it is trimmed for, exactly
        if rho is None:
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
    return VehicleSpec(name=str(v.get("name", p.stem)), mass=float(v["mass"]), inertia=tuple(v["inertia"]),
                       centre_of_gravity=tuple(v.get("centre_of_gravity", (0.0, 0.0, 0.0))),
                       size=tuple(v.get("size", (0.5, 0.2, 0.2))), tow_point=tuple(v.get("tow_point", (0.0, 0.0, 0.0))),
                       hydro=hydro, thrusters=thrusters, fins=fins, propeller=propeller, autopilot=autopilot,
                       sources=dict(v.get("sources", {})),
                       path=str(p), water_density=None if rho is None else float(rho), trimmed=v.get("trimmed", True))


def _numbers_in(table: str, label: str, item: dict) -> None:
    """Refuse text, booleans, NaN, infinities and numbers out of ``RANGES`` (or above
    ``MAX_NUMBER``) where the table ``item`` of a vehicle file (``label``: ``thrusters[1]``) holds
    numbers (every key but ``_NOT_NUMBERS``): NumPy would read ``true`` as 1 and ``"6136"`` as 6136.
    Names are text; ``autopilot.depth_by_pitch`` and ``vehicle.trimmed`` are true or false;
    ``hydro.coriolis_zeroed`` is a list of [row, column] pairs of whole numbers 0 to 5;
    ``hydro.volume`` may be "neutral"."""
    for key, value in item.items():
        name = f"{label}.{key}"
        lo, hi, unit, above = RANGES.get((table, key), (-MAX_NUMBER, MAX_NUMBER, "", False))
        if key == "name":
            _checks.text(name, value)
        elif key in ("depth_by_pitch", "trimmed") and not isinstance(value, bool):
            raise ValueError(f"{name} = {value!r}: must be true or false")
        elif key == "coriolis_zeroed" and not (isinstance(value, list) and all(
                isinstance(pair, list) and len(pair) == 2 and all(type(i) is int and 0 <= i <= 5 for i in pair)
                for pair in value)):
            raise ValueError(f"{name} = {value!r}: must be a list of [row, column] pairs, each a whole number 0 to 5")
        elif key in _NOT_NUMBERS or (key == "volume" and value == "neutral"):
            continue
        elif key == "volume" and isinstance(value, str):
            raise ValueError(f'{name} = {value!r}: must be a number in [0, {MAX_NUMBER:g}] m^3 or "neutral"')
        elif (table, key) in COUNTS:
            _checks.numbers(name, value, lo, hi, unit, count=COUNTS[table, key], above=above)
        elif isinstance(value, list) and key in _LISTS_OF_NUMBERS:
            for k, x in enumerate(value):
                if isinstance(x, list):  # (a 6 x 6 matrix's rows)
                    _checks.numbers(f"{name}[{k}]", x, lo, hi, unit, above=above)
                else:
                    _checks.number(f"{name}[{k}]", x, lo, hi, unit, above=above)
        else:
            _checks.number(name, value, lo, hi, unit, above=above)


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
    and propeller (actuators ``{name}/{part}``) and tow point site ``{name}/tow_point``. Bound to
    water of another density than the one it is trimmed for (``vs.water_density``, where
    ``vs.trimmed``), it warns (``vehicle.TrimDensityWarning``)."""
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
    vm.trim_density = vs.water_density if vs.trimmed else None  # (built in other water: TrimDensityWarning)
    vm.file = vs.path
    return vm


def thrust_matrix(thrusters) -> np.ndarray:
    """The thrust configuration matrix (6 x n): thruster k's unit thrust as a body-frame wrench
    about the origin, [d_k; r_k x d_k]."""
    return np.array([[*t.direction, *np.cross(t.position, t.direction)] for t in thrusters]).T.reshape(6, -1)


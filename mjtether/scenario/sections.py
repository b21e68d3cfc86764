"""A scenario: the typed tree of everything a run needs, and the TOML files that hold one.

``Scenario`` is the one source of every key's default, unit, range and meaning: the TOML
loader, the Python API (``Scenario(tether=Tether(length=300))``), the environments and
``docs/scenarios.md`` (``mjtether.io.reference``) all come from it. Every error is a
``ScenarioError`` naming the file, the key path (``tether.segments``), the value and what is
allowed; everything is checked before anything is simulated, including the size of the run
(``Scenario.estimate``).

Units: SI, except degrees where a key ends in ``_deg`` (and turn rates in deg/s); speeds may be
given in knots by writing the key with a ``_kn`` suffix (``surface_speed_kn = 3``).
Frames: world, z up, water surface at z = 0, seabed at z = -depth; headings from +x towards +y.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from mjtether.cable.makeup import load_line_types
from mjtether.physics.hydro import DRAG_LAWS
from mjtether.cable.tether import MAX_LENGTH, MAX_REACH_STRAIN, MAX_SEGMENTS, TetherSpec
from mjtether.cable.winch import MODES as WINCH_MODES
from mjtether.cable.winch import Winch as _Winch
from mjtether.walker import Tripod

from .config import INF, RENAMED, ConfigError, Section, param, section, tables
from . import sea
from .sea import HeaveCompensation, ShipMotion, Waves
from .weather import CurrentGaussMarkov, Wind

ScenarioError = ConfigError

LINE_TYPES = load_line_types()
"""The line-type library (``mjtether/cable/linetypes.toml``), by name."""


def _default(cls, name: str):
    return next(f.default for f in dataclasses.fields(cls) if f.name == name)

REACH_MARGIN = 2.0
"""Slack (m) given to a vehicle's or vessel's tow point, which is off its position by up to about
its half-length, when a tether is checked for reaching its ends (``Scenario._check_reach``)."""
MAX_START_STRAIN = 0.1
"""The most a tether may be stretched at the start (``scenario.start`` takes no steady state
stretched more)."""
WALKER_REACH = 1.0
"""How far (m) the walker's feet reach from its centre: it must start that far inside a
bathymetry grid."""
MAX_TURN_DEG_S = math.degrees(0.5)
"""The walker's fastest commanded turn (deg/s): its gait's limit, 0.5 rad/s."""

# ------------------------------------------------------------------ sections


OUTPUT_ROUNDING = 0.05
"""Samples are recorded every round(output_interval / timestep) steps (their times in the outputs
are exact); an output_interval further than this fraction from a whole number of steps is
refused, naming the two nearest (0.0075 s at a 0.005 s step would be recorded every 0.01 s)."""


@dataclass(frozen=True)
class Simulation(Section):
    PATH = "simulation"
    duration: float = param(120.0, 1e-3, 1e6, "s", "simulated time")
    timestep: float = param(0.005, 1e-5, 0.05, "s", "MuJoCo time step (see mjtether.cable.stability)")
    output_interval: float = param(0.5, 1e-3, 1e4, "s", "time between recorded samples, taken every "
                                   "round(output_interval / timestep) steps; one more than 5 % from a whole number of "
                                   "steps is refused")
    start: str = param("steady", doc="steady: from the quasi-static steady state, or stop with the reason if there "
                       "is none; settle: the cable falls into place from a guessed shape while the robot is held, "
                       "then the robot is released; auto: steady if it exists, else settle",
                       choices=("steady", "settle", "auto"))
    laid_layout: str = param("straight", doc="how slack cable lies on the seabed at the start: straight back along "
                             "the robot's track, an arc, or an s", choices=("straight", "arc", "s"))
    laid_layout_angle_deg: float = param(90.0, 1.0, 359.0, "deg", "arc / s: total turn of the slack cable")
    max_wall_hours: float = param(6.0, 0.01, 1000.0, "h", "refuse a run estimated to take longer than this on "
                                  "one core (see Scenario.estimate); raise it to run longer")
    max_output_gb: float = param(4.0, 0.01, 1000.0, "GB", "refuse a run whose recorded samples would need more "
                                 "memory than this; raise simulation.output_interval instead")

    def _check(self):
        if self.output_interval < self.timestep:
            self._bad("output_interval", f"must be >= simulation.timestep ({self.timestep:g} s)")
        k = self.output_interval / self.timestep
        if abs(k - round(k)) > OUTPUT_ROUNDING * k:  # (a sample is taken every round(k) steps)
            lo, hi = math.floor(k) * self.timestep, math.ceil(k) * self.timestep
            self._bad("output_interval", f"must be within {100 * OUTPUT_ROUNDING:g} % of a whole number of "
                      f"simulation.timestep ({self.timestep:g} s): it is {k:.4g} steps; give {lo:.6g} or {hi:.6g} s")
        if self.duration < self.timestep:
            self._bad("duration", f"must be at least one simulation.timestep ({self.timestep:g} s)")


@dataclass(frozen=True)
class Density(Section):
    PATH = "water.density"
    type: str = param("constant", doc="constant, linear or table", choices=("constant", "linear", "table"))
    rho: float = param(1025.0, 900.0, 1100.0, "kg/m^3", "constant: the density")
    rho_surface: float = param(1025.0, 900.0, 1100.0, "kg/m^3", "linear: density at z = 0")
    rho_ref: float = param(980.0, 900.0, 1100.0, "kg/m^3", "linear: density at depth_ref")
    depth_ref: float = param(500.0, 0.1, 12000.0, "m", "linear: depth of rho_ref")
    depths: tuple | None = param(None, 0.0, 12000.0, "m", "table: depths, strictly increasing", kind="list")
    values: tuple | None = param(None, 900.0, 1100.0, "kg/m^3", "table: densities", kind="list")

    def _check(self):
        if self.type == "table":
            _check_table(self, ("values",))


@dataclass(frozen=True)
class Current(Section):
    PATH = "water.current"
    type: str = param("constant", doc="constant, linear, exponential, power or table",
                      choices=("constant", "linear", "exponential", "power", "table"))
    speed: float = param(0.0, 0.0, 10.0, "m/s", "constant: speed", knots=True)
    surface_speed: float = param(0.0, 0.0, 10.0, "m/s", "linear/exponential/power: speed at z = 0", knots=True)
    bottom_speed: float = param(0.0, 0.0, 10.0, "m/s", "linear: speed at bottom_depth", knots=True)
    bottom_depth: float = param(100.0, 0.1, 12000.0, "m", "linear: depth of bottom_speed")
    decay_depth: float = param(15.0, 0.01, 12000.0, "m", "exponential: e-folding depth")
    exponent: float = param(1 / 7, 0.0, 2.0, "", "power: exponent (profile zero at the seabed)")
    heading_deg: float = param(0.0, -360.0, 360.0, "deg", "direction the current flows to, from +x towards +y")
    depths: tuple | None = param(None, 0.0, 12000.0, "m", "table: depths, strictly increasing", kind="list")
    speeds: tuple | None = param(None, 0.0, 10.0, "m/s", "table: speeds", kind="list")
    headings_deg: tuple | None = param(None, -360.0, 360.0, "deg", "table: headings (default all 0)", kind="list")
    gauss_markov: CurrentGaussMarkov = section(CurrentGaussMarkov)

    def _check(self):
        if self.type == "table":
            _check_table(self, ("speeds", "headings_deg"))


def _check_table(s: Section, columns) -> None:
    """A depth table: ``depths`` and its first column given, depths strictly increasing, every
    given column as long as ``depths``."""
    for k in ("depths", columns[0]):
        if getattr(s, k) is None:
            raise ConfigError(f"{s.PATH}.{k} is required when {s.PATH}.type = 'table'", f"{s.PATH}.{k}")
    d = s.depths
    if any(b <= a for a, b in zip(d, d[1:])):
        s._bad("depths", "must be strictly increasing (m)")
    for k in columns:
        if getattr(s, k) is not None and len(getattr(s, k)) != len(d):
            s._bad(k, f"must have as many rows as {s.PATH}.depths ({len(d)})")


@dataclass(frozen=True)
class Water(Section):
    PATH = "water"
    depth: float = param(200.0, 0.1, 12000.0, "m", "seabed depth (positive); with bathymetry, the depth the "
                         "water column's density and current profiles span")
    seabed_friction: float = param(0.6, 0.0, 5.0, "", "Coulomb friction of the seabed (robot feet)")
    seabed_slope_deg: float = param(0.0, 0.0, 30.0, "deg", "seabed slope; depth is the depth at x = y = 0")
    seabed_slope_heading_deg: float = param(0.0, -360.0, 360.0, "deg",
                                            "direction in which the seabed rises, from +x towards +y")
    seabed_stiffness: float = param(0.0, 0.0, 1e10, "Pa/m", "the tether's seabed contact: normal pressure per metre "
                                    "of penetration on its projected area d l, as MoorDyn's kBot (0: MuJoCo's soft "
                                    "contact at twice the time step)")
    seabed_damping: float = param(0.0, 0.0, 1e10, "Pa s/m", "the tether's seabed contact: pressure per m/s of "
                                  "penetration speed, as MoorDyn's cBot (used with seabed_stiffness, which is "
                                  "refused if too stiff for simulation.timestep, naming the step that works; a "
                                  "damping beyond what the step resolves, 1/dt per kg of cable, is taken as that: "
                                  "a landing node stops in a step)")
    gravity: float = param(9.81, 9.7, 9.9, "m/s^2", "gravitational acceleration (weight and buoyancy)")
    bathymetry: str = param("", doc="the seabed from a grid file instead of depth and slope (a path, relative to the "
                            "scenario file): MoorDyn's 3-D seafloor file, or a grid of depths (m, positive down; CSV "
                            "or .npy, rows along +y, columns along +x) with bathymetry_spacing_m and "
                            "bathymetry_origin_m; a MuJoCo height field, with no seabed outside it")
    bathymetry_spacing_m: float = param(0.0, 0.0, 1e5, "m", "a depth grid's spacing between nodes along x and y")
    bathymetry_origin_m: tuple = param((0.0, 0.0), -1e6, 1e6, "m", "a depth grid's first node (row 0, column 0), "
                                       "(x, y)", kind="vec2")
    density: Density = section(Density)
    current: Current = section(Current)

    def _check(self):
        if not self.bathymetry:
            return
        if self.seabed_slope_deg != 0.0:
            self._bad("seabed_slope_deg", "must be 0 with a bathymetry grid (water.bathymetry sets the seabed)")
        try:
            self.grid
        except ValueError as exc:
            self._bad("bathymetry", str(exc))

    @property
    def grid(self):
        """The seabed's ``Bathymetry`` (``mjtether.physics.bathymetry``), or None without one."""
        if not self.bathymetry:
            return None
        from mjtether.physics import bathymetry
        return bathymetry.load(self.bathymetry, self.bathymetry_spacing_m, self.bathymetry_origin_m)

    def seabed_z(self, x: float, y: float) -> float:
        """Height (m) of the seabed at (x, y) m."""
        if self.bathymetry:
            return float(self.grid.height(x, y))
        h = math.radians(self.seabed_slope_heading_deg)
        return -self.depth + math.tan(math.radians(self.seabed_slope_deg)) * (x * math.cos(h) + y * math.sin(h))


_SECTION_PROPS = ("diameter", "mass_per_length", "EA", "EI", "cd_normal", "cd_tangential", "ca_normal")


@dataclass(frozen=True)
class TetherSection(Section):
    """One section of a line make-up (``[[tether.sections]]``, listed from the ship end)."""

    PATH = "tether.sections"
    length: float = param(100.0, 1e-3, MAX_LENGTH, "m", "unstretched length of the section")
    segments: int = param(20, 1, MAX_SEGMENTS, "", "its number of elements (each length / segments long)")
    line_type: str = param("", doc="a line type of the library, which sets diameter, mass_per_length, EA, EI, the "
                           "coefficients and mbl (then not given here)", choices=("",) + tuple(LINE_TYPES))
    diameter: float = param(0.0, 0.0, 2.0, "m", "hydrodynamic and buoyancy diameter (required without line_type)")
    mass_per_length: float = param(0.0, 0.0, 1e4, "kg/m", "mass per metre in air (required without line_type)")
    EA: float = param(0.0, 0.0, 1e12, "N", "axial stiffness; 0: inextensible")
    EI: float = param(0.0, 0.0, 1e9, "N m^2", "bending stiffness")
    cd_normal: float = param(1.2, 0.0, 10.0, "", "normal drag coefficient (on d l)")
    cd_tangential: float = param(0.008, 0.0, 10.0, "", "tangential drag coefficient (on pi d l)")
    ca_normal: float = param(1.0, 0.0, 10.0, "", "added-mass coefficient")
    mbl: float = param(0.0, 0.0, INF, "N", "minimum breaking load; 0: unknown (a line_type's when it has one)")
    name: str = param("", doc="a label")

    def _check(self):
        if self.line_type:
            lt = LINE_TYPES[self.line_type]
            for name in _SECTION_PROPS + ("mbl",):
                have, default = getattr(self, name), _default(type(self), name)
                want = {"EA": 0.0 if lt.EA is None else lt.EA, "mbl": lt.mbl or 0.0}.get(name, getattr(lt, name, None))
                if have not in (default, want):
                    self._bad(name, f"line_type = {self.line_type!r} sets it ({want:g}); give one or the other")
                object.__setattr__(self, name, float(want))
            return
        for name in ("diameter", "mass_per_length"):
            if not getattr(self, name) > 0:
                self._bad(name, "must be > 0 (or give a line_type)")

    def to_makeup(self):
        """This section as a ``mjtether.cable.makeup.Section``."""
        from mjtether.cable.makeup import Section as MakeupSection
        return MakeupSection(self.length, self.segments, self.diameter, self.mass_per_length, EA=self.EA or None,
                             EI=self.EI, cd_normal=self.cd_normal, cd_tangential=self.cd_tangential,
                             ca_normal=self.ca_normal, name=self.name or self.line_type, mbl=self.mbl or None)


@dataclass(frozen=True)
class TetherPointLoad(Section):
    """A clump weight or buoyancy module on the line (``[[tether.point_loads]]``)."""

    PATH = "tether.point_loads"
    arc_length: float = param(0.0, 0.0, MAX_LENGTH, "m", "unstretched distance from the ship end")
    mass: float = param(0.0, 0.0, 1e6, "kg", "mass in air")
    volume: float = param(0.0, 0.0, 1e3, "m^3", "displaced volume (buoyancy rho g V under water)")
    cd_area: float = param(0.0, 0.0, 1e3, "m^2", "drag area Cd A (isotropic)")
    ca: float = param(0.0, 0.0, 10.0, "", "added-mass coefficient on the volume")
    name: str = param("", doc="a label")

    def to_makeup(self):
        from mjtether.cable.makeup import PointLoad
        return PointLoad(self.arc_length, self.mass, self.volume, self.cd_area, self.ca, self.name)


@dataclass(frozen=True)
class TetherFloats(Section):
    """Floats spread over a range of the line, a float section (``[[tether.floats]]``)."""

    PATH = "tether.floats"
    start: float = param(0.0, 0.0, MAX_LENGTH, "m", "arc length from the ship end where the floats begin")
    end: float = param(1.0, 0.0, MAX_LENGTH, "m", "arc length where they end (> start)")
    volume_per_length: float = param(0.0, 0.0, 10.0, "m^3/m", "displaced volume of the floats per metre of line")
    mass_per_length: float = param(0.0, 0.0, 1e4, "kg/m", "mass of the floats per metre of line")
    cd_area_per_length: float = param(0.0, 0.0, 100.0, "m^2/m", "normal drag area Cd A of the floats per metre")
    ca: float = param(0.0, 0.0, 10.0, "", "added-mass coefficient on the floats' volume")
    name: str = param("", doc="a label")

    def _check(self):
        if not self.end > self.start:
            self._bad("end", f"must be > start ({self.start:g} m)")

    def to_makeup(self):
        from mjtether.cable.makeup import DistributedBuoyancy
        return DistributedBuoyancy(self.start, self.end, self.volume_per_length, self.mass_per_length,
                                   self.cd_area_per_length, self.ca, self.name)


@dataclass(frozen=True)
class Tether(Section):
    PATH = "tether"
    attached: bool = param(True, doc="false: no tether; the robot (a vehicle) runs alone: no winch, no cable "
                           "forces, and timeseries.csv has no tether columns (the other tether keys are not used)")
    length: float = param(300.0, 0.1, MAX_LENGTH, "m", "initial deployed (unstretched) length")
    segments: int = param(TetherSpec.segments, 4, MAX_SEGMENTS, "", "number of elements N (fewer than 4 cannot represent the sag: the "
                          "lumped line's error is O(1/N^2))")
    diameter: float = param(TetherSpec.diameter, 1e-4, 2.0, "m", "hydrodynamic and buoyancy diameter")
    density: float = param(1050.0, 1.0, 20000.0, "kg/m^3", "bulk density (or give mass_per_length)")
    mass_per_length: float = param(0.0, 0.0, 1e4, "kg/m", "mass per metre in air; 0: use density")
    cd_normal: float = param(TetherSpec.cd_normal, 0.0, 10.0, "", "normal drag coefficient (on d l)")
    cd_tangential: float = param(TetherSpec.cd_tangential, 0.0, 10.0, "", "tangential drag coefficient (on pi d l)")
    ca_normal: float = param(TetherSpec.ca_normal, 0.0, 10.0, "", "added-mass coefficient")
    EA: float = param(0.0, 0.0, 1e12, "N", "axial stiffness; 0: inextensible")
    EI: float = param(TetherSpec.EI, 0.0, 1e9, "N m^2", "bending stiffness")
    seabed_friction: float = param(0.5, 0.0, 5.0, "", "Coulomb friction of the tether on the seabed")
    added_mass: str = param("isotropic", doc="isotropic: each node's added mass on all three axes (along the cable "
                            "too); normal: normal to the cable only, as for a slender cylinder (reproduces the "
                            "flexible jumper of Lowe and Langley 2006; not yet made safe with slack elements and "
                            "touchdown)", choices=("isotropic", "normal"))
    drag_law: str = param("morison", doc="morison: cd_normal on the flow's normal part and cd_tangential on its "
                          "tangential part (the cross-flow principle); loading_functions: Hong et al. (2020, J. Mar. "
                          "Sci. Eng. 8, 485), Eq. 20-21, cd_normal as the one drag coefficient, scaled by loading "
                          "functions of the flow's angle to the cable, tangential drag included (cd_tangential "
                          "unused; a uniform tether only; runs on the NumPy kernels, slower)",
                          choices=DRAG_LAWS)
    rated_load: float = param(INF, 0.0, INF, "N", "breaking/rated load; a run stops above it (a line_type's MBL "
                              "when not given)")
    line_type: str = param("", doc="a line type of the library (mjtether/cable/linetypes.toml: "
                           + ", ".join(LINE_TYPES) + "): sets diameter, mass_per_length, EA, EI and the "
                           "coefficients, which are then not given here", choices=("",) + tuple(LINE_TYPES))

    sections: tuple = tables(TetherSection, "A line make-up: sections of different line types joined end to end, "
                             "listed from the ship end. With sections, tether.length and tether.segments are "
                             "their sums and the uniform keys above (diameter, mass, EA, coefficients, line_type) "
                             "are not used; the winch must be fixed (payout of a make-up is not supported yet).")
    point_loads: tuple = tables(TetherPointLoad, "Clump weights and buoyancy modules at an arc length from the ship "
                                "end, on a make-up or on a uniform tether (lumped on the two nearest nodes by the "
                                "lever rule; the winch must be fixed).")
    floats: tuple = tables(TetherFloats, "Float sections: buoyancy spread over a range of arc length (a lazy wave's "
                           "hog bend); the winch must be fixed.")

    _FROM_TYPE = ("diameter", "mass_per_length", "EA", "EI", "cd_normal", "cd_tangential", "ca_normal")

    @property
    def is_makeup(self) -> bool:
        """Whether the tether is a line make-up (sections, point loads or floats), not one uniform cable."""
        return bool(self.sections or self.point_loads or self.floats)

    def _check(self):
        if self.sections and self.line_type:
            self._bad("line_type", "not used with [[tether.sections]]: give each section its line_type")
        if self.sections:
            L = math.fsum(x.length for x in self.sections)
            n = sum(x.segments for x in self.sections)
            for name, total in (("length", L), ("segments", n)):
                have = getattr(self, name)
                if have != _default(type(self), name) and abs(have - total) > 1e-9 * max(total, 1.0):
                    self._bad(name, f"the sections add up to {total:g}; leave it out or give their sum")
            if n > MAX_SEGMENTS:
                self._bad("segments", f"the sections have {n} elements in all; at most {MAX_SEGMENTS}")
            object.__setattr__(self, "length", L)
            object.__setattr__(self, "segments", n)
            mbls = [x.mbl for x in self.sections if x.mbl > 0]
            if self.rated_load == INF and len(mbls) == len(self.sections):
                object.__setattr__(self, "rated_load", float(min(mbls)))
        for i, p in enumerate(self.point_loads):
            if p.arc_length > self.length * (1 + 1e-12):
                raise ConfigError(f"tether.point_loads[{i}].arc_length = {p.arc_length:g}: must be in [0, "
                                  f"{self.length:g}] m (the tether's length)", f"tether.point_loads[{i}].arc_length")
        for i, p in enumerate(self.floats):
            if p.end > self.length * (1 + 1e-12):
                raise ConfigError(f"tether.floats[{i}].end = {p.end:g}: must be <= {self.length:g} m (the tether's "
                                  "length)", f"tether.floats[{i}].end")
        if not self.line_type:
            return
        lt = LINE_TYPES[self.line_type]
        for name in self._FROM_TYPE:
            have, default = getattr(self, name), _default(type(self), name)
            want = 0.0 if name == "EA" and lt.EA is None else getattr(lt, name)
            if have not in (default, want):
                self._bad(name, f"tether.line_type = {self.line_type!r} sets it ({want:g}); give one or the other")
            object.__setattr__(self, name, float(want))
        if self.rated_load == INF:
            object.__setattr__(self, "rated_load", float(lt.mbl))


@dataclass(frozen=True)
class Ship(Section):
    PATH = "ship"
    mode: str = param("fixed", doc="fixed (dynamic positioning), follow (keeps offset from the robot) or waypoints",
                      choices=("fixed", "follow", "waypoints"))
    position: tuple = param((0.0, 0.0), -1e6, 1e6, "m", "start position (x, y) at the surface", kind="vec2")
    offset: tuple = param((-50.0, 0.0), -1e6, 1e6, "m", "follow: ship position minus robot position (x, y)",
                          kind="vec2")
    waypoints: tuple | None = param(None, -1e6, 1e6, "m", "waypoints: list of [x, y]", kind="rows2")
    speed: float = param(1.0, 0.0, 20.0, "m/s", "waypoints / follow: top speed", knots=True)
    heave_amplitude: float = param(0.0, 0.0, 20.0, "m", "heave of the fairlead (sinusoid)")
    heave_period: float = param(8.0, 0.5, 100.0, "s", "heave period")
    motion: ShipMotion = section(ShipMotion)
    fairlead_z: float = param(0.0, -1000.0, 0.0, "m", "height of the fairlead (where the tether leaves the ship) "
                              "relative to the water surface; negative below it")
    vessel: str = param("", doc="a surface vessel carrying the winch instead of the prescribed ship: a shipped "
                        "vehicle with [surface] (mjtether.vehicles.files.shipped()) or a vehicle file; its autopilot "
                        "holds ship.position (fixed), flies ship.waypoints at ship.speed by line-of-sight "
                        "guidance (robot.lookahead, robot.acceptance_radius), then holds the last, or holds a "
                        "station ship.offset from the robot, moving with it (follow); the tether leaves it at "
                        "its tow point")
    heading_deg: float = param(0.0, -360.0, 360.0, "deg", "vessel: heading at the start and held on station")

    def _check(self):
        if self.mode == "waypoints" and self.waypoints is None:
            raise ConfigError("ship.waypoints is required when ship.mode = 'waypoints': a list of [x, y] in m",
                              "ship.waypoints")
        if self.vessel:
            from mjtether.vehicles.files import load_vehicle
            try:
                vs = load_vehicle(self.vessel)
            except ValueError as exc:
                self._bad("vessel", str(exc))
            if vs.hydro.surface is None or not vs.thrusters:
                self._bad("vessel", f"{self.vessel} is not a surface vessel with thrusters ([surface] and "
                          "[[thrusters]] in its vehicle file)")
            for key in ("heave_amplitude", "fairlead_z"):
                if getattr(self, key) != 0.0:
                    self._bad(key, "is for the prescribed ship: a vessel (ship.vessel) heaves by itself and its "
                              "fairlead is its tow point")


@dataclass(frozen=True)
class Winch(Section):
    PATH = "winch"
    heave_compensation: HeaveCompensation = section(HeaveCompensation)
    mode: str = param(_Winch.mode, doc="fixed, constant, follow, tension, external or free (see mjtether.cable.winch)",
                      choices=WINCH_MODES)
    min_length: float = param(_Winch.min_length, 0.0, MAX_LENGTH, "m", "shortest deployed length")
    max_length: float = param(0.0, 0.0, MAX_LENGTH, "m", "longest deployed length: cable up to it waits on the drum (0: "
                              "the initial length for a fixed winch, twice it otherwise)")
    rate: float = param(_Winch.rate, -10.0, 10.0, "m/s", "constant: payout rate (negative reels in)")
    max_rate: float = param(_Winch.max_rate, 1e-3, 10.0, "m/s", "fastest payout or reel-in")
    max_accel: float = param(_Winch.max_accel, 0.0, 10.0, "m/s^2", "fastest change of the payout rate; 0: 0.2 "
                             "m/s^2 for a driven winch, no limit for a free drum (mode free: its damping alone)")
    band: tuple = param((0.0, 1e9), 0.0, INF, "N", "tension: keep the ship-end tension inside (low, high)",
                        kind="vec2")
    drum_damping: float = param(_Winch.drum_damping, 1e-3, 1e9, "N s/m", "free: tension per unit payout rate")
    start_empty: bool = param(False, doc="true: nothing is deployed at the start (a vehicle pulls its cable off "
                              "the drum from zero length, as from a free drum): the vehicle's tow point starts at "
                              "the fairlead, and tether.length / tether.segments is only the nominal element length "
                              "of the cable paid out")

    def _check(self):
        if self.band[0] >= self.band[1]:
            self._bad("band", "must be (low, high) with low < high")
        if abs(self.rate) > self.max_rate:
            self._bad("rate", f"must be within +-winch.max_rate ({self.max_rate:g} m/s)")


@dataclass(frozen=True)
class Robot(Section):
    PATH = "robot"
    type: str = param("walker", doc="walker (the hexapod of assets/walker), anchor (a fixed tow point) or vehicle "
                      "(a free-swimming vehicle with an autopilot, see robot.vehicle)",
                      choices=("walker", "anchor", "vehicle"))
    position: tuple | None = param(None, -1e6, 1e6, "m", "anchor (required): tow point (x, y, z); vehicle "
                                   "(required): its origin at the start (its tow point is in its vehicle file)", kind="vec3")
    start: tuple = param((60.0, 0.0), -1e6, 1e6, "m", "walker: start position (x, y) on the seabed", kind="vec2")
    heading_deg: float = param(0.0, -360.0, 360.0, "deg", "walker and vehicle: start heading, from +x towards +y")
    commands: tuple = param(((0.0, 0.3, 0.0),), -1e6, 1e6, "s, m/s, deg/s", "walker: schedule of [time, forward "
                            "speed, turn rate], each held until the next", kind="rows3")
    gait_period: float = param(1.2, 0.4, 5.0, "s", "walker: tripod gait cycle")
    vehicle: str = param("bluerov2_heavy", doc="vehicle: a shipped vehicle (mjtether.vehicles.files.shipped()) or a "
                         "vehicle file (.toml, see mjtether.vehicles.files)")
    setpoints: tuple = param(((0.0, 0.0, 0.0, 10.0),), -1e6, 1e6, "s, m/s, deg, m", "vehicle: the autopilot's "
                             "schedule of [time, surge speed, heading, depth], each held until the next "
                             "(robot.setpoint_interpolation)", kind="rows4")
    setpoint_interpolation: str = param("hold", doc="vehicle: hold (each setpoint row held until the next) or "
                                        "linear (ramped linearly between rows: a heading profile psi(t))",
                                        choices=("hold", "linear"))
    pitch_schedule: tuple | None = param(None, -1e6, 1e6, "s, deg", "vehicle that dives by pitching "
                                         "(depth_by_pitch): a pitch profile theta(t) of [time, pitch] rows, linear "
                                         "between them (positive nose down, as recorded), flown instead of the "
                                         "depth setpoints", kind="rows2", optional=True)

    path: tuple | None = param(None, -1e6, 1e6, "s, m/s, deg, deg", "vehicle: a prescribed motion instead of the "
                               "autopilot, as a vehicle 'moving at equilibrium conditions' (its thrust making up "
                               "whatever the cable and the water do): rows of [time, speed through the water along "
                               "the body's x axis, heading, pitch (positive nose down)], linear between them; the "
                               "vehicle's origin moves from robot.position at that speed along its nose, carried by "
                               "the current besides (ramped in from rest until the second row), and the cable's pull "
                               "on it is the output", kind="rows4", optional=True)
    waypoints: tuple | None = param(None, -1e6, 1e6, "m, m, m, m/s", "vehicle: instead of setpoints, a route of "
                                    "[x, y, depth, speed] rows flown by line-of-sight guidance from the start; the "
                                    "vehicle holds station at the last one", kind="rows4", optional=True)
    stop_at_surface: bool = param(False, doc="vehicle: true ends the run when the vehicle breaks the surface (part "
                                  "of its hull out of the water; logged in summary.json's run.surface_events either "
                                  "way)")
    lookahead: float = param(5.0, 0.1, 1e4, "m", "vehicle: line-of-sight lookahead distance along the route")
    los_integral_gain: float = param(0.0, 0.0, 10.0, "", "vehicle: kappa of integral line-of-sight guidance (Fossen "
                                     "2021, Sec. 12.3.3), which takes out a current's cross-track offset; 0: plain LOS")
    acceptance_radius: float = param(2.0, 0.01, 1e4, "m", "vehicle: a waypoint is reached within this horizontal "
                                     "distance")
    manoeuvre: str = param("none", doc="vehicle with a rudder: a standard manoeuvre from robot.manoeuvre_start_s on, "
                           "the rudder set by it instead of the heading loop and the propeller held at its shaft "
                           "speed then (speed and depth loops as before): turning_circle (robot.rudder_deg held), "
                           "zigzag (+-robot.rudder_deg, reversed at +-robot.zigzag_heading_deg of heading change) "
                           "or spiral (robot.spiral_rudders_deg, each held robot.spiral_step_s)",
                           choices=("none", "turning_circle", "zigzag", "spiral"))
    manoeuvre_start_s: float = param(10.0, 0.0, 1e6, "s", "vehicle: when the manoeuvre starts (the setpoints are "
                                     "flown until then)")
    rudder_deg: float = param(15.0, -90.0, 90.0, "deg", "turning_circle, zigzag: rudder angle (positive: the "
                              "vehicle file's positive rudder; the REMUS 100's turns to starboard)")
    zigzag_heading_deg: float = param(20.0, 0.1, 90.0, "deg", "zigzag: heading change that reverses the rudder")
    spiral_rudders_deg: tuple = param((15.0, 10.0, 5.0, 0.0, -5.0, -10.0, -15.0), -90.0, 90.0, "deg",
                                      "spiral: rudder angles, each held robot.spiral_step_s", kind="list")
    spiral_step_s: float = param(60.0, 1.0, 1e5, "s", "spiral: how long each rudder angle is held")

    def _check(self):
        if self.type in ("anchor", "vehicle") and self.position is None:
            raise ConfigError(f"robot.position is required for {'an anchor' if self.type == 'anchor' else 'a vehicle'}"
                              ": [x, y, z] in m", "robot.position")
        if self.type in ("anchor", "vehicle") and self.position[2] > 0.0:
            self._bad("position", "the tow point is above the water surface (z = 0); give z <= 0 m")
        if self.type == "vehicle":
            times = [s[0] for s in self.setpoints]
            if times[0] != 0.0 or any(b <= a for a, b in zip(times, times[1:])):
                self._bad("setpoints", "the times (first column, s) must start at 0 and increase")
            if any(s[3] < 0.0 for s in self.setpoints):
                self._bad("setpoints", "depths (last column) are below the surface: give them >= 0 m")
            if self.pitch_schedule is not None:
                times = [s[0] for s in self.pitch_schedule]
                if times[0] != 0.0 or any(b <= a for a, b in zip(times, times[1:])):
                    self._bad("pitch_schedule", "the times (first column, s) must start at 0 and increase")
                if any(abs(s[1]) >= 90.0 for s in self.pitch_schedule):
                    self._bad("pitch_schedule", "pitch angles must be within (-90, 90) deg")
            if self.path is not None:
                times = [s[0] for s in self.path]
                if times[0] != 0.0 or any(b <= a for a, b in zip(times, times[1:])):
                    self._bad("path", "the times (first column, s) must start at 0 and increase")
                if any(not 0.0 <= s[1] <= 20.0 for s in self.path):
                    self._bad("path", "speeds (second column) must be in [0, 20] m/s")
                if any(abs(s[3]) >= 90.0 for s in self.path):
                    self._bad("path", "pitch angles (last column) must be within (-90, 90) deg")
                if self.path[0][2] != self.heading_deg or self.path[0][3] != 0.0:
                    self._bad("path", f"the first row starts the vehicle as placed: heading robot.heading_deg "
                              f"({self.heading_deg:g} deg) and pitch 0")
                if self.waypoints is not None or self.pitch_schedule is not None or self.manoeuvre != "none":
                    self._bad("path", "a prescribed path replaces the autopilot: give no waypoints, pitch_schedule "
                              "or manoeuvre with it")
            if self.waypoints is not None and any(w[2] < 0.0 or w[3] < 0.0 for w in self.waypoints):
                self._bad("waypoints", "depths (third column) and speeds (fourth) must be >= 0")
            from mjtether.vehicles.files import load_vehicle
            try:
                vs = load_vehicle(self.vehicle)
            except ValueError as exc:
                self._bad("vehicle", str(exc))
            if vs.hydro.surface is not None and self.position[2] != 0.0:
                self._bad("position", f"{self.vehicle} is a surface vessel: its origin is on its design waterline, "
                          "give z = 0")
            if self.pitch_schedule is not None and not vs.autopilot.depth_by_pitch:
                self._bad("pitch_schedule", f"{self.vehicle} does not dive by pitching (autopilot.depth_by_pitch)")
            if self.manoeuvre != "none" and not any(f.yaw_per_angle for f in vs.fins):
                self._bad("manoeuvre", f"{self.manoeuvre} needs a vehicle with a rudder (a fin that turns it in yaw); "
                          f"{self.vehicle} has none")
        times = [c[0] for c in self.commands]
        if times[0] != 0.0 or any(b <= a for a, b in zip(times, times[1:])):
            self._bad("commands", "the times (first column, s) must start at 0 and increase")
        top = Tripod.max_stride / (self.gait_period / 2)  # the tripod gait's longest stroke per half cycle
        for t, v, turn in self.commands:
            if not -top <= v <= top:
                self._bad("commands", f"speed {v:g} m/s at t = {t:g} s: must be in [-{top:.2f}, {top:.2f}] m/s "
                          f"(the walker's top speed at robot.gait_period = {self.gait_period:g} s)")
            if not -MAX_TURN_DEG_S <= turn <= MAX_TURN_DEG_S:
                self._bad("commands", f"turn rate {turn:g} deg/s at t = {t:g} s: must be in "
                          f"[-{MAX_TURN_DEG_S:.1f}, {MAX_TURN_DEG_S:.1f}] deg/s")


RENAMED.update({
    "water.seabed_slope": "was in radians; give water.seabed_slope_deg (degrees)",
    "water.seabed_slope_heading": "was in radians; give water.seabed_slope_heading_deg (degrees)",
    "water.current.heading": "was in radians; give water.current.heading_deg (degrees)",
    "water.current.headings": "was in radians; give water.current.headings_deg (degrees)",
    "robot.heading": "was in radians; give robot.heading_deg (degrees; robot.commands turn rates are in deg/s)",
})

# ------------------------------------------------------------------ the whole scenario

@dataclass(frozen=True)
class Tangle(Section):
    PATH = "tangle"
    clearance_m: float = param(0.0, 0.0, 1e4, "m", "log an event when the cable comes closer than this to a vehicle "
                               "(cable_clearance in timeseries.csv; 0: no threshold)")
    self_clearance_m: float = param(0.0, 0.0, 1e4, "m", "log an event when the cable comes closer than this to "
                                    "itself, or crosses itself in plan view (cable_self_clearance, "
                                    "cable_plan_crossings; 0: no threshold)")
    stop: bool = param(False, doc="true: a logged event ends the run there (its results are written up to then)")


@dataclass(frozen=True)
class Scenario(Section):
    """A whole run: ``Scenario()`` is the built-in defaults; see ``load_scenario``."""

    PATH = ""
    simulation: Simulation = section(Simulation)
    water: Water = section(Water)
    tether: Tether = section(Tether)
    ship: Ship = section(Ship)
    winch: Winch = section(Winch)
    robot: Robot = section(Robot)
    tangle: Tangle = section(Tangle)
    waves: Waves = section(Waves)
    wind: Wind = section(Wind)

    def __post_init__(self):
        super().__post_init__()
        if self.winch.max_length == 0.0:  # resolve the default: the drum holds L (fixed) or 2 L, and a
            L = self.tether.length  # heave compensator's stroke
            hc = self.winch.heave_compensation
            extra = 0.0 if hc.type == "none" else hc.stroke
            object.__setattr__(self, "winch", self.winch.replace(
                max_length=(L if self.winch.mode == "fixed" else min(2.0 * L, 1e5)) + extra))

    def _check(self):
        w, r, L = self.water, self.robot, self.tether.length

        def bad(key, value, why):
            raise ConfigError(f"{key} = {value}: {why}", key)

        grid = w.grid
        if grid is not None:  # (outside the grid there is no seabed)
            x0, x1, y0, y1 = grid.bounds
            where = f"outside the bathymetry grid (x {x0:g} to {x1:g} m, y {y0:g} to {y1:g} m)"
            if r.type == "walker" and not grid.covers(*r.start, margin=WALKER_REACH):
                bad("robot.start", list(r.start), f"is {where}, or within {WALKER_REACH:g} m of its edge")
            if r.type != "walker" and not grid.covers(*r.position[:2]):
                bad("robot.position", list(r.position), f"is {where}")
            if not grid.covers(*self.ship.position):
                bad("ship.position", list(self.ship.position), f"is {where}: the cable would run off the seabed")
        if r.type in ("anchor", "vehicle"):
            x, y, z = r.position
            if z < w.seabed_z(x, y) - 1e-6:
                bad("robot.position", list(r.position), f"z = {z:g} m is below the seabed (z = {w.seabed_z(x, y):.2f} m "
                    f"there; water.depth = {w.depth:g} m)")
        elif w.seabed_z(*r.start) >= -1.0:
            bad("robot.start", list(r.start), f"the seabed there is at z = {w.seabed_z(*r.start):.2f} m; the walker "
                "needs at least 1 m of water")
        if w.seabed_z(*self.ship.position) >= -1.0:
            bad("ship.position", list(self.ship.position), f"the seabed there is at z = "
                f"{w.seabed_z(*self.ship.position):.2f} m, above the surface or within 1 m of it")
        self._check_reach(bad)
        sea.check_scenario(self, bad)
        if not self.tether.attached and r.type != "vehicle":
            bad("tether.attached", "false", f"only a vehicle can run without a tether (robot.type = {r.type!r})")
        wi = self.winch
        if self.tether.is_makeup and wi.mode != "fixed":
            bad("winch.mode", repr(wi.mode), "a tether with sections, point_loads or floats (a line make-up) needs "
                "winch.mode = \"fixed\": payout of a make-up is not supported yet")
        if self.tether.is_makeup and self.tether.drag_law != "morison":
            bad("tether.drag_law", repr(self.tether.drag_law), "is for a uniform tether: a line make-up (sections, "
                "point_loads or floats) takes drag_law = \"morison\"")
        hi = wi.max_length if wi.max_length > 0 else (L if wi.mode == "fixed" else 2 * L)
        if not wi.min_length <= L <= hi:
            bad("tether.length", L, f"must be in [winch.min_length, winch.max_length] = [{wi.min_length:g}, {hi:g}] m")
        if wi.min_length >= hi:
            bad("winch.min_length", wi.min_length, f"must be below winch.max_length ({hi:g} m)")
        if wi.start_empty:
            if r.type != "vehicle" or not self.tether.attached:
                bad("winch.start_empty", "true", f"is for a tethered vehicle (robot.type = {r.type!r})")
            if wi.mode == "fixed":
                bad("winch.start_empty", "true", "needs a winch that pays out (winch.mode = \"free\", \"constant\", "
                    "\"tension\", \"follow\" or \"external\"), not a fixed one")
            if wi.min_length > 0.0:
                bad("winch.min_length", wi.min_length, "must be 0 with winch.start_empty = true")
            if self.ship.vessel:
                bad("winch.start_empty", "true", "is not supported yet with a vessel carrying the winch (ship.vessel)")
        est = self.estimate(max_length=hi)
        s = self.simulation
        if est["wall_hours"] > s.max_wall_hours:
            bad("simulation.duration", f"{s.duration:g} s", f"at simulation.timestep = {s.timestep:g} s that is "
                f"{est['steps']:.3g} steps of about {est['us_per_step']:.0f} us, about {est['wall_hours']:.3g} h on one "
                f"core: over simulation.max_wall_hours = {s.max_wall_hours:g} h (shorten the run, take longer steps, "
                "use fewer tether.segments, or raise simulation.max_wall_hours)")
        if est["output_gb"] > s.max_output_gb:
            bad("simulation.output_interval", f"{s.output_interval:g} s", f"that is {est['samples']:.3g} samples of "
                f"{est['elements']} elements, about {est['output_gb']:.3g} GB of results: over "
                f"simulation.max_output_gb = {s.max_output_gb:g} GB (record less often, or raise it)")

    def _check_reach(self, bad) -> None:
        """A tether too short for its ends is refused before anything runs: the fairlead and the
        robot's tow point (a walker's about 1 m over the seabed at its start; a vehicle's or a
        vessel's within ``REACH_MARGIN`` of its position) farther apart than the tether's length
        (stretched by at most ``tether.MAX_REACH_STRAIN`` if it is elastic)."""
        t, r, s = self.tether, self.robot, self.ship
        if not t.attached or (r.type == "vehicle" and self.winch.start_empty):
            return
        top = np.array([*s.position, s.fairlead_z], dtype=float)
        if r.type == "walker":
            end = np.array([*r.start, self.water.seabed_z(*r.start) + 1.0])
        else:
            end = np.array(r.position, dtype=float)
        margin = (REACH_MARGIN if r.type != "anchor" else 0.0) + (REACH_MARGIN if s.vessel else 0.0)
        span = float(np.linalg.norm(end - top))
        stretch = 1.0 if (t.EA == 0.0 and not t.sections) else 1.0 + MAX_REACH_STRAIN
        if t.length * stretch < span - margin:
            why = (f" less {margin:g} m for the tow point's offset" if margin else "") + (
                f", stretched by at most {100 * MAX_REACH_STRAIN:g} %" if stretch > 1 else "")
            bad("tether.length", f"{t.length:g} m", f"too short for its ends: the fairlead and the robot's tow point "
                f"are {span:.1f} m apart in a straight line (the span); give tether.length >= "
                f"{(span - margin) / stretch:.1f} m (the minimum: the span{why}) or move the robot or ship closer")

    def estimate(self, max_length: float | None = None) -> dict:
        """What the run will cost (``cost.estimate``)."""
        from .cost import estimate
        return estimate(self, max_length)

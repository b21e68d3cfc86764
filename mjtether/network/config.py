"""A network of mooring lines: line types, points, bodies and lines, as MoorDyn and MoorPy name them.

A ``Network`` holds any number of lines, each between two points. A point is

* ``fixed``: held in the world (an anchor, a fixed fairlead);
* ``coupled``: moved by a coupled program (MoorDyn's ``Vessel``/``Coupled``); mjtether holds it
  where the file puts it;
* ``body``: fixed to a body (or a vehicle), at ``position`` in its frame;
* ``free``: a point mass with volume, drag area and added mass (a clump weight, a buoy, a
  connecting ring, a free line end): its position is part of the solution.

Several lines may share a point (a bridle, a spread mooring, two lines to one anchor). A body
is ``coupled`` or ``fixed`` (held at its pose), ``free`` (a 6-DOF rigid body) or ``pinned`` (turning
freely about its ``pin``, a point held in the world: MoorDyn's pinned rods and bodies). A vehicle
(``Vehicle``: a vehicle file, such as the BlueROV2 Heavy) flies on its own thrusters, holding a
station; a walker (``Walker``: the scenario's hexapod) stands on the seabed and walks on its
gait. A line may pay out from a winch at its end B (a drum on a cage, say) at a constant speed
up to a length. The water may be written as a scenario writes it (``WATER_TABLES``). Units SI,
world frame z up, water surface at z = 0, seabed at z = -depth; angles in degrees.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

from mjtether import _checks
from mjtether.cable.tether import MAX_COEFFICIENT, TetherSpec

POINT_KINDS = ("fixed", "coupled", "body", "free")
BODY_KINDS = ("fixed", "coupled", "free", "pinned")
STARTS = ("steady", "as_written")
DEFAULT_GRAVITY = 9.80665
"""MoorDyn-C's default g (m/s^2)."""
MAX_LINES = 500
"""The most lines a network takes (building one of 200 lines of 20 elements took 12 s on this
project's CI machine, growing faster than the count)."""
MAX_HELD_STRAIN = 1.0
"""The largest stretch (unstretched length's share) a line held at both ends may be written with:
no mooring material holds 100 % (chain breaks near 2 %, polyester near 15 %, nylon near 30 %),
so a line that short for its ends is a mistake in the file, refused before a build."""
LINE_ARRAYS = ("nodes", "tension", "compression")
"""The per-line arrays of ``lines.npz`` (``lineNAME_nodes`` ...): a line may not be named so that
one of its arrays takes another line's name."""


def waterline_height(volume: float, height: float | None) -> float:
    """The waterline band (m) of a free point or body of ``volume`` (m^3): ``height`` where given,
    else that of an upright cylinder of the volume as tall as it is wide, (4 V / pi)^(1/3) (a
    body of no volume: 0.2 m, where nothing buoys it)."""
    if height is not None:
        return float(height)
    return (4.0 * volume / math.pi) ** (1.0 / 3.0) if volume > 0 else 0.2


class NetworkError(ValueError):
    """A network that cannot be built; the message names the field."""


@dataclass(frozen=True)
class LineType:
    """A line's cross-section: diameter (m), mass per metre in air (kg/m), EA (N), EI (N m^2),
    normal and axial drag (Cd on d l, CdAx on pi d l) and added mass (Ca, CaAx on rho pi d^2/4 l)."""

    name: str
    diameter: float
    mass_per_length: float
    EA: float
    EI: float = 0.0
    cd_normal: float = 1.2
    ca_normal: float = 1.0
    cd_tangential: float = 0.0
    ca_tangential: float = 0.0

    def __post_init__(self):
        where = f"line type {self.name!r}"
        _checks.positive(f"{where}: diameter", self.diameter, "m")
        _checks.positive(f"{where}: mass_per_length", self.mass_per_length, "kg/m")
        _checks.positive(f"{where}: EA", self.EA, "N")
        _checks.non_negative(f"{where}: EI", self.EI)
        for key in ("cd_normal", "ca_normal", "cd_tangential", "ca_tangential"):
            _checks.in_range(f"{where}: {key}", getattr(self, key), 0.0, MAX_COEFFICIENT)

    @property
    def added_mass(self) -> str:
        """mjtether's added mass along the line: all of Ca (``"isotropic"``) or none (``"normal"``),
        the nearer to CaAx."""
        return "normal" if self.ca_tangential < 0.5 * self.ca_normal else "isotropic"

    def tether(self, length: float, segments: int) -> TetherSpec:
        return TetherSpec(length=length, segments=segments, diameter=self.diameter,
                          mass_per_length=self.mass_per_length, cd_normal=self.cd_normal,
                          cd_tangential=self.cd_tangential, ca_normal=self.ca_normal, EA=self.EA, EI=self.EI,
                          added_mass=self.added_mass)

    def wet_weight(self, rho: float, g: float) -> float:
        """Submerged weight per metre (N/m; negative for a buoyant line)."""
        return (self.mass_per_length - rho * math.pi * self.diameter ** 2 / 4) * g


@dataclass(frozen=True)
class Point:
    """A point of the network (see the module docstring); ``position`` in m (world frame, or the
    body's frame for a ``body`` point); mass (kg), volume (m^3), drag area CdA (m^2), added-mass
    coefficient Ca (on rho V), a constant force (N, world) and the waterline band ``height`` (m;
    see ``waterline_height``) for a ``free`` point."""

    name: str
    kind: str
    position: tuple
    body: str | None = None
    mass: float = 0.0
    volume: float = 0.0
    cd_area: float = 0.0
    ca: float = 0.0
    force: tuple = (0.0, 0.0, 0.0)
    height: float | None = None

    def __post_init__(self):
        where = f"point {self.name!r}"
        if self.kind not in POINT_KINDS:
            raise NetworkError(f"{where}: kind must be one of {', '.join(POINT_KINDS)}, got {self.kind!r}")
        if (self.kind == "body") != (self.body is not None):
            raise NetworkError(f"{where}: a body point names its body (and only a body point does)")
        object.__setattr__(self, "position", tuple(_checks.vector3(f"{where}: position", self.position)))
        object.__setattr__(self, "force", tuple(_checks.vector3(f"{where}: force", self.force)))
        for key in ("mass", "volume", "cd_area", "ca"):
            _checks.non_negative(f"{where}: {key}", getattr(self, key))
        if self.height is not None:
            _checks.in_range(f"{where}: height", self.height, 1e-3, 1e3, "m")


@dataclass(frozen=True)
class Body:
    """A rigid body: pose (m; roll, pitch, yaw in degrees), mass (kg), centre of gravity (m, body
    frame), principal inertia (kg m^2), volume (m^3), drag areas CdA (m^2, per body axis) and
    added-mass coefficients (on rho V, per body axis), the waterline band ``height`` (m; see
    ``waterline_height``). A ``pinned`` body turns about its ``pin`` (m, body frame), which stays
    where the pose puts it."""

    name: str
    kind: str
    position: tuple
    rpy_deg: tuple = (0.0, 0.0, 0.0)
    mass: float = 0.0
    cg: tuple = (0.0, 0.0, 0.0)
    inertia: tuple = (0.0, 0.0, 0.0)
    volume: float = 0.0
    cd_area: tuple = (0.0, 0.0, 0.0)
    ca: tuple = (0.0, 0.0, 0.0)
    pin: tuple = (0.0, 0.0, 0.0)
    height: float | None = None

    def __post_init__(self):
        where = f"body {self.name!r}"
        if self.kind not in BODY_KINDS:
            raise NetworkError(f"{where}: kind must be one of {', '.join(BODY_KINDS)}, got {self.kind!r}")
        for key in ("position", "rpy_deg", "cg", "inertia", "cd_area", "ca", "pin"):
            object.__setattr__(self, key, tuple(_checks.vector3(f"{where}: {key}", getattr(self, key))))
        _checks.non_negative(f"{where}: mass", self.mass)
        _checks.non_negative(f"{where}: volume", self.volume)
        if self.height is not None:
            _checks.in_range(f"{where}: height", self.height, 1e-3, 1e3, "m")
        if self.kind in ("free", "pinned") and (self.mass <= 0 or min(self.inertia) <= 0):
            raise NetworkError(f"{where}: a {self.kind} body needs a mass (kg) and inertia (kg m^2) > 0")
        if self.kind != "pinned" and any(self.pin):
            raise NetworkError(f"{where}: only a pinned body has a pin (kind is {self.kind!r})")


@dataclass(frozen=True)
class Vehicle:
    """A vehicle flown by its autopilot (``mjtether.vehicles``: a shipped vehicle's name or a
    vehicle file): starting at ``position`` (m, world) facing ``heading_deg``, it holds
    ``station`` (x m, y m, depth m below the surface; default: where it starts) at that heading.
    Lines attach to it at ``body`` points (its frame: x forward, z up; its tow point, say)."""

    name: str
    vehicle: str
    position: tuple
    heading_deg: float = 0.0
    station: tuple | None = None

    def __post_init__(self):
        where = f"vehicle {self.name!r}"
        object.__setattr__(self, "position", tuple(_checks.vector3(f"{where}: position", self.position)))
        _checks.finite(f"{where}: heading_deg", self.heading_deg)
        if self.station is None:
            object.__setattr__(self, "station", (self.position[0], self.position[1], -self.position[2]))
        object.__setattr__(self, "station", tuple(_checks.vector3(f"{where}: station", self.station)))
        if self.position[2] > 0 or self.station[2] < 0:
            raise NetworkError(f"{where}: a vehicle starts and holds station under water (position z <= 0, "
                               "station depth >= 0)")
        try:
            self.spec
        except ValueError as exc:
            raise NetworkError(f"{where}: {exc}") from None

    @property
    def spec(self):
        """Its ``vehicles.VehicleSpec``."""
        from mjtether.vehicles.files import load_vehicle
        return load_vehicle(self.vehicle)


WALKER_TOW_POINT = (-0.85, 0.0, 0.05)
"""The walker's tow point (m, its torso's frame: x forward, z up): ``assets/walker/walker.xml``'s
site ``tow_point``; a ``body`` point on a walker given no ``position`` is there."""


@dataclass(frozen=True)
class Walker:
    """A seabed walker: the scenario's hexapod (``mjtether.walker``, 650 kg in air) standing on
    the seabed at ``position`` (x, y m, world; at the seabed's height there) facing ``heading_deg``
    (from +x towards +y), walking on its tripod gait with the scenario's speed ramp and heading
    hold (``scenario.controllers.GaitDrive``): forward at ``speed`` (m/s; 0: it stands, stepping
    in place) or on the schedule ``commands`` (rows of time s, forward speed m/s, turn rate deg/s,
    each held until the next: the scenario's ``robot.commands``); ``gait_period`` (s): its gait's
    cycle. Lines attach to it at ``body`` points (its torso's frame: x forward, z up; its tow
    point ``WALKER_TOW_POINT``). The ranges are the scenario's ``[robot]`` ones."""

    name: str
    position: tuple
    heading_deg: float = 0.0
    speed: float = 0.0
    commands: tuple | None = None
    gait_period: float = 1.2

    def __post_init__(self):
        from mjtether.scenario.sections import Robot
        from mjtether.walker import Tripod
        where = f"walker {self.name!r}"
        try:  # (the scenario's checks of a walker: ranges, the schedule's times, its top speed and turn)
            schedule = {} if self.commands is None else {"commands": self.commands}
            robot = Robot(type="walker", start=self.position, heading_deg=self.heading_deg,
                          gait_period=self.gait_period, **schedule)
        except ValueError as exc:
            why = str(exc).replace("robot.start", "position").replace("robot.", "")
            raise NetworkError(f"{where}: {why}") from None
        object.__setattr__(self, "position", tuple(robot.start))
        object.__setattr__(self, "heading_deg", robot.heading_deg)
        object.__setattr__(self, "gait_period", robot.gait_period)
        if self.commands is not None:
            object.__setattr__(self, "commands", tuple(tuple(row) for row in robot.commands))
        _checks.finite(f"{where}: speed", self.speed)
        top = Tripod.max_stride / (self.gait_period / 2)
        if not -top <= self.speed <= top:
            raise NetworkError(f"{where}: speed = {self.speed!r}: must be in [-{top:.2f}, {top:.2f}] m/s (the "
                               f"walker's top speed at gait_period = {self.gait_period:g} s)")
        if self.commands is not None and self.speed != 0.0:
            raise NetworkError(f"{where}: give speed or commands, not both")

    @property
    def schedule(self) -> tuple:
        """Its commands as rows of (time s, speed m/s, turn rate rad/s)."""
        rows = self.commands if self.commands is not None else ((0.0, self.speed, 0.0),)
        return tuple((t, v, math.radians(w)) for t, v, w in rows)


@dataclass(frozen=True)
class Line:
    """A line of ``type`` from point ``a`` (MoorDyn's end A, usually the anchor) to point ``b``:
    unstretched length (m) in ``segments`` elements."""

    name: str
    type: str
    a: str
    b: str
    length: float
    segments: int
    payout_speed: float = 0.0
    max_length: float = 0.0

    def __post_init__(self):
        where = f"line {self.name!r}"
        _checks.positive(f"{where}: length", self.length, "m")
        _checks.non_negative(f"{where}: payout_speed", self.payout_speed)
        if self.payout_speed > 0 and not self.max_length > self.length:
            raise NetworkError(f"{where}: a line paying out (payout_speed > 0) needs max_length (m, what its drum "
                               f"holds) above its length {self.length:g} m, got {self.max_length!r}")
        if not (isinstance(self.segments, int) and 1 <= self.segments <= 1000):
            raise NetworkError(f"{where}: segments must be a whole number in [1, 1000], got {self.segments!r}")
        if self.a == self.b:
            raise NetworkError(f"{where}: both ends on point {self.a!r}")


@dataclass(frozen=True)
class Network:
    """Lines between points in a water column (depth m, density kg/m^3, gravity m/s^2) with a
    flat seabed of MoorDyn's contact (kBot Pa/m, cBot Pa s/m) and Coulomb friction, a steady
    current tabulated in depth (m below the surface, increasing; speed m/s; heading degrees from
    +x towards +y; the east and north parts interpolated linearly, constant beyond); the run's
    duration (s), time step (s; None: the largest stable one) and output interval (s); ``settle``
    (s): how long it falls into place, damped, before the run (``mjtether.network.run.settle``);
    ``bathymetry``: the seabed from a grid file instead (``mjtether.physics.bathymetry``: MoorDyn's
    3-D seafloor file, or a depth grid with its spacing and first node, m), a MuJoCo height field;
    ``start``: ``"steady"`` (the free points and bodies in equilibrium, ``statics.equilibrium``,
    then settled) or ``"as_written"`` (every point at rest where it is given, each line's own
    steady state between its ends, no settling: a pendulum released from its given angle).
    ``current``: the current as a scenario writes it instead (``[water.current]``: a
    ``scenario.Current``, any of its types, checked as a scenario checks it), not with the
    ``current_depths`` table; ``walkers``: {name: ``Walker``}. The sea: ``waves`` (``[waves]``, a
    ``scenario.sea.Waves``: the scenario's keys and checks) or ``wave_components``, rows of
    (amplitude m, omega rad/s, heading deg, phase deg), eta = sum a cos(k (x cos b + y sin b) -
    omega t + phase) with k from the network's depth and gravity, Wheeler-stretched (a MoorDyn
    file's ``wave_frequencies.txt``, ``io.moordyn_waves``); not both (``wave_field``)."""

    name: str
    line_types: dict
    points: dict
    lines: tuple
    bodies: dict = field(default_factory=dict)
    vehicles: dict = field(default_factory=dict)
    depth: float = 100.0
    rho: float = 1025.0
    gravity: float = DEFAULT_GRAVITY
    seabed_stiffness: float = 3.0e6
    seabed_damping: float = 3.0e5
    seabed_friction: float = 0.0
    current_depths: tuple = ()
    current_speeds: tuple = ()
    current_headings_deg: tuple = ()
    bathymetry: str = ""
    bathymetry_spacing_m: float = 0.0
    bathymetry_origin_m: tuple = (0.0, 0.0)
    duration: float = 60.0
    timestep: float | None = None
    output_interval: float = 0.1
    settle: float = 0.0
    start: str = "steady"
    notes: tuple = ()
    walkers: dict = field(default_factory=dict)
    current: object = None
    waves: object = None
    wave_components: tuple = ()
    max_wall_hours: float = 6.0
    max_output_gb: float = 4.0

    def __post_init__(self):
        _checks.positive("water.depth", self.depth, "m")
        _checks.in_range("water.rho", self.rho, 900.0, 1100.0, "kg/m^3")
        _checks.non_negative("water.gravity", self.gravity)
        _checks.non_negative("water.seabed_stiffness", self.seabed_stiffness)
        _checks.non_negative("water.seabed_damping", self.seabed_damping)
        _checks.non_negative("water.seabed_friction", self.seabed_friction)
        _checks.in_range("simulation.duration", self.duration, 1e-3, 1e6, "s")
        _checks.in_range("simulation.max_wall_hours", self.max_wall_hours, 0.01, 1000.0, "h")
        _checks.in_range("simulation.max_output_gb", self.max_output_gb, 0.01, 1000.0, "GB")
        if len(self.lines) > MAX_LINES:
            raise NetworkError(f"lines: {len(self.lines)} lines; a network takes at most {MAX_LINES} (building 200 "
                               "lines of 20 elements takes 12 s and grows faster than the count; split the system)")
        _checks.positive("simulation.output_interval", self.output_interval, "s")
        _checks.in_range("simulation.settle", self.settle, 0.0, 3600.0, "s")
        if self.start not in STARTS:
            raise NetworkError(f"simulation.start must be one of {', '.join(STARTS)}, got {self.start!r}")
        if self.timestep is not None:
            _checks.in_range("simulation.timestep", self.timestep, 1e-5, 0.05, "s")
        for key in ("current_depths", "current_speeds", "current_headings_deg"):
            object.__setattr__(self, key, tuple(float(_checks.finite(f"water.{key}", v))
                                                for v in getattr(self, key)))
        if not (len(self.current_depths) == len(self.current_speeds) == len(self.current_headings_deg)):
            raise NetworkError("water.current_depths, current_speeds and current_headings_deg must be as long as "
                               "each other")
        if self.current is not None:
            object.__setattr__(self, "current", _scenario_current(self.current))
            if self.current_depths:
                raise NetworkError("water: give the current as [water.current] or as current_depths, current_speeds "
                                   "and current_headings_deg, not both")
        if self.waves is not None:
            object.__setattr__(self, "waves", _scenario_waves(self.waves))
        object.__setattr__(self, "wave_components", _wave_rows(self.wave_components))
        if self.wave_components and self.waves is not None and not self.waves.flat:
            raise NetworkError("waves: give the sea as [waves] or as water.wave_components, not both")
        object.__setattr__(self, "bathymetry_origin_m", tuple(self.bathymetry_origin_m))
        if self.bathymetry:
            try:
                self.grid
            except ValueError as exc:
                raise NetworkError(f"water.bathymetry: {exc}") from None
        if not self.lines and not any(b.kind in ("free", "pinned") for b in self.bodies.values()):
            raise NetworkError("lines: a network needs at least one line (or a free or pinned body)")
        names = [ln.name for ln in self.lines]
        if len(set(names)) != len(names):
            raise NetworkError(f"lines: names must differ, got {names}")
        for ln in self.lines:
            taken = [f"{ln.name}_{what}" for what in LINE_ARRAYS if f"{ln.name}_{what}" in names]
            if taken:
                raise NetworkError(f"line {taken[0]!r}: its name is that of line {ln.name!r}'s array "
                                   f"line{taken[0]} in lines.npz; rename it (not ending in _"
                                   + ", _".join(LINE_ARRAYS) + " after another line's name)")
        for ln in self.lines:
            if ln.type not in self.line_types:
                raise NetworkError(f"line {ln.name!r}: type {ln.type!r} is not a line type "
                                   f"({', '.join(self.line_types)})")
            for end in (ln.a, ln.b):
                if end not in self.points:
                    raise NetworkError(f"line {ln.name!r}: point {end!r} is not a point ({', '.join(self.points)})")
        for p in self.points.values():
            if p.kind == "body" and p.body not in self.bodies and p.body not in self.vehicles \
                    and p.body not in self.walkers:
                raise NetworkError(f"point {p.name!r}: body {p.body!r} is not a body, vehicle or walker "
                                   f"({', '.join([*self.bodies, *self.vehicles, *self.walkers])})")
        both = set(self.bodies) & set(self.vehicles)
        if both:
            raise NetworkError(f"vehicles: {', '.join(sorted(both))} also named as a body")
        both = set(self.walkers) & (set(self.bodies) | set(self.vehicles))
        if both:
            raise NetworkError(f"walkers: {', '.join(sorted(both))} also named as a body or vehicle")
        for w in self.walkers.values():
            self._check_walker_ground(w)
        for ln in self.lines:
            self._check_held_span(ln)

    def _check_held_span(self, ln) -> None:
        """Refuse a line held at both ends (fixed or coupled points) whose ends are further apart
        than ``1 + MAX_HELD_STRAIN`` times its length."""
        ends = [self.points[pid] for pid in (ln.a, ln.b)]
        if any(p.kind not in ("fixed", "coupled") for p in ends):
            return
        span = math.dist(ends[0].position, ends[1].position)
        if span > (1.0 + MAX_HELD_STRAIN) * ln.length:
            raise NetworkError(f"line {ln.name!r}: length {ln.length:g} m between held points {ln.a!r} and {ln.b!r} "
                               f"{span:g} m apart would stretch it {100 * (span / ln.length - 1):.0f} %; a line "
                               f"held at both ends needs length >= {span / (1 + MAX_HELD_STRAIN):g} m (stretch "
                               f"at most {100 * MAX_HELD_STRAIN:.0f} %)")

    def _check_walker_ground(self, w) -> None:
        """Refuse a walker off the bathymetry grid (within 1 m of its edge: its feet reach that far)
        or where the seabed is less than 1 m deep (as a scenario's walker)."""
        grid = self.grid
        if grid is not None and not grid.covers(*w.position, margin=1.0):
            raise NetworkError(f"walker {w.name!r}: position {list(w.position)} is off the bathymetry grid, or "
                               "within 1 m of its edge")
        z = self.seabed_height(*w.position)
        if z >= -1.0:
            raise NetworkError(f"walker {w.name!r}: position {list(w.position)}: the seabed there is at z = {z:.2f} m; "
                               "the walker needs at least 1 m of water")

    @property
    def seabed_z(self) -> float:
        """The level seabed's height (m); see ``seabed_height`` for a bathymetry grid's."""
        return -self.depth

    @property
    def grid(self):
        """The seabed's ``Bathymetry`` (``water.bathymetry``), or None for a level seabed."""
        if not self.bathymetry:
            return None
        from mjtether.physics import bathymetry
        return bathymetry.load(self.bathymetry, self.bathymetry_spacing_m, self.bathymetry_origin_m)

    def seabed_height(self, x, y):
        """Height (m) of the seabed at (x, y) m: the grid's, or the level seabed's."""
        grid = self.grid
        return -self.depth if grid is None else float(grid.height(x, y))

    def wave_field(self):
        """The sea (``physics.waves.WaveField``: ``[waves]`` by the scenario's ``sea.wave_field``,
        or ``wave_components``) in the network's depth and gravity, or None for a flat sea."""
        if self.wave_components:
            import numpy as np

            from mjtether.physics import waves as wv
            a, w, b, p = np.array(self.wave_components).T
            comps = wv.WaveComponents(a, w, wv.wavenumber(w, self.depth, self.gravity), np.radians(b), np.radians(p))
            return wv.WaveField(comps, self.depth, self.gravity, stretching="wheeler")
        if self.waves is None:
            return None
        from mjtether.scenario.sea import wave_field
        return wave_field(self.waves, self.depth, self.gravity)

    def attached(self, point: str) -> list[tuple[Line, str]]:
        """The lines at ``point``, each with the end (``"a"`` or ``"b"``) that is there."""
        return [(ln, end) for ln in self.lines for end in ("a", "b") if getattr(ln, end) == point]


# ------------------------------------------------------------------------------ TOML

_SECTIONS = {"water": {"depth", "rho", "gravity", "seabed_stiffness", "seabed_damping", "seabed_friction",
                       "current_depths", "current_speeds", "current_headings_deg", "bathymetry",
                       "bathymetry_spacing_m", "bathymetry_origin_m", "wave_components"},
             "simulation": {"duration", "timestep", "output_interval", "settle", "start", "max_wall_hours",
                            "max_output_gb"},
             "line_types": None, "points": None, "bodies": None, "vehicles": None, "walkers": None, "lines": None,
             "waves": None}
WATER_TABLES = ("current", "density")
"""``[water.current]`` and ``[water.density]``: the water written as a scenario writes it
(``scenario.Current``, ``scenario.Density``: the same keys, meanings and checks). The current
replaces the ``current_depths`` table; the density must be ``type = "constant"`` (a network's
statics take one density) and replaces ``rho``, its alias."""


def _scenario_table(value, cls, what: str):
    """A scenario section ``cls`` (``scenario.Current``, ``scenario.sea.Waves``) from one, or
    from its table (a dict, as TOML gives it); ``what``: the key and the table, for the error."""
    from mjtether.scenario import config as scenario_config
    if isinstance(value, dict):
        return scenario_config.build(cls, value)
    if not isinstance(value, cls):
        raise NetworkError(f"{what}, got {value!r}")
    return value


def _scenario_current(value):
    """A ``scenario.Current`` from one, or from its table (``[water.current]``)."""
    from mjtether.scenario.sections import Current
    return _scenario_table(value, Current, "water.current must be a [water.current] table (a scenario.Current)")


def _scenario_waves(value):
    """A ``scenario.sea.Waves`` from one, or from its table (``[waves]``)."""
    from mjtether.scenario.sea import Waves
    return _scenario_table(value, Waves, "waves must be a [waves] table (a scenario.sea.Waves)")


MAX_WAVE_OMEGA = 100.0
"""The highest frequency a row of ``water.wave_components`` may have (rad/s: a 0.06 s wave)."""


def _wave_rows(rows) -> tuple:
    """``water.wave_components`` as a tuple of (amplitude m, omega rad/s, heading deg, phase deg) rows."""
    if isinstance(rows, (str, dict)) or not hasattr(rows, "__iter__"):
        raise NetworkError(f"water.wave_components must be a list of [amplitude m, omega rad/s, heading deg, "
                           f"phase deg] rows, got {rows!r}")
    out = []
    for i, row in enumerate(rows):
        key = f"water.wave_components[{i}]"
        if isinstance(row, (str, dict)) or not hasattr(row, "__len__") or len(row) != 4:
            raise NetworkError(f"{key} must be [amplitude m, omega rad/s, heading deg, phase deg], got {row!r}")
        a = _checks.number(f"{key} amplitude", row[0], 0.0, 100.0, "m")
        w = _checks.number(f"{key} omega", row[1], 0.0, MAX_WAVE_OMEGA, "rad/s", above=True)
        b = _checks.number(f"{key} heading", row[2], -360.0, 360.0, "deg")
        p = _checks.number(f"{key} phase", row[3], -360.0, 360.0, "deg")
        out.append((a, w, b, p))
    return tuple(out)


def _water_tables(table: dict) -> dict:
    """The Network fields of ``[water]``'s sub-tables ``WATER_TABLES``, checked by the scenario's sections."""
    from mjtether.scenario import config as scenario_config
    from mjtether.scenario.sections import Density
    out = {}
    for key in WATER_TABLES:
        if key in table and not isinstance(table[key], dict):
            raise NetworkError(f"water.{key} must be a table [water.{key}], got {table[key]!r}")
    if "current" in table:
        out["current"] = _scenario_current(table["current"])
    if "density" in table:
        d = scenario_config.build(Density, table["density"])
        if d.type != "constant":
            raise NetworkError(f"water.density.type = {d.type!r}: a network's water has one density: give "
                               "type = \"constant\" with rho (kg/m^3), or water.rho")
        if "rho" in table:
            raise NetworkError("water: give the density as [water.density] rho or as water.rho, not both")
        out["rho"] = d.rho
    return out


def _fields(cls) -> set:
    return {f for f in cls.__dataclass_fields__ if f != "name"}


def _table(source: str, where: str, entry, cls, **extra):
    if not isinstance(entry, dict):
        raise NetworkError(f"{source}: {where} must be a table of {', '.join(sorted(_fields(cls)))}")
    unknown = set(entry) - _fields(cls)
    if unknown:
        raise NetworkError(f"{source}: {where}: unknown key(s) {', '.join(sorted(unknown))}; allowed: "
                           f"{', '.join(sorted(_fields(cls)))}")
    missing = [f.name for f in dataclasses.fields(cls) if f.name not in entry and f.name not in extra
               and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    if missing:
        raise NetworkError(f"{source}: {where}: missing key(s) {', '.join(missing)}")
    try:
        return cls(**extra, **entry)
    except ValueError as exc:
        raise NetworkError(f"{source}: {where}: {exc}") from None


def from_dict(data: dict, name: str = "<network>", overrides=()) -> Network:
    """A network from its TOML tree: ``[water]`` and ``[simulation]`` (the ``Network`` fields;
    ``[water.current]`` and ``[water.density]`` as a scenario writes them, ``WATER_TABLES``),
    ``[line_types.NAME]``, ``[points.NAME]``, ``[bodies.NAME]``, ``[vehicles.NAME]`` and
    ``[walkers.NAME]`` (the fields of ``LineType``, ``Point``, ``Body``, ``Vehicle`` and
    ``Walker``; a ``body`` point on a walker given no ``position`` is at its tow point) and
    ``[[lines]]`` (those of ``Line``, ``name`` included);
    ``overrides`` as in ``with_overrides``."""
    unknown = set(data) - set(_SECTIONS)
    if unknown:
        raise NetworkError(f"{name}: unknown section(s) {', '.join(sorted(unknown))}; a network has "
                           f"{', '.join(_SECTIONS)}")
    flat = {}
    for sec in ("water", "simulation"):
        table = data.get(sec, {})
        tables = WATER_TABLES if sec == "water" else ()
        bad = set(table) - _SECTIONS[sec] - set(tables)
        if bad:
            raise NetworkError(f"{name}: [{sec}]: unknown key(s) {', '.join(sorted(bad))}; allowed: "
                               f"{', '.join(sorted(_SECTIONS[sec]))}" + (" and the tables [water.current], "
                                                                         "[water.density]" if tables else ""))
        flat.update({(sec, k): v for k, v in table.items() if k not in tables})
        if tables:
            try:
                flat.update({(sec, k): v for k, v in _water_tables(table).items()})
            except ValueError as exc:
                raise NetworkError(f"{name}: {exc}") from None
    if "waves" in data:
        try:
            flat[("waves", "waves")] = _scenario_waves(data["waves"])
        except ValueError as exc:
            raise NetworkError(f"{name}: {exc}") from None
    walkers = {k: _table(name, f"walkers.{k}", v, Walker, name=k) for k, v in data.get("walkers", {}).items()}
    types = {k: _table(name, f"line_types.{k}", v, LineType, name=k) for k, v in data.get("line_types", {}).items()}
    points = {k: _table(name, f"points.{k}", _at_tow_point(v, walkers), Point, name=k)
              for k, v in data.get("points", {}).items()}
    bodies = {k: _table(name, f"bodies.{k}", v, Body, name=k) for k, v in data.get("bodies", {}).items()}
    vehicles = {k: _table(name, f"vehicles.{k}", v, Vehicle, name=k) for k, v in data.get("vehicles", {}).items()}
    lines = data.get("lines", [])
    if not isinstance(lines, list):
        raise NetworkError(f"{name}: lines must be a list of tables ([[lines]])")
    line_list = []
    for i, entry in enumerate(lines):
        if not isinstance(entry, dict) or "name" not in entry:
            raise NetworkError(f"{name}: lines[{i}] needs a name")
        line_list.append(_table(name, f"lines[{i}] ({entry['name']!r})", {k: v for k, v in entry.items()
                                                                          if k != "name"}, Line, name=str(entry["name"])))
    try:
        net = Network(name, types, points, tuple(line_list), bodies=bodies, vehicles=vehicles, walkers=walkers,
                      **{k: v for (_, k), v in flat.items()})
    except ValueError as exc:
        raise NetworkError(f"{name}: {exc}") from None
    from .overrides import with_overrides
    return with_overrides(net, overrides)


def _at_tow_point(entry, walkers: dict):
    """A ``body`` point's table on a walker, given no position: at its tow point."""
    if isinstance(entry, dict) and entry.get("kind") == "body" and entry.get("body") in walkers \
            and "position" not in entry:
        return {**entry, "position": WALKER_TOW_POINT}
    return entry


def to_dict(net: Network) -> dict:
    """``net`` as the TOML tree ``from_dict`` reads (``from_dict(to_dict(net)) == net``, notes
    aside): what a results folder's ``summary.json`` keeps so that the run can be rebuilt."""
    def table(obj):
        values = {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj) if f.name != "name"}
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in values.items() if v is not None}

    water = {k: getattr(net, k) for k in _SECTIONS["water"]}
    sim = {k: getattr(net, k) for k in _SECTIONS["simulation"] if getattr(net, k) is not None}
    water["wave_components"] = [list(r) for r in net.wave_components]
    if not net.wave_components:
        del water["wave_components"]
    out = {"water": {k: (list(v) if isinstance(v, tuple) else v) for k, v in water.items()},
           "simulation": sim,
           "line_types": {k: table(v) for k, v in net.line_types.items()},
           "points": {k: table(v) for k, v in net.points.items()},
           "lines": [{"name": ln.name, **table(ln)} for ln in net.lines]}
    if net.bodies:
        out["bodies"] = {k: table(v) for k, v in net.bodies.items()}
    if net.vehicles:
        out["vehicles"] = {k: table(v) for k, v in net.vehicles.items()}
    if net.walkers:
        out["walkers"] = {k: {f: ([list(r) for r in v] if f == "commands" else v) for f, v in table(w).items()}
                          for k, w in net.walkers.items()}
    if net.current is not None:
        out["water"]["current"] = {k: v for k, v in net.current.to_dict().items() if v is not None}
    if net.waves is not None:
        out["waves"] = net.waves.to_dict()
    return out

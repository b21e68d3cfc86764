"""Scenario files: a TOML description of a run, checked against a schema.

Every key has a type, a default, an allowed range and a unit (``SCHEMA`` below, rendered as
``docs/scenarios.md`` by ``scenario_docs()``). Unknown keys, wrong types and values out of range
raise ``ScenarioError`` naming the file, the key and what is allowed. Speeds may be given in
knots by writing the key with a ``_kn`` suffix (``surface_speed_kn = 3``); they are converted to
m/s on reading, and nothing inside the code sees knots.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

from .units import KNOT
from .walker import Tripod

INF = math.inf


@dataclass(frozen=True)
class Key:
    """One scenario key: type ("float", "int", "str", "bool", "vec2", "vec3", "table"),
    default (None: required where the section is used), range or choices, unit, meaning."""

    type: str
    default: object
    lo: float = -INF
    hi: float = INF
    unit: str = ""
    doc: str = ""
    choices: tuple = ()
    knots: bool = False  # may be given as <key>_kn


SCHEMA: dict[str, dict[str, Key]] = {
    "simulation": {
        "duration": Key("float", 120.0, 0.0, 1e6, "s", "simulated time"),
        "timestep": Key("float", 0.005, 1e-5, 0.05, "s", "MuJoCo time step (see mjtether.stability)"),
        "output_interval": Key("float", 0.5, 1e-3, 1e4, "s", "time between recorded samples"),
        "start": Key("str", "steady", doc="steady: from the quasi-static steady state, or stop with the reason if "
                     "there is none; settle: the cable falls into place from a guessed shape while the robot is "
                     "held, then the robot is released; auto: steady if it exists, else settle",
                     choices=("steady", "settle", "auto")),
        "laid_layout": Key("str", "straight", doc="how slack cable lies on the seabed at the start: straight back "
                           "along the robot's track, an arc, or an s", choices=("straight", "arc", "s")),
        "laid_layout_angle_deg": Key("float", 90.0, 1.0, 359.0, "deg", "arc / s: total turn of the slack cable"),
    },
    "water": {
        "depth": Key("float", 200.0, 0.1, 12000.0, "m", "seabed depth (positive)"),
        "seabed_friction": Key("float", 0.6, 0.0, 5.0, "", "Coulomb friction of the seabed (robot feet)"),
        "seabed_slope": Key("float", 0.0, 0.0, 0.5, "rad", "seabed slope (0.1745 rad = 10 deg); depth is the "
                            "depth at x = y = 0"),
        "seabed_slope_heading": Key("float", 0.0, -2 * math.pi, 2 * math.pi, "rad",
                                    "direction in which the seabed rises, from +x towards +y"),
    },
    "water.density": {
        "type": Key("str", "constant", doc="constant, linear or table", choices=("constant", "linear", "table")),
        "rho": Key("float", 1025.0, 900.0, 1100.0, "kg/m^3", "constant: the density"),
        "rho_surface": Key("float", 1025.0, 900.0, 1100.0, "kg/m^3", "linear: density at z = 0"),
        "rho_ref": Key("float", 980.0, 900.0, 1100.0, "kg/m^3", "linear: density at depth_ref"),
        "depth_ref": Key("float", 500.0, 0.1, 12000.0, "m", "linear: depth of rho_ref"),
        "depths": Key("table", None, 0.0, 12000.0, "m", "table: depths, increasing"),
        "values": Key("table", None, 900.0, 1100.0, "kg/m^3", "table: densities"),
    },
    "water.current": {
        "type": Key("str", "constant", doc="constant, linear, exponential, power or table",
                    choices=("constant", "linear", "exponential", "power", "table")),
        "speed": Key("float", 0.0, 0.0, 10.0, "m/s", "constant: speed", knots=True),
        "surface_speed": Key("float", 0.0, 0.0, 10.0, "m/s", "linear/exponential/power: speed at z = 0",
                             knots=True),
        "bottom_speed": Key("float", 0.0, 0.0, 10.0, "m/s", "linear: speed at bottom_depth", knots=True),
        "bottom_depth": Key("float", 100.0, 0.1, 12000.0, "m", "linear: depth of bottom_speed"),
        "decay_depth": Key("float", 15.0, 0.01, 12000.0, "m", "exponential: e-folding depth"),
        "exponent": Key("float", 1 / 7, 0.0, 2.0, "", "power: exponent (profile zero at the seabed)"),
        "heading": Key("float", 0.0, -2 * math.pi, 2 * math.pi, "rad", "direction the current flows to, from +x "
                       "towards +y"),
        "depths": Key("table", None, 0.0, 12000.0, "m", "table: depths, increasing"),
        "speeds": Key("table", None, 0.0, 10.0, "m/s", "table: speeds"),
        "headings": Key("table", None, -2 * math.pi, 2 * math.pi, "rad", "table: headings (default all 0)"),
    },
    "tether": {
        "length": Key("float", 300.0, 0.1, 1e5, "m", "initial deployed (unstretched) length"),
        "segments": Key("int", 60, 1, 5000, "", "number of elements N"),
        "diameter": Key("float", 0.02, 1e-4, 2.0, "m", "hydrodynamic and buoyancy diameter"),
        "density": Key("float", 1050.0, 1.0, 20000.0, "kg/m^3", "bulk density (or give mass_per_length)"),
        "mass_per_length": Key("float", 0.0, 0.0, 1e4, "kg/m", "mass per metre in air; 0: use density"),
        "cd_normal": Key("float", 1.2, 0.0, 10.0, "", "normal drag coefficient (on d l)"),
        "cd_tangential": Key("float", 0.008, 0.0, 10.0, "", "tangential drag coefficient (on pi d l)"),
        "ca_normal": Key("float", 1.0, 0.0, 10.0, "", "added-mass coefficient"),
        "EA": Key("float", 0.0, 0.0, 1e12, "N", "axial stiffness; 0: inextensible"),
        "EI": Key("float", 0.0, 0.0, 1e9, "N m^2", "bending stiffness"),
        "seabed_friction": Key("float", 0.5, 0.0, 5.0, "", "Coulomb friction of the tether on the seabed"),
        "rated_load": Key("float", INF, 0.0, INF, "N", "breaking/rated load; a run stops above it"),
    },
    "ship": {
        "mode": Key("str", "fixed", doc="fixed (dynamic positioning), follow (keeps offset from the robot) or "
                    "waypoints", choices=("fixed", "follow", "waypoints")),
        "position": Key("vec2", (0.0, 0.0), -1e6, 1e6, "m", "start position (x, y) at the surface"),
        "offset": Key("vec2", (-50.0, 0.0), -1e6, 1e6, "m", "follow: ship position minus robot position (x, y)"),
        "waypoints": Key("table", None, -1e6, 1e6, "m", "waypoints: list of (x, y)"),
        "speed": Key("float", 1.0, 0.0, 20.0, "m/s", "waypoints / follow: top speed", knots=True),
        "heave_amplitude": Key("float", 0.0, 0.0, 20.0, "m", "heave of the fairlead (sinusoid)"),
        "heave_period": Key("float", 8.0, 0.5, 100.0, "s", "heave period"),
    },
    "winch": {
        "mode": Key("str", "fixed", doc="fixed, constant, follow, tension, external or free",
                    choices=("fixed", "constant", "follow", "tension", "external", "free")),
        "min_length": Key("float", 0.0, 0.0, 1e5, "m", "shortest deployed length"),
        "max_length": Key("float", 0.0, 0.0, 1e5, "m", "longest deployed length: cable up to it waits on the drum (0: "
                          "the initial length for a fixed winch, twice it otherwise)"),
        "rate": Key("float", 0.0, -10.0, 10.0, "m/s", "constant: payout rate (negative reels in)"),
        "max_rate": Key("float", 2.0, 1e-3, 10.0, "m/s", "fastest payout or reel-in"),
        "max_accel": Key("float", 0.2, 1e-3, 10.0, "m/s^2", "fastest change of the payout rate"),
        "band": Key("vec2", (0.0, 1e9), 0.0, INF, "N", "tension: keep the ship-end tension inside (low, high)"),
        "drum_damping": Key("float", 200.0, 1e-3, 1e9, "N s/m", "free: tension per unit payout rate"),
    },
    "robot": {
        "type": Key("str", "walker", doc="walker (the hexapod of assets/walker) or anchor (a fixed tow point)",
                    choices=("walker", "anchor")),
        "position": Key("vec3", None, -1e6, 1e6, "m", "anchor: tow point (x, y, z)"),
        "start": Key("vec2", (60.0, 0.0), -1e6, 1e6, "m", "walker: start position (x, y) on the seabed"),
        "heading": Key("float", 0.0, -2 * math.pi, 2 * math.pi, "rad", "walker: start heading, from +x towards +y"),
        "commands": Key("table", [[0.0, 0.3, 0.0]], -1e6, 1e6, "s, m/s, rad/s",
                        "walker: schedule of (time, forward speed, turn rate), each held until the next"),
        "gait_period": Key("float", 1.2, 0.4, 5.0, "s", "walker: tripod gait cycle"),
    },
}

SECTIONS_REQUIRED_KEYS = {("robot", "position")}  # (for an anchor)


class ScenarioError(ValueError):
    """A scenario file is wrong: names the file, the key and what is allowed."""


def _check_value(where: str, key: Key, value):
    def bad(msg):
        raise ScenarioError(f"{where}: {msg}")

    def number(v, what="a number"):
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            bad(f"must be {what}, got {v!r}")
        x = float(v)
        if not math.isfinite(x) and not (x == INF and key.hi == INF):
            bad(f"must be finite, got {v!r}")
        if not key.lo <= x <= key.hi:
            bad(f"must be in [{key.lo:g}, {key.hi:g}]{(' ' + key.unit) if key.unit else ''}, got {v!r}")
        return x

    t = key.type
    if t == "float":
        return number(value)
    if t == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            bad(f"must be an integer, got {value!r}")
        return int(number(value, "an integer"))
    if t == "str":
        if not isinstance(value, str):
            bad(f"must be a string, got {value!r}")
        if key.choices and value not in key.choices:
            bad(f"must be one of {', '.join(key.choices)}; got {value!r}")
        return value
    if t in ("vec2", "vec3"):
        n = 2 if t == "vec2" else 3
        if not isinstance(value, (list, tuple)) or len(value) != n:
            bad(f"must be a list of {n} numbers, got {value!r}")
        return tuple(number(v, "numbers") for v in value)
    if t == "table":
        if not isinstance(value, list) or not value:
            bad(f"must be a non-empty list, got {value!r}")
        return [tuple(number(x) for x in v) if isinstance(v, list) else number(v) for v in value]
    raise AssertionError(t)


def load_scenario(path=None, text: str | None = None, data: dict | None = None, name: str | None = None) -> dict:
    """Read and check a scenario from a TOML file ``path``, TOML ``text`` or ``data`` (the nested
    dict TOML would give, e.g. built by a Gymnasium environment); returns ``{section: {key:
    value}}`` with every default filled in (SI units). ``name`` labels errors. With no source,
    every key takes its default."""
    if name is None:
        name = str(path) if path is not None else "<text>" if text is not None else "<data>"
    if data is not None:
        raw = data
    else:
        if text is None and path is not None:
            try:
                text = Path(path).read_text()
            except OSError as exc:
                raise ScenarioError(f"{name}: cannot read the scenario ({exc.strerror})") from None
        try:
            raw = tomllib.loads(text or "")
        except tomllib.TOMLDecodeError as exc:
            raise ScenarioError(f"{name}: not valid TOML: {exc}") from None

    out: dict[str, dict] = {}
    flat: dict[str, dict] = {}
    for top, val in raw.items():
        if top not in {s.split(".")[0] for s in SCHEMA}:
            raise ScenarioError(f"{name}: unknown section [{top}]; allowed: "
                                f"{', '.join(sorted({s.split('.')[0] for s in SCHEMA}))}")
        if not isinstance(val, dict):
            raise ScenarioError(f"{name}: {top} must be a section [{top}], got {val!r}")
        flat[top] = {k: v for k, v in val.items() if not isinstance(v, dict)}
        for k, v in val.items():
            if isinstance(v, dict):
                if f"{top}.{k}" not in SCHEMA:
                    raise ScenarioError(f"{name}: unknown section [{top}.{k}]")
                flat[f"{top}.{k}"] = v
    for section, keys in SCHEMA.items():
        given = dict(flat.get(section, {}))
        vals = {}
        for k, v in given.items():
            base = k[:-3] if k.endswith("_kn") else k
            key = keys.get(base)
            if key is None or (k != base and not key.knots):
                raise ScenarioError(f"{name}: unknown key {section}.{k}; allowed: {', '.join(sorted(keys))}")
            if base in vals:
                raise ScenarioError(f"{name}: {section}.{base} is given twice (m/s and knots)")
            if k != base:
                v = v * KNOT if isinstance(v, (int, float)) and not isinstance(v, bool) else v
            vals[base] = _check_value(f"{name}: {section}.{base}", key, v)
        for k, key in keys.items():
            if k not in vals:
                vals[k] = key.default
        out[section] = vals
    _cross_checks(name, out)
    return out


def _cross_checks(name: str, sc: dict) -> None:
    def bad(msg):
        raise ScenarioError(f"{name}: {msg}")

    w = sc["water"]
    robot = sc["robot"]

    def seabed_z(x, y):
        along = x * math.cos(w["seabed_slope_heading"]) + y * math.sin(w["seabed_slope_heading"])
        return -w["depth"] + math.tan(w["seabed_slope"]) * along

    if robot["type"] == "anchor":
        if robot["position"] is None:
            bad("robot.position is required for an anchor: (x, y, z) in m")
        x, y, z = robot["position"]
        if z < seabed_z(x, y) - 1e-6:
            bad(f"robot.position z = {z} m is below the seabed (z = {seabed_z(x, y):.2f} m there)")
    elif seabed_z(*robot["start"]) >= -1.0:
        bad(f"robot.start {list(robot['start'])} is where the seabed is {seabed_z(*robot['start']):.2f} m "
            "high: the walker needs at least 1 m of water")
    if robot["type"] == "walker":
        cmds = robot["commands"]
        if any(not isinstance(c, tuple) or len(c) != 3 for c in cmds):
            bad("robot.commands must be a list of [time (s), speed (m/s), turn rate (rad/s)]")
        times = [c[0] for c in cmds]
        if times[0] != 0.0 or any(b <= a for a, b in zip(times, times[1:])):
            bad(f"robot.commands times must start at 0 s and increase, got {times}")
        top = Tripod.max_stride / (robot["gait_period"] / 2)  # the tripod gait's longest stroke per half cycle
        for t, v, turn in cmds:
            if not -top <= v <= top:
                bad(f"robot.commands speed must be in [-{top:.2f}, {top:.2f}] m/s (the walker's top speed at "
                    f"gait_period = {robot['gait_period']:g} s), got {v} at t = {t} s")
            if not -0.5 <= turn <= 0.5:
                bad(f"robot.commands turn rate must be in [-0.5, 0.5] rad/s, got {turn} at t = {t} s")
    if seabed_z(*sc["ship"]["position"]) >= -1.0:
        bad(f"ship.position {list(sc['ship']['position'])}: the seabed there is {seabed_z(*sc['ship']['position']):.2f} m "
            "high, above the surface or within 1 m of it")
    for sec, keys in (("water.density", ("depths", "values")), ("water.current", ("depths", "speeds"))):
        if sc[sec]["type"] == "table":
            for k in keys:
                if sc[sec][k] is None:
                    bad(f"{sec}.{k} is required when {sec}.type = 'table'")
            d = sc[sec]["depths"]
            if any(b <= a for a, b in zip(d, d[1:])):
                bad(f"{sec}.depths must be strictly increasing (m), got {d}")
            if len(sc[sec][keys[1]]) != len(d) or (sec == "water.current" and sc[sec]["headings"] is not None
                                                      and len(sc[sec]["headings"]) != len(d)):
                bad(f"{sec}: every column must have as many rows as depths ({len(d)})")
    w = sc["winch"]
    L = sc["tether"]["length"]
    if w["max_length"] == 0.0:
        w["max_length"] = L if w["mode"] == "fixed" else 2.0 * L
    if not w["min_length"] <= L <= w["max_length"]:
        bad(f"tether.length = {L} m must be in [winch.min_length, winch.max_length] = "
            f"[{w['min_length']}, {w['max_length']}] m")
    if w["band"][0] >= w["band"][1]:
        bad(f"winch.band must be (low, high) with low < high, got {w['band']}")
    if sc["ship"]["mode"] == "waypoints" and not sc["ship"]["waypoints"]:
        bad("ship.waypoints is required when ship.mode = 'waypoints': a list of (x, y) in m")
    if sc["simulation"]["output_interval"] < sc["simulation"]["timestep"]:
        bad("simulation.output_interval must be >= simulation.timestep")


def scenario_docs() -> str:
    """Markdown reference of every key (the body of docs/scenarios.md)."""
    lines = []
    for section, keys in SCHEMA.items():
        lines += [f"### [{section}]", "", "| key | type | default | allowed | unit | meaning |", "|---|---|---|---|---|---|"]
        for k, key in keys.items():
            if key.choices:
                allowed = ", ".join(key.choices)
            elif key.type in ("float", "int", "vec2", "vec3", "table"):
                allowed = f"[{key.lo:g}, {key.hi:g}]"
            else:
                allowed = ""
            name = f"`{k}`" + (f" or `{k}_kn` (knots)" if key.knots else "")
            default = "required" if key.default is None and (section, k) in SECTIONS_REQUIRED_KEYS else (
                "-" if key.default is None else f"`{key.default!r}`")
            lines.append(f"| {name} | {key.type} | {default} | {allowed} | {key.unit} | {key.doc} |")
        lines.append("")
    return "\n".join(lines)

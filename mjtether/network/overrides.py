"""``--set KEY=VALUE`` on a network: the keys a network takes from the command line and a sweep.

* ``simulation.KEY`` and ``water.KEY`` (``NETWORK_KEYS``): numbers (``simulation.timestep=none``:
  the largest stable step; ``simulation.start=steady|as_written``);
* ``waves.KEY``: a key of the sea's ``[waves]`` table (``scenario.sea.Waves``, a scenario's keys
  and checks: ``waves.hs=4``, ``waves.type=jonswap``), on the network's sea or a flat one;
* ``line_types.NAME.KEY``, ``lines.NAME.KEY``, ``points.NAME.KEY``, ``bodies.NAME.KEY``,
  ``vehicles.NAME.KEY`` and ``walkers.NAME.KEY`` (``PART_KEYS``): a field of the named part, a
  number, a whole number (``lines.NAME.segments``), three numbers ``[x, y, z]`` (a position, a
  vector) or two ``[x, y]`` (a walker's position: it stands on the seabed there). ``NAME`` may
  hold dots (the last dot parts it from ``KEY``).

Each change is checked by the part's own checks (``dataclasses.replace`` on the part, then on
the ``Network``), so an error names the key and its allowed range. The changes to one part are
made together (``lines.L.payout_speed`` with ``lines.L.max_length``). A vehicle's ``position``
moves where it starts, not the station it holds (``vehicles.NAME.station``); a walker's
``speed`` is refused on a walker given ``commands`` (its schedule). Units SI as in
``config``: m, kg, N, s; angles in degrees.
"""

from __future__ import annotations

import dataclasses
import tomllib

from .config import Network, NetworkError

NETWORK_KEYS = {
    "simulation": {"duration": ("float", "s"), "output_interval": ("float", "s"), "settle": ("float", "s"),
                   "start": ("str", ""), "timestep": ("timestep", "s"), "max_wall_hours": ("float", "h"),
                   "max_output_gb": ("float", "GB")},
    "water": {"depth": ("float", "m"), "gravity": ("float", "m/s^2"), "rho": ("float", "kg/m^3"),
              "seabed_damping": ("float", "Pa s/m"), "seabed_friction": ("float", ""),
              "seabed_stiffness": ("float", "Pa/m")},
}
"""The ``Network`` fields ``--set`` takes: section -> {key: (kind, unit)}."""

_COEFFICIENT = ("float", "")
PART_KEYS = {
    "line_types": {"diameter": ("float", "m"), "mass_per_length": ("float", "kg/m"), "EA": ("float", "N"),
                   "EI": ("float", "N m^2"), "cd_normal": _COEFFICIENT, "ca_normal": _COEFFICIENT,
                   "cd_tangential": _COEFFICIENT, "ca_tangential": _COEFFICIENT},
    "lines": {"length": ("float", "m"), "segments": ("int", ""), "payout_speed": ("float", "m/s"),
              "max_length": ("float", "m")},
    "points": {"position": ("vec3", "m"), "mass": ("float", "kg"), "volume": ("float", "m^3"),
               "cd_area": ("float", "m^2"), "ca": _COEFFICIENT, "force": ("vec3", "N"), "height": ("float", "m")},
    "bodies": {"position": ("vec3", "m"), "rpy_deg": ("vec3", "deg"), "mass": ("float", "kg"), "cg": ("vec3", "m"),
               "inertia": ("vec3", "kg m^2"), "volume": ("float", "m^3"), "cd_area": ("vec3", "m^2"),
               "ca": ("vec3", ""), "pin": ("vec3", "m"), "height": ("float", "m")},
    "vehicles": {"position": ("vec3", "m"), "station": ("vec3", "m"), "heading_deg": ("float", "deg")},
    "walkers": {"position": ("vec2", "m"), "heading_deg": ("float", "deg"), "speed": ("float", "m/s"),
                "gait_period": ("float", "s")},
}
"""The fields of a network's parts ``--set`` takes: section -> {key: (kind, unit)}."""

_PART = {"line_types": "line type", "lines": "line", "points": "point", "bodies": "body", "vehicles": "vehicle",
         "walkers": "walker"}


@dataclasses.dataclass(frozen=True)
class Key:
    """A ``--set`` key resolved on a network: ``section``, the part's ``name`` (None for
    ``simulation``/``water``), its ``field``, the value's ``kind`` (float, int, vec3, vec2, str,
    timestep: a number or none) and ``unit``."""

    section: str
    name: str | None
    field: str
    kind: str
    unit: str


def _wave_keys() -> dict:
    """``waves.KEY``'s keys: {field: (kind, unit)} of ``scenario.sea.Waves``."""
    from mjtether.scenario.sea import Waves
    return {f.name: (f.metadata["param"].kind, f.metadata["param"].unit) for f in dataclasses.fields(Waves)}


def _unknown(key: str) -> NetworkError:
    flat = ", ".join([*(f"{s}.{k}" for s in ("simulation", "water") for k in sorted(NETWORK_KEYS[s])), "waves.KEY"])
    parts = ", ".join(f"{s}.NAME.KEY" for s in PART_KEYS)
    return NetworkError(f"--set {key}: a network takes --set KEY=VALUE with KEY one of {flat}, or {parts} "
                        f"(a part's field: {'; '.join(f'{s}: ' + ', '.join(PART_KEYS[s]) for s in PART_KEYS)})")


def _parts(net: Network, section: str) -> dict:
    """The network's parts of ``section`` by name (its lines too)."""
    got = getattr(net, section)
    return {ln.name: ln for ln in got} if section == "lines" else got


def resolve(net: Network, key: str) -> Key:
    """The ``Key`` of ``key`` (e.g. ``lines.1a.length``) on ``net``, or NetworkError naming it and
    what it may be: the keys of its section, the names of its part."""
    key = key.strip()
    sec, _, rest = key.partition(".")
    if sec in NETWORK_KEYS:
        if rest not in NETWORK_KEYS[sec]:
            raise _unknown(key)
        return Key(sec, None, rest, *NETWORK_KEYS[sec][rest])
    if sec == "waves":
        keys = _wave_keys()
        if rest not in keys:
            raise NetworkError(f"--set {key}: the sea's keys (waves.KEY) are {', '.join(keys)}")
        return Key(sec, None, rest, *keys[rest])
    if sec not in PART_KEYS or "." not in rest:
        raise _unknown(key)
    name, _, field_ = rest.rpartition(".")
    parts = _parts(net, sec)
    if name not in parts:
        have = ", ".join(parts) if parts else "none"
        raise NetworkError(f"--set {key}: no {_PART[sec]} named {name!r} (the network's {sec}: {have})")
    if field_ not in PART_KEYS[sec]:
        raise NetworkError(f"--set {key}: a {_PART[sec]}'s keys ({sec}.NAME.KEY) are {', '.join(PART_KEYS[sec])}")
    return Key(sec, name, field_, *PART_KEYS[sec][field_])


def parse(k: Key, key: str, text: str):
    """The value of ``--set key=text`` for its kind, or NetworkError naming the key."""
    text = text.strip()
    unit = f" ({k.unit})" if k.unit and k.name is not None else ""
    if k.kind == "str":
        return text
    if k.kind == "timestep" and text.lower() == "none":
        return None
    if k.kind in ("float", "timestep"):
        try:
            return float(text)
        except ValueError:
            raise NetworkError(f"--set {key}: give {key}=NUMBER{unit}, got {text!r}") from None
    if k.kind == "int":
        try:
            return int(text)
        except ValueError:
            raise NetworkError(f"--set {key}: give {key}=WHOLE NUMBER, got {text!r}") from None
    try:
        value = tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        value = None
    n, shape = (2, "[X, Y], two") if k.kind == "vec2" else (3, "[X, Y, Z], three")
    if not (isinstance(value, list) and len(value) == n
            and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in value)):
        raise NetworkError(f"--set {key}: give {key}={shape} numbers{unit}, got {text!r}")
    return [float(x) for x in value]


def _apply(net: Network, changes) -> Network:
    """``net`` with ``changes`` (``(Key, value, label)``) made: each part's together, replaced
    (its checks), then the network (its checks); raises ValueError."""
    top, parts, sea = {}, {}, {}
    for k, value, _ in changes:
        if k.section == "waves":
            sea[k.field] = value
        elif k.name is None:
            top[k.field] = value
        else:
            parts.setdefault(k.section, {}).setdefault(k.name, {})[k.field] = value
    for sec, edits in parts.items():
        new = dict(_parts(net, sec))
        for name, fields in edits.items():
            new[name] = dataclasses.replace(new[name], **fields)
        top[sec] = tuple(new.values()) if sec == "lines" else new
    if sea:
        from mjtether.scenario.sea import Waves
        top["waves"] = dataclasses.replace(net.waves if net.waves is not None else Waves(), **sea)
    return dataclasses.replace(net, **top) if top else net


def with_overrides(net: Network, overrides=()) -> Network:
    """``net`` with ``--set`` items ``KEY=VALUE`` (see the module docstring) applied and
    checked; an item may be ``(item, label)``, the label to blame (``"--set KEY=VALUE"`` if not
    given). Raises NetworkError naming the item."""
    changes = []  # (Key, value, the label to blame: "--set KEY=VALUE", or the one load_scenario was given)
    for item in overrides:
        item, label = item if isinstance(item, tuple) else (item, f"--set {item}")
        key, eq, val = str(item).partition("=")
        key = key.strip()
        if not eq:
            raise _unknown(key)
        k = resolve(net, key)
        changes.append((k, parse(k, key, val), label))
    try:
        return _apply(net, changes) if changes else net
    except ValueError as exc:
        for change in changes:  # which --set: the first refused on its own
            try:
                _apply(net, [change])
            except ValueError as alone:
                raise NetworkError(f"{change[2]}: {alone}") from None
        raise NetworkError(f"{', '.join(label for _, _, label in changes)}: {exc}") from None

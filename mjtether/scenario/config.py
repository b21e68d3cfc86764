"""Typed configuration: sections of parameters, each with its type, default, range, unit and
meaning in one place.

A section is a dataclass deriving from ``Section`` whose fields are made with ``param(...)``
(or are sections themselves). Constructing one checks every field, so the Python API, the
TOML loader (``mjtether.scenario.load_scenario``) and the environments' keyword arguments all
refuse bad values the same way, with a ``ConfigError`` naming the key path
(``tether.segments``), the value and what is allowed. ``markdown_table`` renders a section's
reference (``docs/scenarios.md`` is made from it).

Dataclasses rather than pydantic: the checks and messages here are few and specific (ranges
with units, knots aliases, numpy scalars accepted and bools refused as numbers), a frozen
dataclass is what the rest of the code already uses, and it keeps the dependency list short.

Units: SI inside, except where a key says otherwise in its name (``_deg``: degrees, the unit a
user reads and writes; ``_kn`` aliases: knots, converted on reading).
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from dataclasses import dataclass, field, fields
from typing import ClassVar

import numpy as np

INF = math.inf

KINDS = ("float", "int", "str", "bool", "vec2", "vec3", "list", "rows2", "rows3", "rows4")
"""Parameter kinds: a number, an integer, a string (optionally one of ``choices``), a boolean, a
point (x, y) or (x, y, z), a list of numbers, or a table of rows of 2 or 3 numbers."""


class ConfigError(ValueError):
    """A configuration value is wrong. ``key`` is its path (``tether.segments``), or ``""`` for a
    problem that is not one key's."""

    def __init__(self, message: str, key: str = ""):
        super().__init__(message)
        self.key = key


@dataclass(frozen=True)
class Param:
    """What a parameter may hold (see ``param``)."""

    kind: str
    lo: float = -INF
    hi: float = INF
    unit: str = ""
    doc: str = ""
    choices: tuple = ()
    knots: bool = False  # may be given in knots as <key>_kn
    optional: bool = False  # None is allowed (the meaning of None is in ``doc``)

    def allowed(self) -> str:
        """The allowed values, as the docs and error messages say them."""
        if self.choices:
            return ", ".join(c if c else '""' for c in self.choices)  # ("": none, as a TOML string)
        if self.kind in ("str", "bool"):
            return "true or false" if self.kind == "bool" else "text"
        rng = f"[{self.lo:g}, {self.hi:g}]" + (f" {self.unit}" if self.unit else "")
        what = {"float": "a number in", "int": "an integer in", "vec2": "two numbers [a, b], each in",
                "vec3": "three numbers [x, y, z], each in", "list": "a list of numbers, each in",
                "rows2": "a list of [a, b] rows, each number in",
                "rows3": "a list of [a, b, c] rows, each number in",
                "rows4": "a list of [a, b, c, d] rows, each number in"}[self.kind]
        return f"{what} {rng}"

    def check(self, key: str, value):
        """``value`` converted to its kind (floats, ints, tuples), or ConfigError."""
        if value is None and self.optional:
            return None

        def bad(why=None):
            raise ConfigError(f"{key} = {_show(value)}: {why or 'must be ' + self.allowed()}", key)

        def number(v, integer=False):
            if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.integer, np.floating)):
                bad()
            if integer and not (isinstance(v, (int, np.integer)) or (isinstance(v, float) and v.is_integer())):
                bad()
            x = float(v)
            if math.isnan(x) or (math.isinf(x) and not (x == self.hi == INF or x == self.lo == -INF)):
                bad()
            if not self.lo <= x <= self.hi:
                bad()
            return int(x) if integer else x

        k = self.kind
        if k == "float":
            return number(value)
        if k == "int":
            return number(value, integer=True)
        if k == "bool":
            if not isinstance(value, (bool, np.bool_)):
                bad()
            return bool(value)
        if k == "str":
            if not isinstance(value, str) or (self.choices and value not in self.choices):
                bad()
            return value
        if k in ("vec2", "vec3"):
            n = 2 if k == "vec2" else 3
            if not _is_sequence(value) or len(value) != n:
                bad()
            return tuple(number(v) for v in value)
        if k == "list":
            if not _is_sequence(value) or len(value) == 0:
                bad()
            return tuple(number(v) for v in value)
        if k in ("rows2", "rows3", "rows4"):
            n = int(k[-1])
            if not _is_sequence(value) or len(value) == 0 or any(not _is_sequence(r) or len(r) != n for r in value):
                bad()
            return tuple(tuple(number(v) for v in r) for r in value)
        raise AssertionError(k)


def _is_sequence(v) -> bool:
    return isinstance(v, (list, tuple)) or (isinstance(v, np.ndarray) and v.ndim >= 1)


def param(default, lo: float = -INF, hi: float = INF, unit: str = "", doc: str = "", *, kind: str | None = None,
          choices: tuple = (), knots: bool = False, optional: bool = False):
    """A dataclass field with its ``Param`` (kind inferred from the default where not given)."""
    if kind is None:
        kind = {bool: "bool", int: "int", float: "float", str: "str"}[type(default)]
    assert kind in KINDS, kind
    meta = {"param": Param(kind, lo, hi, unit, doc, tuple(choices), knots, optional or default is None)}
    return field(default=default, metadata=meta)


def section(cls):
    """A field holding a nested section, default-constructed."""
    return field(default_factory=cls)


def tables(cls, doc: str = ""):
    """A field holding a list of ``cls`` sections, ``[[key]]`` arrays of tables in TOML (e.g.
    ``[[tether.sections]]``); none by default. Items are numbered from 0 in error messages
    (``tether.sections[1].length``)."""
    return field(default=(), metadata={"tables": cls, "doc": doc})


class Section:
    """Base of the configuration sections: frozen dataclasses checked on construction.
    ``PATH`` is the section's key path (``"water.current"``); ``_check`` holds the checks
    that involve more than one field."""

    PATH: ClassVar[str] = ""

    def __post_init__(self):
        for f in fields(self):
            p = f.metadata.get("param")
            value = getattr(self, f.name)
            if "tables" in f.metadata:
                object.__setattr__(self, f.name, self._check_tables(f.name, f.metadata["tables"], value))
                continue
            if p is None:
                sub = f.default_factory
                if not isinstance(value, sub):
                    raise ConfigError(f"{self._key(f.name)} must be a section [{self._key(f.name)}], got {value!r}",
                                      self._key(f.name))
                continue
            object.__setattr__(self, f.name, p.check(self._key(f.name), value))
        self._check()

    def _check(self) -> None:
        """Cross-field checks (override)."""

    def _check_tables(self, name: str, cls, value) -> tuple:
        key = self._key(name)
        if not _is_sequence(value):
            raise ConfigError(f"{key} must be a list of [[{key}]] tables, got {_show(value)}", key)
        for i, item in enumerate(value):
            if not isinstance(item, cls):
                raise ConfigError(f"{key}[{i}] must be a [[{key}]] table ({cls.__name__}), got {item!r}", f"{key}[{i}]")
        return tuple(value)

    @classmethod
    def _key(cls, name: str) -> str:
        return f"{cls.PATH}.{name}" if cls.PATH else name

    def _bad(self, name: str, why: str):
        """Raise a ConfigError about field ``name`` (its value shown)."""
        raise ConfigError(f"{self._key(name)} = {_show(getattr(self, name))}: {why}", self._key(name))

    def to_dict(self) -> dict:
        """Nested plain dict (lists for tuples), as a TOML file would hold it."""
        out = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if "tables" in f.metadata:
                out[f.name] = [item.to_dict() for item in v]
            else:
                out[f.name] = v.to_dict() if isinstance(v, Section) else _plain(v)
        return out

    def replace(self, **changes):
        """A copy with ``changes``, checked again."""
        return dataclasses.replace(self, **changes)


def _plain(v):
    """Tuples as lists and NumPy values as Python ones, as TOML shows them."""
    if isinstance(v, (tuple, list)):
        return [_plain(x) for x in v]
    if isinstance(v, np.ndarray):
        return _plain(v.tolist())
    if isinstance(v, np.generic):
        return v.item()
    return v


def _show(v) -> str:
    return repr(_plain(v))


def params(cls) -> dict[str, Param]:
    """{field name: Param} of a section class (nested sections left out)."""
    return {f.name: f.metadata["param"] for f in fields(cls) if "param" in f.metadata}


def subsections(cls) -> dict[str, type]:
    """{field name: section class} of a section class's nested sections."""
    return {f.name: f.default_factory for f in fields(cls) if "param" not in f.metadata and "tables" not in f.metadata}


def table_lists(cls) -> dict[str, type]:
    """{field name: item section class} of a section class's ``tables`` fields."""
    return {f.name: f.metadata["tables"] for f in fields(cls) if "tables" in f.metadata}


def split_index(part: str) -> tuple[str, int | None]:
    """``"floats[1]"`` -> ("floats", 1); ``"water"`` -> ("water", None): a key path's part that
    names one table of an array of tables (``tether.floats[1].start``)."""
    name, sep, rest = part.partition("[")
    if not sep:
        return part, None
    if not rest.endswith("]") or not rest[:-1].isdigit():
        raise ConfigError(f"{part!r}: an index is a whole number in brackets, e.g. floats[0]", part)
    return name, int(rest[:-1])


def build(cls, raw, where: str = ""):
    """A ``cls`` section from ``raw``, a nested dict as TOML gives it: unknown keys and knots
    aliases handled here, values checked by the section itself. ``where`` prefixes errors
    (the file name)."""
    prefix = f"{where}: " if where else ""
    if not isinstance(raw, dict):
        key = cls.PATH
        raise ConfigError(f"{prefix}{key} must be a section [{key}], got {raw!r}", key)
    ps, subs, lists = params(cls), subsections(cls), table_lists(cls)
    kwargs = {}
    for k, v in raw.items():
        base = k[:-3] if k.endswith("_kn") and k[:-3] in ps and ps[k[:-3]].knots else k
        if base in subs:
            kwargs[base] = build(subs[base], v, where)
            continue
        if base in lists:
            key = cls._key(base)
            if not isinstance(v, list) or not all(isinstance(item, dict) for item in v):
                raise ConfigError(f"{prefix}{key} must be a list of [[{key}]] tables, got {_show(v)}", key)
            kwargs[base] = [_build_item(lists[base], item, where, f"{key}[{i}]") for i, item in enumerate(v)]
            continue
        if base not in ps:
            raise ConfigError(prefix + unknown_key_message(cls, k), cls._key(_shown_key(k)))
        if base in kwargs:
            raise ConfigError(f"{prefix}{cls._key(base)} is given twice (m/s and knots)", cls._key(base))
        if base != k and isinstance(v, (int, float)) and not isinstance(v, bool):
            from mjtether.units import KNOT
            v = v * KNOT
        kwargs[base] = v
    try:
        return cls(**kwargs)
    except ConfigError as exc:
        raise ConfigError(prefix + str(exc), exc.key) from None


def _build_item(cls, raw: dict, where: str, key: str):
    """``build`` of one table of an array of tables, its errors naming ``key`` (``tether.sections[1]``)."""
    try:
        return build(cls, raw, where)
    except ConfigError as exc:
        msg, k = str(exc), exc.key
        if k.startswith(cls.PATH):
            k = key + k[len(cls.PATH):]
        msg = msg.replace(f"{cls.PATH}.", f"{key}.").replace(f"[{cls.PATH}]", f"[[{cls.PATH}]] {key}")
        raise ConfigError(msg, k) from None


RENAMED: dict[str, str] = {}
"""Keys of earlier versions that now have another name: {old key path: message}."""


def _shown_key(key: str) -> str:
    """A key as messages show it: an empty or blank one (TOML allows ``"" = 1``) as ``""``."""
    return key if key.strip() else f'"{key}"'


def unknown_key_message(cls, key: str) -> str:
    path = cls._key(_shown_key(key))
    if path in RENAMED:
        return f"{path}: {RENAMED[path]}"
    allowed = sorted(params(cls)) + sorted(subsections(cls)) + sorted(table_lists(cls))
    close = difflib.get_close_matches(key, allowed, n=1)
    hint = f" (did you mean {close[0]}?)" if close else ""
    where = f"[{cls.PATH}]" if cls.PATH else "the top level"
    return f"unknown key {path}{hint}; {where} allows: {', '.join(allowed)}"


def markdown_table(cls) -> list[str]:
    """Markdown reference of a section and its subsections: key, type, default, allowed, unit, meaning."""
    lines = []
    if params(cls):
        lines += [f"### [{cls.PATH}]", "", "| key | type | default | allowed | unit | meaning |", "|---|---|---|---|---|---|"]
    for f in fields(cls):
        p = f.metadata.get("param")
        if p is None:
            continue
        name = f"`{f.name}`" + (f" or `{f.name}_kn` (knots)" if p.knots else "")
        default = "-" if f.default is None else f"`{_show(f.default)}`"
        allowed = p.allowed().replace("|", "\\|")
        lines.append(f"| {name} | {p.kind} | {default} | {allowed} | {p.unit} | {p.doc} |")
    if params(cls):
        lines.append("")
    for name, item in table_lists(cls).items():
        meta = next(f for f in fields(cls) if f.name == name).metadata
        lines += [f"### [[{item.PATH}]]", "", meta["doc"], "", "| key | type | default | allowed | unit | meaning |",
                  "|---|---|---|---|---|---|"]
        lines += markdown_table(item)[4:]
    for sub in subsections(cls).values():
        lines += markdown_table(sub)
    return lines

"""MoorDyn v2 input files: read one as MoorDyn-C 2.7 reads it, write a scenario as one.

MoorDyn (Hall and Goupee, 2015, *Ocean Engineering*; the v2 format of its documentation,
"Input Files") describes a mooring system in sections headed by dashed lines. ``parse`` reads
them as MoorDyn-C 2.7's ``MoorDyn2.cpp`` does: the section headers and their aliases (LINE TYPES
or LINE DICTIONARY; POINTS, POINT LIST, POINT PROPERTIES, CONNECTION PROPERTIES or NODE
PROPERTIES; LINES, LINE LIST or LINE PROPERTIES; BODIES; OPTIONS, SOLVER OPTIONS), the option
names and aliases (g/gravity, rho/WtrDnsty, kBot/kb, cBot/cb, ...; an unknown option is a
warning, as in MoorDyn-C), the point words (Fixed, Anchor, Fix; Vessel, Ves, Coupled, Cpld,
Fairlead; Free, Point, Connect, Con; Body<n>), attachments written ``2``, ``P2``, ``C2``,
``Point2``, points with 9 fields or 12 (a force Fx Fy Fz before CdA), and MoorDyn-C's defaults
(g = 9.80665 m/s^2, rho 1025 kg/m^3, kBot 3e6 Pa/m, cBot 3e5 Pa s/m, no friction; the water at
least as deep as the lowest point).

``read`` then gives

* a ``Scenario`` for one line, or a chain of lines joined end to end at free points (each in
  two lines), from one coupled point (the ship's fairlead) to one fixed point (the anchored
  robot end): a chain is a line make-up, one ``[[tether.sections]]`` per line and a
  ``[[tether.point_loads]]`` at each free point with mass, volume or drag (a chain one tether
  cannot hold, its lines' CaAx mixing 0 and Ca or a force on a joint, is a network);
* a ``mjtether.network.Network`` for anything else: several lines sharing points, free points
  and free line ends, fixed, coupled, free or pinned bodies, and rods (fixed, coupled, free or
  pinned at end A: each a rigid cylinder, a body ``rod<n>`` with points ``R<n>A`` and ``R<n>B``
  at its ends, its hydrodynamics lumped at its middle where MoorDyn spreads them over its
  segments; a file of rods alone is a network without lines). It settles
  for the file's TmaxIC (at most ``MAX_SETTLE``) before its run, as MoorDyn relaxes before its
  own; with TmaxIC 0 it starts, as MoorDyn does, from the file's positions at rest.

Line types: Diam, Mass/m, EA, BA/-zeta, EI, Cd, Ca, CdAx, CaAx; CaAx = Ca is mjtether's
isotropic added mass, CaAx = 0 its "normal" one (other values: the nearer, with a warning);
BA/-zeta: mjtether damps each element's stretch critically (noted). Read, not needed: the
options of MoorDyn's own integrator and initial-condition solver (dtM, CFL, tScheme, dtIC,
TmaxIC, CdScaleIC, threshIC, ICgenDynamic, fileIC; mjtether picks its own stable step, for
one line the largest at which it is stable, keeps its EA and rests on the seabed, up to 0.05 s,
and starts from its steady state), FricDamp (mjtether's friction sticks exactly), the output
options and the OUTPUTS section. Refused, naming the feature and the file's line: rods on
bodies, a line with bending stiffness on a rod's end (MoorDyn clamps it), line failure, SYROPE
line types, viscoelastic ('|') or nonlinear (a curve file) EA, BA in N s, VIV (Cl != 0), waves
other than frequency components (``WaveKin`` 2 and 7, from ``wave_frequencies.txt`` beside the
file: ``moordyn_waves``; a file with them is a network, ``water.wave_components``), MoorDyn's
dynamic current files (Currents 2, 4, 5), static friction other than
kinetic (StatDynFricScale), OpenFAST MoorDyn-F's external loads and line controls (EXTERNAL
LOADS, CONTROL: MoorDyn-C 2.7 skips them) and, as MoorDyn-C refuses them, points, lines, rods
or bodies numbered out of turn. OUTPUTS that name a line, point, rod or body the file does not
have, which MoorDyn-C refuses, are a warning (``moordyn_outputs``). A 3-D seafloor
(SeafloorFile, beside the file or in the working folder, where MoorDyn-C looks) becomes the
seabed's height field. MoorDyn-C
pushes its nodes straight up from it and rubs them horizontally; mjtether's contact and
friction act along the seabed's normal and tangent plane, so on a slope they differ.

The run's duration is not in a MoorDyn file: 60 s unless ``--set simulation.duration=...``.
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass
from pathlib import Path

from mjtether.io import moordyn_waves
from mjtether.io.moordyn_beside import CURRENT_FILE  # noqa: F401 - re-exported: where a current profile goes
from mjtether.io.moordyn_beside import number as _number
from mjtether.io.moordyn_beside import read_current_profile as _current_profile
from mjtether.io.moordyn_beside import seafloor_path as _seafloor
from mjtether.io.moordyn_outputs import unknown_objects
from mjtether.scenario import ScenarioError, load_scenario
from mjtether.scenario.stable_step import stable_timestep

DEFAULT_DURATION = 60.0
"""Simulated time (s) of a scenario read from a MoorDyn file, which does not say."""

MAX_SETTLE = 60.0
"""Longest a network read from a MoorDyn file settles before its run (s); see ``_network``."""

MOORDYN_G = 9.80665
"""MoorDyn-C's default gravity (m/s^2)."""

_HEADER = re.compile(r"^\s*-{2,}.*$")
# MoorDyn-C 2.7 (MoorDyn2.cpp, findStartOfSection): a header line holds "---" and one of these
_SECTIONS = {
    "LINE TYPES": ("LINE DICTIONARY", "LINE TYPES"),
    "ROD TYPES": ("ROD DICTIONARY", "ROD TYPES"),
    "BODIES": ("BODIES", "BODY LIST", "BODY PROPERTIES"),
    "RODS": ("RODS", "ROD LIST", "ROD PROPERTIES"),
    "POINTS": ("POINTS", "POINT LIST", "POINT PROPERTIES", "CONNECTION PROPERTIES", "NODE PROPERTIES"),
    "LINES": ("LINES", "LINE LIST", "LINE PROPERTIES"),
    "FAILURE": ("FAILURE",),
    "SYROPE IC": ("SYROPE IC",),
    "OPTIONS": ("OPTIONS",),
    "OUTPUTS": ("OUTPUTS",),
}
_MOORDYN_F = ("EXTERNAL LOADS", "CONTROL")  # (OpenFAST's MoorDyn-F; MoorDyn-C 2.7 skips them: a header naming one)
_REFUSED_SECTIONS = {"FAILURE": "line failure", "SYROPE IC": "SYROPE line types",
                     "EXTERNAL LOADS": "external loads (MoorDyn-F's; MoorDyn-C 2.7 skips them)",
                     "CONTROL": "line length controls (MoorDyn-F's)"}
# MoorDyn-C's option names and aliases (MoorDyn2.cpp, readOptionsLine), lower case
_OPTION_ALIASES = {"dt": "dtm", "gravity": "g", "wtrdnsty": "rho", "kb": "kbot", "cb": "cbot", "icdt": "dtic",
                   "ictmax": "tmaxic", "icdfac": "cdscaleic", "icthresh": "threshic",
                   "gendynamicic": "icgendynamic", "icfile": "fileic"}
_SOLVER_OPTIONS = {"dtm", "cfl", "tscheme", "dtic", "tmaxic", "cdscaleic", "threshic", "icgendynamic", "fileic",
                   "fricdamp"}
"""Options that steer MoorDyn's own integrator and initial-condition solver: read, not needed
(mjtether picks its own stable step and starts from its steady state; its friction sticks
exactly, the limit FricDamp -> infinity)."""
_OUTPUT_OPTIONS = {"writelog", "writeunits", "dtout", "disableoutput", "disableouttime", "dtwave",
                   "unifycurrentgrid"}
_KNOWN_OPTIONS = {"g", "rho", "wtrdpth", "kbot", "cbot", "frictioncoefficient", "statdynfricscale", "wavekin",
                  "currents", "seafloorfile"} | _SOLVER_OPTIONS | _OUTPUT_OPTIONS
# point and body attachment words (MoorDyn2.cpp), upper case
_FIXED, _COUPLED, _FREE = ("ANCHOR", "FIXED", "FIX"), ("FAIRLEAD", "VESSEL", "VES", "COUPLED", "CPLD"), \
    ("POINT", "CONNECT", "CON", "FREE")
_PINNED = ("VESSELPINNED", "VESPIN", "CPLDPIN", "COUPLEDPINNED")


class MoorDynWarning(UserWarning):
    """A MoorDyn entry mjtether approximates or does not know (the message names the line)."""


def is_moordyn(text: str) -> bool:
    """Whether ``text`` looks like a MoorDyn input file (it has a LINE TYPES or ROD TYPES section, or
    their DICTIONARY aliases)."""
    return any(_HEADER.match(line) and any(k in line.upper() for k in ("LINE TYPES", "LINE DICTIONARY", "ROD TYPES",
                                                                       "ROD DICTIONARY"))
               for line in text.splitlines())


def _section_of(line: str) -> str | None:
    up = line.upper()
    title = up.strip(" -\t")
    for key in _MOORDYN_F:
        if title.startswith(key):
            return key
    for key, names in _SECTIONS.items():
        if any(n in up for n in names):
            return key
    return None


def _sections(name: str, text: str) -> dict[str, tuple[int, list[tuple[int, list[str]]]]]:
    """{section: (header line number, [(line number, fields), ...])}: every line between a
    header and the next, as MoorDyn-C reads them (fields split on blanks; text after ``!``, ``#``
    or ``%`` left out); headers that name no section MoorDyn reads (the title, "need this
    line") close the section before them."""
    out: dict = {}
    current = None
    for no, raw in enumerate(text.splitlines(), 1):
        line = re.split(r"[!#%]", raw, maxsplit=1)[0].rstrip()
        if _HEADER.match(raw):
            current = _section_of(raw)
            if current is not None:
                out.setdefault(current, (no, []))
            continue
        if current is None or not line.strip():
            continue
        out[current][1].append((no, line.split()))
    return out


def _table(name, sec, key):
    """The data rows of a table section (its first two rows are column names and units)."""
    no, rows = sec[key]
    if len(rows) < 2:
        raise ScenarioError(f"{name}: line {no}: the {key} section needs its column-name and unit lines")
    return rows[0], rows[2:]


def _in_turn(name, no, given, k, what):
    if given != str(k):  # (MoorDyn-C: "... ID must be sequential starting from 1")
        raise ScenarioError(f"{name}: line {no}: {what} IDs must run 1, 2, 3, ... (as MoorDyn requires); got {given!r}")


def _word(text: str) -> tuple[str, str]:
    """MoorDyn's decomposeString: the leading letters (upper case) and the number after them."""
    m = re.match(r"([A-Za-z]*)(\d*)", text)
    return m.group(1).upper(), m.group(2)


@dataclass
class Parsed:
    """A MoorDyn file read: its line types, points, bodies and lines (``mjtether.network``
    objects), the options mjtether uses, and notes on what it read but does not need."""

    name: str
    line_types: dict
    points: dict
    bodies: dict
    lines: list
    rows: dict  # object name -> the file's line number
    depth: float
    rho: float
    gravity: float
    kbot: float
    cbot: float
    friction: float
    tmax_ic: float
    notes: list
    current: tuple = ((), (), ())  # depths (m, below the surface), speeds (m/s), headings (deg)
    seafloor: str = ""  # a 3-D seafloor file (its absolute path), or "" for a level seabed
    waves: tuple = ()  # (amplitude m, omega rad/s, heading deg, phase deg) per component (moordyn_waves)


def parse(text: str, name: str = "<moordyn>") -> Parsed:
    """Read a MoorDyn v2 file as MoorDyn-C 2.7 reads it; ScenarioError naming the file's line for
    what mjtether cannot represent (rods, VIV, viscoelastic or nonlinear line types, waves other
    than frequency components, dynamic currents, line failure) or what is not a valid entry."""
    from mjtether.network import Body, Line, LineType, Point
    sec = _sections(name, text)
    for key, what in _REFUSED_SECTIONS.items():
        if key in sec and len(sec[key][1]) > (2 if key != "FAILURE" else 1):
            no = sec[key][1][min(2, len(sec[key][1]) - 1)][0]
            raise ScenarioError(f"{name}: line {no}: {what} ({key} section) are not supported by mjtether")
    if "RODS" in sec:  # (first: a file of rods alone has no LINE TYPES)
        _rods(name, sec, [])
    elif "LINE TYPES" not in sec:
        raise ScenarioError(f"{name}: line 1: no LINE TYPES section: not a MoorDyn v2 input file")
    elif "LINES" not in sec:
        raise ScenarioError(f"{name}: line 1: no LINES section (and no RODS): nothing to run")

    def table(key):  # (a file of rods alone has no LINE TYPES, POINTS or LINES)
        return _table(name, sec, key)[1] if key in sec else []

    notes, rows = [], {}

    # options first: g and rho are needed for the rest
    options = {}
    for no, f in sec.get("OPTIONS", (0, []))[1]:
        if len(f) < 2:
            warnings.warn(f"{name}: line {no}: an option is a value then its name; ignored (as MoorDyn does)",
                          MoorDynWarning, stacklevel=3)
            continue
        key = _OPTION_ALIASES.get(f[1].lower(), f[1].lower())
        if key not in _KNOWN_OPTIONS:
            warnings.warn(f"{name}: line {no}: option {f[1]!r} is not a MoorDyn-C 2.7 option; ignored (as MoorDyn "
                          "does)", MoorDynWarning, stacklevel=3)
            continue
        options[key] = (no, f[0])

    def opt(key, default):
        if key not in options:
            return default
        no, val = options[key]
        return _number(name, no, val, f"option {key}")

    waves, wave_kin = (), opt("wavekin", 0)
    if wave_kin in moordyn_waves.WAVE_KINDS:
        waves, wave_notes = moordyn_waves.read_components(name, options["wavekin"][0], int(wave_kin))
        notes.extend(wave_notes)
    elif wave_kin != 0:
        moordyn_waves.refuse(name, *options["wavekin"])
    current = ((), (), ())
    mode = opt("currents", 0)
    if mode in (1, 3):  # a steady profile, on a grid or at the nodes: both the same steady current here
        current = _current_profile(name, options["currents"][0])
    elif mode != 0:
        raise ScenarioError(f"{name}: line {options['currents'][0]}: Currents = {options['currents'][1]}: dynamic or "
                            "4-D currents are not supported by mjtether (a steady profile, Currents = 1, is)")
    seafloor = _seafloor(name, *options["seafloorfile"]) if "seafloorfile" in options else ""
    if opt("statdynfricscale", 1.0) != 1.0:
        raise ScenarioError(f"{name}: line {options['statdynfricscale'][0]}: StatDynFricScale = "
                            f"{options['statdynfricscale'][1]}: static and kinetic friction differ; mjtether's "
                            "seabed friction is one coefficient")
    for key in sorted(set(options) & _SOLVER_OPTIONS):
        if key not in ("tscheme", "fileic"):
            opt(key, 0.0)  # (a number, as MoorDyn needs, though mjtether does not use it)
        notes.append(f"line {options[key][0]}: {key} = {options[key][1]} (MoorDyn's own solver): not needed")
    g, rho = opt("g", MOORDYN_G), opt("rho", 1025.0)

    types = {}
    for no, f in table("LINE TYPES"):
        if len(f) < 10:
            raise ScenarioError(f"{name}: line {no}: a line type needs TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx "
                                f"CaAx, got {len(f)} columns")
        if "|" in f[3] or "|" in f[4]:
            raise ScenarioError(f"{name}: line {no}: viscoelastic line types ('|' in EA or BA) are not supported by "
                                "mjtether")
        for col, what in ((3, "EA"), (5, "EI")):
            try:
                float(f[col])
            except ValueError:
                raise ScenarioError(f"{name}: line {no}: a nonlinear {what} curve ({f[col]!r}) is not supported by "
                                    "mjtether") from None
        v = [_number(name, no, x, col) for x, col in zip(f[1:10], ("Diam", "Mass/m", "EA", "BA/-zeta", "EI", "Cd",
                                                                    "Ca", "CdAx", "CaAx"))]
        extra = [_number(name, no, x, "Cl/dF/cF") for x in f[10:13]]
        if extra and extra[0] != 0.0:
            raise ScenarioError(f"{name}: line {no}: VIV (Cl = {extra[0]:g}) is not supported by mjtether")
        diam, mass, EA, BA, EI, cd, ca, cdax, caax = v
        if BA > 0:
            raise ScenarioError(f"{name}: line {no}: BA = {BA:g} N s: mjtether damps each element's stretch as a "
                                "fraction of critical; give a negative BA (-zeta)")
        if BA < 0 and BA != -1.0:
            notes.append(f"line {no}: BA/-zeta = {BA:g}: mjtether damps each element's stretch critically (zeta 1)")
        if caax not in (0.0, ca):
            warnings.warn(f"{name}: line {no}: CaAx = {caax:g}: mjtether's added mass along the line is either Ca "
                          f"({ca:g}) or 0; taking the nearer", MoorDynWarning, stacklevel=3)
        try:
            types[f[0]] = LineType(f[0], diam, mass, EA, EI, cd, ca, cdax, caax)
        except ValueError as exc:
            raise ScenarioError(f"{name}: line {no}: {exc}") from None

    bodies = {}
    if "BODIES" in sec:
        _, body_rows = _table(name, sec, "BODIES")
        for k, (no, f) in enumerate(body_rows, 1):
            _in_turn(name, no, f[0], k, "body")
            bodies[f[0]] = _body(name, no, f, Body)
            rows[f"body{f[0]}"] = no

    points = {}
    if "RODS" in sec:  # (each a rigid body, its ends points R<n>A and R<n>B)
        for body, ends, no in _rods(name, sec, notes):
            bodies[body.name] = body
            rows[f"body{body.name}"] = no
            points.update(ends)
    depth = opt("wtrdpth", 0.0)
    for k, (no, f) in enumerate(table("POINTS"), 1):
        if len(f) < 9:
            raise ScenarioError(f"{name}: line {no}: a point needs 9 fields (ID Attachment X Y Z Mass Volume CdA Ca) "
                                f"or 12 (with Fx Fy Fz before CdA), got {len(f)}")
        _in_turn(name, no, f[0], k, "point")
        xyz = [_number(name, no, x, "X/Y/Z") for x in f[2:5]]
        mass, volume = _number(name, no, f[5], "Mass"), _number(name, no, f[6], "Volume")
        force = [0.0, 0.0, 0.0]
        if len(f) >= 12:  # (MoorDyn-C: 12 fields carry a force Fx Fy Fz before CdA and Ca)
            force = [_number(name, no, x, "Fx/Fy/Fz") for x in f[7:10]]
            cda, ca = _number(name, no, f[10], "CdA"), _number(name, no, f[11], "Ca")
        else:
            cda, ca = _number(name, no, f[7], "CdA"), _number(name, no, f[8], "Ca")
        word, num = _word(f[1])
        body = None
        if word in _FIXED:
            kind = "fixed"
        elif word in _COUPLED:
            kind = "coupled"
        elif word in _FREE:
            kind = "free"
        elif word == "BODY":
            if num not in bodies:
                raise ScenarioError(f"{name}: line {no}: point {f[0]} is on body {num or '?'}, which is not in the "
                                    "BODIES section")
            kind, body = "body", num
        else:
            raise ScenarioError(f"{name}: line {no}: point type {f[1]!r} is not one MoorDyn reads (Fixed, Anchor, Fix; "
                                "Vessel, Ves, Coupled, Cpld, Fairlead; Free, Point, Connect, Con; Body<n>)")
        if body is None and xyz[2] < -depth:
            depth = -xyz[2]  # (MoorDyn: the water is at least as deep as the lowest point)
        try:
            points[f[0]] = Point(f[0], kind, xyz, body=body, mass=mass, volume=volume, cd_area=cda, ca=ca,
                                 force=force)
        except ValueError as exc:
            raise ScenarioError(f"{name}: line {no}: {exc}") from None
        rows[f"point{f[0]}"] = no

    lines = []
    line_rows = table("LINES")
    for k, (no, f) in enumerate(line_rows, 1):
        if len(f) < 6:
            raise ScenarioError(f"{name}: line {no}: a line needs ID LineType AttachA AttachB UnstrLen NumSegs")
        _in_turn(name, no, f[0], k, "line")
        if f[1] not in types:
            raise ScenarioError(f"{name}: line {no}: line type {f[1]!r} is not in LINE TYPES ({', '.join(types)})")
        ends = []
        for end in f[2:4]:
            word, num = _word(end)
            if word in ("R", "ROD"):
                rod_end = re.fullmatch(r"(?i)r(?:od)?(\d+)([ab])", end)
                if rod_end is None or f"R{rod_end[1]}{rod_end[2].upper()}" not in points:
                    raise ScenarioError(f"{name}: line {no}: attachment {end!r} is not an end of a rod of RODS")
                if types[f[1]].EI > 0:
                    raise ScenarioError(f"{name}: line {no}: a line with bending stiffness (EI) on a rod's end, which "
                                        "MoorDyn clamps (a cantilever), is not supported by mjtether")
                ends.append(f"R{rod_end[1]}{rod_end[2].upper()}")
                continue
            if word not in ("", "C", "CON", "P", "POINT") or num not in points:
                raise ScenarioError(f"{name}: line {no}: attachment {end!r} is not a point of POINTS")
            ends.append(num)
        length, segs = _number(name, no, f[4], "UnstrLen"), _number(name, no, f[5], "NumSegs")
        if not (segs >= 1 and float(segs).is_integer()):
            raise ScenarioError(f"{name}: line {no}: NumSegs must be a whole number >= 1, got {f[5]!r}")
        try:
            lines.append(Line(f[0], f[1], ends[0], ends[1], length, int(segs)))
        except ValueError as exc:
            raise ScenarioError(f"{name}: line {no}: {exc}") from None
        rows[f"line{f[0]}"] = no
    if not lines and "RODS" not in sec:
        raise ScenarioError(f"{name}: line {sec['LINES'][0]}: the LINES section has no line")
    for pid, p in points.items():
        if p.kind == "free" and not any(pid in (ln.a, ln.b) for ln in lines):
            raise ScenarioError(f"{name}: line {rows['point' + pid]}: free point {pid} is in no line")
    if depth <= 0:
        raise ScenarioError(f"{name}: line {sec.get('OPTIONS', (1,))[0]}: WtrDpth (the water depth, m) is needed")
    counts = {"line": len(lines), "point": len(table("POINTS")), "rod": len(table("RODS")), "body": len(table("BODIES"))}
    for no, why in unknown_objects(sec.get("OUTPUTS", (0, []))[1], counts):
        warnings.warn(f"{name}: line {no}: {why}", MoorDynWarning, stacklevel=3)
    return Parsed(name, types, points, bodies, lines, rows, depth, rho, g, opt("kbot", 3.0e6), opt("cbot", 3.0e5),
                  opt("frictioncoefficient", 0.0), opt("tmaxic", 120.0), notes, current, seafloor, waves)


def _held_kind(word: str, rod: bool = False) -> str | None:
    """A body's or rod's attachment word as a ``Body`` kind (fixed, coupled, free, pinned), or
    None. MoorDyn-C pins a rod (Pinned: its end A held in place; CoupledPinned: held where the
    coupled program puts it, which a file run leaves where the file puts it) and a body
    (CoupledPinned: its reference point)."""
    if word in _PINNED or (rod and word in ("PINNED", "PIN")):
        return "pinned"
    return "fixed" if word in _FIXED else "coupled" if word in _COUPLED else "free" if word == "FREE" else None


def _rods(name, sec, notes):
    """Each rod of RODS as a rigid ``Body`` (``rod<n>``, its x axis from end A to end B, at its
    middle) with points ``R<n>A`` and ``R<n>B`` at its ends: [(body, {point name: Point}, line
    number)]. Its mass and volume are the cylinder's, its inertia a solid cylinder's, its drag
    areas Cd d L across and CdEnd pi d^2/4 along, its added mass Ca across and, along, CaEnd on
    its two end half-spheres (MoorDyn's V = 2/3 pi r^3 at each end)."""
    from mjtether.network import Body, Point
    if "ROD TYPES" not in sec:
        raise ScenarioError(f"{name}: line {sec['RODS'][0]}: rods need a ROD TYPES section")
    rod_types = {}
    for no, f in _table(name, sec, "ROD TYPES")[1]:
        if len(f) < 7:
            raise ScenarioError(f"{name}: line {no}: a rod type needs TypeName Diam Mass/m Cd Ca CdEnd CaEnd")
        rod_types[f[0]] = [_number(name, no, x, "a rod type's Diam/Mass/Cd/Ca/CdEnd/CaEnd") for x in f[1:7]]
    out = []
    for k, (no, f) in enumerate(_table(name, sec, "RODS")[1], 1):
        if len(f) < 10:
            raise ScenarioError(f"{name}: line {no}: a rod needs ID RodType Attachment Xa Ya Za Xb Yb Zb NumSegs")
        _in_turn(name, no, f[0], k, "rod")
        if f[1] not in rod_types:
            raise ScenarioError(f"{name}: line {no}: rod type {f[1]!r} is not in ROD TYPES ({', '.join(rod_types)})")
        word, _ = _word(f[1 + 1])
        kind = _held_kind(word, rod=True)
        if kind is None:
            why = "rods on a body" if word == "BODY" else f"rod type {f[2]!r}"
            raise ScenarioError(f"{name}: line {no}: {why} are not supported by mjtether (Fixed, Coupled, Free, "
                                "Pinned rods are)")
        a = [_number(name, no, x, "Xa/Ya/Za") for x in f[3:6]]
        b = [_number(name, no, x, "Xb/Yb/Zb") for x in f[6:9]]
        d, m, cd, ca, cd_end, ca_end = rod_types[f[1]]
        axis = [q - p for p, q in zip(a, b)]
        L = math.sqrt(sum(x * x for x in axis))
        if L <= 0:
            raise ScenarioError(f"{name}: line {no}: a rod of zero length (a MoorDyn point-like rod) is not supported")
        u = [x / L for x in axis]
        yaw, pitch = math.asin(max(-1.0, min(1.0, u[1]))), math.atan2(-u[2], u[0])
        mass, area = m * L, math.pi * d * d / 4
        volume = area * L
        ends_ca = ca_end * 2 * (2 / 3 * math.pi * (d / 2) ** 3) / volume
        try:
            body = Body(f"rod{f[0]}", kind, [(p + q) / 2 for p, q in zip(a, b)], rpy_deg=(0.0, math.degrees(pitch),
                                                                                           math.degrees(yaw)),
                        mass=mass, inertia=(mass * d * d / 8, mass * (L * L / 12 + d * d / 16),
                                            mass * (L * L / 12 + d * d / 16)),
                        volume=volume, cd_area=(cd_end * area, cd * d * L, cd * d * L), ca=(ends_ca, ca, ca),
                        pin=(-L / 2, 0.0, 0.0) if kind == "pinned" else (0.0, 0.0, 0.0))
            ends = {f"R{f[0]}{e}": Point(f"R{f[0]}{e}", "body", (s * L / 2, 0.0, 0.0), body=body.name)
                    for e, s in (("A", -1.0), ("B", 1.0))}
        except ValueError as exc:
            raise ScenarioError(f"{name}: line {no}: {exc}") from None
        notes.append(f"line {no}: rod {f[0]} is a rigid body (its hydrodynamics lumped at its middle, not along "
                     f"its {f[9]} segments)")
        out.append((body, ends, no))
    return out


def _body(name, no, f, Body):
    if len(f) < 14:
        raise ScenarioError(f"{name}: line {no}: a body needs 14 fields (ID Attachment X0 Y0 Z0 r0 p0 y0 Mass CG* I* "
                            f"Volume CdA* Ca*), got {len(f)}")
    word, _ = _word(f[1])
    kind = _held_kind(word)
    if kind is None:
        raise ScenarioError(f"{name}: line {no}: body type {f[1]!r} is not supported by mjtether (Fixed, Coupled, "
                            "Free, CoupledPinned)")

    def parts(text, what, counts):
        vals = [_number(name, no, x, what) for x in text.split("|")]
        if len(vals) not in counts:
            raise ScenarioError(f"{name}: line {no}: {what} takes {' or '.join(map(str, counts))} values, got {text!r}")
        return vals

    cg = parts(f[9], "CG", (1, 3))
    inertia = parts(f[10], "I", (1, 3))
    cda = parts(f[12], "CdA", (1, 2, 3, 6))
    ca = parts(f[13], "Ca", (1, 3))
    pose = [_number(name, no, x, "X0/Y0/Z0/r0/p0/y0") for x in f[2:8]]
    try:
        return Body(f[0], kind, pose[:3], rpy_deg=pose[3:], mass=_number(name, no, f[8], "Mass"),
                    cg=[0.0, 0.0, cg[0]] if len(cg) == 1 else cg, inertia=inertia * 3 if len(inertia) == 1 else inertia,
                    volume=_number(name, no, f[11], "Volume"),
                    cd_area=(cda[0],) * 3 if len(cda) <= 2 else cda[:3], ca=ca * 3 if len(ca) == 1 else ca)
    except ValueError as exc:
        raise ScenarioError(f"{name}: line {no}: {exc}") from None


def read(path=None, *, text: str | None = None, name: str | None = None, overrides=()):
    """What a MoorDyn v2 file describes: a ``Scenario`` for one line (or a chain of lines joined at
    free points) from a coupled fairlead to a fixed anchor, otherwise a ``mjtether.network.Network``
    (see the module docstring). ``overrides`` as in ``load_scenario`` (``simulation.duration=...``)."""
    if name is None:
        name = str(path) if path is not None else "<moordyn>"
    if text is None:
        from mjtether.scenario.loading import _read
        text = _read(name, path)
    p = parse(text, name)
    found = None if p.bodies or p.waves else _chain(p)  # (waves from a file's components: a network's)
    if found is None or _not_one_tether(name, p, found[0]):  # (a network holds each line as it is)
        return _network(p, overrides)
    tree = _tree(p)
    sc = load_scenario(data=tree, name=name, overrides=overrides)
    if not any(str(o).startswith("simulation.timestep=") for o in overrides):
        dt = stable_timestep(sc)
        if dt != sc.simulation.timestep:
            tree["simulation"]["timestep"] = dt
            sc = load_scenario(data=tree, name=name, overrides=overrides)
    return sc


def to_dict(text: str, name: str = "<moordyn>") -> dict:
    """The scenario tree (as TOML would hold it) of a MoorDyn v2 file that is one chain of lines
    from a coupled fairlead to a fixed anchor; ScenarioError naming a line otherwise."""
    return _tree(parse(text, name))


def _tree(p: Parsed) -> dict:
    name = p.name
    found = None if p.bodies or p.waves else _chain(p)
    if found is None:
        raise ScenarioError(f"{name}: line {p.rows['line' + p.lines[0].name]}: not one chain of lines from a "
                            "coupled fairlead to a fixed anchor" + (" without waves" if p.waves else "")
                            + ": a network (mjtether.network), not a scenario")
    chain, top, bottom = found
    sc: dict = {
        "simulation": {"duration": DEFAULT_DURATION},
        "water": {"depth": p.depth, "density": {"type": "constant", "rho": p.rho}, "gravity": p.gravity,
                  "seabed_stiffness": p.kbot, "seabed_damping": p.cbot, "bathymetry": p.seafloor},
        "tether": _tether(name, p, chain),
        "ship": {"mode": "fixed", "position": list(top.position[:2]), "fairlead_z": top.position[2]},
        "winch": {"mode": "fixed"},
        "robot": {"type": "anchor", "position": list(bottom.position)},
    }
    sc["tether"]["seabed_friction"] = p.friction
    if p.current[0]:
        sc["water"]["current"] = {"type": "table", "depths": list(p.current[0]), "speeds": list(p.current[1]),
                                  "headings_deg": list(p.current[2])}
    return sc


def _chain(p: Parsed):
    """(lines from the fairlead to the anchor as [(line, free point after it or None)], top
    point, bottom point) when the lines form one chain joined end to end at free points (each in
    exactly two lines) from one coupled point to one fixed point; otherwise None."""
    ends = {}
    for ln in p.lines:
        ends.setdefault(ln.a, []).append(ln)
        ends.setdefault(ln.b, []).append(ln)
    for pid, attached in ends.items():
        if len(attached) != (2 if p.points[pid].kind == "free" else 1):
            return None
    terminals = [pid for pid in ends if p.points[pid].kind != "free"]
    kinds = sorted(p.points[pid].kind for pid in terminals)
    if kinds != ["coupled", "fixed"]:
        return None
    top = next(pid for pid in terminals if p.points[pid].kind == "coupled")
    bottom = next(pid for pid in terminals if p.points[pid].kind == "fixed")
    if p.points[top].position[2] < p.points[bottom].position[2]:
        return None
    chain, here, came = [], top, None
    while here != bottom:
        (ln,) = [x for x in ends[here] if x is not came]
        nxt = ln.a if ln.b == here else ln.b
        chain.append((ln, nxt if nxt != bottom else None))
        here, came = nxt, ln
    if len(chain) != len(p.lines):
        return None
    return chain, p.points[top], p.points[bottom]


def _tether(name, p: Parsed, chain) -> dict:
    """The ``[tether]`` tree of a chain: one line, uniform; several, a make-up with a section per
    line and a point load at each free point that has mass, volume or drag."""
    def props(lt):
        return {"diameter": lt.diameter, "mass_per_length": lt.mass_per_length, "EA": lt.EA, "EI": lt.EI,
                "cd_normal": lt.cd_normal, "ca_normal": lt.ca_normal, "cd_tangential": lt.cd_tangential}

    if len(chain) == 1:
        ln = chain[0][0]
        lt = p.line_types[ln.type]
        return {"length": ln.length, "segments": ln.segments, **props(lt), "added_mass": lt.added_mass}
    why = _not_one_tether(name, p, chain)
    if why:
        raise ScenarioError(why)
    sections, loads, arc = [], [], 0.0
    for ln, joint in chain:
        sections.append({"length": ln.length, "segments": ln.segments, "name": ln.type,
                         **props(p.line_types[ln.type])})
        arc += ln.length
        if joint is not None:
            q = p.points[joint]
            if q.mass or q.volume or q.cd_area:
                loads.append({"arc_length": arc, "mass": q.mass, "volume": q.volume, "cd_area": q.cd_area,
                              "ca": q.ca, "name": f"point {joint}"})
    return {"sections": sections, "point_loads": loads, "added_mass": p.line_types[chain[0][0].type].added_mass}


def _not_one_tether(name, p: Parsed, chain) -> str:
    """Why a chain of lines is not one scenario tether (a line make-up), or "": its lines' CaAx
    mix 0 and Ca, or a force acts on a point where two of them join. ``read`` runs such a file
    as a network; ``to_dict`` (a scenario TOML) refuses it with this."""
    if len({p.line_types[ln.type].added_mass for ln, _ in chain}) > 1:
        return (f"{name}: line {p.rows['line' + chain[0][0].name]}: the lines' CaAx mix 0 and Ca; mjtether's added "
                "mass along a tether is one choice for all of it (tether.added_mass): a network, not a scenario")
    for _, joint in chain:
        if joint is not None and any(p.points[joint].force):
            return (f"{name}: line {p.rows['point' + joint]}: a force on a point of a line make-up is not supported: "
                    "a network, not a scenario")
    return ""


def _network(p: Parsed, overrides=()):
    """The ``Network`` of a parsed file, ``overrides`` applied (``network.config.with_overrides``).
    MoorDyn relaxes the system for up to TmaxIC before its run: mjtether settles as long (at most
    ``MAX_SETTLE``), damped, from its steady state. With TmaxIC 0 MoorDyn starts from the file's
    positions at rest, and so does mjtether (``start = "as_written"``)."""
    from mjtether.network import Network, with_overrides
    try:
        net = Network(p.name, p.line_types, p.points, tuple(p.lines), bodies=p.bodies, depth=p.depth, rho=p.rho,
                      gravity=p.gravity, seabed_stiffness=p.kbot, seabed_damping=p.cbot, seabed_friction=p.friction,
                      current_depths=p.current[0], current_speeds=p.current[1], current_headings_deg=p.current[2],
                      bathymetry=p.seafloor, wave_components=p.waves,
                      duration=DEFAULT_DURATION, settle=min(p.tmax_ic, MAX_SETTLE),
                      start="as_written" if p.tmax_ic <= 0 else "steady", notes=tuple(p.notes))
        return with_overrides(net, overrides)
    except ValueError as exc:  # (NetworkError, and the range checks' ValueError)
        raise _scenario_error(exc) from None


def _scenario_error(exc) -> ScenarioError:
    """A network's error as the CLI reports a scenario's (the key of a ``--set`` it names)."""
    msg = str(exc)
    return ScenarioError(msg, msg.partition(":")[0].removeprefix("--set ") if msg.startswith("--set ") else "")


def load_any(path, overrides=()):
    """A scenario from a TOML scenario file or a MoorDyn input file (told apart by content); a
    ``mjtether.network.Network`` from a MoorDyn file that holds one or a TOML file with
    ``[[lines]]`` (``mjtether.network.from_dict``). ``path`` may name a shipped example
    (``"default_walker"``, ``"networks/rov_cage_excursion"``)."""
    import tomllib

    from mjtether.files.packagedata import shipped_example
    from mjtether.network import NetworkError, from_dict
    from mjtether.scenario.loading import _read
    path = shipped_example(path) or path  # (a shipped example by name: "default_walker")
    name = str(path)
    text = _read(name, path)
    if not any(line.strip() and not line.lstrip().startswith("#") for line in text.splitlines()):
        raise ScenarioError(f"{name}: is empty (no MoorDyn section, no TOML key): nothing to run; give a scenario "
                            "or a MoorDyn file (with no file at all, the built-in scenario runs)")
    moordyn_name = Path(path).suffix.lower() != ".toml"
    if moordyn_name and is_moordyn(text):
        return read(text=text, name=name, overrides=overrides)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        if moordyn_name:  # (a MoorDyn file without its LINE TYPES header reads as broken TOML)
            raise ScenarioError(f"{name}: neither a MoorDyn v2 input file (no LINE TYPES or ROD TYPES section) nor "
                                f"a scenario TOML file ({exc})") from None
        data = {}  # (load_scenario says what is wrong with it)
    if "lines" in data:
        water = data.get("water")
        if isinstance(water, dict) and isinstance(water.get("bathymetry"), str) and water["bathymetry"] \
                and not Path(water["bathymetry"]).is_absolute():
            water["bathymetry"] = str(Path(path).resolve().parent / water["bathymetry"])  # (beside the file)
        try:
            return from_dict(data, name, overrides)
        except NetworkError as exc:
            raise _scenario_error(exc) from None
    return load_scenario(path, text=text, name=name, overrides=overrides)


from .moordyn_write import current_profile, current_table, write, write_network  # noqa: F401 - the writers, re-exported

"""MoorDyn v2 input files: read one into a scenario, write a scenario as one.

MoorDyn (Hall and Goupee, 2015, *Ocean Engineering*; the v2 format of its documentation,
"Input Files") describes a mooring system in sections headed by dashed lines: LINE TYPES,
POINTS, LINES, OPTIONS (and ROD TYPES, BODIES, RODS, OUTPUTS...). mjtether runs one tether
between a ship's fairlead and a robot end, so a file maps onto a scenario when it has:

* one line between two points that are ``Fixed``, ``Coupled`` or ``Vessel``: the higher one is
  the ship's fairlead (``ship.position``, ``ship.fairlead_z``), the other the anchored robot end
  (``robot.type = "anchor"``); or a chain of lines joined end to end at ``Free`` points (each in
  exactly two lines) between two such points: a line make-up, one ``[[tether.sections]]`` per
  line and a ``[[tether.point_loads]]`` (mass, volume, CdA, Ca) at each free point that has
  any (a clump weight or buoyancy module at a joint). Written back the same way (floats and
  loads off the nodes refused);
* line type columns Diam, Mass/m, EA, BA/-zeta, EI, Cd, Ca, CdAx, CaAx (+ Cl, dF, cF = 0):
  ``tether.diameter``, ``mass_per_length``, ``EA``, ``EI``, ``cd_normal``, ``ca_normal``,
  ``cd_tangential``, and CaAx = Ca or 0 as ``tether.added_mass`` "isotropic" or "normal";
* options WtrDpth, rho/rhoW, g, kBot, cBot, FrictionCoefficient, dtM: ``water.depth``,
  ``water.density.rho``, ``water.gravity``, ``water.seabed_stiffness`` and ``seabed_damping``,
  ``tether.seabed_friction`` (0 when not given, as in MoorDyn), ``simulation.timestep`` (dtM
  capped at 10 ms: mjtether
  integrates implicitly and needs no explicit-scheme step).

Refused, with the line of the file named: lines that do not form one chain (a bridle, a free
point in three lines, several anchors), bodies and rods; a BA in N s (mjtether's axial damping is a fraction of critical:
give a negative BA); VIV (Cl != 0); waves, currents and seafloor files; a static/dynamic
friction ratio other than 1 (mjtether's seabed friction is one coefficient). Approximated,
with a warning naming the line: CaAx other than Ca or 0 (mjtether's added mass along the line
is all of Ca, ``tether.added_mass = "isotropic"``, or none, ``"normal"``) and BA/-zeta (mjtether damps each element's stretch critically). Read and not needed: the
options of MoorDyn's own integrator and initial-condition solver (tScheme, CFL, dtIC, TmaxIC,
CdScaleIC, threshIC, ICgenDynamic), FricDamp (mjtether's friction sticks exactly: the
limit FricDamp -> infinity), and the output options and OUTPUTS section (mjtether's outputs
are its own).

The run's duration is not in a MoorDyn file: 60 s unless ``--set simulation.duration=...``.
"""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

from mjtether.scenario import Scenario, ScenarioError, load_scenario

DEFAULT_DURATION = 60.0
"""Simulated time (s) of a scenario read from a MoorDyn file, which does not say."""

_HEADER = re.compile(r"^\s*-{2,}\s*([A-Za-z][A-Za-z /]*?)\s*-*\s*$")
_IGNORED_OPTIONS = {"writelog", "tscheme", "cfl", "dtic", "tmaxic", "cdscaleic", "threshic", "icgendynamic",
                    "fricdamp", "cv", "dtout", "writeunits", "disableoutput", "disableouttime", "echo",
                    "outswitch", "dtwave", "wavekin_rampt", "unifycurrentgrid"}
_REFUSED_SECTIONS = ("ROD TYPES", "BODIES", "RODS", "FAILURE", "CONTROL", "EXTERNAL LOADS")


class MoorDynWarning(UserWarning):
    """A MoorDyn entry mjtether approximates (the message names the line)."""


def is_moordyn(text: str) -> bool:
    """Whether ``text`` looks like a MoorDyn input file (it has a LINE TYPES or LINE DICTIONARY section)."""
    return any((m := _HEADER.match(line)) and m.group(1).strip().upper() in ("LINE TYPES", "LINE DICTIONARY")
               for line in text.splitlines())


def _sections(name: str, text: str) -> dict[str, list[tuple[int, list[str]]]]:
    """{section title: [(line number, fields), ...]} with comments (!, #, %) removed."""
    out: dict[str, list] = {}
    current = None
    for no, raw in enumerate(text.splitlines(), 1):
        line = re.split(r"[!#%]", raw, maxsplit=1)[0].rstrip()
        m = _HEADER.match(line)
        if m:
            current = m.group(1).strip().upper()
            if current in ("LINE DICTIONARY", "NODE PROPERTIES", "LINE PROPERTIES", "SOLVER OPTIONS",
                           "POINT PROPERTIES", "CONNECTION PROPERTIES"):
                raise ScenarioError(f"{name}: line {no}: '{current}' is a MoorDyn v1 section; mjtether reads the v2 "
                                    "format (LINE TYPES, POINTS, LINES, OPTIONS)")
            out.setdefault(current, [])
            continue
        if current is None or not line.strip():
            continue
        out[current].append((no, line.split()))
    return out


def _table(name, rows, section):
    """The data rows of a table section: its first two rows are column names and units."""
    if len(rows) < 2:
        raise ScenarioError(f"{name}: the {section} section needs its column-name and unit lines")
    return rows[2:]


def _number(name, no, text, what):
    try:
        return float(text)
    except ValueError:
        raise ScenarioError(f"{name}: line {no}: {what} must be a number, got {text!r}") from None


def read(path=None, *, text: str | None = None, name: str | None = None, overrides=()) -> Scenario:
    """The scenario a MoorDyn v2 file describes (see the module docstring), checked; ``overrides``
    as in ``load_scenario`` (``simulation.duration=...``)."""
    if name is None:
        name = str(path) if path is not None else "<moordyn>"
    if text is None:
        from mjtether.scenario.loading import _read
        text = _read(name, path)
    raw = to_dict(text, name)
    return load_scenario(data=raw, name=name, overrides=overrides)


def to_dict(text: str, name: str = "<moordyn>") -> dict:
    """The scenario tree (as TOML would hold it) of a MoorDyn v2 file's text."""
    sec = _sections(name, text)
    for s in _REFUSED_SECTIONS:
        rows = sec.get(s, [])
        if len(rows) > 2:
            raise ScenarioError(f"{name}: line {rows[2][0]}: {s.lower()} are not supported by mjtether (it runs one "
                                "line between a fixed or coupled fairlead and an anchor)")
    if "LINE TYPES" not in sec:
        raise ScenarioError(f"{name}: no LINE TYPES section: not a MoorDyn v2 input file")
    for s in ("POINTS", "LINES"):
        if s not in sec:
            raise ScenarioError(f"{name}: no {s} section")

    types = {}
    for no, f in _table(name, sec["LINE TYPES"], "LINE TYPES"):
        if len(f) < 10:
            raise ScenarioError(f"{name}: line {no}: a line type needs TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx "
                                f"CaAx, got {len(f)} columns")
        if "|" in f[3] or "|" in f[4]:
            raise ScenarioError(f"{name}: line {no}: viscoelastic EA or BA ('|') is not supported")
        v = [_number(name, no, x, col) for x, col in zip(f[1:10], ("Diam", "Mass/m", "EA", "BA/-zeta", "EI", "Cd",
                                                                    "Ca", "CdAx", "CaAx"))]
        extra = [_number(name, no, x, "Cl/dF/cF") for x in f[10:13]]
        if extra and extra[0] != 0.0:
            raise ScenarioError(f"{name}: line {no}: VIV (Cl = {extra[0]:g}) is not supported")
        diam, mass, EA, BA, EI, cd, ca, cdax, caax = v
        if BA > 0:
            raise ScenarioError(f"{name}: line {no}: BA = {BA:g} N s: mjtether damps each element's stretch as a "
                                "fraction of critical; give a negative BA (-zeta)")
        if BA < 0 and BA != -1.0:
            warnings.warn(f"{name}: line {no}: BA/-zeta = {BA:g}: mjtether damps each element's stretch critically "
                          "(zeta = 1)", MoorDynWarning, stacklevel=3)
        # the added mass along the line: CaAx = Ca is mjtether's isotropic added mass, CaAx = 0 its
        # "normal" one; anything else is the nearer of the two
        added_mass = "normal" if caax < 0.5 * ca else "isotropic"
        if caax not in (0.0, ca):
            warnings.warn(f"{name}: line {no}: CaAx = {caax:g}: mjtether's added mass along the line is either Ca "
                          f"({ca:g}) or 0; taking {'0' if added_mass == 'normal' else 'Ca'} (tether.added_mass = "
                          f"\"{added_mass}\")", MoorDynWarning, stacklevel=3)
        types[f[0]] = {"diameter": diam, "mass_per_length": mass, "EA": EA, "EI": EI, "cd_normal": cd,
                       "ca_normal": ca, "cd_tangential": cdax, "added_mass": added_mass}

    points = {}
    for no, f in _table(name, sec["POINTS"], "POINTS"):
        if len(f) < 8:
            raise ScenarioError(f"{name}: line {no}: a point needs ID Attachment X Y Z Mass Volume CdA Ca")
        kind = f[1].lower()
        if kind == "connect":  # (MoorDyn's older word for a free point)
            kind = "free"
        if kind not in ("fixed", "coupled", "vessel", "free"):
            raise ScenarioError(f"{name}: line {no}: point {f[0]} is {f[1]!r}: mjtether supports Fixed, Coupled "
                                "(Vessel) and Free points; body points are not supported")
        xyz = [_number(name, no, x, "X/Y/Z") for x in f[2:5]]
        load = [_number(name, no, x, "Mass/Volume/CdA/Ca") for x in f[5:9]]
        points[f[0]] = (no, kind, xyz, load)

    chain, top, bottom = _chain(name, _table(name, sec["LINES"], "LINES"), types, points)
    options = {}
    for ono, fo in sec.get("OPTIONS", []):
        if len(fo) < 2:
            raise ScenarioError(f"{name}: line {ono}: an option is a value then its name")
        options[fo[1].lower()] = (ono, fo[0])

    def opt(key, default=None):
        if key not in options:
            return default
        ono, val = options.pop(key)
        return _number(name, ono, val, key)

    depth = opt("wtrdpth")
    if depth is None or depth <= 0:
        raise ScenarioError(f"{name}: OPTIONS: WtrDpth (the water depth, m) is required and must be > 0")
    rho = opt("rho", opt("rhow", 1025.0))
    sc: dict = {
        "simulation": {"duration": DEFAULT_DURATION},
        "water": {"depth": depth, "density": {"type": "constant", "rho": rho}, "gravity": opt("g", 9.81)},
        "tether": _tether(name, chain, types, points),
        "ship": {"mode": "fixed", "position": top[2][:2], "fairlead_z": top[2][2]},
        "winch": {"mode": "fixed"},
        "robot": {"type": "anchor", "position": bottom[2]},
    }
    kb, cb = opt("kbot"), opt("cbot")
    if kb is not None:
        sc["water"]["seabed_stiffness"] = kb
        sc["water"]["seabed_damping"] = 3.0e5 if cb is None else cb
    mu = opt("frictioncoefficient", opt("mu_kt"))
    sc["tether"]["seabed_friction"] = 0.0 if mu is None else mu  # (MoorDyn's default: no friction)
    mu_ka = opt("mu_ka")
    if mu_ka is not None and mu is not None and mu_ka != mu:
        raise ScenarioError(f"{name}: line {options.get('mu_ka', (no,))[0]}: axial friction MU_KA differs from "
                            "transverse: mjtether's seabed friction is one coefficient")
    for key in ("statdynfricscale", "mc"):
        val = opt(key)
        if val is not None and val != 1.0:
            raise ScenarioError(f"{name}: {key}: static and kinetic friction differ ({val:g}); mjtether's seabed "
                                "friction is one coefficient")
    dtm = opt("dtm")
    if dtm is not None:
        sc["simulation"]["timestep"] = min(max(dtm, 1e-5), 0.01)
    for key in ("wavekin", "currents"):
        val = opt(key)
        if val:
            raise ScenarioError(f"{name}: line {options.get(key, (0,))[0]}: {key} = {val:g}: waves and current "
                                "grids are not supported (give the current in the scenario instead)")
    for key, (ono, val) in options.items():
        if key == "seafloorfile":
            raise ScenarioError(f"{name}: line {ono}: SeafloorFile: bathymetry files are not supported")
        if key not in _IGNORED_OPTIONS:
            raise ScenarioError(f"{name}: line {ono}: option {key!r} is not supported by mjtether")
    return sc


def _chain(name, lines, types, points):
    """The lines of the file as one chain from the fairlead to the anchor: ([(line number, line
    type, unstretched length, segments, the free point after it or None), ...], top point,
    bottom point). Lines join end to end at Free points, each in exactly two lines; the chain's
    ends are the two points that are not Free, the higher one the fairlead."""
    if not lines:
        raise ScenarioError(f"{name}: the LINES section has no line")
    ends = {}  # point id -> [(line number, other end, type, length, segments)]
    for no, f in lines:
        if len(f) < 6:
            raise ScenarioError(f"{name}: line {no}: a line needs ID LineType AttachA AttachB UnstrLen NumSegs")
        if f[1] not in types:
            raise ScenarioError(f"{name}: line {no}: line type {f[1]!r} is not in LINE TYPES ({', '.join(types)})")
        for end in f[2:4]:
            if end not in points:
                raise ScenarioError(f"{name}: line {no}: attachment {end!r} is not a point of POINTS (rod ends are "
                                    "not supported)")
        if f[2] == f[3]:
            raise ScenarioError(f"{name}: line {no}: both ends on point {f[2]}")
        length, segments = _number(name, no, f[4], "UnstrLen"), _number(name, no, f[5], "NumSegs")
        for a, b in ((f[2], f[3]), (f[3], f[2])):
            ends.setdefault(a, []).append((no, b, f[1], length, segments))
    for pid, attached in ends.items():
        pno, kind = points[pid][0], points[pid][1]
        want = 2 if kind == "free" else 1
        if len(attached) != want:
            raise ScenarioError(f"{name}: line {pno}: point {pid} ({kind}) has {len(attached)} lines attached; "
                                f"mjtether runs one tether, a chain of lines joined end to end at free points "
                                f"(each in exactly two lines), between two fixed or coupled points")
    terminals = [pid for pid in ends if points[pid][1] != "free"]
    if len(terminals) != 2:
        raise ScenarioError(f"{name}: the lines do not form one chain between two fixed or coupled points "
                            f"(they have {len(terminals)} such ends)")
    top, bottom = sorted(terminals, key=lambda pid: -points[pid][2][2])
    chain, here, came = [], top, None
    while here != bottom:
        (no, nxt, ltype, length, segments), = [e for e in ends[here] if e[0] != came]
        chain.append((no, ltype, length, segments, nxt if nxt != bottom else None))
        here, came = nxt, no
    if len(chain) != len(lines):
        raise ScenarioError(f"{name}: line {lines[0][0]}: the lines form more than one piece (a closed loop of free "
                            "points?)")
    return chain, points[top], points[bottom]


def _tether(name, chain, types, points) -> dict:
    """The ``[tether]`` tree of a chain: one line, uniform; several, a make-up with a section per
    line and a point load at each free point that has mass, volume or drag."""
    def segs(no, x):
        if not (x >= 1 and float(x).is_integer()):
            raise ScenarioError(f"{name}: line {no}: NumSegs must be a whole number >= 1, got {x:g}")
        return int(x)

    if len(chain) == 1:
        no, ltype, length, segments, _ = chain[0]
        return {"length": length, "segments": segs(no, segments), **types[ltype]}
    modes = {types[c[1]]["added_mass"] for c in chain}
    if len(modes) > 1:
        raise ScenarioError(f"{name}: line {chain[0][0]}: the lines' CaAx mix 0 and Ca; mjtether's added mass along "
                            "the tether is one choice for all of it (tether.added_mass)")
    sections, loads, arc = [], [], 0.0
    for no, ltype, length, segments, joint in chain:
        props = {k: v for k, v in types[ltype].items() if k != "added_mass"}
        sections.append({"length": length, "segments": segs(no, segments), "name": ltype, **props})
        arc += length
        if joint is not None:
            mass, volume, cda, ca = points[joint][3]
            if mass or volume or cda:
                loads.append({"arc_length": arc, "mass": mass, "volume": volume, "cd_area": cda, "ca": ca,
                              "name": f"point {joint}"})
    return {"sections": sections, "point_loads": loads, "added_mass": modes.pop()}


def write(sc: Scenario) -> str:
    """A MoorDyn v2 input file of a scenario (one line from the anchored robot end to a coupled
    fairlead); ScenarioError naming the key for what MoorDyn cannot express."""
    t, w, r, s = sc.tether, sc.water, sc.robot, sc.ship

    def refuse(key, why):
        raise ScenarioError(f"{key}: {why}: not expressible in a MoorDyn file", key)

    if r.type != "anchor":
        refuse("robot.type", f"{r.type!r} (only an anchored end is)")
    if t.EA == 0.0 and not t.sections:
        refuse("tether.EA", "0 (inextensible; MoorDyn needs a stiffness)")
    if w.density.type != "constant":
        refuse("water.density.type", repr(w.density.type))
    c = w.current
    if c.type != "constant" or c.speed != 0.0:
        refuse("water.current", "a current (MoorDyn takes currents from grid files)")
    if w.seabed_slope_deg != 0.0:
        refuse("water.seabed_slope_deg", "a sloped seabed (MoorDyn takes bathymetry from a file)")
    if s.mode != "fixed" or s.heave_amplitude != 0.0:
        refuse("ship.mode", "a moving ship (MoorDyn's coupled points move with the coupled program)")
    if sc.winch.mode != "fixed":
        refuse("winch.mode", repr(sc.winch.mode))
    if t.is_makeup:
        return _write_makeup(sc, refuse)
    mass = t.mass_per_length if t.mass_per_length > 0 else t.density * math.pi * t.diameter ** 2 / 4
    x0, y0 = s.position
    lines = [
        "--------------------- MoorDyn Input File ------------------------------------",
        "written by mjtether from a scenario",
        "---------------------- LINE TYPES ---------------------------------------------",
        "TypeName   Diam    Mass/m    EA    BA/-zeta    EI    Cd    Ca    CdAx    CaAx",
        "(name)     (m)     (kg/m)    (N)   (N-s/-)    (N-m^2) (-)   (-)   (-)     (-)",
        f"tether {t.diameter!r} {mass!r} {t.EA!r} -1 {t.EI!r} {t.cd_normal!r} {t.ca_normal!r} {t.cd_tangential!r} "
        f"{t.ca_normal if t.added_mass == 'isotropic' else 0.0!r}",
        "---------------------- POINTS -------------------------------------------------",
        "ID   Attachment  X    Y    Z    Mass   Volume  CdA   Ca",
        "(#)  (word)      (m)  (m)  (m)  (kg)   (m^3)   (m^2) (-)",
        f"1 Fixed {r.position[0]!r} {r.position[1]!r} {r.position[2]!r} 0 0 0 0",
        f"2 Coupled {x0!r} {y0!r} {s.fairlead_z!r} 0 0 0 0",
        "---------------------- LINES --------------------------------------------------",
        "ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs",
        "(#) (name)    (#)      (#)      (m)       (-)      (-)",
        f"1 tether 1 2 {t.length!r} {t.segments} -",
        "---------------------- OPTIONS ------------------------------------------------",
        f"{sc.simulation.timestep!r} dtM",
        f"{w.gravity!r} g",
        f"{w.density.rho!r} rho",
        f"{w.depth!r} WtrDpth",
        f"{t.seabed_friction!r} FrictionCoefficient",
    ]
    if w.seabed_stiffness > 0:
        lines += [f"{w.seabed_stiffness!r} kBot", f"{w.seabed_damping!r} cBot"]
    return "\n".join(lines + _tail(1)) + "\n"


def _tail(n_lines: int) -> list[str]:
    return ["---------------------- OUTPUTS ------------------------------------------------",
            "FAIRTEN1", f"ANCHTEN{n_lines}",
            "------------------------- need this line --------------------------------------"]


def _write_makeup(sc: Scenario, refuse) -> str:
    """``write`` for a line make-up: a line per section (cut also where a point load sits, which
    must be on a node), joined at free points that carry the point loads; floats refused."""
    t, w, r, s = sc.tether, sc.water, sc.robot, sc.ship
    if t.floats:
        refuse("tether.floats", "float sections (MoorDyn has no distributed buoyancy on a line)")
    from mjtether.scenario.runner import makeup_from
    mk = makeup_from(sc)
    if any(sec.EA is None for sec in mk.sections):
        refuse("tether.sections", "an inextensible section (EA 0; MoorDyn needs a stiffness)")
    nodes = mk.node_arc_length
    cuts = {0.0, mk.length, *(float(b) for b in mk.section_bounds)}
    for i, p in enumerate(t.point_loads):
        k = int(abs(nodes - p.arc_length).argmin())
        if abs(nodes[k] - p.arc_length) > 1e-9 * mk.length:
            refuse(f"tether.point_loads[{i}].arc_length", f"{p.arc_length:g} m, between nodes (a MoorDyn free point "
                   "joins two lines at a node; put the load on a node or a section joint)")
        if 0 < k < len(nodes) - 1:
            cuts.add(float(nodes[k]))
    cuts = sorted(cuts)
    types, rows = {}, []
    for a, b in zip(cuts[:-1], cuts[1:]):
        j = min(int(mk.section_bounds.searchsorted(a + 1e-9 * mk.length, side="right")) - 1, len(mk.sections) - 1)
        sec = mk.sections[j]  # the section this piece is cut from
        key = (sec.diameter, sec.mass_per_length, sec.EA, sec.EI, sec.cd_normal, sec.ca_normal, sec.cd_tangential)
        name = types.setdefault(key, f"type{len(types) + 1}")
        rows.append((name, b - a, int(round((b - a) / sec.segment_length))))
    caax = lambda ca: ca if t.added_mass == "isotropic" else 0.0  # noqa: E731
    x0, y0 = s.position
    lines = [
        "--------------------- MoorDyn Input File ------------------------------------",
        "written by mjtether from a scenario (a line make-up)",
        "---------------------- LINE TYPES ---------------------------------------------",
        "TypeName   Diam    Mass/m    EA    BA/-zeta    EI    Cd    Ca    CdAx    CaAx",
        "(name)     (m)     (kg/m)    (N)   (N-s/-)    (N-m^2) (-)   (-)   (-)     (-)",
        *(f"{name} {d!r} {m!r} {ea!r} -1 {ei!r} {cd!r} {ca!r} {cdax!r} {caax(ca)!r}"
          for (d, m, ea, ei, cd, ca, cdax), name in types.items()),
        "---------------------- POINTS -------------------------------------------------",
        "ID   Attachment  X    Y    Z    Mass   Volume  CdA   Ca",
        "(#)  (word)      (m)  (m)  (m)  (kg)   (m^3)   (m^2) (-)",
        f"1 Coupled {x0!r} {y0!r} {s.fairlead_z!r} 0 0 0 0",
    ]
    # free points on the straight chord, where MoorDyn's initial-condition solver starts them
    top, bot = [x0, y0, s.fairlead_z], list(r.position)
    for i, c in enumerate(cuts[1:-1]):
        f = c / mk.length
        at = [p.arc_length == c or abs(p.arc_length - c) <= 1e-9 * mk.length for p in t.point_loads]
        mass = sum(p.mass for p, a in zip(t.point_loads, at) if a)
        vol = sum(p.volume for p, a in zip(t.point_loads, at) if a)
        cda = sum(p.cd_area for p, a in zip(t.point_loads, at) if a)
        ca = sum(p.ca * p.volume for p, a in zip(t.point_loads, at) if a) / vol if vol > 0 else 0.0
        xyz = " ".join(repr(top[k] + f * (bot[k] - top[k])) for k in range(3))
        lines.append(f"{i + 2} Free {xyz} {mass!r} {vol!r} {cda!r} {ca!r}")
    anchor = len(cuts)
    lines += [f"{anchor} Fixed {bot[0]!r} {bot[1]!r} {bot[2]!r} 0 0 0 0",
              "---------------------- LINES --------------------------------------------------",
              "ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs",
              "(#) (name)    (#)      (#)      (m)       (-)      (-)"]
    lines += [f"{i + 1} {name} {i + 1} {i + 2} {length!r} {n} -" for i, (name, length, n) in enumerate(rows)]
    lines += ["---------------------- OPTIONS ------------------------------------------------",
              f"{sc.simulation.timestep!r} dtM", f"{w.gravity!r} g", f"{w.density.rho!r} rho", f"{w.depth!r} WtrDpth",
              f"{t.seabed_friction!r} FrictionCoefficient"]
    if w.seabed_stiffness > 0:
        lines += [f"{w.seabed_stiffness!r} kBot", f"{w.seabed_damping!r} cBot"]
    return "\n".join(lines + _tail(len(rows))) + "\n"


def load_any(path, overrides=()) -> Scenario:
    """A scenario from a TOML scenario file or a MoorDyn input file (told apart by content)."""
    from mjtether.scenario.loading import _read
    name = str(path)
    text = _read(name, path)
    if Path(path).suffix.lower() != ".toml" and is_moordyn(text):
        return read(text=text, name=name, overrides=overrides)
    return load_scenario(text=text, name=name, overrides=overrides)

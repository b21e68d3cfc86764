"""Writing MoorDyn v2 input files: a scenario (one line, or a line make-up as lines joined at
free points) and a network of lines (``mjtether.network``), read back by ``mjtether.io.moordyn``
and run by MoorDyn-C (``tests/io/test_moordyn.py``, ``tests/io/test_moordyn_files.py``)."""

from __future__ import annotations

import math
from pathlib import Path

from mjtether.scenario import Scenario, ScenarioError


def write(sc: Scenario) -> str:
    """A MoorDyn v2 input file of a scenario (one line from the anchored robot end to a coupled
    fairlead); ScenarioError naming the key for what MoorDyn cannot express."""
    t, w, r, s = sc.tether, sc.water, sc.robot, sc.ship
    refuse = _refuse

    if r.type != "anchor":
        refuse("robot.type", f"{r.type!r} (only an anchored end is)")
    if t.EA == 0.0 and not t.sections:
        refuse("tether.EA", "0 (inextensible; MoorDyn needs a stiffness)")
    if t.drag_law != "morison":
        refuse("tether.drag_law", f"{t.drag_law!r} (MoorDyn's drag is Morison's)")
    if w.density.type != "constant":
        refuse("water.density.type", repr(w.density.type))
    c = w.current
    if c.type != "constant" or c.speed != 0.0:
        refuse("water.current", "a current (MoorDyn takes currents from grid files)")
    if w.seabed_slope_deg != 0.0:
        refuse("water.seabed_slope_deg", "a sloped seabed (MoorDyn takes bathymetry from a file)")
    floor = _seafloor_option(w.bathymetry, refuse)
    if s.mode != "fixed" or s.heave_amplitude != 0.0:
        refuse("ship.mode", "a moving ship (MoorDyn's coupled points move with the coupled program)")
    if sc.winch.mode != "fixed":
        refuse("winch.mode", repr(sc.winch.mode))
    if not sc.waves.flat:
        refuse("waves.type", f"{sc.waves.type!r} (MoorDyn reads waves from side files, WaveKin 2 or 7; not written)")
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
        _dtm_option([(mass, t.EA, t.length / t.segments, t.diameter)], *_seabed_of(w)),
        f"{w.gravity!r} g",
        f"{w.density.rho!r} rho",
        f"{w.depth!r} WtrDpth",
        f"{t.seabed_friction!r} FrictionCoefficient",
        *floor,
    ]
    if w.seabed_stiffness > 0:
        lines += [f"{w.seabed_stiffness!r} kBot", f"{w.seabed_damping!r} cBot"]
    return "\n".join(lines + _tail(1)) + "\n"


def _refuse(key, why):
    raise ScenarioError(f"{key}: {why}: not expressible in a MoorDyn file", key)


def _seafloor_option(path: str, refuse) -> list:
    """The option line naming a bathymetry that is MoorDyn's own 3-D seafloor file (its absolute
    path); a depth grid is refused (MoorDyn reads only its own format)."""
    from mjtether.physics import bathymetry
    if not path:
        return []
    if not bathymetry.is_moordyn_seafloor(path) or any(c.isspace() for c in str(path)):
        refuse("water.bathymetry", "a depth grid, or a path with spaces (MoorDyn reads its own 3-D seafloor "
               "format, named without spaces)")
    return [f"{Path(path).resolve()} SeafloorFile"]


def write_network(net) -> str:
    """A MoorDyn v2 input file of a ``mjtether.network.Network``: points, bodies and lines numbered
    in their order (the names in comments), g written exactly; a current (``current_table``) is
    ``1 Currents``, whose profile ``current_profile(net)`` must be written beside the file as
    ``CURRENT_FILE``. Vehicles, walkers, winches and pinned bodies are refused (ScenarioError
    naming the section and the parts)."""
    if net.timestep is not None and net.timestep <= 0:
        raise ScenarioError("simulation.timestep: must be > 0", "simulation.timestep")
    if net.vehicles:
        _refuse("vehicles", f"vehicles flown by an autopilot ({', '.join(net.vehicles)})")
    if net.walkers:
        _refuse("walkers", f"seabed walkers ({', '.join(net.walkers)}: a MoorDyn file has no walker)")
    if net.wave_field() is not None:
        _refuse("waves", "waves (MoorDyn reads them from side files, WaveKin 2 or 7; not written)")
    paying = [ln.name for ln in net.lines if ln.payout_speed > 0]
    if paying:
        _refuse("lines", f"lines paying out from a winch ({', '.join(paying)}: MoorDyn's coupled program does that)")
    pid = {name: i for i, name in enumerate(net.points, 1)}
    bid = {name: i for i, name in enumerate(net.bodies, 1)}
    out = ["--------------------- MoorDyn Input File ------------------------------------",
           f"written by mjtether from the network {net.name} (points: "
           + ", ".join(f"{i} = {n}" for n, i in pid.items()) + ")",
           "---------------------- LINE TYPES ---------------------------------------------",
           "TypeName   Diam    Mass/m    EA    BA/-zeta    EI    Cd    Ca    CdAx    CaAx",
           "(name)     (m)     (kg/m)    (N)   (N-s/-)    (N-m^2) (-)   (-)   (-)     (-)"]
    out += [f"{lt.name} {lt.diameter!r} {lt.mass_per_length!r} {lt.EA!r} -1 {lt.EI!r} {lt.cd_normal!r} "
            f"{lt.ca_normal!r} {lt.cd_tangential!r} {lt.ca_normal if lt.added_mass == 'isotropic' else 0.0!r}"
            for lt in net.line_types.values()]
    if net.bodies:
        out += ["---------------------- BODIES -------------------------------------------------",
                "ID Attachment X0 Y0 Z0 r0 p0 y0 Mass CG* I* Volume CdA* Ca*",
                "(#) (-) (m) (m) (m) (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)"]
        for name, b in net.bodies.items():
            if b.kind == "pinned":
                _refuse("bodies", f"body {name!r} is pinned (a pinned rod, say): a MoorDyn body is pinned only "
                                  "where a coupled program moves it (CoupledPinned)")
            out.append(f"{bid[name]} {b.kind.capitalize()} {' '.join(repr(float(x)) for x in b.position)} "
                       f"{' '.join(repr(float(x)) for x in b.rpy_deg)} {b.mass!r} {_bars(b.cg)} {_bars(b.inertia)} "
                       f"{b.volume!r} {_bars(b.cd_area)} {_bars(b.ca)}")
    out += ["---------------------- POINTS -------------------------------------------------",
            "ID   Attachment  X    Y    Z    Mass   Volume  Fx Fy Fz CdA   Ca",
            "(#)  (word)      (m)  (m)  (m)  (kg)   (m^3)   (N) (N) (N) (m^2) (-)"]
    for name, p in net.points.items():
        word = f"Body{bid[p.body]}" if p.kind == "body" else p.kind.capitalize()
        out.append(f"{pid[name]} {word} {' '.join(repr(float(x)) for x in p.position)} {p.mass!r} {p.volume!r} "
                   f"{' '.join(repr(float(x)) for x in p.force)} {p.cd_area!r} {p.ca!r}")
    out += ["---------------------- LINES --------------------------------------------------",
            "ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs",
            "(#) (name)    (#)      (#)      (m)       (-)      (-)"]
    out += [f"{i} {ln.type} {pid[ln.a]} {pid[ln.b]} {ln.length!r} {ln.segments} -" for i, ln in enumerate(net.lines, 1)]
    out += ["---------------------- OPTIONS ------------------------------------------------",
            f"{net.gravity!r} g", f"{net.rho!r} rho", f"{net.depth!r} WtrDpth", f"{net.seabed_stiffness!r} kBot",
            f"{net.seabed_damping!r} cBot", f"{net.seabed_friction!r} FrictionCoefficient",
            f"{max(net.settle, 1.0)!r} TmaxIC", *(["1 Currents"] if current_table(net) else []),
            *_seafloor_option(net.bathymetry, _refuse),
            _dtm_option([(lt.mass_per_length, lt.EA, ln.length / ln.segments, lt.diameter)
                         for ln, lt in ((ln, net.line_types[ln.type]) for ln in net.lines)],
                        net.seabed_stiffness, net.seabed_damping),
            "------------------------- need this line --------------------------------------"]
    return "\n".join(out) + "\n"


def _bars(values) -> str:
    """A MoorDyn per-axis entry: values joined by '|' (``1.0|2.0|3.0``)."""
    return "|".join(repr(float(x)) for x in values)


CURRENT_TOLERANCE = 0.01
"""How closely ``current_table`` holds a ``[water.current]`` profile: MoorDyn (and mjtether's
reader) interpolate the rows linearly in depth, and the interpolated velocity is within this
fraction of the profile's local speed (plus ``CURRENT_FLOOR``) at every depth but the last
``CURRENT_FINEST`` above a seabed where the profile's slope is infinite (the power law's)."""
CURRENT_FLOOR = 1e-6
"""The least error (m/s) ``current_table`` is held to: a speed that small is still water."""
CURRENT_FINEST = 1e-3
"""The band (m) on the seabed that ``current_table`` leaves whole: the power law u ~ s^a at height
s above the seabed has no linear interpolant near s = 0 (between 0 and s it is off by up to 62 %
of u(s) for a = 1/7, however small s is), so its last row but one is 1 mm or less above the
seabed, and only there is the table off (a line resting on the seabed has its nodes at it, where
both are 0, or a radius above it, in MuJoCo)."""


def current_table(net) -> tuple:
    """The network's current as MoorDyn's steady profile: (depths m below the surface, increasing;
    speeds m/s; headings deg from +x towards +y), or () for still water. The ``current_depths``
    table as it is; a ``[water.current]`` (``net.current``, the profile ``network.run.water_of``
    makes of it) tabulated from the surface to ``net.depth``: rows at its kinks (a linear
    profile's ``bottom_depth``, a table's depths), each interval halved until linear
    interpolation of (ux, uy) is within ``CURRENT_TOLERANCE`` of the profile at 7 points inside
    it (or it is the ``CURRENT_FINEST`` band on the seabed). Rows: a constant current 2, a
    linear one 3, a table its own (within the depth) and the surface's and seabed's; curved
    profiles as many as their curvature asks, 17 to 71 for these (measured): the 1/7 power law 18
    over 60 m, 24 over 3000 m (a row at each halving of the height above the seabed down to 1 mm:
    a geometric step of 2 holds s^(1/7) to 0.73 %); the exponential one about one row per quarter
    decay depth (linear interpolation's error over a step h is h^2 / 8 L^2 of the local speed: 0.8 %)
    until it is a few 1e-5 of its surface speed, 17 rows for L = 15 m over 60 m."""
    if net.current is None:
        if not net.current_depths:
            return ()
        return tuple(tuple(float(x) for x in col)
                     for col in (net.current_depths, net.current_speeds, net.current_headings_deg))
    import numpy as np

    from mjtether.network.run import water_of

    u, c, depth = water_of(net).current, net.current, float(net.depth)
    kinks = {0.0, depth}
    if c.type == "linear":
        kinks.add(min(c.bottom_depth, depth))
    if c.type == "table":
        kinks.update(min(float(d), depth) for d in c.depths)
    if not np.any(u.speed_at(-np.array([*kinks, *np.linspace(0.0, depth, 201)])) > 0.0):
        return ()
    vel = lambda d: u(-np.asarray(d, float))[..., :2]  # noqa: E731 - (ux, uy) at depths d
    inside = np.arange(1, 8) / 8.0
    rows, todo = set(kinks), sorted(kinks)
    todo = list(zip(todo[:-1], todo[1:]))
    while todo:
        a, b = todo.pop()
        d = a + (b - a) * inside
        ua, ub, true = vel(a), vel(b), vel(d)
        err = np.linalg.norm(ua + (ub - ua) * inside[:, None] - true, axis=-1)
        bad = np.any(err > CURRENT_TOLERANCE * np.linalg.norm(true, axis=-1) + CURRENT_FLOOR)
        last = b == depth and b - a <= CURRENT_FINEST  # (the seabed's band, where a power law's slope is infinite)
        if bad and not last and b - a > 1e-9 * depth:
            m = 0.5 * (a + b)
            rows.add(m)
            todo += [(a, m), (m, b)]
    depths = np.array(sorted(rows))
    v = vel(depths)
    return (tuple(depths.tolist()), tuple(np.hypot(v[:, 0], v[:, 1]).tolist()),
            tuple(np.degrees(np.arctan2(v[:, 1], v[:, 0])).tolist()))


def current_profile(net) -> str:
    """MoorDyn's ``CURRENT_FILE`` of a network's current (``current_table``; for
    ``write_network``'s ``1 Currents``)."""
    rows = ["--------------------- MoorDyn steady currents File ----------------------------------",
            f"written by mjtether from the network {net.name}", "z (m), ux (m/s), uy (m/s), uz (m/s)"]
    for d, u, h in sorted(zip(*current_table(net)), reverse=True):
        # (z increasing, from the deepest row up: MoorDyn interpolates on an ascending grid)
        rows.append(f"{-d!r} {u * math.cos(math.radians(h))!r} {u * math.sin(math.radians(h))!r} 0.0")
    return "\n".join(rows) + "\n"


MOORDYN_CFL = 0.1
"""The fraction of a period that the written ``dtM`` steps (MoorDyn's CFL number, as its own files
set it): of each segment's axial period, 2 pi sqrt(m l / (EA / l)) (MoorDyn-C's measure,
``Util/CFL.hpp``), and of the seabed contact's, 2 pi / sqrt(kBot d / m) per metre of line."""
MOORDYN_MAX_DTM = 1e-3
"""The longest ``dtM`` written (s)."""


def moordyn_dtm(pieces, kbot: float, cbot: float) -> float:
    """A step (s) at which MoorDyn-C's explicit integrator runs lines of ``pieces`` [(mass per
    metre kg/m, EA N, segment length m, diameter m)] on a seabed of ``kbot`` (Pa/m) and ``cbot``
    (Pa s/m): MOORDYN_CFL of the shortest axial and seabed-contact period, no more than the
    contact's damping allows explicitly (cBot d dt / m <= 1), and at most MOORDYN_MAX_DTM. mjtether's
    own step is not MoorDyn's: at 0.0417 s, which MuJoCo takes on MoorDyn's chain files, MoorDyn-C
    diverges."""
    dt = MOORDYN_MAX_DTM
    for m, EA, seg, d in pieces:
        dt = min(dt, MOORDYN_CFL * 2 * math.pi * math.sqrt(m * seg * seg / EA))
        if kbot > 0:
            dt = min(dt, MOORDYN_CFL * 2 * math.pi / math.sqrt(kbot * d / m))
        if cbot > 0:
            dt = min(dt, m / (cbot * d))
    return dt


def _dtm_option(pieces, kbot, cbot) -> str:
    return f"{moordyn_dtm(pieces, kbot, cbot):.6g} dtM"


def _seabed_of(w) -> tuple[float, float]:
    """The kBot and cBot MoorDyn-C runs a scenario's file with (its defaults where none is written)."""
    return (w.seabed_stiffness, w.seabed_damping) if w.seabed_stiffness > 0 else (3.0e6, 3.0e5)


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
              _dtm_option([(sec.mass_per_length, sec.EA, sec.segment_length, sec.diameter) for sec in mk.sections],
                          *_seabed_of(w)),
              f"{w.gravity!r} g", f"{w.density.rho!r} rho", f"{w.depth!r} WtrDpth",
              f"{t.seabed_friction!r} FrictionCoefficient", *_seafloor_option(w.bathymetry, refuse)]
    if w.seabed_stiffness > 0:
        lines += [f"{w.seabed_stiffness!r} kBot", f"{w.seabed_damping!r} cBot"]
    return "\n".join(lines + _tail(len(rows))) + "\n"

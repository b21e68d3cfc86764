"""How a scenario run starts: the walker's standing pose, the tether's quasi-static steady state
(or, where there is none and the scenario allows it, a guessed shape that settles with the
robot held), and the pre-roll that loads the seabed contacts before t = 0.

Units SI, world frame (z up, surface z = 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import mujoco
import numpy as np

from mjtether.cable.makeup import LineMakeup
from mjtether.cable.tether import MAX_REACH_STRAIN
from mjtether.physics import water as wm
from mjtether.quasistatic import initial_state, steady_state
from mjtether.simulation import Simulation
from mjtether.walker import Tripod

from .config import ConfigError
from .controllers import CONTROL_HZ
from .scene import Scene, place_walker, seabed_spec
from .sections import MAX_START_STRAIN

PREROLL_S = 1.0
"""Seconds simulated before t = 0 with the ship and winch still (see ``preroll``)."""
STAND_S = 1.0
"""Seconds the walker stands alone on the seabed to find its resting pose before the run is
built. Placed at its standing height (``scene.WALKER_STAND_HEIGHT``), it lands at once and has
settled by 1 s: from then on its torso only bobs with the tripod's stepping, 6 mm peak to
peak, about a mean that moves by 0.2 mm (measured; ``test_starts``). Placed 0.9 m too high, as
it was, it sank for 1.2 s, still bounced at 2 s, and the pre-roll then lowered its tow point
6.5 cm below the one the steady start was solved to."""
SETTLE_S = 10.0
"""Seconds a ``start = "settle"`` run lets the cable fall into place with the robot held (and a
steady start on a level seabed onto a sloped or gridded one, ``floats_over_seabed``)."""
MAX_SETTLE_S = 40.0
"""Longest a steady start on a level seabed settles onto a sloped or gridded one (``preroll``)."""
STILL = 0.01
"""Fastest a node may move (m/s) for a cable settling onto the seabed to count as settled."""
REFINE_START = (1, 2, 3, 4)
"""Element counts, in multiples of the tether's, that the steady start is solved with in turn
until Newton converges (``_solve_start``): where the touchdown sits in a coarse element the
shot map is too rugged for Newton, and which refinement gets past that varies from case to
case (in 100 TetherWinch-v0 resets: 92 converge as given, 7 with 2N, 1 with 3N, which also fails
with 2N and 4N)."""
FALLBACK_SUBSTEPS = 4
"""Pre-roll sub-steps per time step when the run starts from a guessed shape."""


@dataclass(frozen=True)
class Stand:
    """The walker's resting pose after STAND_S on the seabed (``stand_walker``): its joints'
    {(body, index in body): (qpos, qvel)}, its actuators' controls {name: ctrl}, the gait's
    phase, and the torso's position (m), rotation matrix (3, 3) and the tow point (m) in the
    world, where it stood over the seabed point ``origin`` (m)."""

    pose: dict
    ctrl: dict
    phase: float
    position: np.ndarray
    rotation: np.ndarray
    tow_point: np.ndarray
    origin: np.ndarray


_TORSO = ("walker/torso", 0)
"""The torso's free joint in a stand's pose: (body, index in body)."""
_STANDS: dict = {}
"""Stands already made, by ``_stand_key``."""
_STANDS_KEPT = 16


def stand_walker(scene: Scene, gait_run: Tripod, dt: float):
    """Let the walker stand (stepping in place) on the seabed for STAND_S, alone with its
    hydrodynamics in still water, then put it at its commanded position and heading; returns
    ({joint: (qpos, qvel)}, {actuator: control}, tow point (m, world)) of that pose, and
    leaves ``gait_run`` (the run's gait) at the phase it stood in.

    The stand is the walker's own pose on that seabed: the ship, the tether and the current
    (which the pre-roll brings in, ``preroll``) play no part in it. On a flat seabed the walker
    stands at the origin facing +x and is moved and turned into place, so the stand is made
    once for every run on the same seabed (an environment's resets, a sweep) and kept; on a
    slope it stands where it starts, facing its heading."""
    flat = scene.slope == 0.0 and scene.grid is None
    key = _stand_key(scene, gait_run.period, dt, flat)
    stand = _STANDS.get(key) if key is not None else None
    if stand is None:
        if flat:
            stand = _stand(scene, gait_run.period, dt, np.array([0.0, 0.0, float(scene.seabed_z(0.0, 0.0))]), 0.0)
        else:
            x, y = scene.sc.robot.start
            stand = _stand(scene, gait_run.period, dt, np.array([x, y, float(scene.seabed_z(x, y))]), scene.heading)
        if key is not None:
            while len(_STANDS) >= _STANDS_KEPT:
                _STANDS.pop(next(iter(_STANDS)))
            _STANDS[key] = stand
    gait_run.phase = stand.phase  # the run goes on stepping from where it stood
    return _put_back(stand, scene)


def _stand_key(scene: Scene, period: float, dt: float, flat: bool):
    """What a stand depends on (see ``stand_walker``): the seabed (depth, friction, slope), the
    water's density and gravity, the gait's period and the time step; on a slope, also where
    the walker starts and its heading. None where that cannot be told (a density profile that
    cannot be hashed)."""
    w = scene.water
    key = (w.depth, w.density, w.gravity, scene.sc.water.seabed_friction, scene.slope, scene.slope_heading, period,
           dt, STAND_S, CONTROL_HZ, scene.sc.water.bathymetry)
    if not flat:
        x, y = scene.sc.robot.start
        key += (float(x), float(y), scene.heading)
    try:
        hash(key)
    except TypeError:
        return None
    return key


def _stand(scene: Scene, period: float, dt: float, origin: np.ndarray, heading: float) -> Stand:
    """The walker alone over ``origin`` (m, world, on the scene's seabed), facing ``heading``
    (rad), stepping in place for STAND_S in still water."""
    still = wm.WaterColumn(depth=scene.water.depth, density=scene.water.density, gravity=scene.water.gravity)
    spec = seabed_spec(still, dt, scene.sc.water.seabed_friction, scene.slope, scene.slope_heading, point=origin)
    hydro = place_walker(spec, origin, heading)
    with Simulation(spec, still, bodies=[hydro]) as sim:
        m, d = sim.model, sim.data
        gait = Tripod(period=period).bind(m, prefix="walker/")
        every = max(1, int(round(1.0 / (CONTROL_HZ * dt))))
        for _ in range(max(1, int(round(STAND_S / (every * dt))))):
            d.ctrl[gait.actuators] = gait.targets(every * dt, 0.0, 0.0)
            sim.step(every)
        sim.forward()  # (the positions of the last step's end)
        pose = {}
        torso = m.body("walker/torso")
        for j in range(m.njnt):  # every joint of the walker's bodies, by (body, index in body)
            body = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(m.jnt_bodyid[j])) or ""
            if body.startswith("walker/"):
                adr, dof = m.jnt_qposadr[j], m.jnt_dofadr[j]
                nq, nv = {0: (7, 6), 1: (4, 3), 2: (1, 1), 3: (1, 1)}[int(m.jnt_type[j])]
                pose[(body, j - int(m.body_jntadr[m.jnt_bodyid[j]]))] = (d.qpos[adr:adr + nq].copy(),
                                                                        d.qvel[dof:dof + nv].copy())
        ctrl = {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_ACTUATOR, a): float(d.ctrl[a]) for a in range(m.nu)}
        return Stand(pose=pose, ctrl=ctrl, phase=gait.phase,
                     position=d.xpos[torso.id].copy(), rotation=d.xmat[torso.id].reshape(3, 3).copy(),
                     tow_point=d.site_xpos[m.site("walker/tow_point").id].copy(), origin=np.array(origin, dtype=float))


def _put_back(stand: Stand, scene: Scene):
    """``stand_walker``'s answer: the stand moved to the commanded position and turned about
    the seabed's normal to the commanded heading (it may also have turned or slid a little
    while its feet found the seabed), its torso at rest."""
    tilt = scene.tilt
    normal = np.zeros(9)
    mujoco.mju_quat2Mat(normal, tilt)
    n = normal[[2, 5, 8]]
    R = stand.rotation
    fwd = R[:, 0] - (R[:, 0] @ n) * n  # the body's forward axis in the seabed's plane
    want = np.array([math.cos(scene.heading), math.sin(scene.heading), 0.0])
    want = want - (want @ n) * n
    turn = math.atan2(np.cross(fwd, want) @ n, fwd @ want)
    q_turn = np.zeros(4)
    mujoco.mju_axisAngle2Quat(q_turn, n, turn)
    R_turn = np.zeros(9)
    mujoco.mju_quat2Mat(R_turn, q_turn)
    R_turn = R_turn.reshape(3, 3)
    pose = {k: (q.copy(), v.copy()) for k, (q, v) in stand.pose.items()}
    q_torso, v_torso = pose[_TORSO]
    x, y = scene.sc.robot.start
    start = np.array([x, y, float(scene.seabed_z(x, y))])
    p = start + ((stand.position - stand.origin) @ n) * n  # same height over the seabed, at the commanded place
    q = np.zeros(4)
    mujoco.mju_mulQuat(q, q_turn, q_torso[3:7])
    q_torso[:3], q_torso[3:7] = p, q / np.linalg.norm(q)
    v_torso[:] = 0.0
    tow = p + R_turn @ (stand.tow_point - stand.position)
    return pose, dict(stand.ctrl), tow


def steady_start(scene: Scene, top, robot, dt: float):
    """The quasi-static steady state to start from (with the tow point on the seabed the
    seabed is taken one cable radius lower, where the cable's axis lies), or ``None`` and
    why, if there is none; the run then stops, or starts from ``fallback_nodes`` and
    settles where the scenario asks for it (``simulation.start``). An elastic tether shorter than
    the span from the fairlead to the tow point by more than ``MAX_REACH_STRAIN`` is refused
    (``ConfigError`` naming tether.length): it would start stretched to reach, at EA times the strain."""
    radius = scene.contact_diameter / 2
    # the cable's axis rests one radius above the seabed; a walker's tow point is higher: the
    # steady state is solved to the point on the seabed under it, for the length less that
    # height, and the cable then rises straight up to the tow point (on a sloped seabed: a
    # flat one at the depth under the tow point, kept if the line it gives stays clear of
    # the slope)
    depth = -scene.seabed_z(robot[0], robot[1]) - radius
    rise = max(robot[2] + depth, 0.0) if scene.walker else 0.0
    foot = np.array([robot[0], robot[1], robot[2] - rise])
    water = wm.WaterColumn(depth=depth, density=scene.water.density,
                           current=scene.water.current, gravity=scene.water.gravity)
    L = scene.line.length
    reach = float(np.linalg.norm(robot - top))
    if not np.isfinite(line_of(scene).element_EA).any() and reach >= L:
        return None, (f"tether.length = {L:g} m: too short for its ends: the ship's fairlead and the robot's tow "
                      f"point are {reach:.2f} m apart and the tether is inextensible (tether.EA = 0); give "
                      f"tether.length > {reach:.2f} m or tether.EA > 0, or move the robot or the ship closer")
    if reach > L * (1.0 + MAX_REACH_STRAIN):  # (the sections' check allows the tow point's offset; this is the point)
        raise ConfigError(f"tether.length = {L:g} m: too short for its ends: the ship's fairlead and the robot's tow "
                          f"point are {reach:.2f} m apart in a straight line (the span), and the tether would start "
                          f"stretched by {100 * (reach / L - 1):.2g} % to reach it (at most {100 * MAX_REACH_STRAIN:g} "
                          f"%); give tether.length >= {reach / (1 + MAX_REACH_STRAIN):.2f} m (the minimum), or move "
                          "the robot or the ship closer", "tether.length")
    if rise >= 0.5 * L:
        return None, f"no steady state (the tow point is {rise:.2f} m above the seabed, the tether {L:g} m long)"
    if scene.walker and robot[2] < -depth - 1e-9:
        t = scene.sc.tether
        return None, (f"tether.diameter = {t.diameter:g} m: a cable resting on the seabed has its axis {radius:g} m up, "
                      f"above the walker's tow point ({robot[2] + depth + radius:.2f} m up); a walker tows a tether "
                      f"of diameter below {2 * (robot[2] + depth + radius):.2f} m")
    ss, note = _solve_start(scene, water, top, foot, dt, length=L - rise)
    if ss is None:
        return None, _explained(scene, note, robot, L, reach)
    if rise > 0:  # the nodes' material points on the solved line, then up to the tow point
        s_solved = arc_lengths(scene, L - rise)
        pts = np.vstack([ss.nodes, robot])
        s_pts = np.r_[s_solved, L]
        s_new = arc_lengths(scene, L)
        nodes = np.c_[[np.interp(s_new, s_pts, pts[:, k]) for k in range(3)]].T
        # the tow point holds the piece rising to it: the force at the foot plus its wet weight
        hang = np.array([0.0, 0.0, -rise_weight_per_length(scene, robot[2]) * rise])
        ss = replace(ss, nodes=nodes, velocity=np.zeros_like(nodes), tension=np.interp(
            0.5 * (s_new[1:] + s_new[:-1]), 0.5 * (s_solved[1:] + s_solved[:-1]), ss.tension),
            bottom_force=ss.bottom_force + hang)
    x = ss.nodes
    EA = line_of(scene).element_EA  # (inf: inextensible)
    strain = np.nan_to_num(ss.tension / EA, nan=0.0)
    if strain.max() > MAX_START_STRAIN:
        j = int(np.argmax(strain))
        return None, _too_heavy_note(scene, 100 * strain[j], ss.tension[j])
    below = float(np.max(scene.seabed_z(x[:, 0], x[:, 1]) + radius - x[:, 2]))
    if below > 2 * radius:
        return None, f"no steady state clear of the sloped seabed (it crosses it by {below:.2f} m)"
    return ss, note


def line_of(scene: Scene) -> LineMakeup:
    """The scenario's line as a make-up: its own, or the uniform tether's one section."""
    return LineMakeup.of(scene.line)


def cut_line(scene: Scene, length: float) -> LineMakeup:
    """The top ``length`` m of the scenario's line (all of it, or less its rise to a walker's
    tow point), as the steady start solves it: a uniform line keeps its N elements, shortened;
    a make-up keeps its element lengths (``LineMakeup.truncated``: its joints and loads stay on
    nodes)."""
    line = line_of(scene)
    if line.is_uniform:
        return LineMakeup.uniform(replace(line.tether, length=length))
    return line.truncated(length)


def rise_weight_per_length(scene: Scene, z: float) -> float:
    """Wet weight per metre (N/m, positive if it sinks) of the cable at the robot's end, in the water
    at depth ``z`` (m, world): a uniform tether's, or a make-up's last element's (its floats and point
    loads left out)."""
    line = line_of(scene)
    mu, area = float(line.element_mass_per_length[-1]), float(line.element_area[-1])
    rho = float(np.asarray(scene.water.rho(z)).ravel()[0])
    return (mu - rho * area) * scene.water.gravity


def _explained(scene: Scene, note: str, robot, length: float, reach: float) -> str:
    """``note`` (why no steady start was found) with what in the scenario makes it so, where that
    is clear: a buoyant tether (the steady start does not model a cable floating at the
    surface), or an end above the seabed with more cable than reaches it (the excess would lie on
    the seabed between the ends)."""
    t = scene.sc.tether
    if not t.is_makeup:  # (the keys of a uniform [tether])
        mass, wet, rho = _wet_weight(scene)
        if wet < 0.0:
            return (f"{note}: {mass} and tether.diameter = {t.diameter:g} m make the tether {-wet:.3g} N/m buoyant "
                    f"in water ({rho:g} kg/m^3), and its steady start does not model a cable floating up to and "
                    f"along the surface; give a tether heavier than the water it displaces, or "
                    f"simulation.start = \"settle\"")
    if "between its two ends" in note:
        above = float(robot[2] - scene.seabed_z(robot[0], robot[1]))
        return (f"{note}: robot.position is {above:.2f} m above the seabed and tether.length = {length:g} m is "
                f"{length - reach:.2f} m more than the {reach:.2f} m between the ship's fairlead and it; put the "
                f"robot on the seabed, shorten the tether, or give simulation.start = \"settle\"")
    return note


def _wet_weight(scene: Scene) -> tuple[str, float, float]:
    """The uniform tether's weight in water at the surface: (the key that gives its mass, as
    ``tether.density = ...`` or ``tether.mass_per_length = ...``; its wet weight, N/m, positive
    if it sinks; the water's density there, kg/m^3)."""
    t, spec = scene.sc.tether, scene.tether_spec
    rho = float(np.asarray(scene.water.rho(0.0)).ravel()[0])
    mass = (f"tether.mass_per_length = {t.mass_per_length:g} kg/m" if t.mass_per_length > 0
            else f"tether.density = {t.density:g} kg/m^3")
    return mass, (spec.mu - rho * spec.area) * scene.water.gravity, rho


def _too_heavy_note(scene: Scene, stretch_pct: float, tension: float) -> str:
    """Why a steady state is out of the tether's strength, naming the keys that make it so: the
    weight (or buoyancy) per metre from ``tether.mass_per_length`` / ``tether.density`` and
    ``tether.diameter``, against ``tether.EA`` (and ``tether.rated_load`` where the tension is
    above it)."""
    t = scene.sc.tether
    if t.is_makeup:
        return (f"no steady state within the tether's strength (it would be stretched by {stretch_pct:.0f} %, at "
                f"{tension:.3g} N: the sections' EA cannot hold their weight)")
    mass, wet, _ = _wet_weight(scene)
    why = (f"{mass} and tether.diameter = {t.diameter:g} m make it {abs(wet):.3g} N/m "
           f"{'heavy' if wet >= 0 else 'buoyant'} in water, and tether.EA = {t.EA:g} N would stretch by "
           f"{stretch_pct:.0f} % at the {tension:.3g} N that holds it (at most {100 * MAX_START_STRAIN:.0f} %)")
    if tension > t.rated_load:
        why += f"; tether.rated_load = {t.rated_load:g} N is exceeded too"
    return f"no steady state within the tether's strength: {why}; give a lighter or thinner tether or a larger EA"


def floats_over_seabed(scene: Scene, nodes: np.ndarray) -> bool:
    """Whether a steady state of ``steady_start`` (solved on a level seabed at the depth under
    the tow point) lies off the scene's seabed where that is not level (a slope, a bathymetry
    grid): a node of its laid part (those within a cable radius of its lowest) more than a
    cable diameter above the seabed under it. Such a start settles onto the seabed first
    (``preroll``), the robot held."""
    if scene.slope == 0.0 and scene.grid is None:
        return False
    radius = scene.contact_diameter / 2
    laid = nodes[nodes[:, 2] <= nodes[:, 2].min() + radius]
    gap = laid[:, 2] - radius / math.cos(scene.slope) - scene.seabed_z(laid[:, 0], laid[:, 1])
    return bool(gap.max() > 2 * radius)


def _solve_start(scene: Scene, water, top, robot, dt, length=None):
    """``quasistatic.initial_state`` for the scenario's tether, with retries: the laid part's tension
    has a kink where seabed friction takes it all, and a coarse tether's touchdown jumps
    from element to element; either can stall Newton. So: as given; with 2N, 3N, then 4N
    elements (``REFINE_START``), keeping every 2nd, 3rd or 4th node (the same material
    points); then all without friction (the run then starts with the friction the laid cable's
    geometry needs, up to mu w: see ``BoundTether.preload_friction``).
    Returns (state, note) or (None, why)."""
    cb = scene.sc.tether.seabed_friction
    line = line_of(scene) if length is None else cut_line(scene, length)
    if not line.is_uniform:
        return _solve_makeup_start(scene, water, top, robot, line)
    spec = line.tether
    sim = scene.sc.simulation
    layout = dict(layout=sim.laid_layout, layout_angle=math.radians(sim.laid_layout_angle_deg))
    if scene.walker:  # slack cable lies back along the walker's track
        layout["layout_direction"] = (-math.cos(scene.heading), -math.sin(scene.heading))
    tries = []
    for friction in (cb, 0.0) if cb > 0 else (cb,):
        for k in REFINE_START:
            how = f" solved with {k * spec.segments} elements" if k > 1 else ""
            tries.append((k, friction, how + (" without seabed friction" if friction != cb else "")))
    first = None
    for k, friction, how in tries:
        try:
            ss = initial_state(replace(spec, segments=k * spec.segments), water, top, robot, timestep=dt,
                               seabed=True, seabed_friction=friction, **layout)
        except RuntimeError as exc:  # Newton stalled: try the next way
            first = first or exc
            continue
        except ValueError as exc:  # no steady state exists
            return None, f"no steady state ({exc})"
        if k > 1:
            ss = replace(ss, nodes=ss.nodes[::k].copy(), velocity=ss.velocity[::k].copy(),
                         tension=ss.tension.reshape(-1, k).mean(axis=1), jacobian=None)
        return ss, "quasi-static steady state" + (f"{how} (as given: {first})" if how else "")
    return None, f"no steady state (the solver did not converge: {first})"


def _solve_makeup_start(scene: Scene, water, top, robot, line: LineMakeup):
    """``_solve_start`` for a line make-up ``line`` (the scene's, cut to the length solved): its
    steady state (``steady_state`` with each section's EA; a slack laid make-up is not solved),
    with seabed friction, then without."""
    cb = scene.sc.tether.seabed_friction
    first = None
    for friction, how in ((cb, ""), (0.0, " without seabed friction")) if cb > 0 else ((0.0, ""),):
        try:
            ss = steady_state(line, water, top, robot, seabed=True, seabed_friction=friction)
        except RuntimeError as exc:  # Newton stalled (NotImplementedError: a slack make-up)
            if isinstance(exc, NotImplementedError):
                return None, f"no steady state ({exc})"
            first = first or exc
            continue
        except ValueError as exc:
            return None, f"no steady state ({exc})"
        return ss, "quasi-static steady state of the line make-up" + (f"{how} (as given: {first})" if how else "")
    return None, f"no steady state (the solver did not converge: {first})"


def arc_lengths(scene: Scene, length: float) -> np.ndarray:
    """Unstretched arc lengths (m, from the ship) of the nodes of the tether cut to ``length``
    m (the whole of it, or less its rise to a walker's tow point): those of ``cut_line``."""
    return cut_line(scene, length).node_arc_length


def fallback_nodes(scene: Scene, top, robot) -> np.ndarray:
    """A start that stays above the seabed when there is no steady state: the cable hangs
    straight down from the ship to the seabed, then runs along it to the tow point, with any
    excess length laid as a sideways detour (a slack tether coils on the bottom). A cable too
    short for that path (a tow point high above the seabed: a vehicle, an anchor in mid-water)
    hangs as a V from the ship to the tow point instead, as deep as its length allows."""
    L = scene.line.length
    lift = scene.contact_diameter / 2 / math.cos(scene.slope)  # the cable's axis over the seabed

    def on_floor(p):
        return np.array([p[0], p[1], float(scene.seabed_z(p[0], p[1])) + lift])

    a = on_floor(top)
    b = on_floor(robot)
    run = np.array([b[0] - a[0], b[1] - a[1], 0.0])
    span = float(np.linalg.norm(b - a))
    excess = L - (top[2] - a[2]) - span - (robot[2] - b[2])
    side = np.array([-run[1], run[0], 0.0]) / max(np.linalg.norm(run), 1e-9) if span > 1e-9 \
        else np.array([0.0, 1.0, 0.0])
    detour = [on_floor(a + side * excess / 2), on_floor(b + side * excess / 2)] if excess > 0 else []
    pts = np.array([top, a, *detour, b, robot])
    if excess < 0:  # a V whose two legs are L long together, its low point under the chord's middle
        mid = 0.5 * (np.asarray(top, float) + np.asarray(robot, float))

        def v_length(h):
            low = mid - (0.0, 0.0, h)
            return float(np.linalg.norm(top - low) + np.linalg.norm(robot - low))

        h_lo, h_hi = 0.0, max(L, 1e-9)
        for _ in range(60):  # bisection: the V's length grows with its depth
            h = 0.5 * (h_lo + h_hi)
            h_lo, h_hi = (h, h_hi) if v_length(h) < L else (h_lo, h)
        low = mid - (0.0, 0.0, h_lo)
        low[2] = max(low[2], float(on_floor(low)[2]))
        pts = np.array([top, low, robot])
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    s = np.r_[0.0, np.cumsum(seg)]
    u = arc_lengths(scene, L) * (s[-1] / L)
    return np.c_[[np.interp(u, s, pts[:, k]) for k in range(3)]].T


def check_at_fairlead(top, tow_point, position, tol: float = 0.01) -> None:
    """With nothing deployed (``winch.start_empty``) the vehicle's tow point must start at the
    fairlead ``top`` (m, world), within ``tol`` (m); else a ConfigError that gives the
    ``robot.position`` that puts it there."""
    gap = np.asarray(top, dtype=float) - np.asarray(tow_point, dtype=float)
    if float(np.linalg.norm(gap)) > tol:
        fix = [round(float(v), 4) for v in np.asarray(position, dtype=float) + gap]
        raise ConfigError(f"robot.position = {list(position)}: with winch.start_empty = true the vehicle's tow point "
                          f"must start at the fairlead {[round(float(v), 4) for v in top]} (it is "
                          f"{float(np.linalg.norm(gap)):.3g} m away): robot.position = {fix}", "robot.position")


def preroll(run, settle: bool, until_still: bool = False, substeps: int = 1) -> None:
    """Put the walker in its standing pose, then pre-roll ``run`` (a ``runner.ScenarioRun``):
    soft contacts carry the laid cable's (and the walker's) weight only once they are pressed
    in; PREROLL_S of standing still lets them load, then t is reset to 0. A settling start
    settles for SETTLE_S, the walker held (a vehicle flying its first setpoint), then PREROLL_S
    released; ``until_still``: and on, SETTLE_S / 2 at a time, until no node moves faster than
    STILL (up to MAX_SETTLE_S). ``substeps``: steps per time step, all through (a start from a
    guessed shape, far from equilibrium, takes FALLBACK_SUBSTEPS; a steady state falling onto
    a sloped or gridded seabed takes the run's own step). The ship and the winch do not move
    (a vessel carrying the winch holds its station on its autopilot)."""
    sim = run.sim
    m, dt = sim.model, sim.model.opt.timestep
    gait = run.gait_drive
    if gait is not None:
        d = sim.data
        for (body, k), (q, v) in run.stand_pose.items():
            j = m.body_jntadr[m.body(body).id] + k
            d.qpos[m.jnt_qposadr[j]:m.jnt_qposadr[j] + len(q)] = q
            d.qvel[m.jnt_dofadr[j]:m.jnt_dofadr[j] + len(v)] = v
        for name, u in run.stand_ctrl.items():  # (the walker's: a vessel's thrusters are the pilot's)
            d.ctrl[m.actuator(name).id] = u
        sim.forward()
    sub = int(substeps)
    m.opt.timestep = dt / sub
    try:
        if settle:  # (a vehicle flies its first setpoint meanwhile: it is not held in place)
            settled = 0.0
            while settled < SETTLE_S or (until_still and settled < MAX_SETTLE_S and float(
                    np.abs(run.bt.layout.v(run.bt.first)).max()) > STILL):
                for _ in range(max(1, int(round(SETTLE_S / 2 / dt))) * sub):
                    if gait is not None:
                        gait.drive(dt / sub, 0.0, 0.0)
                    for pilot in (run.pilot, run.ship_pilot):
                        if pilot is not None:
                            pilot.update(run, 0.0, dt / sub)
                    sim.step()
                settled += SETTLE_S / 2
            if gait is not None:
                sim.data.eq_active[m.equality("walker/hold").id] = 0
        for _ in range(max(1, int(round(PREROLL_S / dt))) * sub):
            if gait is not None:
                gait.drive(dt / sub, 0.0, 0.0)
            for pilot in (run.pilot, run.ship_pilot):  # a vehicle holds its first setpoint, a vessel its station
                if pilot is not None:
                    pilot.update(run, 0.0, dt / sub)
            sim.step()
    finally:
        m.opt.timestep = dt
    sim.data.time = 0.0
    sim.forward()

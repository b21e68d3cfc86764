"""``mjtether solve``: the quasi-static answer for a scenario's or a network's initial state,
printed with what it holds (the tow point's share, the Khan et al. 2023 method's answer)."""

from __future__ import annotations

import sys

from . import _load


def solve(args) -> int:
    """``mjtether solve [SCENARIO]``: the quasi-static answer for a scenario's or a network's initial
    state, printed (0), or why there is none (1; 2 for a scenario that does not load)."""
    import numpy as np

    from mjtether.network import Network
    from mjtether.scenario.runner import ScenarioRun

    sc = _load(args.scenario, args.set, network=True)
    if sc is None:
        return 2
    if isinstance(sc, Network):
        return _solve_network(sc)
    from mjtether.scenario.runner import RunFailed
    try:
        r = ScenarioRun(sc)
    except ValueError as exc:
        print(f"mjtether solve: {exc}", file=sys.stderr)
        return 2
    except RunFailed as exc:
        print(f"mjtether solve: {_no_steady_state(exc.reason) if exc.reason else exc}", file=sys.stderr)
        return 1
    try:
        ss = r.initial if r.initial is not None else r.steady_state  # (solved, even where the run settles)
        if not r.tethered:
            print("no tether (tether.attached = false): nothing to solve; the vehicle runs alone, starting level "
                  "and at rest")
            return 0
        if sc.winch.start_empty:
            print("nothing deployed at the start (winch.start_empty): the vehicle starts at the fairlead with no "
                  "cable out; its steady state is the empty one")
            return 0
        if ss is None:
            print(f"mjtether solve: {_no_steady_state(r.steady_note)}", file=sys.stderr)
            return 1
        np.set_printoptions(precision=1, suppress=True)
        print(f"steady state of {r.tether_spec.length:g} m of tether ({r.tether_spec.segments} elements):")
        print(f"  force on the ship     {ss.top_force} N  (tension {ss.top_tension:.1f} N)")
        print(f"  force on the tow point {ss.bottom_force} N  (tension {ss.tow_tension:.1f} N)")
        print(f"  lowest point z = {ss.nodes[:, 2].min():.2f} m; on the seabed: {ss.laid_length:.1f} m")
        _print_tow_note(r, ss)
        _print_khan(r)
    finally:
        r.close()
    return 0


def _solve_network(net) -> int:
    """``mjtether solve`` of a network of lines: each line's end forces at the steady state, the
    free points' positions and what the statics hold instead of balancing (``network.solve``)."""
    import numpy as np

    from mjtether.network.solve import solve

    try:
        sol = solve(net)
    except (ValueError, RuntimeError) as exc:
        print(f"mjtether solve: {exc}", file=sys.stderr)
        return 1
    print(f"steady state of {len(net.lines)} line(s): {sol.note}")
    width = max([4] + [len(n) for n in sol.lines])
    print(f"  {'line':{width}s}  {'end A':>10s} {'tension N':>11s} {'horiz. N':>10s}   {'end B':>10s} "
          f"{'tension N':>11s} {'horiz. N':>10s}  shape")
    for ln in net.lines:
        e = sol.lines[ln.name]
        ha, hb = float(np.hypot(*e.force_a[:2])), float(np.hypot(*e.force_b[:2]))
        shape = "catenary" if e.catenary else "straight bar (half its wet weight at each end)"
        print(f"  {ln.name:{width}s}  {ln.a:>10.10s} {e.tension_a:11.1f} {ha:10.1f}   {ln.b:>10.10s} "
              f"{e.tension_b:11.1f} {hb:10.1f}  {shape}")
    free = [n for n, p in net.points.items() if p.kind == "free"]
    for name in free:
        x, y, z = sol.positions[name]
        print(f"  point {name}: ({x:.2f}, {y:.2f}, {z:.2f}) m")
    for name, pose in sorted(getattr(sol, "poses", {}).items()):
        (x, y, z), (roll, pitch, yaw) = pose.position, pose.rpy_deg
        print(f"  body {name}: ({x:.2f}, {y:.2f}, {z:.2f}) m, roll/pitch/yaw ({roll:.2f}, {pitch:.2f}, {yaw:.2f}) deg")
    for sentence in sol.unbalanced:
        print(f"  (not balanced by the statics: {sentence})")
    if not sol.balanced:
        print(f"mjtether solve: {sol.note}", file=sys.stderr)
        return 1
    return 0


def _no_steady_state(note: str) -> str:
    return note if note.startswith("no steady state") else f"no steady state: {note}"


def _print_tow_note(r, ss) -> None:
    """What the steady tow tension is, and why a run's and Khan et al.'s differ from it: the tow point
    holds the cable rising to it from the seabed; the tension at the touchdown is held by seabed
    friction on the laid cable (taken fully mobilised, as a run starts: ``preload_friction``), less
    of it, or none, reaching the tow point; a walking walker drags its laid cable."""
    import numpy as np

    from mjtether.scenario.start import rise_weight_per_length

    if ss.laid_length <= 0.0:
        return
    x, y, z = (float(v) for v in r.robot_position)
    w = rise_weight_per_length(r.scene, z)
    rise = max(z - float(r.seabed_z(x, y)) - r.scene.contact_diameter / 2, 0.0)
    cb, laid = r.sc.tether.seabed_friction, ss.laid_length
    end = float(np.hypot(*ss.bottom_force[:2]))  # (the rising piece adds weight only)
    touchdown = cb * w * (laid - ss.slack_length) + end
    rising = f"the {rise:.2f} m of cable rising to it from the seabed ({w * rise:.1f} N in water) and " \
        if rise > 0.01 else ""
    if cb > 0.0:
        held = (f"{end:.1f} N of the {touchdown:.1f} N the line carries at the touchdown, the rest held by seabed "
                f"friction on the {laid:.1f} m laid (up to tether.seabed_friction x {w:.2f} N/m x {laid:.1f} m = "
                f"{cb * w * laid:.0f} N, taken as fully mobilised, as a run starts)")
    else:
        held = f"all {touchdown:.1f} N the line carries at the touchdown (a frictionless seabed holds none of it)"
    print(f"  (at rest the tow point holds {rising}{held})")
    if r.walker and cb > 0.0 and float(r.gait_drive.commands[0, 1]) > 0.0:
        print(f"  (a run's tow tension is larger once the walker walks: it drags the {laid:.1f} m laid behind it over "
              f"the seabed against sliding friction, about {cb * w * laid:.0f} N and more as more is laid, and the "
              "gait jerks it)")


def _print_khan(r) -> None:
    """The Khan et al. (2023) method for the walker's first commanded speed: the length that
    reaches its depth, both readings of the paper's Eqs. 22-23 (see quasistatic.khan2023)."""
    from mjtether.quasistatic import khan2023

    if not r.walker:
        kind = {"anchor": "an anchor", "vehicle": "a vehicle"}.get(r.sc.robot.type, repr(r.sc.robot.type))
        print("  (the Khan et al. 2023 method applies to a walker moving at constant speed; "
              f"this scenario's robot is {kind})")
        return
    speed = float(r.gait_drive.commands[0, 1])
    if speed <= 0.0:
        print("  (the Khan et al. 2023 method applies to a walker moving away from the ship; "
              f"the first command is {speed:g} m/s)")
        return
    t = r.tether_spec
    depth = -float(r.robot_position[2])
    print(f"Khan et al. (2023) method, walker at {speed:g} m/s, tow point at {depth:.1f} m depth (2-D, "
          "head-on current, no seabed contact):")
    for variant in ("printed", "consistent"):
        try:
            k = khan2023(diameter=t.diameter, cable_density=t.mu / t.area, water=r.water, robot_speed=speed,
                         depth=depth, segments=t.segments, cd_normal=t.cd_normal, cd_axial=t.cd_tangential,
                         gravity=r.water.gravity, variant=variant)
        except (ValueError, RuntimeError) as exc:
            print(f"  {variant:10s} no answer: {exc}")
            continue
        print(f"  {variant:10s} length to reach it {k.length:.1f} m, range {k.range:.1f} m, "
              f"tow tension {k.tow_tension:.1f} N")
    print(f"  (Khan et al.'s method ignores the seabed: all of its cable hangs in the current from the ship to the "
          f"tow point, whose tension is that cable's weight and drag; its length is the one that just reaches the "
          f"walker, not tether.length = {t.length:g} m, part of which lies on the seabed here)")

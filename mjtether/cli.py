"""Command line: ``mjtether run``, ``mjtether solve``, ``mjtether demo``."""

from __future__ import annotations

import argparse
import sys

from pathlib import Path

from . import demo
from .units import knots


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="mjtether", description="Underwater tether simulation in MuJoCo")
    sub = ap.add_subparsers(dest="command", required=True)
    demo_cmd = sub.add_parser("demo", help="a tether hanging from the surface in a current; prints end tensions")
    demo_cmd.add_argument("--length", type=float, default=200.0, help="tether length (m), default 200")
    demo_cmd.add_argument("--segments", type=int, default=50, help="number of elements, default 50")
    demo_cmd.add_argument("--current-knots", type=float, default=3.0, help="surface current (kn), default 3")
    demo_cmd.add_argument("--duration", type=float, default=120.0, help="simulated time (s), default 120")
    run_cmd = sub.add_parser("run", help="run a scenario file and write its results folder")
    run_cmd.add_argument("scenario", nargs="?", help="scenario TOML file (default: the built-in scenario)")
    run_cmd.add_argument("--out", default="results", help="results folder (default: ./results)")
    run_cmd.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    solve_cmd = sub.add_parser("solve", help="print the quasi-static answer for a scenario's initial state")
    solve_cmd.add_argument("scenario", nargs="?", help="scenario TOML file (default: the built-in scenario)")
    args = ap.parse_args(argv)
    if args.command == "run":
        return _run(args)
    if args.command == "solve":
        return _solve(args)
    if args.command == "demo":
        try:
            res = demo.main(duration=args.duration, length=args.length, segments=args.segments,
                            current=knots(args.current_knots))
        except ValueError as exc:
            print(f"mjtether demo: {exc}", file=sys.stderr)
            return 2
        print(f"after {res['time']:.0f} s: ship-end tension {res['ship_tension']:.1f} N, "
              f"weight-end tension {res['weight_tension']:.1f} N")
    return 0


def _load(path):
    from .scenario import ScenarioError, load_scenario

    try:
        return load_scenario(path if path else DEFAULT_SCENARIO)
    except ScenarioError as exc:
        print(f"mjtether: {exc}", file=sys.stderr)
        return None


DEFAULT_SCENARIO = Path(__file__).resolve().parent / "scenarios" / "default.toml"


def _run(args) -> int:
    from tqdm import tqdm

    from . import results
    from .runner import RunFailed, run
    from .simulation import SimulationDiverged

    sc = _load(args.scenario)
    if sc is None:
        return 2
    bar = tqdm(total=int(round(sc["simulation"]["duration"] / sc["simulation"]["timestep"])), unit="step",
               desc="mjtether run", leave=False)

    def progress(k, n):
        bar.update(k - bar.n)

    try:
        rows, nodes, info = run(sc, progress=progress)
    except (RunFailed, SimulationDiverged, ValueError) as exc:
        bar.close()
        print(f"mjtether run: failed, no results written: {exc}", file=sys.stderr)
        return 1
    bar.close()
    out = results.write(args.out, sc, rows, nodes, info, scenario_path=args.scenario, plots=not args.no_plots)
    s = results.summary(sc, rows, info, args.scenario)
    print(f"{info['simulated_s']:.0f} s simulated in {info['wall_time_s']:.1f} s "
          f"({info['realtime_factor']:.1f}x real time); final ship-end tension {s['final']['ship_tension_N']:.0f} N, "
          f"tow tension {s['final']['tow_tension_N']:.0f} N; peak {s['peak']['ship_tension_N']:.0f} N; "
          f"results in {out}/")
    return 0


def _solve(args) -> int:
    import numpy as np

    from .runner import ScenarioRun

    sc = _load(args.scenario)
    if sc is None:
        return 2
    try:
        r = ScenarioRun(sc)
    except ValueError as exc:
        print(f"mjtether solve: {exc}", file=sys.stderr)
        return 2
    try:
        ss = r.initial
        if ss is None:
            print(f"mjtether solve: no steady state: {r.initial_note}", file=sys.stderr)
            return 1
        np.set_printoptions(precision=1, suppress=True)
        print(f"steady state of {r.tether_spec.length:g} m of tether ({r.tether_spec.segments} elements):")
        print(f"  force on the ship     {ss.top_force} N  (tension {ss.top_tension:.1f} N)")
        print(f"  force on the tow point {ss.bottom_force} N  (tension {ss.tow_tension:.1f} N)")
        print(f"  lowest point z = {ss.nodes[:, 2].min():.2f} m; on the seabed: {ss.laid_length:.1f} m")
        _print_khan(r)
    finally:
        r.close()
    return 0


def _print_khan(r) -> None:
    """The Khan et al. (2023) method for the walker's first commanded speed: the length that
    reaches its depth, both readings of the paper's Eqs. 22-23 (see quasistatic.khan2023)."""
    from .quasistatic import khan2023

    if not r.walker:
        print("  (the Khan et al. 2023 method applies to a walker moving at constant speed; "
              "this scenario's robot is an anchor)")
        return
    speed = float(r.commands[0, 1])
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


if __name__ == "__main__":
    sys.exit(main())

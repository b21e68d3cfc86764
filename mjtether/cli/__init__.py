"""Command line: ``mjtether run``, ``render``, ``solve``, ``sweep``, ``report``, ``convert``, ``demo``.

``mjtether solve``'s printout is ``mjtether.cli.solve``. Everything past ``argparse`` is imported
inside the command that needs it, so that ``mjtether --help`` and a mistyped option answer at once
(importing numba, SciPy and the kernels costs seconds; that also needs ``mjtether/__init__.py`` to
import its names lazily).
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import warnings
from pathlib import Path

CAMERAS = ("track", "side", "top", "walker")
"""``mjtether.io.render.CAMERAS``, named here so that building the parser imports no renderer
(a test checks that they agree)."""
SCENARIO = ("scenario TOML file, MoorDyn v2 input file or a shipped example's name (listed below; default: the "
            "built-in scenario)")


def _examples_epilog() -> str:
    """The shipped examples' names (``examples/*.toml``, as ``_load`` takes them), for a ``--help``."""
    from mjtether.files.packagedata import examples_dir

    try:
        folder = examples_dir()
    except FileNotFoundError:
        return ""
    names = sorted(str(p.relative_to(folder).with_suffix("")) for p in folder.rglob("*.toml"))
    return ("shipped examples, run by name instead of a file (e.g. `mjtether run default_walker`; the files are in "
            f"{folder}): " + ", ".join(names))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="mjtether", description="Underwater tether simulation in MuJoCo")
    sub = ap.add_subparsers(dest="command", required=True)
    convert_cmd = sub.add_parser("convert", help="convert a MoorDyn input file to a scenario TOML file, or back "
                                 "(by the files' extensions: .toml is a scenario, anything else a MoorDyn file)")
    convert_cmd.add_argument("source", help="a MoorDyn v2 input file or a scenario .toml")
    convert_cmd.add_argument("target", help="the file to write (.toml for a scenario; else a MoorDyn file)")
    convert_cmd.add_argument("--overwrite", action="store_true", help="replace an existing target file")
    _set_option(convert_cmd)
    demo_cmd = sub.add_parser("demo", help="a tether hanging from the surface in a current; prints end tensions")
    demo_cmd.add_argument("--length", type=float, default=200.0, help="tether length (m), default 200")
    demo_cmd.add_argument("--segments", type=int, default=50, help="number of elements, default 50")
    demo_cmd.add_argument("--current-knots", type=float, default=3.0, help="surface current (kn), default 3")
    demo_cmd.add_argument("--duration", type=float, default=120.0, help="simulated time (s), default 120")
    epilog = _examples_epilog()
    run_cmd = sub.add_parser("run", help="run a scenario file and write its results folder", epilog=epilog)
    run_cmd.add_argument("scenario", nargs="?", help=SCENARIO)
    _set_option(run_cmd)
    run_cmd.add_argument("--out", default="results", help="results folder (default: ./results)")
    run_cmd.add_argument("--overwrite", action="store_true",
                         help="replace DIR only if it holds an earlier mjtether result")
    run_cmd.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    run_cmd.add_argument("--video", nargs="?", const="video.mp4", metavar="NAME",
                         help="also render a video into the results folder (default name video.mp4; .mp4 or .gif)")
    _video_options(run_cmd)
    run_cmd.add_argument("--report", action="store_true", help="also write the results folder's HTML report "
                         "(as `mjtether report DIR` does)")
    render_cmd = sub.add_parser("render", help="render a scenario run to a video file (no display needed), or "
                                "replay a results folder of `mjtether run` without simulating again", epilog=epilog)
    render_cmd.add_argument("scenario", nargs="?", help=SCENARIO + ", or a results folder to replay (mjtether run "
                            "--out DIR)")
    _set_option(render_cmd)
    render_cmd.add_argument("-o", "--output", default="run.mp4", help="video file, .mp4 (H.264) or .gif (default run.mp4)")
    render_cmd.add_argument("--duration", type=float, help="simulated seconds to render (default: the scenario's)")
    render_cmd.add_argument("--overwrite", action="store_true", help="replace an existing video file")
    _video_options(render_cmd)
    solve_cmd = sub.add_parser("solve", help="print the quasi-static answer for a scenario's or a network's initial "
                               "state", epilog=epilog)
    solve_cmd.add_argument("scenario", nargs="?", help=SCENARIO)
    _set_option(solve_cmd)
    sweep_cmd = sub.add_parser("sweep", help="run a scenario or a network of lines over a grid or a random sample "
                               "of key values; one row of figures per case (see mjtether.sweep)", epilog=epilog)
    sweep_cmd.add_argument("scenario", help="scenario TOML file, a network (TOML with [[lines]], or a MoorDyn file), "
                           "or a shipped example's name (listed below)")
    _set_option(sweep_cmd)
    sweep_cmd.add_argument("--vary", action="append", required=True, metavar="KEY=SPEC",
                           help="a key and its values (repeatable): START:STOP:COUNT (both ends included, e.g. "
                                "tether.length=200:1000:9) or a list V1,V2,... (e.g. "
                                "water.current.surface_speed_kn=0,1,2); the cases are their product")
    sweep_cmd.add_argument("--samples", type=int, metavar="K",
                           help="K random cases instead of the product (uniform within each range / over each list)")
    sweep_cmd.add_argument("--seed", type=int, default=0, help="random seed of --samples (default 0)")
    sweep_cmd.add_argument("--jobs", type=int, metavar="N", help="cases run at a time (default 1: in this process)")
    sweep_cmd.add_argument("--ray", nargs="?", const="", metavar="ADDRESS",
                           help="run the cases as Ray tasks (a new local Ray, or the cluster at ADDRESS)")
    sweep_cmd.add_argument("--out", required=True, metavar="DIR",
                           help="results folder: cases.csv, summary.png, cases.parquet with pyarrow (an interrupted sweep "
                                "resumes when the same command is run again)")
    sweep_cmd.add_argument("--overwrite", action="store_true", help="replace DIR only if it holds an earlier sweep")
    sweep_cmd.add_argument("--restart", action="store_true",
                           help="run every case again, discarding those an interrupted sweep into DIR finished")
    sweep_cmd.add_argument("--keep-cases", action="store_true",
                           help="also keep each case's whole results folder, as `mjtether run --out` writes it, in "
                                "DIR/cases/<case>/ (the sweep's report then links each case to its own report)")
    sweep_cmd.add_argument("--report", action="store_true", help="also write the sweep's HTML report (a table "
                           "of its cases, as `mjtether report DIR` does; with --keep-cases each case's too)")
    report_cmd = sub.add_parser("report", help="write one self-contained HTML file of a results folder (of "
                                "`mjtether run` or `mjtether sweep`): a 3-D replay and the plots; it opens from disk, "
                                "with no network")
    report_cmd.add_argument("results", metavar="RESULTS_DIR", help="the results folder (mjtether run --out DIR, "
                            "or a sweep's --out DIR)")
    report_cmd.add_argument("--out", metavar="FILE", help="the HTML file to write (default: RESULTS_DIR/report.html)")
    args = ap.parse_args(argv)
    with _plain_warnings(f"mjtether {args.command}"):
        return _dispatch(args)


@contextlib.contextmanager
def _plain_warnings(prefix: str):
    """Warnings of MuJoCo (``MujocoWarning``) and of mjtether's own kinds shown as one plain line,
    ``prefix: warning: ...``, without Python's source line and file path, and above the progress bar
    rather than glued to it (others, e.g. numpy's, as Python shows them)."""
    from tqdm import tqdm

    from mjtether.files.mjlog import MujocoWarning

    shown = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None):
        if not (issubclass(category, MujocoWarning) or category.__module__.split(".")[0] == "mjtether"):
            return shown(message, category, filename, lineno, file, line)
        who = "MuJoCo warning" if issubclass(category, MujocoWarning) else "warning"
        text = " ".join(str(message).split())
        try:
            tqdm.write(f"{prefix}: {who}: {text}", file=file or sys.stderr)
        except (OSError, ValueError):  # (as Python does: a closed or broken stderr loses the warning)
            pass

    warnings.showwarning = show
    try:
        yield
    finally:
        warnings.showwarning = shown


def _dispatch(args) -> int:
    if args.command == "run":
        return _run(args)
    if args.command == "solve":
        from .solve import solve

        return solve(args)
    if args.command == "sweep":
        return _sweep(args)
    if args.command == "render":
        return _render(args)
    if args.command == "convert":
        return _convert(args)
    if args.command == "report":
        return _report(args)
    if args.command == "demo":
        from mjtether import _checks, demo
        from mjtether.units import knots

        try:
            _checks.in_range("--current-knots", args.current_knots, 0.0, 19.0, "kn")
            _checks.in_range("--duration", args.duration, 1e-3, 86400.0, "s")
            res = demo.main(duration=args.duration, length=args.length, segments=args.segments,
                            current=knots(args.current_knots))
        except ValueError as exc:
            print(f"mjtether demo: {exc}", file=sys.stderr)
            return 2
        print(f"after {res['time']:.0f} s: ship-end tension {res['ship_tension']:.1f} N, "
              f"weight-end tension {res['weight_tension']:.1f} N")
    return 0


def _set_option(p) -> None:
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scenario key, checked as in the file (repeatable), e.g. "
                        "--set simulation.duration=10 --set tether.length=300")


def _video_options(p) -> None:
    p.add_argument("--width", type=int, default=640, help="frame width in pixels, even (default 640)")
    p.add_argument("--height", type=int, default=480, help="frame height in pixels, even (default 480)")
    p.add_argument("--fps", type=float, default=30.0, help="frames per second of simulated time (default 30)")
    p.add_argument("--camera", choices=CAMERAS, default="track",
                   help="track: follows the robot; side/top: the whole tether; walker: the walker's camera")
    p.add_argument("--tension-scale", type=float, metavar="N",
                   help="top of the tension colour scale in N (default: from the run's own tensions: a replay's largest over "
                        "the run, a live render's 2x the initial largest)")
    p.add_argument("--default-visuals", action="store_true",
                   help="MuJoCo's default visuals (shadows, reflections, anti-aliasing): slower")


def _video_settings(args):
    """The ``render.VideoSettings`` of the options in ``args``; raises ValueError on bad ones."""
    from mjtether.io.render import VideoSettings

    return VideoSettings(width=args.width, height=args.height, fps=args.fps, camera=args.camera,
                         tuned=not args.default_visuals, tension_scale=args.tension_scale)


def _video_factory(args, path, duration=None, overwrite=True):
    """A ``run(video=...)`` factory for the options in ``args``; raises ValueError on bad ones."""
    from mjtether.io.render import VideoRecorder, check_output_path

    settings = _video_settings(args)
    check_output_path(path, overwrite=overwrite)
    return lambda runner: VideoRecorder(runner, path, settings, duration=duration)


def _load(path, sets=(), network: bool = False):
    """The checked scenario (the built-in one if ``path`` is None) with ``--set`` overrides, or
    None after printing the one-line reason. A MoorDyn file that holds a network of lines
    (``mjtether.network``) is returned as one where ``network``, refused otherwise."""
    from mjtether.io.moordyn import load_any
    from mjtether.network import Network

    from mjtether.scenario import ScenarioError

    if path is not None and not str(path).strip():
        print("mjtether: scenario '': give a scenario file, a MoorDyn file or a shipped example's name "
              "(or none for the built-in scenario)", file=sys.stderr)
        return None
    try:
        sc = load_any(path if path is not None else DEFAULT_SCENARIO, overrides=sets)
    except ScenarioError as exc:
        print(f"mjtether: {exc}", file=sys.stderr)
        return None
    if isinstance(sc, Network) and not network:
        print(f"mjtether: {path}: a network of {len(sc.lines)} line(s) (not one line from a fairlead to an anchor): "
              "`mjtether run` runs it; this command takes one line", file=sys.stderr)
        return None
    return sc


DEFAULT_SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "default.toml"


def _simulate(sc, command: str, what: str, **kw):
    """``runner.run`` with a progress bar; returns its result, or None after printing why it
    failed (``what``: what the failure leaves unwritten). The first run after an install or an
    update compiles the force kernels as it is built (``_compile_clock``); the bar starts when
    the stepping does."""
    from tqdm import tqdm

    from mjtether.physics import jitcache
    from mjtether.scenario.runner import RunFailed, run

    from mjtether.simulation import SimulationDiverged

    clock = _compile_clock(command)
    bar = None

    def progress(k, n):
        nonlocal bar
        if bar is None:
            bar = tqdm(total=n, unit="step", desc=f"mjtether {command}", leave=False)
        bar.update(k - bar.n)

    def built(runner):
        if clock is not None:
            _compiled(command, clock)

    try:
        result = run(sc, progress=progress, on_start=built, **kw)
        if clock is not None:
            jitcache.mark_warm()
            result.info["compile_s"] = clock.seconds
        return result
    except (RunFailed, SimulationDiverged, ValueError, RuntimeError) as exc:
        if bar is not None:  # (so that the message starts a line of its own)
            bar.close()
            bar = None
        if clock is not None:
            clock.stop()
        print(f"mjtether {command}: failed, no {what} written: {exc}", file=sys.stderr)
        return None
    finally:
        if bar is not None:
            bar.close()
        if clock is not None:
            clock.stop()


COMPILE_ESTIMATE = "about a minute on a free core, minutes on a busy one"
"""How long the first run's compile takes (measured: 50 s building ``default_walker`` with a fresh
``NUMBA_CACHE_DIR`` on an idle 2-core machine, about 2 minutes on a busy one)."""


def _compile_clock(command: str):
    """Where the kernels are not known to be compiled and cached (``jitcache.warm``): says so
    and returns the started ``jitcache.CompileClock`` that counts the seconds of it; else None."""
    from mjtether.physics import compiled, jitcache

    if not (compiled.backend() == "numba" and jitcache.CACHE and not jitcache.warm()):
        return None
    print(f"mjtether {command}: compiling the force kernels for this install, once ({COMPILE_ESTIMATE})",
          file=sys.stderr)
    return jitcache.CompileClock(f"mjtether {command}: compiling").start()


def _compiled(command: str, clock) -> None:
    """Stop ``clock`` and say how long the compile took (once: it is stopped after that)."""
    if clock.seconds is None:
        print(f"mjtether {command}: compiled the force kernels in {clock.stop():.1f} s; later runs skip this",
              file=sys.stderr)


def _run(args) -> int:
    from mjtether.io import results
    from mjtether.files.outdir import OutputError, Staging, check_target
    from mjtether.network import Network

    sc = _load(args.scenario, args.set, network=True)
    if sc is None:
        return 2
    if isinstance(sc, Network):
        return _run_network(args, sc)
    if args.video and Path(args.video).suffix.lower() not in (".mp4", ".gif"):
        print(f"mjtether run: --video must name an .mp4 or .gif file, got {args.video!r}", file=sys.stderr)
        return 2
    try:  # before simulating: a refused --out must cost nothing and be left untouched
        target = check_target(args.out, overwrite=args.overwrite, protect=[args.scenario] if args.scenario else [])
    except OutputError as exc:
        print(f"mjtether run: {exc}", file=sys.stderr)
        return 2
    try:
        # A staging folder for the whole run: it holds the video as it is rendered and goes away on
        # any failure, exception, SIGINT or SIGTERM. results.write stages and commits the results.
        with Staging(target, overwrite=args.overwrite) as scratch:
            video, extra = None, {}
            if args.video:
                name = Path(args.video).name
                try:
                    video = _video_factory(args, scratch.path / name)
                except ValueError as exc:
                    print(f"mjtether run: {exc}", file=sys.stderr)
                    return 2
                extra = {name: scratch.path / name}
            done = _simulate(sc, "run", "results", video=video)
            if done is None:
                return 1
            rows, history, info = done
            if "video" in info:
                info["video"]["file"] = next(iter(extra))  # its name inside the results folder
            out = results.write(target, sc, rows, history, info, scenario_path=args.scenario,
                                plots=not args.no_plots, extra_files=extra, overwrite=args.overwrite)
    except OutputError as exc:
        print(f"mjtether run: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("mjtether run: interrupted; no results written", file=sys.stderr)
        return 130
    s = results.summary(sc, rows, info, args.scenario)
    tensions = (f"final ship-end tension {s['final']['ship_tension_N']:.0f} N, tow tension "
                f"{s['final']['tow_tension_N']:.0f} N; peak {s['peak']['ship_tension_N']:.0f} N"
                if info["tethered"] else "no tether")
    snaps = s.get("snap_loads", {})
    if snaps.get("count"):
        worst = snaps["worst"][0]
        tensions += (f"; {snaps['count']} snap load(s), the worst {worst['peak_tension_N']:.0f} N at t = "
                     f"{worst['time_s']:.1f} s, {worst['from_ship_m']:.0f} m from the ship (summary.json's snap_loads)")
    compiled = ", with the force kernels' compile (once)" if "compile_s" in info else ""
    print(f"{simulated(sc.simulation.duration, info['simulated_s'], sc.simulation.timestep)} simulated in "
          f"{info['stepping_s']:.1f} s of stepping ({info['stepping_realtime_factor']:.1f}x real time; the start took "
          f"{info['start_s']:.1f} s{compiled}); {tensions}; results in {out}/")
    return _report_of(args, "run", out)


def simulated(asked: float, ran: float, dt: float) -> str:
    """The simulated time (s) for a closing line: ``asked`` (the duration) where the run reached
    it to the nearest whole step ``dt`` (10 s at 2.4 ms steps is 4167 of them, 10.0008 s),
    else what it ran (stopped early, or a duration under a step) and what was asked."""
    if abs(ran - asked) <= 0.5 * dt * (1 + 1e-9):
        return f"{asked:g} s"
    return f"{ran:.6g} s (of {asked:g} s asked)"


def _report_of(args, command: str, folder) -> int:
    """With ``--report``: the report of the results folder ``folder`` written (``_report``), its
    path printed; 1 if it could not be (the results stay). Else 0."""
    if not getattr(args, "report", False):
        return 0
    return _report(argparse.Namespace(results=folder, out=None), command, kept=f"the results are in {folder}/, ")


def _run_network(args, net) -> int:
    """``mjtether run`` of a network of lines (``mjtether.network.run``)."""
    from mjtether.files.outdir import OutputError, check_target
    from mjtether.io.network_view import network_video_into
    from mjtether.network import run

    from mjtether.simulation import SimulationDiverged

    video = None
    if args.video:
        try:
            video = network_video_into(_video_settings(args), Path(args.video).name)
        except ValueError as exc:
            print(f"mjtether run: {exc}", file=sys.stderr)
            return 2
    try:
        check_target(args.out, overwrite=args.overwrite, protect=[args.scenario])
    except OutputError as exc:
        print(f"mjtether run: {exc}", file=sys.stderr)
        return 2
    done, rc = _with_bar("run", "results", lambda progress: run.run_to(
        net, args.out, overwrite=args.overwrite, source=args.scenario, progress=progress, video=video),
        (SimulationDiverged, ValueError, RuntimeError, OutputError))
    if done is None:
        return rc
    r, rows = done
    final = dict(zip(run.columns(net), rows[-1]))
    if net.lines:
        worst = max(net.lines, key=lambda ln: final[f"line{ln.name}_B_tension_N"])
        what = f"largest end-B tension {final[f'line{worst.name}_B_tension_N']:.0f} N (line {worst.name})"
    else:
        what = f"{len(net.bodies)} bodies, no lines"
    shown = f"; video {r.video['file']} ({r.video['frames']} frames)" if r.video else ""
    ran = simulated(net.duration, rows[-1, 0] - rows[0, 0], r.timestep)
    print(f"{ran} simulated ({len(net.lines)} lines, step {r.timestep:g} s); {what}{shown}; results in {args.out}/")
    return _report_of(args, "run", args.out)


def _render(args) -> int:
    from mjtether.files.outdir import terminate_as_exit

    if args.scenario and Path(args.scenario).is_dir():
        return _replay(args)
    sets = args.set + ([(f"simulation.duration={args.duration!r}", f"--duration {args.duration:g}")]
                       if args.duration is not None else [])
    sc = _load(args.scenario, sets, network=True)
    if sc is None:
        return 2
    from mjtether.network import Network
    if isinstance(sc, Network):
        return _render_network(args, sc)
    try:
        video = _video_factory(args, args.output, overwrite=args.overwrite)
    except ValueError as exc:
        print(f"mjtether render: {exc}", file=sys.stderr)
        return 2
    try:
        with terminate_as_exit():  # the half-written video is removed on SIGTERM too
            done = _simulate(sc, "render", "video", keep_nodes=False, video=video)
    except KeyboardInterrupt:
        print("mjtether render: interrupted; no video written", file=sys.stderr)
        return 130
    if done is None:
        return 1
    info = done[2]
    v = info["video"]
    colours = f"tension colours 0-{v['tension_scale_N']:g} N" if info["tethered"] else "no tether"
    print(f"{v['frames']} frames ({info['simulated_s']:.1f} s at {v['fps']:g} fps, camera {v['camera']}) in "
          f"{info['wall_time_s']:.1f} s; {colours}; wrote {v['file']}")
    return 0


def _with_bar(command: str, what: str, call, errors):
    """``call(progress)`` under a progress bar: (its result, None), or (None, the exit code) after
    printing why nothing (``what``) was written: one of ``errors`` (1) or Ctrl-C (130). A first
    run's compile is counted (``_compile_clock``) until the bar starts."""
    from tqdm import tqdm

    clock = _compile_clock(command)
    bar = tqdm(total=1, unit="step", desc=f"mjtether {command}", leave=False, delay=1e9 if clock else 0)

    def progress(k, n):
        if clock is not None:
            _compiled(command, clock)
        bar.total = n
        bar.update(k - bar.n)
        bar.delay = 0

    def close():  # (so that a message starts a line of its own)
        bar.close()
        if clock is not None:
            clock.stop()

    try:
        return call(progress), None
    except errors as exc:
        close()
        print(f"mjtether {command}: failed, no {what} written: {exc}", file=sys.stderr)
        return None, 1
    except KeyboardInterrupt:
        close()
        print(f"mjtether {command}: interrupted; no {what} written", file=sys.stderr)
        return None, 130
    finally:
        close()


def _render_network(args, net) -> int:
    """``mjtether render`` of a network of lines: simulated and rendered, nothing else written."""
    import time

    from mjtether.files.outdir import terminate_as_exit
    from mjtether.io.network_view import network_video
    from mjtether.io.render import RenderUnavailable
    from mjtether.network import run

    from mjtether.simulation import SimulationDiverged

    try:
        video = network_video(_video_settings(args), args.output, overwrite=args.overwrite)
    except ValueError as exc:
        print(f"mjtether render: {exc}", file=sys.stderr)
        return 2
    def simulate(progress):
        with terminate_as_exit():  # the half-written video is removed on SIGTERM too
            r, rows = run.simulate(net, progress=progress, video=video)
        r.sim.close()
        return r, rows

    t0 = time.perf_counter()
    done, rc = _with_bar("render", "video", simulate, (SimulationDiverged, ValueError, RuntimeError, RenderUnavailable))
    if done is None:
        return rc
    r, rows = done
    v = r.video
    print(f"{v['frames']} frames ({rows[-1, 0]:.1f} s at {v['fps']:g} fps, camera {v['camera']}) in "
          f"{time.perf_counter() - t0:.1f} s; tension colours 0-{v['tension_scale_N']:g} N; wrote {args.output}")
    return 0


def _replay(args) -> int:
    """``mjtether render DIR``: the results folder DIR replayed from its saved states
    (``mjtether.io.replay``), nothing simulated."""
    from mjtether.files.outdir import terminate_as_exit
    from mjtether.io.render import RenderUnavailable, VideoSettings
    from mjtether.io.replay import ReplayError, replay

    if args.set:
        print(f"mjtether render: --set {args.set[0]}: a results folder is replayed as it was run; --set applies to "
              "a scenario file", file=sys.stderr)
        return 2
    try:
        settings = VideoSettings(width=args.width, height=args.height, fps=args.fps, camera=args.camera,
                                 tuned=not args.default_visuals, tension_scale=args.tension_scale)
        with terminate_as_exit():  # the half-written video is removed on SIGTERM too
            v = replay(args.scenario, args.output, settings, duration=args.duration, overwrite=args.overwrite)
    except (ReplayError, ValueError, RenderUnavailable) as exc:
        print(f"mjtether render: {exc}", file=sys.stderr)
        return 2 if isinstance(exc, ValueError) else 1
    except KeyboardInterrupt:
        print("mjtether render: interrupted; no video written", file=sys.stderr)
        return 130
    colours = f"tension colours 0-{v['tension_scale_N']:g} N" if v.get("tethered", True) else "no tether"
    note = "" if v["smooth"] else (f"; it holds each of the {v['samples']} samples {v['output_interval_s']:g} s "
                                   "apart (simulation.output_interval) for a smooth replay run with it at 1/fps")
    print(f"{v['frames']} frames ({v['simulated_s']:.1f} s at {v['fps']:g} fps, camera {v['camera']}) replayed from "
          f"{args.scenario} in {v['wall_time_s']:.1f} s; {colours}; wrote "
          f"{v['file']}{note}")
    return 0


def _convert(args) -> int:
    """``mjtether convert SOURCE TARGET``: MoorDyn file <-> scenario TOML (see mjtether.io.moordyn),
    or a network of lines (TOML or MoorDyn) -> a MoorDyn file, with its current profile beside it
    (``moordyn.CURRENT_FILE``) where it has a current; every file is written whole or not at all,
    and never over an existing file unless ``--overwrite``."""
    import os
    import tempfile

    from mjtether.io import moordyn
    from mjtether.network import Network

    from mjtether.scenario import ScenarioError, to_toml

    sc = _load(args.source, args.set, network=True)
    if sc is None:
        return 2
    target = Path(args.target)
    try:
        if isinstance(sc, Network):
            if target.suffix.lower() == ".toml":
                raise ScenarioError("a network of lines is written as a MoorDyn file only (give a target that "
                                    "does not end in .toml)")
            files = {target: moordyn.write_network(sc)}
            if moordyn.current_table(sc):
                files[target.parent / moordyn.CURRENT_FILE] = moordyn.current_profile(sc)
        else:
            files = {target: to_toml(sc) if target.suffix.lower() == ".toml" else moordyn.write(sc)}
    except ScenarioError as exc:
        print(f"mjtether convert: {exc}", file=sys.stderr)
        return 2
    source = Path(args.source).resolve()
    for path in files:
        if path.is_dir() or (path.exists() and not args.overwrite) or path.resolve() == source:
            why = ("is a folder" if path.is_dir() else "is the source file" if path.resolve() == source
                   else "exists; pass --overwrite to replace it")
            print(f"mjtether convert: {path} {why}", file=sys.stderr)
            return 2
    for path, text in files.items():
        tmp = None
        try:
            fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.resolve().parent)
            with os.fdopen(fd, "w") as fh:
                fh.write(text)
            os.replace(tmp, path)
        except OSError as exc:
            if tmp is not None:
                Path(tmp).unlink(missing_ok=True)
            print(f"mjtether convert: cannot write {path}: {exc.strerror or exc}", file=sys.stderr)
            return 1
    print("wrote " + " and ".join(str(p) for p in files))
    return 0


def _sweep(args) -> int:
    from mjtether import sweep

    return sweep.cli(args) or _report_of(args, "sweep", args.out)


def _report(args, command: str = "report", kept: str = "") -> int:
    """``mjtether report DIR [--out FILE]``: the one-file HTML report of a results folder or a
    sweep's folder (``mjtether.io.report.write_report``); prints its path. 2 for a folder it
    cannot report on, 1 where the file cannot be written (``kept``: what stays, for a run's
    ``--report``)."""
    from mjtether.io.report import ReportError, write_report

    try:
        path = write_report(args.results, out=args.out)
    except (ReportError, OSError) as exc:
        print(f"mjtether {command}: {kept}no report written: {exc}", file=sys.stderr)
        return 2 if isinstance(exc, ReportError) and not kept else 1
    print(f"report in {path}")
    return 0

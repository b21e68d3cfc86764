"""Benchmark: headless rendering speed (frames per second) at 640x480, MuJoCo's default visuals
against mjtether's tuned ones, on the built-in walker scenario.

    python scripts/bench_render.py [--segments 200] [--frames 60] [--camera side] [--json]

``render_fps`` times drawing and reading back one frame (``VideoRecorder.render``), with the
simulation advanced 1/30 s between frames (not timed). ``video_fps`` is the whole
``mjtether render`` pipeline for 4 s of video (simulation, drawing, H.264 encoding): frames
written per second of wall time.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import numpy as np

from mjtether.cli import DEFAULT_SCENARIO
from mjtether.io.render import VideoRecorder, VideoSettings
from mjtether.scenario.runner import ScenarioRun, run
from mjtether.scenario import load_scenario


def render_fps(sc, settings: VideoSettings, frames: int, folder: Path) -> float:
    r = ScenarioRun(sc)
    try:
        rec = VideoRecorder(r, folder / "probe.mp4", settings)
        try:
            times = []
            steps = max(1, int(round(1 / 30 / r.sim.timestep)))
            for _ in range(frames):
                for _ in range(steps):
                    r.step()
                t0 = time.perf_counter()
                rec.render()
                times.append(time.perf_counter() - t0)
        finally:
            rec.abort()
    finally:
        r.close()
    return 1.0 / float(np.median(times))


def video_fps(sc, settings: VideoSettings, folder: Path) -> float:
    sc = sc.replace(simulation=sc.simulation.replace(duration=4.0))
    t0 = time.perf_counter()
    _, _, info = run(sc, keep_nodes=False, video=lambda r: VideoRecorder(r, folder / "v.mp4", settings))
    return info["video"]["frames"] / (time.perf_counter() - t0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--segments", type=int, default=None, help="tether elements (default: the scenario's 100)")
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--camera", default="side")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    sc = load_scenario(DEFAULT_SCENARIO, overrides=[f"tether.segments={args.segments}"] if args.segments else ())
    out = {"width": 640, "height": 480, "camera": args.camera, "segments": sc.tether.segments}
    with tempfile.TemporaryDirectory() as tmp:
        for label, tuned in (("default", False), ("tuned", True)):
            s = VideoSettings(640, 480, 30.0, args.camera, tuned=tuned)
            out[f"render_fps_{label}"] = round(render_fps(sc, s, args.frames, Path(tmp)), 1)
            out[f"video_fps_{label}"] = round(video_fps(sc, s, Path(tmp)), 1)
    out["speedup"] = round(out["render_fps_tuned"] / out["render_fps_default"], 2)
    if args.json:
        print(json.dumps(out))
    else:
        print(f"640x480, camera {args.camera}, N = {out['segments']}: drawing {out['render_fps_default']} fps with "
              f"MuJoCo's default visuals, {out['render_fps_tuned']} fps tuned ({out['speedup']}x faster); "
              f"whole pipeline {out['video_fps_default']} / {out['video_fps_tuned']} fps")


if __name__ == "__main__":
    main()

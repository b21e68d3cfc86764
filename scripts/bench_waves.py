"""Benchmark: what the waves cost (issue 43): a JONSWAP sea state on the default walker's ship
against the same run on a flat sea, and mjtether against MoorDyn-C on one line in a regular wave.

* **Sea state** (``examples/walker_sea_state.toml``: Hs 3 m, Tp 9 s, 100 components, the ship
  on its box-barge RAOs) with ``tether.length = 300`` (a 300 m umbilical, 100 elements, to the
  walker on a 200 m deep seabed), against the same run with ``waves.type = "none"`` and
  ``ship.motion.type = "none"`` (the flat sea: the same line, current, walker and ship). The
  3-hour sea is sampled over a window of ``--window`` simulated seconds (default 60) from its
  start (its build-up ramp, one peak period, included), and over the same window 10 000 s into
  it (``LATE_S``): the same components with each phase moved on by omega 10 000 s, which is the
  sea of t + 10 000 s exactly (``eta(x, t + T) = eta'(x, t)`` with phase' = phase - omega T),
  the run starting from rest in it with its own build-up. Reported: wall seconds per simulated
  second of the whole run (build, steady start, pre-roll, stepping, records) and of the
  stepping alone, best of ``--repeats`` (default 3), the two seas alternating in one process
  (the machine is shared: only ratios taken within one run mean anything), and the ratio of
  the waves' to the flat sea's stepping (issue 43's goal: at most 1.3).
* **Where the waves' time goes**: one step's parts in the sea-state run, microseconds (best of
  5 x 200 calls on the run's state after 2 s): the sea at the line's 200 Gauss points (compiled,
  and the NumPy reference), the line's loads with the waves, the walker body's loads, and the
  ship's RAO motion (``Ship.update``, at a new time each call, as in a run); and the whole step
  of each run.
* **MoorDyn-C** (the ``moordyn`` package, 2.7): the one-line case of
  ``tests/io/test_moordyn_waves.py`` (its file builder, imported: a 100 m rope of 10 segments
  between two fixed points in 50 m of water, dtM 1 ms) under one regular wave component
  (WaveKin 7, ``REGULAR``: 1 m amplitude, 9 s), run for ``MOORDYN_S`` s by both: whole run
  (reading the file, MoorDyn-C's Init or mjtether's build and settle) and stepping alone, per
  simulated second, and their ratio (mjtether over MoorDyn-C; below 1: mjtether faster).

    python scripts/bench_waves.py [--json] [--window 60] [--repeats 3]
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import importlib.util
import json
import math
import os
import sys
import tempfile
import time
import timeit
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "walker_sea_state.toml"
UMBILICAL = ["tether.length=300.0"]
FLAT = ['waves.type="none"', 'ship.motion.type="none"']
LATE_S = 10000.0
MOORDYN_S = 20.0
REGULAR = (2 * math.pi / 9.0, 1.0, 0.0, 0.0)  # omega rad/s, re m, im m, beta rad: one 1 m, 9 s wave along +x


def _late(shift_s: float):
    """A ``scene.wave_field`` whose sea is the configured one ``shift_s`` s later (each phase
    moved on by omega shift_s; the build-up as configured)."""
    from mjtether.physics import waves as wv
    from mjtether.scenario import sea

    def wave_field(waves, depth, gravity):
        f = sea.wave_field(waves, depth, gravity)
        if f is None:
            return None
        c = f.components
        moved = dataclasses.replace(c, phase=np.remainder(c.phase - c.omega * shift_s, 2 * math.pi))
        return wv.WaveField(moved, f.depth, f.g, stretching=f.stretching, ramp_s=f.ramp_s)
    return wave_field


def _run(sets: list[str], window: float, late: bool = False) -> tuple[float, float]:
    """(whole run, stepping) wall s per simulated s of the example with ``sets``."""
    from mjtether.scenario import load_scenario, scene
    from mjtether.scenario.recording import run

    sc = load_scenario(EXAMPLE, overrides=[f"simulation.duration={window!r}", *UMBILICAL, *sets])
    started = []
    own = scene.wave_field
    if late:
        scene.wave_field = _late(LATE_S)
    try:
        t0 = time.perf_counter()
        result = run(sc, keep_nodes=False, on_start=lambda _: started.append(time.perf_counter()))
        t1 = time.perf_counter()
    finally:
        scene.wave_field = own
    simulated = result.info["simulated_s"]
    return (t1 - t0) / simulated, (t1 - started[0]) / simulated


def _us(fn, calls: int = 200) -> float:
    return round(min(timeit.repeat(fn, number=calls, repeat=5)) / calls * 1e6, 1)


def _parts() -> dict:
    """One step's parts (us) in the sea-state run and on the flat sea (module docstring)."""
    from mjtether.physics.hydro import gauss_points
    from mjtether.scenario import load_scenario
    from mjtether.scenario.runner import ScenarioRun

    out = {}
    for name, sets in (("waves", []), ("flat", FLAT)):
        r = ScenarioRun(load_scenario(EXAMPLE, overrides=[*UMBILICAL, *sets]))
        try:
            for _ in range(round(2.0 / r.sim.timestep)):
                r.step()
            d, loads = r.sim.data, r.bt.forces
            L, k = loads.layout, r.bt.drum.first
            x = d.flexvert_xpos[L.vertadr + k:L.vertadr + L.n + 1].copy()
            out[f"{name}_step_us"] = _us(r.step)
            out[f"{name}_line_loads_us"] = _us(lambda: loads.buffer(d))
            out[f"{name}_walker_body_loads_us"] = _us(lambda: [b.loads(r.sim.model, d) for b in r.sim.bodies])
            out[f"{name}_native_callback"] = bool(r.sim.native)
            if name == "waves":
                sea, t = L.water.waves, float(d.time)
                gp = gauss_points(x).reshape(-1, 3)
                out["sea_points"], out["sea_components"] = len(gp), len(sea.components)
                out["sea_at_line_compiled_us"] = _us(lambda: sea.state(gp, t))
                out["sea_at_line_numpy_us"] = _us(lambda: sea.reference_state(gp, t))
                out["sea_at_one_point_compiled_us"] = _us(lambda: sea.state(gp[:1], t))
                ship = next(c for c in r.controllers if type(c).__name__ == "Ship")
                later = iter(t + r.sim.timestep * np.arange(1, 10 ** 5))  # (a new time each call, as a run's
                # steps: at one time the motion is kept from the call before, which would time the cache)
                out["ship_rao_motion_us"] = _us(lambda: ship.update(r, float(next(later)), r.sim.timestep))
        finally:
            r.close()
    return out


def _moordyn_case():
    """The file builder of tests/io/test_moordyn_waves.py (imported, unchanged)."""
    path = ROOT / "tests" / "io" / "test_moordyn_waves.py"
    spec = importlib.util.spec_from_file_location("test_moordyn_waves", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@contextlib.contextmanager
def _quiet():
    """MoorDyn-C's console output (it prints each step's time to the process's stdout) to
    /dev/null, so that ``--json`` prints one line."""
    sys.stdout.flush()
    saved, null = os.dup(1), os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    try:
        yield
    finally:
        os.dup2(saved, 1)
        os.close(null)
        os.close(saved)


def _moordyn(duration: float) -> dict:
    """mjtether and MoorDyn-C on the one-line regular-wave file (module docstring)."""
    from mjtether.io import moordyn as md_read
    from mjtether.network import run as nrun

    case = _moordyn_case()
    md = case.md
    out = {"moordyn_duration_s": duration}
    with tempfile.TemporaryDirectory(prefix="bench-waves-") as tmp:
        rows = ["0 0 0", " ".join(repr(v) for v in REGULAR)]
        path = case._folder(Path(tmp), 7, rows)
        with case.moordyn_c._cwd(path.parent), _quiet():
            t0 = time.perf_counter()
            s = md.Create(str(path))
            md.Init(s, np.zeros(0), np.zeros(0))
            t1 = time.perf_counter()
            t, dt = 0.0, 0.1
            while t < duration - 1e-9:
                md.Step(s, np.zeros(0), np.zeros(0), t, dt)
                t += dt
            t2 = time.perf_counter()
            md.Close(s)
        out["moordyn_s_per_s"] = round((t2 - t0) / duration, 4)
        out["moordyn_steps_s_per_s"] = round((t2 - t1) / duration, 4)
        best = (math.inf, math.inf)
        for _ in range(2):  # (the first pays for the kernels' first use)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", md_read.MoorDynWarning)
                t0 = time.perf_counter()
                net = md_read.read(path, overrides=[f"simulation.duration={duration}"])
                r = nrun.build(net)
                if net.settle > 0:
                    nrun.settle(r, net.settle)
            t1 = time.perf_counter()
            r.sim.step(round(duration / r.timestep))
            t2 = time.perf_counter()
            r.sim.close()
            best = min(best, ((t2 - t0) / duration, (t2 - t1) / duration))
        out["mjtether_s_per_s"], out["mjtether_steps_s_per_s"] = (round(b, 4) for b in best)
        out["mjtether_timestep_s"] = r.timestep
    out["ratio"] = round(out["mjtether_s_per_s"] / out["moordyn_s_per_s"], 3)
    out["steps_ratio"] = round(out["mjtether_steps_s_per_s"] / out["moordyn_steps_s_per_s"], 3)
    return out


def measure(window: float, repeats: int) -> dict:
    from mjtether.physics import compiled

    out = {"scenario": str(EXAMPLE.relative_to(ROOT)), "overrides": UMBILICAL, "flat_overrides": FLAT,
           "kernels": compiled.backend(), "sea_sampled": f"a {window:g} s window of the 3-hour sea from t = 0 "
           f"(its build-up included) and from t = {LATE_S:g} s (phases moved on by omega {LATE_S:g} s)",
           "window_s": window, "late_start_s": LATE_S, "repeats": repeats}
    _run(FLAT, 2.0), _run([], 2.0)  # (first use: imports, kernels)
    cases = {"waves": ([], False), "flat": (FLAT, False), "waves_late": ([], True)}
    best = {name: (math.inf, math.inf) for name in cases}
    for _ in range(repeats):
        for name, (sets, late) in cases.items():
            best[name] = min(best[name], _run(sets, window, late))
    for name, (whole, steps) in best.items():
        out[f"{name}_s_per_s"], out[f"{name}_steps_s_per_s"] = round(whole, 4), round(steps, 4)
    out["ratio"] = round(best["waves"][1] / best["flat"][1], 2)
    out["ratio_late"] = round(best["waves_late"][1] / best["flat"][1], 2)
    out["ratio_whole_run"] = round(best["waves"][0] / best["flat"][0], 2)
    out["goal_ratio"] = 1.3
    out["parts_us"] = _parts()
    out["moordyn_one_line_regular_wave"] = _moordyn(MOORDYN_S)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--window", type=float, default=60.0, help="simulated seconds of each run (default 60)")
    ap.add_argument("--repeats", type=int, default=3, help="runs of each sea, the best kept (default 3)")
    args = ap.parse_args(argv)
    out = measure(args.window, args.repeats)
    if args.json:
        print(json.dumps(out))
        return
    print(f"sea state {out['waves_steps_s_per_s']:.4f} s/s stepping ({out['waves_s_per_s']:.4f} whole), "
          f"10 000 s in {out['waves_late_steps_s_per_s']:.4f}; flat sea {out['flat_steps_s_per_s']:.4f} "
          f"({out['flat_s_per_s']:.4f}); ratio {out['ratio']:.2f} (late {out['ratio_late']:.2f}; goal 1.3)")
    for key, value in out["parts_us"].items():
        print(f"  {key}: {value}")
    m = out["moordyn_one_line_regular_wave"]
    print(f"one line, regular wave: mjtether {m['mjtether_s_per_s']:.4f} s/s "
          f"(steps {m['mjtether_steps_s_per_s']:.4f}), "
          f"MoorDyn-C {m['moordyn_s_per_s']:.4f} s/s (steps {m['moordyn_steps_s_per_s']:.4f}); ratio {m['ratio']:.2f}")


if __name__ == "__main__":
    main()

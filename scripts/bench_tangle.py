"""Benchmark: the tangle monitor (``mjtether.cable.tangle``), its NumPy and scipy reference against
its compiled twins, per recorded sample, and what recording costs in a run.

* **Per sample**: the monitor's work at one sample as ``Readouts.tangle`` does it (the cable's
  self-clearance with a blind arc of 5 elements, and, with a vehicle, its clearance from a
  REMUS-sized hull with four points and the wrap angle), on a 100 m cable of 20, 100 and 400
  elements of two shapes: ``hanging`` (a catenary-like curve from the surface to the seabed,
  drifting sideways) and ``coiled`` (the same, its lower half lying in loops 2 m across on the
  seabed: many elements near each other). Median wall time of repeated calls, in us.
* **In a run**: MoorDyn's 20-segment chain (``scripts/bench_moordyn.py``'s case, 20 s) and the
  default walker scenario (100 elements, 20 s), each run with the reference monitor and with the
  compiled one (``compiled`` forced in ``tangle``): the stepping's wall time, the recording's
  (``ScenarioRun.record``: every column of a sample, the monitor among them) and its share.

The reference is what ran before the twins (its k-d tree's pairs now sorted, which decides ties).

    python scripts/bench_tangle.py [--json]
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SIZES = (20, 100, 400)
LENGTH = 100.0  # m, the benchmark cable
RUN_S = 20.0  # s simulated per run


def cable(n: int, shape: str) -> np.ndarray:
    """(n+1, 3) nodes (m) of a ``LENGTH`` m cable of ``shape`` (see the module doc), in about
    equal elements."""
    u = np.linspace(0.0, 1.0, 20 * n + 1)
    if shape == "hanging":
        x = np.c_[30.0 * u, 5.0 * u ** 2, -50.0 * np.sin(0.5 * math.pi * u)]
    else:  # the lower half in loops on the seabed at z = -50
        a = np.clip(u - 0.5, 0.0, None) * 2.0 * 8.0 * math.pi
        down = np.minimum(u / 0.5, 1.0)
        x = np.c_[15.0 * down + 1.0 * np.sin(a), 1.0 - np.cos(a), -50.0 * np.sin(0.5 * math.pi * down)]
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(x, axis=0), axis=1))]
    s *= LENGTH / s[-1]
    return np.array([np.interp(np.linspace(0.0, LENGTH, n + 1), s, x[:, k]) for k in range(3)]).T


def monitor_us(nodes: np.ndarray, compiled: bool, vehicle: bool, repeats: int) -> float:
    """Median wall time (us) of one sample's monitoring of ``nodes``."""
    from mjtether.cable import tangle

    l0 = LENGTH / (len(nodes) - 1)
    tail = nodes[-1]
    a, b = tail + [0.0, 0.0, 0.2], tail + [1.6, 0.0, 0.2]  # a 1.6 m hull, 0.095 m in radius, above the tow point
    pts = np.array([a + [0.1, 0.3, 0.0], a + [0.1, -0.3, 0.0], a + [0.0, 0.0, 0.3], a + [0.0, 0.0, -0.3]])

    def once():
        if vehicle:
            tangle.vehicle_clearance(nodes, a, b, 0.095, pts, 1.6, True, compiled=compiled)
            tangle.wrap_angle(nodes, tail, max(3.2, 2.0 * l0))
        tangle.self_clearance(nodes, 5.0 * l0, 5.0 * l0, compiled=compiled)

    once()  # (the compile, or the cache's load)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        once()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)) * 1e6


@contextlib.contextmanager
def monitor_kind(compiled: bool):
    """Force the monitor's kind in a run (``tangle`` asks ``_use_compiled`` when not told)."""
    from mjtether.cable import tangle

    old = tangle._use_compiled
    tangle._use_compiled = lambda asked: compiled if asked is None else bool(asked)
    try:
        yield
    finally:
        tangle._use_compiled = old


def timed_run(sc, compiled: bool) -> dict:
    """One run of ``sc`` with the monitor of that kind: stepping and recording wall s."""
    from mjtether.scenario import runner as runner_mod
    from mjtether.scenario.runner import run

    spent = [0.0]
    record = runner_mod.ScenarioRun.record

    def timed(self):
        t0 = time.perf_counter()
        row = record(self)
        spent[0] += time.perf_counter() - t0
        return row

    runner_mod.ScenarioRun.record = timed
    try:
        with monitor_kind(compiled):
            rows, _, info = run(sc, keep_nodes=False)
    finally:
        runner_mod.ScenarioRun.record = record
    return {"samples": len(rows), "steps": info["steps"], "stepping_s": info["stepping_s"], "record_s": spent[0]}


def run_case(sc, tries: int) -> dict:
    """The best of ``tries`` runs of ``sc`` with each monitor (after one to warm up)."""
    out = {}
    timed_run(sc, True)
    for kind, compiled in (("reference", False), ("compiled", True)):
        best = min((timed_run(sc, compiled) for _ in range(tries)), key=lambda r: r["stepping_s"])
        out[kind] = {"samples": best["samples"], "steps": best["steps"],
                     "stepping_ms": round(1e3 * best["stepping_s"], 2), "record_ms": round(1e3 * best["record_s"], 2),
                     "record_share": round(best["record_s"] / best["stepping_s"], 3),
                     "record_us_per_sample": round(1e6 * best["record_s"] / best["samples"], 1)}
    return out


def chain_scenario(folder: Path):
    sys.path.insert(0, str(ROOT / "scripts"))
    import bench_moordyn
    from mjtether.io import moordyn as md

    path = bench_moordyn._case_file(folder, "WD0200_Chain.txt", 20)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", md.MoorDynWarning)
        return md.read(path, overrides=[f"simulation.duration={RUN_S}"])


def measure(repeats: int = 200, tries: int = 3) -> dict:
    from mjtether.cli import DEFAULT_SCENARIO
    from mjtether.scenario import load_scenario

    out = {"cable_length_m": LENGTH, "per_sample_us": {}}
    for shape in ("hanging", "coiled"):
        for vehicle in (False, True):
            key = f"{shape}{'_vehicle' if vehicle else ''}"
            for n in SIZES:
                x = cable(n, shape)
                ref = monitor_us(x, False, vehicle, max(10, repeats // (n // 20)))
                fast = monitor_us(x, True, vehicle, repeats)
                out["per_sample_us"][f"{key}_N{n}"] = {"reference": round(ref, 1), "compiled": round(fast, 1),
                                                       "speedup": round(ref / fast, 1)}
    with tempfile.TemporaryDirectory(prefix="bench-tangle-") as tmp:
        out["chain_N20_run"] = run_case(chain_scenario(Path(tmp)), tries)
    sc = load_scenario(DEFAULT_SCENARIO, overrides=[f"simulation.duration={RUN_S}"])
    out["default_walker_N100_run"] = run_case(sc, 1)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    out = measure()
    if args.json:
        print(json.dumps(out))
        return
    for key, v in out["per_sample_us"].items():
        print(f"{key:22s} reference {v['reference']:9.1f} us  compiled {v['compiled']:8.1f} us  x{v['speedup']}")
    for case in ("chain_N20_run", "default_walker_N100_run"):
        for kind, v in out[case].items():
            print(f"{case} {kind:9s}: stepping {v['stepping_ms']} ms, recording {v['record_ms']} ms "
                  f"({v['record_share']:.1%}, {v['record_us_per_sample']} us per sample, {v['samples']} samples)")


if __name__ == "__main__":
    main()

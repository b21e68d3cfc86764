"""Benchmark: wall time of the same 16-case ``mjtether sweep`` with ``--jobs 1`` and ``--jobs 2``.

    python scripts/bench_sweep.py [--json] [--jobs N] [--duration S] [--repeat R]

The cases: a 120 m anchored tether (10 elements, 100 m of water), 24 s simulated each (about
1 s of wall time on this project's CI machine), tether.length 110-120 m x diameter 30-45 mm
(4 x 4). Both sweeps run from this process through ``mjtether.sweep.sweep`` into fresh
temporary folders, with mjtether, matplotlib and pyarrow already imported: ``--jobs 1`` pays no
start-up, ``--jobs 2`` pays for starting its worker process. Each wall time covers everything
the command does (checks, running, writing cases.csv/.parquet and summary.png). ``speedup`` =
jobs-1 time / jobs-N time (at most N). The machine's other load counts against it: compare
``case_wall_s_mean_jobs1`` with ``case_wall_s_mean_jobsN``, and see ``busy_fraction_jobsN``, the
share of the N lanes' time spent inside cases (the rest is start-up, scheduling and writing).
"""

from __future__ import annotations

import argparse
import csv
import importlib
import json
import os
import tempfile
import time
from pathlib import Path

from mjtether import sweep

SCENARIO = """\
[simulation]
duration = {duration!r}
output_interval = 0.5
[water]
depth = 100.0
[tether]
length = 120.0
segments = 10
diameter = 0.03
density = 2500.0
EA = 5.0e6
[robot]
type = "anchor"
position = [40.0, 0.0, -90.0]
"""
VARY = ["tether.length=110:120:4", "tether.diameter=0.03:0.045:4"]


def _timed(scenario: Path, out: Path, jobs: int) -> tuple[float, list[float]]:
    t0 = time.perf_counter()
    sweep.sweep(scenario, VARY, out, jobs=jobs, progress=False, log=lambda *a: None)
    wall = time.perf_counter() - t0
    with open(out / "cases.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    bad = [r["error"] for r in rows if r["status"] != "ok"]
    if bad:
        raise SystemExit(f"bench_sweep: {len(bad)} cases failed, e.g. {bad[0]}")
    return wall, [float(r["wall_s"]) for r in rows]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--jobs", type=int, default=2, help="the parallel run's --jobs (default 2)")
    ap.add_argument("--duration", type=float, default=24.0, help="simulated seconds per case (default 24)")
    ap.add_argument("--repeat", type=int, default=1,
                    help="run both sweeps R times, alternating, and report the fastest of each (default 1)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    # warm: neither sweep pays for the first import of the plotting and Parquet libraries
    importlib.import_module("matplotlib.pyplot")
    importlib.import_module("pyarrow.parquet")

    n = args.jobs
    runs1, runsn = [], []
    with tempfile.TemporaryDirectory(prefix="bench_sweep_") as tmp:
        scenario = Path(tmp) / "anchor.toml"
        scenario.write_text(SCENARIO.format(duration=args.duration))
        load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None  # before: the machine's other load
        for k in range(args.repeat):
            runs1.append(_timed(scenario, Path(tmp) / f"jobs1_{k}", 1))
            runsn.append(_timed(scenario, Path(tmp) / f"jobs{n}_{k}", n))
    w1, cases1 = min(runs1)
    wn, casesn = min(runsn)
    out = {"cases": len(cases1), "wall_s_jobs1": round(w1, 2), f"wall_s_jobs{n}": round(wn, 2),
           "speedup": round(w1 / wn, 2), "jobs": n}
    if args.repeat > 1:
        out["all_wall_s_jobs1"] = [round(w, 2) for w, _ in runs1]
        out[f"all_wall_s_jobs{n}"] = [round(w, 2) for w, _ in runsn]
    out |= {
        # a case's mean wall time in each sweep: longer in the parallel one when the cores are shared
        "case_wall_s_mean_jobs1": round(sum(cases1) / len(cases1), 3),
        f"case_wall_s_mean_jobs{n}": round(sum(casesn) / len(casesn), 3),
        # share of the N lanes' time spent inside cases (the rest: start-up, scheduling, writing)
        f"busy_fraction_jobs{n}": round(sum(casesn) / (n * wn), 3),
        "simulated_s_per_case": args.duration, "cpu_count": os.cpu_count(),
        "load_average_1min_before": None if load is None else round(load, 2)}
    if args.json:
        print(json.dumps(out))
    else:
        print(f"{out['cases']} cases of {args.duration:g} s simulated (mean {out['case_wall_s_mean_jobs1']} s wall "
              f"each): --jobs 1 {w1:.1f} s, --jobs {n} {wn:.1f} s: {out['speedup']:.2f}x")


if __name__ == "__main__":
    main()

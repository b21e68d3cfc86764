"""Benchmark: real-time factor of a scenario run (default: the built-in scenario, N = 100 with
seabed contact), on one core, without writing results.

    python scripts/bench_scenario.py [SCENARIO.toml] [--duration 30] [--json]
"""

from __future__ import annotations

import argparse
import json

from mjtether.cli import DEFAULT_SCENARIO
from mjtether.runner import run
from mjtether.scenario import load_scenario


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenario", nargs="?", default=str(DEFAULT_SCENARIO))
    ap.add_argument("--duration", type=float, default=30.0, help="simulated seconds (default 30)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    sc = load_scenario(args.scenario)
    sc["simulation"]["duration"] = args.duration
    _, _, info = run(sc, keep_nodes=False)
    out = {"scenario": args.scenario, "segments": sc["tether"]["segments"], "timestep": sc["simulation"]["timestep"],
           "simulated_s": info["simulated_s"], "wall_s": round(info["wall_time_s"], 2),
           "realtime_factor": round(info["realtime_factor"], 2)}
    print(json.dumps(out) if args.json else
          f"{out['scenario']}: N = {out['segments']}, {out['simulated_s']:.0f} s in {out['wall_s']} s, "
          f"{out['realtime_factor']}x real time (target >= 10 for the walker scenario)")


if __name__ == "__main__":
    main()

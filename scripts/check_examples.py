"""Every shipped example through every command, as a user would type them: ``run`` (with
plots), ``report`` of its results folder (the HTML page), ``solve``, ``render`` of the file (a
live video), ``render`` of the results folder (a replay), a 2-case ``sweep`` (keeping each case's
folder) and the sweep's ``report`` (linking each case's), each for a few simulated seconds.

    python scripts/check_examples.py [--duration 2] [--only NAME ...] [--json]

Prints one line per example and command (its exit code, and the last line it printed to stderr
where it failed) and exits 1 if any command failed. ``solve`` may exit 1 where the statics have no
answer and it says why (its message is shown); that counts as an answer, not a failure, when the
message says which part or why. ``--json`` prints the table as JSON instead.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def examples() -> list[Path]:
    return sorted((ROOT / "examples").glob("*.toml")) + sorted((ROOT / "examples" / "networks").glob("*.toml"))


def _call(argv) -> tuple[int, str, str]:
    from mjtether import cli

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = cli.main(argv)
        except SystemExit as exc:  # (argparse)
            rc = exc.code if isinstance(exc.code, int) else 2
    return rc, out.getvalue(), err.getvalue()


def check(path: Path, duration: float, work: Path) -> dict:
    name = path.relative_to(ROOT / "examples").with_suffix("").as_posix()
    d = work / name.replace("/", "_")
    d.mkdir(parents=True)
    dur = f"simulation.duration={duration:g}"
    video = ["--width", "64", "--height", "48", "--fps", "2", "--camera", "side"]
    commands = {
        "run": ["run", str(path), "--set", dur, "--out", str(d / "run")],
        "report": ["report", str(d / "run")],
        "solve": ["solve", str(path)],
        "render": ["render", str(path), "--duration", f"{duration:g}", "-o", str(d / "live.gif"), *video],
        "replay": ["render", str(d / "run"), "-o", str(d / "replay.gif"), *video],
        "sweep": ["sweep", str(path), "--set", dur, "--vary", f"simulation.duration={duration / 2:g},{duration:g}",
                  "--keep-cases", "--out", str(d / "sweep")],
        "sweep_report": ["report", str(d / "sweep")],
    }
    row = {"example": name}
    for what, argv in commands.items():
        t0 = time.perf_counter()
        rc, out, err = _call(argv)
        last = (err.strip().splitlines() or [""])[-1]
        ok = rc == 0 or (what == "solve" and rc == 1 and "mjtether solve:" in last)
        if what == "sweep" and rc == 0:
            import csv
            with open(d / "sweep" / "cases.csv") as fh:
                statuses = [r["status"] for r in csv.DictReader(fh)]
            ok = statuses == ["ok", "ok"]
            last = last if ok else f"cases: {statuses}"
        row[what] = {"rc": rc, "ok": ok, "wall_s": round(time.perf_counter() - t0, 2),
                     "message": "" if rc == 0 else last}
    return row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=2.0, help="simulated seconds of each run (default 2)")
    ap.add_argument("--only", nargs="*", help="examples by name (default_walker, networks/rov_cage_excursion)")
    ap.add_argument("--json", action="store_true", help="print the table as JSON")
    args = ap.parse_args(argv)
    paths = [p for p in examples() if not args.only
             or p.relative_to(ROOT / "examples").with_suffix("").as_posix() in args.only]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for p in paths:
            row = check(p, args.duration, Path(tmp))
            rows.append(row)
            if not args.json:
                cells = "  ".join(f"{k} {'ok' if v['ok'] else 'FAIL'} ({v['wall_s']:.0f} s)"
                                  for k, v in row.items() if k != "example")
                print(f"{row['example']:36s} {cells}", flush=True)
                for k, v in row.items():
                    if k != "example" and v["message"]:
                        print(f"    {k}: rc {v['rc']}: {v['message'][:300]}", flush=True)
    if args.json:
        print(json.dumps(rows, indent=1))
    return 0 if all(v["ok"] for r in rows for k, v in r.items() if k != "example") else 1


if __name__ == "__main__":
    sys.exit(main())

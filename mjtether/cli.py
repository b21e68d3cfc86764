"""Command line: ``mjtether demo``."""

from __future__ import annotations

import argparse
import sys

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
    args = ap.parse_args(argv)
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


if __name__ == "__main__":
    sys.exit(main())

"""The README's picture: the HTML report of the built-in scenario, as headless Chromium shows it.

    python scripts/make_report_screenshot.py [--results DIR] [--at 40] [--out docs/report_screenshot.png]

Runs the built-in scenario (``mjtether run --report``; about two minutes) into a temporary folder
unless ``--results`` names a results folder already made, writes its ``report.html`` and has
headless Chromium (``chromium``, ``chromium-browser`` or ``google-chrome``; on Debian ``apt-get
install chromium``; WebGL by SwiftShader) open it from disk at ``--at`` seconds of the run and save
a 1280 x 800 screenshot.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
FLAGS = ["--headless=new", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
         "--no-first-run", "--no-default-browser-check", "--disable-extensions", "--hide-scrollbars",
         "--proxy-server=127.0.0.1:9", "--window-size=1280,800", "--virtual-time-budget=4000"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", type=Path, help="a results folder of mjtether run (default: run the built-in scenario)")
    ap.add_argument("--at", type=float, default=40.0, help="the time of the run shown (s, default 40)")
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "report_screenshot.png")
    args = ap.parse_args(argv)
    browser = next((shutil.which(b) for b in BROWSERS if shutil.which(b)), None)
    if browser is None:
        sys.exit("no chromium found: apt-get install chromium")
    from mjtether.io.report import write_report

    with tempfile.TemporaryDirectory(prefix="mjtether-report-shot-") as tmp:
        folder = args.results
        if folder is None:
            folder = Path(tmp) / "results"
            subprocess.run([sys.executable, "-m", "mjtether.cli", "run", "--out", str(folder)], check=True)
        page = write_report(folder, Path(tmp) / "report.html")
        args.out.parent.mkdir(parents=True, exist_ok=True)
        subprocess.run([browser, *FLAGS, f"--user-data-dir={Path(tmp) / 'profile'}",
                        f"--screenshot={args.out.resolve()}", page.as_uri() + f"#t={args.at:g}"],
                       check=True, capture_output=True, timeout=120)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

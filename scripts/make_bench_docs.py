"""Benchmark numbers in README.md and docs/*.md (the site's performance page, docs/performance.md,
gathers them all), from the committed JSON in docs/bench/.

Every number in the docs that a benchmark measures sits inside a marker (an HTML comment, which
GitHub does not show)::

    <!--bench:bench_render.render_fps_tuned:.0f-->57<!--/bench-->

``bench_render`` names ``docs/bench/bench_render.json``; ``render_fps_tuned`` is a key of the
benchmark's own ``--json`` object (``result`` in the file; dots go deeper, an integer picks a
list item: ``bench_tether.realtime_factor.3``); ``@`` instead of the first dot reads the
``measured`` block written beside it (``bench_render@date``, ``bench_render@machine.cpu_count``);
the optional part after ``:`` is a Python format spec (``.0f``, ``,.0f``, ``+.2%``; none: ``str``).

    python scripts/make_bench_docs.py                 # rewrite the markers from docs/bench/*.json
    python scripts/make_bench_docs.py --check         # exit 1 listing markers that differ
    python scripts/make_bench_docs.py --measure NAME  # run a benchmark (see RUNS), write its JSON

``--measure`` runs the benchmark with ``--json`` in this interpreter and writes
``docs/bench/NAME.json`` = ``{"result": <the benchmark's JSON, unchanged>, "measured": {date,
command, wall time, machine, versions}}``; then run without options to update the docs.
"""

from __future__ import annotations

import argparse
import datetime
import importlib.metadata
import json
import os
import platform
import re
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BENCH_DIR = ROOT / "docs" / "bench"

# The files whose markers this script owns: README.md and docs/*.md but docs/scenarios.md, which
# make_scenario_docs.py writes from the code.
GENERATED_ELSEWHERE = {"scenarios.md"}


def doc_files() -> list[Path]:
    return [ROOT / "README.md"] + sorted(p for p in (ROOT / "docs").glob("*.md") if p.name not in GENERATED_ELSEWHERE)


# NAME -> (arguments after the interpreter, a note for the JSON when the options differ from the
# benchmark's defaults). The benchmarks take minutes on 2 cores; each runs once.
RUNS: dict[str, tuple[list[str], str]] = {
    "bench_render": (["scripts/bench_render.py", "--json"], ""),
    "bench_envs": (["scripts/bench_envs.py", "--json"], ""),
    "bench_envs_frame_skip_1": (["scripts/bench_envs.py", "--frame-skip", "1", "--json"],
                                "frame_skip 1 instead of the environment's default 10"),
    "bench_quasistatic": (["scripts/bench_quasistatic.py", "--json"], ""),
    "bench_scenario": (["scripts/bench_scenario.py", "--check", "--json"], ""),
    "bench_scenario_vehicles": (["scripts/bench_scenario.py", "--vehicles", "--json"], "the vehicle cases"),
    "bench_tether": (["scripts/bench_tether.py", "--json"], ""),
    "bench_rollout": (["scripts/bench_rollout.py", "--json"], ""),
    "bench_kernel_choice": (["scripts/bench_kernel_choice.py", "--json"], ""),
    "bench_constructions": (["scripts/bench_constructions.py", "--json"], ""),
    "bench_moordyn": (["scripts/bench_moordyn.py", "--json"], ""),
    "bench_waves": (["scripts/bench_waves.py", "--json"], ""),
    "bench_tangle": (["scripts/bench_tangle.py", "--json"], ""),
}

MARKER = re.compile(r"<!--bench:(?P<ref>[^>]*?)-->(?P<text>.*?)<!--/bench-->")
REF = re.compile(r"(?P<name>[A-Za-z0-9_]+)(?P<sep>[.@])(?P<path>[A-Za-z0-9_.-]+)(?::(?P<fmt>.*))?$")


@dataclass
class Marker:
    file: Path
    line: int
    ref: str
    text: str
    value: str | None  # the text the JSON gives; None with ``error``
    error: str | None = None

    def where(self) -> str:
        return f"{_rel(self.file)}:{self.line}"


def _rel(path: Path) -> Path:
    return path.relative_to(ROOT) if path.is_relative_to(ROOT) else path


def load(name: str, bench_dir: Path = BENCH_DIR) -> dict:
    return json.loads((bench_dir / f"{name}.json").read_text())


def value_of(ref: str, bench_dir: Path = BENCH_DIR) -> str:
    """The text a marker's reference gives; ValueError saying what is wrong."""
    m = REF.match(ref)
    if "--" in ref or ref.endswith("-"):  # CommonMark ends or breaks the comment there
        raise ValueError(f"{ref!r}: a marker may not contain '--' or end with '-'")
    if not m:
        raise ValueError(f"bad reference {ref!r} (NAME.KEY[:FORMAT] or NAME@KEY[:FORMAT])")
    path = bench_dir / f"{m['name']}.json"
    if not path.is_file():
        raise ValueError(f"no file {_rel(path)}")
    obj = json.loads(path.read_text())
    node = obj["result"] if m["sep"] == "." else obj["measured"]
    for part in m["path"].split("."):
        if isinstance(node, list) and part.isdigit() and int(part) < len(node):
            node = node[int(part)]
        elif isinstance(node, dict) and part in node:
            node = node[part]
        else:
            raise ValueError(f"{path.name} has no key {m['path']!r} in {'result' if m['sep'] == '.' else 'measured'}")
    if isinstance(node, (dict, list)):
        raise ValueError(f"{path.name}: {m['path']!r} is not a single value")
    fmt = m["fmt"] or ""
    try:
        return format(node, fmt) if fmt else str(node)
    except (ValueError, TypeError) as e:
        raise ValueError(f"format {fmt!r} does not apply to {node!r}: {e}") from None


def markers(files: list[Path] | None = None, bench_dir: Path = BENCH_DIR) -> list[Marker]:
    out = []
    for f in files if files is not None else doc_files():
        for i, line in enumerate(f.read_text().splitlines(), 1):
            for m in MARKER.finditer(line):
                try:
                    out.append(Marker(f, i, m["ref"], m["text"], value_of(m["ref"], bench_dir)))
                except ValueError as e:
                    out.append(Marker(f, i, m["ref"], m["text"], None, str(e)))
    return out


def problems(files: list[Path] | None = None, bench_dir: Path = BENCH_DIR) -> list[str]:
    """One line per marker that names no JSON value or whose text is not that value."""
    out = []
    for mk in markers(files, bench_dir):
        if mk.error:
            out.append(f"{mk.where()}: {mk.ref}: {mk.error}")
        elif mk.text != mk.value:
            out.append(f"{mk.where()}: {mk.ref}: the text is {mk.text!r}, docs/bench gives {mk.value!r}")
    return out


def rewrite(files: list[Path] | None = None, bench_dir: Path = BENCH_DIR) -> list[Path]:
    """Put the JSON's values into the markers; the files that changed. Markers with errors are
    left as they are (``problems`` names them)."""
    changed = []
    for f in files if files is not None else doc_files():
        old = f.read_text()

        def sub(m):
            try:
                return f"<!--bench:{m['ref']}-->{value_of(m['ref'], bench_dir)}<!--/bench-->"
            except ValueError:
                return m[0]

        new = MARKER.sub(sub, old)
        if new != old:
            f.write_text(new)
            changed.append(f)
    return changed


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _commit() -> str | None:
    """HEAD, with ``+dirty`` when tracked files differ from it (the numbers are of the work tree)."""
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True,
                              check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                               capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None
    return head + ("+dirty" if dirty else "")


_NO_LOAD = object()


def measured_block(command: str, wall_s: float, loadavg_before=_NO_LOAD) -> dict:
    """The ``measured`` block of a JSON file of numbers shown in the docs: date, ``command``,
    commit, ``wall_s`` (s), machine (with ``loadavg_before`` where given), Python, MuJoCo and
    mjtether versions (the reproduction scripts write the same block)."""
    machine = {"platform": platform.platform(), "cpu": _cpu_model(), "cpu_count": os.cpu_count()}
    if loadavg_before is not _NO_LOAD:
        machine["loadavg_before"] = loadavg_before
    return {"date": datetime.date.today().isoformat(), "command": command, "commit": _commit(),
            "wall_s": round(wall_s, 1), "machine": machine, "python": platform.python_version(),
            "mujoco": importlib.metadata.version("mujoco"), "mjtether": importlib.metadata.version("mjtether")}


def measure(name: str, bench_dir: Path = BENCH_DIR) -> Path:
    """Run benchmark ``name`` of RUNS once and write docs/bench/NAME.json."""
    args, note = RUNS[name]
    load_before = [round(x, 2) for x in os.getloadavg()] if hasattr(os, "getloadavg") else None
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, *args], cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        sys.exit(f"{' '.join(args)} failed ({r.returncode}):\n{r.stderr[-3000:]}")
    lines = [ln for ln in r.stdout.splitlines() if ln.strip()]
    result = json.loads(lines[-1])
    measured = measured_block("python " + " ".join(args), wall, loadavg_before=load_before)
    if note:
        measured["note"] = note
    bench_dir.mkdir(parents=True, exist_ok=True)
    out = bench_dir / f"{name}.json"
    out.write_text(json.dumps({"result": result, "measured": measured}, indent=1) + "\n")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="change nothing; exit 1 listing stale or broken markers")
    ap.add_argument("--measure", nargs="+", metavar="NAME", choices=sorted(RUNS),
                    help="run these benchmarks and write docs/bench/NAME.json (then rewrite the docs)")
    args = ap.parse_args(argv)
    if args.check:
        bad = problems()
        for line in bad:
            print(line)
        if bad:
            print(f"{len(bad)} stale or broken marker(s): run python scripts/make_bench_docs.py", file=sys.stderr)
            return 1
        print(f"{len(markers())} benchmark markers match docs/bench/*.json")
        return 0
    for name in args.measure or ():
        print(f"measuring {name}: python {' '.join(RUNS[name][0])}", flush=True)
        out = measure(name)
        print(f"  wrote {out.relative_to(ROOT)} ({load(name)['measured']['wall_s']} s)", flush=True)
    for f in rewrite():
        print(f"rewrote {_rel(f)}")
    bad = problems()
    for line in bad:
        print(line, file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

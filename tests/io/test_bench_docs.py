"""Benchmark numbers in README.md and docs/ come from the committed benchmark JSON (docs/bench/),
through markers that scripts/make_bench_docs.py fills; fast (reads files only)."""

from __future__ import annotations

import importlib.util
import json
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("make_bench_docs", ROOT / "scripts" / "make_bench_docs.py")
mbd = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("make_bench_docs", mbd)  # dataclasses look their module up there
_spec.loader.exec_module(mbd)


def test_markers_match_committed_json():
    """What ``python scripts/make_bench_docs.py --check`` checks: every marker names a JSON file
    and key in docs/bench/ and its text is that value, formatted as the marker says."""
    assert mbd.markers(), "no benchmark markers found in README.md and docs/"
    bad = mbd.problems()
    assert not bad, "stale or broken benchmark numbers (run python scripts/make_bench_docs.py):\n" + "\n".join(bad)


def test_check_mode_exit_code(capsys):
    assert mbd.main(["--check"]) == 0


def test_every_marker_names_an_existing_file_and_key():
    for mk in mbd.markers():
        m = mbd.REF.match(mk.ref)
        assert m, f"{mk.where()}: bad marker {mk.ref!r}"
        assert (mbd.BENCH_DIR / f"{m['name']}.json").is_file(), f"{mk.where()}: no docs/bench/{m['name']}.json"
        assert mk.error is None, f"{mk.where()}: {mk.error}"


def test_committed_json_files_have_the_wrapper():
    files = sorted(mbd.BENCH_DIR.glob("*.json"))
    assert files
    for f in files:
        d = json.loads(f.read_text())
        assert set(d) == {"result", "measured"}, f.name
        assert isinstance(d["result"], dict) and d["result"], f.name
        for key in ("date", "command", "machine", "mujoco"):
            assert key in d["measured"], f"{f.name}: measured.{key}"
        assert {"platform", "cpu_count"} <= set(d["measured"]["machine"]), f.name
        assert f.stem in mbd.RUNS, f"{f.name}: not a run that make_bench_docs.py --measure knows"


def test_check_finds_stale_and_broken_markers(tmp_path):
    bench = tmp_path / "bench"
    bench.mkdir()
    (bench / "bench_x.json").write_text(json.dumps(
        {"result": {"fps": 56.78, "list": [1.5, 2.5], "n": 3}, "measured": {"date": "2026-01-02"}}))
    doc = tmp_path / "doc.md"
    doc.write_text("a <!--bench:bench_x.fps:.0f-->57<!--/bench--> fps, b <!--bench:bench_x.list.1-->2.5<!--/bench-->,\n"
                   "c <!--bench:bench_x@date-->2026-01-01<!--/bench-->, d <!--bench:bench_x.nokey-->1<!--/bench-->,\n"
                   "e <!--bench:bench_y.fps-->1<!--/bench-->, f <!--bench:bench_x.n:.1%-->300.0%<!--/bench-->\n")
    bad = mbd.problems([doc], bench)
    assert len(bad) == 3 and "2026-01-02" in bad[0] and "nokey" in bad[1] and "bench_y.json" in bad[2], bad
    assert mbd.rewrite([doc], bench) == [doc]
    assert "<!--bench:bench_x@date-->2026-01-02<!--/bench-->" in doc.read_text()
    assert len(mbd.problems([doc], bench)) == 2  # the two that name nothing are left as they were


# Benchmark-like quantities: a number followed by one of these units. Such a number must sit inside
# a marker (the markers are cut out of the line before the search).
UNQUOTED = re.compile(
    r"\d\s*(?:x|×|times)\s*(?:faster|slower|real[- ]time)"
    r"|real[- ]time factor (?:of )?\d"
    r"|\d\s*(?:fps|frames/s|frames per second)\b"
    r"|\d\s*(?:\w+\s+)?steps/s\b|\d\s*(?:\w+\s+)?steps per second"
    r"|\d\s*(?:us|µs|μs)(?:/| per | a )step"
    r"|\d\s*ms\b",
    re.IGNORECASE)
# the few legitimate uses that are not benchmark results: (file name, regex of the allowed text)
ALLOWED = [
    ("learning.md", r"MuJoCo steps of 10 ms"),  # the environments' time step, a setting
    ("learning.md", r"MuJoCo steps of 5 ms"),  # TetheredROV-v0's time step, a setting
]


@pytest.mark.parametrize("path", mbd.doc_files(), ids=lambda p: p.name)
def test_no_benchmark_number_outside_a_marker(path):
    bad = []
    for i, line in enumerate(path.read_text().splitlines(), 1):
        text = mbd.MARKER.sub("BENCH", line)
        for name, allowed in ALLOWED:
            if path.name == name:
                text = re.sub(allowed, "", text)
        for m in UNQUOTED.finditer(text):
            bad.append(f"{path.relative_to(ROOT)}:{i}: {m[0]!r} in {line.strip()[:120]!r}")
    assert not bad, ("benchmark numbers must come from docs/bench/*.json through a marker "
                     "(see scripts/make_bench_docs.py):\n" + "\n".join(bad))


def test_unquoted_pattern_examples():
    for s in ("about 57 fps", "200–230 steps/s", "2 000 MuJoCo steps/s", "20× real time", "9.5x real time",
              "58 us/step", "35 us a step", "7.1 ms", "real-time factor 12"):
        assert UNQUOTED.search(s), s
    for s in ("--fps", "1/160 s", "`--fps 30`", "0.3 m/s", "mms"):
        assert not UNQUOTED.search(s), s

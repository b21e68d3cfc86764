"""The paper-reproduction pages quote their scripts' committed JSON (docs/reproductions/), as the
benchmark pages quote docs/bench/ (tests/io/test_bench_docs.py); fast: reads files, runs no
simulation.

Each number a reproduction script computes sits in its page in a marker
``<!--repro:NAME.KEY:FORMAT-->text<!--/repro-->``, the syntax of scripts/make_bench_docs.py's
``bench`` markers with NAME a file of docs/reproductions/ (``@`` reads its ``measured`` block).
The answer each check compares with is the JSON the script wrote when it ran, formatted by
Python's ``format`` with the marker's spec: an exact string comparison, no tolerance. To
regenerate a page after changing only its prose: ``python scripts/reproduce_001.py --render``
(or ``reproduce_khan2023.py --render``); after changing the physics, run the script without
options (it rewrites the JSON, then the page).
"""

from __future__ import annotations

import importlib.util
import json
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
REPRO_DIR = ROOT / "docs" / "reproductions"


def _load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault(name, mod)  # dataclasses look their module up there
    spec.loader.exec_module(mod)
    return sys.modules[name]


mbd = _load("make_bench_docs", ROOT / "scripts" / "make_bench_docs.py")

# page -> (the JSON's NAME, the script that writes both)
PAGES = {
    "auv_fibre_reproduction.md": ("auv_fibre", "reproduce_001.py"),
    "khan2023_reproduction.md": ("khan2023", "reproduce_khan2023.py"),
}
MARKER = re.compile(r"<!--repro:(?P<ref>[^>]*?)-->(?P<text>.*?)<!--/repro-->")
# digits in a table that are names, not numbers: (page, regex of the allowed text)
ALLOWED = [("auv_fibre_reproduction.md", r"REMUS 100")]


def problems(doc: Path, name: str, repro_dir: Path = REPRO_DIR) -> tuple[int, list[str]]:
    """(markers found, one line per marker that names no value of ``name``'s JSON or whose text
    is not that value formatted as the marker says)."""
    n, bad = 0, []
    for i, line in enumerate(doc.read_text().splitlines(), 1):
        for m in MARKER.finditer(line):
            n += 1
            where = f"{doc.name}:{i}: {m['ref']}"
            if not m["ref"].startswith((name + ".", name + "@")):
                bad.append(f"{where}: names another file than {name}.json")
                continue
            try:
                want = mbd.value_of(m["ref"], repro_dir)
            except ValueError as e:
                bad.append(f"{where}: {e}")
                continue
            if m["text"] != want:
                bad.append(f"{where}: the text is {m['text']!r}, {name}.json gives {want!r}")
    return n, bad


def bare_numbers_in_tables(doc: Path) -> list[str]:
    """Digits in a table's cells outside the markers (header rows and the inputs table's
    ``source`` column, the paper's words and our assumptions, excepted)."""
    lines = doc.read_text().splitlines()
    bad, skip = [], set()
    for i, line in enumerate(lines):
        if not line.startswith("|"):
            skip = set()
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if i + 1 < len(lines) and lines[i + 1].startswith("|---"):  # a header row
            skip = {k for k, c in enumerate(cells) if c == "source"}
            continue
        if line.startswith("|---"):
            continue
        text = mbd.MARKER.sub("", MARKER.sub("", line))
        for page, allowed in ALLOWED:
            text = re.sub(allowed, "", text) if doc.name == page else text
        for k, c in enumerate(c.strip() for c in text.strip().strip("|").split("|")):
            if k not in skip and re.search(r"\d", c):
                bad.append(f"{doc.name}:{i + 1}: cell {k + 1} {c!r}")
    return bad


@pytest.mark.parametrize("page", sorted(PAGES))
def test_every_marker_is_its_json_value(page):
    name, _ = PAGES[page]
    n, bad = problems(ROOT / "docs" / page, name)
    assert n >= 50, f"{page}: only {n} markers"
    assert not bad, (f"stale or broken numbers in docs/{page} (run python scripts/{PAGES[page][1]} "
                     "--render, or without options to measure again):\n" + "\n".join(bad))


@pytest.mark.parametrize("page", sorted(PAGES))
def test_no_bare_number_in_a_table_cell(page):
    bad = bare_numbers_in_tables(ROOT / "docs" / page)
    assert not bad, "numbers in tables must come from the JSON through a marker:\n" + "\n".join(bad)


@pytest.mark.parametrize("page", sorted(PAGES))
def test_the_page_is_what_its_script_renders_from_the_json(page):
    """The prose too (the Khan page's timing paragraph had drifted from the script's): the page
    is byte for byte what ``render()`` makes of the committed JSON (and, for the timings, of
    docs/bench/bench_quasistatic.json)."""
    name, script = PAGES[page]
    mod = _load(script[:-3], ROOT / "scripts" / script)
    assert (ROOT / "docs" / page).read_text() == mod.render(), (
        f"docs/{page} is not what scripts/{script} writes: run python scripts/{script} --render")


@pytest.mark.parametrize("page", sorted(PAGES))
def test_the_json_says_where_and_when_it_was_made(page):
    name, script = PAGES[page]
    d = json.loads((REPRO_DIR / f"{name}.json").read_text())
    assert set(d) == {"result", "measured"}
    assert isinstance(d["result"], dict) and d["result"]
    for key in ("date", "command", "commit", "wall_s", "machine", "mujoco", "mjtether"):
        assert key in d["measured"], f"{name}.json: measured.{key}"
    assert {"platform", "cpu_count"} <= set(d["measured"]["machine"])
    assert d["measured"]["command"].startswith(f"python scripts/{script}")
    assert "--quick" not in d["measured"]["command"], "the page shows the full run"


def test_the_checks_find_stale_broken_and_bare_numbers(tmp_path):
    """The checkers themselves, on a page written here: a stale value, a missing key, a marker
    of another file and a bare number in a table are each reported; the good ones are not."""
    (tmp_path / "x.json").write_text(json.dumps(
        {"result": {"T": [1.234, 5.0], "case": "calm 0.35 m/s"}, "measured": {"date": "2026-01-02"}}))
    doc = tmp_path / "x.md"
    doc.write_text("made <!--repro:x@date-->2026-01-02<!--/repro-->\n\n"
                   "| case | T (N) | source |\n|---|---|---|\n"
                   "| <!--repro:x.case-->calm 0.35 m/s<!--/repro--> | <!--repro:x.T.0:.2f-->1.23<!--/repro--> | 5 N |\n"
                   "| b | <!--repro:x.T.1:.1f-->5.1<!--/repro--> | <!--repro:x.nokey-->1<!--/repro--> |\n"
                   "| c 2 | <!--repro:y.T.0-->1<!--/repro--> | quoted 3 |\n")
    n, bad = problems(doc, "x", tmp_path)
    assert n == 6 and len(bad) == 3, bad
    assert "'5.1'" in bad[0] and "'5.0'" in bad[0] and "nokey" in bad[1] and "another file" in bad[2], bad
    assert bare_numbers_in_tables(doc) == ["x.md:7: cell 1 'c 2'"]

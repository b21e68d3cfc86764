"""``mjtether sweep --keep-cases``: each case that ran ok keeps its whole results folder as
``DIR/cases/<case>/``, and the sweep's report links each such case to its own report.

The figures compared here are the same run's, written twice (a row of ``cases.csv`` and the
case's own ``summary.json``), or the same deterministic case run twice (``--jobs 1`` and
``--jobs 2``; a resumed case): so they must agree exactly, to the last bit. The one looser check
is against the case's ``timeseries.csv``, whose values the writer rounds to 9 significant
figures (so to 1e-8 relative), an account of the peak independent of the summary's.
"""

import csv
import hashlib
import json
import re
import shutil

import numpy as np
import pytest

from mjtether import sweep
from mjtether.cli import main
from mjtether.files.outdir import MANIFEST, foreign_content

ANCHOR = """\
[simulation]
duration = 2.0
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
LENGTHS = ["--vary", "tether.length=110,120", "--set", "simulation.duration=2"]
# (a rated load of 1 N fails its cases at the first step: cases 0 and 1 fail, 2 and 3 run)
WITH_FAILURES = ["--vary", "tether.rated_load=1,1e9", *LENGTHS]
SAME_RUN = ("timeseries.csv", "summary.json", "lines.npz")


@pytest.fixture(scope="module")
def scenario(tmp_path_factory):
    p = tmp_path_factory.mktemp("scenario") / "s.toml"
    p.write_text(ANCHOR)
    return p


@pytest.fixture(scope="module")
def kept(scenario, tmp_path_factory):
    """A ``--keep-cases --report`` sweep of four cases, two failing, in this process."""
    out = tmp_path_factory.mktemp("kept") / "sw"
    assert main(["sweep", str(scenario), *WITH_FAILURES, "--keep-cases", "--report", "--out", str(out)]) == 0
    return out


def _rows(folder):
    with open(folder / "cases.csv", newline="") as fh:
        return list(csv.DictReader(fh))


def test_each_ok_case_keeps_its_folder_with_the_rows_figures(kept):
    rows = _rows(kept)
    assert [r["status"] for r in rows] == ["failed", "failed", "ok", "ok"]
    assert sorted(p.name for p in (kept / "cases").iterdir()) == ["2", "3"]  # a failed case has none
    assert json.loads((kept / "sweep.json").read_text())["case_folders"] == [2, 3]
    for r in rows[2:]:
        case = kept / "cases" / r["case"]
        summary = json.loads((case / "summary.json").read_text())
        # the case's own scenario: this row's tether length
        assert summary["scenario"]["tether"]["length"] == float(r["tether.length_m"])
        for figure, key in (("peak_ship_tension_N", "ship_tension_N"), ("peak_tow_tension_N", "tow_tension_N")):
            assert float(r[figure]) == summary["peak"][key]  # exact: one run, both written as repr
        for figure, key in (("final_ship_tension_N", "ship_tension_N"), ("final_tow_tension_N", "tow_tension_N")):
            assert float(r[figure]) == summary["final"][key]
        with open(case / "timeseries.csv", newline="") as fh:
            ship = [float(s["ship_tension_N"]) for s in csv.DictReader(fh)]
        assert max(ship) == pytest.approx(float(r["peak_ship_tension_N"]), rel=1e-8)  # .9g in the CSV


def test_the_report_links_each_ok_case_to_its_own_report(kept):
    page = (kept / "report.html").read_text()
    links = re.findall(r'<a href="([^"]+)"', page)
    assert links == ["cases/2/report.html", "cases/3/report.html"]
    for link in links:  # each resolves to a report of that case, an mjtether page
        assert '<meta name="generator" content="mjtether report">' in (kept / link).read_text()[:4096]
    body = page[page.index("<tbody>"):page.index("</tbody>")]
    for tr in re.findall(r"<tr>.*?</tr>", body)[:2]:  # the failed cases: no link, their status and error
        assert "<a " not in tr and 'class="failed">failed<' in tr and "rated load 1 N" in tr
    assert "--keep-cases" not in page[:page.index("<tbody>")]  # (the links are there: no hint needed)


def test_the_folder_is_still_an_mjtether_result(kept, scenario, tmp_path):
    """Every file, the case reports too, in the sweep's manifest with its current hash; so
    ``--overwrite`` replaces it (a copy: the other tests read ``kept``); the new sweep without
    ``--keep-cases`` keeps no case folders, and its page says how to get the links."""
    m = json.loads((kept / MANIFEST).read_text())["files"]
    on_disk = {p.relative_to(kept).as_posix() for p in kept.rglob("*") if p.is_file()} - {MANIFEST}
    assert set(m) == on_disk and "cases/2/report.html" in m
    for name, entry in m.items():
        assert entry["sha256"] == hashlib.sha256((kept / name).read_bytes()).hexdigest(), name
    assert foreign_content(kept) is None
    again = tmp_path / "sw"
    shutil.copytree(kept, again)
    assert main(["sweep", str(scenario), "--vary", "tether.length=110", "--set", "simulation.duration=2",
                 "--overwrite", "--report", "--out", str(again)]) == 0
    assert not (again / "cases").exists()
    page = (again / "report.html").read_text()
    assert "<a href" not in page and "--keep-cases" in page


def test_two_jobs_write_the_same_case_folders_as_one(scenario, tmp_path):
    """One case runs in a worker process and one here; each folder's numbers are those of
    ``--jobs 1`` bit for bit (the same deterministic run)."""
    one, two = tmp_path / "one", tmp_path / "two"
    for out, jobs in ((one, "1"), (two, "2")):
        assert main(["sweep", str(scenario), *LENGTHS, "--keep-cases", "--jobs", jobs, "--out", str(out)]) == 0
    for i in ("0", "1"):
        a, b = one / "cases" / i, two / "cases" / i
        assert (a / "timeseries.csv").read_text() == (b / "timeseries.csv").read_text()
        sa, sb = (json.loads((f / "summary.json").read_text()) for f in (a, b))
        for key in ("scenario", "peak", "final", "lines", "samples"):
            assert sa[key] == sb[key], key
        with np.load(a / "lines.npz") as na, np.load(b / "lines.npz") as nb:
            assert sorted(na.files) == sorted(nb.files)
            for name in na.files:
                assert np.array_equal(na[name], nb[name]), name
    skip = {"wall_s", "started_at"}
    assert [{k: v for k, v in r.items() if k not in skip} for r in _rows(one)] == \
        [{k: v for k, v in r.items() if k not in skip} for r in _rows(two)]


def _interrupt_after_one(monkeypatch):
    """``run_case`` that runs one case, then stops the sweep as a Ctrl-C does; returns its calls."""
    real = sweep.run_case
    calls = []

    def run_case(sc, *folder):
        if calls:
            raise KeyboardInterrupt
        calls.append(sc.tether.length)
        return real(sc, *folder)

    monkeypatch.setattr(sweep.execute, "run_case", run_case)
    return calls


def _counting(monkeypatch):
    real = sweep.run_case
    calls = []
    monkeypatch.setattr(sweep.execute, "run_case", lambda sc, *folder: calls.append(sc.tether.length)
                        or real(sc, *folder))
    return calls


def test_resume_keeps_folders_and_reruns_a_case_finished_without_one(scenario, tmp_path, monkeypatch, capsys):
    """A case an interrupted ``--keep-cases`` sweep finished is not run again (its folder is in
    the progress folder); one finished by a sweep without ``--keep-cases`` is, for its folder,
    and gives the same figures (a deterministic run)."""
    for first, reruns in ((["--keep-cases"], 1), ([], 2)):
        out = tmp_path / f"sw{len(first)}"
        args = ["sweep", str(scenario), *LENGTHS, "--out", str(out)]
        _interrupt_after_one(monkeypatch)
        assert main(args + first) == 130
        [done] = [json.loads(p.read_text())["record"] for p in (sweep.progress_folder(out) / "cases").glob("*.json")]
        calls = _counting(monkeypatch)
        assert main(args + ["--keep-cases"]) == 0
        assert len(calls) == reruns
        if reruns == 2:
            assert "without their folder" in capsys.readouterr().out
        rows = _rows(out)
        assert sorted(p.name for p in (out / "cases").iterdir()) == ["0", "1"]
        [row] = [r for r in rows if float(r["peak_ship_tension_N"]) == done["peak_ship_tension_N"]]
        assert (row["started_at"] == done["started_at"]) == (reruns == 1)
        summary = json.loads((out / "cases" / row["case"] / "summary.json").read_text())
        assert summary["peak"]["ship_tension_N"] == done["peak_ship_tension_N"]


def test_keep_cases_with_ray_is_refused_before_anything_runs(scenario, tmp_path, capsys):
    out = tmp_path / "sw"
    assert main(["sweep", str(scenario), *LENGTHS, "--keep-cases", "--ray", "--out", str(out)]) == 2
    assert "--keep-cases" in capsys.readouterr().err and not out.exists()


def test_a_network_sweep_keeps_the_network_writers_folders(tmp_path):
    """A network's case folder is ``mjtether run``'s for a network (``"kind": "network"``), and
    its peak line tension (the largest over its lines of each line's peak in ``summary.json``)
    is the row's ``peak_tension_N``, and each line's peak and final end tensions the row's,
    exactly (one run)."""
    out = tmp_path / "net"
    assert main(["sweep", "networks/moored_buoy_body", "--vary", "simulation.duration=0.3,0.4", "--keep-cases",
                 "--out", str(out)]) == 0
    for r in _rows(out):
        summary = json.loads((out / "cases" / r["case"] / "summary.json").read_text())
        assert summary["kind"] == "network"
        assert float(r["peak_tension_N"]) == max(ln["peak_tension_N"] for ln in summary["lines"].values())
        for name, ln in summary["lines"].items():  # (the peak is at the start here: the ends too)
            for key in ("peak_tension_N", "final_A_tension_N", "final_B_tension_N"):
                assert float(r[f"line{name}_{key}"]) == ln[key], (name, key)
        assert (out / "cases" / r["case"] / "lines.npz").is_file()

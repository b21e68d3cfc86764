"""The report's command line (issue 44): ``mjtether report DIR [--out FILE]``, and ``--report``
on ``mjtether run`` (a scenario, a network) and ``mjtether sweep``, each writing the report of the
folder just written, once it is complete. The wiring is tested against a stand-in for
``mjtether.io.report`` that records its calls (so these tests do not depend on the report's
own page); one test runs the real module end to end, skipped where it is not installed."""

import json
import sys
import types
from pathlib import Path

import pytest
from helpers import small

from mjtether import cli

ANCHOR = """\
[simulation]
duration = 1.0
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


@pytest.fixture
def fake_report(monkeypatch):
    """A stand-in ``mjtether.io.report``: ``write_report`` records (folder, out, what the folder
    held when it was called) and writes ``report.html``; it raises ``ReportError`` for a folder
    named ``bad``."""
    mod = types.ModuleType("mjtether.io.report")

    class ReportError(ValueError):
        pass

    mod.ReportError, mod.calls = ReportError, []

    def write_report(folder, out=None):
        folder = Path(folder)
        mod.calls.append((folder, out, sorted(p.name for p in folder.iterdir()) if folder.is_dir() else None))
        if folder.name == "bad":
            raise ReportError(f"{str(folder)!r}: not an mjtether results folder")
        target = Path(out) if out is not None else folder / "report.html"
        target.write_text("<html></html>")
        return target

    mod.write_report = write_report
    monkeypatch.setitem(sys.modules, "mjtether.io.report", mod)
    return mod


def test_report_writes_the_file_and_prints_its_path(tmp_path, fake_report, capsys):
    (tmp_path / "res").mkdir()
    out = tmp_path / "r.html"
    assert cli.main(["report", str(tmp_path / "res"), "--out", str(out)]) == 0
    assert fake_report.calls == [(tmp_path / "res", str(out), [])]
    assert capsys.readouterr().out.strip() == f"report in {out}"


def test_report_of_a_folder_it_cannot_read_is_one_line_and_exit_2(tmp_path, fake_report, capsys):
    (tmp_path / "bad").mkdir()
    assert cli.main(["report", str(tmp_path / "bad")]) == 2
    said = capsys.readouterr()
    assert said.out == "" and said.err.strip().splitlines() == [
        f"mjtether report: no report written: {str(tmp_path / 'bad')!r}: not an mjtether results folder"]


def test_run_report_comes_after_the_results_folder_is_complete(tmp_path, fake_report, capsys):
    """``run --report``: the report is written of the finished folder (its summary.json already
    there), and its path printed after the run's closing line."""
    f = tmp_path / "s.toml"
    f.write_text(small(1.0))
    res = tmp_path / "res"
    assert cli.main(["run", str(f), "--out", str(res), "--no-plots", "--report"]) == 0
    [(folder, out, held)] = fake_report.calls
    assert folder.resolve() == res.resolve() and out is None and "summary.json" in held
    lines = capsys.readouterr().out.strip().splitlines()
    assert "results in" in lines[-2] and lines[-1] == f"report in {folder / 'report.html'}"


def test_run_without_report_writes_none(tmp_path, fake_report):
    f = tmp_path / "s.toml"
    f.write_text(small(0.5))
    assert cli.main(["run", str(f), "--out", str(tmp_path / "res"), "--no-plots"]) == 0
    assert fake_report.calls == []


def test_a_failed_report_keeps_the_results_and_exits_1(tmp_path, fake_report, capsys):
    f = tmp_path / "s.toml"
    f.write_text(small(0.5))
    res = tmp_path / "bad"
    assert cli.main(["run", str(f), "--out", str(res), "--no-plots", "--report"]) == 1
    assert (res / "summary.json").is_file()
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith(f"mjtether run: the results are in {res}/, no report written: ")


def test_network_run_report(tmp_path, fake_report, capsys):
    res = tmp_path / "net"
    assert cli.main(["run", "networks/moored_buoy_body", "--set", "simulation.duration=0.5", "--out", str(res),
                     "--no-plots", "--report"]) == 0
    [(folder, out, held)] = fake_report.calls
    assert folder == res and "summary.json" in held
    assert capsys.readouterr().out.strip().splitlines()[-1] == f"report in {res / 'report.html'}"


def test_sweep_report(tmp_path, fake_report, capsys):
    f = tmp_path / "s.toml"
    f.write_text(ANCHOR)
    res = tmp_path / "sw"
    assert cli.main(["sweep", str(f), "--vary", "tether.length=110,120", "--out", str(res), "--report"]) == 0
    [(folder, out, held)] = fake_report.calls
    assert folder == res and "cases.csv" in held
    assert capsys.readouterr().out.strip().splitlines()[-1] == f"report in {res / 'report.html'}"


def test_run_report_with_the_real_module(tmp_path, capsys):
    """End to end, where ``mjtether.io.report`` is there: a 1 s run's report is one HTML file in
    the results folder, at the path printed."""
    pytest.importorskip("mjtether.io.report")
    f = tmp_path / "s.toml"
    f.write_text(small(1.0))
    res = tmp_path / "res"
    assert cli.main(["run", str(f), "--out", str(res), "--no-plots", "--report"]) == 0
    path = Path(capsys.readouterr().out.strip().splitlines()[-1].removeprefix("report in "))
    assert path.parent.resolve() == res.resolve() and path.is_file()
    assert "<html" in path.read_text()[:2000].lower()
    assert json.loads((res / "summary.json").read_text())

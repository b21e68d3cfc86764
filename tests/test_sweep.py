"""mjtether sweep: cases, failures, bad --vary, resume, --out safety, Parquet, Ray."""

import csv
import json
import math
import os
import signal
import subprocess
import sys
import time

import pytest

from mjtether import sweep
from mjtether.cli import main
from mjtether.scenario.runner import RECORD_FIELDS, run
from mjtether.scenario import load_scenario

pq = pytest.importorskip("pyarrow.parquet", reason="mjtether sweep writes Parquet with pyarrow (extra 'sweep')")

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


@pytest.fixture
def scenario(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(ANCHOR)
    return p


def _rows(folder):
    with open(folder / "cases.csv", newline="") as fh:
        return list(csv.DictReader(fh))


def _sweep(scenario, out, *args):
    return main(["sweep", str(scenario), *args, "--out", str(out)])


def _nothing_written(tmp_path, out):
    assert not out.exists()
    assert not sweep.progress_folder(out).exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(f".{out.name}.")]


def test_product_sweep_in_two_processes_runs_the_cases_it_names(tmp_path, scenario, capsys):
    out = tmp_path / "sw"
    rc = _sweep(scenario, out, "--vary", "tether.length=110:120:2", "--vary", "tether.diameter=0.03,0.04",
                "--jobs", "2")
    assert rc == 0, capsys.readouterr().err
    rows = _rows(out)
    assert [(float(r["tether.length_m"]), float(r["tether.diameter_m"])) for r in rows] == [
        (110.0, 0.03), (110.0, 0.04), (120.0, 0.03), (120.0, 0.04)]
    assert [r["case"] for r in rows] == ["0", "1", "2", "3"]
    assert all(r["status"] == "ok" and r["error"] == "" for r in rows)
    for r in rows:
        assert float(r["peak_ship_tension_N"]) >= float(r["final_ship_tension_N"]) > 0
        assert float(r["final_deployed_length_m"]) == pytest.approx(float(r["tether.length_m"]))
        assert float(r["wall_s"]) > 0 and r["started_at"]
    # an independent run of case 3's scenario gives the same peak tension
    sc = load_scenario(scenario, overrides=["tether.length=120.0", "tether.diameter=0.04"])
    rows_ref, _, _ = run(sc, keep_nodes=False)
    peak = rows_ref[:, [n for n, _, _ in RECORD_FIELDS].index("ship_tension")].max()
    assert float(rows[3]["peak_ship_tension_N"]) == pytest.approx(peak, rel=1e-9, abs=0)
    # the Parquet file holds the same rows, typed
    table = pq.read_table(out / "cases.parquet").to_pylist()
    assert len(table) == len(rows)
    for t, r in zip(table, rows):
        assert list(t) == list(r)
        for k, v in t.items():
            if v is None:
                assert r[k] == ""
            elif isinstance(v, float):
                assert float(r[k]) == v or (math.isnan(v) and math.isnan(float(r[k])))
            else:
                assert str(v) == r[k]
    meta = json.loads((out / "sweep.json").read_text())
    assert meta["format"] == sweep.FORMAT and meta["cases"] == 4 and meta["ok"] == 4
    assert (out / "summary.png").stat().st_size > 1000
    assert (out / "mjtether-manifest.json").is_file()
    assert not sweep.progress_folder(out).exists()  # removed once the results are in place


def test_a_failing_case_is_recorded_and_the_others_finish(tmp_path, scenario, capsys):
    out = tmp_path / "sw"
    assert _sweep(scenario, out, "--vary", "tether.rated_load=1,1e9") == 0
    rows = _rows(out)
    assert [r["status"] for r in rows] == ["failed", "ok"]
    assert "rated load" in rows[0]["error"] and rows[0]["peak_ship_tension_N"] == ""
    assert float(rows[1]["peak_ship_tension_N"]) > 1
    assert "case 0 failed" in capsys.readouterr().out


def test_a_case_invalid_only_in_combination_is_recorded_as_failed(tmp_path, scenario):
    out = tmp_path / "sw"
    assert _sweep(scenario, out, "--vary", "water.depth=100,92",
                  "--vary", "robot.position=[40.0, 0.0, -90.0],[40.0, 0.0, -93.0]") == 0
    rows = _rows(out)
    assert [r["robot.position_m"] for r in rows] == ["[40.0, 0.0, -90.0]", "[40.0, 0.0, -93.0]"] * 2
    assert rows[3]["status"] == "failed" and "invalid case" in rows[3]["error"]
    assert "robot.position" in rows[3]["error"] and "below the seabed" in rows[3]["error"]
    assert rows[0]["status"] == rows[1]["status"] == "ok"


@pytest.mark.parametrize("vary, named", [
    (["tether.lenght=100,120"], "tether.lenght"),
    (["tether.length=1:2"], "tether.length=1:2"),
    (["tether.length=100:120:x"], "tether.length=100:120:x"),
    (["water=1,2"], "water"),
    (["tether.segments=2,10"], "tether.segments = 2"),
    (["tether.segments=10:20:4"], "tether.segments"),  # 13.33... is not an integer
    (["water.current.speed_kn=1,50"], "water.current.speed_kn = 50 kn"),
    (["tether.length=100,120", "tether.length=130"], "tether.length"),
    # invalid in every case, by another key of the file: the anchor is below this seabed
    (["water.depth=80,100", "tether.length=100,120"], "water.depth = 80"),
])
def test_bad_vary_is_one_line_naming_it_and_writes_nothing(tmp_path, scenario, capsys, vary, named):
    out = tmp_path / "sw"
    args = [a for v in vary for a in ("--vary", v)]
    assert _sweep(scenario, out, *args) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and err.startswith("mjtether sweep: ") and named in err, err
    _nothing_written(tmp_path, out)


def test_samples_are_reproducible_draws_within_the_ranges(scenario):
    varies = [sweep.parse_vary("tether.length=110:120:2"), sweep.parse_vary("tether.segments=8,10,12")]
    a = sweep.make_plan(scenario, varies, samples=20, seed=3)
    b = sweep.make_plan(scenario, varies, samples=20, seed=3)
    assert [c.values for c in a.cases] == [c.values for c in b.cases]
    assert len(a.cases) == 20 and all(110 <= c.values[0] <= 120 and c.values[1] in (8, 10, 12) for c in a.cases)
    assert len({c.values[0] for c in a.cases}) == 20
    assert all(c.sc is not None and c.sc.tether.length == c.values[0] for c in a.cases)


def test_resume_runs_only_the_unfinished_cases(tmp_path, scenario, monkeypatch, capsys):
    out = tmp_path / "sw"
    args = ["--vary", "tether.length=105:120:4"]
    real = sweep.run_case
    calls = []

    def interrupted(sc):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(sc.tether.length)
        return real(sc)

    monkeypatch.setattr(sweep.execute, "run_case", interrupted)
    assert _sweep(scenario, out, *args) == 130
    assert "rerun the same command to resume" in capsys.readouterr().err
    assert not out.exists()
    kept = sweep.progress_folder(out)
    journal = [json.loads(p.read_text()) for p in (kept / "cases").glob("*.json")]
    assert len(journal) == 2
    first = {j["overrides"][-1]: j["record"]["started_at"] for j in journal}

    calls.clear()
    monkeypatch.setattr(sweep.execute, "run_case", lambda sc: calls.append(sc.tether.length) or real(sc))
    assert _sweep(scenario, out, *args) == 0
    assert "2 from an earlier interrupted run" in capsys.readouterr().out
    assert len(calls) == 2  # only the two unfinished cases ran
    rows = _rows(out)
    assert len(rows) == 4 and all(r["status"] == "ok" for r in rows)
    again = {f"tether.length={r['tether.length_m']}": r["started_at"] for r in rows}
    for key, started in first.items():  # the finished ones were not run again
        assert again[key] == started
    assert not kept.exists()
    # a finished sweep is complete: the same command is refused, --overwrite runs it again
    assert _sweep(scenario, out, *args) == 2
    assert "--overwrite" in capsys.readouterr().err
    calls.clear()
    assert _sweep(scenario, out, *args, "--overwrite") == 0
    assert len(calls) == 4


def test_sigint_with_two_jobs_keeps_finished_cases_for_the_rerun(tmp_path, scenario, monkeypatch):
    out = tmp_path / "sw"
    args = ["--vary", "tether.length=105:120:6", "--set", "simulation.duration=8", "--jobs", "2"]
    cmd = [sys.executable, "-m", "mjtether.cli", "sweep", str(scenario), *args, "--out", str(out)]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # not ignored, as in `cmd &`
    cases = sweep.progress_folder(out) / "cases"
    deadline = time.monotonic() + 600  # (a hang guard: the first compile may take a minute or more)
    while not (cases.is_dir() and any(cases.glob("*.json"))) and proc.poll() is None:
        assert time.monotonic() < deadline
        time.sleep(0.02)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    if proc.returncode == 0:
        pytest.skip("the sweep finished before it could be interrupted")
    assert proc.returncode == 130, err
    assert "rerun the same command to resume" in err and "Traceback" not in err, err.replace("\r", "\n")
    assert not out.exists()
    done = len(list(cases.glob("*.json")))
    assert 1 <= done < 6
    real = sweep.run_case
    calls = []
    monkeypatch.setattr(sweep.execute, "run_case", lambda sc: calls.append(1) or real(sc))
    assert main(["sweep", str(scenario), *args[:-2], "--out", str(out)]) == 0
    assert len(calls) == 6 - done
    assert len(_rows(out)) == 6


def test_two_sweeps_into_one_folder_are_refused_and_restart_discards_progress(tmp_path, scenario, monkeypatch,
                                                                               capsys):
    out = tmp_path / "sw"
    other = sweep.Journal(out.resolve())
    other.open()  # another sweep holds it
    try:
        assert _sweep(scenario, out, "--vary", "tether.length=110,120") == 2
        assert "another mjtether sweep" in capsys.readouterr().err
    finally:
        other.close()
    real = sweep.run_case
    calls = []
    monkeypatch.setattr(sweep.execute, "run_case", lambda sc: calls.append(1) or real(sc))
    fake = {"status": "ok", "error": "", "peak_ship_tension_N": -1.0}
    case = sweep.make_plan(scenario, [sweep.parse_vary("tether.length=110,120")]).cases[0]
    other.open()
    other.add(case, fake)  # a finished case of an earlier, interrupted sweep
    other.close()
    assert _sweep(scenario, out, "--vary", "tether.length=110,120", "--restart") == 0
    assert len(calls) == 2 and float(_rows(out)[0]["peak_ship_tension_N"]) > 0


def test_user_folder_is_refused_and_left_untouched(tmp_path, scenario, capsys):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    for extra in ([], ["--overwrite"]):
        assert _sweep(scenario, out, "--vary", "tether.length=110,120", *extra) == 2
        err = capsys.readouterr().err
        assert "mine" in err and "\n" not in err.strip()
        assert [p.name for p in out.iterdir()] == ["notes.txt"]
    assert not sweep.progress_folder(out).exists()


def test_overwrite_replaces_only_an_earlier_sweep(tmp_path, scenario, capsys):
    res = tmp_path / "res"
    assert main(["run", str(scenario), "--out", str(res), "--no-plots"]) == 0
    assert _sweep(scenario, res, "--vary", "tether.length=110,120", "--overwrite") == 2
    assert "not a sweep" in capsys.readouterr().err
    assert (res / "timeseries.csv").is_file()


def test_a_foreign_progress_folder_is_refused(tmp_path, scenario, capsys):
    out = tmp_path / "sw"
    sweep.progress_folder(out).mkdir()
    assert _sweep(scenario, out, "--vary", "tether.length=110,120") == 2
    assert "not made by mjtether" in capsys.readouterr().err
    assert not out.exists()


def test_missing_ray_is_one_line_saying_what_to_install(tmp_path, scenario, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "ray", None)  # import fails
    out = tmp_path / "sw"
    assert _sweep(scenario, out, "--vary", "tether.length=110,120", "--ray") == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "pip install mjtether[ray]" in err
    _nothing_written(tmp_path, out)


def test_without_pyarrow_a_sweep_runs_and_writes_the_csv_only(tmp_path, scenario, monkeypatch, capsys):
    """The default install (no pyarrow, the [sweep] extra's) runs a sweep: cases.csv and the plot,
    no cases.parquet, and sweep.json says so."""
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import fails
    monkeypatch.setitem(sys.modules, "pyarrow.parquet", None)
    out = tmp_path / "sw"
    assert _sweep(scenario, out, "--vary", "tether.length=110,120") == 0, capsys.readouterr().err
    assert [r["status"] for r in _rows(out)] == ["ok", "ok"]
    assert (out / "summary.png").is_file() and not (out / "cases.parquet").exists()
    assert json.loads((out / "sweep.json").read_text())["parquet"] is False


@pytest.mark.slow
def test_ray_runs_the_same_cases(tmp_path, scenario, capsys):
    ray = pytest.importorskip("ray", reason="Ray is not installed (pip install mjtether[ray])")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        out_ray, out_local = tmp_path / "ray", tmp_path / "local"
        args = ["--vary", "tether.length=110,120", "--vary", "tether.rated_load=1,1e9"]
        assert _sweep(scenario, out_ray, *args, "--ray") == 0, capsys.readouterr().err
        assert ray.is_initialized()  # the test's Ray was used, and left running
    finally:
        ray.shutdown()
    assert _sweep(scenario, out_local, *args) == 0
    a, b = _rows(out_ray), _rows(out_local)
    assert [r["status"] for r in a] == ["failed", "ok", "failed", "ok"]
    for ra, rb in zip(a, b):
        for k in ("tether.length_m", "tether.rated_load_N", "status", "peak_ship_tension_N", "final_tow_tension_N"):
            assert ra[k] == rb[k]
        if ra["status"] == "failed":
            assert "rated load" in ra["error"]
    assert os.path.isfile(out_ray / "cases.parquet")

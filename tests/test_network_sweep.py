"""mjtether sweep on a network of lines, and the network keys --set and --vary take
(``mjtether.network.overrides``): rows per case, the varied key taking effect (a hanging line
against its closed form), refusals before anything runs, resume."""

import csv
import json
import math
from pathlib import Path

import pytest

from mjtether import sweep
from mjtether.cli import main
from mjtether.io.moordyn import load_any
from mjtether.network import Network, NetworkError, with_overrides

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "networks"
RHO, G = 1025.0, 9.80665
D, MPL, L, V = 0.02, 2.0, 30.0, 0.01  # the wire's diameter (m), mass per length (kg/m), length (m); clump volume (m^3)

HANGING = f"""\
# a wire hanging from a held point with a clump weight at its foot
[water]
depth = 100.0
rho = {RHO}
gravity = {G}
[simulation]
duration = 1.0
settle = 2.0
[line_types.wire]
diameter = {D}
mass_per_length = {MPL}
EA = 1.0e7
[points.top]
kind = "coupled"
position = [0.0, 0.0, -2.0]
[points.clump]
kind = "free"
position = [0.0, 0.0, -32.0]
mass = 100.0
volume = {V}
[[lines]]
name = "wire"
type = "wire"
a = "clump"
b = "top"
length = {L}
segments = 10
"""


@pytest.fixture
def hanging(tmp_path):
    p = tmp_path / "hang.toml"
    p.write_text(HANGING)
    return p


def _rows(folder):
    with open(folder / "cases.csv", newline="") as fh:
        return list(csv.DictReader(fh))


def _sweep(source, out, *args):
    return main(["sweep", str(source), *args, "--out", str(out)])


def test_a_clump_mass_sweep_matches_the_hanging_lines_closed_form(tmp_path, hanging):
    """Two clump masses on a vertical wire: at the end of each case the foot (end A) carries
    the clump's wet weight (m - rho V) g and the top (end B) that plus the wire's wet weight
    (mpl - rho pi d^2 / 4) g L (Archimedes; the stretch does not change the weight of the
    unstretched length). Tolerance 0.5 %: the run settles (damped, up to 2 s) and runs 1 s
    from rest in equilibrium; measured 1e-4 at worst (300 kg, where the statics start is
    missed and the settling finds it). The peak over the run is at least the final tension."""
    out = tmp_path / "sw"
    assert _sweep(hanging, out, "--vary", "points.clump.mass=100,300") == 0
    rows = _rows(out)
    assert [r["status"] for r in rows] == ["ok", "ok"]
    w_line = (MPL - RHO * math.pi * D ** 2 / 4) * G
    for r, mass in zip(rows, (100.0, 300.0)):
        assert float(r["points.clump.mass_kg"]) == mass
        clump = (mass - RHO * V) * G
        assert float(r["linewire_final_A_tension_N"]) == pytest.approx(clump, rel=5e-3)
        assert float(r["linewire_final_B_tension_N"]) == pytest.approx(clump + w_line * L, rel=5e-3)
        assert float(r["peak_tension_N"]) == float(r["linewire_peak_tension_N"]) >= float(
            r["linewire_final_B_tension_N"])
        assert 0 < float(r["timestep_s"]) <= 0.005 and float(r["wall_s"]) > 0
    meta = json.loads((out / "sweep.json").read_text())
    assert meta["kind"] == "network" and meta["ok"] == 2 and "linewire_peak_tension_N" in meta["columns"]
    assert (out / "network.toml").read_text() == HANGING
    assert (out / "summary.png").stat().st_size > 1000
    assert not sweep.progress_folder(out).exists()


def test_the_shipped_spread_mooring_sweeps_a_line_length(tmp_path):
    """examples/networks/spread_mooring_float.toml, cut to 0.5 s: a row per case, each line's figures."""
    out = tmp_path / "sw"
    assert _sweep(EXAMPLES / "spread_mooring_float.toml", out, "--set", "simulation.duration=0.5", "--set",
                  "simulation.settle=0", "--vary", "lines.1a.length=310,330") == 0
    rows = _rows(out)
    assert [r["status"] for r in rows] == ["ok", "ok"] and [r["lines.1a.length_m"] for r in rows] == ["310", "330"]
    for r in rows:
        peaks = [float(r[f"line{n}_peak_tension_N"]) for n in ("1a", "1b", "2", "3")]
        assert float(r["peak_tension_N"]) == max(peaks) > 1e5
    assert rows[0]["line1a_final_A_tension_N"] != rows[1]["line1a_final_A_tension_N"]


@pytest.mark.parametrize("args, says", [
    (["--vary", "points.nosuch.mass=1,2"], "--vary points.nosuch.mass=1,2: no point named 'nosuch' (the network's "
                                           "points: top, clump)"),
    (["--vary", "lines.wire.colour=1,2"], "--vary lines.wire.colour=1,2: a line's keys (lines.NAME.KEY) are length, "
                                          "segments"),
    (["--vary", "tether.length=1,2"], "--vary tether.length=1,2: a network takes --vary KEY=SPEC with KEY one of "
                                      "simulation.duration"),
    (["--vary", "points.clump.mass=100,heavy"], "--vary points.clump.mass=100,heavy: points.clump.mass = heavy is "
                                                "never allowed: points.clump.mass must be a number (kg)"),
    (["--vary", "points.clump.mass=100,-5"], "--vary points.clump.mass=100,-5: points.clump.mass = -5 is invalid in "
                                             "every case (points.clump.mass=-5: point 'clump': mass must be >= 0"),
    (["--vary", "lines.wire.segments=1:4:3"], "--vary lines.wire.segments=1:4:3: lines.wire.segments is an integer"),
    (["--vary", "points.clump.position=[0, 0, -30],[1, 2]"], "--vary points.clump.position=[0, 0, -30],[1, 2]: "
                                                             "points.clump.position = [1, 2] is never allowed"),
    (["--vary", "points.clump.mass=1,2", "--set", "line_types.wire.diameter=-1"],
     "--set line_types.wire.diameter=-1: line type 'wire': diameter must be > 0 m"),
])
def test_a_bad_key_or_value_is_refused_before_anything_runs(tmp_path, hanging, monkeypatch, capsys, args, says):
    monkeypatch.setattr(sweep.execute, "run_case", lambda sc: pytest.fail("a case ran"))
    out = tmp_path / "sw"
    assert _sweep(hanging, out, *args) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"mjtether sweep: {says}") and err.count("\n") == 1, err
    assert not out.exists() and not sweep.progress_folder(out).exists()


def test_resume_runs_no_finished_network_case_again(tmp_path, hanging, monkeypatch, capsys):
    out = tmp_path / "sw"
    args = ["--set", "simulation.settle=0", "--set", "simulation.duration=0.2", "--vary",
            "line_types.wire.mass_per_length=2:5:3"]
    real = sweep.run_case
    calls = []

    def interrupted(sc):
        assert isinstance(sc, Network)
        if len(calls) == 1:
            raise KeyboardInterrupt
        calls.append(sc.line_types["wire"].mass_per_length)
        return real(sc)

    monkeypatch.setattr(sweep.execute, "run_case", interrupted)
    assert _sweep(hanging, out, *args) == 130
    assert "rerun the same command to resume" in capsys.readouterr().err
    journal = [json.loads(p.read_text()) for p in (sweep.progress_folder(out) / "cases").glob("*.json")]
    assert len(journal) == 1
    first = journal[0]["record"]["started_at"]

    again = []
    monkeypatch.setattr(sweep.execute, "run_case",
                        lambda sc: again.append(sc.line_types["wire"].mass_per_length) or real(sc))
    assert _sweep(hanging, out, *args) == 0
    assert "1 from an earlier interrupted run" in capsys.readouterr().out
    assert sorted(again + calls) == [2.0, 3.5, 5.0] and len(again) == 2  # the finished case did not run again
    rows = _rows(out)
    assert all(r["status"] == "ok" for r in rows) and first in [r["started_at"] for r in rows]


# ------------------------------------------------------------------ the keys (--set on any network command)


def test_each_part_key_changes_that_field_only(hanging):
    net = load_any(hanging)
    got = with_overrides(net, ["line_types.wire.EA=2e7", "lines.wire.segments=12", "lines.wire.length=31",
                               "points.clump.position=[1, 0, -31]", "points.clump.cd_area=0.5", "water.depth=90"])
    assert got.line_types["wire"].EA == 2e7 and got.lines[0].segments == 12 and got.lines[0].length == 31.0
    assert got.points["clump"].position == (1.0, 0.0, -31.0) and got.points["clump"].cd_area == 0.5
    assert got.depth == 90.0 and got.points["top"] == net.points["top"]
    assert got.line_types["wire"].diameter == net.line_types["wire"].diameter
    rov = load_any(EXAMPLES / "rov_cage_excursion.toml")
    body = next(iter(rov.bodies))
    moved = with_overrides(rov, ["vehicles.rov.heading_deg=30", f"bodies.{body}.mass=900"])
    assert moved.vehicles["rov"].heading_deg == 30.0 and moved.bodies[body].mass == 900.0
    assert moved.vehicles["rov"].station == rov.vehicles["rov"].station


@pytest.mark.parametrize("items, says", [
    (["lines.wire.payout_speed=1"], "--set lines.wire.payout_speed=1: line 'wire': a line paying out"),
    (["vehicles.rov.heading_deg=1"], "--set vehicles.rov.heading_deg: no vehicle named 'rov' (the network's "
                                     "vehicles: none)"),
    (["line_types.wire.EA=stiff"], "--set line_types.wire.EA: give line_types.wire.EA=NUMBER (N), got 'stiff'"),
    (["line_types.wire.cd_normal=1e9"], "--set line_types.wire.cd_normal=1e9: line type 'wire': cd_normal must be "
                                        "in [0.0,"),
    (["lines.wire.length=0"], "--set lines.wire.length=0: line 'wire': length must be > 0 m"),
])
def test_a_bad_part_key_names_the_key_and_the_range(hanging, items, says):
    with pytest.raises(NetworkError) as exc:
        with_overrides(load_any(hanging), items)
    assert str(exc.value).startswith(says), str(exc.value)


def test_changes_to_one_part_are_checked_together(hanging):
    """payout_speed > 0 needs max_length above the length: refused alone, taken together."""
    net = with_overrides(load_any(hanging), ["lines.wire.payout_speed=0.5", "lines.wire.max_length=40"])
    assert net.lines[0].payout_speed == 0.5 and net.lines[0].max_length == 40.0


def test_two_jobs_give_the_rows_of_one(tmp_path, hanging):
    """--jobs 2 (a spawned worker process beside this one) runs network cases too, to the same figures."""
    args = ["--set", "simulation.settle=0", "--set", "simulation.duration=0.3", "--vary", "points.clump.mass=50,100"]
    assert _sweep(hanging, tmp_path / "one", *args) == 0
    assert _sweep(hanging, tmp_path / "two", *args, "--jobs", "2") == 0
    figures = [n for n, _ in sweep.network_columns(load_any(hanging)) if n not in ("wall_s", "started_at")]
    one, two = _rows(tmp_path / "one"), _rows(tmp_path / "two")
    assert [r["status"] for r in two] == ["ok", "ok"]
    assert [[r[n] for n in figures] for r in one] == [[r[n] for n in figures] for r in two]

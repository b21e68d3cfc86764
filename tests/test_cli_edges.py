"""The CLI at its edges, as a new user meets them (issue 31): ``mjtether render DIR`` replays a
results folder without simulating; an error during a run starts a line of its own below the
progress bar; a ``--set`` or ``--duration`` mistake names the option, not the scenario file;
MuJoCo's warnings show as one plain line; ``solve`` on an inextensible tether too short for its
ends says so in one line."""

import json

import imageio.v3 as iio
import numpy as np
import pytest
from helpers import small

from mjtether import cli
from mjtether.scenario import runner, start
from mjtether.simulation import Simulation


def _scenario(tmp_path, duration=1.0):
    f = tmp_path / "s.toml"
    f.write_text(small(duration))
    return f


def _lines(err: str) -> list[str]:
    """What a terminal shows of stderr: each line as left after its last carriage return (the
    progress bar redraws itself with them)."""
    return [ln.rsplit("\r", 1)[-1] for ln in err.split("\n") if ln.rsplit("\r", 1)[-1].strip()]


# ------------------------------------------------------------------ render DIR: a replay


def test_render_replays_a_results_folder_without_simulating(tmp_path, monkeypatch, capsys):
    """A 1 s run saved at 0.5 s intervals, rendered from its folder at 10 fps: 10 frames, and
    neither a step of any simulation, nor the walker's stand or the tether's steady state, is
    computed (each would fail the test); the frames show the saved run: the first is close to
    the live render's first frame of the same scenario."""
    f = _scenario(tmp_path)
    res = tmp_path / "res"
    assert cli.main(["run", str(f), "--out", str(res), "--no-plots"]) == 0
    saved = {p.name: p.read_bytes() for p in res.iterdir()}
    live = tmp_path / "live.mp4"
    video = ["--fps", "10", "--width", "160", "--height", "120", "--camera", "side"]
    assert cli.main(["render", str(f), "-o", str(live), *video]) == 0
    capsys.readouterr()

    def forbidden(*a, **k):
        raise AssertionError("the replay simulated")

    monkeypatch.setattr(Simulation, "step", forbidden)
    monkeypatch.setattr(start, "steady_start", forbidden)
    monkeypatch.setattr(start, "stand_walker", forbidden)
    monkeypatch.setattr(start, "preroll", forbidden)
    out = tmp_path / "replay.mp4"
    assert cli.main(["render", str(res), "-o", str(out), *video]) == 0
    said = capsys.readouterr().out
    assert "10 frames" in said and "replayed from" in said
    frames = iio.imread(out, index=None)
    assert frames.shape[:3] == (10, 120, 160)
    first_live = iio.imread(live, index=0).astype(int)
    assert np.abs(frames[0].astype(int) - first_live).mean() < 2.0  # (the codec's noise: about 0.2)
    assert {p.name: p.read_bytes() for p in res.iterdir()} == saved  # the results folder is left as it was


def test_render_refuses_what_is_not_a_complete_results_folder(tmp_path, capsys):
    """An empty folder (no summary.json), a folder whose run did not finish (no manifest), and
    a --duration beyond the saved run are refused with one line naming what is missing."""
    empty = tmp_path / "empty"
    empty.mkdir()
    assert cli.main(["render", str(empty), "-o", str(tmp_path / "a.mp4")]) == 2
    err = capsys.readouterr().err
    assert "no summary.json" in err and str(empty) in err and err.count("\n") == 1
    half = tmp_path / "half"
    half.mkdir()
    (half / "summary.json").write_text(json.dumps({"run": {}, "scenario": {}}))
    assert cli.main(["render", str(half), "-o", str(tmp_path / "a.mp4")]) == 2
    err = capsys.readouterr().err
    assert "no mjtether-manifest.json" in err and "did not finish" in err and err.count("\n") == 1
    assert not (tmp_path / "a.mp4").exists() and sorted(p.name for p in half.iterdir()) == ["summary.json"]


# ------------------------------------------------------------------ a failing run, a MuJoCo warning


def test_a_failing_run_prints_the_warning_and_the_error_on_lines_of_their_own(tmp_path, monkeypatch, capsys):
    """A NaN force put into the run at step 150 of 200 (after the progress bar has started):
    MuJoCo warns that the simulation is unstable and the run stops. The warning is one plain line
    (no Python source line, no file path) and the error starts a line of its own, neither glued
    to the progress bar."""
    step = runner.ScenarioRun.step
    count = [0]

    def poisoned(self):
        count[0] += 1
        if count[0] == 150:
            self.sim.data.qfrc_applied[0] = np.nan
        step(self)

    monkeypatch.setattr(runner.ScenarioRun, "step", poisoned)
    monkeypatch.setattr(runner.ScenarioRun, "blocks", False)  # (every step through ``step``: its ship and winch hold still)
    assert cli.main(["run", str(_scenario(tmp_path)), "--out", str(tmp_path / "res")]) == 1
    err = capsys.readouterr().err
    assert "%|" in err  # (the progress bar was drawn)
    shown = _lines(err)
    warned = [ln for ln in shown if "QACC" in ln]
    assert len(warned) == 1 and warned[0].startswith("mjtether run: MuJoCo warning: Nan, Inf or huge value in QACC")
    assert "simulation is unstable" in warned[0]
    failed = [ln for ln in shown if "failed" in ln]
    assert len(failed) == 1 and failed[0].startswith("mjtether run: failed, no results written: simulation diverged")
    assert "simulation.py" not in err and "warnings.warn" not in err and "Traceback" not in err
    assert not (tmp_path / "res").exists()


# ------------------------------------------------------------------ who is blamed


@pytest.mark.parametrize("item, says", [
    ("tether.length=abc", "tether.length = 'abc': must be a number in [0.1, 100000] m"),
    ("tether.lenght=300", "unknown key tether.lenght (did you mean length?)"),
    ("simulation.duration=-1", "simulation.duration = -1: must be a number in [0.001, 1e+06] s"),
    ("tether.length=10", "tether.length = 10 m: too short for its ends"),
    ("nosuch.key=1", "unknown key nosuch"),
])
def test_a_set_mistake_names_the_set_option_not_the_file(tmp_path, capsys, item, says):
    f = _scenario(tmp_path)
    assert cli.main(["solve", str(f), "--set", item]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"mjtether: --set {item}: ") and says in err, err
    assert str(f) not in err and err.count("\n") == 1


def test_a_network_set_mistake_names_the_set_option_not_the_file(capsys):
    """A network (``examples/networks``) takes --set too: a value its checks refuse names the
    --set that gave it, not the network's file (it did)."""
    assert cli.main(["solve", "networks/rov_cage_excursion", "--set", "water.depth=-5"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mjtether: --set water.depth=-5: water.depth must be > 0 m") and ".toml" not in err, err


def test_a_file_mistake_names_the_file_and_duration_blames_the_option(tmp_path, capsys):
    f = tmp_path / "bad.toml"
    f.write_text(small(1.0).replace("length = 120.0", "length = -5.0"))
    assert cli.main(["solve", str(f), "--set", "simulation.duration=2"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"mjtether: {f}: tether.length = -5") and "--set" not in err
    good = _scenario(tmp_path)
    assert cli.main(["render", str(good), "--duration", "-1", "-o", str(tmp_path / "v.mp4")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mjtether: --duration -1: ") and "must be a number in [0.001, 1e+06] s" in err
    assert str(good) not in err and err.count("\n") == 1


# ------------------------------------------------------------------ solve: an inextensible tether too short


def test_solve_on_an_inextensible_tether_that_just_cannot_reach_says_so_in_one_line(tmp_path, capsys):
    """The anchor is 100 m from the fairlead: an inextensible tether of 100 m passes the file's
    reach check (it is not shorter than the distance) but has no steady state (it would have to
    be a straight bar). ``solve`` (both starts) and ``run`` say so in one line, naming
    tether.length, the distance and what would do."""
    f = _scenario(tmp_path)
    sets = ["--set", "tether.EA=0", "--set", "tether.length=100"]
    for extra in ([], ["--set", "simulation.start=settle"]):
        assert cli.main(["solve", str(f), *sets, *extra]) == 1
        err = capsys.readouterr().err
        assert err.startswith("mjtether solve: no steady state: tether.length = 100 m: too short for its ends"), err
        assert "100.00 m apart" in err and "give tether.length > 100.00 m or tether.EA > 0" in err
        assert err.count("\n") == 1 and "Traceback" not in err
    assert cli.main(["run", str(f), *sets, "--out", str(tmp_path / "res")]) == 1
    err = capsys.readouterr().err
    assert "tether.length = 100 m: too short for its ends" in err and "settle" not in err
    assert "Traceback" not in err and not (tmp_path / "res").exists()


# ------------------------------------------------------------------ the closing line and --help (issue 44)


def test_the_simulated_time_is_the_duration_asked_to_a_whole_step():
    """``cli.simulated``: 10 s asked at the 2.4 ms step of a network is run as 4167 steps,
    10.0008 s, and printed as the 10 s asked (the run ends at the step nearest to it); a run
    that stops short (a watch) or a duration under one step prints what it ran and what was
    asked."""
    dt = 0.0024
    assert cli.simulated(10.0, round(10.0 / dt) * dt, dt) == "10 s"
    assert cli.simulated(2.5, 500 * 0.005, 0.005) == "2.5 s"
    assert cli.simulated(10.0, 4.2, 0.005) == "4.2 s (of 10 s asked)"
    assert cli.simulated(0.001, 0.005, 0.005) == "0.005 s (of 0.001 s asked)"


def test_a_network_run_prints_the_duration_asked(tmp_path, capsys):
    """moored_buoy_body for 1 s runs 417 steps of 2.4 ms (1.0008 s: its step does not divide 1 s)
    and says "1 s simulated", not "1.0008 s"; the step is printed beside it."""
    assert cli.main(["run", "networks/moored_buoy_body", "--set", "simulation.duration=1", "--out",
                     str(tmp_path / "net"), "--no-plots"]) == 0
    line = capsys.readouterr().out.strip().splitlines()[-1]
    assert line.startswith("1 s simulated (3 lines, step 0.0024 s)"), line


def test_a_scenario_run_prints_the_duration_asked(tmp_path, capsys):
    """0.75 s asked at 5 ms steps (150 of them) prints "0.75 s simulated", where the old
    ``:.0f`` printed "1 s"."""
    assert cli.main(["run", str(_scenario(tmp_path, 0.75)), "--out", str(tmp_path / "res"), "--no-plots"]) == 0
    assert capsys.readouterr().out.strip().splitlines()[-1].startswith("0.75 s simulated in ")


@pytest.mark.parametrize("command", ["run", "render", "solve", "sweep"])
def test_help_says_a_shipped_examples_name_works_and_lists_them(command, capsys):
    """``run --help`` (and render, solve, sweep) says that a shipped example's name works and
    lists every one, each a name ``_load`` takes (``packagedata.shipped_example`` finds it); the
    list is read here from the examples folder itself."""
    from mjtether.files.packagedata import examples_dir, shipped_example

    with pytest.raises(SystemExit):
        cli.main([command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "shipped example's name" in text
    listed = text.split("mjtether run default_walker`; the files are in ")[1].split("): ", 1)[1]
    names = [n.strip() for n in listed.split(",")]
    folder = examples_dir()
    expected = sorted(str(p.relative_to(folder))[:-len(".toml")] for p in folder.glob("**/*.toml"))
    assert names == expected and "default_walker" in names and "networks/rov_cage_excursion" in names
    assert all(shipped_example(n) is not None for n in names)

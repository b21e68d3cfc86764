"""One run loop (``simulation.drive``) and one results writer (``files.results_folder``) for
every system: a scenario's single tether and a network of lines."""

import json
import re

import numpy as np
import pytest

from mjtether.files.results_folder import write_folder
from mjtether.io import results
from mjtether.network import from_dict
from mjtether.network import run as nrun
from mjtether.scenario import load_scenario
from mjtether.scenario.recording import ScenarioResult, run
from mjtether.simulation import SimulationDiverged, drive

SCENARIO = """
[simulation]
duration = 0.33
output_interval = 0.1
timestep = 0.005
[robot]
type = "anchor"
position = [40.0, 0.0, -100.0]
[water]
depth = 100.0
[tether]
length = 120.0
segments = 10
"""

NET = {"water": {"depth": 100.0}, "simulation": {"duration": 0.33, "output_interval": 0.1, "timestep": 0.0025},
       "line_types": {"rope": {"diameter": 0.08, "mass_per_length": 12.0, "EA": 5e7}},
       "points": {"anchor": {"kind": "fixed", "position": [120.0, 0.0, -100.0]},
                  "top": {"kind": "fixed", "position": [0.0, 0.0, -10.0]}},
       "lines": [{"name": "1", "type": "rope", "a": "anchor", "b": "top", "length": 160.0, "segments": 20}]}


class Counter:
    """A system of no physics for the loop: ``advance(k)`` adds k steps of 0.5 s, ``sample()``
    its row (time s, steps)."""

    def __init__(self):
        self.steps, self.advances = 0, []

    def advance(self, k):
        self.advances.append(k)
        self.steps += k

    def clock(self):
        return 0.5 * self.steps

    def sample(self):
        return [self.clock(), float(self.steps)]


def test_the_loop_samples_every_block_and_the_end():
    """10 steps sampled every 3: blocks of 3, 3, 3 and 1, samples after 0, 3, 6, 9 and 10 steps
    (counted by hand; exact integers), progress at each sample after the first."""
    c, seen = Counter(), []
    out = drive(c.advance, 10, 3, c.sample, clock=c.clock, progress=lambda k, n: seen.append((k, n)))
    assert c.advances == [3, 3, 3, 1]
    assert out.steps == 10
    np.testing.assert_array_equal(out.rows[:, 1], [0, 3, 6, 9, 10])
    assert seen == [(3, 10), (6, 10), (9, 10), (10, 10)]


def test_a_watch_stops_the_run_at_the_sample_where_it_fires():
    """A watch that fires once 7 steps are done stops the run at the first sample after it (step
    9, by hand: samples every 3 steps); every watch is called at every sample, the one after the
    firing one too; a watch firing at the start stops the run there (0 steps, one row)."""
    c, calls = Counter(), []

    def late():
        calls.append("late")
        return False

    out = drive(c.advance, 30, 3, c.sample, clock=c.clock, watches=[lambda: c.steps >= 7, late])
    assert (out.steps, c.steps, len(out.rows)) == (9, 9, 4)
    assert len(calls) == 4
    c = Counter()
    out = drive(c.advance, 30, 3, c.sample, clock=c.clock, watches=[lambda: True])
    assert (out.steps, c.advances, len(out.rows)) == (0, [], 1)


def test_a_non_finite_record_is_a_divergence_naming_its_column_and_time():
    """A NaN in the sample after 6 steps (t = 3 s) raises SimulationDiverged at once, with the
    time as every divergence gives it (what a sweep reads) and the column's name."""
    c = Counter()

    def sample():
        row = c.sample()
        return [row[0], np.nan] if c.steps == 6 else row

    with pytest.raises(SimulationDiverged, match=r"diverged at t = 3\.0000 s.*'steps'"):
        drive(c.advance, 30, 3, sample, clock=c.clock, names=["time_s", "steps"])
    assert c.steps == 6


def test_a_scenario_is_sampled_at_its_end_and_returns_named_results(tmp_path):
    """0.33 s at 5 ms sampled every 0.1 s: 66 steps, samples after 0, 20, 40, 60 and 66 steps
    (by hand: the last block is 6 steps), so the last row is the run's end (time exact to
    rounding, 1e-12 s); ``run`` returns a ScenarioResult that still unpacks into three."""
    (tmp_path / "s.toml").write_text(SCENARIO)
    res = run(load_scenario(tmp_path / "s.toml"))
    assert isinstance(res, ScenarioResult)
    rows, history, info = res
    np.testing.assert_allclose(rows[:, 0], [0.0, 0.1, 0.2, 0.3, 0.33], atol=1e-12)
    assert info["steps"] == 66 and len(history["nodes"]) == 5


def _keys_pattern(files):
    """The npz keys with each line's name replaced by NAME."""
    return sorted({re.sub(r"^line[^_]+", "lineNAME", k) for k in files})


def test_both_systems_write_the_same_folder(tmp_path):
    """A scenario's and a network's folders, each written through ``write_folder``: the same
    files, the same npz key pattern (``time_s``, ``lineNAME``, ``lineNAME_nodes``,
    ``lineNAME_tension``, ``lineNAME_compression``, ``lineNAME_peak_tension``, ``qpos``; the single tether adds its
    ``element_length`` and the mocap state), the summary's ``kind`` and the same plot list form;
    the CSV's first column ``time_s``, its last row the run's end (0.33 s to the 9 figures
    written, and the network's 2.5 ms step: 132 steps)."""
    (tmp_path / "s.toml").write_text(SCENARIO)
    sc = load_scenario(tmp_path / "s.toml")
    a = results.write(tmp_path / "scenario", sc, *run(sc))
    b = tmp_path / "network"
    nrun.run_to(from_dict(NET), b)
    common = {"timeseries.csv", "lines.npz", "summary.json", "tension.png", "profile.png", "line_tension.png",
              "mjtether-manifest.json"}
    assert {p.name for p in b.iterdir()} == common
    assert {p.name for p in a.iterdir()} == common  # (track.png only for a run without a tether)
    with np.load(a / "lines.npz") as za, np.load(b / "lines.npz") as zb:
        ka, kb = _keys_pattern(za.files), _keys_pattern(zb.files)
    assert set(kb) == {"time_s", "lineNAME", "lineNAME_nodes", "lineNAME_tension", "lineNAME_compression",
                       "lineNAME_peak_tension", "qpos"}
    assert set(ka) - set(kb) == {"lineNAME_element_length", "mocap_pos", "mocap_quat"} and set(kb) <= set(ka)
    for folder, kind in ((a, "scenario"), (b, "network")):
        s = json.loads((folder / "summary.json").read_text())
        assert s["kind"] == kind and all((folder / f).is_file() for f in s["plots"])
        t = np.genfromtxt(folder / "timeseries.csv", delimiter=",", names=True)["time_s"]
        assert t[0] == 0.0 and abs(t[-1] - 0.33) < 1e-8


def test_a_diverging_network_writes_no_folder(tmp_path, monkeypatch):
    """A record that turns non-finite half way (the network's sample given a NaN from 0.2 s on):
    SimulationDiverged (its step given, so not run again), and neither the folder nor a staging
    folder beside it is left."""
    real = nrun.sample

    def sample(r):
        row = real(r)
        return row if r.sim.time < 0.2 else [np.nan] + row[1:]

    monkeypatch.setattr(nrun, "sample", sample)
    with pytest.raises(SimulationDiverged, match="'time_s'"):
        nrun.run_to(from_dict(NET), tmp_path / "out")
    assert list(tmp_path.iterdir()) == []


def test_blocks_give_the_bits_of_single_steps(monkeypatch):
    """A network stepped in blocks between samples and the same network stepped one step at a
    time (as a video makes the loop step; here a recorder that never takes a frame): the same
    rows and line records bit for bit (the same MuJoCo steps in the same order)."""
    class NoFrames:
        frames, scale, s = 0, 1.0, type("S", (), {"fps": 1, "camera": "side"})

        def due(self, t):
            return False

        def finish(self):
            return "none.mp4"

    seen, advance = [], nrun.NetworkRun.advance
    monkeypatch.setattr(nrun.NetworkRun, "advance", lambda r, k: (seen.append(k), advance(r, k))[1])
    blocks, rows = nrun.simulate(from_dict(NET))
    blocks.sim.close()
    assert seen == [40, 40, 40, 12]  # (0.1 s of 2.5 ms steps, and the 0.03 s left)
    seen.clear()
    single, rows_1 = nrun.simulate(from_dict(NET), video=lambda r: NoFrames())
    single.sim.close()
    assert seen == [1] * 132
    np.testing.assert_array_equal(rows_1, rows)
    for name, h in blocks.history.items():
        for key, values in h.items():
            np.testing.assert_array_equal(np.array(single.history[name][key]), np.array(values))


def test_the_writer_refuses_rows_that_do_not_fit_the_header(tmp_path):
    """A header of 2 columns over rows of 3: a ValueError naming timeseries.csv and both sizes."""
    with pytest.raises(ValueError, match=r"timeseries\.csv.*\(2, 3\).*2 columns"):
        write_folder(tmp_path, ["a", "b"], np.zeros((2, 3)), {}, {"kind": "test"})

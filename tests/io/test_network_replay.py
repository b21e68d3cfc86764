"""Replay of a network's results folder (``mjtether render DIR``, ``mjtether.io.replay``): the
video, frames as the live run drew them, and folders that cannot be replayed."""

import json
import shutil

import imageio.v3 as iio
import mujoco
import numpy as np
import pytest

from mjtether.io.network_view import NetworkView
from mjtether.io.render import FrameRenderer, VideoRecorder, VideoSettings, tension_colours
from mjtether.io.replay import NetworkReplay, ReplayError, SavedNetwork, replay
from mjtether.network import from_dict
from mjtether.network import run as nrun

from test_network_render import NET  # (the same two lines: anchor -> free float -> fixed fairlead; 1 s)
LIVE = VideoSettings(160, 120, 10, "side")


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """A results folder of NET with a live video, and the live frames (raw, before encoding) and
    tension scale. Frames fall on the samples' times: 10 fps, samples every 0.1 s, 1 ms steps."""
    kept = []

    class Keep(VideoRecorder):
        def capture(self):
            kept.append(self.frame.render().copy())
            self._writer.append_data(kept[-1])
            self.frames += 1

    folder = tmp_path_factory.mktemp("net") / "res"
    r, _ = nrun.run_to(from_dict(NET), folder, plots=False,
                       video=lambda r, f: Keep(NetworkView(r), f / "live.mp4", LIVE))
    return folder, kept, r.video["tension_scale_N"]


def test_replay_writes_every_frame_and_says_what_it_did(results, tmp_path):
    folder, _, scale = results
    v = replay(folder, tmp_path / "r.mp4", VideoSettings(64, 48, 10, "top"))
    assert iio.imread(tmp_path / "r.mp4", index=None).shape[:3] == (10, 48, 64)
    assert set(v) == {"frames", "simulated_s", "fps", "camera", "tension_scale_N", "file", "smooth", "samples",
                      "output_interval_s", "wall_time_s", "tethered"}
    assert v["frames"] == 10 and v["samples"] == 11 and v["smooth"] and v["output_interval_s"] == 0.1
    assert v["simulated_s"] == pytest.approx(1.0, abs=1e-9) and v["tension_scale_N"] == scale
    with pytest.raises(ReplayError, match=r"--duration 2: must be in \(0, 1\] s"):
        replay(folder, tmp_path / "s.mp4", VideoSettings(64, 48), duration=2.0)


def test_replayed_frames_are_the_live_frames(results):
    """Each replayed frame against the live frame at the same sample time, pixel by pixel: at
    most 0.2 % of the pixels (38 of 19200) may differ. Why any: the replay sets the saved qpos
    (the state at the sample's time) while the live frame drew MuJoCo's kinematics after the
    last step (the state that step began from, 1 ms earlier), so the free float's marker may sit
    up to |v| dt apart (3 mm at the end here, where the current has it moving at 3 m/s), against
    pixels of about 0.6 m; the lines are drawn from the same saved nodes in both. Measured: 0
    pixels differ. The frames do change over the run (the clock), so equality is not trivial."""
    folder, kept, _ = results
    saved = SavedNetwork(folder)
    rep = NetworkReplay(saved)
    fr = FrameRenderer(rep, LIVE)
    try:
        for k, live in enumerate(kept):
            rep.show(saved.sample_at(k / LIVE.fps))
            differ = np.any(fr.render() != live, axis=2)
            assert differ.mean() <= 0.002, (k, int(differ.sum()))
    finally:
        fr.close()
        rep.close()
    assert np.any(kept[0] != kept[-1])


def test_the_replay_sets_the_saved_state(results):
    """After ``show(k)`` the float is where timeseries.csv says it was at sample k (its columns,
    written to 9 significant figures: 1e-6 m here), and every line's node sites are at the nodes
    lines.npz saved (end A first in the file, end B first in the model)."""
    folder, _, _ = results
    table = np.loadtxt(folder / "timeseries.csv", delimiter=",", skiprows=1)
    cols = (folder / "timeseries.csv").read_text().splitlines()[0].split(",")
    z = np.load(folder / "lines.npz")
    rep = NetworkReplay(SavedNetwork(folder))
    try:
        m, d = rep.model, rep.data
        for k in (0, 5, 10):
            rep.show(k)
            want = table[k, [cols.index(f"pointfloat_{a}_m") for a in "xyz"]]
            assert np.allclose(d.xpos[m.body("point/float").id], want, atol=1e-6)
            for n in ("lower", "upper"):
                sites = [m.site(f"{n}/node{i}").id for i in range(9)]
                assert np.allclose(d.site_xpos[sites], z[f"line{n}_nodes"][k][::-1], atol=1e-9)
    finally:
        rep.close()


def test_the_overlay_names_the_lines_and_their_saved_end_tensions(results, monkeypatch):
    """The overlay at sample k: the time and, per line by name, the tensions at ends A and B
    that timeseries.csv holds for it (rounded to 1 N); with room for one line only, the line of
    the largest end tension, and how many are left out."""
    from mjtether.io import network_view

    folder, _, _ = results
    table = np.loadtxt(folder / "timeseries.csv", delimiter=",", skiprows=1)
    cols = (folder / "timeseries.csv").read_text().splitlines()[0].split(",")
    rep = NetworkReplay(SavedNetwork(folder))
    try:
        rep.show(7)
        [(_, left, right)] = rep.overlay()
        end = {(n, e): table[7, cols.index(f"line{n}_{e}_tension_N")] for n in ("lower", "upper") for e in "AB"}
        assert left.split("\n") == ["time", "line lower A / B", "line upper A / B"]
        assert right.split("\n") == [f"{table[7, 0]:7.2f} s"] + [f"{end[n, 'A']:7.0f} / {end[n, 'B']:.0f} N"
                                                                 for n in ("lower", "upper")]
        monkeypatch.setattr(network_view, "OVERLAY_LINES", 1)
        [(_, left, _)] = rep.overlay()
        worst = max(("lower", "upper"), key=lambda n: max(end[n, "A"], end[n, "B"]))
        assert left.split("\n") == ["time", f"line {worst} A / B", "(+1 lines)"]
    finally:
        rep.close()


def test_replayed_capsules_carry_the_saved_tensions(results):
    """The replay draws each element of each line, from end A to end B, in the turbo colour of
    the tension lines.npz saved for it (colours from the file with matplotlib, to float32)."""
    folder, _, scale = results
    z = np.load(folder / "lines.npz")
    saved = SavedNetwork(folder)
    rep = NetworkReplay(saved)
    fr = FrameRenderer(rep, VideoSettings(64, 48, 10, "track"))
    try:
        assert fr.scale == scale
        for k in (0, 4, 10):
            rep.show(k)
            fr.render()
            sc = fr.scene
            drawn = [np.array(sc.geoms[i].rgba) for i in range(sc.ngeom)
                     if sc.geoms[i].category == mujoco.mjtCatBit.mjCAT_DECOR
                     and sc.geoms[i].type == mujoco.mjtGeom.mjGEOM_CAPSULE]
            want = np.vstack([tension_colours(z[f"line{n}_tension"][k], scale) for n in ("lower", "upper")])
            assert np.allclose(drawn, want.astype(np.float32), atol=1e-7)
    finally:
        fr.close()
        rep.close()


def _copy(results, tmp_path):
    folder = tmp_path / "copy"
    shutil.copytree(results[0], folder)
    return folder


def test_a_folder_without_lines_npz_is_refused(results, tmp_path):
    folder = _copy(results, tmp_path)
    (folder / "lines.npz").unlink()
    with pytest.raises(ReplayError, match="an incomplete results folder: no lines.npz"):
        replay(folder, tmp_path / "v.mp4", VideoSettings(64, 48))
    assert not (tmp_path / "v.mp4").exists()


def test_an_older_folder_without_qpos_is_refused(results, tmp_path):
    folder = _copy(results, tmp_path)
    with np.load(folder / "lines.npz") as z:
        kept = {k: z[k] for k in z.files if k != "qpos"}
    np.savez_compressed(folder / "lines.npz", **kept)
    with pytest.raises(ReplayError, match=r"lines.npz: holds no qpos \(written by an older mjtether.*run the network "
                                          "again"):
        replay(folder, tmp_path / "v.mp4", VideoSettings(64, 48))


def test_an_older_folder_without_the_network_is_refused(results, tmp_path):
    folder = _copy(results, tmp_path)
    summary = json.loads((folder / "summary.json").read_text())
    del summary["network"]
    (folder / "summary.json").write_text(json.dumps(summary))
    with pytest.raises(ReplayError, match=r"summary.json: holds no network \(written by an older mjtether"):
        replay(folder, tmp_path / "v.mp4", VideoSettings(64, 48))


def test_a_network_with_a_scenario_style_current_replays(tmp_path):
    """A network whose ``[water.current]`` is written as a scenario writes it (here a 1/7 power
    law) stores the current's whole section in summary.json, with the Gauss-Markov defaults'
    infinite bounds as text ("-inf", JSON has no infinity); the replay reads them back as
    numbers and rebuilds the network (before: refused, "must be a number in [-inf, inf] deg")."""
    net = json.loads(json.dumps(NET))
    net["water"] = {"depth": 50.0, "current": {"type": "power", "surface_speed": 0.3, "exponent": 0.142857,
                                               "heading_deg": 90.0}}
    folder = tmp_path / "res"
    nrun.run_to(from_dict(net), folder, plots=False)
    stored = json.loads((folder / "summary.json").read_text())["network"]["water"]["current"]
    assert stored["gauss_markov"]["heading_min_deg"] == "-inf"  # (the case this test is about)
    saved = SavedNetwork(folder)
    assert saved.net.current == from_dict(net).current and saved.net.current is not None

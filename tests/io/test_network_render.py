"""Headless video of a network of lines (``mjtether.io.network_view``): the file, the physics left
alone, and the lines drawn in the colours of their tensions."""

import imageio.v3 as iio
import mujoco
import numpy as np
import pytest

from mjtether.io.network_view import NetworkView, network_video, network_video_into
from mjtether.io.render import FrameRenderer, VideoRecorder, VideoSettings, tension_colours
from mjtether.network import from_dict
from mjtether.network import run as nrun

NET = {  # two lines, anchor -> free float -> fixed fairlead, in a cross current; 1 s at 1 ms
    "water": {"depth": 50.0, "rho": 1025.0, "current_depths": [0.0, 50.0], "current_speeds": [0.8, 0.2],
              "current_headings_deg": [90.0, 90.0]},
    "simulation": {"duration": 1.0, "output_interval": 0.1, "timestep": 0.001},
    "line_types": {"rope": {"diameter": 0.05, "mass_per_length": 5.0, "EA": 1e7, "cd_normal": 1.2}},
    "points": {"anchor": {"kind": "fixed", "position": [-60.0, 0.0, -50.0]},
               "float": {"kind": "free", "position": [0.0, 0.0, -20.0], "mass": 50.0, "volume": 0.5,
                         "cd_area": 0.5, "ca": 0.5},
               "fair": {"kind": "fixed", "position": [40.0, 0.0, -2.0]}},
    "lines": [{"name": "lower", "type": "rope", "a": "anchor", "b": "float", "length": 75.0, "segments": 8},
              {"name": "upper", "type": "rope", "a": "float", "b": "fair", "length": 48.0, "segments": 8}],
}


def capsules(renderer: FrameRenderer) -> list:
    """(rgba, centre) of the capsules drawn into the renderer's last scene (the lines' elements, in
    the order drawn: line after line, each from end A to end B)."""
    sc = renderer.scene
    out = []
    for i in range(sc.ngeom):
        g = sc.geoms[i]
        if g.category == mujoco.mjtCatBit.mjCAT_DECOR and g.type == mujoco.mjtGeom.mjGEOM_CAPSULE:
            out.append((np.array(g.rgba, float), np.array(g.pos, float)))
    return out


def test_network_video_has_every_frame(tmp_path):
    """1 s at 10 fps, 64x48: 10 frames read back with imageio, none blank (pixel standard
    deviation above 5 grey levels: the overlay and the colour bar alone give more), and
    ``r.video`` says what was written."""
    out = tmp_path / "net.mp4"
    r, _ = nrun.simulate(from_dict(NET), video=network_video(VideoSettings(64, 48, 10, "side"), out))
    r.sim.close()
    frames = iio.imread(out, index=None)
    assert frames.shape[:3] == (10, 48, 64)
    assert all(f.std() > 5.0 for f in frames)
    assert r.video == {"file": "net.mp4", "frames": 10, "fps": 10, "camera": "side", "tension_scale_N": 10000.0}
    assert not list(tmp_path.glob(".*partial*"))


def test_network_video_leaves_the_time_series_bit_identical(tmp_path):
    """The same network run with and without a video (the video taken at each step on or after
    a frame time, as the run steps one at a time for it): bitwise equal time series and line
    records (nodes and tensions)."""
    plain, rows = nrun.simulate(from_dict(NET))
    plain.sim.close()
    filmed, rows_v = nrun.simulate(from_dict(NET), video=network_video(VideoSettings(64, 48, 10, "top"),
                                                                      tmp_path / "v.gif"))
    filmed.sim.close()
    assert filmed.video["frames"] == 10 and len(iio.imread(tmp_path / "v.gif", index=None)) == 10
    assert np.array_equal(rows, rows_v)
    for name in ("lower", "upper"):
        for what in ("nodes", "tension"):
            assert np.array_equal(np.array(plain.history[name][what]), np.array(filmed.history[name][what]))


def test_live_capsules_carry_the_saved_tension_colours(tmp_path):
    """At each frame of a live video (frames at the samples' times: 10 fps, samples every 0.1 s,
    1 ms steps) the capsules drawn are, line by line from end A to end B, at the midpoints of the
    nodes and in the turbo colours of the element tensions that the results folder's lines.npz
    saved for that sample (colours computed here from the file with matplotlib's turbo, not by
    the renderer's code path; to float32, as a scene geom holds them). The scale is the default,
    twice the largest initial element tension rounded up to 1, 2 or 5 x 10^k N, checked from the
    file too."""
    seen = []

    class Watch(VideoRecorder):
        def capture(self):
            super().capture()
            seen.append(capsules(self.frame))

    settings = VideoSettings(64, 48, 10, "side")
    factory = lambda r, folder: Watch(NetworkView(r), folder / "v.mp4", settings)  # noqa: E731
    r, _ = nrun.run_to(from_dict(NET), tmp_path / "res", plots=False, video=factory)
    z = np.load(tmp_path / "res" / "lines.npz")
    assert len(seen) == 10 and np.allclose(z["time_s"][:10], np.arange(10) / 10, atol=1e-9)
    top = max(z["linelower_tension"][0].max(), z["lineupper_tension"][0].max())
    scale = r.video["tension_scale_N"]
    assert 2 * top <= scale < 2.5 * 2 * top  # (steps of 1, 2, 5 x 10^k: at most 2.5 apart)
    assert round(scale / 10 ** np.floor(np.log10(scale)), 9) in (1, 2, 5)
    for k, drawn in enumerate(seen):
        want = np.vstack([tension_colours(z[f"line{n}_tension"][k], scale) for n in ("lower", "upper")])
        mid = np.vstack([0.5 * (z[f"line{n}_nodes"][k][1:] + z[f"line{n}_nodes"][k][:-1]) for n in ("lower", "upper")])
        assert len(drawn) == len(want) == 16
        assert np.allclose([c for c, _ in drawn], want.astype(np.float32), atol=1e-7)
        assert np.allclose([p for _, p in drawn], mid, atol=1e-5)


def test_lines_are_drawn_red_above_the_scale_and_never_below_it(tmp_path):
    """The same state drawn with a colour scale far below every element's tension (all at the
    red end of turbo) and far above it (all at the dark blue end): outside the colour bar and
    the overlay, red pixels appear only in the first (tens of them: the two lines' footprint at
    160x120)."""
    r = nrun.build(from_dict(NET))
    try:
        t = [r.sim.tethers[n].element_tension(r.sim.data) for n in ("lower", "upper")]
        lo, hi = min(float(x.min()) for x in t), max(float(x.max()) for x in t)
        assert lo > 0

        def frame(scale):
            fr = FrameRenderer(NetworkView(r), VideoSettings(160, 120, 10, "side", tension_scale=scale))
            try:
                return fr.render().astype(int)
            finally:
                fr.close()

        def red(f):
            f = f.copy()
            f[-30:, :60] = 0  # the colour bar and its label
            f[:40] = 0  # the overlay
            R, G, B = f[..., 0], f[..., 1], f[..., 2]
            return int(np.sum((R > 60) & (R > 3 * G) & (R > 3 * B)))

        hot, cold = red(frame(0.01 * lo)), red(frame(100.0 * hi))
    finally:
        r.sim.close()
    assert hot > 20
    assert cold == 0


def test_walker_camera_and_bad_video_names_are_refused(tmp_path):
    """The walker camera is refused before any simulating (by the factory) and by the renderer."""
    walker = VideoSettings(64, 48, 10, "walker")
    with pytest.raises(ValueError, match="a single-tether scenario's walker camera"):
        network_video(walker, tmp_path / "v.mp4")
    with pytest.raises(ValueError, match="a single-tether scenario's walker camera"):
        network_video_into(walker, "v.mp4")
    r = nrun.build(from_dict(NET))
    try:
        with pytest.raises(ValueError, match="a single-tether scenario's walker camera"):
            VideoRecorder(NetworkView(r), tmp_path / "v.mp4", walker)
    finally:
        r.sim.close()
    assert not list(tmp_path.iterdir())
    with pytest.raises(ValueError, match="video file must end in .mp4 or .gif"):
        network_video(VideoSettings(64, 48), tmp_path / "v.avi")
    with pytest.raises(ValueError, match="--video must name an .mp4 or .gif file"):
        network_video_into(VideoSettings(64, 48), "sub/v.mp4")


def test_elements_on_a_drum_are_left_out():
    """A line paying out from a drum at end B gives its nodes still on the drum at the fairlead
    (the last node): those elements (zero length) are not drawn; a line with none on the drum is
    drawn whole, and one wholly on it not at all."""
    from mjtether.io.network_view import deployed

    x = np.array([[0.0, 0, -10], [1, 0, -9], [2, 0, -8], [2, 0, -8], [2, 0, -8]])
    t = np.array([10.0, 20.0, 0.0, 0.0])
    nodes, tension = deployed(x, t)
    assert np.array_equal(nodes, x[:3]) and np.array_equal(tension, t[:2])
    nodes, tension = deployed(x[:3], t[:2])
    assert np.array_equal(nodes, x[:3]) and np.array_equal(tension, t[:2])
    nodes, tension = deployed(np.zeros((4, 3)), np.zeros(3))
    assert nodes.shape == (1, 3) and tension.shape == (0,)

"""Headless rendering: video files, frame content, and no effect on the physics."""

import imageio.v3 as iio
import numpy as np
import pytest
from helpers import small

from mjtether import cli
from mjtether.io.render import VideoRecorder, VideoSettings, frame_times, nice_scale, tension_colours
from mjtether.scenario.runner import ScenarioRun, run
from mjtether.scenario import load_scenario


def test_colour_scale_and_frame_times():
    """The colour scale is fixed: 0 N and the scale's top are the ends of the turbo map, beyond
    it stays red; frames fall at k / fps."""
    rgba = tension_colours(np.array([0.0, 500.0, 1000.0, 5000.0]), 1000.0)
    from matplotlib import colormaps

    turbo = colormaps["turbo"]
    assert np.allclose(rgba[0], turbo(0.0)) and np.allclose(rgba[1], turbo(0.5))
    assert np.allclose(rgba[2], turbo(1.0)) and np.allclose(rgba[3], turbo(1.0))
    assert nice_scale(2938.0) == 5000.0 and nice_scale(1000.0) == 1000.0 and nice_scale(0.013) == 0.02
    assert np.allclose(frame_times(3.0, 30.0), np.arange(90) / 30.0)


@pytest.mark.parametrize("suffix", [".mp4", ".gif"])
def test_three_second_render_has_every_frame_and_they_are_not_blank(tmp_path, suffix):
    """A 3 s render at 320x240 and 30 fps holds 90 frames, read back with imageio; each frame
    has a pixel standard deviation above 10 grey levels (a blank frame has 0; ours are about
    30), and frames differ over time (the overlay's clock at least)."""
    f = tmp_path / "scenario.toml"
    f.write_text(small(3.0))
    out = tmp_path / f"run{suffix}"
    assert cli.main(["render", str(f), "-o", str(out), "--width", "320", "--height", "240", "--camera", "side"]) == 0
    frames = iio.imread(out, index=None)
    assert frames.shape[0] == 90 and frames.shape[1:3] == (240, 320)
    assert all(fr[..., :3].std() > 10.0 for fr in frames)
    assert np.abs(frames[0].astype(int) - frames[-1].astype(int)).sum() > 0
    assert not list(tmp_path.glob(".*partial*"))


def _frame(runner, scale, path):
    rec = VideoRecorder(runner, path, VideoSettings(320, 240, 30, "side", tension_scale=scale))
    try:
        return rec.render()
    finally:
        rec.abort()


def test_tether_is_drawn_in_tension_colours(tmp_path):
    """The same state drawn with a colour scale far below the tether's tension (every element
    at the red end of the map) and far above it (every element at the dark blue end): outside
    the colour bar, red pixels appear only in the first (hundreds of them: the tether's
    footprint)."""
    r = ScenarioRun(load_scenario(text=small(1.0)))
    try:
        t_max = float(r.bt.tension(r.sim.data).max())
        hot, cold = _frame(r, 0.01 * t_max, tmp_path / "a.mp4"), _frame(r, 100.0 * t_max, tmp_path / "b.mp4")
    finally:
        r.close()

    def red_pixels(fr):
        fr = fr.astype(int).copy()
        fr[-40:, :120] = 0  # the colour bar and its label, bottom left
        R, G, B = fr[..., 0], fr[..., 1], fr[..., 2]
        return int(np.sum((R > 60) & (R > 3 * G) & (R > 3 * B)))

    assert red_pixels(hot) > 100
    assert red_pixels(cold) == 0


def test_rendering_does_not_change_the_physics(tmp_path):
    """The same scenario with and without a video gives bitwise equal time series."""
    sc = load_scenario(text=small(2.0))
    plain, _, _ = run(sc, keep_nodes=False)
    video = lambda runner: VideoRecorder(runner, tmp_path / "v.mp4", VideoSettings(160, 120, 10))  # noqa: E731
    filmed, _, info = run(sc, keep_nodes=False, video=video)
    assert info["video"]["frames"] == 20 and (tmp_path / "v.mp4").stat().st_size > 0
    assert np.array_equal(plain, filmed)


def test_run_with_video_puts_it_in_the_results_folder(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text(small(1.0))
    out = tmp_path / "res"
    assert cli.main(["run", str(f), "--out", str(out), "--no-plots", "--video", "clip.gif", "--width", "160",
                     "--height", "120", "--fps", "10"]) == 0
    assert len(iio.imread(out / "clip.gif", index=None)) == 10
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_failed_run_leaves_no_video(tmp_path, capsys):
    """Above the rated load the run stops: no video file, no partial file."""
    f = tmp_path / "s.toml"
    f.write_text(small(5.0).replace("EA = 5.0e6", "EA = 5.0e6\nrated_load = 100.0"))
    assert cli.main(["render", str(f), "-o", str(tmp_path / "v.mp4"), "--width", "160", "--height", "120"]) == 1
    assert "rated load" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == [f]


@pytest.mark.parametrize("args, message", [
    (["--width", "321"], "video.width must be an even number of pixels in [16, 4096]"),
    (["--fps", "0"], "video.fps must be in [1, 120]"),
    (["-o", "run.avi"], "video file must end in .mp4 or .gif"),
    (["--tension-scale", "-1"], "video.tension_scale must be > 0 N"),
])
def test_bad_video_options_are_refused(tmp_path, capsys, args, message):
    f = tmp_path / "s.toml"
    f.write_text(small(1.0))
    argv = ["render", str(f)] + (args if "-o" in args else args + ["-o", str(tmp_path / "v.mp4")])
    assert cli.main(argv) == 2
    assert message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == [f]


def test_missing_opengl_names_the_system_package(monkeypatch):
    """Asking for OSMesa where it is not installed gives an error naming the package to
    install (on a machine that has OSMesa there is nothing to test)."""
    from mjtether.io import render

    if render._probe("osmesa") is None:
        pytest.skip("OSMesa is installed here")
    monkeypatch.setenv("MUJOCO_GL", "osmesa")
    monkeypatch.setattr(render, "_backend", None)
    with pytest.raises(render.RenderUnavailable, match="libosmesa6"):
        render.gl_backend()


def _one_two_five(value: float) -> float:
    """The smallest 1, 2 or 5 x 10^k (k from -3 to 9) at or above ``value``: by listing them."""
    return min(m * 10.0**k for k in range(-3, 10) for m in (1, 2, 5) if m * 10.0**k >= value)


def test_live_colour_scale_is_the_runs_not_the_rated_load(tmp_path):
    """A live video's colour scale by default: twice the largest element tension at the start
    rounded up to 1, 2 or 5 x 10^k N (read here from MuJoCo's constraint forces, ``raw_element_forces``),
    not the rated load (176.8 kN, as a line type's MBL: it would draw the ~1 kN cable dark
    blue), for two cables (1500 and 2500 kg/m^3) whose scales differ; an explicit
    ``tension_scale`` is kept. Exact (a listing of 1-2-5 values against the code's rounding)."""
    from helpers import raw_element_forces

    from mjtether.io.render import ScenarioView

    scales = []
    for density in ("1500.0", "2500.0"):  # (a lighter cable: about 330 N at the top; as in small(): 1050 N)
        text = small(1.0).replace("EA = 5.0e6", "EA = 5.0e6\nrated_load = 176800.0").replace(
            "density = 2500.0", f"density = {density}")
        r = ScenarioRun(load_scenario(text=text))
        try:
            start = float(np.max(-raw_element_forces(r.bt, r.sim.data)))
            assert 100.0 < start < 2000.0
            scales.append(ScenarioView(r).default_scale())
            assert scales[-1] == _one_two_five(2.0 * start)
            rec = VideoRecorder(r, tmp_path / "a.mp4", VideoSettings(64, 48, 10, "side", tension_scale=176800.0))
            try:
                assert rec.scale == 176800.0
            finally:
                rec.abort()
        finally:
            r.close()
    assert scales == [1000.0, 5000.0]  # (follows the run: neither fixed nor the rated load)


def test_replay_colour_scale_is_the_saved_runs_peak(tmp_path, capsys):
    """``mjtether render DIR`` colours by the largest element tension over the whole saved run
    (lines.npz's ``linetether_tension``, every sample and element), rounded up to 1, 2 or
    5 x 10^k N, and says so; the same replay with its saved tensions scaled by 10 gets a scale 10
    times as large, so the scale is not fixed. Exact (a listing of
    1-2-5 values against the code's rounding; 10x a 1-2-5 value is one)."""
    f = tmp_path / "s.toml"
    f.write_text(small(1.0).replace("EA = 5.0e6", "EA = 5.0e6\nrated_load = 176800.0"))
    res = tmp_path / "res"
    assert cli.main(["run", str(f), "--out", str(res), "--no-plots"]) == 0
    with np.load(res / "lines.npz") as z:
        arrays = {k: z[k] for k in z.files}
    peak = float(arrays["linetether_tension"].max())
    video = ["--fps", "2", "--width", "64", "--height", "48", "--camera", "side"]
    capsys.readouterr()
    assert cli.main(["render", str(res), "-o", str(tmp_path / "a.mp4"), *video]) == 0
    assert f"tension colours 0-{_one_two_five(peak):g} N" in capsys.readouterr().out
    from mjtether.io.render import ScenarioView
    from mjtether.io.replay import Replay, Saved

    rep = Replay(Saved(res))
    try:
        assert ScenarioView(rep).default_scale() == _one_two_five(peak)
        rep.saved.tension = 10.0 * rep.saved.tension
        assert ScenarioView(rep).default_scale() == _one_two_five(10.0 * peak) == 10.0 * _one_two_five(peak)
    finally:
        rep.close()

"""The results folder's tension along each line (``line_tension.png``) and the profile's
snapshots (issue 44): the numbers drawn are those of the ``lines.npz`` written, recomputed here
with plain loops; the rated load where the scenario has one; snapshots told apart by colour; the
side view to scale, or an inset to scale where the cable hangs nearly straight down."""

import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from helpers import small  # noqa: E402

from mjtether.io import results  # noqa: E402
from mjtether.network import from_dict  # noqa: E402
from mjtether.network import plots as net_plots  # noqa: E402
from mjtether.network import run as nrun  # noqa: E402
from mjtether.scenario import load_scenario  # noqa: E402
from mjtether.scenario.runner import RECORD_FIELDS, run  # noqa: E402

PAYOUT = '[winch]\nmode = "constant"\nrate = 2.0\nmax_length = 140.0\n'
"""The small anchor scenario paying out at 2 m/s for 3 s: the element at the drum is let go
near the end, so one element is on the drum (length 0) at all samples but the last."""


def by_gid(fig, gid):
    return [a for a in fig.findobj(lambda o: o.get_gid() == gid)]


def expected(tension, length):
    """Each element's (arc length of its centre from end A, least, mean, largest tension) over
    the samples it is deployed (length > 0), by plain loops over the npz arrays; an element's
    length is its median over those samples; elements never deployed are left out."""
    out = []
    s = 0.0
    for j in range(tension.shape[1]):
        ks = [k for k in range(tension.shape[0]) if length[k, j] > 0.0]
        if not ks:
            continue
        lj = float(np.median([length[k, j] for k in ks]))
        t = [float(tension[k, j]) for k in ks]
        out.append((s + lj / 2, min(t), sum(t) / len(t), max(t)))
        s += lj
    return np.array(out).T


@pytest.fixture(scope="module")
def paid_out(tmp_path_factory):
    sc = load_scenario(text=small(3.0, PAYOUT))
    out = results.write(tmp_path_factory.mktemp("lt") / "res", sc, *run(sc))
    with np.load(out / "lines.npz") as z:
        arrays = {k: z[k] for k in z.files}
    return sc, out, arrays


def test_hand_made_arrays():
    """Three elements over three samples, worked by hand: element 2 is on the drum (length 0)
    at the first two samples, so only its 7 N counts; element 1's lengths 1, 1, 3 m have median
    1 m. Exact (the same few floating-point operations)."""
    t = np.array([[1.0, 2.0, 9.0], [3.0, 4.0, 9.0], [5.0, 9.0, 7.0]])
    length = np.array([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 3.0, 0.5]])
    a = net_plots.tension_along(t, length)
    assert np.array_equal(a["arc_length"], [0.5, 1.5, 2.25])
    assert np.array_equal(a["min"], [1.0, 2.0, 7.0])
    assert np.array_equal(a["mean"], [3.0, 5.0, 7.0])
    assert np.array_equal(a["max"], [5.0, 9.0, 7.0])
    assert np.array_equal(a["element"], [0, 1, 2])
    none = net_plots.tension_along(t, length * [1.0, 1.0, 0.0])  # (element 2 never let go: left out)
    assert np.array_equal(none["element"], [0, 1]) and np.array_equal(none["max"], [5.0, 9.0])


def test_folder_lists_line_tension_and_no_track_with_a_tether(paid_out):
    """``line_tension.png`` is written and listed in summary.json's plots; ``track.png`` is not
    (with a tether the profile's top view draws the same tracks)."""
    _, out, _ = paid_out
    plots = json.loads((out / "summary.json").read_text())["plots"]
    assert plots == ["tension.png", "line_tension.png", "profile.png"]
    assert (out / "line_tension.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not (out / "track.png").exists()


def test_plotted_tension_along_the_line_is_the_npz_written(paid_out):
    """The curves' data read back from the figure equal the min, mean and max per element of the
    lines.npz written, recomputed by ``expected`` (loops, not the code under test), to 1e-12
    relative (the mean's summation order differs; N, no kN here: below 10 kN). The element
    still on the drum at every sample but the last counts at that sample only; the elements
    never let go are left out."""
    sc, _, z = paid_out
    tension, length = z["linetether_tension"], z["linetether_element_length"]
    on = length > 0
    assert on[:, 30].tolist() == [False] * (len(on) - 1) + [True]  # (what the test is about)
    assert not on[:, 31:].any()
    s, lo, mean, hi = expected(tension, length)
    fig = results.line_tension_figure(z, sc)
    try:
        ax = fig.axes[0]
        assert ax.get_ylabel() == "tension (N)"
        for gid, want in (("tension_min", lo), ("tension_mean", mean), ("tension_max", hi)):
            (line,) = by_gid(fig, gid)
            x, y = (np.asarray(v, float) for v in line.get_data())
            np.testing.assert_allclose(x, s, rtol=1e-12)
            np.testing.assert_allclose(y, want, rtol=1e-12)
        assert len(s) == 31
    finally:
        plt.close(fig)


def test_arc_length_spans_the_tether():
    """A fixed-length run: the last element's outer end is the tether's 120 m from end A, within
    0.5 % (the elements' lengths are stretched, T / EA ~ 2e-4, and are the chords of a sagging
    cable; the tolerance is loose on both)."""
    sc = load_scenario(text=small(1.0))
    rows, history, info = run(sc)
    from mjtether.io import lines_npz

    z = lines_npz.tether_arrays(rows[:, 0], history)
    a = net_plots.tension_along(z["linetether_tension"], z["linetether_element_length"])
    end = a["arc_length"][-1] + 0.5 * np.median(z["linetether_element_length"][:, -1])
    assert end == pytest.approx(120.0, rel=5e-3)
    assert a["arc_length"][0] == pytest.approx(2.0, rel=5e-3)  # (the first 4 m element's centre)


@pytest.mark.parametrize("rated, drawn", [(2000.0, True), (176800.0, False)])
def test_rated_load_drawn_where_it_is_on_the_scale(paid_out, rated, drawn):
    """The rated load (``tether.rated_load``) is a horizontal line at its value where it is at
    most twice the largest tension (about 1 kN here), else a note giving it in kN and how many
    times the largest tension it is (176.8 kN: the lazy-wave umbilical's line-type MBL)."""
    sc, _, z = paid_out
    sc2 = load_scenario(text=small(3.0, PAYOUT).replace("EA = 5.0e6", f"EA = 5.0e6\nrated_load = {rated}"))
    fig = results.line_tension_figure(z, sc2)
    try:
        (mark,) = by_gid(fig, "rated_load")
        if drawn:
            assert np.allclose(mark.get_ydata(), rated)
            assert "rated load 2000 N" in mark.get_label()
        else:
            top = z["linetether_tension"].max()
            assert mark.get_text().startswith("rated load 176.8 kN")
            assert f"{rated / top:.3g}x" in mark.get_text()
    finally:
        plt.close(fig)
    fig = results.line_tension_figure(z, sc)  # (no rated load: nothing drawn)
    try:
        assert not by_gid(fig, "rated_load")
    finally:
        plt.close(fig)


def test_network_line_tension_per_line(tmp_path):
    """A network's folder lists line_tension.png; the panel of each line draws the least, mean
    and largest tension per element of its lines.npz tension over the run (``expected``, element
    lengths from the nodes), to 1e-12 relative (kN above 10 kN: scaled back); no rated load (network line types have none)."""
    net = from_dict({"water": {"depth": 100.0}, "simulation": {"duration": 0.5, "output_interval": 0.25},
                     "line_types": {"rope": {"diameter": 0.08, "mass_per_length": 12.0, "EA": 5e7}},
                     "points": {"anchor": {"kind": "fixed", "position": [120.0, 0.0, -100.0]},
                                "top": {"kind": "fixed", "position": [0.0, 0.0, -10.0]},
                                "mid": {"kind": "fixed", "position": [60.0, 30.0, -100.0]}},
                     "lines": [{"name": "1", "type": "rope", "a": "anchor", "b": "top", "length": 160.0,
                                "segments": 10},
                               {"name": "2", "type": "rope", "a": "mid", "b": "top", "length": 130.0,
                                "segments": 8}]})
    r, rows = nrun.simulate(net)
    r.sim.close()
    nrun.write(r, rows, tmp_path)
    assert json.loads((tmp_path / "summary.json").read_text())["plots"] == ["tension.png", "profile.png",
                                                                            "line_tension.png"]
    fig = net_plots.line_tension_figure(r.net, r.history)
    try:
        assert not by_gid(fig, "rated_load")
        with np.load(tmp_path / "lines.npz") as z:
            for name, ax in zip(("1", "2"), fig.axes):
                nodes, tension = z[f"line{name}_nodes"], z[f"line{name}_tension"]
                length = np.sqrt(((nodes[:, 1:] - nodes[:, :-1]) ** 2).sum(axis=2))
                s, lo, mean, hi = expected(tension, length)
                drawn = {ln.get_gid(): ln for ln in ax.get_lines()}
                k = 1e3 if ax.get_ylabel() == "tension (kN)" else 1.0
                assert ax.get_ylabel() == ("tension (kN)" if hi.max() > 1e4 else "tension (N)")
                for gid, want in (("tension_min", lo), ("tension_mean", mean), ("tension_max", hi)):
                    np.testing.assert_allclose(drawn[gid].get_xdata(), s, rtol=1e-12)
                    np.testing.assert_allclose(k * drawn[gid].get_ydata(), want, rtol=1e-12)
                assert name in ax.get_title()
    finally:
        plt.close(fig)


# ------------------------------------------------------------------ the profile


def _rows_nodes(cable_end, n=6, duration=5.0):
    """Hand-made rows and nodes (samples, 9, 3) of a straight cable from the ship at the
    origin to ``cable_end`` (m), its far end moving 1 m along +x over the run."""
    rows = np.zeros((n, len(RECORD_FIELDS)))
    rows[:, 0] = np.linspace(0.0, duration, n)
    s = np.linspace(0.0, 1.0, 9)[:, None]
    nodes = np.array([s * (np.asarray(cable_end, float) + [k / (n - 1), 0.0, 0.0]) for k in range(n)])
    return rows, nodes


def test_snapshots_have_distinct_colours_and_their_times(paid_out):
    """Six snapshots, each in its own colour (no two within 0.02 in RGB), the same in side and
    top view, labelled with their times in s (0, 0.5, ..., 3 s: the samples are 0.5 s apart)."""
    sc, _, _ = paid_out
    rows, nodes = _rows_nodes([60.0, 0.0, -80.0], n=7, duration=3.0)
    fig = results.profile_figure(rows, nodes, sc)
    try:
        side, top = fig.axes
        shots = [ln for ln in side.get_lines() if ln.get_gid() == "snapshot"]
        colours = np.array([matplotlib.colors.to_rgb(ln.get_color()) for ln in shots])
        assert len(shots) == 6
        gaps = np.abs(colours[:, None] - colours[None]).max(axis=2) + np.eye(len(shots))
        assert gaps.min() > 0.02
        tops = np.array([matplotlib.colors.to_rgb(ln.get_color()) for ln in top.get_lines()
                         if ln.get_gid() == "snapshot"])
        assert np.array_equal(tops, colours)
        assert [ln.get_label() for ln in shots] == ["t = 0 s", "t = 0.5 s", "t = 1 s", "t = 2 s", "t = 2.5 s",
                                                    "t = 3 s"]
    finally:
        plt.close(fig)


def _equal_on_screen(ax) -> float:
    """|1 - (pixels per m along x) / (pixels per m along z)| of ``ax`` as drawn."""
    ax.figure.canvas.draw()
    (x0, y0), (x1, y1) = ax.transData.transform([(0.0, 0.0), (1.0, 1.0)])
    return abs(1.0 - (x1 - x0) / (y1 - y0))


def test_side_view_to_scale(paid_out):
    """A cable 60 m across and 80 m down: the side view has equal axes (1 m of x as many pixels as
    1 m of z, to 1e-6) and no inset."""
    sc, _, _ = paid_out
    rows, nodes = _rows_nodes([60.0, 0.0, -80.0])
    fig = results.profile_figure(rows, nodes, sc)
    try:
        side = fig.axes[0]
        assert side.get_aspect() == 1.0 and _equal_on_screen(side) < 1e-6
        assert not by_gid(fig, "to_scale")
    finally:
        plt.close(fig)


def test_nearly_vertical_cable_gets_an_inset_to_scale():
    """A cable 4.5 m across and 1000 m down (under 1 % of its z extent): the side view is
    stretched along x and an inset draws it to scale (equal axes on screen, to 1e-6), the whole
    1000 m in view."""
    sc = load_scenario(text='[water]\ndepth = 1000.0\n[robot]\ntype = "anchor"\nposition = [3.5, 0.0, -1000.0]\n'
                       '[tether]\nlength = 1010.0\n')
    rows, nodes = _rows_nodes([3.5, 0.0, -1000.0])
    fig = results.profile_figure(rows, nodes, sc)
    try:
        side = fig.axes[0]
        (inset,) = by_gid(fig, "to_scale")
        assert _equal_on_screen(inset) < 1e-6 and _equal_on_screen(side) > 10.0
        lo, hi = inset.get_ylim()
        assert lo <= -1000.0 and hi >= 0.0
        assert "inset to scale" in side.get_title()
    finally:
        plt.close(fig)


def test_seabed_far_below_a_shallow_cable_is_left_out_of_view(paid_out):
    """A cable 1.25 m long at 50 m depth in 1000 m of water (the AUV example's first seconds):
    drawn to scale around the cable, not as a dot above 950 m of water; the legend says the
    seabed and the surface are out of view."""
    sc = load_scenario(text='[water]\ndepth = 1000.0\n[robot]\ntype = "anchor"\nposition = [1.0, 0.0, -50.0]\n'
                       '[tether]\nlength = 60.0\n')
    rows, nodes = _rows_nodes([0.25, 0.0, 0.0])
    nodes[..., 2] = -50.0
    fig = results.profile_figure(rows, nodes, sc)
    try:
        side = fig.axes[0]
        assert _equal_on_screen(side) < 1e-6
        lo, hi = side.get_ylim()
        assert hi - lo < 10.0 and lo < -50.0 < hi
        legend = [t.get_text() for t in side.get_legend().get_texts()]
        assert any("seabed" in t and "out of view" in t for t in legend)
        assert any("water surface" in t and "out of view" in t for t in legend)
    finally:
        plt.close(fig)

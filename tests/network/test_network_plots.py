"""A network's results folder has its plots, and they draw the numbers the folder holds."""

import json

import numpy as np

from mjtether.network import from_dict, plots, run


def _net():
    return from_dict({"water": {"depth": 100.0}, "simulation": {"duration": 1.0, "output_interval": 0.25},
                      "line_types": {"rope": {"diameter": 0.08, "mass_per_length": 12.0, "EA": 5e7}},
                      "points": {"anchor": {"kind": "fixed", "position": [120.0, 0.0, -100.0]},
                                 "top": {"kind": "fixed", "position": [0.0, 0.0, -10.0]}},
                      "lines": [{"name": "1", "type": "rope", "a": "anchor", "b": "top", "length": 160.0,
                                 "segments": 20}]})


def test_plots_are_written_and_draw_the_time_series(tmp_path):
    """tension.png and profile.png are in the folder and summary.json lists them; the tension
    figure's curves are timeseries.csv's end-tension columns, the profile's solid curve the last
    sample of lines.npz's nodes (read back from the files, not from the run)."""
    r, rows = run.simulate(_net())
    r.sim.close()
    run.write(r, rows, tmp_path)
    assert json.loads((tmp_path / "summary.json").read_text())["plots"] == ["tension.png", "profile.png", "line_tension.png"]
    assert all((tmp_path / f).stat().st_size > 10_000 for f in ("tension.png", "profile.png"))
    csv = np.genfromtxt(tmp_path / "timeseries.csv", delimiter=",", names=True)
    cols = run.columns(r.net)
    fig = plots.tension_figure(r.net, cols, rows)
    scale = 1e3 if "(kN)" in fig.axes[0].get_ylabel() else 1.0
    drawn = [scale * ln.get_ydata() for ln in fig.axes[0].get_lines()]
    np.testing.assert_allclose(drawn[0], csv["line1_A_tension_N"], rtol=1e-8)
    np.testing.assert_allclose(drawn[1], csv["line1_B_tension_N"], rtol=1e-8)
    with np.load(tmp_path / "lines.npz") as z:
        nodes = z["line1_nodes"]
    side = plots.profile_figure(r.net, r.history).axes[0].get_lines()
    np.testing.assert_allclose(side[1].get_ydata(), nodes[-1, :, 2], rtol=1e-12)

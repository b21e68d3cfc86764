"""A line sliding down a 10 deg slope given as a bathymetry grid, against Coulomb: a = (w / m)
(sin a - mu cos a) along the slope, w the wet weight per metre, m the mass per metre (sliding
along its own axis: no axial added mass, CaAx = 0, and no axial drag, CdAx = 0; no normal
velocity, so no normal drag). Its start lies on the grid: the statics lay a line on a level
seabed at its low end, which put its uphill nodes inside the slope (the line was thrown out and
folded, one end running 5 m uphill)."""

import math

import numpy as np
import pytest

from mjtether.network import from_dict, run

RHO, G = 1025.0, 9.80665
D, M, L = 0.05, 12.0, 20.0  # m, kg/m, m
SLOPE = math.radians(10.0)


def _slide(tmp_path, mu: float):
    xs, ys = np.arange(-10.0, 62.0, 2.0), np.arange(-10.0, 12.0, 2.0)
    np.savetxt(tmp_path / "slope.csv", np.array([[20.0 + x * math.tan(SLOPE) for x in xs] for _ in ys]),
               delimiter=",")  # (depths, m: the seabed at z = -20 - x tan(a))

    def on(x):
        return [x, 0.0, -20.0 - x * math.tan(SLOPE)]  # (a network's line rests with its axis on the seabed)

    net = from_dict({
        "water": {"depth": 40.0 + 70.0 * math.tan(SLOPE), "rho": RHO, "gravity": G, "seabed_friction": mu,
                  "bathymetry": str(tmp_path / "slope.csv"), "bathymetry_spacing_m": 2.0,
                  "bathymetry_origin_m": [-10.0, -10.0]},
        "simulation": {"duration": 4.0, "output_interval": 0.05, "start": "as_written"},
        "line_types": {"l": {"diameter": D, "mass_per_length": M, "EA": 1e8, "cd_normal": 1.2, "ca_normal": 1.0,
                             "cd_tangential": 0.0, "ca_tangential": 0.0}},
        "points": {"a": {"kind": "free", "position": on(0.0)}, "b": {"kind": "free", "position": on(L * math.cos(SLOPE))}},
        "lines": [{"name": "1", "type": "l", "a": "a", "b": "b", "length": L, "segments": 10}]})
    r, rows = run.simulate(net)
    r.sim.close()
    return net, rows


def test_a_line_slides_down_a_grid_slope_as_coulomb_says(tmp_path):
    """The issue's case, mu = 0.1 on 10 deg: each end's acceleration down the slope, fitted to its
    path over 2.5-4 s (the line first straightens from its start), within 2 % of Coulomb's (the
    issue's bound; measured 1e-6 and 6e-4; the issue measured 8.4 % slow, before the line ends'
    masses moved into their points); both ends stay on the grid (their
    axis on it, as a network's lines rest, within 2 mm: the contact's give). (Frictionless, the
    start's axial ringing is undamped and one end's fit over the same window is 10 % off while
    the other's is within 1e-4: not a test of Coulomb.)"""
    mu = 0.1
    net, rows = _slide(tmp_path, mu)
    cols = run.columns(net)
    t = rows[:, 0]
    late = t >= 2.5
    w = (M - RHO * math.pi * D ** 2 / 4) * G
    coulomb = w / M * (math.sin(SLOPE) - mu * math.cos(SLOPE))
    for end in "ab":
        x, z = rows[:, cols.index(f"point{end}_x_m")], rows[:, cols.index(f"point{end}_z_m")]
        along = (x - x[0]) / math.cos(SLOPE)
        assert 2.0 * np.polyfit(t[late], along[late], 2)[0] == pytest.approx(coulomb, rel=0.02)
        over = z - (-20.0 - x * math.tan(SLOPE))
        assert np.all(np.abs(over[t > 0.2]) < 2e-3), (end, np.abs(over).max())

"""The report's moving sea (``report_data.collect``'s ``surface/eta``): a network run's and a
scenario run's surface on the page's grid is the sea the run had, its build-up ramp included,
against Airy's eta = a cos(k (x cos b + y sin b) - omega t + phase) times the half-cosine ramp,
both written here: k from omega^2 = g k tanh(k h) solved with scipy (Brent), the ramp r(t) =
(1 - cos(pi t / T_r)) / 2 for 0 < t < T_r (1 after; T_r = ramp_periods x period, ``waves.ramp_periods``'s
documented formula), not from mjtether. Tolerance 1e-5 m: the page holds float32 of a metre-high
sea (2**-24 relative, ~1e-7 m), the closed form is otherwise exact."""

import math
import re
import tomllib

import numpy as np
import pytest
import scipy.optimize

from mjtether.io import results
from mjtether.io.report import write_report
from mjtether.io.report_data import decode
from mjtether.network import from_dict
from mjtether.network import run as network_run
from mjtether.scenario import load_scenario
from mjtether.scenario.runner import run

TOL = 1e-5
"""m: float32 of a ~1 m surface (see the module docstring)."""

NETWORK = """
[water]
depth = 40.0
gravity = 9.80665
[simulation]
duration = 2.0
output_interval = 0.1
start = "as_written"
[line_types.rope]
diameter = 0.1
mass_per_length = 15.0
EA = 1e6
cd_normal = 1.2
ca_normal = 1.0
[points.anchor]
kind = "fixed"
position = [-40.0, 0.0, -40.0]
[points.fairlead]
kind = "fixed"
position = [0.0, 0.0, -5.0]
[[lines]]
name = "rope"
type = "rope"
a = "anchor"
b = "fairlead"
length = 55.0
segments = 8
"""
NET_WAVES = """
[waves]
type = "regular"
height = 1.6
period = 4.0
heading_deg = 25.0
phase_deg = 50.0
ramp_periods = 0.25
"""
"""A regular wave ramped in over its first second (0.25 x 4 s): the 2 s run has frames before
and after the ramp's end."""

SCENARIO = """
[simulation]
duration = 1.5
output_interval = 0.25
[water]
depth = 50.0
gravity = 9.81
[robot]
type = "anchor"
position = [30.0, 0.0, -50.0]
[tether]
length = 70.0
segments = 10
[waves]
type = "regular"
height = 2.0
period = 2.0
heading_deg = -40.0
phase_deg = 10.0
ramp_periods = 0.5
"""


def payload(page):
    text = page.read_text()
    return decode(re.search(r'<script type="application/octet-stream" id="payload">([^<]*)</script>', text).group(1))


def airy(meta, a, *, amplitude, period, heading_deg, phase_deg, depth, g, ramp_s):
    """The expected surface (F, n, n; m) on the page's grid at its frames' times: Airy's eta
    times the build-up ramp, both written here."""
    n = meta["surface"]["grid"]
    x0, x1, y0, y1 = meta["surface"]["box"]
    gx, gy = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n))
    w = 2 * math.pi / period
    k = scipy.optimize.brentq(lambda kk: g * kk * math.tanh(kk * depth) - w * w, 1e-8, 100.0, xtol=1e-15)
    b, p = math.radians(heading_deg), math.radians(phase_deg)
    out = []
    for t in np.asarray(a["t"], float):
        r = 1.0 if t >= ramp_s else (0.0 if t <= 0.0 else 0.5 * (1.0 - math.cos(math.pi * t / ramp_s)))
        out.append(r * amplitude * np.cos(k * (gx * math.cos(b) + gy * math.sin(b)) - w * t + p))
    return np.array(out)


def _network_page(tmp_path, text):
    net = from_dict(tomllib.loads(text), "test.toml")
    out = tmp_path / "run"
    network_run.run_to(net, out, plots=False)
    return payload(write_report(out))


def test_network_report_draws_the_runs_ramped_regular_wave(tmp_path):
    """A network with ``[waves] type = "regular"``: the page's surface at every frame is
    H/2 cos(k (x cos b + y sin b) - omega t + phase) times the ramp (1e-5 m: float32), on a moving
    grid (not the flat 2 x 2 plane); the frames span the ramp and the full sea after it."""
    meta, a = _network_page(tmp_path, NETWORK + NET_WAVES)
    assert meta["kind"] == "network" and meta["surface"]["grid"] == 25
    eta = a["surface/eta"]
    t = np.asarray(a["t"], float)
    assert eta.shape == (len(t), 25, 25) and t[0] == 0.0 and t[-1] > 1.9
    assert (t < 1.0).sum() >= 5 and (t > 1.0).sum() >= 5  # (inside the ramp and after it)
    want = airy(meta, a, amplitude=0.8, period=4.0, heading_deg=25.0, phase_deg=50.0, depth=40.0, g=9.80665,
                ramp_s=1.0)
    assert np.max(np.abs(eta - want)) < TOL
    assert np.max(np.abs(eta[0])) < TOL  # (the ramp starts the sea from rest: flat at t = 0)
    assert np.max(np.abs(eta[-1])) > 0.5  # (and the full wave after it)


@pytest.mark.parametrize("extra", ["", '\n[waves]\ntype = "none"\n'], ids=["no waves", "type none"])
def test_network_flat_sea_stays_flat(tmp_path, extra):
    """A network without waves (no ``[waves]``, or ``type = "none"``): no surface heights, the flat
    2 x 2 plane at z = 0."""
    meta, a = _network_page(tmp_path, NETWORK + extra)
    assert "surface/eta" not in a and meta["surface"]["grid"] == 2


def test_scenario_report_draws_the_runs_ramp(tmp_path):
    """A scenario run in a regular wave ramped in over half its 2 s period: the page's surface is
    Airy's times the ramp (1e-5 m: float32), so the frames inside the first second are the
    reduced sea the run had, not the full one."""
    sc = load_scenario(text=SCENARIO)
    rows, history, info = run(sc)
    folder = results.write(tmp_path / "run", sc, rows, history, info, plots=False)
    meta, a = payload(write_report(folder))
    t = np.asarray(a["t"], float)
    assert (t < 1.0).sum() >= 3 and (t > 1.0).sum() >= 1
    want = airy(meta, a, amplitude=1.0, period=2.0, heading_deg=-40.0, phase_deg=10.0, depth=50.0, g=9.81,
                ramp_s=1.0)
    assert np.max(np.abs(a["surface/eta"] - want)) < TOL

"""A network's lines and bodies against answers that do not come from mjtether: the closed-form
stretch of a stiff line (and the warning where the step softens it), Archimedes' draft and heave
period of a floating body."""

import dataclasses
import json
import math
import warnings

import numpy as np
import pytest

from mjtether.cable.softening import EAWarning
from mjtether.network import from_dict, run

RHO, G = 1025.0, 9.80665


def _stiff_line(timestep=None):
    """A 100 m wire of EA 1e9 N (2 kg/m, 20 mm) in 200 segments hanging a 200 kg clump from a
    fixed point 10 m down."""
    return from_dict({"water": {"depth": 200.0, "rho": RHO},
                      "simulation": {"duration": 2.0, "timestep": timestep},
                      "line_types": {"wire": {"diameter": 0.02, "mass_per_length": 2.0, "EA": 1e9}},
                      "points": {"top": {"kind": "fixed", "position": [0.0, 0.0, -10.0]},
                                 "clump": {"kind": "free", "position": [0.0, 0.0, -110.0], "mass": 200.0}},
                      "lines": [{"name": "w", "type": "wire", "a": "clump", "b": "top", "length": 100.0,
                                 "segments": 200}]})


def test_a_stiff_line_keeps_its_EA_at_the_step_mjtether_takes(tmp_path):
    """Its stretch after 2 s against the closed form int_0^L (W_clump + w s) / EA ds (w its wet
    weight per metre): 0.278 mm, within 1 % (the issue's bound; measured 3e-11 relative). At the
    1.7 ms step taken before, the line ran at 14 % of its EA and stretched 2.01 mm with no word;
    now that step (given by the user) warns, naming the effective EA, and summary.json carries
    it per line."""
    net = _stiff_line()
    r, rows = run.simulate(net)
    try:
        x = r.line_nodes("w")
        stretch = float(np.linalg.norm(np.diff(x, axis=0), axis=1).sum()) - 100.0
    finally:
        r.sim.close()
    w = (2.0 - RHO * math.pi * 0.02 ** 2 / 4) * G
    closed = (200.0 * G * 100.0 + w * 100.0 ** 2 / 2) / 1e9
    assert stretch == pytest.approx(closed, rel=0.01)
    run.write(r, rows, tmp_path)
    assert json.loads((tmp_path / "summary.json").read_text())["lines"]["w"]["effective_EA"]["ratio"] >= 0.99
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        soft = run.build(dataclasses.replace(net, timestep=0.0017))
        soft.sim.close()
    said = [str(m.message) for m in seen if issubclass(m.category, EAWarning)]
    assert len(said) == 1 and "line 'w'" in said[0] and "effective EA" in said[0], said
    assert soft.effective_EA["w"]["ratio"] < 0.2


def test_a_floating_body_has_archimedes_draft_and_heave_period():
    """A 2 m^3 free body at 0.4 of the water's density, no drag, Ca 0.5, released 5 cm above its
    waterline: an upright cylinder of its volume as tall as wide (h = (4 V / pi)^(1/3), waterplane
    A = V / h) floats with its centre h / 2 - 0.4 h above the surface and heaves at
    T = 2 pi sqrt((m + Ca rho V) / (rho g A)). Mean height within 1 mm (of an undamped 5 cm
    heave; measured 0.04 mm) and period within 2 % (measured 1e-5). The fixed 1 m band used
    before gave a period 15 % short and a draft 0.37 m off."""
    V, share, ca = 2.0, 0.4, 0.5
    h = (4 * V / math.pi) ** (1 / 3)
    m, z_eq = share * RHO * V, h / 2 - share * h
    net = from_dict({"water": {"depth": 50.0, "rho": RHO},
                     "simulation": {"duration": 20.0, "output_interval": 0.01, "start": "as_written"},
                     "bodies": {"buoy": {"kind": "free", "position": [0, 0, z_eq + 0.05], "mass": m,
                                         "inertia": [1e3] * 3, "volume": V, "ca": [ca] * 3}}})
    r, rows = run.simulate(net)
    r.sim.close()
    t, z = rows[:, 0], rows[:, run.columns(net).index("bodybuoy_z_m")] - z_eq
    up = np.flatnonzero((z[:-1] < 0) & (z[1:] >= 0))
    crossings = t[up] - z[up] * (t[up + 1] - t[up]) / (z[up + 1] - z[up])
    period = float(np.mean(np.diff(crossings)))
    assert period == pytest.approx(2 * math.pi * math.sqrt((m + ca * RHO * V) / (RHO * G * V / h)), rel=0.02)
    assert abs(float(np.mean(z[t >= t[up[0]]][: int(round(5 * period / 0.01))]))) < 1e-3

"""A buoyant line lying on the surface floats at its draft (Archimedes), a float's waterplane
holding it there, where buoyancy by the axis alone would switch on and off as the axis crossed
z = 0 and leave it chattering there (MoorDyn's tripod.txt float, tests/io/test_moordyn_files.py)."""

import math

import numpy as np
import pytest
import scipy.optimize

from mjtether.network import from_dict, run


@pytest.mark.parametrize("offset", [0.01, -0.01])
def test_a_level_float_line_rests_at_its_draft(offset):
    """A 10 m line 0.5 m wide at 0.4 of the water's density, its ends free, released level with
    its axis 1 cm above or below its draft: the draft, where the wet part of its cross-section is
    0.4 of the whole (the circular segment: (pi - acos c + c sqrt(1 - c^2)) / pi = 0.4 with the
    axis c r under the water; c = -0.158, the axis 39.4 mm above the surface). It heaves about
    there (nothing radiates waves to damp it, and drag at Cd 10 damps a heave of millimetres
    slowly), so its mean height over the last 20 s of 40 s is compared: within 0.5 mm, what
    is left of the decaying heave in that mean (measured 0.26 mm from above, 0.27 mm from below).
    By the axis alone it would fall onto z = 0 and chatter there, 39 mm off."""
    rho, d, ratio = 1025.0, 0.5, 0.4
    area = math.pi * d * d / 4
    c = scipy.optimize.brentq(lambda c: (math.pi - math.acos(c) + c * math.sqrt(1 - c * c)) / math.pi - ratio, -1, 1)
    axis = -c * d / 2
    assert axis == pytest.approx(0.0394, abs=1e-4)
    z0 = axis + offset
    data = {"water": {"depth": 50.0, "rho": rho}, "simulation": {"duration": 40.0},
            "line_types": {"f": {"diameter": d, "mass_per_length": ratio * rho * area, "EA": 1e7,
                                 "cd_normal": 10.0}},
            "points": {"a": {"kind": "free", "position": [0.0, 0.0, z0], "mass": 0.0, "volume": 0.0},
                       "b": {"kind": "free", "position": [10.0, 0.0, z0], "mass": 0.0, "volume": 0.0}},
            "lines": [{"name": "1", "type": "f", "a": "a", "b": "b", "length": 10.0, "segments": 10}]}
    r, rows = run.simulate(from_dict(data))
    r.sim.close()
    cols = run.columns(r.net)
    late = rows[:, 0] >= 20.0
    for end in "ab":
        z = rows[late, cols.index(f"point{end}_z_m")]
        assert np.mean(z) == pytest.approx(axis, abs=5e-4), np.mean(z)

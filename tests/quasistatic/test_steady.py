"""``steady_state`` where its Newton iteration stalls: the Levenberg-Marquardt fallback."""

import numpy as np
import pytest

import mjtether as mt
from mjtether.quasistatic import steady_state
@pytest.mark.parametrize("span", [200.0, 400.0, 600.0])
def test_the_readme_line_solves_in_currents_up_to_3_kn(span):
    """The docs' line (python_api.md: 800 m, 20 mm, 1050 kg/m^3, EA 2e6 N, a density falling from 1025 to 980
    kg/m^3 over 500 m) from a fixed top to the seabed 500 m down and ``span`` m away, in an
    exponential surface current (15 m decay) of 0 to 3 kn: every case solves (Newton used to
    stall at 3 kn, where its first guess sits in a basin it cannot leave; Levenberg-Marquardt then
    takes over), its last node on the bottom end within the solver's tolerance, nothing above the
    surface. (At 3.5 kn the 400 m span finds none: Levenberg-Marquardt's best leaves the end 45 m
    off from every start tried, a current that would carry the cable along the surface.)"""
    tether = mt.TetherSpec(length=800, segments=100, diameter=0.02, density=1050, EA=2e6)
    for kn in (0.0, 1.0, 2.0, 2.5, 3.0):
        water = mt.WaterColumn(depth=500, density=mt.LinearDensity(1025, 980, 500),
                               current=mt.ExponentialCurrent(mt.knots(kn), decay_depth=15))
        ss = steady_state(tether, water, top=[0, 0, 0], bottom=[span, 0, -500])
        assert np.linalg.norm(ss.nodes[-1] - [span, 0.0, -500.0]) <= 1e-6 * 800.0, kn
        assert ss.nodes[1:, 2].max() < 0.0, kn

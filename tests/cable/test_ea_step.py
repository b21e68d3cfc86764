"""The EA asked for, or the run says so: at a step too long for the axial mode the solver makes
each element as stiff as the step allows (``cable.builder``), and the run warns once with the
effective EA and the step that keeps it (``stability.ea_timestep``, ``max_timestep(keep_EA=True)``),
and records it in summary.json (``run.effective_EA``). Checked against the elastic catenary's own
stretch, int_0^L T(s) ds / EA, of the line between the same ends (``quasistatic.catenary``, H and
V at the fairlead: T(s) = sqrt(H^2 + (V_F - w (L - s))^2))."""

import math
import warnings

import numpy as np
import pytest

from mjtether.cable import stability
from mjtether.cable.tether import TetherSpec
from mjtether.physics.water import WaterColumn
from mjtether.quasistatic import catenary
from mjtether.scenario import load_scenario
from mjtether.scenario.runner import EAWarning, ScenarioRun

TOML = """[simulation]
timestep = {dt}
[water]
depth = 100.0
[tether]
length = 120.0
segments = 100
diameter = 0.03
mass_per_length = 1.5
EA = 1e7
[robot]
type = "anchor"
position = [90.0, 0.0, -60.0]
"""
SPEC = TetherSpec(length=120.0, segments=100, diameter=0.03, mass_per_length=1.5, EA=1e7)
WATER = WaterColumn(depth=100.0)


def _stretch(dt):
    """(stretch after 30 s of a still line at step dt, m; the run's effective EA record; its EA warnings)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run = ScenarioRun(load_scenario(text=TOML.format(dt=dt)))
    try:
        for _ in range(int(round(30.0 / dt))):
            run.step()
        return (run.bt.stretched_length(run.sim.data) - 120.0, run.effective_EA,
                [str(c.message) for c in caught if issubclass(c.category, EAWarning)])
    finally:
        run.close()


def _catenary_stretch(EA):
    wet = (1.5 - 1025.0 * math.pi * 0.03 ** 2 / 4) * 9.81
    c = catenary([90.0, 0.0, -60.0], [0.0, 0.0, 0.0], 120.0, wet, EA=EA, seabed=False)
    s = np.linspace(0.0, 120.0, 20001)
    return float(np.trapezoid(np.hypot(c.H, c.VF - wet * (120.0 - s)), s)) / EA


def test_at_the_step_that_keeps_EA_the_line_stretches_as_its_EA_says():
    """``max_timestep(keep_EA=True)`` (16 ms for this line of 1.2 m elements): no warning, the
    effective EA is the EA asked for and the line stretches by its catenary's int T ds / EA within
    1 % (measured 0.02 %)."""
    dt = stability.max_timestep(SPEC, WATER, keep_EA=True)
    assert dt == pytest.approx(stability.ea_timestep(SPEC, WATER))
    stretch, eff, warned = _stretch(dt)
    assert not warned and eff["ratio"] == pytest.approx(1.0, abs=1e-9)
    assert stretch == pytest.approx(_catenary_stretch(1e7), rel=0.01)


def test_at_the_stable_step_the_run_says_how_soft_the_cable_is():
    """At ``max_timestep``'s stable step (47 ms here) the cable runs at 11 % of its EA: the run
    warns, naming the effective EA and the step that keeps EA, summary.json records it, and the
    line stretches as that effective EA says within 1 % (measured 0.5 %; 8.7 times the stretch
    of the EA asked for)."""
    dt = min(stability.max_timestep(SPEC, WATER), 0.05)
    stretch, eff, warned = _stretch(dt)
    assert len(warned) == 1 and f"{eff['effective_N']:.3g} N of the 1e+07 N asked" in warned[0]
    assert f"simulation.timestep = {stability.ea_timestep(SPEC, WATER):.3g} s or less keeps it" in warned[0]
    assert eff["ratio"] < 0.5
    assert stretch == pytest.approx(_catenary_stretch(eff["effective_N"]), rel=0.01)
    assert stretch > 5 * _catenary_stretch(1e7)

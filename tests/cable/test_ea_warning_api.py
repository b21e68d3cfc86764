"""The Python API says when a tether runs softer than its EA (``Simulation(warn_EA=True)``): at
``max_timestep(tension=...)``'s stable step a stiff line holding a clump stretches as its
effective EA says, not as its EA does, and the warning names the tether, the effective EA and
the step that keeps it. Checked against the closed-form stretch of a vertical line of wet weight
w per metre holding a weight W at its end: int_0^L (W + w s) ds / EA = (W L + w L^2 / 2) / EA."""

import math
import warnings

import mujoco

import mjtether as mt
from mjtether.cable.softening import EAWarning

L, N, EA, M = 100.0, 200, 1e7, 50.0
TETHER = mt.TetherSpec(length=L, segments=N, diameter=0.02, mass_per_length=1.0, EA=EA)
WATER = mt.WaterColumn(depth=300.0)
W_LINE = (1.0 - 1025.0 * math.pi * 0.01 ** 2) * WATER.gravity
TENSION = M * WATER.gravity + W_LINE * L


def _hang(dt: float, seconds: float = 20.0):
    """(stretch after ``seconds``, m; the smallest effective EA, N; the EA warnings)."""
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.gravity = [0.0, 0.0, -WATER.gravity]
    clump = spec.worldbody.add_body(name="clump", pos=[0.0, 0.0, -L])
    clump.add_freejoint()
    clump.explicitinertial = True
    clump.mass, clump.inertia = M, [1.0, 1.0, 1.0]
    clump.add_site(name="clump")
    tm = mt.add_tether(spec, TETHER, mt.FixedPoint([0.0, 0.0, 0.0]), mt.SitePoint("clump"), water=WATER)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sim = mt.Simulation(spec, WATER, [tm])
    with sim:
        sim.run(seconds)
        bt = sim.tether()
        return (bt.stretched_length(sim.data) - L, float(bt.effective_EA.min()),
                [str(c.message) for c in caught if issubclass(c.category, EAWarning)])


def _closed_form(ea: float) -> float:
    return (M * WATER.gravity * L + W_LINE * L * L / 2.0) / ea


def test_the_stable_step_warns_and_the_line_stretches_as_the_effective_EA_says():
    """At the stable step for its tension (13.5 ms) the line keeps 14 % of its EA: one warning
    naming the tether and the effective EA, and the stretch is the closed form's at that EA
    within 1 % (measured 1e-6; 6.9 times the stretch at the EA asked for). The step it names
    keeps the EA: the stretch there is the closed form's at EA within 1 % (measured 4e-7)."""
    dt = mt.stability.max_timestep(TETHER, WATER, tension=TENSION)
    stretch, eff, warned = _hang(dt)
    assert len(warned) == 1
    assert "tether 'tether' EA" in warned[0] and f"effective EA {eff:.3g} N of the 1e+07 N asked" in warned[0]
    assert eff < 0.5 * EA
    assert abs(stretch - _closed_form(eff)) < 0.01 * _closed_form(eff)
    factor = float(warned[0].split("a step ")[1].split(" times")[0])
    stretch, eff, warned = _hang(dt * factor)
    assert not warned and eff > 0.99 * EA
    assert abs(stretch - _closed_form(EA)) < 0.01 * _closed_form(EA)

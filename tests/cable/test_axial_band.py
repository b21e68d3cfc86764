"""Every (mass per length, time step, EA) the builder accepts must give the right statics; the
rest must be refused with a reason.

A sweep over mass per length 1-1000 kg/m (with 98-130 kg/m, a band that used to break),
time steps over three decades and EA from soft to inextensible: a short heavy cable between two
fixed points, started from its static shape and settled with extra damping, against the
analytic elastic catenary.
"""

import math
import re

import numpy as np
import pytest
from conftest import new_spec

import mjtether as mt
from mjtether.quasistatic import catenary, steady_state

MASSES = (1.0, 10.0, 98.0, 100.0, 115.0, 130.0, 1000.0)  # kg/m
STEPS = (1e-4, 1e-3, 1e-2)  # s
EAS = (None, 1e6, 1e9)  # N; None: inextensible

P_TOP, P_END = np.array([0.0, 0.0, -5.0]), np.array([10.0, 0.0, -7.0])
LENGTH, SEGMENTS = 12.0, 15  # l0 = 0.8 m
DENSITY = 5000.0  # kg/m^3: the diameter follows the mass per length
RHO = 1025.0
DAMPING_RATE = 5.0  # 1/s, linear damping of every node dof per unit of its inertia (settling only)
REASON = re.compile(r"EA|mass.per.length|time.?step|axial", re.IGNORECASE)
SECONDS = re.compile(r"(\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)\s*s\b")


def _tether(mu, EA):
    d = math.sqrt(4.0 * mu / (math.pi * DENSITY))
    return mt.TetherSpec(length=LENGTH, segments=SEGMENTS, diameter=d, mass_per_length=mu, EA=EA)


def _settle(mu, dt, EA):
    """Build and run the cable; returns ("refused", message) if the builder refuses the
    combination, else ("ran", top force, end force, catenary) with the forces averaged over the
    last part of the run. Raises SimulationDiverged if it diverges."""
    tether = _tether(mu, EA)
    water = mt.WaterColumn(depth=100.0)
    w = tether.wet_weight_per_length(RHO)
    ref = catenary(P_END, P_TOP, LENGTH, w, EA=EA, seabed=False)  # anchor = the lower end
    start = steady_state(tether, water, P_TOP, P_END, seabed=False)
    spec = new_spec(dt)
    try:
        tm = mt.add_tether(spec, tether, mt.FixedPoint(P_TOP), mt.FixedPoint(P_END), water=water,
                           nodes=start.nodes)
        sim = mt.Simulation(spec, water, [tm])
    except ValueError as e:
        return ("refused", str(e))
    settle, window = max(0.5, 100 * dt), max(0.1, 50 * dt)  # s; at least 150 steps in all
    fa, fb = [], []
    with sim:
        bt = sim.tether()
        dofs = slice(bt._dof0, bt._dof0 + 3 * (bt.n + 1))
        inertia = np.repeat(sim.model.body_mass[bt._bids], 3) + sim.model.dof_armature[dofs]
        sim.model.dof_damping[dofs] = DAMPING_RATE * inertia
        sim.run(settle)

        def sample(s):
            fa.append(bt.end_force(s.data, "start"))
            fb.append(bt.end_force(s.data, "end"))
        sim.run(window, sample, every=max(dt, 0.01))
    return ("ran", np.mean(fa, axis=0), np.mean(fb, axis=0), ref)


def _error(f, ref_f):
    return float(np.linalg.norm(f - ref_f) / np.linalg.norm(ref_f))


@pytest.mark.slow
@pytest.mark.parametrize("EA", EAS, ids=lambda v: f"EA={v:g}" if v else "EA=None")
@pytest.mark.parametrize("dt", STEPS, ids=lambda v: f"dt={v:g}")
@pytest.mark.parametrize("mu", MASSES, ids=lambda v: f"mu={v:g}")
def test_accepted_combinations_match_the_catenary(mu, dt, EA):
    """A 12 m cable of ``mu`` kg/m (diameter for 5000 kg/m^3, so 0.795 mu g N/m wet), 15
    elements of 0.8 m, between fixed points 10 m apart horizontally and 2 m vertically, in still
    water; started from the lumped static shape (``steady_state``), every node dof damped at
    5 /s per unit inertia (linear damping does not change statics; it only settles the swing,
    which drag alone damps slowly for heavy cables), run max(0.5 s, 100 steps), then the end
    forces averaged over max(0.1 s, 50 steps).

    Accepted: both end forces within 1 % of the analytic elastic catenary for the EA asked
    (vector error / magnitude). 1 %: the requirement; the 15-element lumped line is within
    0.3 % of the continuum, and settling leaves < 0.1 %.
    Refused (ValueError from ``add_tether`` or ``Simulation``): the message names the reason
    (EA, mass per length, the time step or the axial mode) and a working time step (a number
    of seconds other than the one refused), and that step is accepted and matches the
    catenary."""
    try:
        result = _settle(mu, dt, EA)
    except mt.SimulationDiverged as e:
        pytest.fail(f"accepted but diverged: {e}")
    if result[0] == "refused":
        msg = result[1]
        assert REASON.search(msg), f"refusal names no reason: {msg!r}"
        steps = [float(s) for s in SECONDS.findall(msg)]
        steps = [s for s in steps if s > 0 and abs(s / dt - 1) > 0.01]
        assert steps, f"refusal names no working time step (s): {msg!r}"
        good = min(steps, key=lambda s: abs(math.log(s / dt)))
        again = _settle(mu, good, EA)
        assert again[0] == "ran", f"the suggested step {good:g} s is refused too: {again[1]!r}"
        _, fa, fb, ref = again
    else:
        _, fa, fb, ref = result
    err_top, err_end = _error(fa, ref.fairlead_force), _error(fb, ref.anchor_force)
    assert max(err_top, err_end) <= 0.01, (f"mu={mu:g} kg/m dt={dt:g} s EA={EA}: top off by {100 * err_top:.2f} %, "
                                           f"end by {100 * err_end:.2f} %")

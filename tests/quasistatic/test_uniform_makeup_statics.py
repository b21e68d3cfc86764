"""A uniform tether is a one-section line make-up: ``steady_state`` takes a ``TetherSpec``, its
``LineMakeup.uniform`` and a make-up of two identical sections alike, and each answer is checked
against a closed form written here (not the solver's).

Tolerances (stated per test): the lumped-mass chain converges to the continuous catenary as
(L / N)^2; where the same solver runs (the uniform make-up is solved as its ``TetherSpec``) the
answers are equal to the bit."""

import math

import numpy as np
import pytest
from scipy.optimize import fsolve

import mjtether as mt
from mjtether.cable.makeup import LineMakeup, Section
from mjtether.quasistatic import dynamic_EA, initial_state, steady_state

G, RHO = 9.81, 1025.0


def _tether(**kw):
    props = dict(length=150.0, segments=120, diameter=0.04, mass_per_length=3.0, EA=5e5, cd_normal=1.1)
    props.update(kw)
    return mt.TetherSpec(**props)


def _wet(t):
    return (t.mu - RHO * math.pi * t.diameter**2 / 4) * G  # N/m


def _elastic_catenary(L, w, EA, span, rise):
    """Irvine's elastic catenary between two suspended points, arc length s from the lower end A:
    x(s) = H/w [asinh(V/H) - asinh(V_A/H)] + H s / EA, z(s) = H/w [sqrt(1 + (V/H)^2) -
    sqrt(1 + (V_A/H)^2)] + (V_A s + w s^2 / 2) / EA, V = V_A + w s. Returns (H, V_A, top tension)."""
    def at(H, VA, s):
        V = VA + w * s
        x = H / w * (math.asinh(V / H) - math.asinh(VA / H)) + H * s / EA
        z = H / w * (math.hypot(1.0, V / H) - math.hypot(1.0, VA / H)) + (VA * s + 0.5 * w * s * s) / EA
        return x, z

    H, VA = fsolve(lambda p: np.subtract(at(p[0], p[1], L), (span, rise)), [w * L, 0.0], xtol=1e-14)
    return H, VA, math.hypot(H, VA + w * L)


def _lines(t):
    """The tether, its one-section make-up, and the same line cut into two identical sections
    (not uniform: the piecewise march)."""
    a = round(0.6 * t.segments)
    sec = dict(diameter=t.diameter, mass_per_length=t.mu, EA=t.EA, cd_normal=t.cd_normal)
    two = LineMakeup((Section(t.length * a / t.segments, a, **sec),
                      Section(t.length * (t.segments - a) / t.segments, t.segments - a, **sec)))
    return {"TetherSpec": t, "uniform make-up": LineMakeup.uniform(t), "two sections": two}


def test_every_form_of_a_uniform_line_hangs_as_the_elastic_catenary():
    """Still water, both ends suspended, 100 m span, 75 m rise, 150 m of 5e5 N line: the top
    tension and the bottom end's horizontal force within 2e-4 of the closed form (the 120-element
    chain's own error, measured 9e-6 and 3e-5). The uniform make-up's answer is the TetherSpec's
    to the bit (the same solver); the two-section line's, by the piecewise march, within 1e-9."""
    t = _tether()
    water = mt.WaterColumn(depth=500.0)
    top, bottom = np.array([0.0, 0.0, -5.0]), np.array([100.0, 0.0, -80.0])
    H, VA, T_top = _elastic_catenary(t.length, _wet(t), t.EA, 100.0, 75.0)
    got = {name: steady_state(line, water, top, bottom, seabed=False) for name, line in _lines(t).items()}
    for name, ss in got.items():
        assert ss.top_tension == pytest.approx(T_top, rel=2e-4), name
        assert -ss.bottom_force[0] == pytest.approx(H, rel=2e-4), name
        assert -ss.bottom_force[2] == pytest.approx(-VA, rel=2e-4), name
    a, b = got["TetherSpec"], got["uniform make-up"]
    for field in ("nodes", "tension", "top_force", "bottom_force"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field))
    c = got["two sections"]
    np.testing.assert_allclose(c.nodes, a.nodes, rtol=0, atol=1e-9 * t.length)
    np.testing.assert_allclose(c.top_force, a.top_force, rtol=0, atol=1e-9 * T_top)


def test_a_uniform_make_up_too_long_to_lie_taut_hangs_slack_as_a_tetherspec():
    """300 m of line from 5 m down to a seabed 100 m deep, its end 50 m away: too long to lie
    taut, so the slack state (uniform lines only) holds: no current, the hang is vertical and
    the top carries the wet weight w s_P of the hanging length s_P, s_P + w s_P^2 / (2 EA) = 95 m
    (the stretched hang reaches the seabed). Within 1e-5 (the hang's length is solved to 1e-7
    of the line; measured 1.3e-7). A line of two identical sections is not uniform: the make-up
    solver does not model a slack lay and says so."""
    t = _tether(length=300.0, segments=60)
    water = mt.WaterColumn(depth=100.0)
    top, bottom = (0.0, 0.0, -5.0), (50.0, 0.0, -100.0)
    w = _wet(t)
    s_hang = (math.sqrt(1.0 + 2.0 * w * 95.0 / t.EA) - 1.0) / (w / t.EA)
    lines = _lines(t)
    for name in ("TetherSpec", "uniform make-up"):
        ss = steady_state(lines[name], water, top, bottom)
        assert ss.top_force[2] == pytest.approx(-w * s_hang, rel=1e-5), name
        assert abs(ss.top_force[0]) <= 1e-9 * w * s_hang and ss.slack_length > 0.0
        assert ss.laid_length == pytest.approx(t.length - s_hang, rel=1e-5)
    with pytest.raises(NotImplementedError, match="modelled for uniform lines only"):
        steady_state(lines["two sections"], water, top, bottom)


def test_the_dynamic_stiffness_takes_a_uniform_make_up_and_refuses_sections():
    """``dynamic_EA`` / ``initial_state`` take a uniform make-up as its TetherSpec (with its
    axial damping ratio and added-mass mode): the same stiffness to the bit; an inextensible
    line's stiffness is finite (the step's, not infinite). A make-up of several sections has no
    one dynamic EA: ValueError naming the line."""
    t = _tether(EA=None, axial_damping_ratio=2.0, added_mass="normal")
    water = mt.WaterColumn(depth=500.0)
    k = dynamic_EA(t, water, 0.005)
    assert math.isfinite(k) and k > 0.0
    assert dynamic_EA(LineMakeup.uniform(t), water, 0.005) == k
    with pytest.raises(ValueError, match="line_makeup: 2 section"):
        initial_state(_lines(_tether())["two sections"], water, (0.0, 0.0, -5.0), (100.0, 0.0, -80.0),
                      timestep=0.005)


def test_the_march_of_a_uniform_make_up_takes_its_own_ea():
    """The solver's line (``line._Cable``) of a uniform make-up with EA = "tether" (each
    section's) is the uniform path's, with the section's EA: 5e5 N, as given here; an
    inextensible one's is infinite."""
    from mjtether.quasistatic.line import _Cable

    water = mt.WaterColumn(depth=500.0)
    for EA, want in ((5e5, 5e5), (None, math.inf)):
        c = _Cable(LineMakeup.uniform(_tether(EA=EA)), water, (0.0, 0.0, 0.0), "tether")
        assert c.uniform and c.makeup is None and c.EA == want and np.all(c.EA_e == want)
        assert c.l == 150.0 / 120 and c.mu == 3.0

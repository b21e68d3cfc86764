"""``mjtether solve`` on a network (``mjtether.network.solve``): the end forces against closed
forms written here, and the parts the statics do not balance named."""

import math

import numpy as np
from scipy.optimize import brentq

from mjtether import cli
from mjtether.network import from_dict
from mjtether.network.solve import solve

RHO, G = 1025.0, 9.80665


def _water():
    return {"depth": 200.0, "rho": RHO, "gravity": G, "seabed_stiffness": 0.0}


def test_held_line_is_the_suspended_catenary():
    """A chain between two held points at one height, 80 m apart, 100 m long: the horizontal
    tension is w a with a from L = 2 a sinh(S / 2a), the vertical w L / 2 at each end (the
    inextensible catenary, solved here with brentq). EA = 1e12 N stretches it by under 1e-7,
    so the tolerance is 1e-5 of the tension (the statics' own solver tolerance is far finer)."""
    d, mu = 0.1, 20.0
    net = from_dict({"water": _water(),
                     "line_types": {"chain": {"diameter": d, "mass_per_length": mu, "EA": 1e12}},
                     "points": {"a": {"kind": "fixed", "position": [-40.0, 0.0, -50.0]},
                                "b": {"kind": "fixed", "position": [40.0, 0.0, -50.0]}},
                     "lines": [{"name": "span", "type": "chain", "a": "a", "b": "b", "length": 100.0,
                                "segments": 20}]})
    w = (mu - RHO * math.pi * d * d / 4) * G
    a = brentq(lambda a: 2 * a * math.sinh(40.0 / a) - 100.0, 1.0, 1e4)
    H, V = w * a, w * 50.0
    sol = solve(net)
    e = sol.lines["span"]
    assert e.catenary
    for f in (e.force_a, e.force_b):
        assert abs(math.hypot(f[0], f[1]) - H) < 1e-5 * H
        assert abs(abs(f[2]) - V) < 1e-5 * math.hypot(H, V)
    assert abs(e.tension_a - math.hypot(H, V)) < 1e-5 * math.hypot(H, V)
    assert sol.unbalanced == ()


def test_clump_on_a_v_bridle_balances_its_weight():
    """A 500 kg clump (0.05 m^3) on two light ropes of 50 m from held points 60 m apart: it
    hangs midway, sqrt(50^2 - 30^2) = 40 m below them (inextensible; EA = 1e10 N stretches the
    ropes by 3e-7), each rope carrying T = W / (2 cos theta), cos theta = 40 / 50, with W the
    clump's wet weight plus the ropes' own (near zero: 1e-3 kg/m). Tolerance 1e-4: the ropes'
    weight shifts the answer by under 1e-5, the stretch by under 1e-6. (The clump starts above
    and aside of its place, with both ropes slack: a light rope has no stiffness there, and the
    statics start again from where the ropes are just taut.)"""
    mass, vol = 500.0, 0.05
    net = from_dict({"water": _water(),
                     "line_types": {"rope": {"diameter": 0.001, "mass_per_length": 1e-3, "EA": 1e10}},
                     "points": {"a": {"kind": "fixed", "position": [-30.0, 0.0, -20.0]},
                                "b": {"kind": "fixed", "position": [30.0, 0.0, -20.0]},
                                "clump": {"kind": "free", "position": [1.0, 0.0, -50.0], "mass": mass,
                                          "volume": vol}},
                     "lines": [{"name": "left", "type": "rope", "a": "clump", "b": "a", "length": 50.0,
                                "segments": 10},
                               {"name": "right", "type": "rope", "a": "clump", "b": "b", "length": 50.0,
                                "segments": 10}]})
    W = (mass - RHO * vol) * G
    T = W / (2 * 40.0 / 50.0)
    sol = solve(net)
    assert sol.balanced, sol.note
    np.testing.assert_allclose(sol.positions["clump"], [0.0, 0.0, -60.0], atol=1e-3)
    for name in ("left", "right"):
        assert abs(sol.lines[name].tension_a - T) < 1e-4 * T


def test_cli_names_what_the_statics_hold(capsys):
    """The ROV spread: the vehicle and the paying-out excursion tether are held where written,
    and ``solve`` says so, naming each; the cage (a free body) is balanced, not named: it hangs
    on the vertical umbilical, 100 m plus its stretch under the cage's wet weight and half its
    own (its mean tension) below the ship, less the 0.6 m to its top (closed form; 1e-6 m, the
    statics' tolerance on the umbilical's EA / L)."""
    assert cli.main(["solve", "examples/networks/rov_cage_excursion.toml"]) == 0
    out = capsys.readouterr().out
    assert "umbilical" in out and "excursion" in out
    assert "body 'cage'" not in out and "1 body(ies) in equilibrium" in out
    assert "vehicle 'rov' is held" in out
    assert "line 'excursion' is solved at its start length 15 m" in out
    from mjtether.io.moordyn import load_any

    net = load_any("examples/networks/rov_cage_excursion.toml")
    w = (3.2 - RHO * math.pi * 0.035 ** 2 / 4) * G
    mean = (800.0 - RHO * 0.3) * G + w * 100.0 / 2
    z = -(100.0 + mean * 100.0 / 6e7) - 0.6
    assert abs(solve(net).poses["cage"].position[2] - z) < 1e-6

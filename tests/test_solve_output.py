"""``mjtether solve`` on a walker whose tether lies partly on the seabed: the tow tension it prints
against a laid catenary solved here, and the sentences that say why a run's and Khan et al.'s
tow tensions differ from it.

The reference (still water, uniform density, inextensible): the cable from the fairlead, h above
the cable's axis on the seabed, to the foot of the tow point, X away horizontally, with L_s = L -
rise of cable (the rest rises straight up to the tow point, ``rise`` above the seabed), is the
classic catenary with a laid part (Irvine 1981; Faltinsen 1990, Eq. 8.4-8.6): a = H / w solves

    L_s - sqrt(h^2 + 2 h a) + a asinh(sqrt(h^2 + 2 h a) / a) = X,

its laid length is L_s - sqrt(h^2 + 2 h a), and Coulomb friction cb w per metre along the laid part
leaves max(H - cb w L_laid, 0) of H at the foot. The tow point holds that (horizontal) and the wet
weight w rise of the piece rising to it. Before, ``solve`` printed the force at the foot as the tow
point's: 0.0 N on the default walker (the rising piece's 6.5 N left out).
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from mjtether.cli import main
from mjtether.scenario import load_scenario
from mjtether.scenario.runner import ScenarioRun

DEPTH, LENGTH, DIAMETER, DENSITY, RHO, G = 100.0, 150.0, 0.025, 2500.0, 1025.0, 9.81
TEXT = f"""\
[water]
depth = {DEPTH}
[water.density]
rho = {RHO}
[water.current]
speed = 0.0
[tether]
length = {LENGTH}
segments = 75
diameter = {DIAMETER}
density = {DENSITY}
EA = 0.0
seabed_friction = {{cb}}
[winch]
mode = "fixed"
[robot]
type = "walker"
start = [60.0, 0.0]
commands = [[0.0, 0.3, 0.0]]
"""
AREA = math.pi * DIAMETER**2 / 4
W = (DENSITY - RHO) * AREA * G  # N/m in water


def _closed_form(tow, cb):
    """Force of the cable on the tow point (N, world) from the laid catenary of the docstring."""
    radius = DIAMETER / 2
    foot_z = -DEPTH + radius
    rise = tow[2] - foot_z
    h, X, Ls = -foot_z, math.hypot(tow[0], tow[1]), LENGTH - rise
    a = brentq(lambda a: Ls - math.sqrt(h * h + 2 * h * a) + a * math.asinh(math.sqrt(h * h + 2 * h * a) / a) - X,
               1e-6, 1e6, xtol=1e-12)
    laid = Ls - math.sqrt(h * h + 2 * h * a)
    left = max(W * a - cb * W * laid, 0.0)
    towards_ship = -np.array([tow[0], tow[1], 0.0]) / X
    return left * towards_ship + np.array([0.0, 0.0, -W * rise]), W * a, laid


@pytest.mark.parametrize("cb", [0.0, 0.5])
def test_the_steady_tow_force_is_the_laid_catenary_s(cb):
    """Within 1 % of the closed-form tow force plus 0.05 N (the lumped line of 75 elements of 2 m,
    O(1/N^2), and the touchdown inside an element: H = 22.3 N came out within 0.07 %). With friction
    the seabed can hold 0.5 x 7.1 N/m x 46 m = 163 N, all of H: the rising piece's 6.5 N is left,
    which the old output left out too (it printed 0.0 N)."""
    sc = load_scenario(text=TEXT.format(cb=cb))
    r = ScenarioRun(sc)
    try:
        tow, ss = np.asarray(r.robot_position, float), r.initial
        want, H, laid = _closed_form(tow, cb)
        assert abs(ss.laid_length - laid) < 2.5, (ss.laid_length, laid)  # within about one element (2 m)
        assert np.linalg.norm(ss.bottom_force - want) < 0.01 * np.linalg.norm(want) + 0.05, (ss.bottom_force, want, H)
    finally:
        r.close()


def test_solve_says_what_the_tow_tension_is_and_why_the_others_differ(capsys):
    """The default walker: the tow tension printed (the rising piece's weight, 6.5 N) and one
    sentence each for it (friction holds the touchdown tension), a run's (the walker drags the laid
    cable) and Khan et al.'s (their method ignores the seabed)."""
    assert main(["solve", "default_walker"]) == 0
    out = capsys.readouterr().out
    tow = [line for line in out.splitlines() if line.startswith("  force on the tow point")][0]
    assert "(tension 0.0 N)" not in tow and float(tow.split("tension ")[1].split(" N")[0]) > 1.0
    assert "held by seabed friction on the 53.1 m laid" in out
    assert "a run's tow tension is larger once the walker walks: it drags" in out
    assert "Khan et al.'s method ignores the seabed" in out

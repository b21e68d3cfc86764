"""The first row of a network's time series (t = 0, before any step): its line forces are the
constraint forces at the start, as the first step finds them (``network.run.first_forces``)."""

import dataclasses

import numpy as np
import pytest

from mjtether.io.moordyn import load_any
from mjtether.network import run

EXAMPLE = "examples/networks/spread_mooring_float.toml"


def _held(**changes):
    """spread_mooring_float.toml with its float held where the file puts it (every point held:
    each line its own catenary), cut to 1 s."""
    net = load_any(EXAMPLE)
    points = {k: dataclasses.replace(p, kind="fixed") if p.kind == "free" else p for k, p in net.points.items()}
    return dataclasses.replace(net, points=points, **{"duration": 1.0, **changes})


def _tensions(net):
    r, rows = run.simulate(net)
    r.sim.close()
    cols = run.columns(net)
    return rows[:, [i for i, c in enumerate(cols) if c.endswith("_tension_N")]]


def test_the_first_row_of_a_settled_start_is_the_steady_state_s():
    """Every point held, settled (the file's 30 s), no current (the statics know none): the
    lines sit still, so the first row's eight end tensions equal the second row's (0.1 s on)
    and the last's within 0.01 % (measured 3e-7 and 3e-6)."""
    T = _tensions(_held(output_interval=0.1, current_depths=(), current_speeds=(), current_headings_deg=()))
    assert np.allclose(T[0], T[1], rtol=1e-4)
    assert np.allclose(T[0], T[-1], rtol=1e-4)


def test_the_first_row_holds_the_forces_the_first_step_uses():
    """Unsettled (settle 0), sampled every step: the second row holds the forces MuJoCo found at
    the state the first step began from, the start, with the elements that pushed switched slack
    and the step redone (``Simulation``); the first row must hold the same, within 1e-6 of
    each tension. Before, it held the forces with those elements still taut: line 1a's end B
    4.3 % low (68.3 kN against 71.4 kN)."""
    net = _held(settle=0.0, timestep=0.005, output_interval=0.005, duration=0.01)
    T = _tensions(net)
    assert T[0] == pytest.approx(T[1], rel=1e-6)

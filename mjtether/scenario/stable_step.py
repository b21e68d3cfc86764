"""The stable step of a scenario: the largest at which its line stays stable, keeps its EA and
rests on its seabed (used for MoorDyn files, whose own ``dtM`` is for MoorDyn's explicit
integrator). Units SI.
"""

from __future__ import annotations

import math

import numpy as np

from mjtether.cable import stability
from mjtether.cable.builder import seabed_timestep
from mjtether.cable.makeup import LineMakeup
from mjtether.quasistatic import steady_state
from mjtether.scenario import Scenario

from .scene import makeup_from, tether_from, water_from

MAX_TIMESTEP = 0.05
"""The longest step (s) ``stable_timestep`` gives (the scenario's own bound on
``simulation.timestep``)."""


def line_from(sc: Scenario) -> LineMakeup:
    """The scenario's line: its make-up, a uniform tether as its one section. (``makeup_from``
    gives a make-up for either once it returns one always; until then the uniform tether is
    wrapped here.)"""
    return makeup_from(sc) if sc.tether.is_makeup else LineMakeup.uniform(tether_from(sc))


def stable_timestep(sc: Scenario) -> float:
    """The step (s) for scenario ``sc``, a whole number of them per output interval. For one
    uniform line (one section, no loads; ``LineMakeup.is_uniform``): the largest at which it is
    stable and keeps its EA at its steady tension (``stability.max_timestep(keep_EA=True)``) and
    that the seabed's kBot allows (``builder.seabed_timestep``), at most ``MAX_TIMESTEP``. For
    a make-up (lines joined at
    points, whose loads have limits of their own): the scenario's own step, or less for the
    seabed. (MoorDyn's own chains, WD0050/0200/0600_Chain.txt, at 0.005 s and at the 0.0417 s
    this gives them agree with MoorDyn-C alike: fairlead tensions within 0.55 %, 0.13 % and
    0.005 % in 50, 200 and 600 m of water.)"""
    line, water = line_from(sc), water_from(sc)
    dt = sc.simulation.timestep
    if line.is_uniform:
        tether = line.tether
        top = np.array([*sc.ship.position, sc.ship.fairlead_z], float)
        try:
            st = steady_state(tether, water, top, np.array(sc.robot.position, float),
                              seabed_friction=sc.tether.seabed_friction)
            tension = max(np.linalg.norm(st.top_force), np.linalg.norm(st.bottom_force))
            dt = min(MAX_TIMESTEP, stability.max_timestep(tether, water, tension=tension, keep_EA=True))
        except (ValueError, RuntimeError):  # (no steady state: the scenario's default step)
            pass
    if sc.water.seabed_stiffness > 0:
        dt = min(dt, seabed_timestep(line, water.rho([water.seabed_z])[0], sc.water.seabed_stiffness))
    interval = sc.simulation.output_interval
    return interval / math.ceil(interval / dt - 1e-9)

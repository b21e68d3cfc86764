"""Scenarios: the typed configuration of a run and the machinery that runs one.

* ``config``: typed sections of parameters (type, default, range, unit, meaning in one place);
* ``sections``: the scenario tree (``Scenario``) built from them, with its checks;
* ``loading``: TOML in and out (``load_scenario``, ``to_toml``);
* ``scene``: the scenario as an ``MjSpec`` (seabed, ship, robot end) and the library objects;
* ``start``: the walker's stand, the tether's steady start and the pre-roll;
* ``controllers``: gait, ship, winch, vehicle pilots and manoeuvres;
* ``readouts``: named readouts of a running scenario (``run.named``) and the record's columns;
* ``runner``: ``ScenarioRun`` (a scenario as a stepping simulation); ``recording``: its run loop, ``run``.

Imports run one way: this package uses the cable, the physics, the vehicles, the walker and the
simulation; nothing below it imports it. ``mjtether.scenario`` offers every name the flat
``mjtether/scenario.py`` module did, so ``from mjtether.scenario import load_scenario`` works as
before.
"""

from .config import INF, RENAMED, ConfigError, Section, build, param, section, split_index, subsections, tables
from .loading import load_scenario, to_toml
from .cost import US_PER_STEP
from .sections import (
    LINE_TYPES,
    MAX_LENGTH,
    MAX_SEGMENTS,
    MAX_TURN_DEG_S,
    WINCH_MODES,
    Current,
    Density,
    Robot,
    Scenario,
    ScenarioError,
    Ship,
    Simulation,
    Tangle,
    Tether,
    TetherFloats,
    TetherPointLoad,
    TetherSection,
    TetherSpec,
    Tripod,
    Water,
    Winch,
)

__all__ = [
    "INF", "LINE_TYPES", "MAX_LENGTH", "MAX_SEGMENTS", "MAX_TURN_DEG_S", "RENAMED", "US_PER_STEP", "WINCH_MODES",
    "ConfigError", "Current", "Density", "Robot", "Scenario", "ScenarioError", "Section", "Ship", "Simulation",
    "Tangle", "Tether", "TetherFloats", "TetherPointLoad", "TetherSection", "TetherSpec", "Tripod", "Water",
    "Winch", "build", "load_scenario", "param", "section", "split_index", "subsections", "tables", "to_toml",
]

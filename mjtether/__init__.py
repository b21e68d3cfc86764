"""mjtether: an underwater tether between a ship's winch and a seabed robot, in MuJoCo.

SI units, world frame z up, water surface at z = 0, seabed at z = -depth.

The package by domain (imports run down this list, never up):

* ``physics``: the water column and the force kernels (NumPy, compiled, native callback);
* ``cable``: the tether's spec, MJCF builder, make-ups, winch, seabed friction and its run-time parts;
* ``vehicles``: Fossen's manoeuvring model, vehicle bodies and files, thrusters, propellers, fins;
* ``walker`` and ``simulation``: the hexapod, and a compiled model stepped with its tethers;
* ``quasistatic``: catenaries and steady states;
* ``scenario``: the typed configuration, the scene, the start, the controllers, the runner;
* ``io``: results folders, MoorDyn files, rendering, MuJoCo's warnings;
* ``sweep``, ``rollouts``, ``cli``: many runs, and the command line.
"""

from mjtether import quasistatic, rollouts
from mjtether.analytic import Catenary, SuspendedWeight, catenary, sagged_polyline
from mjtether.cable import builder, makeup, seabed, stability, tether, winch
from mjtether.cable.builder import BodyPoint, FixedPoint, FreeEnd, SitePoint, TetherModel, add_tether, axial_params
from mjtether.cable.tether import TetherSpec
from mjtether.cable.winch import Winch
from mjtether.files import mjlog
from mjtether.files.mjlog import MujocoWarning
from mjtether.physics import compiled, dispatch, hydro, native, rigidbody, water
from mjtether.physics.rigidbody import RigidBodyHydro, add_body_hydro
from mjtether.physics.water import (
    GRAVITY,
    ConstantCurrent,
    ConstantDensity,
    CurrentProfile,
    DensityProfile,
    ExponentialCurrent,
    LinearCurrent,
    LinearDensity,
    PowerLawCurrent,
    TabulatedCurrent,
    TabulatedDensity,
    WaterColumn,
    teos10_density,
)
from mjtether.simulation import BoundTether, Simulation, SimulationDiverged
from mjtether.units import KNOT, knots, to_knots
from mjtether.vehicles import fins, fossen, propeller, vehicle

# (the module imports above also keep the flat layout's names: ``mt.water``, ``mt.builder``, ...)

__all__ = [
    "BodyPoint", "BoundTether", "Catenary", "ConstantCurrent", "ConstantDensity", "CurrentProfile",
    "DensityProfile", "ExponentialCurrent", "FixedPoint", "FreeEnd", "GRAVITY", "KNOT", "LinearCurrent",
    "LinearDensity", "PowerLawCurrent", "RigidBodyHydro", "Simulation", "SimulationDiverged", "SitePoint",
    "MujocoWarning",
    "SuspendedWeight", "TabulatedCurrent", "TabulatedDensity", "TetherModel", "TetherSpec", "WaterColumn",
    "Winch", "add_body_hydro", "add_tether", "axial_params", "catenary", "knots", "sagged_polyline",
    "teos10_density",
    "to_knots",
]
__version__ = "0.1.0"

# MuJoCo's warnings become MujocoWarning (warnings module) instead of lines appended to
# ./MUJOCO_LOG.TXT; a warning callback set before this import is kept (see mjtether.files.mjlog)
mjlog.install()

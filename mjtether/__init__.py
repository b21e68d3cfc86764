"""mjtether: an underwater tether between a ship's winch and a seabed robot, in MuJoCo.

SI units, world frame z up, water surface at z = 0, seabed at z = -depth.
"""

from .analytic import Catenary, SuspendedWeight, catenary, sagged_polyline
from .builder import BodyPoint, FixedPoint, FreeEnd, SitePoint, TetherModel, add_tether, axial_params
from .rigidbody import RigidBodyHydro, add_body_hydro
from .simulation import BoundTether, Simulation, SimulationDiverged
from .tether import TetherSpec
from .units import KNOT, knots, to_knots
from . import compiled, dispatch, mjlog, native, quasistatic, rollouts, stability
from .mjlog import MujocoWarning
from .winch import Winch
from .water import (
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
# ./MUJOCO_LOG.TXT; a warning callback set before this import is kept (see mjtether.mjlog)
mjlog.install()

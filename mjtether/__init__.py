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

from importlib import import_module as _import_module

# The names below are imported when first used (PEP 562), so that ``import mjtether`` (and
# ``mjtether --help``) does not load NumPy's, SciPy's, numba's and the kernels' modules up front.
_MODULES = {
    "quasistatic": "mjtether.quasistatic", "rollouts": "mjtether.rollouts",
    "builder": "mjtether.cable.builder", "makeup": "mjtether.cable.makeup", "seabed": "mjtether.cable.seabed",
    "stability": "mjtether.cable.stability", "tether": "mjtether.cable.tether", "winch": "mjtether.cable.winch",
    "mjlog": "mjtether.files.mjlog",
    "compiled": "mjtether.physics.compiled", "dispatch": "mjtether.physics.dispatch",
    "hydro": "mjtether.physics.hydro", "native": "mjtether.physics.native",
    "rigidbody": "mjtether.physics.rigidbody", "water": "mjtether.physics.water",
    "fins": "mjtether.vehicles.fins", "fossen": "mjtether.vehicles.fossen",
    "propeller": "mjtether.vehicles.propeller", "vehicle": "mjtether.vehicles.vehicle",
}
"""The flat layout's module names (``mt.water``, ``mt.builder``, ...) and where they live."""
_NAMES = {
    "mjtether.analytic": ("Catenary", "SuspendedWeight", "catenary", "sagged_polyline"),
    "mjtether.cable.builder": ("BodyPoint", "FixedPoint", "FreeEnd", "SitePoint", "TetherModel", "add_tether",
                               "axial_params"),
    "mjtether.cable.tether": ("TetherSpec",),
    "mjtether.cable.winch": ("Winch",),
    "mjtether.files.mjlog": ("MujocoWarning",),
    "mjtether.physics.rigidbody": ("RigidBodyHydro", "add_body_hydro"),
    "mjtether.physics.water": ("GRAVITY", "ConstantCurrent", "ConstantDensity", "CurrentProfile", "DensityProfile",
                               "ExponentialCurrent", "LinearCurrent", "LinearDensity", "PowerLawCurrent",
                               "TabulatedCurrent", "TabulatedDensity", "WaterColumn", "teos10_density"),
    "mjtether.simulation": ("BoundTether", "Simulation", "SimulationDiverged"),
    "mjtether.units": ("KNOT", "knots", "to_knots"),
}
_WHERE = {name: module for module, names in _NAMES.items() for name in names}


def __getattr__(name):
    if name in _MODULES:
        value = _import_module(_MODULES[name])
    elif name in _WHERE:
        value = getattr(_import_module(_WHERE[name]), name)
    else:
        raise AttributeError(f"module 'mjtether' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_MODULES) | set(_WHERE))


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
from mjtether.files import mjlog as _mjlog  # noqa: E402 - (MuJoCo alone: about 0.15 s)

_mjlog.install()

_ENVIRONMENTS = (("mjtether/TetherWinch-v0", "mjtether.envs.tether_winch:TetherWinchEnv", 600),
                 ("mjtether/TetheredWalker-v0", "mjtether.envs.tethered_walker:TetheredWalkerEnv", 900),
                 ("mjtether/TetheredROV-v0", "mjtether.envs.tethered_rov:TetheredROVEnv", 600),
                 ("mjtether/TetheredSystem-v0", "mjtether.envs.tethered_system:TetheredSystemEnv", 600))
"""The Gymnasium environments: (id, entry point, max_episode_steps)."""


def _register_environments() -> None:
    """Register the Gymnasium environments by name: the entry points are strings, so their modules
    (``mjtether.envs.*``) load only at ``gymnasium.make``; this costs the import of Gymnasium
    (20-35 ms). Gymnasium >= 1.0 has no entry-point plugins, so
    ``import mjtether`` (or ``gymnasium.make("mjtether:mjtether/TetherWinch-v0")``, which imports
    it) is what makes the ids known; see docs/environments.md."""
    from gymnasium.envs.registration import register, registry

    for env_id, entry_point, steps in _ENVIRONMENTS:
        if env_id not in registry:
            register(id=env_id, entry_point=entry_point, max_episode_steps=steps)


_register_environments()

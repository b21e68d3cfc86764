"""Gymnasium environments for tether-aware control (installed as ``mjtether.envs``).

``import mjtether`` (and so the import of this package) registers (``mjtether._ENVIRONMENTS``):

* ``mjtether/TetherWinch-v0`` (``TetherWinchEnv``): command the winch behind a walker that
  follows a scripted route (with ``sea_state``, from a ship in waves, against snap loads);
* ``mjtether/TetheredWalker-v0`` (``TetheredWalkerEnv``): command the walker's gait and the
  winch to reach a goal on the seabed;
* ``mjtether/TetheredROV-v0`` (``TetheredROVEnv``): command an ROV's thrusters to hold station
  (or follow waypoints) at depth in a current on its umbilical;
* ``mjtether/TetheredSystem-v0`` (``TetheredSystemEnv``): fly a vehicle of a system file (a network
  of lines, points, bodies and vehicles; a MoorDyn file) to hold station; the observation names the
  lines (``observation_names``).

Hand-written controllers to compare against (``baselines``): ``FollowPayout`` (Khan et al.
2023, Eq. 30), ``SlantRangePayout``, ``SlackPI`` (tuned; the strongest), ``HeaveCompensationPayout``
(an active heave compensator, for ``TetherWinch-v0`` in a sea state), ``SteerToGoal`` and
``StationKeepingPID``.

>>> import gymnasium as gym, mjtether  # noqa: F401
>>> env = gym.make("mjtether/TetherWinch-v0")

or, with no import, ``gym.make("mjtether:mjtether/TetherWinch-v0")`` (Gymnasium imports the module
named before the colon); see docs/environments.md.
"""

from mjtether import _register_environments

from .baselines import FollowPayout, HeaveCompensationPayout, SlackPI, SlantRangePayout, StationKeepingPID, SteerToGoal
from .tether_winch import TetherWinchEnv
from .tethered_rov import TetheredROVEnv
from .tethered_system import TetheredSystemEnv
from .tethered_walker import TetheredWalkerEnv

__all__ = ["TetherWinchEnv", "TetheredWalkerEnv", "TetheredROVEnv", "TetheredSystemEnv", "FollowPayout",
           "HeaveCompensationPayout", "SlantRangePayout", "SlackPI", "SteerToGoal", "StationKeepingPID"]

_register_environments()  # (again, should the ids have been taken out of Gymnasium's registry)

"""Quasi-static solvers: steady tether shapes and tensions without time stepping.

* ``steady_state``: the physically consistent 3-D steady state of the same discretised tether
  as the dynamic model (drag on the relative velocity, rho(z), turning current, tow velocity,
  seabed contact), of a uniform ``TetherSpec`` or a non-uniform ``mjtether.cable.makeup.LineMakeup``
  (sections, clump weights, buoyancy modules, float sections); ``initial_state`` gives it for a
  dynamic run's own stiffness (a uniform line only).
* ``catenary``: the analytic elastic catenary with seabed contact and friction.
* ``khan2023``: the finite-segment method of Khan et al. (2023), as printed and as re-derived.
"""

from .catenary import ElasticCatenary, catenary
from .initial import dynamic_EA, initial_state
from .khan2023 import KhanResult, khan2023
from .steady import SteadyState, steady_state

__all__ = ["ElasticCatenary", "KhanResult", "SteadyState", "catenary", "dynamic_EA", "initial_state",
           "khan2023", "steady_state"]

"""Initial states for dynamic runs: the steady state of the dynamic tether's own configuration.

A dynamic tether started from ``steady_state`` nodes carries, from its first step, the
tension that the constraint solver makes of the elements' stretch. For an elastic tether that
is T = EA strain; an "inextensible" tether (``EA=None``) is in MuJoCo a stiff one, whose
stiffness ``dynamic_EA`` reports, so its initial state must be stretched by that stiffness,
not left unstretched.
"""

from __future__ import annotations

from mjtether.cable.builder import axial_params
from mjtether.cable.makeup import LineMakeup
from mjtether.cable.tether import TetherSpec
from mjtether.physics.water import WaterColumn

from .steady import SteadyState, steady_state


def _uniform(tether) -> TetherSpec:
    """``tether`` as a ``TetherSpec``: as it is, or a uniform ``LineMakeup``'s (ValueError for
    another make-up: its sections have stiffnesses of their own)."""
    return tether if isinstance(tether, TetherSpec) else LineMakeup.of(tether).tether


def dynamic_EA(tether: TetherSpec | LineMakeup, water: WaterColumn, timestep: float) -> float:
    """Axial stiffness (N) of ``tether`` (a uniform line) as the dynamic model builds it at
    ``timestep`` (s): the tether's EA if it has one, else the stiffness the solver gives an
    inextensible one."""
    tether = _uniform(tether)
    l = tether.segment_length
    m_axial = tether.mu * l  # an interior node's inertia along the cable
    if tether.added_mass == "isotropic":  # its added mass along the cable too (see builder)
        m_axial += tether.ca_normal * float(water.rho([0.0])[0]) * tether.area * l
    return float(axial_params(tether.EA, l, 2.0 / m_axial, timestep, tether.axial_damping_ratio).effective_EA(l))


def initial_state(tether: TetherSpec | LineMakeup, water: WaterColumn, top, bottom, *, timestep: float,
                  tow_velocity=(0.0, 0.0, 0.0), **kw) -> SteadyState:
    """``steady_state`` of a uniform line between fixed ends ``top`` and ``bottom`` (m), with the
    stiffness the dynamic model will have at ``timestep`` (s). Pass ``.nodes`` to
    ``add_tether(nodes=...)`` and ``.velocity`` to ``BoundTether.set_state``."""
    tether = _uniform(tether)
    return steady_state(tether, water, top, bottom, tow_velocity=tow_velocity,
                        EA=dynamic_EA(tether, water, timestep), **kw)

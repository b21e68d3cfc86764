"""Time-step limits of the explicit forces.

Forces from ``mjcb_passive`` are not in MuJoCo's implicit derivatives, so Morison drag is
integrated explicitly. Linearised, the normal drag on a cable element relaxes the relative
velocity at the rate

    lambda = rho C_dn d |v_rel| / (mu + C_a rho A)         (1/s, per unit length: independent of l)

Forward Euler is stable for lambda dt < 2 and free of overshoot for lambda dt < 1. Light
cables in strong current are the worst case (lambda grows with |v_rel| / d). Bending
stiffness adds the beam limit dt < l^2 sqrt(mu / EI) / 4 (highest mode of a lumped beam).

Tension adds a limit of its own: MuJoCo evaluates the constraint directions at the start of
the step, so the transverse "string" modes of a taut chain are explicit too. The highest one,
omega = 2 sqrt(T / (m_node l)), needs dt < sqrt((mu + C_a rho A) / T) l. Measured: a 50 m
tether of 10 kg nodes holding a 200 t weight (T = 1 MN) zig-zags at dt = 10 ms (limit 7 ms)
and is clean at 4 ms.
The axial mode needs no limit of its own: ``builder.axial_params`` keeps it at or below
0.5 / dt.
"""

from __future__ import annotations

import math

from .tether import TetherSpec
from .water import WaterColumn


def drag_rate(tether: TetherSpec, water: WaterColumn, relative_speed: float | None = None) -> float:
    """lambda (1/s) for the largest current in the column (or ``relative_speed``, m/s)."""
    if relative_speed is None:
        relative_speed = water.current.max_speed(water.depth)
    rho = float(max(water.rho([0.0])[0], water.rho([-water.depth])[0]))
    m_eff = tether.mu + tether.ca_normal * rho * tether.area
    return rho * tether.cd_normal * tether.diameter * relative_speed / m_eff


def max_timestep(tether: TetherSpec, water: WaterColumn, relative_speed: float | None = None,
                 tension: float | None = None) -> float:
    """Largest step (s) free of drag overshoot (lambda dt <= 1), within the bending limit and,
    given the largest expected ``tension`` (N), within the taut-string limit."""
    lam = drag_rate(tether, water, relative_speed)
    dt = 1.0 / lam if lam > 0 else math.inf
    if tether.EI > 0:
        dt = min(dt, tether.segment_length**2 * math.sqrt(tether.mu / tether.EI) / 4)
    if tension is not None and tension > 0:
        rho = float(water.rho([0.0])[0])
        m_eff = tether.mu + tether.ca_normal * rho * tether.area
        dt = min(dt, tether.segment_length * math.sqrt(m_eff / tension))
    return dt

"""Time-step limits of the explicit forces.

MuJoCo integrates part of the tether's dynamics implicitly (the added mass, carried as joint
armature; the axial mode, which ``builder.axial_params`` slows to ``AXIAL_OMEGA_DT`` / dt; the
seabed contact and the end ``connect`` constraints, whose time constants are 2 dt) and the rest
explicitly. The explicit parts set the largest stable step, and ``max_timestep`` returns
``SAFETY`` times the smallest of their limits:

* **Drag.** Forces from ``mjcb_passive`` are not in MuJoCo's implicit derivatives, so Morison
  drag is explicit. Linearised about a relative velocity v, the normal drag on an element
  relaxes the velocity at the rate

      lambda = rho C_dn d |v| / (mu + C_a rho A)        (1/s; per unit length, so independent of l)

  and forward Euler is stable for lambda dt < 2 (free of overshoot only below 1: above it a
  node's velocity flips about its terminal value after a disturbance, and the flip dies out).
  A cable held across the current is the binding case (measured: lambda dt = 1.9-2.7 at the
  limit). A cable drifting with the flow is held at no terminal velocity, and quadratic drag
  then lets it run to lambda dt = 4.
* **Tension and bending.** MuJoCo evaluates the constraint directions at the start of the
  step, so the transverse ("string") modes of a taut chain are explicit, and so is the bending
  force (a passive force). The highest mode of an interior node (mass m = mu + C_a rho A per
  metre, element length l, tension T, bending stiffness EI) is the zig-zag,

      omega^2 = (4 T / l^2 + 16 EI / l^4) / m,

  and symplectic Euler needs omega dt < 2, i.e. dt < l sqrt(m) / sqrt(T + 4 EI / l^2)
  (measured: the largest stable step is 1.04-1.23 x this). The zig-zag moves no element
  centre, so drag does not damp it, and the drag and string limits do not combine. A winch
  (``BoundTether.set_length``) makes the drum element next to the fairlead as short as
  (SPLIT - 1) l0 when paying out and MERGE l0 when reeling in: the node at its end then rings
  faster than any interior node (``drum_omega``), 1.5 x when paying out, 2.2 x when reeling in
  (measured: 1.04-1.35 x and 1.24-1.4 x the drum limit; a fast reel-in passes the shortest
  drum element in a few steps).
* **Not limits.** The axial mode, the seabed contact, the connects and the added mass: their
  parameters follow the step (the axial mode's as long as it is damped at
  ``tether.MIN_AXIAL_DAMPING_RATIO`` of critical or more: below it no step settles it). Robots and other bodies have limits of their own: the walker
  of ``mjtether.walker`` (position servos of kp = 2e4 on 2 kg m^2 of armature, soft foot
  contacts), alone and walking at 0.3 m/s for 10 s, covers the distance it covers at 5 ms to
  1 % at 0.0125 s, 6-8 % fast at 0.02-0.025 s, 9 % short at 0.035 s, and stumbles at 0.045 s;
  ``max_timestep(walker=True)`` caps the step at ``WALKER_MAX_TIMESTEP``.

``tension`` should be the largest tension the run will see; without it ``expected_tension``
estimates it (the cable's wet weight, or half the drag of the current on it if that is more).
The estimate may be 1.6 x too low and the answer still be stable; a taut mooring, a clump
weight or a towed body needs ``tension`` (e.g. ``quasistatic.steady_state(...).top_tension``).

Measured (MuJoCo 4.0.0, implicitfast; commit ac67e04 with the working tree of 2026-11-23): the
largest stable step, by bisection to 5 % from the answer. Stable: no ``SimulationDiverged`` and
over the second half of the run the ship-end tension within 25 % of the steady state (fixed
ends: from the steady state with 5 cm/s random node velocities, 40 s or 3000 steps) or its
spread within 50 % (free end, 30 s); for payout, 10 % from the steady state of the new length
at the end and no step-to-step change over 50 %; for scenarios, the tension's half-second means
within 25 % of a 5 ms run (walker: 10 %, and the walk within 10 %). The answer is
``max_timestep(tether, water)`` with ``payout`` set for a winch and nothing else (no tension).
Fixed ends: 100 m of cable, ends 80 m apart at 50 deg below the horizontal (no current, or
the current in their plane) or level and across the current ("across"); rho_c: cable density
(kg/m^3), d: diameter, N: elements; EA 5 MN unless stated.

=================================================================  ========  ========  =====
case                                                               measured  answer    ratio
=================================================================  ========  ========  =====
still water, d 30 mm, rho_c 2500, N 20 (T 862 N, estimate 1023 N)  0.304     0.197     0.65
... N 100                                                          0.0558    0.0395    0.71
... N 40, inextensible                                             0.146     0.0987    0.68
... EI 1000 N m^2, N 50                                            0.0760    0.0562    0.74
still water, steel (rho_c 7800), 97 m apart, N 40 (T 5785 N)       0.0867    0.0729    0.84
... tension=5785 given                                             0.0889    0.0657    0.74
still water, rho_c 1100, N 40 (T 44 N)                             0.502     0.340     0.68
across 2 m/s, d 10 mm, rho_c 1030, inextensible, N 20              0.0169    0.0105    0.62
... N 100                                                          0.0130    0.00916   0.71
... across 5 m/s, EA 0.1 MN                                        0.00620   0.00420   0.68
... in-plane 2 m/s, N 50                                           0.0155    0.0105    0.68
across 1 m/s, d 30 mm, rho_c 2500, N 40                            0.140     0.0987    0.71
free end streaming in 5 m/s, d 10 mm, rho_c 1030, N 20 (*)         0.0104    0.00420   0.40
... N 100 (*)                                                      0.0104    0.00367   0.35
examples/static_anchor_current.toml                                0.125     0.0926    0.74
walker on 80 m of 5 mm line across 1 m/s (tests/cable/test_stability.py)    0.0160    0.0129    0.81
examples/default_walker.toml: the walker's own limit               0.0276    0.0414    1.5
... ``walker=True``                                                0.0276    0.0200    0.72
payout 100 -> 130 m at 1 m/s (tests/cable/test_winch.py), payout="out"      0.0991    0.0732    0.74
payout 100 -> 110 m at 0.5 m/s, still water, d 30 mm, N 40         0.113     0.0643    0.57
... in 1 m/s, N 20                                                 0.207     0.108     0.52
reel-in 100 -> 90 m at 0.5 m/s, still water, N 40, payout=True     0.0741    0.0440    0.59
... at 0.1 m/s to 95 m                                             0.0650    0.0440    0.68
... in 1 m/s, N 20, at 0.5 m/s (*)                                 0.184     0.0881    0.48
... at 0.1 m/s to 95 m                                             0.162     0.0881    0.55
examples/anchor_payout.toml, payout="out"                          0.068     0.0406    0.60
=================================================================  ========  ========  =====

(*) Not within 2x: a streaming cable runs to lambda dt = 4 (see Drag); a fast reel-in on long
elements passes the 0.1 l0 drum element in a few steps. The scenario walker is limited by
itself (nothing diverges at the answer, but the walker walks 0.5 m backwards): pass
``walker=True``.
"""

from __future__ import annotations

import math

import numpy as np

from mjtether.cable.drum import MERGE, SPLIT, fairlead_share
from mjtether.physics.water import WaterColumn

from .tether import TetherSpec

SAFETY = 0.8
"""Fraction of the smallest limit that ``max_timestep`` returns. Measured, the largest stable
step is 1.04-1.23 x the string/bending limit at the true tension, 1.04-1.4 x the drum-element
limit and 0.95-1.37 x the drag limit 2 / lambda of a cable held across the current (module
docstring): 0.8 leaves 16 % or more, and room for a tension estimate 1.6 x too low."""

WALKER_MAX_TIMESTEP = 0.02
"""Largest step (s) for the walker of ``mjtether.walker`` (``max_timestep(walker=True)``): alone
on the seabed it covers within 7 % of the distance it covers at 5 ms (0.3-1.2 m/s, turning or
not), its body bobbing 7-15 cm against 1-5 cm. At 0.0125 s it is within 1 % and bobs 2 cm."""

# the drum element's shortest rest length (units of l0): just after a node is released when
# paying out, just before one is taken back when reeling in
_DRUM_SHORTEST = {"out": SPLIT - 1.0, "in": MERGE}
_PAYOUT = {False: None, None: None, "none": None, True: "in", "both": "in", "in": "in", "out": "out"}


def _water_rho(water: WaterColumn) -> tuple[float, float]:
    """(smallest, largest) water density in the column (kg/m^3)."""
    r = np.asarray(water.rho(-np.linspace(0.0, water.depth, 201)), float)
    return float(r.min()), float(r.max())


def effective_mass(tether: TetherSpec, water: WaterColumn) -> float:
    """Transverse mass per metre m = mu + C_a rho A (kg/m), with the densest water of the column."""
    return tether.mu + tether.ca_normal * _water_rho(water)[1] * tether.area


def _relaxation_rate(tether: TetherSpec, water: WaterColumn, relative_speed: float | None, cd: float) -> float:
    if relative_speed is None:
        relative_speed = water.current.max_speed(water.depth)
    rho = float(max(water.rho([0.0])[0], water.rho([-water.depth])[0]))
    m_eff = tether.mu + tether.ca_normal * rho * tether.area
    return rho * cd * tether.diameter * relative_speed / m_eff


def drag_rate(tether: TetherSpec, water: WaterColumn, relative_speed: float | None = None) -> float:
    """lambda (1/s) for the largest current in the column (or ``relative_speed``, m/s)."""
    return _relaxation_rate(tether, water, relative_speed, tether.cd_normal)


def expected_tension(tether: TetherSpec, water: WaterColumn, relative_speed: float | None = None) -> float:
    """Tension (N) to plan the step for when none is given: the larger of the cable's wet weight
    |w| L and half the normal drag of the current on all of it, F / 2, with F = 1/2 rho C_dn d
    times the integral of u^2 along a cable hanging straight down from the surface and then
    lying along the seabed (or ``relative_speed``^2 everywhere, if given).

    A cable hanging from its top end carries its weight there (a catenary to a point on or
    near the seabed a little less: 0.85 |w| L measured at the ship of a 100 m line spanning 80 m
    at 50 deg); a span held across a current carries about half its drag at each end (0.2-0.35
    F measured at the top of 100 m lines spanning 80 m). Not included: bodies hung on the cable,
    the pretension of a taut span, a free-ended cable held across the flow (which carries all of
    F at its top): give ``tension`` for those."""
    rho_lo, rho_hi = _water_rho(water)
    w = max(abs(tether.mu - rho_lo * tether.area), abs(tether.mu - rho_hi * tether.area)) * water.gravity
    L = tether.length
    if relative_speed is None:
        s = np.linspace(0.0, L, 2001)
        u2 = np.asarray(water.current.speed_at(-np.minimum(s, water.depth)), float) ** 2
        mean_u2 = float(np.mean(0.5 * (u2[1:] + u2[:-1])))
    else:
        mean_u2 = float(relative_speed) ** 2
    drag = 0.5 * rho_hi * tether.cd_normal * tether.diameter * mean_u2 * L
    return max(w * L, 0.5 * drag)


def string_omega(tether: TetherSpec, water: WaterColumn, tension: float) -> float:
    """Highest transverse frequency (rad/s) of an interior node: sqrt((4 T / l^2 + 16 EI / l^4) / m)."""
    l, m = tether.segment_length, effective_mass(tether, water)
    return math.sqrt(max(4.0 * tension / l**2 + 16.0 * tether.EI / l**4, 0.0) / m)


def drum_omega(tether: TetherSpec, water: WaterColumn, tension: float, shortest: float) -> float:
    """Highest transverse frequency (rad/s) of a chain whose first element, next to the fixed
    fairlead node, is ``shortest`` x l0 long (the drum element), the others l0: the largest
    eigenvalue of M^-1 K for the tension and bending stiffness of ``hydro.bending_forces``
    (energy EI / l0 (1 - cos theta) per node), with the masses ``BoundTether`` lumps."""
    l0, m, T, EI = tether.segment_length, effective_mass(tether, water), tension, tether.EI
    n = 16  # free nodes; the mode is local to the drum element
    lengths = np.r_[shortest * l0, np.full(n, l0)]  # element j joins node j and j+1; 0 and n+1 fixed
    share = fairlead_share(lengths[0], l0)
    mass = np.full(n, m * l0)
    mass[0] = m * (lengths[0] - share + 0.5 * l0)
    K = np.zeros((n + 2, n + 2))
    for j, lj in enumerate(lengths):  # tension: T / l (y_j+1 - y_j)^2 / 2
        K[j:j + 2, j:j + 2] += T / lj * np.array([[1.0, -1.0], [-1.0, 1.0]])
    if EI > 0:  # bending: EI / l0 theta^2 / 2, theta_i = (y_i+1 - y_i)/l_i - (y_i - y_i-1)/l_i-1
        for i in range(1, n + 1):
            g = np.zeros(n + 2)
            g[i + 1] += 1.0 / lengths[i]
            g[i] -= 1.0 / lengths[i] + 1.0 / lengths[i - 1]
            g[i - 1] += 1.0 / lengths[i - 1]
            K += EI / l0 * np.outer(g, g)
    Kf = K[1:n + 1, 1:n + 1] / np.sqrt(np.outer(mass, mass))
    return math.sqrt(max(float(np.linalg.eigvalsh(Kf)[-1]), 0.0))


def ea_timestep(tether: TetherSpec, water: WaterColumn) -> float:
    """Largest step (s) at which the tether's elements keep the EA asked for (``cable.builder``:
    beyond it the solver cannot slow the axial mode enough even at its largest impedance, and
    makes each element as stiff as the step allows: a softer cable): AXIAL_OMEGA_DT /
    (omega_ax sqrt(1 - MAX_IMP)), omega_ax = sqrt(EA / l x 2 / m) with m an interior node's
    inertia along the cable (its added mass too, for ``added_mass = "isotropic"``). ``math.inf``
    for an inextensible tether (EA None: always as stiff as the step allows)."""
    from mjtether.cable.builder import AXIAL_OMEGA_DT, MAX_IMP
    if tether.EA is None:
        return math.inf
    l = tether.segment_length
    m = tether.mu * l
    if tether.added_mass == "isotropic":
        m += tether.ca_normal * _water_rho(water)[0] * tether.area * l  # (the lightest water: the shortest step)
    omega = math.sqrt(tether.EA / l * 2.0 / m)
    return AXIAL_OMEGA_DT / (omega * math.sqrt(1.0 - MAX_IMP))


def _as_float(value) -> float:
    """``value`` as a float, NaN if it is not a number (text and booleans are not)."""
    if isinstance(value, (str, bytes, bool, np.bool_)):
        return math.nan
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


def max_timestep(tether: TetherSpec, water: WaterColumn, relative_speed: float | None = None,
                 tension: float | None = None, *, payout: bool | str = False, walker: bool = False,
                 keep_EA: bool = False) -> float:
    """Largest stable step (s) for ``tether`` in ``water``: ``SAFETY`` x the smallest of the drag
    limit 2 / lambda and the string/bending limit 2 / omega (see the module docstring).

    Args:
        relative_speed: the largest speed of the water past the cable (m/s); default the largest
            current in the column.
        tension: the largest tension the run will see (N); default ``expected_tension`` (the
            cable's wet weight or half its drag), which is too low for a cable holding up a
            body, a taut span or a free end held across the flow: give it for those.
        payout: whether a winch changes the deployed length (``BoundTether.set_length``):
            ``False`` (no), ``"out"`` (pays out only), ``True``, ``"in"`` or ``"both"`` (reels in
            at times too); the short drum element then lowers the step.
        walker: the model also holds the walker of ``mjtether.walker``: at most
            ``WALKER_MAX_TIMESTEP``.
        keep_EA: also at most ``ea_timestep``, so that the elements keep the EA asked for
            (without it, a stiff cable at the stable step runs softer: a 100 m line of EA 1e7 N
            at about 1e6 N; the run then says so).

    ``math.inf`` if nothing limits the step (no current, no tension, no bending stiffness)."""
    for name, value in (("relative_speed", relative_speed), ("tension", tension)):
        if value is not None and not (_as_float(value) >= 0.0 and _as_float(value) < math.inf):
            raise ValueError(f"max_timestep {name} = {value!r}: must be a finite number >= 0 "
                             f"({'m/s' if name == 'relative_speed' else 'N'}), or None for the default")
    if payout not in _PAYOUT:
        raise ValueError(f"payout must be False, True, 'out', 'in' or 'both', got {payout!r}")
    drum = _PAYOUT[payout]
    if tension is None:
        tension = expected_tension(tether, water, relative_speed)
    tension = max(float(tension), 0.0)
    limits = []
    # normal drag, or tangential drag (C_dt on the wetted area pi d l) if that is stronger
    lam = _relaxation_rate(tether, water, relative_speed, max(tether.cd_normal, math.pi * tether.cd_tangential))
    if lam > 0:
        limits.append(2.0 / lam)
    omega = string_omega(tether, water, tension)
    if drum is not None:
        omega = max(omega, drum_omega(tether, water, tension, _DRUM_SHORTEST[drum]))
    if omega > 0:
        limits.append(2.0 / omega)
    dt = SAFETY * min(limits) if limits else math.inf
    if keep_EA:
        dt = min(dt, ea_timestep(tether, water))
    return min(dt, WALKER_MAX_TIMESTEP) if walker else dt

"""Seabed friction of laid cable: Coulomb friction with a stick point (pure NumPy, no MuJoCo).

A node resting on the seabed is held by a stiff spring to a *stick point* on the seabed. While
the spring force stays within mu N it sticks: the friction force holds whatever tangential load
the cable puts on it, with no drift. When the load exceeds mu N the stick point is dragged
along so that the spring stays at mu N: the node slides, with kinetic friction mu N opposing its
motion. This is OrcaFlex's modified Coulomb model (Orcina, OrcaFlex documentation, "Friction
theory": a friction force towards a friction target position, limited to mu R), and it is what
a laid cable needs: a steady tension gradient along the laid part, mu w per metre, held
indefinitely, as the catenary with seabed friction of MoorPy (M. Hall, NREL) assumes. (MoorDyn's
saturated-damping friction, like MuJoCo's, needs a slip to carry a force.)

MuJoCo's own contact friction is soft: its friction rows have no position reference, so a
constant friction force needs a constant slip, and a practically inextensible laid line relaxes
to the frictionless answer within seconds. MuJoCo's contact therefore supplies only the normal
force (``condim = 1``), and this kernel the friction, as a passive force.

The normal force is the node's share of the cable's submerged weight, times the cosine of the
seabed slope: the support a laid cable gets (MoorPy's and MoorDyn's model of the laid part).
A buoyant cable gets none.

The stick points are state: the caller keeps them between steps (``BoundTether`` keeps them in
MuJoCo's ``userdata``, which MuJoCo saves and restores with the integration state); NaN marks
a node not in contact, which sticks where it lands.

Units SI, world frame.
"""

from __future__ import annotations

import numpy as np

STICK_STIFFNESS = 0.2
"""Stick spring k = STICK_STIFFNESS m / dt^2 for a node of mass m (added mass included): stiff
enough that a node at the friction limit has moved mu g' dt^2 / 0.2 (0.4 mm for mu = 0.1 at
10 ms) from its stick point, soft enough for an explicit force (omega dt = 0.45)."""
STICK_DAMPING = 0.5
"""Damping ratio of the stick spring (c = 2 zeta sqrt(k m)): the node does not ring on it."""
CONTACT_TOLERANCE = 0.05
"""A node is on the seabed when its cable surface is within this fraction of the diameter of it
(MuJoCo's soft contact lets it sink in a little, and a laid cable jitters by less)."""


def seabed_friction(x: np.ndarray, v: np.ndarray, stick: np.ndarray, *, point: np.ndarray, normal: np.ndarray,
                    radius: float, normal_force: np.ndarray, mu: float, stiffness: np.ndarray,
                    damping: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Friction forces on nodes ``x`` (n, 3) m moving at ``v`` (n, 3) m/s over the seabed plane
    through ``point`` with unit ``normal`` (pointing up into the water): each (3,), or (n, 3)
    for each node's own plane (a height field's tangent plane under it).

    ``stick`` (n, 3): the stick points of the last call (NaN where a node was off the seabed);
    ``normal_force`` (n,) N; ``stiffness`` (n,) N/m and ``damping`` (n,) N s/m of the stick springs.
    Returns (forces (n, 3) N, in the seabed's plane, zero off the seabed; the new stick points)."""
    height = np.sum((x - point) * normal, axis=-1)
    on = (height <= (1.0 + 2.0 * CONTACT_TOLERANCE) * radius) & (normal_force > 0.0)
    force, new = np.zeros_like(x), np.full_like(x, np.nan)
    idx = np.flatnonzero(on)
    if len(idx) == 0:
        return force, new
    # the run of nodes from the first to the last on the seabed (a laid cable is one run),
    # computed whole and the ones off the seabed masked at the end: cheaper in NumPy than
    # selecting the ones on it
    lo, hi = idx[0], idx[-1] + 1
    nrm = normal[lo:hi] if np.ndim(normal) == 2 else normal
    force[lo:hi], new[lo:hi] = _stick_slip(x[lo:hi], v[lo:hi], stick[lo:hi], height[lo:hi], on[lo:hi], nrm,
                                           mu * normal_force[lo:hi], stiffness[lo:hi], damping[lo:hi])
    return force, new


def _stick_slip(x, v, stick, height, on, normal, limit, stiffness, damping):
    """``seabed_friction`` for a run of nodes, ``on`` those on the seabed; ``limit`` = mu N."""
    xt = x - height[:, None] * normal  # the node's foot on the seabed
    vt = v - np.sum(v * normal, axis=-1)[:, None] * normal
    s = np.where(np.isnan(stick), xt, stick)  # a node that lands sticks where it lands
    f = stiffness[:, None] * (s - xt)
    # beyond the limit the stick point is dragged along: the spring stays at mu N
    scale = np.minimum(1.0, limit / np.maximum(np.sqrt(np.einsum("ij,ij->i", f, f)), 1e-300))
    s = xt + (s - xt) * scale[:, None]
    f *= scale[:, None]
    f -= damping[:, None] * vt
    scale = np.minimum(1.0, limit / np.maximum(np.sqrt(np.einsum("ij,ij->i", f, f)), 1e-300))
    f *= (scale * on)[:, None]
    s[~on] = np.nan
    return f, s

"""``mjtether solve`` of a network: its steady state (``statics.equilibrium``: each line an elastic
catenary, the free points and the free and pinned bodies in balance), each line's end forces,
the bodies' poses, and which parts of the system the statics do not balance, and why (they
then start where the file puts them, and a run settles them).

Units SI; forces are those of the line on its end (N, world frame, z up).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import statics
from .config import Network


@dataclass(frozen=True)
class LineEnds:
    """One line's steady state: the forces it puts on its ends A and B (N, world), its nodes
    from A to B (m, world) and whether the elastic catenary gave them (else a straight elastic
    bar carrying half its wet weight at each end: ``statics.line_ends``)."""

    name: str
    force_a: np.ndarray
    force_b: np.ndarray
    nodes: np.ndarray
    catenary: bool

    @property
    def tension_a(self) -> float:
        return float(np.linalg.norm(self.force_a))

    @property
    def tension_b(self) -> float:
        return float(np.linalg.norm(self.force_b))


@dataclass(frozen=True)
class NetworkSolution:
    """The steady state of a network: ``positions`` ({point: m, world}), ``lines`` ({name:
    ``LineEnds``}), ``note`` (how the free points and bodies were found, or why not),
    ``unbalanced`` (one sentence for each part the statics hold where it is written instead of
    balancing it) and ``poses`` ({body: ``statics.BodyPose``}: origin m, world, and rotation;
    ``rpy_deg`` its roll, pitch, yaw in degrees; the written pose where the statics hold it)."""

    positions: dict
    lines: dict
    note: str
    unbalanced: tuple
    poses: dict = field(default_factory=dict)

    @property
    def balanced(self) -> bool:
        """Whether the free points' equilibrium was found (``note`` says how, or why not)."""
        return not self.note.startswith(("the free points' equilibrium was not found", "the equilibrium puts"))


def unbalanced_parts(net: Network) -> tuple:
    """What ``statics.equilibrium(..., bodies=True)`` holds at its written place (vehicles, walkers,
    winches, a grid seabed), each as a sentence naming the part; free and pinned bodies it
    balances (coupled and fixed ones are held, as the file asks)."""
    out = []
    for name in net.vehicles:
        out.append(f"vehicle {name!r} is held where it starts: it flies on its autopilot, which has no steady "
                   "state without the current's load on it")
    for name in getattr(net, "walkers", {}) or {}:
        out.append(f"walker {name!r} is held where it stands on the seabed")
    for ln in net.lines:
        if ln.payout_speed > 0:
            out.append(f"line {ln.name!r} is solved at its start length {ln.length:g} m (it pays out at "
                       f"{ln.payout_speed:g} m/s to {ln.max_length:g} m in a run)")
    if net.bathymetry:
        out.append("the seabed is a grid: a line's catenary lies on a level seabed at its low end's depth")
    return tuple(out)


def solve(net: Network) -> NetworkSolution:
    """The network's steady state as a run starts from it (``run.build``), from the positions
    the file gives."""
    from .run import start_positions

    start = start_positions(net)
    if net.start == "as_written":
        positions, note = start, "simulation.start = as_written: every point held where it is written"
        poses = {n: statics.BodyPose(np.array(b.position, float), statics.rotation(b.rpy_deg))
                 for n, b in net.bodies.items()}
    else:
        positions, note, poses = statics.equilibrium(net, start, bodies=True)
    lines = {}
    for ln in net.lines:
        st = statics.line_ends(net, ln, positions[ln.a], positions[ln.b])
        lines[ln.name] = LineEnds(ln.name, st.force_a, st.force_b, st.nodes, st.catenary)
    return NetworkSolution(positions, lines, note, unbalanced_parts(net), poses)

"""A network of lines (``mjtether.network.run.NetworkRun``) as ``render.FrameRenderer`` draws it, and
the video factories that ``network.run.simulate`` and ``run_to`` take.

Every line is drawn as capsules coloured by its element tensions on one fixed scale for all lines
(by default twice the largest element tension of any line when the video starts, rounded up to
1, 2 or 5 x 10^k N: ``render.nice_scale``); the water column is the network's
(``network.run.water_of``); the ``track`` camera frames the whole network from the same angle as
a scenario's (there is no robot to follow), ``side`` and ``top`` as for a scenario; ``walker`` is
refused (a network has no walker). The overlay gives the time and, per line (the
``OVERLAY_LINES`` with the largest end tension where there are more), the tension at its ends A
and B (N), named as in the network. Lines are given from end A to end B, as ``lines.npz`` keeps
them; elements still on a winch's drum (zero length, at end B) are left out. Units SI; world
frame, z up.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from mjtether.network.run import water_of

from .render import FORMATS, FrameView, VideoRecorder, VideoSettings, check_output_path, nice_scale

OVERLAY_LINES = 6
"""Lines named in the overlay at most (those with the largest end tension)."""
WALKER_REFUSED = ("video.camera 'walker' is a single-tether scenario's walker camera; a network's video takes track, side "
                  "or top")


def deployed(nodes: np.ndarray, tension: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A line's ``nodes`` (n+1, 3) and element ``tension`` (n,), from end A to end B, without the
    elements on a drum at end B (their nodes are all given at the fairlead: the same point)."""
    before = np.all(nodes[:-1] == nodes[-1], axis=1)[::-1]  # (nodes n-1 .. 0: at end B's node?)
    on_drum = len(before) if before.all() else int(np.argmin(before))
    keep = len(tension) - on_drum
    return nodes[:keep + 1], tension[:keep]


class NetworkView(FrameView):
    """The live state of a ``NetworkRun`` ``r`` for ``render.FrameRenderer``: its model and data, its
    lines' nodes and element tensions (``BoundTether.all_nodes``/``element_tension``, reversed to
    run from end A to end B), the end forces ``r.line_forces`` gives, and its water."""

    def __init__(self, r):
        self.r, self.net = r, r.net
        self.water = water_of(r.net)
        self.radius = {ln.name: r.net.line_types[ln.type].diameter / 2 for ln in r.net.lines}

    model = property(lambda self: self.r.sim.model)
    data = property(lambda self: self.r.sim.data)
    duration = property(lambda self: self.net.duration)

    @property
    def time(self) -> float:
        """The time shown (s)."""
        return self.r.sim.time

    def line_state(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """Line ``name``'s every node (n+1, 3; m, world) and element tension (n,; N), from end A
        to end B."""
        bt, d = self.r.sim.tethers[name], self.r.sim.data
        return bt.all_nodes(d)[::-1], bt.element_tension(d)[::-1]

    def end_tensions(self) -> dict:
        """{line name: (tension at end A, at end B)} (N)."""
        return {ln.name: tuple(float(np.linalg.norm(f)) for f in self.r.line_forces(ln.name)) for ln in self.net.lines}

    def lines(self) -> list:
        return [(*deployed(*self.line_state(ln.name)), self.radius[ln.name]) for ln in self.net.lines]

    def framed(self, nodes: np.ndarray) -> np.ndarray:
        """The lines' nodes and the bodies' and vehicles' origins."""
        m, d = self.model, self.data
        ids = [m.body(f"body/{n}").id for n in (*self.net.bodies, *self.net.vehicles)]
        return np.vstack([nodes, d.xpos[ids]]) if ids else nodes

    def walker_refusal(self) -> str:
        return WALKER_REFUSED

    def node_count(self) -> int:
        return sum(ln.segments + 1 for ln in self.net.lines)

    def default_scale(self) -> float:
        top = max((float(self.line_state(ln.name)[1].max(initial=0.0)) for ln in self.net.lines), default=0.0)
        return nice_scale(2.0 * max(top, 1.0))

    def overlay(self) -> list:
        ends = self.end_tensions()
        shown = sorted(ends, key=lambda n: -max(ends[n]))[:OVERLAY_LINES]
        left, right = ["time"], [f"{self.time:7.2f} s"]
        for name in (ln.name for ln in self.net.lines if ln.name in shown):
            left.append(f"line {name} A / B")
            right.append(f"{ends[name][0]:7.0f} / {ends[name][1]:.0f} N")
        if len(ends) > len(shown):
            left.append(f"(+{len(ends) - len(shown)} lines)")
            right.append("")
        return [(mujoco.mjtGridPos.mjGRID_TOPLEFT, "\n".join(left), "\n".join(right))]


def network_video(settings: VideoSettings, path, duration: float | None = None, overwrite: bool = True):
    """A ``network.run.simulate(video=...)`` factory: ``f(r)`` makes the ``VideoRecorder`` of the
    ``NetworkRun`` ``r`` writing ``path`` for ``duration`` s (default: the network's). The path and
    the camera are checked now, before any simulating (a ValueError says what is wrong)."""
    check_output_path(path, overwrite=overwrite)
    if settings.camera == "walker":
        raise ValueError(WALKER_REFUSED)
    return lambda r: VideoRecorder(NetworkView(r), path, settings, duration=duration)


def network_video_into(settings: VideoSettings, name: str, duration: float | None = None):
    """A ``network.run.run_to(video=...)`` factory: ``f(r, folder)`` makes the ``VideoRecorder``
    writing the file ``name`` (.mp4 or .gif) into the staged results folder ``folder``."""
    if Path(name).name != str(name) or Path(name).suffix.lower() not in FORMATS:
        raise ValueError(f"--video must name an .mp4 or .gif file (no folder), got {str(name)!r}")
    if settings.camera == "walker":
        raise ValueError(WALKER_REFUSED)
    return lambda r, folder: VideoRecorder(NetworkView(r), Path(folder) / name, settings, duration=duration)

"""Readouts of a bound tether: node positions, element tensions and lengths, and the forces on
its supports, from MuJoCo's state after the last ``mj_forward``/``mj_step``.

Readouts named after the deployed cable (``nodes``, ``tension``) return the deployed part only,
its first row at the ship; ``element_*`` readouts return all ``n`` elements, 0 for those on the
drum. Tensions are never negative (the elements carry tension only). Units SI, world frame.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mjtether.physics.hydro import element_geometry

from . import kernels
from .drum import Drum
from .layout import CableLayout
from .slack import SlackSwitch

_EQUALITY = int(mujoco.mjtConstraint.mjCNSTR_EQUALITY)  # an int: comparing arrays with the enum is slow


class TetherReadouts:
    """What a bound tether reads out of MuJoCo's state."""

    def __init__(self, layout: CableLayout, drum: Drum, switch: SlackSwitch):
        self.layout, self.drum, self.switch = layout, drum, switch
        self.row_cache: dict[int, slice] = {}
        self.peak = np.zeros(layout.n)  # N: each element's largest push since take_peak_compression
        self.snaps = None
        """The line's snap-load detector (``snap.SnapDetector``, ``start_snaps``), or None."""

    def nodes(self, data: mujoco.MjData) -> np.ndarray:
        """Deployed node positions (m, world frame), shape (N+1, 3), the first at the ship."""
        L = self.layout
        return data.flexvert_xpos[L.vertadr + self.drum.first:L.vertadr + L.n + 1].copy()

    def all_nodes(self, data: mujoco.MjData) -> np.ndarray:
        """Every node (m, world), shape (n+1, 3), numbered from the drum's core; nodes on the
        drum are given at the fairlead."""
        L, k = self.layout, self.drum.first
        x = data.flexvert_xpos[L.vertadr:L.vertadr + L.n + 1].copy()
        x[:k] = x[k]
        return x

    def rows(self, data: mujoco.MjData, eq_id: int) -> slice:
        """The constraint rows of equality ``eq_id``: a contiguous block that MuJoCo places
        among the equality rows at the top of efc_*; cached, and checked at its ends."""
        r = self.row_cache.get(eq_id)
        t, i, n = data.efc_type, data.efc_id, data.nefc
        if self.layout.fast is not None:  # the same check and search, compiled (kernels.equality_rows)
            start, stop = kernels.equality_rows(t, i, n, eq_id, -1 if r is None else r.start,
                                                -1 if r is None else r.stop, _EQUALITY)
            if r is None or (start, stop) != (r.start, r.stop):
                r = self.row_cache[eq_id] = slice(start, stop)
            return r
        if r is None or not (r.stop <= n and t[r.start] == _EQUALITY and i[r.start] == eq_id
                             and t[r.stop - 1] == _EQUALITY and i[r.stop - 1] == eq_id
                             and (r.start == 0 or t[r.start - 1] != _EQUALITY or i[r.start - 1] != eq_id)
                             and (r.stop == n or t[r.stop] != _EQUALITY or i[r.stop] != eq_id)):
            rows = np.nonzero((t[:n] == _EQUALITY) & (i[:n] == eq_id))[0]
            r = slice(int(rows[0]), int(rows[-1]) + 1) if len(rows) else slice(0, 0)
            self.row_cache[eq_id] = r
        return r

    def element_tension(self, data: mujoco.MjData) -> np.ndarray:
        """Axial tension of every element (N), shape (n,): never negative (elements carry
        tension only); 0 for slack elements and those on the drum."""
        L = self.layout
        rows = self.switch.element_rows(data)
        out = np.zeros(L.n)
        if rows.stop > data.nefc:
            raise RuntimeError("tether tension is available after mj_forward/mj_step")
        out[np.flatnonzero(self.switch.efc_active(data)[L.eqs])] = np.maximum(-data.efc_force[rows], 0.0)
        out[:self.drum.first] = 0.0
        return out

    def element_compression(self, data: mujoco.MjData) -> np.ndarray:
        """The push of every element's constraint (N, >= 0), shape (n,): the force with which it
        resisted shortening at the last step, which ``element_tension`` leaves out (a cable
        carries tension only, so any push is the model's, not the cable's); 0 for slack elements
        and those on the drum."""
        L = self.layout
        rows = self.switch.element_rows(data)
        out = np.zeros(L.n)
        if rows.stop > data.nefc:
            raise RuntimeError("tether compression is available after mj_forward/mj_step")
        out[np.flatnonzero(self.switch.efc_active(data)[L.eqs])] = np.maximum(data.efc_force[rows], 0.0)
        out[:self.drum.first] = 0.0
        return out

    def track_peak_compression(self, data: mujoco.MjData | None = None) -> None:
        """Raise each element's running peak push to its push now (``element_compression``);
        ``Simulation`` calls it after every step it takes (the step as kept, after any redo)."""
        L = self.layout
        data = L.data if data is None else data
        if L.fast is None:
            np.maximum(self.peak, self.element_compression(data), out=self.peak)
            return
        rows = self.switch.element_rows(data)  # the same, compiled (kernels.peak_push)
        if rows.stop > data.nefc:
            raise RuntimeError("tether compression is available after mj_forward/mj_step")
        kernels.peak_push(self.peak, self.switch.efc_active(data)[L.eqs], data.efc_force[rows], self.drum.first)

    def take_peak_compression(self, data: mujoco.MjData | None = None) -> np.ndarray:
        """The largest push of every element's constraint since the last call (N, >= 0), shape
        (n,): over every step ``Simulation`` took since then and the state now; 0 for elements
        that were slack or on the drum all along. Resets the peak."""
        self.track_peak_compression(data)
        out = self.peak.copy()
        self.peak[:] = 0.0
        return out

    def start_snaps(self, data: mujoco.MjData | None = None, **kwargs):
        """Start finding this line's snap loads (``snap.SnapDetector``) from the state now, the
        static one: each element's slack threshold ``snap.slack_threshold`` of its tension now
        (unless ``slack_threshold_N`` is given; ``kwargs`` go to the detector). ``Simulation``
        then gives it every step it takes (``track_snaps``). Returns the detector."""
        from .snap import SnapDetector, slack_threshold
        data = self.layout.data if data is None else data
        static = self.element_tension(data)
        if "slack_threshold_N" not in kwargs:
            kwargs["slack_threshold_N"] = slack_threshold(static)
        self.snaps = SnapDetector(self.layout.n, **kwargs)
        self.snaps.static_tension_N = static  # (what DNV's slack check weighs the least tension against)
        self.snaps.first_at_start = self.drum.first
        return self.snaps

    def track_snaps(self, data: mujoco.MjData | None = None) -> None:
        """Give the snap detector the element tensions of the step just taken (as kept, after any
        redo); ``Simulation`` calls it after every step where ``start_snaps`` was called. A step
        whose time is not later than the last one's is left out: MuJoCo reset the state after an
        instability (its time too), and ``Simulation.check`` reports the divergence."""
        L = self.layout
        data = L.data if data is None else data
        if not data.time > self.snaps.time:
            return
        rows = self.switch.element_rows(data)
        if rows.stop > data.nefc:
            raise RuntimeError("tether tension is available after mj_forward/mj_step")
        self.snaps.update_from_constraints(data.time, self.switch.efc_active(data)[L.eqs], data.efc_force[rows],
                                           self.drum.first)

    def clear_peak_compression(self) -> None:
        """Forget the pushes tracked so far (``take_peak_compression`` then starts from now)."""
        self.peak[:] = 0.0

    def tension(self, data: mujoco.MjData) -> np.ndarray:
        """Axial tension of the deployed elements (N), shape (N,), the first at the ship."""
        return self.element_tension(data)[self.drum.first:]

    def element_length(self, data: mujoco.MjData) -> np.ndarray:
        """Stretched length of every element (m), shape (n,); 0 for elements on the drum."""
        out = data.ten_length[self.layout.ten].copy()
        out[:self.drum.first] = 0.0
        return out

    def slack_count(self, data: mujoco.MjData) -> int:
        """Deployed elements carrying no tension."""
        return int(np.count_nonzero(self.tension(data) <= 0.0))

    def stretched_length(self, data: mujoco.MjData) -> float:
        """Sum of the deployed elements' lengths (m)."""
        return float(element_geometry(self.nodes(data))[1].sum())

    def end_force(self, data: mujoco.MjData, which: str = "start") -> np.ndarray:
        """Force of the tether on its ``"start"`` (ship) or ``"end"`` (robot) support (N, world):
        the force of the ``connect`` constraint that holds the end node to the support."""
        L = self.layout
        if which not in ("start", "end"):
            raise ValueError(f"which must be 'start' or 'end', got {which!r}")
        eq = L.end_eq if which == "end" else (None if L.drum_eq is None else L.drum_eq[self.drum.first])
        if eq is None:  # a free end
            return np.zeros(3)
        return data.efc_force[self.rows(data, int(eq))].copy()

    def end_tension(self, data: mujoco.MjData, which: str = "start") -> float:
        """Magnitude of ``end_force`` (N)."""
        f = self.end_force(data, which)
        return math.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) if len(f) == 3 else 0.0

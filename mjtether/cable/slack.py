"""Tension-only elements: switching a bound tether's element equalities between taut and slack.

MuJoCo's equalities are two-sided: they push as well as pull. After each step an element whose
equality pushed goes slack (its equality off), and a slack element stretched past its rest
length is taut again. A push worth more than ``SLACK_FORCE`` of an element's weight in water,
or an overshoot worth more than that and ``SLACK_TENSION`` of the highest tension, has its step
redone with the new set (``Simulation.step``), so that no push above SLACK_FORCE survives a step:
that of an element shorter than its rest length, or of one still longer and shortening fast (its
damping pushing; a cable's damping cannot push either). (MuJoCo's one-sided limit constraints
chatter at the stiffness a long time step allows, so tension only is made this way, from
two-sided equalities.) Units SI.
"""

from __future__ import annotations

import numpy as np

from . import kernels
from .drum import Drum
from .layout import CableLayout

SLACK_FORCE = 0.1
"""A push worth more than this part of an element's weight in water has its step redone with the
element switched off; an overshoot (a slack element stretched past its rest length) only if it is
also worth SLACK_TENSION of the highest element tension at that step (see
``SlackSwitch.update``)."""
SLACK_TENSION = 0.1
"""See SLACK_FORCE: an overshoot below either is switched on a step late, which costs less than
redoing the step (measured on the built-in walker scenario, where the gait jerks the cable near
the tow point taut and slack: 1.007 MuJoCo steps per step)."""


class SlackSwitch:
    """The taut/slack switching of a bound tether's elements (``eq_active``) and where the
    active elements' constraint rows are."""

    def __init__(self, layout: CableLayout, drum: Drum):
        self.layout, self.drum = layout, drum
        L, water = layout, drum.water
        self._eq_snapshot = None  # Simulation's copy of eq_active at the last force computation (use_snapshot)
        self._snap_views = None  # its slices before and at the elements (element_rows)
        self._eq_view, self._length_view = L.data.eq_active[L.eqs], L.data.ten_length[L.ten]
        # pushes and overshoots below this (N) switch elements without redoing the step
        mk = L.line
        w0 = L.spec.wet_weight_per_length(float(water.rho([0.0])[0])) if mk.is_uniform else \
            float(np.mean(np.abs(mk.element_wet_weight(float(water.rho([0.0])[0]), water.gravity))))
        self.f_min = max(SLACK_FORCE * abs(w0) * L.l0, 1e-6)

    def update(self, taut: bool = True) -> bool:
        """Switch elements between taut and slack after a step: an element whose equality pushed
        (compression) goes slack; a slack one longer than its rest length is taut again (with
        ``taut`` False, the last pass of a step redone, none is switched on, and only elements
        shorter than their rest length or pushing by more than ``SLACK_FORCE`` of an element's
        weight in water go slack). Returns whether a push was worth more than SLACK_FORCE, or an
        overshoot more than that and ``SLACK_TENSION`` of the highest tension (``Simulation``
        then redoes the step with the new set, so that no element pushes and none overshoots its
        rest length for a step; smaller ones, a laid cable's noise, just switch)."""
        L, dr = self.layout, self.drum
        d, k = L.data, dr.first
        if L.fast is not None:  # the same switching, compiled (kernels.slack_switch)
            rows = self.element_rows(d)
            return kernels.slack_switch(self._eq_view, d.efc_force[rows], self._length_view, dr.rest,
                                        dr.K, k, self.f_min, SLACK_TENSION, taut,
                                        rows.stop - rows.start >= L.n - k)[1]
        act = d.eq_active[L.eqs].copy()
        rows = self.element_rows(d)
        f = d.efc_force[rows]
        changed = redo = False
        # a push is worth a redo above a tenth of an element's weight; an overshoot above that
        # or SLACK_TENSION of the highest tension in the cable now
        f_min = self.f_min
        f_over = max(f_min, -SLACK_TENSION * f.min()) if len(f) else f_min
        if len(f) and f.max() > 0.0:  # efc_force > 0 pushes the nodes apart
            pushing = f > 0.0
            push = np.flatnonzero(act)[pushing]
            if not taut:  # the last time round: elements shorter than their rest length, and pushes worth a redo
                keep = (d.ten_length[L.tadr + push] < dr.rest[push]) | (f[pushing] > f_min)
                push, pushing = push[keep], f[pushing][keep]
            else:
                pushing = f[pushing]
            if len(push):  # (shorter than its rest length or not: a cable's damping cannot push)
                act[push] = 0
                changed = True
                redo = pushing.max() > f_min
        if taut and rows.stop - rows.start < L.n - k:
            slack = np.flatnonzero(act[k:] == 0) + k
            over = d.ten_length[L.tadr + slack] - dr.rest[slack]
            caught = over > 0.0
            if caught.any():
                act[slack[caught]] = 1
                changed = True
                redo = redo or float((over[caught] * dr.K[slack[caught]]).max()) > f_over
        if changed:
            d.eq_active[L.eqs] = act
        return redo

    def element_rows(self, data) -> slice:
        """Constraint rows of the active element equalities: one each, in element order, after
        the rows of the active equalities defined before them (MuJoCo orders equality rows by
        equality)."""
        L = self.layout
        if self._eq_snapshot is None:  # (efc_active)
            before, elements = data.eq_active[:L.eq0], data.eq_active[L.eqs]
        else:
            before, elements = self._snap_views
        r0 = int(L.rows_before @ before) if L.eq0 else 0
        return slice(r0, r0 + int(np.count_nonzero(elements)))

    def use_snapshot(self, snap: np.ndarray) -> None:
        """Read ``eq_active`` as it was at the last force computation from ``snap``, a copy
        that the simulation keeps up to date in place (see ``efc_active``)."""
        self._eq_snapshot = snap
        self._snap_views = (snap[:self.layout.eq0], snap[self.layout.eqs])

    def efc_active(self, data) -> np.ndarray:
        """``eq_active`` as it was when MuJoCo last computed the constraint forces (the slack
        switching changes it after a step, for the next one)."""
        snap = self._eq_snapshot
        return data.eq_active if snap is None else snap

"""Snap loads: a line's slack-to-taut events, found from its element tensions as a run goes.

A ``SnapDetector`` is given every element's tension (N, >= 0) once a time step. For each element
it keeps one of three states, all as NumPy arrays (no Python loop over the elements):

* **taut**: the tension is above ``slack_threshold_N``;
* **slack**: the tension fell to ``slack_threshold_N`` or below (at the first such sample, time
  ``t_slack``); it stays slack until the tension rises above ``taut_threshold_N`` (hysteresis:
  default twice the slack threshold, so that a tension rippling about the slack threshold does
  not make an event of every ripple);
* **snapping**: the first sample above ``taut_threshold_N`` after a slack spell (time
  ``t_taut``) starts a snap. The snap's peak is the largest tension from that sample on, until
  the first of: the element goes slack again (tension <= ``slack_threshold_N``), or ``window_s``
  has passed since ``t_taut`` (the sample at exactly ``t_taut + window_s`` included). A snap
  rings at the line's axial period 2 L / sqrt(EA / m) (under 0.1 s for 100 m of steel wire of
  EA 7 MN, 0.6 kg/m; about 2 s for 2 km of a fibre line of EA 5 MN, 1 kg/m), so the default
  window, 2 s, holds the first peak of most tethers; give a longer ``window_s`` for longer or
  softer lines.

Each snap is one event, a dict with SI keys: ``time_s`` (``t_taut``, the sample at which the
element was taut again), ``element`` (index; element i joins nodes i and i+1, node 0 at the
ship), ``peak_tension_N`` and ``slack_duration_s`` (``t_taut - t_slack``, to the sampling: both
ends are sample times, not interpolated crossings). An element already slack at the first
sample counts as slack from then. An element slack at the end has no event (it never went taut
again); ``slack_now`` says which ones are.

Choosing the slack threshold. A tension-only element (``slack.SlackSwitch``) reads 0 N exactly
only while its equality is off; one switching near slack reads small tensions of solver noise
(a push redone, an overshoot switched on a step late), and a threshold of 0 N would miss slack
spells or split them into many. ``slack_threshold`` gives the default:
``SLACK_FRACTION`` (1 %) of each element's static tension (the steady state the run starts
from), and never below ``SLACK_FLOOR_N``. A line whose static tension is itself small (a line
lying on the seabed) then has a small threshold, not one borrowed from the top tension.

``dnv_slack_check`` states DNV-RP-H103's slack criterion: in the April 2011 edition, Sec. 3.4.2
(splash zone, "slack sling criterion": F_hyd <= 0.9 F_static-min, i.e. the minimum tension at
least 10 % of the static submerged weight), which Sec. 4.7 ("snap forces in slings or hoist
line", deep-water lowering) applies to lift wires. The clause numbers are as read from that
edition; the search tools available when this was written found no copy to confirm them.
Units SI.
"""

from __future__ import annotations

import copy
import math

import numpy as np

from mjtether import _checks
from mjtether.physics.compiled import backend

from . import kernels

SLACK_FRACTION = 0.01
"""The default slack threshold as a part of each element's static tension."""
SLACK_FLOOR_N = 1.0
"""The smallest default slack threshold (N): below it a tension is solver noise."""
TAUT_FACTOR = 2.0
"""The default taut threshold as a multiple of the slack threshold (the hysteresis band)."""
WINDOW_S = 2.0
"""The default time (s) after re-tautening within which a snap's peak is sought."""
DNV_SLACK_FRACTION = 0.1
"""DNV-RP-H103's slack criterion: slack when the minimum tension is below this part of the
static submerged weight (see ``dnv_slack_check``)."""
DNV_REFERENCE = ("DNV-RP-H103 (2011), Sec. 3.4.2 slack sling criterion (F_hyd <= 0.9 F_static-min), "
                 "applied to snap loads in Sec. 4.7")


def slack_threshold(static_tension_N, fraction: float = SLACK_FRACTION, floor_N: float = SLACK_FLOOR_N) -> np.ndarray:
    """The default slack threshold (N) of each element: ``fraction`` of its static tension
    ``static_tension_N`` (N, one per element), at least ``floor_N``."""
    static = np.asarray(static_tension_N, dtype=float)
    if static.ndim > 1 or not np.all(np.isfinite(static)) or np.any(static < 0):
        raise ValueError("static_tension_N must be finite tensions >= 0 N, one per element")
    _checks.in_range("slack fraction", fraction, 0.0, 1.0)
    _checks.non_negative("slack floor_N", floor_N, "N")
    return np.maximum(fraction * static, floor_N)


class SnapDetector:
    """Slack-to-taut events of a line of ``n_elements`` elements (see the module docstring).

    ``slack_threshold_N``: a tension (N) at or below which an element is slack, one number or
    one per element (``slack_threshold`` gives the default from the static tensions);
    ``taut_threshold_N``: above it a slack element is taut again (default ``TAUT_FACTOR`` times
    the slack threshold; at least the slack threshold); ``window_s``: how long after
    re-tautening the peak is sought (s); ``compiled``: let ``update_from_constraints`` run the
    compiled twin (``kernels.snap_update``) where the compiled kernels run (False: the NumPy
    reference, ``update``, always)."""

    def __init__(self, n_elements: int, slack_threshold_N, taut_threshold_N=None, window_s: float = WINDOW_S,
                 compiled: bool = True):
        n = self.n_elements = _checks.positive_int("n_elements", n_elements)
        self.slack_threshold_N = self._per_element("slack_threshold_N", slack_threshold_N)
        if np.any(self.slack_threshold_N <= 0):
            raise ValueError("slack_threshold_N must be > 0 N (0 N exactly misses slack spells: see "
                             f"mjtether.cable.snap), got {slack_threshold_N!r}")
        taut = TAUT_FACTOR * self.slack_threshold_N if taut_threshold_N is None else \
            self._per_element("taut_threshold_N", taut_threshold_N)
        if np.any(taut < self.slack_threshold_N):
            raise ValueError(f"taut_threshold_N must be >= slack_threshold_N, got {taut_threshold_N!r}")
        self.taut_threshold_N = taut
        self.window_s = _checks.positive("window_s", window_s, "s")
        self.slack_now = np.zeros(n, dtype=bool)  # slack at the last sample
        self._snapping = np.zeros(n, dtype=bool)
        self._t_slack = np.full(n, math.nan)  # s, when each slack spell began
        self._t_taut = np.full(n, math.nan)  # s, when each open snap began
        self._slack_for = np.zeros(n)  # s, the slack spell before each open snap
        self._peak = np.zeros(n)  # N, each open snap's peak so far
        self.min_tension_N = np.full(n, math.inf)  # N, each element's least tension so far
        self.max_tension_N = np.zeros(n)  # N, its largest
        self.interval_max_N = np.zeros(n)  # N, its largest since take_interval_max
        self._top_min = np.full(1, math.inf)  # N, the least tension of the element at ``first`` (see top_min_N)
        self.static_tension_N = None
        """Each element's static tension (N), where the detector's owner gave it (``snap_report``'s
        DNV check weighs the least tension against it)."""
        self._closing = np.zeros(n, dtype=bool)  # (the compiled twin's: snaps that ended at its update)
        self._closed = []
        self._clock = np.full(1, -math.inf)  # s, the time of the last update (an array: ``cable.stepping`` writes it)
        self.compiled = compiled and backend() == "numba"
        """Whether ``update_from_constraints`` runs the compiled twin (``kernels.snap_update``)."""

    @property
    def _t(self) -> float:
        return float(self._clock[0])

    @_t.setter
    def _t(self, value: float) -> None:
        self._clock[0] = value

    def _per_element(self, name: str, value) -> np.ndarray:
        v = np.asarray(value, dtype=float)
        if v.ndim == 0:
            v = np.full(self.n_elements, float(v))
        if v.shape != (self.n_elements,) or not np.all(np.isfinite(v)):
            raise ValueError(f"{name} must be one finite tension (N) or {self.n_elements} of them "
                             f"(one per element), got shape {v.shape}")
        return v

    def update(self, t: float, tension_N, first: int = 0) -> None:
        """Take the element tensions ``tension_N`` (N, >= 0, one per element) at time ``t`` (s,
        later than the last call's). Elements before ``first`` are on the drum (not deployed):
        none of them is slack, an open snap there ends, and their tensions are not kept."""
        T = np.asarray(tension_N, dtype=float)
        if T.shape != (self.n_elements,):
            raise ValueError(f"tension_N must hold {self.n_elements} element tensions (N), got shape {T.shape}")
        if not (t > self._t and math.isfinite(t)):
            raise ValueError(f"snap detector time must be finite and later than {self._t} s, got {t!r}")
        lo = T.min()
        if not (lo >= 0.0 and math.isfinite(T.max())):  # (NaN fails both)
            raise ValueError(f"tension_N must be finite and >= 0 N, got minimum {lo!r} at element {int(np.argmin(T))}")
        self._t = t = float(t)
        k = _checks.positive_int("first", first, minimum=0)
        deployed = slice(k, None)
        np.minimum(self.min_tension_N[deployed], T[deployed], out=self.min_tension_N[deployed])
        if k < self.n_elements:
            self._top_min[0] = min(self._top_min[0], T[k])
        np.maximum(self.max_tension_N, T, out=self.max_tension_N)
        np.maximum(self.interval_max_N, T, out=self.interval_max_N)
        low = T <= self.slack_threshold_N
        low[:k] = False
        if self._snapping.any():
            np.maximum(self._peak, T, out=self._peak, where=self._snapping)
            done = self._snapping & (low | (t - self._t_taut >= self.window_s))
            done[:k] = self._snapping[:k]
            if done.any():
                self._close(np.flatnonzero(done))
        self.slack_now[:k] = False
        went_slack = low & ~self.slack_now
        self._t_slack[went_slack] = t
        self.slack_now |= went_slack
        taut = self.slack_now & (T > self.taut_threshold_N)
        if taut.any():
            self.slack_now &= ~taut
            self._snapping |= taut
            self._t_taut[taut] = t
            self._slack_for[taut] = t - self._t_slack[taut]
            self._peak[taut] = T[taut]

    def update_from_constraints(self, t: float, active, force, first: int) -> None:
        """``update`` from the tether's constraint state as ``readouts.TetherReadouts`` reads it:
        ``active`` (n,) each element's equality on, ``force`` the active elements' constraint
        forces in element order (N, tension negative), ``first`` the first deployed element; by
        the compiled twin (``kernels.snap_update``) where there is one, else by ``update``."""
        if not self.compiled:
            T = np.zeros(self.n_elements)
            T[np.flatnonzero(active)] = np.maximum(-np.asarray(force), 0.0)
            T[:first] = 0.0
            self.update(t, T, first)
            return
        if not (t > self._t and math.isfinite(t)):
            raise ValueError(f"snap detector time must be finite and later than {self._t} s, got {t!r}")
        self._t = t = float(t)
        closed = kernels.snap_update(t, active, force, first, self.slack_threshold_N, self.taut_threshold_N,
                                     self.window_s, self.slack_now, self._snapping, self._t_slack, self._t_taut,
                                     self._slack_for, self._peak, self.min_tension_N, self.max_tension_N,
                                     self.interval_max_N, self._closing, self._top_min)
        self.took(closed)

    def took(self, closed: int) -> None:
        """After the compiled twin (``kernels.snap_update``) returned ``closed``: record the snaps
        that ended (``_closing``), or raise for a non-finite force (``closed`` < 0)."""
        if closed < 0:
            raise ValueError(f"tension_N must be finite and >= 0 N, got a non-finite force at element {-closed - 1}")
        if closed:
            idx = np.flatnonzero(self._closing)
            self._closed.extend(_event(self._t_taut[i], i, self._peak[i], self._slack_for[i]) for i in idx)
            self._closing[idx] = False

    @property
    def top_min_N(self) -> float:
        """The least tension (N) of the first deployed element (the one at the fairlead, whichever
        it was at each update) so far; inf before the first update."""
        return float(self._top_min[0])

    @property
    def time(self) -> float:
        """The time (s) of the last update (-inf before the first)."""
        return self._t

    def copy(self) -> "SnapDetector":
        """An independent copy: its state, its events so far (``Simulation.save_state`` keeps one,
        so that a restored simulation goes on from the snaps it had found). Its arrays are copied;
        the events found so far are shared (each is made once and never changed), so that a copy
        costs the same after thousands of snaps as after none (``save_state`` takes one per block
        of steps)."""
        out = copy.copy(self)
        for name, value in vars(self).items():
            if isinstance(value, np.ndarray):
                setattr(out, name, value.copy())
        out._closed = list(self._closed)
        return out

    def take_interval_max(self) -> np.ndarray:
        """Each element's largest tension (N) over every update since the last call; resets it."""
        out = self.interval_max_N.copy()
        self.interval_max_N[:] = 0.0
        return out

    def _close(self, idx: np.ndarray) -> None:
        """End the open snaps of elements ``idx`` (a loop over events, not elements)."""
        self._closed.extend(_event(self._t_taut[i], i, self._peak[i], self._slack_for[i]) for i in idx)
        self._snapping[idx] = False

    @property
    def events(self) -> list[dict]:
        """Every snap so far, in time order (then by element): those still within their window
        with their peak so far. Keys: time_s, element, peak_tension_N, slack_duration_s."""
        open_ = [_event(self._t_taut[i], i, self._peak[i], self._slack_for[i]) for i in np.flatnonzero(self._snapping)]
        return sorted(self._closed + open_, key=lambda e: (e["time_s"], e["element"]))

    def summary(self, worst: int = 10) -> dict:
        """``snap_summary`` of the events so far."""
        return snap_summary(self.events, worst)


def _event(t_taut, element, peak, slack_for) -> dict:
    return {"time_s": float(t_taut), "element": int(element), "peak_tension_N": float(peak),
            "slack_duration_s": float(slack_for)}


def by_element(events: list[dict]) -> list[dict]:
    """The events grouped by element, in element order: ``element``, ``count``, the largest
    ``peak_tension_N``, ``first_time_s`` (s) and the longest ``slack_duration_s``."""
    groups = {}
    for e in events:
        groups.setdefault(e["element"], []).append(e)
    return [{"element": k, "count": len(g), "peak_tension_N": max(e["peak_tension_N"] for e in g),
             "first_time_s": min(e["time_s"] for e in g),
             "slack_duration_s": max(e["slack_duration_s"] for e in g)} for k, g in sorted(groups.items())]


def worst_events(events: list[dict], n: int = 10) -> list[dict]:
    """The ``n`` events of highest peak tension, highest first (ties: the earlier first)."""
    n = _checks.positive_int("worst", n, minimum=0)
    return sorted(events, key=lambda e: (-e["peak_tension_N"], e["time_s"], e["element"]))[:n]


def snap_summary(events: list[dict], worst: int = 10) -> dict:
    """A summary of snap events for ``summary.json``: ``count``, ``max_peak_tension_N`` and
    ``longest_slack_s`` (0 where there are none), ``elements`` (``by_element``) and ``worst``
    (the ``worst`` events of highest peak, ``worst_events``)."""
    return {"count": len(events),
            "max_peak_tension_N": max((e["peak_tension_N"] for e in events), default=0.0),
            "longest_slack_s": max((e["slack_duration_s"] for e in events), default=0.0),
            "elements": by_element(events), "worst": worst_events(events, worst)}


def dnv_slack_check(min_tension_N: float, static_submerged_weight_N: float) -> dict:
    """DNV-RP-H103's slack criterion: a line (a lift wire, a sling, a tether) is taken as slack,
    and snap loads are to be expected, when its minimum tension falls below
    ``DNV_SLACK_FRACTION`` (10 %) of the static submerged weight it carries (N); equivalently the
    dynamic load amplitude exceeds 90 % of the static one. Returns the numbers and the verdict:
    ``min_tension_N``, ``static_submerged_weight_N``, ``limit_N`` (10 % of it), ``ratio``
    (minimum tension / static weight), ``slack`` (bool), ``verdict`` (a sentence) and
    ``criterion`` (the reference)."""
    t_min = _checks.finite("min_tension_N", min_tension_N)
    w = _checks.positive("static_submerged_weight_N", static_submerged_weight_N, "N")
    limit = DNV_SLACK_FRACTION * w
    slack = t_min < limit
    verdict = (f"slack: minimum tension {t_min:.6g} N is below 10 % of the static submerged weight "
               f"({limit:.6g} N of {w:.6g} N); snap loads are to be expected" if slack else
               f"not slack: minimum tension {t_min:.6g} N is at least 10 % of the static submerged weight "
               f"({limit:.6g} N of {w:.6g} N)")
    return {"min_tension_N": t_min, "static_submerged_weight_N": w, "limit_N": limit, "ratio": t_min / w,
            "slack": bool(slack), "verdict": verdict, "criterion": DNV_REFERENCE}


def snap_report(bt) -> dict:
    """A line's snap loads for ``summary.json``, from its bound tether ``bt``
    (``BoundTether``, whose ``snaps`` detector ran): ``snap_summary`` of every slack-to-taut
    event of the run, each element numbered as ``lines.npz`` numbers them (from end A, the
    anchor or robot; the bound tether numbers them from its drum's core, at end B) with
    ``from_ship_m`` (the unstretched arc length from end B, the fairlead, to its middle at the end
    of the run); the thresholds used; the elements slack at the end (``slack_at_end``); and
    DNV-RP-H103's slack criterion at end B (``dnv_slack``, ``dnv_slack_check``): the least
    tension of the element at the fairlead over every time step (``SnapDetector.top_min_N``;
    whichever element was there, on a line paying out) against 10 % of the static tension the
    top carried at the start (the submerged weight it holds up), or why it was not evaluated."""
    det = bt.snaps
    n, rest, top = bt.n, np.asarray(bt.rest_lengths, dtype=float), bt.first  # (top: end B's element)
    from_ship = np.cumsum(rest) - rest / 2 - rest[:top].sum()

    def named(e: int) -> int:  # the drum's numbering to lines.npz's, from end A
        return n - 1 - int(e)
    events = [{**e, "element": named(e["element"]), "from_ship_m": float(from_ship[e["element"]])}
              for e in det.events]
    out = snap_summary(events)
    for g in out["elements"]:
        g["from_ship_m"] = float(from_ship[named(g["element"])])
    out["thresholds"] = {"slack_fraction_of_static": SLACK_FRACTION, "slack_floor_N": SLACK_FLOOR_N,
                         "taut_factor": TAUT_FACTOR, "window_s": det.window_s}
    out["slack_at_end"] = sorted(named(e) for e in np.flatnonzero(det.slack_now))
    first = getattr(det, "first_at_start", top)  # (the fairlead's element when the static state was taken)
    static = float(det.static_tension_N[first]) if det.static_tension_N is not None else 0.0
    if static > 0.0:
        out["dnv_slack"] = dnv_slack_check(det.top_min_N, static)
    else:
        out["dnv_slack"] = {"verdict": "not evaluated: the top carried no static tension (nothing deployed, or "
                            "slack at the start)", "criterion": DNV_REFERENCE}
    out["dnv_slack"]["element"] = named(top)
    return out

"""The ship's winch: how the deployed tether length changes during a run.

A ``Winch`` is a small controller: each control step it gets the time, the ship-end tension
and the robot's speed, and returns the payout rate (m/s, > 0 pays out, < 0 reels in); the
deployed length integrates it and stays within [min_length, max_length]. Modes:

* ``"fixed"``: no payout;
* ``"constant"``: payout (or reel-in, if negative) at ``rate``;
* ``"follow"``: payout at the robot's speed, V_po = v_r (Khan et al. 2023, Eqs. 30-33), taken
  as its net progress along the cable: the caller passes the robot's signed velocity along the
  cable's direction at the robot (away from the ship positive), and the winch low-pass filters
  it over ``FOLLOW_FILTER_S``. A legged robot's gait makes that velocity jitter back and forth;
  paying out on its magnitude, as before, paid out 40 m an hour for a walker standing still,
  while the filtered net progress of a standing walker is zero (and reels in if it comes back);
* ``"tension"``: keep the ship-end tension inside ``band`` = (low, high) N, as a constant-
  tension winch does: a PI regulator on the tension, low-pass filtered over ``TENSION_FILTER_S``
  (the gait and the cable's own vibration make it ripple), towards the band's centre. The
  proportional part pays out at ``max_rate`` when the tension reaches the band's upper edge
  (reels in at the lower); the integral part (time ``TENSION_INTEGRAL_S``) learns the steady
  payout a moving robot or ship needs, so that the tension settles inside the band rather than
  at its edge;
* ``"external"``: the rate last given to ``command`` (e.g. by a Gymnasium agent);
* ``"free"``: a free drum paying out at (nearly) zero tension (the drum-end boundary condition
  T = 0 of a cable paid out from a drum): payout at tension / ``drum_damping`` (N s/m), limited
  to ``max_rate``; a cable that slackens is not reeled back. Given the drum element's stiffness
  K (N/m) and the rate its length grows at (``BoundTether.drum_element``), the tension is taken
  at the end of the step (backward Euler: rate = (T + K l' dt) / (c + K dt), which is T / c in a
  steady payout): with the light drum of a fibre (c of order 1 N s/m) and a short, stiff
  element at the drum, the explicit law T / c overshoots every step and the drum chatters.

Every rate is limited to |rate| <= max_rate, and changes at most at ``max_accel`` (m/s^2): a
real drum has inertia and a drive of finite power, and a step in payout rate jerks the cable at
the fairlead (the length changes at the drum, see ``BoundTether.set_length``). ``max_accel`` 0
(the default) is ``DRIVEN_ACCEL`` for a driven winch and no limit for a free drum, which takes
only its own damping: limited to 0.2 m/s^2, a REMUS 100 pulling fibre off a free drum was held
back by 45 N for its first 8 s, where the drum's damping asks for 0.3 N. A length of 0 is
allowed (nothing deployed: a free drum pays out from there). Units SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mjtether import _checks


def _clip(x: float, lo: float, hi: float) -> float:
    return float(min(max(x, lo), hi))


TENSION_FILTER_S = 2.0
"""Time constant (s) of the low-pass filter on the tension that the ``"tension"`` mode uses."""
TENSION_INTEGRAL_S = 3.0
"""Integral time (s) of the ``"tension"`` mode's PI regulator."""

FOLLOW_FILTER_S = 5.0
"""Time constant (s) of the low-pass filter on the robot's progress in the ``"follow"`` mode
(several gait cycles: the tripod gait's is 1.2 s)."""

MODES = ("fixed", "constant", "follow", "tension", "external", "free")
DRIVEN_ACCEL = 0.2
"""A driven winch's fastest change of payout rate (m/s^2) when ``max_accel`` is not given."""


@dataclass
class Winch:
    """Winch parameters (see the module docstring) and its deployed length ``length`` (m)."""

    length: float
    mode: str = "fixed"
    min_length: float = 0.0
    max_length: float = float("inf")
    rate: float = 0.0
    max_rate: float = 2.0
    max_accel: float = 0.0
    band: tuple = (0.0, float("inf"))
    drum_damping: float = 200.0

    def __post_init__(self):
        if self.mode not in MODES:
            raise ValueError(f"winch.mode must be one of {', '.join(MODES)}; got {self.mode!r}")
        _checks.non_negative("winch.length", self.length, "m")
        _checks.non_negative("winch.min_length", self.min_length, "m")
        if not self.max_length > self.min_length:
            raise ValueError(f"winch.max_length must be > winch.min_length ({self.min_length} m), "
                             f"got {self.max_length!r}")
        if not self.min_length <= self.length <= self.max_length:
            raise ValueError(f"winch.length must be in [{self.min_length}, {self.max_length}] m "
                             f"(min_length, max_length), got {self.length!r}")
        _checks.positive("winch.max_rate", self.max_rate, "m/s")
        _checks.non_negative("winch.max_accel", self.max_accel, "m/s^2")
        _checks.in_range("winch.rate", self.rate, -self.max_rate, self.max_rate, "m/s")
        lo, hi = (float(b) for b in self.band)
        if not (0.0 <= lo < hi):
            raise ValueError(f"winch.band must be (low, high) N with 0 <= low < high, got {self.band!r}")
        self.band = (lo, hi)
        _checks.positive("winch.drum_damping", self.drum_damping, "N s/m")
        self._command = 0.0
        self._tension = None  # filtered tension (N), "tension" mode
        self._integral = 0.0  # integral part of the payout rate (m/s), "tension" mode
        self._progress = None  # filtered progress of the robot along the cable (m/s), "follow" mode
        self.current_rate = 0.0  # m/s, the drum's payout rate now

    @property
    def accel_limit(self) -> float:
        """The fastest change of payout rate (m/s^2): ``max_accel``, or where that is 0,
        ``DRIVEN_ACCEL`` for a driven winch and none (inf) for a free drum."""
        if self.max_accel > 0:
            return self.max_accel
        return math.inf if self.mode == "free" else DRIVEN_ACCEL

    def command(self, rate: float) -> None:
        """Set the payout rate (m/s) of the ``"external"`` mode; clipped to +-max_rate."""
        self._command = _clip(_checks.finite("winch command", rate), -self.max_rate, self.max_rate)

    def payout_rate(self, t: float, tension: float, robot_speed: float, drum=None, dt: float = 0.0) -> float:
        """Payout rate (m/s) for the current state, before the length limits; ``drum``: the
        drum element's (stiffness N/m, length rate m/s), for the free drum's implicit law."""
        m = self.mode
        if m == "fixed":
            r = 0.0
        elif m == "constant":
            r = self.rate
        elif m == "follow":
            r = robot_speed if self._progress is None else self._progress
        elif m == "external":
            r = self._command
        elif m == "free":
            if drum is None:
                r = max(tension, 0.0) / self.drum_damping
            else:
                K, grow = drum
                r = max(tension + K * grow * dt, 0.0) / (self.drum_damping + K * dt)
        else:  # tension band: PI on the (filtered) tension, see the module docstring
            r = self.max_rate * self._band_error(tension) + self._integral
        return _clip(r, -self.max_rate, self.max_rate)

    def _band_error(self, tension: float) -> float:
        """Tension error relative to the band: 0 at its centre, +-1 at its edges."""
        lo, hi = self.band
        if not np.isfinite(hi):  # an open band: regulate to stay above lo
            return min(tension - lo, 0.0) / max(lo, 1.0)
        return (tension - 0.5 * (lo + hi)) / (0.5 * (hi - lo))

    def advance(self, dt: float, t: float, tension: float, robot_speed: float = 0.0, drum=None) -> float:
        """Integrate the deployed length over ``dt`` (s); returns the new length (m).
        ``tension``: the ship-end tension (N); ``robot_speed``: the robot's velocity along the
        cable, away from the ship (m/s; ``"follow"`` mode); ``drum``: the drum element's
        (stiffness N/m, length rate m/s) (``"free"`` mode; None: the explicit law). A step that
        is not a positive number, or a non-finite tension or speed, is a ValueError: it would
        make the length NaN."""
        if not (type(dt) is float and type(tension) is float and type(robot_speed) is float and dt > 0.0
                and math.isfinite(dt + tension + robot_speed)):  # (the checks, for anything else)
            _checks.positive("winch.advance dt", dt, "s")
            tension = _checks.finite("winch.advance tension", tension)
            robot_speed = _checks.finite("winch.advance robot_speed", robot_speed)
        if self.mode == "tension":
            self._tension = tension if self._tension is None else \
                self._tension + min(dt / TENSION_FILTER_S, 1.0) * (tension - self._tension)
            tension = self._tension
            # integral part, clamped to the drum's rate (anti-windup)
            self._integral = _clip(self._integral + dt / TENSION_INTEGRAL_S * self.max_rate * self._band_error(tension),
                                   -self.max_rate, self.max_rate)
        elif self.mode == "follow":
            self._progress = robot_speed if self._progress is None else \
                self._progress + min(dt / FOLLOW_FILTER_S, 1.0) * (robot_speed - self._progress)
        want = self.payout_rate(t, tension, robot_speed, drum, dt)
        # brake in time for the length limits (on a curve a little gentler than max_accel, so the
        # acceleration-limited rate can follow it to zero), then limit the acceleration
        limit = self.accel_limit
        if math.isfinite(limit):
            a_brake = 0.8 * limit
            if want > 0:
                want = min(want, math.sqrt(2.0 * a_brake * max(self.max_length - self.length, 0.0)))
            else:
                want = max(want, -math.sqrt(2.0 * a_brake * max(self.length - self.min_length, 0.0)))
            step = limit * dt
            want = _clip(want, self.current_rate - step, self.current_rate + step)
        self.current_rate = want
        self.length = _clip(self.length + self.current_rate * dt, self.min_length, self.max_length)
        return self.length

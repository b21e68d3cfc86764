"""Heave compensation at the winch: a length offset that cancels the fairlead's vertical motion.

The ship's heave moves the fairlead up and down; a heave-compensated winch pays out as the
fairlead rises and reels in as it falls, so that the line below sees less of the motion. Both
compensators below give a length offset ``length`` (m, > 0 more line deployed) that a runner adds
to the winch's deployed length each step (``BoundTether.set_length``), and the payout rate
(m/s) that moves it there. ``residual`` (m) is the line top's vertical motion left over: the
fairlead's heave minus the offset (for a line hanging straight down from the fairlead, the
motion the line itself sees). Pure Python, no MuJoCo. Frames: world, z up; heave is the
fairlead's height about its mean (m).

* ``ActiveHeaveCompensation``: from the measured fairlead heave z and heave velocity (m, m/s),
  the offset is driven towards ``gain * z_m``, where z_m is the measurement as the drive sees it:
  a pure delay of ``lag_s`` (``lag="delay"``, the default: a sensing and signal latency, the
  sample from ``lag_s`` ago, interpolated linearly between samples; before the first sample, the
  first sample) or a first-order lag of time constant ``lag_s`` (``lag="first_order"``, a
  filtered motion reference unit; integrated exactly for a measurement varying linearly between
  samples). With no limits the offset at each update is the target
  itself (a deadbeat drive: ``update`` at time t sets the offset at t). The drive's payout rate
  is limited to ``max_rate`` (m/s) and changes at most at ``max_accel`` (m/s^2); with an
  acceleration limit the drive follows the target's velocity and closes its position error on a
  braking curve (as ``winch.Winch`` brakes for its length limits), since a deadbeat drive with a
  limited acceleration overshoots (the rate is the smaller of the deadbeat one and the braking
  one, so that a drive on its target stays deadbeat).
* ``PassiveHeaveCompensation``: a spring-damper (stiffness k N/m, damping c N s/m) in series with
  the line at the winch, preloaded to the line's static tension ``preload_N``: its stroke x
  (the offset) obeys k x + c dx/dt = T - preload, with T the line tension at the winch,
  integrated exactly over each step for the tension held through the step (first-order hold
  would need the next tension). In steady state under T = preload + F sin(w t) the stroke's
  amplitude is F / |k + i c w|. The stroke is limited to +-``stroke_m`` / 2.

Units SI.
"""

from __future__ import annotations

import bisect
import math

from mjtether import _checks

LAGS = ("delay", "first_order")
BRAKE = 0.8
"""The part of ``max_accel`` the active drive plans its braking with (so that the acceleration-
limited rate can follow its braking curve)."""


def _clip(x: float, lo: float, hi: float) -> float:
    return min(max(x, lo), hi)


class ActiveHeaveCompensation:
    """An active heave-compensated winch drive (see the module docstring): ``lag_s`` (s) the
    delay or time constant of the measurement, ``lag`` its kind (``"delay"`` or
    ``"first_order"``), ``max_rate`` (m/s) and ``max_accel`` (m/s^2) the drive's limits (inf: none),
    ``gain`` the part of the heave compensated (1: all of it)."""

    def __init__(self, lag_s: float = 0.0, max_rate: float = math.inf, max_accel: float = math.inf,
                 gain: float = 1.0, lag: str = "delay"):
        if lag not in LAGS:
            raise ValueError(f"heave compensation lag must be one of {', '.join(LAGS)}; got {lag!r}")
        self.lag = lag
        self.lag_s = _checks.non_negative("heave compensation lag_s", lag_s, "s")
        self.max_rate = _positive_or_inf("heave compensation max_rate", max_rate, "m/s")
        self.max_accel = _positive_or_inf("heave compensation max_accel", max_accel, "m/s^2")
        self.gain = _checks.in_range("heave compensation gain", gain, 0.0, 2.0)
        self.length = 0.0  # m, the offset added to the deployed length
        self.rate = 0.0  # m/s, the drive's payout rate over the last step
        self.heave = 0.0  # m, the last measured heave (undelayed)
        self._times, self._samples = [], []  # the measurement history ("delay")
        self._filtered = self._raw = None  # (z m, v m/s): lagged, and as last measured ("first_order")
        self._t = -math.inf

    @property
    def residual(self) -> float:
        """The line top's heave left over (m): the last measured heave minus the offset."""
        return self.heave - self.length

    def update(self, t: float, dt: float, measured) -> float:
        """Take the fairlead's measured (heave m, heave velocity m/s) at time ``t`` (s) and move
        the offset over the step ``dt`` (s) since the last update; returns the payout rate (m/s)
        over that step. ``length`` is then the offset at ``t``."""
        try:
            z, v = measured
        except (TypeError, ValueError):
            raise ValueError("heave compensation measured must be (heave m, heave velocity m/s), "
                             f"got {measured!r}") from None
        z = _checks.finite("heave compensation measured heave", z)
        v = _checks.finite("heave compensation measured heave velocity", v)
        dt = _checks.positive("heave compensation dt", dt, "s")
        if not (math.isfinite(t) and t > self._t):
            raise ValueError(f"heave compensation time must be finite and later than {self._t} s, got {t!r}")
        self._t, self.heave = float(t), z
        zm, vm = self._lagged(float(t), dt, z, v)
        error = self.gain * zm - self.length
        want = error / dt  # deadbeat: the offset at t is the target
        if math.isfinite(self.max_accel):  # the target's velocity and a braking curve, never past the target
            brake = self.gain * vm + math.copysign(math.sqrt(2.0 * BRAKE * self.max_accel * abs(error)), error)
            want = min(want, brake) if error >= 0.0 else max(want, brake)
            want = _clip(want, self.rate - self.max_accel * dt, self.rate + self.max_accel * dt)
        self.rate = _clip(want, -self.max_rate, self.max_rate)
        self.length += self.rate * dt
        return self.rate

    def _lagged(self, t: float, dt: float, z: float, v: float) -> tuple[float, float]:
        """The measurement (heave m, velocity m/s) as the drive sees it at ``t``."""
        if self.lag_s == 0.0:
            return z, v
        if self.lag == "first_order":
            if self._filtered is None:
                self._raw = self._filtered = (z, v)
            else:  # exact for a measurement varying linearly through the step (first-order hold)
                e = math.exp(-dt / self.lag_s)
                b = 1.0 - self.lag_s * (1.0 - e) / dt
                self._filtered = tuple(e * f + (1.0 - e) * x0 + b * (x1 - x0)
                                       for f, x0, x1 in zip(self._filtered, self._raw, (z, v)))
                self._raw = (z, v)
            return self._filtered
        self._times.append(t)
        self._samples.append((z, v))
        when = t - self.lag_s
        k = bisect.bisect_right(self._times, when)  # samples [k-1, k] bracket `when`
        if k > 1:  # forget what no later call can need
            del self._times[:k - 1], self._samples[:k - 1]
            k = 1
        if k == 0:
            return self._samples[0]
        t0, t1 = self._times[0], self._times[1]
        (z0, v0), (z1, v1) = self._samples[0], self._samples[1]
        s = (when - t0) / (t1 - t0)
        return z0 + s * (z1 - z0), v0 + s * (v1 - v0)


class PassiveHeaveCompensation:
    """A passive heave compensator (see the module docstring): ``stiffness`` (N/m, > 0),
    ``damping`` (N s/m, >= 0), ``preload_N`` (N, the line tension at which the stroke is 0) and
    ``stroke_m`` (m, the full stroke; inf: unlimited)."""

    def __init__(self, stiffness: float, damping: float = 0.0, preload_N: float = 0.0, stroke_m: float = math.inf):
        self.stiffness = _checks.positive("heave compensation stiffness", stiffness, "N/m")
        self.damping = _checks.non_negative("heave compensation damping", damping, "N s/m")
        self.preload_N = _checks.non_negative("heave compensation preload_N", preload_N, "N")
        self.stroke_m = _positive_or_inf("heave compensation stroke_m", stroke_m, "m")
        self.length = 0.0  # m, the stroke: the offset added to the deployed length
        self.rate = 0.0  # m/s, its rate over the last step
        self.heave = 0.0  # m, the fairlead heave last given (for ``residual``)
        self._t = -math.inf

    @property
    def residual(self) -> float:
        """The line top's heave left over (m): the last given fairlead heave minus the stroke."""
        return self.heave - self.length

    def update(self, t: float, dt: float, tension: float, heave: float = 0.0) -> float:
        """Move the stroke over the step ``dt`` (s) that ends at ``t`` (s) under the line
        tension ``tension`` (N, at the winch), held through the step; ``heave`` (m) the
        fairlead's, for ``residual`` only. Returns the stroke's rate (m/s) over the step;
        ``length`` is then the stroke at ``t``."""
        T = _checks.finite("heave compensation tension", tension)
        self.heave = _checks.finite("heave compensation heave", heave)
        dt = _checks.positive("heave compensation dt", dt, "s")
        if not (math.isfinite(t) and t > self._t):
            raise ValueError(f"heave compensation time must be finite and later than {self._t} s, got {t!r}")
        self._t = float(t)
        x_eq = (T - self.preload_N) / self.stiffness
        if self.damping == 0.0:
            x = x_eq
        else:  # k x + c x' = T - preload, exact for T held over the step
            x = x_eq + (self.length - x_eq) * math.exp(-self.stiffness * dt / self.damping)
        x = _clip(x, -0.5 * self.stroke_m, 0.5 * self.stroke_m)
        self.rate = (x - self.length) / dt
        self.length = x
        return self.rate


def _positive_or_inf(name: str, value, unit: str) -> float:
    """A number > 0, or inf (no limit)."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value == math.inf:
        return math.inf
    return _checks.positive(name, value, unit)

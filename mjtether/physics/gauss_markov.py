"""First-order Gauss-Markov processes, and the slowly varying current that Hong et al. (2020)
drive their USV and UUV with (pure NumPy). ``GaussMarkovCurrent`` is a water column's current
profile (``physics.water.CurrentProfile``, uniform over the depth): a run steps it before each
physics step (``scenario.weather``, from ``[water.current.gauss_markov]``), and every line,
body and vehicle reads the current it gives then.

Hong, Park, Lee, Park and Kim (2020, J. Mar. Sci. Eng. 8, 485), Sec. 2.4.3: "it is common to
model current in marine environment using the first Gauss-Markov process [Fossen]", with the
current's speed V_c and direction beta in the earth-fixed frame (their Fig. 5) and its body-frame
components (their Eq. 10)

    u_c = V_c cos(beta - psi),    v_c = V_c sin(beta - psi).

They print no equation of the process itself; it is Fossen's (Handbook of Marine Craft
Hydrodynamics and Motion Control, Wiley 2011, Sec. 8.3):

    V_c' + mu V_c = w,    V_min <= V_c(t) <= V_max,

w zero-mean Gaussian white noise, mu >= 0 (mu = 0: a random walk), the speed held in its band by
a saturating element; the direction may be simulated the same way. Here each of speed and
direction is one such process about its own mean m (x' + mu (x - m) = w; Fossen's form is
m = 0), with noise of intensity sigma^2 (E[w(t) w(s)] = sigma^2 delta(t - s)). Between samples
dt apart it is stepped exactly (the Ornstein-Uhlenbeck transition, so that its statistics do not
depend on dt, unlike an Euler step):

    x_{k+1} = m + (x_k - m) e^{-mu dt} + sqrt(sigma^2 (1 - e^{-2 mu dt}) / (2 mu)) n_k,

n_k standard normal, then clipped to [lower, upper] (Fossen's saturation, applied to the state).
Unsaturated and with mu > 0 it is stationary with mean m, variance sigma^2 / (2 mu) and
autocorrelation e^{-mu tau} at lag tau (``stationary_variance``, ``autocorrelation``).

Frames: world, z up, heading and direction measured from +x towards +y (rad); the current
flows towards its direction (the water column's convention). The body frame of ``in_body`` is
x forward, y to port (Eq. 10 reads the same in it as in Fossen's x forward, y starboard frame
with angles clockwise). Units SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mjtether import _checks
from mjtether.physics.water import CurrentProfile

NOISE_BLOCK = 1024
"""How many pairs of normal deviates a current draws from its generator at a time (the stream,
and so every run from one seed, does not depend on it)."""


def stationary_variance(mu: float, sigma: float) -> float:
    """Variance sigma^2 / (2 mu) of the unsaturated process x' + mu (x - m) = w once its start
    is forgotten (mu > 0, 1/s; sigma: noise intensity, unit/sqrt(s)); its mean is m."""
    return _checks.non_negative("sigma", sigma) ** 2 / (2.0 * _checks.positive("mu", mu, "1/s"))


def autocorrelation(mu: float, lag) -> np.ndarray:
    """Correlation e^{-mu |lag|} of the stationary unsaturated process between times ``lag`` (s)
    apart."""
    return np.exp(-_checks.positive("mu", mu, "1/s") * np.abs(np.asarray(lag, dtype=float)))


def _bound(name: str, value) -> float:
    """A saturation bound: a number, +-inf meaning none."""
    try:
        ok = not isinstance(value, (str, bytes, bool)) and not math.isnan(float(value))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"{name} must be a number (+-inf for no bound), got {value!r}")
    return float(value)


@dataclass(frozen=True)
class GaussMarkov:
    """One scalar first-order Gauss-Markov process x' + mu (x - mean) = w held in
    [lower, upper]: ``mean`` (unit of x), ``mu`` (1/s, >= 0), ``sigma`` (noise intensity,
    unit/sqrt(s), >= 0); ``name`` names it in errors."""

    mean: float = 0.0
    mu: float = 0.0
    sigma: float = 0.0
    lower: float = -math.inf
    upper: float = math.inf
    name: str = "process"

    def __post_init__(self):
        _checks.finite(f"{self.name}.mean", self.mean)
        _checks.non_negative(f"{self.name}.mu", self.mu, "1/s")
        _checks.non_negative(f"{self.name}.sigma", self.sigma)
        for key in ("lower", "upper"):
            _bound(f"{self.name}.{key}", getattr(self, key))
        if not float(self.lower) <= float(self.mean) <= float(self.upper):
            raise ValueError(f"{self.name}: its mean {self.mean!r} must lie in [lower, upper] = "
                             f"[{self.lower!r}, {self.upper!r}]")

    def decay(self, dt: float) -> float:
        """e^{-mu dt}: how much of its distance from the mean one step of ``dt`` (s) keeps."""
        return math.exp(-self.mu * dt)

    def spread(self, dt: float) -> float:
        """Standard deviation of one exact step of ``dt`` (s) from a known state:
        sqrt(sigma^2 (1 - e^{-2 mu dt}) / (2 mu)), sigma sqrt(dt) at mu = 0."""
        if self.mu == 0.0:
            return self.sigma * math.sqrt(dt)
        return self.sigma * math.sqrt(-math.expm1(-2.0 * self.mu * dt) / (2.0 * self.mu))

    def advance(self, x: float, dt: float, n: float) -> float:
        """The state ``dt`` (s) after ``x``, on the standard normal deviate ``n``, saturated."""
        x = self.mean + (x - self.mean) * self.decay(dt) + self.spread(dt) * n
        return min(max(x, self.lower), self.upper)


class GaussMarkovCurrent(CurrentProfile):
    """A depth-uniform current whose speed (m/s) and direction (rad) are two first-order
    Gauss-Markov processes (module docstring), reproducible from ``seed``.

    Speed: about ``mean_speed`` (m/s) with rate ``mu`` (1/s) and noise intensity ``sigma``
    (m/s/sqrt(s)), held in [``v_min``, ``v_max``] (m/s, v_min >= 0). Direction: about
    ``heading`` (rad, from +x towards +y, the way the water flows) with ``heading_mu`` (1/s) and
    ``heading_sigma`` (rad/sqrt(s)), held in [``heading_min``, ``heading_max``]; the defaults
    (no noise) keep it constant. Both start at their means; ``step(dt)`` advances them by one
    exact step, ``reset()`` starts again from the seed. As a ``CurrentProfile`` it gives its
    present velocity at every height (``__call__``, ``speed_at``)."""

    def __init__(self, mean_speed: float = 0.0, mu: float = 0.0, sigma: float = 0.0,
                 v_min: float = 0.0, v_max: float = math.inf, heading: float = 0.0,
                 heading_mu: float = 0.0, heading_sigma: float = 0.0,
                 heading_min: float = -math.inf, heading_max: float = math.inf, seed: int = 0):
        _checks.non_negative("current.v_min", v_min, "m/s")
        self.speed_process = GaussMarkov(mean_speed, mu, sigma, v_min, v_max, "current.speed")
        self.heading_process = GaussMarkov(heading, heading_mu, heading_sigma, heading_min,
                                           heading_max, "current.heading")
        self.seed = _checks.positive_int("current.seed", seed, minimum=0)
        self.reset()

    def reset(self) -> None:
        """Back to time 0, both processes at their means, the noise stream at the seed's start."""
        self.time = 0.0
        self.speed = float(self.speed_process.mean)
        self.heading = float(self.heading_process.mean)
        self._rng = np.random.default_rng(self.seed)
        self._noise = np.empty((0, 2))
        self._next = 0

    def step(self, dt: float) -> np.ndarray:
        """Advance speed and direction by ``dt`` (s, > 0); returns the new ``velocity()``."""
        dt = _checks.positive("dt", dt, "s")
        if self._next == len(self._noise):
            self._noise, self._next = self._rng.standard_normal((NOISE_BLOCK, 2)), 0
        n_speed, n_heading = self._noise[self._next]
        self._next += 1
        self.speed = self.speed_process.advance(self.speed, dt, n_speed)
        self.heading = self.heading_process.advance(self.heading, dt, n_heading)
        self.time += dt
        return self.velocity()

    def series(self, steps: int, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """(speed m/s, direction rad), each of shape (steps,): the states after each of the next
        ``steps`` steps of ``dt`` (s); the same as that many ``step(dt)`` calls."""
        steps = _checks.positive_int("steps", steps)
        out = np.empty((steps, 2))
        for k in range(steps):
            self.step(dt)
            out[k] = self.speed, self.heading
        return out[:, 0], out[:, 1]

    def speed_at(self, z) -> np.ndarray:
        """The present speed (m/s) at every height ``z`` (m): the current is uniform over the depth."""
        return np.full(np.shape(z), float(self.speed))

    def max_speed(self, depth: float) -> float:
        """The largest speed (m/s) to plan a time step for: v_max, or, for a stationary process
        (mu > 0), the mean plus 5 stationary standard deviations if that is lower (exceeded with
        probability 3e-7 by one sample of the unsaturated process)."""
        p = self.speed_process
        top = float(p.upper)
        if p.mu > 0.0:
            top = min(top, p.mean + 5.0 * math.sqrt(stationary_variance(p.mu, p.sigma)))
        return max(top, self.speed)

    def velocity(self) -> np.ndarray:
        """The current now (m/s, world, shape (3,)): speed (cos dir, sin dir, 0)."""
        return np.array([self.speed * math.cos(self.heading), self.speed * math.sin(self.heading), 0.0])

    def in_body(self, psi: float) -> np.ndarray:
        """Hong et al.'s Eq. 10: the current (m/s, shape (2,)) in the frame of a craft of heading
        ``psi`` (rad), x forward, y to port: V_c (cos(beta - psi), sin(beta - psi))."""
        a = self.heading - _checks.finite("psi", psi)
        return np.array([self.speed * math.cos(a), self.speed * math.sin(a)])

"""Linear (Airy) surface waves: regular waves, JONSWAP and Pierson-Moskowitz seas, and the
particle kinematics that Morison's equation needs (the runs' lines, bodies and ship take them
through ``physics.water.WaterColumn.waves``), and the sea's build-up ramp. ``WaveField.state``
runs a compiled twin (``state_kernel``) where the compiled kernels run (``compiled.backend()``);
its NumPy code, ``WaveField.reference_state``, is the reference (``MJTETHER_KERNELS=numpy``).

Frame and units: world, z up, mean water line z = 0, seabed z = -depth; SI throughout
(m, s, rad). A wave's heading is the direction it travels *towards*, measured from +x towards
+y (the current's convention, ``mjtether.physics.water``; OrcaFlex's wave direction is the
direction of propagation too: a heading of 0 travels along +x).

A sea is a sum of linear components (``WaveComponents``),

    eta(x, y, t) = sum_i a_i cos(k_i (x cos b_i + y sin b_i) - omega_i t + phase_i),

each obeying the finite-depth dispersion relation omega^2 = g k tanh(k h). Under component i
the particle velocity at height z (Airy, e.g. DNV-RP-C205 (2021) Table 3-1) is

    u_h = a omega cosh(k (z + h)) / sinh(k h) cos(theta)    along (cos b, sin b),
    u_z = a omega sinh(k (z + h)) / sinh(k h) sin(theta),

and the local acceleration du/dt (not the convective part) is the time derivative of these at
a fixed point: a omega^2 cosh(...)/sinh(kh) sin(theta) horizontally, -a omega^2 sinh(...)/sinh(kh)
cos(theta) vertically. The profiles are evaluated as exponentials, stable for any k h
(``depth = math.inf`` is deep water: the profile is exp(k z)).

Stretching: linear theory holds up to z = 0. ``WaveField`` uses Wheeler stretching by default:
a point at z under the instantaneous surface eta takes the linear kinematics of
z' = h (z - eta) / (h + eta) (z' = z - eta in deep water), so the free surface sees the
linear value at z = 0 and the seabed its value at -h; points above the instantaneous surface
get zero. Wheeler was chosen because it keeps the velocity under a crest bounded (linear
extrapolation above z = 0 grows as exp(k z)) and ends the kinematics at the surface that the
wet fraction and buoyancy will follow; the time derivative of z' (second order in steepness)
is left out of the acceleration, as is usual. ``stretching="none"``: linear kinematics at z,
zero above z = 0.

Irregular seas (``jonswap``, ``pierson_moskowitz``) by the random-phase method: the band
[band[0], band[1]] x omega_p is cut into equal frequency bins; each component carries the
spectrum's energy in its bin (integrated by Gauss-Legendre, so the realisation's variance
is the spectrum's, to the band's truncation), a phase uniform in [0, 2 pi) and a frequency
drawn uniformly inside its bin. Fixed bin centres would make the sea repeat every
2 pi / d_omega (about 10 minutes with 100 bins at Tp = 10 s, well within a 3-hour sea); the
drawn frequencies are incommensurate, so it does not repeat. Both draws come from
``numpy.random.default_rng(seed)``: a seed gives the same sea on any machine.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mjtether import _checks
from mjtether.physics import compiled
from mjtether.physics.compiled import jit

_DEEP_KH = 40.0
"""k h beyond which tanh(k h) is 1 to double precision: the deep-water root k = omega^2/g."""


def _depth_arg(depth) -> float:
    """The water depth (m): a number > 0, or ``math.inf`` for deep water."""
    if isinstance(depth, (float, np.floating)) and depth == math.inf:
        return math.inf
    return _checks.number("depth", depth, 0.0, math.inf, "m", above=True)


def _gravity_arg(g) -> float:
    return _checks.number("g", g, 0.1, 100.0, "m/s^2")


def wavenumber(omega, depth, g=9.81):
    """The wavenumber k (rad/m) of angular frequency ``omega`` (rad/s, >= 0; array or scalar)
    in water of ``depth`` (m, or ``math.inf``) under gravity ``g`` (m/s^2): the root of
    omega^2 = g k tanh(k h).

    Newton's method on y = k h from Fenton & McKee's (1990) explicit estimate (1.7e-3 relative),
    iterated until the step is below 1e-15 of y (three or four steps); k h > 40 takes the
    deep-water root omega^2/g, exact there to double precision. ``omega = 0`` gives 0."""
    h, g = _depth_arg(depth), _gravity_arg(g)
    w = np.asarray(omega, dtype=float)
    if w.size and not (np.all(np.isfinite(w)) and np.all(w >= 0.0)):
        raise ValueError("omega must be finite numbers >= 0 rad/s")
    deep = w * w / g
    if h == math.inf:
        return deep[()]
    x = deep * h
    with np.errstate(divide="ignore", invalid="ignore"):
        y = x / np.tanh(x ** 0.75) ** (2.0 / 3.0)
    y = np.where(x > _DEEP_KH, x, np.where(x > 0.0, y, 0.0))
    for _ in range(8):
        t = np.tanh(y)
        step = (y * t - x) / np.where(y > 0.0, t + y * (1.0 - t * t), 1.0)
        y = y - step
        if np.all(np.abs(step) <= 1e-15 * y):
            break
    return (y / h)[()]


@dataclass(frozen=True)
class WaveComponents:
    """Linear wave components, equal-length 1-D arrays: ``amplitude`` a (m, >= 0), ``omega``
    (rad/s, > 0), ``k`` wavenumber (rad/m, > 0), ``heading`` b (rad, the direction the
    component travels towards, from +x towards +y) and ``phase`` (rad). The surface is

        eta(x, y, t) = sum_i a_i cos(k_i (x cos b_i + y sin b_i) - omega_i t + phase_i)

    (a crest of a component with phase 0 passes x = y = 0 at t = 0), written out as OrcaFlex
    and MoorDyn state theirs: heading is the direction of propagation, anticlockwise from +x
    seen from above; check a tool's phase sign (lead or lag) before exchanging phases with it."""

    amplitude: np.ndarray
    omega: np.ndarray
    k: np.ndarray
    heading: np.ndarray
    phase: np.ndarray

    def __post_init__(self):
        units = {"amplitude": "m", "omega": "rad/s", "k": "rad/m", "heading": "rad", "phase": "rad"}
        size = np.size(self.amplitude)
        for name, unit in units.items():
            v = np.array(getattr(self, name), dtype=float)
            if v.ndim != 1 or not v.size or v.size != size:
                raise ValueError(f"WaveComponents.{name} must be a 1-D array of one or more numbers ({unit}), "
                                 f"as long as amplitude ({size}); got shape {v.shape}")
            if not np.all(np.isfinite(v)):
                raise ValueError(f"WaveComponents.{name} must be finite numbers ({unit})")
            if name == "amplitude" and np.any(v < 0.0):
                raise ValueError("WaveComponents.amplitude must be >= 0 m")
            if name in ("omega", "k") and np.any(v <= 0.0):
                raise ValueError(f"WaveComponents.{name} must be > 0 {unit}")
            v.setflags(write=False)
            object.__setattr__(self, name, v)

    def __len__(self) -> int:
        return int(self.amplitude.size)

    @property
    def variance(self) -> float:
        """The sea's elevation variance m0 = sum a_i^2 / 2 (m^2); Hs = 4 sqrt(m0)."""
        return float(0.5 * np.sum(self.amplitude ** 2))


def regular(height, period, heading=0.0, depth=math.inf, g=9.81, phase=0.0) -> WaveComponents:
    """One regular Airy wave: crest-to-trough ``height`` (m, >= 0), ``period`` (s, > 0),
    ``heading`` (rad, direction of travel from +x towards +y), ``phase`` (rad, the convention
    of ``WaveComponents``), in water of ``depth`` (m, or ``math.inf``)."""
    h = _checks.number("height", height, 0.0, 1e3, "m")
    t = _checks.number("period", period, 0.0, 1e3, "s", above=True)
    b = _checks.number("heading", heading, unit="rad")
    p = _checks.number("phase", phase, unit="rad")
    w = 2.0 * math.pi / t
    return WaveComponents([h / 2.0], [w], [wavenumber(w, depth, g)], [b], [p])


def jonswap_spectrum(omega, hs, tp, gamma=3.3):
    """The JONSWAP spectrum S(omega) (m^2 s/rad) as DNV-RP-C205 (2021) Sec. 3.5.5 writes it:

        S(w) = A_gamma (5/16) Hs^2 wp^4 w^-5 exp(-5/4 (w/wp)^-4) gamma^exp(-(w - wp)^2 / (2 s^2 wp^2)),

    wp = 2 pi / Tp, s = 0.07 for w <= wp and 0.09 above, A_gamma = 1 - 0.287 ln(gamma) (an
    approximate normalisation: the integral is Hs^2/16 exactly only at gamma = 1, the
    Pierson-Moskowitz spectrum). ``omega`` rad/s (array or scalar; 0 where <= 0), ``hs`` m,
    ``tp`` s, ``gamma`` in [1, 7]."""
    hs = _checks.number("hs", hs, 0.0, 100.0, "m", above=True)
    tp = _checks.number("tp", tp, 0.0, 100.0, "s", above=True)
    gamma = _checks.number("gamma", gamma, 1.0, 7.0)
    w = np.asarray(omega, dtype=float)
    wp = 2.0 * math.pi / tp
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        r = wp / w
        pm = 5.0 / 16.0 * hs * hs / wp * r ** 5 * np.exp(-1.25 * r ** 4)
        sigma = np.where(w <= wp, 0.07, 0.09)
        peak = gamma ** np.exp(-0.5 * ((w - wp) / (sigma * wp)) ** 2)
        s = (1.0 - 0.287 * math.log(gamma)) * pm * peak
    return np.where(w > 0.0, s, 0.0)[()]


_GAUSS = np.polynomial.legendre.leggauss(8)


def _bin_integrals(f, edges) -> np.ndarray:
    """The integral of ``f`` over each interval [edges[i], edges[i+1]] (8-point Gauss-Legendre)."""
    x, wts = _GAUSS
    lo, hi = edges[:-1, None], edges[1:, None]
    return (f(0.5 * (hi - lo) * x + 0.5 * (hi + lo)) @ wts) * 0.5 * (hi - lo)[:, 0]


def jonswap(hs, tp, gamma=3.3, heading=0.0, depth=math.inf, g=9.81, *, seed, n_components=100,
            spreading_s=None, n_directions=None, band=(0.5, 5.0)) -> WaveComponents:
    """An irregular sea from the JONSWAP spectrum (``jonswap_spectrum``): significant wave
    height ``hs`` (m), peak period ``tp`` (s), peak enhancement ``gamma`` in [1, 7], mean
    ``heading`` (rad, direction of travel), ``depth`` (m or ``math.inf``), ``g`` (m/s^2).

    ``seed``: an integer >= 0 (required: a sea state must be reproducible). ``n_components``
    equal frequency bins in [1, 2000] over ``band`` = (low, high) multiples of the peak frequency
    (default 0.5 to 5: the part of the Pierson-Moskowitz energy outside it is
    exp(-20) below and 1 - exp(-1.25 / 5^4) = 0.2 % above; the realisation is not rescaled to
    make up for it). Random phases and in-bin frequencies, as the module docstring says.

    ``spreading_s``: None for a long-crested sea, or s in (0, 1000] for cos-2s spreading,
    D(b) proportional to cos^(2s)((b - heading) / 2) on |b - heading| <= pi. Directions are cut
    into ``n_directions`` (default 9, in [1, 361]) equal bins centred on the heading; each
    frequency bin then holds one component per direction bin (n_components x n_directions in
    all, ordered frequency-major), with the bin's energy times that direction bin's share of D,
    and each with its own frequency drawn in the bin, so no two components are phase-locked."""
    hs = _checks.number("hs", hs, 0.0, 100.0, "m", above=True)
    tp = _checks.number("tp", tp, 0.0, 100.0, "s", above=True)
    gamma = _checks.number("gamma", gamma, 1.0, 7.0)
    heading = _checks.number("heading", heading, unit="rad")
    depth, g = _depth_arg(depth), _gravity_arg(g)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed = {seed!r}: must be an integer >= 0 (a sea state must be reproducible)")
    n = _count("n_components", n_components, 2000)
    if spreading_s is None:
        if n_directions is not None:
            raise ValueError(f"n_directions = {n_directions!r}: needs spreading_s (a long-crested sea has one "
                             "direction)")
        offsets, share = np.zeros(1), np.ones(1)
    else:
        s = _checks.number("spreading_s", spreading_s, 0.0, 1000.0, above=True)
        nd = _count("n_directions", 9 if n_directions is None else n_directions, 361)
        step = 2.0 * math.pi / nd
        offsets = (np.arange(nd) - 0.5 * (nd - 1)) * step
        share = _bin_integrals(lambda b: np.cos(0.5 * b) ** (2.0 * s), np.append(offsets - 0.5 * step,
                                                                                   offsets[-1] + 0.5 * step))
        share = share / share.sum()
    lo, hi = _checks.numbers("band", band, 0.0, 100.0, count=(2,), above=True)
    if not lo < hi:
        raise ValueError(f"band = {band!r}: the low multiple of the peak frequency must be below the high one")
    wp = 2.0 * math.pi / tp
    edges = np.linspace(lo * wp, hi * wp, n + 1)
    energy = _bin_integrals(lambda w: jonswap_spectrum(w, hs, tp, gamma), edges)
    rng = np.random.default_rng(int(seed))
    shape = (n, offsets.size)
    omega = edges[:-1, None] + rng.random(shape) * (edges[1] - edges[0])
    phase = rng.random(shape) * (2.0 * math.pi)
    amplitude = np.sqrt(2.0 * energy[:, None] * share[None, :])
    return WaveComponents(amplitude.ravel(), omega.ravel(), wavenumber(omega.ravel(), depth, g),
                          np.broadcast_to(heading + offsets, shape).ravel(), phase.ravel())


def pierson_moskowitz(hs, tp, heading=0.0, depth=math.inf, g=9.81, **kwargs) -> WaveComponents:
    """An irregular sea from the Pierson-Moskowitz spectrum: ``jonswap`` with gamma = 1 (the
    same keywords: ``seed``, ``n_components``, ``spreading_s``, ``n_directions``, ``band``)."""
    return jonswap(hs, tp, 1.0, heading, depth, g, **kwargs)


def _count(name: str, value, most: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 1 <= value <= most:
        raise ValueError(f"{name} = {value!r}: must be an integer in [1, {most}]")
    return int(value)


_COS = tuple((-1.0) ** n / math.factorial(2 * n) for n in range(7))  # cos x = sum C_n x^2n, to x^12
_SIN = tuple((-1.0) ** n / math.factorial(2 * n + 1) for n in range(7))  # sin x = x sum S_n x^2n


def _sincos(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(sin theta, cos theta) of a float64 array, to about 1e-15 absolute after reducing theta to
    [-pi, pi] (the reduction costs |theta| x 2e-16): Taylor series of theta / 8 (|x| <= pi / 8, the
    first term dropped is below 3e-17) and three angle doublings, in place. NumPy's float64
    ``sin`` and ``cos`` are scalar code here (measured 16 ns an element each, against 2 ns for a
    multiply); this costs about 40 passes of multiplies and adds, 5 to 6 times less."""
    x = np.rint(theta * (0.5 / math.pi))
    x *= -2.0 * math.pi
    x += theta
    x *= 0.125
    x2 = x * x
    c, s = x2 * _COS[-1], x2 * _SIN[-1]
    for cn, sn in zip(_COS[-2:0:-1], _SIN[-2:0:-1]):
        c += cn
        c *= x2
        s += sn
        s *= x2
    c += 1.0
    s += 1.0
    s *= x
    for _ in range(3):  # sin 2x = 2 sin x cos x, cos 2x = 1 - 2 sin^2 x
        c2 = s * s
        c2 *= -2.0
        c2 += 1.0
        s *= c
        s *= 2.0
        c = c2
    return s, c


def build_up(t, duration: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The sea's build-up ramp at time(s) ``t`` (s) and its first and second time derivatives
    (1/s, 1/s^2): r = (1 - cos(pi t / duration)) / 2 from t = 0 to ``duration`` (s), 1 after
    (0 before); ``duration`` 0: no ramp (r = 1 from t = 0). A half-cosine, so that the motion it
    multiplies starts from rest with no jump in position or velocity (OrcaFlex's build-up stage
    ramps its waves and vessel motions the same way)."""
    t = np.asarray(t, dtype=float)
    if duration <= 0.0:
        one = np.ones_like(t)
        return one, 0.0 * one, 0.0 * one
    w = math.pi / duration
    inside = (t > 0.0) & (t < duration)
    phase = w * np.clip(t, 0.0, duration)
    r = np.where(t >= duration, 1.0, np.where(inside, 0.5 * (1.0 - np.cos(phase)), 0.0))
    return r, np.where(inside, 0.5 * w * np.sin(phase), 0.0), np.where(inside, 0.5 * w * w * np.cos(phase), 0.0)


class WaveField:
    """The surface and the particle kinematics of a sum of linear components in water of
    ``depth`` (m, or ``math.inf``) under ``g`` (m/s^2). ``stretching``: ``"wheeler"`` (default)
    or ``"none"`` (the module docstring says what each does). The components' wavenumbers
    must obey the dispersion relation at this depth (build them with the same depth).
    ``ramp_s``: the sea's build-up (s, ``build_up``): the elevation and velocity are the
    linear sea's times r(t), the acceleration the time derivative of that (r du/dt + r' u);
    0 (the default): the full sea from t = 0.

    The NumPy reference is vectorised over points and components: one (N, M) array per step of
    the kernel, no Python loop. Measured (2026-12-02, 2 shared cores under load, best of 7 x 300):
    ``kinematics`` of 200 points x 100 components 310-370 us (Wheeler), 270-290 us ("none"),
    of which ``_sincos`` is 130 us (NumPy's sin and cos would be 500 us); ``elevation`` of one
    point 10-12 us. The compiled twin (``compiled``: True where it runs): 200 points x 100
    components 52 us on an Intel Xeon (76 us without fused multiply-adds; the sines and cosines
    29 us, the profiles 23 us), one point 5 us (``scripts/bench_waves.py``); it keeps no state
    between calls."""

    STRETCHINGS = ("wheeler", "none")

    def __init__(self, components: WaveComponents, depth=math.inf, g=9.81, stretching: str = "wheeler",
                 ramp_s: float = 0.0):
        if not isinstance(components, WaveComponents):
            raise ValueError(f"components must be WaveComponents (from regular, jonswap, ...), got "
                             f"{type(components).__name__}")
        if stretching not in self.STRETCHINGS:
            raise ValueError(f"stretching = {stretching!r}: must be one of {', '.join(self.STRETCHINGS)}")
        h, g = _depth_arg(depth), _gravity_arg(g)
        c = components
        kh = c.k * h if h != math.inf else np.full(len(c), math.inf)
        residual = c.omega ** 2 - g * c.k * np.tanh(kh)
        if np.any(np.abs(residual) > 1e-9 * c.omega ** 2):
            raise ValueError(f"components: their k do not obey omega^2 = g k tanh(k h) at depth {h:g} m, "
                             f"g {g:g} m/s^2; build them with the same depth and g")
        self.components, self.depth, self.g, self.stretching = c, h, g, stretching
        self.ramp_s = _checks.non_negative("ramp_s", ramp_s, "s")
        self._kxy = np.stack([c.k * np.cos(c.heading), c.k * np.sin(c.heading)])  # (2, M) rad/m
        self._q = np.where(kh < 350.0, np.exp(-np.minimum(kh, 350.0) * 2.0), 0.0)  # exp(-2 k h), the
        # seabed's image term of the profiles (0 where it would be a subnormal number: those are slow)
        scale = c.amplitude * c.omega / -np.expm1(-2.0 * kh)  # a omega / (1 - exp(-2 k h))
        cos_b, sin_b = np.cos(c.heading), np.sin(c.heading)
        self._w_h = np.stack([scale * cos_b, scale * sin_b], axis=1)  # (M, 2)
        self._w_z = scale
        self._w_h2 = self._w_h * c.omega[:, None]  # the accelerations' weights, a omega^2 / (1 - q)
        self._w_z2 = scale * c.omega
        # the compiled twin (``state_kernel``), where the compiled kernels run: its per-component rows
        self.compiled = compiled.backend() == "numba"
        self._table = np.ascontiguousarray(np.stack([self._kxy[0], self._kxy[1], c.phase, c.omega, c.amplitude, c.k,
                                                     self._q, *self._w_h.T, self._w_z, *self._w_h2.T, self._w_z2]))

    def _theta(self, xy: np.ndarray, t: float) -> np.ndarray:
        """The phases theta (N, M) of the components at horizontal positions ``xy`` (N, 2) and
        time ``t``; the time part is reduced modulo 2 pi per component first (omega t reaches
        1e4 rad in a 3-hour sea)."""
        c = self.components
        return xy @ self._kxy + np.remainder(c.phase - c.omega * t, 2.0 * math.pi)

    def elevation(self, x, y, t):
        """The surface elevation eta (m, from the mean water line) at horizontal positions
        ``x``, ``y`` (m, world) and times ``t`` (s): arrays broadcast together (a float for
        scalars)."""
        c = self.components
        if np.ndim(x) == np.ndim(y) == np.ndim(t) == 0 and self.compiled:  # (the compiled twin, surface only)
            eta, p = np.empty(1), np.array([[x, y, 0.0]], dtype=float)
            state_kernel(p, _checks.finite("t", t), self._table, self.depth, False, self.ramp_s, eta, p, p, False)
            return float(eta[0])
        if np.ndim(x) == np.ndim(y) == np.ndim(t) == 0:  # one point, one time: (M,) arrays only
            theta = self._theta(np.array([[x, y]], dtype=float), float(t))[0]
            eta = float(np.cos(theta) @ c.amplitude)
            return eta if self.ramp_s == 0.0 or t >= self.ramp_s else eta * float(build_up(t, self.ramp_s)[0])
        x, y, t = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float),
                                      np.asarray(t, dtype=float))
        theta = x[..., None] * self._kxy[0] + y[..., None] * self._kxy[1] - t[..., None] * c.omega + c.phase
        eta = np.cos(theta) @ c.amplitude
        return (eta if self.ramp_s == 0.0 else eta * build_up(t, self.ramp_s)[0])[()]

    def kinematics(self, points, t) -> tuple[np.ndarray, np.ndarray]:
        """(velocity (N, 3) m/s, acceleration (N, 3) m/s^2) of the water at ``points`` (N, 3),
        world m, at time ``t`` (s): the Airy particle velocity and local acceleration du/dt,
        stretched as ``stretching`` says; zero above the (instantaneous, for Wheeler) surface."""
        _, velocity, acceleration = self.state(points, t)
        return velocity, acceleration

    def state(self, points, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(elevation (N,) m, velocity (N, 3) m/s, acceleration (N, 3) m/s^2) at ``points``
        (N, 3), world m, at time ``t`` (s): ``elevation`` of each point's (x, y) and
        ``kinematics``, from one evaluation of the phases. By the compiled twin
        (``state_kernel``) where the compiled kernels run (``compiled``), else by
        ``reference_state``: the same numbers to 1e-12 of the largest value."""
        if not self.compiled:
            return self.reference_state(points, t)
        p = _points_arg(points)
        t = _checks.finite("t", t)
        eta, vel, acc = np.empty(p.shape[0]), np.empty(p.shape), np.empty(p.shape)
        state_kernel(p, t, self._table, self.depth, self.stretching == "wheeler", self.ramp_s, eta, vel, acc, True)
        return eta, vel, acc

    def reference_state(self, points, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``state`` in NumPy, the reference that states the physics (``MJTETHER_KERNELS=numpy``
        runs it): one (N, M) array per step, no Python loop."""
        p = _points_arg(points)
        t = _checks.finite("t", t)
        sin, cos = _sincos(self._theta(p[:, :2], t))
        eta = cos @ self.components.amplitude
        r = dr = None
        if t < self.ramp_s:  # (the build-up: the surface r eta, the kinematics under it r u)
            r, dr, _ = (float(v) for v in build_up(t, self.ramp_s))
            eta = r * eta
        z, h = p[:, 2], self.depth
        if self.stretching == "wheeler":
            wet = z <= eta
            zs = z - eta if h == math.inf else h * (z - eta) / (h + eta)
        else:
            wet = z <= 0.0
            zs = z
        zs = np.clip(zs, -h, 0.0)
        kz = np.maximum(zs[:, None] * self.components.k, -350.0)  # exp(-350): below any profile's reach
        e1 = np.exp(kz)  # exp(k z')
        e2 = self._q / e1  # exp(-k (z' + 2 h))
        ch, sh = e1 + e2, e1 - e2  # cosh(k (z' + h)), sinh(k (z' + h)) times 2 exp(-k h)
        velocity = np.empty((p.shape[0], 3))
        acceleration = np.empty((p.shape[0], 3))
        velocity[:, :2] = (ch * cos) @ self._w_h
        velocity[:, 2] = (sh * sin) @ self._w_z
        acceleration[:, :2] = (ch * sin) @ self._w_h2
        acceleration[:, 2] = -((sh * cos) @ self._w_z2)
        if r is not None:  # d(r u)/dt = r du/dt + r' u
            acceleration *= r
            acceleration += dr * velocity
            velocity *= r
        velocity[~wet] = 0.0
        acceleration[~wet] = 0.0
        return eta, velocity, acceleration


def _points_arg(points) -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3:
        raise ValueError(f"points must be an (N, 3) array of world positions (m), got shape {p.shape}")
    return p


_BLOCK = 32
"""Points per block of ``state_kernel``: its (M, 32) work arrays stay in the core's caches."""
_DEEP = 40.0
"""``state_kernel`` leaves out a component's kinematics over a block of points all below its
reach, k z' < -40 (exp(-40) = 4e-18 of its value at the surface)."""
_LOG2E, _LN2_HI, _LN2_LO = 1.0 / math.log(2.0), 6.93147180369123816490e-01, 1.90821492927058770002e-10
_E2, _E3, _E4, _E5, _E6, _E7, _E8, _E9, _E10, _E11, _E12, _E13 = (1.0 / math.factorial(n) for n in range(2, 14))
# (exp r = sum r^n / n! to r^13, |r| <= ln 2 / 2; the series of _sincos as numbers the kernel's loops inline)
_C1, _C2, _C3, _C4, _C5, _C6 = _COS[1:]
_S1, _S2, _S3, _S4, _S5, _S6 = _SIN[1:]


@jit
def _time_phases(phase, omega, t):
    """The time part of the phases, phase - omega t reduced modulo 2 pi (``WaveField._theta``), as
    NumPy rounds it: omega t is rounded before the subtraction (not fused with it, as
    ``state_kernel``'s ``fma`` would: at t = 3 h, omega t ~ 4e4 rad, whose rounding is 4e-12 rad)."""
    tk = np.empty(phase.shape[0])
    for i in range(phase.shape[0]):
        tk[i] = (phase[i] - omega[i] * t) % (2.0 * math.pi)
    return tk


@jit(fma=True)
def state_kernel(p, t, table, depth, wheeler, ramp_s, eta, vel, acc, kinematics):
    """``WaveField.reference_state`` compiled, into ``eta`` (N,), ``vel`` and ``acc`` (N, 3)
    (only ``eta`` where ``kinematics`` is False; Wheeler stretching where ``wheeler``); ``table``
    (13, M): the components' kx, ky (rad/m), phase (rad), omega (rad/s), amplitude (m), k (rad/m),
    exp(-2 k h), then the velocity's and the acceleration's weights (``WaveField.__init__``).

    The same expressions in the same order but for the sums over components (sequential here),
    fused multiply-adds (``compiled.jit``'s ``fma``: each a * b + c rounded once; the time part
    of the phases is not fused, ``_time_phases``) and two left-out terms: a component whose k z'
    is below -40 over a whole block of points (4e-18 of its surface value; the reference clips
    k z' at -350), and exp evaluated as 2^n times a Taylor series to r^13 (|r| <= ln 2 / 2:
    4e-18 relative), so that the loops over a block's points vectorise (the sine and cosine are
    the reference's ``_sincos``, written out). Measured against the reference: 2e-14 of the
    largest value (1.5e-15 unfused), in a third less time."""
    n, m = p.shape[0], table.shape[1]
    kx, ky, phase, omega, amp, kk, qq = table[0], table[1], table[2], table[3], table[4], table[5], table[6]
    two_pi = 2.0 * math.pi
    r, dr = 1.0, 0.0
    ramped = ramp_s > 0.0 and t < ramp_s
    if ramped:  # (build_up)
        w = math.pi / ramp_s
        inside = 0.0 < t
        r = 0.5 * (1.0 - math.cos(w * t)) if inside else 0.0
        dr = 0.5 * w * math.sin(w * t) if inside else 0.0
    tk = _time_phases(phase, omega, t)
    b = max(min(n, _BLOCK), 1)
    sn, cs = np.empty((m, b)), np.empty((m, b))
    e, zs, ex, xb, yb = np.empty(b), np.empty(b), np.empty(b), np.empty(b), np.empty(b)
    bits = np.empty(b, dtype=np.int64)
    pw = bits.view(np.float64)  # 2^n of the exponentials
    u = np.empty((6, b))
    u0, u1, u2, u3, u4, u5 = u[0], u[1], u[2], u[3], u[4], u[5]
    for j0 in range(0, n, b):
        nb = min(b, n - j0)
        for j in range(nb):
            e[j] = 0.0
            xb[j], yb[j] = p[j0 + j, 0], p[j0 + j, 1]
        for i in range(m):  # the phases' sines and cosines (``_sincos``), and the surface
            a, c, tki, am = kx[i], ky[i], tk[i], amp[i]
            sni, csi = sn[i], cs[i]
            for j in range(nb):
                th = (xb[j] * a + yb[j] * c) + tki
                x = (th + (-two_pi) * math.floor(th * (0.5 / math.pi) + 0.5)) * 0.125
                x2 = x * x
                co = (((((x2 * _C6 + _C5) * x2 + _C4) * x2 + _C3) * x2 + _C2) * x2 + _C1) * x2 + 1.0
                si = ((((((x2 * _S6 + _S5) * x2 + _S4) * x2 + _S3) * x2 + _S2) * x2 + _S1) * x2 + 1.0) * x
                co, si = 1.0 - 2.0 * si * si, 2.0 * si * co  # (three angle doublings)
                co, si = 1.0 - 2.0 * si * si, 2.0 * si * co
                co, si = 1.0 - 2.0 * si * si, 2.0 * si * co
                sni[j] = si
                csi[j] = co
                e[j] += am * co
        top = -math.inf
        for j in range(nb):
            ej = r * e[j] if ramped else e[j]
            eta[j0 + j] = ej
            z = p[j0 + j, 2]
            if wheeler:
                zz = z - ej if depth == math.inf else depth * (z - ej) / (depth + ej)
            else:
                zz = z
            zs[j] = min(max(zz, -depth), 0.0)
            top = max(top, zs[j])
        if not kinematics:
            continue
        u[:, :nb] = 0.0
        for i in range(m):
            ki, qi = kk[i], qq[i]
            if ki * top < -_DEEP:
                continue
            for j in range(nb):  # exp(k z'), as 2^n exp(r)
                kz = max(zs[j] * ki, -350.0)
                nn = math.floor(kz * _LOG2E + 0.5)
                rr = (kz - nn * _LN2_HI) - nn * _LN2_LO
                y = ((((rr * _E13 + _E12) * rr + _E11) * rr + _E10) * rr + _E9) * rr + _E8
                y = (((((y * rr + _E7) * rr + _E6) * rr + _E5) * rr + _E4) * rr + _E3) * rr + _E2
                ex[j] = (y * rr + 1.0) * rr + 1.0
                bits[j] = (np.int64(nn) + 1023) << 52
            h0, h1, hz, g0, g1, gz = table[7, i], table[8, i], table[9, i], table[10, i], table[11, i], table[12, i]
            sni, csi = sn[i], cs[i]
            for j in range(nb):
                e1 = ex[j] * pw[j]
                e2 = qi / e1
                ch, sh = e1 + e2, e1 - e2
                si, co = sni[j], csi[j]
                u0[j] += ch * co * h0
                u1[j] += ch * co * h1
                u2[j] += sh * si * hz
                u3[j] += ch * si * g0
                u4[j] += ch * si * g1
                u5[j] -= sh * co * gz
        for j in range(nb):
            z = p[j0 + j, 2]
            wet = z <= eta[j0 + j] if wheeler else z <= 0.0
            for d in range(3):
                if not wet:
                    vel[j0 + j, d] = 0.0
                    acc[j0 + j, d] = 0.0
                elif ramped:  # d(r u)/dt = r du/dt + r' u
                    acc[j0 + j, d] = r * u[3 + d, j] + dr * u[d, j]
                    vel[j0 + j, d] = r * u[d, j]
                else:
                    vel[j0 + j, d] = u[d, j]
                    acc[j0 + j, d] = u[3 + d, j]

"""The compiled twin of the sea's kinematics (``waves.state_kernel``, what ``WaveField.state``
runs where the compiled kernels do) against the NumPy reference (``WaveField.reference_state``)
and against Airy's closed form written out here; the compiled waves' inertia load on a line
(``compiled.add_wave_inertia``) against ``hydro.wave_inertia``; and a line's whole load in a sea,
compiled against NumPy.

Tolerance against the reference: 1e-12 of the largest value of each array (as
``test_compiled``; for the sea's kinematics at least of its surface scale, sum a, sum a omega,
sum a omega^2, where a few points all lie deep): the two compute the same expressions but sum the components in another
order (a few ulp of the terms, 1e-16 relative), the kernel's exp is a series accurate to 4e-18,
and it leaves out components below exp(-40) = 4e-18 of their surface value; 1e-12 leaves room
for that and for nothing else (a wrong sign, weight or profile is O(1) off)."""

import math

import numpy as np
import pytest

from mjtether.physics import compiled, hydro
from mjtether.physics import waves as W
from mjtether.scenario import load_scenario
from mjtether.scenario.runner import ScenarioRun

pytestmark = pytest.mark.skipif(compiled.numba is None, reason="numba is not installed")

G, TOL = 9.81, 1e-12
RNG = np.random.default_rng(43)


def close(a, b, tol=TOL, floor=1e-300):
    """|a - b| within ``tol`` of b's largest value, or of ``floor`` where that is larger."""
    scale = max(float(np.max(np.abs(b), initial=0.0)), floor)
    assert np.max(np.abs(a - b)) <= tol * scale, f"{np.max(np.abs(a - b)) / scale:.3g} of the largest value"


def _seas():
    """(name, WaveField): a regular wave in deep water, a spread JONSWAP sea in 200 m (Wheeler),
    the walker example's sea with its build-up, and a Pierson-Moskowitz sea without stretching in
    30 m (shallow: the seabed's image term matters)."""
    yield "regular_deep", W.WaveField(W.regular(4.0, 11.0, 0.3, math.inf, G, 1.1), math.inf, G)
    yield "jonswap_spread", W.WaveField(W.jonswap(3.0, 9.0, 3.3, -0.4, 200.0, G, seed=5, n_components=40,
                                                  spreading_s=4.0, n_directions=5), 200.0, G)
    yield "walker_example", W.WaveField(W.jonswap(3.0, 9.0, 3.3, 0.0, 200.0, G, seed=1), 200.0, G, ramp_s=9.0)
    yield "pm_shallow_none", W.WaveField(W.pierson_moskowitz(2.0, 7.0, 2.0, 30.0, G, seed=2, n_components=70),
                                         30.0, G, stretching="none", ramp_s=5.0)


def _points(depth: float, n: int) -> np.ndarray:
    """n points spread over 600 m by 300 m from 3 m above the mean water line (dry, in the
    troughs or under the crests) to the seabed (or 3000 m down in deep water: beyond the short
    components' reach, where the kernel leaves them out)."""
    bottom = -depth if math.isfinite(depth) else -3000.0
    z = np.r_[3.0, 0.5, 0.0, -0.5, bottom, bottom * RNG.random(n - 5) ** 2]
    return np.c_[RNG.uniform(-300.0, 300.0, n), RNG.uniform(-150.0, 150.0, n), z]


@pytest.mark.parametrize("name, sea", list(_seas()), ids=[n for n, _ in _seas()])
def test_the_kernel_gives_the_reference_numbers(name, sea):
    """``state`` (the kernel) against ``reference_state`` (NumPy) for 1, 33 (a block of 32 and
    one more) and 200 points, before the sea starts, during its build-up, at its end and 3 hours
    in; the surface at one point (``elevation``) against the reference's own scalar sum (NumPy's
    cos). Points above the surface get zero in both, exactly."""
    assert sea.compiled
    a, w = sea.components.amplitude, sea.components.omega
    surface = [a.sum(), a @ w, a @ w ** 2]  # (the sea's scale, for points all below the short components' reach)
    ramp = [sea.ramp_s / 3, sea.ramp_s] if sea.ramp_s else []
    dried = 0
    for n in (1, 33, 200):
        p = _points(sea.depth, n) if n > 5 else _points(sea.depth, 6)[-n:]
        for t in (-1.0, 0.0, *ramp, 137.25, 10800.0):
            got, want = sea.state(p, t), sea.reference_state(p, t)
            for g, w, scale in zip(got, want, surface):
                close(g, w, floor=scale)
            dry = p[:, 2] > (want[0] if sea.stretching == "wheeler" else 0.0)
            assert not np.any(got[1][dry]) and not np.any(got[2][dry]) and not np.any(want[1][dry])
            dried += dry.sum()
    assert dried > 0
    sea.compiled = False
    try:
        want = [sea.elevation(x, y, t) for x, y, t in ((3.0, -40.0, 2.5), (250.0, 90.0, 10800.0))]
    finally:
        sea.compiled = True
    got = [sea.elevation(x, y, t) for x, y, t in ((3.0, -40.0, 2.5), (250.0, 90.0, 10800.0))]
    assert np.allclose(got, want, rtol=0.0, atol=TOL * 2 * np.sum(sea.components.amplitude))
    assert sea.state(np.zeros((0, 3)), 1.0)[0].shape == (0,)


def _k_bisection(omega: float, depth: float) -> float:
    lo, hi = omega ** 2 / G, omega ** 2 / G + omega / math.sqrt(G * depth) + 1.0 / depth
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if G * mid * math.tanh(mid * depth) < omega ** 2 else (lo, mid)
    return 0.5 * (lo + hi)


def test_the_kernel_is_airys_closed_form():
    """A regular wave (H 2 m, T 9 s, heading 0.7 rad, phase 0.4 rad) in 40 m without stretching:
    the kernel's surface, velocity and acceleration at points over depth and 2 km along the wave
    against Airy's textbook form (cosh k (z + h) / sinh k h and sinh k (z + h) / sinh k h written
    out with ``math``, k by bisection), within 1e-9 of the amplitude (the two differ in round-off
    only; a quarter-period phase error or the wrong profile would be O(1))."""
    H, T, b, ph, h = 2.0, 9.0, 0.7, 0.4, 40.0
    w = 2 * math.pi / T
    k = _k_bisection(w, h)
    sea = W.WaveField(W.WaveComponents([H / 2], [w], [k], [b], [ph]), h, G, stretching="none")
    p = np.array([[x, 0.3 * x, z] for x in (0.0, 37.0, 2000.0) for z in (-0.2, -7.0, -25.0, -40.0)])
    for t in (0.0, 3.1, 10000.0):
        eta, vel, acc = sea.state(p, t)
        for (x, y, z), e, v, a in zip(p, eta, vel, acc):
            th = k * (x * math.cos(b) + y * math.sin(b)) - w * t + ph
            ch, sh = math.cosh(k * (z + h)) / math.sinh(k * h), math.sinh(k * (z + h)) / math.sinh(k * h)
            uh, uz = H / 2 * w * ch * math.cos(th), H / 2 * w * sh * math.sin(th)
            ah, az = H / 2 * w * w * ch * math.sin(th), -H / 2 * w * w * sh * math.cos(th)
            want = (H / 2 * math.cos(th), [uh * math.cos(b), uh * math.sin(b), uz],
                    [ah * math.cos(b), ah * math.sin(b), az])
            assert abs(e - want[0]) <= 1e-9 * H / 2
            assert np.abs(v - want[1]).max() <= 1e-9 * H / 2 * w
            assert np.abs(a - want[2]).max() <= 1e-9 * H / 2 * w * w


def test_the_compiled_wave_inertia_matches_the_numpy_kernel():
    """``compiled.add_wave_inertia`` against ``hydro.wave_inertia`` on a wavy line of 40 elements
    crossing a moved surface (some elements dry, some cut), with floats' added mass on some and
    the axial added mass isotropic or none: to 1e-12 of the largest load."""
    n = 40
    s = np.linspace(0.0, 1.0, n + 1)
    x = np.c_[60 * s, 5 * np.sin(6 * s), -50 + 51.5 * s ** 1.4] + RNG.normal(scale=0.05, size=(n + 1, 3))
    rest, d = RNG.uniform(1.0, 2.0, n), RNG.uniform(0.02, 0.3, n)
    area = np.pi * d ** 2 / 4 * RNG.uniform(1.0, 3.0, n)
    surface, rho, acc = RNG.uniform(-0.8, 0.8, n), RNG.uniform(1020.0, 1030.0, (2, n)), RNG.normal(size=(2, n, 3))
    normal = np.pi * d ** 2 / 4 + np.where(RNG.random(n) < 0.3, 0.01, 0.0)
    for axial in (normal, np.zeros(n)):
        want = hydro.wave_inertia(x, rest, area, d, surface, rho, acc, normal, axial)
        got = np.full((n + 1, 3), 0.25)
        compiled.add_wave_inertia(x, rest, area, d, surface, rho.T.ravel(), acc.transpose(1, 0, 2).reshape(-1, 3),
                                  normal, axial, got)
        close(got - 0.25, want)
        assert np.abs(want).max() > 1.0  # (the load is there: the comparison means something)


SEA_LINE = """
[simulation]
duration = 1.0
timestep = 0.005
[water]
depth = 80.0
[tether]
length = 90.0
segments = 30
diameter = 0.05
density = 2000.0
EA = 2.0e6
[robot]
type = "anchor"
position = [40.0, 0.0, -80.0]
[waves]
type = "jonswap"
hs = 3.0
tp = 8.0
seed = 3
components = 60
"""


def test_a_lines_loads_in_a_sea_match_the_numpy_path():
    """A line from the surface to an anchor 80 m down in a JONSWAP sea (Hs 3 m): its loads
    (``CableLoads.hydro``: drag on the relative velocity, buoyancy under the instantaneous
    surface, the waves' inertia) on the compiled path (the kernel, the interleaved Gauss points,
    ``add_wave_inertia``) and on the NumPy path, with the same nodes and velocities, during the
    sea's build-up and 3 hours in: to 1e-12 of the largest load; and the sea along the line
    (``CableLoads.sea``) the same on both."""
    run = ScenarioRun(load_scenario(text=SEA_LINE))
    try:
        for _ in range(5):
            run.step()
        loads, L = run.bt.forces, run.bt.layout
        k, d = run.bt.drum.first, run.sim.data
        x = d.flexvert_xpos[L.vertadr + k:L.vertadr + L.n + 1].copy()
        x[:, 2] += np.linspace(0.0, 1.0, len(x)) ** 8 * 1.5  # (the top elements up into the crests and troughs)
        v = RNG.normal(scale=0.5, size=x.shape)
        fast = L.fast
        assert fast is not None and L.water.waves.compiled
        for t in (2.0, 10800.0):
            got, sea_got = loads.hydro(x, v, t).copy(), loads.sea(x, t)
            L.fast, L.water.waves.compiled = None, False
            try:
                want, sea_want = loads.hydro(x, v, t), loads.sea(x, t)
            finally:
                L.fast, L.water.waves.compiled = fast, True
            close(got, want)
            for g, w in zip(sea_got, sea_want):
                close(g, w)
            assert np.abs(sea_want.acceleration).max() > 0.1  # (the sea is there)
    finally:
        run.close()

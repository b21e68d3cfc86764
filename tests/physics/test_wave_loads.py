"""Morison's equation in waves on a cable element: the loads kernels (``hydro.tether_loads`` with
the waves' surface and particle velocity, ``hydro.wave_inertia``) against the closed-form time
history written out here from linear (Airy) theory."""

import math

import numpy as np
import pytest

from mjtether.physics import hydro, waves


RHO, G, DEPTH = 1025.0, 9.81, 60.0
H, T = 3.0, 8.0  # m, s
D, L, CD, CA = 0.2, 2.0, 1.2, 1.0  # the element: diameter m, length m, C_dn, C_a


def airy(x, z, t):
    """(u, w, du/dt, dw/dt) of a regular wave H, T travelling along +x in DEPTH, written from
    the textbook form (Dean & Dalrymple 1991, Ch. 4), k from a bisection of the dispersion."""
    w = 2 * math.pi / T
    lo, hi = 1e-6, 10.0
    for _ in range(200):
        k = 0.5 * (lo + hi)
        lo, hi = (k, hi) if w * w > G * k * math.tanh(k * DEPTH) else (lo, k)
    th = k * x - w * t
    a = H / 2
    ch, sh = math.cosh(k * (z + DEPTH)) / math.sinh(k * DEPTH), math.sinh(k * (z + DEPTH)) / math.sinh(k * DEPTH)
    return a * w * ch * math.cos(th), a * w * sh * math.sin(th), a * w * w * ch * math.sin(th), \
        -a * w * w * sh * math.cos(th)


@pytest.mark.parametrize("stretching", ["wheeler", "none"])
def test_a_fixed_horizontal_element_in_a_regular_wave(stretching):
    """A fixed element 2 m long along y (square to the wave), its axis 6 m down: the load on it
    over a period against F = 1/2 rho C_d D L |u| u + rho (1 + C_a) (pi D^2 / 4) L du/dt (u the
    particle velocity in the x-z plane, all of it normal to the element), within 1 % of the
    load's amplitude (measured 1e-15: the kernel and the closed form differ only in
    round-off). Linear theory is taken at z, Wheeler's at the stretched z' = h (z - eta) / (h +
    eta), eta = H/2 cos(k x - omega t) written here. Buoyancy is taken out by comparing with the
    still-water load."""
    sea = waves.WaveField(waves.regular(H, T, 0.0, DEPTH, G), DEPTH, G, stretching=stretching)
    x = np.array([[5.0, 0.0, -6.0], [5.0, L, -6.0]])
    v = np.zeros_like(x)
    area = np.array([math.pi * D ** 2 / 4])
    still = hydro.tether_loads(x, v, segment_length=np.array([L]), diameter=np.array([D]), cd_normal=np.array([CD]),
                               cd_tangential=np.array([0.0]), rho_fn=lambda z: np.full(np.shape(z), RHO),
                               current_fn=lambda z: np.zeros(np.shape(z) + (3,)), gravity=G)
    got, want = [], []
    for t in np.linspace(0.0, T, 41):
        gp = hydro.gauss_points(x)
        eta, vel, acc = sea.state(gp.reshape(-1, 3), t)
        f = hydro.tether_loads(x, v, segment_length=np.array([L]), diameter=np.array([D]), cd_normal=np.array([CD]),
                               cd_tangential=np.array([0.0]), rho_fn=lambda z: np.full(np.shape(z), RHO),
                               current_fn=lambda z: np.zeros(np.shape(z) + (3,)), gravity=G,
                               surface=eta.reshape(2, -1).mean(axis=0), wave_velocity=vel.reshape(2, 1, 3))
        f += hydro.wave_inertia(x, np.array([L]), area, np.array([D]), eta.reshape(2, -1).mean(axis=0),
                                np.full((2, 1), RHO), acc.reshape(2, 1, 3), CA * area, CA * area)
        got.append((f - still).sum(axis=0))
        z = -6.0
        if stretching == "wheeler":
            e = float(sea.elevation(5.0, 0.0, t))
            assert abs(e - H / 2 * math.cos(sea.components.k[0] * 5.0 - 2 * math.pi / T * t)) < 1e-12
            z = DEPTH * (z - e) / (DEPTH + e)
        u, w, du, dw = airy(5.0, z, t)
        speed = math.hypot(u, w)
        m = RHO * (1 + CA) * area[0] * L
        want.append([0.5 * RHO * CD * D * L * speed * u + m * du, 0.0, 0.5 * RHO * CD * D * L * speed * w + m * dw])
    got, want = np.array(got), np.array(want)
    assert np.abs(got - want).max() <= 0.01 * np.abs(want).max()


def test_the_wet_fraction_follows_the_surface():
    """An element lying flat 0.5 m under the mean water line is buoyed fully under a crest and
    not at all under a trough 1 m deep (the surface 1 m below the mean): its buoyancy against
    Archimedes' rho g A l, within 1e-9 relative (both ends of the wet fraction are exact)."""
    x = np.array([[0.0, 0.0, -0.5], [0.0, L, -0.5]])
    kw = dict(segment_length=np.array([L]), diameter=np.array([D]), cd_normal=np.array([CD]),
              cd_tangential=np.array([0.0]), rho_fn=lambda z: np.full(np.shape(z), RHO),
              current_fn=lambda z: np.zeros(np.shape(z) + (3,)), gravity=G)
    full = RHO * G * math.pi * D ** 2 / 4 * L
    crest = hydro.tether_loads(x, np.zeros_like(x), surface=np.array([1.0]), **kw)
    trough = hydro.tether_loads(x, np.zeros_like(x), surface=np.array([-1.0]), **kw)
    assert crest[:, 2].sum() == pytest.approx(full, rel=1e-9)
    assert trough[:, 2].sum() == pytest.approx(0.0, abs=1e-9 * full)

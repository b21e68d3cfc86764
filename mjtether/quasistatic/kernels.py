"""Compiled twins (numba) of the steady solver's inner loops: the march of a line's elements
from its top, the hang of its lower part from the touchdown, and the residuals of a batch of
shots. ``steady`` holds the NumPy reference of each (``tests/physics/test_compiled.py`` checks them
against it to 1e-12). Units SI, world frame (z up, surface z = 0); the water as the codes of
``compiled.profile_codes``."""

from __future__ import annotations

import math

import numpy as np

from mjtether.physics.compiled import GAUSS, _current, _density, _wet_fraction, jit


@jit
def _element_load(z0, t, l_s, l, d, A, mu, cdn, cdt_pi, float_cda, dkind, dp, ckind, cp, v_tow, g, f):
    """``quasistatic.line._Cable.loads`` of one element into ``f`` (3,), N: from height ``z0``
    (m) along the unit tangent ``t`` for the stretched length ``l_s`` (m); its wet length, the
    water at its two Gauss points (each for half of it), Morison drag on the current less
    ``v_tow``, buoyancy less weight."""
    z1 = z0 + l_s * t[2]
    h = 0.5 * d * math.sqrt(max(1.0 - t[2] * t[2], 0.0))  # (the cross-section's vertical half-height)
    if z0 + h <= 0.0 and z1 + h <= 0.0:
        l_wet = l
    else:
        l_wet = l * _wet_fraction(z0, z1, h)[0]
    f[0] = f[1] = f[2] = 0.0
    rho_mean = 0.0
    for gp in range(2):
        s = 0.5 - GAUSS if gp == 0 else 0.5 + GAUSS
        depth = max(-min(z0 + s * (z1 - z0), 0.0), 0.0)
        rho = _density(dkind, dp, depth)
        rho_mean += 0.5 * rho
        u0, u1 = _current(ckind, cp, depth)
        u0, u1, u2 = u0 - v_tow[0], u1 - v_tow[1], 0.0 - v_tow[2]
        ut = u0 * t[0] + u1 * t[1] + u2 * t[2]
        n0, n1, n2 = u0 - ut * t[0], u1 - ut * t[1], u2 - ut * t[2]
        q = 0.25 * d * l_wet * rho
        un_mag = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        kn = q * cdn * un_mag
        kt = q * cdt_pi * abs(ut) * ut
        f[0] += kn * n0 + kt * t[0]
        f[1] += kn * n1 + kt * t[1]
        f[2] += kn * n2 + kt * t[2]
        if float_cda > 0.0:
            kf = 0.25 * float_cda * l_wet * rho * un_mag
            f[0] += kf * n0
            f[1] += kf * n1
            f[2] += kf * n2
    rho = rho_mean
    f[2] += (rho * A * l_wet - mu * l) * g


@jit
def hang_up(s_td, seabed_z, stop_z, max_iterations, l, EA, d, A, mu, cdn, cdt_pi, float_cda, dkind, dp, ckind, cp,
            v_tow, g, xs, Ts, p):
    """``quasistatic.seabed_lay._hang_up`` of a uniform line (element properties as scalars, the
    water as codes): the nodes from the touchdown up into ``xs`` (k + 2, 3), the tensions into
    ``Ts`` (k + 1,), the force at the last node into ``p`` (3,); returns (nodes written, phi)."""
    k = int(math.floor(s_td / l * (1 + 1e-12)))
    phi = s_td / l - k
    first = 0 if phi > 1e-12 else 1  # (a hanging part of the touchdown element, if any)
    x = np.array([0.0, 0.0, seabed_z])
    t = np.array([0.0, 0.0, -1.0])
    f, E, gg = np.empty(3), np.empty(3), np.empty(3)
    p[0] = p[1] = p[2] = 0.0
    xs[0] = x
    count = 1
    T = 0.0
    for i in range(first, k + 1):
        frac = phi if i == 0 else 1.0
        alpha, miss_old = 1.0, math.inf
        for _ in range(max_iterations):
            l_s = frac * l * (1.0 + T / EA)
            _element_load(x[2] - l_s * t[2], t, l_s, l, d, A, mu, cdn, cdt_pi, float_cda, dkind, dp, ckind, cp,
                          v_tow, g, f)
            for j in range(3):
                E[j] = p[j] + 0.5 * frac * f[j]
            T = math.sqrt(E[0] * E[0] + E[1] * E[1] + E[2] * E[2])
            for j in range(3):
                gg[j] = E[j] / max(T, 1e-300)
            miss = math.sqrt((gg[0] - t[0]) ** 2 + (gg[1] - t[1]) ** 2 + (gg[2] - t[2]) ** 2)
            if miss <= 1e-10:
                break
            if miss > 0.5 * miss_old:  # not contracting: relax
                alpha = max(0.5 * alpha, 1.0 / 64)
            miss_old = miss
            for j in range(3):
                t[j] = t[j] + alpha * (gg[j] - t[j])
            norm = math.sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
            for j in range(3):
                t[j] /= norm
        for j in range(3):
            t[j] = gg[j]
        s = frac * l * (1.0 + T / EA)
        for j in range(3):
            x[j] = x[j] - s * t[j]
            p[j] = p[j] + frac * f[j]
        xs[count] = x
        Ts[count - 1] = T
        count += 1
        if x[2] > stop_z:
            break
    return count, phi


@jit
def steady_march(x0, P0, l_e, EA_e, d_e, A_e, mu_e, cdn_e, cdt_pi_e, float_cda, dkind, dp, ckind, cp, v_tow, g,
                 iterations, stop_on_touchdown, k_min, allow_first, X, T, P, td):
    """``quasistatic.line._Cable.march`` of a line without point loads from node 0: the
    elements marched from ``x0`` (K, 3) with top forces ``P0`` (K, 3) into nodes ``X`` (K, n+1,
    3), tensions ``T`` (K, n) and forces ``P`` (K, n+1, 3) (N, m), and with
    ``stop_on_touchdown`` the touchdown element of each shot into ``td`` (K,), -1 if none.
    Per element (n,): unstretched length (m), EA (N, inf: inextensible), diameter (m),
    displaced area (m^2), mass per length (kg/m), C_dn, pi C_dt, floats' normal drag area per
    metre (m^2/m); the water as codes (``profile_codes``); ``v_tow`` the tow velocity (m/s)."""
    K, n = x0.shape[0], l_e.shape[0]
    f = np.empty(3)
    E = np.empty(3)
    t = np.empty(3)
    for s in range(K):
        for j in range(3):
            X[s, 0, j] = x0[s, j]
            P[s, 0, j] = P0[s, j]
        td[s] = -1
        f[0], f[1], f[2] = 0.0, 0.0, -mu_e[0] * l_e[0] * g
        for k in range(n):
            l, EA, d = l_e[k], EA_e[k], d_e[k]
            Tk, l_s = 0.0, 0.0
            for _ in range(iterations):
                for j in range(3):
                    E[j] = P[s, k, j] - 0.5 * f[j]
                Tk = math.sqrt(E[0] * E[0] + E[1] * E[1] + E[2] * E[2])
                inv = max(Tk, 1e-300)
                for j in range(3):
                    t[j] = E[j] / inv
                l_s = l * (1.0 + Tk / EA)
                _element_load(X[s, k, 2], t, l_s, l, d, A_e[k], mu_e[k], cdn_e[k], cdt_pi_e[k], float_cda[k], dkind,
                              dp, ckind, cp, v_tow, g, f)
            T[s, k] = Tk
            for j in range(3):
                X[s, k + 1, j] = X[s, k, j] + l_s * t[j]
                P[s, k + 1, j] = P[s, k, j] - f[j]
            if stop_on_touchdown and k >= k_min and td[s] < 0 and P[s, k + 1, 2] >= 0.0:
                if (k == k_min and allow_first) or P[s, k, 2] < 0.0:
                    td[s] = k


@jit
def shot_residuals(X, P, td, bottom, contact, seabed_z, cb, w, L, l, EA, r):
    """``quasistatic.steady._shoot``'s residuals (m) of K marches of a uniform line into ``r``
    (K, 3): the last node's miss of ``bottom``, or with ``contact`` and a touchdown in element
    ``td[s]``, the laid end's miss (``_lay`` with ``end_only``: the rest of the unstretched
    length ``L`` (m) laid straight from the touchdown along the horizontal force there, stretched
    under the tension that seabed friction ``cb`` takes off it at ``w`` N/m) with, as the third
    component, the touchdown's height above ``seabed_z``. Nodes ``X`` (K, n+1, 3), forces ``P``
    (K, n+1, 3), element length ``l`` (m), ``EA`` (N, inf: inextensible)."""
    for s in range(X.shape[0]):
        k = td[s]
        if not (contact and k >= 0):
            for j in range(3):
                r[s, j] = X[s, X.shape[1] - 1, j] - bottom[j]
            continue
        pz0, pz1 = P[s, k, 2], P[s, k + 1, 2]
        phi = min(max(-pz0 / (pz1 - pz0), 0.0), 1.0) if pz1 != pz0 else 1.0
        px = P[s, k, 0] + phi * (P[s, k + 1, 0] - P[s, k, 0])
        py = P[s, k, 1] + phi * (P[s, k + 1, 1] - P[s, k, 1])
        H = math.hypot(px, py)
        LB = max(L - (k + phi) * l, 0.0)
        if EA == math.inf:
            stretch = LB
        elif cb <= 0 or w <= 0:
            stretch = LB * (1 + H / EA)
        else:
            uc = min(LB, min(H / (cb * w), 1e300))
            stretch = LB + (H * uc - cb * w * uc * uc / 2) / EA
        Hm = max(H, 1e-300)
        r[s, 0] = X[s, k, 0] + phi * (X[s, k + 1, 0] - X[s, k, 0]) + stretch * (px / Hm) - bottom[0]
        r[s, 1] = X[s, k, 1] + phi * (X[s, k + 1, 1] - X[s, k, 1]) + stretch * (py / Hm) - bottom[1]
        r[s, 2] = X[s, k, 2] + phi * (X[s, k + 1, 2] - X[s, k, 2]) - seabed_z

"""The line of the steady-state solver (``steady``): ``_Cable``, one tether (a uniform
``TetherSpec`` or a ``LineMakeup``) in one water column, and its march.

``_Cable`` holds the line's properties per element (length, EA, diameter, area, mass per metre,
drag coefficients, distributed floats) and per node (point loads), the elements' loads (wet
weight and Morison drag on the relative velocity at the element's two Gauss points, as the
dynamic tether takes it (``hydro.GAUSS_POINTS``); weight, buoyancy and
drag of the point loads) and the march of the elements from a node and a force
(``march``; its compiled twin is ``kernels.steady_march``). The method is in the docstring of
``steady``.

Frames: world, z up, water surface z = 0, seabed z = -water.depth. SI units.
"""

from __future__ import annotations

import math

import numpy as np

from mjtether.cable.makeup import LineMakeup
from mjtether.cable.tether import TetherSpec
from mjtether.physics import compiled
from mjtether.physics.hydro import GAUSS_POINTS, element_drag, section_half_height, wet_fraction
from mjtether.physics.water import WaterColumn

from . import kernels


class _Cable:
    """Constants of the march for one line (a ``TetherSpec`` or a ``LineMakeup``: ``line``) in
    one water column: per-element arrays (``l_e``, ``d_e``, ...) and, for a uniform line
    (``uniform``: one section, no loads, marched as its ``TetherSpec``), the same as scalars
    (``l``, ``d``, ...; ``None`` for a non-uniform make-up). ``EA``: a number, ``None``
    (inextensible) or, for a make-up, "tether" (each section's)."""

    def __init__(self, tether, water: WaterColumn, tow_velocity, EA):
        self.g = water.gravity
        self.water = water
        self._wet_at = {}  # seabed height (m): wet weight per metre there (N/m), see seabed_wet_weight
        self.v_tow = np.asarray(tow_velocity, dtype=float)
        self.float_cda = None  # normal drag area of distributed floats per metre, per element
        self.node_loads = None  # (mass, volume, cd_area) per node, where any
        self.k_min = 0  # first element that may hold the touchdown
        self.line = line = LineMakeup.of(tether)
        self.uniform = line.is_uniform
        self.drag_law = line.drag_law
        if self.uniform:  # the scalars of the uniform path (the slack state and the lay use them)
            tether = tether if isinstance(tether, TetherSpec) else line.tether
            if EA == "tether":
                EA = tether.EA
            self.N = N = tether.segments
            self.l = tether.segment_length
            self.L = tether.length
            self.EA = math.inf if EA is None else float(EA)
            self.d = tether.diameter
            self.A = tether.area
            self.mu = tether.mu
            self.cdn = tether.cd_normal
            self.cdt_pi = math.pi * tether.cd_tangential
            self.l_e, self.EA_e, self.d_e = np.full(N, self.l), np.full(N, self.EA), np.full(N, self.d)
            self.A_e, self.mu_e = np.full(N, self.A), np.full(N, self.mu)
            self.cdn_e, self.cdt_pi_e = np.full(N, self.cdn), np.full(N, self.cdt_pi)
            self.s_node = np.arange(N + 1) * self.l
            self.fast = self._compiled()
            return
        self.N = N = line.segments
        self.L = line.length
        self.l_e = line.element_length
        if EA == "tether":
            self.EA_e = line.element_EA
        else:
            self.EA_e = np.full(N, math.inf if EA is None else float(EA))
        self.d_e = line.element_diameter
        self.A_e = line.element_area
        self.mu_e = line.element_mass_per_length
        self.cdn_e = line.element_cd_normal
        self.cdt_pi_e = math.pi * line.element_cd_tangential
        self.s_node = line.node_arc_length
        if np.any(line.element_float_cd_area > 0):
            self.float_cda = line.element_float_cd_area
        if line.has_point_loads:
            self.node_loads = (line.node_mass, line.node_volume, line.node_cd_area)
        self.l = self.EA = self.d = self.A = self.mu = self.cdn = self.cdt_pi = None
        # buoyant parts cannot lie on the seabed: the touchdown comes after the last of them
        self.w_sb = self.seabed_weight(self.mu_e, self.A_e)
        buoyant = [e + 1 for e in np.flatnonzero(self.w_sb < 0.0)]
        if self.node_loads is not None:
            self.W_sb = self.seabed_weight(self.node_loads[0], self.node_loads[1])
            buoyant += list(np.flatnonzero(self.W_sb < 0.0))
        else:
            self.W_sb = np.zeros(N + 1)
        self.k_min = int(max(buoyant, default=0))
        self.fast = self._compiled()

    @property
    def makeup(self):
        """The make-up of a non-uniform line, else None (for callers that read it so; new code
        reads ``uniform`` and ``line``)."""
        return None if self.uniform else self.line

    def _compiled(self):
        """The arguments of ``kernels.steady_march`` after the shots (the same march, compiled),
        or None where it does not apply (the NumPy kernels, a water profile it does not know)."""
        if self.drag_law != "morison":  # (the compiled march knows Morison's drag law only)
            return None
        codes = compiled.profile_codes(self.water) if compiled.backend() == "numba" else None
        if codes is None:
            return None
        f = lambda a: np.ascontiguousarray(np.broadcast_to(a, (self.N,)), dtype=float)  # noqa: E731
        return (f(self.l_e), f(self.EA_e), f(self.d_e), f(self.A_e), f(self.mu_e), f(self.cdn_e), f(self.cdt_pi_e),
                f(0.0 if self.float_cda is None else self.float_cda), *codes, self.v_tow.astype(float), float(self.g))

    def seabed_wet_weight(self, seabed_z: float) -> float:
        """Submerged weight per metre (N/m) of the uniform line on a seabed at ``seabed_z`` (m)."""
        w = self._wet_at.get(seabed_z)
        if w is None:
            w = self._wet_at[seabed_z] = (self.mu - float(self.water.rho(np.array([seabed_z]))[0]) * self.A) * self.g
        return w

    def seabed_weight(self, mass, volume):
        """Submerged weight (N or N/m) of ``mass`` and ``volume`` at the seabed's density."""
        rho = float(self.water.rho(np.array([self.water.seabed_z]))[0])
        return (np.asarray(mass) - rho * np.asarray(volume)) * self.g

    def loads(self, x0, t, l_s, k=0):
        """External load (N) on elements ``k`` starting at ``x0`` (K, 3) with tangents ``t`` (K, 3)
        and stretched lengths ``l_s`` (K,)."""
        l, d, A, mu = self.l_e[k], self.d_e[k], self.A_e[k], self.mu_e[k]
        z0 = x0[:, 2]
        z1 = z0 + l_s * t[:, 2]
        h = section_half_height(d, t)
        if (z0 + h).max() <= 0.0 and (z1 + h).max() <= 0.0:  # fully wet, the usual case
            l_wet = l
        else:
            l_wet = l * wet_fraction(z0, z1, h)[0]
        floats = self.float_cda[k] if self.float_cda is not None and self.float_cda[k] > 0.0 else None
        f, rho_mean = 0.0, 0.0
        for s in GAUSS_POINTS:  # (the drag at the element's two Gauss points, each for half of it)
            zg = np.minimum(z0 + s * (z1 - z0), 0.0)
            rho = self.water.rho(zg)
            u = self.water.velocity(zg) - self.v_tow
            f = f + element_drag(self.drag_law, t, u, rho, 0.5 * l_wet, d, self.cdn_e[k], self.cdt_pi_e[k], floats)
            rho_mean = rho_mean + 0.5 * rho
        f[:, 2] += (rho_mean * A * l_wet - mu * l) * self.g
        return f

    def node_load(self, x, j):
        """Point load (N) on node ``j`` at positions ``x`` (K, 3): weight, buoyancy (under water
        only) and drag 1/2 rho CdA |u| u on the relative velocity; ``None`` if the node has none."""
        if self.node_loads is None:
            return None
        m, V, cda = (a[j] for a in self.node_loads)
        if m == 0.0 and V == 0.0 and cda == 0.0:
            return None
        z = x[:, 2]
        zc = np.minimum(z, 0.0)
        wet = (z <= 0.0).astype(float)
        rho = self.water.rho(zc)
        g = np.zeros((x.shape[0], 3))
        g[:, 2] = (rho * V * wet - m) * self.g
        if cda > 0.0:
            u = self.water.velocity(zc) - self.v_tow
            g += (0.5 * rho * cda * wet * np.sqrt((u * u).sum(axis=1)))[:, None] * u
        return g

    def march(self, x0, P0, stop_on_touchdown=False, iterations=2, start=0, first_frac=1.0, allow_first=True,
              own_load=True):
        """March the N elements from node positions ``x0`` with forces ``P0`` (K, 3).

        Returns (nodes (K, n+1, 3), tension (K, n), P (K, n+1, 3)); P excludes the point load on
        its own node (``P0`` includes node 0's: it is the top force). With
        ``stop_on_touchdown`` the march of each shot also records the first element k (from
        ``k_min`` on) where the vertical component of P becomes >= 0 (P_k,z < 0 <= P_k+1,z, or
        just P_k+1,z >= 0 at k = k_min with ``allow_first``), returned as the fourth item, -1 if
        never. Make-ups only: a march may start at node ``start`` (``x0`` is then the point where
        it starts, ``P0`` the force there, already net of any point load there when not
        ``own_load``) with a first element of fraction ``first_frac``; the fifth item is the
        point loads on the nodes (K, n+1, 3).
        """
        n = self.N
        K = x0.shape[0]
        X = np.empty((K, n + 1, 3))
        P = np.empty((K, n + 1, 3))
        T = np.empty((K, n))
        if self.fast is not None and start == 0 and first_frac == 1.0 and self.node_loads is None:
            td = np.empty(K, dtype=np.int64)
            kernels.steady_march(np.ascontiguousarray(x0, dtype=float), np.ascontiguousarray(P0, dtype=float),
                                  *self.fast, iterations, stop_on_touchdown, max(self.k_min, start), allow_first,
                                  X, T, P, td)
            if not self.uniform:
                return X, T, P, td, np.zeros((K, n + 1, 3))
            return (X, T, P, td) if stop_on_touchdown else (X, T, P)
        X[:, start], P[:, start] = x0, P0
        G = None if self.uniform else np.zeros((K, n + 1, 3))
        if start == 0 and own_load:
            g0 = self.node_load(X[:, 0], 0)
            if g0 is not None:
                G[:, 0] = g0
                P[:, 0] = P0 - g0
        td = np.full(K, -1)
        k_min = max(self.k_min, start)
        f = np.zeros((K, 3))
        f[:, 2] = -self.mu_e[start] * self.l_e[start] * self.g
        for k in range(start, n):
            p = P[:, k]
            l, EA = self.l_e[k], self.EA_e[k]
            if k == start and first_frac != 1.0:
                frac = first_frac
                for _ in range(iterations):
                    E = p - 0.5 * frac * f
                    Tk = np.sqrt((E * E).sum(axis=1))
                    t = E / np.maximum(Tk, 1e-300)[:, None]
                    l_s = frac * l * (1.0 + Tk / EA)
                    f = self.loads(X[:, k], t, l_s, k)
                f = frac * f
            else:
                for _ in range(iterations):
                    E = p - 0.5 * f
                    Tk = np.sqrt((E * E).sum(axis=1))
                    t = E / np.maximum(Tk, 1e-300)[:, None]
                    l_s = l * (1.0 + Tk / EA)
                    f = self.loads(X[:, k], t, l_s, k)
            T[:, k] = Tk
            X[:, k + 1] = X[:, k] + l_s[:, None] * t
            g = self.node_load(X[:, k + 1], k + 1)
            if g is None:
                P[:, k + 1] = p - f
            else:
                G[:, k + 1] = g
                P[:, k + 1] = p - f - g
            if stop_on_touchdown and k >= k_min:
                new = (td < 0) & (P[:, k + 1, 2] >= 0.0)
                if not (k == k_min and allow_first):
                    new &= P[:, k, 2] < 0.0
                td[new] = k
        if not self.uniform:
            return X, T, P, td, G
        if stop_on_touchdown:
            return X, T, P, td
        return X, T, P

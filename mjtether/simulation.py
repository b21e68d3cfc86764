"""A MuJoCo simulation with tethers and hydrodynamic bodies: compile, step, read out, close.

``Simulation`` compiles an ``MjSpec`` that ``add_tether`` and ``add_body_hydro`` prepared,
registers its force providers with the process-wide passive callback
(``mjtether.dispatch``), steps with divergence detection, and removes its providers on
``close()`` (or at the end of a ``with`` block).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from . import dispatch
from .builder import TetherModel, axial_params
from .hydro import bending_forces, element_geometry, tether_loads
from .rigidbody import BodyHydroModel, BoundBodyHydro, make_not_simple
from .water import WaterColumn


_EQUALITY = int(mujoco.mjtConstraint.mjCNSTR_EQUALITY)  # an int: comparing arrays with the enum is slow
MASS_REFRESH = 1e-4
"""Relative change of the deployed length after which ``set_length`` refreshes node masses."""
_BADQPOS, _BADQVEL, _BADQACC = (int(w) for w in (mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL,
                                                  mujoco.mjtWarning.mjWARN_BADQACC))


class SimulationDiverged(RuntimeError):
    """The state became non-finite or MuJoCo reported a bad acceleration."""


class BoundTether:
    """A ``TetherModel`` bound to a compiled model: indices, force provider, readouts.

    Readouts refer to the state of the last ``mj_forward``/``mj_step`` force computation.
    Forces are those the tether exerts on its ends (N, world frame).
    """

    def __init__(self, tm: TetherModel, model: mujoco.MjModel, data: mujoco.MjData, water: WaterColumn):
        self.tm = tm
        self.spec = s = tm.spec
        self.water = water
        self.N = N = s.segments
        fid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_FLEX, tm.name)
        self.vertadr = model.flex_vertadr[fid]
        edgeadr = model.flex_edgeadr[fid]
        # rest length of every element is the material length l, whatever the initial shape
        model.flexedge_length0[edgeadr:edgeadr + N] = s.segment_length
        self._row_cache: dict[int, slice] = {}
        self.eq_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, tm.edge_equality)
        self.connect_ids = {k: mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, v)
                            for k, v in tm.connects.items()}
        bids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, b) for b in tm.node_bodies]
        self.dofs = np.concatenate([model.body_dofadr[b] + np.arange(3) for b in bids])
        # node dofs are contiguous (one body after another): a slice is faster to write through
        if np.all(np.diff(self.dofs) == 1):
            self.dofs = slice(int(self.dofs[0]), int(self.dofs[-1]) + 1)
        self.qpos_adr = np.concatenate([model.jnt_qposadr[model.body_jntadr[b]] + np.arange(3) for b in bids])
        m_eff = s.mu * s.segment_length + tm.added_mass[N // 2]  # interior node, mass + armature
        # retune the edge constraint with the diagA MuJoCo actually uses for interior edges
        mujoco.mj_forward(model, data)
        diag = np.median(data.efc_diagA[self._rows(data, self.eq_id)])
        tm.axial = axial_params(s.EA, s.segment_length, m_eff, model.opt.timestep,
                                s.axial_damping_ratio, diag_a=float(diag))
        model.eq_solref[self.eq_id] = tm.axial.solref
        model.eq_solimp[self.eq_id] = tm.axial.solimp
        # what set_length scales with the element length
        self._edges = slice(edgeadr, edgeadr + N)
        self._bids = np.array(bids)
        self._l0 = s.segment_length
        self._mass0 = model.body_mass[self._bids].copy()
        self._inertia0 = model.body_inertia[self._bids].copy()
        self._armature0 = model.dof_armature[self.dofs].copy()
        self._m_eff0 = m_eff
        self._diag0 = float(diag)
        self.segment_length = self._l_mass = s.segment_length
        make_not_simple(model, self._bids)  # masses and armature change with the deployed length

    # ----------------------------------------------------------------- forces

    def loads(self, data: mujoco.MjData) -> np.ndarray:
        """Hydrodynamic (+ bending) loads on every node (N, shape (N+1, 3))."""
        s = self.spec
        x = data.flexvert_xpos[self.vertadr:self.vertadr + self.N + 1]
        v = data.qvel[self.dofs].reshape(-1, 3)
        f = tether_loads(x, v, segment_length=self.segment_length, diameter=s.diameter,
                         cd_normal=s.cd_normal, cd_tangential=s.cd_tangential,
                         rho_fn=self.water.rho, current_fn=self.water.velocity,
                         gravity=self.water.gravity)
        if s.EI > 0:
            f += bending_forces(x, s.EI, self.segment_length)
        return f

    def apply(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        data.qfrc_passive[self.dofs] += self.loads(data).ravel()

    def set_state(self, data: mujoco.MjData, nodes=None, velocity=None) -> None:
        """Set node positions (m) and/or velocities (m/s), world frame, shape (N+1, 3), e.g.
        from a ``quasistatic.steady_state``; call ``Simulation.forward()`` afterwards."""
        for label, arr in (("nodes", nodes), ("velocity", velocity)):
            if arr is None:
                continue
            a = np.asarray(arr, dtype=float)
            if a.shape != (self.N + 1, 3) or not np.all(np.isfinite(a)):
                raise ValueError(f"{label} must be a finite array of shape ({self.N + 1}, 3)")
            if label == "nodes":
                data.qpos[self.qpos_adr] = (a - self.tm.initial_nodes).ravel()
            else:
                data.qvel[self.dofs] = a.ravel()

    # ----------------------------------------------------------------- readouts

    def nodes(self, data: mujoco.MjData) -> np.ndarray:
        """Node positions (m, world frame), shape (N+1, 3), node 0 at the ship."""
        return data.flexvert_xpos[self.vertadr:self.vertadr + self.N + 1].copy()

    def _rows(self, data: mujoco.MjData, eq_id: int) -> slice:
        """The constraint rows of equality ``eq_id``: a contiguous block that MuJoCo places
        among the equality rows at the top of efc_*; cached, and checked at its ends."""
        r = self._row_cache.get(eq_id)
        t, i, n = data.efc_type, data.efc_id, data.nefc
        if r is None or not (r.stop <= n and t[r.start] == _EQUALITY and i[r.start] == eq_id
                             and t[r.stop - 1] == _EQUALITY and i[r.stop - 1] == eq_id
                             and (r.start == 0 or t[r.start - 1] != _EQUALITY or i[r.start - 1] != eq_id)
                             and (r.stop == n or t[r.stop] != _EQUALITY or i[r.stop] != eq_id)):
            rows = np.nonzero((t[:n] == _EQUALITY) & (i[:n] == eq_id))[0]
            r = slice(int(rows[0]), int(rows[-1]) + 1) if len(rows) else slice(0, 0)
            self._row_cache[eq_id] = r
        return r

    def tension(self, data: mujoco.MjData) -> np.ndarray:
        """Axial tension of each element (N), shape (N,); negative means compression."""
        rows = self._rows(data, self.eq_id)
        if rows.stop - rows.start != self.N:
            raise RuntimeError("tether tension is available after mj_forward/mj_step")
        return -data.efc_force[rows]

    def stretched_length(self, data: mujoco.MjData) -> float:
        """Sum of element lengths (m)."""
        return float(element_geometry(self.nodes(data))[1].sum())

    @property
    def deployed_length(self) -> float:
        """Unstretched deployed length (m)."""
        return self.segment_length * self.N

    def set_length(self, model: mujoco.MjModel, length: float) -> None:
        """Change the deployed (unstretched) length to ``length`` (m), as a winch does.

        Every element takes the length L / N (the variable-segment-length approach of Khan et
        al. 2023, Table 6): rest lengths, node masses, added mass and the axial constraint all
        scale with it, so the cable's mass follows its length and its stiffness stays EA. A
        change of a small fraction of an element per step adds no tension of its own. Rest
        lengths follow every call; masses and the constraint's tuning are refreshed once the
        length has moved by MASS_REFRESH of itself since their last refresh (their error is
        then below that fraction, and a winch paying out every step costs little).
        """
        L = float(length)
        if not (np.isfinite(L) and L > 0):
            raise ValueError(f"length must be a finite number > 0 m, got {length!r}")
        l = L / self.N
        if l == self.segment_length:
            return  # (a fixed winch calls this every step)
        model.flexedge_length0[self._edges] = l
        self.segment_length = l
        if abs(l - self._l_mass) > MASS_REFRESH * self._l_mass:
            self._refresh_mass(model)

    def _refresh_mass(self, model: mujoco.MjModel) -> None:
        l = self.segment_length
        r = l / self._l0
        s = self.spec
        model.body_mass[self._bids] = self._mass0 * r
        model.body_inertia[self._bids] = self._inertia0 * r
        model.dof_armature[self.dofs] = self._armature0 * r
        self.tm.axial = axial_params(s.EA, l, self._m_eff0 * r, model.opt.timestep, s.axial_damping_ratio,
                                     diag_a=self._diag0 / r)
        model.eq_solref[self.eq_id] = self.tm.axial.solref
        model.eq_solimp[self.eq_id] = self.tm.axial.solimp
        self._l_mass = l

    def end_force(self, data: mujoco.MjData, which: str = "start") -> np.ndarray:
        """Force of the tether on its ``"start"`` (ship) or ``"end"`` (robot) support (N, world):
        the force of the ``connect`` constraint that holds the end node to the support."""
        if which not in ("start", "end"):
            raise ValueError(f"which must be 'start' or 'end', got {which!r}")
        if which not in self.connect_ids:  # a free end
            return np.zeros(3)
        return data.efc_force[self._rows(data, self.connect_ids[which])].copy()


    def end_tension(self, data: mujoco.MjData, which: str = "start") -> float:
        """Magnitude of ``end_force`` (N)."""
        f = self.end_force(data, which)
        return math.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) if len(f) == 3 else 0.0


class Simulation:
    """Compile ``spec`` and simulate it with tether and body hydrodynamics in ``water``.

    >>> # sim = Simulation(spec, water, tethers=[tm]); sim.step(1000); sim.close()
    """

    def __init__(self, spec: mujoco.MjSpec, water: WaterColumn, tethers=(), bodies=()):
        if not isinstance(water, WaterColumn):
            raise ValueError(f"water must be a WaterColumn, got {type(water).__name__}")
        self.water = water
        self.model = dispatch.compile_spec(spec)
        self.data = mujoco.MjData(self.model)
        self.tethers = {}
        for tm in tethers:
            if not isinstance(tm, TetherModel):
                raise ValueError("tethers must be TetherModel objects returned by add_tether")
            self.tethers[tm.name] = BoundTether(tm, self.model, self.data, water)
        self.bodies = []
        for bm in bodies:
            if not isinstance(bm, BodyHydroModel):
                raise ValueError("bodies must be BodyHydroModel objects returned by add_body_hydro")
            self.bodies.append(BoundBodyHydro(bm, self.model, water))
        self._providers = [*self.tethers.values(), *self.bodies]
        self._closed = False
        self._bad_acc0 = 0
        dispatch.register(self.data, self._passive)
        mujoco.mj_forward(self.model, self.data)
        dispatch.raise_pending(self.data)

    def _passive(self, m, d):
        for p in self._providers:
            p.apply(m, d)

    @property
    def time(self) -> float:
        return float(self.data.time)

    @property
    def timestep(self) -> float:
        return float(self.model.opt.timestep)

    def tether(self, name: str = "tether") -> BoundTether:
        return self.tethers[name]

    def forward(self) -> None:
        """Recompute forces and readouts for the current state without stepping."""
        mujoco.mj_forward(self.model, self.data)
        dispatch.raise_pending(self.data)

    def step(self, nstep: int = 1) -> None:
        """Advance ``nstep`` steps; raise ``SimulationDiverged`` if the state blows up."""
        if self._closed:
            raise RuntimeError("simulation is closed")
        mujoco.mj_step(self.model, self.data, nstep)
        dispatch.raise_pending(self.data)
        self.check()

    def run(self, duration: float, callback=None, every: float | None = None) -> None:
        """Simulate ``duration`` seconds; call ``callback(sim)`` every ``every`` seconds."""
        dt = self.timestep
        n = int(round(duration / dt))
        k = max(1, int(round((every or duration) / dt))) if callback else n
        done = 0
        while done < n:
            m = min(k, n - done)
            self.step(m)
            done += m
            if callback:
                callback(self)

    def check(self) -> None:
        d = self.data
        # MuJoCo checks qpos, qvel and qacc for NaN or > 1e10 at every step; it warns and (by
        # default) resets the state, which would otherwise hide the blow-up
        w = d.warning
        bad = w[_BADQPOS].number + w[_BADQVEL].number + w[_BADQACC].number
        if bad > self._bad_acc0 or not math.isfinite(d.qvel[0] + d.qpos[0]):
            self._bad_acc0 = bad
            raise SimulationDiverged(
                f"simulation diverged at t = {d.time:.3f} s (time step {self.timestep:g} s); "
                "reduce the time step (see mjtether.stability.max_timestep)")

    def close(self) -> None:
        """Remove this simulation's force providers from the passive callback."""
        if not self._closed:
            dispatch.unregister(self.data)
            self._closed = True

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass

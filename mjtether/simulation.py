"""A MuJoCo simulation with tethers and hydrodynamic bodies: compile, step, read out, close.

``Simulation`` compiles an ``MjSpec`` that ``add_tether`` and ``add_body_hydro`` prepared,
registers its force providers with the process-wide passive callback
(``mjtether.physics.dispatch``), steps with divergence detection, and removes its providers on
``close()`` (or at the end of a ``with`` block). ``drive`` is the run loop of every system
built on one (a scenario's ``ScenarioRun``, a network's ``NetworkRun``): it steps it to its end,
sampling it as it goes.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import mujoco
import numpy as np

from mjtether import _checks
from mjtether.cable import kernels, softening, stepping
from mjtether.cable.bound import BoundTether
from mjtether.cable.builder import TetherModel
from mjtether.cable.drum import FAIRLEAD_SHARE, MERGE, SPLIT, START_SLACK  # noqa: F401 - the flat layout's names
from mjtether.cable.slack import SLACK_FORCE, SLACK_TENSION  # noqa: F401 - the flat layout's names
from mjtether.physics import dispatch, native
from mjtether.physics.rigidbody import BodyHydroModel, BoundBodyHydro
from mjtether.physics.water import WaterColumn
from mjtether.vehicles.vehicle import BoundVehicle, VehicleModel

_BADQPOS, _BADQVEL, _BADQACC = (int(w) for w in (mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL,
                                                  mujoco.mjtWarning.mjWARN_BADQACC))
MAX_RUN_S = 1e9
"""The longest ``Simulation.run`` accepted (s, about 32 years): beyond it is a typo or inf."""
MAX_NODE_SPEED = 1000.0
"""Tether node speed (m/s) taken as divergence: no cable in water moves at 1 km/s."""
MAX_STRAIN = 1.0
"""Stretch of an element, over the nominal element length, taken as divergence: a cable
stretched to twice its length has failed."""
_STATE = mujoco.mjtState.mjSTATE_INTEGRATION
SLACK_REDOS = 1
"""Times a step is redone with elements switched both ways; one more redo may then switch off
elements still pushing (those shorter than their rest length, and any pushing by more than
``cable.slack.SLACK_FORCE`` of an element's weight). (3 redos gave 1.6 MuJoCo steps per step on
the built-in walker scenario and no fewer pushes in the tests.)"""


class SimulationDiverged(RuntimeError):
    """The state became non-finite or MuJoCo reported a bad acceleration."""


def _warn_soft(name: str, bt: BoundTether, timestep: float) -> None:
    """``softening.warn`` for the tether ``name`` bound as ``bt`` at ``timestep`` (s)."""
    asked = bt.drum.EA[bt.drum.first:]  # N, each deployed element's (inf: inextensible, never softened)
    elastic = np.isfinite(asked)
    report = softening.softening(asked[elastic], bt.effective_EA[elastic]) if elastic.any() else None
    if report is not None:
        softening.warn(f"tether {name!r} EA", report, timestep,
                       f"; a step {report['ratio'] ** 0.5:.3g} times this one keeps it", stacklevel=4)


class Simulation:
    """Compile ``spec`` and simulate it with tether and body hydrodynamics in ``water``.

    >>> # sim = Simulation(spec, water, tethers=[tm]); sim.step(1000); sim.close()

    ``warn_EA``: warn (``cable.softening.EAWarning``, once per tether) where the model's time step
    makes a tether softer than its EA, naming the tether, its effective EA and the step that keeps
    it (the scenario and the network runners pass False: they warn naming their own keys).
    """

    compiled_steps = True
    """Step tethers in compiled blocks where ``cable.stepping.usable`` (False, on the class or
    one simulation: the Python loop always; the same bits, ``tests/cable/test_stepping.py``)."""

    def __init__(self, spec: mujoco.MjSpec, water: WaterColumn, tethers=(), bodies=(), warn_EA: bool = True):
        if not isinstance(water, WaterColumn):
            raise ValueError(f"water must be a WaterColumn, got {type(water).__name__}")
        self.water = water
        self.model = dispatch.compile_spec(spec)
        # buoyancy uses water.gravity, weight MuJoCo's option.gravity: they must be the same
        g_model = np.array(self.model.opt.gravity, dtype=float)
        disabled = bool(self.model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY)
        g_eff = np.zeros(3) if disabled else g_model
        if np.linalg.norm(g_eff - (0.0, 0.0, -water.gravity)) > 1e-9 * max(water.gravity, np.linalg.norm(g_eff)):
            shown = ", ".join(f"{c:.12g}" for c in g_model)
            raise ValueError(
                f"WaterColumn.gravity = {water.gravity:.12g} m/s^2 differs from the model's option.gravity "
                f"({shown}){' (disabled by option.disableflags: 0 in effect)' if disabled else ''}: buoyancy "
                "and weight would not balance; set one to the other")
        self.data = mujoco.MjData(self.model)
        self.tethers = {}
        for tm in tethers:
            if not isinstance(tm, TetherModel):
                raise ValueError("tethers must be TetherModel objects returned by add_tether")
            self.tethers[tm.name] = BoundTether(tm, self.model, self.data, water)
        self.bodies = []
        for bm in bodies:
            if isinstance(bm, VehicleModel):
                self.bodies.append(BoundVehicle(bm, self.model, water))
            elif isinstance(bm, BodyHydroModel):
                self.bodies.append(BoundBodyHydro(bm, self.model, water))
            else:
                raise ValueError("bodies must be BodyHydroModel or VehicleModel objects returned by add_body_hydro "
                                 "or add_vehicle")
        if warn_EA:
            for name, bt in self.tethers.items():
                _warn_soft(name, bt, float(self.model.opt.timestep))
        self._providers = [*self.tethers.values(), *self.bodies]
        self._buf = np.empty(mujoco.mj_stateSize(self.model, _STATE))
        self._eq_snapshot = self.data.eq_active.copy()
        self._eq_scratch = self.data.eq_active.copy()  # (``stepping``'s, for a redo)
        self._redone = np.zeros(1, dtype=np.int64)  # (see redone_steps)
        self._stepper = stepping.Stepper(self)
        for t in self.tethers.values():
            t.use_snapshot(self._eq_snapshot)
        # views of mjData's arrays that the per-step code reads (they never move)
        self._eq_active, self._qpos, self._qvel = self.data.eq_active, self.data.qpos, self.data.qvel
        self._tether_list = tuple(self.tethers.values())
        self._closed = False
        self._warnings = self.data.warning.number  # MuJoCo's warning counts (a live view)
        self._bad_acc0 = 0
        self._t_step = 0.0  # s, the time at the end of the step being taken
        self.revision = 0  # counts steps, forward() and restore_state(): what was read at one revision holds
        self._worst = []  # what was furthest out after the last step (see check)
        with dispatch.suspended():  # (the first call reads MuJoCo's structs from two small models)
            ok = native.available()
        tables = [p.native_table() for p in self._providers] if ok else [None]
        block = None
        if all(t is not None for t in tables):
            kinds = [native.TETHER] * len(self.tethers) + [native.VEHICLE if isinstance(b, BoundVehicle) else native.BODY
                                                           for b in self.bodies]
            writes = any(t._normal_prm is not None for t in self.tethers.values()) or \
                any(isinstance(b, BoundVehicle) for b in self.bodies)
            block = native.Block(list(zip(kinds, tables)), writes_model=writes)
        self.native = block is not None  # MuJoCo applies the loads itself, on any thread (``native``)
        dispatch.register(self.data, self._passive, self.model, block=block)
        try:
            mujoco.mj_forward(self.model, self.data)
            dispatch.raise_pending(self.data)
        except BaseException:  # a provider failed on the first state: leave nothing registered
            self.close()
            raise

    def _passive(self, m, d):
        for p in self._providers:
            p.apply(m, d)

    @property
    def time(self) -> float:
        return float(self.data.time)

    @property
    def timestep(self) -> float:
        return float(self.model.opt.timestep)

    @property
    def redone_steps(self) -> int:
        """MuJoCo steps taken again so far, with tether elements switched between taut and slack
        (``cable.slack``: where a push or an overshoot was worth it); each step counts once, the
        redone ones again (MuJoCo's steps = steps + this)."""
        return int(self._redone[0])

    def tether(self, name: str = "tether") -> BoundTether:
        return self.tethers[name]

    def forward(self) -> None:
        """Recompute forces and readouts for the current state without stepping."""
        self.revision += 1
        mujoco.mj_forward(self.model, self.data)
        self._eq_snapshot[:] = self.data.eq_active
        dispatch.raise_pending(self.data)

    def step(self, nstep: int = 1) -> None:
        """Advance ``nstep`` steps; raise ``SimulationDiverged`` if the state blows up, naming
        the time and what went first (see ``check``)."""
        if self._closed:
            raise RuntimeError("simulation is closed")
        if isinstance(nstep, bool) or not isinstance(nstep, (int, np.integer)) or nstep < 1:
            raise ValueError(f"Simulation.step nstep must be an integer >= 1, got {nstep!r}")
        saved = self.save_state() if nstep > 1 else None
        self._advance(nstep)
        dispatch.raise_pending(self.data)
        try:
            self.check()
        except SimulationDiverged:
            if saved is None:
                raise
            # find the step where it went, one step at a time from the saved state
            self.restore_state(saved)
            for _ in range(nstep):
                self._advance(1)
                dispatch.raise_pending(self.data)
                self.check()
            raise

    def _advance(self, nstep: int) -> None:
        """``nstep`` MuJoCo steps, switching slack tether elements after each and tracking
        every element's peak push (``BoundTether.take_peak_compression``) and its snap loads
        (``BoundTether.snaps``, where started): in compiled blocks where ``cable.stepping``
        can (``compiled_steps``), else in the Python loop here, which gives the same bits."""
        self.revision += 1
        if not self.tethers:
            self._t_step = self.data.time + self.model.opt.timestep
            mujoco.mj_step(self.model, self.data, nstep)
            return
        if stepping.usable(self):
            self._advance_compiled(nstep)
            return
        tethers = self._tether_list
        m, d, buf, spec = self.model, self.data, self._buf, _STATE
        snap, eq_active = self._eq_snapshot, self._eq_active
        dt = m.opt.timestep
        for _ in range(nstep):
            self._t_step = d.time + dt
            mujoco.mj_getState(m, d, buf, spec)
            mujoco.mj_step(m, d)
            snap[:] = eq_active
            changed = False
            for t in tethers:
                changed |= t.update_slack()
            redo = 0
            while changed:  # redo the step with the elements taut now (see update_slack)
                redo += 1
                self._redone[0] += 1
                active = d.eq_active.copy()
                mujoco.mj_setState(m, d, buf, spec)
                d.eq_active[:] = active
                mujoco.mj_step(m, d)
                snap[:] = d.eq_active
                if redo > SLACK_REDOS:
                    break
                changed = False
                for t in tethers:  # the last time round, only switch off elements that pushed
                    changed |= t.update_slack(taut=redo < SLACK_REDOS)
            for t in tethers:  # the pushes and snaps of the step as kept (BoundTether.take_peak_compression, .snaps)
                t.track_peak_compression()
                if t.readouts.snaps is not None:
                    t.track_snaps()

    def _advance_compiled(self, nstep: int) -> None:
        """``_advance``'s loop in compiled blocks (``cable.stepping``), back in Python only where
        a snap ended (to record it) or something failed."""
        while nstep > 0:
            done, self._t_step, status, which, code = self._stepper.advance(nstep, _STATE, SLACK_REDOS)
            nstep -= done
            if status == stepping.DONE:
                continue
            t = self._tether_list[which]
            if status == stepping.ROWS_MISSING:
                raise RuntimeError("tether tension is available after mj_forward/mj_step")
            if status == stepping.BAD_FORCE:
                t.snaps.took(code)
            for t in self._tether_list:  # (a snap ended on this tether, and maybe others, at this step)
                if t.snaps is not None and t.snaps._closing.any():
                    t.snaps.took(1)

    def save_state(self):
        """Everything needed to continue exactly from here (MuJoCo's integration state and the
        payout state and the snap detector of every tether); see ``restore_state``."""
        spec = mujoco.mjtState.mjSTATE_INTEGRATION
        buf = np.empty(mujoco.mj_stateSize(self.model, spec))
        mujoco.mj_getState(self.model, self.data, buf, spec)
        return buf, {k: (t.payout_state(), None if t.snaps is None else t.snaps.copy()) for k, t in self.tethers.items()}

    def restore_state(self, state) -> None:
        """Return to a ``save_state()``; readouts are valid after ``forward()`` or a step."""
        buf, payout = state
        self.revision += 1
        mujoco.mj_setState(self.model, self.data, buf, mujoco.mjtState.mjSTATE_INTEGRATION)
        for k, t in self.tethers.items():
            drum, snaps = payout[k]
            t.restore_payout(drum)
            t.clear_peak_compression()  # (the pushes tracked led elsewhere)
            t.readouts.snaps = None if snaps is None else snaps.copy()  # (the snaps found up to then)
        w = self.data.warning  # (MuJoCo's warning counts are not part of its state)
        self._bad_acc0 = w[_BADQPOS].number + w[_BADQVEL].number + w[_BADQACC].number

    def run(self, duration: float, callback=None, every: float | None = None) -> None:
        """Simulate ``duration`` seconds; call ``callback(sim)`` every ``every`` seconds."""
        dt = self.timestep
        try:
            x = math.nan if isinstance(duration, (str, bytes, bool, np.bool_)) else float(duration)
        except (TypeError, ValueError):
            x = math.nan
        if not 0.0 <= x <= MAX_RUN_S:
            raise ValueError(f"Simulation.run duration = {duration!r}: must be a number of seconds in [0, "
                             f"{MAX_RUN_S:g}] (0 runs nothing; it is rounded to whole steps of {dt:g} s)")
        if every is not None:
            _checks.positive("Simulation.run every", every, "s")
        n = int(round(x / dt))
        k = max(1, int(round((every or x) / dt))) if callback else n
        done = 0
        while done < n:
            m = min(k, n - done)
            self.step(m)
            done += m
            if callback:
                callback(self)

    def check(self) -> None:
        """Raise ``SimulationDiverged`` if the state has gone bad: MuJoCo's own check (a
        position, velocity or acceleration non-finite or above 1e10, after which it resets the
        state), a tether node faster than ``MAX_NODE_SPEED`` or an element stretched by more
        than ``MAX_STRAIN``. The message names the time, the tether element or MuJoCo degree of
        freedom, and the quantity."""
        d = self.data
        count = self._warnings  # (a view of the counts: cheaper than the list's items)
        bad = int(count[_BADQPOS]) + int(count[_BADQVEL]) + int(count[_BADQACC])
        if bad > self._bad_acc0 or not math.isfinite(self._qvel[0] + self._qpos[0]):
            w = d.warning
            self._bad_acc0 = bad
            what = []
            for code, q in ((_BADQPOS, "position"), (_BADQVEL, "velocity"), (_BADQACC, "acceleration")):
                if w[code].number:
                    what.append(f"{q} of {self._dof_name(int(w[code].lastinfo))}")
            # MuJoCo has reset the state (time too): report the step it went in, and what was
            # already furthest out in the last good state
            self._diverged(self._t_step, "MuJoCo found a non-finite or huge " + " and ".join(what)
                           + (f"; a step earlier {self._furthest()}" if self._worst else ""))
        worst = []
        qvel, ten_length = self._qvel, d.ten_length
        for name, t in self.tethers.items():
            k = t.first
            v = qvel[t._dof0 + 3 * k:t._dof0 + 3 * (t.n + 1)]
            if t._fast is not None:  # (kernels.tether_extremes: the same search)
                i, vmax, j, stretch = kernels.tether_extremes(v, ten_length[t.tadr + k:t.tadr + t.n], t._deployed_rest)
            else:
                i = int(np.argmax(np.abs(v)))
                vmax = abs(float(v[i]))
            if not vmax <= MAX_NODE_SPEED:  # (NaN too)
                self._diverged(d.time, f"{name} node {i // 3} (of {t.N + 1} deployed, 0 at the ship) moves at "
                                       f"{vmax:.3g} m/s")
            if t.spec.EA is not None:
                # stretch over the nominal element length (the drum element may be short)
                if t._fast is None:
                    s = ten_length[t.tadr + k:t.tadr + t.n] - t._deployed_rest
                    j = int(np.argmax(s))
                    stretch = float(s[j])
                strain = stretch / t.l0
                if strain > MAX_STRAIN:
                    self._diverged(d.time, f"{name} element {j} (0 at the ship) is stretched by "
                                           f"{100 * strain:.0f} % (EA {t.spec.EA:g} N)")
                worst.append((name, i // 3, vmax, j, strain))
            else:
                worst.append((name, i // 3, vmax, None, None))
        self._worst = worst  # formatted only if the next step fails (see _furthest)

    def _furthest(self) -> str:
        """What was furthest out after the last good step: each tether's fastest node and most
        stretched element."""
        out = []
        for name, i, vmax, j, strain in self._worst:
            out.append(f"{name} node {i} (0 at the ship) moved fastest, at {vmax:.3g} m/s")
            if j is not None:
                out.append(f"element {j} was the most stretched, by {100 * strain:.2g} %")
        return ", ".join(out)

    def _dof_name(self, dof: int) -> str:
        m = self.model
        if not 0 <= dof < m.nv:
            return "the state"
        body = int(m.dof_bodyid[dof])
        for name, t in self.tethers.items():
            hits = np.nonzero(t._bids == body)[0]
            if len(hits):
                return f"{name} node {int(hits[0]) - t.first} (0 at the ship)"
        return f"body {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, body) or body}"

    def _diverged(self, t: float, what: str) -> None:
        raise SimulationDiverged(
            f"simulation diverged at t = {t:.4f} s (time step {self.timestep:g} s): {what}; "
            "reduce the time step (see mjtether.cable.stability.max_timestep)")

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


class Driven(NamedTuple):
    """What ``drive`` did: the rows sampled (samples, columns) and the steps taken."""

    rows: np.ndarray
    steps: int


def drive(advance, total_steps: int, every: int, on_sample, *, clock, watches=(), video=None, progress=None,
          names=None) -> Driven:
    """The run loop of every system: step it ``total_steps`` times by ``advance(k)`` (k steps),
    sampling it by ``on_sample()`` (it records what its system keeps and returns the row of its
    time series) at the start, after every ``every`` steps and at the end: a run whose length is
    not a whole number of ``every`` ends with a shorter block and is sampled there, so that its
    results always hold its last state. At each sample every ``watches`` callable is called (all
    of them; each keeps its own events and why it stopped); where one returns True the run stops
    there, at the start too. ``video`` (``due(t)``, ``capture()``, as ``io.render.VideoRecorder``;
    finishing or aborting it is the caller's) takes a frame after the first step on or after each
    frame's time; the run then steps one step at a time, which gives the same bits as the blocks
    (``Simulation.step``). ``clock()`` is the simulated time (s); ``progress(done, total_steps)``
    is called at each sample after the first. Raises ``SimulationDiverged`` at the first sample
    with a non-finite value (naming its column, from ``names``, where given), as for any other
    divergence."""
    rows = [_finite(on_sample(), clock(), names)]
    stop = _stops(watches)
    if video is not None and video.due(clock()):
        video.capture()
    done = 0
    while done < total_steps and not stop:
        k = min(every, total_steps - done)
        if video is None:
            advance(k)
        else:
            for _ in range(k):
                advance(1)
                if video.due(clock()):
                    video.capture()
        done += k
        rows.append(_finite(on_sample(), clock(), names))
        stop = _stops(watches)
        if progress is not None:
            progress(done, total_steps)
    return Driven(np.array(rows), done)


def _stops(watches) -> bool:
    """Call every watch (none left out when an earlier one stops the run); True if one did."""
    return any([watch() for watch in watches])


def _finite(row, t: float, names):
    """``row`` if every value in it is finite, else ``SimulationDiverged`` naming the first that
    is not (its column in ``names``, else its index) and the time ``t`` (s)."""
    bad = np.flatnonzero(~np.isfinite(np.asarray(row, dtype=float)))
    if bad.size:
        i = int(bad[0])
        what = f"column {names[i]!r}" if names is not None and i < len(names) else f"column {i}"
        raise SimulationDiverged(f"simulation diverged at t = {t:.4f} s: a recorded value became non-finite "
                                 f"({what} = {np.asarray(row, dtype=float)[i]}, the first of {bad.size})")
    return row

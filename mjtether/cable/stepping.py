"""Many steps per Python call: ``Simulation``'s step loop compiled around MuJoCo's own ``mj_step``.

A tether's step is more than MuJoCo's: after each ``mj_step`` its tension-only elements are
switched between taut and slack (``cable.slack``), the step is redone where a push or an
overshoot was worth it, and the step as kept gives each element's running peak push
(``readouts.track_peak_compression``) and the snap detector its tensions (``cable.snap``). In
Python that work costs as much as MuJoCo's step of a short line. ``advance`` does all of it for
``nstep`` steps in one numba function that calls ``mj_step``, ``mj_getState`` and ``mj_setState``
through their symbols in MuJoCo's library (as ``native`` calls ``mj_applyFT``), with the same
compiled kernels (``cable.kernels.slack_switch``, ``peak_push``, ``snap_update``) in the same order
as the Python loop, so that the two give the same bits (``tests/cable/test_stepping.py``).

It returns to Python after ``nstep`` steps, or early, after a step that ended a snap (whose
event ``SnapDetector`` records in Python) or whose element rows are not all there (``RuntimeError``
in Python, as the per-step path raises).

**When it runs** (``usable``): the loads are ``native``'s compiled callback for every live
simulation (a Python callback's exception could not come back through compiled frames: MuJoCo
would end the process), every tether runs the compiled kernels, and MuJoCo's arena has used less
than half of its size so far (a ``mju_error`` inside a compiled block, such as a stack overflow,
ends the process with MuJoCo's message instead of raising; where the arena is that full the
Python loop steps, and raises). ``Simulation.compiled_steps = False`` steps in Python always.

Units SI; times in s.
"""

from __future__ import annotations

import ctypes
import warnings

import mujoco
import numpy as np

from mjtether.physics import compiled, dispatch, native

from . import kernels
from .slack import SLACK_TENSION

numba = compiled.numba
if numba is not None:
    from numba import types

    _mj_step = types.ExternalFunction("mj_step", types.void(types.voidptr, types.voidptr))
    _mj_get_state = types.ExternalFunction("mj_getState", types.void(
        types.voidptr, types.voidptr, types.voidptr, types.int32))
    _mj_set_state = types.ExternalFunction("mj_setState", types.void(
        types.voidptr, types.voidptr, types.voidptr, types.int32))
    _bool = native._cast(types.CPointer(types.boolean))
    _i32 = native._i32

_f64, _i64, _void = (native._f64, native._i64, native._void) if numba is not None else (None, None, None)

# A tether's table, by slot: (address, length) of each array
S_INT, S_REAL, S_REST, S_K, S_ROWS_BEFORE, S_PEAK, S_SLACK_AT, S_TAUT_AT, S_SLACK_NOW, S_SNAPPING, S_T_SLACK, \
    S_T_TAUT, S_SLACK_FOR, S_SNAP_PEAK, S_MIN, S_MAX, S_INTERVAL_MAX, S_CLOSING, S_TOP_MIN, S_CLOCK = range(20)
SLOTS = 20
# S_INT: eq0 (the first element's equality), n, tadr (its tendon), first deployed element, snaps (0/1)
# S_REAL: f_min (``SlackSwitch.f_min``, N), the snap window (s)

# what ``advance`` returns in its status
DONE, SNAPPED, ROWS_MISSING, BAD_FORCE = 0, 1, 2, 3

_OFFSETS: dict[str, int] = {}


def _probe(n_connect: int, n_friction: int) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """A small model and its ``mjData`` after ``mj_forward``, with 3 (``n_connect`` - 1) +
    ``n_friction`` constraint rows (so that its ``nefc`` differs from its equality rows ``ne`` and
    from the most it had, ``maxuse_efc``)."""
    bodies = "".join(f'<body pos="{i} 0 0"><joint type="hinge" frictionloss="1"/><geom size=".1" mass="1"/></body>'
                     for i in range(n_friction))
    bodies += "".join(f'<body name="c{i}" pos="0 {i + 1} 0"><freejoint/><geom size=".1" mass="1"/></body>'
                      for i in range(n_connect))
    eqs = "".join(f'<connect body1="c{i}" anchor="0 0 0"/>' for i in range(n_connect))
    m = mujoco.MjModel.from_xml_string(f"<mujoco><worldbody>{bodies}</worldbody><equality>{eqs}</equality></mujoco>")
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    d.eq_active[0] = 0  # (3 rows fewer now than the most so far, ``maxuse_efc``)
    mujoco.mj_forward(m, d)
    return m, d


def offsets() -> tuple[int, int]:
    """(word offset of mjData's ``efc_force`` pointer, byte offset of its ``nefc``), read once
    per process from two probe models: the pointer by ``native._scan``, ``nefc`` as the one
    place before that pointer where both structs hold their own ``nefc``. Raises RuntimeError
    where they are not found so (another MuJoCo's layout)."""
    if not _OFFSETS:
        found = []
        for nc, nf in ((2, 1), (3, 4)):
            m, d = _probe(nc, nf)
            efc = native._scan(d, ("efc_force",))[0]
            ints = np.frombuffer(ctypes.string_at(d._address, 8 * efc), dtype=np.int32)  # (the struct's head)
            found.append((efc, set(np.flatnonzero(ints == d.nefc).tolist())))
        common = found[0][1] & found[1][1]
        if found[0][0] != found[1][0] or len(common) != 1:
            raise RuntimeError("mjtether.cable.stepping: mjData's efc_force and nefc were not found consistently; "
                               "this MuJoCo is not supported by the compiled step loop")
        _OFFSETS["efc_force"], _OFFSETS["nefc"] = found[0][0], 4 * common.pop()
    return _OFFSETS["efc_force"], _OFFSETS["nefc"]


def _readable() -> bool:
    """Whether this MuJoCo's mjData could be read (``offsets``); else a warning says so, once,
    and the Python loop steps."""
    if "unreadable" in _OFFSETS:
        return False
    try:
        offsets()
    except RuntimeError as exc:
        _OFFSETS["unreadable"] = 1
        warnings.warn(f"{exc}; tethers are stepped in Python", RuntimeWarning, stacklevel=3)
        return False
    return True


def usable(sim) -> bool:
    """Whether ``advance`` may step ``sim`` (the module docstring's conditions)."""
    if not (sim.compiled_steps and sim.native and sim.tethers and dispatch.native_only() and _readable()):
        return False
    for t in sim._tether_list:
        if t._fast is None or (t.readouts.snaps is not None and not t.readouts.snaps.compiled):
            return False
    d = sim.data
    return 2 * (int(d.maxuse_arena) + int(d.maxuse_stack)) < int(sim.model.narena)


def tether_table(bt) -> tuple[np.ndarray, list]:
    """The table ``advance`` reads for the bound tether ``bt``: the addresses of its arrays as
    they are now, and those arrays (to keep alive while the table is used)."""
    L, dr, snaps = bt.layout, bt.drum, bt.readouts.snaps
    ints = np.array([L.eq0, L.n, L.tadr, dr.first, snaps is not None], dtype=np.int64)
    real = np.array([bt.switch.f_min, snaps.window_s if snaps is not None else 0.0])
    arrays = [ints, real, dr.rest, dr.K, L.rows_before, bt.readouts.peak]
    if snaps is not None:
        arrays += [snaps.slack_threshold_N, snaps.taut_threshold_N, snaps.slack_now, snaps._snapping, snaps._t_slack,
                   snaps._t_taut, snaps._slack_for, snaps._peak, snaps.min_tension_N, snaps.max_tension_N,
                   snaps.interval_max_N, snaps._closing, snaps._top_min, snaps._clock]
    table = np.zeros((SLOTS, 2), dtype=np.int64)
    for slot, a in enumerate(arrays):
        if not (isinstance(a, np.ndarray) and a.flags.c_contiguous and a.dtype in _DTYPES[slot]):
            raise TypeError(f"stepping table slot {slot}: a C-contiguous array of {_DTYPES[slot]} is needed")
        table[slot] = (a.ctypes.data if a.size else 0, a.size)
    return table, arrays


_DTYPES = {S_INT: (np.int64,), S_ROWS_BEFORE: (np.int64,), S_SLACK_NOW: (np.bool_,), S_SNAPPING: (np.bool_,),
           S_CLOSING: (np.bool_,)}
_DTYPES = [_DTYPES.get(slot, (np.float64,)) for slot in range(SLOTS)]


class Stepper:
    """``advance`` for one simulation, with its tethers' tables kept between calls (made again
    where a drum replaced an array, or a snap detector was started or restored)."""

    def __init__(self, sim):
        self.sim = sim
        self.calls = 0
        """Compiled blocks run so far (a diagnostic: 0 where the Python loop did all the steps)."""
        self._key = None
        self._tables = self._keep = None

    def _table(self) -> np.ndarray:
        ts = self.sim._tether_list
        key = tuple((id(t.drum.rest), id(t.drum.K), id(t.readouts.peak), id(t.readouts.snaps)) for t in ts)
        if key != self._key:
            made = [tether_table(t) for t in ts]
            self._tables, self._keep, self._key = np.stack([m[0] for m in made]), [m[1] for m in made], key
        for t, arrays in zip(ts, self._keep):
            arrays[S_INT][3] = t.drum.first  # (the drum releases nodes as it pays out)
        return self._tables

    def advance(self, nstep: int, state_spec, redos: int) -> tuple[int, float, int, int, int]:
        """Up to ``nstep`` steps as ``Simulation._advance`` takes them (saving and restoring
        MuJoCo's ``state_spec`` for a redo, at most ``redos`` + 1 of them), compiled: returns
        (steps taken, the time at the end of the last step as begun (s), status, the tether whose
        snaps or rows stopped the block early, else -1, and what its snap detector's kernel
        returned then); status ``DONE``, ``SNAPPED`` (a snap ended at the last step: record it,
        with ``SnapDetector.took``), ``ROWS_MISSING`` (an element's constraint row was missing
        after the last step) or ``BAD_FORCE`` (a non-finite element force reached the snap
        detector)."""
        efc, nefc = offsets()
        self.calls += 1
        sim = self.sim
        m, d = sim.model, sim.data
        words = native.offsets()
        done, t_step, status, which, closed = _advance(
            m._address, d._address, nstep, sim._buf, int(state_spec), d.eq_active, sim._eq_snapshot,
            sim._eq_scratch, d.ten_length, self._table(), efc, nefc, int(words[native.TIME]),
            int(words[native.TIMESTEP]), SLACK_TENSION, redos, sim._redone)
        return int(done), float(t_step), int(status), int(which), int(closed)


@compiled.jit
def _rows(snap, tab):
    """(first row, rows) of a tether's active element equalities (``SlackSwitch.element_rows``)."""
    I = _ints(tab, S_INT)
    eq0, n = I[0], I[1]
    before = _ints(tab, S_ROWS_BEFORE)
    r0 = 0
    for j in range(eq0):
        r0 += before[j] * snap[j]
    count = 0
    for e in range(eq0, eq0 + n):
        if snap[e]:
            count += 1
    return r0, count


@compiled.jit
def _switch(eq_active, snap, ten_length, f_all, tab, slack_tension, taut):
    """``SlackSwitch.update`` of one tether (its compiled branch); returns redo."""
    I, R = _ints(tab, S_INT), _vec(tab, S_REAL)
    eq0, n, tadr, first = I[0], I[1], I[2], I[3]
    r0, count = _rows(snap, tab)
    return kernels.slack_switch(eq_active[eq0:eq0 + n], f_all[r0:r0 + count], ten_length[tadr:tadr + n],
                                _vec(tab, S_REST), _vec(tab, S_K), first, R[0], slack_tension, taut,
                                count >= n - first)[1]


@compiled.jit
def _ints(table, slot):
    return numba.carray(_i64(table[slot, 0]), (table[slot, 1],))


@compiled.jit
def _vec(table, slot):
    return numba.carray(_f64(table[slot, 0]), (table[slot, 1],))


@compiled.jit
def _flags(table, slot):
    return numba.carray(_bool(table[slot, 0]), (table[slot, 1],))


@compiled.jit
def _advance(mp, dp, nstep, buf, spec, eq_active, snap, scratch, ten_length, tables, efc, nefc_at, time_at,
             timestep_at, slack_tension, redos, redone):
    """The loop of ``advance`` (``Simulation._advance``'s, step for step); ``time_at``,
    ``timestep_at``: the words of mjData's ``time`` and mjModel's ``opt.timestep``; ``redone``
    (1,) counts the steps redone."""
    m, d = _void(mp), _void(dp)
    state = _void(buf.ctypes.data)
    clock = numba.carray(_f64(dp + 8 * time_at), (1,))
    dt = numba.carray(_f64(mp + 8 * timestep_at), (1,))
    nt = tables.shape[0]
    t_step = 0.0
    for s in range(nstep):
        t_step = clock[0] + dt[0]
        _mj_get_state(m, d, state, spec)
        _mj_step(m, d)
        snap[:] = eq_active
        f_all = _efc(dp, efc, nefc_at)
        redo = False
        for i in range(nt):
            redo |= _switch(eq_active, snap, ten_length, f_all, tables[i], slack_tension, True)
        r = 0
        while redo:  # redo the step with the elements taut now (``Simulation._advance``)
            r += 1
            redone[0] += 1
            scratch[:] = eq_active
            _mj_set_state(m, d, state, spec)
            eq_active[:] = scratch
            _mj_step(m, d)
            snap[:] = eq_active
            f_all = _efc(dp, efc, nefc_at)
            if r > redos:
                break
            redo = False
            for i in range(nt):
                redo |= _switch(eq_active, snap, ten_length, f_all, tables[i], slack_tension, r < redos)
        t = clock[0]
        status, which, code = DONE, -1, 0
        for i in range(nt):  # the pushes and snaps of the step as kept
            tab = tables[i]
            I = _ints(tab, S_INT)
            eq0, n, first = I[0], I[1], I[3]
            r0, count = _rows(snap, tab)
            if r0 + count > f_all.shape[0]:
                return s + 1, t_step, ROWS_MISSING, i, 0
            act, f = snap[eq0:eq0 + n], f_all[r0:r0 + count]
            kernels.peak_push(_vec(tab, S_PEAK), act, f, first)
            if I[4] and t > _vec(tab, S_CLOCK)[0]:
                _vec(tab, S_CLOCK)[0] = t
                R = _vec(tab, S_REAL)
                closed = kernels.snap_update(
                    t, act, f, first, _vec(tab, S_SLACK_AT), _vec(tab, S_TAUT_AT), R[1], _flags(tab, S_SLACK_NOW),
                    _flags(tab, S_SNAPPING), _vec(tab, S_T_SLACK), _vec(tab, S_T_TAUT), _vec(tab, S_SLACK_FOR),
                    _vec(tab, S_SNAP_PEAK), _vec(tab, S_MIN), _vec(tab, S_MAX), _vec(tab, S_INTERVAL_MAX),
                    _flags(tab, S_CLOSING), _vec(tab, S_TOP_MIN))
                if closed < 0:
                    return s + 1, t_step, BAD_FORCE, i, closed
                if closed > 0 and status == DONE:
                    status, which, code = SNAPPED, i, closed
        if status != DONE:
            return s + 1, t_step, status, which, code
    return nstep, t_step, DONE, -1, 0


@compiled.jit
def _efc(dp, efc, nefc_at):
    """mjData's ``efc_force`` now (its arena moves it), ``nefc`` long."""
    nefc = numba.carray(_i32(dp + nefc_at), (1,))[0]
    return numba.carray(_f64(numba.carray(_i64(dp + 8 * efc), (1,))[0]), (nefc,))

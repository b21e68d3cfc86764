"""Batched open-loop rollouts of a ``Simulation``'s model with its hydrodynamics, on threads.

``mujoco.rollout`` steps MuJoCo alone, on worker threads: the tether, rigid-body and vehicle
loads apply there because the simulation's callback is native (``mjtether.physics.native``). What
``Simulation`` does *between* steps in Python does not happen in a rollout, so a rollout is
the simulation's own run only while that is idle:

* slack switching: each element stays taut (a two-sided equality, which may push) or slack as it
  is at the start. ``rollout`` checks the returned states and warns, naming the first step and
  element, where a taut element was shorter than its rest length (it pushed) or a slack one
  longer (it would have pulled);
* payout: the deployed length is the simulation's now, the winch does not turn;
* controllers: ``control`` is open loop (MuJoCo's ``ctrl``, per step).

A model whose callback turns tendons in the model (the normal added mass, a vehicle's added
mass) gets one registered copy per rollout, so that threads never share what it writes.
"""

from __future__ import annotations

import copy
import warnings

import mujoco
import numpy as np
from mujoco import rollout as _mj_rollout

from mjtether.physics import native

from .simulation import Simulation

STATE = mujoco.mjtState.mjSTATE_FULLPHYSICS
"""The state a rollout starts from and returns (``mujoco.rollout``'s)."""


def initial_state(sim: Simulation) -> np.ndarray:
    """The simulation's state now, as ``rollout`` takes it (``STATE``)."""
    s = np.empty(mujoco.mj_stateSize(sim.model, STATE))
    mujoco.mj_getState(sim.model, sim.data, s, STATE)
    return s


def rollout(sim: Simulation, initial_state, control=None, nstep: int | None = None, nthread: int = 1):
    """Roll out ``sim``'s model from each of ``initial_state`` (nbatch x nstate, ``STATE``) under
    ``control`` (nbatch or 1 x nstep x nu, MuJoCo's ctrl) on ``nthread`` threads; returns the
    states (nbatch x nstep x nstate) and sensor data as ``mujoco.rollout`` does.

    Raises ValueError where the loads cannot apply on MuJoCo's threads (the simulation's loads
    run in Python: the NumPy kernels, or a profile or hull the compiled kernels do not know) or
    where the model has state a rollout does not carry (seabed friction's stick points)."""
    if not isinstance(sim, Simulation):
        raise ValueError(f"sim must be a Simulation, got {type(sim).__name__}")
    if not (isinstance(nthread, (int, np.integer)) and 1 <= nthread <= 256):
        raise ValueError(f"nthread must be an integer from 1 to 256, got {nthread!r}")
    if not sim.native:
        raise ValueError("rollout: this simulation's loads run in Python (the NumPy kernels, MJTETHER_KERNELS="
                         "numpy, or a water profile or hull class the compiled kernels do not know), which "
                         "MuJoCo's rollout threads cannot call: it would run in vacuum")
    for name, t in sim.tethers.items():
        if t._seabed is not None:
            raise ValueError(f"rollout: tether {name!r} has seabed friction, whose stick points (data.userdata) "
                             "are state that mujoco.rollout does not carry; step it with Simulation.run")
    if sim._closed:
        raise ValueError("rollout: the simulation is closed")
    size = mujoco.mj_stateSize(sim.model, STATE)
    try:
        s0 = np.atleast_2d(np.asarray(initial_state, dtype=float))
    except (TypeError, ValueError):
        raise ValueError(f"initial_state must be numbers, shape (nbatch, {size}) (rollouts.initial_state gives one), "
                         f"got {type(initial_state).__name__}") from None
    if s0.ndim != 2 or s0.shape[1] != size or len(s0) == 0 or not np.all(np.isfinite(s0)):
        raise ValueError(f"initial_state must be finite, shape (nbatch >= 1, {size}) (rollouts.initial_state gives "
                         f"one), got shape {s0.shape}" + ("" if np.all(np.isfinite(s0)) else " with NaN or inf"))
    nbatch = len(s0)
    writes = native._blocks[sim.model._address].writes_model
    models = [copy.copy(sim.model) for _ in range(nbatch)] if writes else sim.model
    if writes:
        for m in models:
            native.register_copy(m, sim.model)
    try:
        # copies of the simulation's data: its equalities' activity (which elements are slack,
        # which drum node holds the cable) is not part of a rollout's state, and stays as it is
        datas = [copy.copy(sim.data) for _ in range(nthread)]
        if nthread == 1:
            states, sensors = _mj_rollout.rollout(models, datas[0], s0, control, nstep=nstep)
        else:
            with _mj_rollout.Rollout(nthread=nthread) as r:
                states, sensors = r.rollout(models, datas, s0, control, nstep=nstep)
    finally:
        if writes:
            for m in models:
                native.unregister(m)
    _warn_if_switched(sim, states)
    return states, sensors


def _warn_if_switched(sim: Simulation, states: np.ndarray) -> None:
    """Warn where a rollout's taut element was shorter than its rest length (it pushed), or a
    slack one longer (it would have pulled): where a Simulation would have switched it."""
    q0 = 1  # STATE's layout: time, then qpos
    for name, t in sim.tethers.items():
        k, n = t.first, t.n
        q = states[..., q0 + t.layout.q0 + 3 * k:q0 + t.layout.q0 + 3 * (n + 1)] + t.layout.body0[3 * k:]
        x = q.reshape(*q.shape[:-1], n - k + 1, 3)
        strain = np.linalg.norm(np.diff(x, axis=-2), axis=-1) / t._deployed_rest - 1.0
        taut = sim.data.eq_active[t._eqs][k:].astype(bool)
        wrong = np.where(taut, strain < -1e-6, strain > 1e-6)
        if wrong.any():
            b, step, j = (int(i[0]) for i in np.nonzero(wrong))
            what = ("taut, and shorter than its rest length: it pushed" if taut[j] else
                    "slack, and longer than its rest length: it would have pulled")
            warnings.warn(f"rollout: tether {name!r} element {j} (0 at the ship) was {what}, at step {step + 1} of "
                          f"rollout {b}; a Simulation switches such elements, a rollout cannot",
                          RuntimeWarning, stacklevel=3)

"""One ``mjcb_passive`` callback per process, dispatching to per-simulation force providers.

MuJoCo has a single global passive-force callback slot. Every ``MjData`` that mjtether
simulates registers its providers here under the address of its ``MjData``; the installed
callback looks them up, so two simulations in one process (a ``SyncVectorEnv``, two tests)
never see each other's forces. ``unregister`` removes them when a simulation closes.
mjtether owns the slot: a callback that other code installed is replaced.

A Python exception inside a MuJoCo callback cannot propagate through ``mj_step``; it is
stored here and re-raised by ``raise_pending`` right after the step.

An ``MjData`` that no simulation registered, of a model that one did (``mujoco.rollout``'s, or
one made by hand), would step with no hydrodynamic force at all: a cable in vacuum. That is
refused: on the main thread the callback raises (MuJoCo passes it on as the step's error); on a
rollout's worker thread, where an exception would bring the process down, it warns and makes
the passive forces NaN, so the rollout's states come back NaN rather than plausible and wrong.
Rollouts with hydrodynamics are not supported yet.
"""

from __future__ import annotations

import contextlib
import threading
import warnings
from typing import Callable

import mujoco

Provider = Callable[[mujoco.MjModel, mujoco.MjData], None]

_providers: dict[int, list[Provider]] = {}
_errors: dict[int, BaseException] = {}
_models: dict[int, int] = {}  # model address -> how many registered MjData use it
_owner: dict[int, int] = {}  # registered MjData address -> its model's address

UNOWNED = ("mjtether: MuJoCo asked for the passive forces of an MjData that no mjtether Simulation owns "
           "(mujoco.rollout's, or one made by hand), of a model with tether or vehicle hydrodynamics: "
           "it would run with none (a cable in vacuum). Step it through its Simulation (step, run); "
           "rollouts with hydrodynamics are not supported yet.")


def _passive(m: mujoco.MjModel, d: mujoco.MjData) -> None:
    fns = _providers.get(d._address)
    if fns is None:
        if m._address in _models:  # an unowned MjData of one of our models: refuse, never run in vacuum
            if threading.current_thread() is threading.main_thread():
                raise RuntimeError(UNOWNED)
            warnings.warn(UNOWNED, RuntimeWarning, stacklevel=1)
            d.qfrc_passive[:] = float("nan")
        return
    try:
        for fn in fns:
            fn(m, d)
    except BaseException as exc:  # noqa: BLE001 - re-raised after mj_step
        _errors.setdefault(d._address, exc)


def _ensure_installed() -> None:
    # (Re)install on every registration: cheap, and it wins back the slot if other code
    # replaced it. The binding wraps the function anew on each get, so identity tests fail.
    mujoco.set_mjcb_passive(_passive)


def register(data: mujoco.MjData, provider: Provider, model: mujoco.MjModel | None = None) -> None:
    """Apply ``provider(model, data)`` whenever MuJoCo computes passive forces for ``data``;
    with ``model``, any other ``MjData`` of that model is refused (the module docstring)."""
    _ensure_installed()
    if data._address not in _providers and model is not None:
        _models[model._address] = _models.get(model._address, 0) + 1
        _owner[data._address] = model._address
    _providers.setdefault(data._address, []).append(provider)


def unregister(data: mujoco.MjData) -> None:
    """Remove every provider of ``data``; free the slot when none is left."""
    _providers.pop(data._address, None)
    _errors.pop(data._address, None)
    m = _owner.pop(data._address, None)
    if m is not None:
        _models[m] -= 1
        if _models[m] <= 0:
            del _models[m]
    if not _providers:
        mujoco.set_mjcb_passive(None)


@contextlib.contextmanager
def suspended():
    """Free the slot while MuJoCo compiles a model.

    Compiling runs the pipeline on an ``mjData`` that Python does not know, and the binding
    then fails the callback ("engine error: Python exception raised"). Compile inside this
    block (``Simulation`` and ``add_tether`` do) while other simulations are live.
    """
    mujoco.set_mjcb_passive(None)
    try:
        yield
    finally:
        if _providers:
            mujoco.set_mjcb_passive(_passive)


def compile_spec(spec: mujoco.MjSpec) -> mujoco.MjModel:
    """``spec.compile()`` safe to call while simulations are live."""
    with suspended(), warnings.catch_warnings():
        # the tether's flex is geometry only (its elements are tendons, see builder)
        warnings.filterwarnings("ignore", message="flex .* is not rigid and has no equality constraints")
        return spec.compile()


def raise_pending(data: mujoco.MjData) -> None:
    """Re-raise an exception a provider of ``data`` raised inside the callback."""
    exc = _errors.pop(data._address, None)
    if exc is not None:
        raise exc


def active_count() -> int:
    """Number of ``MjData`` with registered providers (for tests and diagnostics)."""
    return len(_providers)

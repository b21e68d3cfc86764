"""One ``mjcb_passive`` callback per process, dispatching to per-simulation force providers.

MuJoCo has a single global passive-force callback slot; mjtether owns it (a callback other
code installed is replaced). A simulation registers its ``MjData`` here in one of two ways:

* **native** (the default where numba runs): its loads are a force block of ``native``, keyed
  by its model; while every live simulation is native, the installed callback is
  ``native``'s compiled one, which MuJoCo calls itself on any thread. Every ``MjData`` of the
  model gets the loads, ``mujoco.rollout``'s worker threads' too, except where the loads write
  to the model (a vehicle, the normal added mass): there only the simulation's own (see
  ``native``; ``rollouts`` rolls such models out on copies).
* **Python** (the NumPy reference kernels, or a provider the compiled kernels do not cover): a
  Python function called for its ``MjData``. While any such simulation is live the installed
  callback is ``_passive`` here, which runs the Python providers and the native blocks.

A Python exception inside a MuJoCo callback cannot propagate through ``mj_step``; it is
stored here and re-raised by ``raise_pending`` right after the step.

An ``MjData`` that no simulation registered, of a model whose forces are Python, would step with
no hydrodynamic force at all: a cable in vacuum. That is refused: on the main thread the
callback raises (MuJoCo passes it on as the step's error); on a rollout's worker thread, where
an exception would bring the process down, it warns and makes the passive forces NaN, so the
rollout's states come back NaN rather than plausible and wrong.
"""

from __future__ import annotations

import contextlib
import threading
import warnings
from typing import Callable

import mujoco

from mjtether.physics import actuation, native

Provider = Callable[[mujoco.MjModel, mujoco.MjData], None]

_providers: dict[int, list[Provider]] = {}
_errors: dict[int, BaseException] = {}
_models: dict[int, int] = {}  # model address -> how many registered MjData use it
_owner: dict[int, int] = {}  # registered MjData address -> its model's address
_native: dict[int, mujoco.MjModel] = {}  # registered MjData address -> its natively forced model

UNOWNED = ("mjtether: MuJoCo asked for the passive forces of an MjData that no mjtether Simulation owns "
           "(mujoco.rollout's, or one made by hand), of a model whose hydrodynamics run in Python (the "
           "NumPy kernels, MJTETHER_KERNELS=numpy, or a water profile or hull the compiled kernels do not "
           "know): it would run with none (a cable in vacuum). Step it through its Simulation (step, run), "
           "or use the compiled kernels, whose forces apply on any thread (mjtether.rollouts).")


def _passive(m: mujoco.MjModel, d: mujoco.MjData) -> None:
    if native.is_registered(m):
        native.apply(m, d)
        return
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


def _install() -> None:
    """Install the callback the live simulations need (see the module docstring), or none.
    Done on every registration: cheap, and it wins back the slot if other code replaced it."""
    if any(a not in _native for a in _providers):
        mujoco.set_mjcb_passive(_passive)
    elif _native:
        mujoco.set_mjcb_passive(native.callback())
    else:
        mujoco.set_mjcb_passive(None)


def register(data: mujoco.MjData, provider: Provider, model: mujoco.MjModel | None = None,
             block: native.Block | None = None) -> None:
    """Apply ``provider(model, data)`` whenever MuJoCo computes passive forces for ``data``;
    with ``model``, any other ``MjData`` of that model is refused (the module docstring). With
    ``block`` (a ``native.Block``) the forces are the block's, for every ``MjData`` of ``model``,
    and ``provider`` is not called."""
    if block is not None:
        if model is None:
            raise ValueError("a native force block needs its model")
        with suspended():  # (finding the struct offsets compiles two small models)
            native.offsets()
            native.callback()
        native.register(model, block, owner=data)
        _native[data._address] = model
        _providers[data._address] = [provider]
        _install()
        return
    if data._address not in _providers and model is not None:
        _models[model._address] = _models.get(model._address, 0) + 1
        _owner[data._address] = model._address
    _providers.setdefault(data._address, []).append(provider)
    _install()


def unregister(data: mujoco.MjData) -> None:
    """Remove every provider of ``data``; free the slot when none is left."""
    _providers.pop(data._address, None)
    _errors.pop(data._address, None)
    forced = _native.pop(data._address, None)
    if forced is not None:
        native.unregister(forced)
    m = _owner.pop(data._address, None)
    if m is not None:
        _models[m] -= 1
        if _models[m] <= 0:
            del _models[m]
    _install()


@contextlib.contextmanager
def suspended():
    """Free the slots (``mjcb_passive``, and ``actuation``'s ``mjcb_act_dyn``) while MuJoCo
    compiles a model.

    Compiling runs the pipeline on an ``mjData`` that Python does not know, and the binding
    then fails the callback ("engine error: Python exception raised"). Compile inside this
    block (``Simulation`` and ``add_tether`` do) while other simulations are live.
    """
    mujoco.set_mjcb_passive(None)
    actuation.release()
    try:
        yield
    finally:
        _install()
        actuation.reinstall()


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


def native_only() -> bool:
    """Whether the installed passive-force callback is ``native``'s compiled one (every live
    simulation's loads are native): no Python runs inside ``mj_step``, so compiled code may call
    it (``stepping``)."""
    return bool(_native) and all(a in _native for a in _providers)


def active_count() -> int:
    """Number of ``MjData`` with registered providers (for tests and diagnostics)."""
    return len(_providers)

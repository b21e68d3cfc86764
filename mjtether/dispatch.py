"""One ``mjcb_passive`` callback per process, dispatching to per-simulation force providers.

MuJoCo has a single global passive-force callback slot. Every ``MjData`` that mjtether
simulates registers its providers here under the address of its ``MjData``; the installed
callback looks them up, so two simulations in one process (a ``SyncVectorEnv``, two tests)
never see each other's forces. ``unregister`` removes them when a simulation closes.

A Python exception inside a MuJoCo callback cannot propagate through ``mj_step``; it is
stored here and re-raised by ``raise_pending`` right after the step.
"""

from __future__ import annotations

from typing import Callable

import mujoco

Provider = Callable[[mujoco.MjModel, mujoco.MjData], None]

_providers: dict[int, list[Provider]] = {}
_errors: dict[int, BaseException] = {}
_previous = None  # a callback somebody else installed before us


def _passive(m: mujoco.MjModel, d: mujoco.MjData) -> None:
    fns = _providers.get(d._address)
    if fns is None:
        if _previous is not None:
            _previous(m, d)
        return
    try:
        for fn in fns:
            fn(m, d)
    except BaseException as exc:  # noqa: BLE001 - re-raised after mj_step
        _errors.setdefault(d._address, exc)


def _ensure_installed() -> None:
    global _previous
    current = mujoco.get_mjcb_passive()
    if current is _passive:
        return
    _previous = current
    mujoco.set_mjcb_passive(_passive)


def register(data: mujoco.MjData, provider: Provider) -> None:
    """Apply ``provider(model, data)`` whenever MuJoCo computes passive forces for ``data``."""
    _ensure_installed()
    _providers.setdefault(data._address, []).append(provider)


def unregister(data: mujoco.MjData) -> None:
    """Remove every provider of ``data``."""
    _providers.pop(data._address, None)
    _errors.pop(data._address, None)


def raise_pending(data: mujoco.MjData) -> None:
    """Re-raise an exception a provider of ``data`` raised inside the callback."""
    exc = _errors.pop(data._address, None)
    if exc is not None:
        raise exc


def active_count() -> int:
    """Number of ``MjData`` with registered providers (for tests and diagnostics)."""
    return len(_providers)

"""MuJoCo's warnings as Python warnings, never as a ``MUJOCO_LOG.TXT`` in the working folder.

Left alone, MuJoCo's default log handler prints each engine warning (``Nan, Inf or huge value
in QACC``, ``nefc overflow``...) to stderr and appends it to ``MUJOCO_LOG.TXT`` in the current
folder. ``install()``, called when ``mjtether`` is imported, sets the warning callback of the
Python bindings (``mujoco.set_mju_user_warning``, the legacy ``mju_user_warning`` hook, which
MuJoCo calls instead of its default handler) so that each warning is issued as a
``MujocoWarning`` (a ``RuntimeWarning``) through :mod:`warnings`, or, with
``install(route="logging")``, logged at WARNING level on the logger ``mjtether.mujoco``.
Either way nothing is written to a file, and the usual tools apply: ``warnings.filterwarnings``,
``pytest.warns``, ``logging.captureWarnings``.

Why this hook: MuJoCo 4's own handler API (``mju_setLogHandler``) is not exposed to Python; its
configuration (``mujoco.MjLogConfig``: ``logto_file``, ``logto_console``, ``logfile``) can stop
the file but still prints to the C stderr, out of Python's reach. ``mju_writeLog`` only writes
to the file. Engine *errors* need nothing here: the bindings raise them as Python exceptions.

A warning callback must never raise (an exception thrown through MuJoCo's C code aborts the
process), so a warning that a filter turns into an error (``-W error``) is logged on
``mjtether.mujoco`` instead of raised.

``install`` leaves a callback that someone else set (``mujoco.get_mju_user_warning()`` is not
None) in place, unless ``force=True``; ``uninstall`` restores what ``install`` replaced.
"""

from __future__ import annotations

import logging
import warnings

import mujoco

__all__ = ["MujocoWarning", "install", "installed", "uninstall"]

logger = logging.getLogger("mjtether.mujoco")


class MujocoWarning(RuntimeWarning):
    """A warning from the MuJoCo engine (the text is MuJoCo's)."""


_installed: str | None = None  # the route of the installed callback, None if not ours
_previous = None  # the callback that install(force=True) replaced


def _to_warnings(msg: str) -> None:
    try:
        # stacklevel 2: the Python line that called into MuJoCo (mj_step, mj_forward...)
        warnings.warn(msg, MujocoWarning, stacklevel=2)
    except BaseException:  # noqa: BLE001 - raising through MuJoCo's C code aborts the process
        logger.warning("%s", msg)


def _to_logging(msg: str) -> None:
    try:
        logger.warning("%s", msg)
    except BaseException:  # noqa: BLE001 - as above
        pass


def install(route: str = "warnings", force: bool = False) -> bool:
    """Route MuJoCo's warnings to ``warnings`` (as ``MujocoWarning``) or to ``logging``
    (logger ``mjtether.mujoco``), so that MuJoCo writes no ``MUJOCO_LOG.TXT``.

    Does nothing, and returns False, if a warning callback that mjtether did not install is
    set, unless ``force``. Returns True if mjtether's callback is installed on return."""
    global _installed, _previous
    if route not in ("warnings", "logging"):
        raise ValueError(f"mjlog.install: route must be 'warnings' or 'logging', got {route!r}")
    current = mujoco.get_mju_user_warning()
    if current is not None and _installed is None:
        if not force:
            return False
        _previous = current
    mujoco.set_mju_user_warning(_to_warnings if route == "warnings" else _to_logging)
    _installed = route
    return True


def uninstall() -> None:
    """Remove mjtether's callback, restoring the one ``install(force=True)`` replaced (or
    MuJoCo's default handler, which writes ``MUJOCO_LOG.TXT``)."""
    global _installed, _previous
    if _installed is None:
        return
    mujoco.set_mju_user_warning(_previous)
    _installed, _previous = None, None


def installed() -> str | None:
    """The route of mjtether's installed callback ("warnings" or "logging"), or None."""
    return _installed

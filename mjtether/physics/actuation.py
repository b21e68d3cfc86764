"""Linear actuator responses as MuJoCo activation dynamics, through the one ``mjcb_act_dyn`` of
the process.

A thruster whose delivered thrust follows the thrust asked for through a transfer function
K(s) = b(s) / a(s) of order n = 1 to 3 (von Benzon et al. 2022's BlueROV2 thrusters, their
Eq. 19, are third order) is a MuJoCo actuator with ``dyntype="user"`` and ``actdim = n``. Its n
activations are the states of K(s)'s zero-order-hold discretisation for the model's time step,
in the observer form whose last state is the output: the thrust delivered is the actuator's last
activation, the one MuJoCo's gain multiplies. As with MuJoCo's own ``filterexact``, the thrust at
each step is exactly K(s)'s response to the command held over each step before it.

MuJoCo integrates activations by Euler's rule, act += dt act_dot; the callback returns the
act_dot that makes that rule the exact step, (x_next - x) / dt. The model carries all it needs
in the actuator's ``dynprm`` (``response_parameters``)::

    [n, dt, lo, hi, a_0 .. a_{n-1}, b_0 .. b_{n-1}]

the order; the step it is discretised for (s); the command's range (MuJoCo clamps ``ctrl`` to
``ctrlrange`` for the actuator's force, but the callback reads it as set, so it clamps it
itself); and the discrete K(z) = (b_{n-1} z^{n-1} + ... + b_0) / (z^n + a_{n-1} z^{n-1} + ... +
a_0). An actuator stepped at another time step than its ``dt`` (or whose ``dynprm`` is not of
this layout) gets NaN activations, which the run's divergence check reports:
``set_response`` re-discretises it (``vehicle.Vehicle`` does, for the model it is given).

The callback is process-wide. mjtether installs it when it builds such an actuator
(``install``) and leaves it installed: the compiled one (``native.act_dyn_callback``), which
MuJoCo calls itself on any thread (``mujoco.rollout``'s too), where numba runs; else the Python
one here. MuJoCo calls it for ``dyntype="user"`` actuators only. Like the Python passive-force
callback, the Python one fails a ``spec.compile()`` of such a model (MuJoCo runs the pipeline on
an ``mjData`` the bindings do not know): compile with ``dispatch.compile_spec``, which frees both
slots while it compiles (``Simulation`` does).

Units SI; the time step in s.
"""

from __future__ import annotations

import mujoco
import numpy as np
from scipy import signal

from mjtether.physics import compiled

ORDER_MAX = 3
"""The highest order of a response: 4 + 2 n numbers must fit MuJoCo's 10 ``dynprm``."""


def check_response(field: str, numerator, denominator) -> tuple[np.ndarray, np.ndarray]:
    """The transfer function numerator(s) / denominator(s) (coefficients from the highest power
    of s down), checked: finite, of order 1 to ``ORDER_MAX``, strictly proper (no instant thrust:
    the thrust delivered is a state), stable, and of unit gain at rest. Returns the numerator and
    denominator scaled so that the denominator is monic; errors name ``field``."""
    try:
        num = np.atleast_1d(np.asarray(numerator, dtype=float))
        den = np.atleast_1d(np.asarray(denominator, dtype=float))
    except (TypeError, ValueError):
        raise ValueError(f"{field}: numerator and denominator must be lists of numbers") from None
    if num.ndim != 1 or den.ndim != 1 or not (np.all(np.isfinite(num)) and np.all(np.isfinite(den))):
        raise ValueError(f"{field}: numerator and denominator must be lists of finite numbers")
    num = np.trim_zeros(num, "f")
    den = np.trim_zeros(den, "f")
    n = len(den) - 1
    if not 1 <= n <= ORDER_MAX:
        raise ValueError(f"{field}: the denominator's order must be 1 to {ORDER_MAX}, got {max(n, 0)}")
    if len(num) == 0 or len(num) > n:
        raise ValueError(f"{field}: the numerator's order must be 0 to {n - 1} (strictly proper: the thrust delivered "
                         f"cannot jump with the command), got {len(num) - 1}")
    num, den = num / den[0], den / den[0]
    poles = np.roots(den)
    if np.any(poles.real >= 0.0):
        raise ValueError(f"{field}: every pole must have a negative real part (a stable response), got "
                         f"{', '.join(f'{p:.4g}' for p in poles)} 1/s")
    gain = num[-1] / den[-1]
    if abs(gain - 1.0) > 1e-9:
        raise ValueError(f"{field}: the gain at rest K(0) = numerator(0) / denominator(0) must be 1 (a thrust asked "
                         f"for long enough is delivered), got {gain:.9g}")
    return num, den


def response_parameters(numerator, denominator, ctrlrange, dt: float) -> np.ndarray:
    """The actuator's ``dynprm`` (10 numbers, the module docstring) for the response
    numerator(s) / denominator(s), commands clamped to ``ctrlrange`` (lo, hi), at time step
    ``dt`` (s)."""
    num, den = check_response("response", numerator, denominator)
    if not (np.isfinite(dt) and dt > 0.0):
        raise ValueError(f"response: the time step must be > 0 s, got {dt}")
    n = len(den) - 1
    ad, bd, cd, dd, _ = signal.cont2discrete(signal.tf2ss(num, den), dt, method="zoh")
    bz, az = signal.ss2tf(ad, bd, cd, dd)  # az = [1, a_{n-1}, ..., a_0]; bz[0] = [~0, b_{n-1}, ..., b_0]
    prm = np.zeros(10)
    prm[:4] = (n, dt, ctrlrange[0], ctrlrange[1])
    prm[4:4 + n] = az[1:][::-1]
    prm[4 + n:4 + 2 * n] = np.asarray(bz)[0, 1:][::-1]
    return prm


@compiled.jit
def response_act_dot(prm, x, u, dt, out) -> None:
    """``out[:] =`` the activation rate that carries the states ``x`` (the actuator's
    activations) over one Euler step of ``dt`` (s, the model's) to their exact next value under
    the command ``u`` held over the step, for ``dynprm`` ``prm`` (the module docstring); NaN where
    ``prm`` is for another step or another order than ``x``'s. Compiled (``compiled.jit``; the
    native callback inlines it), so that ``jitcache`` stamps this module's source."""
    n = int(prm[0])
    if n < 1 or n > ORDER_MAX or n != x.shape[0] or prm[1] != dt:
        for i in range(x.shape[0]):
            out[i] = np.nan
        return
    u = min(max(u, prm[2]), prm[3])
    y = x[n - 1]
    before = 0.0
    for i in range(n):
        nxt = before - prm[4 + i] * y + prm[4 + n + i] * u
        before = x[i]
        out[i] = (nxt - x[i]) / dt


def _act_dyn(m: mujoco.MjModel, d: mujoco.MjData, i: int) -> float:
    """The Python ``mjcb_act_dyn`` (where the native one cannot run)."""
    adr, k = int(m.actuator_actadr[i]), int(m.actuator_actnum[i])
    out = np.empty(k)
    response_act_dot(m.actuator_dynprm[i], d.act[adr:adr + k], float(d.ctrl[i]), m.opt.timestep, out)
    d.act_dot[adr:adr + k] = out
    return float(out[-1])


_installed: list = []  # the callback installed (kept alive here), once one is


def install() -> None:
    """Install the process's ``mjcb_act_dyn`` (the module docstring); cheap after the first call."""
    from mjtether.physics import dispatch, native

    with dispatch.suspended():  # (the native check compiles two small probe models the first time)
        cb = native.act_dyn_callback() if native.available() else _act_dyn
    _installed[:] = [cb]
    mujoco.set_mjcb_act_dyn(cb)


def release() -> None:
    """Free the slot while MuJoCo compiles (``dispatch.suspended``), if mjtether holds it: a
    callback other code installed is left alone."""
    if _installed:
        mujoco.set_mjcb_act_dyn(None)


def reinstall() -> None:
    """Put back the callback ``install`` installed, if any (after ``release``)."""
    if _installed:
        mujoco.set_mjcb_act_dyn(_installed[0])


def set_response(model: mujoco.MjModel, actuator: int, numerator, denominator) -> None:
    """Discretise actuator ``actuator``'s response for ``model``'s time step, in place, keeping
    its command range."""
    lo, hi = model.actuator_ctrlrange[actuator]
    model.actuator_dynprm[actuator] = response_parameters(numerator, denominator, (lo, hi), model.opt.timestep)
    install()


def delivered(model: mujoco.MjModel, actuator) -> np.ndarray:
    """The index in ``data.act`` of each actuator's output (its last activation: the thrust a
    thruster delivers, a fin's angle), for one actuator id or an array of them."""
    a = np.asarray(actuator)
    return model.actuator_actadr[a] + model.actuator_actnum[a] - 1

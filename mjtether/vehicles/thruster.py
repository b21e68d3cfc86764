"""Propeller thrusters as MuJoCo actuators: a force along a site's x axis on the hull, with a
first-order (or a transfer function's) response and asymmetric saturation, and the thrust
curve that turns a control voltage into the thrust asked of it (dead zone, different forward
and reverse maxima).

The actuator's control is the thrust wanted (N); MuJoCo clips it to [-max_reverse, max_forward]
(``ctrlrange``) and lags it by ``time_constant`` (its ``filterexact`` activation is the thrust
delivered), or, where the thruster gives a ``response`` (a transfer function from thrust asked
to thrust delivered, e.g. von Benzon et al.'s 2022 third-order K(s)), passes it through that
(``physics.actuation``: the activation's last element is the thrust delivered). A
``ThrustCurve`` gives that control from a command voltage as the thruster tests of Hong et al.
(2020, J. Mar. Sci. Eng. 8, 485) measure it: no thrust inside a dead zone, linear beyond it up
to the forward and reverse maxima.

Units SI (thrust N; the papers' kgf are converted at the edges); body frame x forward, y left,
z up.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from mjtether import _checks
from mjtether.physics import actuation

KGF = 9.80665
"""Newtons per kilogram-force."""

MAX_POLE = 1.0e4
"""The fastest pole a thruster's ``response`` may have (1/s): a time constant of 0.1 ms, shorter
than any time step a vehicle runs at and about 100 times faster than von Benzon et al.'s T200
(its fastest poles 90.9 1/s). Faster ones are not a thruster's, and their discretisation overflows
(a pole of 1e300 1/s gave a LinAlgError)."""
MAX_NUMERATOR = 1.0e15
"""The largest numerator coefficient (SI, the denominator scaled to lead with 1) of a ``response``:
the benchmark's largest is 1.087e5; K(0) = 1 makes the last one the denominator's, at most
MAX_POLE^3 = 1e12 for a third order, and 1e15 leaves the others a thousand times that."""


@dataclass(frozen=True)
class ThrustCurve:
    """Thrust (N) against control voltage (V): zero between ``dead_low`` and ``dead_high``,
    rising linearly to ``max_forward`` at ``v_max`` and to ``-max_reverse`` at ``v_min``
    (Hong et al. 2020 linearise their measured curves so)."""

    v_min: float
    dead_low: float
    dead_high: float
    v_max: float
    max_forward: float  # N
    max_reverse: float  # N, > 0: the largest thrust backwards

    def __post_init__(self):
        if not (self.v_min < self.dead_low <= self.dead_high < self.v_max):
            raise ValueError(f"thrust curve voltages must satisfy v_min < dead_low <= dead_high < v_max, got "
                             f"{self.v_min}, {self.dead_low}, {self.dead_high}, {self.v_max} V")
        _checks.positive("thrust curve max_forward", self.max_forward, "N")
        _checks.positive("thrust curve max_reverse", self.max_reverse, "N")

    def thrust(self, voltage) -> np.ndarray:
        """Thrust (N) for ``voltage`` (V), clipped to the curve's range."""
        v = np.clip(np.asarray(voltage, dtype=float), self.v_min, self.v_max)
        fwd = self.max_forward * (v - self.dead_high) / (self.v_max - self.dead_high)
        rev = -self.max_reverse * (self.dead_low - v) / (self.dead_low - self.v_min)
        return np.where(v > self.dead_high, fwd, np.where(v < self.dead_low, rev, 0.0))


@dataclass(frozen=True)
class Thruster:
    """A thruster on a hull: its thrust acts at ``position`` (m, body frame) along the unit
    ``direction`` (body frame); at most ``max_forward`` N forwards and ``max_reverse`` N
    backwards; the delivered thrust follows the command with ``time_constant`` (s, a first-order
    lag; 0.1 s where neither it nor ``response`` is given), or through ``response``: a
    transfer function K(s) = numerator(s) / denominator(s) (coefficients from the highest power
    of s down, SI), strictly proper, stable, of order 1 to 3 and unit gain at rest (a thrust
    asked for long enough is delivered). Give one of the two."""

    name: str
    position: tuple
    direction: tuple
    max_forward: float
    max_reverse: float
    time_constant: float | None = None
    response: tuple | None = None  # (numerator, denominator); a TOML table {numerator, denominator}

    def __post_init__(self):
        _checks.text("thruster.name", self.name)
        object.__setattr__(self, "position", tuple(_checks.vector3(f"{self.name}.position", self.position)))
        d = np.asarray(_checks.vector3(f"{self.name}.direction", self.direction))
        if np.linalg.norm(d) < 1e-9:
            raise ValueError(f"{self.name}.direction must not be zero")
        object.__setattr__(self, "direction", tuple(d / np.linalg.norm(d)))
        _checks.positive(f"{self.name}.max_forward", self.max_forward, "N")
        _checks.non_negative(f"{self.name}.max_reverse", self.max_reverse, "N")
        if self.response is None:
            tau = 0.1 if self.time_constant is None else self.time_constant
            _checks.positive(f"{self.name}.time_constant", tau, "s")
            object.__setattr__(self, "time_constant", float(tau))
            return
        if self.time_constant is not None:
            raise ValueError(f"{self.name}: give time_constant (a first-order lag) or response (a transfer "
                             "function), not both")
        r = self.response
        if isinstance(r, dict):
            extra = set(r) - {"numerator", "denominator"}
            if extra or len(r) != 2:
                raise ValueError(f"{self.name}.response must be a table of numerator and denominator (coefficients "
                                 f"from the highest power of s down), got keys {sorted(r)}")
            r = (r["numerator"], r["denominator"])
        if not (isinstance(r, (tuple, list)) and len(r) == 2):
            raise ValueError(f"{self.name}.response must be a table of numerator and denominator (coefficients from "
                             f"the highest power of s down), got {r!r}")
        num, den = _check_response(f"{self.name}.response", *r)
        object.__setattr__(self, "response", (tuple(map(float, num)), tuple(map(float, den))))


def _check_response(field: str, numerator, denominator):
    """``actuation.check_response``, with text and booleans refused as coefficients (NumPy reads
    ``true`` as 1 and ``"6136"`` as 6136) and the poles and numerator within ``MAX_POLE`` and
    ``MAX_NUMERATOR``."""
    for part, coefficients in (("numerator", numerator), ("denominator", denominator)):
        if isinstance(coefficients, (str, bytes)) or _checks._has_flag_or_text(coefficients):
            raise ValueError(f"{field}.{part} = {coefficients!r}: must be a list of finite numbers (coefficients "
                             "from the highest power of s down)")
    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            num, den = actuation.check_response(field, numerator, denominator)
    except np.linalg.LinAlgError:  # (coefficients so far apart that scaling the denominator overflows)
        num = den = np.array([np.inf])
    with np.errstate(over="ignore", invalid="ignore"):
        poles = np.roots(den) if np.all(np.isfinite(den)) else np.array([np.inf])
    fastest = float(np.max(np.abs(poles)))
    if not fastest <= MAX_POLE:
        raise ValueError(f"{field}: every pole must be within {MAX_POLE:g} 1/s (a time constant of at least "
                         f"{1e3 / MAX_POLE:g} ms), got one of {fastest:.4g} 1/s")
    if not np.max(np.abs(num)) <= MAX_NUMERATOR:
        raise ValueError(f"{field}: the numerator's coefficients (the denominator scaled to lead with 1) must be "
                         f"within [-{MAX_NUMERATOR:g}, {MAX_NUMERATOR:g}], got {np.max(np.abs(num)):.4g}")
    return num, den


def add_thruster(spec: mujoco.MjSpec, body: str, th: Thruster) -> str:
    """Add ``th`` to the body named ``body``: a site ``{body}/{th.name}`` whose x axis is the
    thrust direction, and an actuator of the same name (control: thrust wanted, N). A thruster with
    a ``response`` is discretised for the spec's time step as it is now (``physics.actuation``;
    ``vehicle.Vehicle`` re-discretises it for the compiled model's). Returns the actuator's name."""
    b = spec.body(body)
    if b is None:
        raise ValueError(f"add_thruster: no body named {body!r} in the spec")
    name = f"{body}/{th.name}"
    x = np.asarray(th.direction)
    # a site frame whose x axis is the direction: the shortest rotation from (1, 0, 0)
    quat = np.zeros(4)
    axis = np.cross([1.0, 0.0, 0.0], x)
    s, c = np.linalg.norm(axis), float(x[0])
    if s < 1e-12:
        quat[:] = [1.0, 0.0, 0.0, 0.0] if c > 0 else [0.0, 0.0, 0.0, 1.0]
    else:
        mujoco.mju_axisAngle2Quat(quat, axis / s, float(np.arctan2(s, c)))
    b.add_site(name=name, pos=list(th.position), quat=list(quat), size=[0.02, 0.0, 0.0])
    a = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_SITE)
    a.gear = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    if th.response is None:
        a.dyntype = mujoco.mjtDyn.mjDYN_FILTEREXACT
        a.dynprm[0] = th.time_constant
    else:
        a.dyntype = mujoco.mjtDyn.mjDYN_USER
        a.actdim = len(th.response[1]) - 1
        a.dynprm = list(actuation.response_parameters(*th.response, (-th.max_reverse, th.max_forward),
                                                      spec.option.timestep))
        actuation.install()
    a.gaintype = mujoco.mjtGain.mjGAIN_FIXED
    a.gainprm[0] = 1.0
    a.biastype = mujoco.mjtBias.mjBIAS_NONE
    a.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
    a.ctrlrange = [-th.max_reverse, th.max_forward]
    return name

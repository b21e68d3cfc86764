"""A vehicle's propeller: thrust and torque from its shaft speed and the water's inflow, and the
MuJoCo actuator that holds the shaft speed.

Open-water curves linear in the advance ratio J = V_a / (n D) between J = 0 and ``ja_max``, as
Fossen (2021) fits the Wageningen B-series for his REMUS 100 model:

    T = rho D^4 (KT_0 |n| n + (KT_max - KT_0) / J_max (V_a / D) |n|),    n > 0,
    T = rho D^4 KT_0 |n| n,                                               n <= 0,

and the torque Q alike with KQ; n in revolutions per second, V_a = (1 - w) u_r the inflow (w the
wake fraction; u_r the surge speed through the water, where Fossen uses the speed over ground:
the same in still water). The hull is pushed by (1 - t) T along the shaft (t the thrust
deduction) at ``position``, and rolled by ``torque_scale`` Q.

The actuator (``{body}/{name}``) takes the commanded shaft speed (rpm), clipped to
+-``max_rpm``, and lags it with ``time_constant`` (its ``filterexact`` activation is the shaft
speed); it makes no force itself: ``vehicle.BoundVehicle`` applies the thrust.

Units SI except shaft speeds (rpm at the edges); body frame x forward, y left, z up.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco

from mjtether import _checks


@dataclass(frozen=True)
class Propeller:
    """A propeller on the hull's axis, pushing along +x: ``position`` (m, body), ``diameter``
    (m), open-water coefficients ``kt0``, ``kt_max``, ``kq0``, ``kq_max`` at J = 0 and
    J = ``ja_max``, ``thrust_deduction`` t, ``wake_fraction`` w, ``max_rpm``, the shaft's
    ``time_constant`` (s) and the share ``torque_scale`` of the torque that rolls the hull."""

    name: str
    position: tuple
    diameter: float
    kt0: float
    kt_max: float
    ja_max: float
    kq0: float = 0.0
    kq_max: float = 0.0
    thrust_deduction: float = 0.0
    wake_fraction: float = 0.0
    max_rpm: float = 1000.0
    time_constant: float = 1.0
    torque_scale: float = 1.0

    def __post_init__(self):
        _checks.text("propeller.name", self.name)
        object.__setattr__(self, "position", tuple(_checks.vector3(f"{self.name}.position", self.position)))
        for key, unit in (("diameter", "m"), ("kt0", ""), ("ja_max", ""), ("max_rpm", "rpm"),
                          ("time_constant", "s")):
            _checks.positive(f"{self.name}.{key}", getattr(self, key), unit)
        for key in ("kt_max", "kq0", "kq_max", "torque_scale"):
            _checks.non_negative(f"{self.name}.{key}", getattr(self, key), "")
        for key in ("thrust_deduction", "wake_fraction"):
            v = getattr(self, key)
            if not (0.0 <= v < 1.0):
                raise ValueError(f"{self.name}.{key} must be in [0, 1), got {v!r}")

    def thrust(self, rpm: float, u_r: float, rho: float) -> tuple[float, float]:
        """(thrust on the hull (1 - t) T (N, along +x), torque Q (N m)) at shaft speed ``rpm``
        and surge speed through the water ``u_r`` (m/s)."""
        n = rpm / 60.0
        D = self.diameter
        if n > 0.0:
            j = (1.0 - self.wake_fraction) * u_r / D * abs(n) / self.ja_max
            T = rho * D ** 4 * (self.kt0 * n * n + (self.kt_max - self.kt0) * j)
            Q = rho * D ** 5 * (self.kq0 * n * n + (self.kq_max - self.kq0) * j)
        else:
            T = rho * D ** 4 * self.kt0 * abs(n) * n
            Q = rho * D ** 5 * self.kq0 * abs(n) * n
        return (1.0 - self.thrust_deduction) * T, self.torque_scale * Q

    def bollard_thrust(self, rho: float = 1025.0) -> float:
        """Thrust on the hull (N) at ``max_rpm`` with no inflow."""
        return self.thrust(self.max_rpm, 0.0, rho)[0]

    def rpm_for(self, thrust: float, u_r: float, rho: float) -> float:
        """The shaft speed (rpm) giving ``thrust`` (N on the hull) at ``u_r`` (m/s), within
        +-``max_rpm``: the inverse of ``thrust`` (a quadratic in n)."""
        D, t = self.diameter, self.thrust_deduction
        T = thrust / (1.0 - t) / (rho * D ** 4)
        if T > 0.0:  # kt0 n^2 + b n - T = 0, b = (kt_max - kt0) (1 - w) u_r / (D ja_max)
            b = (self.kt_max - self.kt0) * (1.0 - self.wake_fraction) * u_r / (D * self.ja_max)
            n = (-b + (b * b + 4.0 * self.kt0 * T) ** 0.5) / (2.0 * self.kt0)
        else:
            n = -((-T / self.kt0) ** 0.5)
        return max(-self.max_rpm, min(self.max_rpm, 60.0 * n))


def add_propeller(spec: mujoco.MjSpec, body: str, prop: Propeller) -> str:
    """Add ``prop`` to the body named ``body``: a site ``{body}/{prop.name}`` and an actuator of
    the same name whose control is the commanded shaft speed (rpm) and whose activation is the
    shaft speed (no force of its own). Returns the actuator's name."""
    b = spec.body(body)
    if b is None:
        raise ValueError(f"add_propeller: no body named {body!r} in the spec")
    name = f"{body}/{prop.name}"
    b.add_site(name=name, pos=list(prop.position), size=[0.02, 0.0, 0.0])
    a = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_SITE)
    a.dyntype = mujoco.mjtDyn.mjDYN_FILTEREXACT
    a.dynprm[0] = prop.time_constant
    a.gaintype = mujoco.mjtGain.mjGAIN_FIXED
    a.gainprm[0] = 0.0
    a.biastype = mujoco.mjtBias.mjBIAS_NONE
    a.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
    a.ctrlrange = [-prop.max_rpm, prop.max_rpm]
    return name

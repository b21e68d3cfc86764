"""A pinned body (``Body(kind="pinned")``, a ball joint at its pin) swinging as a compound
pendulum in water, against the closed form; its added mass acts at the body's origin and so adds
Ca rho V r^2 to the inertia about the pin (``rigidbody.BoundBodyHydro``)."""

import math

import numpy as np
import pytest

from mjtether.network import Body, Network
from mjtether.network import run as netrun

M, V, CA, RHO, G = 100.0, 0.05, 1.0, 1025.0, 9.80665  # kg, m^3, -, kg/m^3, m/s^2
I_OWN, R = 2.0, 2.0  # kg m^2 about the body's origin; m from the pin down to the origin
THETA0 = 5.0  # deg, released at rest


def _swing(ca: float) -> tuple[np.ndarray, np.ndarray]:
    """The body hung R below its pin 20 m down, released THETA0 from the vertical (turned about
    the pin, in the y-z plane), no drag; its origin's y (m) every 0.01 s for 45 s."""
    th = math.radians(THETA0)
    pin = np.array([0.0, 0.0, -20.0])
    body = Body("bob", "pinned", tuple(pin + [0.0, R * math.sin(th), -R * math.cos(th)]), rpy_deg=(THETA0, 0.0, 0.0),
                mass=M, inertia=(I_OWN,) * 3, volume=V, ca=(ca,) * 3, pin=(0.0, 0.0, R))
    net = Network("pendulum", {}, {}, (), bodies={"bob": body}, depth=100.0, rho=RHO, gravity=G, duration=45.0,
                  output_interval=0.01, start="as_written", timestep=0.001)
    r, rows = netrun.simulate(net)
    r.sim.close()
    cols = netrun.columns(net)
    return rows[:, 0], rows[:, cols.index("bodybob_y_m")]


@pytest.mark.parametrize("ca", [0.0, CA])
def test_a_pinned_body_swings_with_the_compound_pendulum_period(ca):
    """T = 2 pi sqrt((I + (m + Ca rho V) R^2) / ((m - rho V) g R)) (1 + theta0^2 / 16): the
    compound pendulum with the added mass moving with the origin, at 5 degrees (the amplitude's
    correction, 4.8e-4, is in the formula). With Ca = 1 the added mass is half the inertia about
    the pin, so an added mass left out or put on the wrong axis misses by 20 % or more.
    Tolerance 0.1 %: the period is measured from 16 or more zero crossings at 1 ms steps, whose
    phase error is (w dt)^2 / 24 ~ 1e-6 (measured 1.1e-7 and 1.4e-7)."""
    t, y = _swing(ca)
    i = np.flatnonzero(np.sign(y[1:]) != np.sign(y[:-1]))
    cross = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    period = 2.0 * float(np.mean(np.diff(cross)))
    inertia = I_OWN + (M + ca * RHO * V) * R * R
    expected = 2 * math.pi * math.sqrt(inertia / ((M - RHO * V) * G * R)) * (1 + math.radians(THETA0) ** 2 / 16)
    assert len(cross) >= 16
    assert period == pytest.approx(expected, rel=1e-3), (period, expected)

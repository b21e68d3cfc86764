"""Heave compensation: the active drive's residual heave and the passive spring-damper's stroke,
against closed forms.

The heave is z = A sin(w t), A = 1.5 m, period 8 s, sampled at dt = 1/256 s (w dt = 0.003)."""

import math

import numpy as np
import pytest

from mjtether.cable.heave_compensation import ActiveHeaveCompensation, PassiveHeaveCompensation

A, W, DT = 1.5, 2 * math.pi / 8, 1.0 / 256


def drive(comp, seconds):
    """Run ``comp`` on the heave for ``seconds``: (times, residuals, offsets, rates)."""
    out = []
    for k in range(1, int(round(seconds / DT)) + 1):
        t = k * DT
        rate = comp.update(t, DT, (A * math.sin(W * t), A * W * math.cos(W * t)))
        out.append((t, comp.residual, comp.length, rate))
    return tuple(np.array(c) for c in zip(*out))


def test_no_lag_no_limits_follows_the_heave_exactly():
    """With no lag and no limits the offset is the heave itself at every update: residual 0
    (to 1e-12 m, round-off), and the payout rate the heave's finite difference."""
    t, res, length, rate = drive(ActiveHeaveCompensation(), 24.0)
    assert np.abs(res).max() < 1e-12
    np.testing.assert_allclose(length, A * np.sin(W * t), atol=1e-12)
    np.testing.assert_allclose(rate[1:], np.diff(A * np.sin(W * t)) / DT, atol=1e-9)


def test_a_rate_limit_below_the_peak_heave_velocity():
    """Rate limit r = 0.7 A w (rho = 0.7). The drive falls behind where the heave's speed
    exceeds r, moves at r, and catches up before the next such spell (rho > 2/sqrt(pi^2 + 4)).
    Closed form, alpha = arccos(rho): from rest at t = 0 the residual A sin(w t) - r t peaks at
    w t = alpha, at R = A (sqrt(1 - rho^2) - rho alpha); in steady state each spell runs over
    2 alpha / w about a heave extreme's velocity peak, and the residual peaks at 2 R. Tolerance
    1e-4 relative: the sampling's O(w dt)^2 and the deadbeat step's O(r dt) at the catch-up."""
    rho = 0.7
    alpha = math.acos(rho)
    R = A * (math.sqrt(1 - rho ** 2) - rho * alpha)
    t, res, _, _ = drive(ActiveHeaveCompensation(max_rate=rho * A * W), 40.0)
    first = t < 4.0  # the first half period
    assert res[first].max() == pytest.approx(R, rel=1e-4)
    assert t[first][np.argmax(res[first])] == pytest.approx(alpha / W, abs=2 * DT)
    steady = t > 16.0
    assert res[steady].max() == pytest.approx(2 * R, rel=1e-4)  # on the rise and on the fall
    assert -res[steady].min() == pytest.approx(2 * R, rel=1e-4)
    # and it is back on the heave (to round-off) before the next spell, which begins where the
    # heave's speed passes r again, at phase pi - alpha (mod pi)
    phase = np.mod(W * t[steady], math.pi)
    before = (phase > math.pi - alpha - 0.1) & (phase < math.pi - alpha - 0.01)
    assert before.sum() > 100 and np.abs(res[steady][before]).max() < 1e-12


@pytest.mark.parametrize("lag_steps", [1, 77, 256])
def test_a_pure_delay_leaves_two_a_sin_half_w_tau(lag_steps):
    """A pure delay tau = lag_steps dt: the offset is the heave tau ago, the residual
    A sin(w t) - A sin(w (t - tau)) = 2 A sin(w tau / 2) cos(w (t - tau / 2)), amplitude
    2 A sin(w tau / 2) (closed form). tau is a whole number of steps, so the delayed sample is
    a stored one: to 1e-12 m after the first tau."""
    tau = lag_steps * DT
    t, res, _, _ = drive(ActiveHeaveCompensation(lag_s=tau), 16.0)
    on = t >= DT + tau
    want = 2 * A * math.sin(W * tau / 2) * np.cos(W * (t - tau / 2))
    np.testing.assert_allclose(res[on], want[on], atol=1e-12)
    assert np.abs(res[on]).max() == pytest.approx(2 * A * math.sin(W * tau / 2), rel=1e-4)


def test_a_delay_between_samples_is_interpolated():
    """tau = 0.3 s (76.8 steps): the delayed heave is interpolated linearly between samples, off
    by at most A (w dt)^2 / 8 from the exact delay: so is the residual against its closed form."""
    tau = 0.3
    t, res, _, _ = drive(ActiveHeaveCompensation(lag_s=tau), 16.0)
    on = t >= DT + tau
    want = 2 * A * math.sin(W * tau / 2) * np.cos(W * (t - tau / 2))
    assert np.abs(res[on] - want[on]).max() <= A * (W * DT) ** 2 / 8 * 1.01


def test_a_first_order_lag():
    """A first-order lag of time constant tau = 0.5 s on the measurement: the residual is the
    heave through 1 - 1 / (1 + i w tau), of amplitude A w tau / sqrt(1 + (w tau)^2) (closed form)
    once the start's transient (e^(-t / tau)) has gone. The lag is integrated exactly for a
    linearly varying heave: 1e-6 relative (the O(w dt)^2 of the samples' straight lines)."""
    tau = 0.5
    t, res, _, _ = drive(ActiveHeaveCompensation(lag_s=tau, lag="first_order"), 40.0)
    amp = A * W * tau / math.sqrt(1 + (W * tau) ** 2)
    assert np.abs(res[t > 24.0]).max() == pytest.approx(amp, rel=1e-6)


def test_an_acceleration_limit_above_the_heaves_settles_on_it():
    """Limits at twice the heave's peak velocity (A w) and acceleration (A w^2): the drive,
    starting at rest while the heave moves at A w, lags at first, then follows the heave exactly
    (residual to 1e-9 m after two periods: the ideal, 0, since the heave is within the limits)."""
    comp = ActiveHeaveCompensation(max_rate=2 * A * W, max_accel=2 * A * W ** 2)
    t, res, _, rate = drive(comp, 32.0)
    assert np.abs(res[t < 2.0]).max() > 0.05  # (the start's lag)
    assert np.abs(res[t > 16.0]).max() < 1e-9


def test_passive_spring_damper_transmissibility():
    """A spring-damper (k 2e4 N/m, c 5e3 N s/m) preloaded to 10 kN, under T = 10 kN + F sin(w t)
    (F 3 kN, period 6 s): after 10 time constants (c / k = 0.25 s) the stroke's amplitude is
    F / |k + i c w| and it lags the tension by atan(c w / k) (closed form). Tolerances: 1e-4
    relative on the amplitude, 0.005 rad on the phase (the tension is held through each step:
    a dt / 2 = 0.002 s delay, 0.002 rad)."""
    k, c, F, w = 2e4, 5e3, 3e3, 2 * math.pi / 6
    comp = PassiveHeaveCompensation(k, c, preload_N=1e4)
    ts = np.arange(1, int(36 / DT) + 1) * DT
    x = np.array([(comp.update(t, DT, 1e4 + F * math.sin(w * t)), comp.length)[1] for t in ts])
    late = ts > 12.0  # two periods, after 48 time constants
    amp = F / abs(k + 1j * c * w)
    assert np.abs(x[late]).max() == pytest.approx(amp, rel=1e-4)
    # phase from the projection on sin and cos over whole periods
    s, co = (2 * np.mean(x[late] * f(w * ts[late])) for f in (np.sin, np.cos))
    assert -math.atan2(co, s) == pytest.approx(math.atan(c * w / k), abs=0.005)


def test_passive_without_damping_is_hookes_law_and_the_stroke_is_limited():
    """c = 0: the stroke is (T - preload) / k at once; a stroke of 0.4 m caps it at +-0.2 m."""
    comp = PassiveHeaveCompensation(1e4, preload_N=5e3, stroke_m=0.4)
    comp.update(0.1, 0.1, 6e3, heave=0.5)
    assert comp.length == pytest.approx(0.1) and comp.residual == pytest.approx(0.4)
    assert comp.rate == pytest.approx(1.0)
    comp.update(0.2, 0.1, 1e4)
    assert comp.length == pytest.approx(0.2)
    comp.update(0.3, 0.1, 0.0)
    assert comp.length == pytest.approx(-0.2)


def test_bad_input_names_the_field():
    with pytest.raises(ValueError, match="lag must be one of delay, first_order"):
        ActiveHeaveCompensation(lag="pid")
    with pytest.raises(ValueError, match="lag_s must be >= 0 s"):
        ActiveHeaveCompensation(lag_s=-1.0)
    with pytest.raises(ValueError, match="max_rate must be > 0 m/s"):
        ActiveHeaveCompensation(max_rate=0.0)
    with pytest.raises(ValueError, match="gain must be in"):
        ActiveHeaveCompensation(gain=3.0)
    with pytest.raises(ValueError, match="stiffness must be > 0 N/m"):
        PassiveHeaveCompensation(0.0)
    comp = ActiveHeaveCompensation()
    with pytest.raises(ValueError, match="measured heave must be a finite number"):
        comp.update(0.0, 0.1, (math.nan, 0.0))
    with pytest.raises(ValueError, match=r"measured must be \(heave m, heave velocity m/s\)"):
        comp.update(0.0, 0.1, 0.5)
    comp.update(0.0, 0.1, (0.0, 0.0))
    with pytest.raises(ValueError, match="later than"):
        comp.update(0.0, 0.1, (0.0, 0.0))
    with pytest.raises(ValueError, match="dt must be > 0 s"):
        comp.update(1.0, 0.0, (0.0, 0.0))

"""The Gauss-Markov current in a run (``[water.current.gauss_markov]``, Hong et al. 2020 Sec. 2.4.3
after Fossen; ``physics.gauss_markov``, ``scenario.weather``): the current the water column gives
at each step of a long run against the process's closed form, and every provider of the run
reading that one current."""

import math

import numpy as np
import pytest

from mjtether.physics.gauss_markov import GaussMarkovCurrent
from mjtether.scenario import ConfigError, load_scenario, weather
from mjtether.scenario.runner import ScenarioRun

MU, STD, MEAN = 16.0, 0.1, 0.5  # 1/s, m/s, m/s
H_MEAN, H_STD = 45.0, 10.0  # deg
DT, STEPS = 0.02, 40000

ALONE = """
[simulation]
duration = {duration}
timestep = {dt}
output_interval = 1.0
[water]
depth = 50.0
[water.current]
speed = {mean}
heading_deg = {heading}
[water.current.gauss_markov]
{gm}
[tether]
attached = false
[robot]
type = "vehicle"
vehicle = "hong2020_usv"
position = [0.0, 0.0, 0.0]
setpoints = [[0.0, 0.0, 0.0, 0.0]]
"""


def _gm(**kw) -> str:
    return "".join(f"{k} = {v!r}\n" for k, v in kw.items())


def test_a_long_runs_current_has_the_closed_form_mean_and_variance():
    """40,000 steps of 0.02 s (800 s) of a run whose current's speed and direction are
    Gauss-Markov processes (mu = 16 1/s each; stationary standard deviations 0.1 m/s and 10 deg,
    sigma = std sqrt(2 mu); saturated 5 standard deviations out): the sample mean and variance of
    the surface current's speed and direction, read from the water column after each step, against
    the closed form (mean m, variance sigma^2 / (2 mu)), within 5 %.

    Why 5 % is honest here: consecutive samples correlate by rho = e^{-mu dt} = 0.726, so the
    standard error of the sample mean is sqrt(var / N (1 + rho) / (1 - rho)): 0.25 % of 0.5 m/s and
    0.28 % of 45 deg; that of the sample variance is var sqrt(2 / N (1 + rho^2) / (1 - rho^2)):
    1.27 %. The 5 % is 3.9 of those standard errors for the variance (20 for the means); the run
    starts at the mean, which biases the variance by about 1 / (mu N dt) = 0.008 %. The current is
    the same at depth (uniform), and the speed's saturation is not reached in 1e-3 of the samples
    (the closed form is the unsaturated process's)."""
    gm = _gm(mu=MU, sigma=STD * math.sqrt(2 * MU), v_min=0.0, v_max=MEAN + 5 * STD, heading_mu=MU,
             heading_sigma_deg=H_STD * math.sqrt(2 * MU), heading_min_deg=H_MEAN - 50.0,
             heading_max_deg=H_MEAN + 50.0, seed=7)
    run = ScenarioRun(load_scenario(text=ALONE.format(duration=STEPS * DT, dt=DT, mean=MEAN, heading=H_MEAN, gm=gm)))
    try:
        weather.attach(run)
        run.release_pilot()
        z = np.array([0.0, -40.0])
        u = np.empty((STEPS, 2, 3))
        for k in range(STEPS):
            run.step()
            u[k] = run.water.velocity(z)
    finally:
        run.close()
    assert np.array_equal(u[:, 0], u[:, 1])
    speed = np.hypot(u[:, 0, 0], u[:, 0, 1])
    heading = np.degrees(np.arctan2(u[:, 0, 1], u[:, 0, 0]))
    rho = math.exp(-MU * DT)
    se_var = math.sqrt(2 / STEPS * (1 + rho ** 2) / (1 - rho ** 2))
    assert 5 * 0.01 > 3.5 * se_var  # (the tolerance is several standard errors)
    assert speed.mean() == pytest.approx(MEAN, rel=0.05)
    assert speed.var() == pytest.approx(STD ** 2, rel=0.05)
    assert heading.mean() == pytest.approx(H_MEAN, rel=0.05)
    assert heading.var() == pytest.approx(H_STD ** 2, rel=0.05)
    assert np.mean((speed <= 0.0) | (speed >= MEAN + 5 * STD)) < 1e-3


def test_the_vessel_is_carried_by_the_current_the_process_gives():
    """The USV alone, thrusters off, in a current whose speed is a random walk (mu = 0, sigma
    0.05 m/s/sqrt(s), from 0.5 m/s, held in [0, 1] m/s) for 60 s: it is carried by the current the
    process gives, not by its mean. Its displacement is the water's (the current integrated step
    by step) within 1.5 m (measured: 1.01 m); a hull that catches up with the water on a time
    constant tau lags it by tau times its velocity change, under 1.25 s x 1 m/s here (tau = (m +
    m_a) / X_u: 1.03 s in surge, 1.22 s in sway; the speed stays in its 1 m/s band), 1.5 m leaving
    20 % for the hull's quadratic terms. The seed's walk ends over 10 m (measured: 15.8 m) from where the mean
    current would carry it, so a vessel that saw the mean would fail."""
    gm = _gm(mu=0.0, sigma=0.05, v_min=0.0, v_max=1.0, seed=3)
    steps, dt = 6000, 0.01
    run = ScenarioRun(load_scenario(text=ALONE.format(duration=steps * dt, dt=dt, mean=0.5, heading=30.0, gm=gm)))
    try:
        weather.attach(run)
        run.release_pilot()
        body = run.vehicle.id
        start = run.sim.data.xpos[body][:2].copy()
        water = np.zeros(2)
        for _ in range(steps):
            run.step()
            water += run.water.velocity(np.zeros(1))[0][:2] * dt  # (the current the step read)
        moved = run.sim.data.xpos[body][:2] - start
        assert run.vehicle.water.current is run.water.current
        assert not run.sim.native  # (no compiled provider holds a copy of the current)
    finally:
        run.close()
    mean_carry = 0.5 * steps * dt * np.array([math.cos(math.radians(30.0)), math.sin(math.radians(30.0))])
    assert np.linalg.norm(water - mean_carry) > 10.0
    assert np.linalg.norm(moved - water) < 1.5, np.linalg.norm(moved - water)


def test_every_line_body_and_vehicle_of_a_run_reads_the_one_current():
    """A tethered run (a prescribed ship, 10 elements to an anchor) with a Gauss-Markov current:
    the tether's loads, and the water column every provider holds, read the process itself (one
    object, stepped once per step: step k reads the process's k-th value from the seed, the first
    its mean),
    through the NumPy profile path (the compiled kernels would bake a constant current in)."""
    text = """
[simulation]
duration = 5.0
timestep = 0.005
output_interval = 0.5
[water]
depth = 20.0
[water.current]
speed = 0.4
heading_deg = 10.0
[water.current.gauss_markov]
mu = 0.5
sigma = 0.2
seed = 11
[tether]
length = 25.0
segments = 10
diameter = 0.02
density = 3000.0
[robot]
type = "anchor"
position = [-10.0, 0.0, -20.0]
"""
    run = ScenarioRun(load_scenario(text=text))
    try:
        w = weather.attach(run)
        assert weather.attach(run) is w and run.controllers.count(w) == 1  # (attached once)
        for _ in range(200):
            run.step()
        c = run.water.current
        assert isinstance(c, GaussMarkovCurrent)
        assert run.sim.water.current is c and run.bt.layout.water.current is c
        assert all(b.water.current is c for b in run.sim.bodies)
        assert run.bt.layout.fast is None or run.bt.layout.fast["water"] is None
        alone = GaussMarkovCurrent(0.4, 0.5, 0.2, 0.0, 10.0, math.radians(10.0), seed=11)
        alone.series(199, 0.005)  # (the 200th step read the value after 199: the first read the mean)
        assert w.steps == 199 and c.speed == alone.speed and c.heading == alone.heading
    finally:
        run.close()


@pytest.mark.parametrize("current, gm, key, words", [
    ('type = "linear"\nsurface_speed = 0.5\n', "sigma = 0.1\n", "water.current.gauss_markov", "'constant'"),
    ("speed = 2.0\n", "sigma = 0.1\nv_max = 1.0\n", "water.current.speed", r"\[0, 1\] m/s"),
    ("speed = 0.5\n", "sigma = 0.1\nv_min = 0.8\nv_max = 0.6\n", "water.current.gauss_markov.v_min", "v_max"),
    ("speed = 0.5\n", "mu = -1.0\n", "water.current.gauss_markov.mu", r"\[0, 100\] 1/s"),
])
def test_bad_gauss_markov_current_is_named(current, gm, key, words):
    """A Gauss-Markov current on a profile that is not uniform, a mean outside its band, a band
    upside down and a negative mu are refused naming the key and what is allowed."""
    text = ALONE.format(duration=1.0, dt=0.01, mean=0.0, heading=0.0, gm=gm).replace("speed = 0.0\nheading_deg = 0.0\n",
                                                                                    current)
    with pytest.raises(ConfigError, match=words) as err:
        ScenarioRun(load_scenario(text=text)).close()
    assert err.value.key == key

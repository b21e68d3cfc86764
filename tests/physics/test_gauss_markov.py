"""The first-order Gauss-Markov current (``physics.gauss_markov``: Fossen 2011, Sec. 8.3, as Hong
et al. 2020, Sec. 2.4.3 use it) against the closed form of the Ornstein-Uhlenbeck process
x' + mu (x - m) = w, written here: stationary mean m, variance sigma^2 / (2 mu),
autocorrelation e^{-mu tau}; and Hong et al.'s Eq. 10 against a rotation worked out here."""

import math

import numpy as np
import pytest

from mjtether.physics.gauss_markov import GaussMarkov, GaussMarkovCurrent

MEAN, MU, STD = 1.0, 0.5, 0.1          # m/s, 1/s, m/s: the speed's mean, rate, stationary spread
H_MEAN, H_MU, H_STD = 0.3, 0.8, 0.05   # rad, 1/s, rad: the direction's
T_RUN = 4.0e4                          # s: mu T = 2e4 (speed), 3.2e4 (direction)


def _current(seed=7, v_min=0.0, v_max=math.inf):
    """Noise intensities from the stationary spreads by sigma = std sqrt(2 mu)."""
    return GaussMarkovCurrent(MEAN, MU, STD * math.sqrt(2 * MU), v_min=v_min, v_max=v_max,
                              heading=H_MEAN, heading_mu=H_MU, heading_sigma=H_STD * math.sqrt(2 * H_MU),
                              seed=seed)


@pytest.mark.parametrize("dt", [0.2, 2.0])
def test_mean_and_variance_match_the_closed_form_at_any_step(dt):
    """Over T = 4e4 s, the sample mean and variance of speed and direction against m and
    sigma^2 / (2 mu), within 5 %. Statistical error: the sample variance of an OU process has
    relative standard deviation sqrt(2 / (mu T)) = 1 % (speed), 0.8 % (direction), the mean
    std sqrt(2 / (mu T)) = 1 % of STD; so 5 % is about 5 standard errors. At dt = 2 s (mu dt = 1
    for the speed) an Euler step would give twice the variance: the exact step must not. The
    band [0, inf) lies 10 standard deviations below the mean and is checked never reached, so
    the saturation does not touch what is measured. The first 20 / mu of the run are dropped
    (the start at the mean)."""
    speed, heading = _current().series(int(T_RUN / dt), dt)
    skip = int(20.0 / MU / dt)
    speed, heading = speed[skip:], heading[skip:]
    assert speed.min() > 0.0
    assert speed.mean() == pytest.approx(MEAN, rel=0.05)
    assert speed.var() == pytest.approx(STD ** 2, rel=0.05)
    assert heading.mean() == pytest.approx(H_MEAN, rel=0.05)
    assert heading.var() == pytest.approx(H_STD ** 2, rel=0.05)


def test_autocorrelation_decays_as_exp_minus_mu_tau():
    """The sample autocorrelation of the speed at lags 1/mu and 2/mu against e^{-1} and e^{-2},
    to 0.03 (absolute): its standard error over mu T = 2e4 is about sqrt(1 / (mu T)) ~ 0.007."""
    dt = 0.2
    speed, _ = _current(seed=11).series(int(T_RUN / dt), dt)
    x = speed[int(20.0 / MU / dt):] - speed.mean()
    for k in (1, 2):
        lag = int(round(k / MU / dt))
        rho = np.dot(x[:-lag], x[lag:]) / np.dot(x, x) * len(x) / (len(x) - lag)
        assert rho == pytest.approx(math.exp(-k), abs=0.03)


def test_seeded_runs_repeat_and_do_not_depend_on_how_they_are_stepped():
    """The same seed gives the same run bit for bit, whether stepped one at a time, in a
    ``series`` or after ``reset``; another seed gives another run."""
    a, b = _current(seed=3), _current(seed=3)
    sa, ha = a.series(3000, 0.1)
    sb = np.array([b.step(0.1) for _ in range(3000)])
    np.testing.assert_array_equal(sb[:, 0], sa * np.cos(ha))
    np.testing.assert_array_equal(sb[:, 1], sa * np.sin(ha))
    a.reset()
    np.testing.assert_array_equal(a.series(3000, 0.1)[0], sa)
    assert not np.array_equal(_current(seed=4).series(3000, 0.1)[0], sa)
    assert a.time == pytest.approx(300.0)


def test_saturation_holds_the_band_and_changes_nothing_inside_it():
    """Fossen's saturation, V_min <= V_c <= V_max, on a band +-0.5 standard deviation wide: every
    sample lies in it and both bounds are reached (so it acts); and until the unsaturated process
    of the same seed first leaves the band, the two runs are the same (the clip does nothing
    else). The band is here, not in the statistics tests."""
    lo, hi = MEAN - 0.05, MEAN + 0.05
    clipped, _ = _current(seed=5, v_min=lo, v_max=hi).series(20000, 0.1)
    free, _ = _current(seed=5).series(20000, 0.1)
    assert clipped.min() >= lo and clipped.max() <= hi
    assert np.any(clipped == lo) and np.any(clipped == hi)
    out = np.flatnonzero((free < lo) | (free > hi))[0]
    assert out > 0
    np.testing.assert_array_equal(clipped[:out], free[:out])
    assert clipped[out] != free[out]


def test_body_components_are_the_world_current_rotated_into_the_craft():
    """Hong et al.'s Eq. 10, u_c = V_c cos(beta - psi), v_c = V_c sin(beta - psi), against the
    world current rotated by -psi into a body frame x forward, y to port (to 1e-12)."""
    c = _current()
    c.series(50, 0.5)
    u = c.velocity()
    for psi in (0.0, 1.1, -2.5):
        R = np.array([[math.cos(psi), math.sin(psi)], [-math.sin(psi), math.cos(psi)]])
        np.testing.assert_allclose(c.in_body(psi), R @ u[:2], atol=1e-12)
    assert np.hypot(*u[:2]) == pytest.approx(c.speed)


def test_random_walk_spread_grows_as_sigma_root_t():
    """mu = 0 (Fossen's random walk, V_c' = w): the spread of 400 independent walks after
    T = 100 s is sigma sqrt(T), to 15 % (the sample std of 400 normals: 3.5 % standard error)."""
    sigma, T, dt = 0.02, 100.0, 1.0
    ends = [GaussMarkovCurrent(1.0, 0.0, sigma, seed=s).series(int(T / dt), dt)[0][-1] for s in range(400)]
    assert np.std(ends) == pytest.approx(sigma * math.sqrt(T), rel=0.15)


@pytest.mark.parametrize("kwargs, words", [
    ({"mu": -0.1}, ["current.speed.mu", ">= 0"]),
    ({"sigma": float("nan")}, ["current.speed.sigma"]),
    ({"mean_speed": 2.0, "v_max": 1.5}, ["current.speed", "[lower, upper]"]),
    ({"v_min": -1.0}, ["current.v_min", ">= 0"]),
    ({"heading_max": "north"}, ["current.heading.upper"]),
    ({"seed": -1}, ["current.seed"]),
])
def test_bad_arguments_name_the_field_and_its_range(kwargs, words):
    args = {"mean_speed": 0.5, "mu": 0.1, "sigma": 0.01} | kwargs
    with pytest.raises(ValueError) as err:
        GaussMarkovCurrent(**args)
    assert all(w in str(err.value) for w in words)


def test_a_step_must_be_positive():
    with pytest.raises(ValueError, match="dt must be > 0 s"):
        GaussMarkovCurrent(0.5, 0.1, 0.01).step(0.0)
    with pytest.raises(ValueError, match="process.mean"):
        GaussMarkov(mean=float("inf"))

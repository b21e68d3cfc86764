"""Water column profiles against their defining formulas and TEOS-10."""

import numpy as np
import pytest

import mjtether as mt


def test_exponential_current_decays_by_e_per_decay_depth():
    c = mt.ExponentialCurrent(2.5, decay_depth=15.0, heading=np.pi / 2)
    u = c(np.array([0.0, -15.0, -30.0]))
    np.testing.assert_allclose(u[:, 1], 2.5 * np.exp([0.0, -1.0, -2.0]), rtol=1e-12)
    np.testing.assert_allclose(u[:, [0, 2]], 0.0, atol=1e-12)
    assert c(np.array([5.0]))[0, 1] == pytest.approx(2.5)  # above water: surface value


def test_linear_density_matches_khan_profile():
    rho = mt.LinearDensity(1025.0, 980.0, 500.0)
    np.testing.assert_allclose(rho(np.array([0.0, -250.0, -500.0])), [1025.0, 1002.5, 980.0])


def test_power_law_and_linear_current():
    p = mt.PowerLawCurrent(1.0, seabed_depth=100.0, exponent=1 / 7)
    np.testing.assert_allclose(p.speed_at(np.array([0.0, -50.0, -100.0])), [1.0, 0.5 ** (1 / 7), 0.0])
    lin = mt.LinearCurrent(2.0, 0.0, depth_ref=40.0)
    np.testing.assert_allclose(lin.speed_at(np.array([0.0, -10.0, -40.0, -80.0])), [2.0, 1.5, 0.0, 0.0])


def test_tabulated_current_turns_with_depth():
    tab = mt.TabulatedCurrent([0.0, 100.0], [1.0, 1.0], [0.0, np.pi / 2])
    u = tab(np.array([0.0, -50.0, -100.0, -200.0]))
    np.testing.assert_allclose(u[0], [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(u[1], [0.5, 0.5, 0], atol=1e-12)  # components interpolated
    np.testing.assert_allclose(u[3], [0, 1, 0], atol=1e-12)  # constant beyond the table


def test_teos10_density_against_reference_value():
    pytest.importorskip("gsw")
    # TEOS-10 check value: SA = 35.16504 g/kg, CT = 10 C at 0 dbar gives 1026.95 kg/m^3
    # (gsw's own check: rho(35.16504, 10, 0) = 1026.9496...); here from practical salinity
    # 35 and in-situ temperature 10 C at the surface, which map to almost the same point
    rho = mt.teos10_density([0.0, 1000.0], [10.0, 4.0], [35.0, 34.5])
    assert rho(np.array([0.0]))[0] == pytest.approx(1026.95, abs=0.1)
    assert rho(np.array([-1000.0]))[0] > 1030.0  # compressibility: denser at depth


def test_knots_only_at_the_edges():
    assert mt.knots(1.0) == 1852.0 / 3600.0  # the international nautical mile, exactly
    assert mt.to_knots(mt.knots(5.0)) == pytest.approx(5.0)

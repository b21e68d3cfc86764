"""The USV wind load (``vehicles.wind``: Hong et al. 2020, Eqs. 7-9, Fossen's coefficients)
against Eqs. 7-8 evaluated by hand here, in Fossen's frame (x forward, y starboard, yaw positive
bow to starboard) and turned into mjtether's (y to port, z up) by hand, for winds set up in
the world as a sailor names them: from ahead, from starboard, from the starboard quarter."""

import math

import numpy as np
import pytest

from mjtether.vehicles.wind import HONG2020_USV, Windage, wind_load, wind_load_world, wind_velocity

RHO_AIR = 1.225
BOAT = Windage(frontal_area=0.8, lateral_area=2.1, length=3.4, cx=0.6, cy=0.9, cn=0.1)  # (all distinct)


def _from(bearing_off_bow, psi, speed):
    """World velocity of a wind of ``speed`` coming from ``bearing_off_bow`` (rad; positive to
    port, as z up counts angles) of a craft heading ``psi``: it blows the opposite way."""
    a = psi + bearing_off_bow + math.pi
    return np.array([speed * math.cos(a), speed * math.sin(a), 0.0])


def _by_hand(gamma_fossen, V, w=BOAT):
    """Eqs. 7-8 in Fossen's frame at his angle gamma_R (0 ahead, -90 deg from starboard), then
    y and N to mjtether's frame (y port, z up: both change sign)."""
    q = 0.5 * RHO_AIR * V ** 2
    X = q * (-w.cx * math.cos(gamma_fossen)) * w.frontal_area
    Y = q * (w.cy * math.sin(gamma_fossen)) * w.lateral_area
    N = q * (w.cn * math.sin(2 * gamma_fossen)) * w.lateral_area * w.length
    return np.array([X, -Y, -N])


@pytest.mark.parametrize("name, bearing, gamma_fossen", [
    ("head", 0.0, 0.0),
    ("beam from starboard", -math.pi / 2, -math.pi / 2),
    ("starboard quarter", -3 * math.pi / 4, -3 * math.pi / 4),
])
def test_load_matches_eq7_by_hand(name, bearing, gamma_fossen):
    """A craft at rest heading psi = 0.7 rad in 6 m/s of wind: the world load against Eq. 7-8
    by hand, rotated by psi into the world, to 1e-9 relative (round-off only)."""
    psi, V = 0.7, 6.0
    body = _by_hand(gamma_fossen, V)
    c, s = math.cos(psi), math.sin(psi)
    expected = [c * body[0] - s * body[1], s * body[0] + c * body[1], body[2]]
    got = wind_load_world(BOAT, _from(bearing, psi, V), np.zeros(3), psi)
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-9 * np.abs(body).max())


def test_signs_head_wind_pushes_astern_beam_wind_to_leeward():
    """Whatever the heading: a head wind pushes the craft astern and does not turn it; a wind
    from starboard pushes it to port by q c_y A_L (to 1e-9); a wind on the starboard bow turns its
    bow to port, away from the wind (c_n > 0); one on the starboard quarter turns it to
    starboard (it lies beam-on to the wind)."""
    V = 5.0
    q = 0.5 * RHO_AIR * V ** 2
    for psi in (0.0, 2.0, -2.8):
        ahead, port = np.array([math.cos(psi), math.sin(psi)]), np.array([-math.sin(psi), math.cos(psi)])
        head = wind_load_world(BOAT, _from(0.0, psi, V), np.zeros(3), psi)
        assert head[:2] @ ahead == pytest.approx(-q * BOAT.cx * BOAT.frontal_area, rel=1e-9)
        assert abs(head[:2] @ port) < 1e-9 and abs(head[2]) < 1e-9
        beam = wind_load_world(BOAT, _from(-math.pi / 2, psi, V), np.zeros(3), psi)
        assert beam[:2] @ port == pytest.approx(q * BOAT.cy * BOAT.lateral_area, rel=1e-9)
        assert wind_load_world(BOAT, _from(-math.pi / 4, psi, V), np.zeros(3), psi)[2] > 0.0
        assert wind_load_world(BOAT, _from(-3 * math.pi / 4, psi, V), np.zeros(3), psi)[2] < 0.0


def test_relative_wind_includes_the_craft_own_speed():
    """Running ahead at 2 m/s in still air is a 2 m/s head wind; running at 2 m/s before a 2 m/s
    following wind is no wind; a 3 m/s wind from starboard on a craft making 4 m/s ahead is a
    5 m/s relative wind from gamma_R = -atan2(3, 4) (Fossen's angle), by hand."""
    psi = -1.2
    ahead = 2.0 * np.array([math.cos(psi), math.sin(psi), 0.0])
    q = 0.5 * RHO_AIR * 2.0 ** 2
    np.testing.assert_allclose(wind_load_world(BOAT, np.zeros(3), ahead, psi)[:2],
                               -q * BOAT.cx * BOAT.frontal_area * ahead[:2] / 2.0, rtol=1e-9)
    np.testing.assert_allclose(wind_load_world(BOAT, ahead, ahead, psi), 0.0, atol=1e-12)
    body = wind_load_world(BOAT, _from(-math.pi / 2, psi, 3.0), 2.0 * ahead, psi)
    c, s = math.cos(psi), math.sin(psi)
    R = np.array([[c, s], [-s, c]])
    np.testing.assert_allclose(np.r_[R @ body[:2], body[2]], _by_hand(-math.atan2(3.0, 4.0), 5.0),
                               rtol=1e-9)


def test_wind_velocity_blows_towards_its_direction_and_hong_preset_is_in_eq9():
    """``wind_velocity`` is the way the air moves (Hong's Case 2 wind, 1 m/s at 90 deg, blows
    along +y); the preset's coefficients lie in Eq. 9's ranges and its length is Table 4's 3 m."""
    np.testing.assert_allclose(wind_velocity(1.0, math.pi / 2), [0.0, 1.0, 0.0], atol=1e-15)
    w = HONG2020_USV
    assert 0.5 <= w.cx <= 0.9 and 0.7 <= w.cy <= 0.95 and 0.05 <= w.cn <= 0.2 and w.length == 3.0


@pytest.mark.parametrize("kwargs, words", [
    ({"cx": 1.2}, ["windage.cx", "[0.5, 0.9]", "Eq. 9"]),
    ({"cy": 0.5}, ["windage.cy", "[0.7, 0.95]"]),
    ({"cn": 0.3}, ["windage.cn", "[0.05, 0.2]"]),
    ({"frontal_area": 0.0}, ["windage.frontal_area", "> 0 m^2"]),
    ({"lateral_area": -1.0}, ["windage.lateral_area"]),
    ({"length": "3"}, ["windage.length"]),
    ({"air_density": 0.0}, ["windage.air_density", "kg/m^3"]),
])
def test_bad_windage_names_the_field_and_its_range(kwargs, words):
    with pytest.raises(ValueError) as err:
        Windage(**({"frontal_area": 1.0, "lateral_area": 2.0, "length": 3.0} | kwargs))
    assert all(w in str(err.value) for w in words)


def test_bad_loads_arguments_are_named():
    with pytest.raises(ValueError, match="speed must be >= 0 m/s"):
        wind_load(BOAT, -1.0, 0.0)
    with pytest.raises(ValueError, match="wind must be finite"):
        wind_load_world(BOAT, [1.0], np.zeros(3), 0.0)
    with pytest.raises(ValueError, match="heading must be finite"):
        wind_load_world(BOAT, np.zeros(3), np.zeros(3), float("nan"))
    with pytest.raises(ValueError, match="wind.speed must be >= 0"):
        wind_velocity(-2.0, 0.0)

"""A vehicle built in water of another density than the one its file says it is trimmed for warns
(issue 44: a REMUS 100 trimmed for 1026 kg/m^3 sank 2.6 m in 60 s in the default 1025 kg/m^3
without a word). The warning names the file, its trim density, the water's density at the
vehicle's depth and the change of buoyancy (rho_w - rho_trim) g V, worked out here from the
file's stated mass and trim density (Fossen's REMUS 100: 31.0294 kg, neutral in 1026 kg/m^3, so
V = 31.0294 / 1026 m^3), typed in, not read from mjtether."""

import re
import warnings

import mujoco
import numpy as np
import pytest

import mjtether as mt
from mjtether.vehicles.files import build_vehicle, load_vehicle
from mjtether.vehicles.vehicle import TrimDensityWarning

REMUS_MASS, REMUS_TRIM = 31.0294, 1026.0  # kg, kg/m^3: assets/vehicles/remus100.toml (Fossen's numbers)
REMUS_HEAVE_ADDED = 29.43764  # kg: its heave added mass (Lamb's k2 on the spheroid), the file's
G = 9.81  # m/s^2: mjtether's water column's


def _build(name, rho, z=-20.0, steps=0):
    """Build vehicle file ``name`` at height ``z`` (m) in still water of ``rho`` kg/m^3 (a depth
    profile where ``rho`` is a DensityProfile); the TrimDensityWarnings it gave and its vertical
    velocity (m/s) after ``steps`` 5 ms steps from rest."""
    vs = load_vehicle(name)
    density = rho if not isinstance(rho, float) else mt.ConstantDensity(rho)
    water = mt.WaterColumn(depth=100.0, density=density)
    assert water.gravity == G
    spec = mujoco.MjSpec()
    spec.option.timestep = 0.005
    vm = build_vehicle(spec, vs, "auv", pos=(0.0, 0.0, z))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        with mt.Simulation(spec, water, bodies=[vm]) as sim:
            for _ in range(steps):
                sim.step()
            w = float(sim.data.qvel[sim.bodies[0]._v][2])
    return [m for m in seen if issubclass(m.category, TrimDensityWarning)], w


def test_a_remus_trimmed_for_1026_warns_in_1025():
    """In the default sea water (1025 kg/m^3) the REMUS 100 (trimmed neutral in 1026) warns once,
    naming its file, 1026 kg/m^3, the 1025 kg/m^3 at its 20 m and its change of buoyancy,
    (1025 - 1026) 9.81 (31.0294 / 1026) = -0.29669 N (heavier). Tolerance 1e-5: the message gives
    six figures."""
    said, _ = _build("remus100", 1025.0)
    assert len(said) == 1
    text = str(said[0].message)
    assert "remus100.toml" in text and "1026 kg/m^3" in text and "1025 kg/m^3" in text and "(20 m)" in text
    change = float(re.search(r"by ([-+][0-9.e+-]+) N", text).group(1))
    expected = (1025.0 - REMUS_TRIM) * G * (REMUS_MASS / REMUS_TRIM)
    assert change == pytest.approx(expected, rel=1e-5)
    assert "sinks" in text


def test_the_warned_change_is_the_force_it_feels():
    """The buoyancy change the warning gives is what moves the vehicle: from rest in 1025 kg/m^3
    the REMUS 100 (mass 31.0294 kg, heave added mass 29.43764 kg: the file's) starts down at
    a = dB / (m + Z_w') = -0.29669 / 60.467 = -4.907e-3 m/s^2, so after one 5 ms step its
    vertical speed is dt a = -2.4534e-5 m/s. Tolerance 1e-6 relative: nothing else acts at rest
    (no current, no thrust; the fins and the shaft idle), and MuJoCo's semi-implicit Euler step
    takes the force at rest exactly."""
    said, w = _build("remus100", 1025.0, steps=1)
    change = float(re.search(r"by ([-+][0-9.e+-]+) N", str(said[0].message)).group(1))
    expected_w = 0.005 * ((1025.0 - REMUS_TRIM) * G * REMUS_MASS / REMUS_TRIM) / (REMUS_MASS + REMUS_HEAVE_ADDED)
    assert w == pytest.approx(expected_w, rel=1e-6)
    assert 0.005 * change / (REMUS_MASS + REMUS_HEAVE_ADDED) == pytest.approx(w, rel=1e-5)


def test_no_warning_in_the_water_it_is_trimmed_for():
    """In 1026 kg/m^3 the REMUS 100 is as trimmed: no warning."""
    said, _ = _build("remus100", 1026.0)
    assert said == []


def test_the_density_at_the_vehicles_depth_is_the_one_compared():
    """In a linear profile from 1020 at the surface to 1030 kg/m^3 at 100 m the water is 1026 at
    60 m (no warning there) and 1022 at 20 m (a warning giving 1022 and (1022 - 1026) g V)."""
    profile = mt.LinearDensity(rho_surface=1020.0, rho_ref=1030.0, depth_ref=100.0)
    assert float(profile(np.array([-60.0]))[0]) == pytest.approx(1026.0, rel=1e-12)
    assert _build("remus100", profile, z=-60.0)[0] == []
    said, _ = _build("remus100", profile, z=-20.0)
    assert len(said) == 1 and "1022 kg/m^3" in str(said[0].message)
    change = float(re.search(r"by ([-+][0-9.e+-]+) N", str(said[0].message)).group(1))
    assert change == pytest.approx((1022.0 - REMUS_TRIM) * G * REMUS_MASS / REMUS_TRIM, rel=1e-5)


def test_a_vehicle_only_identified_in_its_water_does_not_warn():
    """The BlueROV2 files' 1000 kg/m^3 is the pool it was identified in (``trimmed = false``):
    2.3 N buoyant in sea water is how it is meant to be, and it does not warn there."""
    assert load_vehicle("bluerov2_heavy").trimmed is False
    assert _build("bluerov2_heavy", 1025.0)[0] == []


def test_trimmed_must_be_true_or_false(tmp_path):
    bad = tmp_path / "rov.toml"
    text = load_vehicle("bluerov2_heavy").path
    bad.write_text(open(text).read().replace("trimmed = false", 'trimmed = "no"'))
    with pytest.raises(ValueError, match=r"rov.toml: vehicle.trimmed = 'no': must be true or false"):
        load_vehicle(bad)


@pytest.mark.parametrize("example, warns", [("remus_turning_circle", True), ("auv_fibre_circle", False)])
def test_a_vehicle_moved_along_a_prescribed_path_does_not_warn(example, warns):
    """Both examples put the REMUS 100 (trimmed for 1026 kg/m^3) in 1025 kg/m^3 water. The
    turning circle flies it, so its buoyancy matters and it warns; the fibre circle moves it
    along ``robot.path`` (its motion prescribed: buoyancy plays no part), so it does not."""
    from mjtether.scenario import load_scenario
    from mjtether.scenario.runner import ScenarioRun

    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        ScenarioRun(load_scenario(example)).close()
    assert any(issubclass(w.category, TrimDensityWarning) for w in seen) == warns

"""A surface vessel (``vehicle.Surface``: hydrostatics about the design waterline) against
analytic answers: it floats at its waterline, and heave, roll and pitch oscillate at the natural
periods of linear hydrostatics,

    T_heave = 2 pi sqrt((m + A_33) / (rho g A_wp)),
    T_roll  = 2 pi sqrt((I_x + A_44) / (rho g V GM_T)),
    T_pitch = 2 pi sqrt((I_y + A_55) / (rho g V GM_L))

(Fossen 2021, Sec. 4.2), for a test vessel with its centre of gravity at the origin (no
coupling with sway or surge) and no damping. Tolerance 1 %: the 5 ms step's first-order
integration of an undamped oscillator shifts its period by well under 0.1 %, and the 2 deg (or
1 cm) amplitudes' sin(angle) by 0.02 %."""

import math

import mujoco
import numpy as np
import pytest

import mjtether as mt
from mjtether.vehicles.vehicle import Surface, VehicleHydro, add_vehicle

RHO, G = 1025.0, 9.81
# a 2 m catamaran-like test vessel (made-up numbers of a plausible size)
VOLUME = 0.08  # m^3 displaced floating: 82 kg
MASS = RHO * VOLUME
INERTIA = (9.0, 20.0, 24.0)
ADDED = np.array([5.0, 60.0, 70.0, 4.0, 12.0, 10.0])
A_WP, GM_T, GM_L = 0.8, 0.6, 2.5


def _sim(dt=0.005):
    water = mt.WaterColumn(depth=50.0, density=mt.ConstantDensity(RHO), gravity=G)
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, -G]
    hydro = VehicleHydro(volume=VOLUME, added_mass=ADDED,
                         surface=Surface(waterplane_area=A_WP, gm_t=GM_T, gm_l=GM_L, max_volume=0.3))
    vm = add_vehicle(spec, "usv", mass=MASS, inertia=INERTIA, hydro=hydro, pos=(0.0, 0.0, 0.0))
    return mt.Simulation(spec, water, bodies=[vm])


def test_it_floats_at_its_waterline():
    """Level at its design waterline it stays there: 100 s later within 1e-9 m and 1e-9 rad."""
    with _sim() as sim:
        sim.step(20000)
        assert abs(sim.data.qpos[2]) < 1e-9 and np.abs(sim.data.qvel).max() < 1e-9


def _period(axis: str, duration: float) -> float:
    with _sim() as sim:
        m, d = sim.model, sim.data
        if axis == "heave":
            d.qpos[2] = 0.01
        else:
            half = math.radians(2.0) / 2
            adr = m.joint("usv/ball").qposadr[0]
            d.qpos[adr:adr + 4] = [math.cos(half), *(math.sin(half) * np.eye(3)[0 if axis == "roll" else 1])]
        sim.forward()
        t, a = [], []
        body = sim.bodies[0].id
        for _ in range(int(round(duration / sim.timestep))):
            sim.step()
            R = d.xmat[body].reshape(3, 3)
            t.append(d.time)
            a.append({"heave": d.xpos[body][2], "roll": math.atan2(R[2, 1], R[2, 2]),
                      "pitch": -math.asin(R[2, 0])}[axis])
    t, a = np.array(t), np.array(a)
    up = np.flatnonzero((a[:-1] < 0) & (a[1:] >= 0))
    tc = t[up] - a[up] * (t[up + 1] - t[up]) / (a[up + 1] - a[up])
    assert len(tc) >= 3
    return float(np.mean(np.diff(tc)))


@pytest.mark.parametrize("axis", ["heave", "roll", "pitch"])
def test_natural_periods(axis):
    k = {"heave": (MASS + ADDED[2], RHO * G * A_WP),
         "roll": (INERTIA[0] + ADDED[3], RHO * G * VOLUME * GM_T),
         "pitch": (INERTIA[1] + ADDED[4], RHO * G * VOLUME * GM_L)}[axis]
    T = 2 * math.pi * math.sqrt(k[0] / k[1])
    assert _period(axis, 4.5 * T) == pytest.approx(T, rel=0.01)


def test_bad_surface_is_named():
    with pytest.raises(ValueError, match=r"surface.gm_t must be > 0"):
        Surface(waterplane_area=1.0, gm_t=-0.1, gm_l=1.0, max_volume=1.0)
    with pytest.raises(ValueError, match=r"surface.max_volume \(0.01 m\^3\) must be at least hydro.volume"):
        VehicleHydro(volume=0.08, surface=Surface(waterplane_area=1.0, gm_t=0.5, gm_l=1.0, max_volume=0.01))

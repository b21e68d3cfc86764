"""A vehicle towing a cable: the tether's force on the vehicle is the cable's drag, and at
steady speed it balances the thrust less the hull's own drag.

A neutrally buoyant vehicle with the same added mass on its three axes drives at a constant 10 N
of thrust with 30 m of neutrally buoyant cable (8 mm, no current) trailing from its origin, free
at its end. (Equal added masses make no Munk moment: a bare torpedo hull, without the fins that
stabilise real ones, porpoises at this speed; measured with the test torpedo of
``test_vehicle``: +-0.3 m/s of heave, 0.57 rad/s of pitch rate.) Checked once it has settled
(the last 10 s of 80 s):

* force balance along the track: thrust - D_hull(u) + F_cable,x = 0, with D_hull(u) the
  vehicle's own surge damping at its measured speed (2 u + 5 u|u|): within 1 % of the thrust
  (the acceleration left is 1e-4 of it);
* the cable's pull is the skin-friction drag of a straight cable towed along its axis,
  1/2 rho C_dt pi d L u^2 (Morison's tangential term): within 2 % (the lumped cable's first
  element is dragged at the vehicle's speed too, and the line is straight to 1e-3 rad);
* the cable slows the vehicle: it is slower than the same vehicle alone, whose speed solves
  2 u + 5 u^2 = 10 N.
"""

import math

import mujoco
import numpy as np

import mjtether as mt
from mjtether.vehicles.vehicle import VehicleHydro, add_vehicle

RHO, G = 1025.0, 9.81
THRUST = 10.0
LINEAR, QUADRATIC = 2.0, 5.0


def test_towed_cable_slows_the_vehicle_by_its_drag():
    water = mt.WaterColumn(depth=200.0, density=mt.ConstantDensity(RHO), gravity=G)
    dt = 0.005
    spec = mujoco.MjSpec()
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, -G]
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    hydro = VehicleHydro(volume=31.0 / RHO, added_mass=[15.0, 15.0, 15.0, 0.5, 1.6, 1.6],
                         linear_damping=[LINEAR, 10.0, 10.0, 0.5, 5.0, 5.0],
                         quadratic_damping=[QUADRATIC, 60.0, 60.0, 0.1, 10.0, 10.0])
    z = -50.0
    vm = add_vehicle(spec, "auv", mass=31.0, inertia=(0.112, 3.99, 3.99), hydro=hydro,
                     centre_of_gravity=(0.0, 0.0, -0.02), pos=(0.0, 0.0, z))
    L, N = 30.0, 15
    cable = mt.TetherSpec(length=L, segments=N, diameter=0.008, density=RHO, EA=2e6, cd_tangential=0.01)
    nodes = np.c_[-np.linspace(0.0, L, N + 1), np.zeros(N + 1), np.full(N + 1, z)]
    tm = mt.add_tether(spec, cable, mt.SitePoint("auv/origin"), mt.FreeEnd(), water=water, nodes=nodes)
    with mt.Simulation(spec, water, tethers=[tm], bodies=[vm]) as sim:
        d = sim.data
        bv = sim.bodies[0]
        u, fx, acc = [], [], []
        for k in range(int(round(80.0 / dt))):
            R = d.xmat[bv.id].reshape(3, 3)
            d.qfrc_applied[bv._v] = R @ [THRUST, 0.0, 0.0]
            sim.step()
            if d.time > 70.0:
                nu, R = bv.velocity(d)
                u.append(nu[0])
                fx.append((R.T @ sim.tether().end_force(d, "start"))[0])
                acc.append((R.T @ d.qacc[bv._v])[0])
        x = sim.tether().nodes(d)
    u, fx = float(np.mean(u)), float(np.mean(fx))
    assert abs(float(np.mean(acc))) * 46.0 < 1e-3 * THRUST  # settled: (m + X_u') a is 1e-3 of the thrust
    hull = LINEAR * u + QUADRATIC * u * abs(u)
    assert abs(THRUST - hull + fx) <= 0.01 * THRUST, (u, hull, fx)
    drag = 0.5 * RHO * 0.01 * math.pi * 0.008 * L * u * u
    assert fx < 0.0 and abs(-fx - drag) <= 0.02 * drag, (fx, drag)
    alone = (-LINEAR + math.sqrt(LINEAR**2 + 4 * QUADRATIC * THRUST)) / (2 * QUADRATIC)
    assert u < alone - 0.02, (u, alone)
    e = np.diff(x, axis=0)
    assert np.max(np.abs(e[:, 1:])) / np.min(np.linalg.norm(e, axis=1)) < 1e-2  # a straight line behind

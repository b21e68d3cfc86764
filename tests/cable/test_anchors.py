"""Tether ends on a mocap ship and on a site of another body follow their supports."""

import mujoco
import numpy as np
import pytest

import mjtether as mt
from conftest import new_spec


def test_mocap_ship_and_site_end():
    water = mt.WaterColumn(depth=200.0)
    spec = new_spec(0.005)
    ship = spec.worldbody.add_body(name="ship", pos=[0, 0, 0], mocap=True)
    ship.add_site(name="winch", pos=[-5.0, 0, -1.0])
    rov = spec.worldbody.add_body(name="rov", pos=[20, 0, -60])
    rov.add_freejoint()
    rov.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.5, 0.4, 0.3], mass=400.0, contype=0, conaffinity=0)
    rov.add_site(name="tow_point", pos=[-0.5, 0, 0.3])
    hydro = mt.add_body_hydro(spec, "rov", mt.RigidBodyHydro(volume=0.0, drag_cd=1.0, drag_area=1.0,
                                                             angular_drag=50.0))
    tether = mt.TetherSpec(length=80.0, segments=20, diameter=0.02, density=1100.0)
    tm = mt.add_tether(spec, tether, mt.SitePoint("winch"), mt.SitePoint("tow_point"), water=water)
    with mt.Simulation(spec, water, [tm], [hydro]) as sim:
        for k in range(400):  # the ship moves off at 0.5 m/s along x for 2 s
            sim.data.mocap_pos[0] = [0.5 * sim.time, 0, 0]
            sim.step()
        lag = np.linalg.norm(sim.tether().nodes(sim.data)[0] - sim.data.site_xpos[sim.model.site("winch").id])
        sim.run(60.0)  # then holds station while the ROV settles
        t = sim.tether()
        winch = sim.data.site_xpos[sim.model.site("winch").id]
        tow = sim.data.site_xpos[sim.model.site("tow_point").id]
        x = t.nodes(sim.data)
        # the connects hold the ends to their sites: within 2 mm at the ROV; at the moving
        # mocap the soft connect (time constant 2 dt, and a mocap body has no velocity for it
        # to track) lags by about speed x 4 dt = 1 cm
        assert np.linalg.norm(x[-1] - tow) < 2e-3
        assert lag < 0.02
        assert np.linalg.norm(x[0] - winch) < 2e-3
        # at rest, the ROV hangs on the tether: the pull on it balances its weight (2 %:
        # what is left of the settling swing), and the ship end carries the ROV and the
        # tether's wet weight
        f_rov = t.end_force(sim.data, "end")
        np.testing.assert_allclose(f_rov, [0, 0, 400 * 9.81], atol=0.02 * 400 * 9.81)
        wet = 400 * 9.81 + tether.wet_weight_per_length(1025.0) * 80.0
        assert -t.end_force(sim.data, "start")[2] == pytest.approx(wet, rel=0.02)

"""With EA given, the tether stretches by the integral of T / EA (Hooke's law)."""

import numpy as np
import pytest

import mujoco
import mjtether as mt
from conftest import new_spec


@pytest.mark.parametrize("EA", [2e5, 5e6])
def test_elongation_matches_hooke(EA):
    L, M = 100.0, 500.0
    tether = mt.TetherSpec(length=L, segments=20, diameter=0.02, density=7800.0, EA=EA)
    water = mt.WaterColumn(depth=500.0)
    w = tether.wet_weight_per_length(1025.0)
    top = np.array([0.0, 0.0, -5.0])
    spec = new_spec(0.002)
    body = spec.worldbody.add_body(name="weight", pos=top - [0, 0, L])
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.3, 0, 0], mass=M, contype=0, conaffinity=0)
    # drag on the weight damps its bounce on the elastic tether; no buoyancy
    hydro = mt.add_body_hydro(spec, "weight", mt.RigidBodyHydro(volume=0.0, drag_cd=1.0, drag_area=2.0))
    tm = mt.add_tether(spec, tether, mt.FixedPoint(top), mt.BodyPoint("weight"), water=water)
    lengths = []
    with mt.Simulation(spec, water, [tm], [hydro]) as sim:
        sim.run(30.0)
        sim.run(30.0, lambda s: lengths.append(s.tether().stretched_length(s.data)), every=0.05)
    # T(s) = M g + w (L - s) along the tether: stretch = (M g L + w L^2 / 2) / EA
    expected = (M * 9.81 * L + w * L**2 / 2) / EA
    # 10 %: the tolerance (time-averaged over 30 s of residual bounce)
    assert np.mean(lengths) - L == pytest.approx(expected, rel=0.10)


def test_inextensible_strain_below_1e3():
    """EA = None: strain below 0.1 % at working tension (here 100 kN on a 20 mm line)."""
    L = 100.0
    tether = mt.TetherSpec(length=L, segments=50, diameter=0.02, density=7800.0)
    water = mt.WaterColumn(depth=500.0)
    spec = new_spec(0.002)
    body = spec.worldbody.add_body(name="weight", pos=[0, 0, -L - 1])
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.3, 0, 0], mass=1e4, contype=0, conaffinity=0)
    tm = mt.add_tether(spec, tether, mt.FixedPoint([0, 0, -1.0]), mt.BodyPoint("weight"), water=water)
    with mt.Simulation(spec, water, [tm]) as sim:
        sim.run(5.0)
        strain = sim.tether().stretched_length(sim.data) / L - 1
        T = sim.tether().tension(sim.data).max()
    assert T > 9.5e4
    assert 0 <= strain < 1e-3

"""Bad input raises ValueError naming the field."""

import math

import numpy as np
import pytest

import mjtether as mt
from conftest import new_spec


@pytest.mark.parametrize("field,value", [
    ("length", 0.0), ("length", -5.0), ("length", math.nan),
    ("diameter", 0.0), ("diameter", -0.01), ("diameter", math.inf),
    ("segments", 0), ("segments", -3), ("segments", 2.5),
    ("EA", 0.0), ("EA", math.nan), ("cd_normal", math.nan), ("density", -1.0),
])
def test_tether_spec_rejects(field, value):
    kwargs = dict(length=100.0, segments=10, diameter=0.02)
    kwargs[field] = value
    with pytest.raises(ValueError, match=f"tether.{field}"):
        mt.TetherSpec(**kwargs)


def test_current_table_must_be_sorted():
    with pytest.raises(ValueError, match="sorted by depth"):
        mt.TabulatedCurrent([0.0, 50.0, 20.0], [1.0, 0.5, 0.2])
    with pytest.raises(ValueError, match="non-finite"):
        mt.TabulatedCurrent([0.0, 50.0], [1.0, math.nan])


@pytest.mark.parametrize("make,match", [
    (lambda: mt.WaterColumn(depth=-10.0), "water.depth"),
    (lambda: mt.WaterColumn(depth=math.nan), "water.depth"),
    (lambda: mt.ExponentialCurrent(2.0, decay_depth=0.0), "current.decay_depth"),
    (lambda: mt.ConstantCurrent(math.nan), "current.speed"),
    (lambda: mt.LinearDensity(rho_surface=2000.0), "density.rho_surface"),
    (lambda: mt.TabulatedDensity([0, 10], [1025, 1020, 1000]), "density table"),
    (lambda: mt.FixedPoint([0, math.nan, 0]), "FixedPoint.position"),
    (lambda: mt.RigidBodyHydro(volume=-1.0), "hydro.volume"),
    (lambda: mt.RigidBodyHydro(volume=1.0, drag_area=(1.0, -1.0, 0.0)), r"hydro.drag_area\[y\]"),
])
def test_profiles_and_anchors_reject(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def test_add_tether_rejects_bad_nodes_and_anchor():
    tether = mt.TetherSpec(length=10.0, segments=5)
    spec = new_spec(0.005)
    with pytest.raises(ValueError, match="nodes"):
        mt.add_tether(spec, tether, mt.FixedPoint([0, 0, 0]), mt.FixedPoint([5, 0, -5]),
                      nodes=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="BodyPoint.body"):
        mt.add_tether(new_spec(0.005), tether, mt.FixedPoint([0, 0, 0]), mt.BodyPoint("nope"))
    with pytest.raises(ValueError, match="timestep"):
        s = new_spec(0.005)
        s.option.timestep = 0.0
        mt.add_tether(s, tether, mt.FixedPoint([0, 0, 0]), mt.FixedPoint([5, 0, -5]))

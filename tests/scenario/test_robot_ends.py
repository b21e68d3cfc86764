"""The robot end of a scenario as a part (``scenario.robot_ends``): where each part puts the
tether's end at the start, checked against geometry written here; what holds it while the cable
settles; and that only the config's robot types reach the registry."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from mjtether.scenario.config import ConfigError
from mjtether.scenario.loading import load_scenario
from mjtether.scenario.robot_ends import ROBOT_ENDS, Anchor, Vehicle, Walker
from mjtether.scenario.runner import ScenarioRun
from mjtether.scenario.scene import build_scene
from mjtether.scenario.sections import Robot
from mjtether.vehicles.files import load_vehicle

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _plane_distance(p, depth: float, slope: float, heading: float) -> float:
    """Signed distance (m) of point ``p`` from the seabed plane of the design's convention: z = -depth
    at the origin, rising at ``slope`` (rad) towards ``heading`` (rad), normal (-sin a cos h,
    -sin a sin h, cos a)."""
    n = np.array([-math.sin(slope) * math.cos(heading), -math.sin(slope) * math.sin(heading), math.cos(slope)])
    return float(n @ (np.asarray(p, dtype=float) - np.array([0.0, 0.0, -depth])))


@pytest.mark.parametrize("slope_deg", [0.0, 8.0])
def test_an_anchor_on_the_seabed_is_held_one_cable_radius_above_it(slope_deg):
    """An anchor given on the seabed, or 5 mm above it (less than the cable's radius), starts with
    the cable's axis one cable radius (diameter 0.03 m / 2) from the seabed's plane, measured
    along its normal (an independent plane through (0, 0, -depth)), straight above its (x, y);
    one given 2 m above the seabed stays where it was given. (The config refuses one below the
    seabed.) Tolerance 1e-9 m: the same arithmetic in another order."""
    depth, x, y = 150.0, 100.0, 20.0
    slope, heading = math.radians(slope_deg), math.radians(30.0)
    seabed = -depth + math.tan(slope) * (x * math.cos(heading) + y * math.sin(heading))
    for dz, inside in ((0.0, True), (0.005, True), (2.0, False)):
        sc = load_scenario(EXAMPLES / "static_anchor_current.toml", overrides=[
            f"robot.position=[{x}, {y}, {seabed + dz}]", f"water.seabed_slope_deg={slope_deg}",
            "water.seabed_slope_heading_deg=30.0", "tether.length=260.0", "winch.max_length=300.0"])
        scene = build_scene(sc)
        end = scene.robot_end
        assert isinstance(end, Anchor) and end.heading is None and not scene.bodies
        p = end.tow_point(scene, sc.simulation.timestep)
        np.testing.assert_allclose(p[:2], [x, y], atol=0.0)
        if inside:
            assert _plane_distance(p, depth, slope, heading) == pytest.approx(0.015, abs=1e-9)
        else:
            assert p[2] == pytest.approx(seabed + dz, abs=1e-9)
        assert end.end_at(p) is None
        np.testing.assert_array_equal(end.tether_end().position, p)


@pytest.mark.parametrize("heading_deg", [0.0, 90.0, -135.0])
def test_a_vehicles_tow_point_turns_with_its_heading(heading_deg):
    """The vehicle's tow point at the start is its origin (robot.position) plus its vehicle file's
    tow point turned by its heading about z, written out here as x cos h - y sin h, x sin h + y cos h;
    and the compiled model puts the site ``vehicle/tow_point`` there once ``start`` has set the
    vehicle level at that heading (a replay build: no pre-roll moves it). Tolerance 1e-9 m
    (rounding of a rotation of a vector under 1 m)."""
    sc = load_scenario(EXAMPLES / "rov_umbilical.toml", overrides=[f"robot.heading_deg={heading_deg}"])
    tx, ty, tz = load_vehicle(sc.robot.vehicle).tow_point
    h = math.radians(heading_deg)
    want = np.array(sc.robot.position) + [tx * math.cos(h) - ty * math.sin(h), tx * math.sin(h) + ty * math.cos(h),
                                          tz]
    run = ScenarioRun(sc, replay=True)
    try:
        end = run.robot_end
        assert isinstance(end, Vehicle) and run.is_vehicle and not run.walker
        np.testing.assert_allclose(run.robot_position, want, atol=1e-9)
        site = run.sim.data.site_xpos[run.sim.model.site("vehicle/tow_point").id]
        np.testing.assert_allclose(site, want, atol=1e-9)
        assert end.controllers == [run.pilot] and run.pilot is not None and run.vehicle is end.vehicle
        assert run.controllers[0] is run.pilot
    finally:
        run.close()


def test_a_walkers_standing_tow_point_turns_with_its_heading():
    """On a level seabed the walker stands once and is moved and turned into place: its standing
    tow point's offset from its start (x, y, seabed) at heading 90 deg is the one at heading 0
    turned by 90 deg about z (written out: (x, y) -> (-y, x)), at the same height. Tolerance
    1e-9 m: the stand is the same one, only turned."""
    offsets = []
    for heading in (0.0, 90.0):
        sc = load_scenario(overrides=[f"robot.heading_deg={heading}", "robot.start=[40.0, -10.0]"])
        scene = build_scene(sc)
        end = scene.robot_end
        assert isinstance(end, Walker) and scene.walker and end.heading == pytest.approx(math.radians(heading))
        p = end.tow_point(scene, sc.simulation.timestep)
        offsets.append(p - [40.0, -10.0, -sc.water.depth])
        assert end.stand_pose and end.controllers == [end.gait_drive]
    a, b = offsets
    np.testing.assert_allclose(b, [-a[1], a[0], a[2]], atol=1e-9)
    assert a[2] > 0.5  # (the tow point is on the torso, standing above the seabed)


def test_only_the_walker_is_held_while_the_cable_settles():
    """``hold`` adds the walker's weld ``walker/hold`` (on its torso) to the spec, and nothing for
    an anchor or a vehicle."""
    for path, kind in ((None, Walker), (EXAMPLES / "static_anchor_current.toml", Anchor),
                       (EXAMPLES / "rov_umbilical.toml", Vehicle)):
        scene = build_scene(load_scenario(path))
        assert type(scene.robot_end) is kind
        before = len(scene.spec.equalities)
        scene.robot_end.hold(scene.spec)
        added = [e.name for e in scene.spec.equalities][before:]
        assert added == (["walker/hold"] if kind is Walker else [])


def test_an_unknown_robot_type_is_refused_before_the_registry():
    """The registry holds exactly the config's robot types, and any other is refused by the
    config, naming ``robot.type`` and the allowed ones, before a scene is built."""
    choices = {f.name: f for f in dataclasses.fields(Robot)}["type"].metadata["param"].choices
    assert set(ROBOT_ENDS) == set(choices)
    with pytest.raises(ConfigError) as err:
        load_scenario(overrides=['robot.type="boat"'])
    assert "robot.type" in str(err.value) and all(c in str(err.value) for c in choices)

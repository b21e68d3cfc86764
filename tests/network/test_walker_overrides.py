"""``--set walkers.NAME.KEY=VALUE`` on a network (``mjtether.network.overrides``): a walker's
``position`` (two numbers [x, y], m: it stands on the seabed there), ``heading_deg``, ``speed``
(m/s) and ``gait_period`` (s), checked by the walker's own checks; a bad key, name or value is
refused naming it. The effect is checked where the network starts the walker: its tow point moves
with its position and turns with its heading about its torso, as a rigid body does on a level
seabed (the tow point's offset ``WALKER_TOW_POINT`` rotated by the heading, written out here)."""

import math
from pathlib import Path

import numpy as np
import pytest

from mjtether.io.moordyn import load_any
from mjtether.network import WALKER_TOW_POINT, NetworkError, Walker, with_overrides
from mjtether.network import run as nr

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "networks" / "walker_clump_bridle.toml"


@pytest.fixture(scope="module")
def net():
    return load_any(EXAMPLE)


def test_walker_keys_take_effect(net):
    """position, heading_deg, speed and gait_period reach the walker ``crab``; its tow point (a
    body point given no position) starts at its torso plus the tow offset turned by the heading:
    90 deg puts the offset (-0.85, 0, 0.05) m at (0, -0.85) m in the world, within 2 cm (the
    standing torso's small pitch and roll over a 0.85 m lever; the stand is on a level seabed)."""
    assert isinstance(net.walkers["crab"], Walker) and net.walkers["crab"].position == (20.0, 0.0)
    got = with_overrides(net, ["walkers.crab.position=[25.0, 3.0]", "walkers.crab.heading_deg=90",
                               "walkers.crab.speed=0.05", "walkers.crab.gait_period=1.5"])
    w = got.walkers["crab"]
    assert (w.position, w.heading_deg, w.speed, w.gait_period) == ((25.0, 3.0), 90.0, 0.05, 1.5)
    assert w.schedule == ((0.0, 0.05, 0.0),)  # what the gait drive walks on
    torso = nr.body_frame(got, "crab")[0]
    assert abs(torso[0] - 25.0) < 0.02 and abs(torso[1] - 3.0) < 0.02  # (it stands where it is put)
    tow = nr.start_positions(got)["crab_tow"]
    h = math.radians(90.0)
    x, y, z = WALKER_TOW_POINT
    want = torso + [x * math.cos(h) - y * math.sin(h), x * math.sin(h) + y * math.cos(h), z]
    assert np.allclose(tow, want, atol=0.02), (tow, want)
    assert net.walkers["crab"].position == (20.0, 0.0)  # (the network given is not changed)


@pytest.mark.parametrize("item, message", [
    ("walkers.crab.speed=5", "--set walkers.crab.speed=5: walker 'crab': speed = 5.0: must be in ["),
    ("walkers.crab.gait_period=-1", "--set walkers.crab.gait_period=-1: walker 'crab': gait_period"),
    ("walkers.crab.position=[1.0, 2.0, 3.0]", "--set walkers.crab.position: give walkers.crab.position=[X, Y], two "
                                              "numbers (m), got '[1.0, 2.0, 3.0]'"),
    ("walkers.crab.heading_deg=north", "--set walkers.crab.heading_deg: give walkers.crab.heading_deg=NUMBER (deg)"),
    ("walkers.lobster.speed=0.1", "--set walkers.lobster.speed: no walker named 'lobster' (the network's walkers: "
                                  "crab)"),
    ("walkers.crab.stride=1", "--set walkers.crab.stride: a walker's keys (walkers.NAME.KEY) are position, "
                              "heading_deg, speed, gait_period"),
])
def test_a_bad_walker_key_is_refused_naming_it(net, item, message):
    """Each refusal names the --set item, and the range or the keys or names allowed."""
    with pytest.raises(NetworkError) as exc:
        with_overrides(net, [item])
    assert str(exc.value).startswith(message), str(exc.value)

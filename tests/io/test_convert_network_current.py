"""A network whose current is a ``[water.current]`` table (``Network.current``, a scenario's
profile, not the ``current_depths`` table) converts to a MoorDyn file with its current beside it
(``moordyn.current_table``, ``current_profile``: rows MoorDyn interpolates linearly in depth),
and reads back (``load_any``) as the same current within 1 % of the local speed: the profile's
formulas are written out here, not taken from ``mjtether.physics.water``. A network with a
seabed walker is refused naming it (a MoorDyn file has no walker)."""

import math
from pathlib import Path

import numpy as np
import pytest

from mjtether import cli
from mjtether.io import moordyn
from mjtether.network import from_dict
from mjtether.network import run as nr
from mjtether.scenario import ScenarioError

DEPTH = 80.0
ROOT = Path(__file__).resolve().parents[2]


def tree(current: dict) -> dict:
    """Two lines from anchors to a ship's coupled point in ``current`` ([water.current]); (one
    line from an anchor to a fairlead would read back as a scenario)."""
    line = {"type": "rope", "b": "ship", "length": 110.0, "segments": 10}
    return {"water": {"depth": DEPTH, "current": current}, "simulation": {"duration": 2.0},
            "line_types": {"rope": {"diameter": 0.03, "mass_per_length": 2.0, "EA": 1e7}},
            "points": {"ship": {"kind": "coupled", "position": [0.0, 0.0, 0.0]},
                       "east": {"kind": "fixed", "position": [60.0, 0.0, -DEPTH]},
                       "west": {"kind": "fixed", "position": [-60.0, 0.0, -DEPTH]}},
            "lines": [{"name": "e", "a": "east", **line}, {"name": "w", "a": "west", **line}]}


# depths (m below the surface) compared: the surface, between rows, near the seabed (down to 2 mm
# above it: the table leaves the last 1 mm whole, where the 1/7 power law has no linear interpolant)
DEPTHS = np.concatenate([np.linspace(0.0, DEPTH, 97)[:-1] + 0.37, DEPTH - np.geomspace(2e-3, 20.0, 25)])
CASES = [  # ([water.current], its speed at depths d from the profile's formula, heading deg)
    ({"type": "power", "surface_speed": 0.6, "exponent": 1 / 7, "heading_deg": 30.0},
     lambda d: 0.6 * ((DEPTH - d) / DEPTH) ** (1 / 7), 30.0),  # (DNV-RP-C205 4.1.3: zero at the seabed)
    ({"type": "linear", "surface_speed": 0.8, "bottom_speed": 0.2, "bottom_depth": 50.0, "heading_deg": -45.0},
     lambda d: 0.8 + (0.2 - 0.8) * np.minimum(d / 50.0, 1.0), -45.0),
    ({"type": "exponential", "surface_speed": 1.2, "decay_depth": 6.0, "heading_deg": 90.0},
     lambda d: 1.2 * np.exp(-d / 6.0), 90.0),
]


def convert(net, folder: Path) -> Path:
    """What ``mjtether convert NET out.txt`` writes: the file, and its current beside it."""
    out = folder / "out.txt"
    out.write_text(moordyn.write_network(net))
    assert moordyn.current_table(net), "a current must give a table"
    (folder / moordyn.CURRENT_FILE).write_text(moordyn.current_profile(net))
    return out


def check_current(back, speed, heading_deg):
    """The read-back network's current at DEPTHS against the formula: within 1 % of the local
    speed (the table's promise, ``CURRENT_TOLERANCE``) plus 1e-6 m/s (its floor, still water)."""
    want = speed(DEPTHS)[:, None] * [math.cos(math.radians(heading_deg)), math.sin(math.radians(heading_deg)), 0.0]
    got = nr.water_of(back).current(-DEPTHS)
    err = np.linalg.norm(got - want, axis=-1)
    worst = int(np.argmax(err / (0.01 * speed(DEPTHS) + 1e-6)))
    assert np.all(err <= 0.01 * speed(DEPTHS) + 1e-6), \
        f"at {DEPTHS[worst]:.4f} m: {got[worst]} m/s, the formula {want[worst]}"


@pytest.mark.parametrize("current, speed, heading", CASES, ids=[c["type"] for c, _, _ in CASES])
def test_a_scenario_current_converts_and_reads_back_within_1_percent(tmp_path, current, speed, heading):
    """write_network + current_profile -> load_any: the MoorDyn file's current (``1 Currents``
    and its ``CURRENT_FILE``) is the profile within 1 % of its local speed at 121 depths."""
    net = from_dict(tree(current))
    assert net.current is not None and not net.current_depths
    text = moordyn.write_network(net)
    assert "1 Currents" in text.splitlines()
    back = moordyn.load_any(convert(net, tmp_path))
    assert back.current is None and len(back.current_depths) >= 3
    check_current(back, speed, heading)


def test_the_power_law_tables_in_a_few_rows():
    """The 1/7 power law over 80 m: a row at each halving of the height above the seabed down to
    1 mm (log2(80 m / 1 mm) = 16.3) and the surface: fewer than 30 rows, the last but one within
    1 mm of the seabed; a constant current is two rows, still water none."""
    rows = moordyn.current_table(from_dict(tree(CASES[0][0])))[0]
    assert 17 <= len(rows) < 30 and rows[0] == 0.0 and rows[-1] == DEPTH and DEPTH - rows[-2] <= 1e-3
    assert len(moordyn.current_table(from_dict(tree({"type": "constant", "speed": 0.5})))[0]) == 2
    assert moordyn.current_table(from_dict(tree({"type": "constant", "speed": 0.0}))) == ()
    assert "Currents" not in moordyn.write_network(from_dict(tree({"type": "constant", "speed": 0.0})))


def test_mjtether_convert_writes_a_scenario_current_beside_the_file(tmp_path):
    """``mjtether convert NET.toml out.txt`` on a network with a ``[water.current]`` power law
    writes ``CURRENT_FILE`` beside ``out.txt``, and the pair reads back within 1 %."""
    src = tmp_path / "net.toml"
    src.write_text('[water]\ndepth = 80.0\n[water.current]\ntype = "power"\nsurface_speed = 0.6\n'
                   'exponent = 0.14285714285714285\nheading_deg = 30.0\n[simulation]\nduration = 2.0\n'
                   '[line_types.rope]\ndiameter = 0.03\nmass_per_length = 2.0\nEA = 1e7\n'
                   '[points.ship]\nkind = "coupled"\nposition = [0.0, 0.0, 0.0]\n'
                   '[points.east]\nkind = "fixed"\nposition = [60.0, 0.0, -80.0]\n'
                   '[points.west]\nkind = "fixed"\nposition = [-60.0, 0.0, -80.0]\n'
                   '[[lines]]\nname = "e"\ntype = "rope"\na = "east"\nb = "ship"\nlength = 110.0\nsegments = 10\n'
                   '[[lines]]\nname = "w"\ntype = "rope"\na = "west"\nb = "ship"\nlength = 110.0\nsegments = 10\n')
    out = tmp_path / "out" / "out.txt"
    out.parent.mkdir()
    assert cli.main(["convert", str(src), str(out)]) == 0
    assert (out.parent / moordyn.CURRENT_FILE).is_file(), \
        "cli._convert must write the current of a [water.current] network: `if moordyn.current_table(sc):`"
    check_current(moordyn.load_any(out), CASES[0][1], 30.0)


def test_a_network_with_a_walker_is_refused_naming_it():
    """The shipped walker_clump_bridle has the walker ``crab``: write_network refuses it (it read
    ``KeyError: 'crab'`` before), naming the section and the walker."""
    net = moordyn.load_any(ROOT / "examples" / "networks" / "walker_clump_bridle.toml")
    with pytest.raises(ScenarioError, match=r"^walkers: seabed walkers \(crab: a MoorDyn file has no walker\)"):
        moordyn.write_network(net)

"""A network of lines written in TOML (``mjtether.network.from_dict``): what a careless file gets."""

import pytest

from mjtether import cli

GOOD = """[water]
depth = 50.0
[line_types.c]
diameter = 0.05
mass_per_length = 5.0
EA = 1e7
[points.a]
kind = "fixed"
position = [0.0, 0.0, -50.0]
[points.b]
kind = "fixed"
position = [30.0, 0.0, -10.0]
[[lines]]
name = "1"
type = "c"
a = "a"
b = "b"
length = 60.0
segments = 10
"""

BAD = {  # edit of GOOD: what the one-line error must say
    "a missing key": (('length = 60.0\n', ''), "lines[0] ('1'): missing key(s) length"),
    "an unknown key": (("EA = 1e7\n", "EA = 1e7\nwobble = 1\n"), "line_types.c: unknown key(s) wobble; allowed: EA"),
    "an unknown section": (("[water]\n", "[ship]\nx = 1\n[water]\n"), "unknown section(s) ship"),
    "a negative mass": (('kind = "fixed"\nposition = [30.0', 'kind = "free"\nmass = -3.0\nposition = [30.0'),
                        "points.b: point 'b': mass must be >= 0, got -3"),
    "a point that is not there": (('b = "b"', 'b = "c"'), "line '1': point 'c' is not a point (a, b)"),
    "a text for a number": (("depth = 50.0", 'depth = "deep"'), "water.depth"),
    "half a segment": (("segments = 10", "segments = 10.5"), "segments must be a whole number in [1, 1000]"),
    "an unknown vehicle": (("[points.a]", '[vehicles.rov]\nvehicle = "nautilus"\nposition = [0.0, 0.0, -20.0]\n'
                                          "[points.a]"), "vehicles.rov: vehicle 'rov': vehicle 'nautilus': not a "
                                                         "shipped vehicle"),
    "a vehicle above the water": (("[points.a]", '[vehicles.rov]\nvehicle = "bluerov2_heavy"\n'
                                                 "position = [0.0, 0.0, 2.0]\n[points.a]"),
                                  "a vehicle starts and holds station under water"),
    "a payout with no room on the drum": (("segments = 10", "segments = 10\npayout_speed = 0.5"),
                                          "line '1': a line paying out (payout_speed > 0) needs max_length"),
    "a pin on a free body": (("[points.a]", '[bodies.buoy]\nkind = "free"\nposition = [0.0, 0.0, -20.0]\n'
                                            "mass = 10.0\ninertia = [1.0, 1.0, 1.0]\npin = [0.0, 0.0, 1.0]\n"
                                            "[points.a]"), "body 'buoy': only a pinned body has a pin"),
    "a pinned body with no inertia": (("[points.a]", '[bodies.arm]\nkind = "pinned"\nposition = [0.0, 0.0, -20.0]'
                                                     "\nmass = 10.0\n[points.a]"),
                                      "body 'arm': a pinned body needs a mass (kg) and inertia (kg m^2) > 0"),
    "a bathymetry that is not there": (("depth = 50.0", 'depth = 50.0\nbathymetry = "nowhere.csv"'),
                                       "nowhere.csv: no such file"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_a_bad_network_file_gets_one_line_naming_the_key(tmp_path, capsys, case):
    (old, new), words = BAD[case]
    assert old in GOOD
    path = tmp_path / "net.toml"
    path.write_text(GOOD.replace(old, new, 1))
    out = tmp_path / "res"
    assert cli.main(["run", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1 and "Traceback" not in err, err
    assert not out.exists()


def test_the_good_file_runs(tmp_path):
    path = tmp_path / "net.toml"
    path.write_text(GOOD)
    assert cli.main(["run", str(path), "--set", "simulation.duration=1", "--out", str(tmp_path / "res")]) == 0
    assert (tmp_path / "res" / "timeseries.csv").exists() and path.read_text() == GOOD

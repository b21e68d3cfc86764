"""Bad input on the files a scenario names or is: vehicle files (``mjtether.vehicles.files``),
MoorDyn input files and the side files beside them (a steady current profile, a SeafloorFile).
Each is refused with one message naming the file, the key or line, and what is allowed, never
with a traceback, never by running something else (the built-in scenario for an empty file), and
never showing what a file holds (a side file may be a link to anything); a few valid edge inputs
are checked to be read right, against values worked out here by hand.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest

from mjtether.io import moordyn
from mjtether.scenario import ScenarioError
from mjtether.vehicles.files import load_vehicle
from mjtether.vehicles.thruster import Thruster
from test_bad_input_table import _run_cli

VEHICLES = Path(__file__).resolve().parents[1] / "assets" / "vehicles"
ROV = (VEHICLES / "bluerov2_heavy.toml").read_text()
BENCH = (VEHICLES / "bluerov2_heavy_benchmark.toml").read_text()
K_S = "response = { numerator = [6136.0, 108700.0], denominator = [1.0, 89.0, 9258.0, 108700.0] }"
"""The benchmark BlueROV2's thruster response as its file writes it (von Benzon et al. 2022, Eq. 19)."""


def _edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


VEHICLE_FILES = {  # name: (file text, what the error must contain)
    "a boolean mass": (_edit(ROV, "mass = 13.5 ", "mass = true "),
                       "vehicle.mass = True: must be a number in (0, 1e+09] kg"),
    "mass as text": (_edit(ROV, "mass = 13.5 ", 'mass = "13.5" '),
                     "vehicle.mass = '13.5': must be a number in (0, 1e+09]"),
    "NaN gain": (_edit(ROV, "speed_kp = 200.0", "speed_kp = nan"),
                 "autopilot.speed_kp = nan: must be a number in [0, 1e+09]"),
    "gain as text": (_edit(ROV, "speed_kp = 200.0", 'speed_kp = "fast"'),
                     "autopilot.speed_kp = 'fast': must be a number in [0, 1e+09]"),
    "negative gain": (_edit(ROV, "heading_kp = 10.0", "heading_kp = -10.0"), "autopilot.heading_kp = -10.0: must be"),
    "gain as a list": (_edit(ROV, "speed_kp = 200.0", "speed_kp = [200.0]"), "autopilot.speed_kp = [200.0]: must be"),
    "flag as a number": (_edit(ROV, "speed_kp = 200.0", "speed_kp = 200.0\ndepth_by_pitch = 1"),
                         "autopilot.depth_by_pitch = 1: must be true or false"),
    "boolean in a point": (_edit(ROV, "tow_point = [-0.229, 0.0, 0.0]", "tow_point = [true, 0.0, 0.0]"),
                           "vehicle.tow_point[0] = True: must be a number in [-1000, 1000] m"),
    "text in a thruster's position": (_edit(ROV, "position = [0.156, -0.111, -0.085]", 'position = ["0.156", 0, 0]'),
                                      "thrusters[0].position[0] = '0.156': must be a number in"),
    "two moments of inertia": (_edit(ROV, "inertia = [0.26, 0.23, 0.37]", "inertia = [0.26, 0.23]"),
                               "vehicle.inertia = [0.26, 0.23]: must be a list of 3 or 6 numbers"),
    "added mass of 1e300": (_edit(ROV, "added_mass = [6.36,", "added_mass = [1e300,"),
                            "hydro.added_mass[0] = 1e+300: must be a number in [-1e+15, 1e+15]"),
    "a thruster named true": (_edit(ROV, 'name = "t1"', "name = true"), "thrusters[0].name = True: must be text"),
    "a boolean coefficient": (_edit(BENCH, "numerator = [6136.0,", "numerator = [true,"),
                              "t1.response.numerator = [True, 108700.0]: must be a list of finite numbers"),
    "a coefficient as text": (_edit(BENCH, "numerator = [6136.0,", 'numerator = ["6136",'),
                              "t1.response.numerator = ['6136', 108700.0]: must be a list of finite numbers"),
    "a pole at 1e300 1/s": (_edit(BENCH, K_S, "response = { numerator = [1e300], denominator = [1.0, 1e300] }"),
                            "t1.response: every pole must be within 10000 1/s (a time constant of at least 0.1 ms), "
                            "got one of 1e+300 1/s"),
    "a zero of 1e300": (_edit(BENCH, "numerator = [6136.0,", "numerator = [1e300,"),
                        "t1.response: the numerator's coefficients (the denominator scaled to lead with 1) must be "
                        "within [-1e+15, 1e+15], got 1e+300"),
    "water of 1500 kg/m^3": (_edit(ROV, "water_density = 1000.0", "water_density = 1500.0"),
                             "vehicle.water_density = 1500.0: must be a number in [900, 1100] kg/m^3"),
}


@pytest.mark.parametrize("case", list(VEHICLE_FILES))
def test_bad_vehicle_file_names_the_file_the_key_and_the_range(case, tmp_path):
    """Each was accepted (a boolean mass as a 1 kg vehicle, a NaN or text gain, ``true`` as a
    coefficient 1, 1e300 anywhere) or a traceback (a 1e300 pole: LinAlgError, at build)."""
    text, message = VEHICLE_FILES[case]
    f = tmp_path / "bad.toml"
    f.write_text(text)
    with pytest.raises(ValueError) as info:
        load_vehicle(f)
    assert str(info.value).startswith("bad.toml: ") and message in str(info.value), str(info.value)


@pytest.mark.parametrize("data, message", [
    (bytes(range(256)) * 4, "line 2: byte 0x80 is not UTF-8 (a binary file?)"),  # (a UnicodeDecodeError)
    (ROV.encode("utf-16"), "is UTF-16 text; save it as UTF-8"),
], ids=["binary", "UTF-16"])
def test_a_vehicle_file_that_is_not_utf8_text_is_named(data, message, tmp_path):
    f = tmp_path / "bin.toml"
    f.write_bytes(data)
    with pytest.raises(ValueError) as info:
        load_vehicle(f)
    assert str(info.value).startswith(f"vehicle file {f}: {message}"), str(info.value)


def test_a_vehicle_that_is_not_text_is_named():
    with pytest.raises(ValueError, match=r"vehicle = 5: must be text: a shipped vehicle \(bluerov2_heavy,"):
        load_vehicle(5)


SCENARIO = '[robot]\ntype = "vehicle"\nposition = [0.0, 0.0, -10.0]\nvehicle = {vehicle}\n[water]\ndepth = 100.0\n'


@pytest.mark.parametrize("vehicle, parts", [
    ("5", ["robot.vehicle = 5: must be text"]),
    ('"{tmp}/bad.toml"', ["robot.vehicle = ", "bad.toml: vehicle.mass = True: must be a number in (0, 1e+09] kg"]),
    ('"{tmp}/bin.toml"', ["robot.vehicle = ", "bin.toml: line 1: byte 0xff is not UTF-8"]),
], ids=["a number", "a bad vehicle file", "a binary vehicle file"])
def test_a_scenarios_vehicle_is_refused_on_one_line(vehicle, parts, tmp_path, capsys):
    """``mjtether solve`` on a scenario whose robot.vehicle is bad: exit 2, one line naming the
    scenario file, robot.vehicle and, for a file, the vehicle file and its key."""
    (tmp_path / "bad.toml").write_text(_edit(ROV, "mass = 13.5 ", "mass = true "))
    (tmp_path / "bin.toml").write_bytes(b"\xff\x00\x01" * 100)
    f = tmp_path / "s.toml"
    f.write_text(SCENARIO.format(vehicle=vehicle.replace("{tmp}", tmp_path.as_posix())))
    rc, err = _run_cli(["solve", str(f)], capsys)
    assert rc == 2 and len(err) == 1 and str(f) in err[0], err
    for part in parts:
        assert part in err[0], err[0]


def test_a_response_scaled_through_is_the_same_response(tmp_path):
    """Valid: K(s) with numerator and denominator both multiplied by 1e10 (coefficients up to
    1.087e15) is the benchmark's K(s): read as the file's coefficients divided by its leading
    denominator coefficient, 1e10 (to 1e-12 relative: a division each)."""
    scaled = "response = { numerator = [6136e10, 108700e10], denominator = [1e10, 89e10, 9258e10, 108700e10] }"
    f = tmp_path / "scaled.toml"
    f.write_text(_edit(BENCH, K_S, scaled))
    num, den = load_vehicle(f).thrusters[0].response
    assert num == pytest.approx((6136.0, 108700.0), rel=1e-12)
    assert den == pytest.approx((1.0, 89.0, 9258.0, 108700.0), rel=1e-12)


@pytest.mark.parametrize("response, message", [
    (((True,), (1.0, 1.0)), "port.response.numerator = (True,): must be a list of finite numbers"),
    (((1.0,), ("1", 1.0)), "port.response.denominator = ('1', 1.0): must be a list of finite numbers"),
    (((1e5,), (1.0, 1e5)), "every pole must be within 10000 1/s"),
])
def test_a_thrusters_response_refuses_text_booleans_and_fast_poles(response, message):
    """The Python API refuses what the file does (``Thruster``)."""
    with pytest.raises(ValueError) as info:
        Thruster("port", (0, 0, 0), (1, 0, 0), 100.0, 50.0, response=response)
    assert message in str(info.value), str(info.value)


# ------------------------------------------------------------------ MoorDyn files and their side files

CHAIN = """--------------------- MoorDyn Input File ------------------------------------
A chain from an anchor on a 150 m deep seabed to a fairlead 9 m below the surface.
---------------------- LINE TYPES ----------------------------------------------------------------------
TypeName   Diam    Mass/m     EA     BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)    (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
Chain      0.1      150.0     1e8    -1          0          2.3     1     1.0     1.0
---------------------- POINTS ---------------------------------------
ID   Attachment  X       Y     Z      Mass   Volume  CdA    Ca
(#)   (word/ID) (m)     (m)   (m)    (kg)   (m^3)   (m^2)  (-)
1     Fixed      -400    0     -150    0      0       0      0
2     Coupled    0       0     -9      0      0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (ID)     (ID)      (m)       (-)      (-)
1     Chain       1        2        450        40       pt
---------------------- OPTIONS -----------------------------------------
150           WtrDpth       water depth (m)
{option}
------------------------- need this line -------------------------------------
"""
"""A valid MoorDyn file (one chain, as tests/io/test_moordyn.py's) with one more option line."""
SECRET = "root:x:0:0:hunter2:/root:/bin/bash\nsecret: hunter2 xyzzy\nhunter2\nhunter2 hunter2 hunter2\n"
"""A file that is not a side file (as /etc/passwd is not): none of it may be shown."""
SHOWN = ("hunter2", "xyzzy", "/bin/bash", "0:0")
"""Pieces of ``SECRET`` that are in no path of the test's."""


@pytest.mark.parametrize("text, name, message", [
    ("", "empty.dat", "empty.dat: is empty (no MoorDyn section, no TOML key): nothing to run"),
    ("\n   \n# a comment\n", "blank.txt", "blank.txt: is empty"),
    ("# a scenario, not written yet\n", "blank.toml", "blank.toml: is empty"),
    ("hello world\n", "words.dat", "words.dat: neither a MoorDyn v2 input file (no LINE TYPES or ROD TYPES section) "
                                   "nor a scenario TOML file"),
], ids=["empty MoorDyn file", "blank MoorDyn file", "a TOML file of comments", "words"])
def test_an_empty_file_is_refused_not_run_as_the_built_in_scenario(text, name, message, tmp_path, capsys):
    """An empty file named on the command line ran the built-in walker scenario (it read as an
    empty TOML, all defaults): now exit 2, one line, no results."""
    f = tmp_path / name
    f.write_text(text)
    out = tmp_path / "res"
    rc, err = _run_cli(["run", str(f), "--out", str(out)], capsys)
    assert rc == 2 and len(err) == 1 and message in err[0], err
    assert not out.exists()


def _moordyn(tmp_path, option: str) -> Path:
    folder = tmp_path / "run"
    folder.mkdir(exist_ok=True)
    f = folder / "lines.dat"
    f.write_text(CHAIN.format(option=option))
    return f


def _refusal(f) -> str:
    with pytest.raises(ScenarioError) as info:
        moordyn.load_any(f)
    return str(info.value)


def test_a_current_profile_linked_to_another_file_is_named_not_shown(tmp_path):
    """``current_profile.txt`` a link to a file that is not a profile (a system file): the error
    names the profile, its line and column; it printed the line back."""
    f = _moordyn(tmp_path, "1             Currents")
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "elsewhere" / "passwd").write_text("a\nb\nc\n" + SECRET)
    (f.parent / moordyn.CURRENT_FILE).symlink_to(Path("..") / "elsewhere" / "passwd")
    msg = _refusal(f)
    assert f"{f.parent / moordyn.CURRENT_FILE}: line 4: column 1 (z, m) is not a finite number: a row is z ux uy uz" \
        in msg, msg
    assert not any(word in msg for word in SHOWN), msg


@pytest.mark.skipif(not os.path.isfile("/etc/passwd"), reason="needs a /etc/passwd")
def test_a_current_profile_linked_to_etc_passwd_shows_none_of_it(tmp_path):
    f = _moordyn(tmp_path, "1             Currents")
    (f.parent / moordyn.CURRENT_FILE).symlink_to("/etc/passwd")
    msg = _refusal(f)
    lines = Path("/etc/passwd").read_text().splitlines()
    assert "line 4: column 1 (z, m)" in msg or "line 4: no row" in msg, msg
    assert not any(field in msg for ln in lines for field in ln.split(":") if len(field) > 4), msg


@pytest.mark.parametrize("rows, message", [
    (b"h\nh\nh\n\xff\xfe\x00binary\n", "line 4: byte 0xff is not UTF-8 (a binary file?)"),  # (a UnicodeDecodeError)
    (b"h\nh\nh\n-150 0.1 nan 0\n", "line 4: column 3 (uy, m/s) is not a finite number"),
    (b"h\nh\nh\n-150 11 0 0\n", "line 4: the current (ux, uy) = (11, 0) m/s is 11 m/s: must be in [0, 10] m/s"),
    (b"h\nh\nh\n-15000 1 0 0\n", "line 4: z = -15000 m: must be in [-12000, 0] m for a row in the water"),
    (b"h\nh\nh\n-150 0.1 0 0\n-50 0.3 0 0\n-50 0.5 0 0\n", "line 6: z = -50 m again (line 5): give each depth once"),
], ids=["binary", "NaN", "11 m/s", "15 km deep", "a depth twice"])
def test_a_bad_current_profile_names_its_line_and_the_range(rows, message, tmp_path):
    f = _moordyn(tmp_path, "1             Currents")
    (f.parent / moordyn.CURRENT_FILE).write_bytes(rows)
    msg = _refusal(f)
    assert str(f.parent / moordyn.CURRENT_FILE) in msg and message in msg, msg


def test_a_current_profile_in_a_sibling_folder_is_read_right(tmp_path):
    """Decided: a side file reached out of the input's folder (here a link into ``../profiles``)
    is allowed and read as it is. Rows (z, ux, uy): (-150, 0.3, 0.4), (-50, 0, 0.2), (0, 1, 0) and
    one above the water (5 m, skipped): depths 0, 50, 150 m; speeds 1, 0.2, 0.5 m/s (hypot, by
    hand); headings 0, 90 and atan2(0.4, 0.3) = 53.130 deg (to 1e-9: float arithmetic)."""
    f = _moordyn(tmp_path, "1             Currents")
    (tmp_path / "profiles").mkdir()
    (tmp_path / "profiles" / "gulf.txt").write_text("MoorDyn steady currents\nmade here\nz ux uy uz\n"
                                                    "-150 0.3 0.4 0\n-50 0 0.2 0.0\n0 1 0 0\n5 2 0 0\n")
    (f.parent / moordyn.CURRENT_FILE).symlink_to(Path("..") / "profiles" / "gulf.txt")
    c = moordyn.load_any(f).water.current
    assert c.type == "table" and c.depths == (0.0, 50.0, 150.0)
    assert c.speeds == pytest.approx((1.0, 0.2, 0.5), abs=1e-9)
    assert c.headings_deg == pytest.approx((0.0, 90.0, math.degrees(math.atan(4.0 / 3.0))), abs=1e-9)


def test_a_seafloor_file_out_of_the_folder_is_named_not_shown(tmp_path):
    """SeafloorFile ``../elsewhere/secret.txt`` (a ``../`` path, allowed) that is not a grid: the
    error names the line of the MoorDyn file and the path, none of what the file holds; a binary
    one says so (it was a UnicodeDecodeError's words)."""
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "elsewhere" / "secret.txt").write_text("2 2\n" + SECRET)
    f = _moordyn(tmp_path, "../elsewhere/secret.txt   SeafloorFile")
    msg = _refusal(f)
    assert f"{f}: line 18: SeafloorFile: " in msg and "secret.txt" in msg, msg
    assert not any(word in msg for word in SHOWN), msg
    (tmp_path / "elsewhere" / "secret.txt").write_bytes(b"2 2\n\xfc\xfd\x00" * 10)
    assert "SeafloorFile: ../elsewhere/secret.txt: line 2: byte 0xfc is not UTF-8" in _refusal(f)


def test_a_seafloor_file_in_a_sibling_folder_is_read(tmp_path):
    """Valid: a level 2 x 2 grid at z = -150 m in ``../grids``: the scenario's bathymetry is that
    file (resolved)."""
    (tmp_path / "grids").mkdir()
    grid = tmp_path / "grids" / "floor.txt"
    grid.write_text("2 2\n-1000 1000\n-1000 1000\n-1000 -1000 -150\n1000 -1000 -150\n-1000 1000 -150\n"
                    "1000 1000 -150\n")
    f = _moordyn(tmp_path, "../grids/floor.txt   SeafloorFile")
    assert moordyn.parse(f.read_text(), str(f)).seafloor == str(grid.resolve())


def test_an_empty_scenario_name_is_refused_not_read_as_the_built_in_one(tmp_path, capsys):
    """`mjtether run ""` ran the built-in walker; it is refused, and nothing is written."""
    from mjtether import cli
    assert cli.main(["run", "", "--out", str(tmp_path / "res"), "--no-plots"]) == 2
    assert "scenario ''" in capsys.readouterr().err and not (tmp_path / "res").exists()

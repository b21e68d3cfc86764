"""Hand-picked bad inputs across scenario files, the command line, the Python API and the
environments: each is refused before anything is simulated, with one line that names the key
(or flag, or argument) and what is allowed; never a traceback, a hang or a silently wrong run.

Every case lists what the message must contain. The scenario cases run ``mjtether run`` on a
file (exit status 2, one line on stderr, no results folder); a few valid edge inputs that used
to be refused are checked to be accepted.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mjtether as mt
from mjtether import cli
from mjtether.scenario.config import ConfigError
from mjtether.scenario import Scenario, Simulation, Tether, load_scenario

ANCHOR = '[robot]\ntype = "anchor"\nposition = [40.0, 0.0, -90.0]\n[water]\ndepth = 100.0\n'
"""A valid base: the cases below add or replace keys (the [water] and [robot] sections are left
out where a case gives its own)."""

TOML = {  # name: (file body, what the one-line error must contain)
    "misspelt key": ("[tether]\nlenght = 100.0\n", "unknown key tether.lenght (did you mean length?)"),
    "unknown section": ("[boat]\nspeed = 1.0\n", "unknown key boat"),
    "number as text": ('[tether]\nlength = "100"\n', "tether.length = '100': must be a number in"),
    "boolean as number": ("[simulation]\nduration = true\n", "simulation.duration = True: must be a number"),
    "NaN duration": ("[simulation]\nduration = nan\n", "simulation.duration = nan"),
    "infinite step": ("[simulation]\ntimestep = inf\n", "simulation.timestep = inf"),
    "one element": ("[tether]\nsegments = 1\n", "tether.segments = 1: must be an integer in [4, 5000]"),
    "20 000 elements": ("[tether]\nsegments = 20000\n", "tether.segments = 20000"),
    "fractional elements": ("[tether]\nsegments = 2.5\n", "tether.segments = 2.5"),
    "absurd length": ("[tether]\nlength = 1e12\n", "tether.length = 1000000000000.0: must be a number in"),
    "a run of weeks": ("[simulation]\nduration = 1e6\n", "simulation.duration = 1e+06 s: at simulation.timestep = 0.005 s that is 2e+08 steps"),
    "history larger than memory": ("[simulation]\nduration = 20000.0\noutput_interval = 0.005\n[tether]\n"
                                   "segments = 2000\n", "simulation.output_interval = 0.005 s: that is 4e+06 samples"),
    "samples finer than the step": ("[simulation]\ntimestep = 0.01\noutput_interval = 0.005\n",
                                    "simulation.output_interval = 0.005: must be >= simulation.timestep"),
    "duration shorter than a step": ("[simulation]\nduration = 0.002\ntimestep = 0.005\noutput_interval = 0.005\n",
                                     "simulation.duration = 0.002: must be at least one simulation.timestep"),
    "unknown start": ('[simulation]\nstart = "warm"\n', "simulation.start = 'warm': must be steady, settle, auto"),
    "anchor above the surface": ('[robot]\ntype = "anchor"\nposition = [40.0, 0.0, 5.0]\n',
                                 "robot.position = [40.0, 0.0, 5.0]: the tow point is above the water surface"),
    "anchor below the seabed": ('[robot]\ntype = "anchor"\nposition = [40.0, 0.0, -150.0]\n[water]\ndepth = 100.0\n',
                                "robot.position = [40.0, 0.0, -150.0]: z = -150 m is below the seabed"),
    "anchor with no position": ('[robot]\ntype = "anchor"\n', "robot.position is required for an anchor"),
    "3-D waypoints": ('[ship]\nmode = "waypoints"\nwaypoints = [[10.0, 0.0, 0.0]]\n', "ship.waypoints = [[10.0, 0.0, 0.0]]"),
    "waypoints missing": ('[ship]\nmode = "waypoints"\n', "ship.waypoints is required when ship.mode = 'waypoints'"),
    "commands of two columns": ('[robot]\ncommands = [[0.0, 0.3]]\n', "robot.commands = [[0.0, 0.3]]: must be a list of"),
    "commands not from t = 0": ('[robot]\ncommands = [[5.0, 0.3, 0.0]]\n', "the times (first column, s) must start at 0"),
    "walker too fast": ('[robot]\ncommands = [[0.0, 3.0, 0.0]]\n', "speed 3 m/s at t = 0 s: must be in"),
    "turn in radians": ('[robot]\ncommands = [[0.0, 0.3, 45.0]]\n', "turn rate 45 deg/s at t = 0 s: must be in"),
    "heading in radians (old key)": ("[robot]\nheading = 1.57\n", "robot.heading: was in radians; give robot.heading_deg"),
    "slope in radians (old key)": ("[water]\nseabed_slope = 0.17\n", "water.seabed_slope: was in radians"),
    "unsorted current table": ('[water.current]\ntype = "table"\ndepths = [0.0, 50.0, 20.0]\nspeeds = [1.0, 0.5, 0.2]\n',
                               "water.current.depths = [0.0, 50.0, 20.0]: must be strictly increasing"),
    "current table rows differ": ('[water.current]\ntype = "table"\ndepths = [0.0, 50.0]\nspeeds = [1.0]\n',
                                  "water.current.speeds = [1.0]: must have as many rows as water.current.depths (2)"),
    "current table missing": ('[water.current]\ntype = "table"\n', "water.current.depths is required"),
    "water too dense": ("[water.density]\nrho = 1500.0\n", "water.density.rho = 1500.0: must be a number in [900, 1100]"),
    "speed in m/s and knots": ("[water.current]\nspeed = 1.0\nspeed_kn = 2.0\n", "water.current.speed is given twice"),
    "empty tension band": ("[winch]\nband = [500.0, 100.0]\n", "winch.band = [500.0, 100.0]: must be (low, high)"),
    "payout faster than the drum": ("[winch]\nrate = 3.0\nmax_rate = 1.0\n", "winch.rate = 3.0: must be within"),
    "cable longer than the drum": ("[tether]\nlength = 500.0\n[winch]\nmax_length = 300.0\n",
                                   "tether.length = 500.0: must be in [winch.min_length, winch.max_length] = [0, 300] m"),
    "section given a value": ("tether = 5\n", "tether must be a section [tether]"),
    "walker a million metres out": ('[robot]\ntype = "walker"\nstart = [1e6, 0.0]\n',  # (an OverflowError once)
                                    "tether.length = 300 m: too short for its ends"),
    "samples between steps": ("[simulation]\ntimestep = 0.005\noutput_interval = 0.0075\n",  # (was every 0.01 s)
                              "simulation.output_interval = 0.0075: must be within 5 % of a whole number of "
                              "simulation.timestep (0.005 s): it is 1.5 steps; give 0.005 or 0.01 s"),
    "not TOML": ("[tether\nlength = 3\n", "not valid TOML"),
}


def _anchor_text(body: str) -> str:
    """``body`` on the valid anchor base, the base's sections dropped where ``body`` has its own."""
    base = "" if "[robot]" in body else '[robot]\ntype = "anchor"\nposition = [40.0, 0.0, -90.0]\n'
    base += "" if "[water]" in body else "[water]\ndepth = 100.0\n"
    return body + base


def _run_cli(args, capsys) -> tuple[int, list[str]]:
    rc = cli.main(args)
    return rc, capsys.readouterr().err.strip().splitlines()


@pytest.mark.parametrize("case", list(TOML))
def test_bad_scenario_file_is_refused_with_the_key(case, tmp_path, capsys):
    body, message = TOML[case]
    f = tmp_path / "bad.toml"
    f.write_text(_anchor_text(body))
    out = tmp_path / "res"
    rc, err = _run_cli(["run", str(f), "--out", str(out)], capsys)
    assert rc == 2 and len(err) == 1, err
    assert str(f) in err[0] and message in err[0], err[0]
    assert not out.exists()


ENCODINGS = {  # name: (bytes of the file, what the error must contain)
    "Latin-1": ("# profondeur mesur\xe9e\n[water]\ndepth = 100.0\n".encode("latin-1"),
                "line 1: byte 0xe9 is not UTF-8 (a binary file?); save it as UTF-8 text"),
    "UTF-16": ("[water]\ndepth = 100.0\n".encode("utf-16"), "is UTF-16 text; save it as UTF-8"),
}


@pytest.mark.parametrize("case", list(ENCODINGS))
def test_scenario_file_in_another_encoding_is_refused(case, tmp_path, capsys):
    data, message = ENCODINGS[case]
    f = tmp_path / "enc.toml"
    f.write_bytes(data)
    rc, err = _run_cli(["solve", str(f)], capsys)
    assert rc == 2 and len(err) == 1 and message in err[0], err


def test_utf8_with_a_byte_order_mark_is_read(tmp_path):
    """A UTF-8 file saved with a byte-order mark (as some Windows editors do) is UTF-8: accepted."""
    f = tmp_path / "bom.toml"
    f.write_bytes("\ufeff".encode("utf-8") + _anchor_text("").encode("utf-8"))
    assert load_scenario(f).water.depth == 100.0


CLI = {  # name: (arguments after the scenario file, what the one-line error must contain)
    "--set without a value": (["run", "--set", "tether.length"], "--set 'tether.length': must be KEY=VALUE"),
    "--set of an unknown key": (["run", "--set", "tether.lenght=3"], "unknown key tether.lenght"),
    "--set of an unknown section": (["solve", "--set", "boat.speed=3"], "unknown key boat"),
    "--set with a bad value": (["run", "--set", "tether.segments=abc"], "tether.segments = 'abc': must be an integer"),
    "--set out of range": (["render", "--set", "simulation.timestep=1"], "simulation.timestep = 1: must be a number"),
    "render --duration 0": (["render", "--duration", "0"], "simulation.duration = 0.0: must be a number in"),
    "render --duration nan": (["render", "--duration", "nan"], "simulation.duration = nan"),
    "render to an unknown format": (["render", "-o", "{tmp}/run.avi"], "video file must end in .mp4 or .gif"),
    "render onto a folder": (["render", "-o", "{tmp}/clip.mp4"], "is a folder"),
    "render over an existing video": (["render", "-o", "{tmp}/old.gif"], "exists; choose another name or pass --overwrite"),
    "demo for no time": (["demo", "--duration", "0"], "--duration must be in [0.001, 86400.0] s"),
    "demo current in knots": (["demo", "--current-knots", "100"], "--current-knots must be in [0.0, 19.0] kn"),
    "demo with one element": (["demo", "--segments", "0"], "tether.segments must be an integer >= 1"),
    "video of an unknown format": (["run", "--video", "clip.txt"], "--video must name an .mp4 or .gif file"),
    "scenario is a folder": (["solve", "{tmp}"], "is a folder; give a scenario .toml file"),
    "scenario missing": (["run", "{tmp}/nope.toml"], "nope.toml: no such file"),
}


@pytest.mark.parametrize("case", list(CLI))
def test_bad_command_line_is_refused_before_simulating(case, tmp_path, capsys):
    args, message = CLI[case]
    (tmp_path / "clip.mp4").mkdir()
    (tmp_path / "old.gif").write_bytes(b"GIF89a")
    f = tmp_path / "s.toml"
    f.write_text(_anchor_text(""))
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    if args[0] in ("run", "render", "solve") and not any(a.startswith(str(tmp_path)) and a.endswith(("toml", str(tmp_path)))
                                                         for a in args[1:2]):
        args.insert(1, str(f))
    if args[0] == "run":
        args += ["--out", str(tmp_path / "res")]
    rc, err = _run_cli(args, capsys)
    assert rc == 2 and len(err) == 1 and message in err[0], err
    assert not (tmp_path / "res").exists()
    assert (tmp_path / "old.gif").read_bytes() == b"GIF89a"


def test_a_tether_too_heavy_for_its_EA_names_the_keys(capsys):
    """tether.mass_per_length at its maximum (1e4 kg/m) on the built-in scenario's EA: no steady
    state within the tether's strength, and the one line says which keys and why (it named none)."""
    rc, err = _run_cli(["solve", "--set", "tether.mass_per_length=1e4"], capsys)
    assert rc == 1 and len(err) == 1, err
    for part in ("tether.mass_per_length = 10000 kg/m", "tether.EA = 5e+06 N would stretch by", "(at most 10 %)"):
        assert part in err[0], err[0]


@pytest.mark.parametrize("args, parts", [
    (["solve", "--set", "tether.diameter=2"],
     ("tether.diameter = 2 m", "above the walker's tow point", "diameter below 1.86 m")),
    (["solve", "--set", "tether.density=1"],
     ("tether.density = 1 kg/m^3", "4.93 N/m buoyant", 'simulation.start = "settle"')),
    (["solve", "static_anchor_current", "--set", "tether.length=10000"],
     ("robot.position is 40.00 m above the seabed", "tether.length = 10000 m is 9851.34 m more than the 148.66 m")),
], ids=["a 2 m tether on the walker", "a buoyant tether", "10 km of tether to an anchor 149 m away"])
def test_a_start_that_cannot_be_solved_names_the_keys(args, parts, capsys):
    """Valid values for which the steady start has no answer: one line naming the keys that make
    it so and what would do (they named none: "below the seabed", "Newton stalled", "rest on the
    seabed between its two ends")."""
    rc, err = _run_cli(args, capsys)
    assert rc == 1 and len(err) == 1, err
    for part in parts:
        assert part in err[0], err[0]


@pytest.mark.skipif(not __import__("os").path.isdir("/proc/self"), reason="needs Linux's /proc")
def test_results_on_a_file_system_that_refuses_folders_is_one_line(tmp_path, capsys):
    """/proc takes no new folders (even for root): one line, exit 1, nothing left behind."""
    f = tmp_path / "s.toml"
    f.write_text(_anchor_text("[simulation]\nduration = 0.5\n"))
    rc, err = _run_cli(["run", str(f), "--out", "/proc/mjtether-results", "--no-plots"], capsys)
    assert rc == 1 and len(err) == 1 and "while writing results to '/proc/mjtether-results'" in err[0], err


API = {  # name: (call, what the ValueError must contain)
    "tether length as text": (lambda: mt.TetherSpec(length="100"), "tether.length must be a finite number, got '100'"),
    "tether of 1e12 m": (lambda: mt.TetherSpec(length=1e12), "tether.length must be in"),
    "tether of 20 000 elements": (lambda: mt.TetherSpec(length=100.0, segments=20000), "tether.segments"),
    "boolean diameter": (lambda: mt.TetherSpec(length=100.0, diameter=True), "tether.diameter must be a finite number"),
    "winch step NaN": (lambda: mt.Winch(length=10.0).advance(math.nan, 0.0, 0.0), "winch.advance dt must be a finite"),
    "winch step negative": (lambda: mt.Winch(length=10.0).advance(-0.1, 0.0, 0.0), "winch.advance dt must be > 0"),
    "winch tension NaN": (lambda: mt.Winch(length=10.0).advance(0.1, 0.0, math.nan), "winch.advance tension"),
    "scenario with two elements": (lambda: Scenario(tether=Tether(segments=2)), "tether.segments = 2"),
    "section of the wrong kind": (lambda: Scenario(tether=Simulation()), "tether must be a section [tether]"),
    "negative duration": (lambda: Simulation(duration=-1.0), "simulation.duration = -1.0"),
    "duration as numpy NaN": (lambda: Simulation(duration=np.float64("nan")), "simulation.duration = nan"),
    "load with a bad override": (lambda: load_scenario(overrides=["water.depth=-3"]), "water.depth = -3"),
}




def _on_a_sim(call):
    """``call(sim)`` on a small simulation: 100 m of tether between fixed points 70 m apart."""
    import mujoco

    def run():
        spec = mujoco.MjSpec()
        spec.option.timestep = 0.005
        water = mt.WaterColumn(depth=200.0)
        tm = mt.add_tether(spec, mt.TetherSpec(length=100.0, segments=10), mt.FixedPoint([0, 0, 0]),
                           mt.FixedPoint([70, 0, 0]), water=water, max_length=100.0)
        with mt.Simulation(spec, water, [tm]) as sim:
            call(sim)
    return run


_T = mt.TetherSpec(length=100.0, segments=10)
API.update({  # (each a traceback or a silent no-op before)
    "add_tether(None, ...)": (lambda: mt.add_tether(None, _T, mt.FixedPoint([0, 0, 0]), mt.FixedPoint([50, 0, 0])),
                              "spec must be a mujoco.MjSpec"),
    "add_tether('spec', ...)": (lambda: mt.add_tether("spec", _T, mt.FixedPoint([0, 0, 0]), mt.FixedPoint([50, 0, 0])),
                                "spec must be a mujoco.MjSpec (the model to add the tether to"),
    "max_timestep at NaN speed": (lambda: mt.stability.max_timestep(_T, mt.WaterColumn(depth=100.0),
                                                                   relative_speed=math.nan),
                                  "max_timestep relative_speed = nan: must be a finite number >= 0"),
    "run for ever": (_on_a_sim(lambda sim: sim.run(math.inf)),
                     "Simulation.run duration = inf: must be a number of seconds in [0, 1e+09]"),
    "run backwards": (_on_a_sim(lambda sim: sim.run(-5)), "Simulation.run duration = -5: must be"),
    "step backwards": (_on_a_sim(lambda sim: sim.step(-1)), "Simulation.step nstep must be an integer >= 1, got -1"),
    "reel in below the span": (_on_a_sim(lambda sim: sim.tether().set_length(0.0)),
                               "set_length length = 0.0 m: the tether's fixed ends are 70 m apart; give length >= "
                               "70 m (inextensible)"),
})


@pytest.mark.parametrize("case", list(API))
def test_bad_api_arguments_raise_value_errors_naming_them(case):
    call, message = API[case]
    with pytest.raises(ValueError) as info:
        call()
    assert message in str(info.value), str(info.value)


def test_config_errors_carry_the_key_path():
    with pytest.raises(ConfigError) as info:
        load_scenario(overrides=["tether.segments=1"])
    assert info.value.key == "tether.segments"


def test_numpy_scalars_are_valid_numbers():
    """Values computed with NumPy (np.int64, np.float32) are valid input, as Python numbers are."""
    sc = Scenario(tether=Tether(segments=np.int64(10), length=np.float32(240.0)))
    assert sc.tether.segments == 10 and isinstance(sc.tether.segments, int)


ENV_KWARGS = {  # name: (keyword arguments, what the error must contain)
    "start out of the tether's reach": ({"start_distance": 1e4}, "start_distance = 10000.0: the walker"),
    "unknown keyword": ({"segmnets": 10}, "unknown keyword argument 'segmnets'"),
    "fractional segments": ({"segments": 2.5}, "segments = 2.5: must be an integer in [4, 400]"),
    "NaN depth": ({"depth": math.nan}, "depth = nan"),
    "minimum above the start": ({"min_length": 200.0}, "min_length = 200.0: 200 m must be <= tether_length"),
    "text frame_skip": ({"frame_skip": "10"}, "frame_skip = '10'"),
    "camera config as a name": ({"default_camera_config": "track"},  # (a dict-update error before)
                                "default_camera_config = 'track': must be a dict, as in Gymnasium's MuJoCo environments"),
}


@pytest.mark.parametrize("case", list(ENV_KWARGS))
def test_bad_environment_arguments_are_refused_in_the_constructor(case):
    from mjtether.envs import TetherWinchEnv

    kwargs, message = ENV_KWARGS[case]
    with pytest.raises(ValueError) as info:
        TetherWinchEnv(**kwargs)
    assert message in str(info.value), str(info.value)


def test_environment_accepts_numpy_integers_and_names_a_nan_action():
    """``segments=np.int64(10)`` is a valid integer; a NaN action is refused naming the action
    (before, it surfaced as a leg inverse-kinematics error)."""
    from mjtether.envs import TetheredWalkerEnv, TetherWinchEnv

    env = TetherWinchEnv(segments=np.int64(10))
    try:
        env.reset(seed=0)
        with pytest.raises(ValueError, match=r"action must be 1 finite numbers in \[-1, 1\]"):
            env.step(np.array([np.nan], dtype=np.float32))
    finally:
        env.close()
    env = TetheredWalkerEnv(segments=10)
    try:
        env.reset(seed=0)
        with pytest.raises(ValueError, match=r"action must be 3 finite numbers"):
            env.step([0.0, math.nan, 0.0])
        with pytest.raises(ValueError, match=r"action must be 3 finite numbers"):
            env.step([0.0, 0.0])
    finally:
        env.close()


def count_cases() -> dict:
    """How many bad inputs this file checks, by where they enter (for the issue's note)."""
    return {"toml": len(TOML) + len(ENCODINGS), "cli": len(CLI), "api": len(API) + 1,
            "envs": len(ENV_KWARGS) + 3}

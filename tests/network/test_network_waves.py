"""A network's sea: ``[waves]`` (the scenario's keys and checks) or ``water.wave_components``, its
round trip, and one line under a regular wave against MoorDyn-C 2.7 (issue 43)."""

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.optimize

from mjtether.io import moordyn
from mjtether.network import NetworkError, from_dict, to_dict
from mjtether.network import run as nr

_spec = importlib.util.spec_from_file_location("test_moordyn_waves",
                                               Path(__file__).parents[1] / "io" / "test_moordyn_waves.py")
_md_waves = importlib.util.module_from_spec(_spec)  # (MoorDyn-C's force on a fixed fairlead: fairlead_force)
_spec.loader.exec_module(_md_waves)

G, RHO = 9.80665, 1025.0
DEPTH, HEIGHT, PERIOD = 50.0, 4.0, 10.0
ROPE = {"diameter": 0.1, "mass_per_length": 15.0, "EA": 1e6, "cd_normal": 1.2, "ca_normal": 1.0,
        "cd_tangential": 0.0, "ca_tangential": 0.0}


def rope_net(waves=None, duration=30.0, **water) -> dict:
    """An 80 m rope (d 0.1 m, 15 kg/m, EA 1 MN) from an anchor on a 50 m deep seabed to a fixed
    fairlead 5 m under the mean water line, 60 m off: fully suspended, 5.5 kN at the top."""
    data = {"water": {"depth": DEPTH, "rho": RHO, "gravity": G, **water},
            "simulation": {"duration": duration, "output_interval": 0.01, "start": "as_written"},
            "line_types": {"rope": ROPE},
            "points": {"1": {"kind": "fixed", "position": [-60.0, 0.0, -DEPTH]},
                       "2": {"kind": "fixed", "position": [0.0, 0.0, -5.0]}},
            "lines": [{"name": "1", "type": "rope", "a": "1", "b": "2", "length": 80.0, "segments": 20}]}
    if waves is not None:
        data["waves"] = waves
    return data


def _k(omega: float) -> float:
    """The dispersion relation omega^2 = g k tanh(k h) solved here (Brent), not by mjtether."""
    return scipy.optimize.brentq(lambda k: G * k * math.tanh(k * DEPTH) - omega ** 2, 1e-6, 10.0)


def test_a_network_takes_the_scenarios_waves_table_and_keeps_it():
    """``[waves]`` in a network's TOML is the scenario's section (``sea.Waves``); the water column
    carries its sea, whose surface is H/2 cos(k x - omega t + phase) with k from the dispersion
    relation solved here (to 1e-9 m; the elevation is closed form), and to_dict / from_dict keep
    it (as they keep ``water.wave_components``)."""
    net = from_dict(rope_net({"type": "regular", "height": HEIGHT, "period": PERIOD, "phase_deg": 30.0,
                              "heading_deg": 20.0}))
    assert net.waves.type == "regular" and net.waves.height == HEIGHT
    sea = nr.water_of(net).waves
    w, k = 2 * math.pi / PERIOD, _k(2 * math.pi / PERIOD)
    b = math.radians(20.0)
    for x, y, t in ((0.0, 0.0, 10.0), (-37.0, 12.0, 13.3), (25.0, -8.0, 71.9)):  # (after the 1-period build-up)
        want = HEIGHT / 2 * math.cos(k * (x * math.cos(b) + y * math.sin(b)) - w * t + math.radians(30.0))
        assert sea.elevation(x, y, t) == pytest.approx(want, abs=1e-9)
    assert from_dict(to_dict(net)) == net
    rows = [[0.5, 0.4, 28.6, 36.9], [0.7, 0.6, -57.3, -74.1]]
    net2 = from_dict(rope_net(wave_components=rows))
    assert net2.wave_components == tuple(map(tuple, rows)) and net2.waves is None
    assert from_dict(to_dict(net2)) == net2
    eta = sum(a * math.cos(_k(w) * (10 * math.cos(math.radians(b))) - w * 4.0 + math.radians(p)) for a, w, b, p in rows)
    assert nr.water_of(net2).waves.elevation(10.0, 0.0, 4.0) == pytest.approx(eta, abs=1e-9)
    assert nr.water_of(from_dict(rope_net())).waves is None  # (no [waves]: a flat sea)
    assert "waves" not in to_dict(from_dict(rope_net())) and "wave_components" not in to_dict(net)["water"]


@pytest.mark.parametrize("waves, water, words", [
    ({"type": "regular", "height": -1.0}, {}, "waves.height = -1"),
    ({"type": "regular", "height": 0.0}, {}, "waves.height"),
    ({"type": "choppy"}, {}, "waves.type"),
    ({"type": "regular", "height": 2.0, "hieght": 3.0}, {}, "hieght"),
    ("regular", {}, "[waves]"),
    ({"type": "regular", "height": 2.0}, {"wave_components": [[1.0, 0.5, 0.0, 0.0]]}, "not both"),
    (None, {"wave_components": [[1.0, 0.0, 0.0, 0.0]]}, "water.wave_components[0] omega = 0.0"),
    (None, {"wave_components": [[-1.0, 0.5, 0.0, 0.0]]}, "water.wave_components[0] amplitude = -1.0"),
    (None, {"wave_components": [[1.0, 0.5, 0.0]]}, "water.wave_components[0] must be [amplitude m"),
    (None, {"wave_components": "1 0.5 0 0"}, "water.wave_components must be a list"),
])
def test_bad_waves_name_the_key(waves, water, words):
    """Bad ``[waves]`` or ``water.wave_components`` entries are refused naming the key (the
    scenario's own checks and ranges for ``[waves]``)."""
    with pytest.raises(NetworkError) as err:
        from_dict(rope_net(waves, **water), "net.toml")
    assert words in str(err.value) and str(err.value).startswith("net.toml")


MOORDYN_FILE = """--------------------- MoorDyn Input File ------------------------------------
The rope of rope_net under a regular wave (H 4 m, T 10 s) given as one frequency component
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
rope       0.1     15         1e6        -1.0        0          1.2    1.0    0.0     0.0
---------------------- POINTS --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     -60     0.0     -50.0   0      0       0      0
2     Fixed     0.0     0.0     -5.0    0      0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     rope       1        2         80        20      -
---------------------- OPTIONS -----------------------------------------
0.0005        dtM
1025          WtrDnsty
50            WtrDpth
0.0           TmaxIC
7             WaveKin     (the components of wave_frequencies.txt summed at the nodes)
------------------------- need this line --------------------------------------
"""


def _last_periods(t, x, periods: int) -> tuple:
    """(mean, half peak-to-peak) of ``x`` over the last ``periods`` wave periods."""
    late = t > t[-1] - periods * PERIOD + 1e-9
    return float(x[late].mean()), float(0.5 * np.ptp(x[late]))


def test_a_regular_wave_on_one_line_as_moordyn_c(tmp_path):
    """Issue 43: the same regular wave (H 4 m, T 10 s, heading +x, in 50 m of water) on one line
    in MoorDyn-C 2.7 (a one-component wave_frequencies.txt, WaveKin 7: 2 m at 2 pi / 10 rad/s,
    MoorDyn's eta = 2 sin(omega t - k x), i.e. phase_deg = 90 in mjtether's cos(k x - omega t +
    phase)) and in mjtether (the network's ``[waves]``, type regular): the force on the fixed
    fairlead (MoorDyn-C's ``test_moordyn_waves.fairlead_force``, mjtether's end force)'s mean
    and amplitude (half peak-to-peak) over the last two of three periods within 2 % (the
    issue's tolerance; both are periodic to 0.1 % from the second period on). Measured: mean
    5515.4 N (MoorDyn-C) and 5515.0 N (mjtether), -0.01 %; amplitude 383.0 N and 385.4 N,
    +0.6 %. The peaks come at the same time, within 0.05 s (half a percent of the period;
    measured 0.007 s): the phase conventions agree. Both start from the line's still-water
    catenary at rest (TmaxIC 0; ``start = "as_written"``) and settle within the first period.

    The rope is chosen so that the tension follows the wave: EA 1 MN. With EA 10 MN the same
    rope rings at 1.4 to 1.7 Hz (its 14th to 17th wave harmonics) on top of the wave's response;
    the first harmonic still agrees (384.7 N and 383.6 N), but the ringing adds 4 % (MoorDyn-C at
    its 1 ms step) or 0.5 % (mjtether at its 2.4 ms one) to the peak-to-peak and depends on
    each program's step (mjtether at 1 ms: -1.1 % against MoorDyn-C, at 2.4 ms -3.0 %), so
    it is not a comparison of the waves. The test's MoorDyn-C runs at dtM 0.5 ms, mjtether at
    the step it picks (2.4 ms)."""
    path = tmp_path / "rope.txt"
    path.write_text(MOORDYN_FILE)
    (tmp_path / "wave_frequencies.txt").write_text(f"0.0 0.0 0.0\n{2 * math.pi / PERIOD!r} {HEIGHT / 2!r} 0.0\n")
    duration = 3 * PERIOD
    t_md, f_md = _md_waves.fairlead_force(path, duration, 0.01)
    net = from_dict(rope_net({"type": "regular", "height": HEIGHT, "period": PERIOD, "phase_deg": 90.0,
                              "ramp_periods": 0.0}, duration=duration))  # (MoorDyn-C has no build-up)
    r, rows = nr.simulate(net)
    r.sim.close()
    f_mj = rows[:, nr.columns(net).index("line1_B_tension_N")]
    (m_md, a_md), (m_mj, a_mj) = _last_periods(t_md, f_md, 2), _last_periods(rows[:, 0], f_mj, 2)
    assert m_mj == pytest.approx(m_md, rel=0.02), (m_md, m_mj)
    assert a_mj == pytest.approx(a_md, rel=0.02), (a_md, a_mj)
    assert a_md > 0.05 * m_md  # (the wave moves the tension: 7 % of its mean)
    last = (t_md > duration - PERIOD, rows[:, 0] > duration - PERIOD)  # (and in phase: the peaks' times)
    peaks = t_md[last[0]][np.argmax(f_md[last[0]])], rows[last[1], 0][np.argmax(f_mj[last[1]])]
    assert abs(peaks[0] - peaks[1]) <= 0.05, peaks
    read = moordyn.read(path)  # (the file's own component reads as the same sea)
    for t in (0.0, 2.7, 6.1):
        assert nr.water_of(read).waves.elevation(13.0, 0.0, t) == pytest.approx(
            nr.water_of(net).waves.elevation(13.0, 0.0, t), abs=1e-9)


def test_set_takes_the_seas_keys_on_a_network():
    """``--set waves.KEY=VALUE`` on a network: the sea's keys with the scenario's checks (a regular
    wave needs a height: refused naming it), on a flat network too; the wave field it gives
    has the height asked (its one component's amplitude, half of it)."""
    from mjtether.network import with_overrides

    flat = from_dict(rope_net())
    net = with_overrides(flat, ["waves.type=regular", "waves.height=3", "waves.period=9"])
    assert net.waves.type == "regular" and net.wave_field().components.amplitude[0] == pytest.approx(1.5)
    with pytest.raises(NetworkError, match="height"):
        with_overrides(flat, ["waves.type=regular"])
    with pytest.raises(NetworkError, match="waves.KEY"):
        with_overrides(flat, ["waves.hss=3"])

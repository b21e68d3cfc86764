"""MoorDyn's waves as frequency components (``WaveKin`` 2 and 7, ``mjtether.io.moordyn_waves``):
the components read against MoorDyn-C 2.7's own wave kinematics, a line under MoorDyn's
``tests/Mooring/wavekin_2`` waves against MoorDyn-C's run of it, and the forms refused."""

import importlib.util
import math
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from mjtether.io import moordyn
from mjtether.network import Network
from mjtether.network import run as nr
from mjtether.scenario import ScenarioError

_spec = importlib.util.spec_from_file_location("moordyn_c", Path(__file__).with_name("moordyn_c.py"))
moordyn_c = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(moordyn_c)
md = moordyn_c.moordyn

WAVEKIN_2 = Path(__file__).resolve().parents[1] / "data" / "moordyn_waves" / "wavekin_2"

LINE = """--------------------- MoorDyn Input File ------------------------------------
one rope between two fixed points, under waves
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
rope       0.1     20         1e8        -1.0        0          1.2    1.0    0.5     0.0
---------------------- POINTS --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     -80     0.0     -50.0   0      0       0      0
2     {top}     0.0     0.0     -5.0    0      0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     rope       1        2         100       10      -
---------------------- OPTIONS -----------------------------------------
0.001         dtM
50            WtrDpth
0.0           TmaxIC
{kin}         WaveKin
------------------------- need this line --------------------------------------
"""
COMPONENTS = [(0.4, 0.3, 0.4, 0.5), (0.6, -0.7, 0.2, -1.0)]  # omega rad/s, re m, im m, beta rad


def _folder(tmp_path, kin, rows=None, top="Fixed") -> Path:
    """A MoorDyn file with ``WaveKin = kin`` and its ``wave_frequencies.txt`` (``rows``, lines of
    text; by default 0, the two ``COMPONENTS`` and zero rows every 0.2 rad/s up to 12 rad/s, so
    that WaveKin 2 samples the waves every pi / 12 s) and, for WaveKin 2, ``water_grid.txt``."""
    if rows is None:
        comps = {round(w / 0.2): (w, re, im, b) for w, re, im, b in COMPONENTS}
        rows = [" ".join(repr(x) for x in comps.get(i, (round(0.2 * i, 10), 0.0, 0.0)))
                for i in range(61)]
    (tmp_path / "wave_frequencies.txt").write_text("\n".join(rows) + "\n")
    if kin == 2:
        axes = (np.arange(-100.0, 20.1, 2.0), np.arange(-20.0, 20.1, 2.0), np.arange(-51.0, 5.1, 1.0))
        (tmp_path / "water_grid.txt").write_text("--- waves grid\nx, y, z\nblocks\n" + "".join(
            "1\n" + " ".join(repr(float(v)) for v in a) + "\n" for a in axes))
    path = tmp_path / "line.txt"
    path.write_text(LINE.format(kin=kin, top=top))
    return path


@pytest.mark.parametrize("kin", [7, 2])
def test_the_components_are_moordyn_cs_own_waves(tmp_path, kin):
    """The surface, particle velocity and acceleration of the components read from
    ``wave_frequencies.txt`` against MoorDyn-C's own (``GetWavesKin``, at its integrator's time
    after steps to 3.3, 10.4 and 22.3 s) at four points under the surface, with headings 0.5
    and -1.0 rad and complex amplitudes in all four quadrants' mix (so the phase and heading
    conventions show): WaveKin 7 (MoorDyn-C sums |A| sin(omega t - k l + arg A)) within 1e-9 of
    the 1.2 m of amplitude (the same sums; measured 7e-11, from MoorDyn-C's own wavenumber
    iteration and its integrator's clock); WaveKin 2 (an inverse FFT,
    Re(A exp(i (omega t - k l))), on a grid of 2 m by 2 m by 1 m, sampled every pi/12 s and
    interpolated linearly) within 1 % of it (linear interpolation of a wave of frequency omega
    sampled dt apart is off by up to (omega dt)^2 / 8 = 0.3 % at 0.6 rad/s; measured 0.16 %).
    A phase convention off by a quarter period would be 70 % off."""
    path = _folder(tmp_path, kin)
    net = moordyn.read(path)
    sea = nr.water_of(net).waves
    scale = sum(abs(complex(re, im)) for _, re, im, _ in COMPONENTS)
    points = np.array([[0.0, 0.0, -5.0], [-30.0, 10.0, -20.0], [-70.0, -5.0, -45.0], [10.0, 3.0, -3.5]])
    worst = 0.0
    with moordyn_c._cwd(tmp_path):
        s = md.Create(str(path))
        try:
            md.Init(s, np.zeros(0), np.zeros(0))
            waves, t = md.GetWaves(s), 0.0
            for dt in (3.3, 7.1, 11.9):
                md.Step(s, np.zeros(0), np.zeros(0), t, dt)
                t += dt
                eta, u, a = sea.state(points, t)
                for i, q in enumerate(points):
                    U, Ud, zeta, _ = md.GetWavesKin(waves, *q, None)
                    assert q[2] < min(zeta, eta[i])  # (under the surface: where both take the waves)
                    worst = max(worst, abs(zeta - eta[i]), *np.abs(np.array(U) - u[i]),
                                *np.abs(np.array(Ud) - a[i]))
        finally:
            md.Close(s)
    assert worst <= (1e-9 if kin == 7 else 0.01) * scale, worst / scale


@moordyn_c._scratch
def fairlead_force(path, duration: float, every: float) -> tuple:
    """(times s, |force| N) of line 1 on the point at its end B (a fixed point) in MoorDyn-C,
    every ``every`` s: minus the end segment's tension plus the end node's weight with buoyancy,
    drag, Froude-Krylov force and seabed force (what mjtether's end force, the constraint holding
    its end node, carries; the end segment's tension alone is 8 kN less on wavekin_2's chain)."""
    with moordyn_c._cwd(path.parent):
        s = md.Create(str(path))
        try:
            md.Init(s, np.zeros(0), np.zeros(0))
            ln = md.GetLine(s, 1)
            n = md.GetLineN(ln)
            times, forces, t = [], [], 0.0
            for _ in range(round(duration / every)):
                md.Step(s, np.zeros(0), np.zeros(0), t, every)
                t += every
                f = -np.array(md.GetLineNodeTen(ln, n)) + sum(np.array(get(ln, n)) for get in (
                    md.GetLineNodeWeight, md.GetLineNodeDrag, md.GetLineNodeFroudeKrilov, md.GetLineNodeSeabedForce))
                times.append(t)
                forces.append(np.linalg.norm(f))
            return np.array(times), np.array(forces)
        finally:
            md.Close(s)


def _wavekin_2_run(folder: Path, kin: int, duration: float) -> tuple:
    """(times s, MoorDyn-C's force on the fairlead N, mjtether's at the same times) of MoorDyn's
    ``wavekin_2.txt`` (its files copied to ``folder``) run with ``WaveKin = kin`` (2, or 0: still
    water). The copy's ``water_grid.txt`` is the y = 0 plane of MoorDyn's own, every 2 m in x
    (MoorDyn-C spends 13 s building its 501 x 5 x 57 grid, 2.5 s for this one; the waves travel
    along x, and interpolating them linearly over 2 m is off by (k dx)^2 / 8 < 1e-3)."""
    shutil.copytree(WAVEKIN_2, folder)
    path = folder / "wavekin_2.txt"
    text = path.read_text()
    assert "2             WaveKin" in text
    path.write_text(text.replace("2             WaveKin", f"{kin}             WaveKin"))
    axes = (np.arange(-450.0, 50.1, 2.0), np.array([0.0]), np.arange(-51.0, 5.1, 1.0))
    blocks = "".join("1\n" + " ".join(repr(float(v)) for v in a) + "\n" for a in axes)
    (folder / "water_grid.txt").write_text(f"--- wavekin_2's grid, its y = 0 plane, 2 m in x\nx y z\nblocks\n{blocks}")
    times, theirs = fairlead_force(path, duration, 0.1)
    net = moordyn.read(path, overrides=[f"simulation.duration={duration}", "simulation.output_interval=0.1"])
    r, rows = nr.simulate(net)
    r.sim.close()
    return times, theirs, np.interp(times, rows[:, 0], rows[:, nr.columns(net).index("line1_B_tension_N")])


def test_a_line_under_moordyns_wavekin_2_waves_follows_moordyn_c(tmp_path):
    """MoorDyn's own tests/Mooring/wavekin_2 case (v2.7.1, kept in tests/data/moordyn_waves): a
    410 m chain (0.252 m, 390 kg/m, EA 1.674 GN) from an anchor on a 50 m deep seabed to a fixed
    point 2 m under the surface 400 m off, in its sheared current (Currents 1, to 1.25 m/s) and
    under four frequency components (WaveKin 2: 0.5 m at 0.2 rad/s, 0.2 m at 0.25, 1 m at 0.4,
    0.5 m at 0.45, phases 0 and 90 degrees), each program from the file's positions at rest
    (TmaxIC 0), 60 s, sampled every 0.1 s. After the start's transient (20 s):

    * the fairlead force (``fairlead_force``) within 0.5 % of MoorDyn-C's (measured 0.38 %): the still-water runs
      (WaveKin 0, the current alone) differ by as much (0.35 %: how each settles the laid
      chain, as in ``test_moordyn_files``' chain files);
    * the waves' part of it, each program's run with the waves less its still-water run (a
      range of 22 kN), within 5 % of that range (measured 3.2 %, rms 0.8 %): MoorDyn-C samples
      these waves every pi / 6 s (its top row is 6 rad/s) and interpolates them linearly
      (0.7 % off at 0.45 rad/s), and the start's transients differ by up to 1.3 kN before 20 s. A
      phase off by a quarter period (WaveKin 7's convention read for WaveKin 2) is 50 % off."""
    duration, late = 60.0, 20.0
    t, theirs, ours = _wavekin_2_run(tmp_path / "waves", 2, duration)
    _, still_theirs, still_ours = _wavekin_2_run(tmp_path / "still", 0, duration)
    after = t >= late
    assert np.abs(ours / theirs - 1)[after].max() <= 0.005, np.abs(ours / theirs - 1)[after].max()
    wave_theirs, wave_ours = (theirs - still_theirs)[after], (ours - still_ours)[after]
    span = np.ptp(wave_theirs)
    assert span > 0.02 * theirs.mean()  # (the waves move the tension: 22 kN of 0.89 MN)
    assert np.abs(wave_ours - wave_theirs).max() <= 0.05 * span, np.abs(wave_ours - wave_theirs).max() / span


def test_a_wave_file_reads_as_a_network_with_its_components(tmp_path):
    """A coupled fairlead and an anchor with waves: a network (a scenario's ``[waves]`` cannot hold
    a file's components), its components in ``water.wave_components`` (mjtether's convention:
    |A|, omega, beta in degrees, 90 - arg A in degrees under WaveKin 7), the file's notes kept;
    the scenario tree and the MoorDyn writer refuse it, naming why."""
    path = _folder(tmp_path, 7, ["0 0 0", "0.5 0.0 -2.0 0.25"], top="Vessel")
    net = moordyn.read(path)
    assert isinstance(net, Network)
    ((a, w, b, p),) = net.wave_components
    assert (a, w) == (2.0, 0.5) and b == pytest.approx(math.degrees(0.25)) and p == pytest.approx(180.0)
    with pytest.raises(ScenarioError, match="without waves: a network"):
        moordyn.to_dict(path.read_text(), str(path))
    with pytest.raises(ScenarioError, match="waves"):
        moordyn.write_network(net)


@pytest.mark.parametrize("kin, rows, words", [
    (3, None, "line 20: WaveKin = 3 (an elevation time series on a grid): waves are not supported by mjtether in "
              "this form; WaveKin 0 (none), 2 and 7"),
    (1, None, "WaveKin = 1 (kinematics set through MoorDyn's API)"),
    (7, ["0 0 0", "0.5 1.0 zzz-secret"], "wave_frequencies.txt: line 2: column 3 (im (m)) is not a finite number"),
    (7, ["0 0 0", "0.5 1.0"], "line 2: a component is omega (rad/s) re im (m) [beta (rad)]: 3 or 4 columns, got 2"),
    (7, ["0 0 0", "0.5 1.0 0.0 7.0"], "line 2: beta = 7: must be in [-2 pi, 2 pi] rad"),
    (7, ["0.1 0 0", "0.5 1.0 0.0"], "line 1: the first component's omega must be 0 rad/s"),
    (7, ["0 0.2 0", "0.5 1.0 0.0"], "line 1: the 0 rad/s row's amplitude must be 0"),
    (7, ["0 0 0", "0.5 1.0 0.0", "0.5 1.0 0.0"], "line 3: omega = 0.5 rad/s: the frequencies must ascend"),
    (7, ["0 0 0"], "at least 2 components are needed"),
    (7, ["0 0 0", "", "0.5 1.0 0.0"], "line 2: is blank"),
    (2, ["0 0 0", "0.5 0 0", "1.0 0.3 0"], "the top frequency, 1 rad/s, is MoorDyn-C's Nyquist bin"),
])
def test_refused_waves_name_the_file_and_line(tmp_path, kin, rows, words):
    """Waves mjtether does not read (other WaveKin values) and bad wave_frequencies.txt rows are
    refused naming the file, its line and what is allowed, never the file's contents."""
    path = _folder(tmp_path, kin, rows)
    with pytest.raises(ScenarioError) as err:
        moordyn.read(path)
    assert words in str(err.value) and "secret" not in str(err.value)


def test_a_missing_wave_file_is_named(tmp_path):
    path = _folder(tmp_path, 7)
    os.remove(tmp_path / "wave_frequencies.txt")
    with pytest.raises(ScenarioError, match=r"line\.txt: line 20: WaveKin = 7: .*wave_frequencies\.txt: no such file"):
        moordyn.read(path)

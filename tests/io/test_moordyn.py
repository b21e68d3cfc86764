"""MoorDyn v2 input files (``mjtether.io.moordyn``): read, run, write, refuse.

The run is checked against the analytic elastic catenary with seabed contact of the file's own
inputs, not against anything the reader computes.
"""

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from mjtether import cli
from mjtether.io import moordyn
from mjtether.quasistatic import catenary
from mjtether.scenario.runner import ScenarioRun
from mjtether.scenario import ScenarioError, load_scenario

CHAIN = """--------------------- MoorDyn Input File ------------------------------------
A chain from an anchor on a 150 m deep seabed to a fairlead 9 m below the surface. The line type
is the "Chain" of MoorDyn's documentation (Input Files, v2 format); ends and length chosen here.
---------------------- LINE TYPES ----------------------------------------------------------------------
TypeName   Diam    Mass/m     EA     BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)    (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
Chain      0.1      150.0     1e8    -1          0          2.3     1     1.0     {caax}
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
0.002         dtM           time step (s)
3000000       kbot          bottom stiffness (Pa/m)
300000        cbot          bottom damping (Pa-s/m)
150           WtrDpth       water depth (m)
1025          rho           ! water density
9.81          g
0.5           dtIC          (MoorDyn's initial-condition solver: not needed)
---------------------- OUTPUTS -----------------------------------------
FairTen1
------------------------- need this line -------------------------------------
"""


def chain(caax="1.0") -> str:
    return CHAIN.format(caax=caax)


def test_file_maps_onto_the_scenario_keys():
    sc = moordyn.read(text=chain(), name="chain.txt")
    t, w = sc.tether, sc.water
    assert (t.length, t.segments, t.diameter, t.mass_per_length, t.EA) == (450.0, 40, 0.1, 150.0, 1e8)
    assert (t.cd_normal, t.ca_normal, t.cd_tangential) == (2.3, 1.0, 1.0)
    assert (w.depth, w.density.rho, w.gravity, w.seabed_stiffness, w.seabed_damping) == (150.0, 1025.0, 9.81, 3e6, 3e5)
    assert sc.robot.type == "anchor" and sc.robot.position == (-400.0, 0.0, -150.0)
    assert sc.ship.position == (0.0, 0.0) and sc.ship.fairlead_z == -9.0
    # dtM is MoorDyn's explicit step: mjtether takes its own, here the longest its seabed contact
    # allows (MoorDyn's kBot on d l per kg of chain with its added mass, k dt^2 = 0.1: 7.26 ms),
    # a whole number of them per output interval
    k = 3e6 * 0.1 / (150.0 + 1.0 * 1025.0 * math.pi * 0.1 ** 2 / 4)
    dt, interval = sc.simulation.timestep, sc.simulation.output_interval
    assert 0.5 * math.sqrt(0.1 / k) < dt <= math.sqrt(0.1 / k)
    assert interval / dt == pytest.approx(round(interval / dt), abs=1e-9)
    assert sc.simulation.duration == moordyn.DEFAULT_DURATION


def test_a_moordyn_file_runs_to_the_analytic_catenary(tmp_path, capsys):
    """`mjtether run chain.txt --set simulation.duration=8`: the mean end forces over the last 3 s
    against the elastic catenary with seabed contact of the file's inputs (w = (150 - 1025 pi
    0.1^2/4) 9.81 N/m, EA = 1e8 N; the anchor, like the cable's axis, one radius above the
    seabed): fairlead and anchor tension within 1 % (the lumped 40-element line and the soft
    seabed contact, kBot = 3e6 Pa/m; measured +0.09 % and +0.16 %), laid length within one
    element."""
    f = tmp_path / "chain.txt"
    f.write_text(chain())
    assert cli.main(["run", str(f), "--set", "simulation.duration=8", "--out", str(tmp_path / "res"),
                     "--no-plots"]) == 0
    rows = np.genfromtxt(tmp_path / "res" / "timeseries.csv", delimiter=",", names=True)
    late = rows["time_s"] >= 5.0
    w = (150.0 - 1025.0 * math.pi * 0.1**2 / 4) * 9.81
    c = catenary([-400.0, 0.0, -150.0 + 0.05], [0.0, 0.0, -9.0], 450.0, w, EA=1e8)
    fair = math.hypot(c.H, c.VF)
    assert rows["ship_tension_N"][late].mean() == pytest.approx(fair, rel=0.01)
    assert rows["tow_tension_N"][late].mean() == pytest.approx(c.H, rel=0.01)
    laid = rows["length_on_seabed_m"][late].mean()
    assert abs(laid - c.laid_length) <= 450.0 / 40


def test_round_trips():
    """MoorDyn -> scenario -> MoorDyn -> scenario gives the same scenario, and a scenario
    written as MoorDyn and read back is the same scenario (its duration and time step aside:
    MoorDyn files have no duration, and their dtM is MoorDyn's step, not mjtether's)."""
    sc = moordyn.read(text=chain(), name="a")
    again = moordyn.read(text=moordyn.write(sc), name="b")
    assert again == sc
    toml = load_scenario(text='[simulation]\nduration = 5.0\ntimestep = 0.004\n[water]\ndepth = 80.0\ngravity = 9.80665\n'
                              'seabed_stiffness = 1e6\nseabed_damping = 1e4\n[tether]\nlength = 120.0\nsegments = 24\n'
                              'diameter = 0.03\nmass_per_length = 2.0\nEA = 2e6\nEI = 50.0\nseabed_friction = 0.3\n'
                              '[ship]\nposition = [5.0, -2.0]\nfairlead_z = -3.0\n[robot]\ntype = "anchor"\n'
                              'position = [60.0, 10.0, -80.0]\n')
    back = moordyn.read(text=moordyn.write(toml), name="c",
                        overrides=["simulation.duration=5.0", "simulation.timestep=0.004"])
    assert back == toml


def test_approximations_warn_naming_the_line():
    with pytest.warns(moordyn.MoorDynWarning, match=r"line 7: CaAx = 0.5: mjtether's added mass along the line is"):
        moordyn.read(text=chain("0.5"), name="chain.txt")


def test_axial_added_mass_maps_onto_added_mass_and_back():
    """CaAx = 0 (a slender line: no added mass along it) is tether.added_mass = "normal", CaAx =
    Ca the isotropic default; written back out, each gives its CaAx again."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # neither is an approximation
        for caax, mode in (("0.0", "normal"), ("1.0", "isotropic")):
            sc = moordyn.read(text=chain(caax), name="chain.txt")
            assert sc.tether.added_mass == mode
            assert moordyn.read(text=moordyn.write(sc), name="back.txt").tether.added_mass == mode


REFUSED = {  # name: (edit of the chain file, what the error must contain)
    "a body point without its body": (("2     Coupled    0       0     -9      0      0       0      0",
                                       "2     Body1      0       0     -9      0      0       0      0"),
                                      "line 12: point 2 is on body 1, which is not in the BODIES section"),
    "damping in N s": (("Chain      0.1      150.0     1e8    -1 ", "Chain      0.1      150.0     1e8    2e5 "),
                       "line 7: BA = 200000 N s"),
    "VIV": (("1.0     1.0\n---------------------- POINTS", "1.0     1.0   0.8\n---------------------- POINTS"),
            "line 7: VIV (Cl = 0.8) is not supported"),
    "a text where a number goes": (("1     Chain       1        2        450 ", "1     Chain       1        2        long "),
                                   "line 16: UnstrLen must be a number, got 'long'"),
    "a seafloor file": (("150           WtrDpth", "sea.txt       SeafloorFile\n150           WtrDpth"),
                        "line 21: SeafloorFile sea.txt: no such file beside the input file"),
    "a dynamic current": (("150           WtrDpth", "2             Currents\n150           WtrDpth"),
                          "line 21: Currents = 2: dynamic or 4-D currents are not supported"),
    "static friction above kinetic": (("150           WtrDpth", "0.5 FrictionCoefficient\n1.5 StatDynFricScale\n150 WtrDpth"),
                                      "static and kinetic friction differ"),
    "a rod pinned to a body": (("---------------------- POINTS", "---------------------- ROD TYPES ---\nName Diam Mass "
                                "Cd Ca CdEnd CaEnd\n(-) (m) (kg/m) (-) (-) (-) (-)\nCan 1 10 1 1 1 1\n"
                                "---------------------- RODS ---\nID RodType\n(#) (name)\n1 Can Body1Pinned 0 0 0 0 0 "
                                "5 4 -\n---------------------- POINTS"),
                               "line 15: rods on a body are not supported by mjtether"),
}


@pytest.mark.parametrize("case", list(REFUSED))
def test_unsupported_entries_are_errors_naming_the_line(case):
    (old, new), message = REFUSED[case]
    text = chain()
    assert old in text, old
    with pytest.raises(ScenarioError) as info:
        moordyn.read(text=text.replace(old, new, 1), name="chain.txt")
    assert str(info.value).startswith("chain.txt: ") and message in str(info.value), str(info.value)


NETWORKS = {  # name: edit of the chain file that makes it a network of lines (not refused any more)
    "two lines side by side": ("1     Chain       1        2        450        40       pt",
                               "1     Chain       1        2        450        40       pt\n2     Chain       1        2   "
                               "     450        40       pt"),
    "a free end": ("2     Coupled    0       0     -9      0      0       0      0",
                   "2     Free       0       0     -9      500    0       0      0"),
}


@pytest.mark.parametrize("case", list(NETWORKS))
def test_what_is_not_one_line_reads_as_a_network(case):
    from mjtether.network import Network

    old, new = NETWORKS[case]
    net = moordyn.read(text=chain().replace(old, new, 1), name="chain.txt")
    assert isinstance(net, Network)


def test_moordyn_c_spellings_read_as_moordyn_c_reads_them():
    """MoorDyn-C 2.7's section headers, option aliases and point words (MoorDyn2.cpp): a LINE
    DICTIONARY and POINT PROPERTIES, WtrDnsty, kb, cb, gravity, "Vessel"/"Anchor"; no WtrDpth
    takes the depth of the lowest point; an unknown option is a warning, as in MoorDyn-C."""
    text = (chain().replace("LINE TYPES", "LINE DICTIONARY").replace("- POINTS -", "- POINT PROPERTIES -")
            .replace("1025          rho", "1000          WtrDnsty").replace("3000000       kbot", "2000000 kb")
            .replace("300000        cbot", "200000 cb").replace("9.81          g", "9.80665 gravity")
            .replace("1     Fixed  ", "1     Anchor ").replace("2     Coupled", "2     Vessel ")
            .replace("150           WtrDpth       water depth (m)\n", "7 Wiggle\n"))
    with pytest.warns(moordyn.MoorDynWarning, match="line 21: option 'Wiggle' is not a MoorDyn-C 2.7 option"):
        sc = moordyn.read(text=text, name="chain.txt")
    w = sc.water
    assert (w.depth, w.density.rho, w.seabed_stiffness, w.seabed_damping, w.gravity) == \
        (150.0, 1000.0, 2e6, 2e5, 9.80665)


def test_what_moordyn_cannot_express_is_refused_when_writing():
    walker = load_scenario()
    with pytest.raises(ScenarioError, match="robot.type: 'walker'"):
        moordyn.write(walker)
    lazy_wave = load_scenario(LAZY_WAVE, overrides=["water.current.speed=0.0"])
    with pytest.raises(ScenarioError, match="tether.floats: float sections"):
        moordyn.write(lazy_wave)
    off_node = load_scenario(text=MAKEUP.replace("arc_length = 200.0", "arc_length = 202.0"))
    with pytest.raises(ScenarioError, match=r"tether.point_loads\[1\].arc_length: 202 m, between nodes"):
        moordyn.write(off_node)


LAZY_WAVE = Path(__file__).resolve().parents[2] / "examples" / "lazy_wave_umbilical.toml"
MAKEUP = """
[water]
depth = 100.0
[tether]
seabed_friction = 0.0
[[tether.sections]]
line_type = "steel_armoured_umbilical_17mm"
length = 120.0
segments = 24
[[tether.sections]]
line_type = "polyester_rope_24mm"
length = 180.0
segments = 36
[[tether.point_loads]]
arc_length = 120.0
mass = 300.0
volume = 0.05
cd_area = 0.4
ca = 1.0
[[tether.point_loads]]
arc_length = 200.0
volume = 0.3
cd_area = 0.5
ca = 1.0
[ship]
fairlead_z = -2.0
[winch]
mode = "fixed"
[robot]
type = "anchor"
position = [220.0, 0.0, -100.0]
"""


def test_a_make_up_round_trips_as_lines_joined_at_free_points():
    """Two sections with a clump at their joint and a buoy within the second: written as three
    lines (the second section cut at the buoy's node) joined at two free points carrying the
    loads, and read back as the same line element by element and node by node (names, line-type
    names and breaking loads, which MoorDyn files do not hold, aside)."""
    from mjtether.scenario.runner import makeup_from

    sc = load_scenario(text=MAKEUP)
    text = moordyn.write(sc)
    assert text.count(" Free ") == 2 and "\n3 type2 3 4 100.0 20 -" in text
    a, b = makeup_from(sc), makeup_from(moordyn.read(text=text, name="back.txt"))
    for attr in ("element_length", "element_diameter", "element_mass_per_length", "element_EA", "element_EI",
                 "element_cd_normal", "element_cd_tangential", "element_ca_normal", "node_mass", "node_volume",
                 "node_cd_area", "node_ca"):
        np.testing.assert_array_equal(getattr(a, attr), getattr(b, attr), err_msg=attr)


def test_a_moordyn_chain_with_a_free_clump_runs_from_its_steady_state():
    """MoorDyn's chain split at a free point carrying a 2 t clump: it starts from the make-up's
    quasi-static steady state, and 2 s on the fairlead force is still that state's within 1 %
    (a start that holds; the make-up's dynamics against statics are in test_scenario_makeup)."""
    text = chain().replace("1     Chain       1        2        450        40       pt",
                           "1     Chain       1        3        200        20       pt\n"
                           "2     Chain       3        2        250        20       pt").replace(
        "2     Coupled    0       0     -9      0      0       0      0",
        "2     Coupled    0       0     -9      0      0       0      0\n"
        "3     Free       -250    0     -120    2000   0.1     0.5    1.0")
    sc = moordyn.read(text=text, name="clump.txt", overrides=["simulation.duration=2.0"])
    assert [s.length for s in sc.tether.sections] == [250.0, 200.0]  # from the fairlead down
    assert sc.tether.point_loads[0].arc_length == 250.0 and sc.tether.point_loads[0].mass == 2000.0
    r = ScenarioRun(sc)
    try:
        assert r.initial_note.startswith("quasi-static steady state")
        f0 = np.array(r.initial.top_force)
        for _ in range(int(round(2.0 / sc.simulation.timestep))):
            r.step()
        f = r.bt.end_force(r.sim.data, "start")
    finally:
        r.close()
    assert np.linalg.norm(f - f0) <= 0.01 * np.linalg.norm(f0), (f, f0)


def test_convert_writes_both_ways_and_never_over_a_file(tmp_path, capsys):
    src = tmp_path / "chain.txt"
    src.write_text(chain())
    out = tmp_path / "chain.toml"
    assert cli.main(["convert", str(src), str(out)]) == 0
    assert load_scenario(out) == moordyn.read(src)
    assert cli.main(["convert", str(out), str(tmp_path / "back.dat")]) == 0
    assert moordyn.read(tmp_path / "back.dat") == moordyn.read(src)
    before = out.read_bytes()
    capsys.readouterr()
    assert cli.main(["convert", str(src), str(out)]) == 2
    assert "exists; pass --overwrite" in capsys.readouterr().err and out.read_bytes() == before
    assert cli.main(["convert", str(src), str(src)]) == 2  # never over its own source
    assert moordyn.read(src) is not None


def test_solve_reads_a_moordyn_file(tmp_path):
    """The steady state of the file's line starts the run as for a TOML scenario."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", moordyn.MoorDynWarning)
        sc = moordyn.read(text=chain(), name="chain.txt")
    r = ScenarioRun(sc)
    try:
        assert r.initial is not None and r.initial.laid_length > 100.0
    finally:
        r.close()


def _moordyn_c_reads(path) -> bool:
    """Whether MoorDyn-C 2.7 (the ``moordyn`` package) reads the file at ``path``."""
    md = pytest.importorskip("moordyn")
    try:
        s = md.Create(str(path))
    except RuntimeError:
        return False
    md.Close(s)
    return True


def test_ids_out_of_turn_are_refused_naming_the_line_as_moordyn_c_refuses_them(tmp_path):
    """MoorDyn-C refuses points, lines, rods and bodies not numbered 1, 2, 3, ... ("ID must be
    sequential starting from 1"); mjtether too, naming the line, where it would otherwise have
    read two rods numbered 3 (MoorDyn's own bench/Mooring/floating_rods.txt) as one."""
    text = chain().replace("1     Chain       1        2        450        40       pt",
                           "1     Chain       1        2        450        40       pt\n"
                           "3     Chain       1        2        450        40       pt")
    (tmp_path / "ids.txt").write_text(text)
    assert not _moordyn_c_reads(tmp_path / "ids.txt")
    with pytest.raises(ScenarioError, match=r"ids.txt: line 17: line IDs must run 1, 2, 3, \.\.\. \(as MoorDyn "
                                            r"requires\); got '3'"):
        moordyn.read(tmp_path / "ids.txt")


def test_an_output_naming_a_missing_line_warns_naming_the_line(tmp_path):
    """MoorDyn-C refuses a file whose OUTPUTS name a line it does not have ("Invalid Line ID
    specifier"); mjtether does not use the section, runs the file and warns, naming the line."""
    (tmp_path / "outs.txt").write_text(chain().replace("FairTen1\n", "FairTen1\nFairTen2\n"))
    assert not _moordyn_c_reads(tmp_path / "outs.txt")
    with pytest.warns(moordyn.MoorDynWarning, match=r"line 27: output 'FairTen2' names line 2, and the file has 1 "
                                                     r"line: MoorDyn-C 2.7 refuses the file"):
        moordyn.read(tmp_path / "outs.txt")


def test_moordyn_f_external_loads_are_refused_which_moordyn_c_skips(tmp_path):
    """OpenFAST's MoorDyn-F reads an EXTERNAL LOADS section (a force and damping on a body or
    point); MoorDyn-C 2.7 skips it without a word, and the fairlead's pull is the same with or
    without it (checked here over its first 0.1 s). mjtether refuses it, naming its first row, rather
    than run without the load."""
    md = pytest.importorskip("moordyn")
    load = ("---------------------- EXTERNAL LOADS ---------------------\nID  Object  Fext  Blin  Bquad  CSys\n"
            "(#)  (name)  (N)  (Ns/m)  (Ns^2/m^2)  (-)\n1  Point2  1e5|0|0  0  0  G\n")
    base = chain().replace("0.5           dtIC", "0             TmaxIC\n0.5           dtIC")
    pulls = []
    for name, text in (("plain.txt", base), ("loaded.txt", base.replace("---------------------- OPTIONS", load +
                                                                        "---------------------- OPTIONS"))):
        (tmp_path / name).write_text(text)
        s = md.Create(str(tmp_path / name))
        try:
            x, v = np.array([0.0, 0.0, -9.0]), np.zeros(3)
            md.Init(s, x, v)
            md.Step(s, x, v, 0.0, 0.1)
            pulls.append(np.array(md.GetPointForce(md.GetPoint(s, 2))))
        finally:
            md.Close(s)
    assert np.array_equal(pulls[0], pulls[1]) and np.linalg.norm(pulls[0]) > 1e5
    with pytest.raises(ScenarioError, match=r"loaded.txt: line 20: external loads \(MoorDyn-F's; MoorDyn-C 2.7 skips "
                                            r"them\) \(EXTERNAL LOADS section\) are not supported by mjtether"):
        moordyn.read(tmp_path / "loaded.txt")

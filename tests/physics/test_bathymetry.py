"""Bathymetry grids (``mjtether.physics.bathymetry``) against what did not come from them:
MoorDyn-C's own reading of a 3-D seafloor file (``GetDepthAt``), MuJoCo's height field built
from the grid (a ray cast down onto it), and the grid's own nodes."""

import math
import os
from pathlib import Path

import mujoco
import numpy as np
import pytest

from mjtether.cable import builder
from mjtether.physics import bathymetry

MOORING = Path(__file__).resolve().parents[1] / "data" / "moordyn" / "tests" / "Mooring"


def _bumpy(nx=21, ny=11, dx=2.0, dy=3.0):
    x = -10.0 + dx * np.arange(nx)
    y = -15.0 + dy * np.arange(ny)
    X, Y = np.meshgrid(x, y)
    z = -50.0 + 0.1 * X + 1.5 * np.sin(X / 3.0) * np.cos(Y / 4.0)
    return x, y, z


def _write_moordyn_seafloor(path, x, y, z):
    rows = [f"{len(x)} {len(y)}", " ".join(f"{v:.17g}" for v in x), " ".join(f"{v:.17g}" for v in y)]
    rows += [f"{xi:.17g} {yj:.17g} {z[j, i]:.17g}" for i, xi in enumerate(x) for j, yj in enumerate(y)]
    path.write_text("\n".join(rows) + "\n")


def test_heights_between_the_nodes_are_moordyn_c_s(tmp_path):
    """A bumpy 3-D seafloor file read by mjtether and by MoorDyn-C (a minimal input file naming
    it): the heights at 200 random points agree to 1e-5 m (both interpolate bilinearly; MoorDyn-C
    rounds in single precision, 1.6e-6 m measured, where a triangulated or nearest-node reading
    would be centimetres off on this relief)."""
    moordyn = pytest.importorskip("moordyn")
    x, y, z = _bumpy()
    _write_moordyn_seafloor(tmp_path / "floor.txt", x, y, z)
    (tmp_path / "lines.txt").write_text("\n".join([
        "--- MoorDyn input", "--- LINE TYPES ---", "Name Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx",
        "(-) (m) (kg/m) (N) (-) (-) (-) (-) (-) (-)", "c 0.1 20 1e8 -1 0 1 1 0 0", "--- POINTS ---",
        "ID Type X Y Z M V CdA CA", "(-) (-) (m) (m) (m) (kg) (m3) (m2) (-)", "1 Fixed 0 0 -40 0 0 0 0",
        "2 Fixed 5 0 -40 0 0 0 0", "--- LINES ---", "ID Type A B L N Out", "(-) (-) (-) (-) (m) (-) (-)",
        "1 c 1 2 6 5 -", "--- OPTIONS ---", "60 WtrDpth", "floor.txt SeafloorFile", "0 TmaxIC",
        "--- need this line ---", ""]))
    ours = bathymetry.load(tmp_path / "floor.txt")
    rng = np.random.default_rng(1)
    px, py = rng.uniform(x[0], x[-1], 200), rng.uniform(y[0], y[-1], 200)
    cwd = Path.cwd()
    os.chdir(tmp_path)
    try:
        s = moordyn.Create("lines.txt")
        try:
            floor = moordyn.GetSeafloor(s)
            theirs = np.array([moordyn.GetDepthAt(floor, a, b) for a, b in zip(px, py)])
        finally:
            moordyn.Close(s)
    finally:
        os.chdir(cwd)
    assert np.abs(ours.height(px, py) - theirs).max() < 1e-5


def test_moordyn_s_own_seafloor_file_reads_its_nodes():
    """MoorDyn's tests/Mooring/3D_seafloor/seafloor_profile_3d.txt: 100 x 5 nodes, a slope of
    0.2 in x (z = -40 at x = -50, -20 at x = 50); every node's height as the file gives it."""
    path = MOORING / "3D_seafloor" / "seafloor_profile_3d.txt"
    g = bathymetry.load(path)
    rows = np.loadtxt(path.read_text().splitlines()[3:])
    assert g.z.shape == (5, 100)
    assert np.allclose(g.height(rows[:, 0], rows[:, 1]), rows[:, 2], atol=1e-12)
    slope, heading = g.plane_at(0.0, 0.0, 5.0)
    assert math.tan(slope) == pytest.approx(0.2, rel=1e-9) and heading == pytest.approx(0.0, abs=1e-9)


def test_mujoco_s_height_field_is_the_grid():
    """``add_seabed_grid``'s height field, hit by rays cast straight down at every node and at
    random points: MuJoCo's surface is the grid at the nodes (to its float32 storage, 1e-6 of the
    relief) and, between them, within the bilinear surface's difference from MuJoCo's two
    triangles per cell (at most a quarter of a cell's twist, |z00 - z10 - z01 + z11| / 4); and
    ``grid_of`` reads the grid back from the compiled model."""
    x, y, z = _bumpy()
    g = bathymetry.Bathymetry(x, y, z)
    spec = mujoco.MjSpec()
    builder.add_seabed_grid(spec, g)
    m = spec.compile()
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    geom = np.zeros(1, np.int32)

    def ray(px, py):
        return 100.0 - mujoco.mj_ray(m, d, np.array([px, py, 100.0]), np.array([0.0, 0.0, -1.0]), None, 1, -1, geom)

    X, Y = np.meshgrid(x[1:-1], y[1:-1])  # (rays exactly on the outer edge may miss)
    hits = np.array([ray(a, b) for a, b in zip(X.ravel(), Y.ravel())])
    relief = np.ptp(z)
    assert np.abs(hits - z[1:-1, 1:-1].ravel()).max() <= 1e-6 * relief
    twist = np.abs(z[:-1, :-1] - z[:-1, 1:] - z[1:, :-1] + z[1:, 1:]).max() / 4
    rng = np.random.default_rng(2)
    px, py = rng.uniform(x[0] + 0.1, x[-1] - 0.1, 100), rng.uniform(y[0] + 0.1, y[-1] - 0.1, 100)
    hits = np.array([ray(a, b) for a, b in zip(px, py)])
    assert np.abs(hits - g.height(px, py)).max() <= twist + 1e-6 * relief
    back = builder.grid_of(m, 0)
    assert np.allclose(back.x, x) and np.allclose(back.y, y) and np.allclose(back.z, z, atol=1e-6 * relief)


def test_a_depth_grid_reads_as_csv_and_npy(tmp_path):
    x, y, z = _bumpy()
    np.savetxt(tmp_path / "d.csv", -z, delimiter=",")
    np.save(tmp_path / "d.npy", -z)
    for name in ("d.csv", "d.npy"):
        g = bathymetry.load(tmp_path / name, spacing=2.0, origin=(-10.0, -15.0))
        assert np.allclose(g.x, x) and np.allclose(g.y, -15.0 + 2.0 * np.arange(len(y)))
        assert np.allclose(g.z, z)


@pytest.mark.parametrize("content, words", [
    ("1,2\n3,x\n", "not a grid of numbers"),
    ("1,2\n3,-4\n", "depths are positive down"),
    ("1,2,3\n", "at least 2 x 2 nodes"),
])
def test_a_bad_depth_grid_is_refused_naming_the_file(tmp_path, content, words):
    (tmp_path / "d.csv").write_text(content)
    with pytest.raises(bathymetry.BathymetryError) as err:
        bathymetry.load(tmp_path / "d.csv", spacing=1.0)
    assert "d.csv" in str(err.value) and words in str(err.value)


def test_an_irregular_moordyn_grid_is_refused(tmp_path):
    _write_moordyn_seafloor(tmp_path / "f.txt", np.array([0.0, 1.0, 3.0]), np.array([0.0, 1.0]),
                            -np.ones((2, 3)) * 10)
    with pytest.raises(bathymetry.BathymetryError, match="equal steps"):
        bathymetry.load(tmp_path / "f.txt")

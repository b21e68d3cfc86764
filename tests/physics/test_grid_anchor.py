"""An anchor on a bathymetry grid (``builder.add_tether`` on ``add_seabed_grid``'s height field)
against the same anchor on the seabed plane and against an elastic catenary with a touchdown
written here; and the grid files' bad input (``mjtether.physics.bathymetry``).

A node held at a fixed point cannot move out of a contact, so any push of the seabed on it goes
to the anchor: at a grid node MuJoCo found penetrations of 1e-4 m in any direction (40-55 kN on a
chain) until the held node became the world's vertex of the flex, which MuJoCo does not collide
with a height field."""

import math
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq, fsolve

from mjtether.network import config
from mjtether.network import run as network_run
from mjtether.physics import bathymetry
from mjtether.scenario import load_scenario
from mjtether.scenario.runner import ScenarioRun

# ------------------------------------------------------------------ the spread mooring's line 1a

CHAIN = {"diameter": 0.1368, "mass_per_length": 115.6, "EA": 5.8e8, "cd_normal": 2.4, "ca_normal": 1.0,
         "cd_tangential": 1.15}  # (examples/networks/spread_mooring_float.toml)
ANCHOR, TOP, LENGTH, SEGMENTS = (600.0, 0.0, -200.0), (306.0, 0.0, -120.0), 320.0, 20


def _line_1a(grid=None):
    """Line 1a of the spread mooring, 320 m of chain in 20 elements, from its anchor on the 200 m
    deep seabed to a fixed point where its float pulls it to about 140 kN; without seabed friction
    (a laid chain that has not slid holds any share of friction: the catenary's is then moot)."""
    water = {"depth": 200.0, "rho": 1025.0, "seabed_friction": 0.0}
    if grid is not None:
        water.update(bathymetry=str(grid), bathymetry_spacing_m=50.0, bathymetry_origin_m=[300.0, -100.0])
    return config.from_dict({
        "water": water, "simulation": {"duration": 10.0, "settle": 30.0}, "line_types": {"chain": CHAIN},
        "points": {"anchor": {"kind": "fixed", "position": list(ANCHOR)},
                   "top": {"kind": "fixed", "position": list(TOP)}},
        "lines": [{"name": "1a", "type": "chain", "a": "anchor", "b": "top", "length": LENGTH,
                   "segments": SEGMENTS}]}, "line 1a")


def _anchor_force(net) -> np.ndarray:
    """The line's mean force on its anchor (N, world) over 2 s after the network settled."""
    r = network_run.build(net)
    try:
        network_run.settle(r, net.settle)
        every = max(1, round(0.1 / r.timestep))
        forces = []
        for _ in range(20):
            r.advance(every)
            forces.append(r.line_forces("1a")[0])
        return np.mean(forces, axis=0)
    finally:
        r.sim.close()


def _flat_catenary_H(w, EA, L, X, Z):
    """Horizontal tension (N) of an elastic line of wet weight ``w`` (N/m), stiffness ``EA`` (N) and
    length ``L`` (m) lying on a flat frictionless seabed from its anchor and rising ``Z`` m to a
    point ``X`` m away: the suspended length s reaches Z, the laid L - s (stretched by H/EA) and
    the suspended part's span add up to X."""
    def suspended(H):
        return brentq(lambda s: H / w * (math.hypot(1.0, w * s / H) - 1.0) + w * s * s / (2 * EA) - Z, 1e-9, L)

    def span(H):
        s = suspended(H)
        return H / w * math.asinh(w * s / H) + H * s / EA + (L - s) * (1.0 + H / EA) - X
    return brentq(span, 1e3, 3e5, xtol=1e-6)


def test_an_anchor_on_a_flat_grid_takes_the_plane_s_tension(tmp_path):
    """Line 1a of ``examples/networks/spread_mooring_float.toml`` on its flat seabed, given once as
    the plane and once as a flat 50 m grid whose node the anchor sits on: the force on the anchor
    within 1 % of the plane's and of the catenary's (horizontal H from the closed form above; the
    node the anchor holds carries half an element's wet weight, w l0 / 2, that the seabed does not
    support, downwards). Measured: grid and plane 1e-5 apart, both 0.13 % from the catenary (20
    elements of 16 m); before the held node left the grid's contact, the grid's was 29 % off
    (72 kN sideways), as the issue saw (+42 %)."""
    np.savetxt(tmp_path / "flat.csv", np.full((5, 9), 200.0), delimiter=",")
    plane = _anchor_force(_line_1a())
    grid = _anchor_force(_line_1a(tmp_path / "flat.csv"))
    net = _line_1a()
    w = (CHAIN["mass_per_length"] - net.rho * math.pi * CHAIN["diameter"] ** 2 / 4) * net.gravity
    H = _flat_catenary_H(w, CHAIN["EA"], LENGTH, ANCHOR[0] - TOP[0], TOP[2] - ANCHOR[2])
    expected = np.array([-H, 0.0, -w * LENGTH / SEGMENTS / 2])
    assert np.linalg.norm(grid - plane) <= 0.01 * np.linalg.norm(plane), (grid, plane)
    for name, f in (("plane", plane), ("grid", grid)):
        assert np.linalg.norm(f - expected) <= 0.01 * H, (name, f, expected)


# ------------------------------------------------------------------ an anchor on a 5 degree slope

SLOPE = math.radians(5.0)
SCENARIO = """
[simulation]
duration = 10.0
timestep = 0.00625
[water]
depth = 120.0
{seabed}
[tether]
length = 200.0
segments = 80
diameter = 0.025
density = 2500.0
EA = 5.0e6
seabed_friction = 0.0
[ship]
mode = "fixed"
position = [0.0, 0.0]
[robot]
type = "anchor"
position = [100.0, 0.0, {z!r}]
"""


def _slope_run(tmp_path, name, seabed):
    """The anchor's mean force (N, world) over the last 5 s of 10 s, and the run."""
    path = tmp_path / f"{name}.toml"
    path.write_text(SCENARIO.format(seabed=seabed, z=-120.0 + math.tan(SLOPE) * 100.0))
    r = ScenarioRun(load_scenario(path))
    forces = []
    try:
        for k in range(1600):
            r.step()
            if k >= 800 and k % 20 == 0:
                forces.append(r.bt.end_force(r.sim.data, "end"))
        return np.mean(forces, axis=0), r.scene.anchor_point(), r.scene.fairlead_start(), r.water.gravity
    finally:
        r.close()


def _slope_catenary(A, F, L, w, EA, alpha):
    """Tension (N) at anchor ``A`` (m, its axis on the seabed) of a frictionless line laid down a
    slope ``alpha`` (rad, rising towards +x, the fairlead ``F`` downhill at smaller x), then
    hanging to F: along the laid part L - s the tension grows uphill by w sin(alpha) a metre from
    H / cos(alpha) at the touchdown, where the suspended part of length s leaves the slope
    tangent to it (its vertical tension -H tan(alpha) there); the elastic catenary from there
    reaches F. Solved for H and s."""
    down = np.array([-math.cos(alpha), 0.0, -math.sin(alpha)])

    def misses(p):
        H, s = p
        laid, t_td = L - s, H / math.cos(alpha)
        td = A + down * (laid + (t_td * laid + w * math.sin(alpha) * laid ** 2 / 2) / EA)
        v0 = -H * math.tan(alpha)
        v1 = v0 + w * s
        dx = H / w * (math.asinh(v1 / H) - math.asinh(v0 / H)) + H * s / EA
        dz = H / w * (math.hypot(1.0, v1 / H) - math.hypot(1.0, v0 / H)) + (v0 * s + w * s * s / 2) / EA
        return [td[0] - dx - F[0], td[2] + dz - F[2]]
    (H, s), info, ok, _ = fsolve(misses, [100.0, 0.6 * L], xtol=1e-12, full_output=True)
    assert ok == 1 and max(map(abs, misses([H, s]))) < 1e-6
    return H / math.cos(alpha) + w * math.sin(alpha) * (L - s), down


def test_an_anchor_on_a_sloped_grid_takes_the_plane_s_tension(tmp_path):
    """200 m of umbilical from a ship to an anchor on a 5 deg slope, 75 m of it laid, no friction
    and no current: as ``seabed_slope_deg = 5`` and as a 2 m grid of the same plane (the anchor on
    a node). The anchor's force (the mean over the last 5 s) within 1 % of each other's and of the
    catenary's: its tension T_A along the slope, plus the normal part of the weight of the node the
    anchor holds (w l0 / 2 cos(alpha), which the seabed does not support). Measured: 0.28 % (plane)
    and 0.21 % (grid) from the catenary, 0.05 % apart; before the held node left the grid's
    contact, the grid's contact held 4 N of the anchor's 17 N downwards (4 % of its force)."""
    x = np.arange(-20.0, 150.0 + 1e-9, 2.0)
    y = np.arange(-40.0, 40.0 + 1e-9, 2.0)
    X, _ = np.meshgrid(x, y)
    np.savetxt(tmp_path / "slope.csv", 120.0 - math.tan(SLOPE) * X, delimiter=",", fmt="%.9f")
    plane, A, F, g = _slope_run(tmp_path, "plane", "seabed_slope_deg = 5.0")
    grid, A_grid, _, _ = _slope_run(tmp_path, "grid", 'bathymetry = "slope.csv"\nbathymetry_spacing_m = 2.0\n'
                                                       "bathymetry_origin_m = [-20.0, -40.0]")
    assert np.allclose(A, A_grid, atol=1e-6)
    d, L, n = 0.025, 200.0, 80
    w = (2500.0 - 1025.0) * math.pi * d * d / 4 * g
    T_A, down = _slope_catenary(A, F, L, w, 5.0e6, SLOPE)
    normal = np.array([-math.sin(SLOPE), 0.0, math.cos(SLOPE)])
    expected = T_A * down - w * L / n / 2 * math.cos(SLOPE) * normal
    assert np.linalg.norm(grid - plane) <= 0.01 * np.linalg.norm(plane), (grid, plane)
    for name, f in (("plane", plane), ("grid", grid)):
        assert np.linalg.norm(f - expected) <= 0.01 * T_A, (name, f, expected)


# ------------------------------------------------------------------ the grid files' bad input


def test_a_comment_with_spaces_and_a_comma_reads(tmp_path):
    """A space-separated depth grid whose comments hold commas and spaces: the numbers as
    written (not taken for a comma-separated file)."""
    (tmp_path / "d.txt").write_text("# depths in m, rows along +y\n200 201.5 202\n203 204 205  # deepest, last\n")
    g = bathymetry.load(tmp_path / "d.txt", spacing=2.0, origin=(1.0, 3.0))
    assert np.array_equal(g.z, -np.array([[200.0, 201.5, 202.0], [203.0, 204.0, 205.0]]))
    assert np.array_equal(g.x, [1.0, 3.0, 5.0]) and np.array_equal(g.y, [3.0, 5.0])


def _refused_small(call):
    """The error ``call`` raises and the most memory (bytes) Python allocated meanwhile."""
    tracemalloc.start()
    try:
        with pytest.raises(bathymetry.BathymetryError) as err:
            call()
        return str(err.value), tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_an_oversized_grid_is_refused_naming_the_limit_before_it_is_read(tmp_path, monkeypatch):
    """10 000 x 10 000 nodes (8e8 bytes of heights) announced by a MoorDyn seafloor file's first
    line and by a .npy header (no data behind either): refused naming the file and MAX_NODES,
    with under 1 MB allocated; a CSV over the limit (lowered here to 100 nodes, 11 x 10 given)
    likewise; a text file larger than a grid of MAX_NODES nodes can be, before it is read."""
    (tmp_path / "floor.txt").write_text("10000 10000\n0 1\n0 1\n")
    with open(tmp_path / "big.npy", "wb") as f:
        np.lib.format.write_array_header_1_0(f, {"descr": "<f8", "fortran_order": False, "shape": (10000, 10000)})
    limit = f"{bathymetry.MAX_NODES:,}"
    for name in ("floor.txt", "big.npy"):
        message, peak = _refused_small(lambda: bathymetry.load(tmp_path / name, spacing=1.0))
        assert name in message and limit in message and "10000 x 10000" in message, message
        assert peak < 1e6, peak
    np.savetxt(tmp_path / "d.csv", np.full((10, 11), 50.0), delimiter=",")
    with monkeypatch.context() as m:
        m.setattr(bathymetry, "MAX_NODES", 100)
        with pytest.raises(bathymetry.BathymetryError, match=r"d\.csv: a grid of 11 x 10 nodes; at most 100"):
            bathymetry.load(tmp_path / "d.csv", spacing=1.0)
        m.setattr(bathymetry, "MAX_NODES", 1)  # (a 2 x 2 grid takes more than 64 bytes as text)
        np.savetxt(tmp_path / "e.csv", np.full((2, 2), 50.0), delimiter=",")
        with pytest.raises(bathymetry.BathymetryError, match=r"e\.csv: .* MiB, more than a grid of at most 1 nodes"):
            bathymetry.load(tmp_path / "e.csv", spacing=1.0)
    assert bathymetry.load(tmp_path / "d.csv", spacing=1.0).z.shape == (10, 11)  # (under the real limit: read)


SECRET = "password = hunter2, api_token: sk-LIVE-0123456789abcdef\nuser alice, admin\n"
SECRET_WORDS = ("password", "hunter2", "api_token", "sk-LIVE", "0123456789abcdef", "alice")


@pytest.mark.parametrize("which", ["secret", "moordyn", "passwd", "binary"])
def test_a_file_that_is_not_a_grid_is_refused_without_its_text(tmp_path, which):
    """A text file with secret-looking lines, as a depth grid and as a seafloor file whose first
    line looks like NX NY; /etc/passwd; a binary file: refused naming the file (and for the first
    two the line), with none of its words, nor any of its lines, in the message."""
    path = tmp_path / "floor.csv"
    if which == "passwd":
        path = Path("/etc/passwd")
        if not path.is_file():
            pytest.skip("no /etc/passwd here")
    elif which == "binary":
        path.write_bytes(bytes(range(256)) * 4)
    elif which == "moordyn":
        path.write_text("2 2\n0 1\n0 1\n" + SECRET + "0 1 -5\n1 1 -5\n")
    else:
        path.write_text(SECRET)
    with pytest.raises(bathymetry.BathymetryError) as err:
        bathymetry.load(path, spacing=1.0)
    message = str(err.value)
    assert str(path.resolve()) in message, message
    rest = message.replace(str(path.resolve()), "")
    lines = [ln.strip() for ln in path.read_bytes().decode("utf-8", "replace").splitlines() if len(ln.strip()) >= 6]
    assert not [ln for ln in lines if ln in rest], message
    assert not [w for w in SECRET_WORDS if w in rest], message
    if which != "passwd" and which != "binary":
        assert ("line 4" if which == "moordyn" else "line 1") in rest, message
